//! `rfeid frf`: FRFs of the linearised model ([`rfeid::frf`]), at the
//! model's values or a result's estimate with its 95 % band, over the H1
//! and coherence of measured data.
mod inputs;
mod write;

use crate::cli::FrfArgs;
use crate::diagnostics::Failure;
use crate::outputs::Plan;
use crate::run::failures::simulation_failure;
use crate::run::show::json_conflict;
use crate::ui::Ui;
use rfeid::frf::{study, FrfError, FrfStudy};

/// Runs the command.
pub fn run(args: FrfArgs, ui: &Ui) -> Result<(), Failure> {
    let inputs = inputs::gather(&args, ui)?;
    let mut plan = Plan::new();
    plan.input(&args.model);
    for f in inputs.files() {
        plan.input(&f);
    }
    for (flag, path) in [
        ("-o", &args.output),
        ("--json-file", &args.json_file),
        ("--plot", &args.plot),
    ] {
        if let Some(p) = path {
            plan.file(flag, p);
        }
    }
    let outputs = plan.check()?;
    json_conflict(ui, &outputs)?;
    let result = study(&inputs.request(), &inputs.data_sets()).map_err(|e| match e {
        FrfError::Linearisation(e) => simulation_failure("linearising the model", e),
        FrfError::Segment { .. } => Failure::input_msg(format!("--segment: {e}")),
        FrfError::Singular { .. } => Failure::failed(e),
    })?;
    let mut batch = outputs.batch();
    if args.output.is_some() {
        batch.file("-o", write::csv(&result).into_bytes())?;
    }
    let json = write::json(&result, inputs.band_error.as_deref());
    if args.json_file.is_some() {
        batch.file("--json-file", json.clone().into_bytes())?;
    }
    if args.plot.is_some() {
        let svg = rfeid::report::frf::study_svg(&result).ok_or_else(|| {
            Failure::failed("--plot: the FRFs have no positive magnitude to draw")
        })?;
        batch.file("--plot", svg.into_bytes())?;
    }
    batch.commit()?;
    if outputs.uses_stdout() {
        return Ok(());
    }
    if ui.json {
        println!("{json}");
        return Ok(());
    }
    print_summary(&result, inputs.band_error.as_deref());
    for (flag, path) in [
        ("-o", &args.output),
        ("--json-file", &args.json_file),
        ("--plot", &args.plot),
    ] {
        if let Some(p) = path {
            ui.note(format!("{flag}: written to {}", p.display()));
        }
    }
    Ok(())
}

/// The linearisation, then each pair's peaks (with the band) and measured
/// coherence, in words.
fn print_summary(s: &FrfStudy, band_error: Option<&str>) {
    println!(
        "FRFs of the model linearised at {}, {} frequencies from {} to {} Hz",
        s.linearised_at,
        s.frequencies_hz.len(),
        crate::format::sig(s.frequencies_hz[0], 4),
        crate::format::sig(*s.frequencies_hz.last().unwrap_or(&0.0), 4)
    );
    if let Some(why) = band_error {
        println!("no band: {why}");
    }
    for pair in &s.pairs {
        println!("\n{} → {} ({})", pair.excitation, pair.output, pair.unit);
        print!("{}", write::peaks_table(s, pair));
        for m in &pair.measured {
            println!("{}", write::measured_line(m));
        }
    }
    for n in &s.notes {
        println!("note: {n}");
    }
}
