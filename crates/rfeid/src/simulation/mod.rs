//! Simulation of the equations of motion (eq. 1) with forward sensitivities,
//! static equilibrium and modal analysis.
pub mod aliasing;
mod aligned;
mod calibration;
mod columns;
mod dim;
mod envelope;
pub mod equilibrium;
mod force_derivative;
mod integrator;
mod madd;
pub mod modal;
mod power_law;
mod preload;
mod response;
pub mod run;
mod simulate;
mod simulator;
mod sines;
mod sparse;
mod sparse_tangent;
mod step_choice;
mod stepper;
pub mod steps;
pub mod structure;
pub mod system;
pub mod tableau;
mod tangent;
#[cfg(test)]
mod test_models;
mod workspace;

pub use integrator::{Integrator, Kernel};
pub use response::{Response, Sensitivities};
pub use simulator::Simulator;
pub use step_choice::StepChoice;
pub use workspace::Workspace;

/// The default integration method.
pub const DEFAULT_TABLEAU: tableau::Tableau = tableau::DOP853;

/// The most integrator steps per sample interval, fixed or automatic.
pub const MAX_SUBSTEPS: usize = 1000;

/// Default `[simulation] tolerance`: the relative RMS error of the simulated
/// signals that the automatic steps aim at ([`steps`]). The step-doubling
/// estimate is the error of the coarser run itself, so this keeps a 10×
/// margin to the 1e-6 the benchmark asks for: measured, the knee–column is
/// within 2.0e-9 to 1.2e-8 of an independent reference at 10, 5, 2 and
/// 1 kHz (`tests/knee_column_reference.rs`), and a 50-body machine tool at
/// 10 kHz within 1.9e-8 of 16 steps per sample.
pub const DEFAULT_TOLERANCE: f64 = 1e-7;

/// The tolerances accepted.
pub const TOLERANCE_RANGE: std::ops::RangeInclusive<f64> = 1e-13..=1e-2;

/// Describes the fastest mode for an error message.
fn fastest_mode_text(fastest_hz: &Option<f64>, sample_rate: f64, substeps: usize) -> String {
    match fastest_hz {
        Some(f) => format!(
            "; the model's fastest mode (linearised at rest) is at {f:.4} Hz, ωh = {:.3} at \
             {substeps} step(s) per sample of {sample_rate} Hz",
            2.0 * std::f64::consts::PI * f / (sample_rate * substeps as f64)
        ),
        None => String::new(),
    }
}

/// What to do about a divergence, by whether `substeps` was fixed.
fn divergence_advice(fixed: bool) -> &'static str {
    match fixed {
        true => {
            "steps that long are unstable for it: leave `substeps` unset so that steps are \
             chosen from `tolerance`, or raise `substeps`"
        }
        false => {
            "the steps chosen for `tolerance` are unstable at these parameter values: a \
             smaller `tolerance` takes more steps per sample, or fix `substeps`"
        }
    }
}

/// Why a simulation failed. During identification such a point is recorded
/// as failed, never fatal.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimulationError {
    /// The state grew without bound or became NaN.
    #[error(
        "the response diverged at t = {time:.6} s (state not finite or beyond 1e6){}; {}; \
         a mode far above the sample rate may also be an unintended stiffness (see `rfeid modal`)",
        fastest_mode_text(fastest_hz, *sample_rate, *substeps),
        divergence_advice(*fixed)
    )]
    Diverged {
        /// Sample time at which it was detected, s.
        time: f64,
        /// The highest natural frequency of the model linearised at rest at
        /// these parameter values, Hz, if the modal analysis succeeded.
        fastest_hz: Option<f64>,
        /// The sample rate, Hz.
        sample_rate: f64,
        /// Integrator steps per sample.
        substeps: usize,
        /// Whether the model fixed them (`substeps`), rather than
        /// `tolerance` choosing them.
        fixed: bool,
    },
    /// No number of steps per sample up to [`MAX_SUBSTEPS`] meets the tolerance.
    #[error(
        "{substeps} steps per sample give an estimated relative error of {estimate:.2e}, more \
         than the tolerance {tolerance:.1e}{}; raise `tolerance`, or check for an unintended \
         stiffness (see `rfeid modal`)",
        fastest_mode_text(fastest_hz, *sample_rate, *substeps)
    )]
    Inaccurate {
        /// The most steps tried.
        substeps: usize,
        /// Their estimated relative RMS error.
        estimate: f64,
        /// The tolerance.
        tolerance: f64,
        /// The model's fastest mode at rest, Hz.
        fastest_hz: Option<f64>,
        /// The sample rate, Hz.
        sample_rate: f64,
    },
    /// A parameter value is not a finite number.
    #[error("parameter '{name}' is not finite ({value})")]
    BadParameter {
        /// Parameter name.
        name: String,
        /// Its value.
        value: f64,
    },
    /// A mass or moment of inertia is not positive.
    #[error("body '{body}' has a non-positive mass or moment of inertia ({value})")]
    NonPositiveInertia {
        /// Body name.
        body: String,
        /// The offending value.
        value: f64,
    },
    /// A power-law exponent below 1.
    #[error("element '{element}' has a power-law exponent m = {value} < 1")]
    BadExponent {
        /// Element name.
        element: String,
        /// The exponent.
        value: f64,
    },
    /// The run it belonged to was cancelled
    /// ([`crate::identification::cancel::Cancel`]); nothing was simulated.
    #[error("cancelled")]
    Cancelled,
    /// Newton's method for the static equilibrium under gravity failed.
    #[error("no static equilibrium under gravity: {reason}")]
    NoEquilibrium {
        /// What went wrong.
        reason: String,
    },
}

impl SimulationError {
    /// Whether the failure comes from parameter values the model cannot
    /// take (not finite, a non-positive mass, an exponent below 1): the
    /// input's fault, where the other failures (divergence, no step
    /// meeting the tolerance, no equilibrium) are the computation's.
    pub fn is_bad_values(&self) -> bool {
        matches!(
            self,
            SimulationError::BadParameter { .. }
                | SimulationError::NonPositiveInertia { .. }
                | SimulationError::BadExponent { .. }
        )
    }
}
