//! What an identification is asked to do ([`Settings`]) and what a caller
//! may watch while it runs ([`Progress`]).
use crate::identification::bfgs::BfgsSettings;
use crate::identification::lm::LmSettings;
pub use crate::identification::noise::NoiseModel;
#[cfg(doc)]
use crate::identification::output_error::OutputError;
pub use crate::identification::profile::ProfileRequest;
pub use crate::identification::search::Method;
use crate::identification::uncertainty::UncertaintySettings;
use crate::identification::verdict::VerdictSettings;

/// How the sensors are weighted in J (eq. 13).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Weighting {
    /// w_c = 1, the paper's choice (eq. 14).
    #[default]
    Equal,
    /// w_c = 1/σ_c², with σ_c² estimated from each sensor's residuals after a
    /// fit; the fit is repeated with the new weights (up to 5 times).
    EstimatedNoise,
}

/// Where the local search starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Start {
    /// From the best [`Settings::starts`] points of the LP_τ plan (eq. 18–19).
    #[default]
    Plan,
    /// Once, from the identified parameters' `value`s in the model file
    /// (which lie in their boxes). [`super::identify`] then evaluates a plan
    /// of one point only, for the checks of the problem; the global search
    /// is skipped, so the estimate is the minimum nearest the values.
    Values,
}

/// `plan` when not given: points of the LP_τ plan (eq. 18–19).
pub const DEFAULT_PLAN: usize = 100;
/// `starts` when not given: local searches from the best plan points.
pub const DEFAULT_STARTS: usize = 1;

/// Settings of an identification. [`Settings::default`] is the paper's run
/// ([`DEFAULT_PLAN`] plan points, one start, equal weights, no window, no
/// restarts); `rfeid identify`'s defaults are
/// [`crate::identification::options::SearchOptions`]'.
#[derive(Debug, Clone)]
pub struct Settings {
    /// N_p, plan points (≥ 1).
    pub plan_points: usize,
    /// Local searches from the best few plan points (≥ 1).
    pub starts: usize,
    /// Local search method.
    pub method: Method,
    /// Sensor weighting.
    pub weighting: Weighting,
    /// How the noise is modelled when the sensors are weighted by their
    /// estimated noise ([`Weighting::EstimatedNoise`]; equal weights model
    /// none): white, or an autoregressive model per sensor (the default).
    pub noise_model: NoiseModel,
    /// Levenberg–Marquardt settings.
    pub lm: LmSettings,
    /// BFGS settings.
    pub bfgs: BfgsSettings,
    /// Uncertainty settings.
    pub uncertainty: UncertaintySettings,
    /// Thresholds of the verdict.
    pub verdict: VerdictSettings,
    /// If set, each start first fits this fraction (0, 1) of the record
    /// (from its first used sample), then the whole record from there: the
    /// short record's criterion is less rugged, so a start far from the
    /// truth is less likely to end in a side minimum.
    pub window: Option<f64>,
    /// Where the local search starts.
    pub start: Start,
    /// Automatic restarts: when no local search from the plan ends where
    /// the fit passes the verdict's per-sensor checks (fit, whiteness,
    /// noise level), up to this many further searches start from the
    /// next-best plan points that are distinct from every start and end so
    /// far, until one passes (see the `restarts` stage). 0: none.
    /// `rfeid identify` uses [`DEFAULT_RESTARTS`].
    pub restarts: usize,
    /// Bytes the whole Jacobian may take before the searches and the
    /// bounds take it as its triangular factor, block by block from the
    /// simulation ([`OutputError::set_jacobian_memory`]); `None` keeps the
    /// criterion's own setting (256 MiB unless set).
    pub jacobian_memory: Option<usize>,
    /// Profile likelihoods of these parameters after the bounds
    /// ([`crate::identification::profile`]); `None`: none.
    pub profiles: Option<ProfileRequest>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            plan_points: DEFAULT_PLAN,
            starts: DEFAULT_STARTS,
            method: Method::default(),
            weighting: Weighting::default(),
            noise_model: NoiseModel::default(),
            lm: LmSettings::default(),
            bfgs: BfgsSettings::default(),
            uncertainty: UncertaintySettings::default(),
            verdict: VerdictSettings::default(),
            window: None,
            start: Start::default(),
            restarts: 0,
            jacobian_memory: None,
            profiles: None,
        }
    }
}

/// The automatic restarts of `rfeid identify` ([`Settings::restarts`]).
pub const DEFAULT_RESTARTS: usize = 8;

/// What a caller may watch (progress bars, logs). Every method has a no-op default.
pub trait Progress: Sync {
    /// The plan of `points` points starts.
    fn plan_started(&self, _points: usize) {}
    /// One plan point is done.
    fn plan_point(&self) {}
    /// Local search `k` of `of` starts at criterion `cost`.
    fn search_started(&self, _k: usize, _of: usize, _cost: f64) {}
    /// An iteration of the local search ended at criterion `cost`.
    fn iteration(&self, _iteration: usize, _cost: f64) {}
    /// The profiles of `parameters` parameters start (after the bounds).
    fn profiles_started(&self, _parameters: usize) {}
    /// The profile of parameter `name` is done (from any worker thread).
    fn profile_done(&self, _name: &str) {}
}

/// No progress reporting.
pub struct Silent;
impl Progress for Silent {}
