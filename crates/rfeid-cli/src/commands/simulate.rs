//! `rfeid simulate`: the response at nominal (or `--set`) parameter values.
use super::common::{apply_sets, load, simulation_failure};
use crate::cli::SimulateArgs;
use crate::diagnostics::Failure;
use crate::ui::Ui;
use rfeid::io::timeseries::write_csv;
use rfeid::measurement::{add_noise, rms, to_timeseries};
use rfeid::simulation::{Integrator, Simulator, Workspace};

/// Runs the command.
pub fn run(args: SimulateArgs, ui: &Ui) -> Result<(), Failure> {
    let model = load(&args.model)?;
    let mut params = model.nominal();
    apply_sets(&model, &args.set, &mut params)?;
    if let Some(f) = args.noise {
        if !(f >= 0.0 && f.is_finite()) {
            return Err(Failure::input_msg(format!(
                "--noise {f}: must be a non-negative fraction"
            )));
        }
    }
    let mut sim = Simulator::new(&model);
    if let Some(s) = args.substeps {
        if !(1..=1000).contains(&s) {
            return Err(Failure::input_msg("--substeps must be 1 to 1000"));
        }
        sim = Simulator::with_integrator(
            &model,
            Integrator {
                substeps: s,
                ..sim.integrator()
            },
        );
    }
    let mut out = sim.response_buffer();
    let start = std::time::Instant::now();
    sim.run(&params, &mut Workspace::default(), &mut out)
        .map_err(|e| simulation_failure("simulation failed", e))?;
    let elapsed = start.elapsed();
    if let Some(f) = args.noise {
        add_noise(&mut out, f, args.seed);
    }
    let series = to_timeseries(&model, &out);
    write_csv(&args.output, &series).map_err(Failure::input_msg)?;
    if let Some(path) = &args.plot {
        let svg = rfeid::report::response_svg(&model, &series.time, &out);
        rfeid::io::atomic::write_atomically(path, |w| std::io::Write::write_all(w, svg.as_bytes()))
            .map_err(|e| Failure::input_msg(format!("{}: {e}", path.display())))?;
        ui.note(format!("plot written to {}", path.display()));
    }
    if ui.json {
        return ui.print_json(&serde_json::json!({
            "output": args.output,
            "samples": out.n_samples,
            "elapsed_ms": elapsed.as_secs_f64() * 1e3,
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
