//! `rfeid identify … --shard K/N`: one share of the LP_τ plan, written to a
//! shard file that `rfeid merge` continues from.
//!
//! Shard K of N evaluates the plan points whose index i (0-based) has
//! `i mod N = K`, so any N works and the shares differ by at most one point.
//! The shard file records the run's hash (model file, its signal tables,
//! the data file and the search settings, FNV-1a 64 over their bytes: a
//! check that the shards belong together, not a protection against
//! tampering), the shard's number, the search settings, the model and data
//! paths, and J (or the failure) at every finished point. It is rewritten
//! every [`CHECKPOINT_SECONDS`] while the shard runs, so a killed shard
//! resumes, when run again with the same `-o`, from its last checkpoint
//! without redoing finished points.
use super::identify::{identify_failure, prepare};
use crate::cli::{IdentifyArgs, MethodArg, SearchArgs, WeightsArg};
use crate::diagnostics::Failure;
use crate::outputs::Checked;
use crate::ui::Ui;
use clap::ValueEnum;
use rfeid::identification::pipeline::{evaluate_points, plan, Silent};
use rfeid::model::Model;
use rfeid::simulation::Response;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The format tag of a shard file.
pub const FORMAT: &str = "rfeid-shard-1";

/// A shard file is rewritten at least this often while its points run.
pub const CHECKPOINT_SECONDS: f64 = 10.0;

/// The search settings a shard was computed with (all that changes J or
/// the local searches; not the thread count).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SearchSpec {
    /// `--plan`.
    pub plan: usize,
    /// `--starts`.
    pub starts: usize,
    /// `--method`.
    pub method: String,
    /// `--weights`.
    pub weights: String,
    /// `--from`, s.
    pub from: f64,
    /// `--tolerance`.
    #[serde(default)]
    pub tolerance: Option<f64>,
    /// `--substeps`.
    #[serde(default)]
    pub substeps: Option<usize>,
    /// `--window`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub window: Option<f64>,
}

impl SearchSpec {
    /// The settings of `a`.
    pub fn of(a: &SearchArgs) -> Self {
        let name = |v: Option<clap::builder::PossibleValue>| {
            v.map(|v| v.get_name().to_string()).unwrap_or_default()
        };
        SearchSpec {
            plan: a.plan,
            starts: a.starts,
            method: name(a.method.to_possible_value()),
            weights: name(
                a.weights
                    .unwrap_or(super::identify::DEFAULT_WEIGHTS)
                    .to_possible_value(),
            ),
            from: a.from,
            tolerance: a.steps.tolerance,
            substeps: a.steps.substeps,
            window: a.window,
        }
    }

    /// Search arguments with these settings and `threads`.
    pub fn to_args(&self, threads: Option<usize>, timings: bool) -> Result<SearchArgs, String> {
        Ok(SearchArgs {
            plan: self.plan,
            starts: self.starts,
            method: MethodArg::from_str(&self.method, false)?,
            weights: Some(WeightsArg::from_str(&self.weights, false)?),
            threads,
            from: self.from,
            timings,
            steps: crate::cli::StepArgs {
                tolerance: self.tolerance,
                substeps: self.substeps,
            },
            window: self.window,
        })
    }
}

/// J at one plan point, or why it failed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointRecord {
    /// Plan index (0-based).
    pub index: usize,
    /// J, if the point could be evaluated.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cost: Option<f64>,
    /// Why it could not, otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
}

/// A shard file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShardFile {
    /// [`FORMAT`].
    pub format: String,
    /// FNV-1a 64 of the model, its tables, the data and the settings.
    pub hash: String,
    /// K.
    pub shard: usize,
    /// N.
    pub of: usize,
    /// The search settings.
    pub search: SearchSpec,
    /// The model file, as given.
    pub model: String,
    /// The data file, as given.
    pub data: String,
    /// Wall time spent on this shard's points, s (all runs of it).
    pub seconds: f64,
    /// `true` when every point of the shard is done.
    pub complete: bool,
    /// The finished points, by index.
    pub points: Vec<PointRecord>,
}

/// Parses `K/N` (0 ≤ K < N) or `auto` (from Slurm's job-array variables).
pub fn parse_shard(text: &str) -> Result<(usize, usize), Failure> {
    if text == "auto" {
        let var = |name: &str| -> Result<Option<usize>, Failure> {
            match std::env::var(name) {
                Err(_) => Ok(None),
                Ok(v) => v.trim().parse().map(Some).map_err(|_| {
                    Failure::input_msg(format!("--shard auto: {name}='{v}' is not a count"))
                }),
            }
        };
        let (Some(id), Some(count)) = (var("SLURM_ARRAY_TASK_ID")?, var("SLURM_ARRAY_TASK_COUNT")?)
        else {
            return Err(Failure::input_msg(
                "--shard auto: SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT are not set (not in a Slurm job array?)",
            ));
        };
        let min = var("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
        let k = id.checked_sub(min).ok_or_else(|| {
            Failure::input_msg(format!(
                "--shard auto: SLURM_ARRAY_TASK_ID {id} is below SLURM_ARRAY_TASK_MIN {min}"
            ))
        })?;
        return checked(k, count, "auto");
    }
    let bad = || {
        Failure::input_msg(format!(
            "--shard '{text}': expected K/N with 0 <= K < N (e.g. 0/4), or auto"
        ))
    };
    let (k, n) = text.split_once('/').ok_or_else(bad)?;
    let k: usize = k.trim().parse().map_err(|_| bad())?;
    let n: usize = n.trim().parse().map_err(|_| bad())?;
    checked(k, n, text)
}

fn checked(k: usize, n: usize, text: &str) -> Result<(usize, usize), Failure> {
    if n == 0 || k >= n {
        return Err(Failure::input_msg(format!(
            "--shard {text}: shard {k} of {n} does not exist (0 <= K < N)"
        )));
    }
    Ok((k, n))
}

/// FNV-1a 64 of `parts`, each preceded by its length.
fn fnv1a(parts: &[&[u8]]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for part in parts {
        for b in (part.len() as u64).to_le_bytes().iter().chain(part.iter()) {
            h ^= *b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    format!("{h:016x}")
}

/// The hash of a run: the model file, its signal tables, the data file and
/// the search settings.
pub fn run_hash(
    model_path: &Path,
    model: &Model,
    data: &Path,
    spec: &SearchSpec,
) -> Result<String, Failure> {
    let read = |p: &Path| {
        std::fs::read(p).map_err(|e| Failure::input_msg(format!("{}: {e}", p.display())))
    };
    let mut files = vec![read(model_path)?];
    for f in &model.files {
        files.push(read(f)?);
    }
    files.push(read(data)?);
    files.push(
        serde_json::to_vec(spec)
            .map_err(|e| Failure::failed(format!("the settings as JSON: {e}")))?,
    );
    files.insert(0, FORMAT.as_bytes().to_vec());
    let parts: Vec<&[u8]> = files.iter().map(Vec::as_slice).collect();
    Ok(fnv1a(&parts))
}

/// Reads a shard file.
pub fn read_shard(path: &Path) -> Result<ShardFile, Failure> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Failure::input_msg(format!("{}: {e}", path.display())))?;
    let shard: ShardFile = serde_json::from_str(&text).map_err(|e| {
        Failure::input_msg(format!("{}: not an rfeid shard file: {e}", path.display()))
    })?;
    if shard.format != FORMAT {
        return Err(Failure::input_msg(format!(
            "{}: format '{}', expected '{FORMAT}'",
            path.display(),
            shard.format
        )));
    }
    Ok(shard)
}

/// The plan indices of shard `k` of `n` in a plan of `points`.
pub fn share(k: usize, n: usize, points: usize) -> Vec<usize> {
    (k..points).step_by(n).collect()
}

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
    let spec = SearchSpec::of(&args.search);
    let hash = run_hash(&args.model, model, data, &spec)?;
    let mut file = ShardFile {
        format: FORMAT.into(),
        hash,
        shard: k,
        of: n,
        search: spec,
        model: args.model.display().to_string(),
        data: data.display().to_string(),
        seconds: 0.0,
        complete: false,
        points: Vec::new(),
    };
    let to_stdout = args.output == Path::new("-");
    let mut done: BTreeMap<usize, PointRecord> = BTreeMap::new();
    if !to_stdout && args.output.exists() {
        let old = read_shard(&args.output).map_err(|_| {
            Failure::input_msg(format!(
                "{}: exists and is not a shard file; remove it or choose another -o",
                args.output.display()
            ))
        })?;
        if (old.hash.as_str(), old.shard, old.of) != (file.hash.as_str(), k, n) {
            return Err(Failure::input_msg(format!(
                "{}: holds shard {}/{} of another run (hash {}, this run's {}); remove it or choose another -o",
                args.output.display(),
                old.shard,
                old.of,
                old.hash,
                file.hash
            )));
        }
        file.seconds = old.seconds;
        done.extend(old.points.into_iter().map(|p| (p.index, p)));
    }
    let (problem, settings, progress) = prepare(model, measured, &args.search, ui)?;
    progress.bar.finish_and_clear();
    let plan = plan(&problem, &settings).map_err(identify_failure)?;
    let mine = share(k, n, plan.len());
    // Only this shard's points count; anything else in the file is dropped.
    done.retain(|i, _| i % n == k && *i < plan.len());
    let todo: Vec<usize> = mine
        .iter()
        .copied()
        .filter(|i| !done.contains_key(i))
        .collect();
    if !done.is_empty() {
        ui.note(format!(
            "shard {k}/{n}: resuming, {} of its {} points already done",
            done.len(),
            mine.len()
        ));
    }
    let chunk = (4 * rayon::current_num_threads()).max(1);
    let mut since = Instant::now();
    let started = Instant::now();
    let base_seconds = file.seconds;
    for (c, indices) in todo.chunks(chunk).enumerate() {
        let outcomes =
            evaluate_points(&problem, &plan, indices, &Silent).map_err(identify_failure)?;
        for (&index, o) in indices.iter().zip(outcomes) {
            done.insert(
                index,
                PointRecord {
                    index,
                    cost: o.as_ref().ok().copied(),
                    failure: o.err(),
                },
            );
        }
        let last = (c + 1) * chunk >= todo.len();
        if !to_stdout && !last && since.elapsed().as_secs_f64() >= CHECKPOINT_SECONDS {
            file.points = done.values().cloned().collect();
            file.seconds = base_seconds + started.elapsed().as_secs_f64();
            write(outputs, &file)?;
            since = Instant::now();
        }
    }
    file.points = done.into_values().collect();
    file.seconds = base_seconds + started.elapsed().as_secs_f64();
    file.complete = true;
    write(outputs, &file)?;
    let failed = file.points.iter().filter(|p| p.cost.is_none()).count();
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
    let mut text = serde_json::to_vec_pretty(file)
        .map_err(|e| Failure::failed(format!("the shard as JSON: {e}")))?;
    text.push(b'\n');
    let mut batch = outputs.batch();
    batch.file("-o", text)?;
    batch.commit()
}

/// Resolves a path recorded in a shard file: as given if it exists (or is
/// absolute), else relative to the shard file's directory.
pub fn resolve(recorded: &str, shard_path: &Path) -> PathBuf {
    let p = PathBuf::from(recorded);
    if p.exists() || p.is_absolute() {
        p
    } else {
        shard_path.parent().unwrap_or(Path::new("")).join(p)
    }
}
