//! Reading and writing files.
pub mod units;
