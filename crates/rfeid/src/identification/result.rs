//! The outcome of an identification, as written to RESULT.json (SPEC §3).
use super::verdict::Verdict;
use crate::model::Scale;
use serde::{Deserialize, Serialize};

/// One identified parameter, SI.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParameterEstimate {
    /// Name.
    pub name: String,
    /// Unit symbol the model file used for it (empty for SI).
    pub unit: String,
    /// SI value of one `unit`.
    pub unit_scale: f64,
    /// The estimate x̂.
    pub estimate: f64,
    /// Cramér–Rao standard error (eq. 26), if it could be computed.
    pub std_error: Option<f64>,
    /// Lower end of the box.
    pub min: f64,
    /// Upper end of the box.
    pub max: f64,
    /// How the search mapped the box onto [0, 1] (`linear` for results
    /// written before scales existed).
    #[serde(default)]
    pub scale: Scale,
    /// Nominal value from the model file.
    pub nominal: f64,
}

/// The LP_τ plan's outcome.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanSummary {
    /// N_p.
    pub points: usize,
    /// Points whose simulation failed (J = +∞), of those evaluated to the
    /// end.
    pub failed: usize,
    /// J at each point in plan order; `None` where the simulation failed
    /// or the point was abandoned.
    pub costs: Vec<Option<f64>>,
    /// Plan indices (0-based) the local searches started from.
    pub starts: Vec<usize>,
    /// The first failure's message, if any.
    pub first_failure: Option<String>,
    /// Plan indices (0-based) of the points abandoned: their running J
    /// passed the J of the best points found before them, so they could
    /// not be among the best, and their simulation stopped there (neither
    /// a J nor a failure; absent when none was).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub abandoned: Vec<usize>,
}

/// A local search that could not run (its start point's evaluation with
/// sensitivities failed, for instance). Recorded like a failed plan point:
/// the other starts still run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StartFailure {
    /// Plan index (0-based) of the start point.
    pub plan_index: usize,
    /// Why the search failed.
    pub reason: String,
}

/// One iterate of the local search that gave the estimate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Iterate {
    /// Iteration number (0 = start point).
    pub iteration: usize,
    /// J.
    pub cost: f64,
    /// Identified parameters, SI.
    pub parameters: Vec<f64>,
}

/// Wall time of each phase, s, and where the simulations' time went (not
/// results: they change with the machine and the threads).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Timings {
    /// The LP_τ plan.
    pub plan: f64,
    /// The local search(es), all starts and reweightings.
    pub local_search: f64,
    /// The Cramér–Rao bounds.
    pub uncertainty: f64,
    /// The profile likelihoods (0 when none were asked).
    #[serde(default)]
    pub profiles: f64,
    /// Everything.
    pub total: f64,
    /// Each local search from a start (the starts, then the restarts, each
    /// with its window search), in the order they ran (absent in results
    /// written before they were timed).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub searches: Vec<f64>,
    /// Each restart that ran at the same time as the ones before it and
    /// whose end was not needed (one of those settled the restarts, or
    /// ended near its start), s; not in [`Timings::searches`].
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub discarded: Vec<f64>,
    /// The simulations this process ran and their time (zero in results
    /// written before they were counted; a merge's plan ran in its shards).
    #[serde(default)]
    pub simulations: super::tally::Work,
}

/// Where the model and the data came from, so that a report can be rebuilt
/// from RESULT.json alone.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Source {
    /// The model file, as given.
    pub model: Option<String>,
    /// The data file, as given.
    pub data: Option<String>,
    /// For `rfeid demo`: the noise fraction of the simulated data (None: noise-free).
    pub demo_noise: Option<f64>,
    /// For `rfeid demo`: the noise seed.
    pub demo_seed: Option<u64>,
    /// Parameters fixed for the run, `NAME=VALUE` as given
    /// (`identify --set`); a report applies them again.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub set: Vec<String>,
    /// What the input files held when the result was computed, so that a
    /// later `report` or `validate` can tell that one changed (absent for
    /// the demo and in results written before they were recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub digests: Option<InputDigests>,
}

/// Digests of a run's input files: FNV-1a 64 of their bytes, in hex (a check
/// that a file is unchanged, not a protection against tampering).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct InputDigests {
    /// The model file.
    pub model: String,
    /// The model's signal tables, in the model's order.
    #[serde(default)]
    pub tables: Vec<String>,
    /// The data: the data file, or a campaign's experiments' files in the
    /// model's order.
    #[serde(default)]
    pub data: Vec<String>,
}

/// One experiment of a campaign, as RESULT.json lists it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExperimentSummary {
    /// Its name.
    pub name: String,
    /// Fitted, or left out for validation.
    pub role: crate::model::Role,
    /// Its data file, as the model file resolves it.
    #[serde(default)]
    pub data: Option<String>,
    /// Samples per sensor.
    pub samples: usize,
    /// Sample rate, Hz.
    pub sample_rate: f64,
    /// Start of the fitted part, s.
    pub from: f64,
    /// Its weight w_e.
    pub weight: f64,
    /// Its sensors.
    pub sensors: Vec<String>,
    /// Fit per sensor at the estimate, % (normalised RMS fit as MATLAB's
    /// `compare`, `100 (1 − ‖y − ŷ‖/‖y − mean y‖)`); `None` for a constant
    /// measured signal.
    #[serde(default)]
    pub fits: Vec<Option<f64>>,
    /// The integrator's steps per sample for this experiment, and their
    /// estimated error at the estimate (a validation experiment's at the
    /// steps it was simulated with; `None` in results written before they
    /// were recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps: Option<crate::simulation::StepChoice>,
}

/// Why a model could not be simulated at a result's estimate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EstimateError {
    /// The result does not belong to the model (the message names the
    /// parameter).
    #[error("{0}")]
    NotInModel(String),
    /// The simulation failed.
    #[error(transparent)]
    Simulation(crate::simulation::SimulationError),
}

/// Everything an identification found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct IdentificationResult {
    /// The identified parameters.
    pub parameters: Vec<ParameterEstimate>,
    /// Final criterion J (eq. 13, with the final weights).
    pub criterion: f64,
    /// Sum of squared unweighted residuals.
    pub ssr: f64,
    /// s² = SSR/(N − r − 1) (eq. 29), weighted like J.
    pub s2: Option<f64>,
    /// Number of scalar observations N (samples × sensors).
    pub observations: usize,
    /// Correlation matrix of the estimates.
    pub correlation: Option<Vec<Vec<f64>>>,
    /// Condition number of the column-scaled Fisher matrix H₁ᵀH₁.
    pub condition_number: Option<f64>,
    /// Warnings (identifiability, restarts, steps, aliasing), in words in
    /// RESULT.json.
    pub warnings: Vec<super::warning::Warning>,
    /// Why the bounds could not be computed, if they could not.
    pub uncertainty_error: Option<String>,
    /// The local search method (`lm` or `bfgs`).
    pub method: super::search::Method,
    /// Why the local search stopped (machine-readable: the variant's name).
    pub termination: super::termination::StopReason,
    /// Why the local search stopped, in words.
    pub termination_message: String,
    /// Iterations of the local search that gave the estimate.
    pub iterations: usize,
    /// Simulations of the response alone, all phases.
    pub simulations: usize,
    /// Simulations with sensitivities (a Jacobian), counted apart from
    /// `simulations`.
    pub simulations_with_sensitivities: usize,
    /// Simulations that failed (recorded, not fatal).
    pub failed_simulations: usize,
    /// Per-sensor weights w_c (eq. 13).
    pub weights: Vec<f64>,
    /// Sensor names, in the order of `weights`.
    pub sensors: Vec<String>,
    /// Start of the record used, s (`--from`).
    pub from: f64,
    /// The plan.
    pub plan: PlanSummary,
    /// Local searches that failed to run (the others gave the estimate).
    #[serde(default)]
    pub failed_starts: Vec<StartFailure>,
    /// The local search's history.
    pub history: Vec<Iterate>,
    /// Wall time of each phase.
    pub timings: Timings,
    /// Worker threads.
    pub threads: usize,
    /// Where the model and data came from.
    #[serde(default)]
    pub source: Source,
    /// Whether the result can be trusted, and every reason it cannot
    /// (absent in results written before verdicts existed).
    #[serde(default)]
    pub verdict: Option<Verdict>,
    /// The integrator's steps per sample used, and the estimated relative
    /// RMS error of the simulated signals at the estimate.
    #[serde(default)]
    pub simulation: Option<crate::simulation::StepChoice>,
    /// Each sensor's noise model at the estimate (empty with equal
    /// weights, which model no noise).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub noise: Vec<super::noise::SensorNoise>,
    /// What the standard errors cover: `noise`, or `noise_only` when the
    /// verdict found model error (its bias is not in them).
    #[serde(default)]
    pub std_errors_cover: super::noise::StdErrorScope,
    /// The experiments of a campaign (SPEC §5), fitted and validation ones;
    /// empty for a single data file.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub experiments: Vec<ExperimentSummary>,
    /// The profile likelihoods asked for (`--profiles`), with their
    /// likelihood-ratio and Wald intervals; empty when none were asked.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub profiles: Vec<super::profile::ParameterProfile>,
}

impl IdentificationResult {
    /// The result as RESULT.json holds it: pretty-printed JSON with a
    /// final newline (numbers round-trip exactly).
    pub fn to_json_text(&self) -> Result<String, serde_json::Error> {
        let mut text = serde_json::to_string_pretty(self)?;
        text.push('\n');
        Ok(text)
    }

    /// All of `model`'s parameter values (SI) at the estimate, as experiment
    /// `experiment` of a campaign sees them (`""` for a data file on its
    /// own): the model's values, with each estimate put in, a
    /// `name[experiment]` estimate only for its own experiment. An estimate
    /// whose parameter the model lacks is an error naming it.
    pub fn parameter_values(
        &self,
        model: &crate::model::Model,
        experiment: &str,
    ) -> Result<Vec<f64>, String> {
        let mut x = model.nominal();
        for p in &self.parameters {
            let Ok(column) = p.name.parse::<crate::model::ColumnName>();
            let i = model.parameter_index(&column.name).ok_or_else(|| {
                format!("the result's parameter '{}' is not in the model", p.name)
            })?;
            if column.experiment.as_deref().is_none_or(|e| e == experiment) {
                x[i] = p.estimate;
            }
        }
        Ok(x)
    }

    /// `model` simulated at the estimate, as experiment `experiment` sees it
    /// ([`IdentificationResult::parameter_values`]), with steps per sample
    /// chosen there for the model's tolerance: the response and the steps.
    pub fn simulate_at_estimate(
        &self,
        model: &crate::model::Model,
        experiment: &str,
    ) -> Result<(crate::simulation::Response, crate::simulation::StepChoice), EstimateError> {
        use crate::simulation::{Simulator, Workspace};
        let x = self
            .parameter_values(model, experiment)
            .map_err(EstimateError::NotInModel)?;
        let sim = Simulator::choose(model, &x).map_err(EstimateError::Simulation)?;
        let mut out = sim.response_buffer();
        sim.run(&x, &mut Workspace::default(), &mut out)
            .map_err(EstimateError::Simulation)?;
        Ok((out, sim.steps()))
    }

    /// The result as one experiment of its campaign shows it, for a report
    /// of that experiment's data: the per-sensor entries (sensor names,
    /// weights, noise models, the verdict's checks) narrowed to
    /// `sensors[experiment]`, in the order of `sensors`. A validation
    /// experiment was not fitted, so its sensors have no weights or noise
    /// models: those lists come out empty (as for `experiment` `""`, data
    /// outside the campaign). A result without experiments is returned as
    /// it is.
    pub fn seen_by(&self, experiment: &str, sensors: &[String]) -> IdentificationResult {
        let mut view = self.clone();
        if self.experiments.is_empty() {
            return view;
        }
        let names: Vec<String> = sensors
            .iter()
            .map(|s| match experiment {
                "" => s.clone(),
                e => format!("{s}[{e}]"),
            })
            .collect();
        let weights: Option<Vec<f64>> = names
            .iter()
            .map(|n| {
                let i = self.sensors.iter().position(|s| s == n)?;
                self.weights.get(i).copied()
            })
            .collect();
        view.weights = weights.unwrap_or_default();
        view.noise = names
            .iter()
            .filter_map(|n| self.noise.iter().find(|x| &x.sensor == n).cloned())
            .collect();
        if let Some(v) = &mut view.verdict {
            v.sensors.retain(|s| names.contains(&s.sensor));
        }
        view.sensors = names;
        view
    }

    /// `true` if a verdict was drawn and it is not trustworthy.
    pub fn is_suspect(&self) -> bool {
        self.verdict.as_ref().is_some_and(|v| !v.trustworthy)
    }
}
