//! Stage 7, the bounds: Cramér–Rao standard errors and correlations
//! (eq. 26–29) from the exact Jacobian at the estimate, whole or, for a
//! long record, as its triangular factor built block by block. With equal
//! weights and several sensors, the covariance takes each sensor's own
//! noise level ([`crate::identification::sensor_levels`]).
use crate::identification::blocked_qr::BlockedQr;
use crate::identification::output_error::OutputError;
use crate::identification::problem::{sum_of_squares, LeastSquares};
use crate::identification::search::Linearised;
use crate::identification::sensor_levels::{with_sensor_levels, SensorRows};
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
/// from a simulation with sensitivities. `sensor_levels`: the covariance
/// takes each sensor's own noise level (equal weights), not eq. 26's one
/// s².
pub(super) fn at(
    problem: &OutputError<'_>,
    u: &[f64],
    linearised: Option<&Linearised>,
    settings: &UncertaintySettings,
    sensor_levels: bool,
) -> Bounds {
    let (n, r) = (problem.n_residuals(), problem.n_params());
    let mut ws = problem.workspace();
    let mut res = vec![0.0; n];
    let dx_du = problem.dx_du(u);
    let levels = sensor_levels && problem.weights().len() > 1;
    let finish = |bounds: Result<CramerRao, UncertaintyError>, sensors: Option<Vec<SensorRows>>| {
        bounds
            .map_err(BoundsError::Analysis)
            .map(|b| match sensors {
                Some(rows) => with_sensor_levels(b, &rows, &dx_du, problem.widths(), settings),
                None => b,
            })
    };
    if let Some(l) = linearised {
        let same = problem.residuals(&mut ws, u, &mut res).is_ok()
            && res
                .iter()
                .zip(&l.residuals)
                .all(|(a, b)| a.to_bits() == b.to_bits());
        if same && l.jacobian.shape() == (n, r) {
            let ssr = sum_of_squares(&res);
            let bounds = cramer_rao_mapped(&l.jacobian, ssr, &dx_du, problem.widths(), settings);
            let sensors =
                levels.then(|| SensorRows::split(&l.jacobian, &res, &problem.weight_samples()));
            return Bounds {
                cramer_rao: finish(bounds, sensors),
                s2: Some(ssr / (n - r - 1) as f64),
            };
        }
    }
    let analysis = if problem.jacobian_by_blocks() {
        let mut qr = BlockedQr::new(r);
        problem
            .residuals_factor(&mut ws, u, &mut res, &mut qr)
            .and_then(|()| {
                let ssr = sum_of_squares(&res);
                let bounds = cramer_rao_blocked(&qr, ssr, &dx_du, problem.widths(), settings);
                let sensors = match levels && bounds.is_ok() {
                    true => Some(sensor_factors(problem, u, &res)?),
                    false => None,
                };
                Ok((bounds, sensors, ssr))
            })
    } else {
        let mut jac = DMatrix::zeros(n, r);
        problem
            .residuals_jacobian(&mut ws, u, &mut res, &mut jac)
            .map(|()| {
                let ssr = sum_of_squares(&res);
                let bounds = cramer_rao_mapped(&jac, ssr, &dx_du, problem.widths(), settings);
                let sensors =
                    levels.then(|| SensorRows::split(&jac, &res, &problem.weight_samples()));
                (bounds, sensors, ssr)
            })
    };
    match analysis {
        Err(e) => Bounds {
            cramer_rao: Err(BoundsError::Simulation(e)),
            s2: None,
        },
        Ok((cramer_rao, sensors, ssr)) => Bounds {
            cramer_rao: finish(cramer_rao, sensors),
            s2: Some(ssr / (n - r - 1) as f64),
        },
    }
}

/// Each sensor's rows of a Jacobian taken by blocks: the sensor's alone
/// (the others weighted 0), one simulation with sensitivities each, as
/// the Gram matrix of their triangular factor; their residuals from `res`,
/// the whole criterion's at `u`.
fn sensor_factors(
    problem: &OutputError<'_>,
    u: &[f64],
    res: &[f64],
) -> Result<Vec<SensorRows>, SimulationError> {
    let (weights, counts) = (problem.weights(), problem.weight_samples());
    let mut one = problem.clone();
    let mut ws = problem.workspace();
    let mut scratch = vec![0.0; res.len()];
    let mut qr = BlockedQr::new(problem.n_params());
    let mut start = 0;
    let mut sensors = Vec::with_capacity(weights.len());
    for (c, &rows) in counts.iter().enumerate() {
        let alone: Vec<f64> = (0..weights.len())
            .map(|k| if k == c { weights[k] } else { 0.0 })
            .collect();
        one.set_weights(&alone);
        one.residuals_factor(&mut ws, u, &mut scratch, &mut qr)?;
        let ssr = sum_of_squares(&res[start..start + rows]);
        start += rows;
        sensors.push(SensorRows {
            gram: qr.r().transpose() * qr.r(),
            ssr,
            rows,
        });
    }
    Ok(sensors)
}
