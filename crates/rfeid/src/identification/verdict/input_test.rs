//! The residual–input test: a correct model leaves residuals that do not
//! depend on the input (Ljung, *System Identification*, §16.6).
//!
//! The measurement noise of an output-error model is independent of the
//! excitation, whatever its colour; a misfit of the dynamics is not: it is
//! the input passed through the difference of two systems, or, for a
//! misfit of a nonlinear joint, through a nonlinear map (harmonics of a
//! sine). The test regresses what the noise model leaves, ε, on the inputs
//! and their past (`u_i(t_k − τ)`, τ = 0 … [`LAGS`] samples) and on their
//! squares and cubes and those of the last [`POWER_LAGS`] samples (a cube
//! of a sine holds its third harmonic), from sample [`LAGS`] on (every
//! regressor then has its samples: no column is cut at the record's
//! start). With ε white and independent of the
//! inputs, any function of them is a valid regressor, and
//! `T = εᵀ P ε / σ̂²` (P the projection on the regressors, σ̂² = εᵀε / n)
//! is χ² with as many degrees of freedom as the regressors have
//! independent directions.
//! The regression has an intercept: the residuals and every regressor are
//! centred (their means over the samples tested removed), so an offset of
//! the residuals (a sensor's bias, or the drift of 1/f noise over a short
//! record) is not taken for dependence on the input through a regressor
//! with a mean (the square of a sine has one).
//!
//! A noise model fitted to residuals that hold a misfit whitens it only in
//! part, and what is left still follows the input: this test is what tells
//! model error from coloured noise (a misfit small beside the noise can
//! pass it, as it passes every residual test).
use nalgebra::{DMatrix, DVector, SymmetricEigen};

/// Past samples of each input regressed on, besides the present one.
pub const LAGS: usize = 10;

/// Past samples of each input's square and cube regressed on, besides the
/// present one.
pub const POWER_LAGS: usize = 2;

/// Eigenvalues of the regressors' (column-scaled) normal matrix below this
/// fraction of the largest are directions the inputs do not span.
const RANK_TOLERANCE: f64 = 1e-9;

/// `T` and its degrees of freedom for residuals `e` against `inputs` (each
/// as long as `e`), or `None` when there is no input, no residual, or no
/// direction the inputs span.
pub fn input_statistic(e: &[f64], inputs: &[Vec<f64>]) -> Option<(f64, usize)> {
    InputRegressors::new(inputs, e.len())?.statistic(e)
}

/// The regressors of the test for records of one length, with the
/// eigen-decomposition of their column-scaled normal matrix.
pub struct InputRegressors<'a> {
    inputs: &'a [Vec<f64>],
    /// (input, lag, power) of each regressor.
    columns: Vec<(usize, usize, i32)>,
    /// Each column's mean over the samples tested.
    means: Vec<f64>,
    /// Each centred column's norm.
    scale: Vec<f64>,
    /// The spanned directions: eigenvalue and eigenvector.
    directions: Vec<(f64, DVector<f64>)>,
}

impl<'a> InputRegressors<'a> {
    /// The regressors of `inputs` for `n` samples; `None` without an input
    /// that is not zero, for too short a record, or when they span nothing.
    pub fn new(inputs: &'a [Vec<f64>], n: usize) -> Option<Self> {
        let columns: Vec<(usize, usize, i32)> = inputs
            .iter()
            .enumerate()
            .filter(|(_, u)| u.len() == n && u.iter().any(|v| *v != 0.0))
            .flat_map(|(i, _)| {
                let linear = (0..=LAGS).map(move |lag| (i, lag, 1));
                let powers = [2, 3]
                    .into_iter()
                    .flat_map(move |p| (0..=POWER_LAGS).map(move |lag| (i, lag, p)));
                linear.chain(powers)
            })
            .collect();
        let m = columns.len();
        if m == 0 || n <= LAGS + 2 * m {
            return None;
        }
        let mut x = InputRegressors {
            inputs,
            columns,
            means: vec![0.0; m],
            scale: Vec::new(),
            directions: Vec::new(),
        };
        let mut row = vec![0.0; m];
        let mut sums = vec![0.0; m];
        for k in LAGS..n {
            x.row(k, &mut row);
            for (s, r) in sums.iter_mut().zip(&row) {
                *s += r;
            }
        }
        x.means = sums.iter().map(|s| s / (n - LAGS) as f64).collect();
        let mut normal = DMatrix::<f64>::zeros(m, m);
        for k in LAGS..n {
            x.row(k, &mut row);
            for a in 0..m {
                if row[a] != 0.0 {
                    for b in a..m {
                        normal[(a, b)] += row[a] * row[b];
                    }
                }
            }
        }
        // A constant input's regressors are the intercept's: centred, they
        // are zero, and stay zero (a direction of eigenvalue 0, not spanned).
        x.scale = (0..m)
            .map(|a| match normal[(a, a)] > 0.0 {
                true => normal[(a, a)].sqrt(),
                false => 1.0,
            })
            .collect();
        for a in 0..m {
            for b in a..m {
                let v = normal[(a, b)] / (x.scale[a] * x.scale[b]);
                normal[(a, b)] = v;
                normal[(b, a)] = v;
            }
        }
        let eig = SymmetricEigen::new(normal);
        let top = eig.eigenvalues.iter().cloned().fold(0.0, f64::max);
        x.directions = eig
            .eigenvalues
            .iter()
            .enumerate()
            .filter(|(_, &l)| l > RANK_TOLERANCE * top)
            .map(|(j, &l)| (l, eig.eigenvectors.column(j).into_owned()))
            .collect();
        (!x.directions.is_empty()).then_some(x)
    }

    /// The number of regressors.
    pub fn columns(&self) -> usize {
        self.columns.len()
    }

    /// The regressors at sample k ≥ [`LAGS`], centred (their means are
    /// zero until [`InputRegressors::new`] has them), into `row`.
    fn row(&self, k: usize, row: &mut [f64]) {
        for ((r, &(i, lag, power)), mean) in row.iter_mut().zip(&self.columns).zip(&self.means) {
            *r = self.inputs[i][k - lag].powi(power) - mean;
        }
    }

    /// `Xᵀ e` in the scaled columns, projected on each spanned direction.
    fn projections(&self, e: &[f64]) -> Vec<f64> {
        let m = self.columns.len();
        let mut right = DVector::<f64>::zeros(m);
        let mut row = vec![0.0; m];
        for (k, ek) in e.iter().enumerate().skip(LAGS) {
            self.row(k, &mut row);
            for a in 0..m {
                right[a] += row[a] * ek;
            }
        }
        for a in 0..m {
            right[a] /= self.scale[a];
        }
        self.directions.iter().map(|(_, v)| v.dot(&right)).collect()
    }

    /// `T` and its degrees of freedom for residuals `e` (as long as the
    /// record), or `None` for zero residuals.
    pub fn statistic(&self, e: &[f64]) -> Option<(f64, usize)> {
        let used = &e[LAGS.min(e.len())..];
        let mean = used.iter().sum::<f64>() / used.len().max(1) as f64;
        let sigma2 =
            used.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / used.len().max(1) as f64;
        if !(sigma2 > 0.0) {
            return None;
        }
        // The regressors are centred, so Xᵀ(e − ē) = Xᵀe: the projections
        // need not centre e.
        let t: f64 = self
            .projections(e)
            .iter()
            .zip(&self.directions)
            .map(|(p, (l, _))| p * p / l)
            .sum();
        Some((t / sigma2, self.directions.len()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::identification::chi_square::chi_square_sf;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, StandardNormal};

    fn noise(n: usize, seed: u64) -> Vec<f64> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        (0..n).map(|_| StandardNormal.sample(&mut rng)).collect()
    }

    fn sine(n: usize, cycles_per_sample: f64) -> Vec<f64> {
        (0..n)
            .map(|k| (std::f64::consts::TAU * cycles_per_sample * k as f64).sin())
            .collect()
    }

    #[test]
    fn noise_independent_of_the_input_passes() {
        let n = 5000;
        let u = sine(n, 0.008);
        let mut p_values = Vec::new();
        for seed in 0..20 {
            let (t, rank) = input_statistic(&noise(n, seed), std::slice::from_ref(&u)).unwrap();
            // sin and cos; their squares' second harmonic (their constant
            // is the intercept's); the cubes' third harmonic.
            assert_eq!(rank, 6);
            p_values.push(chi_square_sf(t, rank));
        }
        // Independent noise: p uniform; none of 20 below 1e-3 but by chance.
        assert!(
            p_values.iter().filter(|p| **p < 1e-3).count() <= 1,
            "{p_values:?}"
        );
    }

    #[test]
    fn a_misfit_that_follows_the_input_fails() {
        let n = 5000;
        let u = sine(n, 0.008);
        // A 2 % gain error with a phase lag, on unit noise 50 times larger.
        let e: Vec<f64> = noise(n, 7)
            .iter()
            .zip(sine(n, 0.008).iter().cycle().skip(3))
            .map(|(w, s)| w + 0.2 * s)
            .collect();
        let (t, rank) = input_statistic(&e, &[u]).unwrap();
        assert!(chi_square_sf(t, rank) < 1e-6, "T = {t}");
    }

    #[test]
    fn a_third_harmonic_of_the_input_fails() {
        // What a misfit of a cubic spring leaves under a sine: its third
        // harmonic, uncorrelated with the sine itself.
        let n = 5000;
        let u = sine(n, 0.008);
        let e: Vec<f64> = noise(n, 8)
            .iter()
            .zip(sine(n, 0.024))
            .map(|(w, s)| w + 0.2 * s)
            .collect();
        let (t, rank) = input_statistic(&e, &[u]).unwrap();
        assert!(chi_square_sf(t, rank) < 1e-6, "T = {t} on {rank}");
    }

    #[test]
    fn an_offset_of_the_residuals_is_not_the_input() {
        // White noise plus a constant (a sensor's bias): the square of the
        // sine has a mean, but the offset does not follow the input.
        let n = 5000;
        let u = sine(n, 0.008);
        for seed in 0..5 {
            let e: Vec<f64> = noise(n, seed).iter().map(|w| w + 0.5).collect();
            let (t, rank) = input_statistic(&e, std::slice::from_ref(&u)).unwrap();
            assert!(
                chi_square_sf(t, rank) > 1e-4,
                "seed {seed}: T = {t} on {rank}"
            );
        }
    }

    #[test]
    fn a_constant_input_beside_a_varying_one_is_the_intercept() {
        // An input's offset modelled as a constant force: the test runs on
        // the varying input's directions.
        let n = 5000;
        let inputs = [sine(n, 0.008), vec![3.0; n]];
        let (_, rank) = input_statistic(&noise(n, 1), &inputs).unwrap();
        assert_eq!(rank, 6);
    }

    #[test]
    fn no_input_no_test() {
        assert!(input_statistic(&noise(100, 1), &[]).is_none());
        assert!(input_statistic(&noise(100, 1), &[vec![0.0; 100]]).is_none());
        assert!(input_statistic(&[0.0; 100], &[sine(100, 0.1)]).is_none());
    }
}
