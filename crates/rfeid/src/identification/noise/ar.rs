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
    /// κ_1 … κ_p, the reflection (partial autocorrelation) coefficients
    /// whose Levinson recursion builds the filter: the orders below p
    /// predict the record's first samples ([`Whitener`]). Empty when the
    /// model was given by its coefficients alone.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub reflection: Vec<f64>,
}

impl ArModel {
    /// White noise of variance σ² (the model of order 0).
    pub fn white(variance: f64) -> Self {
        ArModel {
            coefficients: Vec::new(),
            innovation_variance: variance,
            reflection: Vec::new(),
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
        let mut reflection: Vec<f64> = Vec::with_capacity(max_order);
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
            reflection.push(k);
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
                        reflection: reflection.clone(),
                    },
                );
            }
        }
        Some(best.1)
    }

    /// The whitening filter of this model, with its exact start
    /// ([`Whitener`]): from the reflection coefficients when the model has
    /// them (Burg's fit), else from the coefficients.
    pub fn whitener(&self) -> Whitener {
        match self.reflection.len() == self.coefficients.len() {
            true => Whitener::from_reflection(&self.reflection),
            false => Whitener::new(&self.coefficients),
        }
    }

    /// Whitens `x` in place ([`Whitener`]).
    pub fn whiten(&self, x: &mut [f64]) {
        self.whitener().apply(x);
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

/// The whitening of a record by an autoregressive model, with the exact
/// start of the stationary process's Gaussian likelihood.
///
/// Sample k ≥ p is filtered by `A(q)`: `ε_k = x_k + Σ_{i=1}^{p} a_i x_{k−i}`,
/// of variance σ² = σ_p². Sample k < p has only k samples before it; its
/// innovation is the error of the best linear predictor of order k of the
/// same stationary process, `x_k + Σ_{i=1}^{k} a^{(k)}_i x_{k−i}`, of
/// variance σ_k² = σ_p² / Π_{j=k+1}^{p} (1 − κ_j²), and is scaled by
/// σ_p / σ_k. Every row then has the innovation variance σ², and the rows
/// are independent: `Σ ε_k²` is the exact Gaussian log-likelihood of the
/// whole record under the model, up to its determinant (fixed while the
/// noise model is), i.e. `L⁻¹ x` for L the Cholesky factor of the
/// stationary Toeplitz covariance over σ² (the innovations algorithm).
/// The predictors a^{(k)} and variances come from the reflection
/// coefficients κ_j by the Levinson recursion, which is stable for
/// |κ_j| < 1 however close to 1, so nothing is inverted.
///
/// A filter given by its coefficients alone gets its reflection
/// coefficients by the step-down recursion ([`Whitener::new`]); one that
/// is not stationary (some |κ_j| ≥ 1) has no stationary start and is
/// truncated at the record's start instead (A(q)'s first k coefficients at
/// sample k, unscaled).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Whitener {
    /// a_1 … a_p.
    coefficients: Vec<f64>,
    /// The start's predictors, row k (0 < k < p) holding a^{(k)}_1 …
    /// a^{(k)}_k from index k (k − 1) / 2 on.
    start: Vec<f64>,
    /// σ_p / σ_k for k = 0 … p − 1.
    gains: Vec<f64>,
}

impl Whitener {
    /// No filter (white noise).
    pub const NONE: Whitener = Whitener {
        coefficients: Vec::new(),
        start: Vec::new(),
        gains: Vec::new(),
    };

    /// The whitener of the model with coefficients `a` (a_1 … a_p; empty:
    /// none), its reflection coefficients found by the step-down
    /// (backward Levinson) recursion.
    pub fn new(a: &[f64]) -> Self {
        match step_down(a) {
            Some(kappa) => Self::from_reflection(&kappa),
            None => Self::truncated(a),
        }
    }

    /// The whitener of the stationary model with reflection coefficients
    /// κ_1 … κ_p (each |κ| < 1), by the Levinson recursion
    /// `a^{(m)}_i = a^{(m−1)}_i + κ_m a^{(m−1)}_{m−i}`, `a^{(m)}_m = κ_m`.
    pub fn from_reflection(kappa: &[f64]) -> Self {
        let p = kappa.len();
        let mut start = Vec::with_capacity(p * p.saturating_sub(1) / 2);
        let mut a: Vec<f64> = Vec::with_capacity(p);
        let mut previous = Vec::with_capacity(p);
        for (m, &k) in kappa.iter().enumerate() {
            start.extend_from_slice(&a);
            previous.clone_from(&a);
            for i in 0..m {
                a[i] += k * previous[m - 1 - i];
            }
            a.push(k);
        }
        // σ_p² / σ_k² = Π_{j>k} (1 − κ_j²), as a running product from the end.
        let mut gains = vec![1.0; p];
        let mut ratio = 1.0;
        for k in (0..p).rev() {
            ratio *= 1.0 - kappa[k] * kappa[k];
            gains[k] = ratio.sqrt();
        }
        Whitener {
            coefficients: a,
            start,
            gains,
        }
    }

    /// The filter truncated at the record's start: sample k < p filtered
    /// by a_1 … a_k of `a`, unscaled.
    fn truncated(a: &[f64]) -> Self {
        let p = a.len();
        let mut start = Vec::with_capacity(p * p.saturating_sub(1) / 2);
        for k in 1..p {
            start.extend_from_slice(&a[..k]);
        }
        Whitener {
            coefficients: a.to_vec(),
            start,
            gains: vec![1.0; p],
        }
    }

    /// a_1 … a_p.
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    /// The order p (0: no filter).
    pub fn order(&self) -> usize {
        self.coefficients.len()
    }

    /// Whitens `x`, the record from its first sample on, in place, from
    /// the end backwards so that every sample read is still the input.
    /// Does not allocate.
    pub fn apply(&self, x: &mut [f64]) {
        let p = self.coefficients.len();
        if p == 0 {
            return;
        }
        for k in (p..x.len()).rev() {
            let mut acc = x[k];
            for (i, ai) in self.coefficients.iter().enumerate() {
                acc += ai * x[k - 1 - i];
            }
            x[k] = acc;
        }
        for k in (0..p.min(x.len())).rev() {
            let row = &self.start[k * k.saturating_sub(1) / 2..][..k];
            let mut acc = x[k];
            for (i, ai) in row.iter().enumerate() {
                acc += ai * x[k - 1 - i];
            }
            x[k] = self.gains[k] * acc;
        }
    }

    /// Whitens `values`, the next samples of a record whose samples before
    /// them are `past` (unfiltered, at most the filter's order p: all of
    /// them while the record has fewer), as [`Whitener::apply`] does them
    /// in the whole record, bit for bit; then keeps the last p unfiltered
    /// samples in `past` for the next call. `line` is scratch.
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

/// κ_1 … κ_p of the filter a_1 … a_p by the step-down recursion
/// `a^{(m−1)}_i = (a^{(m)}_i − κ_m a^{(m)}_{m−i}) / (1 − κ_m²)`,
/// `κ_m = a^{(m)}_m`; `None` when the filter is not that of a stationary
/// process (some |κ_m| ≥ 1, or a value not finite).
fn step_down(a: &[f64]) -> Option<Vec<f64>> {
    let p = a.len();
    let mut kappa = vec![0.0; p];
    let mut cur = a.to_vec();
    for m in (1..=p).rev() {
        let k = cur[m - 1];
        if !(k.abs() < 1.0) {
            return None;
        }
        kappa[m - 1] = k;
        let d = 1.0 - k * k;
        let next: Vec<f64> = (0..m - 1)
            .map(|i| (cur[i] - k * cur[m - 2 - i]) / d)
            .collect();
        if next.iter().any(|v| !v.is_finite()) {
            return None;
        }
        cur = next;
    }
    Some(kappa)
}

/// Σ ε² of what `filter` leaves of `e`.
pub(crate) fn whitened_ssr(filter: &Whitener, e: &[f64]) -> f64 {
    let mut w = e.to_vec();
    filter.apply(&mut w);
    w.iter().map(|v| v * v).sum()
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
            reflection: vec![],
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
    fn a_filter_that_is_not_stationary_is_truncated_at_the_start() {
        // A(z) = 1 − 2.5 z⁻¹ + z⁻²: a root at z = 2, no stationary process.
        let mut x = vec![2.0, 3.0, 5.0];
        Whitener::new(&[-2.5, 1.0]).apply(&mut x);
        assert_eq!(x, vec![2.0, 3.0 - 2.5 * 2.0, 5.0 - 2.5 * 3.0 + 2.0]);
    }

    #[test]
    fn the_start_of_an_ar1_is_scaled_by_its_stationary_variance() {
        // e_k = 0.9 e_{k−1} + ε_k: Var e = σ² / (1 − 0.81), so the first
        // row is e_0 √(1 − 0.81); the others are e_k − 0.9 e_{k−1}.
        let mut x = vec![2.0, 3.0, 5.0];
        Whitener::new(&[-0.9]).apply(&mut x);
        let expected = [2.0 * 0.19f64.sqrt(), 3.0 - 0.9 * 2.0, 5.0 - 0.9 * 3.0];
        for (a, b) in x.iter().zip(&expected) {
            assert!((a - b).abs() < 1e-15, "{x:?}");
        }
    }

    #[test]
    fn step_down_inverts_the_levinson_recursion() {
        let kappa = [0.95, -0.7, 0.3, -0.999];
        let w = Whitener::from_reflection(&kappa);
        let back = step_down(w.coefficients()).unwrap();
        for (a, b) in back.iter().zip(&kappa) {
            assert!((a - b).abs() < 1e-9, "{back:?}");
        }
        let v = Whitener::new(w.coefficients());
        for (a, b) in v.gains.iter().zip(&w.gains) {
            assert!(
                (a - b).abs() < 1e-9 * b.max(1e-3),
                "{:?} {:?}",
                v.gains,
                w.gains
            );
        }
        for (a, b) in v.start.iter().zip(&w.start) {
            assert!((a - b).abs() < 1e-9, "{:?} {:?}", v.start, w.start);
        }
    }

    #[test]
    fn every_whitened_row_has_the_innovation_variance() {
        // A stationary AR(2) with poles at radius 0.98 (e^{±0.3i}): over
        // 8000 records of 500 samples, each whitened at its exact start,
        // every row's variance is within 10 % of σ² = 1. (A row's variance
        // over R records has a standard deviation of √(2/R): 1.6 % here, so
        // the largest of 500 is far inside 10 %; over 2000 records it
        // would be about 10 % by chance alone.) The truncated start leaves
        // the first rows at many times σ².
        let (r, theta) = (0.98f64, 0.3f64);
        let a = [-2.0 * r * theta.cos(), r * r];
        let exact = Whitener::new(&a);
        let truncated = Whitener::truncated(&a);
        let (n, records) = (500, 8000);
        let (mut var, mut var_truncated) = (vec![0.0; n], vec![0.0; n]);
        let mut rng = ChaCha8Rng::seed_from_u64(42);
        for _ in 0..records {
            // A burn-in of 3000 samples: 0.98³⁰⁰⁰ of the start is left.
            let (mut e1, mut e2) = (0.0, 0.0);
            let mut record = Vec::with_capacity(n);
            for k in 0..3000 + n {
                let eps: f64 = StandardNormal.sample(&mut rng);
                let e = -a[0] * e1 - a[1] * e2 + eps;
                (e2, e1) = (e1, e);
                if k >= 3000 {
                    record.push(e);
                }
            }
            let mut t = record.clone();
            exact.apply(&mut record);
            truncated.apply(&mut t);
            for k in 0..n {
                var[k] += record[k] * record[k] / records as f64;
                var_truncated[k] += t[k] * t[k] / records as f64;
            }
        }
        let worst = var.iter().map(|v| (v - 1.0).abs()).fold(0.0, f64::max);
        assert!(
            worst < 0.1,
            "worst row variance off by {worst}: {:?}",
            &var[..4]
        );
        assert!(var_truncated[0] > 20.0, "{:?}", &var_truncated[..4]);
    }

    #[test]
    fn density_integrates_to_the_variance() {
        // AR(1) with a = −0.9: variance σ² / (1 − 0.81).
        let m = ArModel {
            coefficients: vec![-0.9],
            innovation_variance: 1.0,
            reflection: vec![],
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
