//! Autoregressive models of a sensor's residuals: the fit (Burg's method,
//! order by the Bayesian information criterion), the whitening filter and
//! the model's spectrum.
//!
//! The residuals e of a correct model are its measurement noise. Modelled
//! as `e_k + a_1 e_{k−1} + … + a_p e_{k−p} = ε_k`, ε white of variance σ²,
//! the filter `A(q) = 1 + a_1 q⁻¹ + … + a_p q⁻ᵖ` turns them into ε; applied
//! to the residuals of eq. 13 it makes the criterion the prediction-error
//! criterion of a model with noise model 1/A, whose Cramér–Rao bound
//! (eq. 26–29 on the filtered Jacobian) stays honest when the noise is
//! coloured.
use serde::{Deserialize, Serialize};

/// An autoregressive model `A(q) e = ε` of a noise sequence.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ArModel {
    /// a_1 … a_p (empty: white noise).
    pub coefficients: Vec<f64>,
    /// σ², the variance of the innovations ε (per sample).
    pub innovation_variance: f64,
}

impl ArModel {
    /// White noise of variance σ² (the model of order 0).
    pub fn white(variance: f64) -> Self {
        ArModel {
            coefficients: Vec::new(),
            innovation_variance: variance,
        }
    }

    /// The order p.
    pub fn order(&self) -> usize {
        self.coefficients.len()
    }

    /// The model of `e` of the order 0 … `max_order` (at most a fiftieth of
    /// the samples: a short record has no room for a coloured noise model) with the least Bayesian information criterion
    /// `n ln σ²_p + p ln n`, fitted by Burg's method (the criterion's
    /// residuals are not centred). Burg's reflection coefficients minimise
    /// the forward and backward prediction errors of the record itself, so
    /// the filter is always stable and, unlike the Yule–Walker equations on
    /// a tapered autocovariance, it whitens noise whose spectrum spans many
    /// decades (a low-pass that leaves almost nothing near the Nyquist
    /// frequency). `None` for an empty or all-zero `e`.
    pub fn fit(e: &[f64], max_order: usize) -> Option<Self> {
        let n = e.len();
        let max_order = max_order.min(n / 50);
        let energy = e.iter().map(|v| v * v).sum::<f64>();
        if n == 0 || !(energy > 0.0) || !energy.is_finite() {
            return None;
        }
        let ln_n = (n as f64).ln();
        let mut variance = energy / n as f64;
        let mut best = (n as f64 * variance.ln(), ArModel::white(variance));
        // Forward and backward prediction errors of the current order.
        let (mut f, mut b) = (e.to_vec(), e.to_vec());
        let mut a: Vec<f64> = Vec::with_capacity(max_order);
        for p in 1..=max_order {
            let (mut num, mut den) = (0.0, 0.0);
            for i in p..n {
                num += f[i] * b[i - 1];
                den += f[i] * f[i] + b[i - 1] * b[i - 1];
            }
            let k = -2.0 * num / den;
            if !k.is_finite() || k.abs() >= 1.0 {
                break;
            }
            // Levinson's update of the coefficients, then of the errors
            // (from the end, so that b[i − 1] is still of the last order).
            let previous = a.clone();
            for i in 0..a.len() {
                a[i] += k * previous[previous.len() - 1 - i];
            }
            a.push(k);
            for i in (p..n).rev() {
                let (fi, bi) = (f[i], b[i - 1]);
                f[i] = fi + k * bi;
                b[i] = bi + k * fi;
            }
            variance *= 1.0 - k * k;
            if !(variance > 0.0) {
                break;
            }
            let bic = n as f64 * variance.ln() + p as f64 * ln_n;
            if bic < best.0 {
                best = (
                    bic,
                    ArModel {
                        coefficients: a.clone(),
                        innovation_variance: variance,
                    },
                );
            }
        }
        Some(best.1)
    }

    /// Whitens `x` in place ([`Whitener`]).
    pub fn whiten(&self, x: &mut [f64]) {
        whiten(&self.coefficients, x);
    }

    /// The model's one-sided power spectral density at `f` Hz for sampling
    /// at `fs` Hz, `2 σ² / (fs |A(e^{iω})|²)` with `ω = 2π f / fs`, in the
    /// signal's unit squared per Hz (it integrates to the variance over
    /// 0 … fs/2).
    pub fn density(&self, f: f64, fs: f64) -> f64 {
        let w = std::f64::consts::TAU * f / fs;
        let (mut re, mut im) = (1.0, 0.0);
        for (i, a) in self.coefficients.iter().enumerate() {
            let phase = w * (i + 1) as f64;
            re += a * phase.cos();
            im -= a * phase.sin();
        }
        2.0 * self.innovation_variance / (fs * (re * re + im * im))
    }
}

/// The whitening of a record by an autoregressive model: sample k ≥ p is
/// filtered by `A(q)`, sample k < p, which has only k samples before it, by
/// `A(q)` truncated at the record's start. (An exact start, the
/// lower-order predictors of the same process by the Levinson recursion run
/// backwards, is ill-conditioned for reflection coefficients near ±1; the
/// truncated start costs a few rows of larger variance.)
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Whitener {
    coefficients: Vec<f64>,
}

impl Whitener {
    /// The whitener of the model with coefficients `a` (a_1 … a_p; empty:
    /// none).
    pub fn new(a: &[f64]) -> Self {
        Whitener {
            coefficients: a.to_vec(),
        }
    }

    /// a_1 … a_p.
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    /// Whitens `x` in place, from the end backwards so that every sample
    /// read is still the input. Does not allocate.
    pub fn apply(&self, x: &mut [f64]) {
        for k in (1..x.len()).rev() {
            let mut acc = x[k];
            for (i, ai) in self.coefficients.iter().enumerate().take(k) {
                acc += ai * x[k - 1 - i];
            }
            x[k] = acc;
        }
    }

    /// Whitens `values`, the next samples of a record whose samples before
    /// them are `past` (unfiltered, at most the filter's order p), as
    /// [`Whitener::apply`] does them in the whole record, bit for bit; then
    /// keeps the last p unfiltered samples in `past` for the next call.
    /// `line` is scratch.
    pub fn apply_after(&self, past: &mut Vec<f64>, values: &mut [f64], line: &mut Vec<f64>) {
        line.clear();
        line.extend_from_slice(past);
        line.extend_from_slice(values);
        let keep = self.coefficients.len().min(line.len());
        past.clear();
        past.extend_from_slice(&line[line.len() - keep..]);
        let h = line.len() - values.len();
        self.apply(line);
        values.copy_from_slice(&line[h..]);
    }
}

/// Σ (A(q) e)² for the coefficients `a` (a_1 … a_p): the sum of squares of
/// what the filter leaves of `e`.
pub(crate) fn whitened_ssr(a: &[f64], e: &[f64]) -> f64 {
    let mut w = e.to_vec();
    whiten(a, &mut w);
    w.iter().map(|v| v * v).sum()
}

/// [`Whitener`] of the coefficients `a` (a_1 … a_p) applied to `x`.
pub(crate) fn whiten(a: &[f64], x: &mut [f64]) {
    if !a.is_empty() {
        Whitener::new(a).apply(x);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, StandardNormal};

    fn noise(n: usize, seed: u64) -> Vec<f64> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        (0..n).map(|_| StandardNormal.sample(&mut rng)).collect()
    }

    #[test]
    fn white_noise_gets_order_zero() {
        let e = noise(20_000, 1);
        let m = ArModel::fit(&e, 20).unwrap();
        assert_eq!(m.order(), 0);
        assert!((m.innovation_variance - 1.0).abs() < 0.03);
    }

    #[test]
    fn recovers_an_ar2_process_and_whitens_it() {
        // e_k = 1.6 e_{k−1} − 0.8 e_{k−2} + ε_k: A(q) = 1 − 1.6 q⁻¹ + 0.8 q⁻².
        let eps = noise(50_000, 2);
        let mut e = vec![0.0; eps.len()];
        for k in 0..e.len() {
            let past1 = if k >= 1 { e[k - 1] } else { 0.0 };
            let past2 = if k >= 2 { e[k - 2] } else { 0.0 };
            e[k] = 1.6 * past1 - 0.8 * past2 + eps[k];
        }
        let m = ArModel::fit(&e, 20).unwrap();
        assert_eq!(m.order(), 2, "{m:?}");
        assert!((m.coefficients[0] + 1.6).abs() < 0.01, "{m:?}");
        assert!((m.coefficients[1] - 0.8).abs() < 0.01, "{m:?}");
        assert!((m.innovation_variance - 1.0).abs() < 0.02, "{m:?}");
        // The exact filter turns e back into ε (after its start).
        let mut w = e.clone();
        ArModel {
            coefficients: vec![-1.6, 0.8],
            innovation_variance: 1.0,
        }
        .whiten(&mut w);
        for (a, b) in w.iter().zip(&eps).skip(2) {
            assert!((a - b).abs() < 1e-12);
        }
    }

    #[test]
    fn whitens_noise_an_anti_alias_filter_leaves() {
        // A second-order Butterworth at 1/20 of the sample rate (bilinear:
        // a double zero at the Nyquist frequency), 3000 samples, 5 seeds:
        // what the fitted filter leaves passes the verdict's Ljung–Box test.
        use crate::identification::chi_square::chi_square_sf;
        use crate::identification::verdict::ljung_box;
        for seed in 0..5 {
            let mut r = crate::simulation::Response {
                n_samples: 3000,
                n_sensors: 1,
                values: vec![1.0; 3000],
            };
            crate::measurement::add_filtered_noise(&mut r, 1.0, 500.0, 10_000.0, seed);
            let mut e: Vec<f64> = r.values.iter().map(|v| v - 1.0).collect();
            let m = ArModel::fit(&e, 64).unwrap();
            assert!(m.order() > 10, "{}", m.order());
            m.whiten(&mut e);
            let q = ljung_box(&e, 20).unwrap();
            assert!(
                chi_square_sf(q, 20) > 1e-6,
                "seed {seed}: Q = {q}, order {}",
                m.order()
            );
        }
    }

    #[test]
    fn the_start_is_filtered_by_the_truncated_filter() {
        let mut x = vec![2.0, 3.0, 5.0];
        Whitener::new(&[-0.9, 0.2]).apply(&mut x);
        assert_eq!(x, vec![2.0, 3.0 - 0.9 * 2.0, 5.0 - 0.9 * 3.0 + 0.2 * 2.0]);
    }

    #[test]
    fn density_integrates_to_the_variance() {
        // AR(1) with a = −0.9: variance σ² / (1 − 0.81).
        let m = ArModel {
            coefficients: vec![-0.9],
            innovation_variance: 1.0,
        };
        let fs = 1000.0;
        let n = 200_000;
        let df = fs / 2.0 / n as f64;
        let integral: f64 = (0..n)
            .map(|i| m.density((i as f64 + 0.5) * df, fs) * df)
            .sum();
        assert!(
            (integral - 1.0 / 0.19).abs() < 1e-6 * integral,
            "{integral}"
        );
    }

    #[test]
    fn degenerate_records_have_no_model() {
        assert!(ArModel::fit(&[], 5).is_none());
        assert!(ArModel::fit(&[0.0; 100], 5).is_none());
        let short = ArModel::fit(&[1.0, -1.0, 1.0, -1.0], 5).unwrap();
        assert_eq!(short.order(), 0);
    }
}
