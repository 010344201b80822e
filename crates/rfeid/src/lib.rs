//! rfeid: identification of nonlinear joint parameters in rigid-finite-element
//! models of machine-tool supporting systems.
// `!(x > 0.0)` is used on purpose: unlike `x <= 0.0` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod identification;
pub mod io;
pub mod measurement;
pub mod model;
pub mod report;
pub mod simulation;
pub mod units;
