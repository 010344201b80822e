//! The `rfeid` command line.
mod cli;
mod commands;
mod diagnostics;
mod format;

use clap::Parser;
use diagnostics::Failure;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    let result = match args.command {
        cli::Command::Check(a) => commands::check::run(a),
        cli::Command::Simulate(a) => commands::simulate::run(a),
        cli::Command::Modal(a) => commands::modal::run(a),
        cli::Command::Identify(a) => commands::identify::run(a),
        cli::Command::Demo(a) => commands::demo::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure { code, report }) => {
            eprintln!("{report:?}");
            ExitCode::from(code)
        }
    }
}
