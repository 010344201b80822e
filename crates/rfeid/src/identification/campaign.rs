//! A campaign (SPEC §5) as one run, for the command line and the Python
//! module alike: every experiment's data read on the experiment's own
//! model ([`read_campaign`]), the options checked for a campaign and the
//! criterion of the fitted experiments built (eq. 13 summed over them,
//! [`prepare_campaign`]), and the result's experiments listed, the
//! validation ones simulated at the estimate ([`record_experiments`]).
use crate::identification::cancel::Cancel;
use crate::identification::options::{OptionError, SearchOptions};
use crate::identification::output_error::{ExperimentData, OutputError};
use crate::identification::pipeline::Settings;
use crate::identification::result::{EstimateError, ExperimentSummary, IdentificationResult};
use crate::measurement::measured::Source;
use crate::measurement::{constant_sensors, fit_percent};
use crate::model::{Model, Role};
use crate::simulation::{Response, SimulationError, Simulator, StepChoice};

/// Why a campaign cannot be run; names the model, the experiment and its
/// field.
#[derive(Debug, thiserror::Error)]
pub enum CampaignError {
    /// An experiment's data or one of its fields cannot be used.
    #[error("{model}: experiment \"{experiment}\", field '{field}': {message}")]
    Experiment {
        /// The model file (or `the model`).
        model: String,
        /// The experiment.
        experiment: String,
        /// Its field (`data`, `sensors`, `from`).
        field: &'static str,
        /// What is wrong.
        message: String,
    },
    /// Data given for an experiment the model does not list.
    #[error(
        "data for experiment \"{name}\": {model} has no such [[experiment]] (experiments: {known})"
    )]
    UnknownExperiment {
        /// The model file (or `the model`).
        model: String,
        /// The name given.
        name: String,
        /// The model's experiments.
        known: String,
    },
    /// A search option that a campaign cannot take, or out of its range.
    #[error(transparent)]
    Option(#[from] OptionError),
    /// An experiment's steps could not be chosen at the nominal values.
    #[error("experiment \"{experiment}\": choosing the integrator's steps at the nominal values: {source}")]
    Steps {
        /// The experiment.
        experiment: String,
        /// Why.
        source: SimulationError,
    },
    /// A validation experiment could not be simulated at the estimate.
    #[error("experiment \"{experiment}\": {source}")]
    Estimate {
        /// The experiment.
        experiment: String,
        /// Why.
        source: EstimateError,
    },
}

/// Every experiment's model, data and notes, in the model's order.
#[derive(Debug, Clone)]
pub struct CampaignData {
    /// Each experiment's model ([`Model::for_experiment`]).
    pub models: Vec<Model>,
    /// Each experiment's measured signals, on its model's sampling.
    pub measured: Vec<Response>,
    /// Where each experiment's data came from.
    pub sources: Vec<Source>,
    /// Notes of the reading (columns ignored, a record cut), each naming
    /// its experiment.
    pub notes: Vec<String>,
}

impl CampaignData {
    /// The data files, in the model's order, when every experiment's data
    /// are a file (for the result's digests).
    pub fn files(&self) -> Option<Vec<std::path::PathBuf>> {
        self.sources
            .iter()
            .map(|s| s.file().map(std::path::Path::to_path_buf))
            .collect()
    }
}

/// Reads every experiment's data on its own model: from `given` (by
/// experiment name) where given, else from the data file the experiment
/// names. `label` names the model in messages; every problem names the
/// experiment and its field.
pub fn read_campaign(
    model: &Model,
    label: &str,
    given: Vec<(String, Source)>,
) -> Result<CampaignData, CampaignError> {
    let mut sources: Vec<Source> = model
        .experiments
        .iter()
        .map(|x| Source::File(x.data.clone()))
        .collect();
    for (name, source) in given {
        let e = model
            .experiment_index(&name)
            .ok_or_else(|| CampaignError::UnknownExperiment {
                model: label.to_string(),
                name: name.clone(),
                known: experiment_names(model),
            })?;
        sources[e] = source;
    }
    let mut data = CampaignData {
        models: Vec::new(),
        measured: Vec::new(),
        sources: Vec::new(),
        notes: Vec::new(),
    };
    for (e, source) in sources.into_iter().enumerate() {
        let m = model.for_experiment(e);
        let (measured, notes) = read_experiment(model, label, e, &m, &source)?;
        data.notes.extend(notes);
        data.models.push(m);
        data.measured.push(measured);
        data.sources.push(source);
    }
    Ok(data)
}

/// Experiment `e`'s data from `source` on its own model `m`
/// ([`Model::for_experiment`]), and the reading's notes, each naming the
/// experiment. `label` names the model in messages.
pub fn read_experiment(
    model: &Model,
    label: &str,
    e: usize,
    m: &Model,
    source: &Source,
) -> Result<(Response, Vec<String>), CampaignError> {
    let x = &model.experiments[e];
    let fail = |field: &'static str, message: String| CampaignError::Experiment {
        model: label.to_string(),
        experiment: x.name.clone(),
        field,
        message,
    };
    if let Source::File(path) = source {
        if !path.is_file() {
            let message = format!("cannot read {}: no such file", path.display());
            return Err(fail("data", message));
        }
    }
    let field = if x.sensors.is_some() {
        "sensors"
    } else {
        "data"
    };
    let read = source
        .measured(m)
        .map_err(|err| fail(field, err.to_string()))?;
    let name = &x.name;
    let notes = read
        .notes
        .into_iter()
        .map(|n| format!("experiment \"{name}\": {n}"))
        .collect();
    Ok((read.response, notes))
}

/// The model's experiments, for a message.
fn experiment_names(model: &Model) -> String {
    let names: Vec<&str> = model.experiments.iter().map(|e| e.name.as_str()).collect();
    match names.is_empty() {
        true => "it has none".into(),
        false => names.join(", "),
    }
}

/// A campaign ready to start: the criterion of the fitted experiments, the
/// pipeline's settings, and what the caller shows before the run.
#[derive(Debug)]
pub struct PreparedCampaign<'m> {
    /// The criterion (eq. 13 summed over the fitted experiments, each with
    /// its weight).
    pub problem: OutputError<'m>,
    /// The pipeline's settings.
    pub settings: Settings,
    /// Warnings (an experiment's constant signals), each naming its
    /// experiment.
    pub warnings: Vec<String>,
    /// Each fitted experiment's name and the steps chosen for it.
    pub steps: Vec<(String, StepChoice)>,
}

/// Checks `options` for a campaign and builds the criterion of `data`'s
/// fitted experiments with each one's steps chosen at the nominal values.
///
/// A campaign's experiments have records of their own lengths, so the
/// local searches fit whole records: `window` is off for a campaign, and
/// a window asked for is refused rather than ignored. An experiment's own
/// `from` takes the place of `options.from`.
pub fn prepare_campaign<'m>(
    model: &Model,
    label: &str,
    data: &'m CampaignData,
    options: &SearchOptions,
    cancel: &Cancel,
) -> Result<PreparedCampaign<'m>, CampaignError> {
    options.check()?;
    if let Some(w) = options.window.filter(|w| *w > 0.0) {
        let detail = format!(
            "{w}: a campaign's experiments have records of their own lengths, so its local \
             searches fit whole records; leave the window out (or give 0)"
        );
        return Err(OptionError::new("window", detail).into());
    }
    if !(options.from >= 0.0 && options.from.is_finite()) {
        let detail = format!("{}: must be a time ≥ 0 s", options.from);
        return Err(OptionError::new("from", detail).into());
    }
    let mut parts = Vec::new();
    let mut warnings = Vec::new();
    let mut steps = Vec::new();
    for e in model.fitted_experiments() {
        let x = &model.experiments[e];
        let (m, measured) = (&data.models[e], &data.measured[e]);
        let from = if x.from > 0.0 { x.from } else { options.from };
        let first = m.sampling.first_sample(from);
        if first + 2 > m.sampling.n_samples() {
            let message = format!(
                "{from} s leaves {} of the record's {} samples to fit",
                m.sampling.n_samples().saturating_sub(first),
                m.sampling.n_samples()
            );
            return Err(CampaignError::Experiment {
                model: label.to_string(),
                experiment: x.name.clone(),
                field: "from",
                message,
            });
        }
        let constant = constant_sensors(measured, first);
        if !constant.is_empty() {
            let names: Vec<&str> = constant
                .iter()
                .map(|&c| m.sensors[c].name.as_str())
                .collect();
            warnings.push(format!(
                "experiment \"{}\": these measured signals are constant and carry no information: {}",
                x.name,
                names.join(", ")
            ));
        }
        let sim = Simulator::choose(m, &m.nominal()).map_err(|source| CampaignError::Steps {
            experiment: x.name.clone(),
            source,
        })?;
        steps.push((x.name.clone(), sim.steps()));
        parts.push(ExperimentData {
            name: x.name.clone(),
            sim,
            measured: measured.clone(),
            first,
            weight: x.weight,
        });
    }
    let mut problem = OutputError::campaign(parts);
    problem.set_cancel(cancel.clone());
    let settings = Settings {
        window: None,
        ..options.settings()
    };
    Ok(PreparedCampaign {
        problem,
        settings,
        warnings,
        steps,
    })
}

/// Lists every experiment in `result` in the model's order: the fitted
/// ones' summaries (from the pipeline) with their data named, and the
/// validation ones simulated at the estimate with their fit per sensor.
pub fn record_experiments(
    result: &mut IdentificationResult,
    model: &Model,
    data: &CampaignData,
) -> Result<(), CampaignError> {
    let mut fitted = std::mem::take(&mut result.experiments).into_iter();
    let mut all = Vec::with_capacity(model.experiments.len());
    for (e, x) in model.experiments.iter().enumerate() {
        let label = data.sources[e].label();
        let summary = match x.role {
            Role::Fit => fitted.next().map(|mut s| {
                s.data = Some(label);
                s
            }),
            Role::Validation => Some(validation(result, model, data, e)?),
        };
        all.extend(summary);
    }
    result.experiments = all;
    Ok(())
}

/// Validation experiment `e` simulated at the estimate, with its fit per
/// sensor.
fn validation(
    result: &IdentificationResult,
    model: &Model,
    data: &CampaignData,
    e: usize,
) -> Result<ExperimentSummary, CampaignError> {
    let x = &model.experiments[e];
    let (m, measured) = (&data.models[e], &data.measured[e]);
    let (fitted, steps) =
        result
            .simulate_at_estimate(m, &x.name)
            .map_err(|source| CampaignError::Estimate {
                experiment: x.name.clone(),
                source,
            })?;
    let first = m.sampling.first_sample(x.from);
    Ok(ExperimentSummary {
        name: x.name.clone(),
        role: Role::Validation,
        data: Some(data.sources[e].label()),
        samples: measured.n_samples,
        sample_rate: m.sampling.sample_rate,
        from: m.sampling.time(first),
        weight: x.weight,
        sensors: m.sensors.iter().map(|s| s.name.clone()).collect(),
        fits: (0..m.sensors.len())
            .map(|c| fit_percent(&measured.sensor(c)[first..], &fitted.sensor(c)[first..]))
            .collect(),
        steps: Some(steps),
    })
}
