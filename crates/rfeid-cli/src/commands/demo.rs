//! `rfeid demo`: the paper's numerical example (§4) in one command.
use super::identify::{run_search, show_result, write_result};
use super::report::{self, demo_title, reference_of};
use crate::cli::DemoArgs;
use crate::diagnostics::{model_error, Failure};
use crate::ui::Ui;
use rfeid::io::model_file::parse_model;
use rfeid::measurement::add_noise;
use rfeid::model::Model;
use rfeid::simulation::{Response, Simulator, Workspace};
use std::path::Path;

/// The knee–column benchmark (SPEC §4), built into the binary.
const KNEE_COLUMN: &str = include_str!("../../../../examples/knee-column/model.toml");

/// The built-in knee–column model.
pub fn demo_model() -> Result<Model, Failure> {
    parse_model(KNEE_COLUMN, Path::new("examples/knee-column/model.toml")).map_err(model_error)
}

/// The demo's data: the model at its true (nominal) values, plus seeded noise.
pub fn demo_data(model: &Model, noise: Option<f64>, seed: u64) -> Result<Response, Failure> {
    let sim = Simulator::new(model);
    let mut data = sim.response_buffer();
    sim.run(&model.nominal(), &mut Workspace::default(), &mut data)
        .map_err(|e| Failure::failed(format!("simulating the data failed: {e}")))?;
    match noise {
        Some(f) if !(f >= 0.0 && f.is_finite()) => {
            return Err(Failure::input_msg(
                "--noise must be a non-negative fraction",
            ))
        }
        Some(f) => add_noise(&mut data, f, seed),
        None => {}
    }
    Ok(data)
}

/// Runs the command.
pub fn run(args: DemoArgs, ui: &Ui) -> Result<(), Failure> {
    let model = demo_model()?;
    let data = demo_data(&model, args.noise, args.seed)?;
    match args.noise {
        Some(f) => ui.note(format!(
            "knee–column benchmark: data simulated with {}% noise (seed {})",
            100.0 * f,
            args.seed
        )),
        None => {
            ui.note("knee–column benchmark: noise-free data simulated at the true parameter values")
        }
    }
    ui.note(format!(
        "identifying {} parameters from {} signals × {} samples",
        model.identified().len(),
        model.sensors.len(),
        model.sampling.n_samples()
    ));
    let mut result = run_search(&model, data.clone(), &args.search, ui)?;
    result.source.model =
        Some("built-in knee–column benchmark (examples/knee-column/model.toml)".into());
    result.source.demo_noise = args.noise;
    result.source.demo_seed = args.noise.map(|_| args.seed);
    if let Some(path) = &args.output {
        write_result(path, &result)?;
        ui.note(format!("result written to {}", path.display()));
    }
    if let Some(dir) = &args.report {
        let reference = reference_of(&model, &result);
        report::write(
            ui,
            dir,
            &model,
            &result,
            &data,
            Some(&reference),
            &demo_title(&result),
        )?;
    }
    show_result(&model, &result, "actual", args.search.timings, ui)?;
    if ui.json {
        return Ok(());
    }
    let worst = result
        .parameters
        .iter()
        .map(|p| {
            (
                p.name.as_str(),
                100.0 * ((p.estimate - p.nominal) / p.nominal).abs(),
            )
        })
        .fold(("", 0.0), |a, b| if b.1 > a.1 { b } else { a });
    println!(
        "largest error: {:.4}% ({}); the paper's was 11.4% (h_t3) after about 7.3 hours",
        worst.1, worst.0
    );
    Ok(())
}
