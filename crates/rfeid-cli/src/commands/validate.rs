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
use crate::run::failures::failure;
use crate::run::inputs::{fixed, load};
use crate::run::report::{read_result, render_fitted};
use crate::ui::Ui;
use rfeid::identification::result::IdentificationResult;
use rfeid::identification::validation::{self, Case, Fits, ValidationError};
use rfeid::measurement::measured::Source;
use rfeid::model::Model;
use rfeid::simulation::Response;

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

/// The fits of one data set, and the model's response at the estimate
/// ([`validation::fits`]).
fn fits_of(
    model: &Model,
    result: &IdentificationResult,
    case: &Case,
) -> Result<(Fits, Response), Failure> {
    validation::fits(model, result, case).map_err(validation_failure)
}

/// The data sets the arguments name ([`validation::cases`]), the
/// reading's notes shown.
fn cases(model: &Model, args: &ValidateArgs, ui: &Ui) -> Result<Vec<Case>, Failure> {
    let source = args.data.clone().map(Source::File);
    let (cases, notes) = validation::cases(
        model,
        &args.model.display().to_string(),
        source.as_ref(),
        args.experiment.as_deref(),
        args.from,
    )
    .map_err(validation_failure)?;
    for note in notes {
        ui.note(format!("note: {note}"));
    }
    Ok(cases)
}

/// A validation's error as a failure ([`failure`]).
fn validation_failure(e: ValidationError) -> Failure {
    failure(e)
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
