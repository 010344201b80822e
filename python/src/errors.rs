//! The module's exceptions: bad model files and settings are
//! `ModelError`, bad data `DataError` (both `ValueError`s), and a run that
//! cannot be done `IdentificationError` (a `RuntimeError`). Each carries the
//! library's message, which names the file, the entry and the field.
use pyo3::create_exception;
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyValueError};
use pyo3::PyErr;
use rfeid::error_kind::{ErrorKind, Kind};
use rfeid::identification::campaign::CampaignError;
use rfeid::identification::options::{OptionError, PrepareError, Spelling};
use rfeid::identification::pipeline::IdentifyError;
use rfeid::simulation::SimulationError;

create_exception!(
    rfeid,
    ModelError,
    PyValueError,
    "A model file, or a setting of the model (`set`, `tolerance`, …), that cannot be used."
);
create_exception!(
    rfeid,
    DataError,
    PyValueError,
    "Measured data that do not fit the model: a missing column, another sample rate, a value that is not finite."
);
create_exception!(
    rfeid,
    IdentificationError,
    PyRuntimeError,
    "An identification or simulation that could not be done."
);

/// A bad model or setting.
pub fn model_error(e: impl std::fmt::Display) -> PyErr {
    ModelError::new_err(e.to_string())
}

/// A setting of the model that cannot be used (`set`, `tolerance`,
/// `substeps`: [`rfeid::model::set_values`]), spelt with the keywords
/// (`set: unknown parameter 'a_n9' …`, `tolerance=0e0: …`).
pub fn setting_error(e: OptionError) -> PyErr {
    ModelError::new_err(e.spelt(Spelling::Keyword))
}

/// Bad data.
pub fn data_error(e: impl std::fmt::Display) -> PyErr {
    DataError::new_err(e.to_string())
}

/// A computation that could not be done.
pub fn failed(e: impl std::fmt::Display) -> PyErr {
    IdentificationError::new_err(e.to_string())
}

/// An option out of range, named as a keyword argument (`plan=0: …`).
pub fn option_error(e: &OptionError) -> PyErr {
    PyValueError::new_err(e.spelt(Spelling::Keyword))
}

/// A library error as the module's exception, by whose fault it is
/// ([`Kind`]): the model's a `ModelError`, the data's a `DataError`, an
/// option's a `ValueError`, a failed computation an `IdentificationError`,
/// a cancelled run `KeyboardInterrupt`; an option it is about is named as
/// the keyword. The one place the module maps a library error to an
/// exception.
pub fn py_error<E: Kind + std::fmt::Display>(e: E) -> PyErr {
    let text = e
        .option_error()
        .map_or_else(|| e.to_string(), |o| o.spelt(Spelling::Keyword));
    match e.kind() {
        ErrorKind::Model => ModelError::new_err(text),
        ErrorKind::Data => DataError::new_err(text),
        ErrorKind::Option => PyValueError::new_err(text),
        ErrorKind::Failed => IdentificationError::new_err(text),
        ErrorKind::Interrupted => PyKeyboardInterrupt::new_err(text),
    }
}

/// A failed simulation at values the user chose, with what was being
/// done ([`py_error`]'s classes).
pub fn simulation_error(what: &str, e: &SimulationError) -> PyErr {
    let text = format!("{what}: {e}");
    match e.kind() {
        ErrorKind::Model => ModelError::new_err(text),
        _ => IdentificationError::new_err(text),
    }
}

/// A run that could not be set up ([`py_error`]).
pub fn prepare_error(e: PrepareError) -> PyErr {
    py_error(e)
}

/// An identification that failed ([`py_error`]).
pub fn identify_error(e: IdentifyError) -> PyErr {
    py_error(e)
}

/// A campaign that could not be run ([`py_error`]).
pub fn campaign_error(e: CampaignError) -> PyErr {
    py_error(e)
}
