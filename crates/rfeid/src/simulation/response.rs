//! The results of a run: the simulated sensor signals ([`Response`]) and
//! their sensitivities to the parameters ([`Sensitivities`]).
#[cfg(doc)]
use crate::model::Model;

/// Simulated sensor signals: `values[c * n_samples + k]` is sensor c at sample k.
#[derive(Debug, Clone, PartialEq)]
pub struct Response {
    /// Number of samples N.
    pub n_samples: usize,
    /// Number of sensors.
    pub n_sensors: usize,
    /// Sensor-major signals.
    pub values: Vec<f64>,
}

impl Response {
    /// An all-zero response of the given shape.
    pub fn zeros(n_sensors: usize, n_samples: usize) -> Self {
        Response {
            n_samples,
            n_sensors,
            values: vec![0.0; n_sensors * n_samples],
        }
    }

    /// The signal of sensor c.
    pub fn sensor(&self, c: usize) -> &[f64] {
        &self.values[c * self.n_samples..(c + 1) * self.n_samples]
    }
}

/// Sensitivities of every sensor sample to the parameters `wrt`:
/// `values[(c * n_samples + k) * wrt.len() + j] = ∂y_ck / ∂x_j` (eq. 27–28).
#[derive(Debug, Clone, PartialEq)]
pub struct Sensitivities {
    /// Parameter indices (into [`Model::parameters`]) of the columns.
    pub wrt: Vec<usize>,
    /// Row-major (observation × parameter).
    pub values: Vec<f64>,
}
