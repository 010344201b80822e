//! `rfeid demo`: the paper's numerical example (§4) in one command.
use super::common::{apply_steps, report_note};
use super::identify::{
    check_limits, json_conflict, result_json, run_search, show_result, suspect_status,
};
use super::report::{self, demo_title, reference_of};
use super::simulate::noise_sensor;
use crate::cli::DemoArgs;
use crate::diagnostics::{model_error, Failure};
use crate::outputs::Plan;
use crate::ui::Ui;
use rfeid::io::model_file::parse_model;
use rfeid::measurement::{add_noise, check_noise};
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
    let sim = Simulator::choose(model, &model.nominal())
        .map_err(|e| Failure::failed(format!("simulating the data failed: {e}")))?;
    let mut data = sim.response_buffer();
    sim.run(&model.nominal(), &mut Workspace::default(), &mut data)
        .map_err(|e| Failure::failed(format!("simulating the data failed: {e}")))?;
    if let Some(f) = noise {
        check_noise(&data, f)
            .map_err(|e| Failure::input_msg(format!("--noise: {}", noise_sensor(model, e))))?;
        add_noise(&mut data, f, seed);
    }
    Ok(data)
}

/// Runs the command.
pub fn run(mut args: DemoArgs, ui: &Ui) -> Result<(), Failure> {
    check_limits(&args.search)?;
    // The benchmark's boxes are narrow: no short-window start unless asked.
    args.search.window.get_or_insert(0.0);
    // The paper's equal weights (eq. 14) unless asked.
    args.search
        .weights
        .get_or_insert(crate::cli::WeightsArg::Equal);
    let mut plan = Plan::new();
    if let Some(path) = &args.output {
        plan.file("-o", path);
    }
    if let Some(dir) = &args.report {
        plan.report("--report", dir);
    }
    let outputs = plan.check()?;
    json_conflict(ui, &outputs)?;
    let mut model = demo_model()?;
    apply_steps(&mut model, &args.search.steps)?;
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
    let mut batch = outputs.batch();
    if args.report.is_some() {
        let reference = reference_of(&model, &result);
        let files = report::render(
            &model,
            &result,
            &data,
            Some(&reference),
            &demo_title(&result),
        )?;
        batch.report("--report", &files)?;
    }
    if args.output.is_some() {
        batch.file("-o", result_json(&result)?)?;
    }
    batch.commit()?;
    report_note(args.report.as_deref(), ui);
    let taken = outputs.uses_stdout();
    if let Some(path) = args.output.as_ref().filter(|_| !taken) {
        ui.note(format!("result written to {}", path.display()));
    }
    show_result(&model, &result, "actual", args.search.timings, taken, ui)?;
    let written = match &args.output {
        Some(p) if !taken => p.display().to_string(),
        Some(_) => "standard output".to_string(),
        None => "nowhere (no -o)".to_string(),
    };
    if ui.json || (taken && ui.quiet) {
        return suspect_status(&result, &written);
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
    let line = format!(
        "largest error: {:.4}% ({}); the paper's was 11.4% (h_t3) after about 7.3 hours",
        worst.1, worst.0
    );
    if taken {
        eprintln!("{line}");
    } else {
        println!("{line}");
    }
    suspect_status(&result, &written)
}
