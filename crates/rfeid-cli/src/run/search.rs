//! The search set up from the command line: the library's [`Settings`],
//! the fitted part of the record, the problem, and the search run.
use super::failures::{identify_failure, simulation_failure};
use super::limits::{check_limits, start_threads};
use super::progress::Bars;
use super::show::steps_note;
use crate::cli::{MethodArg, NoiseModelArg, SearchArgs, StartArg, WeightsArg};
use crate::diagnostics::Failure;
use crate::ui::Ui;
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{
    identify, IdentifyError, Method, NoiseModel, Settings, Start, Weighting,
};
use rfeid::identification::result::IdentificationResult;
use rfeid::measurement::constant_sensors;
use rfeid::model::Model;
use rfeid::simulation::{Response, Simulator};

/// `--weights` of `identify` when not given: each sensor weighted by its
/// noise level, estimated from its residuals. With equal weights and sensors
/// whose noise differs, eq. 26's single s² misstates the standard errors
/// (measured on the wide-box cases of `examples/wide_boxes.rs`: 6 of 30
/// cases had an estimate 3.2–3.4 standard errors from the truth at the
/// truth's own minimum; estimated weights: 30 of 30 within 3).
pub const DEFAULT_WEIGHTS: WeightsArg = WeightsArg::Estimated;

/// `--window` of `identify` when not given: each local search first fits
/// the first 15 % of the record. Measured on wide boxes (README, "The
/// verdict"): the 3-body lathe found the truth in 11 of 12 cases with it, 6
/// of 12 without; the knee–column in 12 of 12 either way, 0.4 s slower.
pub const DEFAULT_WINDOW: f64 = 0.15;

/// The library's start of the local search for `--start`.
pub fn start_of(start: StartArg) -> Start {
    match start {
        StartArg::Plan => Start::Plan,
        StartArg::Values => Start::Values,
    }
}

/// Checks the search settings and runs the pipeline.
pub fn run_search(
    model: &Model,
    measured: Response,
    a: &SearchArgs,
    ui: &Ui,
) -> Result<IdentificationResult, Failure> {
    run_search_from(model, measured, a, Start::Plan, ui)
}

/// [`run_search`] with the local search starting at `start`.
pub fn run_search_from(
    model: &Model,
    measured: Response,
    a: &SearchArgs,
    start: Start,
    ui: &Ui,
) -> Result<IdentificationResult, Failure> {
    let (problem, mut settings, progress) = prepare(model, measured, a, ui)?;
    settings.start = start;
    let result = identify(problem, &settings, &progress).map_err(identify_failure)?;
    progress.bar.finish_and_clear();
    Ok(result)
}

/// Checks the search settings and builds the problem, the pipeline's
/// settings and the progress display.
pub fn prepare<'m>(
    model: &'m Model,
    measured: Response,
    a: &SearchArgs,
    ui: &Ui,
) -> Result<(OutputError<'m>, Settings, Bars), Failure> {
    check_limits(a)?;
    start_threads(a.threads)?;
    let first = first_sample(model, a.from)?;
    if model.identified().is_empty() {
        return Err(Failure::input_msg(IdentifyError::NoParameters));
    }
    check_constant(model, &measured, first, a.from, ui)?;
    let (settings, progress) = search_settings(a, ui)?;
    let sim = Simulator::choose(model, &model.nominal()).map_err(|e| {
        simulation_failure(
            "choosing the integrator's steps at the nominal parameter values",
            e,
        )
    })?;
    ui.note(steps_note(&sim.steps()));
    let problem = OutputError::new(sim, measured, first);
    Ok((problem, settings, progress))
}

/// The first sample fitted for `--from` (s), which must leave at least two.
fn first_sample(model: &Model, from: f64) -> Result<usize, Failure> {
    let s = model.sampling;
    if !(from >= 0.0 && from < s.duration) {
        return Err(Failure::input_msg(format!(
            "--from {from}: must lie in [0, {}) s",
            s.duration
        )));
    }
    let first = s.first_sample(from);
    if first + 2 > s.n_samples() {
        return Err(Failure::input_msg(format!(
            "--from {from}: leaves {} of the record's {} samples to fit",
            s.n_samples().saturating_sub(first),
            s.n_samples()
        )));
    }
    Ok(first)
}

/// Refuses data whose every signal is constant from `first` on, and warns
/// about the constant ones otherwise.
fn check_constant(
    model: &Model,
    measured: &Response,
    first: usize,
    from: f64,
    ui: &Ui,
) -> Result<(), Failure> {
    let constant = constant_sensors(measured, first);
    let names: Vec<&str> = constant
        .iter()
        .map(|&c| model.sensors[c].name.as_str())
        .collect();
    if constant.len() == measured.n_sensors {
        return Err(Failure::input_msg(format!(
            "every measured signal is constant from t = {from} s on ({}): constant data carry no \
             information about the parameters",
            names.join(", ")
        )));
    }
    if !constant.is_empty() {
        ui.note(format!(
            "warning: these measured signals are constant and carry no information: {}",
            names.join(", ")
        ));
    }
    Ok(())
}

/// The pipeline's settings from the command line, and the progress display.
pub fn search_settings(a: &SearchArgs, ui: &Ui) -> Result<(Settings, Bars), Failure> {
    let window = a.window.unwrap_or(DEFAULT_WINDOW);
    if !(0.0..1.0).contains(&window) {
        return Err(Failure::input_msg(format!(
            "--window {window}: must lie in [0, 1) (0: off)"
        )));
    }
    let settings = Settings {
        plan_points: a.plan,
        starts: a.starts,
        method: match a.method {
            MethodArg::Lm => Method::Lm,
            MethodArg::Bfgs => Method::Bfgs,
        },
        weighting: match a.weights.unwrap_or(DEFAULT_WEIGHTS) {
            WeightsArg::Equal => Weighting::Equal,
            WeightsArg::Estimated => Weighting::EstimatedNoise,
        },
        noise_model: match a.noise_model {
            NoiseModelArg::Ar => NoiseModel::default(),
            NoiseModelArg::White => NoiseModel::White,
        },
        window: Some(window).filter(|w| *w > 0.0),
        restarts: rfeid::identification::pipeline::DEFAULT_RESTARTS,
        ..Settings::default()
    };
    Ok((settings, Bars::new(a, ui)))
}
