//! The warnings of an identification, as values: what the run noticed that
//! does not by itself make the result suspect (the verdict says that), in
//! the order they arose. RESULT.json lists them in words.
use super::verdict::Reason;
use serde::{Deserialize, Serialize};
use std::fmt;

/// One warning of an identification.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(into = "String", from = "String")]
pub enum Warning {
    /// An identifiability warning of the Cramér–Rao analysis (eq. 26–29),
    /// worded as the verdict's reason.
    Identifiability(Reason),
    /// No local search from the plan ended where the fit passes the
    /// verdict's per-sensor checks, so automatic restarts ran.
    SideMinimum {
        /// The lowest J the searches from the plan reached.
        first_cost: f64,
        /// Restarts run.
        restarts: usize,
        /// The lowest J of an end that passes, if a restart found one (the
        /// side minima are then left out of the result).
        found: Option<f64>,
        /// Whether the restarts stopped because two came back to the lowest
        /// minimum (the model's best fit).
        agreed: bool,
    },
    /// No end passed the fit checks, and no restart ran: the bounds at the
    /// best end show that these parameters cannot be told apart, which no
    /// restart changes (the verdict names the combinations the data fix).
    RidgeNotRestarted {
        /// The lowest J the searches from the plan reached.
        first_cost: f64,
        /// The parameters that cannot be told apart.
        parameters: Vec<String>,
    },
    /// Fixed steps per sample whose estimated error at the estimate exceeds
    /// the tolerance.
    StepsTooCoarse {
        /// Steps per sample.
        substeps: usize,
        /// Estimated relative error.
        error: f64,
        /// The tolerance.
        tolerance: f64,
    },
    /// The simulation's accuracy at the estimate could not be checked.
    StepsUnchecked(crate::simulation::SimulationError),
    /// A mode above the Nyquist frequency at the estimate (the simulation
    /// module's words).
    AboveNyquist(String),
    /// A start's search on the first part of the record
    /// ([`crate::identification::pipeline::Settings::window`]) could not
    /// run; that start searched the whole record from where it was.
    WindowFailed {
        /// The fraction of the record.
        fraction: f64,
        /// Why.
        reason: super::termination::SolveError<crate::simulation::SimulationError>,
    },
    /// A warning read back from a RESULT.json, in its words.
    Recorded(String),
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::Identifiability(r) => r.fmt(f),
            Warning::SideMinimum {
                first_cost,
                restarts,
                found: Some(best),
                ..
            } => write!(
                f,
                "the local search from the plan ended at J = {first_cost:.6e}, where the fit \
                 fails the verdict's per-sensor checks (a side minimum); {restarts} automatic \
                 restart(s) from the next-best distinct plan points found J = {best:.6e}, where \
                 it passes; the side minima are left out of the result"
            ),
            Warning::SideMinimum {
                first_cost,
                restarts,
                found: None,
                agreed: true,
            } => write!(
                f,
                "the local search from the plan ended at J = {first_cost:.6e}, where the fit fails \
                 the verdict's per-sensor checks; {restarts} automatic restart(s) from the \
                 next-best distinct plan points came back to the lowest minimum, so the \
                 restarts stopped: it is the model's best fit"
            ),
            Warning::SideMinimum {
                first_cost,
                restarts,
                found: None,
                agreed: false,
            } => write!(
                f,
                "the local search from the plan ended at J = {first_cost:.6e}, where the fit fails \
                 the verdict's per-sensor checks, and {restarts} automatic restart(s) from the \
                 next-best distinct plan points found no minimum where it passes"
            ),
            Warning::RidgeNotRestarted {
                first_cost,
                parameters,
            } => write!(
                f,
                "the local search from the plan ended at J = {first_cost:.6e}, where the fit fails \
                 the verdict's per-sensor checks; no automatic restart ran, because the bounds \
                 there show that {} cannot be told apart (a ridge of the criterion), which no \
                 restart changes: fix one of them (--set) or add a test that separates them",
                parameters.join(", ")
            ),
            Warning::StepsTooCoarse {
                substeps,
                error,
                tolerance,
            } => write!(
                f,
                "the fixed {substeps} step(s) per sample give an estimated relative error of \
                 {error:.2e} at the estimate, more than the tolerance {tolerance:.1e}; leave \
                 `substeps` unset to have them chosen"
            ),
            Warning::StepsUnchecked(e) => write!(
                f,
                "the simulation's accuracy at the estimate could not be checked: {e}"
            ),
            Warning::WindowFailed { fraction, reason } => write!(
                f,
                "a start's search on the first {:.0} % of the record failed ({reason}); it \
                 searched the whole record from its plan point instead",
                fraction * 100.0
            ),
            Warning::AboveNyquist(text) | Warning::Recorded(text) => f.write_str(text),
        }
    }
}

impl From<Warning> for String {
    fn from(w: Warning) -> String {
        w.to_string()
    }
}

impl From<String> for Warning {
    fn from(text: String) -> Warning {
        Warning::Recorded(text)
    }
}
