//! Stage 6, the bounds: Cramér–Rao standard errors and correlations
//! (eq. 26–29) from the exact Jacobian at the estimate.
use crate::identification::output_error::OutputError;
use crate::identification::problem::{sum_of_squares, LeastSquares};
use crate::identification::uncertainty::{
    cramer_rao_mapped, CramerRao, UncertaintyError, UncertaintySettings,
};
use crate::simulation::SimulationError;
use nalgebra::DMatrix;

/// Why the bounds could not be computed.
#[derive(Debug, Clone, thiserror::Error)]
pub(super) enum BoundsError {
    /// The simulation with sensitivities failed at the estimate.
    #[error("the simulation at the estimate failed: {0}")]
    Simulation(SimulationError),
    /// The Fisher matrix could not be inverted, or the problem is too small.
    #[error(transparent)]
    Analysis(UncertaintyError),
}

/// The bounds at the estimate, and s² (eq. 29) when the residuals could be
/// evaluated.
pub(super) struct Bounds {
    /// Standard errors, correlations, identifiability warnings.
    pub cramer_rao: Result<CramerRao, BoundsError>,
    /// s² = SSR/(N − r − 1), weighted like J.
    pub s2: Option<f64>,
}

/// The bounds at `u`.
pub(super) fn at(problem: &OutputError<'_>, u: &[f64], settings: &UncertaintySettings) -> Bounds {
    let (n, r) = (problem.n_residuals(), problem.n_params());
    let mut ws = problem.workspace();
    let mut res = vec![0.0; n];
    let mut jac = DMatrix::zeros(n, r);
    if let Err(e) = problem.residuals_jacobian(&mut ws, u, &mut res, &mut jac) {
        return Bounds {
            cramer_rao: Err(BoundsError::Simulation(e)),
            s2: None,
        };
    }
    let ssr = sum_of_squares(&res);
    let dx_du = problem.dx_du(u);
    Bounds {
        cramer_rao: cramer_rao_mapped(&jac, ssr, &dx_du, problem.widths(), settings)
            .map_err(BoundsError::Analysis),
        s2: Some(ssr / (n - r - 1) as f64),
    }
}
