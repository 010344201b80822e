//! Evaluation of the criterion J (eq. 16) at every point of an LP_τ plan
//! (eq. 18–19), in parallel.
//!
//! Each point's J is computed on its own (one workspace per rayon task, the
//! residual squares summed in index order), and the outcomes are collected in
//! plan order, so the result is bit-identical for any number of threads.
//! A point where the evaluation fails has `J = +∞` in the paper's sense; here
//! it keeps its [`EvalError`], is counted in
//! [`PlanEvaluation::n_failed`] and ranks after every successful point.
use rayon::prelude::*;

use super::plan::{Plan, PlanError};
use super::problem::{evaluate_cost, EvalError, LeastSquares};

/// J at one point, or why its evaluation failed.
pub type Outcome<E> = Result<f64, EvalError<E>>;

/// The criterion J at every point of a plan.
#[derive(Debug, Clone)]
pub struct PlanEvaluation<E> {
    /// The evaluated points.
    pub plan: Plan,
    /// `outcomes[k]`: J at `plan.point(k)`, or why its evaluation failed.
    pub outcomes: Vec<Result<f64, EvalError<E>>>,
    /// Number of failed points.
    pub n_failed: usize,
    /// Positions `k` sorted by increasing J; failed points last (in plan
    /// order), ties in plan order.
    pub ranking: Vec<usize>,
}

impl<E> PlanEvaluation<E> {
    /// Position and J of the best point, or `None` if every point failed.
    pub fn best(&self) -> Option<(usize, f64)> {
        let k = *self.ranking.first()?;
        self.outcomes[k].as_ref().ok().map(|&cost| (k, cost))
    }

    /// Positions and J of the (at most) `count` best successful points, best
    /// first: the start points of local searches.
    pub fn best_few(&self, count: usize) -> Vec<(usize, f64)> {
        self.ranking
            .iter()
            .filter_map(|&k| self.outcomes[k].as_ref().ok().map(|&cost| (k, cost)))
            .take(count)
            .collect()
    }

    /// `true` if no point could be evaluated.
    pub fn all_failed(&self) -> bool {
        self.n_failed == self.outcomes.len()
    }

    /// Appends the evaluation of a plan extension (see
    /// [`crate::identification::plan::LpTau::plan_range`]), re-ranking all
    /// points: the first N_p points are not evaluated again (paper §3).
    pub fn append(&mut self, other: PlanEvaluation<E>) -> Result<(), PlanError> {
        self.plan.append(&other.plan)?;
        self.outcomes.extend(other.outcomes);
        self.n_failed += other.n_failed;
        self.ranking = rank(&self.outcomes);
        Ok(())
    }
}

/// Evaluates J (eq. 16) at every point of `plan`, in parallel on the current
/// rayon pool.
///
/// `progress`, if given, is called once per finished point (from worker
/// threads, in no particular order), e.g. to advance a progress bar.
pub fn evaluate_plan<P: LeastSquares>(
    problem: &P,
    plan: &Plan,
    progress: Option<&(dyn Fn() + Sync)>,
) -> Result<PlanEvaluation<P::Error>, PlanError> {
    if plan.dims() != problem.n_params() {
        return Err(PlanError::DimensionMismatch {
            plan: plan.dims(),
            problem: problem.n_params(),
        });
    }
    let all: Vec<usize> = (0..plan.len()).collect();
    let outcomes = evaluate_indices(problem, plan, &all, progress)?;
    let n_failed = outcomes.iter().filter(|o| o.is_err()).count();
    let ranking = rank(&outcomes);
    Ok(PlanEvaluation {
        plan: plan.clone(),
        outcomes,
        n_failed,
        ranking,
    })
}

/// J at the points of `plan` at positions `indices` (each < `plan.len()`),
/// in the order of `indices`, in parallel on the current rayon pool. Each
/// point is evaluated on its own, so its outcome does not depend on which
/// other points are evaluated, nor on the thread count.
pub fn evaluate_indices<P: LeastSquares>(
    problem: &P,
    plan: &Plan,
    indices: &[usize],
    progress: Option<&(dyn Fn() + Sync)>,
) -> Result<Vec<Outcome<P::Error>>, PlanError> {
    if plan.dims() != problem.n_params() {
        return Err(PlanError::DimensionMismatch {
            plan: plan.dims(),
            problem: problem.n_params(),
        });
    }
    if let Some(&k) = indices.iter().find(|&&k| k >= plan.len()) {
        return Err(PlanError::IndexOutOfRange {
            first: plan.sobol_index(k),
            count: 1,
        });
    }
    let n_residuals = problem.n_residuals();
    Ok(indices
        .par_iter()
        .map_init(
            || (problem.workspace(), vec![0.0; n_residuals]),
            |(ws, r), &k| {
                let outcome = evaluate_cost(problem, ws, plan.point(k), r);
                if let Some(progress) = progress {
                    progress();
                }
                outcome
            },
        )
        .collect())
}

/// Positions sorted by J, failed last; the sort is stable so ties keep plan
/// order.
pub fn rank<E>(outcomes: &[Result<f64, E>]) -> Vec<usize> {
    let mut ranking: Vec<usize> = (0..outcomes.len()).collect();
    ranking.sort_by(|&a, &b| match (&outcomes[a], &outcomes[b]) {
        (Ok(ja), Ok(jb)) => ja.total_cmp(jb),
        (Ok(_), Err(_)) => std::cmp::Ordering::Less,
        (Err(_), Ok(_)) => std::cmp::Ordering::Greater,
        (Err(_), Err(_)) => std::cmp::Ordering::Equal,
    });
    ranking
}
