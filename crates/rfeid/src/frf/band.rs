//! Confidence bands of an FRF from the estimate's covariance, by the delta
//! method: with the Cramér–Rao covariance Σ of x̂ (eq. 26–29) and the exact
//! derivatives of H ([`super::response`]), `log|H|` and `arg H` have
//! variances `gᵀ Σ g` with `g_j = Re(∂_j H / H)` and `Im(∂_j H / H)`.
//! The magnitude's band is taken on `log|H|` (it stays positive and is
//! symmetric on a log axis): `|H| exp(± z σ)`.
use super::response::{Frf, C64};
use nalgebra::DMatrix;

/// The two-sided 95 % quantile of the standard normal distribution.
pub const Z95: f64 = 1.959963984540054;

/// A band about one FRF, per frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct Band {
    /// Standard deviation of `ln|H|`.
    pub log_magnitude_sd: Vec<f64>,
    /// Standard deviation of the phase, rad.
    pub phase_sd: Vec<f64>,
}

impl Band {
    /// The magnitude's bounds at quantile `z` (e.g. [`Z95`]), given |H|.
    pub fn magnitude_bounds(&self, magnitude: &[f64], z: f64) -> (Vec<f64>, Vec<f64>) {
        magnitude
            .iter()
            .zip(&self.log_magnitude_sd)
            .map(|(m, s)| (m * (-z * s).exp(), m * (z * s).exp()))
            .unzip()
    }
}

/// The band of pair `pair` of `frf` for the covariance `cov` of the
/// parameters it was differentiated in (r × r, in their SI units).
pub fn band(frf: &Frf, pair: usize, cov: &DMatrix<f64>) -> Band {
    let r = frf.parameters;
    assert_eq!(cov.nrows(), r, "one covariance row per parameter");
    let (mut log_magnitude_sd, mut phase_sd) = (Vec::new(), Vec::new());
    let mut g = vec![C64::new(0.0, 0.0); r];
    for (k, h) in frf.values[pair].iter().enumerate() {
        let dh = &frf.derivatives[pair][k * r..(k + 1) * r];
        for (gj, d) in g.iter_mut().zip(dh) {
            *gj = if h.norm() > 0.0 {
                d / h
            } else {
                C64::new(0.0, 0.0)
            };
        }
        let quad = |part: fn(&C64) -> f64| {
            let mut s = 0.0;
            for i in 0..r {
                for j in 0..r {
                    s += part(&g[i]) * cov[(i, j)] * part(&g[j]);
                }
            }
            s.max(0.0).sqrt()
        };
        log_magnitude_sd.push(quad(|c| c.re));
        phase_sd.push(quad(|c| c.im));
    }
    Band {
        log_magnitude_sd,
        phase_sd,
    }
}
