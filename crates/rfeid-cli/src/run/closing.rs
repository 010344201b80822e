//! The closing sequence of a search (`identify`, its campaign form,
//! `demo`, `merge`): the outputs written all or nothing (the report if
//! asked, RESULT.json), the results shown, and the exit status picked (0,
//! or 3 for a suspect result).
use super::report::ReportFiles;
use super::show::{report_note, show_result};
use crate::diagnostics::Failure;
use crate::outputs::Checked;
use crate::ui::Ui;
use rfeid::identification::result::IdentificationResult;
use rfeid::identification::verdict::Outcome;
use rfeid::model::Model;
use std::path::Path;

/// Where the note "result written to …" goes relative to the tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WrittenNote {
    /// Before the tables (`demo`).
    BeforeTables,
    /// After the tables (`identify`, `merge`).
    AfterTables,
}

/// What the closing sequence writes and shows.
pub struct Closing<'a> {
    /// The model searched.
    pub model: &'a Model,
    /// The result.
    pub result: &'a IdentificationResult,
    /// The report directory (`--report`) and its files, if asked for.
    pub report: Option<(&'a Path, ReportFiles)>,
    /// Whether to note where the report was written (`merge` does not).
    pub note_report: bool,
    /// RESULT.json (`-o`), if asked for.
    pub output: Option<&'a Path>,
    /// Where the "result written to" note goes.
    pub written_note: WrittenNote,
    /// What a suspect result's message calls the place it was written to.
    pub written: String,
    /// The tables' reference column (`nominal`, `actual`).
    pub reference: &'a str,
    /// `--timings`.
    pub timings: bool,
    /// A last line after the tables (on standard output, or standard error
    /// when an output took it), not shown with `--json` nor with `--quiet`
    /// when standard output is taken.
    pub epilogue: Option<String>,
}

impl<'a> Closing<'a> {
    /// The closing of a run that wrote RESULT.json to `output` (`identify`,
    /// a campaign, `merge`): the note after the tables, the nominal values
    /// as reference, no epilogue.
    pub fn of_result(
        model: &'a Model,
        result: &'a IdentificationResult,
        report: Option<(&'a Path, ReportFiles)>,
        output: &'a Path,
        timings: bool,
    ) -> Self {
        Closing {
            model,
            result,
            report,
            note_report: true,
            output: Some(output),
            written_note: WrittenNote::AfterTables,
            written: match output == std::path::Path::new("-") {
                true => "standard output".into(),
                false => output.display().to_string(),
            },
            reference: "nominal",
            timings,
            epilogue: None,
        }
    }
}

/// Writes the outputs all or nothing, shows the results and picks the exit
/// status: 0, or 3 for a suspect verdict.
pub fn close(outputs: &Checked, c: Closing<'_>, ui: &Ui) -> Result<(), Failure> {
    write_outputs(outputs, &c)?;
    if c.note_report {
        report_note(c.report.as_ref().map(|(dir, _)| *dir), ui);
    }
    let taken = outputs.uses_stdout();
    let written_note = || {
        if let Some(path) = c.output.filter(|_| !taken) {
            ui.note(format!("result written to {}", path.display()));
        }
    };
    if c.written_note == WrittenNote::BeforeTables {
        written_note();
    }
    show_result(c.model, c.result, c.reference, c.timings, taken, ui)?;
    if c.written_note == WrittenNote::AfterTables {
        written_note();
    }
    let shown = !(ui.json || (taken && ui.quiet));
    if let Some(line) = c.epilogue.as_ref().filter(|_| shown) {
        if taken {
            eprintln!("{line}");
        } else {
            println!("{line}");
        }
    }
    suspect_status(c.result, &c.written)
}

/// Stages the report and RESULT.json, then commits them together.
fn write_outputs(outputs: &Checked, c: &Closing<'_>) -> Result<(), Failure> {
    let mut batch = outputs.batch();
    if let Some((_, files)) = &c.report {
        batch.report("--report", files)?;
    }
    if c.output.is_some() {
        batch.file("-o", result_json(c.result)?)?;
    }
    batch.commit()
}

/// Exit status 3 for a written result whose verdict is suspect, 4 for one
/// whose verdict is model error alone.
pub fn suspect_status(result: &IdentificationResult, written: &str) -> Result<(), Failure> {
    let Some(v) = &result.verdict else {
        return Ok(());
    };
    match v.outcome() {
        Outcome::Trustworthy => Ok(()),
        Outcome::ModelError => Err(Failure::model_error(format!(
            "the model cannot fit these data better (model error, listed above): the estimates \
             are its best fit, their standard errors cover the noise only; written to {written}"
        ))),
        Outcome::Suspect => Err(Failure::suspect(format!(
            "the result is suspect ({} reason{}, listed above); it was written to {written} all the same",
            v.reasons.len(),
            if v.reasons.len() == 1 { "" } else { "s" }
        ))),
    }
}

/// RESULT.json's text.
pub fn result_json(r: &IdentificationResult) -> Result<Vec<u8>, Failure> {
    r.to_json_text()
        .map(String::into_bytes)
        .map_err(|e| Failure::failed(format!("the result as JSON: {e}")))
}
