//! Integrator settings: the Runge–Kutta method and the steps per sample
//! ([`Integrator`], [`integrator`]), and the kernel that evaluates the
//! equations of motion ([`Kernel`]).
use super::tableau::Tableau;
use super::DEFAULT_TABLEAU;

/// Integrator settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Integrator {
    /// The Runge–Kutta method.
    pub tableau: Tableau,
    /// Steps per sample interval (≥ 1).
    pub substeps: usize,
    /// Split steps at the zero crossings of power-law deformations, where
    /// the force's second derivative jumps, so the method keeps its order.
    pub locate_crossings: bool,
}

/// Which kernel evaluates the equations of motion and their sensitivities.
/// Both give the same results to rounding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kernel {
    /// The one with fewer operations for the model's size (the default):
    /// dense for a few bodies, element by element for many.
    #[default]
    Auto,
    /// Dense matrices in register panels (`system`), fastest for a few bodies.
    Dense,
    /// Element by element (`sparse`): cost grows with the number of
    /// components, not with n².
    Sparse,
}

/// The integrator with `substeps` steps per sample and the default method.
pub fn integrator(substeps: usize) -> Integrator {
    Integrator {
        tableau: DEFAULT_TABLEAU,
        substeps,
        locate_crossings: true,
    }
}
