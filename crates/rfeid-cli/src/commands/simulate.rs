//! `rfeid simulate`: the response at nominal (or `--set`) parameter values.
use crate::cli::SimulateArgs;
use crate::diagnostics::Failure;
use crate::outputs::{Checked, Plan};
use crate::run::experiments::experiment_model;
use crate::run::failures::simulation_failure_of;
use crate::run::inputs::{apply_sets, load, stepped};
use crate::run::show::{json_conflict, steps_note};
use crate::ui::Ui;
use rfeid::io::timeseries::{write_csv_to, TimeSeries};
use rfeid::measurement::simulated::{simulate_record, NoiseSpec, Simulated};
use rfeid::measurement::{rms, to_timeseries};
use rfeid::model::Model;
use rfeid::simulation::aliasing::{above_nyquist_after, modes_at_rest};
use rfeid::simulation::steps::integrator;
use rfeid::simulation::{Response, Simulator};

/// Runs the command.
pub fn run(args: SimulateArgs, ui: &Ui) -> Result<(), Failure> {
    let mut model = load(&args.model, ui)?;
    if let Some(name) = &args.experiment {
        model = experiment_model(&model, &args.model, name)?;
    }
    let model = stepped(model, &args.steps)?;
    let outputs = check_outputs(&args, &model)?;
    json_conflict(ui, &outputs)?;
    let mut params = model.nominal();
    apply_sets(&model, &args.set, &mut params)?;
    let noise = args.noise.map(|fraction| NoiseSpec {
        fraction,
        corner: args.noise_corner,
        seed: args.seed,
    });
    // The modes at rest for the Nyquist check are independent of the run:
    // computed beside it.
    let (simulated, rest) = rayon::join(
        || simulate_record(&model, &params, noise.as_ref()),
        || modes_at_rest(&Simulator::with_integrator(&model, integrator(1)), &params),
    );
    let Simulated {
        sim,
        response: out,
        elapsed,
        peaks,
    } = simulated.map_err(simulation_failure_of)?;
    let steps = sim.steps();
    let series = to_timeseries(&model, &out);
    // The Nyquist check's eigenproblems and writing the files are
    // independent.
    let (warnings, written) = rayon::join(
        || above_nyquist_after(&sim, &params, peaks.as_ref(), rest),
        || write_outputs(&args, &model, (&series, &out), &outputs),
    );
    written?;
    if let Some(path) = &args.plot {
        ui.note(format!("plot written to {}", path.display()));
    }
    if ui.json {
        return ui.print_json(&serde_json::json!({
            "output": args.output,
            "samples": out.n_samples,
            "elapsed_ms": elapsed.as_secs_f64() * 1e3,
            "simulation": steps,
            "sensors": model.sensors.iter().enumerate().map(|(c, s)| serde_json::json!({
                "name": s.name, "unit": s.kind.unit(), "rms": rms(out.sensor(c)),
            })).collect::<Vec<_>>(),
        }));
    }
    ui.note(format!(
        "{} samples × {} sensors in {:.1} ms → {}",
        out.n_samples,
        out.n_sensors,
        elapsed.as_secs_f64() * 1e3,
        args.output.display()
    ));
    ui.note(steps_note(&steps));
    for w in warnings {
        ui.note(format!("warning: {w}"));
    }
    for (c, s) in model.sensors.iter().enumerate() {
        ui.note(format!(
            "  {:<16} RMS {:.4e} {}",
            s.name,
            rms(out.sensor(c)),
            s.kind.unit()
        ));
    }
    Ok(())
}

/// Writes the CSV (and the plot, if asked for), all or nothing.
fn write_outputs(
    args: &SimulateArgs,
    model: &Model,
    (series, out): (&TimeSeries, &Response),
    outputs: &Checked,
) -> Result<(), Failure> {
    let mut csv = Vec::new();
    write_csv_to(&mut csv, series).map_err(|e| Failure::failed(format!("CSV: {e}")))?;
    let mut batch = outputs.batch();
    if args.plot.is_some() {
        let svg = rfeid::report::response_svg(model, &series.time, out);
        batch.file("--plot", svg.into_bytes())?;
    }
    batch.file("-o", csv)?;
    batch.commit()
}

/// The run's inputs and outputs (`-o`, `--plot`), checked.
fn check_outputs(args: &SimulateArgs, model: &Model) -> Result<Checked, Failure> {
    let mut plan = Plan::new();
    plan.input(&args.model).file("-o", &args.output);
    for f in &model.files {
        plan.input(f);
    }
    if let Some(p) = &args.plot {
        plan.file("--plot", p);
    }
    plan.check()
}
