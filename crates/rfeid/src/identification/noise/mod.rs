//! The measurement noise as the identification models it: white per sensor
//! (eq. 12, 14), or coloured, an autoregressive model per sensor ([`ar`])
//! estimated from the residuals together with the parameters.
//!
//! Real records carry coloured noise (an anti-alias filter leaves noise
//! correlated over a few samples). Output error with white weights still
//! gives consistent estimates then, but its Cramér–Rao bounds (eq. 26–29)
//! assume independent samples and come out too small, and the residual
//! checks of the verdict fire on a correct model. Prewhitening the
//! criterion with each sensor's filter `A(q)` (the prediction-error method)
//! fixes both: the exact sensitivities pass through the same fixed filter,
//! the bounds on the filtered Jacobian are those of the noise model, and the
//! verdict checks what the noise model leaves.
pub mod ar;

pub use self::ar::{ArModel, Whitener};
use serde::{Deserialize, Serialize};

/// Highest autoregressive order tried by default (and never more than a
/// fiftieth of the samples): a low-pass that leaves almost no noise near the
/// Nyquist frequency (a second-order Butterworth at a tenth of the sample
/// rate, discretised by the bilinear transform) needs about 40 to be
/// whitened to the verdict's Ljung–Box level on 3000 samples.
pub const DEFAULT_MAX_ORDER: usize = 64;

/// How the measurement noise is modelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NoiseModel {
    /// White noise per sensor: output error, the paper's eq. 12–16.
    White,
    /// An autoregressive model per sensor, order chosen by the Bayesian
    /// information criterion up to `max_order` (white noise gets order 0).
    Autoregressive {
        /// The highest order tried.
        max_order: usize,
    },
}

impl Default for NoiseModel {
    fn default() -> Self {
        NoiseModel::Autoregressive {
            max_order: DEFAULT_MAX_ORDER,
        }
    }
}

impl NoiseModel {
    /// The model of one sensor's residuals `e`: white of their mean square,
    /// or the autoregressive fit. `None` when `e` is empty or zero.
    pub fn fit(&self, e: &[f64]) -> Option<ArModel> {
        match *self {
            NoiseModel::White => {
                let ms = e.iter().map(|v| v * v).sum::<f64>() / e.len() as f64;
                (ms > 0.0 && ms.is_finite()).then(|| ArModel::white(ms))
            }
            NoiseModel::Autoregressive { max_order } => ArModel::fit(e, max_order),
        }
    }

    /// The whitening filter of the model of `e` ([`Self::fit`]), with its
    /// exact start; none (order 0) for white noise, or when `e` has no
    /// model.
    pub fn filter(&self, e: &[f64]) -> Whitener {
        self.fit(e).map(|m| m.whitener()).unwrap_or_default()
    }
}

/// The noise model of one sensor at the estimate, as RESULT.json and the
/// report show it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SensorNoise {
    /// The sensor (`sensor[experiment]` in a campaign).
    pub sensor: String,
    /// The autoregressive order (0: white).
    pub order: usize,
    /// a_1 … a_p of `A(q)`.
    pub coefficients: Vec<f64>,
    /// Standard deviation of the innovations, in the sensor's unit.
    pub innovation_std: f64,
    /// Standard deviation of the residuals, in the sensor's unit.
    pub residual_std: f64,
}

impl SensorNoise {
    /// The noise model of sensor `sensor` whose residuals are `e` and whose
    /// whitening filter is `filter`.
    pub fn of(sensor: String, e: &[f64], filter: &Whitener) -> Self {
        let n = e.len().max(1) as f64;
        SensorNoise {
            sensor,
            order: filter.order(),
            coefficients: filter.coefficients().to_vec(),
            innovation_std: (ar::whitened_ssr(filter, e) / n).sqrt(),
            residual_std: (e.iter().map(|v| v * v).sum::<f64>() / n).sqrt(),
        }
    }

    /// The noise model as an [`ArModel`] (for its spectrum).
    pub fn ar_model(&self) -> ArModel {
        ArModel {
            coefficients: self.coefficients.clone(),
            innovation_variance: self.innovation_std * self.innovation_std,
            reflection: Vec::new(),
        }
    }
}

/// The criterion's weighting, as one value: each sensor's weight w_ec
/// (eq. 13 with a diagonal R, eq. 14 with each sensor's own σ²) and its
/// whitening filter (order 0: white noise), every experiment's sensors in
/// turn. The weights stage computes it; the criterion takes it whole
/// ([`crate::identification::output_error::OutputError::set_weighting`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SensorWeighting {
    /// w_ec per sensor.
    pub weights: Vec<f64>,
    /// The whitening filter per sensor.
    pub filters: Vec<Whitener>,
}

/// What the standard errors cover.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StdErrorScope {
    /// The whole uncertainty of the estimates, as far as the model is right
    /// (the verdict found no model error).
    #[default]
    Noise,
    /// The noise only: the verdict found model error, whose bias no
    /// residual-based standard error covers.
    NoiseOnly,
}
