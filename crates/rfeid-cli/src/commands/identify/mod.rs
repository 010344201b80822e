//! `rfeid identify`: the full pipeline on measured data, in stages: the
//! arguments checked, the model loaded and edited, the outputs checked,
//! the data read, the search run, the run closed. A model with
//! `[[experiment]]` entries goes to [`campaign`], `--shard` to [`shard`].
mod campaign;
mod shard;

use crate::cli::{IdentifyArgs, StartArg};
use crate::diagnostics::Failure;
use crate::outputs::{Checked, Plan};
use crate::run::closing::{close, Closing};
use crate::run::digest::input_digests;
use crate::run::inputs::{fixed, load, load_data, stepped};
use crate::run::limits::{check_limits, start_threads};
use crate::run::report::render;
use crate::run::search::{options, run_search_from};
use crate::run::shard_arg::parse_shard;
use crate::run::show::json_conflict;
use crate::ui::Ui;
use rfeid::model::Model;
use rfeid::simulation::Response;
use std::path::Path;

/// Runs the command.
pub fn run(args: IdentifyArgs, ui: &Ui) -> Result<(), Failure> {
    check_limits(&options(&args.search, args.start))?;
    // Before any computation (see `start_threads`).
    start_threads(args.search.threads)?;
    let shard = args.shard.as_deref().map(parse_shard).transpose()?;
    if let Some((_, n)) = shard.filter(|&(_, n)| n > args.search.plan) {
        return Err(Failure::input_msg(format!(
            "--shard: {n} shards of a plan of {} points (--plan): the shards beyond the plan's size would have no point; use at most {} shards",
            args.search.plan, args.search.plan
        )));
    }
    check_combinations(&args, shard.is_some())?;
    let model = stepped(
        fixed(load(&args.model, ui)?, &args.set)?,
        &args.search.steps,
    )?;
    if !model.experiments.is_empty() {
        return campaign::run(&args, &model, ui);
    }
    let data = args.data.as_deref().ok_or_else(|| {
        Failure::input_msg(format!(
            "--data DATA is needed: {} lists no [[experiment]] with data files of its own",
            args.model.display()
        ))
    })?;
    let outputs = check_outputs(&args, data, &model)?;
    json_conflict(ui, &outputs)?;
    let measured = load_data(data, &model, ui)?;
    if let Some(shard) = shard {
        return shard::run(&args, data, &model, measured, shard, &outputs, ui);
    }
    single(&args, data, &model, measured, &outputs, ui)
}

/// Refuses options that do not go together.
fn check_combinations(args: &IdentifyArgs, sharded: bool) -> Result<(), Failure> {
    if sharded && args.report.is_some() {
        return Err(Failure::input_msg(
            "--report with --shard: a shard has no result to report; give --report to `rfeid merge`",
        ));
    }
    if sharded && args.search.profile.profiles.is_some() {
        return Err(Failure::input_msg(
            "--profiles with --shard: a shard computes no estimate to profile; give --profiles to `rfeid merge`",
        ));
    }
    if sharded && (!args.set.is_empty() || args.start == StartArg::Values) {
        return Err(Failure::input_msg(
            "--set or --start values with --shard: shards share one run's model file; write the values into a copy of the model file instead",
        ));
    }
    Ok(())
}

/// The run's inputs and outputs, checked before anything is computed.
fn check_outputs(args: &IdentifyArgs, data: &Path, model: &Model) -> Result<Checked, Failure> {
    let mut plan = Plan::new();
    plan.input(&args.model).input(data).file("-o", &args.output);
    for f in &model.files {
        plan.input(f);
    }
    if let Some(dir) = &args.report {
        plan.report("--report", dir);
    }
    plan.check()
}

/// One identification on one data file, closed with its outputs.
fn single(
    args: &IdentifyArgs,
    data: &Path,
    model: &Model,
    measured: Response,
    outputs: &Checked,
    ui: &Ui,
) -> Result<(), Failure> {
    let mut result = run_search_from(model, measured.clone(), &args.search, args.start, ui)?;
    result.source.set = args.set.clone();
    result.source.model = Some(args.model.display().to_string());
    result.source.data = Some(data.display().to_string());
    result.source.digests = Some(input_digests(&args.model, model, &[data.to_path_buf()])?);
    let report = match &args.report {
        Some(dir) => {
            let title = format!("{} with {}", args.model.display(), data.display());
            Some((
                dir.as_path(),
                render(model, &result, "", &measured, None, &title)?,
            ))
        }
        None => None,
    };
    let closing = Closing::of_result(model, &result, report, &args.output, args.search.timings);
    close(outputs, closing, ui)
}
