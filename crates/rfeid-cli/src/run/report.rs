//! Report files of a run (`--report`, `rfeid report`), and reading a
//! RESULT.json back.
use crate::diagnostics::Failure;
use rfeid::identification::result::IdentificationResult;
use rfeid::model::Model;
use rfeid::report::at_estimate::{self, RenderError};
use rfeid::simulation::Response;
use std::path::Path;

/// A report's files: (name, text).
pub type ReportFiles = Vec<(String, String)>;

/// Reads a RESULT.json; an unreadable or foreign file is bad input naming it.
pub fn read_result(path: &Path) -> Result<IdentificationResult, Failure> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Failure::input_msg(format!("{}: {e}", path.display())))?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    serde_json::from_str(text).map_err(|e| {
        let shard = serde_json::from_str::<serde_json::Value>(text)
            .is_ok_and(|v| v["format"] == rfeid::io::shard_file::FORMAT);
        match shard {
            true => Failure::input_msg(format!(
                "{}: a shard file of `identify --shard`, not a result: merge the shards first (rfeid merge SHARD… -o RESULT.json)",
                path.display()
            )),
            false => Failure::input_msg(format!("{}: not an rfeid result: {e}", path.display())),
        }
    })
}

/// The report of a campaign ([`at_estimate::render_campaign`]).
pub fn render_campaign(
    model: &Model,
    models: &[Model],
    result: &IdentificationResult,
    measured: &[Response],
    title: &str,
) -> Result<ReportFiles, Failure> {
    at_estimate::render_campaign(model, models, result, measured, title).map_err(render_failure)
}

/// Simulates at the estimate, as experiment `experiment` of a campaign
/// sees it (`""` for a data file on its own), and renders the report's
/// files ([`at_estimate::render`]).
pub fn render(
    model: &Model,
    result: &IdentificationResult,
    experiment: &str,
    measured: &Response,
    reference: Option<&[f64]>,
    title: &str,
) -> Result<ReportFiles, Failure> {
    at_estimate::render(model, result, experiment, measured, reference, title)
        .map_err(render_failure)
}

/// Renders the report's files of `result` with the model's response
/// `fitted` at the estimate already simulated
/// ([`at_estimate::render_fitted`]).
pub fn render_fitted(
    model: &Model,
    result: &IdentificationResult,
    measured: &Response,
    fitted: &Response,
    reference: Option<&[f64]>,
    title: &str,
) -> Result<ReportFiles, Failure> {
    at_estimate::render_fitted(model, result, measured, fitted, reference, title)
        .map_err(render_failure)
}

/// A report not rendered ([`super::failures::failure`]): a failed
/// simulation is a failed computation (1), inputs that do not belong
/// together are bad input (2).
fn render_failure(e: RenderError) -> Failure {
    super::failures::failure(e)
}
