//! How a local search ends: a [`StopReason`] when it ran, a [`SolveError`]
//! when it could not start.
use serde::{Deserialize, Serialize};
use std::fmt;

use super::problem::EvalError;

/// Why a local search (Levenberg–Marquardt or the BFGS of eq. 20–25) stopped.
///
/// The `Converged*` variants mean a tolerance was met; the others that the
/// search gave up, in which case the returned point is still the best one
/// found (every accepted step decreases J).
///
/// RESULT.json names a reason by its variant's name (`ConvergedDecrement`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum StopReason {
    /// The last step was shorter than the step tolerance.
    ConvergedStep,
    /// The relative decrease of J (and, for Levenberg–Marquardt, its
    /// predicted decrease) fell below the cost tolerance, or J is exactly 0.
    ConvergedCost,
    /// The projected gradient of J is below the gradient tolerance.
    ConvergedGradient,
    /// The undamped Gauss–Newton step would lower J by less than the
    /// decrement tolerance times the residual variance: the point is within
    /// a small fraction of a standard error of the minimum (Levenberg–
    /// Marquardt only).
    ConvergedDecrement,
    /// The iteration limit was reached.
    MaxIterations,
    /// No step decreased J: Levenberg–Marquardt rejected a step at the
    /// maximal damping, or the line search of eq. 20 found no decrease.
    NoProgress,
    /// Steps towards lower J kept failing to evaluate until they became
    /// negligible (or the damping maximal): the search stopped at the edge of
    /// the region where the problem can be evaluated, not at a minimum.
    EvaluationFailures,
    /// The finite-difference gradient (BFGS) could not be formed: the
    /// evaluations on both sides of the point failed for some variable.
    GradientUnavailable,
}

impl StopReason {
    /// `true` for the `Converged*` variants.
    pub fn is_converged(self) -> bool {
        matches!(
            self,
            StopReason::ConvergedStep
                | StopReason::ConvergedCost
                | StopReason::ConvergedGradient
                | StopReason::ConvergedDecrement
        )
    }
}

impl fmt::Display for StopReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let text = match self {
            StopReason::ConvergedStep => "converged: the step became smaller than the step tolerance",
            StopReason::ConvergedCost => {
                "converged: the criterion stopped decreasing (relative decrease below the cost tolerance)"
            }
            StopReason::ConvergedGradient => {
                "converged: the projected gradient is below the gradient tolerance"
            }
            StopReason::ConvergedDecrement => {
                "converged: the estimate is within a small fraction of a standard error of the \
                 minimum (Gauss–Newton decrement below its tolerance)"
            }
            StopReason::MaxIterations => "stopped: the iteration limit was reached",
            StopReason::NoProgress => "stopped: no step could decrease the criterion",
            StopReason::EvaluationFailures => {
                "stopped: steps towards a lower criterion failed to evaluate (edge of the feasible region)"
            }
            StopReason::GradientUnavailable => {
                "stopped: the finite-difference gradient could not be evaluated"
            }
        };
        f.write_str(text)
    }
}

/// Why a local search could not start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError<E> {
    /// The problem has no parameters or no residuals.
    #[error("the problem is empty ({n_params} parameters, {n_residuals} residuals)")]
    EmptyProblem {
        /// Number of parameters of the problem.
        n_params: usize,
        /// Number of residuals of the problem.
        n_residuals: usize,
    },
    /// The start point has the wrong length.
    #[error("the start point has {got} coordinates, the problem has {expected} parameters")]
    StartDimension {
        /// Number of parameters of the problem.
        expected: usize,
        /// Length of the given start point.
        got: usize,
    },
    /// A start coordinate lies outside `[0, 1]` (eq. 17) or is not finite.
    #[error("start coordinate {index} = {value} lies outside the normalised box [0, 1]")]
    StartOutsideBox {
        /// Index of the coordinate.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// The evaluation at the start point failed, so there is nothing to
    /// improve on (J = +∞ there).
    #[error("the evaluation at the start point failed: {0}")]
    StartFailed(EvalError<E>),
}

/// Checks a start point against the problem's size and the box (eq. 17).
pub(crate) fn check_start<E>(
    n_params: usize,
    n_residuals: usize,
    u0: &[f64],
) -> Result<(), SolveError<E>> {
    if n_params == 0 || n_residuals == 0 {
        return Err(SolveError::EmptyProblem {
            n_params,
            n_residuals,
        });
    }
    if u0.len() != n_params {
        return Err(SolveError::StartDimension {
            expected: n_params,
            got: u0.len(),
        });
    }
    if let Some((index, &value)) = u0
        .iter()
        .enumerate()
        .find(|(_, v)| !(0.0..=1.0).contains(*v))
    {
        return Err(SolveError::StartOutsideBox { index, value });
    }
    Ok(())
}
