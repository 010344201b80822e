//! Parameter values given for one run as `NAME=VALUE` (the option `set`:
//! `--set` on the command line, `set={…}` in the Python module), and the
//! integrator's `tolerance` / `substeps` given for one run. The value may carry a unit
//! (`P0=20 daN`), which must have the parameter's dimension. Edits go
//! through the validated [`Model::with_fixed`] and [`Model::with_steps`].
use super::{EditError, Model};
use crate::identification::options::OptionError;
use crate::simulation::MAX_SUBSTEPS;
use crate::units::parse_quantity;

/// A `NAME=VALUE` setting or a step option refused: an option's error
/// (`set`, `tolerance`, `substeps`), which each front end spells its own
/// way ([`OptionError::spelt`]).
pub type SetError = OptionError;

/// One `NAME=VALUE`: the parameter's index and the value in SI.
pub fn parse_set(model: &Model, s: &str) -> Result<(usize, f64), SetError> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| OptionError::new("set", format!("'{s}': expected NAME=VALUE")))?;
    let name = name.trim();
    let i = model.parameter_index(name).ok_or_else(|| {
        let known: Vec<&str> = model.parameters.iter().map(|p| p.name.as_str()).collect();
        OptionError::new(
            "set",
            format!(
                ": unknown parameter '{name}' (parameters: {})",
                known.join(", ")
            ),
        )
    })?;
    let q = parse_quantity(value).map_err(|e| OptionError::new("set", format!("{name}: {e}")))?;
    let p = &model.parameters[i];
    let bare = value.trim().parse::<f64>().is_ok();
    if !bare && q.dim != p.dimension {
        let detail = format!(
            "{name}: '{value}' has the dimension {}, but {name} is {}",
            q.dim, p.dimension
        );
        return Err(OptionError::new("set", detail));
    }
    if !q.value.is_finite() {
        return Err(OptionError::new(
            "set",
            format!("{name}: not a finite number"),
        ));
    }
    Ok((i, q.value))
}

/// Applies `NAME=VALUE` settings to parameter values `params` (SI). A value
/// outside the parameter's box is not refused; the warnings say which, each
/// worded as a message about `set` for the front end to spell. A parameter
/// given twice is refused.
pub fn apply_sets(
    model: &Model,
    sets: &[String],
    params: &mut [f64],
) -> Result<Vec<OptionError>, SetError> {
    let mut warnings = Vec::new();
    for (i, value) in parse_once(model, sets)? {
        let p = &model.parameters[i];
        if let Some((lo, hi)) = p.bounds.filter(|&(lo, hi)| value < lo || value > hi) {
            let detail = format!(
                "{}: the value lies outside its box [{lo:e}, {hi:e}] (SI)",
                p.name
            );
            warnings.push(OptionError::new("set", detail));
        }
        params[i] = value;
    }
    Ok(warnings)
}

/// [`apply_sets`] for a run over every experiment of the model file (`design`
/// of a campaign): a parameter an experiment sets itself is refused too,
/// as its experiments' own values would override it.
pub fn apply_sets_to_campaign(
    model: &Model,
    sets: &[String],
    params: &mut [f64],
) -> Result<Vec<OptionError>, SetError> {
    for (s, (i, _)) in sets.iter().zip(parse_once(model, sets)?) {
        not_set_by_experiments(model, i, s)?;
    }
    apply_sets(model, sets, params)
}

/// Each setting parsed; a parameter given twice is refused.
fn parse_once(model: &Model, sets: &[String]) -> Result<Vec<(usize, f64)>, SetError> {
    let mut given: Vec<(usize, f64, &str)> = Vec::new();
    for s in sets {
        let (i, value) = parse_set(model, s)?;
        if let Some((_, _, earlier)) = given.iter().find(|(j, _, _)| *j == i) {
            let detail = format!(
                "'{s}': {} is already set by `set` '{earlier}'; give each parameter once",
                model.parameters[i].name
            );
            return Err(OptionError::new("set", detail));
        }
        given.push((i, value, s));
    }
    Ok(given.into_iter().map(|(i, v, _)| (i, v)).collect())
}

/// Refuses setting parameter `i` (by `s`) where an experiment of the model
/// file sets it itself: each experiment's own `set` would win, silently.
fn not_set_by_experiments(model: &Model, i: usize, s: &str) -> Result<(), SetError> {
    let setters: Vec<&str> = model
        .experiments
        .iter()
        .filter(|x| x.set.iter().any(|(j, _)| *j == i))
        .map(|x| x.name.as_str())
        .collect();
    if setters.is_empty() {
        return Ok(());
    }
    let detail = format!(
        "'{s}': {} is set by the experiment{} {} of the model file (`set = {{ … }}`), which would override it; change it there",
        model.parameters[i].name,
        if setters.len() == 1 { "" } else { "s" },
        setters.join(", ")
    );
    Err(OptionError::new("set", detail))
}

/// The model with parameters fixed for one run (`set` of `identify`):
/// each takes its value and loses its box, so it is not identified. A parameter given twice, or one an experiment of the model
/// file sets itself, is refused.
pub fn fixed(model: Model, sets: &[String]) -> Result<Model, SetError> {
    let parsed = parse_once(&model, sets)?;
    sets.iter()
        .zip(parsed)
        .try_fold(model, |model, (s, (i, value))| {
            not_set_by_experiments(&model, i, s)?;
            model.with_fixed(i, value).map_err(set_failure)
        })
}

/// The model with `tolerance` and `substeps` applied to its sampling.
pub fn stepped(
    model: Model,
    tolerance: Option<f64>,
    substeps: Option<usize>,
) -> Result<Model, SetError> {
    model.with_steps(tolerance, substeps).map_err(|e| match e {
        EditError::Tolerance(t) => OptionError::new(
            "tolerance",
            format!(
                "{t:e}: {}",
                crate::simulation::steps::tolerance_range_text()
            ),
        ),
        EditError::Substeps(s) => {
            OptionError::new("substeps", format!("{s}: must be 1 to {MAX_SUBSTEPS}"))
        }
        other => OptionError::new("tolerance", format!(": {other}")),
    })
}

/// A refused `set` edit, worded like [`parse_set`]'s own refusals.
fn set_failure(e: EditError) -> SetError {
    match e {
        EditError::NotFinite { name, .. } => {
            OptionError::new("set", format!("{name}: not a finite number"))
        }
        other => OptionError::new("set", format!(": {other}")),
    }
}
