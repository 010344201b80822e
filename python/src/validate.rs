//! A result on its own: `validate` (an identification checked on other
//! data, as `rfeid validate --json` does) and an identification rebuilt
//! from a RESULT.json with its model and data (`Identification.load`).
use super::data::{DataArg, Source};
use super::errors::{campaign_error, data_error, model_error, py_error, setting_error};
use super::model::PyModel;
use super::result::{Fitted, PyIdentification};
use super::run::model_label;
use pyo3::prelude::*;
use rfeid::identification::campaign::read_campaign;
use rfeid::identification::result::IdentificationResult;
use rfeid::identification::validation::{self, ValidationError};
use rfeid::io::digest::input_digests;
use rfeid::model::{set_values, Model};

/// A RESULT.json's text as a result; `label` names it in the error.
fn parse_result(text: &str, label: &str) -> PyResult<IdentificationResult> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    serde_json::from_str(text).map_err(|e| data_error(format!("{label}: not an rfeid result: {e}")))
}

/// The model with the result's `set` values fixed, checked to be the
/// result's model.
fn model_of(model: &PyModel, result: &IdentificationResult, label: &str) -> PyResult<Model> {
    let fixed =
        set_values::fixed(model.model.clone(), &result.source.set).map_err(setting_error)?;
    let model_label = model_label(model);
    validation::check_belongs(&fixed, result, &model_label, label).map_err(model_error)?;
    Ok(fixed)
}

/// Checks the result (RESULT.json's text, `label` naming it) on data:
/// `data` (on the model, or on `experiment`'s model when named), else
/// the named experiment's data file, else every experiment's; `from_` (s)
/// the first time compared. Returns (the fits as `rfeid validate --json`
/// writes them, as JSON text; the reading's notes).
#[pyfunction]
#[pyo3(signature = (model, result, label, data=None, experiment=None, from_=None))]
pub fn validate(
    py: Python<'_>,
    model: &PyModel,
    result: &str,
    label: &str,
    data: Option<DataArg<'_>>,
    experiment: Option<String>,
    from_: Option<f64>,
) -> PyResult<(String, Vec<String>)> {
    let result = parse_result(result, label)?;
    let fixed = model_of(model, &result, label)?;
    let source = data.map(|d| d.source()).transpose()?;
    let model_label = model_label(model);
    let (json, notes) = py
        .detach(|| {
            let (cases, notes) = validation::cases(
                &fixed,
                &model_label,
                source.as_ref(),
                experiment.as_deref(),
                from_,
            )?;
            let fits = cases
                .iter()
                .map(|c| validation::fits(&fixed, &result, c).map(|(f, _)| f))
                .collect::<Result<Vec<_>, _>>()?;
            let json = serde_json::to_string(&fits).expect("fits serialise");
            Ok::<_, ValidationError>((json, notes))
        })
        .map_err(py_error)?;
    Ok((json, notes))
}

/// An identification rebuilt from RESULT.json's text (`label` naming it)
/// with its model and data: `data` for one record, or `None` for a
/// campaign (the experiments' files). Returns it with notes: a warning
/// when an input no longer holds what the result records.
#[pyfunction]
#[pyo3(signature = (result, label, model, data=None))]
pub fn load_result(
    py: Python<'_>,
    result: &str,
    label: &str,
    model: &PyModel,
    data: Option<DataArg<'_>>,
) -> PyResult<(PyIdentification, Vec<String>)> {
    let result = parse_result(result, label)?;
    let fixed = model_of(model, &result, label)?;
    let source = data.map(|d| d.source()).transpose()?;
    let model_label = model_label(model);
    let (fitted, mut notes, title) = match &source {
        Some(s) => {
            let read = py.detach(|| s.measured(&fixed)).map_err(data_error)?;
            let title = format!("{model_label} with {}", s.label());
            (Fitted::Single(read.response), read.notes, title)
        }
        None if !fixed.experiments.is_empty() => {
            let data = py
                .detach(|| read_campaign(&fixed, &model_label, Vec::new()))
                .map_err(campaign_error)?;
            let notes = data.notes.clone();
            (Fitted::Campaign(data), notes, format!("campaign {model_label}"))
        }
        None => {
            return Err(data_error(format!(
                "{label}: data needed, as {model_label} lists no [[experiment]] with data files of its own"
            )))
        }
    };
    notes.extend(changed(model, &fixed, &result, source.as_ref()));
    let identification = PyIdentification {
        result,
        model: fixed,
        fitted,
        title,
    };
    Ok((identification, notes))
}

/// A warning when the model file, its tables or the data files no longer
/// hold what the result records (nothing to compare for a model from a
/// text, data from a table, or a result without digests).
fn changed(
    model: &PyModel,
    fixed: &Model,
    result: &IdentificationResult,
    source: Option<&Source>,
) -> Option<String> {
    let (recorded, path) = (result.source.digests.as_ref()?, model.path.as_ref()?);
    let data: Vec<_> = match source {
        Some(s) => vec![s.file()?.to_path_buf()],
        None => fixed.experiments.iter().map(|x| x.data.clone()).collect(),
    };
    let now = input_digests(path, fixed, &data).ok()?;
    (&now != recorded).then(|| {
        "warning: the model file, its signal tables or the data are not what the result was \
         computed with: the report and FRFs use the files as they are now"
            .to_string()
    })
}
