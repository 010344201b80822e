//! What `rfeid design` prints and writes: the table of predicted standard
//! errors (placed, and chosen with `--choose`), the choice's certificate,
//! the experiments' worth, and the JSON of SPEC §6.
use crate::format::{sig, table};
use rfeid::design::predict::{warning_texts, Prediction};
use rfeid::design::Design;
use rfeid::model::{ColumnName, Model, Parameter};
use serde_json::{json, Value};

/// The model parameter of decision variable `name` (`name[experiment]`).
fn parameter<'m>(model: &'m Model, name: &str) -> &'m Parameter {
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
pub fn design_json(model: &Model, d: &Design) -> Value {
    let placed = prediction_json(model, d, &d.placed);
    let mut top = match &d.chosen {
        Some(c) => prediction_json(model, d, &c.prediction),
        None => placed.clone(),
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
    obj.insert("placed".into(), placed);
    if let Some(c) = &d.chosen {
        obj.insert(
            "choice".into(),
            json!({
                "search": c.search,
                "upper_bound_log_det": c.upper_bound,
                "efficiency_at_least": c.efficiency_at_least,
                "determinant_ratio_log": c.prediction.log_det - d.placed.log_det,
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
            }),
        );
    }
    top
}

/// The table of predicted standard errors: placed, and chosen.
fn parameter_table(model: &Model, d: &Design) -> String {
    let chosen = d.chosen.as_ref().map(|c| &c.prediction);
    let rows: Vec<Vec<String>> = d
        .parts
        .columns
        .iter()
        .enumerate()
        .map(|(j, name)| {
            let p = parameter(model, name);
            let shown = |v: f64| sig(v / p.unit.scale, 4);
            let se = |pr: &Prediction| match (pr.std_errors.get(j), pr.relative_std_errors.get(j)) {
                (Some(s), Some(r)) if r.is_finite() => [shown(*s), format!("{:.3}", 100.0 * r)],
                (Some(s), _) => [shown(*s), "-".into()],
                _ => ["-".into(), "-".into()],
            };
            let mut row = vec![
                name.clone(),
                if p.unit.symbol.is_empty() {
                    p.dimension.to_string()
                } else {
                    p.unit.symbol.clone()
                },
                shown(d.parts.values[j]),
            ];
            row.extend(se(&d.placed));
            if let Some(c) = chosen {
                row.extend(se(c));
                row.push(match (d.placed.std_errors.get(j), c.std_errors.get(j)) {
                    (Some(a), Some(b)) => format!("{:.2}", a / b),
                    _ => "-".into(),
                });
            }
            row
        })
        .collect();
    let mut header = vec!["parameter", "unit", "value", "s.e. placed", "% placed"];
    if chosen.is_some() {
        header.extend(["s.e. chosen", "% chosen", "placed/chosen"]);
    }
    table(&header, &rows)
}

/// Prints the design.
pub fn print_design(model: &Model, d: &Design) {
    let placed: Vec<&str> = model.sensors.iter().map(|s| s.name.as_str()).collect();
    println!(
        "Predicted at the parameters' values, each sensor's `noise` as its σ (Cramér–Rao, eq. 26–29); placed sensors: {}",
        placed.join(", ")
    );
    println!();
    print!("{}", parameter_table(model, d));
    println!();
    let cond = |p: &Prediction| p.condition_number.map_or("-".into(), |c| sig(c, 3));
    println!(
        "placed: log det F = {:.3}, condition number {}, N = {}",
        d.placed.log_det,
        cond(&d.placed),
        d.placed.observations
    );
    for w in warning_texts(&d.parts.columns, &d.placed) {
        println!("  warning (placed): {w}");
    }
    if let Some(c) = &d.chosen {
        let r = d.parts.columns.len() as f64;
        let gain = c.prediction.log_det - d.placed.log_det;
        println!(
            "chosen ({}): {}",
            match c.search {
                rfeid::design::choose::Search::Exhaustive => "every subset tried",
                rfeid::design::choose::Search::GreedyExchange => "greedy, then exchanges",
            },
            c.names.join(", ")
        );
        println!(
            "with them: log det F = {:.3} (det ratio e^{:.2}, {:.2}× the information per parameter), condition number {}",
            c.prediction.log_det,
            gain,
            (gain / r).exp(),
            cond(&c.prediction)
        );
        println!(
            "optimality: no set of {} reaches log det F above {:.3} (convex relaxation), so the choice's D-efficiency is at least {:.4}",
            c.chosen.len(),
            c.upper_bound,
            c.efficiency_at_least
        );
        for w in warning_texts(&d.parts.columns, &c.prediction) {
            println!("  warning (chosen): {w}");
        }
    }
    if let Some(b) = &d.over_box {
        let names = |s: &[usize]| -> String {
            s.iter()
                .map(|&i| model.candidates[i].name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut eff = b.efficiency.clone();
        eff.sort_by(f64::total_cmp);
        println!(
            "over the box ({} LP_τ points{}): chosen for the average log det; at the values alone: {}; {} of {} points would choose it or an equally good set on their own; its D-efficiency against each point's own best: min {:.3}, median {:.3}",
            b.points,
            if b.failed > 0 { format!(", {} failed and left out", b.failed) } else { String::new() },
            names(&b.at_values),
            b.agree,
            b.points,
            eff.first().copied().unwrap_or(f64::NAN),
            eff.get(eff.len() / 2).copied().unwrap_or(f64::NAN)
        );
    }
    if !d.experiments.is_empty() {
        println!("experiments (information each adds; the campaign's D-efficiency without it):");
        for e in &d.experiments {
            println!(
                "  {}: log det +{:.3}, without it {:.3}",
                e.name, e.log_det_gain, e.efficiency_without
            );
        }
    }
}
