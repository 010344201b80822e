//! Stage 9, the result: the stages' values assembled into what RESULT.json
//! records.
use super::bounds::Bounds;
use super::judge::fit_signals;
use super::plan_run::PlanRun;
use super::settings::{Settings, Weighting};
use crate::identification::noise::{SensorNoise, StdErrorScope};
use crate::identification::output_error::OutputError;
use crate::identification::problem::LeastSquares;
use crate::identification::profile::ParameterProfile;
use crate::identification::result::{
    ExperimentSummary, IdentificationResult, Iterate, ParameterEstimate, StartFailure, Timings,
};
use crate::identification::search::SearchOutcome;
use crate::identification::tally::Tally;
use crate::identification::uncertainty::CramerRao;
use crate::identification::verdict::{identifiability_reason, Reason, Verdict};
use crate::identification::warning::Warning;
use crate::model::Role;
use crate::simulation::{Response, SimulationError};

/// Everything the stages found, for [`assemble`].
pub(super) struct Found<'a> {
    /// The plan.
    pub plan: &'a PlanRun<'a, 'a>,
    /// The search that gave the estimate.
    pub best: SearchOutcome,
    /// The bounds at the estimate.
    pub bounds: Bounds,
    /// The fit at the estimate.
    pub fitted: Result<Vec<Response>, SimulationError>,
    /// The verdict.
    pub verdict: Verdict,
    /// The warnings of the restarts, the steps and the searches.
    pub warnings: Vec<Warning>,
    /// Starts whose search could not run.
    pub failed_starts: Vec<StartFailure>,
    /// Every simulation of the run.
    pub tally: Tally,
    /// Wall times.
    pub timings: Timings,
    /// The profile likelihoods asked for.
    pub profiles: Vec<ParameterProfile>,
}

/// The result of the run.
pub(super) fn assemble(
    problem: &OutputError<'_>,
    settings: &Settings,
    f: Found<'_>,
) -> IdentificationResult {
    let model = problem.model();
    let bounds = f.bounds.cramer_rao.as_ref();
    let cramer_rao = bounds.ok();
    let x = problem.to_physical(&f.best.u);
    let names: Vec<String> = problem.columns().iter().map(|c| c.name.clone()).collect();
    let parameters = estimates(problem, &x, cramer_rao);
    let mut warnings: Vec<Warning> = cramer_rao
        .map(|c| {
            c.warnings
                .iter()
                .map(|w| Warning::Identifiability(identifiability_reason(w, &names)))
                .collect()
        })
        .unwrap_or_default();
    warnings.extend(f.warnings);
    let ssr = match &f.fitted {
        Ok(g) => problem.sensor_ssr(g).iter().sum(),
        Err(_) => f64::NAN,
    };
    IdentificationResult {
        parameters,
        criterion: f.best.cost,
        ssr,
        s2: f.bounds.s2,
        observations: problem.n_residuals(),
        correlation: cramer_rao.map(|c| {
            c.correlation
                .row_iter()
                .map(|row| row.iter().copied().collect())
                .collect()
        }),
        condition_number: cramer_rao.map(|c| c.condition_number),
        warnings,
        uncertainty_error: bounds.err().map(|e| e.describe(&names)),
        method: settings.method,
        termination: f.best.stop,
        termination_message: f.best.stop.to_string(),
        iterations: f.best.iterations,
        simulations: f.tally.simulations,
        simulations_with_sensitivities: f.tally.with_sensitivities,
        failed_simulations: f.tally.failed,
        weights: problem.weights(),
        sensors: fit_signals(problem, None)
            .into_iter()
            .map(|s| s.sensor)
            .collect(),
        // A campaign's first experiment's; every experiment's are in
        // `experiments`.
        from: model.sampling.time(problem.experiment_first(0)),
        plan: f.plan.summary(),
        failed_starts: f.failed_starts,
        history: f
            .best
            .history
            .iter()
            .map(|h| Iterate {
                iteration: h.iteration,
                cost: h.cost,
                parameters: problem.to_physical(&h.u),
            })
            .collect(),
        timings: f.timings,
        threads: rayon::current_num_threads(),
        source: Default::default(),
        experiments: experiment_summaries(problem, &f.verdict),
        noise: match (&f.fitted, settings.weighting) {
            (Ok(g), Weighting::EstimatedNoise) => noise_models(problem, g),
            _ => Vec::new(),
        },
        std_errors_cover: std_error_scope(&f.verdict),
        verdict: Some(f.verdict),
        simulation: Some(problem.experiment_simulator(0).steps()),
        profiles: f.profiles,
    }
}

/// What the standard errors cover: the noise only under model error.
fn std_error_scope(verdict: &Verdict) -> StdErrorScope {
    match verdict
        .reasons
        .iter()
        .any(|r| matches!(r, Reason::ModelError { .. }))
    {
        true => StdErrorScope::NoiseOnly,
        false => StdErrorScope::Noise,
    }
}

/// Each sensor's noise model at the fit `g`.
fn noise_models(problem: &OutputError<'_>, g: &[Response]) -> Vec<SensorNoise> {
    let names = fit_signals(problem, None).into_iter().map(|s| s.sensor);
    problem
        .sensor_residuals(g)
        .iter()
        .zip(problem.whitening_filters())
        .zip(names)
        .map(|((e, filter), name)| SensorNoise::of(name, e, filter))
        .collect()
}

/// Every identified parameter's estimate, with its standard error.
fn estimates(
    problem: &OutputError<'_>,
    x: &[f64],
    cramer_rao: Option<&CramerRao>,
) -> Vec<ParameterEstimate> {
    let model = problem.model();
    problem
        .columns()
        .iter()
        .enumerate()
        .map(|(j, col)| {
            let p = &model.parameters[col.parameter];
            let (min, max) = p.bounds.expect("identified");
            ParameterEstimate {
                name: col.name.clone(),
                unit: p.unit.symbol.clone(),
                unit_scale: p.unit.scale,
                estimate: x[j],
                std_error: cramer_rao.map(|c| c.std_errors[j]),
                min,
                max,
                scale: p.scale,
                nominal: p.value,
            }
        })
        .collect()
}

/// The experiments of a campaign as RESULT.json lists them, each with its
/// own first sample and steps per sample (none for a single data file).
fn experiment_summaries(problem: &OutputError<'_>, verdict: &Verdict) -> Vec<ExperimentSummary> {
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
                role: Role::Fit,
                data: None,
                samples: problem.experiment_measured(p).n_samples,
                sample_rate: m.sampling.sample_rate,
                from: m.sampling.time(problem.experiment_first(p)),
                weight: problem.experiment_weight(p),
                sensors: m.sensors.iter().map(|s| s.name.clone()).collect(),
                fits: fits.by_ref().take(m.sensors.len()).collect(),
                steps: Some(sim.steps()),
            }
        })
        .collect()
}
