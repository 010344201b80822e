//! Inputs of a run: a model file, its measured data, `--set` and
//! `--tolerance` / `--substeps`. Edits of a model go through the library's
//! validated edits ([`Model::with_fixed`], [`Model::with_steps`]).
use crate::cli::StepArgs;
use crate::diagnostics::{model_error, Failure};
use crate::ui::Ui;
use rfeid::io::data_file::read_measurement;
use rfeid::io::model_file::load_model;
use rfeid::measurement::match_data;
use rfeid::model::{EditError, Model};
use rfeid::simulation::{Response, MAX_SUBSTEPS};
use rfeid::units::parse_quantity;
use std::path::Path;

/// Loads and validates a model file; the reading's notes (a signal
/// table's time axis taken on the model's grid) go to the terminal.
pub fn load(path: &Path, ui: &Ui) -> Result<Model, Failure> {
    let model = load_model(path).map_err(model_error)?;
    for note in &model.notes {
        ui.note(format!("note: {note}"));
    }
    Ok(model)
}

/// Reads the measured data of `model`'s sensors from `path` on the model's
/// sampling; the reading's notes (columns ignored, a record shifted or cut)
/// go to the terminal. Every problem is bad input naming the file.
pub fn load_data(path: &Path, model: &Model, ui: &Ui) -> Result<Response, Failure> {
    let sources: Vec<_> = model.sensors.iter().map(|s| s.data.clone()).collect();
    let read = read_measurement(path, model, &sources).map_err(Failure::input_msg)?;
    let matched = match_data(model, &read.series)
        .map_err(|e| Failure::input_msg(format!("{}: {e}", path.display())))?;
    for note in read.notes {
        ui.note(format!("note: {note}"));
    }
    for note in matched.notes {
        ui.note(format!("note: {}: {note}", path.display()));
    }
    Ok(matched.response)
}

/// Applies `NAME=VALUE` settings to parameter values (SI); a value with a
/// unit must have the parameter's dimension. A value outside the
/// parameter's box is warned about, not refused.
pub fn apply_sets(model: &Model, sets: &[String], params: &mut [f64]) -> Result<(), Failure> {
    for s in sets {
        let (i, value) = parse_set(model, s)?;
        let p = &model.parameters[i];
        if let Some((lo, hi)) = p.bounds {
            if value < lo || value > hi {
                let name = &p.name;
                tracing::warn!("--set {name}: {value} lies outside its box [{lo:e}, {hi:e}]");
                eprintln!(
                    "warning: --set {name}: the value lies outside its box [{lo:e}, {hi:e}] (SI)"
                );
            }
        }
        params[i] = value;
    }
    Ok(())
}

/// The model with parameters fixed for one run (`identify --set
/// NAME=VALUE`): each takes its value and loses its box, so it is not
/// identified.
pub fn fixed(model: Model, sets: &[String]) -> Result<Model, Failure> {
    let mut given: Vec<(usize, &str)> = Vec::new();
    sets.iter().try_fold(model, |model, s| {
        let (i, value) = parse_set(&model, s)?;
        if let Some((_, earlier)) = given.iter().find(|(j, _)| *j == i) {
            return Err(Failure::input_msg(format!(
                "--set '{s}': {} is already set by --set '{earlier}'; give each parameter once",
                model.parameters[i].name
            )));
        }
        given.push((i, s));
        let setters: Vec<&str> = model
            .experiments
            .iter()
            .filter(|x| x.set.iter().any(|(j, _)| *j == i))
            .map(|x| x.name.as_str())
            .collect();
        if !setters.is_empty() {
            // Each experiment's own `set` would win over it, silently.
            return Err(Failure::input_msg(format!(
                "--set '{s}': {} is set by the experiment{} {} of the model file (`set = {{ … }}`), which would override it; change it there",
                model.parameters[i].name,
                if setters.len() == 1 { "" } else { "s" },
                setters.join(", ")
            )));
        }
        model.with_fixed(i, value).map_err(set_failure)
    })
}

/// The model with `--tolerance` and `--substeps` applied to its sampling.
pub fn stepped(model: Model, a: &StepArgs) -> Result<Model, Failure> {
    model
        .with_steps(a.tolerance, a.substeps)
        .map_err(|e| match e {
            EditError::Tolerance(t) => Failure::input_msg(format!(
                "--tolerance {t:e}: {}",
                rfeid::simulation::steps::tolerance_range_text()
            )),
            EditError::Substeps(s) => {
                Failure::input_msg(format!("--substeps {s}: must be 1 to {MAX_SUBSTEPS}"))
            }
            other => Failure::input_msg(other),
        })
}

/// A refused `--set` edit as bad input, worded like [`parse_set`]'s own
/// refusals.
fn set_failure(e: EditError) -> Failure {
    match e {
        EditError::NotFinite { name, .. } => {
            Failure::input_msg(format!("--set {name}: not a finite number"))
        }
        other => Failure::input_msg(format!("--set: {other}")),
    }
}

/// One `NAME=VALUE`: the parameter's index and the value in SI.
fn parse_set(model: &Model, s: &str) -> Result<(usize, f64), Failure> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| Failure::input_msg(format!("--set '{s}': expected NAME=VALUE")))?;
    let name = name.trim();
    let i = model.parameter_index(name).ok_or_else(|| {
        let known: Vec<&str> = model.parameters.iter().map(|p| p.name.as_str()).collect();
        Failure::input_msg(format!(
            "--set: unknown parameter '{name}' (parameters: {})",
            known.join(", ")
        ))
    })?;
    let q = parse_quantity(value).map_err(|e| Failure::input_msg(format!("--set {name}: {e}")))?;
    let p = &model.parameters[i];
    let bare = value.trim().parse::<f64>().is_ok();
    if !bare && q.dim != p.dimension {
        return Err(Failure::input_msg(format!(
            "--set {name}: '{value}' has the dimension {}, but {name} is {}",
            q.dim, p.dimension
        )));
    }
    if !q.value.is_finite() {
        return Err(Failure::input_msg(format!(
            "--set {name}: not a finite number"
        )));
    }
    Ok((i, q.value))
}
