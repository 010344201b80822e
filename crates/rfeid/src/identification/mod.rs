//! Identification: LP_τ plan, local search and Cramér–Rao bounds (paper §3).
pub mod bfgs;
pub mod lm;
pub mod plan;
pub mod problem;
pub mod termination;
pub mod uncertainty;
