//! The search set up from the command line: the library's
//! [`SearchOptions`] from the arguments, the run prepared by the library
//! ([`options::prepare`]), its notes shown, and the search run.
use super::failures::{failure, identify_failure};
use super::limits::start_threads;
use super::progress::Bars;
use super::show::search_steps_note;
use crate::cli::{MethodArg, NoiseModelArg, ProfileArgs, SearchArgs, StartArg, WeightsArg};
use crate::diagnostics::Failure;
use crate::ui::Ui;
use rfeid::identification::cancel::Cancel;
use rfeid::identification::options::{self, PrepareError, SearchOptions};
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{
    identify, Method, NoiseModel, ProfileRequest, Settings, Start, Weighting,
};
use rfeid::identification::profile::DEFAULT_POINTS;
use rfeid::identification::result::IdentificationResult;
use rfeid::model::Model;
use rfeid::simulation::Response;

/// The library's start of the local search for `--start`.
pub fn start_of(start: StartArg) -> Start {
    match start {
        StartArg::Plan => Start::Plan,
        StartArg::Values => Start::Values,
    }
}

/// The library's options of a search from the command line's.
pub fn options(a: &SearchArgs, start: StartArg) -> SearchOptions {
    SearchOptions {
        plan: a.plan,
        starts: a.starts,
        method: match a.method {
            MethodArg::Lm => Method::Lm,
            MethodArg::Bfgs => Method::Bfgs,
        },
        weights: a.weights.map(|w| match w {
            WeightsArg::Equal => Weighting::Equal,
            WeightsArg::Estimated => Weighting::EstimatedNoise,
        }),
        noise_model: match a.noise_model {
            NoiseModelArg::Ar => NoiseModel::default(),
            NoiseModelArg::White => NoiseModel::White,
        },
        threads: a.threads,
        from: a.from,
        window: a.window,
        start: start_of(start),
        jacobian_memory: a.jacobian_memory,
        profiles: profile_request(&a.profile),
    }
}

/// The library's profile request of `--profiles` and `--profile-points`.
pub fn profile_request(a: &ProfileArgs) -> Option<ProfileRequest> {
    let names = a.profiles.as_ref()?;
    Some(ProfileRequest {
        parameters: names
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(String::from)
            .collect(),
        points: a.profile_points.unwrap_or(DEFAULT_POINTS),
    })
}

/// Checks the search settings and runs the pipeline.
pub fn run_search(
    model: &Model,
    measured: Response,
    a: &SearchArgs,
    ui: &Ui,
) -> Result<IdentificationResult, Failure> {
    run_search_from(model, measured, a, StartArg::Plan, ui)
}

/// [`run_search`] with the local search starting at `start`.
pub fn run_search_from(
    model: &Model,
    measured: Response,
    a: &SearchArgs,
    start: StartArg,
    ui: &Ui,
) -> Result<IdentificationResult, Failure> {
    let (problem, settings, progress) = prepare_from(model, measured, a, start, ui)?;
    let result = identify(problem, &settings, &progress).map_err(identify_failure)?;
    progress.finish();
    Ok(result)
}

/// Checks the search settings and builds the problem, the pipeline's
/// settings and the progress display, for a search from the plan.
pub fn prepare<'m>(
    model: &'m Model,
    measured: Response,
    a: &SearchArgs,
    ui: &Ui,
) -> Result<(OutputError<'m>, Settings, Bars), Failure> {
    prepare_from(model, measured, a, StartArg::Plan, ui)
}

/// [`prepare`] for a search that starts at `start`.
fn prepare_from<'m>(
    model: &'m Model,
    measured: Response,
    a: &SearchArgs,
    start: StartArg,
    ui: &Ui,
) -> Result<(OutputError<'m>, Settings, Bars), Failure> {
    prepare_options(model, measured, &options(a, start), ui)
}

/// The library's [`options::prepare`] of the options `o` (which checks
/// them), with the worker threads started and the notes shown.
pub fn prepare_options<'m>(
    model: &'m Model,
    measured: Response,
    o: &SearchOptions,
    ui: &Ui,
) -> Result<(OutputError<'m>, Settings, Bars), Failure> {
    start_threads(o.threads)?;
    let p = options::prepare(model, measured, o, &Cancel::new()).map_err(prepare_failure)?;
    if let Some(w) = p.constant_warning() {
        ui.note(format!("warning: {w}"));
    }
    ui.note(search_steps_note(
        &p.problem.experiment_simulator(0).steps(),
    ));
    Ok((p.problem, p.settings, Bars::new(o.plan, ui)))
}

/// A run that could not be set up as a failure ([`failure`]): a problem of
/// the options, the model or the data is bad input (2); steps that cannot
/// be chosen are a failed computation unless the values are the model's
/// fault.
fn prepare_failure(e: PrepareError) -> Failure {
    failure(e)
}
