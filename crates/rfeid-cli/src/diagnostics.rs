//! Turning library errors into reports and exit codes.
use miette::{LabeledSpan, MietteDiagnostic, NamedSource, Report};
use rfeid::io::model_file::ModelFileError;

/// Bad input: arguments, model or data files.
pub const EXIT_INPUT: u8 = 2;
/// A computation failed.
pub const EXIT_FAILURE: u8 = 1;
/// The identification ran and its result was written, but its verdict is
/// suspect (see `rfeid::identification::verdict`).
pub const EXIT_SUSPECT: u8 = 3;
/// The identification ran and its result was written, and its verdict is
/// model error alone: the estimates are the model's best fit, their standard
/// errors cover the noise only.
pub const EXIT_MODEL_ERROR: u8 = 4;

/// A failed command: its exit status and what to tell the user.
pub struct Failure {
    /// Exit status.
    pub code: u8,
    /// The report.
    pub report: Report,
}

impl Failure {
    /// Bad input, from a message.
    pub fn input_msg(msg: impl std::fmt::Display) -> Self {
        Failure {
            code: EXIT_INPUT,
            report: miette::miette!("{msg}"),
        }
    }

    /// A failed computation.
    pub fn failed(msg: impl std::fmt::Display) -> Self {
        Failure {
            code: EXIT_FAILURE,
            report: miette::miette!("{msg}"),
        }
    }
}

impl Failure {
    /// A written result whose verdict is suspect.
    pub fn suspect(msg: impl std::fmt::Display) -> Self {
        Failure {
            code: EXIT_SUSPECT,
            report: miette::miette!("{msg}"),
        }
    }

    /// A written result whose verdict is model error alone.
    pub fn model_error(msg: impl std::fmt::Display) -> Self {
        Failure {
            code: EXIT_MODEL_ERROR,
            report: miette::miette!("{msg}"),
        }
    }
}

/// A model-file error as a report with a span-annotated snippet.
pub fn model_error(e: ModelFileError) -> Failure {
    let mut where_ = e.entry.clone();
    if !e.field.is_empty() {
        if !where_.is_empty() {
            where_.push_str(", ");
        }
        where_.push_str(&format!("field '{}'", e.field));
    }
    let headline = if where_.is_empty() {
        format!("{}: {}", e.path.display(), e.message)
    } else {
        format!("{}: {}: {}", e.path.display(), where_, e.message)
    };
    let mut diag = MietteDiagnostic::new(headline);
    if let Some(span) = e.span.clone() {
        diag = diag.with_label(LabeledSpan::at(span, e.message.clone()));
    }
    let report = Report::new(diag);
    let report = match e.source_text {
        Some(text) if e.span.is_some() => report.with_source_code(NamedSource::new(
            e.path.display().to_string(),
            text.to_string(),
        )),
        _ => report,
    };
    Failure {
        code: EXIT_INPUT,
        report,
    }
}
