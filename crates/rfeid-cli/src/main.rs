//! The `rfeid` command line.
mod cli;
mod commands;
mod diagnostics;
mod format;
mod outputs;
mod run;
mod ui;

use clap::Parser;
use diagnostics::Failure;
use std::process::ExitCode;

fn main() -> ExitCode {
    restore_sigpipe();
    outputs::signals::install();
    let args = cli::Cli::parse();
    let ui = ui::Ui {
        quiet: args.quiet,
        json: args.json,
    };
    let result = match args.command {
        cli::Command::Check(a) => commands::check::run(a, &ui),
        cli::Command::Simulate(a) => commands::simulate::run(a, &ui),
        cli::Command::Modal(a) => commands::modal::run(a, &ui),
        cli::Command::Frf(a) => commands::frf::run(a, &ui),
        cli::Command::Design(a) => commands::design::run(a, &ui),
        cli::Command::Identify(a) => commands::identify::run(a, &ui),
        cli::Command::Demo(a) => commands::demo::run(a, &ui),
        cli::Command::Report(a) => commands::report::run(a, &ui),
        cli::Command::Merge(a) => commands::merge::run(a, &ui),
        cli::Command::Validate(a) => commands::validate::run(a, &ui),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure { code, report }) => {
            eprintln!("{report:?}");
            ExitCode::from(code)
        }
    }
}

/// Rust ignores SIGPIPE, so printing into a closed pipe (`rfeid check m.toml
/// | head`) would panic. Like other command-line tools, end quietly instead.
fn restore_sigpipe() {
    #[cfg(unix)]
    // SAFETY: resetting a signal's disposition to its default at start-up,
    // before any thread exists, has no preconditions.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
