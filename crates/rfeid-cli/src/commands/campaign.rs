//! `rfeid identify` on a campaign (SPEC §5): every `[[experiment]]` of the
//! model file fitted together, and the validation experiments' fits.
use super::common::{report_note, simulation_failure, steps_note};
use super::identify::{
    identify_failure, json_conflict, result_json, search_settings, show_result, start_threads,
    suspect_status,
};
use crate::cli::IdentifyArgs;
use crate::diagnostics::Failure;
use crate::outputs::Plan;
use crate::ui::Ui;
use rfeid::identification::output_error::{ExperimentData, OutputError};
use rfeid::identification::pipeline::{identify, Start};
use rfeid::identification::result::{EstimateError, ExperimentSummary, IdentificationResult};
use rfeid::io::data_file::read_measurement;
use rfeid::measurement::{constant_sensors, fit_percent, match_data};
use rfeid::model::{Model, Role};
use rfeid::simulation::{Response, Simulator};
use std::path::Path;

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
    let mut plan = Plan::new();
    plan.input(&args.model).file("-o", &args.output);
    for f in &model.files {
        plan.input(f);
    }
    for e in &model.experiments {
        check_exists(model, &args.model, e)?;
        plan.input(&e.data);
    }
    if let Some(dir) = &args.report {
        plan.report("--report", dir);
    }
    let outputs = plan.check()?;
    json_conflict(ui, &outputs)?;
    let (models, measured) = campaign_data(model, &args.model, ui)?;
    let result = fit(args, model, &models, &measured, ui)?;
    let mut batch = outputs.batch();
    if args.report.is_some() {
        let title = format!("campaign {}", args.model.display());
        let files = super::report::render_campaign(model, &models, &result, &measured, &title)?;
        batch.report("--report", &files)?;
    }
    batch.file("-o", result_json(&result)?)?;
    batch.commit()?;
    report_note(args.report.as_deref(), ui);
    let taken = outputs.uses_stdout();
    show_result(model, &result, "nominal", args.search.timings, taken, ui)?;
    if !taken {
        ui.note(format!("result written to {}", args.output.display()));
    }
    suspect_status(&result, &args.output.display().to_string())
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
    let (mut settings, progress) = search_settings(&args.search, ui)?;
    settings.start = match args.start {
        crate::cli::StartArg::Plan => Start::Plan,
        crate::cli::StartArg::Values => Start::Values,
    };
    let mut parts = Vec::new();
    for e in model.fitted_experiments() {
        let x = &model.experiments[e];
        let m = &models[e];
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
        let constant = constant_sensors(&measured[e], first);
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
            steps_note(&sim.steps())
        ));
        parts.push(ExperimentData {
            name: x.name.clone(),
            sim,
            measured: measured[e].clone(),
            first,
            weight: x.weight,
        });
    }
    let problem = OutputError::campaign(parts);
    let mut result = identify(problem, &settings, &progress).map_err(identify_failure)?;
    progress.bar.finish_and_clear();
    result.source.set = args.set.clone();
    result.source.model = Some(args.model.display().to_string());
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

/// A validation experiment simulated at the estimate, with its fit per
/// sensor.
fn validation(
    result: &IdentificationResult,
    x: &rfeid::model::Experiment,
    m: &Model,
    measured: &Response,
) -> Result<ExperimentSummary, Failure> {
    let (fitted, steps) = result
        .simulate_at_estimate(m, &x.name)
        .map_err(estimate_failure)?;
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

/// `m` simulated at the result's estimate, as experiment `experiment` sees
/// it, with steps chosen there.
pub fn simulate_at_estimate(
    result: &IdentificationResult,
    m: &Model,
    experiment: &str,
) -> Result<Response, Failure> {
    Ok(result
        .simulate_at_estimate(m, experiment)
        .map_err(estimate_failure)?
        .0)
}

/// A model that cannot be simulated at a result's estimate: a result of
/// another model is bad input, a failed simulation as [`simulation_failure`].
pub fn estimate_failure(e: EstimateError) -> Failure {
    match e {
        EstimateError::NotInModel(m) => Failure::input_msg(m),
        EstimateError::Simulation(e) => simulation_failure("simulating at the estimate", e),
    }
}

/// A missing data file is bad input naming the model file, the experiment
/// and its field.
fn check_exists(model: &Model, path: &Path, x: &rfeid::model::Experiment) -> Result<(), Failure> {
    let _ = model;
    if !x.data.is_file() {
        return Err(Failure::input_msg(format!(
            "{}: experiment \"{}\", field 'data': cannot read {}: no such file",
            path.display(),
            x.name,
            x.data.display()
        )));
    }
    Ok(())
}

/// Every experiment's model (its settings applied) and measured data.
pub fn campaign_data(
    model: &Model,
    path: &Path,
    ui: &Ui,
) -> Result<(Vec<Model>, Vec<Response>), Failure> {
    let models: Vec<Model> = (0..model.experiments.len())
        .map(|e| model.for_experiment(e))
        .collect();
    let measured = models
        .iter()
        .enumerate()
        .map(|(e, m)| experiment_data(model, path, e, m, ui))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((models, measured))
}

/// Experiment e's measured data on its model `m`'s sensors and sampling;
/// every problem names the model file, the experiment and its field.
pub fn experiment_data(
    model: &Model,
    path: &Path,
    e: usize,
    m: &Model,
    ui: &Ui,
) -> Result<Response, Failure> {
    let x = &model.experiments[e];
    let field = if x.sensors.is_some() {
        "sensors"
    } else {
        "data"
    };
    let fail = |msg: String| {
        Failure::input_msg(format!(
            "{}: experiment \"{}\", field '{field}': {msg}",
            path.display(),
            x.name
        ))
    };
    check_exists(model, path, x)?;
    let sources: Vec<_> = m.sensors.iter().map(|s| s.data.clone()).collect();
    let read = read_measurement(&x.data, m, &sources).map_err(|err| fail(err.to_string()))?;
    let matched =
        match_data(m, &read.series).map_err(|err| fail(format!("{}: {err}", x.data.display())))?;
    for note in read.notes.iter().chain(&matched.notes) {
        ui.note(format!("note: experiment \"{}\": {note}", x.name));
    }
    Ok(matched.response)
}
