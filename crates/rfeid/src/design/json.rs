//! A design as JSON (SPEC §6), the document `rfeid design -o` writes and
//! the Python module's `design` returns, and the checks of a design's
//! request (`choose`, `over_box`, values inside the box).
use super::predict::{warning_texts, Prediction};
use super::Design;
use crate::identification::options::OptionError;
use crate::model::{ColumnName, Model, Parameter};
use serde_json::{json, Value};

/// Most points of `over_box`.
pub const MAX_OVER_BOX: usize = 4096;

/// A design asked for that cannot be made: an option out of range, or a
/// model that cannot give what is asked (no candidates; values outside the
/// box), as [`RequestError::of_model`] says. Either way the message is an
/// option's ([`OptionError`]), for each front end to spell.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{error}")]
pub struct RequestError {
    error: OptionError,
    model: bool,
}

impl RequestError {
    fn option(option: &'static str, detail: String) -> Self {
        let error = OptionError::new(option, detail);
        RequestError {
            error,
            model: false,
        }
    }

    fn model(option: &'static str, detail: String) -> Self {
        let error = OptionError::new(option, detail);
        RequestError { error, model: true }
    }

    /// Whether the model (rather than an option) is at fault.
    pub fn of_model(&self) -> bool {
        self.model
    }

    /// The option the message is about.
    pub fn option_error(&self) -> &OptionError {
        &self.error
    }
}

/// Checks `choose` and `over_box` against their limits and the model's
/// candidates, before anything is simulated; `model_label` names the model
/// file in the messages. A model without placed sensors needs `choose`.
pub fn check_request(
    model: &Model,
    model_label: &str,
    choose: Option<usize>,
    over_box: Option<usize>,
) -> Result<(), RequestError> {
    if model.sensors.is_empty() && choose.is_none() {
        return Err(RequestError::model("choose", no_placed_sensor(model_label)));
    }
    if let Some(k) = choose {
        if k == 0 {
            return Err(RequestError::option(
                "choose",
                "0: choose at least one sensor".into(),
            ));
        }
        if model.candidates.is_empty() {
            return Err(RequestError::model("choose", format!(
                "{k}: {model_label} has no candidate sensors: mark the places a sensor could go with `candidate = true` in their [[sensor]] entries"
            )));
        }
    }
    match (over_box, choose) {
        (Some(_), None) => Err(RequestError::option(
            "over_box",
            "without `choose`: the box design chooses sensors; give `choose` too".into(),
        )),
        (Some(n), _) if !(1..=MAX_OVER_BOX).contains(&n) => Err(RequestError::option(
            "over_box",
            format!("{n}: must be 1 to {MAX_OVER_BOX} points"),
        )),
        _ => Ok(()),
    }
}

/// What `choose` not given says of `model_label`, a model that places no
/// sensor.
pub(crate) fn no_placed_sensor(model_label: &str) -> String {
    format!(
        "is needed: {model_label} places no sensor (every [[sensor]] is a candidate), so the design chooses where K sensors go (`choose` K) and compares them with no sensor"
    )
}

/// The model with its parameters' values set to `values` (SI), each of
/// which must lie in its parameter's box: a design predicts inside the box.
pub fn at_values(mut model: Model, values: Vec<f64>) -> Result<Model, RequestError> {
    for (p, v) in model.parameters.iter().zip(&values) {
        if let Some((lo, hi)) = p.bounds.filter(|(lo, hi)| !(lo..=hi).contains(&v)) {
            return Err(RequestError::model("set", format!(
                "{}: {v:e} lies outside its box [{lo:e}, {hi:e}] (SI): a design predicts inside the box; widen min and max in the model file to design there",
                p.name
            )));
        }
    }
    for (p, v) in model.parameters.iter_mut().zip(values) {
        p.value = v;
    }
    Ok(model)
}

/// The model parameter of decision variable `name` (`name[experiment]`).
pub fn parameter<'m>(model: &'m Model, name: &str) -> &'m Parameter {
    let Ok(c) = name.parse::<ColumnName>();
    let i = model
        .parameter_index(&c.name)
        .expect("a design's columns are the model's parameters");
    &model.parameters[i]
}

/// One prediction as JSON: log det, standard errors by parameter,
/// correlations, condition number, warnings.
fn prediction_json(model: &Model, d: &Design, p: &Prediction) -> Value {
    let parameters: Vec<Value> = d
        .parts
        .columns
        .iter()
        .enumerate()
        .map(|(j, name)| {
            json!({
                "name": name,
                "unit": parameter(model, name).unit.symbol,
                "value": d.parts.values[j],
                "std_error": p.std_errors.get(j),
                "relative_std_error": p.relative_std_errors.get(j),
            })
        })
        .collect();
    json!({
        "log_det": p.log_det,
        "observations": p.observations,
        "parameters": parameters,
        "correlation": p.correlation,
        "condition_number": p.condition_number,
        "warnings": warning_texts(&d.parts.columns, p),
    })
}

/// The design as JSON (SPEC §6): the final design's `chosen`, `log_det`,
/// `parameters`, `correlation` and `warnings` at the top, the placed
/// sensors' prediction under `placed`, and the choice's certificate, the
/// experiments' worth and the box design where there are any.
///
/// `compared_with` says what the choice is compared with:
/// `"placed_sensors"`, or `"no_sensor"` when none is placed; then
/// `placed_sensors` is empty, `placed` is null and so is the choice's
/// `determinant_ratio_log` (against F = 0 there is no ratio: the chosen
/// set's own standard errors, at the top, are the comparison).
pub fn design_json(model: &Model, d: &Design) -> Value {
    let placed = d.placed.as_ref().map(|p| prediction_json(model, d, p));
    let mut top = match (&d.chosen, &placed) {
        (Some(c), _) => prediction_json(model, d, &c.prediction),
        (None, Some(p)) => p.clone(),
        (None, None) => Value::Object(Default::default()),
    };
    let obj = top.as_object_mut().expect("an object");
    obj.insert(
        "chosen".into(),
        json!(d.chosen.as_ref().map_or(Vec::new(), |c| c.names.clone())),
    );
    obj.insert(
        "placed_sensors".into(),
        json!(model.sensors.iter().map(|s| &s.name).collect::<Vec<_>>()),
    );
    obj.insert(
        "compared_with".into(),
        json!(match d.placed {
            Some(_) => "placed_sensors",
            None => "no_sensor",
        }),
    );
    obj.insert("placed".into(), json!(placed));
    if let Some(c) = &d.chosen {
        obj.insert("warnings".into(), json!(c.warning_texts(&d.parts.columns)));
        obj.insert(
            "choice".into(),
            json!({
                "search": c.search,
                "upper_bound_log_det": c.upper_bound,
                "efficiency_at_least": c.efficiency_at_least,
                "determinant_ratio_log": d.placed.as_ref().map(|p| c.prediction.log_det - p.log_det),
            }),
        );
    }
    obj.insert("experiments".into(), json!(d.experiments));
    if let Some(b) = &d.over_box {
        let names = |s: &[usize]| -> Vec<String> {
            s.iter()
                .map(|&i| model.candidates[i].name.clone())
                .collect()
        };
        obj.insert(
            "over_box".into(),
            json!({
                "points": b.points,
                "failed": b.failed,
                "first_failure": b.first_failure,
                "robust": names(&b.robust),
                "at_values": names(&b.at_values),
                "points_agreeing": b.agree,
                "efficiency": b.efficiency,
                "points_singular": b.singular,
            }),
        );
    }
    top
}
