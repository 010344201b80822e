//! What `rfeid design` prints and writes: the table of predicted standard
//! errors (placed, and chosen with `--choose`), the choice's certificate,
//! the experiments' worth, and the JSON of SPEC §6. With no sensor placed
//! the choice is compared with no sensor: its own (absolute and relative)
//! standard errors, no ratio.
use crate::format::{sig, table};
use rfeid::design::choose::Search;
use rfeid::design::json::parameter;
use rfeid::design::over_box::BoxChoice;
use rfeid::design::predict::{warning_texts, Prediction};
use rfeid::design::{ChosenSet, Design};
use rfeid::model::Model;

/// A percentage with three decimals, or in e-notation from 10⁶ % on (a
/// standard error 10⁴ times the value and beyond).
fn percent(p: f64) -> String {
    match p.abs() < 1e6 {
        true => format!("{p:.3}"),
        false => format!("{p:.3e}"),
    }
}

/// The table of predicted standard errors: placed (if any are), and
/// chosen, with their ratio when both are there.
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
                (Some(s), Some(r)) if r.is_finite() => [shown(*s), percent(100.0 * r)],
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
            if let Some(p) = &d.placed {
                row.extend(se(p));
            }
            if let Some(c) = chosen {
                row.extend(se(c));
            }
            if let (Some(p), Some(c)) = (&d.placed, chosen) {
                row.push(match (p.std_errors.get(j), c.std_errors.get(j)) {
                    (Some(a), Some(b)) => format!("{:.2}", a / b),
                    _ => "-".into(),
                });
            }
            row
        })
        .collect();
    let mut header = vec!["parameter", "unit", "value"];
    if d.placed.is_some() {
        header.extend(["s.e. placed", "% placed"]);
    }
    if chosen.is_some() {
        header.extend(["s.e. chosen", "% chosen"]);
    }
    if d.placed.is_some() && chosen.is_some() {
        header.push("placed/chosen");
    }
    table(&header, &rows)
}

/// Prints the design.
pub fn print_design(model: &Model, d: &Design) {
    let placed: Vec<&str> = model.sensors.iter().map(|s| s.name.as_str()).collect();
    println!(
        "Predicted at the parameters' values, each sensor's `noise` as its σ (Cramér–Rao, eq. 26–29); placed sensors: {}",
        match placed.is_empty() {
            true => "none".into(),
            false => placed.join(", "),
        }
    );
    println!();
    print!("{}", parameter_table(model, d));
    println!();
    print_placed(d);
    if let Some(c) = &d.chosen {
        print_choice(d, c);
    }
    if let Some(b) = &d.over_box {
        print_over_box(model, b);
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

/// The placed sensors' log det, condition number and warnings; with none
/// placed, that the choice is compared with no sensor.
fn print_placed(d: &Design) {
    let Some(p) = &d.placed else {
        println!(
            "placed: none (every sensor is a candidate): the choice is compared with no sensor, whose Fisher matrix is 0 (no parameter identifiable), so no ratio is given; the standard errors above are the chosen sensors' own"
        );
        return;
    };
    let log_det = match p.log_det.is_finite() {
        true => format!("{:.3}", p.log_det),
        false => "- (F singular)".into(),
    };
    println!(
        "placed: log det F = {log_det}, condition number {}, N = {}",
        p.condition_number.map_or("-".into(), |c| sig(c, 3)),
        p.observations
    );
    for w in warning_texts(&d.parts.columns, p) {
        println!("  warning (placed): {w}");
    }
}

/// The chosen sensors, what they add and the choice's certificate; with a
/// Fisher matrix still singular, that the choice cannot be judged by its
/// information (no NaN or infinite numbers).
fn print_choice(d: &Design, c: &ChosenSet) {
    let r = d.parts.columns.len() as f64;
    println!(
        "chosen ({}): {}",
        match c.search {
            Search::Exhaustive => "every subset tried",
            Search::GreedyExchange => "greedy, then exchanges",
        },
        c.names.join(", ")
    );
    if !c.prediction.log_det.is_finite() {
        let why = c
            .prediction
            .error
            .as_deref()
            .unwrap_or("the Fisher matrix is singular");
        println!(
            "with them: {why}; the choice cannot be judged by its information (no set of {} makes F regular): fix or tie the parameters named, or add other sensors",
            c.chosen.len()
        );
        return;
    }
    let against = match &d.placed {
        None => "compared with no sensor: F = 0 before, so no ratio".into(),
        Some(p) => match c.prediction.log_det - p.log_det {
            gain if gain.is_finite() => format!(
                "det ratio e^{gain:.2}, {:.2}× the information per parameter",
                (gain / r).exp()
            ),
            _ => "det ratio -, placed: singular".into(),
        },
    };
    println!(
        "with them: log det F = {:.3} ({against}), condition number {}",
        c.prediction.log_det,
        c.prediction
            .condition_number
            .map_or("-".into(), |v| sig(v, 3))
    );
    println!(
        "optimality: no set of {} reaches log det F above {:.3} (convex relaxation), so the choice's D-efficiency is at least {:.4}",
        c.chosen.len(),
        c.upper_bound,
        c.efficiency_at_least
    );
    for w in c.warning_texts(&d.parts.columns) {
        println!("  warning (chosen): {w}");
    }
}

/// The box design: the robust choice against the choice at the values and
/// each point's own best; points where F is singular whatever is chosen
/// are said to be so, and left out of the efficiencies.
fn print_over_box(model: &Model, b: &BoxChoice) {
    let names = |s: &[usize]| -> String {
        s.iter()
            .map(|&i| model.candidates[i].name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut eff: Vec<f64> = b
        .efficiency
        .iter()
        .copied()
        .filter(|e| e.is_finite())
        .collect();
    eff.sort_by(f64::total_cmp);
    let spread = match (eff.first(), eff.get(eff.len() / 2)) {
        (Some(min), Some(median)) => format!(
            "its D-efficiency against each point's own best: min {min:.3}, median {median:.3}"
        ),
        _ => "its D-efficiency cannot be judged at any point".into(),
    };
    println!(
        "over the box ({} LP_τ points{}): chosen for the average log det; at the values alone: {}; {} of {} points would choose it or an equally good set on their own; {spread}",
        b.points,
        if b.failed > 0 { format!(", {} failed and left out", b.failed) } else { String::new() },
        names(&b.at_values),
        b.agree,
        b.points,
    );
    if b.singular > 0 {
        println!(
            "  warning (over the box): the Fisher matrix is singular at {} of {} points whatever is chosen (some parameters cannot be told apart there, see the warnings above): every choice is as good there, and none can be judged",
            b.singular, b.points
        );
    }
}
