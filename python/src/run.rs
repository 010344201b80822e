//! `identify`: the run of `rfeid identify` on one data set, stage by stage
//! through the library, with the options of the command line.
use super::data::{DataArg, Source};
use super::errors::{
    campaign_error, data_error, identify_error, option_error, prepare_error, setting_error,
};
use super::model::PyModel;
use super::result::{Fitted, PyIdentification};
use super::watch::{watched, Counters};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rfeid::identification::campaign::{prepare_campaign, read_campaign, record_experiments};
use rfeid::identification::cancel::Cancel;
use rfeid::identification::options::{
    named, prepare, SearchOptions, METHODS, NOISE_MODELS, STARTS, WEIGHTS,
};
use rfeid::identification::pipeline::{identify as run_pipeline, ProfileRequest};
use rfeid::identification::result::{IdentificationResult, InputDigests};
use rfeid::io::digest::file_digest;
use rfeid::model::{set_values, Model};

/// A keyword's value among the library's names for it ([`named`]).
fn choice<T: Copy>(option: &'static str, value: &str, choices: &[(&str, T)]) -> PyResult<T> {
    named(option, value, choices).map_err(|e| option_error(&e))
}

/// The search options as the Python layer passes them, one dict with a
/// key per keyword (`from_` as `from`; `profiles` `None` for none), each
/// already of its type: the one list of the keywords that
/// [`identify`] and [`super::shards::identify_shard`] both take.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct OptionsArg {
    plan: usize,
    starts: usize,
    method: String,
    weights: Option<String>,
    noise_model: String,
    window: Option<f64>,
    from: f64,
    threads: Option<usize>,
    start: String,
    jacobian_memory: Option<usize>,
    profiles: Option<Vec<String>>,
    profile_points: usize,
}

impl OptionsArg {
    /// The library's options, checked; a name or value out of range is a
    /// `ValueError` naming the keyword.
    pub(crate) fn options(self) -> PyResult<SearchOptions> {
        let options = SearchOptions {
            plan: self.plan,
            starts: self.starts,
            method: choice("method", &self.method, &METHODS)?,
            weights: self
                .weights
                .map(|w| choice("weights", &w, &WEIGHTS))
                .transpose()?,
            noise_model: choice("noise_model", &self.noise_model, &NOISE_MODELS)?,
            threads: self.threads,
            from: self.from,
            window: self.window,
            start: choice("start", &self.start, &STARTS)?,
            jacobian_memory: self.jacobian_memory,
            profiles: self.profiles.map(|parameters| ProfileRequest {
                parameters,
                points: self.profile_points,
            }),
        };
        options.check().map_err(|e| option_error(&e))?;
        Ok(options)
    }
}

/// Records in `result` what it was computed from, as `rfeid identify`
/// does: the set values, the files, and their digests (the model's taken
/// when it was loaded, the data files' when they were read); returns the
/// report's title.
fn record_source(
    result: &mut IdentificationResult,
    model: &PyModel,
    label: Option<String>,
    data_digests: Option<Vec<String>>,
    set: Vec<String>,
) -> String {
    let model_name = model_label(model);
    result.source.set = set;
    result.source.model = model.path.as_ref().map(|p| p.display().to_string());
    result.source.data = label.clone();
    if let (Some((m, tables)), Some(data)) = (&model.digests, data_digests) {
        result.source.digests = Some(InputDigests {
            model: m.clone(),
            tables: tables.clone(),
            data,
        });
    }
    match label {
        Some(label) => format!("{model_name} with {label}"),
        None => format!("campaign {model_name}"),
    }
}

/// The model as messages name it: its file, or `the model`.
pub(crate) fn model_label(model: &PyModel) -> String {
    model
        .path
        .as_ref()
        .map_or("the model".into(), |p| p.display().to_string())
}

/// What the worker thread found.
struct Searched {
    result: IdentificationResult,
    fitted: Fitted,
    notes: Vec<String>,
    /// The data's label (one record's file or table; `None`: a campaign).
    label: Option<String>,
    /// The data files' digests, when every datum is a file.
    data_digests: Option<Vec<String>>,
}

/// The data of a run: one record, or a campaign's experiments (those
/// given by name, the others from the files the model names).
enum Input {
    Single(Source),
    Campaign(Vec<(String, Source)>),
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
        fitted: Fitted::Single(measured.response),
        notes,
        label: Some(source.label()),
        data_digests: data_digest.map(|d| vec![d]),
    })
}

/// A campaign's run on the worker thread, as `rfeid identify` runs a model
/// with `[[experiment]]` entries: every experiment's data read
/// ([`read_campaign`]), the fitted ones searched together, the validation
/// ones simulated at the estimate ([`record_experiments`]).
fn search_campaign(
    model: &Model,
    label: &str,
    given: Vec<(String, Source)>,
    options: &SearchOptions,
    cancel: &Cancel,
    progress: &Counters,
) -> PyResult<Searched> {
    let data = read_campaign(model, label, given).map_err(campaign_error)?;
    let data_digests = data
        .files()
        .map(|files| {
            files
                .iter()
                .map(|f| file_digest(f))
                .collect::<Result<Vec<_>, _>>()
        })
        .transpose()
        .map_err(data_error)?;
    let prepared =
        prepare_campaign(model, label, &data, options, cancel).map_err(campaign_error)?;
    let mut notes = data.notes.clone();
    notes.extend(prepared.warnings.iter().map(|w| format!("warning: {w}")));
    let mut result =
        run_pipeline(prepared.problem, &prepared.settings, progress).map_err(identify_error)?;
    record_experiments(&mut result, model, &data).map_err(campaign_error)?;
    Ok(Searched {
        result,
        fitted: Fitted::Campaign(data),
        notes,
        label: None,
        data_digests,
    })
}

/// The data of a run from the keywords: `data` for a model without
/// experiments, `experiments` (name → data, each optional) for a campaign.
fn input(
    model: &Model,
    label: &str,
    data: Option<DataArg<'_>>,
    experiments: Vec<(String, DataArg<'_>)>,
) -> PyResult<Input> {
    if model.experiments.is_empty() {
        if !experiments.is_empty() {
            return Err(data_error(format!(
                "data per experiment: {label} lists no [[experiment]]; give one data set as `data`"
            )));
        }
        let data = data.ok_or_else(|| {
            PyValueError::new_err(format!(
                "data: needed, as {label} lists no [[experiment]] with data files of its own"
            ))
        })?;
        return Ok(Input::Single(data.source()?));
    }
    if data.is_some() {
        return Err(data_error(format!(
            "data: {label} lists [[experiment]] entries, which name their own data files; give \
             data per experiment (a dict of experiment name to data), or none"
        )));
    }
    let given = experiments
        .iter()
        .map(|(name, d)| Ok((name.clone(), d.source()?)))
        .collect::<PyResult<_>>()?;
    Ok(Input::Campaign(given))
}

/// Identifies `model`'s parameters from `data`: the library's options,
/// `set` fixed, the data read and matched, the run prepared and searched,
/// the result's source recorded, as `rfeid identify` does. A model with
/// `[[experiment]]` entries is a campaign: `data` is then `None` and
/// `experiments` gives data by experiment name in place of the files the
/// model names. `options` holds the search's keywords ([`OptionsArg`]:
/// `from` in s, `window` a fraction of the record, `jacobian_memory` MiB,
/// `profiles` the parameters to profile after the bounds, empty: every
/// one); `tolerance` is a relative RMS error, `substeps` steps per sample;
/// `progress(done, total, search, searches, iteration, J)` is called every
/// 50 ms and once at the end. Returns the result and the notes of the
/// reading.
#[pyfunction]
#[pyo3(signature = (model, data, *, set, options, tolerance, substeps, progress,
    experiments=Vec::new()))]
#[allow(clippy::too_many_arguments)]
pub fn identify(
    py: Python<'_>,
    model: &PyModel,
    data: Option<DataArg<'_>>,
    set: Vec<String>,
    options: OptionsArg,
    tolerance: Option<f64>,
    substeps: Option<usize>,
    progress: Option<Bound<'_, PyAny>>,
    experiments: Vec<(String, DataArg<'_>)>,
) -> PyResult<(PyIdentification, Vec<String>)> {
    let options = options.options()?;
    let fixed = set_values::fixed(model.model.clone(), &set).map_err(setting_error)?;
    let edited = set_values::stepped(fixed, tolerance, substeps).map_err(setting_error)?;
    let label = model_label(model);
    let input = input(&edited, &label, data, experiments)?;
    let cancel = Cancel::new();
    let counters = Counters::default();
    let pool = super::shards::pool(options.threads)?;
    let searched = watched(py, &cancel, &counters, progress.as_ref(), || {
        pool.install(|| match input {
            Input::Single(source) => search(&edited, &source, &options, &cancel, &counters),
            Input::Campaign(given) => {
                search_campaign(&edited, &label, given, &options, &cancel, &counters)
            }
        })
    })??;
    let Searched {
        mut result,
        fitted,
        notes,
        label,
        data_digests,
    } = searched;
    let title = record_source(&mut result, model, label, data_digests, set);
    let identification = PyIdentification {
        result,
        model: edited,
        fitted,
        title,
    };
    Ok((identification, notes))
}

/// Each search option's default, by the option's name (the library's
/// [`rfeid::identification::options::defaults`]): the package's keyword
/// defaults are read from here, so they are the command line's.
#[pyfunction]
pub fn search_defaults(py: Python<'_>) -> PyResult<Bound<'_, pyo3::types::PyDict>> {
    use rfeid::identification::options::{defaults, DefaultValue};
    let d = pyo3::types::PyDict::new(py);
    for (name, value) in defaults() {
        match value {
            DefaultValue::Count(n) => d.set_item(name, n)?,
            DefaultValue::Seconds(x) => d.set_item(name, x)?,
            DefaultValue::Name(text) => d.set_item(name, text)?,
        }
    }
    Ok(d)
}
