//! `rfeid identify`: the full pipeline on measured data.
use super::common::load;
use crate::cli::{IdentifyArgs, MethodArg, SearchArgs, WeightsArg};
use crate::diagnostics::Failure;
use crate::format::{sig, table};
use crate::ui::Ui;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{
    identify, IdentifyError, Method, Progress, Settings, Weighting,
};
use rfeid::identification::result::IdentificationResult;
use rfeid::io::atomic::write_atomically;
use rfeid::io::data_file::read_measurement;
use rfeid::measurement::match_data;
use rfeid::model::Model;
use rfeid::simulation::{Response, Simulator};
use std::path::Path;

/// Runs the command.
pub fn run(args: IdentifyArgs, ui: &Ui) -> Result<(), Failure> {
    let model = load(&args.model)?;
    let sources: Vec<_> = model.sensors.iter().map(|s| s.data.clone()).collect();
    let data = read_measurement(&args.data, &model, &sources).map_err(Failure::input_msg)?;
    let measured = match_data(&model, &data)
        .map_err(|e| Failure::input_msg(format!("{}: {e}", args.data.display())))?;
    let mut result = run_search(&model, measured.clone(), &args.search, ui)?;
    result.source.model = Some(args.model.display().to_string());
    result.source.data = Some(args.data.display().to_string());
    write_result(&args.output, &result)?;
    if let Some(dir) = &args.report {
        let title = format!("{} with {}", args.model.display(), args.data.display());
        super::report::write(ui, dir, &model, &result, &measured, None, &title)?;
    }
    show_result(&model, &result, "nominal", args.search.timings, ui)?;
    ui.note(format!("result written to {}", args.output.display()));
    Ok(())
}

/// The tables, or the result as JSON with `--json`.
pub fn show_result(
    model: &Model,
    r: &IdentificationResult,
    reference: &str,
    timings: bool,
    ui: &Ui,
) -> Result<(), Failure> {
    if ui.json {
        ui.print_json(r)
    } else {
        print_result(model, r, reference, timings);
        Ok(())
    }
}

/// Progress on stderr: a bar over the plan, then one line per iteration.
struct Bars {
    bar: ProgressBar,
    quiet: bool,
}

impl Progress for Bars {
    fn plan_started(&self, points: usize) {
        self.bar.set_length(points as u64);
        self.bar.set_message("LP_τ plan");
    }
    fn plan_point(&self) {
        self.bar.inc(1);
    }
    fn search_started(&self, k: usize, of: usize, cost: f64) {
        self.bar.finish_and_clear();
        if !self.quiet {
            eprintln!("local search {}/{of} from the plan's J = {cost:.6e}", k + 1);
        }
    }
    fn iteration(&self, iteration: usize, cost: f64) {
        if !self.quiet {
            eprintln!("  iteration {iteration:3}  J = {cost:.6e}");
        }
    }
}

/// Checks the search settings and runs the pipeline.
pub fn run_search(
    model: &Model,
    measured: Response,
    a: &SearchArgs,
    ui: &Ui,
) -> Result<IdentificationResult, Failure> {
    if let Some(t) = a.threads {
        if t == 0 {
            return Err(Failure::input_msg("--threads must be at least 1"));
        }
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global();
    }
    if a.plan == 0 {
        return Err(Failure::input_msg(
            "--plan 0: the plan needs at least one point",
        ));
    }
    if a.starts == 0 || a.starts > a.plan {
        return Err(Failure::input_msg(format!(
            "--starts {}: must be 1 to the plan size ({})",
            a.starts, a.plan
        )));
    }
    let s = model.sampling;
    if !(a.from >= 0.0 && a.from < s.duration) {
        return Err(Failure::input_msg(format!(
            "--from {}: must lie in [0, {}) s",
            a.from, s.duration
        )));
    }
    let first = (a.from * s.sample_rate - 1e-9).ceil().max(0.0) as usize;
    if first + 2 > s.n_samples() {
        return Err(Failure::input_msg(format!(
            "--from {}: leaves {} of the record's {} samples to fit",
            a.from,
            s.n_samples().saturating_sub(first),
            s.n_samples()
        )));
    }
    if model.identified().is_empty() {
        return Err(Failure::input_msg(IdentifyError::NoParameters));
    }
    let settings = Settings {
        plan_points: a.plan,
        starts: a.starts,
        method: match a.method {
            MethodArg::Lm => Method::Lm,
            MethodArg::Bfgs => Method::Bfgs,
        },
        weighting: match a.weights {
            WeightsArg::Equal => Weighting::Equal,
            WeightsArg::Estimated => Weighting::EstimatedNoise,
        },
        ..Settings::default()
    };
    let problem = OutputError::new(Simulator::new(model), measured, first);
    let target = if ui.quiet {
        ProgressDrawTarget::hidden()
    } else {
        ProgressDrawTarget::stderr()
    };
    let bar = ProgressBar::with_draw_target(Some(a.plan as u64), target);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} points, {elapsed} (eta {eta})")
            .expect("valid template")
            .progress_chars("=> "),
    );
    let progress = Bars {
        bar,
        quiet: ui.quiet,
    };
    let result = identify(problem, &settings, &progress).map_err(|e| match e {
        IdentifyError::NoParameters
        | IdentifyError::Plan(_)
        | IdentifyError::NoStarts
        | IdentifyError::TooFewObservations { .. } => Failure::input_msg(e),
        _ => Failure::failed(e),
    })?;
    progress.bar.finish_and_clear();
    Ok(result)
}

/// Prints the paper-style tables (Tables 1–2) and diagnostics.
pub fn print_result(model: &Model, r: &IdentificationResult, reference: &str, timings: bool) {
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
    println!();
    print!(
        "{}",
        table(
            &[
                "parameter",
                "unit",
                "min",
                "max",
                reference,
                "identified",
                &diff,
                "std. error"
            ],
            &rows
        )
    );
    println!();
    println!(
        "criterion J = {:.6e}   s² = {}   N = {}",
        r.criterion,
        r.s2.map(|v| format!("{v:.4e}")).unwrap_or("-".into()),
        r.observations
    );
    println!(
        "{} after {} iterations ({})",
        r.termination_message, r.iterations, r.method
    );
    println!(
        "plan: {} points, {} failed; simulations: {} (+{} with sensitivities), {} failed",
        r.plan.points,
        r.plan.failed,
        r.simulations,
        r.simulations_with_sensitivities,
        r.failed_simulations
    );
    for f in &r.failed_starts {
        println!(
            "warning: the local search from plan point {} failed and was skipped: {}",
            f.plan_index + 1,
            f.reason
        );
    }
    if let Some(c) = r.condition_number {
        println!("condition number of the scaled Fisher matrix: {c:.3e}");
    }
    if let Some(e) = &r.uncertainty_error {
        println!("warning: no standard errors: {e}");
    }
    for w in &r.warnings {
        println!("warning: {w}");
    }
    if timings {
        let t = &r.timings;
        println!(
            "timings: plan {:.3} s, local search {:.3} s, uncertainty {:.3} s, total {:.3} s ({} threads)",
            t.plan, t.local_search, t.uncertainty, t.total, r.threads
        );
    }
}

/// Writes RESULT.json atomically.
pub fn write_result(path: &Path, r: &IdentificationResult) -> Result<(), Failure> {
    write_atomically(path, |w| {
        serde_json::to_writer_pretty(&mut *w, r).map_err(std::io::Error::other)?;
        std::io::Write::write_all(w, b"\n")
    })
    .map_err(|e| Failure::input_msg(format!("{}: {e}", path.display())))
}
