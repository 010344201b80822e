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
//! - **whiteness**: the Ljung–Box statistic of each sensor's residuals on
//!   `lags` (default 20) lags, `Q = n (n + 2) Σ_k ρ_k² / (n − k)`, is χ²_lags
//!   under white residuals; `p < whiteness_level` (default 1e-6) is not
//!   white;
//! - **noise level**: white noise of variance σ² has first differences of
//!   variance 2σ², while a smooth misfit hardly shows in them. The ratio of
//!   each sensor's residual variance `Σ e² / n` to `Σ (Δe)² / (2 (n − 1))` is
//!   about 1 (± √(3/n)) for white residuals; above `max_noise_ratio`
//!   (default 1.5, many standard deviations for records of more than a few
//!   hundred samples) the residuals hold a systematic part, so s² is far
//!   above the measurement noise;
//! - **identifiability** (eq. 26–29): correlations beyond the warning
//!   threshold, standard errors wider than the box, an ill-conditioned or
//!   singular Fisher matrix.
//!
//! A sensor fitted to `exact_fit` (default 1e-6) of its signal's variation,
//! `‖y − ŷ‖ ≤ exact_fit ‖y − mean(y)‖`, is fitted to the accuracy of the
//! simulation itself (noise-free data): its residuals are rounding and
//! integration error, not noise, so the whiteness and noise-level tests are
//! not applied to it.
//!
//! Caveat: measured noise that is not white (for instance filtered by an
//! anti-aliasing filter with a cut-off well below the Nyquist frequency)
//! makes the whiteness and noise-level tests fire with a correct model. That
//! is intended: the Cramér–Rao bounds assume white noise, and are too
//! optimistic then.
mod minima;
mod reason;
mod residuals;
mod settings;

pub use self::minima::cluster_minima;
pub use self::reason::{Minimum, Reason, SensorCheck, Side, StartEnd};
pub(crate) use self::residuals::fit_fails;
pub use self::residuals::{ljung_box, noise_ratio};
pub use self::settings::VerdictSettings;

use self::residuals::check_sensors;
use crate::identification::termination::StopReason;
use crate::identification::uncertainty::IdentifiabilityWarning;
use serde::{Deserialize, Serialize};

/// The verdict on an identification.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Verdict {
    /// `true` when no reason applies.
    pub trustworthy: bool,
    /// Every reason the result is suspect.
    pub reasons: Vec<Reason>,
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

impl Verdict {
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
    Verdict {
        trustworthy: reasons.is_empty(),
        reasons,
        minima,
        minima_threshold,
        sensors,
        correlation_threshold: e.correlation_threshold,
        settings: s.clone(),
    }
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
        } => Reason::StrongCorrelation {
            first: *first,
            second: *second,
            first_name: name(*first),
            second_name: name(*second),
            correlation: *correlation,
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
