//! `rfeid identify` on a campaign (SPEC §5): every `[[experiment]]` of the
//! model file fitted together, and the validation experiments' fits.
use crate::cli::IdentifyArgs;
use crate::diagnostics::Failure;
use crate::outputs::{Checked, Plan};
use crate::run::closing::{close, Closing};
use crate::run::digest::input_digests;
use crate::run::estimate::simulate_at_estimate;
use crate::run::experiments::{campaign_data, check_exists};
use crate::run::failures::{identify_failure, simulation_failure};
use crate::run::limits::start_threads;
use crate::run::report::render_campaign;
use crate::run::search::search_settings;
use crate::run::show::{json_conflict, search_steps_note};
use crate::ui::Ui;
use rfeid::identification::output_error::{ExperimentData, OutputError};
use rfeid::identification::pipeline::identify;
use rfeid::identification::result::{ExperimentSummary, IdentificationResult};
use rfeid::measurement::{constant_sensors, fit_percent};
use rfeid::model::{Experiment, Model, Role};
use rfeid::simulation::{Response, Simulator};
use std::path::PathBuf;

/// Runs `identify` on the model's experiments.
pub fn run(args: &IdentifyArgs, model: &Model, ui: &Ui) -> Result<(), Failure> {
    if let Some(data) = &args.data {
        return Err(Failure::input_msg(format!(
            "--data {}: {} lists [[experiment]] entries, which name their own data files; drop --data (or fit one file with a model without experiments)",
            data.display(),
            args.model.display()
        )));
    }
    if args.shard.is_some() {
        return Err(Failure::input_msg(
            "--shard with a campaign ([[experiment]] entries): not supported; run the campaign in one process",
        ));
    }
    let outputs = check_outputs(args, model)?;
    json_conflict(ui, &outputs)?;
    let (models, measured) = campaign_data(model, &args.model, ui)?;
    let result = fit(args, model, &models, &measured, ui)?;
    let report = match &args.report {
        Some(dir) => {
            let title = format!("campaign {}", args.model.display());
            let files = render_campaign(model, &models, &result, &measured, &title)?;
            Some((dir.as_path(), files))
        }
        None => None,
    };
    let closing = Closing::of_result(model, &result, report, &args.output, args.search.timings);
    close(&outputs, closing, ui)
}

/// The campaign's inputs (every experiment's data) and outputs, checked.
fn check_outputs(args: &IdentifyArgs, model: &Model) -> Result<Checked, Failure> {
    let mut plan = Plan::new();
    plan.input(&args.model).file("-o", &args.output);
    for f in &model.files {
        plan.input(f);
    }
    for e in &model.experiments {
        check_exists(&args.model, e)?;
        plan.input(&e.data);
    }
    if let Some(dir) = &args.report {
        plan.report("--report", dir);
    }
    plan.check()
}

/// The identification of the fitted experiments, with every experiment
/// (validation ones too) listed in the result.
fn fit(
    args: &IdentifyArgs,
    model: &Model,
    models: &[Model],
    measured: &[Response],
    ui: &Ui,
) -> Result<IdentificationResult, Failure> {
    start_threads(args.search.threads)?;
    let (settings, progress) = search_settings(&args.search, args.start, ui)?;
    let parts = model
        .fitted_experiments()
        .into_iter()
        .map(|e| fitted_part(args, &model.experiments[e], &models[e], &measured[e], ui))
        .collect::<Result<Vec<_>, _>>()?;
    let problem = OutputError::campaign(parts);
    let mut result = identify(problem, &settings, &progress).map_err(identify_failure)?;
    progress.finish();
    result.source.set = args.set.clone();
    result.source.model = Some(args.model.display().to_string());
    let data: Vec<PathBuf> = model.experiments.iter().map(|x| x.data.clone()).collect();
    result.source.digests = Some(input_digests(&args.model, model, &data)?);
    let fitted = std::mem::take(&mut result.experiments);
    let mut fitted = fitted.into_iter();
    for (e, x) in model.experiments.iter().enumerate() {
        let summary = match x.role {
            Role::Fit => fitted.next().map(|mut s| {
                s.data = Some(x.data.display().to_string());
                s
            }),
            Role::Validation => Some(validation(&result, x, &models[e], &measured[e])?),
        };
        result.experiments.extend(summary);
    }
    Ok(result)
}

/// One fitted experiment `x` with its model `m` and data: its fitted part of
/// the record, its simulator and its weight.
fn fitted_part<'m>(
    args: &IdentifyArgs,
    x: &Experiment,
    m: &'m Model,
    measured: &Response,
    ui: &Ui,
) -> Result<ExperimentData<'m>, Failure> {
    let from = if x.from > 0.0 {
        x.from
    } else {
        args.search.from
    };
    let first = m.sampling.first_sample(from);
    if first + 2 > m.sampling.n_samples() {
        return Err(Failure::input_msg(format!(
            "{}: experiment \"{}\", field 'from': leaves {} of the record's {} samples to fit",
            args.model.display(),
            x.name,
            m.sampling.n_samples().saturating_sub(first),
            m.sampling.n_samples()
        )));
    }
    let constant = constant_sensors(measured, first);
    if !constant.is_empty() {
        let names: Vec<&str> = constant
            .iter()
            .map(|&c| m.sensors[c].name.as_str())
            .collect();
        ui.note(format!(
            "warning: experiment \"{}\": these measured signals are constant and carry no information: {}",
            x.name,
            names.join(", ")
        ));
    }
    let sim = Simulator::choose(m, &m.nominal()).map_err(|err| {
        simulation_failure(
            &format!(
                "experiment \"{}\": choosing the integrator's steps at the nominal values",
                x.name
            ),
            err,
        )
    })?;
    ui.note(format!(
        "experiment \"{}\": {}",
        x.name,
        search_steps_note(&sim.steps())
    ));
    Ok(ExperimentData {
        name: x.name.clone(),
        sim,
        measured: measured.clone(),
        first,
        weight: x.weight,
    })
}

/// A validation experiment simulated at the estimate, with its fit per
/// sensor.
fn validation(
    result: &IdentificationResult,
    x: &Experiment,
    m: &Model,
    measured: &Response,
) -> Result<ExperimentSummary, Failure> {
    let (fitted, steps) = simulate_at_estimate(result, m, &x.name)?;
    let first = m.sampling.first_sample(x.from);
    Ok(ExperimentSummary {
        name: x.name.clone(),
        role: Role::Validation,
        data: Some(x.data.display().to_string()),
        samples: measured.n_samples,
        sample_rate: m.sampling.sample_rate,
        from: m.sampling.time(first),
        weight: x.weight,
        sensors: m.sensors.iter().map(|s| s.name.clone()).collect(),
        fits: (0..m.sensors.len())
            .map(|c| fit_percent(&measured.sensor(c)[first..], &fitted.sensor(c)[first..]))
            .collect(),
        steps: Some(steps),
    })
}
