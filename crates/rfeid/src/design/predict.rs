//! What `identify` would report on a design's data: the Cramér–Rao bound
//! (eq. 26–29) from the design's Fisher matrix, whose rows carry each
//! sensor's σ₀/σ so that s² = σ₀² ([`FisherParts::noise_scale`]).
use super::choose::log_det;
use super::fisher::FisherParts;
use super::fisher_bound::cramer_rao_fisher;
use crate::identification::uncertainty::{
    IdentifiabilityWarning, UncertaintyError, UncertaintySettings,
};
use nalgebra::DMatrix;

/// A design's predicted uncertainty.
#[derive(Debug, Clone, PartialEq)]
pub struct Prediction {
    /// `log det F`, F in the relative parameters `x_j / s_j`; −∞ when F is
    /// singular by the test of the standard errors (where a finite value
    /// would be rounding).
    pub log_det: f64,
    /// Scalar observations N (samples × sensors, every experiment).
    pub observations: usize,
    /// Standard errors, SI (empty when F is singular).
    pub std_errors: Vec<f64>,
    /// Standard errors relative to the values (NaN where a value is 0).
    pub relative_std_errors: Vec<f64>,
    /// Correlations of the estimates (empty when F is singular).
    pub correlation: Vec<Vec<f64>>,
    /// Condition number of the column-scaled F, as `identify` reports it
    /// (also when F is singular, unless it is infinite).
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
    // F here is F·σ₀²: log det F = log det(F·σ₀²) − r ln σ₀².
    let s2 = parts.noise_scale.powi(2);
    let log_det = log_det(f) + parts.log_det_shift();
    let (scale, widths) = (&parts.scale, &parts.widths);
    match cramer_rao_fisher(f, observations, scale, widths, s2, settings) {
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
            log_det: f64::NEG_INFINITY,
            observations,
            std_errors: Vec::new(),
            relative_std_errors: Vec::new(),
            correlation: Vec::new(),
            condition_number: match e {
                UncertaintyError::Singular {
                    condition_number, ..
                } => Some(condition_number).filter(|c| c.is_finite()),
                _ => None,
            },
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
            match names.as_slice() {
                [one] => format!(
                    "the Fisher matrix is {cond}: this test carries no information on {one} (the readings do not depend on it)"
                ),
                _ => format!(
                    "the Fisher matrix is {cond}: {} cannot be told apart by this test",
                    names.join(", ")
                ),
            }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::fisher::ExperimentFisher;

    /// Two parameters, one experiment of 100 samples and one sensor.
    fn parts() -> FisherParts {
        FisherParts {
            columns: vec!["a".into(), "b".into()],
            values: vec![1.0, 2.0],
            scale: vec![1.0, 2.0],
            widths: vec![1.0, 2.0],
            noise_scale: 1e-3,
            experiments: vec![ExperimentFisher {
                name: String::new(),
                placed: DMatrix::zeros(2, 2),
                candidates: Vec::new(),
                samples: 100,
                placed_sensors: 1,
            }],
        }
    }

    #[test]
    fn a_singular_fisher_matrix_has_no_finite_log_det_and_names_what_it_lacks() {
        let settings = UncertaintySettings::default();
        // b has no information at all.
        let f = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 0.0]);
        let p = predict(&parts(), &f, 0, &settings);
        assert_eq!(p.log_det, f64::NEG_INFINITY);
        assert_eq!(p.condition_number, None);
        let e = p.error.unwrap();
        assert!(e.contains("carries no information on b"), "{e}");
        // a and b nearly equal in their effect: singular to rounding, a
        // finite condition number, and the pair named.
        let f = DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0 + 1e-17]);
        let p = predict(&parts(), &f, 0, &settings);
        assert_eq!(p.log_det, f64::NEG_INFINITY);
        let e = p.error.unwrap();
        assert!(e.contains("a, b cannot be told apart"), "{e}");
        // A regular F: log det F = log det(F·σ₀²) − r ln σ₀².
        let f = DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0]);
        let p = predict(&parts(), &f, 0, &settings);
        let expected = (2.0f64 - 0.25).ln() - 2.0 * 1e-6f64.ln();
        assert!((p.log_det - expected).abs() < 1e-12, "{}", p.log_det);
        assert_eq!(p.std_errors.len(), 2);
    }
}
