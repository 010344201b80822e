//! Why an identification could not be done.
use crate::identification::plan::PlanError;
use crate::identification::result::StartFailure;
use crate::identification::termination::SolveError;
use crate::simulation::SimulationError;

/// A local search that could not start.
pub type SearchError = SolveError<SimulationError>;

/// Why an identification could not be done.
#[derive(Debug, Clone, thiserror::Error)]
pub enum IdentifyError {
    /// The model has no parameter with a box.
    #[error("the model has no identified parameters (give a parameter 'min' and 'max')")]
    NoParameters,
    /// Zero plan points, or too many dimensions.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// Zero starts.
    #[error("the number of starts must be at least 1")]
    NoStarts,
    /// Fewer observations than the bounds need (eq. 29: N − r − 1 > 0).
    #[error("{observations} observations are too few for {parameters} parameters (eq. 29 needs N − r − 1 > 0); does the fit start too late (`from`)?")]
    TooFewObservations {
        /// N.
        observations: usize,
        /// r.
        parameters: usize,
    },
    /// No plan point could be simulated.
    #[error("all {points} plan points failed to simulate; the first failure: {first}")]
    AllPlanPointsFailed {
        /// N_p.
        points: usize,
        /// The first failure.
        first: String,
    },
    /// A local search after the starts (reweighting, finer steps) could not
    /// start.
    #[error("local search: {0}")]
    Search(SearchError),
    /// The search from the parameters' values (`Start::Values`) could not
    /// start.
    #[error("local search from the parameters' values: {0}")]
    ValuesStart(SearchError),
    /// The model could not be simulated where the weights are estimated.
    #[error("local search: {0}")]
    Simulation(SimulationError),
    /// Settings derived for a stage were refused (a programming error
    /// surfaced as an error, never a panic).
    #[error(transparent)]
    Settings(#[from] crate::identification::settings::SettingsError),
    /// The run was cancelled ([`crate::identification::cancel::Cancel`]).
    #[error("the identification was cancelled")]
    Cancelled,
    /// A profile was asked of a parameter that is not identified.
    #[error("profile of '{name}': not an identified parameter (identified: {identified})")]
    UnknownProfileParameter {
        /// The name asked for.
        name: String,
        /// The identified parameters, comma-separated.
        identified: String,
    },
    /// Every local search failed to start; each start's reason, in order.
    #[error("all {} local searches failed: {}", .0.len(), describe_failures(.0))]
    AllStartsFailed(Vec<StartFailure>),
}

impl From<SearchError> for IdentifyError {
    fn from(e: SearchError) -> Self {
        IdentifyError::Search(e)
    }
}

fn describe_failures(failures: &[StartFailure]) -> String {
    failures
        .iter()
        .map(|f| format!("start at plan point {}: {}", f.plan_index + 1, f.reason))
        .collect::<Vec<_>>()
        .join("; ")
}
