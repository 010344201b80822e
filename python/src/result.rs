//! The result of `identify`: RESULT.json's document, and the report.
use super::errors::{failed, model_error};
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use rfeid::identification::result::IdentificationResult;
use rfeid::identification::verdict::Outcome;
use rfeid::io::atomic::write_atomically;
use rfeid::model::Model;
use rfeid::report::at_estimate::{render, RenderError};
use rfeid::simulation::Response;
use std::io::Write;
use std::path::{Path, PathBuf};

/// An identification's result with what its report needs.
#[pyclass(name = "Identification", module = "rfeid._rfeid", frozen)]
pub struct PyIdentification {
    /// The result.
    pub result: IdentificationResult,
    /// The model identified (with `set` fixed).
    pub model: Model,
    /// The measured signals.
    pub measured: Response,
    /// The report's title.
    pub title: String,
}

#[pymethods]
impl PyIdentification {
    /// Returns the result as RESULT.json holds it (JSON text, SI values).
    fn to_json(&self) -> PyResult<String> {
        self.result.to_json_text().map_err(failed)
    }

    /// The verdict (docs/reference/verdict.md) as (outcome, reasons): the outcome
    /// `"trustworthy"`, `"suspect"` or `"model error"`, each reason in
    /// words; `None` when no verdict was reached.
    fn verdict(&self) -> Option<(&'static str, Vec<String>)> {
        let v = self.result.verdict.as_ref()?;
        let outcome = match v.outcome() {
            Outcome::Trustworthy => "trustworthy",
            Outcome::Suspect => "suspect",
            Outcome::ModelError => "model error",
        };
        Some((outcome, v.reasons.iter().map(|r| r.to_string()).collect()))
    }

    /// Writes the HTML report (report.html and its SVG figures) into `dir`,
    /// created if missing (its parent must exist); returns report.html's
    /// path.
    fn report(&self, py: Python<'_>, dir: PathBuf) -> PyResult<PathBuf> {
        let files = py
            .detach(|| {
                render(
                    &self.model,
                    &self.result,
                    "",
                    &self.measured,
                    None,
                    &self.title,
                )
            })
            .map_err(|e| match e {
                RenderError::Simulation(_) => failed(e),
                _ => model_error(e),
            })?;
        write_report(&dir, &files)
    }
}

/// Writes a report's files into `dir` (created if missing; its parent must
/// exist), each whole or not at all; returns report.html's path.
pub fn write_report(dir: &Path, files: &[(String, String)]) -> PyResult<PathBuf> {
    let io = |e: std::io::Error| PyOSError::new_err(format!("{}: {e}", dir.display()));
    if !dir.is_dir() {
        std::fs::create_dir(dir).map_err(io)?;
    }
    for (name, text) in files {
        write_atomically(&dir.join(name), |w| w.write_all(text.as_bytes())).map_err(io)?;
    }
    Ok(dir.join("report.html"))
}
