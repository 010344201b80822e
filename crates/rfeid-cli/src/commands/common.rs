//! What several commands share: loading a model and its data, `--set`.
use crate::diagnostics::{model_error, Failure};
use crate::ui::Ui;
use rfeid::io::data_file::read_measurement;
use rfeid::io::model_file::load_model;
use rfeid::measurement::match_data;
use rfeid::model::Model;
use rfeid::simulation::Response;
use rfeid::simulation::SimulationError;
use rfeid::units::parse_quantity;
use std::path::Path;

/// Loads and validates a model file.
pub fn load(path: &Path) -> Result<Model, Failure> {
    load_model(path).map_err(model_error)
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
/// unit must have the parameter's dimension.
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

/// Fixes parameters for one run (`identify --set NAME=VALUE`): each takes
/// its value and loses its box, so it is not identified.
pub fn fix_parameters(model: &mut Model, sets: &[String]) -> Result<(), Failure> {
    for s in sets {
        let (i, value) = parse_set(model, s)?;
        let p = &mut model.parameters[i];
        p.value = value;
        p.bounds = None;
    }
    Ok(())
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

/// A failed simulation at user-chosen values: parameter values the model
/// cannot take (from `--set`) are bad input (exit 2); a run that diverges is
/// a failed computation (exit 1).
pub fn simulation_failure(what: &str, e: SimulationError) -> Failure {
    match e {
        SimulationError::BadParameter { .. }
        | SimulationError::NonPositiveInertia { .. }
        | SimulationError::BadExponent { .. } => Failure::input_msg(format!("{what}: {e}")),
        _ => Failure::failed(format!("{what}: {e}")),
    }
}

/// Applies `--tolerance` and `--substeps` to the model's sampling.
pub fn apply_steps(model: &mut Model, a: &crate::cli::StepArgs) -> Result<(), Failure> {
    use rfeid::simulation::{MAX_SUBSTEPS, TOLERANCE_RANGE};
    if let Some(t) = a.tolerance {
        if !TOLERANCE_RANGE.contains(&t) {
            return Err(Failure::input_msg(format!(
                "--tolerance {t}: {}",
                rfeid::simulation::steps::tolerance_range_text()
            )));
        }
        model.sampling.tolerance = t;
    }
    if let Some(s) = a.substeps {
        if !(1..=MAX_SUBSTEPS).contains(&s) {
            return Err(Failure::input_msg(format!(
                "--substeps {s}: must be 1 to {MAX_SUBSTEPS}"
            )));
        }
        model.sampling.substeps = Some(s);
    }
    Ok(())
}

/// The integrator's steps in words, with their estimated error.
pub fn steps_note(steps: &rfeid::simulation::StepChoice) -> String {
    format!(
        "integrator: {} step(s) per sample ({}), estimated relative error {}",
        steps.substeps,
        if steps.automatic {
            format!("chosen for tolerance {:.0e}", steps.tolerance)
        } else {
            "fixed".to_string()
        },
        steps
            .estimated_error
            .map(|e| format!("{e:.1e}"))
            .unwrap_or_else(|| "not estimated".into())
    )
}

/// Notes where a run's report was written, if it wrote one.
pub fn report_note(dir: Option<&Path>, ui: &Ui) {
    if let Some(dir) = dir {
        ui.note(format!(
            "report written to {}",
            dir.join("report.html").display()
        ));
    }
}
