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

/// Reads and validates a model file. Relative paths inside it (signal
/// tables) are taken relative to the file's directory.
#[allow(clippy::result_large_err)] // a cold path; the error carries the file's text for a snippet
pub fn load_model(path: &Path) -> Result<Model, ModelFileError> {
    let text = std::fs::read_to_string(path).map_err(|e| ModelFileError {
        path: path.into(),
        source_text: None,
        span: None,
        entry: String::new(),
        field: String::new(),
        message: format!("cannot read the file: {e}"),
    })?;
    parse_model(&text, path)
}

/// Parses and validates model text; `path` names it in errors and anchors
/// relative paths.
#[allow(clippy::result_large_err)] // as above
pub fn parse_model(text: &str, path: &Path) -> Result<Model, ModelFileError> {
    build::build(text, path).map_err(|e| *e)
}
