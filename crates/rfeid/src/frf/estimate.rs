//! An identification's estimate and covariance as the FRF needs them: all
//! of a model's parameter values, which of them were identified, and the
//! Cramér–Rao covariance of those (eq. 26), `Σ_ij = s_i s_j ρ_ij` from the
//! standard errors and correlations RESULT.json holds.
use crate::identification::result::IdentificationResult;
use crate::model::{ColumnName, Model};
use nalgebra::DMatrix;

/// A result's estimate as one experiment sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct AtEstimate {
    /// All of the model's parameter values (SI).
    pub params: Vec<f64>,
    /// The identified parameters that act in this experiment, as indices
    /// into the model's parameters.
    pub wrt: Vec<usize>,
    /// Their covariance (SI), or why there is none.
    pub covariance: Result<DMatrix<f64>, String>,
}

/// The estimate of `result` for `model` as experiment `experiment` sees it
/// (`""` outside a campaign; see
/// [`IdentificationResult::parameter_values`]).
pub fn at_estimate(
    result: &IdentificationResult,
    model: &Model,
    experiment: &str,
) -> Result<AtEstimate, String> {
    let params = result.parameter_values(model, experiment)?;
    let mut wrt = Vec::new();
    let mut rows = Vec::new();
    for (k, p) in result.parameters.iter().enumerate() {
        let Ok(column) = p.name.parse::<ColumnName>();
        if column.experiment.as_deref().is_none_or(|e| e == experiment) {
            if let Some(i) = model.parameter_index(&column.name) {
                wrt.push(i);
                rows.push(k);
            }
        }
    }
    let covariance = covariance(result, &rows);
    Ok(AtEstimate {
        params,
        wrt,
        covariance,
    })
}

/// The covariance of the result's parameters `rows`.
fn covariance(result: &IdentificationResult, rows: &[usize]) -> Result<DMatrix<f64>, String> {
    let missing = || {
        result
            .uncertainty_error
            .clone()
            .unwrap_or_else(|| "the result has no standard errors".into())
    };
    let corr = result.correlation.as_ref().ok_or_else(missing)?;
    let se: Vec<f64> = rows
        .iter()
        .map(|&k| result.parameters[k].std_error.ok_or_else(missing))
        .collect::<Result<_, _>>()?;
    let r = rows.len();
    Ok(DMatrix::from_fn(r, r, |i, j| {
        se[i] * se[j] * corr[rows[i]][rows[j]]
    }))
}
