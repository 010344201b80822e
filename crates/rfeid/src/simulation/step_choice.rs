//! How the steps per sample were chosen ([`StepChoice`]); the choice itself
//! is in `steps`.
use serde::{Deserialize, Serialize};

/// How the steps per sample were chosen, and how accurate they are.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StepChoice {
    /// Integrator steps per sample interval.
    pub substeps: usize,
    /// Whether they were chosen from the tolerance (false: fixed by the
    /// model's or the command line's `substeps`).
    pub automatic: bool,
    /// The tolerance aimed at (relative RMS error).
    pub tolerance: f64,
    /// The estimated relative RMS error of the simulated signals (largest
    /// over the sensors) where it was last checked; `None` if not estimated.
    pub estimated_error: Option<f64>,
    /// Simulations the choice and the estimate took, counting for each
    /// step count checked the run and its check at twice the steps (a
    /// long record's check windows together as one).
    #[serde(default)]
    pub runs: usize,
}
