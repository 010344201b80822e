//! `rfeid report`, and the reports of `identify --report` and `demo --report`.
use super::common::{fix_parameters, load, load_data};
use super::demo::{demo_data, demo_model};
use crate::cli::ReportArgs;
use crate::diagnostics::Failure;
use crate::outputs::Plan;
use crate::ui::Ui;
use rfeid::identification::result::IdentificationResult;
use rfeid::model::Model;
use rfeid::report::{report_files, ReportInput};
use rfeid::simulation::{Response, Simulator, Workspace};
use std::path::{Path, PathBuf};

/// Runs the command: reloads the model and data that RESULT.json names,
/// simulates the model at the estimate and writes the report.
pub fn run(args: ReportArgs, ui: &Ui) -> Result<(), Failure> {
    let result = read_result(&args.result)?;
    let base = args.result.parent().unwrap_or(Path::new(""));
    let resolve = |p: &str| -> PathBuf {
        let p = PathBuf::from(p);
        if p.exists() || p.is_absolute() {
            p
        } else {
            base.join(p)
        }
    };
    let mut plan = Plan::new();
    plan.input(&args.result).report("-o", &args.output);
    if let (Some(model_path), None, false) = (
        &result.source.model,
        &result.source.data,
        result.experiments.is_empty(),
    ) {
        // A campaign: every experiment's data, as the model file names them.
        let model_path = resolve(model_path);
        let mut model = load(&model_path)?;
        fix_parameters(&mut model, &result.source.set)?;
        plan.input(&model_path);
        for f in model
            .files
            .iter()
            .chain(model.experiments.iter().map(|x| &x.data))
        {
            plan.input(f);
        }
        let outputs = plan.check()?;
        let (models, measured) = super::campaign::campaign_data(&model, &model_path, ui)?;
        let title = format!("campaign {}", model_path.display());
        let files = render_campaign(&model, &models, &result, &measured, &title)?;
        let mut batch = outputs.batch();
        batch.report("-o", &files)?;
        batch.commit()?;
        ui.note(format!(
            "report written to {}",
            args.output.join("report.html").display()
        ));
        return Ok(());
    }
    let (model, measured, reference, title) = match (&result.source.model, &result.source.data) {
        (_, Some(data)) => {
            let model_path = result
                .source
                .model
                .as_deref()
                .ok_or_else(|| Failure::input_msg("RESULT.json names no model file"))?;
            let mut model = load(&resolve(model_path))?;
            fix_parameters(&mut model, &result.source.set)?;
            plan.input(&resolve(model_path)).input(&resolve(data));
            for f in &model.files {
                plan.input(f);
            }
            plan.check()?;
            let measured = load_data(&resolve(data), &model, ui)?;
            let title = format!("{} with {}", model_path, data);
            (model, measured, None, title)
        }
        (Some(m), None) if m.starts_with("built-in") => {
            let model = demo_model()?;
            let measured = demo_data(
                &model,
                result.source.demo_noise,
                result.source.demo_seed.unwrap_or(1),
            )?;
            let reference = reference_of(&model, &result);
            (model, measured, Some(reference), demo_title(&result))
        }
        _ => {
            return Err(Failure::input_msg(format!(
                "{}: names no model and data to rebuild the report from",
                args.result.display()
            )))
        }
    };
    let outputs = plan.check()?;
    let files = render(&model, &result, &measured, reference.as_deref(), &title)?;
    let mut batch = outputs.batch();
    batch.report("-o", &files)?;
    batch.commit()?;
    ui.note(format!(
        "report written to {} ({} figures)",
        args.output.join("report.html").display(),
        files.len() - 1
    ));
    Ok(())
}

/// Reads a RESULT.json; an unreadable or foreign file is bad input naming it.
pub fn read_result(path: &Path) -> Result<IdentificationResult, Failure> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Failure::input_msg(format!("{}: {e}", path.display())))?;
    serde_json::from_str(&text)
        .map_err(|e| Failure::input_msg(format!("{}: not an rfeid result: {e}", path.display())))
}

/// The demo's title.
pub fn demo_title(result: &IdentificationResult) -> String {
    match (result.source.demo_noise, result.source.demo_seed) {
        (Some(f), Some(seed)) => {
            format!("Knee–column benchmark, {}% noise (seed {seed})", 100.0 * f)
        }
        _ => "Knee–column benchmark, noise-free data".into(),
    }
}

/// The true values of the identified parameters (the model's nominal ones).
pub fn reference_of(model: &Model, result: &IdentificationResult) -> Vec<f64> {
    result
        .parameters
        .iter()
        .map(|p| {
            model
                .parameter_index(&p.name)
                .map(|i| model.parameters[i].value)
                .unwrap_or(f64::NAN)
        })
        .collect()
}

/// The report of a campaign: the fitted experiments' sensors side by side
/// (`sensor[experiment]`, as in the result), each simulated at the estimate,
/// on the shortest of their records; the experiments' fits in the summary.
pub fn render_campaign(
    model: &Model,
    models: &[Model],
    result: &IdentificationResult,
    measured: &[Response],
    title: &str,
) -> Result<Vec<(String, String)>, Failure> {
    let fitted_idx = model.fitted_experiments();
    let n = fitted_idx
        .iter()
        .map(|&e| measured[e].n_samples)
        .min()
        .unwrap_or(0);
    let (mut y, mut g) = (Vec::new(), Vec::new());
    let mut sensors = 0;
    for &e in &fitted_idx {
        let name = &model.experiments[e].name;
        let sim = super::campaign::simulate_at_estimate(result, &models[e], name)?;
        for c in 0..measured[e].n_sensors {
            y.extend_from_slice(&measured[e].sensor(c)[..n]);
            g.extend_from_slice(&sim.sensor(c)[..n]);
            sensors += 1;
        }
    }
    let stack = |values| Response {
        n_samples: n,
        n_sensors: sensors,
        values,
    };
    let (measured, fitted) = (stack(y), stack(g));
    let first = fitted_idx.first().map_or(0, |&e| e);
    let time: Vec<f64> = (0..n).map(|k| models[first].sampling.time(k)).collect();
    let input = ReportInput {
        title: title.to_string(),
        model,
        result,
        time: &time,
        measured: &measured,
        fitted: &fitted,
        reference: None,
    };
    report_files(&input).map_err(|e| Failure::input_msg(format!("report: {e}")))
}

/// Simulates at the estimate and renders the report's files (name, text).
pub fn render(
    model: &Model,
    result: &IdentificationResult,
    measured: &Response,
    reference: Option<&[f64]>,
    title: &str,
) -> Result<Vec<(String, String)>, Failure> {
    let mut params = model.nominal();
    for p in &result.parameters {
        let i = model.parameter_index(&p.name).ok_or_else(|| {
            Failure::input_msg(format!(
                "the result's parameter '{}' is not in the model",
                p.name
            ))
        })?;
        params[i] = p.estimate;
    }
    // The steps the identification ended with, as recorded.
    let sim = match &result.simulation {
        Some(steps) => {
            Simulator::with_integrator(model, rfeid::simulation::steps::integrator(steps.substeps))
        }
        None => Simulator::new(model),
    };
    let mut fitted = sim.response_buffer();
    sim.run(&params, &mut Workspace::default(), &mut fitted)
        .map_err(|e| Failure::failed(format!("simulating at the estimate failed: {e}")))?;
    let time: Vec<f64> = (0..fitted.n_samples)
        .map(|k| model.sampling.time(k))
        .collect();
    let input = ReportInput {
        title: title.to_string(),
        model,
        result,
        time: &time,
        measured,
        fitted: &fitted,
        reference,
    };
    report_files(&input).map_err(|e| Failure::input_msg(format!("report: {e}")))
}
