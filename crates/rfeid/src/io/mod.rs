//! Reading and writing files: model files, units, time series.
pub mod atomic;
pub mod model_file;
pub mod timeseries;
pub mod units;
