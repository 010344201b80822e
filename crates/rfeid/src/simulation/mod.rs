//! Simulation of the equations of motion (eq. 1) with forward sensitivities,
//! static equilibrium and modal analysis.
mod dim;
pub mod equilibrium;
mod madd;
pub mod modal;
pub mod run;
mod sines;
mod stepper;
pub mod structure;
pub mod system;
pub mod tableau;
mod tangent;

pub use run::{Integrator, Response, Sensitivities, Simulator, Workspace};

/// The default integration method.
pub const DEFAULT_TABLEAU: tableau::Tableau = tableau::DOP853;

/// Default integrator steps per sample interval.
pub const DEFAULT_SUBSTEPS: usize = 1;

/// Why a simulation failed. During identification such a point is recorded
/// as failed, never fatal.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimulationError {
    /// The state grew without bound or became NaN.
    #[error("the response diverged at t = {time:.6} s (state not finite or beyond 1e6)")]
    Diverged {
        /// Sample time at which it was detected, s.
        time: f64,
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
    /// Newton's method for the static equilibrium under gravity failed.
    #[error("no static equilibrium under gravity: {reason}")]
    NoEquilibrium {
        /// What went wrong.
        reason: String,
    },
}
