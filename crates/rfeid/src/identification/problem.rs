//! The least-squares problem the identification solvers work on.
//!
//! The paper's criterion (eq. 13, with R⁻¹ = I/σ² of eq. 14, reduced to
//! eq. 16) is a sum of squared residuals
//!
//! ```text
//! J(u) = Σ_i r_i(u)²,        u ∈ [0, 1]^n
//! ```
//!
//! where `r = y − g(x(u))` stacks every sensor sample and `u` are the decision
//! variables of eq. 11 normalised to their box of eq. 17:
//! `x_j = x_j^min + u_j (x_j^max − x_j^min)`. Note that J carries no factor
//! ½: it is exactly the paper's eq. 16, and its gradient is `∇J = 2 Jacᵀ r`.
//!
//! A problem knows nothing of the solvers ([`crate::identification::lm`],
//! [`crate::identification::bfgs`], [`crate::identification::plan`]); the
//! solvers know nothing of models or simulators. The only meeting point is the
//! [`LeastSquares`] trait.
use super::blocked_qr::BlockedQr;
use nalgebra::DMatrix;

/// A nonlinear least-squares problem `J(u) = Σ r_i(u)²` on the normalised box
/// `u ∈ [0, 1]^n` (eq. 13, 16, 17).
///
/// Evaluations must be deterministic: the same `u` gives bit-identical
/// residuals whichever workspace or thread computes them. This is what makes
/// plan evaluation reproducible for any number of threads.
///
/// A failed evaluation (the simulation diverged, an integrator gave up …) is
/// reported as `Err`, never as a huge residual: the solvers treat it as
/// `J = +∞` in the paper's sense (a rejected step, a failed plan point) and
/// count it.
pub trait LeastSquares: Sync {
    /// Scratch memory for one evaluation; one per thread, so evaluations do
    /// not allocate.
    type Workspace: Send;
    /// Why an evaluation failed (e.g. the simulation diverged).
    type Error: std::error::Error + Clone + Send + Sync + 'static;

    /// Number of decision variables n (the r of eq. 11).
    fn n_params(&self) -> usize;

    /// Number of residuals (scalar observations N of eq. 29).
    fn n_residuals(&self) -> usize;

    /// A fresh workspace for [`LeastSquares::residuals`] and
    /// [`LeastSquares::residuals_jacobian`].
    fn workspace(&self) -> Self::Workspace;

    /// Residuals `r(u)` (length [`LeastSquares::n_residuals`]) at
    /// `u` (length [`LeastSquares::n_params`], inside `[0, 1]^n`).
    fn residuals(
        &self,
        ws: &mut Self::Workspace,
        u: &[f64],
        r: &mut [f64],
    ) -> Result<(), Self::Error>;

    /// Residuals and Jacobian `∂r/∂u` (`n_residuals × n_params`) at `u`.
    ///
    /// The residuals must be bit-identical to those of
    /// [`LeastSquares::residuals`] at the same `u`.
    fn residuals_jacobian(
        &self,
        ws: &mut Self::Workspace,
        u: &[f64],
        r: &mut [f64],
        jac: &mut DMatrix<f64>,
    ) -> Result<(), Self::Error>;

    /// Whether the solvers should take the Jacobian as its triangular
    /// factor ([`LeastSquares::residuals_factor`]) rather than whole: `true`
    /// when the whole `n_residuals × n_params` matrix would not fit the
    /// memory the problem is allowed.
    fn jacobian_by_blocks(&self) -> bool {
        false
    }

    /// Residuals `r(u)` into `r` and the triangular factor of the Jacobian
    /// at `u` with `Qᵀ r` ([`BlockedQr`]) into `qr` (emptied first), so that
    /// the Jacobian need never be held whole. The residuals must be those
    /// of [`LeastSquares::residuals`]. The default builds the whole
    /// Jacobian and factors it; a problem with a long record overrides it
    /// to hand the rows over block by block.
    fn residuals_factor(
        &self,
        ws: &mut Self::Workspace,
        u: &[f64],
        r: &mut [f64],
        qr: &mut BlockedQr,
    ) -> Result<(), Self::Error> {
        let mut jac = DMatrix::zeros(self.n_residuals(), self.n_params());
        self.residuals_jacobian(ws, u, r, &mut jac)?;
        *qr = BlockedQr::from_rows(&jac, r, 256);
        Ok(())
    }
}

/// Why one evaluation of a problem gave no usable value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EvalError<E> {
    /// The problem reported a failure (for instance a diverging simulation).
    #[error("evaluation failed: {0}")]
    Problem(E),
    /// The problem returned a residual or Jacobian entry that is NaN or
    /// infinite; `index` is the first offending residual (row).
    #[error("evaluation returned a non-finite value at residual {index}")]
    NonFinite {
        /// Index of the first non-finite residual (or Jacobian row).
        index: usize,
    },
    /// Every residual is finite but `Σ r_i²` overflows to infinity.
    #[error("the sum of squared residuals overflows")]
    CostOverflow,
}

/// `Σ r_i²`, summed in index order (so the value is reproducible bit for bit).
pub fn sum_of_squares(r: &[f64]) -> f64 {
    r.iter().fold(0.0, |acc, &ri| acc + ri * ri)
}

/// Evaluates the criterion `J(u) = Σ r_i(u)²` (eq. 16), writing the residuals
/// into `r`; a problem failure or a non-finite residual is an [`EvalError`].
pub fn evaluate_cost<P: LeastSquares + ?Sized>(
    problem: &P,
    ws: &mut P::Workspace,
    u: &[f64],
    r: &mut [f64],
) -> Result<f64, EvalError<P::Error>> {
    problem.residuals(ws, u, r).map_err(EvalError::Problem)?;
    finite_cost(r)
}

/// Evaluates residuals and Jacobian at `u` and returns `J(u)` (eq. 16);
/// non-finite entries are an [`EvalError::NonFinite`].
pub fn evaluate_cost_jacobian<P: LeastSquares + ?Sized>(
    problem: &P,
    ws: &mut P::Workspace,
    u: &[f64],
    r: &mut [f64],
    jac: &mut DMatrix<f64>,
) -> Result<f64, EvalError<P::Error>> {
    problem
        .residuals_jacobian(ws, u, r, jac)
        .map_err(EvalError::Problem)?;
    let cost = finite_cost(r)?;
    for j in 0..jac.ncols() {
        if let Some(i) = jac.column(j).iter().position(|v| !v.is_finite()) {
            return Err(EvalError::NonFinite { index: i });
        }
    }
    Ok(cost)
}

/// Evaluates residuals and the Jacobian's triangular factor at `u`
/// ([`LeastSquares::residuals_factor`]) and returns `J(u)` (eq. 16);
/// non-finite entries are an [`EvalError::NonFinite`] (for the Jacobian,
/// the row in the order the factor took them).
pub fn evaluate_cost_factor<P: LeastSquares + ?Sized>(
    problem: &P,
    ws: &mut P::Workspace,
    u: &[f64],
    r: &mut [f64],
    qr: &mut BlockedQr,
) -> Result<f64, EvalError<P::Error>> {
    problem
        .residuals_factor(ws, u, r, qr)
        .map_err(EvalError::Problem)?;
    let cost = finite_cost(r)?;
    match qr.first_non_finite_row() {
        Some(index) => Err(EvalError::NonFinite { index }),
        None => Ok(cost),
    }
}

/// J (eq. 16) of the residuals `r`, or why it is not finite.
pub(crate) fn finite_cost<E>(r: &[f64]) -> Result<f64, EvalError<E>> {
    if let Some(index) = r.iter().position(|v| !v.is_finite()) {
        return Err(EvalError::NonFinite { index });
    }
    let cost = sum_of_squares(r);
    if cost.is_finite() {
        Ok(cost)
    } else {
        Err(EvalError::CostOverflow)
    }
}

/// Clamps every coordinate into the normalised box `[0, 1]` (eq. 17).
pub fn clamp_to_box(u: &mut [f64]) {
    for v in u.iter_mut() {
        *v = v.clamp(0.0, 1.0);
    }
}
