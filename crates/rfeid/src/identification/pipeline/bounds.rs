//! Stage 7, the bounds: Cramér–Rao standard errors and correlations
//! (eq. 26–29) from the exact Jacobian at the estimate, whole or, for a
//! long record, as its triangular factor built block by block.
use crate::identification::blocked_qr::BlockedQr;
use crate::identification::output_error::OutputError;
use crate::identification::problem::{sum_of_squares, LeastSquares};
use crate::identification::search::Linearised;
use crate::identification::uncertainty::{
    cramer_rao_blocked, cramer_rao_mapped, CramerRao, UncertaintyError, UncertaintySettings,
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

impl BoundsError {
    /// The error in words, the parameters by name (the library's error
    /// counts them by index): RESULT.json's `uncertainty_error` and the
    /// verdict's reason.
    pub(super) fn describe(&self, names: &[String]) -> String {
        match self {
            BoundsError::Analysis(UncertaintyError::Singular {
                parameters,
                condition_number,
            }) => {
                let named: Vec<&str> = parameters.iter().map(|&j| names[j].as_str()).collect();
                format!(
                    "the Fisher matrix is singular (scaled condition number {condition_number:e}): {} cannot be told apart from the data",
                    named.join(", ")
                )
            }
            other => other.to_string(),
        }
    }
}

/// The bounds at the estimate, and s² (eq. 29) when the residuals could be
/// evaluated.
pub(super) struct Bounds {
    /// Standard errors, correlations, identifiability warnings.
    pub cramer_rao: Result<CramerRao, BoundsError>,
    /// s² = SSR/(N − r − 1), weighted like J.
    pub s2: Option<f64>,
}

/// The bounds at `u`, from the Jacobian a search ended with there
/// (`linearised`) if the criterion's residuals at `u` are still its
/// residuals bit for bit (same weights, whitening and steps), otherwise
/// from a simulation with sensitivities.
pub(super) fn at(
    problem: &OutputError<'_>,
    u: &[f64],
    linearised: Option<&Linearised>,
    settings: &UncertaintySettings,
) -> Bounds {
    let (n, r) = (problem.n_residuals(), problem.n_params());
    let mut ws = problem.workspace();
    let mut res = vec![0.0; n];
    let dx_du = problem.dx_du(u);
    if let Some(l) = linearised {
        let same = problem.residuals(&mut ws, u, &mut res).is_ok()
            && res
                .iter()
                .zip(&l.residuals)
                .all(|(a, b)| a.to_bits() == b.to_bits());
        if same && l.jacobian.shape() == (n, r) {
            let ssr = sum_of_squares(&res);
            let bounds = cramer_rao_mapped(&l.jacobian, ssr, &dx_du, problem.widths(), settings);
            return Bounds {
                cramer_rao: bounds.map_err(BoundsError::Analysis),
                s2: Some(ssr / (n - r - 1) as f64),
            };
        }
    }
    let analysis = if problem.jacobian_by_blocks() {
        let mut qr = BlockedQr::new(r);
        problem
            .residuals_factor(&mut ws, u, &mut res, &mut qr)
            .map(|()| {
                let ssr = sum_of_squares(&res);
                let bounds = cramer_rao_blocked(&qr, ssr, &dx_du, problem.widths(), settings);
                (bounds, ssr)
            })
    } else {
        let mut jac = DMatrix::zeros(n, r);
        problem
            .residuals_jacobian(&mut ws, u, &mut res, &mut jac)
            .map(|()| {
                let ssr = sum_of_squares(&res);
                let bounds = cramer_rao_mapped(&jac, ssr, &dx_du, problem.widths(), settings);
                (bounds, ssr)
            })
    };
    match analysis {
        Err(e) => Bounds {
            cramer_rao: Err(BoundsError::Simulation(e)),
            s2: None,
        },
        Ok((cramer_rao, ssr)) => Bounds {
            cramer_rao: cramer_rao.map_err(BoundsError::Analysis),
            s2: Some(ssr / (n - r - 1) as f64),
        },
    }
}
