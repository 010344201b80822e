//! Measured data for a model from a CSV file, a MATLAB MAT-file or a
//! universal file (dataset 58), chosen by the file's extension.
//!
//! Each sensor reads one signal, given by a [`DataSource`] (from the model
//! file's optional `data = { … }` of the sensor; by default the signal named
//! like the sensor). The result is a [`TimeSeries`] whose columns are named
//! and ordered like the model's sensors, ready for
//! [`match_data`](crate::measurement::match_data). The same numbers in any
//! of the formats give the same time series, hence the same identification.
//!
//! The time axis: CSV, the `time` column; MAT-file, a `time` (or `t`)
//! vector, else `t_k = k / rate` from a `sample_rate` (or `fs`) scalar,
//! else the model's grid from t = 0, with a note ([`mat_time_axis`]);
//! universal file, the first sensor's record's abscissa
//! (`min + k · increment`, or the stored values), which every other
//! sensor's record must share. The axis must be finite and strictly
//! increasing, every signal as long as it and finite.
//!
//! A CSV may hold columns no sensor reads (a force channel, say) in any
//! order; they are listed in a note, so that a misspelt column does not pass
//! unnoticed. A MAT-file or universal file may hold other variables or
//! records.
mod error;
mod formats;
mod time_axis;

pub use error::DataFileError;
pub(crate) use time_axis::check_time_axis;
pub use time_axis::{mat_time_axis, MatTimeAxis};

use crate::io::timeseries::TimeSeries;
use crate::model::{DataSource, Model};
use std::path::Path;

/// The data formats, by file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DataFormat {
    /// `.csv`.
    Csv,
    /// `.mat`: MATLAB Level 5.
    Mat,
    /// `.uff`, `.unv`, `.58`: universal file, dataset 58.
    Uff,
}

impl DataFormat {
    /// The format of `path` by its extension (case-insensitive).
    pub fn of(path: &Path) -> Option<DataFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "csv" => DataFormat::Csv,
            "mat" => DataFormat::Mat,
            "uff" | "unv" | "58" => DataFormat::Uff,
            _ => return None,
        })
    }
}

/// Measured signals read from a file, with what the user should know about
/// the reading.
#[derive(Debug, Clone, PartialEq)]
pub struct DataRead {
    /// The signals, named and ordered like the model's sensors.
    pub series: TimeSeries,
    /// Notes for the user (columns ignored, say), each naming the file.
    pub notes: Vec<String>,
}

/// Reads the measured signals of `model`'s sensors from `path`;
/// `sources[i]` says where sensor `i`'s signal is (see
/// [`default_sources`](crate::model::default_sources)).
pub fn read_measurement(
    path: &Path,
    model: &Model,
    sources: &[DataSource],
) -> Result<DataRead, DataFileError> {
    one_source_per_sensor(path, model, sources)?;
    let raw = match DataFormat::of(path) {
        Some(DataFormat::Csv) => formats::csv(path, model, sources)?,
        Some(DataFormat::Mat) => formats::mat(path, model, sources)?,
        Some(DataFormat::Uff) => formats::uff(path, model, sources)?,
        None => {
            return Err(DataFileError::UnknownFormat {
                path: path.into(),
                extension: path
                    .extension()
                    .map(|e| format!(".{}", e.to_string_lossy()))
                    .unwrap_or_default(),
            })
        }
    };
    check(path, model, raw)
}

/// Reads the measured signals of `model`'s sensors from a table already in
/// memory (a data frame, say) with the checks of [`read_measurement`]'s CSV
/// files: `label` names the table in messages, its `time` is the axis, and
/// `sources[i]` names sensor `i`'s column (a record number is refused).
pub fn read_table(
    label: &Path,
    table: &TimeSeries,
    model: &Model,
    sources: &[DataSource],
) -> Result<DataRead, DataFileError> {
    one_source_per_sensor(label, model, sources)?;
    check(label, model, formats::table(label, table, model, sources)?)
}

/// One source per sensor of `model` (a caller's mistake otherwise).
fn one_source_per_sensor(
    path: &Path,
    model: &Model,
    sources: &[DataSource],
) -> Result<(), DataFileError> {
    match sources.len() == model.sensors.len() {
        true => Ok(()),
        false => Err(DataFileError::SourceCount {
            path: path.into(),
            sources: sources.len(),
            sensors: model.sensors.len(),
        }),
    }
}

/// Largest |value| a measured signal may have (SI units). Squares of larger
/// values, summed over a record, overflow the criterion (eq. 13); no real
/// acceleration, velocity or displacement comes near it.
pub const MAX_DATA_MAGNITUDE: f64 = 1e100;

/// The shared checks: a finite, strictly increasing time axis, and finite
/// signals as long as it.
fn check(path: &Path, model: &Model, raw: formats::Raw) -> Result<DataRead, DataFileError> {
    if raw.time.is_empty() {
        return Err(DataFileError::Empty { path: path.into() });
    }
    check_time_axis(path, &raw.axis, &raw.time)?;
    for ((sensor, col), origin) in model.sensors.iter().zip(&raw.columns).zip(&raw.origins) {
        if col.len() != raw.time.len() {
            return Err(DataFileError::Length {
                path: path.into(),
                sensor: sensor.name.clone(),
                source_desc: origin.clone(),
                found: col.len(),
                expected: raw.time.len(),
                axis: raw.axis.clone(),
            });
        }
        if let Some(k) = col.iter().position(|v| !v.is_finite()) {
            return Err(DataFileError::NotFinite {
                path: path.into(),
                sensor: sensor.name.clone(),
                source_desc: origin.clone(),
                index: k,
                value: col[k],
            });
        }
        if let Some(k) = col.iter().position(|v| v.abs() > MAX_DATA_MAGNITUDE) {
            return Err(DataFileError::TooLarge {
                path: path.into(),
                sensor: sensor.name.clone(),
                source_desc: origin.clone(),
                index: k,
                value: col[k],
                limit: MAX_DATA_MAGNITUDE,
            });
        }
    }
    Ok(DataRead {
        series: TimeSeries {
            time: raw.time,
            names: model.sensors.iter().map(|s| s.name.clone()).collect(),
            columns: raw.columns,
        },
        notes: raw.notes,
    })
}
