//! A plan split across processes from Python: one shard of a run's LP_τ
//! plan written to a shard file (`identify(shard=…)`, as `rfeid identify
//! --shard K/N` writes it) and shards merged into the run's result
//! (`merge`, as `rfeid merge` does). The files are the command line's, so
//! either side may write and the other merge.
use super::errors::{
    data_error, failed, identify_error, model_error, option_error, prepare_error, py_error,
    setting_error,
};
use super::model::PyModel;
use super::result::{Fitted, PyIdentification};
use super::run::OptionsArg;
use super::watch::{watched, Counters};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use rfeid::identification::cancel::Cancel;
use rfeid::identification::options::prepare;
use rfeid::identification::pipeline::{plan as pipeline_plan, ProfileRequest, Start};
use rfeid::identification::profile::DEFAULT_POINTS;
use rfeid::identification::shard::{check_together, evaluate_share, merge_shards};
use rfeid::io::atomic::write_atomically;
use rfeid::io::digest::input_digests;
use rfeid::io::model_file::load_model;
use rfeid::io::shard_file::{read_shard, resolve, run_hash, shard_text, SearchSpec, ShardFile};
use rfeid::measurement::measured::measured_from_file;
use rfeid::model::set_values;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The worker threads of a call (`None`: one per core).
pub(crate) fn pool(threads: Option<usize>) -> PyResult<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| failed(format!("could not start the worker threads: {e}")))
}

/// The checks of a shard's arguments before anything is computed: (K, N)
/// within the plan, a search from the plan without profiles, a model from
/// a file (not a campaign), an output that is neither input. Returns the
/// model's file and the model with `steps` (tolerance, substeps) applied.
fn shard_inputs(
    model: &PyModel,
    data: &Path,
    (k, n): (usize, usize),
    output: &Path,
    options: &rfeid::identification::options::SearchOptions,
    (tolerance, substeps): (Option<f64>, Option<usize>),
) -> PyResult<(PathBuf, rfeid::model::Model)> {
    if !(k < n && n <= options.plan) {
        return Err(PyValueError::new_err(format!(
            "shard=({k}, {n}): expected (K, N) with 0 <= K < N <= plan ({})",
            options.plan
        )));
    }
    if options.start != Start::Plan || options.profiles.is_some() {
        return Err(PyValueError::new_err(
            "shard with start='values' or profiles: a shard evaluates plan points only; give profiles to merge",
        ));
    }
    let model_path = model.path.clone().ok_or_else(|| {
        model_error("shard: the model must be loaded from a file (Model.load), which the shard records for merge")
    })?;
    let edited =
        set_values::stepped(model.model.clone(), tolerance, substeps).map_err(setting_error)?;
    if !edited.experiments.is_empty() {
        return Err(model_error(format!(
            "{}: shards of a campaign ([[experiment]] entries) are not supported; run the campaign in one call",
            model_path.display()
        )));
    }
    for (p, what) in [(model_path.as_path(), "model"), (data, "data")] {
        if output == p {
            return Err(PyValueError::new_err(format!(
                "output={}: the {what} file; choose another output",
                output.display()
            )));
        }
    }
    Ok((model_path, edited))
}

/// Runs shard `shard` = (K, N) of the identification of `model` from the
/// data file `data` with `options` (the model's `tolerance` and
/// `substeps` replaced when given) and writes its shard file to `output`
/// whole (resuming the points a shard file of this run and shard already
/// there holds). Returns (points, failed points, seconds).
#[pyfunction]
#[pyo3(signature = (model, data, shard, output, *, options, tolerance, substeps))]
#[allow(clippy::too_many_arguments)]
pub fn identify_shard(
    py: Python<'_>,
    model: &PyModel,
    data: PathBuf,
    shard: (usize, usize),
    output: PathBuf,
    options: OptionsArg,
    tolerance: Option<f64>,
    substeps: Option<usize>,
) -> PyResult<(usize, usize, f64)> {
    let options = options.options()?;
    let (k, n) = shard;
    let (model_path, edited) = shard_inputs(
        model,
        &data,
        shard,
        &output,
        &options,
        (tolerance, substeps),
    )?;
    let spec = SearchSpec::of(&options, tolerance, substeps);
    let hash = run_hash(&model_path, &edited, &data, &spec).map_err(data_error)?;
    let mut file = ShardFile::new(hash, (k, n), spec, &model_path, &data);
    let done = file.resume(&output).map_err(|e| {
        PyValueError::new_err(format!("output={e}; remove it or choose another output"))
    })?;
    let (cancel, counters) = (Cancel::new(), Counters::default());
    let pool = pool(options.threads)?;
    watched(py, &cancel, &counters, None, || {
        pool.install(|| -> PyResult<()> {
            let measured = measured_from_file(&data, &edited).map_err(data_error)?;
            let prepared =
                prepare(&edited, measured.response, &options, &cancel).map_err(prepare_error)?;
            let points =
                pipeline_plan(&prepared.problem, &prepared.settings).map_err(identify_error)?;
            let mine = rfeid::io::shard_file::share(k, n, points.len());
            let done = done.into_iter().filter(|(i, _)| mine.contains(i)).collect();
            evaluate_share(&prepared.problem, &points, &mine, done, &mut file, |_| {
                Ok::<_, rfeid::identification::pipeline::IdentifyError>(())
            })
            .map_err(identify_error)
        })
    })??;
    file.complete = true;
    write_atomically(&output, |w| w.write_all(&shard_text(&file)))
        .map_err(|e| PyOSError::new_err(format!("{}: {e}", output.display())))?;
    let failed = file.points.iter().filter(|p| p.cost.is_none()).count();
    Ok((file.points.len(), failed, file.seconds))
}

/// Merges the shard files `shards` (every shard of one run, each
/// complete) into the run's result, as `rfeid merge` does: the model and
/// data files the shards record (found as given, else beside the first
/// shard) or `model` / `data`, checked against the shards' hash; then the
/// local searches, bounds, verdict and `profiles` with the merging
/// machine's `threads`. Returns the result and the reading's notes.
#[pyfunction]
#[pyo3(signature = (shards, model, data, threads, progress, profiles=None, profile_points=DEFAULT_POINTS))]
#[allow(clippy::too_many_arguments)]
pub fn merge(
    py: Python<'_>,
    shards: Vec<PathBuf>,
    model: Option<PathBuf>,
    data: Option<PathBuf>,
    threads: Option<usize>,
    progress: Option<Bound<'_, PyAny>>,
    profiles: Option<Vec<String>>,
    profile_points: usize,
) -> PyResult<(PyIdentification, Vec<String>)> {
    let shards: Vec<(PathBuf, ShardFile)> = shards
        .into_iter()
        .map(|p| read_shard(&p).map(|s| (p, s)))
        .collect::<Result<_, _>>()
        .map_err(data_error)?;
    check_together(&shards).map_err(py_error)?;
    let (first_path, first) = &shards[0];
    let found = |given: Option<PathBuf>, recorded: &str, what: &str| -> PyResult<PathBuf> {
        let path = given.unwrap_or_else(|| resolve(recorded, first_path));
        match path.exists() {
            true => Ok(path),
            false => Err(data_error(format!(
                "{}: the {what} file {} is not found from here; give {what}=PATH",
                first_path.display(),
                path.display()
            ))),
        }
    };
    let model_path = found(model, &first.model, "model")?;
    let data_path = found(data, &first.data, "data")?;
    let loaded = load_model(&model_path).map_err(model_error)?;
    let hash = run_hash(&model_path, &loaded, &data_path, &first.search).map_err(data_error)?;
    if hash != first.hash {
        return Err(data_error(format!(
            "the run's inputs changed since the shards were computed (hash {hash}, the shards' {}): the model file {}, its signal tables, the data file {} or the search settings; run the shards again",
            first.hash,
            model_path.display(),
            data_path.display()
        )));
    }
    let mut options = first.search.options(threads);
    options.profiles = profiles.map(|parameters| ProfileRequest {
        parameters,
        points: profile_points,
    });
    options.check().map_err(|e| option_error(&e))?;
    let edited = set_values::stepped(loaded, first.search.tolerance, first.search.substeps)
        .map_err(model_error)?;
    let (cancel, counters) = (Cancel::new(), Counters::default());
    let pool = pool(threads)?;
    let (mut result, measured) = watched(py, &cancel, &counters, progress.as_ref(), || {
        pool.install(|| {
            let measured = measured_from_file(&data_path, &edited).map_err(data_error)?;
            let prepared = prepare(&edited, measured.response.clone(), &options, &cancel)
                .map_err(prepare_error)?;
            let result = merge_shards(prepared.problem, &prepared.settings, &shards, &counters)
                .map_err(py_error)?;
            Ok::<_, PyErr>((result, measured))
        })
    })??;
    result.source.model = Some(first.model.clone());
    result.source.data = Some(first.data.clone());
    result.source.digests =
        Some(input_digests(&model_path, &edited, &[data_path]).map_err(data_error)?);
    let title = format!("{} with {}", first.model, first.data);
    let identification = PyIdentification {
        result,
        model: edited,
        fitted: Fitted::Single(measured.response),
        title,
    };
    Ok((identification, measured.notes))
}
