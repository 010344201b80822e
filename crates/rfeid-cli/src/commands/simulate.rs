//! `rfeid simulate`: the response at nominal (or `--set`) parameter values.
use super::common::{apply_sets, apply_steps, load, simulation_failure, steps_note};
use crate::cli::SimulateArgs;
use crate::diagnostics::Failure;
use crate::outputs::Plan;
use crate::ui::Ui;
use rfeid::io::timeseries::write_csv_to;
use rfeid::measurement::{add_noise, check_noise, rms, to_timeseries};
use rfeid::simulation::{Simulator, Workspace};

/// Runs the command.
pub fn run(args: SimulateArgs, ui: &Ui) -> Result<(), Failure> {
    let mut model = load(&args.model)?;
    if let Some(name) = &args.experiment {
        model = experiment_model(&model, &args.model, name)?;
    }
    apply_steps(&mut model, &args.steps)?;
    let mut plan = Plan::new();
    plan.input(&args.model).file("-o", &args.output);
    for f in &model.files {
        plan.input(f);
    }
    if let Some(p) = &args.plot {
        plan.file("--plot", p);
    }
    let outputs = plan.check()?;
    if ui.json && outputs.uses_stdout() {
        return Err(Failure::input_msg(
            "--json: standard output already carries an output file (-); drop one of them",
        ));
    }
    let mut params = model.nominal();
    apply_sets(&model, &args.set, &mut params)?;
    if let Some(f) = args.noise {
        if !(f >= 0.0 && f.is_finite()) {
            return Err(Failure::input_msg(format!(
                "--noise {f}: must be a non-negative fraction"
            )));
        }
    }
    let sim = Simulator::choose(&model, &params)
        .map_err(|e| simulation_failure("choosing the integrator's steps", e))?;
    let steps = sim.steps();
    let mut out = sim.response_buffer();
    let start = std::time::Instant::now();
    sim.run(&params, &mut Workspace::default(), &mut out)
        .map_err(|e| simulation_failure("simulation failed", e))?;
    let elapsed = start.elapsed();
    if let Some(f) = args.noise {
        check_noise(&out, f)
            .map_err(|e| Failure::input_msg(format!("--noise: {}", noise_sensor(&model, e))))?;
        add_noise(&mut out, f, args.seed);
    }
    let series = to_timeseries(&model, &out);
    let mut csv = Vec::new();
    write_csv_to(&mut csv, &series).map_err(|e| Failure::failed(format!("CSV: {e}")))?;
    let mut batch = outputs.batch();
    if args.plot.is_some() {
        let svg = rfeid::report::response_svg(&model, &series.time, &out);
        batch.file("--plot", svg.into_bytes())?;
    }
    batch.file("-o", csv)?;
    batch.commit()?;
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
    for w in rfeid::simulation::aliasing::above_nyquist(&sim, &params) {
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

/// The model as experiment `name` sees it; an unknown name is bad input
/// that lists the experiments.
pub fn experiment_model(
    model: &rfeid::model::Model,
    path: &std::path::Path,
    name: &str,
) -> Result<rfeid::model::Model, Failure> {
    let e = model.experiment_index(name).ok_or_else(|| {
        let known: Vec<&str> = model.experiments.iter().map(|e| e.name.as_str()).collect();
        Failure::input_msg(format!(
            "--experiment {name}: {} has no such [[experiment]] ({})",
            path.display(),
            if known.is_empty() {
                "it has none".to_string()
            } else {
                format!("experiments: {}", known.join(", "))
            }
        ))
    })?;
    Ok(model.for_experiment(e))
}

/// A noise error with the sensor named.
pub fn noise_sensor(model: &rfeid::model::Model, e: rfeid::measurement::NoiseError) -> String {
    use rfeid::measurement::NoiseError;
    let sensor = match &e {
        NoiseError::Overflow { sensor, .. } | NoiseError::BelowRounding { sensor, .. } => {
            model.sensors.get(*sensor).map(|s| s.name.as_str())
        }
        NoiseError::BadFraction { .. } => None,
    };
    match sensor {
        Some(name) => format!("{e} ('{name}')"),
        None => e.to_string(),
    }
}
