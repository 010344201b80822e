//! The result of `identify`: RESULT.json's document, and the report.
use super::data::f64_bytes;
use super::errors::{failed, model_error};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use rfeid::identification::campaign::CampaignData;
use rfeid::identification::result::EstimateError;
use rfeid::identification::result::IdentificationResult;
use rfeid::identification::verdict::Outcome;
use rfeid::io::report_dir::{write_report as write_report_dir, ReportDirError};
use rfeid::model::Model;
use rfeid::report::at_estimate::{render, render_campaign, RenderError};
use rfeid::simulation::{steps::integrator, Response, Simulator, Workspace};
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

/// One fitted record at the estimate for Python: (experiment, sensor
/// names, their SI units, the sample rate in Hz, the first time fitted in
/// s, time in s, measured, fitted), the arrays as little-endian f64 bytes,
/// the signals sensor by sensor.
type Signals<'py> = (
    String,
    Vec<String>,
    Vec<&'static str>,
    f64,
    f64,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
);

/// A fitted record with the model's response at the estimate: (experiment,
/// sensors, units, sample rate, from, time, measured, fitted), the signals
/// sensor by sensor on the samples both have.
type AtEstimate = (
    String,
    Vec<String>,
    Vec<&'static str>,
    f64,
    f64,
    Vec<f64>,
    Vec<f64>,
    Vec<f64>,
);

/// `model`'s record at the estimate as `AtEstimate`: `measured` and
/// `fitted` cut to the samples both have.
fn at_estimate_record(
    experiment: &str,
    model: &Model,
    from: f64,
    measured: &Response,
    fitted: &Response,
) -> AtEstimate {
    let n = measured.n_samples.min(fitted.n_samples);
    let cut = |r: &Response| -> Vec<f64> {
        (0..r.n_sensors)
            .flat_map(|c| r.sensor(c)[..n].iter().copied())
            .collect()
    };
    (
        experiment.to_string(),
        model.sensors.iter().map(|s| s.name.clone()).collect(),
        model.sensors.iter().map(|s| s.kind.unit()).collect(),
        model.sampling.sample_rate,
        from,
        (0..n).map(|k| model.sampling.time(k)).collect(),
        cut(measured),
        cut(fitted),
    )
}

impl PyIdentification {
    /// The fitted records with the model simulated at the estimate as the
    /// report simulates it ([`render`], [`render_campaign`]): one record
    /// with the steps the identification ended with, or each fitted
    /// experiment of a campaign on its own model, with steps chosen there.
    fn at_estimate(&self) -> Result<Vec<AtEstimate>, RenderError> {
        match &self.fitted {
            Fitted::Single(measured) => {
                let params = self
                    .result
                    .parameter_values(&self.model, "")
                    .map_err(RenderError::Parameters)?;
                let sim = match &self.result.simulation {
                    Some(steps) => {
                        Simulator::with_integrator(&self.model, integrator(steps.substeps))
                    }
                    None => Simulator::new(&self.model),
                };
                let mut fitted = sim.response_buffer();
                sim.run(&params, &mut Workspace::default(), &mut fitted)?;
                let from = self.result.from;
                Ok(vec![at_estimate_record(
                    "",
                    &self.model,
                    from,
                    measured,
                    &fitted,
                )])
            }
            Fitted::Campaign(data) => self
                .model
                .fitted_experiments()
                .into_iter()
                .map(|e| {
                    let name = self.model.experiments[e].name.as_str();
                    let (fitted, _) = self
                        .result
                        .simulate_at_estimate(&data.models[e], name)
                        .map_err(|e| match e {
                            EstimateError::NotInModel(m) => RenderError::Parameters(m),
                            EstimateError::Simulation(s) => RenderError::Simulation(s),
                        })?;
                    let from = self
                        .result
                        .experiments
                        .iter()
                        .find(|x| x.name == name)
                        .map_or(self.model.experiments[e].from, |x| x.from);
                    let measured = &data.measured[e];
                    Ok(at_estimate_record(
                        name,
                        &data.models[e],
                        from,
                        measured,
                        &fitted,
                    ))
                })
                .collect(),
        }
    }

    /// The report's files (name, text), rendered as `rfeid identify
    /// --report` renders them.
    fn render_files(&self) -> Result<Vec<(String, String)>, RenderError> {
        match &self.fitted {
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
        }
    }

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
        let files = self.report_files(py)?;
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

    /// The report's files as (name, text), report.html and its SVG
    /// figures, rendered as [`PyIdentification::report`] writes them but
    /// not written.
    fn report_files(&self, py: Python<'_>) -> PyResult<Vec<(String, String)>> {
        py.detach(|| self.render_files()).map_err(render_error)
    }

    /// The fitted records with the model simulated at the estimate, as the
    /// report shows them: one record, or each fitted experiment of a
    /// campaign in the model's order. Each is (experiment (`""` for one
    /// record), sensor names, their SI units, the sample rate in Hz, the
    /// first time fitted in s, time in s, measured, fitted), the arrays as
    /// little-endian f64 bytes, the signals sensor by sensor (SI).
    fn signals<'py>(&self, py: Python<'py>) -> PyResult<Vec<Signals<'py>>> {
        let records = py.detach(|| self.at_estimate()).map_err(render_error)?;
        let bytes = |v: &[f64]| PyBytes::new(py, &f64_bytes(v));
        Ok(records
            .into_iter()
            .map(|(e, names, units, rate, from, t, y, g)| {
                (e, names, units, rate, from, bytes(&t), bytes(&y), bytes(&g))
            })
            .collect())
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

/// A report or simulation at the estimate that failed: a simulation's
/// failure an `IdentificationError`, a result that does not fit the model
/// a `ModelError`.
fn render_error(e: RenderError) -> PyErr {
    match e {
        RenderError::Simulation(_) => failed(e),
        _ => model_error(e),
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
