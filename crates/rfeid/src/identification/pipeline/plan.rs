//! Stage 1, the plan: the problem checked against the settings, the LP_τ
//! plan (eq. 18–19) and J at its points (in batches that abandon the
//! hopeless ones: `batches`; what the rest of the run takes from them:
//! `plan_run`).
use super::error::IdentifyError;
use super::settings::{Progress, Settings};
use crate::identification::output_error::OutputError;
use crate::identification::plan::{LpTau, Plan, PlanError};
use crate::identification::plan_eval::evaluate_indices;
use crate::identification::problem::LeastSquares;
use rayon::prelude::*;

/// J at one plan point, or why it could not be evaluated (in words, as a
/// shard file keeps it).
pub type PointOutcome = Result<f64, String>;

/// Checks the problem against the settings and builds the LP_τ plan
/// (eq. 18–19) of `settings.plan_points` points.
pub fn plan(problem: &OutputError<'_>, settings: &Settings) -> Result<Plan, IdentifyError> {
    let r = problem.n_params();
    if r == 0 {
        return Err(IdentifyError::NoParameters);
    }
    if settings.starts == 0 {
        return Err(IdentifyError::NoStarts);
    }
    if problem.n_residuals() <= r + 1 {
        return Err(IdentifyError::TooFewObservations {
            observations: problem.n_residuals(),
            parameters: r,
        });
    }
    Ok(LpTau::new(r)?.plan(settings.plan_points)?)
}

/// One plan point evaluated to the end: J or why it failed, and the
/// largest running J its checks saw ([`crate::identification::output_error::Watched::reach`]),
/// from which a merge tells whether a single run would have abandoned it.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluated {
    /// J, or why it could not be evaluated.
    pub outcome: PointOutcome,
    /// The largest running J of its evaluation's checks.
    pub reach: f64,
}

/// J (eq. 16) at the plan points at positions `indices`, in parallel, in
/// the order of `indices`, each evaluated to the end. Each point is
/// evaluated on its own, so its J is bit-identical whichever subset
/// (shard) or thread evaluates it.
///
/// The points are simulated with the steps a search may take
/// ([`crate::simulation::StepChoice::search`]): their error is within 100 ×
/// the tolerance, far below the differences in J that rank the points. A
/// point those cannot simulate is evaluated again at the chosen steps, and
/// fails only if it fails there too (its reach stays the first
/// evaluation's).
pub fn evaluate_points(
    problem: &OutputError<'_>,
    plan: &Plan,
    indices: &[usize],
    progress: &dyn Progress,
) -> Result<Vec<Evaluated>, IdentifyError> {
    let all = evaluate_within(problem, plan, indices, f64::INFINITY, progress)?;
    Ok(all
        .into_iter()
        .map(|e| e.expect("no point is abandoned below an infinite limit"))
        .collect())
}

/// [`evaluate_points`], except that a point whose running J passes
/// `limit` (at the search's steps) stops there: `None`.
pub(super) fn evaluate_within(
    problem: &OutputError<'_>,
    plan: &Plan,
    indices: &[usize],
    limit: f64,
    progress: &dyn Progress,
) -> Result<Vec<Option<Evaluated>>, IdentifyError> {
    check_indices(problem, plan, indices)?;
    let switched = (problem.has_search_steps() && !problem.searching()).then(|| {
        let mut p = problem.clone();
        p.use_search_steps();
        p
    });
    let first = switched.as_ref().unwrap_or(problem);
    let n_residuals = problem.n_residuals();
    let mut points: Vec<Option<Evaluated>> = indices
        .par_iter()
        .map_init(
            || (first.workspace(), vec![0.0; n_residuals]),
            |(ws, r), &k| {
                let w = first.cost_watched(ws, plan.point(k), r, limit);
                progress.plan_point();
                w.outcome.map(|o| Evaluated {
                    outcome: o.map_err(|e| e.to_string()),
                    reach: w.reach,
                })
            },
        )
        .collect();
    let failed: Vec<usize> = (0..indices.len())
        .filter(|&k| first.searching() && points[k].as_ref().is_some_and(|e| e.outcome.is_err()))
        .collect();
    if !failed.is_empty() && !problem.cancel().is_set() {
        let again: Vec<usize> = failed.iter().map(|&k| indices[k]).collect();
        let chosen = problem.searching().then(|| problem.at_chosen_steps());
        let retried = evaluate_indices(chosen.as_ref().unwrap_or(problem), plan, &again, None)?;
        for (k, o) in failed.into_iter().zip(retried) {
            if let Some(e) = points[k].as_mut() {
                e.outcome = o.map_err(|e| e.to_string());
            }
        }
    }
    Ok(points)
}

/// The plan fits the problem and holds every index.
fn check_indices(
    problem: &OutputError<'_>,
    plan: &Plan,
    indices: &[usize],
) -> Result<(), PlanError> {
    if plan.dims() != problem.n_params() {
        return Err(PlanError::DimensionMismatch {
            plan: plan.dims(),
            problem: problem.n_params(),
        });
    }
    match indices.iter().find(|&&k| k >= plan.len()) {
        Some(&k) => Err(PlanError::IndexOutOfRange {
            first: plan.sobol_index(k),
            count: 1,
        }),
        None => Ok(()),
    }
}
