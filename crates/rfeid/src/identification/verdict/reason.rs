//! Why a result is suspect ([`Reason`]), with the values the reasons
//! carry, in words.
use serde::{Deserialize, Serialize};
use std::fmt;

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
    /// The residual–input statistic T ([`super::input_test`]), if tested.
    #[serde(default)]
    pub input_statistic: Option<f64>,
    /// Its p-value.
    #[serde(default)]
    pub input_p_value: Option<f64>,
    /// The residuals' spectral peak and band, Hz, when a check failed.
    #[serde(default)]
    pub misfit_band: Option<[f64; 3]>,
    /// The order of the autoregressive noise model fitted to the sensor's
    /// residuals whose innovations the whiteness, noise-level and input
    /// tests judged (0: the residuals as they are), when tested.
    #[serde(default)]
    pub noise_order: Option<usize>,
}

/// Where a sensor's misfit lies: its fit and the band of its residuals'
/// spectrum ([`crate::measurement::spectrum::Spectrum::peak_band`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Misfit {
    /// The sensor.
    pub sensor: String,
    /// Its fit, %.
    pub fit_percent: Option<f64>,
    /// The residuals' spectral peak and the band around it where the
    /// density stays above a tenth of the peak's, Hz.
    pub band: Option<[f64; 3]>,
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
    /// What the noise model leaves of a sensor's residuals depends on the
    /// inputs ([`super::input_test`]): the misfit follows the excitation.
    InputCorrelated {
        /// The sensor.
        sensor: String,
        /// The statistic T.
        statistic: f64,
        /// Its degrees of freedom.
        dof: usize,
        /// P(χ²_dof ≥ T).
        p_value: f64,
        /// The level below which p fails.
        level: f64,
    },
    /// The fit fails the residual checks at a minimum that several distinct
    /// starts reached: the model's best fit, so the misfit is model error,
    /// not a wrong minimum.
    ModelError {
        /// Distinct starts that ended in the lowest minimum.
        starts: usize,
        /// Its J.
        cost: f64,
        /// Each sensor whose fit fails a check: its fit and where in
        /// frequency its misfit lies.
        sensors: Vec<Misfit>,
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
        /// The data fix `first − slope · second` best (SI units).
        #[serde(default)]
        slope: Option<f64>,
        /// That combination's standard error, in the first's SI unit.
        #[serde(default)]
        combination_std_error: Option<f64>,
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
        /// Why (RESULT.json's `detail`; `message` holds the reason's words).
        #[serde(rename = "detail")]
        message: String,
    },
    /// The model could not be simulated at the estimate.
    SimulationFailed {
        /// Why (RESULT.json's `detail`).
        #[serde(rename = "detail")]
        message: String,
    },
}

/// [`Reason::AtBound`] in words.
fn at_bound(f: &mut fmt::Formatter<'_>, parameter: &str, side: Side, distance: f64) -> fmt::Result {
    let side = match side {
        Side::Lower => "lower",
        Side::Upper => "upper",
    };
    if distance == 0.0 {
        write!(
            f,
            "{parameter} is on its {side} bound: the minimum may lie outside the box"
        )
    } else {
        write!(
            f,
            "{parameter} is {:.3} % of its box's width from its {side} bound: the minimum may lie outside the box",
            100.0 * distance
        )
    }
}

/// [`Reason::DistinctMinima`] in words.
fn distinct_minima(f: &mut fmt::Formatter<'_>, minima: &[Minimum], threshold: f64) -> fmt::Result {
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
        fmt_sig(threshold)
    )
}

/// [`Reason::ModelError`] in words.
fn model_error(
    f: &mut fmt::Formatter<'_>,
    starts: usize,
    cost: f64,
    sensors: &[Misfit],
) -> fmt::Result {
    let list: Vec<String> = sensors
        .iter()
        .map(|m| {
            let fit = m
                .fit_percent
                .map_or("-".to_string(), |v| format!("{v:.2} %"));
            match m.band {
                Some([peak, lo, hi]) => format!(
                    "{} fit {fit}, misfit largest at {peak:.4} Hz (band {lo:.4}–{hi:.4} Hz)",
                    m.sensor
                ),
                None => format!("{} fit {fit}", m.sensor),
            }
        })
        .collect();
    write!(
        f,
        "model error: {starts} distinct starts reached the same minimum (J = {}), and its fit fails the residual checks ({}); the model cannot fit the data better, so the standard errors cover the noise only, not the model error's bias",
        fmt_sig(cost),
        list.join("; ")
    )
}

/// A p-value in messages.
fn fmt_p(p: f64) -> String {
    if p > 0.0 {
        format!("p = {p:.1e}")
    } else {
        "p < 1e-300".to_string()
    }
}

/// J and thresholds in messages: four significant digits.
fn fmt_sig(v: f64) -> String {
    format!("{v:.3e}")
}

impl Reason {
    /// The check of the verdict that gave this reason (the module
    /// documentation of [`super`] lists them).
    pub fn check(&self) -> &'static str {
        match self {
            Reason::IterationLimit { .. } | Reason::NotConverged { .. } => "convergence",
            Reason::AtBound { .. } => "bounds",
            Reason::DistinctMinima { .. } => "distinct minima",
            Reason::PoorFit { .. } => "fit",
            Reason::NotWhite { .. } => "whiteness",
            Reason::NoiseMismatch { .. } => "noise level",
            Reason::InputCorrelated { .. } => "residuals and input",
            Reason::ModelError { .. } => "model error",
            Reason::StrongCorrelation { .. }
            | Reason::PoorlyDetermined { .. }
            | Reason::IllConditioned { .. }
            | Reason::NoStandardErrors { .. } => "identifiability",
            Reason::SimulationFailed { .. } => "simulation",
        }
    }
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
            Reason::AtBound {
                parameter,
                side,
                distance,
                ..
            } => at_bound(f, parameter, *side, *distance),
            Reason::DistinctMinima { minima, threshold } => distinct_minima(f, minima, *threshold),
            Reason::PoorFit { sensor, fit_percent: Some(fit), threshold } => write!(
                f,
                "{sensor} is poorly fitted: {fit:.1} % (below {threshold} %)"
            ),
            Reason::PoorFit { sensor, fit_percent: None, .. } => write!(
                f,
                "{sensor}'s measured signal is constant: it carries no information to fit"
            ),
            Reason::NotWhite { sensor, statistic, p_value, lags, level } => write!(
                f,
                "what the noise model leaves of {sensor}'s residuals is not white (Ljung–Box Q = {statistic:.1} on {lags} lags, {} < {level:e}): a sign of model error or a wrong minimum",
                fmt_p(*p_value)
            ),
            Reason::NoiseMismatch { sensor, ratio, threshold } => write!(
                f,
                "the residual variance of {sensor} is {ratio:.2} times the noise level its first differences show (more than {threshold}): a systematic misfit, from model error or a wrong minimum"
            ),
            Reason::InputCorrelated { sensor, statistic, dof, p_value, level } => write!(
                f,
                "the residuals of {sensor} follow the input (T = {statistic:.1} on {dof} degrees of freedom, {} < {level:e}): the misfit is in the dynamics, not in the noise",
                fmt_p(*p_value)
            ),
            Reason::ModelError { starts, cost, sensors } => model_error(f, *starts, *cost, sensors),
            Reason::StrongCorrelation { first_name, second_name, correlation, slope, combination_std_error, .. } => {
                write!(
                    f,
                    "{first_name} and {second_name} are correlated ({correlation:+.4}); the data determine mostly a combination of them"
                )?;
                match (slope, combination_std_error) {
                    (Some(k), Some(se)) => write!(
                        f,
                        ": {first_name} {} {:.4} {second_name} (SI), to a standard error of {se:.3e}",
                        if *k < 0.0 { "+" } else { "−" },
                        k.abs()
                    ),
                    _ => Ok(()),
                }
            }
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
