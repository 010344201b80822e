//! The signals of each format, before the shared checks: a time axis and
//! one vector per sensor, each with a description of where it came from.
use super::time_axis::mat_time_axis;
use super::DataFileError;
use crate::io::mat::read_mat_vectors;
use crate::io::timeseries::{read_csv, TimeSeries};
use crate::io::uff::{read_uff58, Abscissa, UffRecord};
use crate::model::Model;
use crate::model::{DataSource, RecordRef};
use std::path::Path;

/// Signals read from a file, not yet checked.
#[derive(Debug)]
pub struct Raw {
    /// Sample instants.
    pub time: Vec<f64>,
    /// Where the time axis comes from, for messages.
    pub axis: String,
    /// One vector per sensor, in the model's order.
    pub columns: Vec<Vec<f64>>,
    /// Where each came from, for messages.
    pub origins: Vec<String>,
    /// What the user should know about the file (columns ignored, say).
    pub notes: Vec<String>,
}

/// CSV: the `time` column and the sensors' columns, in any order; columns
/// no sensor reads (a force channel, say) are listed in a note.
pub fn csv(path: &Path, model: &Model, sources: &[DataSource]) -> Result<Raw, DataFileError> {
    table(path, &read_csv(path)?, model, sources)
}

/// A table already in memory (a CSV read, a data frame), `path` naming it
/// in messages: the sensors' columns, by name, in any order; columns no
/// sensor reads are listed in a note.
pub fn table(
    path: &Path,
    ts: &TimeSeries,
    model: &Model,
    sources: &[DataSource],
) -> Result<Raw, DataFileError> {
    let wanted: Vec<&str> = sources.iter().filter_map(DataSource::name).collect();
    let extra: Vec<&str> = ts
        .names
        .iter()
        .map(String::as_str)
        .filter(|c| !wanted.contains(c))
        .collect();
    let mut notes = Vec::new();
    if !extra.is_empty() {
        notes.push(format!(
            "{}: column{} {} read by no sensor, ignored",
            path.display(),
            if extra.len() == 1 { "" } else { "s" },
            extra
                .iter()
                .map(|c| format!("'{c}'"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    let mut raw = Raw {
        time: ts.time.clone(),
        axis: "column 'time'".into(),
        columns: Vec::new(),
        origins: Vec::new(),
        notes,
    };
    for (sensor, source) in model.sensors.iter().zip(sources) {
        let name = by_name(path, &sensor.name, source)?;
        let col = ts
            .column(name)
            .ok_or_else(|| DataFileError::MissingColumn {
                path: path.into(),
                sensor: sensor.name.clone(),
                column: name.to_string(),
                columns: ts.names.join(", "),
            })?;
        raw.columns.push(col.to_vec());
        raw.origins.push(format!("column '{name}'"));
    }
    Ok(raw)
}

/// MAT-file: the sensors' vectors; time from `time` or `t`, else
/// t_k = k / rate from `sample_rate` or `fs`, else the model's grid from
/// t = 0 with a note ([`mat_time_axis`]).
pub fn mat(path: &Path, model: &Model, sources: &[DataSource]) -> Result<Raw, DataFileError> {
    let file = read_mat_vectors(path)?;
    let mut columns = Vec::new();
    let mut origins = Vec::new();
    let mut read = Vec::new();
    for (sensor, source) in model.sensors.iter().zip(sources) {
        let name = by_name(path, &sensor.name, source)?;
        read.push(name);
        let v = file
            .require_vector(name)
            .map_err(|e| DataFileError::SensorVariable {
                sensor: sensor.name.clone(),
                source: Box::new(e),
            })?;
        columns.push(v.to_vec());
        origins.push(format!("variable '{name}'"));
    }
    let n = columns.first().map_or(0, Vec::len);
    let axis = mat_time_axis(&file, n, model.sampling.sample_rate, &read)?;
    Ok(Raw {
        time: axis.time,
        axis: axis.axis,
        columns,
        origins,
        notes: axis.note.into_iter().collect(),
    })
}

/// Universal file: the sensors' records (real, time response or general);
/// time from the first record's abscissa, which the others must share.
pub fn uff(path: &Path, model: &Model, sources: &[DataSource]) -> Result<Raw, DataFileError> {
    let file = read_uff58(path)?;
    let mut records: Vec<&UffRecord> = Vec::new();
    for (sensor, source) in model.sensors.iter().zip(sources) {
        let r = file.real_record(&source.record_ref()).map_err(|source| {
            DataFileError::SensorRecord {
                sensor: sensor.name.clone(),
                source: Box::new(source),
            }
        })?;
        if !matches!(r.function_type, 0 | 1) {
            return Err(DataFileError::NotTimeResponse {
                path: path.into(),
                sensor: sensor.name.clone(),
                record: r.number,
                name: r.name().into(),
                function_type: r.function_type,
            });
        }
        records.push(r);
    }
    let Some(first) = records.first() else {
        return Err(DataFileError::Empty { path: path.into() });
    };
    let time = first.abscissa.values();
    for r in &records[1..] {
        if let Some(detail) = abscissa_differs(&first.abscissa, &time, &r.abscissa) {
            return Err(DataFileError::AbscissaMismatch {
                path: path.into(),
                first: first.number,
                other: r.number,
                detail,
            });
        }
    }
    Ok(Raw {
        time,
        axis: format!("abscissa of record {}", first.number),
        columns: records.iter().map(|r| r.values.clone()).collect(),
        origins: records
            .iter()
            .map(|r| format!("record {} '{}'", r.number, r.name()))
            .collect(),
        notes: Vec::new(),
    })
}

/// How abscissa `b` differs from `a` (whose values are `xa`), if it does:
/// equal even spacings match exactly; otherwise the values must agree to
/// 10⁻⁶ of a sample interval.
fn abscissa_differs(a: &Abscissa, xa: &[f64], b: &Abscissa) -> Option<String> {
    if a == b {
        return None;
    }
    let xb = b.values();
    if xa.len() != xb.len() {
        return Some(format!("{} and {} points", xa.len(), xb.len()));
    }
    let step = match xa {
        [first, .., last] => (last - first) / (xa.len() - 1) as f64,
        _ => 0.0,
    };
    let tol = 1e-6 * step.abs();
    xa.iter()
        .zip(&xb)
        .position(|(p, q)| !((p - q).abs() <= tol))
        .map(|k| format!("point {k} is at {} and {}", xa[k], xb[k]))
}

/// The name a source reads in a CSV or MAT-file.
fn by_name<'s>(
    path: &Path,
    sensor: &str,
    source: &'s DataSource,
) -> Result<&'s str, DataFileError> {
    if let DataSource::Record(RecordRef::Index(n)) = source {
        return Err(DataFileError::RecordNumber {
            path: path.into(),
            sensor: sensor.into(),
            record: *n,
        });
    }
    Ok(source.name().unwrap_or_default())
}
