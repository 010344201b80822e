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
use serde::{Deserialize, Serialize};
use std::fmt;

use super::chi_square::{chi_square_quantile, chi_square_sf};
use super::settings::{at_least, in_unit_interval, positive, SettingsError};
use super::termination::StopReason;
use super::uncertainty::IdentifiabilityWarning;

/// Thresholds of the verdict, validated when set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VerdictSettings {
    bound_distance: f64,
    minima_level: f64,
    min_fit_percent: f64,
    lags: usize,
    whiteness_level: f64,
    max_noise_ratio: f64,
    exact_fit: f64,
}

impl Default for VerdictSettings {
    /// `bound_distance` 1e-3 (of the normalised width), `minima_level`
    /// 0.999, `min_fit_percent` 90, `lags` 20, `whiteness_level` 1e-6,
    /// `max_noise_ratio` 1.5, `exact_fit` 1e-6.
    fn default() -> Self {
        VerdictSettings {
            bound_distance: 1e-3,
            minima_level: 0.999,
            min_fit_percent: 90.0,
            lags: 20,
            whiteness_level: 1e-6,
            max_noise_ratio: 1.5,
            exact_fit: 1e-6,
        }
    }
}

impl VerdictSettings {
    /// Distance from a bound, as a fraction of the normalised width, at or
    /// below which an estimate counts as on the bound, in (0, 1).
    pub fn with_bound_distance(mut self, value: f64) -> Result<Self, SettingsError> {
        self.bound_distance = in_unit_interval("bound_distance", value)?;
        Ok(self)
    }
    /// Confidence level whose χ² quantile separates distinct minima, in (0, 1).
    pub fn with_minima_level(mut self, value: f64) -> Result<Self, SettingsError> {
        self.minima_level = in_unit_interval("minima_level", value)?;
        Ok(self)
    }
    /// Fit (%) below which a sensor is poorly fitted (> 0).
    pub fn with_min_fit_percent(mut self, value: f64) -> Result<Self, SettingsError> {
        self.min_fit_percent = positive("min_fit_percent", value)?;
        Ok(self)
    }
    /// Lags of the Ljung–Box test (≥ 1).
    pub fn with_lags(mut self, value: usize) -> Result<Self, SettingsError> {
        self.lags = at_least("lags", value, 1, ">= 1")?;
        Ok(self)
    }
    /// p-value below which residuals are not white, in (0, 1).
    pub fn with_whiteness_level(mut self, value: f64) -> Result<Self, SettingsError> {
        self.whiteness_level = in_unit_interval("whiteness_level", value)?;
        Ok(self)
    }
    /// Residual variance over the first-difference noise level above which
    /// the residuals hold a systematic part (> 1).
    pub fn with_max_noise_ratio(mut self, value: f64) -> Result<Self, SettingsError> {
        let value = positive("max_noise_ratio", value)?;
        if value <= 1.0 {
            return Err(SettingsError {
                name: "max_noise_ratio",
                value,
                requirement: "> 1",
            });
        }
        self.max_noise_ratio = value;
        Ok(self)
    }
    /// Relative residual norm at or below which a sensor is fitted exactly,
    /// in (0, 1).
    pub fn with_exact_fit(mut self, value: f64) -> Result<Self, SettingsError> {
        self.exact_fit = in_unit_interval("exact_fit", value)?;
        Ok(self)
    }
}

/// Which end of the box.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// `min`.
    Lower,
    /// `max`.
    Upper,
}

/// One minimum the starts reached.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Minimum {
    /// The lowest J of the starts that reached it.
    pub cost: f64,
    /// How many starts reached it.
    pub starts: usize,
    /// The identified parameters (SI) at its lowest J.
    pub parameters: Vec<f64>,
}

/// The end of one local search.
#[derive(Debug, Clone, PartialEq)]
pub struct StartEnd {
    /// J at the end.
    pub cost: f64,
    /// The identified parameters (SI) at the end.
    pub parameters: Vec<f64>,
}

/// The residual checks of one sensor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SensorCheck {
    /// Sensor name.
    pub sensor: String,
    /// Normalised RMS fit, % (`None` for a constant measured signal).
    pub fit_percent: Option<f64>,
    /// Ljung–Box statistic Q (`None` where the test was not applied).
    pub ljung_box: Option<f64>,
    /// Its p-value.
    pub p_value: Option<f64>,
    /// Residual variance over the first-difference noise level.
    pub noise_ratio: Option<f64>,
}

/// Why a result is suspect.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Reason {
    /// The local search stopped at its iteration limit.
    IterationLimit {
        /// The limit.
        iterations: usize,
    },
    /// The local search stopped without meeting a tolerance.
    NotConverged {
        /// Why it stopped, in words.
        termination: String,
    },
    /// A parameter is on, or within `threshold` of, a bound.
    AtBound {
        /// Parameter name.
        parameter: String,
        /// Which bound.
        side: Side,
        /// Distance from it, as a fraction of the normalised width.
        distance: f64,
        /// The threshold.
        threshold: f64,
    },
    /// The starts ended in minima whose J differ by more than noise explains.
    DistinctMinima {
        /// The minima, lowest J first.
        minima: Vec<Minimum>,
        /// The J difference beyond which two ends are different minima.
        threshold: f64,
    },
    /// A sensor's fit is below the threshold (or undefined).
    PoorFit {
        /// Sensor name.
        sensor: String,
        /// Its fit, % (`None`: the measured signal is constant).
        fit_percent: Option<f64>,
        /// The threshold, %.
        threshold: f64,
    },
    /// A sensor's residuals fail the Ljung–Box test.
    NotWhite {
        /// Sensor name.
        sensor: String,
        /// Q.
        statistic: f64,
        /// Its p-value.
        p_value: f64,
        /// Lags.
        lags: usize,
        /// The level.
        level: f64,
    },
    /// A sensor's residual variance is far above its noise level.
    NoiseMismatch {
        /// Sensor name.
        sensor: String,
        /// Residual variance over the first-difference noise level.
        ratio: f64,
        /// The threshold.
        threshold: f64,
    },
    /// Two estimates are correlated beyond the warning threshold.
    StrongCorrelation {
        /// Index of the first parameter.
        first: usize,
        /// Index of the second parameter.
        second: usize,
        /// First parameter's name.
        first_name: String,
        /// Second parameter's name.
        second_name: String,
        /// The correlation.
        correlation: f64,
    },
    /// A standard error exceeds the width of its box.
    PoorlyDetermined {
        /// Parameter name.
        parameter: String,
        /// The standard error.
        std_error: f64,
        /// The box width.
        box_width: f64,
    },
    /// The scaled Fisher matrix is ill-conditioned.
    IllConditioned {
        /// Its condition number.
        condition_number: f64,
    },
    /// The Cramér–Rao analysis could not be done.
    NoStandardErrors {
        /// Why.
        message: String,
    },
    /// The model could not be simulated at the estimate.
    SimulationFailed {
        /// Why.
        message: String,
    },
}

/// J and thresholds in messages: four significant digits.
fn fmt_sig(v: f64) -> String {
    format!("{v:.3e}")
}

impl fmt::Display for Reason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Reason::IterationLimit { iterations } => write!(
                f,
                "the local search stopped at its iteration limit ({iterations}) before converging"
            ),
            Reason::NotConverged { termination } => {
                write!(f, "the local search did not converge ({termination})")
            }
            Reason::AtBound { parameter, side, distance, .. } => {
                let side = match side {
                    Side::Lower => "lower",
                    Side::Upper => "upper",
                };
                if *distance == 0.0 {
                    write!(f, "{parameter} is on its {side} bound: the minimum may lie outside the box")
                } else {
                    write!(
                        f,
                        "{parameter} is {:.3} % of its box's width from its {side} bound: the minimum may lie outside the box",
                        100.0 * distance
                    )
                }
            }
            Reason::DistinctMinima { minima, threshold } => {
                let starts: usize = minima.iter().map(|m| m.starts).sum();
                let list: Vec<String> = minima
                    .iter()
                    .map(|m| {
                        let s = if m.starts == 1 { "start" } else { "starts" };
                        format!("J = {} ({} {s})", fmt_sig(m.cost), m.starts)
                    })
                    .collect();
                write!(
                    f,
                    "the {starts} starts ended in {} different minima: {}; J differences above {} are more than the noise explains",
                    minima.len(),
                    list.join(", "),
                    fmt_sig(*threshold)
                )
            }
            Reason::PoorFit { sensor, fit_percent: Some(fit), threshold } => write!(
                f,
                "{sensor} is poorly fitted: {fit:.1} % (below {threshold} %)"
            ),
            Reason::PoorFit { sensor, fit_percent: None, .. } => write!(
                f,
                "{sensor}'s measured signal is constant: it carries no information to fit"
            ),
            Reason::NotWhite { sensor, statistic, p_value, lags, level } => {
                let p = if *p_value > 0.0 {
                    format!("p = {p_value:.1e}")
                } else {
                    "p < 1e-300".to_string()
                };
                write!(
                    f,
                    "the residuals of {sensor} are not white (Ljung–Box Q = {statistic:.1} on {lags} lags, {p} < {level:e}): a sign of model error or a wrong minimum"
                )
            }
            Reason::NoiseMismatch { sensor, ratio, threshold } => write!(
                f,
                "the residual variance of {sensor} is {ratio:.2} times the noise level its first differences show (more than {threshold}): a systematic misfit, from model error or a wrong minimum"
            ),
            Reason::StrongCorrelation { first_name, second_name, correlation, .. } => write!(
                f,
                "{first_name} and {second_name} are correlated ({correlation:+.4}); the data determine mostly a combination of them"
            ),
            Reason::PoorlyDetermined { parameter, std_error, box_width } => write!(
                f,
                "{parameter}: the standard error ({std_error:.3e}) exceeds the width of its box ({box_width:.3e}); the data hardly constrain it"
            ),
            Reason::IllConditioned { condition_number } => write!(
                f,
                "the scaled Fisher matrix is ill-conditioned (condition number {condition_number:.3e})"
            ),
            Reason::NoStandardErrors { message } => {
                write!(f, "no standard errors could be computed: {message}")
            }
            Reason::SimulationFailed { message } => {
                write!(f, "the model could not be simulated at the estimate: {message}")
            }
        }
    }
}

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

fn identifiability_reason(w: &IdentifiabilityWarning, names: &[String]) -> Reason {
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

/// Clusters the ends by J: sorted by J, an end starts a new minimum when its
/// J exceeds the current minimum's lowest J by more than
/// `χ²_r(level) · J_best / (N − r − 1)`. Returns the minima and that
/// threshold.
pub fn cluster_minima(
    ends: &[StartEnd],
    r: usize,
    observations: usize,
    level: f64,
) -> (Vec<Minimum>, f64) {
    let mut order: Vec<usize> = (0..ends.len()).collect();
    order.sort_by(|&a, &b| ends[a].cost.total_cmp(&ends[b].cost));
    let dof = observations.saturating_sub(r + 1).max(1) as f64;
    let best = order.first().map_or(0.0, |&k| ends[k].cost);
    let threshold = chi_square_quantile(level, r.max(1)) * best / dof;
    let mut minima: Vec<Minimum> = Vec::new();
    for k in order {
        match minima.last_mut() {
            Some(m) if ends[k].cost - m.cost <= threshold => m.starts += 1,
            _ => minima.push(Minimum {
                cost: ends[k].cost,
                starts: 1,
                parameters: ends[k].parameters.clone(),
            }),
        }
    }
    (minima, threshold)
}

fn check_sensors(
    signals: &[FitSignal<'_>],
    s: &VerdictSettings,
    reasons: &mut Vec<Reason>,
) -> Vec<SensorCheck> {
    let mut checks = Vec::with_capacity(signals.len());
    let mut residual = Vec::new();
    for sig in signals {
        let (name, y, g) = (&sig.sensor, sig.measured, sig.fitted);
        checks.push(check_sensor(name, y, g, s, &mut residual, reasons));
    }
    checks
}

/// Whether the fit fails any per-sensor check of the verdict (poor fit,
/// residuals not white, residual variance beyond the noise level): a sign
/// of a side minimum, or of model error.
pub(crate) fn fit_fails(signals: &[FitSignal<'_>], s: &VerdictSettings) -> bool {
    let (mut residual, mut reasons) = (Vec::new(), Vec::new());
    signals.iter().any(|sig| {
        check_sensor("", sig.measured, sig.fitted, s, &mut residual, &mut reasons);
        !reasons.is_empty()
    })
}

/// The fit, whiteness and noise-level checks of one sensor's measured `y`
/// and fitted `g`; `residual` is scratch.
fn check_sensor(
    name: &str,
    y: &[f64],
    g: &[f64],
    s: &VerdictSettings,
    residual: &mut Vec<f64>,
    reasons: &mut Vec<Reason>,
) -> SensorCheck {
    let name = name.to_string();
    residual.clear();
    residual.extend(y.iter().zip(g).map(|(y, g)| y - g));
    let n = y.len().max(1) as f64;
    let mean = y.iter().sum::<f64>() / n;
    let spread = y
        .iter()
        .map(|v| (v - mean) * (v - mean))
        .sum::<f64>()
        .sqrt();
    let misfit = residual.iter().map(|v| v * v).sum::<f64>().sqrt();
    let fit_percent = (spread > 0.0).then(|| 100.0 * (1.0 - misfit / spread));
    if fit_percent.is_none_or(|f| f < s.min_fit_percent) {
        reasons.push(Reason::PoorFit {
            sensor: name.clone(),
            fit_percent,
            threshold: s.min_fit_percent,
        });
    }
    let mut check = SensorCheck {
        sensor: name.clone(),
        fit_percent,
        ljung_box: None,
        p_value: None,
        noise_ratio: None,
    };
    let exact = misfit <= s.exact_fit * spread;
    if !exact {
        if let Some(q) = ljung_box(residual, s.lags) {
            let p = chi_square_sf(q, s.lags);
            (check.ljung_box, check.p_value) = (Some(q), Some(p));
            if p < s.whiteness_level {
                reasons.push(Reason::NotWhite {
                    sensor: name.clone(),
                    statistic: q,
                    p_value: p,
                    lags: s.lags,
                    level: s.whiteness_level,
                });
            }
        }
        if let Some(ratio) = noise_ratio(residual) {
            check.noise_ratio = Some(ratio);
            if ratio > s.max_noise_ratio {
                reasons.push(Reason::NoiseMismatch {
                    sensor: name,
                    ratio,
                    threshold: s.max_noise_ratio,
                });
            }
        }
    }
    check
}

/// The Ljung–Box statistic `Q = n (n + 2) Σ_{k=1}^{h} ρ_k² / (n − k)` of
/// `e` (its mean removed), or `None` if the record is shorter than `2h + 2`
/// samples or constant.
pub fn ljung_box(e: &[f64], lags: usize) -> Option<f64> {
    let n = e.len();
    if n < 2 * lags + 2 {
        return None;
    }
    let mean = e.iter().sum::<f64>() / n as f64;
    let c0: f64 = e.iter().map(|v| (v - mean) * (v - mean)).sum();
    if c0 <= 0.0 {
        return None;
    }
    let mut q = 0.0;
    for k in 1..=lags {
        let ck: f64 = e[k..]
            .iter()
            .zip(e)
            .map(|(a, b)| (a - mean) * (b - mean))
            .sum();
        let rho = ck / c0;
        q += rho * rho / (n - k) as f64;
    }
    Some(n as f64 * (n as f64 + 2.0) * q)
}

/// `(Σ e² / n) / (Σ (Δe)² / (2 (n − 1)))`: about 1 for white residuals, large
/// when they hold a smooth part; `None` for fewer than 3 samples or
/// constant residuals.
pub fn noise_ratio(e: &[f64]) -> Option<f64> {
    let n = e.len();
    if n < 3 {
        return None;
    }
    let variance = e.iter().map(|v| v * v).sum::<f64>() / n as f64;
    let diff = e
        .windows(2)
        .map(|w| (w[1] - w[0]) * (w[1] - w[0]))
        .sum::<f64>()
        / (2.0 * (n - 1) as f64);
    (diff > 0.0).then(|| variance / diff)
}
