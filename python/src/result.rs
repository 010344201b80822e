//! The result of `identify`: RESULT.json's document, and the report.
use super::errors::{failed, model_error};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use rfeid::identification::campaign::CampaignData;
use rfeid::identification::result::IdentificationResult;
use rfeid::identification::verdict::Outcome;
use rfeid::io::report_dir::{write_report as write_report_dir, ReportDirError};
use rfeid::model::Model;
use rfeid::report::at_estimate::{render, render_campaign, RenderError};
use rfeid::simulation::Response;
use std::path::{Path, PathBuf};

/// An identification's result with what its report needs.
#[pyclass(name = "Identification", module = "rfeid._rfeid", frozen)]
pub struct PyIdentification {
    /// The result.
    pub result: IdentificationResult,
    /// The model identified (with `set` fixed).
    pub model: Model,
    /// The data fitted: one record, or a campaign's experiments.
    pub fitted: Fitted,
    /// The report's title.
    pub title: String,
}

/// The data an identification fitted.
pub enum Fitted {
    /// One record's measured signals.
    Single(Response),
    /// A campaign's experiments (SPEC §5).
    Campaign(CampaignData),
}

impl PyIdentification {
    /// The model, experiment name and measured signals an FRF compares
    /// with: the record, or a campaign's first fitted experiment.
    fn frf_data(&self) -> (&Model, &str, &Response) {
        match &self.fitted {
            Fitted::Single(measured) => (&self.model, "", measured),
            Fitted::Campaign(data) => {
                let e = self
                    .model
                    .fitted_experiments()
                    .first()
                    .copied()
                    .unwrap_or(0);
                let name = self.model.experiments[e].name.as_str();
                (&data.models[e], name, &data.measured[e])
            }
        }
    }
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

    /// Writes the HTML report (report.html and its SVG figures) into `dir`
    /// by the rules of `rfeid identify --report DIR` ([`write_report`]);
    /// returns report.html's path.
    fn report(&self, py: Python<'_>, dir: PathBuf) -> PyResult<PathBuf> {
        let files = py
            .detach(|| match &self.fitted {
                Fitted::Single(measured) => {
                    render(&self.model, &self.result, "", measured, None, &self.title)
                }
                Fitted::Campaign(data) => render_campaign(
                    &self.model,
                    &data.models,
                    &self.result,
                    &data.measured,
                    &self.title,
                ),
            })
            .map_err(|e| match e {
                RenderError::Simulation(_) => failed(e),
                _ => model_error(e),
            })?;
        let source = &self.result.source;
        let inputs: Vec<PathBuf> = [&source.model, &source.data]
            .into_iter()
            .flatten()
            .map(PathBuf::from)
            .chain(self.model.files.iter().cloned())
            .chain(self.model.experiments.iter().map(|x| x.data.clone()))
            .collect();
        write_report(&dir, &files, &inputs)
    }

    /// FRFs of the model linearised at rest (or at its static equilibrium
    /// under gravity) at the estimate, from each excitation to each sensor,
    /// with the 95 % band from the estimate's covariance (delta method), and
    /// with `measured` the H1 and coherence of the identification's data
    /// (Welch, `segment` samples per segment). Frequencies in Hz: `fmin`,
    /// `fmax` (default the Nyquist frequency), `points` (default: fine
    /// enough for the sharpest mode), `spacing` `"log"` or `"linear"`.
    /// Returns (the study as JSON text, the figure as SVG text or None).
    #[pyo3(signature = (fmin=None, fmax=None, points=None, spacing="log", segment=None, measured=true))]
    #[allow(clippy::too_many_arguments)]
    fn frf(
        &self,
        py: Python<'_>,
        fmin: Option<f64>,
        fmax: Option<f64>,
        points: Option<usize>,
        spacing: &str,
        segment: Option<usize>,
        measured: bool,
    ) -> PyResult<(String, Option<String>)> {
        let bad = |m: String| pyo3::exceptions::PyValueError::new_err(m);
        let spacing = match spacing {
            "log" => rfeid::frf::Spacing::Log,
            "linear" => rfeid::frf::Spacing::Linear,
            s => return Err(bad(format!("spacing {s:?}: \"log\" or \"linear\""))),
        };
        let (model, experiment, measured_data) = self.frf_data();
        let nyquist = model.sampling.sample_rate / 2.0;
        let top = fmax.unwrap_or(nyquist);
        if !(top > 0.0 && top.is_finite()) {
            return Err(bad(format!(
                "fmax {top}: must be a positive frequency in Hz"
            )));
        }
        if let Some(f) = fmin.filter(|f| !(*f >= 0.0 && *f < top)) {
            return Err(bad(format!(
                "fmin {f}: must be from 0 to below fmax ({top} Hz)"
            )));
        }
        if let Some(n) = points.filter(|n| !(2..=100_000).contains(n)) {
            return Err(bad(format!("points {n}: must be from 2 to 100 000")));
        }
        let at = rfeid::frf::at_estimate(&self.result, model, experiment).map_err(model_error)?;
        let frequencies = rfeid::frf::grid(model, &at.params, fmin, Some(top), points, spacing);
        let request = rfeid::frf::FrfRequest {
            model,
            params: at.params,
            wrt: at.wrt,
            covariance: at.covariance.ok(),
            excitations: (0..model.excitations.len()).collect(),
            outputs: rfeid::frf::Output::sensors(model),
            frequencies,
        };
        let data = rfeid::frf::DataSet {
            label: "measured",
            model,
            measured: measured_data,
            first: model.sampling.first_sample(self.result.from),
            segment,
            force: None,
        };
        let data = if measured { vec![data] } else { Vec::new() };
        let study = py
            .detach(|| rfeid::frf::study(&request, &data))
            .map_err(|e| match e {
                rfeid::frf::FrfError::Segment { .. } => bad(e.to_string()),
                _ => failed(e),
            })?;
        let json = serde_json::to_string(&study).map_err(failed)?;
        Ok((json, rfeid::report::frf::study_svg(&study)))
    }
}

/// Writes a report's files into `dir` by the rules of `--report DIR`
/// ([`rfeid::io::report_dir::write_report`]): a new directory (its parent
/// must exist) or one holding only an earlier report, replaced as a whole,
/// never one holding an input; returns report.html's path. A directory
/// refused is a `ValueError`, a failed write an `OSError`.
pub fn write_report(
    dir: &Path,
    files: &[(String, String)],
    inputs: &[PathBuf],
) -> PyResult<PathBuf> {
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    write_report_dir(dir, files, &inputs).map_err(|e| match e {
        ReportDirError::Refused { .. } => PyValueError::new_err(e.to_string()),
        ReportDirError::Io { .. } => PyOSError::new_err(e.to_string()),
    })
}
