//! An identification run as its users ask for it: the options of `rfeid
//! identify` (SPEC §4) and of the Python module's `identify`, with their
//! names, defaults and limits in one place, checked, and turned into the
//! pipeline's [`Settings`] and criterion. The command line and the Python
//! module both go through here, so the same options give the same run.
use crate::identification::cancel::Cancel;
pub use crate::identification::option_error::{OptionError, Spelling, OPTION_NAMES};
pub use crate::identification::option_names::{
    name_of, named, METHODS, NOISE_MODELS, STARTS, WEIGHTS,
};
use crate::identification::output_error::OutputError;
use crate::identification::pipeline::{
    IdentifyError, Method, NoiseModel, ProfileRequest, Settings, Start, Weighting, DEFAULT_RESTARTS,
};
pub use crate::identification::pipeline::{DEFAULT_PLAN, DEFAULT_STARTS};
use crate::identification::profile::{MAX_POINTS, MIN_POINTS};
use crate::measurement::constant_sensors;
use crate::model::Model;
use crate::simulation::{Response, SimulationError, Simulator};
use serde::{Deserialize, Serialize};

/// Most plan points `plan` may ask for: a plan of 10⁶ points of a
/// 1000-parameter model holds 8 GB of coordinates, so larger plans are a
/// mistake rather than a wish.
pub const MAX_PLAN: usize = 1_000_000;
/// Most local searches `starts` may ask for.
pub const MAX_STARTS: usize = 1000;
/// Most worker threads `threads` may ask for.
pub const MAX_THREADS: usize = 1024;

/// `method` when not given: Levenberg–Marquardt.
pub const DEFAULT_METHOD: Method = Method::Lm;
/// `noise_model` when not given: autoregressive (`ar`).
pub const DEFAULT_NOISE_MODEL: NoiseModel = NOISE_MODELS[0].1;
/// `from` when not given, s.
pub const DEFAULT_FROM: f64 = 0.0;
/// `start` when not given: from the plan.
pub const DEFAULT_START: Start = Start::Plan;
/// `jacobian_memory` when not given, MiB
/// ([`crate::identification::output_error::DEFAULT_JACOBIAN_MEMORY`]).
pub const DEFAULT_JACOBIAN_MIB: usize =
    crate::identification::output_error::DEFAULT_JACOBIAN_MEMORY >> 20;
/// `profile_points` when not given.
pub const DEFAULT_PROFILE_POINTS: usize = crate::identification::profile::DEFAULT_POINTS;

/// `weights` of `identify` when not given: each sensor weighted by its
/// noise level, estimated from its residuals. With equal weights and sensors
/// whose noise differs, eq. 26's single s² misstates the standard errors
/// (measured on the wide-box cases of `examples/wide_boxes.rs`: 6 of 30
/// cases had an estimate 3.2–3.4 standard errors from the truth at the
/// truth's own minimum; estimated weights: 30 of 30 within 3).
pub const DEFAULT_WEIGHTS: Weighting = Weighting::EstimatedNoise;

/// `window` of `identify` when not given: each local search first fits
/// the first 15 % of the record. Measured on wide boxes (README, "The
/// verdict"): the 3-body lathe found the truth in 11 of 12 cases with it, 6
/// of 12 without; the knee–column in 12 of 12 either way, 0.4 s slower.
pub const DEFAULT_WINDOW: f64 = 0.15;

/// The options of one identification, named as the reference names them
/// (`plan`, `noise_model`, …): the one record the command line's
/// arguments, the Python module's keywords and shard files (as JSON, each
/// choice by its name, every field optional) all convert into, checked by
/// [`Self::check`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SearchOptions {
    /// Points of the LP_τ plan (eq. 18–19), 1 to [`MAX_PLAN`]; default
    /// [`DEFAULT_PLAN`].
    pub plan: usize,
    /// Local searches from the best plan points; default [`DEFAULT_STARTS`].
    pub starts: usize,
    /// The local search; default Levenberg–Marquardt.
    pub method: Method,
    /// Sensor weights; `None`: [`DEFAULT_WEIGHTS`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub weights: Option<Weighting>,
    /// The noise model with estimated weights; default autoregressive.
    #[serde(with = "crate::identification::option_names::noise_model_name")]
    pub noise_model: NoiseModel,
    /// Worker threads; `None`: one per core. Results do not depend on it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub threads: Option<usize>,
    /// The record before this time (s) is not fitted; default 0.
    pub from: f64,
    /// The fraction of the record each local search fits first, in [0, 1)
    /// (0: off); `None`: [`DEFAULT_WINDOW`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub window: Option<f64>,
    /// Where the local search starts; default the plan.
    #[serde(skip_serializing_if = "is_default")]
    pub start: Start,
    /// MiB a whole Jacobian may take before it is taken block by block
    /// ([`Settings::jacobian_memory`]); `None`: [`DEFAULT_JACOBIAN_MIB`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jacobian_memory: Option<usize>,
    /// Profile likelihoods after the bounds ([`Settings::profiles`]);
    /// `None`: none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub profiles: Option<ProfileRequest>,
}

/// Whether `v` is its type's default (a field written only when set).
fn is_default<T: Default + PartialEq>(v: &T) -> bool {
    *v == T::default()
}

impl Default for SearchOptions {
    fn default() -> Self {
        SearchOptions {
            plan: DEFAULT_PLAN,
            starts: DEFAULT_STARTS,
            method: DEFAULT_METHOD,
            weights: None,
            noise_model: DEFAULT_NOISE_MODEL,
            threads: None,
            from: DEFAULT_FROM,
            window: None,
            start: DEFAULT_START,
            jacobian_memory: None,
            profiles: None,
        }
    }
}

/// Each option's default as its front ends show it, by the option's name:
/// numbers as numbers, choices by name (the Python module's keyword
/// defaults are read from here).
pub fn defaults() -> Vec<(&'static str, DefaultValue)> {
    use DefaultValue::{Count, Name, Seconds};
    vec![
        ("plan", Count(DEFAULT_PLAN)),
        ("starts", Count(DEFAULT_STARTS)),
        ("method", Name(name_of(&DEFAULT_METHOD, &METHODS))),
        ("weights", Name(name_of(&DEFAULT_WEIGHTS, &WEIGHTS))),
        (
            "noise_model",
            Name(name_of(&DEFAULT_NOISE_MODEL, &NOISE_MODELS)),
        ),
        ("window", Seconds(DEFAULT_WINDOW)),
        ("from", Seconds(DEFAULT_FROM)),
        ("start", Name(name_of(&DEFAULT_START, &STARTS))),
        ("jacobian_memory", Count(DEFAULT_JACOBIAN_MIB)),
        ("profile_points", Count(DEFAULT_PROFILE_POINTS)),
    ]
}

/// An option's default ([`defaults`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DefaultValue {
    /// A count.
    Count(usize),
    /// A real number (a time in s, or a fraction).
    Seconds(f64),
    /// A choice, by name.
    Name(&'static str),
}

/// Checks `threads` (1 to [`MAX_THREADS`]; `None`: one per core), as
/// every command that takes it (`identify`, `design`) does.
pub fn check_threads(threads: Option<usize>) -> Result<(), OptionError> {
    match threads.filter(|t| !(1..=MAX_THREADS).contains(t)) {
        Some(t) => Err(OptionError::new(
            "threads",
            format!("{t}: must be 1 to {MAX_THREADS}"),
        )),
        None => Ok(()),
    }
}

impl SearchOptions {
    /// Checks `plan`, `starts`, `threads`, `window`, the profiles' points and that a search from
    /// the values starts once, before anything is computed.
    pub fn check(&self) -> Result<(), OptionError> {
        if !(1..=MAX_PLAN).contains(&self.plan) {
            let detail = format!("{}: must be 1 to {MAX_PLAN}", self.plan);
            return Err(OptionError::new("plan", detail));
        }
        if !(1..=MAX_STARTS.min(self.plan)).contains(&self.starts) {
            let detail = format!(
                "{}: must be 1 to the plan size ({}) and at most {MAX_STARTS}",
                self.starts, self.plan
            );
            return Err(OptionError::new("starts", detail));
        }
        check_threads(self.threads)?;
        if let Some(w) = self.window.filter(|w| !(0.0..1.0).contains(w)) {
            let detail = format!("{w}: must lie in [0, 1) (0: off)");
            return Err(OptionError::new("window", detail));
        }
        if let Some(n) = self
            .profiles
            .as_ref()
            .map(|p| p.points)
            .filter(|n| !(MIN_POINTS..=MAX_POINTS).contains(n))
        {
            let detail = format!("{n}: must be {MIN_POINTS} to {MAX_POINTS}");
            return Err(OptionError::new("profile_points", detail));
        }
        if self.start == Start::Values && self.starts != 1 {
            let detail = format!(
                "{} with a start from the values: the search starts once, from the values",
                self.starts
            );
            return Err(OptionError::new("starts", detail));
        }
        Ok(())
    }

    /// The pipeline's settings (the options checked by [`Self::check`]).
    pub fn settings(&self) -> Settings {
        let window = self.window.unwrap_or(DEFAULT_WINDOW);
        Settings {
            plan_points: self.plan,
            starts: self.starts,
            method: self.method,
            weighting: self.weights.unwrap_or(DEFAULT_WEIGHTS),
            noise_model: self.noise_model,
            window: Some(window).filter(|w| *w > 0.0),
            restarts: DEFAULT_RESTARTS,
            start: self.start,
            jacobian_memory: self.jacobian_memory.map(|mib| mib.saturating_mul(1 << 20)),
            profiles: self.profiles.clone(),
            ..Settings::default()
        }
    }

    /// The first sample fitted for `from`, which must leave at least two.
    pub fn first_sample(&self, model: &Model) -> Result<usize, OptionError> {
        let (s, from) = (model.sampling, self.from);
        if !(from >= 0.0 && from < s.duration) {
            let detail = format!("{from}: must lie in [0, {}) s", s.duration);
            return Err(OptionError::new("from", detail));
        }
        let first = s.first_sample(from);
        if first + 2 > s.n_samples() {
            let detail = format!(
                "{from}: leaves {} of the record's {} samples to fit",
                s.n_samples().saturating_sub(first),
                s.n_samples()
            );
            return Err(OptionError::new("from", detail));
        }
        Ok(first)
    }
}

/// Why a run could not be set up.
#[derive(Debug, Clone, thiserror::Error)]
pub enum PrepareError {
    /// An option outside its range.
    #[error(transparent)]
    Option(#[from] OptionError),
    /// The model has no identified parameters.
    #[error(transparent)]
    Identify(#[from] IdentifyError),
    /// Every measured signal is constant over the fitted record.
    #[error(
        "every measured signal is constant from t = {from} s on ({}): constant data carry no \
         information about the parameters",
        sensors.join(", ")
    )]
    AllConstant {
        /// `from`, s.
        from: f64,
        /// The sensors.
        sensors: Vec<String>,
    },
    /// The integrator's steps could not be chosen at the nominal values.
    #[error("choosing the integrator's steps at the nominal parameter values: {0}")]
    Steps(SimulationError),
}

/// A run ready to start: the criterion, the pipeline's settings, and the
/// sensors whose measured signal is constant (which carry no information;
/// the caller warns about them).
#[derive(Debug)]
pub struct Prepared<'m> {
    /// The criterion (eq. 13), stopped by the cancellation flag given.
    pub problem: OutputError<'m>,
    /// The pipeline's settings.
    pub settings: Settings,
    /// Sensors (indices) whose measured signal is constant from the first
    /// fitted sample on.
    pub constant: Vec<usize>,
}

impl Prepared<'_> {
    /// The warning about the sensors whose measured signal is constant, if
    /// any.
    pub fn constant_warning(&self) -> Option<String> {
        let model = self.problem.model();
        let names: Vec<&str> = self
            .constant
            .iter()
            .map(|&c| model.sensors[c].name.as_str())
            .collect();
        (!names.is_empty()).then(|| {
            format!(
                "these measured signals are constant and carry no information: {}",
                names.join(", ")
            )
        })
    }
}

/// Checks `options` against `model` and `measured` (on the model's
/// sampling, [`crate::measurement::match_data`]) and builds the criterion
/// with the steps chosen at the nominal values: the stage before
/// [`crate::identification::pipeline::identify`].
pub fn prepare<'m>(
    model: &'m Model,
    measured: Response,
    options: &SearchOptions,
    cancel: &Cancel,
) -> Result<Prepared<'m>, PrepareError> {
    options.check()?;
    let first = options.first_sample(model)?;
    if model.identified().is_empty() {
        return Err(IdentifyError::NoParameters.into());
    }
    let constant = constant_sensors(&measured, first);
    if constant.len() == measured.n_sensors {
        return Err(PrepareError::AllConstant {
            from: options.from,
            sensors: constant
                .iter()
                .map(|&c| model.sensors[c].name.clone())
                .collect(),
        });
    }
    let sim = Simulator::choose(model, &model.nominal()).map_err(PrepareError::Steps)?;
    let mut problem = OutputError::new(sim, measured, first);
    problem.set_cancel(cancel.clone());
    Ok(Prepared {
        problem,
        settings: options.settings(),
        constant,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_the_command_lines() {
        let s = SearchOptions::default().settings();
        assert_eq!((s.plan_points, s.starts), (100, 1));
        assert_eq!(s.weighting, Weighting::EstimatedNoise);
        assert_eq!(s.window, Some(DEFAULT_WINDOW));
        assert_eq!(s.restarts, DEFAULT_RESTARTS);
        let off = SearchOptions {
            window: Some(0.0),
            ..SearchOptions::default()
        };
        assert_eq!(off.settings().window, None);
    }

    #[test]
    fn options_outside_their_range_name_the_option() {
        let bad = [
            (
                SearchOptions {
                    plan: 0,
                    ..Default::default()
                },
                "--plan 0: must be 1 to 1000000",
            ),
            (
                SearchOptions {
                    starts: 101,
                    ..Default::default()
                },
                "--starts 101:",
            ),
            (
                SearchOptions {
                    threads: Some(0),
                    ..Default::default()
                },
                "--threads 0:",
            ),
            (
                SearchOptions {
                    window: Some(1.0),
                    ..Default::default()
                },
                "--window 1:",
            ),
            (
                SearchOptions {
                    start: Start::Values,
                    starts: 2,
                    ..Default::default()
                },
                "--starts 2 with a start from the values",
            ),
        ];
        for (o, text) in bad {
            let e = o.check().unwrap_err();
            let cli = e.spelt(Spelling::CommandLine);
            assert!(cli.starts_with(text), "{cli}");
            assert!(!e.to_string().contains("--"), "{e}");
            let keyword = e.spelt(Spelling::Keyword);
            assert!(keyword.starts_with(&format!("{}=", e.option)), "{keyword}");
        }
        assert!(SearchOptions::default().check().is_ok());
    }
}
