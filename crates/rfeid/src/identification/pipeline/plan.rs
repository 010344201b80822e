//! Stage 1, the plan: the problem checked against the settings, the LP_τ
//! plan (eq. 18–19), J at its points, and what the rest of the run takes
//! from them ([`PlanRun`]).
use super::error::IdentifyError;
use super::settings::{Progress, Settings};
use crate::identification::output_error::OutputError;
use crate::identification::plan::{LpTau, Plan, PlanError};
use crate::identification::plan_eval::{evaluate_indices, rank};
use crate::identification::problem::LeastSquares;
use crate::identification::result::PlanSummary;
use crate::identification::tally::Tally;

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

/// J (eq. 16) at the plan points at positions `indices`, in parallel, in
/// the order of `indices`. Each point is evaluated on its own, so its J is
/// bit-identical whichever subset (shard) or thread evaluates it.
///
/// The points are simulated with the steps a search may take
/// ([`crate::simulation::StepChoice::search`]): their error is within 100 ×
/// the tolerance, far below the differences in J that rank the points. A
/// point those cannot simulate is evaluated again at the chosen steps, and
/// fails only if it fails there too.
pub fn evaluate_points(
    problem: &OutputError<'_>,
    plan: &Plan,
    indices: &[usize],
    progress: &dyn Progress,
) -> Result<Vec<PointOutcome>, IdentifyError> {
    let tick = || progress.plan_point();
    let switched = (problem.has_search_steps() && !problem.searching()).then(|| {
        let mut p = problem.clone();
        p.use_search_steps();
        p
    });
    let first = switched.as_ref().unwrap_or(problem);
    let mut outcomes = evaluate_indices(first, plan, indices, Some(&tick))?;
    let failed: Vec<usize> = (0..indices.len())
        .filter(|&k| first.searching() && outcomes[k].is_err())
        .collect();
    if !failed.is_empty() && !problem.cancel().is_set() {
        let again: Vec<usize> = failed.iter().map(|&k| indices[k]).collect();
        let chosen = problem.searching().then(|| problem.at_chosen_steps());
        let retried = evaluate_indices(chosen.as_ref().unwrap_or(problem), plan, &again, None)?;
        for (k, o) in failed.into_iter().zip(retried) {
            outcomes[k] = o;
        }
    }
    Ok(outcomes
        .into_iter()
        .map(|o| o.map_err(|e| e.to_string()))
        .collect())
}

/// The evaluated plan, checked, with the points the local searches start
/// from.
pub(super) struct PlanRun<'p> {
    /// The plan.
    pub plan: &'p Plan,
    /// J at every point, in plan order.
    pub outcomes: Vec<PointOutcome>,
    /// Points that failed.
    pub failed: usize,
    /// The best `settings.starts` points (plan index, J), best first.
    pub starts: Vec<(usize, f64)>,
    /// The simulations the plan took: each point simulates every
    /// experiment once; a failed point counts one failure (a point that
    /// the searches' fewer steps could not simulate, evaluated again at the
    /// chosen ones, counts once).
    pub tally: Tally,
}

impl<'p> PlanRun<'p> {
    /// Checks `outcomes` against the plan and the problem and ranks them;
    /// an error if they do not belong together or every point failed.
    pub fn new(
        problem: &OutputError<'_>,
        settings: &Settings,
        plan: &'p Plan,
        outcomes: Vec<PointOutcome>,
    ) -> Result<Self, IdentifyError> {
        if outcomes.len() != plan.len() || plan.dims() != problem.n_params() {
            return Err(IdentifyError::Plan(PlanError::DimensionMismatch {
                plan: plan.dims(),
                problem: problem.n_params(),
            }));
        }
        let failed = outcomes.iter().filter(|o| o.is_err()).count();
        if failed == outcomes.len() {
            return Err(IdentifyError::AllPlanPointsFailed {
                points: plan.len(),
                first: first_failure(&outcomes).unwrap_or_default(),
            });
        }
        let starts = rank(&outcomes)
            .into_iter()
            .filter_map(|k| outcomes[k].as_ref().ok().map(|&cost| (k, cost)))
            .take(settings.starts)
            .collect();
        let tally = Tally {
            simulations: plan.len() * problem.n_experiments(),
            with_sensitivities: 0,
            failed,
        };
        Ok(PlanRun {
            plan,
            outcomes,
            failed,
            starts,
            tally,
        })
    }

    /// The plan as RESULT.json records it.
    pub fn summary(&self) -> PlanSummary {
        PlanSummary {
            points: self.plan.len(),
            failed: self.failed,
            costs: self
                .outcomes
                .iter()
                .map(|o| o.as_ref().ok().copied())
                .collect(),
            starts: self.starts.iter().map(|s| s.0).collect(),
            first_failure: first_failure(&self.outcomes),
        }
    }
}

fn first_failure(outcomes: &[PointOutcome]) -> Option<String> {
    outcomes.iter().find_map(|o| o.as_ref().err().cloned())
}
