//! `rfeid identify` on a campaign (SPEC §5): every `[[experiment]]` of the
//! model file fitted together, and the validation experiments' fits.
use crate::cli::IdentifyArgs;
use crate::diagnostics::Failure;
use crate::outputs::{Checked, Plan};
use crate::run::closing::{close, Closing};
use crate::run::digest::input_digests;
use crate::run::experiments::{campaign, campaign_failure, check_exists};
use crate::run::failures::identify_failure;
use crate::run::limits::start_threads;
use crate::run::progress::Bars;
use crate::run::report::render_campaign;
use crate::run::search::options;
use crate::run::show::{json_conflict, search_steps_note};
use crate::ui::Ui;
use rfeid::identification::campaign::{prepare_campaign, record_experiments, CampaignData};
use rfeid::identification::cancel::Cancel;
use rfeid::identification::pipeline::identify;
use rfeid::identification::result::IdentificationResult;
use rfeid::model::Model;
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
    let data = campaign(model, &args.model, ui)?;
    let result = fit(args, model, &data, ui)?;
    let report = match &args.report {
        Some(dir) => {
            let title = format!("campaign {}", args.model.display());
            let files = render_campaign(model, &data.models, &result, &data.measured, &title)?;
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
    data: &CampaignData,
    ui: &Ui,
) -> Result<IdentificationResult, Failure> {
    start_threads(args.search.threads)?;
    let label = args.model.display().to_string();
    let options = options(&args.search, args.start);
    let prepared = prepare_campaign(model, &label, data, &options, &Cancel::new())
        .map_err(campaign_failure)?;
    for w in &prepared.warnings {
        ui.note(format!("warning: {w}"));
    }
    for (name, steps) in &prepared.steps {
        ui.note(format!(
            "experiment \"{name}\": {}",
            search_steps_note(steps)
        ));
    }
    let progress = Bars::new(args.search.plan, ui);
    let mut result =
        identify(prepared.problem, &prepared.settings, &progress).map_err(identify_failure)?;
    progress.finish();
    record_experiments(&mut result, model, data).map_err(campaign_failure)?;
    result.source.set = args.set.clone();
    result.source.model = Some(label);
    let files: Vec<PathBuf> = model.experiments.iter().map(|x| x.data.clone()).collect();
    result.source.digests = Some(input_digests(&args.model, model, &files)?);
    Ok(result)
}
