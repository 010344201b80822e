//! The line search of the BFGS iteration (eq. 20): λ_k approximately
//! minimises `φ(λ) = J(P(u − λ d))` along the search direction, P the
//! projection onto the box `[0, 1]^n` (eq. 17).
//!
//! The paper takes λ_k as the exact minimiser along d; this approximates it
//! with few evaluations (each one a simulation):
//!
//! 1. **Decrease.** Try λ₀; while φ does not decrease, shrink λ by safeguarded
//!    quadratic interpolation (to [0.1 λ, 0.5 λ]; halving after a failed
//!    evaluation, which counts as φ = +∞).
//! 2. **Bracket.** If λ₀ already decreased φ, double λ (up to the step that
//!    puts every moving coordinate on a bound) while φ keeps decreasing.
//! 3. **Refine.** With a bracket `a < b < c`, `φ(b) < φ(a)`, `φ(b) ≤ φ(c)`,
//!    step to the vertex of the parabola through the three points (or a
//!    golden-section step when it is undefined or outside the bracket) until
//!    the vertex moves by less than `tolerance · b`. On a quadratic the first
//!    vertex is the exact minimiser.
//!
//! The result is the best point found; it always has `φ < φ(0)`.
use super::problem::{evaluate_cost, EvalError, LeastSquares};

/// Where a line search ended.
pub(crate) enum LineSearchOutcome {
    /// φ(`alpha`) = `cost` < φ(0); the point and residuals are in the
    /// search's `best_u` and `best_r`.
    Decrease { alpha: f64, cost: f64 },
    /// No decrease within the evaluation budget or before the step became
    /// negligible (`step_exhausted`); `failed` says whether any trial failed
    /// to evaluate.
    NoDecrease { failed: bool, step_exhausted: bool },
}

/// Limits of one line search.
pub(crate) struct LineSearchLimits {
    /// Maximal number of evaluations of φ.
    pub(crate) max_evaluations: usize,
    /// Relative tolerance on λ for the refinement.
    pub(crate) tolerance: f64,
    /// A trial whose largest coordinate change is below this ends the search.
    pub(crate) min_step: f64,
}

/// Evaluates φ along `u + λ p`, projected, and keeps the best point.
pub(crate) struct LineSearch<'a, P: LeastSquares> {
    pub(crate) problem: &'a P,
    pub(crate) ws: &'a mut P::Workspace,
    pub(crate) u: &'a [f64],
    /// Descent direction (−d of eq. 20–21).
    pub(crate) p: &'a [f64],
    pub(crate) trial_u: Vec<f64>,
    pub(crate) trial_r: Vec<f64>,
    pub(crate) best_u: Vec<f64>,
    pub(crate) best_r: Vec<f64>,
    pub(crate) evaluations: usize,
    pub(crate) failures: usize,
    pub(crate) last_failure: Option<EvalError<P::Error>>,
}

/// A point of φ: (λ, φ(λ)), φ = +∞ for a failed evaluation.
#[derive(Clone, Copy)]
struct Pt {
    a: f64,
    f: f64,
}

const GOLDEN: f64 = 0.381_966_011_250_105_1;

impl<P: LeastSquares> LineSearch<'_, P> {
    /// φ(λ), or +∞ (internally only) if the evaluation failed.
    fn phi(&mut self, alpha: f64, best: f64) -> f64 {
        for ((t, &u), &p) in self.trial_u.iter_mut().zip(self.u).zip(self.p) {
            *t = (u + alpha * p).clamp(0.0, 1.0);
        }
        self.evaluations += 1;
        match evaluate_cost(self.problem, self.ws, &self.trial_u, &mut self.trial_r) {
            Ok(f) => {
                if f < best {
                    std::mem::swap(&mut self.trial_u, &mut self.best_u);
                    std::mem::swap(&mut self.trial_r, &mut self.best_r);
                }
                f
            }
            Err(e) => {
                self.failures += 1;
                self.last_failure = Some(e);
                f64::INFINITY
            }
        }
    }

    // long-fn: numerical kernel (the bracketing and zoom of the line search, eq. 20)
    /// Runs the search from φ(0) = `f0` with slope `slope` = ∇Jᵀp < 0, first
    /// trial `alpha0`, and `alpha_max` the step beyond which the projected
    /// point no longer moves.
    pub(crate) fn run(
        &mut self,
        f0: f64,
        slope: f64,
        alpha0: f64,
        alpha_max: f64,
        limits: &LineSearchLimits,
    ) -> LineSearchOutcome {
        let p_inf = self.p.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let mut failed = false;
        let lo = Pt { a: 0.0, f: f0 };
        // 1. Find a decrease.
        let mut a = alpha0.min(alpha_max);
        let mut hi: Option<Pt> = None;
        let mid = loop {
            let step_exhausted = a * p_inf < limits.min_step;
            if step_exhausted || self.evaluations >= limits.max_evaluations {
                return LineSearchOutcome::NoDecrease {
                    failed,
                    step_exhausted,
                };
            }
            let f = self.phi(a, f0);
            failed |= f.is_infinite();
            if f < f0 {
                break Pt { a, f };
            }
            hi = Some(Pt { a, f });
            a = if f.is_finite() {
                let q = -slope * a * a / (2.0 * (f - f0 - slope * a));
                q.clamp(0.1 * a, 0.5 * a)
            } else {
                0.5 * a
            };
        };
        let (mut lo, mut mid) = (lo, mid);
        // 2. Bracket by expansion.
        let mut hi = match hi {
            Some(hi) => hi,
            None => loop {
                if mid.a >= alpha_max || self.evaluations >= limits.max_evaluations {
                    return LineSearchOutcome::Decrease {
                        alpha: mid.a,
                        cost: mid.f,
                    };
                }
                let b = (2.0 * mid.a).min(alpha_max);
                let f = self.phi(b, mid.f);
                if f < mid.f {
                    (lo, mid) = (mid, Pt { a: b, f });
                } else {
                    break Pt { a: b, f };
                }
            },
        };
        // 3. Refine in (lo, mid, hi).
        while self.evaluations < limits.max_evaluations {
            let golden = if hi.a - mid.a > mid.a - lo.a {
                mid.a + GOLDEN * (hi.a - mid.a)
            } else {
                mid.a - GOLDEN * (mid.a - lo.a)
            };
            let v = vertex(lo, mid, hi)
                .filter(|&v| v > lo.a && v < hi.a)
                .unwrap_or(golden);
            if (v - mid.a).abs() <= limits.tolerance * mid.a {
                break;
            }
            let f = self.phi(v, mid.f);
            let pt = Pt { a: v, f };
            if f < mid.f {
                if v < mid.a {
                    hi = mid;
                } else {
                    lo = mid;
                }
                mid = pt;
            } else if v < mid.a {
                lo = pt;
            } else {
                hi = pt;
            }
        }
        LineSearchOutcome::Decrease {
            alpha: mid.a,
            cost: mid.f,
        }
    }
}

/// Abscissa of the vertex of the parabola through three points, if it is a
/// minimum (all values finite, positive curvature).
fn vertex(a: Pt, b: Pt, c: Pt) -> Option<f64> {
    if !(a.f.is_finite() && b.f.is_finite() && c.f.is_finite()) {
        return None;
    }
    let (ba, bc) = (b.a - a.a, b.a - c.a);
    let (fba, fbc) = (b.f - a.f, b.f - c.f);
    let num = ba * ba * fbc - bc * bc * fba;
    let den = ba * fbc - bc * fba;
    // Positive curvature ⇔ den < 0 here (b between a and c, φ(b) lowest).
    if den >= 0.0 || !den.is_finite() {
        return None;
    }
    let v = b.a - 0.5 * num / den;
    v.is_finite().then_some(v)
}
