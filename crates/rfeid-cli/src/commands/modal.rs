//! `rfeid modal`: modes of the linearised model.
use crate::cli::ModalArgs;
use crate::diagnostics::Failure;
use crate::format::{sig, table};
use crate::outputs::Plan;
use crate::run::failures::simulation_failure;
use crate::run::inputs::{apply_sets, load};
use crate::run::show::json_conflict;
use crate::ui::Ui;
use rfeid::model::Model;
use rfeid::simulation::modal::{modal_analysis, ModalAnalysis};
use rfeid::simulation::Simulator;

/// Runs the command.
pub fn run(args: ModalArgs, ui: &Ui) -> Result<(), Failure> {
    let model = load(&args.model, ui)?;
    let mut plan = Plan::new();
    plan.input(&args.model);
    for f in &model.files {
        plan.input(f);
    }
    if let Some(path) = &args.json_file {
        plan.file("--json-file", path);
    }
    let outputs = plan.check()?;
    json_conflict(ui, &outputs)?;
    let mut params = model.nominal();
    apply_sets(&model, &args.set, &mut params)?;
    // The modes do not depend on the integrator's steps.
    let sim = Simulator::with_integrator(&model, rfeid::simulation::steps::integrator(1));
    let modal = modal_analysis(&sim, &params)
        .map_err(|e| simulation_failure("modal analysis failed", e))?;
    let coordinates: Vec<String> = model
        .bodies
        .iter()
        .flat_map(|b| ["u1", "u2", "u3", "phi1", "phi2", "phi3"].map(|c| format!("{}.{c}", b.name)))
        .collect();
    let json = serde_json::json!({ "coordinates": coordinates, "analysis": modal });
    if let Some(path) = &args.json_file {
        let mut text = serde_json::to_vec_pretty(&json)
            .map_err(|e| Failure::failed(format!("modes as JSON: {e}")))?;
        text.push(b'\n');
        let mut batch = outputs.batch();
        batch.file("--json-file", text)?;
        batch.commit()?;
        if outputs.uses_stdout() {
            return Ok(());
        }
        ui.note(format!("modes written to {}", path.display()));
    }
    if ui.json {
        return ui.print_json(&json);
    }
    print_modes(&modal);
    if args.shapes {
        print_shapes(&model, &modal);
    }
    Ok(())
}

/// The modes' table, with notes on what it leaves out.
fn print_modes(modal: &ModalAnalysis) {
    println!(
        "Modes of the model linearised {}",
        if modal.at_equilibrium {
            "at its static equilibrium (under gravity, or of its contacts)"
        } else {
            "at rest"
        }
    );
    let rows: Vec<Vec<String>> = modal
        .modes
        .iter()
        .enumerate()
        .map(|(i, m)| {
            vec![
                format!("{}", i + 1),
                if m.free.is_some() {
                    "0 (free)".into()
                } else if m.zero_stiffness {
                    "0 (zero stiffness)".into()
                } else {
                    sig(m.frequency_hz, 5)
                },
                m.damping_ratio
                    .map(|z| sig(100.0 * z, 3))
                    .unwrap_or_else(|| "-".into()),
            ]
        })
        .collect();
    print!("{}", table(&["mode", "frequency Hz", "damping %"], &rows));
    if !modal.zero_slope_components.is_empty() {
        println!(
            "\nnote: these power-law springs have zero slope at the linearisation point and add no stiffness to it: {}",
            modal.zero_slope_components.join(", ")
        );
        println!("      their stiffness grows with deformation, so the frequencies under load are higher.");
    }
    let free: Vec<String> = modal
        .modes
        .iter()
        .enumerate()
        .filter_map(|(i, m)| m.free.as_ref().map(|d| format!("mode {}: {d}", i + 1)))
        .collect();
    if !free.is_empty() {
        println!(
            "note: free modes are rigid-body motions along directions no spring restrains (no restoring force; dampers and friction only slow them):"
        );
        for f in &free {
            println!("      {f}");
        }
    } else if !modal.free_directions.is_empty() {
        println!(
            "note: free directions (no spring restrains them): {}",
            modal.free_directions.join("; ")
        );
    }
    if modal
        .modes
        .iter()
        .any(|m| m.zero_stiffness && m.free.is_none())
    {
        println!("note: zero-stiffness modes are rigid-body motions that no linear spring restrains at this point.");
    }
    println!("damping ratios are modal projections φᵀCφ/(2ω): exact for proportional damping, approximate otherwise.");
}

/// Each mode's shape, scaled to a peak of 1.
fn print_shapes(model: &Model, modal: &ModalAnalysis) {
    let names: Vec<String> = model
        .bodies
        .iter()
        .flat_map(|b| ["u1", "u2", "u3", "φ1", "φ2", "φ3"].map(|c| format!("{}.{c}", b.name)))
        .collect();
    for (i, m) in modal.modes.iter().enumerate() {
        let peak = m
            .shape
            .iter()
            .fold(0.0_f64, |a, v| a.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        println!("\nmode {} shape (scaled to a peak of 1):", i + 1);
        for (n, v) in names.iter().zip(&m.shape) {
            println!("  {n:<14} {:>8.4}", v / peak);
        }
    }
}
