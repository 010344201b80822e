//! `design`: `rfeid design` from Python (SPEC §6): predicted standard
//! errors of a planned test, and the D-optimal choice of candidate sensors.
use super::errors::{model_error, option_error, py_error, setting_error, simulation_error};
use super::model::PyModel;
use super::result::write_report;
use super::watch::{watched, Counters};
use pyo3::prelude::*;
use rfeid::design::json::{at_values, check_request, design_json};
use rfeid::design::{design as run_design, Design, DesignError, DesignSettings};
use rfeid::identification::cancel::Cancel;
use rfeid::identification::options::{check_threads, Spelling};
use rfeid::model::{set_values, Model};
use std::path::PathBuf;

/// A design with its model, for the report.
#[pyclass(name = "Design", module = "rfeid._rfeid", frozen)]
pub struct PyDesign {
    model: Model,
    design: Design,
    title: String,
    /// The model file and its tables, which the report must not replace.
    inputs: Vec<PathBuf>,
}

#[pymethods]
impl PyDesign {
    /// Returns the design as `rfeid design -o` writes it (JSON text, SI
    /// values).
    fn to_json(&self) -> PyResult<String> {
        let value = design_json(&self.model, &self.design);
        serde_json::to_string_pretty(&value)
            .map(|t| t + "\n")
            .map_err(super::errors::failed)
    }

    /// Writes the HTML report (the candidates on the bodies, the predicted
    /// standard errors) into `dir` by the rules of `rfeid design --report
    /// DIR` ([`write_report`]); returns report.html's path.
    fn report(&self, dir: PathBuf) -> PyResult<PathBuf> {
        let files =
            rfeid::report::design::design_report_files(&self.model, &self.design, &self.title);
        write_report(&dir, &files, &self.inputs)
    }
}

/// Designs a test of `model` as `rfeid design` does: `set` (`NAME=VALUE`)
/// inside the box, `choose` candidates added, `over_box` LP_τ points,
/// `threads` worker threads (all cores by default). Returns (the design,
/// the notes of the settings).
#[pyfunction]
#[pyo3(signature = (model, *, set, choose, over_box, threads))]
pub fn design(
    py: Python<'_>,
    model: &PyModel,
    set: Vec<String>,
    choose: Option<usize>,
    over_box: Option<usize>,
    threads: Option<usize>,
) -> PyResult<(PyDesign, Vec<String>)> {
    let label = model
        .path
        .as_ref()
        .map_or("the model".into(), |p| p.display().to_string());
    check_threads(threads).map_err(|e| option_error(&e))?;
    check_request(&model.model, &label, choose, over_box).map_err(py_error)?;
    let mut values = model.model.nominal();
    let notes: Vec<String> = set_values::apply_sets_to_campaign(&model.model, &set, &mut values)
        .map_err(setting_error)?
        .iter()
        .map(|w| w.spelt(Spelling::Keyword))
        .collect();
    let at = at_values(model.model.clone(), values).map_err(py_error)?;
    let cancel = Cancel::new();
    let settings = DesignSettings {
        choose,
        over_box,
        cancel: cancel.clone(),
        ..Default::default()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| super::errors::failed(format!("could not start the worker threads: {e}")))?;
    let found = watched(py, &cancel, &Counters::default(), None, || {
        pool.install(|| run_design(&at, &settings, &|| {}))
    })?
    .map_err(|e| match e {
        DesignError::Simulation(s) => simulation_error("simulating at the parameters' values", &s),
        DesignError::EveryPointFailed { .. } => super::errors::failed(e),
        DesignError::Cancelled => super::errors::failed(e),
        DesignError::Option(o) => model_error(format!("{label}: {}", o.spelt(Spelling::Keyword))),
        other => model_error(format!("{label}: {other}")),
    })?;
    let inputs = model
        .path
        .iter()
        .cloned()
        .chain(model.model.files.iter().cloned());
    let design = PyDesign {
        inputs: inputs.collect(),
        model: at,
        design: found,
        title: label,
    };
    Ok((design, notes))
}
