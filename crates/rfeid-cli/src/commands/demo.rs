//! `rfeid demo`: the paper's numerical example (§4) in one command.
use crate::cli::{DemoArgs, StartArg, WeightsArg};
use crate::diagnostics::Failure;
use crate::outputs::{Checked, Plan};
use crate::run::closing::{close, Closing, WrittenNote};
use crate::run::demo_case::{demo_data, demo_model, demo_title, reference_of};
use crate::run::inputs::stepped;
use crate::run::limits::{check_limits, start_threads};
use crate::run::report::render;
use crate::run::search::{options, run_search};
use crate::run::show::json_conflict;
use crate::ui::Ui;
use rfeid::identification::result::IdentificationResult;

/// Runs the command.
pub fn run(mut args: DemoArgs, ui: &Ui) -> Result<(), Failure> {
    check_limits(&options(&args.search, StartArg::Plan))?;
    // Before the data are simulated (the step choice runs in parallel).
    start_threads(args.search.threads)?;
    // The benchmark's boxes are narrow: no short-window start unless asked.
    args.search.window.get_or_insert(0.0);
    // The paper's equal weights (eq. 14) unless asked.
    args.search.weights.get_or_insert(WeightsArg::Equal);
    let outputs = check_outputs(&args)?;
    json_conflict(ui, &outputs)?;
    let model = stepped(demo_model()?, &args.search.steps)?;
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
    let report = match &args.report {
        Some(dir) => {
            let reference = reference_of(&model, &result);
            let title = demo_title(&result);
            let files = render(&model, &result, "", &data, Some(&reference), &title)?;
            Some((dir.as_path(), files))
        }
        None => None,
    };
    let taken = outputs.uses_stdout();
    let closing = Closing {
        model: &model,
        result: &result,
        report,
        note_report: true,
        output: args.output.as_deref(),
        written_note: WrittenNote::BeforeTables,
        written: match &args.output {
            Some(p) if !taken => p.display().to_string(),
            Some(_) => "standard output".to_string(),
            None => "nowhere (no -o)".to_string(),
        },
        reference: "actual",
        timings: args.search.timings,
        epilogue: Some(largest_error(&result)),
    };
    close(&outputs, closing, ui)
}

/// The demo's outputs (`-o`, `--report`), checked.
fn check_outputs(args: &DemoArgs) -> Result<Checked, Failure> {
    let mut plan = Plan::new();
    if let Some(path) = &args.output {
        plan.file("-o", path);
    }
    if let Some(dir) = &args.report {
        plan.report("--report", dir);
    }
    plan.check()
}

/// The largest error of the estimates against the true values, beside the
/// paper's.
fn largest_error(result: &IdentificationResult) -> String {
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
    format!(
        "largest error: {:.4}% ({}); the paper's was 11.4% (h_t3) after about 7.3 hours",
        worst.1, worst.0
    )
}
