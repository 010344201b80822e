//! How the commands talk to the user: `--quiet` and `--json`.
use crate::diagnostics::Failure;

/// Output settings shared by every command.
#[derive(Debug, Clone, Copy)]
pub struct Ui {
    /// No progress and no notes on stderr.
    pub quiet: bool,
    /// JSON on stdout instead of tables.
    pub json: bool,
}

impl Ui {
    /// A note on stderr, unless `--quiet`.
    pub fn note(&self, msg: impl std::fmt::Display) {
        if !self.quiet {
            eprintln!("{msg}");
        }
    }

    /// Prints a value as pretty JSON on stdout.
    pub fn print_json<T: serde::Serialize>(&self, value: &T) -> Result<(), Failure> {
        let text = serde_json::to_string_pretty(value)
            .map_err(|e| Failure::failed(format!("JSON output: {e}")))?;
        println!("{text}");
        Ok(())
    }
}
