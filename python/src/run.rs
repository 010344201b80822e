//! `identify`: the run of `rfeid identify` on one data set, stage by stage
//! through the library, with the options of the command line.
use super::data::{DataArg, Source};
use super::errors::{data_error, identify_error, model_error, option_error, prepare_error};
use super::model::PyModel;
use super::result::PyIdentification;
use super::watch::{watched, Counters};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rfeid::identification::cancel::Cancel;
use rfeid::identification::options::{prepare, SearchOptions};
use rfeid::identification::pipeline::{
    identify as run_pipeline, Method, NoiseModel, ProfileRequest, Start, Weighting,
};
use rfeid::identification::profile::DEFAULT_POINTS;
use rfeid::identification::result::{IdentificationResult, InputDigests};
use rfeid::io::digest::file_digest;
use rfeid::model::{set_values, Model};
use rfeid::simulation::Response;

/// A keyword's value among its choices.
fn choice<T: Copy>(name: &str, value: &str, choices: &[(&str, T)]) -> PyResult<T> {
    choices
        .iter()
        .find(|(n, _)| *n == value)
        .map(|(_, v)| *v)
        .ok_or_else(|| {
            let names: Vec<&str> = choices.iter().map(|(n, _)| *n).collect();
            PyValueError::new_err(format!(
                "{name}='{value}': must be one of {}",
                names.join(", ")
            ))
        })
}

/// The library's options from the keywords, with their names.
#[allow(clippy::too_many_arguments)]
fn search_options(
    plan: usize,
    starts: usize,
    method: &str,
    weights: Option<&str>,
    noise_model: &str,
    window: Option<f64>,
    from_: f64,
    threads: Option<usize>,
    start: &str,
    jacobian_memory: Option<usize>,
    profiles: Option<ProfileRequest>,
) -> PyResult<SearchOptions> {
    Ok(SearchOptions {
        plan,
        starts,
        method: choice(
            "method",
            method,
            &[("lm", Method::Lm), ("bfgs", Method::Bfgs)],
        )?,
        weights: weights
            .map(|w| {
                choice(
                    "weights",
                    w,
                    &[
                        ("equal", Weighting::Equal),
                        ("estimated", Weighting::EstimatedNoise),
                    ],
                )
            })
            .transpose()?,
        noise_model: choice(
            "noise_model",
            noise_model,
            &[("ar", NoiseModel::default()), ("white", NoiseModel::White)],
        )?,
        threads,
        from: from_,
        window,
        start: choice(
            "start",
            start,
            &[("plan", Start::Plan), ("values", Start::Values)],
        )?,
        jacobian_memory,
        profiles,
    })
}

/// Records in `result` what it was computed from, as `rfeid identify`
/// does: the set values, the files, and their digests (the model's taken
/// when it was loaded, the data file's when it was read); returns the
/// report's title.
fn record_source(
    result: &mut IdentificationResult,
    model: &PyModel,
    source: &Source,
    data_digest: Option<String>,
    set: Vec<String>,
) -> String {
    let model_name = model
        .path
        .as_ref()
        .map_or("model".into(), |p| p.display().to_string());
    result.source.set = set;
    result.source.model = model.path.as_ref().map(|p| p.display().to_string());
    result.source.data = source.file().map(|p| p.display().to_string());
    if let (Some((m, tables)), Some(d)) = (&model.digests, data_digest) {
        result.source.digests = Some(InputDigests {
            model: m.clone(),
            tables: tables.clone(),
            data: vec![d],
        });
    }
    format!("{model_name} with {}", source.label())
}

/// What the worker thread found.
struct Searched {
    result: IdentificationResult,
    measured: Response,
    notes: Vec<String>,
    data_digest: Option<String>,
}

/// The run on the worker thread: the data read (and their file's digest
/// taken) and matched, the run prepared, the pipeline run.
fn search(
    model: &Model,
    source: &Source,
    options: &SearchOptions,
    cancel: &Cancel,
    progress: &Counters,
) -> PyResult<Searched> {
    let data_digest = source
        .file()
        .map(file_digest)
        .transpose()
        .map_err(data_error)?;
    let measured = source.measured(model).map_err(data_error)?;
    let mut notes = measured.notes;
    let prepared =
        prepare(model, measured.response.clone(), options, cancel).map_err(prepare_error)?;
    if let Some(w) = prepared.constant_warning() {
        notes.push(format!("warning: {w}"));
    }
    let result =
        run_pipeline(prepared.problem, &prepared.settings, progress).map_err(identify_error)?;
    Ok(Searched {
        result,
        measured: measured.response,
        notes,
        data_digest,
    })
}

/// Identifies `model`'s parameters from `data`: the library's options,
/// `set` fixed, the data read and matched, the run prepared and searched,
/// the result's source recorded, as `rfeid identify` does. Units: `from_`
/// in s, `window` a fraction of the record, `tolerance` a relative RMS
/// error, `substeps` steps per sample, `jacobian_memory` MiB; `profiles`
/// the parameters to profile after the bounds (empty: every one; `None`:
/// none), on `profile_points` points each;
/// `progress(done, total, search, searches, iteration, J)` is called every
/// 50 ms and once at the end. Returns the result and the notes of the
/// reading.
#[pyfunction]
#[pyo3(signature = (model, data, *, set, plan, starts, method, weights, noise_model, window,
    from_, threads, start, tolerance, substeps, jacobian_memory, progress, profiles=None,
    profile_points=DEFAULT_POINTS))]
#[allow(clippy::too_many_arguments)]
pub fn identify(
    py: Python<'_>,
    model: &PyModel,
    data: DataArg<'_>,
    set: Vec<String>,
    plan: usize,
    starts: usize,
    method: &str,
    weights: Option<&str>,
    noise_model: &str,
    window: Option<f64>,
    from_: f64,
    threads: Option<usize>,
    start: &str,
    tolerance: Option<f64>,
    substeps: Option<usize>,
    jacobian_memory: Option<usize>,
    progress: Option<Bound<'_, PyAny>>,
    profiles: Option<Vec<String>>,
    profile_points: usize,
) -> PyResult<(PyIdentification, Vec<String>)> {
    let options = search_options(
        plan,
        starts,
        method,
        weights,
        noise_model,
        window,
        from_,
        threads,
        start,
        jacobian_memory,
        profiles.map(|parameters| ProfileRequest {
            parameters,
            points: profile_points,
        }),
    )?;
    options.check().map_err(|e| option_error(&e))?;
    let fixed = set_values::fixed(model.model.clone(), &set).map_err(model_error)?;
    let edited = set_values::stepped(fixed, tolerance, substeps).map_err(model_error)?;
    if !edited.experiments.is_empty() {
        return Err(model_error(format!(
            "{}: a campaign ([[experiment]] entries) is identified by `rfeid identify` on the command line; the Python module identifies one data set",
            model.path.as_ref().map_or("the model".into(), |p| p.display().to_string())
        )));
    }
    let source = data.source()?;
    let cancel = Cancel::new();
    let counters = Counters::default();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| super::errors::failed(format!("could not start the worker threads: {e}")))?;
    let searched = watched(py, &cancel, &counters, progress.as_ref(), || {
        pool.install(|| search(&edited, &source, &options, &cancel, &counters))
    })??;
    let Searched {
        mut result,
        measured,
        notes,
        data_digest,
    } = searched;
    let title = record_source(&mut result, model, &source, data_digest, set);
    let identification = PyIdentification {
        result,
        model: edited,
        measured,
        title,
    };
    Ok((identification, notes))
}
