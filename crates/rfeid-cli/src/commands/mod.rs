//! One module per command.
pub mod check;
pub mod common;
pub mod modal;
pub mod simulate;
