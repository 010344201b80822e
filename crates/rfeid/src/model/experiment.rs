//! The tests of a campaign (SPEC §5): each [`Experiment`] shares the model
//! and its parameters, and has its own data and whatever differs between
//! tests (fixed parameters' values, sampling, active excitations, sensors).
use super::Model;
use std::path::PathBuf;

/// What an experiment is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    /// Fitted by `identify`.
    #[default]
    Fit,
    /// Left out of the fit; its fit at the estimate is reported.
    Validation,
}

/// One test of a campaign.
#[derive(Debug, Clone, PartialEq)]
pub struct Experiment {
    /// Unique name; identifies the experiment in reports and in `name[experiment]`.
    pub name: String,
    /// The data file, resolved against the model file's directory.
    pub data: PathBuf,
    /// Values (SI) of fixed parameters in this test: (parameter index, value).
    pub set: Vec<(usize, f64)>,
    /// Start of the fitted part of the record, s.
    pub from: f64,
    /// Record length, s, if it differs from `[simulation]`.
    pub duration: Option<f64>,
    /// Sample rate, Hz, if it differs from `[simulation]`.
    pub sample_rate: Option<f64>,
    /// The model's excitations active in this test (indices); `None`: all.
    pub excitations: Option<Vec<usize>>,
    /// The sensors measured in this test (indices); `None`: all.
    pub sensors: Option<Vec<usize>>,
    /// Fitted or validation.
    pub role: Role,
    /// The weight of this test's residuals in J (eq. 13), default 1.
    pub weight: f64,
}

impl Model {
    /// Index of the experiment with this name.
    pub fn experiment_index(&self, name: &str) -> Option<usize> {
        self.experiments.iter().position(|e| e.name == name)
    }

    /// The model as experiment `e` sees it: its `set` values in the
    /// parameters, its sampling, only its excitations and sensors, and no
    /// experiments of its own. Parameter indices are unchanged.
    pub fn for_experiment(&self, e: usize) -> Model {
        let x = &self.experiments[e];
        let mut m = self.clone();
        m.experiments.clear();
        for &(i, v) in &x.set {
            m.parameters[i].value = v;
        }
        if let Some(d) = x.duration {
            m.sampling.duration = d;
        }
        if let Some(r) = x.sample_rate {
            m.sampling.sample_rate = r;
        }
        if let Some(active) = &x.excitations {
            m.excitations = active
                .iter()
                .map(|&k| self.excitations[k].clone())
                .collect();
        }
        if let Some(sensors) = &x.sensors {
            m.sensors = sensors.iter().map(|&k| self.sensors[k].clone()).collect();
        }
        m
    }

    /// Indices of the experiments that `identify` fits, in file order.
    pub fn fitted_experiments(&self) -> Vec<usize> {
        (0..self.experiments.len())
            .filter(|&e| self.experiments[e].role == Role::Fit)
            .collect()
    }
}
