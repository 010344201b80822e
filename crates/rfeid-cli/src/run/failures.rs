//! Library errors as the CLI's failures: bad input (exit 2) or a failed
//! computation (exit 1).
use crate::diagnostics::Failure;
use rfeid::error_kind::{ErrorKind, Kind};
use rfeid::identification::options::{OptionError, Spelling};
use rfeid::identification::pipeline::IdentifyError;
use rfeid::measurement::simulated::SimulatedError;
use rfeid::measurement::NoiseError;
use rfeid::model::Model;
use rfeid::simulation::SimulationError;

/// A failed simulation at user-chosen values: parameter values the model
/// cannot take (from `--set`) are bad input (exit 2); a run that diverges is
/// a failed computation (exit 1).
pub fn simulation_failure(what: &str, e: SimulationError) -> Failure {
    simulation_failure_kind(&e, &format!("{what}: {e}"))
}

/// A simulated record's failure ([`SimulatedError`]): a failed
/// simulation as [`simulation_failure`] says, the rest an option's.
pub fn simulation_failure_of(e: SimulatedError) -> Failure {
    match &e {
        SimulatedError::Steps(s) => simulation_failure_kind(s, &e),
        SimulatedError::Option(_) => failure(e),
    }
}

/// [`simulation_failure`]'s choice of exit status for `cause`, with the
/// message `e`.
fn simulation_failure_kind(cause: &SimulationError, e: &dyn std::fmt::Display) -> Failure {
    match cause.kind().is_bad_input() {
        true => Failure::input_msg(e),
        false => Failure::failed(e),
    }
}

/// A library error as a failure, by whose fault it is ([`Kind`]): bad
/// input (the model, the data or an option) exits 2, a failed computation
/// 1, a cancelled run 130. The one place the command line maps a library
/// error to its exit status.
pub fn failure<E: Kind + std::fmt::Display>(e: E) -> Failure {
    if let Some(o) = e.option_error() {
        return Failure::input_msg(option_text(o));
    }
    match e.kind() {
        k if k.is_bad_input() => Failure::input_msg(e),
        ErrorKind::Interrupted => Failure {
            code: 130,
            report: miette::miette!("{e}"),
        },
        _ => Failure::failed(e),
    }
}

/// An option's error as the command line spells it: `--plan 0: …`.
pub fn option_text(e: &OptionError) -> String {
    e.spelt(Spelling::CommandLine)
}

/// An identification error as a failure ([`failure`]).
pub fn identify_failure(e: IdentifyError) -> Failure {
    failure(e)
}

/// A noise error with the sensor named.
pub fn noise_sensor(model: &Model, e: NoiseError) -> String {
    let sensor = match &e {
        NoiseError::Overflow { sensor, .. } | NoiseError::BelowRounding { sensor, .. } => {
            model.sensors.get(*sensor).map(|s| s.name.as_str())
        }
        NoiseError::BadFraction { .. } => None,
    };
    match sensor {
        Some(name) => format!("{e} ('{name}')"),
        None => e.to_string(),
    }
}

impl From<IdentifyError> for Failure {
    /// As [`identify_failure`] says.
    fn from(e: IdentifyError) -> Self {
        identify_failure(e)
    }
}
