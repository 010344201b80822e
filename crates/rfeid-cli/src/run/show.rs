//! The results shown after a search: the paper-style tables (Tables 1–2)
//! and the notes, or the result as JSON with `--json`.
use super::profile_text::write_profiles;
use super::verdict_text::write_verdict;
use crate::diagnostics::Failure;
use crate::format::{sig, table};
use crate::outputs::Checked;
use crate::ui::Ui;
use rfeid::identification::noise::StdErrorScope;
use rfeid::identification::result::IdentificationResult;
use rfeid::model::{Model, Role};
use rfeid::simulation::StepChoice;
use std::fmt::Write as _;
use std::path::Path;

/// The tables, or the result as JSON with `--json`. When an output file
/// went to standard output, the tables go to standard error (unless
/// `--quiet`).
pub fn show_result(
    model: &Model,
    r: &IdentificationResult,
    reference: &str,
    timings: bool,
    stdout_taken: bool,
    ui: &Ui,
) -> Result<(), Failure> {
    if ui.json {
        ui.print_json(r)
    } else {
        let text = format_result(model, r, reference, timings);
        if !stdout_taken {
            print!("{text}");
        } else if !ui.quiet {
            eprint!("{text}");
        }
        Ok(())
    }
}

/// Refuses `--json` when an output file goes to standard output.
pub fn json_conflict(ui: &Ui, outputs: &Checked) -> Result<(), Failure> {
    if ui.json && outputs.uses_stdout() {
        return Err(Failure::input_msg(
            "--json: standard output already carries an output file (-); drop one of them",
        ));
    }
    Ok(())
}

/// The integrator's steps in words, with their estimated error.
pub fn steps_note(steps: &StepChoice) -> String {
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

/// [`steps_note`] for an identification: with the fewer steps the plan and
/// the searches take before the estimate is refined at the chosen ones,
/// when there are fewer.
pub fn search_steps_note(steps: &StepChoice) -> String {
    match steps.search {
        Some(s) => format!(
            "{}; the plan and the searches take {} (estimated error {:.1e}), the estimate is refined at {}",
            steps_note(steps),
            s.substeps,
            s.estimated_error,
            steps.substeps
        ),
        None => steps_note(steps),
    }
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

/// The paper-style tables (Tables 1–2) and diagnostics.
pub fn format_result(
    model: &Model,
    r: &IdentificationResult,
    reference: &str,
    timings: bool,
) -> String {
    let mut out = String::new();
    let _ = writeln!(out);
    out.push_str(&parameter_table(model, r, reference));
    let _ = writeln!(out);
    write_profiles(&mut out, model, r);
    write_search(&mut out, r);
    write_experiments(&mut out, r);
    write_verdict(&mut out, r);
    if timings {
        let _ = writeln!(out, "{}", timings_line(r));
    }
    out
}

/// The `--timings` line: the wall time of the plan (its points abandoned),
/// of each local search from a start, of the bounds, the profiles if any
/// and the whole run, then the simulations with and without
/// sensitivities, how many and their time summed over the threads.
fn timings_line(r: &IdentificationResult) -> String {
    let t = &r.timings;
    let w = &t.simulations;
    let abandoned = match r.plan.abandoned.len() {
        0 => String::new(),
        n => format!(", {n} abandoned"),
    };
    let seconds = |s: &[f64]| {
        s.iter()
            .map(|x| format!("{x:.3}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let searches = match (t.searches.as_slice(), t.discarded.as_slice()) {
        ([] | [_], []) => String::new(),
        (s, []) => format!(" ({} searches: {} s)", s.len(), seconds(s)),
        (s, d) => format!(
            " ({} searches: {} s; {} run at the same time and not needed: {} s)",
            s.len(),
            seconds(s),
            d.len(),
            seconds(d)
        ),
    };
    let profiles = match r.profiles.is_empty() {
        true => String::new(),
        false => format!(" profiles {:.3} s,", t.profiles),
    };
    format!(
        "timings: plan {:.3} s ({} points{abandoned}), local search {:.3} s{searches}, \
         uncertainty {:.3} s,{profiles} total {:.3} s ({} thread{}); simulations: {} plain \
         {:.3} s, {} with sensitivities {:.3} s (summed over threads)",
        t.plan,
        r.plan.points,
        t.local_search,
        t.uncertainty,
        t.total,
        r.threads,
        if r.threads == 1 { "" } else { "s" },
        w.plain,
        w.plain_seconds,
        w.with_sensitivities,
        w.sensitivity_seconds,
    )
}

/// Table 1–2: each identified parameter's box, reference value, estimate
/// and standard error.
fn parameter_table(model: &Model, r: &IdentificationResult, reference: &str) -> String {
    let rows: Vec<Vec<String>> = r
        .parameters
        .iter()
        .map(|p| {
            let show = |v: f64| sig(v / p.unit_scale, 5);
            let unit = if p.unit.is_empty() {
                model
                    .parameter_index(&p.name)
                    .map(|i| model.parameters[i].dimension.to_string())
                    .unwrap_or_default()
            } else {
                p.unit.clone()
            };
            vec![
                p.name.clone(),
                unit,
                show(p.min),
                show(p.max),
                p.scale.as_str().into(),
                show(p.nominal),
                show(p.estimate),
                format!("{:+.3}", 100.0 * (p.estimate - p.nominal) / p.nominal),
                p.std_error
                    .map(|s| sig(s / p.unit_scale, 4))
                    .unwrap_or_else(|| "-".into()),
            ]
        })
        .collect();
    let diff = format!("vs {reference} %");
    let std_error = match r.std_errors_cover {
        StdErrorScope::Noise => "std. error",
        StdErrorScope::NoiseOnly => "std. error (noise only)",
    };
    let header = [
        "parameter",
        "unit",
        "min",
        "max",
        "scale",
        reference,
        "identified",
        &diff,
        std_error,
    ];
    table(&header, &rows)
}

/// The criterion, the search's course and its warnings.
fn write_search(out: &mut String, r: &IdentificationResult) {
    let _ = writeln!(
        out,
        "criterion J = {:.6e}   s² = {}   N = {}",
        r.criterion,
        r.s2.map(|v| format!("{v:.4e}")).unwrap_or("-".into()),
        r.observations
    );
    let _ = writeln!(
        out,
        "{} after {} iteration{} ({})",
        r.termination_message,
        r.iterations,
        if r.iterations == 1 { "" } else { "s" },
        r.method
    );
    let _ = writeln!(
        out,
        "plan: {} points, {} failed{}; simulations: {} (+{} with sensitivities), {} failed",
        r.plan.points,
        r.plan.failed,
        match r.plan.abandoned.len() {
            0 => String::new(),
            n => format!(", {n} abandoned"),
        },
        r.simulations,
        r.simulations_with_sensitivities,
        r.failed_simulations
    );
    if let Some(steps) = &r.simulation {
        let _ = writeln!(out, "{} (at the estimate)", steps_note(steps));
        if let Some(s) = steps.search {
            let _ = writeln!(
                out,
                "searches: the plan and the searches took {} step(s) per sample (estimated error {:.1e}); the estimate was refined at {}",
                s.substeps, s.estimated_error, steps.substeps
            );
        }
    }
    if !r.noise.is_empty() {
        let list: Vec<String> = r
            .noise
            .iter()
            .map(|n| {
                let kind = match n.order {
                    0 => "white".to_string(),
                    p => format!("AR({p})"),
                };
                format!("{} {kind}, σ {:.3e}", n.sensor, n.innovation_std)
            })
            .collect();
        let _ = writeln!(out, "noise model: {}", list.join("; "));
    }
    for f in &r.failed_starts {
        let _ = writeln!(
            out,
            "warning: the local search from plan point {} failed and was skipped: {}",
            f.plan_index + 1,
            f.reason
        );
    }
    if let Some(c) = r.condition_number {
        let _ = writeln!(out, "condition number of the scaled Fisher matrix: {c:.3e}");
    }
    if let Some(e) = &r.uncertainty_error {
        let _ = writeln!(out, "warning: no standard errors: {e}");
    }
    // The profiles' warnings are shown under their table.
    for w in r.warnings.iter().filter(|w| !w.is_profile()) {
        let _ = writeln!(out, "warning: {w}");
    }
}

/// One line per experiment of a campaign, with its fit per sensor.
fn write_experiments(out: &mut String, r: &IdentificationResult) {
    for e in &r.experiments {
        let fits: Vec<String> = e
            .sensors
            .iter()
            .zip(&e.fits)
            .map(|(s, f)| match f {
                Some(f) => format!("{s} {f:.2} %"),
                None => format!("{s} -"),
            })
            .collect();
        let role = match e.role {
            Role::Fit => "fitted",
            Role::Validation => "validation, not fitted",
        };
        let _ = writeln!(
            out,
            "experiment {} ({role}, {} samples from t = {} s): {}",
            e.name,
            e.samples,
            e.from,
            fits.join(", ")
        );
    }
}
