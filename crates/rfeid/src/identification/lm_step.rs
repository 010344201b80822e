//! The damped Gauss–Newton step of Levenberg–Marquardt, by two QR
//! factorisations.
//!
//! For the free variables F, the step δ minimises
//!
//! ```text
//! ‖J_F δ + r‖² + λ ‖D_F δ‖²
//! ```
//!
//! i.e. solves `(J_FᵀJ_F + λ D_F²) δ = −J_Fᵀ r` without forming `J_FᵀJ_F`
//! (which would square the condition number; joint parameters easily give
//! Jacobians with condition numbers of 10⁸). `J_F = Q R` is factorised once
//! per iteration (cost ≈ 2 N f², negligible beside a simulation); each trial
//! damping λ then factorises the small `2f × f` matrix `[R; √λ D_F]` and
//! solves a triangular system.
use super::blocked_qr::BlockedQr;
use super::problem::{evaluate_cost_factor, evaluate_cost_jacobian, EvalError, LeastSquares};
use nalgebra::{DMatrix, DVector};

/// A point of a Levenberg–Marquardt run and its evaluations: the residuals,
/// J, and the linear model's Jacobian, whole (N × n) or, for a problem that
/// takes it by blocks, as its triangular factor R (n × n) beside `Qᵀ r`.
/// The step, the gradient `Jᵀr = RᵀQᵀr`, the decrement and the predicted
/// decrease `‖J s‖² = ‖R s‖²` are the same from either.
pub(crate) struct State {
    pub(crate) u: Vec<f64>,
    pub(crate) r: Vec<f64>,
    pub(crate) jac: DMatrix<f64>,
    /// `Qᵀ r` beside R (by blocks); empty otherwise.
    qtr: Vec<f64>,
    pub(crate) cost: f64,
}

impl State {
    /// A state for n variables and m residuals.
    pub(crate) fn new(n: usize, m: usize, by_blocks: bool) -> Self {
        State {
            u: vec![0.0; n],
            r: vec![0.0; m],
            jac: DMatrix::zeros(if by_blocks { n } else { m }, n),
            qtr: Vec::new(),
            cost: 0.0,
        }
    }

    /// The residuals of the linear model: r, or `Qᵀ r` beside R.
    pub(crate) fn lin_res(&self) -> &[f64] {
        match self.qtr.is_empty() {
            true => &self.r,
            false => &self.qtr,
        }
    }

    /// Evaluates the residuals, J and the Jacobian (or, with `qr`, its
    /// factor) at `u`.
    pub(crate) fn linearise<P: LeastSquares>(
        &mut self,
        problem: &P,
        ws: &mut P::Workspace,
        qr: &mut Option<BlockedQr>,
    ) -> Result<(), EvalError<P::Error>> {
        self.cost = match qr {
            None => evaluate_cost_jacobian(problem, ws, &self.u, &mut self.r, &mut self.jac)?,
            Some(qr) => {
                let cost = evaluate_cost_factor(problem, ws, &self.u, &mut self.r, qr)?;
                self.jac.copy_from(qr.r());
                self.qtr.clear();
                self.qtr.extend_from_slice(qr.qtr());
                cost
            }
        };
        Ok(())
    }
}

/// QR factorisation of the free columns of the Jacobian, reused for every
/// damping value tried in one iteration.
pub(crate) struct DampedSolver {
    /// Upper-triangular factor R of `J_F = Q R` (min(N, f) × f).
    r: DMatrix<f64>,
    /// The first min(N, f) entries of `−Qᵀ r`.
    rhs: DVector<f64>,
    /// Scaling `D_F` of the free variables.
    scale: Vec<f64>,
}

impl DampedSolver {
    /// Factorises `J_F` (the free columns of `jac`, listed in `free`).
    pub(crate) fn new(
        jac: &DMatrix<f64>,
        residuals: &[f64],
        free: &[usize],
        scale: &[f64],
    ) -> Self {
        let jf = jac.select_columns(free.iter());
        let qr = jf.qr();
        let mut qtr = DVector::from_column_slice(residuals);
        qr.q_tr_mul(&mut qtr);
        let r = qr.unpack_r();
        let k = r.nrows();
        let rhs = -qtr.rows(0, k);
        DampedSolver {
            r,
            rhs,
            scale: free.iter().map(|&j| scale[j]).collect(),
        }
    }

    /// The Gauss–Newton decrement `‖Q₁ᵀ r‖²`: the decrease of J that the
    /// undamped step would give if the residuals were linear in u (the
    /// squared norm of the part of r in the span of J_F's columns).
    pub(crate) fn decrement(&self) -> f64 {
        self.rhs.norm_squared()
    }

    /// The step δ_F for damping `lambda` > 0, or `None` if the damped system
    /// is numerically singular or the step is not finite.
    pub(crate) fn step(&self, lambda: f64) -> Option<DVector<f64>> {
        let f = self.scale.len();
        let k = self.r.nrows();
        let mut a = DMatrix::zeros(k + f, f);
        a.view_mut((0, 0), (k, f)).copy_from(&self.r);
        let sqrt_lambda = lambda.sqrt();
        for (i, d) in self.scale.iter().enumerate() {
            a[(k + i, i)] = sqrt_lambda * d;
        }
        let mut b = DVector::zeros(k + f);
        b.rows_mut(0, k).copy_from(&self.rhs);
        let qr = a.qr();
        qr.q_tr_mul(&mut b);
        let r2 = qr.unpack_r();
        let mut delta = b.rows(0, f).into_owned();
        if !r2.solve_upper_triangular_mut(&mut delta) {
            return None;
        }
        delta.iter().all(|v| v.is_finite()).then_some(delta)
    }
}

/// Updates the Marquardt scaling `D` (Moré 1978): `d_j = max(d_j, ‖J_j‖)`,
/// the largest column norm seen so far, with a floor of `1e-8 · max_k d_k`
/// (or 1 when every column is zero) so a column of zeros does not make the
/// damping vanish for that variable.
pub(crate) fn update_scale(col_norms: &[f64], scale: &mut [f64]) {
    for (d, &c) in scale.iter_mut().zip(col_norms) {
        *d = d.max(c);
    }
    let max = scale.iter().fold(0.0_f64, |a, &d| a.max(d));
    let floor = if max > 0.0 { 1e-8 * max } else { 1.0 };
    for d in scale.iter_mut() {
        *d = d.max(floor);
    }
}
