//! Coloured measurement noise, as a data acquisition system's anti-alias
//! filter leaves it: white Gaussian noise through a second-order
//! Butterworth low-pass, for rehearsing an identification on realistic
//! records.
use super::rms;
use crate::simulation::Response;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// Adds to every sensor Gaussian noise passed through a second-order
/// Butterworth low-pass with its corner at `corner` Hz (bilinear transform,
/// pre-warped, for sampling at `sample_rate` Hz), scaled so that its
/// standard deviation is `fraction × RMS(signal)`; from a ChaCha8 generator
/// seeded with `seed`. Corners at or above the Nyquist frequency add white
/// noise.
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
    for c in 0..response.n_sensors {
        let sigma = fraction * rms(response.sensor(c));
        for v in noise.iter_mut() {
            *v = StandardNormal.sample(&mut rng);
        }
        if corner < sample_rate / 2.0 {
            low_pass(&mut noise, corner / sample_rate);
        }
        let scale = sigma / rms(&noise).max(f64::MIN_POSITIVE);
        for (v, e) in response.values[c * n..(c + 1) * n].iter_mut().zip(&noise) {
            *v += scale * e;
        }
    }
}

/// Second-order Butterworth low-pass of normalised corner `fc` (cycles per
/// sample, < 0.5) applied to `x` in place, from rest.
fn low_pass(x: &mut [f64], fc: f64) {
    let k = (std::f64::consts::PI * fc).tan();
    let q = std::f64::consts::FRAC_1_SQRT_2;
    let norm = 1.0 / (1.0 + k / q + k * k);
    let b0 = k * k * norm;
    let (b1, b2) = (2.0 * b0, b0);
    let a1 = 2.0 * (k * k - 1.0) * norm;
    let a2 = (1.0 - k / q + k * k) * norm;
    let (mut x1, mut x2, mut y1, mut y2) = (0.0, 0.0, 0.0, 0.0);
    for v in x.iter_mut() {
        let y = b0 * *v + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2;
        (x2, x1, y2, y1) = (x1, *v, y1, y);
        *v = y;
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
}
