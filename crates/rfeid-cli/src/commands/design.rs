//! `rfeid design`: what a test will give before it is run (SPEC §6): the
//! predicted standard errors of the placed sensors and, with `--choose K`,
//! the D-optimal K of the candidate sensors added to them (or, with none
//! placed, the K that make the whole test).
use crate::cli::DesignArgs;
use crate::diagnostics::Failure;
use crate::outputs::Plan;
use crate::run::design_text::print_design;
use crate::run::failures::{failure, option_text, simulation_failure};
use crate::run::inputs::{apply_campaign_sets, load_for};
use crate::run::limits::start_threads;
use crate::run::show::json_conflict;
use crate::ui::Ui;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rfeid::design::json::{at_values, check_request, design_json};
use rfeid::design::{design, DesignError, DesignSettings};
use rfeid::identification::options::check_threads;
use rfeid::io::model_file::Purpose;

/// Runs the command.
pub fn run(args: DesignArgs, ui: &Ui) -> Result<(), Failure> {
    // Before a first test every sensor may be a candidate (`--choose K`).
    let model = load_for(&args.model, Purpose::Design, ui)?;
    let mut plan = Plan::new();
    plan.input(&args.model);
    for f in &model.files {
        plan.input(f);
    }
    if let Some(path) = &args.output {
        plan.file("-o", path);
    }
    if let Some(dir) = &args.report {
        plan.report("--report", dir);
    }
    check_threads(args.threads).map_err(crate::run::failures::failure)?;
    let outputs = plan.check()?;
    json_conflict(ui, &outputs)?;
    let label = args.model.display().to_string();
    check_request(&model, &label, args.choose, args.over_box).map_err(failure)?;
    let mut values = model.nominal();
    apply_campaign_sets(&model, &args.set, &mut values)?;
    let model = at_values(model, values).map_err(failure)?;
    start_threads(args.threads)?;
    let settings = DesignSettings {
        choose: args.choose,
        over_box: args.over_box,
        ..Default::default()
    };
    let bar = progress(ui, 1 + args.over_box.unwrap_or(0));
    let found = design(&model, &settings, &|| bar.inc(1)).map_err(|e| design_failure(&args, e))?;
    bar.finish_and_clear();
    let json = design_json(&model, &found);
    // The report first and the design last, as identify puts its result.
    let mut batch = outputs.batch();
    if args.report.is_some() {
        let title = args.model.display().to_string();
        let files = rfeid::report::design::design_report_files(&model, &found, &title);
        batch.report("--report", &files)?;
    }
    if args.output.is_some() {
        let mut text = serde_json::to_vec_pretty(&json)
            .map_err(|e| Failure::failed(format!("the design as JSON: {e}")))?;
        text.push(b'\n');
        batch.file("-o", text)?;
    }
    batch.commit()?;
    if let Some(dir) = &args.report {
        ui.note(format!(
            "report written to {}",
            dir.join("report.html").display()
        ));
    }
    if let (Some(path), false) = (&args.output, outputs.uses_stdout()) {
        ui.note(format!("design written to {}", path.display()));
    }
    if outputs.uses_stdout() {
        return Ok(());
    }
    if ui.json {
        return ui.print_json(&json);
    }
    print_design(&model, &found);
    Ok(())
}

/// A design's failure: bad input (a sensor without noise, K beyond the
/// candidates) names the model file; a failed simulation is a failure.
fn design_failure(args: &DesignArgs, e: DesignError) -> Failure {
    match e {
        DesignError::Simulation(s) => simulation_failure("simulating at the parameters' values", s),
        DesignError::EveryPointFailed { .. } => Failure::failed(e.to_string()),
        DesignError::Option(o) => {
            Failure::input_msg(format!("{}: {}", args.model.display(), option_text(&o)))
        }
        other => Failure::input_msg(format!("{}: {other}", args.model.display())),
    }
}

/// The bar over the simulations (hidden with `--quiet`).
fn progress(ui: &Ui, total: usize) -> ProgressBar {
    let target = if ui.quiet {
        ProgressDrawTarget::hidden()
    } else {
        ProgressDrawTarget::stderr()
    };
    let bar = ProgressBar::with_draw_target(Some(total as u64), target);
    bar.set_style(
        ProgressStyle::with_template("design [{bar:40}] {pos}/{len} simulations, {elapsed}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar
}
