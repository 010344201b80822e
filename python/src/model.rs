//! `Model`: a model file loaded and validated by the library, its
//! parameters and sensors, and its simulation.
use super::data::f64_bytes;
use super::errors::{model_error, setting_error, simulation_error};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use rfeid::identification::options::Spelling;
use rfeid::io::digest::file_digest;
use rfeid::io::model_file::{load_model_for, parse_model, Purpose};
use rfeid::measurement::simulated::{simulate_record, NoiseSpec, SimulatedError};
use rfeid::model::{set_values, Model};
use std::path::PathBuf;

/// A simulated record for Python: (time, values, n_samples, n_sensors,
/// warnings), the arrays as little-endian f64 bytes, values sensor by sensor.
type Record<'py> = (
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    usize,
    usize,
    Vec<String>,
);

/// A model file, loaded and validated.
#[pyclass(name = "Model", module = "rfeid._rfeid", frozen)]
pub struct PyModel {
    /// The model.
    pub model: Model,
    /// The file it came from, if any.
    pub path: Option<PathBuf>,
    /// The digests of the file and of its signal tables when it was
    /// loaded, which a result records ([`rfeid::io::digest`]).
    pub digests: Option<(String, Vec<String>)>,
}

impl PyModel {
    /// [`PyModel::load`] for `purpose`, with the digests of the file and
    /// its tables.
    fn load_for(path: PathBuf, purpose: Purpose) -> PyResult<Self> {
        let model = load_model_for(&path, purpose).map_err(model_error)?;
        let tables = model.files.iter().map(|f| file_digest(f));
        let digests = (
            file_digest(&path).map_err(model_error)?,
            tables.collect::<Result<_, _>>().map_err(model_error)?,
        );
        Ok(PyModel {
            model,
            path: Some(path),
            digests: Some(digests),
        })
    }
}

#[pymethods]
impl PyModel {
    /// Loads a model file (TOML; docs/reference/model-file.md) and returns
    /// the Model. Raises ModelError naming the file, entry and field (a
    /// missing file too).
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        Self::load_for(path, Purpose::Measure)
    }

    /// Loads a model file for a design (`rfeid.design(path, …)`): its
    /// sensors may all be candidates, before a first test.
    #[staticmethod]
    fn load_for_design(path: PathBuf) -> PyResult<Self> {
        Self::load_for(path, Purpose::Design)
    }

    /// A model from the text of a model file; relative paths in it (signal
    /// tables) are found from `base_dir` (default: the current directory).
    /// Returns the Model; raises ModelError.
    #[staticmethod]
    #[pyo3(signature = (text, base_dir = None))]
    fn from_toml(text: &str, base_dir: Option<PathBuf>) -> PyResult<Self> {
        let base = base_dir.unwrap_or_else(|| PathBuf::from("."));
        let model = parse_model(text, &base.join("<text>")).map_err(model_error)?;
        Ok(PyModel {
            model,
            path: None,
            digests: None,
        })
    }

    /// The file the model came from (`None` for a text).
    #[getter]
    fn path(&self) -> Option<PathBuf> {
        self.path.clone()
    }

    /// What the reading noted (a table's time axis taken on the grid, say).
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.model.notes.clone()
    }

    /// The parameters, each a dict: name, value, min, max (SI; `None` for a
    /// fixed one), unit (as the file wrote it; "" for a bare number),
    /// unit_scale (one such unit in SI), scale ("linear" or "log"),
    /// dimension (the SI unit as text), identified, per_experiment.
    #[getter]
    fn parameters<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.model
            .parameters
            .iter()
            .map(|p| {
                let d = PyDict::new(py);
                d.set_item("name", &p.name)?;
                d.set_item("value", p.value)?;
                d.set_item("min", p.bounds.map(|b| b.0))?;
                d.set_item("max", p.bounds.map(|b| b.1))?;
                d.set_item("unit", &p.unit.symbol)?;
                d.set_item("unit_scale", p.unit.scale)?;
                d.set_item("scale", p.scale.as_str())?;
                d.set_item("dimension", p.dimension.to_string())?;
                d.set_item("identified", p.bounds.is_some())?;
                d.set_item("per_experiment", p.per_experiment)?;
                Ok(d)
            })
            .collect()
    }

    /// The experiments of a campaign (SPEC §5), in the model's order, as
    /// (name, role, data file): role `"fit"` or `"validation"`, the file
    /// resolved against the model file's directory. Empty for a model
    /// without `[[experiment]]` entries.
    #[getter]
    fn experiments(&self) -> Vec<(String, &'static str, PathBuf)> {
        use rfeid::model::Role;
        self.model
            .experiments
            .iter()
            .map(|x| {
                let role = match x.role {
                    Role::Fit => "fit",
                    Role::Validation => "validation",
                };
                (x.name.clone(), role, x.data.clone())
            })
            .collect()
    }

    /// The sensors (names, SI units) experiment `name` measures, `None`
    /// when the model has no such experiment.
    fn experiment_sensors(&self, name: &str) -> Option<(Vec<String>, Vec<&'static str>)> {
        let m = self
            .model
            .for_experiment(self.model.experiment_index(name)?);
        Some((
            m.sensors.iter().map(|s| s.name.clone()).collect(),
            m.sensors.iter().map(|s| s.kind.unit()).collect(),
        ))
    }

    /// The sensors' names, in the model's order.
    #[getter]
    fn sensor_names(&self) -> Vec<String> {
        self.model.sensors.iter().map(|s| s.name.clone()).collect()
    }

    /// The sensors' SI units ("m", "m/s" or "m/s^2"), in the model's order.
    #[getter]
    fn sensor_units(&self) -> Vec<&'static str> {
        self.model.sensors.iter().map(|s| s.kind.unit()).collect()
    }

    /// The sample rate, Hz.
    #[getter]
    fn sample_rate(&self) -> f64 {
        self.model.sampling.sample_rate
    }

    /// The record's length, s.
    #[getter]
    fn duration(&self) -> f64 {
        self.model.sampling.duration
    }

    /// The number of samples in the record: round(duration × sample_rate).
    #[getter]
    fn n_samples(&self) -> usize {
        self.model.sampling.n_samples()
    }

    /// Simulates at the nominal values with `set` (`NAME=VALUE`) applied,
    /// as `rfeid simulate` does: returns (time, values, n_samples,
    /// n_sensors, warnings), the arrays as little-endian f64 bytes, values
    /// sensor by sensor; time in s, values in the sensors' SI units.
    /// `noise` is a fraction of each sensor's RMS, `noise_corner` in Hz,
    /// `tolerance` a relative RMS error (1e-13 to 1e-2), `substeps` steps
    /// per sample; `experiment` a campaign's experiment, whose settings,
    /// sampling, excitations and sensors are simulated (`--experiment`).
    #[pyo3(signature = (set, noise, noise_corner, seed, tolerance, substeps, experiment=None))]
    #[allow(clippy::too_many_arguments)]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        set: Vec<String>,
        noise: Option<f64>,
        noise_corner: Option<f64>,
        seed: u64,
        tolerance: Option<f64>,
        substeps: Option<usize>,
        experiment: Option<String>,
    ) -> PyResult<Record<'py>> {
        let base = match &experiment {
            None => self.model.clone(),
            Some(name) => {
                let e = self.model.experiment_index(name).ok_or_else(|| {
                    let known: Vec<&str> = self
                        .model
                        .experiments
                        .iter()
                        .map(|x| x.name.as_str())
                        .collect();
                    pyo3::exceptions::PyValueError::new_err(format!(
                        "experiment='{name}': the model has no such [[experiment]] ({})",
                        match known.is_empty() {
                            true => "it has none".to_string(),
                            false => format!("experiments: {}", known.join(", ")),
                        }
                    ))
                })?;
                self.model.for_experiment(e)
            }
        };
        let model = set_values::stepped(base, tolerance, substeps).map_err(setting_error)?;
        let mut params = model.nominal();
        let warnings: Vec<String> = set_values::apply_sets(&model, &set, &mut params)
            .map_err(setting_error)?
            .iter()
            .map(|w| w.spelt(Spelling::Keyword))
            .collect();
        let spec = noise.map(|fraction| NoiseSpec {
            fraction,
            corner: noise_corner,
            seed,
        });
        let record = py
            .detach(|| simulate_record(&model, &params, spec.as_ref()))
            .map_err(|e| simulated_error(&e))?;
        let n = record.response.n_samples;
        let time: Vec<f64> = (0..n).map(|k| model.sampling.time(k)).collect();
        Ok((
            PyBytes::new(py, &f64_bytes(&time)),
            PyBytes::new(py, &f64_bytes(&record.response.values)),
            n,
            record.response.n_sensors,
            warnings,
        ))
    }

    fn __repr__(&self) -> String {
        let m = &self.model;
        format!(
            "<rfeid.Model {}: {} bodies, {} elements, {} parameters ({} identified), {} sensors, {} samples at {} Hz>",
            self.path
                .as_ref()
                .map_or("(text)".to_string(), |p| p.display().to_string()),
            m.bodies.len(),
            m.elements.len(),
            m.parameters.len(),
            m.identified().len(),
            m.sensors.len(),
            m.sampling.n_samples(),
            m.sampling.sample_rate
        )
    }
}

/// A simulated record's failure as an exception.
fn simulated_error(e: &SimulatedError) -> PyErr {
    match e {
        SimulatedError::Steps(s) => simulation_error("choosing the integrator's steps", s),
        SimulatedError::Option(o) => super::errors::option_error(o),
    }
}
