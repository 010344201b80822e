//! Measured signals: matching a data file to the model's sensors and
//! sampling (eq. 10, 15), and adding seeded measurement noise.
use crate::io::timeseries::TimeSeries;
use crate::model::Model;
use crate::simulation::Response;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// Why a data file does not fit the model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeasurementError {
    /// A sensor has no column.
    #[error("no column for sensor '{sensor}' (columns: {columns})")]
    MissingColumn {
        /// The sensor.
        sensor: String,
        /// The columns present.
        columns: String,
    },
    /// A column that is not a sensor of the model.
    #[error("column '{column}' is not a sensor of the model (sensors: {sensors})")]
    ExtraColumn {
        /// The column.
        column: String,
        /// The model's sensors.
        sensors: String,
    },
    /// Fewer samples than the model's duration needs.
    #[error(
        "the data has {found} samples, but the model needs {needed} ({duration} s at {rate} Hz)"
    )]
    TooShort {
        /// Samples present.
        found: usize,
        /// Samples needed.
        needed: usize,
        /// Model duration, s.
        duration: f64,
        /// Model sample rate, Hz.
        rate: f64,
    },
    /// A sample time off the model's grid t_k = k / rate.
    #[error("sample {index} is at t = {time} s, but the model samples at t = {expected} s ({rate} Hz from t = 0)")]
    TimeMismatch {
        /// 0-based sample index.
        index: usize,
        /// Time in the file.
        time: f64,
        /// Time the model expects.
        expected: f64,
        /// Model sample rate, Hz.
        rate: f64,
    },
}

/// Measured signals in the model's sensor order and sampling; samples past
/// the model's duration are ignored.
pub fn match_data(model: &Model, data: &TimeSeries) -> Result<Response, MeasurementError> {
    let sensors: Vec<&str> = model.sensors.iter().map(|s| s.name.as_str()).collect();
    if let Some(extra) = data.names.iter().find(|c| !sensors.contains(&c.as_str())) {
        return Err(MeasurementError::ExtraColumn {
            column: extra.clone(),
            sensors: sensors.join(", "),
        });
    }
    let s = model.sampling;
    let n = s.n_samples();
    if data.time.len() < n {
        return Err(MeasurementError::TooShort {
            found: data.time.len(),
            needed: n,
            duration: s.duration,
            rate: s.sample_rate,
        });
    }
    let dt = 1.0 / s.sample_rate;
    for (k, &t) in data.time.iter().take(n).enumerate() {
        let expected = s.time(k);
        if (t - expected).abs() > 1e-6 * dt {
            return Err(MeasurementError::TimeMismatch {
                index: k,
                time: t,
                expected,
                rate: s.sample_rate,
            });
        }
    }
    let mut out = Response::zeros(sensors.len(), n);
    for (c, name) in sensors.iter().enumerate() {
        let col = data
            .column(name)
            .ok_or_else(|| MeasurementError::MissingColumn {
                sensor: name.to_string(),
                columns: data.names.join(", "),
            })?;
        out.values[c * n..(c + 1) * n].copy_from_slice(&col[..n]);
    }
    Ok(out)
}

/// The response as a time series with the sensors' names.
pub fn to_timeseries(model: &Model, response: &Response) -> TimeSeries {
    TimeSeries {
        time: (0..response.n_samples)
            .map(|k| model.sampling.time(k))
            .collect(),
        names: model.sensors.iter().map(|s| s.name.clone()).collect(),
        columns: (0..response.n_sensors)
            .map(|c| response.sensor(c).to_vec())
            .collect(),
    }
}

/// Root mean square of a signal.
pub fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len().max(1) as f64).sqrt()
}

/// Sensors whose signal from sample `first` on is constant (all zero, say):
/// such a signal carries no information about the parameters.
pub fn constant_sensors(response: &Response, first: usize) -> Vec<usize> {
    (0..response.n_sensors)
        .filter(|&c| {
            let s = &response.sensor(c)[first.min(response.n_samples)..];
            s.iter().all(|v| *v == s[0])
        })
        .collect()
}

/// Why `--noise` cannot add the noise asked for.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NoiseError {
    /// The fraction is negative or not finite.
    #[error("the noise fraction {fraction:e} must be a finite number ≥ 0")]
    BadFraction {
        /// The fraction.
        fraction: f64,
    },
    /// σ = fraction × RMS, or the noisy signal, would not be finite.
    #[error("noise of {fraction:e} × RMS overflows on sensor {sensor} (RMS {rms:e})")]
    Overflow {
        /// Sensor index.
        sensor: usize,
        /// The fraction.
        fraction: f64,
        /// The sensor's RMS.
        rms: f64,
    },
    /// σ is below the rounding of the signal's values: adding it would
    /// change nothing.
    #[error("noise of {fraction:e} × RMS is below the rounding of sensor {sensor}'s values (largest {peak:e}) and would change nothing")]
    BelowRounding {
        /// Sensor index.
        sensor: usize,
        /// The fraction.
        fraction: f64,
        /// The sensor's largest |value|.
        peak: f64,
    },
}

/// Checks that [`add_noise`] with `fraction` adds noise to every sensor that
/// has a signal: σ and the noisy values finite, and σ not lost in the
/// values' rounding. A fraction of 0 (no noise) is accepted; a sensor whose
/// signal is all zero gets no noise from any fraction.
pub fn check_noise(response: &Response, fraction: f64) -> Result<(), NoiseError> {
    if !(fraction.is_finite() && fraction >= 0.0) {
        return Err(NoiseError::BadFraction { fraction });
    }
    if fraction == 0.0 {
        return Ok(());
    }
    for c in 0..response.n_sensors {
        let rms = rms(response.sensor(c));
        let sigma = fraction * rms;
        let peak = response
            .sensor(c)
            .iter()
            .fold(0.0_f64, |a, v| a.max(v.abs()));
        // A normal sample beyond 40 σ has probability below 1e-300.
        if !sigma.is_finite() || !(peak + 40.0 * sigma).is_finite() {
            return Err(NoiseError::Overflow {
                sensor: c,
                fraction,
                rms,
            });
        }
        if rms > 0.0 && sigma < f64::EPSILON * peak {
            return Err(NoiseError::BelowRounding {
                sensor: c,
                fraction,
                peak,
            });
        }
    }
    Ok(())
}

/// Adds white Gaussian noise of standard deviation `fraction × RMS(signal)`
/// to every sensor (SPEC §3), from a ChaCha8 generator seeded with `seed`:
/// the same seed gives the same noise on every machine.
pub fn add_noise(response: &mut Response, fraction: f64, seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let n = response.n_samples;
    for c in 0..response.n_sensors {
        let sigma = fraction * rms(response.sensor(c));
        let Ok(normal) = Normal::new(0.0, sigma) else {
            continue;
        };
        for v in &mut response.values[c * n..(c + 1) * n] {
            *v += normal.sample(&mut rng);
        }
    }
}
