//! A shard file: one share of a run's LP_τ plan, written by
//! `identify --shard K/N` and read by `rfeid merge`.
//!
//! Shard K of N evaluates the plan points whose index i (0-based) has
//! `i mod N = K`, so any N works and the shares differ by at most one point.
//! The shard file records the run's hash (model file, its signal tables,
//! the data file and the search settings, FNV-1a 64 over their bytes: a
//! check that the shards belong together, not a protection against
//! tampering), the shard's number, the search settings, the model and data
//! paths, and J (or the failure) at every finished point, with the
//! largest running J its evaluation's checks saw (its reach, from which
//! the merge tells the points a single run abandons).
use crate::identification::options::{SearchOptions, DEFAULT_WEIGHTS};
use crate::identification::pipeline::Start;
use crate::io::digest::{fnv1a, read_bytes, DigestError};
use crate::model::Model;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A shard file that cannot be used: the file and what is wrong (the
/// field, or the line and column of JSON that does not parse).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {message}", path.display())]
pub struct ShardError {
    /// The shard file.
    pub path: PathBuf,
    /// What is wrong.
    pub message: String,
}

impl ShardError {
    fn new(path: &Path, message: String) -> Self {
        ShardError {
            path: path.to_path_buf(),
            message,
        }
    }
}

/// The format tag of a shard file.
pub const FORMAT: &str = "rfeid-shard-1";

/// The search settings a shard was computed with: the run's options (all
/// that changes J or the local searches; not the thread count, the memory
/// or the profiles, which are the merging machine's) and the integrator's
/// `tolerance` and `substeps` (the model's when absent). A shard written
/// before noise models existed has no `noise_model`: `ar`, the default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SearchSpec {
    /// The options.
    #[serde(flatten)]
    pub options: SearchOptions,
    /// `tolerance`.
    #[serde(default)]
    pub tolerance: Option<f64>,
    /// `substeps`.
    #[serde(default)]
    pub substeps: Option<usize>,
}

impl SearchSpec {
    /// The settings of `o` with the integrator's `tolerance` and
    /// `substeps` (the model's when `None`): the weights resolved to their
    /// default, the threads, memory and profiles left out.
    pub fn of(o: &SearchOptions, tolerance: Option<f64>, substeps: Option<usize>) -> Self {
        SearchSpec {
            options: SearchOptions {
                weights: Some(o.weights.unwrap_or(DEFAULT_WEIGHTS)),
                threads: None,
                jacobian_memory: None,
                profiles: None,
                ..o.clone()
            },
            tolerance,
            substeps,
        }
    }

    /// The search options of these settings with `threads`. Memory, like
    /// the threads, is the merging machine's (its default); profiles do not
    /// change the plan, so the merge asks for them.
    pub fn options(&self, threads: Option<usize>) -> SearchOptions {
        SearchOptions {
            threads,
            ..self.options.clone()
        }
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
    /// The largest running J the evaluation's checks saw, from which the
    /// merge tells whether a single run abandons the point (absent in
    /// shards written before it was recorded: never abandoned).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reach: Option<f64>,
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

/// The hash of a run: the model file, its signal tables, the data file and
/// the search settings.
pub fn run_hash(
    model_path: &Path,
    model: &Model,
    data: &Path,
    spec: &SearchSpec,
) -> Result<String, DigestError> {
    let mut files = vec![read_bytes(model_path)?];
    for f in &model.files {
        files.push(read_bytes(f)?);
    }
    files.push(read_bytes(data)?);
    files.push(serde_json::to_vec(spec).expect("the settings serialise"));
    files.insert(0, FORMAT.as_bytes().to_vec());
    let parts: Vec<&[u8]> = files.iter().map(Vec::as_slice).collect();
    Ok(fnv1a(&parts))
}

/// Reads a shard file.
pub fn read_shard(path: &Path) -> Result<ShardFile, ShardError> {
    let text = std::fs::read_to_string(path).map_err(|e| ShardError::new(path, e.to_string()))?;
    parse_shard(&text, path)
}

/// A shard file's `text`, read from `path`: parsed, its format checked, and
/// its content validated ([`ShardFile::validate`]); a refusal names the
/// file and the field (or the line and column of broken JSON).
pub fn parse_shard(text: &str, path: &Path) -> Result<ShardFile, ShardError> {
    // A byte-order mark (an editor's) is not JSON; it is no reason to refuse.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut de = serde_json::Deserializer::from_str(text);
    let shard: ShardFile = serde_path_to_error::deserialize(&mut de)
        .map_err(|e| not_a_shard(path, &e.path().to_string(), e.inner()))?;
    de.end().map_err(|e| not_a_shard(path, ".", &e))?;
    if shard.format != FORMAT {
        let message = format!("`format` is '{}', expected '{FORMAT}'", shard.format);
        return Err(ShardError::new(path, message));
    }
    shard
        .validate()
        .map_err(|(field, what)| ShardError::new(path, format!("`{field}` {what}")))?;
    Ok(shard)
}

/// A shard file that does not parse: the file, the field at `field` (`.`:
/// none, the JSON itself), and serde's message (with line and column).
fn not_a_shard(path: &Path, field: &str, e: &serde_json::Error) -> ShardError {
    let at = match field {
        "." | "" => String::new(),
        f => format!("`{f}`: "),
    };
    ShardError::new(path, format!("not an rfeid shard file: {at}{e}"))
}

/// A file at a shard's output that this shard cannot resume from. Each
/// front end adds what to do (remove it, or write elsewhere).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ResumeError {
    /// The file is not a shard file.
    #[error("{}: exists and is not a shard file to resume ({})", .0.path.display(), .0.message)]
    NotAShard(ShardError),
    /// It holds a shard of another run.
    #[error(
        "{}: holds shard {}/{} of another run (the model, its tables, the data or the search \
         settings differ: hash {hash}, this run's {this})",
        path.display(), held.0, held.1
    )]
    OtherRun {
        /// The file.
        path: PathBuf,
        /// The shard it holds, (K, N).
        held: (usize, usize),
        /// Its run's hash.
        hash: String,
        /// This run's hash.
        this: String,
    },
    /// It holds another shard of this run.
    #[error(
        "{}: holds shard {}/{} of this run, not {}/{}",
        path.display(), held.0, held.1, this.0, this.1
    )]
    OtherShard {
        /// The file.
        path: PathBuf,
        /// The shard it holds, (K, N).
        held: (usize, usize),
        /// This shard, (K, N).
        this: (usize, usize),
    },
}

impl ShardFile {
    /// Shard `k` of `n` of the run whose hash is `hash` ([`run_hash`]),
    /// with its search settings and the model and data files as given;
    /// no point done yet.
    pub fn new(
        hash: String,
        (k, n): (usize, usize),
        search: SearchSpec,
        model: &Path,
        data: &Path,
    ) -> Self {
        ShardFile {
            format: FORMAT.into(),
            hash,
            shard: k,
            of: n,
            search,
            model: model.display().to_string(),
            data: data.display().to_string(),
            seconds: 0.0,
            complete: false,
            points: Vec::new(),
        }
    }

    /// The points an earlier run of this shard left in `output`, if there
    /// is a file there, with its time added to this file's; a file that is
    /// not this shard of this run is refused.
    pub fn resume(&mut self, output: &Path) -> Result<BTreeMap<usize, PointRecord>, ResumeError> {
        let mut done = BTreeMap::new();
        if !output.exists() {
            return Ok(done);
        }
        let old = read_shard(output).map_err(ResumeError::NotAShard)?;
        let (path, held) = (output.to_path_buf(), (old.shard, old.of));
        if old.hash != self.hash {
            let (hash, this) = (old.hash, self.hash.clone());
            return Err(ResumeError::OtherRun {
                path,
                held,
                hash,
                this,
            });
        }
        if held != (self.shard, self.of) {
            let this = (self.shard, self.of);
            return Err(ResumeError::OtherShard { path, held, this });
        }
        self.seconds = old.seconds;
        done.extend(old.points.into_iter().map(|p| (p.index, p)));
        Ok(done)
    }

    /// Checks what the file says before anything is sized by it (the hash
    /// does not cover an edited file): the search options within their
    /// limits ([`SearchOptions::check`]) and from the plan, 1 ≤ N ≤ the
    /// plan's points, K < N, a finite time of at least 0, and
    /// each point in this shard's share with exactly one of a finite J ≥ 0
    /// and a failure. The field at fault and what is wrong otherwise.
    fn validate(&self) -> Result<(), (String, String)> {
        let search = &self.search.options;
        search
            .check()
            .map_err(|e| (format!("search.{}", e.option), format!("is {}", e.detail)))?;
        if search.start != Start::Plan {
            let what = "is 'values': a shard evaluates plan points, from which the searches start";
            return Err(("search.start".into(), what.into()));
        }
        let (plan, of) = (search.plan, self.of);
        if !(1..=plan).contains(&of) {
            return Err((
                "of".into(),
                format!("is {of}: must be 1 to the plan's {plan} points"),
            ));
        }
        if self.shard >= of {
            return Err((
                "shard".into(),
                format!("is {}: must be below `of` ({of})", self.shard),
            ));
        }
        if !(self.seconds.is_finite() && self.seconds >= 0.0) {
            return Err((
                "seconds".into(),
                format!("is {}: must be a finite time of at least 0", self.seconds),
            ));
        }
        self.points.iter().try_for_each(|p| self.check_point(p))
    }

    /// One point of [`Self::validate`].
    fn check_point(&self, p: &PointRecord) -> Result<(), (String, String)> {
        if p.index >= self.search.options.plan || p.index % self.of != self.shard {
            return Err((
                "points".into(),
                format!(
                    "holds plan point {}, which is not in shard {}/{} of a plan of {} points",
                    p.index, self.shard, self.of, self.search.options.plan
                ),
            ));
        }
        if let Some(reach) = p.reach.filter(|r| !(r.is_finite() && *r >= 0.0)) {
            return Err((
                "points".into(),
                format!(
                    "gives plan point {} reach = {reach}: a reach is finite and at least 0",
                    p.index
                ),
            ));
        }
        match (p.cost, &p.failure) {
            (Some(j), None) if j.is_finite() && j >= 0.0 => Ok(()),
            (Some(j), None) => Err((
                "points".into(),
                format!(
                    "gives plan point {} J = {j}: J is finite and at least 0",
                    p.index
                ),
            )),
            (None, Some(_)) => Ok(()),
            (c, _) => Err((
                "points".into(),
                format!(
                    "gives plan point {} {} of `cost` and `failure`: exactly one is needed",
                    p.index,
                    if c.is_some() { "both" } else { "neither" }
                ),
            )),
        }
    }

    /// What is missing from a shard that is not complete, or `None` when
    /// every point of its share is there once and it is marked complete.
    pub fn incomplete(&self) -> Option<String> {
        let mine = share(self.shard, self.of, self.search.options.plan);
        let mut have: Vec<usize> = self.points.iter().map(|p| p.index).collect();
        have.sort_unstable();
        if let Some(w) = have.windows(2).find(|w| w[0] == w[1]) {
            return Some(format!("it holds plan point {} twice", w[0]));
        }
        if have.len() < mine.len() {
            let first = mine
                .iter()
                .zip(&have)
                .find(|(a, b)| a != b)
                .map_or(mine[have.len()], |(a, _)| *a);
            return Some(format!(
                "{} of its {} points are done, {} missing (the first: plan point {first})",
                have.len(),
                mine.len(),
                mine.len() - have.len()
            ));
        }
        (!self.complete).then(|| {
            "all its points are there, but it is not marked complete (its run was stopped before the end)".to_string()
        })
    }
}

/// The plan indices of shard `k` of `n` in a plan of `points`.
pub fn share(k: usize, n: usize, points: usize) -> Vec<usize> {
    (k..points).step_by(n).collect()
}

/// The shard file's text: pretty JSON and a final newline.
pub fn shard_text(file: &ShardFile) -> Vec<u8> {
    let mut text = serde_json::to_vec_pretty(file).expect("a shard serialises");
    text.push(b'\n');
    text
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
