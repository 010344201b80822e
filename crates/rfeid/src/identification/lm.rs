//! Levenberg–Marquardt on the residual vector, inside the box `[0, 1]^n`.
//!
//! Minimises the paper's criterion `J(u) = Σ r_i(u)²` (eq. 16) over the
//! normalised box of eq. 17 with the exact Jacobian `∂r/∂u` of the problem
//! (forward sensitivities, for a simulator). Near the optimum this converges
//! quadratically on small-residual problems, in far fewer iterations than the
//! BFGS of eq. 20–25, and each iteration needs one Jacobian rather than 2n
//! finite-difference evaluations.
//!
//! # Algorithm
//!
//! Each iteration, at the current point u with residuals r and Jacobian J:
//!
//! 1. **Active set.** With `g = Jᵀ r` (half the gradient of J), a variable at
//!    a bound whose descent direction `−g_j` points out of the box
//!    (`u_j = 0, g_j > 0` or `u_j = 1, g_j < 0`) is frozen for this
//!    iteration; the others are free (set F).
//! 2. **Convergence on the gradient**: stop if
//!    `max_{j∈F} |J_jᵀ r| / (‖J_j‖ ‖r‖) ≤ gradient_tolerance` (the cosine of
//!    the angle between the residual and each free column, as in MINPACK; it
//!    does not depend on the units of J or u).
//! 3. **Convergence in standard errors**: stop if the undamped
//!    Gauss–Newton step would lower J by at most `decrement_tolerance`
//!    residual variances `s² = J/(N − f)`: the point is then within
//!    `√decrement_tolerance` standard errors (eq. 26) of the minimum of the
//!    linearised problem. Steps smaller than that do not change the
//!    estimate in any way its uncertainty could show.
//! 4. **Damped step** (see `lm_step`): δ minimises
//!    `‖J_F δ + r‖² + λ ‖D_F δ‖²`, with the Marquardt scaling D the running
//!    maximum of the column norms (Moré 1978), solved by QR without forming
//!    JᵀJ. The trial point `clamp(u + δ)` is projected onto the box.
//! 5. **Acceptance.** The trial is accepted iff J decreases; λ then shrinks
//!    by `max(1/3, 1 − (2ρ − 1)³)`, ρ the ratio of actual to predicted
//!    decrease (Nielsen 1999). A rejected trial, or one whose evaluation
//!    failed (`Err`, J = +∞), multiplies λ by ν and doubles ν, and the step
//!    is solved again from the same factorisation.
//!
//! Trials evaluate the residuals only; the Jacobian is evaluated once per
//! accepted point, so the result carries the Jacobian at the final point
//! (reusable by [`crate::identification::uncertainty`]).
//!
//! # Stopping
//!
//! See [`StopReason`]: converged on the gradient (step 2), in standard
//! errors (step 3), on the step
//! (`‖u⁺ − u‖₂ ≤ step_tolerance (‖u‖₂ + step_tolerance)`), on the cost (actual
//! and predicted relative decrease both `≤ cost_tolerance`, or J = 0), the
//! iteration limit, no progress (λ beyond `max_damping`), or evaluation
//! failures (trials kept failing until the step became negligible: the
//! search is stuck at the edge of the region where the problem evaluates).
//!
//! # Reference
//!
//! K. Madsen, H. B. Nielsen, O. Tingleff, *Methods for non-linear least
//! squares problems*, 2004 (damping update); J. J. Moré, *The
//! Levenberg–Marquardt algorithm: implementation and theory*, 1978 (scaling,
//! QR solution, convergence tests).
use nalgebra::{DMatrix, DVector, DVectorView};
use serde::Serialize;

use super::blocked_qr::BlockedQr;
use super::lm_step::{update_scale, DampedSolver, State};
use super::problem::{evaluate_cost, EvalError, LeastSquares};
use super::settings::{at_least, positive, SettingsError};
use super::termination::{check_start, SolveError, StopReason};

/// Settings of [`LevenbergMarquardt`], validated when set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LmSettings {
    max_iterations: usize,
    step_tolerance: f64,
    cost_tolerance: f64,
    gradient_tolerance: f64,
    initial_damping: f64,
    max_damping: f64,
    decrement_tolerance: f64,
}

impl Default for LmSettings {
    /// `max_iterations` 100; `step_tolerance` 1e-10 (relative, in normalised
    /// coordinates); `cost_tolerance` 1e-12 (relative decrease of J);
    /// `gradient_tolerance` 1e-12 (cosine measure); `initial_damping` 1e-3
    /// (relative to the scaled `JᵀJ`, whose diagonal is ≤ 1); `max_damping`
    /// 1e16; `decrement_tolerance` 5e-2 (within 0.22 standard errors of the
    /// minimum).
    fn default() -> Self {
        LmSettings {
            max_iterations: 100,
            step_tolerance: 1e-10,
            cost_tolerance: 1e-12,
            gradient_tolerance: 1e-12,
            initial_damping: 1e-3,
            max_damping: 1e16,
            decrement_tolerance: 5e-2,
        }
    }
}

impl LmSettings {
    /// Maximum number of iterations (Jacobian evaluations after the first), ≥ 1.
    pub fn with_max_iterations(mut self, value: usize) -> Result<Self, SettingsError> {
        self.max_iterations = at_least("max_iterations", value, 1, ">= 1")?;
        Ok(self)
    }
    /// Relative step tolerance (> 0).
    pub fn with_step_tolerance(mut self, value: f64) -> Result<Self, SettingsError> {
        self.step_tolerance = positive("step_tolerance", value)?;
        Ok(self)
    }
    /// Relative cost-decrease tolerance (> 0).
    pub fn with_cost_tolerance(mut self, value: f64) -> Result<Self, SettingsError> {
        self.cost_tolerance = positive("cost_tolerance", value)?;
        Ok(self)
    }
    /// Gradient tolerance on the cosine measure (> 0).
    pub fn with_gradient_tolerance(mut self, value: f64) -> Result<Self, SettingsError> {
        self.gradient_tolerance = positive("gradient_tolerance", value)?;
        Ok(self)
    }
    /// Initial damping λ₀ (> 0, below `max_damping`).
    pub fn with_initial_damping(mut self, value: f64) -> Result<Self, SettingsError> {
        self.initial_damping = positive("initial_damping", value)?;
        self.check_damping_order()?;
        Ok(self)
    }
    /// Damping beyond which the search gives up with
    /// [`StopReason::NoProgress`] (> `initial_damping`).
    pub fn with_max_damping(mut self, value: f64) -> Result<Self, SettingsError> {
        self.max_damping = positive("max_damping", value)?;
        self.check_damping_order()?;
        Ok(self)
    }
    /// Statistical convergence (> 0): stop when the undamped Gauss–Newton
    /// step would lower J by at most this multiple of the residual variance
    /// `s² = J/(N − f)` (f free variables). The Gauss–Newton step's length
    /// in the metric of the Cramér–Rao covariance (eq. 26, `s²(JᵀJ)⁻¹`) is
    /// `√(decrement/s²)`, so the point is then within `√tolerance`
    /// standard errors of the minimum of the linearised problem, in every
    /// direction. Only with at least 30 degrees of freedom `N − f`. On a
    /// zero-residual problem the ratio grows as J falls and
    /// the test never fires; the other tolerances stop the search there.
    pub fn with_decrement_tolerance(mut self, value: f64) -> Result<Self, SettingsError> {
        self.decrement_tolerance = positive("decrement_tolerance", value)?;
        Ok(self)
    }
    fn check_damping_order(&self) -> Result<(), SettingsError> {
        if self.max_damping > self.initial_damping {
            Ok(())
        } else {
            Err(SettingsError {
                name: "max_damping",
                value: self.max_damping,
                requirement: "greater than initial_damping",
            })
        }
    }

    /// Maximum number of iterations.
    pub fn max_iterations(&self) -> usize {
        self.max_iterations
    }
    /// Relative step tolerance.
    pub fn step_tolerance(&self) -> f64 {
        self.step_tolerance
    }
    /// Relative cost-decrease tolerance.
    pub fn cost_tolerance(&self) -> f64 {
        self.cost_tolerance
    }
    /// Gradient tolerance (cosine measure).
    pub fn gradient_tolerance(&self) -> f64 {
        self.gradient_tolerance
    }
    /// Initial damping λ₀.
    pub fn initial_damping(&self) -> f64 {
        self.initial_damping
    }
    /// Maximal damping.
    pub fn max_damping(&self) -> f64 {
        self.max_damping
    }
    /// Statistical convergence tolerance on the Gauss–Newton decrement.
    pub fn decrement_tolerance(&self) -> f64 {
        self.decrement_tolerance
    }
}

/// One accepted iterate of a Levenberg–Marquardt run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LmIterate {
    /// Iteration number (0 = start point).
    pub iteration: usize,
    /// J at `u` (eq. 16).
    pub cost: f64,
    /// The point, normalised.
    pub u: Vec<f64>,
    /// Damping λ of the accepted step (λ₀ for the start point).
    pub damping: f64,
}

/// The outcome of a Levenberg–Marquardt run.
#[derive(Debug, Clone)]
pub struct LmResult<E> {
    /// Final point, normalised (the best point found).
    pub u: Vec<f64>,
    /// J(u) (eq. 16).
    pub cost: f64,
    /// Residuals at `u`.
    pub residuals: Vec<f64>,
    /// Jacobian `∂r/∂u` at `u` (N × n), for the Cramér–Rao bounds (eq. 26);
    /// for a problem that takes its Jacobian by blocks
    /// ([`LeastSquares::jacobian_by_blocks`]), its triangular factor R
    /// (n × n), which gives the same `JᵀJ`.
    pub jacobian: DMatrix<f64>,
    /// Why the search stopped.
    pub stop_reason: StopReason,
    /// Iterations performed (Jacobian factorisations).
    pub iterations: usize,
    /// Calls of [`LeastSquares::residuals`] (trial points).
    pub residual_evaluations: usize,
    /// Calls of [`LeastSquares::residuals_jacobian`], the start included.
    pub jacobian_evaluations: usize,
    /// Evaluations (of either kind) that failed.
    pub failed_evaluations: usize,
    /// The most recent failure, if any.
    pub last_failure: Option<EvalError<E>>,
    /// The start point and every accepted iterate.
    pub history: Vec<LmIterate>,
}

/// Projected Levenberg–Marquardt (see the module documentation).
#[derive(Debug, Clone, Default)]
pub struct LevenbergMarquardt {
    settings: LmSettings,
}

/// How one iteration's inner loop over λ ended.
enum Inner {
    /// A trial was accepted; `Some` if a tolerance was met on the way.
    Accepted(Option<StopReason>),
    /// The run stops at the current point.
    Stop(StopReason),
}

impl LevenbergMarquardt {
    /// A solver with the given settings.
    pub fn new(settings: LmSettings) -> Self {
        LevenbergMarquardt { settings }
    }

    /// The settings.
    pub fn settings(&self) -> &LmSettings {
        &self.settings
    }

    /// Minimises J from `u0` ∈ `[0, 1]^n`.
    pub fn minimize<P: LeastSquares>(
        &self,
        problem: &P,
        u0: &[f64],
    ) -> Result<LmResult<P::Error>, SolveError<P::Error>> {
        self.minimize_observed(problem, u0, &mut |_, _| {})
    }

    // long-fn: numerical kernel (the Levenberg–Marquardt iteration, one loop)
    /// Minimises J from `u0`, calling `observer(iteration, cost)` at the start
    /// (iteration 0) and after every iteration.
    pub fn minimize_observed<P: LeastSquares>(
        &self,
        problem: &P,
        u0: &[f64],
        observer: &mut dyn FnMut(usize, f64),
    ) -> Result<LmResult<P::Error>, SolveError<P::Error>> {
        let (n, m) = (problem.n_params(), problem.n_residuals());
        check_start(n, m, u0)?;
        let s = &self.settings;
        let mut ws = problem.workspace();
        let by_blocks = problem.jacobian_by_blocks();
        let mut cur = State::new(n, m, by_blocks);
        cur.u.copy_from_slice(u0);
        let mut qr = by_blocks.then(|| BlockedQr::new(n));
        cur.linearise(problem, &mut ws, &mut qr)
            .map_err(SolveError::StartFailed)?;
        let mut trial = State::new(n, m, by_blocks);
        let mut run = Run {
            qr,
            residual_evaluations: 0,
            jacobian_evaluations: 1,
            failed_evaluations: 0,
            last_failure: None,
            lambda: s.initial_damping,
            nu: 2.0,
            accepted_lambda: s.initial_damping,
        };
        let mut history = vec![LmIterate {
            iteration: 0,
            cost: cur.cost,
            u: cur.u.clone(),
            damping: run.lambda,
        }];
        observer(0, cur.cost);
        let mut scale = vec![0.0; n];
        let mut iterations = 0;
        let stop_reason = loop {
            if cur.cost == 0.0 {
                break StopReason::ConvergedCost;
            }
            let col_norms: Vec<f64> = cur.jac.column_iter().map(|c| c.norm()).collect();
            update_scale(&col_norms, &mut scale);
            let res = cur.lin_res();
            let g = cur.jac.tr_mul(&DVectorView::from_slice(res, res.len()));
            let free: Vec<usize> = (0..n)
                .filter(|&j| !((cur.u[j] <= 0.0 && g[j] > 0.0) || (cur.u[j] >= 1.0 && g[j] < 0.0)))
                .collect();
            let r_norm = cur.cost.sqrt();
            let cosine = free
                .iter()
                .filter(|&&j| col_norms[j] > 0.0)
                .map(|&j| g[j].abs() / (col_norms[j] * r_norm))
                .fold(0.0_f64, f64::max);
            if cosine <= s.gradient_tolerance {
                break StopReason::ConvergedGradient;
            }
            if iterations >= s.max_iterations {
                break StopReason::MaxIterations;
            }
            iterations += 1;
            let solver = DampedSolver::new(&cur.jac, cur.lin_res(), &free, &scale);
            if converged_decrement(s.decrement_tolerance, &solver, cur.cost, m, free.len()) {
                break StopReason::ConvergedDecrement;
            }
            let inner = self.inner_loop(
                problem, &mut ws, &solver, &free, &g, &mut cur, &mut trial, &mut run,
            );
            observer(iterations, cur.cost);
            tracing::debug!(
                iteration = iterations,
                cost = cur.cost,
                damping = run.lambda,
                free = free.len(),
                "Levenberg–Marquardt iteration"
            );
            match inner {
                Inner::Accepted(pending) => {
                    history.push(LmIterate {
                        iteration: iterations,
                        cost: cur.cost,
                        u: cur.u.clone(),
                        damping: run.accepted_lambda,
                    });
                    if let Some(reason) = pending {
                        break reason;
                    }
                }
                Inner::Stop(reason) => break reason,
            }
        };
        tracing::debug!(%stop_reason, iterations, cost = cur.cost, "Levenberg–Marquardt stopped");
        Ok(LmResult {
            u: cur.u,
            cost: cur.cost,
            residuals: cur.r,
            jacobian: cur.jac,
            stop_reason,
            iterations,
            residual_evaluations: run.residual_evaluations,
            jacobian_evaluations: run.jacobian_evaluations,
            failed_evaluations: run.failed_evaluations,
            last_failure: run.last_failure,
            history,
        })
    }

    // long-fn: numerical kernel (the damping loop of one Levenberg–Marquardt step)
    /// Tries damping values until a trial point decreases J or the run
    /// stops; on acceptance `cur` holds the new point with its Jacobian.
    #[allow(clippy::too_many_arguments)]
    fn inner_loop<P: LeastSquares>(
        &self,
        problem: &P,
        ws: &mut P::Workspace,
        solver: &DampedSolver,
        free: &[usize],
        g: &DVector<f64>,
        cur: &mut State,
        trial: &mut State,
        run: &mut Run<P::Error>,
    ) -> Inner {
        let s = &self.settings;
        let n = cur.u.len();
        let u_norm = cur.u.iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut step = DVector::zeros(n);
        // Whether a trial of this iteration failed to evaluate, and whether
        // the latest one did.
        let mut any_failed = false;
        let mut last_failed = false;
        loop {
            if run.lambda > s.max_damping {
                return Inner::Stop(if last_failed {
                    StopReason::EvaluationFailures
                } else {
                    StopReason::NoProgress
                });
            }
            let Some(delta) = solver.step(run.lambda) else {
                run.reject();
                continue;
            };
            trial.u.copy_from_slice(&cur.u);
            for (i, &j) in free.iter().enumerate() {
                trial.u[j] = (cur.u[j] + delta[i]).clamp(0.0, 1.0);
            }
            for j in 0..n {
                step[j] = trial.u[j] - cur.u[j];
            }
            if step.iter().all(|&v| v == 0.0) {
                // Every moving variable is on a bound and pushed outwards:
                // more damping turns the step towards −g, into the box.
                run.reject();
                continue;
            }
            let small_step = step.norm() <= s.step_tolerance * (u_norm + s.step_tolerance);
            // Predicted decrease of the linear model: −2 sᵀg − ‖J s‖².
            let predicted = -(2.0 * step.dot(g) + (&cur.jac * &step).norm_squared());
            run.residual_evaluations += 1;
            let trial_cost = match evaluate_cost(problem, ws, &trial.u, &mut trial.r) {
                Ok(c) => c,
                Err(e) => {
                    run.fail(e);
                    (any_failed, last_failed) = (true, true);
                    if small_step {
                        return Inner::Stop(StopReason::EvaluationFailures);
                    }
                    continue;
                }
            };
            last_failed = false;
            let actual = cur.cost - trial_cost;
            let cost_small = actual.abs() <= s.cost_tolerance * cur.cost
                && predicted <= s.cost_tolerance * cur.cost;
            if trial_cost >= cur.cost {
                run.reject();
                if small_step {
                    return Inner::Stop(StopReason::ConvergedStep);
                }
                if cost_small {
                    return Inner::Stop(StopReason::ConvergedCost);
                }
                continue;
            }
            // Decrease: evaluate the Jacobian there before moving.
            run.jacobian_evaluations += 1;
            match trial.linearise(problem, ws, &mut run.qr) {
                Ok(()) => {}
                Err(e) => {
                    run.fail(e);
                    (any_failed, last_failed) = (true, true);
                    continue;
                }
            }
            let rho = if predicted > 0.0 {
                actual / predicted
            } else {
                1.0
            };
            run.accept(rho);
            std::mem::swap(cur, trial);
            let pending = if small_step && any_failed {
                Some(StopReason::EvaluationFailures)
            } else if small_step {
                Some(StopReason::ConvergedStep)
            } else if cost_small {
                Some(StopReason::ConvergedCost)
            } else {
                None
            };
            return Inner::Accepted(pending);
        }
    }
}

/// Fewest degrees of freedom `N − f` for which the residual variance is
/// estimated well enough (±26 %, `√(2/30)`) to stop on it.
const MIN_DEGREES_OF_FREEDOM: usize = 30;

/// Whether the Gauss–Newton decrement at the current point is within
/// `tolerance` residual variances ([`LmSettings::with_decrement_tolerance`]);
/// never with fewer than [`MIN_DEGREES_OF_FREEDOM`] (a small problem such as
/// an algebraic test has no residual variance to speak of).
fn converged_decrement(
    tolerance: f64,
    solver: &DampedSolver,
    cost: f64,
    residuals: usize,
    free: usize,
) -> bool {
    let dof = residuals.saturating_sub(free);
    dof >= MIN_DEGREES_OF_FREEDOM && solver.decrement() <= tolerance * cost / dof as f64
}

/// Counters and damping of one run, and the factor a problem that takes
/// its Jacobian by blocks fills.
struct Run<E> {
    qr: Option<BlockedQr>,
    residual_evaluations: usize,
    jacobian_evaluations: usize,
    failed_evaluations: usize,
    last_failure: Option<EvalError<E>>,
    lambda: f64,
    nu: f64,
    /// λ of the last accepted step.
    accepted_lambda: f64,
}

impl<E> Run<E> {
    fn reject(&mut self) {
        self.lambda *= self.nu;
        self.nu *= 2.0;
    }
    fn fail(&mut self, e: EvalError<E>) {
        self.failed_evaluations += 1;
        self.last_failure = Some(e);
        self.reject();
    }
    /// Shrinks λ after an accepted step with gain ratio `rho` (Nielsen);
    /// remembers the λ the step was taken with.
    fn accept(&mut self, rho: f64) {
        self.accepted_lambda = self.lambda;
        let factor = (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
        self.lambda *= factor;
        self.nu = 2.0;
    }
}
