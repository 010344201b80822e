//! Whether a RESULT.json belongs to a model file: the check of `validate`
//! and `frf --result`.
use crate::diagnostics::Failure;
use rfeid::identification::result::IdentificationResult;
use rfeid::model::{ColumnName, Model};
use std::path::Path;

/// The result must be of this model: every estimated parameter (by name,
/// `name[experiment]` for one identified per experiment) must be one of its
/// parameters.
pub fn check_belongs(
    model: &Model,
    result: &IdentificationResult,
    model_path: &Path,
    result_path: &Path,
) -> Result<(), Failure> {
    let refuse = |what: String| {
        Err(Failure::input_msg(format!(
            "{}: field 'parameters': {what}",
            result_path.display()
        )))
    };
    for (k, p) in result.parameters.iter().enumerate() {
        let Ok(column) = p.name.parse::<ColumnName>();
        if model.parameter_index(&column.name).is_none() {
            return refuse(format!(
                "'{}' is not a parameter of {}: the result belongs to another model",
                p.name,
                model_path.display()
            ));
        }
        if result.parameters[..k].iter().any(|q| q.name == p.name) {
            return refuse(format!("'{}' is listed twice", p.name));
        }
    }
    // The other direction: every parameter the model identifies has its
    // estimate in the result (else it would be simulated at its nominal value).
    for q in model.parameters.iter().filter(|q| q.bounds.is_some()) {
        let held = result
            .parameters
            .iter()
            .any(|p| p.name.parse::<ColumnName>().is_ok_and(|c| c.name == q.name));
        if !held {
            return refuse(format!(
                "'{}', identified in {}, has no estimate: the result belongs to another model, or was edited",
                q.name,
                model_path.display()
            ));
        }
    }
    Ok(())
}
