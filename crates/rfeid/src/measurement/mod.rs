//! Measured signals: matching a data file to the model's sensors and
//! sampling (eq. 10, 15), and adding seeded measurement noise.
mod coloured;
pub mod measured;
pub mod simulated;
pub mod spectrum;

pub use coloured::add_filtered_noise;

use crate::io::timeseries::TimeSeries;
use crate::model::{Model, Sampling};
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
    /// A record sampled at another rate than the model.
    #[error(
        "the data are sampled at {} Hz, but the model samples at {} Hz: resample the data to \
         {} Hz (with an anti-aliasing filter when lowering the rate), or set \
         sample_rate = {} Hz in [simulation]; rfeid does not resample",
        short(*data_rate), short(*rate), short(*rate), short(*data_rate)
    )]
    RateMismatch {
        /// The data's rate, from its first and last time stamps, Hz.
        data_rate: f64,
        /// Model sample rate, Hz.
        rate: f64,
    },
    /// A sample time off the model's grid t_k = start + k / rate.
    #[error("sample {index} is at t = {time} s, but the model samples at t = {} s ({rate} Hz from the record's start at {start} s, to within {tolerance:.3e} s)", start + expected)]
    TimeMismatch {
        /// 0-based sample index.
        index: usize,
        /// Time in the file.
        time: f64,
        /// Time the model expects, from the record's start.
        expected: f64,
        /// The record's first time stamp.
        start: f64,
        /// The tolerance at this sample ([`GRID_TOLERANCE`]).
        tolerance: f64,
        /// Model sample rate, Hz.
        rate: f64,
    },
}

/// A rate or time for messages: 6 significant digits, so that a rate
/// computed from float32 time stamps (good to about 10⁻⁷) reads `500`
/// rather than `500.000014`.
fn short(x: f64) -> f64 {
    format!("{x:.5e}").parse().unwrap_or(x)
}

/// How far a time stamp may lie from the model's grid, as a fraction of the
/// sample interval: 10⁻³. A record's time stamp t_k is accepted when
/// |(t_k − t_0) − k·Δt| ≤ 10⁻³·Δt + 2⁻²⁴·(|t_k| + |t_0|); the second term
/// is the rounding of stamps stored as float32 (half a unit in the last
/// place of a 24-bit significand), so that float32 time columns of
/// acquisition systems pass at any record length. A stamp that far off
/// still names its sample unambiguously (the bound stays far below Δt/2
/// for records up to 10⁵ samples).
pub const GRID_TOLERANCE: f64 = 1e-3;

/// Relative rounding of a float32 value: half a unit in the last place.
const F32_ROUNDING: f64 = 1.0 / 16_777_216.0;

/// Measured signals on the model's sampling, with notes for the user.
#[derive(Debug, Clone, PartialEq)]
pub struct Matched {
    /// The signals in the model's sensor order, `n_samples` long.
    pub response: Response,
    /// What the user should know: columns ignored, a record shifted to
    /// start at t = 0, samples cut past the model's duration.
    pub notes: Vec<String>,
}

/// Measured signals in the model's sensor order and sampling (eq. 10, 15).
///
/// The record's time stamps must lie on the grid t_0 + k/rate to within
/// [`GRID_TOLERANCE`]; a record that starts at t_0 ≠ 0 (a triggered record)
/// is taken as starting at the model's t = 0, and a note says so. A record
/// sampled at another rate is an error naming both rates (no resampling).
/// Samples past the model's duration are cut, with a note; columns that are
/// not sensors are ignored, with a note.
pub fn match_data(model: &Model, data: &TimeSeries) -> Result<Matched, MeasurementError> {
    let sensors: Vec<&str> = model.sensors.iter().map(|s| s.name.as_str()).collect();
    let mut notes = Vec::new();
    notes.extend(extra_columns_note(&sensors, data));
    let s = model.sampling;
    let n = s.n_samples();
    let m = data.time.len();
    check_rate(data, &s)?;
    if m < n {
        return Err(MeasurementError::TooShort {
            found: m,
            needed: n,
            duration: s.duration,
            rate: s.sample_rate,
        });
    }
    if let Some(start) = check_grid(data, &s)? {
        notes.push(format!(
            "the record starts at t = {start} s; it is taken as starting at the model's t = 0"
        ));
    }
    if m > n {
        notes.push(format!(
            "the record has {m} samples ({} s); the model uses the first {n} ({} s at {} Hz), \
             the other {} are ignored",
            short(m as f64 * (1.0 / s.sample_rate)),
            s.duration,
            s.sample_rate,
            m - n
        ));
    }
    Ok(Matched {
        response: sensor_columns(&sensors, data, n)?,
        notes,
    })
}

/// A note naming the columns that are not sensors, if there are any.
fn extra_columns_note(sensors: &[&str], data: &TimeSeries) -> Option<String> {
    let extra: Vec<String> = data
        .names
        .iter()
        .filter(|c| !sensors.contains(&c.as_str()))
        .map(|c| format!("'{c}'"))
        .collect();
    (!extra.is_empty()).then(|| {
        format!(
            "columns that are not sensors, ignored: {}",
            extra.join(", ")
        )
    })
}

/// The record's mean sample interval (first to last stamp) must be the model's.
fn check_rate(data: &TimeSeries, s: &Sampling) -> Result<(), MeasurementError> {
    let m = data.time.len();
    if m >= 2 {
        let dt = 1.0 / s.sample_rate;
        let start = data.time[0];
        let step = (data.time[m - 1] - start) / (m - 1) as f64;
        if !((step - dt).abs() <= GRID_TOLERANCE * dt) {
            return Err(MeasurementError::RateMismatch {
                data_rate: 1.0 / step,
                rate: s.sample_rate,
            });
        }
    }
    Ok(())
}

/// Every used time stamp lies on the model's grid from the record's start;
/// the start, when the record is taken as shifted to t = 0.
fn check_grid(data: &TimeSeries, s: &Sampling) -> Result<Option<f64>, MeasurementError> {
    let dt = 1.0 / s.sample_rate;
    let start = data.time.first().copied().unwrap_or(0.0);
    let slack = |t: f64| GRID_TOLERANCE * dt + F32_ROUNDING * (t.abs() + start.abs());
    let shifted = start.abs() > slack(start);
    let origin = if shifted { start } else { 0.0 };
    for (k, &t) in data.time.iter().take(s.n_samples()).enumerate() {
        let expected = s.time(k);
        let tolerance = slack(t);
        if !((t - origin - expected).abs() <= tolerance) {
            return Err(MeasurementError::TimeMismatch {
                index: k,
                time: t,
                expected,
                start: origin,
                tolerance,
                rate: s.sample_rate,
            });
        }
    }
    Ok(shifted.then_some(start))
}

/// The first `n` samples of each sensor's column, in sensor order.
fn sensor_columns(
    sensors: &[&str],
    data: &TimeSeries,
    n: usize,
) -> Result<Response, MeasurementError> {
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
    /// σ = fraction × RMS, or the noisy signal, would not be finite or
    /// would exceed [`MAX_DATA_MAGNITUDE`](crate::io::data_file::MAX_DATA_MAGNITUDE),
    /// beyond which `identify` refuses data.
    #[error("noise of {fraction:e} × RMS overflows on sensor {sensor} (RMS {rms:e}): the noisy values would exceed {:e}, the largest measured value rfeid accepts", crate::io::data_file::MAX_DATA_MAGNITUDE)]
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
        // A normal sample beyond 40 σ has probability below 1e-300; the
        // noisy record must stay data that `identify` reads.
        let limit = crate::io::data_file::MAX_DATA_MAGNITUDE;
        let noisy = peak + 40.0 * sigma;
        if !sigma.is_finite() || !noisy.is_finite() || noisy > limit {
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

/// The normalised RMS fit of `fitted` to `measured`, %, as MATLAB's
/// `compare`: `100 (1 − ‖y − ŷ‖ / ‖y − mean(y)‖)`; 100 is a perfect fit, 0
/// no better than the mean. `None` for a constant measured signal.
pub fn fit_percent(measured: &[f64], fitted: &[f64]) -> Option<f64> {
    let (misfit, spread) = misfit_and_spread(measured, fitted);
    percent_fit(misfit, spread)
}

/// `100 (1 − misfit / spread)`, or `None` for a constant measured signal
/// (no spread).
pub fn percent_fit(misfit: f64, spread: f64) -> Option<f64> {
    (spread > 0.0).then(|| 100.0 * (1.0 - misfit / spread))
}

/// The misfit `‖y − ŷ‖` of `fitted` ŷ to `measured` y, and the spread
/// `‖y − mean(y)‖` of the measured signal.
pub fn misfit_and_spread(measured: &[f64], fitted: &[f64]) -> (f64, f64) {
    let n = measured.len().max(1) as f64;
    let mean = measured.iter().sum::<f64>() / n;
    let spread = measured
        .iter()
        .map(|v| (v - mean) * (v - mean))
        .sum::<f64>()
        .sqrt();
    let misfit = measured
        .iter()
        .zip(fitted)
        .map(|(y, g)| (y - g) * (y - g))
        .sum::<f64>()
        .sqrt();
    (misfit, spread)
}
