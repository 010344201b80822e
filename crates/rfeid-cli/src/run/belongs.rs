//! Whether a RESULT.json belongs to a model file: the check of `validate`
//! and `frf --result` ([`validation::check_belongs`]).
use crate::diagnostics::Failure;
use rfeid::identification::result::IdentificationResult;
use rfeid::identification::validation;
use rfeid::model::Model;
use std::path::Path;

/// The result must be of this model: every estimated parameter (by name,
/// `name[experiment]` for one identified per experiment) must be one of its
/// parameters, and every identified one estimated.
pub fn check_belongs(
    model: &Model,
    result: &IdentificationResult,
    model_path: &Path,
    result_path: &Path,
) -> Result<(), Failure> {
    validation::check_belongs(
        model,
        result,
        &model_path.display().to_string(),
        &result_path.display().to_string(),
    )
    .map_err(Failure::input_msg)
}
