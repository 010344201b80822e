//! Measured data for a run: a data file (CSV, MAT, UFF) or a table in
//! memory (a data frame), read with the file's checks and put on the
//! model's sampling ([`match_data`]). `rfeid identify` and the Python
//! module's `identify` both read here.
use super::{match_data, MeasurementError};
use crate::io::data_file::{read_measurement, read_table, DataFileError};
use crate::io::timeseries::TimeSeries;
use crate::model::Model;
use crate::simulation::Response;
use std::path::{Path, PathBuf};

/// Why measured data cannot be used; names the file or table.
#[derive(Debug, thiserror::Error)]
pub enum MeasuredError {
    /// The file or table could not be read, or a signal is missing or bad.
    #[error(transparent)]
    Read(#[from] DataFileError),
    /// The signals do not fit the model's sampling.
    #[error("{}: {source}", path.display())]
    Match {
        /// The file or table.
        path: PathBuf,
        /// What does not fit.
        source: MeasurementError,
    },
}

/// Measured signals on the model's sampling, with notes for the user
/// (columns ignored, a record shifted or cut), each naming the source.
#[derive(Debug, Clone, PartialEq)]
pub struct Measured {
    /// The signals, in the model's sensor order.
    pub response: Response,
    /// The notes.
    pub notes: Vec<String>,
}

/// Reads `model`'s sensors' signals from the data file at `path`.
pub fn measured_from_file(path: &Path, model: &Model) -> Result<Measured, MeasuredError> {
    let sources: Vec<_> = model.sensors.iter().map(|s| s.data.clone()).collect();
    let read = read_measurement(path, model, &sources)?;
    matched(path, model, read.series, read.notes)
}

/// Reads `model`'s sensors' signals from a table in memory (a `time` axis
/// and named columns), with the checks of a CSV file; `label` names it.
pub fn measured_from_table(
    label: &Path,
    table: &TimeSeries,
    model: &Model,
) -> Result<Measured, MeasuredError> {
    let sources: Vec<_> = model.sensors.iter().map(|s| s.data.clone()).collect();
    let read = read_table(label, table, model, &sources)?;
    matched(label, model, read.series, read.notes)
}

/// The series on the model's sampling, the reading's notes first.
fn matched(
    path: &Path,
    model: &Model,
    series: TimeSeries,
    mut notes: Vec<String>,
) -> Result<Measured, MeasuredError> {
    let m = match_data(model, &series).map_err(|source| MeasuredError::Match {
        path: path.to_path_buf(),
        source,
    })?;
    notes.extend(
        m.notes
            .into_iter()
            .map(|n| format!("{}: {n}", path.display())),
    );
    Ok(Measured {
        response: m.response,
        notes,
    })
}

/// Reads `model`'s sensors' signals and one more, `force` (an excitation's
/// measured force, for an FRF's H1), from the data file at `path` on the
/// model's sampling, with the checks of [`measured_from_file`]: the
/// sensors' signals and the force's samples. A model without sensors
/// reads the force alone.
pub fn measured_with_force(
    path: &Path,
    model: &Model,
    force: &crate::model::DataSource,
) -> Result<(Measured, Vec<f64>), MeasuredError> {
    let mut with = model.clone();
    let probe = crate::model::Sensor {
        name: force.to_string(),
        body: 0,
        at: nalgebra::Vector3::zeros(),
        direction: nalgebra::Vector3::x(),
        kind: crate::model::SensorKind::Displacement,
        data: force.clone(),
        gain: crate::model::Value::Fixed(1.0),
        offset: crate::model::Value::Fixed(0.0),
        noise: None,
    };
    with.sensors.push(probe);
    let mut m = measured_from_file(path, &with)?;
    let r = &mut m.response;
    let force = r.values.split_off((r.n_sensors - 1) * r.n_samples);
    r.n_sensors -= 1;
    Ok((m, force))
}

/// Where measured data come from: a data file, or a table in memory with
/// the label that names it in messages (a data frame in the Python
/// module). Plain values, so a worker thread may read them.
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// A data file (CSV, MAT, UFF).
    File(PathBuf),
    /// A table in memory, and its label.
    Table(String, TimeSeries),
}

impl Source {
    /// The file, if the data are one.
    pub fn file(&self) -> Option<&Path> {
        match self {
            Source::File(p) => Some(p),
            Source::Table(..) => None,
        }
    }

    /// What names the data: the file, or the table's label.
    pub fn label(&self) -> String {
        match self {
            Source::File(p) => p.display().to_string(),
            Source::Table(label, _) => label.clone(),
        }
    }

    /// The signals on `model`'s sampling, with the reading's notes
    /// ([`measured_from_file`], [`measured_from_table`]).
    pub fn measured(&self, model: &Model) -> Result<Measured, MeasuredError> {
        match self {
            Source::File(path) => measured_from_file(path, model),
            Source::Table(label, table) => measured_from_table(Path::new(label), table, model),
        }
    }
}
