//! A run's LP_τ plan split across processes (`identify --shard K/N`, the
//! Python module's `identify(shard=…)`) and merged again (`rfeid merge`,
//! `rfeid.merge`): a shard evaluates its share of the plan
//! ([`evaluate_share`]); the merge checks that the shards belong together
//! ([`check_together`]), gathers J at every point and finishes the run
//! from them ([`merge_shards`]). The plan's values are J's own (written
//! with round-trip exactness), so a merged result equals the single run's
//! in every field but the wall times and the thread count.
//!
//! A shard cannot know which points a single run abandons (that takes the
//! best J of every point before them), so it evaluates each of its points
//! to the end and records, with J, the largest running J its checks saw
//! (`reach`). The merge replays the single run's batches on them
//! ([`replay`]): a point is abandoned there if and only if its reach
//! passes its batch's limit, so the merge abandons the same points, and
//! takes their J from the shards where the restarts need it.
use crate::identification::output_error::OutputError;
use crate::identification::pipeline::{
    evaluate_points, finish, keep, plan, replay, Evaluated, IdentifyError, PlanPoints, Progress,
    Settings, Silent,
};
use crate::identification::plan::Plan;
use crate::identification::problem::LeastSquares;
use crate::identification::result::IdentificationResult;
use crate::io::shard_file::{PointRecord, ShardFile};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

/// Why shards cannot be merged.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    /// The shards do not make one complete run (bad input); names the
    /// shard file at fault where there is one.
    #[error("{0}")]
    Shards(String),
    /// The run could not be finished.
    #[error(transparent)]
    Identify(#[from] IdentifyError),
}

/// Evaluates the points of `mine` not yet in `done`, in chunks; after
/// each chunk but the last, `checkpoint(file)` may save the points so far
/// (it is called with `file.points` and `file.seconds` up to date). At
/// the end `file` holds every point and the shard's total time.
pub fn evaluate_share<E: From<IdentifyError>>(
    problem: &OutputError<'_>,
    plan: &Plan,
    mine: &[usize],
    mut done: BTreeMap<usize, PointRecord>,
    file: &mut ShardFile,
    mut checkpoint: impl FnMut(&ShardFile) -> Result<(), E>,
) -> Result<(), E> {
    let todo: Vec<usize> = mine
        .iter()
        .copied()
        .filter(|i| !done.contains_key(i))
        .collect();
    let chunk = (4 * rayon::current_num_threads()).max(1);
    // Switched to the searches' fewer steps once, not at every chunk
    // (`evaluate_points` would otherwise take a copy of the problem each time).
    let mut switched = problem.clone();
    switched.use_search_steps();
    let started = Instant::now();
    let base_seconds = file.seconds;
    for (c, indices) in todo.chunks(chunk).enumerate() {
        let outcomes = evaluate_points(&switched, plan, indices, &Silent)?;
        for (&index, e) in indices.iter().zip(outcomes) {
            let record = PointRecord {
                index,
                cost: e.outcome.as_ref().ok().copied(),
                failure: e.outcome.err(),
                // JSON has no infinity: the largest finite number is
                // above every limit as infinity is.
                reach: Some(e.reach.min(f64::MAX)),
            };
            done.insert(index, record);
        }
        if (c + 1) * chunk < todo.len() {
            file.points = done.values().cloned().collect();
            file.seconds = base_seconds + started.elapsed().as_secs_f64();
            checkpoint(file)?;
        }
    }
    file.points = done.into_values().collect();
    file.seconds = base_seconds + started.elapsed().as_secs_f64();
    Ok(())
}

/// The shards (each with the path that names it) belong to one run, cover
/// every shard number once, and are each complete.
pub fn check_together(shards: &[(PathBuf, ShardFile)]) -> Result<(), MergeError> {
    let refuse = |m: String| Err(MergeError::Shards(m));
    let Some((first_path, first)) = shards.first() else {
        return refuse("no shard files given".into());
    };
    let first_name = first_path.display();
    let mut seen = vec![false; first.of];
    for (path, s) in shards {
        let name = path.display();
        if let Some(what) = differs(first, s) {
            return refuse(format!(
                "{name}: belongs to another run than {first_name}: {what}"
            ));
        }
        if std::mem::replace(&mut seen[s.shard], true) {
            return refuse(format!("{name}: shard {}/{} is given twice", s.shard, s.of));
        }
        if let Some(what) = s.incomplete() {
            return refuse(format!(
                "{name}: shard {}/{} is not complete: {what}; run it again to resume it",
                s.shard, s.of
            ));
        }
    }
    if let Some(k) = seen.iter().position(|s| !s) {
        return refuse(format!(
            "shard {k}/{} is missing ({} shard files given, the run has {})",
            first.of,
            shards.len(),
            first.of
        ));
    }
    let seconds: f64 = shards.iter().map(|(_, s)| s.seconds).sum();
    if !seconds.is_finite() {
        return refuse(format!(
            "the shards' `seconds` add up to {seconds}: a shard file's time was edited"
        ));
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

/// Every point of a plan of `points` as the shards evaluated it (a point
/// without a reach, from a shard written before reaches were recorded:
/// reach 0, never abandoned).
fn gather(shards: &[(PathBuf, ShardFile)], points: usize) -> Result<Vec<Evaluated>, MergeError> {
    let mut outcomes: Vec<Option<Evaluated>> = vec![None; points];
    for (path, s) in shards {
        for p in &s.points {
            let slot = outcomes.get_mut(p.index).ok_or_else(|| {
                MergeError::Shards(format!(
                    "{}: point {} lies beyond the plan of {points}",
                    path.display(),
                    p.index,
                ))
            })?;
            // The shard file was validated: exactly one of the two is there.
            let outcome = match (&p.cost, &p.failure) {
                (Some(c), _) => Ok(*c),
                (None, f) => Err(f.clone().unwrap_or_default()),
            };
            *slot = Some(Evaluated {
                outcome,
                reach: p.reach.unwrap_or(0.0),
            });
        }
    }
    outcomes
        .into_iter()
        .enumerate()
        .map(|(i, o)| o.ok_or_else(|| MergeError::Shards(format!("no shard holds plan point {i}"))))
        .collect()
}

/// Finishes the run the shards (checked by [`check_together`], their
/// hash against the run's inputs by the caller) began: the plan rebuilt,
/// J at every point taken from the shards, the points a single run
/// abandons abandoned again ([`replay`]), then the local searches, bounds
/// and verdict ([`finish`]); the plan's time is the shards' summed wall
/// time.
pub fn merge_shards(
    problem: OutputError<'_>,
    settings: &Settings,
    shards: &[(PathBuf, ShardFile)],
    progress: &dyn Progress,
) -> Result<IdentificationResult, MergeError> {
    check_together(shards)?;
    let plan = plan(&problem, settings)?;
    let evaluated = gather(shards, plan.len())?;
    let points = PlanPoints {
        states: replay(&evaluated, keep(settings), problem.n_residuals()),
        known: Some(evaluated.into_iter().map(|e| e.outcome).collect()),
    };
    let seconds: f64 = shards.iter().map(|(_, s)| s.seconds).sum();
    Ok(finish(problem, settings, &plan, points, seconds, progress)?)
}
