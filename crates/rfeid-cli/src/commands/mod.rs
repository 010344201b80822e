//! One module per command, each thin over the shared layer
//! ([`crate::run`]); no command imports another.
pub mod check;
pub mod demo;
pub mod design;
pub mod frf;
pub mod identify;
pub mod merge;
pub mod modal;
pub mod report;
pub mod simulate;
pub mod validate;
