//! Identification: LP_τ plan, local search and Cramér–Rao bounds (paper §3).
//!
//! Everything here works on a generic least-squares problem
//! ([`problem::LeastSquares`]) in normalised coordinates `u ∈ [0, 1]^r`
//! (eq. 17) and knows nothing of models or simulators:
//!
//! - [`plan`] builds LP_τ (Sobol) plans (eq. 18–19) and [`plan_eval`]
//!   evaluates J (eq. 16) at their points in parallel;
//! - [`lm`] (Levenberg–Marquardt with the exact Jacobian) and [`bfgs`] (the
//!   paper's BFGS with finite-difference gradients, eq. 20–25) search locally
//!   inside the box, and end with a [`termination::StopReason`];
//! - [`uncertainty`] turns the Jacobian at the estimate into Cramér–Rao
//!   bounds (eq. 26–29) and identifiability warnings, and [`profile`] into
//!   profile likelihoods and their intervals;
//! - [`verdict`] says whether the result can be trusted, with every reason
//!   it cannot (bounds, distinct minima, convergence, fit, residual
//!   whiteness, identifiability).
pub mod bfgs;
pub mod blocked_qr;
pub mod box_map;
pub mod campaign;
pub mod cancel;
pub mod chi_square;
mod fd_gradient;
mod line_search;
pub mod lm;
mod lm_step;
pub mod noise;
pub mod option_error;
pub mod option_names;
pub mod options;
pub mod output_error;
pub mod pipeline;
pub mod plan;
pub mod plan_eval;
pub mod problem;
pub mod profile;
pub mod result;
pub mod search;
pub mod sensor_levels;
pub mod settings;
pub mod shard;
pub mod tally;
pub mod termination;
pub mod uncertainty;
pub mod validation;
pub mod verdict;
pub mod warning;
