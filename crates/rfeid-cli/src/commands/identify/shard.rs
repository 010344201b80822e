//! `rfeid identify … --shard K/N`: one share of the LP_τ plan, written to a
//! shard file ([`crate::run::shard_file`]) that `rfeid merge` continues
//! from. The file is rewritten every [`CHECKPOINT_SECONDS`] while the
//! shard runs, so a killed shard resumes, when run again with the same
//! `-o`, from its last checkpoint without redoing finished points.
use crate::cli::IdentifyArgs;
use crate::diagnostics::Failure;
use crate::outputs::Checked;
use crate::run::failures::identify_failure;
use crate::run::search::{options, prepare};
use crate::ui::Ui;
use rfeid::identification::pipeline::plan;
use rfeid::identification::shard::evaluate_share;
use rfeid::io::shard_file::{run_hash, shard_text, share, SearchSpec, ShardFile};
use rfeid::model::Model;
use rfeid::simulation::Response;
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

/// A shard file is rewritten at least this often while its points run.
pub const CHECKPOINT_SECONDS: f64 = 10.0;

/// Runs shard `(k, n)` of `args`' identification and writes its file.
pub fn run(
    args: &IdentifyArgs,
    data: &Path,
    model: &Model,
    measured: Response,
    (k, n): (usize, usize),
    outputs: &Checked,
    ui: &Ui,
) -> Result<(), Failure> {
    let a = &args.search;
    let spec = SearchSpec::of(&options(a, args.start), a.steps.tolerance, a.steps.substeps);
    let hash = run_hash(&args.model, model, data, &spec).map_err(Failure::input_msg)?;
    let mut file = ShardFile::new(hash, (k, n), spec, &args.model, data);
    // Only a regular file (or none yet) holds a shard to resume and takes
    // checkpoints: standard output, a FIFO or a device gets the file once.
    let resumable = args.output != Path::new("-")
        && std::fs::metadata(&args.output).map_or(true, |m| m.is_file());
    let mut done = if resumable {
        file.resume(&args.output)
            .map_err(|e| Failure::input_msg(format!("{e}; remove it or choose another -o")))?
    } else {
        BTreeMap::new()
    };
    let (problem, settings, progress) = prepare(model, measured, &args.search, ui)?;
    progress.bar.finish_and_clear();
    let plan = plan(&problem, &settings).map_err(identify_failure)?;
    let mine = share(k, n, plan.len());
    // Only this shard's points count; anything else in the file is dropped.
    done.retain(|i, _| i % n == k && *i < plan.len());
    if !done.is_empty() {
        ui.note(format!(
            "shard {k}/{n}: resuming, {} of its {} points already done",
            done.len(),
            mine.len()
        ));
    }
    let mut since = Instant::now();
    evaluate_share(&problem, &plan, &mine, done, &mut file, |f| {
        // A checkpoint every CHECKPOINT_SECONDS, where the output can resume.
        if resumable && since.elapsed().as_secs_f64() >= CHECKPOINT_SECONDS {
            write(outputs, f)?;
            since = Instant::now();
        }
        Ok::<_, Failure>(())
    })?;
    file.complete = true;
    write(outputs, &file)?;
    let failed = file.points.iter().filter(|p| p.cost.is_none()).count();
    if ui.json {
        // What the note says, for scripts (the shard itself is in -o).
        ui.print_json(&serde_json::json!({
            "shard": k,
            "of": n,
            "points": file.points.len(),
            "failed": failed,
            "seconds": file.seconds,
            "output": args.output.display().to_string(),
        }))?;
    }
    ui.note(format!(
        "shard {k}/{n}: {} plan points ({} failed) written to {}",
        file.points.len(),
        failed,
        args.output.display()
    ));
    Ok(())
}

/// Writes the shard file (`-o`) through the run's checked outputs.
fn write(outputs: &Checked, file: &ShardFile) -> Result<(), Failure> {
    let mut batch = outputs.batch();
    batch.file("-o", shard_text(file))?;
    batch.commit()
}
