//! Errors of reading measured data: each names the file, and the sensor
//! and its column, variable or record.
use crate::io::mat::MatError;
use crate::io::timeseries::DataError;
use crate::io::uff::UffError;
use std::path::PathBuf;

/// A problem reading measured data for a model.
#[derive(Debug, thiserror::Error)]
pub enum DataFileError {
    /// A problem with the CSV file.
    #[error(transparent)]
    Csv(#[from] DataError),
    /// A problem with the MAT-file as a whole, or its time axis.
    #[error(transparent)]
    Mat(#[from] MatError),
    /// A problem with the universal file as a whole.
    #[error(transparent)]
    Uff(#[from] UffError),
    /// A sensor's variable is missing or not a real numeric vector.
    #[error("sensor '{sensor}': {source}")]
    SensorVariable {
        /// The sensor.
        sensor: String,
        /// The cause (names the file and the variable).
        source: Box<MatError>,
    },
    /// A sensor's record is missing, ambiguous or complex.
    #[error("sensor '{sensor}': {source}")]
    SensorRecord {
        /// The sensor.
        sensor: String,
        /// The cause (names the file and the record).
        source: Box<UffError>,
    },
    /// An extension that names no supported format.
    #[error("{}: unknown data format '{extension}' (expected .csv, .mat, .uff, .unv or .58)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
        /// Its extension, or empty.
        extension: String,
    },
    /// Not one source per sensor (a programming error in the caller).
    #[error("{}: {sources} data sources for {sensors} sensors", path.display())]
    SourceCount {
        /// The file.
        path: PathBuf,
        /// Sources given.
        sources: usize,
        /// Sensors of the model.
        sensors: usize,
    },
    /// A sensor whose CSV column is missing.
    #[error("{}: no column {} (columns: {columns})", path.display(), missing(sensor, column))]
    MissingColumn {
        /// The file.
        path: PathBuf,
        /// The sensor.
        sensor: String,
        /// The column it reads.
        column: String,
        /// The columns present.
        columns: String,
    },
    /// A record number given for a file without numbered records.
    #[error("{}: sensor '{sensor}' reads record {record}, but only universal files (.uff, .unv, .58) have numbered records", path.display())]
    RecordNumber {
        /// The file.
        path: PathBuf,
        /// The sensor.
        sensor: String,
        /// The record number.
        record: usize,
    },
    /// A MAT-file without a time axis but with a variable that looks like
    /// one under another name, so that the samples' instants are ambiguous.
    #[error("{}: no time axis: the file needs a 'time' or 't' vector, or a 'sample_rate' or 'fs' scalar; variable '{candidate}' increases like a time axis under another name, so the samples cannot be taken on the model's grid from t = 0 (rename it 'time', or remove it) (variables: {variables})", path.display())]
    NoTimeAxis {
        /// The file.
        path: PathBuf,
        /// The variable that looks like a time axis.
        candidate: String,
        /// The variables present.
        variables: String,
    },
    /// A sample rate that is not one positive number.
    #[error("{}: variable '{name}' must be one positive sample rate in Hz, found {found}", path.display())]
    BadSampleRate {
        /// The file.
        path: PathBuf,
        /// The variable.
        name: String,
        /// What it holds.
        found: String,
    },
    /// A time axis that is not finite and strictly increasing.
    #[error("{}: time axis ({axis}): sample {index}: {message}", path.display())]
    BadTime {
        /// The file.
        path: PathBuf,
        /// Where the time axis comes from, e.g. `variable 'time'`.
        axis: String,
        /// 0-based sample.
        index: usize,
        /// What is wrong.
        message: String,
    },
    /// No samples at all.
    #[error("{}: no samples", path.display())]
    Empty {
        /// The file.
        path: PathBuf,
    },
    /// A signal of another length than the time axis.
    #[error("{}: sensor '{sensor}' ({source_desc}) has {found} samples, the time axis ({axis}) has {expected}", path.display())]
    Length {
        /// The file.
        path: PathBuf,
        /// The sensor.
        sensor: String,
        /// Its source, e.g. `variable 'acc_x'`.
        source_desc: String,
        /// Its samples.
        found: usize,
        /// The time axis's samples.
        expected: usize,
        /// Where the time axis comes from.
        axis: String,
    },
    /// A value that is not a finite number.
    #[error("{}: sensor '{sensor}' ({source_desc}): sample {index} is {value}, not a finite number", path.display())]
    NotFinite {
        /// The file.
        path: PathBuf,
        /// The sensor.
        sensor: String,
        /// Its source.
        source_desc: String,
        /// 0-based sample.
        index: usize,
        /// The value.
        value: f64,
    },
    /// A finite value so large that the criterion's squares would overflow:
    /// no measured signal is near [`MAX_DATA_MAGNITUDE`](super::MAX_DATA_MAGNITUDE).
    #[error("{}: sensor '{sensor}' ({source_desc}): sample {index} is {value:e}; measured values must be below {limit:e} in magnitude (SI units)", path.display())]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// The sensor.
        sensor: String,
        /// Its source.
        source_desc: String,
        /// 0-based sample.
        index: usize,
        /// The value.
        value: f64,
        /// The limit.
        limit: f64,
    },
    /// A universal-file record that is not a time signal.
    #[error("{}: sensor '{sensor}': record {record} ('{name}') has function type {function_type}, not a time response (1) or general function (0)", path.display())]
    NotTimeResponse {
        /// The file.
        path: PathBuf,
        /// The sensor.
        sensor: String,
        /// The record number.
        record: usize,
        /// Its ID line 1.
        name: String,
        /// Its function type.
        function_type: i64,
    },
    /// Two records with different abscissas.
    #[error("{}: records {first} and {other} have different time axes ({detail})", path.display())]
    AbscissaMismatch {
        /// The file.
        path: PathBuf,
        /// The record giving the time axis.
        first: usize,
        /// The record that differs.
        other: usize,
        /// How they differ.
        detail: String,
    },
}

fn missing(sensor: &str, column: &str) -> String {
    if sensor == column {
        format!("for sensor '{sensor}'")
    } else {
        format!("'{column}' for sensor '{sensor}'")
    }
}
