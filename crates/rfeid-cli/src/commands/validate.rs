//! `rfeid validate`: an identification checked on other data. The model is
//! simulated at the estimate (with the steps chosen there) and compared
//! with the data, sensor by sensor, by the normalised RMS fit that the
//! verdict also uses (MATLAB `compare`'s).
use crate::cli::ValidateArgs;
use crate::diagnostics::Failure;
use crate::format::table;
use crate::outputs::Plan;
use crate::run::belongs::check_belongs;
use crate::run::digest::changed_input;
use crate::run::estimate::simulate_at_estimate;
use crate::run::experiments::experiment_data;
use crate::run::inputs::{fixed, load, load_data};
use crate::run::report::{read_result, render_fitted};
use crate::ui::Ui;
use rfeid::identification::result::IdentificationResult;
use rfeid::measurement::fit_percent;
use rfeid::model::{Model, Role};
use rfeid::simulation::Response;
use serde::Serialize;

/// One data set compared with the model at the estimate.
struct Case {
    /// The experiment's name ("" for a data file of a model without experiments).
    experiment: String,
    /// Its model (the experiment's settings applied).
    model: Model,
    /// Its measured data.
    measured: Response,
    /// The first sample compared.
    first: usize,
}

/// The fits of one data set, as printed and as `--json` writes them.
#[derive(Serialize)]
struct Fits {
    experiment: String,
    /// `fit` or `validation` for an experiment of the model file.
    role: Option<String>,
    sensors: Vec<String>,
    /// Normalised RMS fit per sensor in % (none for a constant signal).
    fit_percent: Vec<Option<f64>>,
}

/// Runs the command.
pub fn run(args: ValidateArgs, ui: &Ui) -> Result<(), Failure> {
    let result = read_result(&args.result)?;
    let model = fixed(load(&args.model, ui)?, &result.source.set)?;
    check_belongs(&model, &result, &args.model, &args.result)?;
    if let Some((path, what)) =
        changed_input(result.source.digests.as_ref(), &args.model, &model, None)?
    {
        ui.note(format!(
            "warning: {what} {} is not what {} was computed with: the estimate is checked with the file as it is now",
            path.display(),
            args.result.display()
        ));
    }
    let mut plan = Plan::new();
    plan.input(&args.model).input(&args.result);
    if let Some(d) = &args.data {
        plan.input(d);
    }
    for f in &model.files {
        plan.input(f);
    }
    if let Some(dir) = &args.report {
        plan.report("--report", dir);
    }
    let outputs = plan.check()?;
    let cases = cases(&model, &args, ui)?;
    if args.report.is_some() && cases.len() != 1 {
        return Err(Failure::input_msg(format!(
            "{}: --report needs one data set: name one of the {} experiments with --experiment",
            args.model.display(),
            cases.len()
        )));
    }
    let (all, simulated): (Vec<Fits>, Vec<Response>) = cases
        .iter()
        .map(|case| fits_of(&model, &result, case))
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .unzip();
    if ui.json {
        ui.print_json(&all)?;
    } else {
        print!("{}", fits_table(&all));
    }
    if let (Some(dir), [case], [fitted]) = (&args.report, cases.as_slice(), simulated.as_slice()) {
        let title = format!("{} on {}", args.result.display(), source_name(&args, case));
        let sensors: Vec<String> = case.model.sensors.iter().map(|s| s.name.clone()).collect();
        let seen = result.seen_by(&case.experiment, &sensors);
        let files = render_fitted(&case.model, &seen, &case.measured, fitted, None, &title)?;
        let mut batch = outputs.batch();
        batch.report("--report", &files)?;
        batch.commit()?;
        ui.note(format!(
            "report written to {}",
            dir.join("report.html").display()
        ));
    }
    Ok(())
}

/// The fits of one data set, and the model's response at the estimate.
fn fits_of(
    model: &Model,
    result: &IdentificationResult,
    case: &Case,
) -> Result<(Fits, Response), Failure> {
    let (fitted, _) = simulate_at_estimate(result, &case.model, &case.experiment)?;
    let fits = (0..case.model.sensors.len())
        .map(|c| {
            fit_percent(
                &case.measured.sensor(c)[case.first..],
                &fitted.sensor(c)[case.first..],
            )
        })
        .collect();
    let role = model
        .experiments
        .iter()
        .find(|x| x.name == case.experiment)
        .map(|x| match x.role {
            Role::Fit => "fit".to_string(),
            Role::Validation => "validation".to_string(),
        });
    let fits = Fits {
        experiment: case.experiment.clone(),
        role,
        sensors: case.model.sensors.iter().map(|s| s.name.clone()).collect(),
        fit_percent: fits,
    };
    Ok((fits, fitted))
}

/// The data sets the arguments name.
fn cases(model: &Model, args: &ValidateArgs, ui: &Ui) -> Result<Vec<Case>, Failure> {
    let index = |name: &str| -> Result<usize, Failure> {
        model
            .experiments
            .iter()
            .position(|x| x.name == name)
            .ok_or_else(|| {
                let names: Vec<&str> = model.experiments.iter().map(|x| x.name.as_str()).collect();
                Failure::input_msg(format!(
                    "--experiment {name}: {} has no such experiment (it has: {})",
                    args.model.display(),
                    if names.is_empty() {
                        "none".to_string()
                    } else {
                        names.join(", ")
                    }
                ))
            })
    };
    let first = |m: &Model, from: f64| -> Result<usize, Failure> {
        let from = args.from.unwrap_or(from);
        if from < 0.0 || !from.is_finite() {
            return Err(Failure::input_msg(format!(
                "--from {from}: must be a time ≥ 0 in seconds"
            )));
        }
        let k = m.sampling.first_sample(from);
        if k + 2 > m.sampling.n_samples() {
            return Err(Failure::input_msg(format!(
                "--from {from}: leaves {} of the record's {} samples",
                m.sampling.n_samples().saturating_sub(k),
                m.sampling.n_samples()
            )));
        }
        Ok(k)
    };
    let experiment = |e: usize| -> Result<Case, Failure> {
        let m = model.for_experiment(e);
        let measured = experiment_data(model, &args.model, e, &m, ui)?;
        let first = first(&m, model.experiments[e].from)?;
        Ok(Case {
            experiment: model.experiments[e].name.clone(),
            model: m,
            measured,
            first,
        })
    };
    match (&args.data, &args.experiment) {
        (Some(data), name) => {
            let (m, experiment) = match name {
                Some(n) => (model.for_experiment(index(n)?), n.clone()),
                None => (model.clone(), String::new()),
            };
            let measured = load_data(data, &m, ui)?;
            let first = first(&m, 0.0)?;
            Ok(vec![Case {
                experiment,
                model: m,
                measured,
                first,
            }])
        }
        (None, Some(n)) => Ok(vec![experiment(index(n)?)?]),
        (None, None) if !model.experiments.is_empty() => {
            (0..model.experiments.len()).map(experiment).collect()
        }
        (None, None) => Err(Failure::input_msg(format!(
            "{} lists no experiments: give the data to check with --data FILE",
            args.model.display()
        ))),
    }
}

/// What the data of `case` are called in the report's title.
fn source_name(args: &ValidateArgs, case: &Case) -> String {
    match (&args.data, case.experiment.as_str()) {
        (Some(d), _) => d.display().to_string(),
        (None, e) => format!("experiment {e}"),
    }
}

/// The fits as a table: one row per experiment and sensor.
fn fits_table(all: &[Fits]) -> String {
    let rows: Vec<Vec<String>> = all
        .iter()
        .flat_map(|f| {
            f.sensors.iter().zip(&f.fit_percent).map(|(s, fit)| {
                vec![
                    match (&f.experiment, &f.role) {
                        (e, _) if e.is_empty() => "-".to_string(),
                        (e, Some(r)) => format!("{e} ({r})"),
                        (e, None) => e.clone(),
                    },
                    s.clone(),
                    fit.map_or("- (constant signal)".into(), |v| format!("{v:.2}")),
                ]
            })
        })
        .collect();
    table(&["experiment", "sensor", "fit %"], &rows)
}
