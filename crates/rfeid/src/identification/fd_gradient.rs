//! Finite-difference gradient of J (paper §3, "differential quotients"), for
//! the BFGS of eq. 20–25.
//!
//! With a fixed step h in normalised coordinates, coordinate j uses
//!
//! ```text
//! central:   ∂J/∂u_j ≈ (J(u + h e_j) − J(u − h e_j)) / 2h
//! forward:   ∂J/∂u_j ≈ (−3 J(u) + 4 J(u + h e_j) − J(u + 2h e_j)) / 2h   (u_j < h)
//! backward:  ∂J/∂u_j ≈ ( 3 J(u) − 4 J(u − h e_j) + J(u − 2h e_j)) / 2h   (u_j > 1 − h)
//! ```
//!
//! all second-order accurate, so every point evaluated lies in the box. If
//! one of the two evaluations of a coordinate fails, a first-order quotient
//! from the other one and J(u) is used; if both fail, the gradient is
//! unavailable. The 2n evaluations are independent and run in parallel on
//! the current rayon pool; the result does not depend on the thread count.
use rayon::prelude::*;

use super::problem::{evaluate_cost, EvalError, LeastSquares};

/// Counters of one finite-difference gradient.
#[derive(Debug)]
pub(crate) struct FdStats<E> {
    pub(crate) evaluations: usize,
    pub(crate) failures: usize,
    pub(crate) last_failure: Option<EvalError<E>>,
}

/// The scheme for one coordinate: offsets of its two evaluations.
#[derive(Clone, Copy)]
enum Scheme {
    Central,
    Forward,
    Backward,
}

impl Scheme {
    fn of(u: f64, h: f64) -> Self {
        if u - h < 0.0 {
            Scheme::Forward
        } else if u + h > 1.0 {
            Scheme::Backward
        } else {
            Scheme::Central
        }
    }
    fn offsets(self, h: f64) -> [f64; 2] {
        match self {
            Scheme::Central => [h, -h],
            Scheme::Forward => [h, 2.0 * h],
            Scheme::Backward => [-h, -2.0 * h],
        }
    }
    /// The derivative from J(u) = `f0` and the two evaluations.
    fn combine(self, f0: f64, f: [Option<f64>; 2], h: f64) -> Option<f64> {
        match (self, f) {
            (Scheme::Central, [Some(fp), Some(fm)]) => Some((fp - fm) / (2.0 * h)),
            (Scheme::Forward, [Some(f1), Some(f2)]) => {
                Some((-3.0 * f0 + 4.0 * f1 - f2) / (2.0 * h))
            }
            (Scheme::Backward, [Some(f1), Some(f2)]) => {
                Some((3.0 * f0 - 4.0 * f1 + f2) / (2.0 * h))
            }
            // One evaluation failed: first-order quotient with J(u).
            (s, [Some(f1), None]) => {
                let d = s.offsets(h)[0];
                Some((f1 - f0) / d)
            }
            (s, [None, Some(f2)]) => {
                let d = s.offsets(h)[1];
                Some((f2 - f0) / d)
            }
            (_, [None, None]) => None,
        }
    }
}

/// Writes the finite-difference gradient of J at `u` (where J = `f0`) into
/// `grad`. `Err(j)` names a coordinate whose evaluations all failed.
pub(crate) fn fd_gradient<P: LeastSquares>(
    problem: &P,
    u: &[f64],
    f0: f64,
    h: f64,
    grad: &mut [f64],
) -> (Result<(), usize>, FdStats<P::Error>) {
    let n = u.len();
    let m = problem.n_residuals();
    let schemes: Vec<Scheme> = u.iter().map(|&uj| Scheme::of(uj, h)).collect();
    let outcomes: Vec<Result<f64, EvalError<P::Error>>> = (0..2 * n)
        .into_par_iter()
        .map_init(
            || (problem.workspace(), u.to_vec(), vec![0.0; m]),
            |(ws, trial, r), task| {
                let (j, side) = (task / 2, task % 2);
                trial.copy_from_slice(u);
                trial[j] = (u[j] + schemes[j].offsets(h)[side]).clamp(0.0, 1.0);
                evaluate_cost(problem, ws, trial, r)
            },
        )
        .collect();
    let mut stats = FdStats {
        evaluations: 2 * n,
        failures: 0,
        last_failure: None,
    };
    let mut values = Vec::with_capacity(2 * n);
    for outcome in outcomes {
        match outcome {
            Ok(f) => values.push(Some(f)),
            Err(e) => {
                stats.failures += 1;
                stats.last_failure = Some(e);
                values.push(None);
            }
        }
    }
    for j in 0..n {
        match schemes[j].combine(f0, [values[2 * j], values[2 * j + 1]], h) {
            Some(g) => grad[j] = g,
            None => return (Err(j), stats),
        }
    }
    (Ok(()), stats)
}
