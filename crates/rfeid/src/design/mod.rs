//! Experiment design (SPEC §6): what a test will give before it is run.
//!
//! At the identified parameters' values, each sensor's share of the Fisher
//! information comes from one simulation with exact sensitivities per
//! experiment ([`fisher`]); the Cramér–Rao bound of eq. 26–29 with each
//! sensor's `noise` as its σ (s² = 1) predicts the standard errors,
//! correlations, condition number and identifiability warnings that
//! `identify` would report ([`predict()`]). `--choose K` adds the D-optimal K
//! candidates ([`choose`]), with an upper bound on how far from the optimum
//! the choice can be ([`bound`]); a campaign's experiments are ranked by
//! the information each adds; `--over-box N` chooses for the average over N
//! LP_τ points of the parameter box ([`over_box`]).
pub mod basis;
pub mod bound;
pub mod choose;
pub mod fisher;
pub mod fisher_bound;
pub mod json;
pub mod over_box;
pub mod predict;

use crate::identification::options::OptionError;
use crate::identification::uncertainty::UncertaintySettings;
use crate::model::Model;
use crate::simulation::SimulationError;
use choose::{log_det, Search};
use fisher::{fisher_parts, FisherParts};
use nalgebra::DMatrix;
use predict::{predict, Prediction};

/// Why a design could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DesignError {
    /// A sensor lacks the standard deviation of its noise. A design reads
    /// no data, so each sensor's σ is its own `noise` (no default, and none
    /// taken from another sensor).
    #[error("sensor \"{sensor}\": `noise` is missing: a design needs every {} sensor's noise standard deviation (e.g. noise = \"1e-3 {unit}\"){}", if *candidate { "candidate" } else { "placed" }, if *candidate { "; no data is read before the test, so nothing else can give it" } else { "" })]
    NoNoise {
        /// The sensor.
        sensor: String,
        /// Whether it is a candidate.
        candidate: bool,
        /// Its reading's unit.
        unit: String,
    },
    /// An option the design cannot take: `choose` missing where no sensor
    /// is placed (every `[[sensor]]` a candidate: there is no test to
    /// predict) or beyond the candidates, or `over_box` with too many
    /// Fisher matrices to hold.
    #[error(transparent)]
    Option(OptionError),
    /// The model identifies no parameter.
    #[error(
        "the model identifies no parameter (none has min and max): there is nothing to design for"
    )]
    NoParameters,
    /// The design was cancelled ([`DesignSettings::cancel`]).
    #[error("the design was cancelled")]
    Cancelled,
    /// A campaign without a fitted experiment: every experiment is for
    /// validation.
    #[error("every experiment is for validation: a design needs a fitted one")]
    NoFittedExperiment,
    /// An experiment leaves fewer than two samples after its `from`.
    #[error("experiment \"{experiment}\": fewer than two samples after `from`")]
    TooShort {
        /// The experiment.
        experiment: String,
    },
    /// The simulation at the parameters' values failed.
    #[error("simulating at the parameters' values: {0}")]
    Simulation(SimulationError),
    /// Every point of a box design failed.
    #[error("every one of the {points} points of the box failed to simulate (first: {first})")]
    EveryPointFailed {
        /// Points tried.
        points: usize,
        /// The first failure.
        first: String,
    },
    /// The LP_τ plan over the box could not be built.
    #[error("the plan over the box: {0}")]
    Plan(String),
}

/// What a design is asked for.
#[derive(Debug, Clone, Default)]
pub struct DesignSettings {
    /// `--choose K`: candidates to add.
    pub choose: Option<usize>,
    /// `--over-box N`: choose for the average over N LP_τ points.
    pub over_box: Option<usize>,
    /// Greedy plus exchange even where exhaustive search is cheap.
    pub force_greedy: bool,
    /// The identifiability thresholds, as `identify`'s.
    pub uncertainty: UncertaintySettings,
    /// Set to stop a box design between its points
    /// ([`DesignError::Cancelled`]).
    pub cancel: crate::identification::cancel::Cancel,
}

/// The chosen set and its certificate.
#[derive(Debug, Clone)]
pub struct ChosenSet {
    /// Candidate indices (model order), ascending.
    pub chosen: Vec<usize>,
    /// Their names.
    pub names: Vec<String>,
    /// How they were found.
    pub search: Search,
    /// What the placed sensors with these give.
    pub prediction: Prediction,
    /// Upper bound on log det F of any K-set at the values (the convex
    /// relaxation; with `--over-box` too, where the choice maximises the
    /// average over the box instead).
    pub upper_bound: f64,
    /// The D-efficiency the choice is guaranteed: `exp((log det − bound)/r)`.
    pub efficiency_at_least: f64,
    /// Chosen candidates (indices) that carry no information: their
    /// readings do not depend on the parameters (a body no force reaches),
    /// so a smaller set does as well.
    pub uninformative: Vec<usize>,
}

impl ChosenSet {
    /// The chosen set's warnings in words: its prediction's
    /// ([`predict::warning_texts`]) and one per chosen candidate that
    /// carries no information.
    pub fn warning_texts(&self, columns: &[String]) -> Vec<String> {
        let mut out = predict::warning_texts(columns, &self.prediction);
        out.extend(self.uninformative.iter().map(|&i| {
            let name = &self.names[self.chosen.iter().position(|&c| c == i).unwrap_or(0)];
            format!(
                "the chosen candidate {name} carries no information on the parameters (its readings do not depend on them): fewer sensors do as well"
            )
        }));
        out
    }
}

/// One fitted experiment's worth in a campaign.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ExperimentGain {
    /// The experiment.
    pub name: String,
    /// `log det F − log det F_without`: the information it adds.
    pub log_det_gain: f64,
    /// The D-efficiency of the campaign without it, `exp(−gain/r)` over
    /// the shared parameters.
    pub efficiency_without: f64,
}

/// A design's findings.
#[derive(Debug, Clone)]
pub struct Design {
    /// The pieces at the parameters' values.
    pub parts: FisherParts,
    /// The placed sensors' prediction; `None` when no sensor is placed
    /// (every `[[sensor]]` a candidate, before a first test): the choice is
    /// then compared with no sensor, whose Fisher matrix is 0 (nothing
    /// identifiable, no finite standard error), so there is no ratio to
    /// give, only the chosen set's own standard errors.
    pub placed: Option<Prediction>,
    /// With `--choose`: the chosen set.
    pub chosen: Option<ChosenSet>,
    /// Each fitted experiment's worth (campaigns of two or more).
    pub experiments: Vec<ExperimentGain>,
    /// With `--over-box`: the robust choice and how it compares.
    pub over_box: Option<over_box::BoxChoice>,
}

/// Designs at the model's values: predictions for the placed sensors and,
/// as `settings` ask, the chosen candidates and the box design. `tick` is
/// called once per simulation finished (progress). A model without placed
/// sensors (read with [`crate::io::model_file::Purpose::Design`]) needs
/// `choose` ([`DesignError::Option`]): the K are then chosen from a base
/// information of 0.
pub fn design(
    model: &Model,
    settings: &DesignSettings,
    tick: &(dyn Fn() + Sync),
) -> Result<Design, DesignError> {
    if model.sensors.is_empty() && settings.choose.is_none_or(|k| k == 0) {
        let detail = json::no_placed_sensor("the model");
        return Err(DesignError::Option(OptionError::new("choose", detail)));
    }
    if let Some(k) = settings.choose.filter(|&k| k > model.candidates.len()) {
        let detail = format!(
            "{k}: the model has {} candidate sensor(s) (`candidate = true`)",
            model.candidates.len()
        );
        return Err(DesignError::Option(OptionError::new("choose", detail)));
    }
    // Without `choose` the candidates play no part (and need no noise).
    let without;
    let model = match settings.choose {
        Some(_) => model,
        None => {
            without = Model {
                candidates: Vec::new(),
                ..model.clone()
            };
            &without
        }
    };
    let parts = fisher_parts(model, &model.nominal())?;
    tick();
    // With no placed sensor the base information is 0 (eq. 27: F is a sum
    // over the sensors measured, and there are none).
    let placed_f = parts.placed();
    let placed =
        (!model.sensors.is_empty()).then(|| predict(&parts, &placed_f, 0, &settings.uncertainty));
    let over_box = match (settings.choose, settings.over_box) {
        (Some(k), Some(n)) => Some(over_box::choose_over_box(
            model, &parts, k, n, settings, tick,
        )?),
        _ => None,
    };
    let chosen = settings.choose.map(|k| {
        let cand = parts.candidates();
        let choice = match &over_box {
            Some(b) => b.robust.clone(),
            None => {
                let base = std::slice::from_ref(&placed_f);
                choose::choose(base, std::slice::from_ref(&cand), k, settings.force_greedy).chosen
            }
        };
        chosen_set(
            model,
            &parts,
            &placed_f,
            cand,
            choice,
            over_box.as_ref(),
            settings,
        )
    });
    let final_set = chosen.as_ref().map_or(&[][..], |c| c.chosen.as_slice());
    let experiments = experiment_gains(&parts, final_set);
    Ok(Design {
        parts,
        placed,
        chosen,
        experiments,
        over_box,
    })
}

/// The chosen set's prediction and certificate; `cand` holds every
/// candidate's information.
fn chosen_set(
    model: &Model,
    parts: &FisherParts,
    placed_f: &DMatrix<f64>,
    cand: Vec<DMatrix<f64>>,
    chosen: Vec<usize>,
    over_box: Option<&over_box::BoxChoice>,
    settings: &DesignSettings,
) -> ChosenSet {
    let (k, r) = (chosen.len(), parts.columns.len());
    let f = chosen.iter().fold(placed_f.clone(), |m, &i| m + &cand[i]);
    let prediction = predict(parts, &f, chosen.len(), &settings.uncertainty);
    // A share whose trace is below rounding of the whole carries nothing.
    let uninformative = chosen
        .iter()
        .copied()
        .filter(|&i| cand[i].trace() <= 1e-12 * f.trace())
        .collect();
    // In F·σ₀²'s units, before log det F's shift (which would cost the
    // difference its digits); a singular F's D-efficiency is 0.
    let raw_bound = bound::upper_bound(std::slice::from_ref(placed_f), &[cand], k);
    let raw = match prediction.log_det {
        f64::NEG_INFINITY => f64::NEG_INFINITY,
        _ => log_det(&f),
    };
    let efficiency_at_least = ((raw - raw_bound) / r as f64).exp().min(1.0);
    let upper_bound = raw_bound + parts.log_det_shift();
    let search = match over_box {
        Some(b) => b.search,
        None if !settings.force_greedy
            && choose::binomial(model.candidates.len(), k) <= choose::EXHAUSTIVE_LIMIT =>
        {
            Search::Exhaustive
        }
        None => Search::GreedyExchange,
    };
    ChosenSet {
        names: chosen
            .iter()
            .map(|&i| model.candidates[i].name.clone())
            .collect(),
        chosen,
        search,
        prediction,
        upper_bound,
        efficiency_at_least,
        uninformative,
    }
}

/// Each fitted experiment's information gain, with the placed sensors and
/// the candidates `chosen` (only for two or more experiments), on the
/// parameters it shares with the others: its own `name[experiment]`
/// columns go with it.
fn experiment_gains(parts: &FisherParts, chosen: &[usize]) -> Vec<ExperimentGain> {
    if parts.experiments.len() < 2 {
        return Vec::new();
    }
    let r = parts.columns.len();
    let each: Vec<DMatrix<f64>> = parts
        .experiments
        .iter()
        .map(|e| {
            chosen
                .iter()
                .fold(e.placed.clone(), |m, &i| m + &e.candidates[i])
        })
        .collect();
    let total = each.iter().fold(DMatrix::zeros(r, r), |m, f| m + f);
    parts
        .experiments
        .iter()
        .zip(&each)
        .map(|(e, f)| {
            let keep: Vec<usize> = (0..r)
                .filter(|&j| {
                    let Ok(c) = parts.columns[j].parse::<crate::model::ColumnName>();
                    c.experiment.as_deref() != Some(e.name.as_str())
                })
                .collect();
            let shared = |m: &DMatrix<f64>| m.select_rows(&keep).select_columns(&keep);
            let gain = log_det(&shared(&total)) - log_det(&shared(&(&total - f)));
            ExperimentGain {
                name: e.name.clone(),
                log_det_gain: gain,
                efficiency_without: (-gain / keep.len().max(1) as f64).exp(),
            }
        })
        .collect()
}
