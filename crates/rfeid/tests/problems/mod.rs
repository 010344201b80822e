//! Test problems with known answers for the identification solvers.
#![allow(dead_code)]
use nalgebra::DMatrix;
use rfeid::identification::problem::LeastSquares;

/// A failure reported by a test problem (a "diverged simulation").
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("the test model diverged at u = {0:?}")]
pub struct Diverged(pub Vec<f64>);

type ResidualFn = dyn Fn(&[f64], &mut [f64]) -> Result<(), Diverged> + Sync;
type JacobianFn = dyn Fn(&[f64], &mut DMatrix<f64>) + Sync;

/// A least-squares problem given by closures (residuals and exact Jacobian).
pub struct FnProblem {
    pub n: usize,
    pub m: usize,
    pub residuals: Box<ResidualFn>,
    pub jacobian: Box<JacobianFn>,
}

impl LeastSquares for FnProblem {
    type Workspace = ();
    type Error = Diverged;
    fn n_params(&self) -> usize {
        self.n
    }
    fn n_residuals(&self) -> usize {
        self.m
    }
    fn workspace(&self) {}
    fn residuals(&self, _: &mut (), u: &[f64], r: &mut [f64]) -> Result<(), Diverged> {
        (self.residuals)(u, r)
    }
    fn residuals_jacobian(
        &self,
        _: &mut (),
        u: &[f64],
        r: &mut [f64],
        jac: &mut DMatrix<f64>,
    ) -> Result<(), Diverged> {
        (self.residuals)(u, r)?;
        (self.jacobian)(u, jac);
        Ok(())
    }
}

/// Box of the exponential-decay fit: A ∈ [0.5, 4], k ∈ [0.2, 3].
pub const EXP_BOX: [(f64, f64); 2] = [(0.5, 4.0), (0.2, 3.0)];
/// True parameters of the exponential-decay fit.
pub const EXP_TRUE: [f64; 2] = [2.0, 1.3];

pub fn to_physical(u: &[f64], boxes: &[(f64, f64)]) -> Vec<f64> {
    u.iter()
        .zip(boxes)
        .map(|(&u, &(lo, hi))| lo + u * (hi - lo))
        .collect()
}

pub fn to_normalised(x: &[f64], boxes: &[(f64, f64)]) -> Vec<f64> {
    x.iter()
        .zip(boxes)
        .map(|(&x, &(lo, hi))| (x - lo) / (hi - lo))
        .collect()
}

/// y = A exp(−k t), t = 0, 0.1, …, 2.9, noise-free data at [`EXP_TRUE`];
/// exact answer u* = normalised [`EXP_TRUE`], J(u*) = 0.
pub fn exp_decay() -> FnProblem {
    let t: Vec<f64> = (0..30).map(|k| 0.1 * k as f64).collect();
    let y: Vec<f64> = t
        .iter()
        .map(|&t| EXP_TRUE[0] * (-EXP_TRUE[1] * t).exp())
        .collect();
    let t2 = t.clone();
    FnProblem {
        n: 2,
        m: t.len(),
        residuals: Box::new(move |u, r| {
            let x = to_physical(u, &EXP_BOX);
            for ((ri, &ti), &yi) in r.iter_mut().zip(&t).zip(&y) {
                *ri = yi - x[0] * (-x[1] * ti).exp();
            }
            Ok(())
        }),
        jacobian: Box::new(move |u, jac| exp_decay_jacobian(&t2, u, jac)),
    }
}

/// [`exp_decay`] with 200 samples over 0 … 3 s and seeded Gaussian noise of
/// standard deviation `sigma` on the data (Box–Muller on a fixed linear
/// congruential sequence): J at the minimum is about `200 σ²`.
pub fn noisy_exp_decay(sigma: f64) -> FnProblem {
    let m = 200;
    let t: Vec<f64> = (0..m).map(|k| 3.0 * k as f64 / m as f64).collect();
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut uniform = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    let y: Vec<f64> = t
        .iter()
        .map(|&t| {
            let (u1, u2) = (uniform(), uniform());
            let gauss = (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos();
            EXP_TRUE[0] * (-EXP_TRUE[1] * t).exp() + sigma * gauss
        })
        .collect();
    let t2 = t.clone();
    FnProblem {
        n: 2,
        m,
        residuals: Box::new(move |u, r| {
            let x = to_physical(u, &EXP_BOX);
            for ((ri, &ti), &yi) in r.iter_mut().zip(&t).zip(&y) {
                *ri = yi - x[0] * (-x[1] * ti).exp();
            }
            Ok(())
        }),
        jacobian: Box::new(move |u, jac| exp_decay_jacobian(&t2, u, jac)),
    }
}

/// `∂r/∂u` of the exponential-decay residuals `y − A e^{−k t}`.
fn exp_decay_jacobian(t: &[f64], u: &[f64], jac: &mut DMatrix<f64>) {
    let x = to_physical(u, &EXP_BOX);
    let (wa, wk) = (EXP_BOX[0].1 - EXP_BOX[0].0, EXP_BOX[1].1 - EXP_BOX[1].0);
    for (i, &ti) in t.iter().enumerate() {
        let e = (-x[1] * ti).exp();
        jac[(i, 0)] = -e * wa;
        jac[(i, 1)] = x[0] * ti * e * wk;
    }
}

/// Rosenbrock as residuals [10(x2 − x1²), 1 − x1] with x = 4u − 2 ∈ [−2, 2]²;
/// optimum x = (1, 1), u* = (0.75, 0.75), J = 0.
pub fn rosenbrock() -> FnProblem {
    FnProblem {
        n: 2,
        m: 2,
        residuals: Box::new(|u, r| {
            let (x1, x2) = (4.0 * u[0] - 2.0, 4.0 * u[1] - 2.0);
            r[0] = 10.0 * (x2 - x1 * x1);
            r[1] = 1.0 - x1;
            Ok(())
        }),
        jacobian: Box::new(|u, jac| {
            let x1 = 4.0 * u[0] - 2.0;
            jac[(0, 0)] = -20.0 * x1 * 4.0;
            jac[(0, 1)] = 10.0 * 4.0;
            jac[(1, 0)] = -4.0;
            jac[(1, 1)] = 0.0;
        }),
    }
}

/// Linear residuals r = A u − b (J quadratic), with the given A (row-major,
/// m × n) and b.
pub fn linear(a: Vec<f64>, b: Vec<f64>, n: usize) -> FnProblem {
    let m = b.len();
    let a2 = a.clone();
    FnProblem {
        n,
        m,
        residuals: Box::new(move |u, r| {
            for i in 0..m {
                r[i] = (0..n).map(|j| a[i * n + j] * u[j]).sum::<f64>() - b[i];
            }
            Ok(())
        }),
        jacobian: Box::new(move |_, jac| {
            for i in 0..m {
                for j in 0..n {
                    jac[(i, j)] = a2[i * n + j];
                }
            }
        }),
    }
}

/// Correlated linear residuals with the unconstrained optimum (1.3, 0.2)
/// outside the box; returns the problem and the constrained optimum
/// (1, u2*) on the face u1 = 1, u2* = a2ᵀ(b − a1)/‖a2‖².
pub fn correlated_face() -> (FnProblem, [f64; 2]) {
    let a = [1.0, 0.95, 0.95, 1.0, 0.3, -0.2];
    let u_unc = [1.3, 0.2];
    let b: Vec<f64> = (0..3)
        .map(|i| a[2 * i] * u_unc[0] + a[2 * i + 1] * u_unc[1])
        .collect();
    let (mut num, mut den) = (0.0, 0.0);
    for i in 0..3 {
        num += a[2 * i + 1] * (b[i] - a[2 * i]);
        den += a[2 * i + 1] * a[2 * i + 1];
    }
    (linear(a.to_vec(), b, 2), [1.0, num / den])
}
