//! The refits of one side of a profile: from the estimate outwards, each
//! held value's minimum of J (eq. 16) over the other variables found by
//! Levenberg–Marquardt ([`crate::identification::lm`]) on the
//! [`Pinned`] problem, started where the last refits point (warm start).
//!
//! The planned points are `û_j ± k·step`, k = 1 … `points`. If the last of
//! them is still below the threshold, the walk goes on with steps twice the
//! last each time, clipped to the box, up to `extra` points: so a flat side
//! reaches its bound and is found open. It stops at the box's bound, and
//! after [`MAX_CONSECUTIVE_FAILURES`] refits in a row that failed.
//!
//! Like the solvers, this works on any [`LeastSquares`] problem in
//! normalised coordinates (eq. 17); a refit's result depends only on its
//! start, so a walk gives the same points whichever thread runs it.
use super::pinned::Pinned;
use crate::identification::lm::LevenbergMarquardt;
use crate::identification::problem::{evaluate_cost, LeastSquares};
use crate::identification::termination::StopReason;

/// Refits in a row that may fail before a side's walk stops (the region
/// beyond is taken to be where the problem cannot be evaluated).
pub const MAX_CONSECUTIVE_FAILURES: usize = 3;

/// Which side of the estimate a walk goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// Towards u_j = 0.
    Lower,
    /// Towards u_j = 1.
    Upper,
}

impl Side {
    fn sign(self) -> f64 {
        match self {
            Side::Lower => -1.0,
            Side::Upper => 1.0,
        }
    }
    fn bound(self) -> f64 {
        match self {
            Side::Lower => 0.0,
            Side::Upper => 1.0,
        }
    }
}

/// What every walk of one parameter's profile shares.
#[derive(Debug, Clone, Copy)]
pub struct Walk<'a> {
    /// The local search of the refits.
    pub lm: &'a LevenbergMarquardt,
    /// The estimate, normalised.
    pub u_hat: &'a [f64],
    /// J at the estimate.
    pub cost_hat: f64,
    /// The held variable.
    pub index: usize,
    /// ΔJ (in J's units) beyond which the walk need not extend.
    pub threshold: f64,
    /// `du_i/du_j` along the linearised profile (the regression of the
    /// others on x_j in the bounds' covariance, eq. 26; 0 at j), for the
    /// first refit's start; `None`: the others start at the estimate.
    pub direction: Option<&'a [f64]>,
}

/// One side's plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SidePlan {
    /// The side.
    pub side: Side,
    /// Distance between the planned points (normalised, > 0).
    pub step: f64,
    /// Planned points.
    pub points: usize,
    /// Most points beyond them while the profile stays below the threshold.
    pub extra: usize,
}

/// Where a refit ended.
#[derive(Debug, Clone, PartialEq)]
pub struct RefitEnd {
    /// Every variable (the held one included), normalised.
    pub u: Vec<f64>,
    /// J there.
    pub cost: f64,
    /// Why the search stopped.
    pub stop: StopReason,
    /// Its iterations.
    pub iterations: usize,
}

/// One refit: the held value (normalised) and its end, or why it failed.
#[derive(Debug, Clone, PartialEq)]
pub struct Refit {
    /// The held value u_j.
    pub at: f64,
    /// Its end, or the failure in words.
    pub end: Result<RefitEnd, String>,
}

/// The refits of one side, from the estimate outwards (see the module
/// documentation). `observe` is called after each.
pub fn walk_side<P: LeastSquares>(
    problem: &P,
    w: &Walk<'_>,
    plan: &SidePlan,
    observe: &dyn Fn(),
) -> Vec<Refit> {
    let j = w.index;
    let (sign, bound) = (plan.side.sign(), plan.side.bound());
    let mut out: Vec<Refit> = Vec::new();
    // The last two refits' ends (the estimate before any).
    let mut last: Vec<f64> = w.u_hat.to_vec();
    let mut before: Option<Vec<f64>> = None;
    let (mut at, mut step, mut failures) = (w.u_hat[j], plan.step, 0);
    for k in 1..=plan.points + plan.extra {
        if k > plan.points {
            if !below_threshold(&out, w) {
                break;
            }
            step *= 2.0;
        }
        let next = match k <= plan.points {
            true => w.u_hat[j] + sign * plan.step * k as f64,
            false => at + sign * step,
        };
        let next = clip(next, bound, sign);
        if next == at || !next.is_finite() {
            break;
        }
        let start = predict(w, &last, before.as_deref(), next);
        let refit = refit_from(problem, w, next, &start, &last);
        observe();
        match &refit.end {
            Ok(e) => {
                before = Some(std::mem::replace(&mut last, e.u.clone()));
                failures = 0;
            }
            Err(_) => failures += 1,
        }
        out.push(refit);
        at = next;
        if failures >= MAX_CONSECUTIVE_FAILURES {
            break;
        }
    }
    out
}

/// `u` not beyond `bound` in the direction `sign`.
fn clip(u: f64, bound: f64, sign: f64) -> f64 {
    match sign * (u - bound) >= 0.0 {
        true => bound,
        false => u,
    }
}

/// Whether the last refit that succeeded is below the threshold (the
/// estimate, if none did).
fn below_threshold(out: &[Refit], w: &Walk<'_>) -> bool {
    out.iter()
        .rev()
        .find_map(|r| r.end.as_ref().ok())
        .is_none_or(|e| e.cost - w.cost_hat < w.threshold)
}

/// The start of the refit at `next`: the others extrapolated linearly from
/// the last two ends (the estimate and the bounds' direction for the
/// first), clamped to the box; u_j = next.
fn predict(w: &Walk<'_>, last: &[f64], before: Option<&[f64]>, next: f64) -> Vec<f64> {
    let j = w.index;
    let mut start = last.to_vec();
    let slope: Option<Vec<f64>> = match before {
        Some(b) if last[j] != b[j] => Some(
            last.iter()
                .zip(b)
                .map(|(l, p)| (l - p) / (last[j] - b[j]))
                .collect(),
        ),
        _ => w.direction.map(<[f64]>::to_vec),
    };
    if let Some(slope) = slope {
        let dj = next - last[j];
        for (s, d) in start.iter_mut().zip(&slope) {
            let v = *s + d * dj;
            if v.is_finite() {
                *s = v.clamp(0.0, 1.0);
            }
        }
    }
    start[j] = next;
    start
}

/// The refit at `next` from `start`, and again from `last` (the others as
/// the last refit left them) if that one failed.
fn refit_from<P: LeastSquares>(
    problem: &P,
    w: &Walk<'_>,
    next: f64,
    start: &[f64],
    last: &[f64],
) -> Refit {
    let first = refit(problem, w, next, start);
    let plain: Vec<f64> = last
        .iter()
        .enumerate()
        .map(|(i, &v)| if i == w.index { next } else { v })
        .collect();
    match first.end {
        Err(_) if plain != start => refit(problem, w, next, &plain),
        _ => first,
    }
}

/// One refit: J minimised over the others with u_j held at `at`, from
/// `start` (whose u_j is `at`).
fn refit<P: LeastSquares>(problem: &P, w: &Walk<'_>, at: f64, start: &[f64]) -> Refit {
    if problem.n_params() == 1 {
        return evaluate(problem, at);
    }
    let pinned = match Pinned::new(problem, w.index, at) {
        Ok(p) => p,
        Err(e) => {
            return Refit {
                at,
                end: Err(e.to_string()),
            }
        }
    };
    let free = pinned.reduce(start);
    let end = w.lm.minimize(&pinned, &free).map(|r| {
        let mut u = vec![0.0; start.len()];
        pinned.expand(&r.u, &mut u);
        RefitEnd {
            u,
            cost: r.cost,
            stop: r.stop_reason,
            iterations: r.iterations,
        }
    });
    Refit {
        at,
        end: end.map_err(|e| e.to_string()),
    }
}

/// The "refit" of a problem of one variable: J at `at`, nothing to
/// minimise.
fn evaluate<P: LeastSquares>(problem: &P, at: f64) -> Refit {
    let mut r = vec![0.0; problem.n_residuals()];
    let cost = evaluate_cost(problem, &mut problem.workspace(), &[at], &mut r);
    Refit {
        at,
        end: cost
            .map(|cost| RefitEnd {
                u: vec![at],
                cost,
                stop: StopReason::ConvergedGradient,
                iterations: 0,
            })
            .map_err(|e| e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    /// r = y − A u with two correlated columns: J is quadratic, and its
    /// profile in u_0 is (u_0 − û_0)²/C_00 with C = (AᵀA)⁻¹.
    struct Linear {
        a: DMatrix<f64>,
        y: Vec<f64>,
    }

    impl LeastSquares for Linear {
        type Workspace = ();
        type Error = std::fmt::Error;
        fn n_params(&self) -> usize {
            self.a.ncols()
        }
        fn n_residuals(&self) -> usize {
            self.a.nrows()
        }
        fn workspace(&self) {}
        fn residuals(&self, _: &mut (), u: &[f64], r: &mut [f64]) -> Result<(), Self::Error> {
            for (i, ri) in r.iter_mut().enumerate() {
                *ri = self.y[i] - (0..u.len()).map(|c| self.a[(i, c)] * u[c]).sum::<f64>();
            }
            Ok(())
        }
        fn residuals_jacobian(
            &self,
            ws: &mut (),
            u: &[f64],
            r: &mut [f64],
            jac: &mut DMatrix<f64>,
        ) -> Result<(), Self::Error> {
            self.residuals(ws, u, r)?;
            jac.copy_from(&(-&self.a));
            Ok(())
        }
    }

    #[test]
    fn a_quadratic_profile_is_the_parabola_of_the_covariance() {
        let n = 50;
        let a = DMatrix::from_fn(n, 2, |i, c| {
            let t = i as f64 / n as f64;
            if c == 0 {
                1.0 + t
            } else {
                t * t + 0.3
            }
        });
        let y: Vec<f64> = (0..n)
            .map(|i| 0.4 * a[(i, 0)] + 0.6 * a[(i, 1)] + 0.01 * ((i * 7 % 11) as f64 - 5.0))
            .collect();
        // The minimum exactly (normal equations), and searches that stop
        // only on the step or the cost.
        let ata_inv = a.tr_mul(&a).try_inverse().unwrap();
        let u_hat = (&ata_inv * a.tr_mul(&nalgebra::DVector::from_column_slice(&y)))
            .as_slice()
            .to_vec();
        let p = Linear { a, y };
        let mut r = vec![0.0; n];
        p.residuals(&mut (), &u_hat, &mut r).unwrap();
        let cost_hat: f64 = r.iter().map(|v| v * v).sum();
        let c00 = ata_inv[(0, 0)];
        let settings = crate::identification::lm::LmSettings::default()
            .with_decrement_tolerance(1e-12)
            .unwrap();
        let lm = LevenbergMarquardt::new(settings);
        let w = Walk {
            lm: &lm,
            u_hat: &u_hat,
            cost_hat,
            index: 0,
            threshold: 1.0,
            direction: None,
        };
        for side in [Side::Lower, Side::Upper] {
            let plan = SidePlan {
                side,
                step: 0.01,
                points: 5,
                extra: 0,
            };
            let refits = walk_side(&p, &w, &plan, &|| ());
            assert_eq!(refits.len(), 5);
            for r in &refits {
                let e = r.end.as_ref().unwrap();
                let expected = (r.at - u_hat[0]).powi(2) / c00;
                let got = e.cost - cost_hat;
                assert!(
                    (got - expected).abs() <= 1e-6 * expected,
                    "{got} {expected}"
                );
                assert_eq!(e.u[0], r.at);
            }
        }
    }

    #[test]
    fn a_walk_below_the_threshold_extends_to_the_bound_and_stops_there() {
        let a = DMatrix::from_fn(40, 2, |i, c| if c == 0 { 1e-4 } else { i as f64 });
        let y = (0..40).map(|i| 0.5 * i as f64).collect();
        let p = Linear { a, y };
        let lm = LevenbergMarquardt::default();
        let u_hat = [0.5, 0.5];
        let w = Walk {
            lm: &lm,
            u_hat: &u_hat,
            cost_hat: 0.0,
            index: 0,
            threshold: 1.0,
            direction: None,
        };
        let plan = SidePlan {
            side: Side::Upper,
            step: 0.01,
            points: 3,
            extra: 10,
        };
        let refits = walk_side(&p, &w, &plan, &|| ());
        assert_eq!(refits.last().unwrap().at, 1.0);
        assert!(refits.len() <= 13);
        assert!(refits.windows(2).all(|p| p[1].at > p[0].at));
    }
}
