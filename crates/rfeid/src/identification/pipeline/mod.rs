//! The whole identification (paper §3) as a short sequence of stages, each
//! in a file of its own, with values, not strings, between them:
//!
//! 1. [`plan`]: the problem checked, the LP_τ plan (eq. 18–19) and J at its
//!    points, in batches that abandon the points that cannot be among the
//!    best ([`evaluate_abandoning`]; in shards: [`evaluate_points`], then
//!    [`replay`]);
//! 2. `starts`: local searches ([`crate::identification::search`]) from the
//!    best points, on a short window of the record first;
//! 3. `weights`, before the restarts: only when no end passes the fit
//!    checks, sensor weights (eq. 14, white noise models) estimated at the
//!    best end, and the other ends searched again with them;
//! 4. `restarts`: more starts when every end still fails the fit checks
//!    (none on a ridge the bounds already show);
//! 5. `weights`, final: the noise model decided at the best end (the
//!    settings' where its fit passes the checks, else white) and the
//!    [`SensorWeighting`](crate::identification::noise::SensorWeighting) estimated
//!    there, which the criterion takes whole;
//! 6. `accuracy`: the steps per sample checked at the estimate, and the
//!    estimate refined there when the plan and the searches took fewer
//!    (`crate::simulation::steps`, "Searches");
//! 7. `bounds`: Cramér–Rao bounds (eq. 26–29), then, when asked,
//!    `profiles`: profile likelihoods of chosen parameters and their
//!    intervals ([`crate::identification::profile`]);
//! 8. `judge`: the verdict;
//! 9. `assemble`: the [`IdentificationResult`].
//!
//! Whether a fit passes the checks (stages 3–5) and what the verdict's
//! residual tests judge (stage 8) come from one function,
//! `judge::own_filters`: each sensor's residuals whitened by a noise model
//! fitted to them, whatever weighting the criterion holds.
//!
//! Every simulation is counted where it runs, in the criterion's
//! [`crate::identification::tally::Counter`].
mod accuracy;
mod assemble;
mod batches;
mod bounds;
mod error;
mod judge;
mod plan;
mod plan_run;
mod profiles;
mod restarts;
mod searcher;
mod settings;
mod starts;
mod weights;

pub use self::batches::{evaluate_abandoning, keep, replay, PlanPoints, PointState};
pub use self::error::{IdentifyError, SearchError};
pub use self::plan::{evaluate_points, plan, Evaluated, PointOutcome};
pub use self::settings::{
    Method, NoiseModel, ProfileRequest, Progress, Settings, Silent, Start, Weighting, DEFAULT_PLAN,
    DEFAULT_RESTARTS, DEFAULT_STARTS,
};
pub use crate::identification::result::StartFailure;

use self::assemble::{assemble, Found};
use self::plan_run::PlanRun;
use self::searcher::Searcher;
use crate::identification::output_error::OutputError;
use crate::identification::plan::Plan;
use crate::identification::problem::LeastSquares;
use crate::identification::result::{IdentificationResult, Timings};
use crate::identification::search::SearchOutcome;
use crate::identification::verdict::StartEnd;
use std::time::Instant;

/// Runs the identification of `problem`'s parameters: [`plan`], then
/// [`evaluate_abandoning`], then [`finish`].
pub fn identify(
    problem: OutputError<'_>,
    settings: &Settings,
    progress: &dyn Progress,
) -> Result<IdentificationResult, IdentifyError> {
    let t_start = Instant::now();
    // A profile of a parameter that is not identified is refused first.
    profiles::columns(&problem, settings)?;
    let one_point = Settings {
        plan_points: 1,
        starts: 1,
        ..settings.clone()
    };
    let plan = plan(
        &problem,
        match settings.start {
            Start::Plan => settings,
            Start::Values => &one_point,
        },
    )?;
    progress.plan_started(plan.len());
    let states = evaluate_abandoning(&problem, &plan, keep(settings), progress);
    if problem.cancel().is_set() {
        return Err(IdentifyError::Cancelled);
    }
    let points = PlanPoints {
        states: states?,
        known: None,
    };
    let plan_seconds = t_start.elapsed().as_secs_f64();
    finish(problem, settings, &plan, points, plan_seconds, progress)
}

/// Continues an identification from the plan's points (`points.states[k]`
/// for `plan.point(k)`, from [`evaluate_abandoning`], or from
/// [`evaluate_points`] in pieces through [`replay`]):
/// local searches from the best points, reweighting, restarts, the
/// accuracy check, Cramér–Rao bounds and the verdict. `plan_seconds` is
/// the wall time the plan took. A run whose criterion was cancelled
/// ([`OutputError::set_cancel`]) ends with [`IdentifyError::Cancelled`],
/// whatever its stages made of the failed simulations.
pub fn finish(
    problem: OutputError<'_>,
    settings: &Settings,
    plan: &Plan,
    points: PlanPoints,
    plan_seconds: f64,
    progress: &dyn Progress,
) -> Result<IdentificationResult, IdentifyError> {
    let cancel = problem.cancel().clone();
    let result = finish_stages(problem, settings, plan, points, plan_seconds, progress);
    match cancel.is_set() {
        true => Err(IdentifyError::Cancelled),
        false => result,
    }
}

/// The stages of [`finish`].
fn finish_stages(
    mut problem: OutputError<'_>,
    settings: &Settings,
    plan: &Plan,
    points: PlanPoints,
    plan_seconds: f64,
    progress: &dyn Progress,
) -> Result<IdentificationResult, IdentifyError> {
    let t_finish = Instant::now();
    let profiled = profiles::columns(&problem, settings)?;
    if let Some(bytes) = settings.jacobian_memory {
        problem.set_jacobian_memory(bytes);
    }
    // Until the accuracy stage, the searches take the steps a search may.
    problem.use_search_steps();
    let mut plan = PlanRun::new(&problem, settings, plan, points)?;
    let before = problem.tally();
    let searcher = Searcher::new(settings, problem.n_params(), progress)?;
    let t_local = Instant::now();
    let mut ends = first_searches(&mut problem, &searcher, &plan)?;
    let judged = restarts::run(&problem.clone(), &searcher, &mut plan, &mut ends);
    let (best, kept) = best_end(&problem, ends.searches, &judged)
        .ok_or_else(|| IdentifyError::AllStartsFailed(ends.failures.clone()))?;
    let best = match settings.weighting {
        Weighting::EstimatedNoise => {
            let noise_model = weights::final_noise_model(&problem, settings, &best.u);
            weights::estimate(&mut problem, &searcher, best, noise_model)?
        }
        Weighting::Equal => best,
    };
    let (best, step_warnings) = accuracy::check(&mut problem, &searcher, best)?;
    let t_local = t_local.elapsed().as_secs_f64();
    let t_bounds = Instant::now();
    let bounds = bounds::at(
        &problem,
        &best.u,
        best.linearised.as_ref(),
        &settings.uncertainty,
        settings.weighting == Weighting::Equal,
    );
    problem.keep_runs(false);
    let t_bounds = t_bounds.elapsed().as_secs_f64();
    let t_profiles = Instant::now();
    let (profiles, profile_warnings) =
        profiles::run(&problem, settings, &profiled, &best, &bounds, progress);
    let t_profiles = t_profiles.elapsed().as_secs_f64();
    let fitted = problem.simulate_all(&best.u);
    let verdict = judge::verdict(&problem, &best, &kept, &bounds, &fitted, settings);
    let warnings = ends
        .restart_warning
        .into_iter()
        .chain(step_warnings)
        .chain(ends.warnings)
        .chain(profile_warnings)
        .collect();
    let tally = plan.tally() + (problem.tally() - before);
    let (completion, completion_seconds) = plan.completion_work();
    let found = Found {
        plan: &plan,
        best,
        bounds,
        fitted,
        verdict,
        warnings,
        failed_starts: ends.failures,
        tally,
        timings: Timings {
            plan: plan_seconds + completion_seconds,
            local_search: t_local - completion_seconds,
            uncertainty: t_bounds,
            profiles: t_profiles,
            total: plan_seconds + t_finish.elapsed().as_secs_f64(),
            searches: searcher.times(),
            discarded: searcher.discarded(),
            simulations: problem.work() + completion,
        },
        profiles,
    };
    Ok(assemble(&problem, settings, found))
}

/// The first searches and the reweighting before the restarts, one after
/// the other: from here until the bounds, a search that starts
/// where one ended takes its first Jacobian from that one's runs
/// ([`OutputError::keep_runs`]). The restarts, which search at once, take
/// a clone, which keeps none.
fn first_searches(
    problem: &mut OutputError<'_>,
    searcher: &Searcher<'_>,
    plan: &PlanRun<'_, '_>,
) -> Result<starts::Ends, IdentifyError> {
    problem.keep_runs(true);
    let mut ends = starts::run(problem, searcher, plan)?;
    weights::before_restarts(problem, searcher, &mut ends)?;
    Ok(ends)
}

/// The search with the lowest J among those the restarts kept, and the
/// kept ends (for the verdict's minima); `None` if none is left.
fn best_end(
    problem: &OutputError<'_>,
    searches: Vec<SearchOutcome>,
    judged: &restarts::Judged,
) -> Option<(SearchOutcome, Vec<StartEnd>)> {
    let mut kept = Vec::new();
    let mut best: Option<SearchOutcome> = None;
    for (k, s) in searches.into_iter().enumerate() {
        if !judged.keeps(k) {
            // A side minimum, left behind (and described in a warning).
            continue;
        }
        kept.push(StartEnd {
            cost: s.cost,
            parameters: problem.to_physical(&s.u),
        });
        if best.as_ref().is_none_or(|b| s.cost < b.cost) {
            best = Some(s);
        }
    }
    best.map(|b| (b, kept))
}
