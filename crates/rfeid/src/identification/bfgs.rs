//! The paper's BFGS variable-metric search (eq. 20–25) inside the box
//! `[0, 1]^n`, with finite-difference gradients.
//!
//! ```text
//! u_{k+1} = P(u_k − λ_k d_k)                                   (eq. 20)
//! d_k     = B_k ∇J(u_k),       B_k ≈ H_k⁻¹                     (eq. 21, 22)
//! B_{k+1} = B_k + [1 + ∂vᵀB∂v / ∂xᵀ∂v] ∂x∂xᵀ/∂xᵀ∂v
//!               − (∂x ∂vᵀB + B ∂v ∂xᵀ) / ∂xᵀ∂v                 (eq. 23)
//! ∂x = u_{k+1} − u_k,   ∂v = ∇J(u_{k+1}) − ∇J(u_k)             (eq. 24, 25)
//! ```
//!
//! with `B_0 = I` and P the projection onto the box (eq. 17).
//!
//! # Details the paper leaves open
//!
//! - **Gradient**: finite differences with a fixed step h in normalised
//!   coordinates, central inside the box and second-order one-sided within h
//!   of a bound; the 2n evaluations run in parallel (see `fd_gradient`).
//! - **Bounds** (a projected quasi-Newton method): a variable at a bound whose
//!   descent direction `−∂J/∂u_j` points out of the box is *active*; it is
//!   held fixed and left out of the direction and of the update, and the
//!   convergence test uses the projected gradient (zero on active
//!   variables). When the active set changes, B restarts from I.
//! - **Line search**: approximates the paper's exact minimisation along d
//!   (see `line_search`); failed evaluations count as J = +∞ and shrink the
//!   step. After a restart the first trial moves the farthest coordinate by
//!   `initial_step`; otherwise it is the quasi-Newton step λ = 1.
//! - **Scaling**: with J in physical units, `B_0 = I` has the wrong scale.
//!   Unless disabled (`with_scale_initial_inverse_hessian(false)`, the paper's
//!   plain method), B is replaced by `(∂xᵀ∂v / ∂vᵀ∂v) I` just before its first
//!   update after each (re)start (Nocedal & Wright, eq. 6.20).
//! - **Curvature**: the update is skipped when `∂xᵀ∂v ≤ 1e-10 ‖∂x‖ ‖∂v‖`, and
//!   B restarts when `d_k` is not a descent direction.
//!
//! # Stopping
//!
//! Projected gradient `‖∇_P J‖_∞ ≤ gradient_tolerance · J` (a change of the
//! whole box width would change J by less than that fraction, to first order);
//! step `‖∂x‖_∞ ≤ step_tolerance`, or no decrease of J along the steepest
//! descent for any step down to that size (near a zero-residual minimum the
//! finite-difference gradient is mostly rounding noise, and this is how the
//! search ends there); relative decrease of J below
//! `cost_tolerance` (or J = 0); the iteration limit; a line search that finds
//! no decrease even along the steepest descent ([`StopReason::NoProgress`],
//! or [`StopReason::EvaluationFailures`] if its trials failed); or a gradient
//! that cannot be formed ([`StopReason::GradientUnavailable`]).
//!
//! # Reference
//!
//! P. Y. Papalambros, D. J. Wilde, *Principles of optimal design* (the
//! paper's \[7\]); J. Nocedal, S. J. Wright, *Numerical optimization*, 2006,
//! §6.1.
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use super::fd_gradient::fd_gradient;
use super::line_search::{LineSearch, LineSearchLimits, LineSearchOutcome};
use super::problem::{evaluate_cost, EvalError, LeastSquares};
use super::settings::{at_least, in_unit_interval, positive, SettingsError};
use super::termination::{check_start, SolveError, StopReason};

/// Settings of [`Bfgs`], validated when set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BfgsSettings {
    max_iterations: usize,
    gradient_tolerance: f64,
    step_tolerance: f64,
    cost_tolerance: f64,
    fd_step: f64,
    initial_step: f64,
    line_search_max_evaluations: usize,
    line_search_tolerance: f64,
    scale_initial_inverse_hessian: bool,
}

impl Default for BfgsSettings {
    /// `max_iterations` 1000; `gradient_tolerance` 1e-8 (relative to J);
    /// `step_tolerance` 1e-10 (normalised); `cost_tolerance` 1e-12 (relative
    /// decrease); `fd_step` 1e-6; `initial_step` 0.1; line search: at most 20
    /// evaluations, relative tolerance 0.01 on λ; initial scaling on.
    fn default() -> Self {
        BfgsSettings {
            max_iterations: 1000,
            gradient_tolerance: 1e-8,
            step_tolerance: 1e-10,
            cost_tolerance: 1e-12,
            fd_step: 1e-6,
            initial_step: 0.1,
            line_search_max_evaluations: 20,
            line_search_tolerance: 1e-2,
            scale_initial_inverse_hessian: true,
        }
    }
}

impl BfgsSettings {
    /// Maximum number of iterations (≥ 1).
    pub fn with_max_iterations(mut self, value: usize) -> Result<Self, SettingsError> {
        self.max_iterations = at_least("max_iterations", value, 1, ">= 1")?;
        Ok(self)
    }
    /// Projected-gradient tolerance relative to J (> 0).
    pub fn with_gradient_tolerance(mut self, value: f64) -> Result<Self, SettingsError> {
        self.gradient_tolerance = positive("gradient_tolerance", value)?;
        Ok(self)
    }
    /// Step tolerance on `‖∂x‖_∞` in normalised coordinates (> 0).
    pub fn with_step_tolerance(mut self, value: f64) -> Result<Self, SettingsError> {
        self.step_tolerance = positive("step_tolerance", value)?;
        Ok(self)
    }
    /// Relative cost-decrease tolerance (> 0).
    pub fn with_cost_tolerance(mut self, value: f64) -> Result<Self, SettingsError> {
        self.cost_tolerance = positive("cost_tolerance", value)?;
        Ok(self)
    }
    /// Finite-difference step h in normalised coordinates, in (0, 0.25].
    pub fn with_fd_step(mut self, value: f64) -> Result<Self, SettingsError> {
        if !(value > 0.0 && value <= 0.25) {
            return Err(SettingsError {
                name: "fd_step",
                value,
                requirement: "in (0, 0.25]",
            });
        }
        self.fd_step = value;
        Ok(self)
    }
    /// Largest coordinate change of the first trial after a restart, in (0, 1).
    pub fn with_initial_step(mut self, value: f64) -> Result<Self, SettingsError> {
        self.initial_step = in_unit_interval("initial_step", value)?;
        Ok(self)
    }
    /// Evaluation budget of one line search (≥ 2).
    pub fn with_line_search_max_evaluations(mut self, value: usize) -> Result<Self, SettingsError> {
        self.line_search_max_evaluations =
            at_least("line_search_max_evaluations", value, 2, ">= 2")?;
        Ok(self)
    }
    /// Relative tolerance on λ of the line-search refinement, in (0, 1).
    pub fn with_line_search_tolerance(mut self, value: f64) -> Result<Self, SettingsError> {
        self.line_search_tolerance = in_unit_interval("line_search_tolerance", value)?;
        Ok(self)
    }
    /// Whether B is rescaled before its first update (see the module docs);
    /// `false` is the paper's plain `B_0 = I`.
    pub fn with_scale_initial_inverse_hessian(mut self, value: bool) -> Self {
        self.scale_initial_inverse_hessian = value;
        self
    }

    /// Maximum number of iterations.
    pub fn max_iterations(&self) -> usize {
        self.max_iterations
    }
    /// Projected-gradient tolerance relative to J.
    pub fn gradient_tolerance(&self) -> f64 {
        self.gradient_tolerance
    }
    /// Step tolerance.
    pub fn step_tolerance(&self) -> f64 {
        self.step_tolerance
    }
    /// Relative cost-decrease tolerance.
    pub fn cost_tolerance(&self) -> f64 {
        self.cost_tolerance
    }
    /// Finite-difference step.
    pub fn fd_step(&self) -> f64 {
        self.fd_step
    }
    /// First-trial coordinate change after a restart.
    pub fn initial_step(&self) -> f64 {
        self.initial_step
    }
    /// Evaluation budget of one line search.
    pub fn line_search_max_evaluations(&self) -> usize {
        self.line_search_max_evaluations
    }
    /// Relative λ tolerance of the line search.
    pub fn line_search_tolerance(&self) -> f64 {
        self.line_search_tolerance
    }
    /// Whether B is rescaled before its first update.
    pub fn scale_initial_inverse_hessian(&self) -> bool {
        self.scale_initial_inverse_hessian
    }
}

/// One iterate of a BFGS run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BfgsIterate {
    /// Iteration number (0 = start point).
    pub iteration: usize,
    /// J at `u` (eq. 16).
    pub cost: f64,
    /// The point, normalised.
    pub u: Vec<f64>,
    /// Step size λ_k of eq. 20 that led here (0 for the start point).
    pub step_size: f64,
}

/// The outcome of a BFGS run.
#[derive(Debug, Clone)]
pub struct BfgsResult<E> {
    /// Final point, normalised (the best point found).
    pub u: Vec<f64>,
    /// J(u) (eq. 16).
    pub cost: f64,
    /// Residuals at `u`.
    pub residuals: Vec<f64>,
    /// Projected finite-difference gradient of J at `u` (`None` if it could
    /// not be evaluated there).
    pub projected_gradient: Option<Vec<f64>>,
    /// Why the search stopped.
    pub stop_reason: StopReason,
    /// Iterations performed (line searches that decreased J).
    pub iterations: usize,
    /// All evaluations of J (start, line searches and gradients).
    pub cost_evaluations: usize,
    /// Finite-difference gradients computed (2n evaluations each).
    pub gradient_evaluations: usize,
    /// Evaluations of J spent in line searches.
    pub line_search_evaluations: usize,
    /// Evaluations that failed.
    pub failed_evaluations: usize,
    /// The most recent failure, if any.
    pub last_failure: Option<EvalError<E>>,
    /// The start point and every iterate.
    pub history: Vec<BfgsIterate>,
}

/// The BFGS method of eq. 20–25 on the box (see the module documentation).
#[derive(Debug, Clone, Default)]
pub struct Bfgs {
    settings: BfgsSettings,
}

/// Evaluation counters of one run.
struct Counts<E> {
    cost: usize,
    gradients: usize,
    line_search: usize,
    failed: usize,
    last_failure: Option<EvalError<E>>,
}

impl Bfgs {
    /// A solver with the given settings.
    pub fn new(settings: BfgsSettings) -> Self {
        Bfgs { settings }
    }

    /// The settings.
    pub fn settings(&self) -> &BfgsSettings {
        &self.settings
    }

    /// Minimises J from `u0` ∈ `[0, 1]^n`.
    pub fn minimize<P: LeastSquares>(
        &self,
        problem: &P,
        u0: &[f64],
    ) -> Result<BfgsResult<P::Error>, SolveError<P::Error>> {
        self.minimize_observed(problem, u0, &mut |_, _| {})
    }

    // long-fn: numerical kernel (the BFGS iteration of eq. 20–25, one loop)
    /// Minimises J from `u0`, calling `observer(iteration, cost)` at the start
    /// (iteration 0) and after every iteration.
    pub fn minimize_observed<P: LeastSquares>(
        &self,
        problem: &P,
        u0: &[f64],
        observer: &mut dyn FnMut(usize, f64),
    ) -> Result<BfgsResult<P::Error>, SolveError<P::Error>> {
        let (n, m) = (problem.n_params(), problem.n_residuals());
        check_start(n, m, u0)?;
        let s = &self.settings;
        let mut ws = problem.workspace();
        let mut u = u0.to_vec();
        let mut r = vec![0.0; m];
        let mut cost =
            evaluate_cost(problem, &mut ws, &u, &mut r).map_err(SolveError::StartFailed)?;
        let mut counts = Counts {
            cost: 1,
            gradients: 0,
            line_search: 0,
            failed: 0,
            last_failure: None,
        };
        let mut history = vec![BfgsIterate {
            iteration: 0,
            cost,
            u: u.clone(),
            step_size: 0.0,
        }];
        observer(0, cost);
        let mut g = vec![0.0; n];
        let mut gradient_ok = self.gradient(problem, &u, cost, &mut g, &mut counts);
        let mut active = active_set(&u, &g);
        let mut b = DMatrix::identity(n, n);
        let mut fresh = true;
        let mut iterations = 0;
        // Buffers of the line search, reused.
        let mut bufs = (vec![0.0; n], vec![0.0; m], vec![0.0; n], vec![0.0; m]);
        let stop_reason = loop {
            if !gradient_ok {
                break StopReason::GradientUnavailable;
            }
            if cost == 0.0 {
                break StopReason::ConvergedCost;
            }
            let pg = projected(&g, &active);
            if pg.iter().fold(0.0_f64, |a, v| a.max(v.abs())) <= s.gradient_tolerance * cost {
                break StopReason::ConvergedGradient;
            }
            if iterations >= s.max_iterations {
                break StopReason::MaxIterations;
            }
            // Search direction p = −d (eq. 21), restarting B if it is not a
            // descent direction or the line search fails along it.
            let step = loop {
                let p = direction(&b, &pg, &u, &active);
                let slope: f64 = g.iter().zip(&p).map(|(a, b)| a * b).sum();
                let descent = slope < 0.0;
                if !descent && !fresh {
                    b.fill_with_identity();
                    fresh = true;
                    continue;
                }
                let p_inf = p.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
                let alpha_max = max_step(&u, &p);
                let alpha0 = if fresh { s.initial_step / p_inf } else { 1.0 };
                let mut ls = LineSearch {
                    problem,
                    ws: &mut ws,
                    u: &u,
                    p: &p,
                    trial_u: std::mem::take(&mut bufs.0),
                    trial_r: std::mem::take(&mut bufs.1),
                    best_u: std::mem::take(&mut bufs.2),
                    best_r: std::mem::take(&mut bufs.3),
                    evaluations: 0,
                    failures: 0,
                    last_failure: None,
                };
                let limits = LineSearchLimits {
                    max_evaluations: s.line_search_max_evaluations,
                    tolerance: s.line_search_tolerance,
                    min_step: s.step_tolerance,
                };
                let outcome = if slope < 0.0 && p_inf > 0.0 {
                    ls.run(cost, slope, alpha0, alpha_max, &limits)
                } else {
                    LineSearchOutcome::NoDecrease {
                        failed: false,
                        step_exhausted: false,
                    }
                };
                counts.cost += ls.evaluations;
                counts.line_search += ls.evaluations;
                counts.failed += ls.failures;
                if ls.last_failure.is_some() {
                    counts.last_failure = ls.last_failure.take();
                }
                bufs = (ls.trial_u, ls.trial_r, ls.best_u, ls.best_r);
                match outcome {
                    LineSearchOutcome::Decrease { alpha, cost } => break Ok((alpha, cost)),
                    // Along the steepest descent (B = I) nothing decreased J.
                    LineSearchOutcome::NoDecrease { failed: true, .. } if fresh => {
                        break Err(StopReason::EvaluationFailures)
                    }
                    LineSearchOutcome::NoDecrease {
                        step_exhausted: true,
                        ..
                    } if fresh => break Err(StopReason::ConvergedStep),
                    LineSearchOutcome::NoDecrease { .. } if fresh => {
                        break Err(StopReason::NoProgress)
                    }
                    LineSearchOutcome::NoDecrease { .. } => {
                        b.fill_with_identity();
                        fresh = true;
                    }
                }
            };
            let (alpha, new_cost) = match step {
                Ok(step) => step,
                Err(reason) => break reason,
            };
            iterations += 1;
            // Accept the best point of the line search.
            let ds: Vec<f64> = bufs.2.iter().zip(&u).map(|(a, b)| a - b).collect();
            std::mem::swap(&mut u, &mut bufs.2);
            std::mem::swap(&mut r, &mut bufs.3);
            let old_cost = cost;
            cost = new_cost;
            let g_old = g.clone();
            gradient_ok = self.gradient(problem, &u, cost, &mut g, &mut counts);
            history.push(BfgsIterate {
                iteration: iterations,
                cost,
                u: u.clone(),
                step_size: alpha,
            });
            observer(iterations, cost);
            tracing::debug!(
                iteration = iterations,
                cost,
                step_size = alpha,
                "BFGS iteration"
            );
            if gradient_ok {
                let new_active = active_set(&u, &g);
                if new_active != active {
                    active = new_active;
                    b.fill_with_identity();
                    fresh = true;
                } else {
                    let dv: Vec<f64> = g.iter().zip(&g_old).map(|(a, b)| a - b).collect();
                    if self.update(&mut b, &ds, &dv, &active, fresh) {
                        fresh = false;
                    }
                }
            }
            if ds.iter().fold(0.0_f64, |a, v| a.max(v.abs())) <= s.step_tolerance {
                break StopReason::ConvergedStep;
            }
            if old_cost - cost <= s.cost_tolerance * old_cost {
                break StopReason::ConvergedCost;
            }
        };
        tracing::debug!(%stop_reason, iterations, cost, "BFGS stopped");
        let projected_gradient = gradient_ok.then(|| projected(&g, &active_set(&u, &g)));
        Ok(BfgsResult {
            u,
            cost,
            residuals: r,
            projected_gradient,
            stop_reason,
            iterations,
            cost_evaluations: counts.cost,
            gradient_evaluations: counts.gradients,
            line_search_evaluations: counts.line_search,
            failed_evaluations: counts.failed,
            last_failure: counts.last_failure,
            history,
        })
    }

    /// Finite-difference gradient into `g`; `false` if unavailable.
    fn gradient<P: LeastSquares>(
        &self,
        problem: &P,
        u: &[f64],
        cost: f64,
        g: &mut [f64],
        counts: &mut Counts<P::Error>,
    ) -> bool {
        let (outcome, stats) = fd_gradient(problem, u, cost, self.settings.fd_step, g);
        counts.gradients += 1;
        counts.cost += stats.evaluations;
        counts.failed += stats.failures;
        if stats.last_failure.is_some() {
            counts.last_failure = stats.last_failure;
        }
        outcome.is_ok()
    }

    /// The update of eq. 23 on the free variables; returns whether B changed.
    fn update(
        &self,
        b: &mut DMatrix<f64>,
        ds: &[f64],
        dv: &[f64],
        active: &[bool],
        fresh: bool,
    ) -> bool {
        let mask = |v: &[f64]| {
            DVector::from_iterator(
                v.len(),
                v.iter().zip(active).map(|(&x, &a)| if a { 0.0 } else { x }),
            )
        };
        let (dx, dv) = (mask(ds), mask(dv));
        let sy = dx.dot(&dv);
        let curvature = sy > 1e-10 * dx.norm() * dv.norm();
        if !curvature {
            return false;
        }
        if fresh && self.settings.scale_initial_inverse_hessian {
            let gamma = sy / dv.norm_squared();
            b.fill_with_identity();
            *b *= gamma;
        }
        let bv = &*b * &dv;
        let vbv = dv.dot(&bv);
        // B += (1 + ∂vᵀB∂v/∂xᵀ∂v) ∂x∂xᵀ/∂xᵀ∂v − (∂x (B∂v)ᵀ + B∂v ∂xᵀ)/∂xᵀ∂v
        b.ger((1.0 + vbv / sy) / sy, &dx, &dx, 1.0);
        b.ger(-1.0 / sy, &dx, &bv, 1.0);
        b.ger(-1.0 / sy, &bv, &dx, 1.0);
        true
    }
}

/// Active variables: at a bound with the descent direction `−∂J/∂u_j`
/// pointing out of the box.
fn active_set(u: &[f64], g: &[f64]) -> Vec<bool> {
    u.iter()
        .zip(g)
        .map(|(&u, &g)| (u <= 0.0 && g > 0.0) || (u >= 1.0 && g < 0.0))
        .collect()
}

/// The gradient with active components zeroed.
fn projected(g: &[f64], active: &[bool]) -> Vec<f64> {
    g.iter()
        .zip(active)
        .map(|(&g, &a)| if a { 0.0 } else { g })
        .collect()
}

/// `p = −B ∇_P J`, without components that would push a variable sitting on
/// a bound out of the box (they would be clamped away).
fn direction(b: &DMatrix<f64>, pg: &[f64], u: &[f64], active: &[bool]) -> Vec<f64> {
    let pgv = DVector::from_column_slice(pg);
    let bp = b * pgv;
    bp.iter()
        .zip(active)
        .zip(u)
        .map(|((&d, &a), &u)| {
            let p = if a { 0.0 } else { -d };
            if (u <= 0.0 && p < 0.0) || (u >= 1.0 && p > 0.0) {
                0.0
            } else {
                p
            }
        })
        .collect()
}

/// The step λ beyond which `clamp(u + λ p)` no longer moves: every moving
/// coordinate is on a bound.
fn max_step(u: &[f64], p: &[f64]) -> f64 {
    u.iter()
        .zip(p)
        .filter(|(_, &p)| p != 0.0)
        .map(|(&u, &p)| if p > 0.0 { (1.0 - u) / p } else { u / -p })
        .fold(0.0, f64::max)
}
