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
    /// Fewer steps per sample, among those checked, whose estimated error
    /// is within [`search_tolerance`]`(tolerance)`: what the plan and the
    /// searches take before the estimate is refined at `substeps` (see
    /// [`crate::simulation::steps`], "Searches"); `None` if no checked
    /// count below `substeps` met it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub search: Option<SearchSteps>,
}

/// Steps per sample that a search may take ([`StepChoice::search`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SearchSteps {
    /// Integrator steps per sample interval.
    pub substeps: usize,
    /// Their estimated relative RMS error (at most [`search_tolerance`]).
    pub estimated_error: f64,
}

/// The looser tolerance of the steps a search takes for a simulation
/// tolerance `tolerance`: 100 times it, but at most 10⁻⁴ (and never
/// tighter than `tolerance`). A search only has to rank plan points and
/// find the basin; the error of its responses stays far below any
/// sensor's noise, and the end is refined at the full tolerance.
pub fn search_tolerance(tolerance: f64) -> f64 {
    (100.0 * tolerance).min(1e-4).max(tolerance)
}
