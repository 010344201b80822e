//! The module's exceptions: bad model files and settings are
//! `ModelError`, bad data `DataError` (both `ValueError`s), and a run that
//! cannot be done `IdentificationError` (a `RuntimeError`). Each carries the
//! library's message, which names the file, the entry and the field.
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::PyErr;
use rfeid::identification::campaign::CampaignError;
use rfeid::identification::options::{keyword_spelling, OptionError, PrepareError};
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
    PyValueError::new_err(e.keyword_text())
}

/// A keyword's value refused, with the library's message spelt with
/// keywords ([`keyword_spelling`]).
pub fn option_text(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(keyword_spelling(&e.to_string()))
}

/// A failed simulation at values the user chose: values the model cannot
/// take are the model's fault, a diverging run a failed computation.
pub fn simulation_error(what: &str, e: &SimulationError) -> PyErr {
    let text = format!("{what}: {e}");
    match e.is_bad_values() {
        true => ModelError::new_err(text),
        false => IdentificationError::new_err(text),
    }
}

/// A run that could not be set up.
pub fn prepare_error(e: PrepareError) -> PyErr {
    match e {
        PrepareError::Option(o) => option_error(&o),
        PrepareError::Identify(e) => identify_error(e),
        PrepareError::AllConstant { .. } => data_error(e),
        PrepareError::Steps(s) => simulation_error(
            "choosing the integrator's steps at the nominal parameter values",
            &s,
        ),
    }
}

/// An identification that failed: the model's or the settings' fault, or a
/// computation that could not be done.
pub fn identify_error(e: IdentifyError) -> PyErr {
    match e {
        IdentifyError::NoParameters => model_error(e),
        IdentifyError::Plan(_)
        | IdentifyError::NoStarts
        | IdentifyError::UnknownProfileParameter { .. } => PyValueError::new_err(e.to_string()),
        IdentifyError::TooFewObservations { .. } => data_error(e),
        _ => failed(e),
    }
}

/// A campaign that could not be run: an option is named as a keyword, an
/// experiment's data or its `from` are bad data or a bad model, a failed
/// simulation as [`simulation_error`] says.
pub fn campaign_error(e: CampaignError) -> PyErr {
    match e {
        CampaignError::Option(o) => option_error(&o),
        CampaignError::Experiment { field: "from", .. } => model_error(e),
        CampaignError::Experiment { .. } | CampaignError::UnknownExperiment { .. } => data_error(e),
        _ if e.is_bad_input() => ModelError::new_err(e.to_string()),
        _ => IdentificationError::new_err(e.to_string()),
    }
}
