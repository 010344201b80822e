//! The TOML model file (SPEC §1, §3): reading, unit conversion and
//! validation, done once when the [`Model`] is built.
//!
//! Every error names the file, the entry and the field, with the byte span
//! of the offending text. Unknown keys are errors, so a typo cannot pass
//! silently.
mod build;
mod error;
mod raw;

pub use error::ModelFileError;

use crate::model::Model;
use std::path::Path;

/// What a model file is read for, which decides whether it must place a
/// sensor.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Purpose {
    /// A test's data: simulating, identifying, validating, checking. At
    /// least one `[[sensor]]` must be placed (not `candidate = true`), or
    /// there is nothing to measure; the error names the file.
    #[default]
    Measure,
    /// Experiment design before a first test (SPEC §6, `rfeid design
    /// --choose K`): every sensor may be a candidate, the choice then
    /// compared with no sensor. A model without any `[[sensor]]` is still
    /// refused.
    Design,
}

/// Reads and validates a model file for a test's data
/// ([`Purpose::Measure`]). Relative paths inside it (signal tables) are
/// taken relative to the file's directory.
#[allow(clippy::result_large_err)] // a cold path; the error carries the file's text for a snippet
pub fn load_model(path: &Path) -> Result<Model, ModelFileError> {
    load_model_for(path, Purpose::Measure)
}

/// [`load_model`] for `purpose`: [`Purpose::Design`] accepts a model whose
/// sensors are all candidates.
#[allow(clippy::result_large_err)] // as above
pub fn load_model_for(path: &Path, purpose: Purpose) -> Result<Model, ModelFileError> {
    let text = std::fs::read_to_string(path).map_err(|e| ModelFileError {
        path: path.into(),
        source_text: None,
        span: None,
        entry: String::new(),
        field: String::new(),
        message: format!("cannot read the file: {e}"),
    })?;
    parse_model_for(&text, path, purpose)
}

/// Parses and validates model text for a test's data
/// ([`Purpose::Measure`]); `path` names it in errors and anchors relative
/// paths.
#[allow(clippy::result_large_err)] // as above
pub fn parse_model(text: &str, path: &Path) -> Result<Model, ModelFileError> {
    parse_model_for(text, path, Purpose::Measure)
}

/// [`parse_model`] for `purpose` (see [`load_model_for`]).
#[allow(clippy::result_large_err)] // as above
pub fn parse_model_for(text: &str, path: &Path, purpose: Purpose) -> Result<Model, ModelFileError> {
    build::build(text, path, purpose).map_err(|e| *e)
}
