//! What `identify` would report on a design's data: the Cramér–Rao bound
//! (eq. 26–29) from the design's Fisher matrix, whose rows carry each
//! sensor's 1/σ so that s² = 1.
use super::choose::log_det;
use super::fisher::FisherParts;
use crate::identification::uncertainty::{
    cramer_rao_fisher, IdentifiabilityWarning, UncertaintySettings,
};
use nalgebra::DMatrix;

/// A design's predicted uncertainty.
#[derive(Debug, Clone, PartialEq)]
pub struct Prediction {
    /// `log det F`, F in the relative parameters `x_j / s_j`.
    pub log_det: f64,
    /// Scalar observations N (samples × sensors, every experiment).
    pub observations: usize,
    /// Standard errors, SI (empty when F is singular).
    pub std_errors: Vec<f64>,
    /// Standard errors relative to the values (to the scale s_j where a
    /// value is 0).
    pub relative_std_errors: Vec<f64>,
    /// Correlations of the estimates (empty when F is singular).
    pub correlation: Vec<Vec<f64>>,
    /// Condition number of the column-scaled F, as `identify` reports it.
    pub condition_number: Option<f64>,
    /// Identifiability warnings, as `identify`'s.
    pub warnings: Vec<IdentifiabilityWarning>,
    /// Why there are no standard errors (a singular F), if there are none.
    pub error: Option<String>,
}

/// The prediction of Fisher matrix `f` (relative parameters) of `parts`'
/// placed sensors with `extra` more sensors.
pub fn predict(
    parts: &FisherParts,
    f: &DMatrix<f64>,
    extra: usize,
    settings: &UncertaintySettings,
) -> Prediction {
    let observations = parts.observations(extra);
    let log_det = log_det(f);
    match cramer_rao_fisher(f, observations, &parts.scale, &parts.widths, settings) {
        Ok(b) => Prediction {
            log_det,
            observations,
            relative_std_errors: b
                .std_errors
                .iter()
                .zip(&parts.scale)
                .map(|(se, s)| se / s)
                .collect(),
            std_errors: b.std_errors,
            correlation: b
                .correlation
                .row_iter()
                .map(|row| row.iter().copied().collect())
                .collect(),
            condition_number: Some(b.condition_number),
            warnings: b.warnings,
            error: None,
        },
        Err(e) => Prediction {
            log_det,
            observations,
            std_errors: Vec::new(),
            relative_std_errors: Vec::new(),
            correlation: Vec::new(),
            condition_number: None,
            warnings: Vec::new(),
            error: Some(e.to_string()),
        },
    }
}
