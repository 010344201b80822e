//! The whole identification (paper §3): LP_τ plan over the box, local search
//! from the best point(s), Cramér–Rao bounds at the estimate.
use super::bfgs::{Bfgs, BfgsSettings};
use super::lm::{LevenbergMarquardt, LmSettings};
use super::output_error::OutputError;
use super::plan::{LpTau, Plan, PlanError};
use super::plan_eval::{evaluate_indices, rank};
use super::problem::{sum_of_squares, LeastSquares};
pub use super::result::StartFailure;
use super::result::{
    ExperimentSummary, IdentificationResult, Iterate, ParameterEstimate, PlanSummary, Timings,
};
use super::termination::{SolveError, StopReason};
use super::uncertainty::{cramer_rao_mapped, IdentifiabilityWarning, UncertaintySettings};
use super::verdict::{assess, fit_fails, Evidence, FitSignal, StartEnd, VerdictSettings};
use crate::simulation::steps::{choose_steps, estimate_error};
use crate::simulation::{SimulationError, StepChoice};
use nalgebra::DMatrix;
use std::time::Instant;

/// The local search method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// Levenberg–Marquardt with the exact Jacobian.
    #[default]
    Lm,
    /// The paper's BFGS with finite-difference gradients (eq. 20–25).
    Bfgs,
}

/// How the sensors are weighted in J (eq. 13).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Weighting {
    /// w_c = 1, the paper's choice (eq. 14).
    #[default]
    Equal,
    /// w_c = 1/σ_c², with σ_c² estimated from each sensor's residuals after a
    /// fit; the fit is repeated with the new weights (up to 5 times).
    EstimatedNoise,
}

/// Where the local search starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Start {
    /// From the best [`Settings::starts`] points of the LP_τ plan (eq. 18–19).
    #[default]
    Plan,
    /// Once, from the identified parameters' `value`s in the model file
    /// (which lie in their boxes). [`identify`] then evaluates a plan of one
    /// point only, for the checks of the problem; the global search is
    /// skipped, so the estimate is the minimum nearest the values.
    Values,
}

/// Settings of an identification.
#[derive(Debug, Clone, Default)]
pub struct Settings {
    /// N_p, plan points (≥ 1).
    pub plan_points: usize,
    /// Local searches from the best few plan points (≥ 1).
    pub starts: usize,
    /// Local search method.
    pub method: Method,
    /// Sensor weighting.
    pub weighting: Weighting,
    /// Levenberg–Marquardt settings.
    pub lm: LmSettings,
    /// BFGS settings.
    pub bfgs: BfgsSettings,
    /// Uncertainty settings.
    pub uncertainty: UncertaintySettings,
    /// Thresholds of the verdict.
    pub verdict: VerdictSettings,
    /// If set, each start first fits this fraction (0, 1) of the record
    /// (from its first used sample), then the whole record from there: the
    /// short record's criterion is less rugged, so a start far from the
    /// truth is less likely to end in a side minimum.
    pub window: Option<f64>,
    /// Where the local search starts.
    pub start: Start,
    /// Automatic restarts: when no local search from the plan ends where
    /// the fit passes the verdict's per-sensor checks (fit, whiteness,
    /// noise level), up to this many further searches start from the
    /// next-best plan points that are distinct from every start and end so
    /// far, until one passes ([`restart_from_side_minima`]). 0: none.
    /// `rfeid identify` uses [`DEFAULT_RESTARTS`].
    pub restarts: usize,
}

/// The automatic restarts of `rfeid identify` ([`Settings::restarts`]).
pub const DEFAULT_RESTARTS: usize = 8;

/// Plan points closer than this (RMS over the normalised coordinates) to a
/// start or an end already searched are not restarted from: they would most
/// likely end in the same minimum.
const DISTINCT: f64 = 0.1;

/// What a caller may watch (progress bars, logs). Every method has a no-op default.
pub trait Progress: Sync {
    /// The plan of `points` points starts.
    fn plan_started(&self, _points: usize) {}
    /// One plan point is done.
    fn plan_point(&self) {}
    /// Local search `k` of `of` starts at criterion `cost`.
    fn search_started(&self, _k: usize, _of: usize, _cost: f64) {}
    /// An iteration of the local search ended at criterion `cost`.
    fn iteration(&self, _iteration: usize, _cost: f64) {}
}

/// No progress reporting.
pub struct Silent;
impl Progress for Silent {}

/// Why an identification could not be done.
#[derive(Debug, Clone, thiserror::Error)]
pub enum IdentifyError {
    /// The model has no parameter with a box.
    #[error("the model has no identified parameters (give a parameter 'min' and 'max')")]
    NoParameters,
    /// Zero plan points, or too many dimensions.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// Zero starts.
    #[error("the number of starts must be at least 1")]
    NoStarts,
    /// Fewer observations than the bounds need (eq. 29: N − r − 1 > 0).
    #[error("{observations} observations are too few for {parameters} parameters (eq. 29 needs N − r − 1 > 0); is --from too late?")]
    TooFewObservations {
        /// N.
        observations: usize,
        /// r.
        parameters: usize,
    },
    /// No plan point could be simulated.
    #[error("all {points} plan points failed to simulate; the first failure: {first}")]
    AllPlanPointsFailed {
        /// N_p.
        points: usize,
        /// The first failure.
        first: String,
    },
    /// The local search could not start.
    #[error("local search: {0}")]
    Solve(String),
    /// Every local search failed to start; each start's reason, in order.
    #[error("all {} local searches failed: {}", .0.len(), describe_failures(.0))]
    AllStartsFailed(Vec<StartFailure>),
}

fn describe_failures(failures: &[StartFailure]) -> String {
    failures
        .iter()
        .map(|f| format!("start at plan point {}: {}", f.plan_index + 1, f.reason))
        .collect::<Vec<_>>()
        .join("; ")
}

/// Runs `search` from every start, recording a failed start instead of
/// ending there; the best finished search and the failures, or
/// [`IdentifyError::AllStartsFailed`] if none finished.
fn run_starts<S>(
    starts: &[(usize, f64)],
    mut search: impl FnMut(usize, usize, f64) -> Result<S, IdentifyError>,
) -> Result<(Vec<S>, Vec<StartFailure>), IdentifyError> {
    let mut done = Vec::new();
    let mut failures = Vec::new();
    for (k, &(idx, cost)) in starts.iter().enumerate() {
        match search(k, idx, cost) {
            Ok(s) => done.push(s),
            Err(e) => failures.push(StartFailure {
                plan_index: idx,
                reason: match e {
                    IdentifyError::Solve(m) => m,
                    e => e.to_string(),
                },
            }),
        }
    }
    if done.is_empty() {
        return Err(IdentifyError::AllStartsFailed(failures));
    }
    Ok((done, failures))
}

/// A finished local search, whichever method.
struct Search {
    u: Vec<f64>,
    cost: f64,
    stop: StopReason,
    iterations: usize,
    residual_evals: usize,
    jacobian_evals: usize,
    failed: usize,
    history: Vec<(usize, f64, Vec<f64>)>,
}

fn solve_err<E: std::fmt::Display>(e: SolveError<E>) -> IdentifyError {
    IdentifyError::Solve(e.to_string())
}

/// A local search from a plan point: on the short window first if
/// `settings.window` says so (see [`Settings::window`]), then on the whole
/// record. The counts include both searches; the history is the last one's.
fn start_search(
    problem: &OutputError<'_>,
    settings: &Settings,
    u0: &[f64],
    progress: &dyn Progress,
) -> Result<Search, IdentifyError> {
    let Some(fraction) = settings.window.filter(|f| *f > 0.0 && *f < 1.0) else {
        return local_search(problem, settings, u0, progress);
    };
    if problem.n_experiments() > 1 {
        // A campaign's experiments have records of their own lengths; the
        // window applies to one record.
        return local_search(problem, settings, u0, progress);
    }
    let model = problem.simulator().model();
    let first = problem.first_sample();
    let n = problem.measured().n_samples;
    let r = problem.n_params();
    let used = ((fraction * (n - first) as f64).ceil() as usize).max(r + 2);
    if first + used >= n {
        return local_search(problem, settings, u0, progress);
    }
    let n_w = first + used;
    let mut short = model.clone();
    short.sampling.duration = n_w as f64 / short.sampling.sample_rate;
    if short.sampling.n_samples() != n_w {
        return local_search(problem, settings, u0, progress);
    }
    let y = problem.measured();
    let mut values = Vec::with_capacity(y.n_sensors * n_w);
    for c in 0..y.n_sensors {
        values.extend_from_slice(&y.sensor(c)[..n_w]);
    }
    let truncated = crate::simulation::Response {
        n_samples: n_w,
        n_sensors: y.n_sensors,
        values,
    };
    // The whole record's integrator and steps per sample, held as they are.
    let mut sim =
        crate::simulation::Simulator::with_integrator(&short, problem.simulator().integrator());
    sim.set_steps(problem.simulator().steps());
    let mut window = OutputError::new(sim, truncated, first);
    window.set_weights(&problem.weights());
    // The window only has to bring the search into the whole record's
    // basin: stop once the Gauss–Newton step would gain less than r residual
    // variances there, the expected scatter of the window's own minimum
    // about the truth (a χ² with r degrees of freedom), instead of
    // polishing a minimum the whole record moves anyway.
    let mut window_settings = settings.clone();
    window_settings.lm = settings
        .lm
        .clone()
        .with_decrement_tolerance(r as f64)
        .unwrap_or_else(|_| settings.lm.clone());
    let (u1, pre) = match local_search(&window, &window_settings, u0, progress) {
        Ok(s) => (s.u.clone(), Some(s)),
        Err(_) => (u0.to_vec(), None),
    };
    let mut s = local_search(problem, settings, &u1, progress)?;
    if let Some(pre) = pre {
        s.residual_evals += pre.residual_evals;
        s.jacobian_evals += pre.jacobian_evals;
        s.failed += pre.failed;
    }
    Ok(s)
}

/// Whether the fit at u passes the verdict's per-sensor checks (fit,
/// whiteness, noise level); a failed simulation does not.
fn fit_passes(problem: &OutputError<'_>, settings: &Settings, u: &[f64]) -> bool {
    problem
        .simulate_all(u)
        .is_ok_and(|g| !fit_fails(&fit_signals(problem, Some(&g)), &settings.verdict))
}

/// What the automatic restarts did.
#[derive(Debug, Default)]
struct Restarts {
    /// Simulations spent on the fit checks (one per experiment and check).
    checks: usize,
    /// When a restart found an end that passes the fit checks: whether
    /// each search (in order) passes, so that the side minima are left out.
    passed: Option<Vec<bool>>,
    /// What happened, in words, when any restart ran.
    warning: Option<String>,
}

/// The automatic restarts ([`Settings::restarts`]): if no search in
/// `searches` ends where the fit passes the verdict's per-sensor checks,
/// further searches start from the best remaining plan points (by J) that
/// lie at least [`DISTINCT`] from every start and end so far, one at a
/// time, until one passes or `settings.restarts` have run. Their searches
/// and failures are appended. Deterministic: the candidates follow the
/// plan's ranking.
#[allow(clippy::too_many_arguments)]
fn restart_from_side_minima(
    problem: &OutputError<'_>,
    settings: &Settings,
    plan: &Plan,
    outcomes: &[PointOutcome],
    used: &[usize],
    searches: &mut Vec<Search>,
    failures: &mut Vec<StartFailure>,
    progress: &dyn Progress,
) -> Restarts {
    let mut out = Restarts::default();
    if settings.restarts == 0 {
        return out;
    }
    let mut passes = |u: &[f64]| {
        out.checks += problem.n_experiments();
        fit_passes(problem, settings, u)
    };
    let mut passed: Vec<bool> = searches.iter().map(|s| passes(&s.u)).collect();
    if passed.iter().any(|&p| p) || searches.is_empty() {
        return out;
    }
    let first_cost = searches
        .iter()
        .map(|s| s.cost)
        .fold(f64::INFINITY, f64::min);
    let distance = |a: &[f64], b: &[f64]| {
        (a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>() / a.len() as f64).sqrt()
    };
    let mut visited: Vec<Vec<f64>> = used.iter().map(|&i| plan.point(i).to_vec()).collect();
    visited.extend(searches.iter().map(|s| s.u.clone()));
    let mut tried = 0;
    for idx in rank(outcomes) {
        let Ok(cost) = outcomes[idx] else { break };
        if tried == settings.restarts {
            break;
        }
        let p = plan.point(idx);
        if used.contains(&idx) || visited.iter().any(|v| distance(v, p) < DISTINCT) {
            continue;
        }
        tried += 1;
        visited.push(p.to_vec());
        progress.search_started(used.len() + tried - 1, used.len() + settings.restarts, cost);
        match start_search(problem, settings, p, progress) {
            Ok(s) => {
                visited.push(s.u.clone());
                let ok = passes(&s.u);
                searches.push(s);
                passed.push(ok);
                if ok {
                    break;
                }
            }
            Err(e) => failures.push(StartFailure {
                plan_index: idx,
                reason: match e {
                    IdentifyError::Solve(m) => m,
                    e => e.to_string(),
                },
            }),
        }
    }
    let found = passed.iter().any(|&p| p);
    out.warning = Some(match found {
        true => {
            let best = searches
                .iter()
                .zip(&passed)
                .filter(|(_, p)| **p)
                .map(|(s, _)| s.cost)
                .fold(f64::INFINITY, f64::min);
            format!(
                "the local search from the plan ended at J = {first_cost:.6e}, where the fit \
                 fails the verdict's per-sensor checks (a side minimum); {tried} automatic \
                 restart(s) from the next-best distinct plan points found J = {best:.6e}, where \
                 it passes; the side minima are left out of the result"
            )
        }
        false => format!(
            "the local search from the plan ended at J = {first_cost:.6e}, where the fit fails \
             the verdict's per-sensor checks, and {tried} automatic restart(s) from the \
             next-best distinct plan points found no minimum where it passes"
        ),
    });
    out.passed = found.then_some(passed);
    out
}

/// Sensor weights estimated from the residuals ([`Weighting::EstimatedNoise`]):
/// each sensor weighted by the inverse of its residual variance at the end
/// of `best` (eq. 14 with each sensor's own noise level), the search
/// continued with those weights, until they change by less than 1 % (at
/// most 5 rounds). Returns the end under the weights `problem` then holds;
/// adds the simulations spent (plain, with sensitivities, failed) to
/// `counts`.
fn estimate_weights(
    problem: &mut OutputError<'_>,
    settings: &Settings,
    mut best: Search,
    progress: &dyn Progress,
    counts: &mut (usize, usize, usize),
) -> Result<Search, IdentifyError> {
    for _ in 0..5 {
        let ssr = sensor_ssr(problem, &best.u).map_err(|e| IdentifyError::Solve(e.to_string()))?;
        counts.0 += problem.n_experiments();
        let weights: Vec<f64> = ssr
            .iter()
            .zip(problem.weight_samples())
            .map(|(s, used)| {
                if *s > 0.0 {
                    used as f64 / s
                } else {
                    f64::INFINITY
                }
            })
            .collect();
        // A sensor fitted exactly (zero residuals) gets the largest finite
        // weight, not an arbitrary one.
        let largest = weights
            .iter()
            .cloned()
            .filter(|w| w.is_finite())
            .fold(1.0, f64::max);
        let weights: Vec<f64> = weights
            .iter()
            .map(|w| if w.is_finite() { *w } else { largest })
            .collect();
        let scale = weights.iter().cloned().fold(f64::INFINITY, f64::min);
        let weights: Vec<f64> = weights.iter().map(|w| w / scale).collect();
        let change = weights
            .iter()
            .zip(problem.weights())
            .map(|(a, b)| (a / b - 1.0).abs())
            .fold(0.0, f64::max);
        if change < 0.01 {
            // Keep the weights J was minimised with, so that the
            // reported criterion and weights belong together.
            break;
        }
        problem.set_weights(&weights);
        let s = local_search(problem, settings, &best.u, progress)?;
        counts.0 += s.residual_evals;
        counts.1 += s.jacobian_evals;
        counts.2 += s.failed;
        best = s;
    }
    Ok(best)
}

fn local_search(
    problem: &OutputError<'_>,
    settings: &Settings,
    u0: &[f64],
    progress: &dyn Progress,
) -> Result<Search, IdentifyError> {
    let mut observe = |it: usize, cost: f64| progress.iteration(it, cost);
    match settings.method {
        Method::Lm => {
            let r = LevenbergMarquardt::new(settings.lm.clone())
                .minimize_observed(problem, u0, &mut observe)
                .map_err(solve_err)?;
            Ok(Search {
                u: r.u,
                cost: r.cost,
                stop: r.stop_reason,
                iterations: r.iterations,
                residual_evals: r.residual_evaluations,
                jacobian_evals: r.jacobian_evaluations,
                failed: r.failed_evaluations,
                history: r
                    .history
                    .into_iter()
                    .map(|h| (h.iteration, h.cost, h.u))
                    .collect(),
            })
        }
        Method::Bfgs => {
            let r = Bfgs::new(settings.bfgs.clone())
                .minimize_observed(problem, u0, &mut observe)
                .map_err(solve_err)?;
            Ok(Search {
                u: r.u,
                cost: r.cost,
                stop: r.stop_reason,
                iterations: r.iterations,
                residual_evals: r.cost_evaluations,
                jacobian_evals: 0,
                failed: r.failed_evaluations,
                history: r
                    .history
                    .into_iter()
                    .map(|h| (h.iteration, h.cost, h.u))
                    .collect(),
            })
        }
    }
}

/// Per-sensor sums of squared unweighted residuals at u, every
/// experiment's sensors in turn.
fn sensor_ssr(problem: &OutputError<'_>, u: &[f64]) -> Result<Vec<f64>, SimulationError> {
    Ok(problem.sensor_ssr(&problem.simulate_all(u)?))
}

/// J at one plan point, or why it could not be evaluated (in words).
pub type PointOutcome = Result<f64, String>;

/// Runs the identification of `problem`'s parameters: [`plan`], then
/// [`evaluate_points`] on every point, then [`finish`].
pub fn identify(
    problem: OutputError<'_>,
    settings: &Settings,
    progress: &dyn Progress,
) -> Result<IdentificationResult, IdentifyError> {
    let t_start = Instant::now();
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
    let all: Vec<usize> = (0..plan.len()).collect();
    let outcomes = evaluate_points(&problem, &plan, &all, progress)?;
    finish(
        problem,
        settings,
        &plan,
        outcomes,
        t_start.elapsed().as_secs_f64(),
        progress,
    )
}

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
pub fn evaluate_points(
    problem: &OutputError<'_>,
    plan: &Plan,
    indices: &[usize],
    progress: &dyn Progress,
) -> Result<Vec<PointOutcome>, IdentifyError> {
    let tick = || progress.plan_point();
    let outcomes = evaluate_indices(problem, plan, indices, Some(&tick))?;
    Ok(outcomes
        .into_iter()
        .map(|o| o.map_err(|e| e.to_string()))
        .collect())
}

/// Continues an identification from J at every plan point (`outcomes[k]`
/// for `plan.point(k)`, from [`evaluate_points`], possibly in pieces):
/// local searches from the best points, reweighting, Cramér–Rao bounds and
/// the verdict. `plan_seconds` is the wall time the plan took.
pub fn finish(
    mut problem: OutputError<'_>,
    settings: &Settings,
    plan: &Plan,
    outcomes: Vec<PointOutcome>,
    plan_seconds: f64,
    progress: &dyn Progress,
) -> Result<IdentificationResult, IdentifyError> {
    let t_finish = Instant::now();
    let r = problem.n_params();
    if outcomes.len() != plan.len() || plan.dims() != r {
        return Err(IdentifyError::Plan(PlanError::DimensionMismatch {
            plan: plan.dims(),
            problem: r,
        }));
    }
    let model = problem.simulator().model();
    let n_failed = outcomes.iter().filter(|o| o.is_err()).count();
    let first_failure = outcomes.iter().find_map(|o| o.as_ref().err().cloned());
    if n_failed == outcomes.len() {
        return Err(IdentifyError::AllPlanPointsFailed {
            points: plan.len(),
            first: first_failure.unwrap_or_default(),
        });
    }
    let t_plan = plan_seconds;

    // 2. Local search from the best few points; keep the best end.
    let t_local = Instant::now();
    let starts: Vec<(usize, f64)> = rank(&outcomes)
        .into_iter()
        .filter_map(|k| outcomes[k].as_ref().ok().map(|&cost| (k, cost)))
        .take(settings.starts)
        .collect();
    let mut ends = Vec::with_capacity(starts.len());
    let (mut sims, mut sims_sens, mut failed) = (plan.len(), 0, n_failed);
    let (searches, start_failures) = match settings.start {
        Start::Plan => run_starts(&starts, |k, idx, cost| {
            progress.search_started(k, starts.len(), cost);
            start_search(&problem, settings, plan.point(idx), progress)
        })?,
        Start::Values => {
            let values: Vec<f64> = problem
                .wrt()
                .iter()
                .map(|&i| model.parameters[i].value)
                .collect();
            let u0: Vec<f64> = problem
                .to_normalised(&values)
                .into_iter()
                .map(|u| u.clamp(0.0, 1.0))
                .collect();
            let search = start_search(&problem, settings, &u0, progress)
                .map_err(|e| IdentifyError::Solve(format!("from the parameters' values: {e}")))?;
            (vec![search], Vec::new())
        }
    };
    let (mut searches, mut start_failures) = (searches, start_failures);
    let used: Vec<usize> = starts.iter().map(|&(idx, _)| idx).collect();
    // When no end passes the fit checks and the sensors are weighted by
    // their noise, the weights are estimated at the best end first, and the
    // other ends searched again with them: with the first weights a sensor
    // of little signal (a campaign's low force level) is left underfitted
    // even at the right minimum, and its residuals fail the checks. Only
    // then do the restarts judge the ends.
    let reweight = settings.weighting == Weighting::EstimatedNoise
        && settings.start == Start::Plan
        && settings.restarts > 0
        && !searches.is_empty()
        && {
            sims += searches.len() * problem.n_experiments();
            !searches
                .iter()
                .any(|s| fit_passes(&problem, settings, &s.u))
        };
    if reweight {
        let k = (0..searches.len())
            .min_by(|&a, &b| searches[a].cost.total_cmp(&searches[b].cost))
            .unwrap_or(0);
        let mut counts = (0, 0, 0);
        let end = estimate_weights(
            &mut problem,
            settings,
            searches.remove(k),
            progress,
            &mut counts,
        )?;
        searches.insert(k, end);
        for j in (0..searches.len()).filter(|&j| j != k) {
            let s = local_search(&problem, settings, &searches[j].u, progress)?;
            counts.0 += s.residual_evals;
            counts.1 += s.jacobian_evals;
            counts.2 += s.failed;
            searches[j] = s;
        }
        sims += counts.0;
        sims_sens += counts.1;
        failed += counts.2;
    }
    let restarted = match settings.start {
        Start::Plan => restart_from_side_minima(
            &problem,
            settings,
            plan,
            &outcomes,
            &used,
            &mut searches,
            &mut start_failures,
            progress,
        ),
        Start::Values => Restarts::default(),
    };
    sims += restarted.checks;
    // A failed start cost one simulation with sensitivities, which failed.
    sims_sens += start_failures.len();
    failed += start_failures.len();
    let mut best: Option<Search> = None;
    for (k, s) in searches.into_iter().enumerate() {
        sims += s.residual_evals;
        sims_sens += s.jacobian_evals;
        failed += s.failed;
        if restarted.passed.as_ref().is_some_and(|p| !p[k]) {
            // A side minimum, left behind (and described in a warning).
            continue;
        }
        ends.push(StartEnd {
            cost: s.cost,
            parameters: problem.to_physical(&s.u),
        });
        if best.as_ref().is_none_or(|b| s.cost < b.cost) {
            best = Some(s);
        }
    }
    let Some(mut best) = best else {
        return Err(IdentifyError::AllStartsFailed(start_failures));
    };
    if settings.weighting == Weighting::EstimatedNoise {
        let mut counts = (0, 0, 0);
        best = estimate_weights(&mut problem, settings, best, progress, &mut counts)?;
        sims += counts.0;
        sims_sens += counts.1;
        failed += counts.2;
    }
    // The steps per sample were chosen before the search and held fixed (so
    // that J stays smooth); check them at the estimate, and if it needs
    // finer ones, continue the search with those.
    let mut step_warnings = Vec::new();
    for _ in 0..3 {
        let mut finer = false;
        for p in 0..problem.n_experiments() {
            match check_steps(&mut problem, p, &best.u) {
                Ok((c, changed)) => {
                    sims += c;
                    finer |= changed.is_none();
                    step_warnings.extend(changed.flatten());
                }
                Err(w) => step_warnings.push(w),
            }
        }
        if !finer {
            break;
        }
        let s = local_search(&problem, settings, &best.u, progress)?;
        sims += s.residual_evals;
        sims_sens += s.jacobian_evals;
        failed += s.failed;
        best = s;
    }
    step_warnings.dedup();
    for p in 0..problem.n_experiments() {
        let mut x = Vec::new();
        problem.experiment_params(p, &best.u, &mut x);
        step_warnings.extend(crate::simulation::aliasing::above_nyquist(
            problem.experiment_simulator(p),
            &x,
        ));
    }
    step_warnings.dedup();
    let t_local = t_local.elapsed().as_secs_f64();

    // 3. Cramér–Rao bounds (eq. 26–29) from the exact Jacobian at the estimate.
    let t_unc = Instant::now();
    let n_res = problem.n_residuals();
    let mut ws = problem.workspace();
    let mut res = vec![0.0; n_res];
    let mut jac = DMatrix::zeros(n_res, r);
    sims_sens += 1;
    let mut s2 = None;
    let (uncertainty, unc_error) = match problem
        .residuals_jacobian(&mut ws, &best.u, &mut res, &mut jac)
    {
        Err(e) => (
            None,
            Some(format!("the simulation at the estimate failed: {e}")),
        ),
        Ok(()) => {
            let ssr = sum_of_squares(&res);
            s2 = Some(ssr / (n_res - r - 1) as f64);
            let dx_du = problem.dx_du(&best.u);
            match cramer_rao_mapped(&jac, ssr, &dx_du, problem.widths(), &settings.uncertainty) {
                Ok(c) => (Some(c), None),
                Err(e) => (None, Some(e.to_string())),
            }
        }
    };
    let t_unc = t_unc.elapsed().as_secs_f64();

    let wrt = problem.wrt();
    let names: Vec<&str> = problem.columns().iter().map(|c| c.name.as_str()).collect();
    let x = problem.to_physical(&best.u);
    let parameters = wrt
        .iter()
        .enumerate()
        .map(|(j, &i)| {
            let p = &model.parameters[i];
            let (min, max) = p.bounds.expect("identified");
            ParameterEstimate {
                name: names[j].to_string(),
                unit: p.unit.symbol.clone(),
                unit_scale: p.unit.scale,
                estimate: x[j],
                std_error: uncertainty.as_ref().map(|c| c.std_errors[j]),
                min,
                max,
                scale: p.scale,
                nominal: p.value,
            }
        })
        .collect();
    let mut warnings: Vec<String> = uncertainty
        .as_ref()
        .map(|c| c.warnings.iter().map(|w| describe(w, &names)).collect())
        .unwrap_or_default();
    warnings.extend(restarted.warning);
    warnings.extend(step_warnings);
    let fitted = problem.simulate_all(&best.u);
    let ssr = match &fitted {
        Ok(g) => problem.sensor_ssr(g).iter().sum(),
        Err(_) => f64::NAN,
    };
    let n_obs = n_res;
    let signals = fit_signals(&problem, fitted.as_deref().ok());
    let sensors: Vec<String> = signals.iter().map(|s| s.sensor.clone()).collect();
    let parameter_names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    let verdict = assess(
        &Evidence {
            parameters: &parameter_names,
            u: &best.u,
            ends: &ends,
            observations: n_obs,
            stop: best.stop,
            iterations: best.iterations,
            termination: best.stop.to_string(),
            signals: match &fitted {
                Ok(_) => Ok(signals.clone()),
                Err(e) => Err(e.to_string()),
            },
            identifiability: match (&uncertainty, &unc_error) {
                (Some(c), _) => Ok(&c.warnings),
                (None, e) => Err(e.clone().unwrap_or_default()),
            },
            correlation_threshold: settings.uncertainty.correlation_threshold(),
        },
        &settings.verdict,
    );
    let experiments = experiment_summaries(&problem, &verdict);
    Ok(IdentificationResult {
        parameters,
        criterion: best.cost,
        ssr,
        s2,
        observations: n_obs,
        correlation: uncertainty.as_ref().map(|c| {
            c.correlation
                .row_iter()
                .map(|row| row.iter().copied().collect())
                .collect()
        }),
        condition_number: uncertainty.as_ref().map(|c| c.condition_number),
        warnings,
        uncertainty_error: unc_error,
        method: match settings.method {
            Method::Lm => "lm".into(),
            Method::Bfgs => "bfgs".into(),
        },
        termination: format!("{:?}", best.stop),
        termination_message: best.stop.to_string(),
        iterations: best.iterations,
        simulations: sims + 1,
        simulations_with_sensitivities: sims_sens,
        failed_simulations: failed,
        weights: problem.weights(),
        sensors,
        from: model.sampling.time(problem.first_sample()),
        plan: PlanSummary {
            points: plan.len(),
            failed: n_failed,
            costs: outcomes.iter().map(|o| o.as_ref().ok().copied()).collect(),
            starts: starts.iter().map(|s| s.0).collect(),
            first_failure,
        },
        failed_starts: start_failures,
        history: best
            .history
            .iter()
            .map(|(it, cost, u)| Iterate {
                iteration: *it,
                cost: *cost,
                parameters: problem.to_physical(u),
            })
            .collect(),
        timings: Timings {
            plan: t_plan,
            local_search: t_local,
            uncertainty: t_unc,
            total: plan_seconds + t_finish.elapsed().as_secs_f64(),
        },
        threads: rayon::current_num_threads(),
        source: Default::default(),
        verdict: Some(verdict),
        simulation: Some(problem.simulator().steps()),
        experiments,
    })
}

/// Checks experiment p's steps per sample at u and holds the checked ones:
/// the simulations it took, and `Some(warning)` if the steps stay as they
/// were (the warning if their error exceeds the tolerance) or `None` if
/// they became finer, so the search must go on.
fn check_steps(
    problem: &mut OutputError<'_>,
    p: usize,
    u: &[f64],
) -> Result<(usize, Option<Option<String>>), String> {
    let mut x = Vec::new();
    problem.experiment_params(p, u, &mut x);
    let model = problem.experiment_simulator(p).model();
    let held = problem.experiment_simulator(p).steps();
    let checked = match held.automatic {
        true => choose_steps(model, &x, held.tolerance, held.substeps),
        false => estimate_error(model, &x, held.substeps).map(|e| StepChoice {
            estimated_error: Some(e),
            runs: 2,
            ..held
        }),
    };
    let c = checked.map_err(|e| {
        format!("the simulation's accuracy at the estimate could not be checked: {e}")
    })?;
    problem.set_experiment_steps(
        p,
        StepChoice {
            runs: held.runs + c.runs,
            ..c
        },
    );
    if c.substeps != held.substeps {
        return Ok((c.runs, None));
    }
    let warning = c.estimated_error.filter(|e| *e > c.tolerance).map(|e| {
        format!(
            "the fixed {} step(s) per sample give an estimated relative error of {e:.2e} \
             at the estimate, more than the tolerance {:.1e}; leave `substeps` unset to \
             have them chosen",
            c.substeps, c.tolerance
        )
    });
    Ok((c.runs, Some(warning)))
}

/// Every sensor of every experiment, named `sensor[experiment]` in a
/// campaign, with its measured and fitted signals from the first sample used.
fn fit_signals<'a>(
    problem: &'a OutputError<'_>,
    fitted: Option<&'a [crate::simulation::Response]>,
) -> Vec<FitSignal<'a>> {
    let mut out = Vec::new();
    for p in 0..problem.n_experiments() {
        let model = problem.experiment_simulator(p).model();
        let y = problem.experiment_measured(p);
        let first = problem.experiment_first(p);
        for (c, s) in model.sensors.iter().enumerate() {
            out.push(FitSignal {
                sensor: signal_name(&s.name, problem.experiment_name(p)),
                measured: &y.sensor(c)[first..],
                fitted: fitted.map_or(&[][..], |g| &g[p].sensor(c)[first..]),
            });
        }
    }
    out
}

/// `sensor`, or `sensor[experiment]` in a campaign.
pub fn signal_name(sensor: &str, experiment: &str) -> String {
    match experiment {
        "" => sensor.to_string(),
        e => format!("{sensor}[{e}]"),
    }
}

/// The experiments of a campaign as RESULT.json lists them (none for a
/// single data file).
fn experiment_summaries(
    problem: &OutputError<'_>,
    verdict: &super::verdict::Verdict,
) -> Vec<ExperimentSummary> {
    if problem.n_experiments() == 1 && problem.experiment_name(0).is_empty() {
        return Vec::new();
    }
    let mut fits = verdict.sensors.iter().map(|c| c.fit_percent);
    (0..problem.n_experiments())
        .map(|p| {
            let sim = problem.experiment_simulator(p);
            let m = sim.model();
            ExperimentSummary {
                name: problem.experiment_name(p).to_string(),
                role: crate::model::Role::Fit,
                data: None,
                samples: problem.experiment_measured(p).n_samples,
                sample_rate: m.sampling.sample_rate,
                from: m.sampling.time(problem.experiment_first(p)),
                weight: problem.experiment_weight(p),
                sensors: m.sensors.iter().map(|s| s.name.clone()).collect(),
                fits: fits.by_ref().take(m.sensors.len()).collect(),
            }
        })
        .collect()
}

/// An identifiability warning in words, with parameter names.
fn describe(w: &IdentifiabilityWarning, names: &[&str]) -> String {
    match w {
        IdentifiabilityWarning::StdErrorExceedsBox { index, std_error, box_width } => format!(
            "{}: the standard error ({std_error:.3e}) exceeds the width of its box ({box_width:.3e}); the data hardly constrain it",
            names[*index]
        ),
        IdentifiabilityWarning::StrongCorrelation { first, second, correlation } => format!(
            "{} and {} are correlated ({correlation:+.4}); the data determine mostly a combination of them",
            names[*first], names[*second]
        ),
        IdentifiabilityWarning::IllConditioned { condition_number } => {
            format!("the scaled Fisher matrix is ill-conditioned (condition number {condition_number:.3e})")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression: one start whose first evaluation failed ended the whole
    /// identification, and the other starts were never tried.
    #[test]
    fn a_failed_start_does_not_end_the_identification() {
        let starts = [(4, 1.0), (7, 2.0), (2, 3.0)];
        let mut tried = Vec::new();
        let (done, failures) = run_starts(&starts, |k, idx, _| {
            tried.push(k);
            if idx == 4 {
                Err(IdentifyError::Solve("not finite".into()))
            } else {
                Ok(idx)
            }
        })
        .unwrap();
        assert_eq!(tried, [0, 1, 2]);
        assert_eq!(done, [7, 2]);
        assert_eq!(
            failures,
            [StartFailure {
                plan_index: 4,
                reason: "not finite".into()
            }]
        );
    }

    /// Only when every start fails does the identification fail, naming each
    /// start's reason.
    #[test]
    fn all_starts_failed_names_every_reason() {
        let starts = [(4, 1.0), (7, 2.0)];
        let e = run_starts(&starts, |_, idx, _| -> Result<(), _> {
            Err(IdentifyError::Solve(format!("reason {idx}")))
        })
        .unwrap_err();
        let IdentifyError::AllStartsFailed(f) = &e else {
            panic!("{e:?}")
        };
        assert_eq!(f.len(), 2);
        let msg = e.to_string();
        assert!(
            msg.contains("plan point 5: reason 4") && msg.contains("plan point 8: reason 7"),
            "{msg}"
        );
    }
}
