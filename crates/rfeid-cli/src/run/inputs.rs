//! Inputs of a run: a model file, its measured data, `--set` and
//! `--tolerance` / `--substeps`, through the library's
//! [`rfeid::model::set_values`].
use crate::cli::StepArgs;
use crate::diagnostics::{model_error, Failure};
use crate::run::failures::{failure, option_text};
use crate::ui::Ui;
use rfeid::io::model_file::{load_model_for, Purpose};
use rfeid::measurement::measured::measured_from_file;
use rfeid::model::{set_values, Model};
use rfeid::simulation::Response;
use std::path::Path;

/// Loads and validates a model file for a test's data (it must place a
/// sensor, [`Purpose::Measure`]); the reading's notes (a signal table's
/// time axis taken on the model's grid) go to the terminal.
pub fn load(path: &Path, ui: &Ui) -> Result<Model, Failure> {
    load_for(path, Purpose::Measure, ui)
}

/// [`load`] for `purpose`: `design` reads with [`Purpose::Design`], which
/// accepts a model whose sensors are all candidates.
pub fn load_for(path: &Path, purpose: Purpose, ui: &Ui) -> Result<Model, Failure> {
    let model = load_model_for(path, purpose).map_err(model_error)?;
    for note in &model.notes {
        ui.note(format!("note: {note}"));
    }
    Ok(model)
}

/// Reads the measured data of `model`'s sensors from `path` on the model's
/// sampling; the reading's notes (columns ignored, a record shifted or cut)
/// go to the terminal. Every problem is bad input naming the file.
pub fn load_data(path: &Path, model: &Model, ui: &Ui) -> Result<Response, Failure> {
    let m = measured_from_file(path, model).map_err(Failure::input_msg)?;
    for note in m.notes {
        ui.note(format!("note: {note}"));
    }
    Ok(m.response)
}

/// Applies `NAME=VALUE` settings to parameter values (SI)
/// ([`set_values::apply_sets`]); a value outside the parameter's box is
/// warned about, not refused.
pub fn apply_sets(model: &Model, sets: &[String], params: &mut [f64]) -> Result<(), Failure> {
    let warnings = set_values::apply_sets(model, sets, params).map_err(failure)?;
    for w in warnings {
        let w = option_text(&w);
        tracing::warn!("{w}");
        eprintln!("warning: {w}");
    }
    Ok(())
}

/// `--set` for `design`, which runs every experiment of a campaign: a
/// parameter an experiment sets is refused too
/// ([`set_values::apply_sets_to_campaign`]). Nothing is warned: a value
/// outside its box, which other commands warn about, is refused by the
/// design itself ([`rfeid::design::json::at_values`]).
pub fn apply_campaign_sets(
    model: &Model,
    sets: &[String],
    params: &mut [f64],
) -> Result<(), Failure> {
    set_values::apply_sets_to_campaign(model, sets, params).map_err(failure)?;
    Ok(())
}

/// The model with parameters fixed for one run (`identify --set
/// NAME=VALUE`, [`set_values::fixed`]).
pub fn fixed(model: Model, sets: &[String]) -> Result<Model, Failure> {
    set_values::fixed(model, sets).map_err(failure)
}

/// The model with `--tolerance` and `--substeps` applied to its sampling.
pub fn stepped(model: Model, a: &StepArgs) -> Result<Model, Failure> {
    set_values::stepped(model, a.tolerance, a.substeps).map_err(failure)
}
