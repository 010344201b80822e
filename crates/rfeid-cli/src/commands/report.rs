//! `rfeid report`: the report of a RESULT.json, rebuilt from the model and
//! data it names.
use crate::cli::ReportArgs;
use crate::diagnostics::Failure;
use crate::outputs::Plan;
use crate::run::demo_case::{demo_data, demo_model, demo_title, reference_of};
use crate::run::digest::check_unchanged;
use crate::run::experiments::campaign_data;
use crate::run::inputs::{fixed, load, load_data};
use crate::run::report::{read_result, render, render_campaign};
use crate::ui::Ui;
use rfeid::identification::result::IdentificationResult;
use rfeid::model::Model;
use rfeid::simulation::Response;
use std::path::{Path, PathBuf};

/// What a report is rebuilt from: the model, the measured data, the true
/// values (the demo's) and the title.
type Rebuilt = (Model, Response, Option<Vec<f64>>, String);

/// Runs the command: reloads the model and data that RESULT.json names,
/// simulates the model at the estimate and writes the report.
pub fn run(args: ReportArgs, ui: &Ui) -> Result<(), Failure> {
    let result = read_result(&args.result)?;
    let base = args.result.parent().unwrap_or(Path::new(""));
    let mut plan = Plan::new();
    plan.input(&args.result).report("-o", &args.output);
    if let (Some(model_path), None, false) = (
        &result.source.model,
        &result.source.data,
        result.experiments.is_empty(),
    ) {
        return campaign(&args, &result, &resolve(base, model_path), plan, ui);
    }
    let (model, measured, reference, title) = rebuild(&args, &result, base, &mut plan, ui)?;
    let outputs = plan.check()?;
    let files = render(&model, &result, "", &measured, reference.as_deref(), &title)?;
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

/// A path RESULT.json records: as given if it exists (or is absolute),
/// else relative to RESULT.json's directory `base`.
fn resolve(base: &Path, p: &str) -> PathBuf {
    let p = PathBuf::from(p);
    if p.exists() || p.is_absolute() {
        p
    } else {
        base.join(p)
    }
}

/// A campaign's report: every experiment's data, as the model file names
/// them.
fn campaign(
    args: &ReportArgs,
    result: &IdentificationResult,
    model_path: &Path,
    mut plan: Plan,
    ui: &Ui,
) -> Result<(), Failure> {
    let model = fixed(load(model_path, ui)?, &result.source.set)?;
    let data: Vec<PathBuf> = model.experiments.iter().map(|x| x.data.clone()).collect();
    check_unchanged(
        &args.result,
        result.source.digests.as_ref(),
        model_path,
        &model,
        &data,
    )?;
    plan.input(model_path);
    for f in model
        .files
        .iter()
        .chain(model.experiments.iter().map(|x| &x.data))
    {
        plan.input(f);
    }
    let outputs = plan.check()?;
    let (models, measured) = campaign_data(&model, model_path, ui)?;
    let title = format!("campaign {}", model_path.display());
    let files = render_campaign(&model, &models, result, &measured, &title)?;
    let mut batch = outputs.batch();
    batch.report("-o", &files)?;
    batch.commit()?;
    ui.note(format!(
        "report written to {}",
        args.output.join("report.html").display()
    ));
    Ok(())
}

/// The model and data of a single run (its files, added to `plan`'s
/// inputs) or of the demo.
fn rebuild(
    args: &ReportArgs,
    result: &IdentificationResult,
    base: &Path,
    plan: &mut Plan,
    ui: &Ui,
) -> Result<Rebuilt, Failure> {
    match (&result.source.model, &result.source.data) {
        (_, Some(data)) => {
            let model_path = result
                .source
                .model
                .as_deref()
                .ok_or_else(|| Failure::input_msg("RESULT.json names no model file"))?;
            let model = fixed(load(&resolve(base, model_path), ui)?, &result.source.set)?;
            check_unchanged(
                &args.result,
                result.source.digests.as_ref(),
                &resolve(base, model_path),
                &model,
                &[resolve(base, data)],
            )?;
            plan.input(&resolve(base, model_path))
                .input(&resolve(base, data));
            for f in &model.files {
                plan.input(f);
            }
            plan.check()?;
            let measured = load_data(&resolve(base, data), &model, ui)?;
            let title = format!("{} with {}", model_path, data);
            Ok((model, measured, None, title))
        }
        (Some(m), None) if m.starts_with("built-in") => {
            let model = demo_model()?;
            let measured = demo_data(
                &model,
                result.source.demo_noise,
                result.source.demo_seed.unwrap_or(1),
            )?;
            let reference = reference_of(&model, result);
            Ok((model, measured, Some(reference), demo_title(result)))
        }
        (Some(m), None) => Err(Failure::input_msg(format!(
            "{}: names the model {m} but no data file (the data were a table in memory, a \
             DataFrame say): rebuild the report where the data are, from Python: \
             rfeid.Identification.load(\"{}\", data=frame).report(\"DIR\")",
            args.result.display(),
            args.result.display()
        ))),
        (None, None) => Err(Failure::input_msg(format!(
            "{}: names no model and data to rebuild the report from",
            args.result.display()
        ))),
    }
}
