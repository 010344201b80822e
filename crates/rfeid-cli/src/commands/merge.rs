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
use crate::run::failures::identify_failure;
use crate::run::inputs::{load, load_data, stepped};
use crate::run::report::render;
use crate::run::search::prepare;
use crate::run::shard_file::{read_shard, resolve, run_hash, ShardFile};
use crate::run::show::json_conflict;
use crate::ui::Ui;
use rfeid::identification::pipeline::{finish, plan, PointOutcome};
use rfeid::model::Model;
use std::path::Path;

/// Runs the command.
pub fn run(args: MergeArgs, ui: &Ui) -> Result<(), Failure> {
    let shards: Vec<ShardFile> = args
        .shards
        .iter()
        .map(|p| read_shard(p))
        .collect::<Result<_, _>>()?;
    let first = &shards[0];
    let first_path = &args.shards[0];
    check_together(&args, &shards)?;
    let model_path = recorded(args.model.as_deref(), &first.model, first_path, "--model")?;
    let data_path = recorded(args.data.as_deref(), &first.data, first_path, "--data")?;
    let model = load(&model_path, ui)?;
    let outputs = check_outputs(&args, &model, &model_path, &data_path)?;
    json_conflict(ui, &outputs)?;
    let hash = run_hash(&model_path, &model, &data_path, &first.search)?;
    if hash != first.hash {
        return Err(Failure::input_msg(format!(
            "the run's inputs changed since the shards were computed (hash {hash}, the shards' {}): the model file {}, its signal tables, the data file {} or the search settings; run the shards again",
            first.hash,
            model_path.display(),
            data_path.display(),
        )));
    }
    let measured = load_data(&data_path, &model, ui)?;
    let mut search = first
        .search
        .to_args(args.threads, args.timings)
        .map_err(|e| {
            Failure::input_msg(format!("{}: search settings: {e}", first_path.display()))
        })?;
    search.profile = args.profile.clone();
    let model = stepped(model, &search.steps)?;
    let (problem, settings, progress) = prepare(&model, measured.clone(), &search, ui)?;
    progress.bar.finish_and_clear();
    let plan = plan(&problem, &settings).map_err(identify_failure)?;
    let outcomes = gather(&args, &shards, plan.len())?;
    let seconds: f64 = shards.iter().map(|s| s.seconds).sum();
    let mut result = finish(problem, &settings, &plan, outcomes, seconds, &progress)
        .map_err(identify_failure)?;
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

/// The outcome of every plan point of a plan of `points`, from the shards.
fn gather(
    args: &MergeArgs,
    shards: &[ShardFile],
    points: usize,
) -> Result<Vec<PointOutcome>, Failure> {
    let mut outcomes: Vec<Option<PointOutcome>> = vec![None; points];
    for (s, path) in shards.iter().zip(&args.shards) {
        for p in &s.points {
            let slot = outcomes.get_mut(p.index).ok_or_else(|| {
                Failure::input_msg(format!(
                    "{}: point {} lies beyond the plan of {points}",
                    path.display(),
                    p.index,
                ))
            })?;
            // read_shard checked that exactly one of the two is there.
            *slot = Some(match (&p.cost, &p.failure) {
                (Some(c), _) => Ok(*c),
                (None, f) => Err(f.clone().unwrap_or_default()),
            });
        }
    }
    outcomes
        .into_iter()
        .enumerate()
        .map(|(i, o)| o.ok_or_else(|| Failure::input_msg(format!("no shard holds plan point {i}"))))
        .collect()
}
/// The shards belong to one run, cover every shard number once, and are
/// each complete.
fn check_together(args: &MergeArgs, shards: &[ShardFile]) -> Result<(), Failure> {
    let first = &shards[0];
    let first_name = args.shards[0].display();
    let mut seen = vec![false; first.of];
    for (s, path) in shards.iter().zip(&args.shards) {
        let name = path.display();
        if let Some(what) = differs(first, s) {
            return Err(Failure::input_msg(format!(
                "{name}: belongs to another run than {first_name}: {what}"
            )));
        }
        if std::mem::replace(&mut seen[s.shard], true) {
            return Err(Failure::input_msg(format!(
                "{name}: shard {}/{} is given twice",
                s.shard, s.of
            )));
        }
        if let Some(what) = s.incomplete() {
            return Err(Failure::input_msg(format!(
                "{name}: shard {}/{} is not complete: {what}; run it again to resume it",
                s.shard, s.of
            )));
        }
    }
    if let Some(k) = seen.iter().position(|s| !s) {
        return Err(Failure::input_msg(format!(
            "shard {k}/{} is missing ({} shard files given, the run has {})",
            first.of,
            shards.len(),
            first.of
        )));
    }
    let seconds: f64 = shards.iter().map(|s| s.seconds).sum();
    if !seconds.is_finite() {
        return Err(Failure::input_msg(format!(
            "the shards' `seconds` add up to {seconds}: a shard file's time was edited"
        )));
    }
    Ok(())
}

/// What makes shard `s` part of another run than `first`, if anything.
fn differs(first: &ShardFile, s: &ShardFile) -> Option<String> {
    if s.hash != first.hash {
        Some(format!(
            "their hashes of the model, its tables, the data and the settings differ ({} against {})",
            s.hash, first.hash
        ))
    } else if s.of != first.of {
        Some(format!(
            "it is one of {} shards, against {}",
            s.of, first.of
        ))
    } else if s.search != first.search {
        Some(format!(
            "its search settings differ ({:?} against {:?})",
            s.search, first.search
        ))
    } else {
        None
    }
}
