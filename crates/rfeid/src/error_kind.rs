//! Whose fault an error is: the one classification of the library's
//! errors that the command line maps to its exit status (bad input 2, a
//! failed computation 1) and the Python module to its exception
//! (`ModelError`, `DataError`, `ValueError`, `IdentificationError`,
//! `KeyboardInterrupt`), each in one place.
use crate::design::json::RequestError;
use crate::design::DesignError;
use crate::identification::campaign::CampaignError;
use crate::identification::options::{OptionError, PrepareError};
use crate::identification::pipeline::IdentifyError;
use crate::identification::result::EstimateError;
use crate::identification::shard::MergeError;
use crate::identification::validation::ValidationError;
use crate::io::shard_file::{ResumeError, ShardError};
use crate::measurement::measured::MeasuredError;
use crate::measurement::simulated::SimulatedError;
use crate::report::at_estimate::RenderError;
use crate::simulation::SimulationError;

/// Whose fault an error is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// The model file, or a setting of the model (values it cannot take).
    Model,
    /// The measured data, or a file that is not what it should be.
    Data,
    /// An option out of its range, or options that do not go together.
    Option,
    /// A computation that could not be done (a diverging simulation,
    /// every start failed).
    Failed,
    /// The run was cancelled.
    Interrupted,
}

impl ErrorKind {
    /// Whether the input is at fault (the model, the data or an option).
    pub fn is_bad_input(self) -> bool {
        matches!(self, ErrorKind::Model | ErrorKind::Data | ErrorKind::Option)
    }
}

/// An error that knows whose fault it is.
pub trait Kind {
    /// Whose fault the error is.
    fn kind(&self) -> ErrorKind;

    /// The option at fault, when an option is, for the front end to name
    /// as it spells it ([`OptionError::spelt`]).
    fn option_error(&self) -> Option<&OptionError> {
        None
    }
}

impl Kind for SimulationError {
    /// Values the model cannot take are the model's fault; divergence, no
    /// step meeting the tolerance or no equilibrium the computation's.
    fn kind(&self) -> ErrorKind {
        match self {
            SimulationError::Cancelled => ErrorKind::Interrupted,
            e if e.is_bad_values() => ErrorKind::Model,
            _ => ErrorKind::Failed,
        }
    }
}

impl Kind for IdentifyError {
    fn kind(&self) -> ErrorKind {
        match self {
            IdentifyError::NoParameters => ErrorKind::Model,
            IdentifyError::Plan(_)
            | IdentifyError::NoStarts
            | IdentifyError::UnknownProfileParameter { .. } => ErrorKind::Option,
            IdentifyError::TooFewObservations { .. } => ErrorKind::Data,
            IdentifyError::Cancelled => ErrorKind::Interrupted,
            _ => ErrorKind::Failed,
        }
    }
}

impl Kind for OptionError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Option
    }
    fn option_error(&self) -> Option<&OptionError> {
        Some(self)
    }
}

impl Kind for PrepareError {
    fn kind(&self) -> ErrorKind {
        match self {
            PrepareError::Option(e) => e.kind(),
            PrepareError::Identify(e) => e.kind(),
            PrepareError::AllConstant { .. } => ErrorKind::Data,
            PrepareError::Steps(e) => e.kind(),
        }
    }
    fn option_error(&self) -> Option<&OptionError> {
        match self {
            PrepareError::Option(e) => Some(e),
            _ => None,
        }
    }
}

impl Kind for MeasuredError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Data
    }
}

impl Kind for ResumeError {
    /// A file in the way of a shard's output is the input's fault.
    fn kind(&self) -> ErrorKind {
        ErrorKind::Data
    }
}

impl Kind for ShardError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Data
    }
}

impl Kind for EstimateError {
    /// A result of another model is the input's fault.
    fn kind(&self) -> ErrorKind {
        match self {
            EstimateError::NotInModel(_) => ErrorKind::Model,
            EstimateError::Simulation(e) => e.kind(),
        }
    }
}

impl Kind for CampaignError {
    /// An experiment's `from` is the model file's; its data the data's.
    fn kind(&self) -> ErrorKind {
        match self {
            CampaignError::Experiment { field: "from", .. } => ErrorKind::Model,
            CampaignError::Experiment { .. } | CampaignError::UnknownExperiment { .. } => {
                ErrorKind::Data
            }
            CampaignError::Option(e) => e.kind(),
            CampaignError::Steps { source, .. } => source.kind(),
            CampaignError::Estimate { source, .. } => source.kind(),
        }
    }
    fn option_error(&self) -> Option<&OptionError> {
        match self {
            CampaignError::Option(e) => Some(e),
            _ => None,
        }
    }
}

impl Kind for ValidationError {
    fn kind(&self) -> ErrorKind {
        match self {
            ValidationError::Option(e) => e.kind(),
            ValidationError::NotOfModel { .. } => ErrorKind::Model,
            ValidationError::Experiment(e) => e.kind(),
            ValidationError::Data(e) => e.kind(),
            ValidationError::Estimate(e) => e.kind(),
        }
    }
    fn option_error(&self) -> Option<&OptionError> {
        match self {
            ValidationError::Option(e) => Some(e),
            _ => None,
        }
    }
}

impl Kind for MergeError {
    fn kind(&self) -> ErrorKind {
        match self {
            MergeError::Shards(_) => ErrorKind::Data,
            MergeError::Identify(e) => e.kind(),
        }
    }
}

impl Kind for SimulatedError {
    fn kind(&self) -> ErrorKind {
        match self {
            SimulatedError::Steps(e) => e.kind(),
            SimulatedError::Option(e) => e.kind(),
        }
    }
    fn option_error(&self) -> Option<&OptionError> {
        match self {
            SimulatedError::Option(e) => Some(e),
            SimulatedError::Steps(_) => None,
        }
    }
}

impl Kind for RequestError {
    /// A model that cannot give what is asked is the model's fault, an
    /// option out of range the option's.
    fn kind(&self) -> ErrorKind {
        match self.of_model() {
            true => ErrorKind::Model,
            false => ErrorKind::Option,
        }
    }
    fn option_error(&self) -> Option<&OptionError> {
        Some(RequestError::option_error(self))
    }
}

impl Kind for DesignError {
    /// A failed simulation is the computation's (or, at values the model
    /// cannot take, the model's); a sensor without noise, a model without
    /// parameters or a fitted experiment, the model's.
    fn kind(&self) -> ErrorKind {
        match self {
            DesignError::Option(e) => e.kind(),
            DesignError::Simulation(e) => e.kind(),
            DesignError::Cancelled => ErrorKind::Interrupted,
            DesignError::EveryPointFailed { .. } | DesignError::Plan(_) => ErrorKind::Failed,
            _ => ErrorKind::Model,
        }
    }
    fn option_error(&self) -> Option<&OptionError> {
        match self {
            DesignError::Option(e) => Some(e),
            _ => None,
        }
    }
}

impl Kind for RenderError {
    /// A failed simulation is a failed computation; inputs that do not
    /// belong together the input's fault.
    fn kind(&self) -> ErrorKind {
        match self {
            RenderError::Simulation(_) => ErrorKind::Failed,
            RenderError::Parameters(_) | RenderError::Report(_) => ErrorKind::Model,
        }
    }
}
