//! What `rfeid design` prints and writes: the table of predicted standard
//! errors (placed, and chosen with `--choose`), the choice's certificate,
//! the experiments' worth, and the JSON of SPEC §6.
use crate::format::{sig, table};
use rfeid::design::json::parameter;
use rfeid::design::predict::{warning_texts, Prediction};
use rfeid::design::Design;
use rfeid::model::Model;

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
