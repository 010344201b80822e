//! `rfeid merge SHARD… -o RESULT.json`: the plan's values from every shard
//! of one run, then the rest of the identification (local searches, bounds,
//! verdict).
//!
//! The shards must carry one hash, one shard count and every shard number
//! exactly once, each complete. The model and data files they name are
//! read again and must still give that hash. The local searches then start
//! from the same plan values as a single run's (J is written with
//! round-trip exactness), so the result equals the single run's in every
//! field but the wall times (`timings`, where `plan` is the shards' summed
//! wall time) and the thread count.
use crate::cli::MergeArgs;
use crate::diagnostics::Failure;
use crate::outputs::{Checked, Plan};
use crate::run::closing::{close, Closing};
use crate::run::digest::input_digests;
use crate::run::failures::failure;
use crate::run::inputs::{load, load_data};
use crate::run::report::render;
use crate::run::search::{prepare_options, profile_request};
use crate::run::shard_arg::shard_failure;
use crate::run::show::json_conflict;
use crate::ui::Ui;
use rfeid::identification::shard::{check_together, merge_shards, MergeError};
use rfeid::io::shard_file::{read_shard, resolve, run_hash, ShardFile};
use rfeid::model::{set_values, Model};
use std::path::{Path, PathBuf};

/// Runs the command.
pub fn run(args: MergeArgs, ui: &Ui) -> Result<(), Failure> {
    let shards: Vec<(PathBuf, ShardFile)> = args
        .shards
        .iter()
        .map(|p| read_shard(p).map(|s| (p.clone(), s)))
        .collect::<Result<_, _>>()
        .map_err(shard_failure)?;
    let (first_path, first) = &shards[0];
    check_together(&shards).map_err(merge_failure)?;
    let model_path = recorded(args.model.as_deref(), &first.model, first_path, "--model")?;
    let data_path = recorded(args.data.as_deref(), &first.data, first_path, "--data")?;
    let model = load(&model_path, ui)?;
    let outputs = check_outputs(&args, &model, &model_path, &data_path)?;
    json_conflict(ui, &outputs)?;
    let hash =
        run_hash(&model_path, &model, &data_path, &first.search).map_err(Failure::input_msg)?;
    if hash != first.hash {
        return Err(Failure::input_msg(format!(
            "the run's inputs changed since the shards were computed (hash {hash}, the shards' {}): the model file {}, its signal tables, the data file {} or the search settings; run the shards again",
            first.hash,
            model_path.display(),
            data_path.display(),
        )));
    }
    let measured = load_data(&data_path, &model, ui)?;
    let mut options = first.search.options(args.threads);
    options.profiles = profile_request(&args.profile);
    let model = set_values::stepped(model, first.search.tolerance, first.search.substeps)
        .map_err(failure)?;
    let (problem, settings, progress) = prepare_options(&model, measured.clone(), &options, ui)?;
    progress.bar.finish_and_clear();
    let mut result = merge_shards(problem, &settings, &shards, &progress).map_err(merge_failure)?;
    progress.finish();
    result.source.model = Some(first.model.clone());
    result.source.data = Some(first.data.clone());
    result.source.digests = Some(input_digests(
        &model_path,
        &model,
        std::slice::from_ref(&data_path),
    )?);
    let report = match &args.report {
        Some(dir) => {
            let title = format!("{} with {}", first.model, first.data);
            Some((
                dir.as_path(),
                render(&model, &result, "", &measured, None, &title)?,
            ))
        }
        None => None,
    };
    let mut closing = Closing::of_result(&model, &result, report, &args.output, args.timings);
    // merge does not note where the report went.
    closing.note_report = false;
    close(&outputs, closing, ui)
}

/// The model or data file of the run: `given` (`flag`), else the path the
/// first shard recorded ([`resolve`]d); one not found says where the path
/// came from.
fn recorded(
    given: Option<&Path>,
    recorded: &str,
    shard: &Path,
    flag: &str,
) -> Result<std::path::PathBuf, Failure> {
    if let Some(p) = given {
        return Ok(p.to_path_buf());
    }
    let path = resolve(recorded, shard);
    if !path.exists() {
        return Err(Failure::input_msg(format!(
            "{}: records the file '{recorded}', which is not found from here ({}): run merge from the folder `identify --shard` ran in, or give {flag} PATH",
            shard.display(),
            path.display()
        )));
    }
    Ok(path)
}

/// The merge's inputs (model, data, shards) and outputs, checked.
fn check_outputs(
    args: &MergeArgs,
    model: &Model,
    model_path: &Path,
    data_path: &Path,
) -> Result<Checked, Failure> {
    let mut outputs = Plan::new();
    outputs.input(model_path).input(data_path);
    for p in &args.shards {
        outputs.input(p);
    }
    for f in &model.files {
        outputs.input(f);
    }
    outputs.file("-o", &args.output);
    if let Some(dir) = &args.report {
        outputs.report("--report", dir);
    }
    outputs.check()
}

/// A merge refused (bad input) or a run that could not be finished
/// ([`failure`]).
fn merge_failure(e: MergeError) -> Failure {
    failure(e)
}
