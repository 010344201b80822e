//! Simulation of the equations of motion (eq. 1) with forward sensitivities,
//! static equilibrium and modal analysis.
pub mod aliasing;
mod aligned;
mod blocks;
mod calibration;
mod columns;
mod contact_events;
mod crossings;
mod dim;
mod envelope;
pub mod equilibrium;
mod force_derivative;
#[cfg(test)]
mod forces_tests;
pub mod free;
mod integrator;
mod lanczos;
mod law_rows;
pub mod laws;
mod madd;
pub mod modal;
mod preload;
mod response;
pub mod run;
mod simulate;
mod simulator;
mod sines;
mod sparse;
mod sparse_tangent;
mod split_column;
mod split_shifts;
mod stage_sums;
mod step_choice;
mod step_error;
mod step_windows;
mod stepper;
pub mod steps;
pub mod structure;
pub mod system;
mod system_matrices;
pub mod tableau;
mod tangent;
#[cfg(test)]
mod test_models;
mod unbounded;
mod workspace;

pub use blocks::Block;
pub use integrator::{Integrator, Kernel};
pub use response::{Response, Sensitivities};
pub use run::{SampleState, SampleView, Span};
pub use simulator::Simulator;
pub use step_choice::{search_tolerance, SearchSteps, StepChoice};
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

/// What a friction key must be.
fn friction_rule(key: &str) -> &'static str {
    match key {
        "smoothing" | "vs" => "a velocity scale must be positive",
        _ => "a friction force must not be negative",
    }
}

/// A generalized force's size to four significant digits, in N or N·m.
fn load_text(load: f64, moment: bool) -> String {
    let (unit, v) = (if moment { "N·m" } else { "N" }, load.abs());
    if (1e-3..1e6).contains(&v) {
        let decimals = (3 - v.log10().floor() as i32).max(0) as usize;
        format!("{v:.decimals$} {unit}")
    } else {
        format!("{v:.3e} {unit}")
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
        /// The largest |state| (m, rad, m/s) when it was detected; infinite
        /// if a value was not finite.
        magnitude: f64,
    },
    /// The state passed the divergence bound at the same sample, along the
    /// same path, at `substeps` and at `finer` steps per sample: the
    /// model's response at these parameter values grows beyond every bound
    /// (or at least beyond 1e6), which no step choice cures (the private
    /// `unbounded` module says how the two are told apart).
    #[error(
        "the response grows without bound at these parameter values: the state passes 1e6 \
         (m, rad, m/s) at t = {time:.6} s alike at {substeps} and {finer} steps per sample, \
         along the same path, so it is the model's motion, not the integrator's steps: a \
         smaller `tolerance` or more `substeps` will not help; check the values (a force's \
         size, or a law that feeds energy in: a negative stiffness or damping, Bouc–Wen's \
         beta, gamma and d)"
    )]
    Unbounded {
        /// Sample time at which both runs passed the bound, s.
        time: f64,
        /// Integrator steps per sample of the first run.
        substeps: usize,
        /// Those of the finer run.
        finer: usize,
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
    /// A friction law with a negative force or a velocity scale that is not
    /// positive.
    #[error(
        "element '{element}' has a friction law with {key} = {value}: {}",
        friction_rule(key)
    )]
    BadFriction {
        /// Element name.
        element: String,
        /// The key (`f`, `f_neg`, `fs`, `smoothing`, `vs`).
        key: &'static str,
        /// Its value.
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
    /// Gravity pulls along a direction no spring restrains
    /// ([`free`]): the weights would accelerate it for ever, so no static
    /// equilibrium exists.
    #[error(
        "no static equilibrium under gravity: {direction} (no spring restrains it), and the \
         weights pull along it with {}; add a spring along it (a component with k, or a \
         friction law's k), or make gravity perpendicular to it",
        load_text(*load, *moment)
    )]
    FreeUnderGravity {
        /// The first body that moves in that direction.
        body: String,
        /// The free direction as a sentence, e.g. `carriage is free along x`.
        direction: String,
        /// The weights' generalized force along it.
        load: f64,
        /// Whether that is a moment (N·m, a rotation) rather than a force (N).
        moment: bool,
    },
}

impl SimulationError {
    /// Whether the failure comes from parameter values the model cannot
    /// take (not finite, a non-positive mass, an exponent below 1, gravity
    /// along a free direction): the
    /// input's fault, where the other failures (divergence, no step
    /// meeting the tolerance, no equilibrium) are the computation's.
    pub fn is_bad_values(&self) -> bool {
        matches!(
            self,
            SimulationError::BadParameter { .. }
                | SimulationError::NonPositiveInertia { .. }
                | SimulationError::BadExponent { .. }
                | SimulationError::FreeUnderGravity { .. }
                | SimulationError::BadFriction { .. }
        )
    }
}
