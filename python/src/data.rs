//! Arrays across the boundary (little-endian f64 bytes) and the measured
//! data of an identification: a data file, or a table from a data frame or
//! a mapping.
use super::errors::data_error;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use rfeid::io::timeseries::TimeSeries;
pub use rfeid::measurement::measured::Source;
use std::path::PathBuf;

/// `values` as little-endian bytes.
pub fn f64_bytes(values: &[f64]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// Little-endian f64 bytes as values; `what` names the array in the error.
pub fn f64_values(bytes: &[u8], what: &str) -> PyResult<Vec<f64>> {
    if bytes.len() % 8 != 0 {
        return Err(data_error(format!(
            "{what}: {} bytes are not a whole number of float64 values",
            bytes.len()
        )));
    }
    Ok(bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect())
}

/// The measured data of an identification, as the package passes them.
#[derive(FromPyObject)]
pub enum DataArg<'py> {
    /// A data file (CSV, MAT, UFF).
    File(PathBuf),
    /// A table: (label, time, column names, columns), the arrays as bytes.
    Table(
        (
            String,
            Bound<'py, PyBytes>,
            Vec<String>,
            Vec<Bound<'py, PyBytes>>,
        ),
    ),
}

impl DataArg<'_> {
    /// The data as Rust values (the table's arrays copied), which a worker
    /// thread may read; a table with a column named twice, or columns of
    /// other lengths than its time, is refused naming the column.
    pub fn source(&self) -> PyResult<Source> {
        match self {
            DataArg::File(path) => Ok(Source::File(path.clone())),
            DataArg::Table((label, time, names, columns)) => {
                if let Some((_, n)) = names
                    .iter()
                    .enumerate()
                    .find(|(i, n)| names[..*i].contains(n))
                {
                    return Err(data_error(format!(
                        "{label}: the column '{n}' appears twice"
                    )));
                }
                let table = TimeSeries {
                    time: f64_values(time.as_bytes(), "time")?,
                    names: names.clone(),
                    columns: names
                        .iter()
                        .zip(columns)
                        .map(|(n, c)| f64_values(c.as_bytes(), n))
                        .collect::<PyResult<_>>()?,
                };
                Ok(Source::Table(label.clone(), table))
            }
        }
    }
}
