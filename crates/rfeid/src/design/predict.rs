//! What `identify` would report on a design's data: the Cramér–Rao bound
//! (eq. 26–29) from the design's Fisher matrix, whose rows carry each
//! sensor's 1/σ so that s² = 1.
use super::choose::log_det;
use super::fisher::FisherParts;
use crate::identification::uncertainty::{
    cramer_rao_fisher, IdentifiabilityWarning, UncertaintyError, UncertaintySettings,
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
    /// Standard errors relative to the values (NaN where a value is 0).
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
                .zip(&parts.values)
                .map(|(se, v)| if *v != 0.0 { se / v.abs() } else { f64::NAN })
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
            error: Some(error_text(&parts.columns, observations, &e)),
        },
    }
}

/// Why there are no standard errors, parameters by name.
fn error_text(columns: &[String], observations: usize, e: &UncertaintyError) -> String {
    match e {
        UncertaintyError::Singular {
            parameters,
            condition_number,
        } => {
            let names: Vec<&str> = parameters.iter().map(|&j| columns[j].as_str()).collect();
            let cond = match condition_number.is_finite() {
                true => format!("singular (scaled condition number {condition_number:.3e})"),
                false => "exactly singular".into(),
            };
            format!(
                "the Fisher matrix is {cond}: {} cannot be told apart by this test",
                names.join(", ")
            )
        }
        UncertaintyError::TooFewObservations { .. } => format!(
            "{observations} observations are too few for {} parameters",
            columns.len()
        ),
        other => other.to_string(),
    }
}

/// A prediction's warnings in words, parameters by name (and why there are
/// no standard errors, if there are none).
pub fn warning_texts(columns: &[String], p: &Prediction) -> Vec<String> {
    let mut out: Vec<String> = p
        .warnings
        .iter()
        .map(|w| match w {
            IdentifiabilityWarning::StdErrorExceedsBox {
                index,
                std_error,
                box_width,
            } => format!(
                "{}: the standard error {std_error:.3e} exceeds the box's width {box_width:.3e} (SI)",
                columns[*index]
            ),
            IdentifiabilityWarning::StrongCorrelation {
                first,
                second,
                correlation,
                ..
            } => format!(
                "{} and {} are correlated ({correlation:+.3}): the test determines mostly a combination of them",
                columns[*first], columns[*second]
            ),
            IdentifiabilityWarning::IllConditioned { condition_number } => format!(
                "the scaled Fisher matrix is ill-conditioned (condition number {condition_number:.3e})"
            ),
        })
        .collect();
    if let Some(e) = &p.error {
        out.push(format!("no standard errors: {e}"));
    }
    out
}
