//! One module per command.
pub mod campaign;
pub mod check;
pub mod common;
pub mod demo;
pub mod identify;
pub mod merge;
pub mod modal;
pub mod report;
pub mod shard;
pub mod simulate;
pub mod validate;
