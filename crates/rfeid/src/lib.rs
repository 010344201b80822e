//! rfeid: identification of nonlinear joint parameters in rigid-finite-element
//! models of machine-tool supporting systems.
pub mod identification;
pub mod io;
pub mod measurement;
pub mod model;
pub mod simulation;
