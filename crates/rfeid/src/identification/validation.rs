//! An identification checked on other data (`rfeid validate`, the Python
//! module's `validate`): the model simulated at the estimate, with steps
//! chosen there, and compared with the data sensor by sensor by the
//! normalised RMS fit the verdict also uses (MATLAB `compare`'s).
use crate::identification::campaign::{read_experiment, CampaignError};
use crate::identification::options::OptionError;
use crate::identification::result::{EstimateError, IdentificationResult};
use crate::measurement::fit_percent;
use crate::measurement::measured::{MeasuredError, Source};
use crate::model::{ColumnName, Model, Role};
use crate::simulation::Response;
use serde::{Deserialize, Serialize};

/// Why a validation cannot be done.
#[derive(Debug, thiserror::Error)]
pub enum ValidationError {
    /// An option (`from`, `experiment`, `data`) that cannot be used.
    #[error(transparent)]
    Option(#[from] OptionError),
    /// The result is not of this model.
    #[error("{result}: field 'parameters': {message}")]
    NotOfModel {
        /// The result (its file, or `the result`).
        result: String,
        /// What does not belong.
        message: String,
    },
    /// An experiment's data cannot be read.
    #[error(transparent)]
    Experiment(#[from] CampaignError),
    /// The data given cannot be read.
    #[error(transparent)]
    Data(#[from] MeasuredError),
    /// The model could not be simulated at the estimate.
    #[error("simulating at the estimate: {0}")]
    Estimate(#[from] EstimateError),
}

/// One data set to compare with the model at the estimate.
#[derive(Debug, Clone)]
pub struct Case {
    /// The experiment's name (`""` for data of a model without
    /// experiments, or data given without an experiment).
    pub experiment: String,
    /// Its model (the experiment's settings applied).
    pub model: Model,
    /// Its measured signals.
    pub measured: Response,
    /// The first sample compared.
    pub first: usize,
}

/// The fits of one data set: what `rfeid validate --json` writes for it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Fits {
    /// The experiment (`""` for data of their own).
    pub experiment: String,
    /// `fit` or `validation` for an experiment of the model file.
    pub role: Option<String>,
    /// The sensors, in the model's order.
    pub sensors: Vec<String>,
    /// Normalised RMS fit per sensor in % (none for a constant signal).
    pub fit_percent: Vec<Option<f64>>,
}

/// The result must be of this model: every estimated parameter (by name,
/// `name[experiment]` for one identified per experiment) one of its
/// parameters, listed once, and every parameter the model identifies
/// estimated. `label` names the result, `model_label` the model.
pub fn check_belongs(
    model: &Model,
    result: &IdentificationResult,
    model_label: &str,
    label: &str,
) -> Result<(), ValidationError> {
    let refuse = |message: String| ValidationError::NotOfModel {
        result: label.to_string(),
        message,
    };
    for (k, p) in result.parameters.iter().enumerate() {
        let Ok(column) = p.name.parse::<ColumnName>();
        if model.parameter_index(&column.name).is_none() {
            return Err(refuse(format!(
                "'{}' is not a parameter of {model_label}: the result belongs to another model",
                p.name
            )));
        }
        if result.parameters[..k].iter().any(|q| q.name == p.name) {
            return Err(refuse(format!("'{}' is listed twice", p.name)));
        }
    }
    // Every parameter the model identifies has its estimate in the result
    // (else it would be simulated at its nominal value).
    for q in model.parameters.iter().filter(|q| q.bounds.is_some()) {
        let held = result
            .parameters
            .iter()
            .any(|p| p.name.parse::<ColumnName>().is_ok_and(|c| c.name == q.name));
        if !held {
            return Err(refuse(format!(
                "'{}', identified in {model_label}, has no estimate: the result belongs to \
                 another model, or was edited",
                q.name
            )));
        }
    }
    Ok(())
}

/// The data sets to compare, with the reading's notes: `data` (on the
/// model, or on experiment `experiment`'s model when named); else the
/// named experiment's data file; else every experiment's. `from` (s)
/// replaces each data set's first time compared (an experiment's own
/// `from`, else 0). `label` names the model in messages.
pub fn cases(
    model: &Model,
    label: &str,
    data: Option<&Source>,
    experiment: Option<&str>,
    from: Option<f64>,
) -> Result<(Vec<Case>, Vec<String>), ValidationError> {
    let index = |name: &str| {
        model.experiment_index(name).ok_or_else(|| {
            let names: Vec<&str> = model.experiments.iter().map(|x| x.name.as_str()).collect();
            let known = match names.is_empty() {
                true => "none".to_string(),
                false => names.join(", "),
            };
            OptionError::new(
                "experiment",
                format!("{name}: {label} has no such experiment (it has: {known})"),
            )
        })
    };
    let first = |m: &Model, own: f64| first_sample(m, from.unwrap_or(own));
    if let Some(source) = data {
        let (m, name) = match experiment {
            Some(n) => (model.for_experiment(index(n)?), n.to_string()),
            None => (model.clone(), String::new()),
        };
        let read = source.measured(&m)?;
        let first = first(&m, 0.0)?;
        let case = Case {
            experiment: name,
            model: m,
            measured: read.response,
            first,
        };
        return Ok((vec![case], read.notes));
    }
    let chosen: Vec<usize> = match experiment {
        Some(n) => vec![index(n)?],
        None if !model.experiments.is_empty() => (0..model.experiments.len()).collect(),
        None => {
            let detail = format!(
                "not given: {label} lists no experiments, so the data to check must be given"
            );
            return Err(OptionError::new("data", detail).into());
        }
    };
    let (mut out, mut notes) = (Vec::new(), Vec::new());
    for e in chosen {
        let x = &model.experiments[e];
        let m = model.for_experiment(e);
        let source = Source::File(x.data.clone());
        let (measured, n) = read_experiment(model, label, e, &m, &source)?;
        notes.extend(n);
        let first = first(&m, x.from)?;
        out.push(Case {
            experiment: x.name.clone(),
            model: m,
            measured,
            first,
        });
    }
    Ok((out, notes))
}

/// The first sample compared from time `from` (s), which must leave two.
fn first_sample(m: &Model, from: f64) -> Result<usize, OptionError> {
    if from < 0.0 || !from.is_finite() {
        let detail = format!("{from}: must be a time ≥ 0 in seconds");
        return Err(OptionError::new("from", detail));
    }
    let k = m.sampling.first_sample(from);
    if k + 2 > m.sampling.n_samples() {
        let detail = format!(
            "{from}: leaves {} of the record's {} samples",
            m.sampling.n_samples().saturating_sub(k),
            m.sampling.n_samples()
        );
        return Err(OptionError::new("from", detail));
    }
    Ok(k)
}

/// The fits of `case`, and the model's response at the estimate; `model`
/// is the whole model (for the experiment's role).
pub fn fits(
    model: &Model,
    result: &IdentificationResult,
    case: &Case,
) -> Result<(Fits, Response), ValidationError> {
    let (fitted, _) = result.simulate_at_estimate(&case.model, &case.experiment)?;
    let fit_percent = (0..case.model.sensors.len())
        .map(|c| {
            fit_percent(
                &case.measured.sensor(c)[case.first..],
                &fitted.sensor(c)[case.first..],
            )
        })
        .collect();
    let role = model
        .experiments
        .iter()
        .find(|x| x.name == case.experiment)
        .map(|x| match x.role {
            Role::Fit => "fit".to_string(),
            Role::Validation => "validation".to_string(),
        });
    let fits = Fits {
        experiment: case.experiment.clone(),
        role,
        sensors: case.model.sensors.iter().map(|s| s.name.clone()).collect(),
        fit_percent,
    };
    Ok((fits, fitted))
}
