//! Coloured measurement noise, as a data acquisition system's anti-alias
//! filter leaves it: white Gaussian noise through a second-order
//! Butterworth low-pass, for rehearsing an identification on realistic
//! records.
//!
//! The noise is stationary from the first sample on, as a rig records it:
//! the amplifiers and the filter were running long before the trigger. The
//! filter is run over a burn-in of white noise until its start-up has
//! decayed below rounding (its poles' radius r to the power of the burn-in
//! length under 1e-17) before the record begins.
use super::rms;
use crate::simulation::Response;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// Adds to every sensor stationary Gaussian noise passed through a
/// second-order Butterworth low-pass with its corner at `corner` Hz
/// (bilinear transform, pre-warped, for sampling at `sample_rate` Hz),
/// scaled so that its standard deviation over the record is
/// `fraction × RMS(signal)`; from a ChaCha8 generator seeded with `seed`.
/// Corners at or above the Nyquist frequency add white noise.
pub fn add_filtered_noise(
    response: &mut Response,
    fraction: f64,
    corner: f64,
    sample_rate: f64,
    seed: u64,
) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let n = response.n_samples;
    let mut noise = vec![0.0; n];
    let filter = (corner < sample_rate / 2.0).then(|| LowPass::butterworth(corner / sample_rate));
    for c in 0..response.n_sensors {
        let sigma = fraction * rms(response.sensor(c));
        let mut state = [0.0; 4];
        if let Some(f) = &filter {
            for _ in 0..f.burn_in() {
                f.step(&mut state, StandardNormal.sample(&mut rng));
            }
        }
        for v in noise.iter_mut() {
            let x = StandardNormal.sample(&mut rng);
            *v = match &filter {
                Some(f) => f.step(&mut state, x),
                None => x,
            };
        }
        let scale = sigma / rms(&noise).max(f64::MIN_POSITIVE);
        for (v, e) in response.values[c * n..(c + 1) * n].iter_mut().zip(&noise) {
            *v += scale * e;
        }
    }
}

/// A second-order Butterworth low-pass in direct form I:
/// `y_k = b0 x_k + b1 x_{k−1} + b2 x_{k−2} − a1 y_{k−1} − a2 y_{k−2}`.
struct LowPass {
    b: [f64; 3],
    a: [f64; 2],
}

/// The longest burn-in, in samples (a corner far below the sample rate).
const MAX_BURN_IN: usize = 10_000_000;

impl LowPass {
    /// The filter of normalised corner `fc` (cycles per sample, < 0.5).
    fn butterworth(fc: f64) -> Self {
        let k = (std::f64::consts::PI * fc).tan();
        let q = std::f64::consts::FRAC_1_SQRT_2;
        let norm = 1.0 / (1.0 + k / q + k * k);
        let b0 = k * k * norm;
        LowPass {
            b: [b0, 2.0 * b0, b0],
            a: [2.0 * (k * k - 1.0) * norm, (1.0 - k / q + k * k) * norm],
        }
    }

    /// Samples after which the response to the initial state has decayed
    /// by 1e-17: `ln(1e-17) / ln r`, r = √a2 the poles' radius (a complex
    /// pair for the Butterworth's Q = 1/√2), at least 100.
    fn burn_in(&self) -> usize {
        let ln_r = 0.5 * self.a[1].ln();
        let n = (17.0 * std::f64::consts::LN_10 / -ln_r).ceil();
        match n.is_finite() && n > 0.0 {
            true => (n as usize).clamp(100, MAX_BURN_IN),
            false => MAX_BURN_IN,
        }
    }

    /// One sample through the filter; `state` is [x_{k−1}, x_{k−2},
    /// y_{k−1}, y_{k−2}].
    fn step(&self, state: &mut [f64; 4], x: f64) -> f64 {
        let [x1, x2, y1, y2] = *state;
        let y = self.b[0] * x + self.b[1] * x1 + self.b[2] * x2 - self.a[0] * y1 - self.a[1] * y2;
        *state = [x, x1, y, y1];
        y
    }
}

/// The filter of normalised corner `fc` applied to `x` in place, from rest.
#[cfg(test)]
fn low_pass(x: &mut [f64], fc: f64) {
    let f = LowPass::butterworth(fc);
    let mut state = [0.0; 4];
    for v in x.iter_mut() {
        *v = f.step(&mut state, *v);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_dc_and_halves_the_power_at_the_corner() {
        let fc = 0.05;
        let gain = |f: f64| {
            let n = 20_000;
            let mut x: Vec<f64> = (0..n)
                .map(|k| (std::f64::consts::TAU * f * k as f64).cos())
                .collect();
            low_pass(&mut x, fc);
            rms(&x[n / 2..]) / std::f64::consts::FRAC_1_SQRT_2
        };
        let mut dc = vec![1.0; 1000];
        low_pass(&mut dc, fc);
        assert!((dc[999] - 1.0).abs() < 1e-9);
        assert!((gain(fc) - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-3);
        assert!(gain(0.4) < 0.01);
    }

    #[test]
    fn noise_has_the_asked_level_and_seed() {
        let mut a = Response {
            n_samples: 4000,
            n_sensors: 1,
            values: (0..4000).map(|k| (k as f64 * 0.01).sin()).collect(),
        };
        let clean = a.values.clone();
        let mut b = a.clone();
        add_filtered_noise(&mut a, 0.02, 1000.0, 10_000.0, 3);
        add_filtered_noise(&mut b, 0.02, 1000.0, 10_000.0, 3);
        assert_eq!(a, b);
        let e: Vec<f64> = a.values.iter().zip(&clean).map(|(x, y)| x - y).collect();
        assert!((rms(&e) - 0.02 * rms(&clean)).abs() < 1e-12);
    }

    #[test]
    fn noise_is_stationary_from_the_first_sample() {
        // Over 2000 seeds, the noise's variance at the first samples is
        // that at the record's end (a filter started from rest would give
        // b0² ≈ 0.02 of it at the first sample).
        let (n, seeds) = (200, 2000);
        let mut first = [0.0; 3];
        let mut last = 0.0;
        for seed in 0..seeds {
            let mut r = Response {
                n_samples: n,
                n_sensors: 1,
                values: vec![1.0; n],
            };
            add_filtered_noise(&mut r, 1.0, 500.0, 10_000.0, seed);
            // The per-record scaling to unit RMS is the same for every
            // sample of a record, so the ratios are the process's.
            for (k, f) in first.iter_mut().enumerate() {
                *f += (r.values[k] - 1.0).powi(2);
            }
            last += (r.values[n - 1] - 1.0).powi(2);
        }
        for f in first {
            // 2000 seeds: the ratio's standard deviation is about 0.045.
            assert!((f / last - 1.0).abs() < 0.2, "{f} vs {last}");
        }
    }
}
