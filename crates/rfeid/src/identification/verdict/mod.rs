//! The verdict on an identification: **trustworthy**, or **suspect** with
//! every reason that applies.
//!
//! A local search that stops has not necessarily found the right answer:
//! it may sit on a bound of the box, in one of several minima, at its
//! iteration limit, or at a point the model cannot fit. Each check below is
//! built so that a correct model at its best fit to white noise passes it,
//! and a wrong minimum or a wrong model does not:
//!
//! - **bounds**: an estimate within `bound_distance` (default 0.1 %) of the
//!   box's width from a bound, measured in the normalised coordinate of the
//!   search (eq. 17, or its logarithmic form);
//! - **distinct minima**: the starts' end values of J are clustered; two
//!   ends belong to different minima when their J differ by more than
//!   `χ²_r(minima_level) · s²`, with `s² = J_best / (N − r − 1)` (eq. 29)
//!   in the same weighting as the ends. For a model linear near the estimate
//!   the parameters whose J exceeds J_best by less than that lie inside the
//!   `minima_level` (default 99.9 %) confidence region of the estimate: the
//!   noise cannot tell them apart, so they are one minimum. The default
//!   level 0.999 gives, for r = 16, a threshold of 39.3 s²;
//! - **convergence**: the search hit its iteration limit or stopped without
//!   meeting a tolerance;
//! - **fit** per sensor, as MATLAB's `compare` prints it,
//!   `100 (1 − ‖y − ŷ‖ / ‖y − mean(y)‖)` % over the samples used; below
//!   `min_fit_percent` (default 90 %) is poor;
//! - **whiteness**: the Ljung–Box statistic of what each sensor's noise
//!   model ([`crate::identification::noise`]) leaves of its residuals, on
//!   `lags` (default 20) lags, `Q = n (n + 2) Σ_k ρ_k² / (n − k)`, is χ²_lags
//!   under white residuals; `p < whiteness_level` (default 1e-6) is not
//!   white;
//! - **noise level**: white noise of variance σ² has first differences of
//!   variance 2σ², while a smooth misfit hardly shows in them. The ratio of
//!   the variance `Σ e² / n` of what the noise model leaves to
//!   `Σ (Δe)² / (2 (n − 1))` is about 1 (± √(3/n)) for white residuals;
//!   above `max_noise_ratio` (default 1.5, many standard deviations for
//!   records of more than a few hundred samples) the residuals hold a
//!   systematic part, so s² is far above the measurement noise;
//! - **residuals and input** ([`input_test`]): what the noise model leaves
//!   must not depend on the excitation; `p < whiteness_level` of the
//!   regression test says the misfit is in the dynamics. A noise model
//!   fitted to residuals that hold a misfit whitens the misfit only in
//!   part, and what it leaves still follows the input: with the whiteness
//!   test, this is what keeps a wrong model suspect on coloured noise (a
//!   misfit small beside the noise can pass both);
//! - **model error**: when the fit fails any of the checks above at the
//!   lowest minimum and at least two distinct starts ended there (the
//!   restarts stop once two agree), the misfit is the model's, not the
//!   search's: [`Reason::ModelError`] says so, with each failing sensor's
//!   fit and where in frequency its misfit lies. Its standard errors cover
//!   the noise only: a misfit under a deterministic input is bias;
//! - **identifiability** (eq. 26–29): correlations beyond the warning
//!   threshold, standard errors wider than the box, an ill-conditioned or
//!   singular Fisher matrix.
//!
//! A sensor fitted to `exact_fit` (default 1e-6) of its signal's variation,
//! `‖y − ŷ‖ ≤ exact_fit ‖y − mean(y)‖`, is fitted to the accuracy of the
//! simulation itself (noise-free data): its residuals are rounding and
//! integration error, not noise, so the residual tests are not applied to
//! it.
//!
//! Coloured measurement noise (an anti-alias filter's) passes these checks
//! with a correct model once the noise is modelled (`--noise-model ar`, the
//! default of `rfeid identify`); with white noise models, it makes the
//! whiteness and noise-level tests fire, as it should: the Cramér–Rao
//! bounds of white output error are too optimistic then.
pub mod input_test;
mod minima;
mod reason;
mod residuals;
mod settings;

pub use self::minima::{cluster_minima, minima_threshold};
pub use self::reason::{Minimum, Misfit, Reason, SensorCheck, Side, StartEnd};
pub(crate) use self::residuals::{fit_fails, fitted_exactly};
pub use self::residuals::{ljung_box, noise_ratio};
pub use self::settings::VerdictSettings;

use self::residuals::check_sensors;
use crate::identification::noise::ar::Whitener;
use crate::identification::termination::StopReason;
use crate::identification::uncertainty::IdentifiabilityWarning;
use serde::{Deserialize, Serialize};

/// The verdict on an identification.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Verdict {
    /// `true` when no reason applies.
    pub trustworthy: bool,
    /// Every reason the result is suspect; RESULT.json writes each tagged
    /// by its `kind`, with its values and its words in `message`.
    #[serde(
        serialize_with = "reasons_with_messages",
        deserialize_with = "reasons_without_messages"
    )]
    pub reasons: Vec<Reason>,
    /// The checks that decided the verdict: each check that gave a reason
    /// ([`Reason::check`]), once, in the reasons' order; empty when every
    /// check passed.
    #[serde(default)]
    pub decided_by: Vec<String>,
    /// The minima the starts reached, lowest J first.
    pub minima: Vec<Minimum>,
    /// J difference beyond which two ends are different minima.
    pub minima_threshold: f64,
    /// Fit and residual tests per sensor.
    pub sensors: Vec<SensorCheck>,
    /// |correlation| above which a pair is a reason.
    pub correlation_threshold: f64,
    /// The thresholds used.
    pub settings: VerdictSettings,
}

/// The reasons as RESULT.json records them: each one's tagged object with
/// its words added as `message` (ignored when read back).
fn reasons_with_messages<S: serde::Serializer>(
    reasons: &[Reason],
    s: S,
) -> Result<S::Ok, S::Error> {
    use serde::ser::{Error, SerializeSeq};
    let mut seq = s.serialize_seq(Some(reasons.len()))?;
    for r in reasons {
        let mut v = serde_json::to_value(r).map_err(S::Error::custom)?;
        if let serde_json::Value::Object(map) = &mut v {
            map.insert("message".into(), serde_json::Value::String(r.to_string()));
        }
        seq.serialize_element(&v)?;
    }
    seq.end()
}

/// The reasons read back from RESULT.json: each one's words (`message`)
/// dropped, as its values say them again. A file written before the words
/// were added kept the `detail` of `no_standard_errors` and
/// `simulation_failed` under `message`: that is taken as the detail.
fn reasons_without_messages<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Vec<Reason>, D::Error> {
    use serde::de::Error;
    let values = Vec::<serde_json::Value>::deserialize(d)?;
    values
        .into_iter()
        .map(|mut v| {
            if let serde_json::Value::Object(map) = &mut v {
                let words = map.remove("message");
                if let (false, Some(w)) = (map.contains_key("detail"), words) {
                    map.insert("detail".into(), w);
                }
            }
            serde_json::from_value(v).map_err(D::Error::custom)
        })
        .collect()
}

/// What a verdict comes to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// No reason applies.
    Trustworthy,
    /// Model error and nothing else: the fit fails its checks at a minimum
    /// distinct starts agree on. The estimates are the model's best fit;
    /// their standard errors cover the noise only.
    ModelError,
    /// Some other reason applies: do not use the estimates before
    /// resolving it.
    Suspect,
}

impl Verdict {
    /// Trustworthy, model error alone, or suspect.
    pub fn outcome(&self) -> Outcome {
        if self.trustworthy {
            return Outcome::Trustworthy;
        }
        let model_error = self
            .reasons
            .iter()
            .any(|r| matches!(r, Reason::ModelError { .. }));
        let only = self
            .reasons
            .iter()
            .all(|r| matches!(r, Reason::ModelError { .. }) || is_fit_reason(r));
        match model_error && only {
            true => Outcome::ModelError,
            false => Outcome::Suspect,
        }
    }

    /// The pairs (i, j), i < j, whose correlation is a reason.
    pub fn correlated_pairs(&self) -> Vec<(usize, usize)> {
        self.reasons
            .iter()
            .filter_map(|r| match r {
                Reason::StrongCorrelation { first, second, .. } => Some((*first, *second)),
                _ => None,
            })
            .collect()
    }
}

/// What the verdict is drawn from.
pub struct Evidence<'a> {
    /// Names of the identified parameters.
    pub parameters: &'a [String],
    /// The estimate in the normalised coordinate of the search.
    pub u: &'a [f64],
    /// The end of every local search (J in one weighting).
    pub ends: &'a [StartEnd],
    /// N, the number of scalar observations.
    pub observations: usize,
    /// Why the search that gave the estimate stopped.
    pub stop: StopReason,
    /// Its iterations.
    pub iterations: usize,
    /// Its termination message.
    pub termination: String,
    /// Every fitted sensor's measured and simulated signals at the
    /// estimate (from the first sample used), or why the model could not be
    /// simulated there.
    pub signals: Result<Vec<FitSignal<'a>>, String>,
    /// The Cramér–Rao warnings, or why the analysis could not be done.
    pub identifiability: Result<&'a [IdentifiabilityWarning], String>,
    /// The warning threshold on |correlation| the warnings were made with.
    pub correlation_threshold: f64,
}

/// One sensor's signals, measured and simulated at the estimate.
#[derive(Debug, Clone)]
pub struct FitSignal<'a> {
    /// The sensor's name (`sensor[experiment]` in a campaign).
    pub sensor: String,
    /// Measured, from the first sample used.
    pub measured: &'a [f64],
    /// Simulated at the estimate, the same samples.
    pub fitted: &'a [f64],
    /// The whitening filter of the sensor's noise model (order 0: white
    /// noise): the residual tests apply to what it leaves.
    pub whitening: &'a Whitener,
    /// The experiment's inputs (each excitation's force) at the same
    /// samples, for the residual–input test (empty: not tested).
    pub inputs: &'a [Vec<f64>],
    /// The sample rate, Hz (for where in frequency a misfit lies).
    pub sample_rate: f64,
}

impl FitSignal<'_> {
    /// The residuals, fitted minus measured, sample by sample.
    pub fn residuals(&self) -> Vec<f64> {
        self.fitted
            .iter()
            .zip(self.measured)
            .map(|(g, y)| g - y)
            .collect()
    }
}

/// Draws the verdict (see the module documentation).
pub fn assess(e: &Evidence<'_>, s: &VerdictSettings) -> Verdict {
    let mut reasons = Vec::new();
    match e.stop {
        StopReason::MaxIterations => reasons.push(Reason::IterationLimit {
            iterations: e.iterations,
        }),
        stop if !stop.is_converged() => reasons.push(Reason::NotConverged {
            termination: e.termination.clone(),
        }),
        _ => {}
    }
    for (name, &u) in e.parameters.iter().zip(e.u) {
        let (side, distance) = if u <= 0.5 {
            (Side::Lower, u.max(0.0))
        } else {
            (Side::Upper, (1.0 - u).max(0.0))
        };
        if distance <= s.bound_distance {
            reasons.push(Reason::AtBound {
                parameter: name.clone(),
                side,
                distance,
                threshold: s.bound_distance,
            });
        }
    }
    let r = e.parameters.len();
    let (minima, minima_threshold) = cluster_minima(e.ends, r, e.observations, s.minima_level);
    if minima.len() > 1 {
        reasons.push(Reason::DistinctMinima {
            minima: minima.clone(),
            threshold: minima_threshold,
        });
    }
    let sensors = match &e.signals {
        Ok(signals) => check_sensors(signals, s, &mut reasons),
        Err(message) => {
            reasons.push(Reason::SimulationFailed {
                message: message.clone(),
            });
            Vec::new()
        }
    };
    if let Some(best) = minima.first().filter(|m| m.starts >= 2) {
        if let Some(error) = model_error(best, &sensors, &reasons) {
            reasons.insert(0, error);
        }
    }
    match &e.identifiability {
        Ok(warnings) => {
            for w in warnings.iter() {
                reasons.push(identifiability_reason(w, e.parameters));
            }
        }
        Err(message) => reasons.push(Reason::NoStandardErrors {
            message: message.clone(),
        }),
    }
    let mut decided_by: Vec<String> = Vec::new();
    for check in reasons.iter().map(Reason::check) {
        if !decided_by.iter().any(|c| c == check) {
            decided_by.push(check.to_string());
        }
    }
    Verdict {
        trustworthy: reasons.is_empty(),
        reasons,
        decided_by,
        minima,
        minima_threshold,
        sensors,
        correlation_threshold: e.correlation_threshold,
        settings: s.clone(),
    }
}

/// Whether a reason is a failed check of the fit (fit, whiteness, noise
/// level, residual–input): a wrong minimum or model error.
pub fn is_fit_reason(r: &Reason) -> bool {
    matches!(
        r,
        Reason::PoorFit { .. }
            | Reason::NotWhite { .. }
            | Reason::NoiseMismatch { .. }
            | Reason::InputCorrelated { .. }
    )
}

/// [`Reason::ModelError`] when the fit fails a check at the lowest minimum
/// `best`, which several distinct starts reached.
fn model_error(best: &Minimum, sensors: &[SensorCheck], reasons: &[Reason]) -> Option<Reason> {
    let failed: Vec<&str> = reasons
        .iter()
        .filter_map(|r| match r {
            Reason::PoorFit { sensor, .. }
            | Reason::NotWhite { sensor, .. }
            | Reason::NoiseMismatch { sensor, .. }
            | Reason::InputCorrelated { sensor, .. } => Some(sensor.as_str()),
            _ => None,
        })
        .collect();
    if failed.is_empty() {
        return None;
    }
    let sensors = sensors
        .iter()
        .filter(|c| failed.contains(&c.sensor.as_str()))
        .map(|c| Misfit {
            sensor: c.sensor.clone(),
            fit_percent: c.fit_percent,
            band: c.misfit_band,
        })
        .collect();
    Some(Reason::ModelError {
        starts: best.starts,
        cost: best.cost,
        sensors,
    })
}

/// An identifiability warning of the Cramér–Rao analysis as a reason, with
/// the parameters' names.
pub(crate) fn identifiability_reason(w: &IdentifiabilityWarning, names: &[String]) -> Reason {
    let name = |i: usize| names.get(i).cloned().unwrap_or_default();
    match w {
        IdentifiabilityWarning::StrongCorrelation {
            first,
            second,
            correlation,
            slope,
            combination_std_error,
        } => Reason::StrongCorrelation {
            first: *first,
            second: *second,
            first_name: name(*first),
            second_name: name(*second),
            correlation: *correlation,
            slope: Some(*slope),
            combination_std_error: Some(*combination_std_error),
        },
        IdentifiabilityWarning::StdErrorExceedsBox {
            index,
            std_error,
            box_width,
        } => Reason::PoorlyDetermined {
            parameter: name(*index),
            std_error: *std_error,
            box_width: *box_width,
        },
        IdentifiabilityWarning::IllConditioned { condition_number } => Reason::IllConditioned {
            condition_number: *condition_number,
        },
    }
}
