//! Reading and writing files: model files, time series, and measured
//! data as CSV, MATLAB MAT-files or Universal File Format dataset 58.
pub mod atomic;
pub mod data_file;
pub mod digest;
pub mod mat;
pub mod model_file;
pub mod report_dir;
pub mod shard_file;
#[cfg(test)]
mod shard_fuzz;
pub mod timeseries;
pub mod uff;
