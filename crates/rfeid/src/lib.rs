//! rfeid: identification of nonlinear joint parameters in rigid-finite-element
//! models of machine-tool supporting systems.
//!
//! # A tour
//!
//! The modules stack in floors: [`model`] is the ground floor (the domain,
//! units and data sources included); [`simulation`] builds on the model;
//! [`io`] and [`measurement`] read files into models and responses;
//! [`identification`] builds on the simulation and the measurements; and
//! [`report`] draws what an identification found.
//!
//! | module | does |
//! | --- | --- |
//! | [`model`] | the validated model: bodies, spring–damping elements and their laws (eq. 1–9), sensors, loads, parameters with boxes, experiments |
//! | [`simulation`] | the equations of motion (eq. 1) integrated on the sample grid with forward sensitivities; static equilibrium; modal analysis; the steps per sample |
//! | [`measurement`] | measured signals matched to the model's sensors and sampling; seeded noise |
//! | [`identification`] | the output-error criterion (eq. 10–16), LP_τ plans (eq. 18–19), local searches, Cramér–Rao bounds (eq. 26–29), the verdict, and the [`identification::pipeline`] that runs them as stages |
//! | [`io`] | files: model files (TOML with units), data files (CSV, MAT, UFF 58), atomic writes |
//! | [`report`] | the HTML report and its SVG figures |
//! | [`design`] | experiment design: predicted standard errors of a planned test, D-optimal sensor choice (SPEC §6) |
//!
//! # The data's path
//!
//! 1. [`io::model_file::load_model`] reads a model file into a
//!    [`model::Model`]; [`io::data_file::read_measurement`] and
//!    [`measurement::match_data`] turn a data file into a
//!    [`simulation::Response`] on the model's sampling.
//! 2. A [`simulation::Simulator`] of the model and the measured response
//!    make an [`identification::output_error::OutputError`]: J(u) over the
//!    normalised box, a [`identification::problem::LeastSquares`] problem
//!    whose residuals and exact Jacobian come from the simulator's forward
//!    sensitivities.
//! 3. [`identification::pipeline::identify`] runs the stages: the plan, the
//!    starts' local searches ([`identification::search::LocalSearch`]:
//!    Levenberg–Marquardt or BFGS), the noise weights, the restarts, the
//!    accuracy check, the bounds and the verdict. Between stages pass
//!    values: a [`identification::search::SearchOutcome`] per search, a
//!    [`identification::tally::Tally`] of the simulations counted where
//!    they run, typed [`identification::warning::Warning`]s.
//! 4. The [`identification::result::IdentificationResult`] is RESULT.json;
//!    [`report::write_report`] draws it.
// `!(x > 0.0)` is used on purpose: unlike `x <= 0.0` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod design;
pub mod error_kind;
pub mod frf;
pub mod identification;
pub mod io;
pub mod measurement;
pub mod model;
pub mod report;
pub mod simulation;
pub mod units;
