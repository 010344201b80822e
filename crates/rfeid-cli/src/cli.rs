//! Command-line arguments.
use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// Identify stiffness and damping of nonlinear machine-tool joints from
/// vibration tests (rigid-finite-element models).
#[derive(Debug, Parser)]
#[command(name = "rfeid", version, about, long_about = None)]
#[command(
    after_help = "Exit status: 0 success, 1 a computation failed, 2 bad input (arguments, model or data file)."
)]
pub struct Cli {
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Validate a model file and summarise it.
    #[command(after_help = "Example:\n  rfeid check examples/knee-column/model.toml")]
    Check(CheckArgs),
    /// Simulate the sensors' response at the parameters' nominal values and write CSV.
    #[command(
        after_help = "Example:\n  rfeid simulate examples/knee-column/model.toml -o knee.csv --noise 0.02 --seed 1\n  rfeid simulate model.toml -o stiff.csv --set a_n1=\"450 daN/um^2\""
    )]
    Simulate(SimulateArgs),
    /// Natural frequencies, damping ratios and mode shapes of the linearised model.
    #[command(after_help = "Example:\n  rfeid modal examples/knee-column/model.toml")]
    Modal(ModalArgs),
}

/// `rfeid check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// The model file (TOML).
    pub model: PathBuf,
}

/// `rfeid simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// The model file (TOML).
    pub model: PathBuf,
    /// Output CSV: a `time` column, then one column per sensor (SI units).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Add Gaussian noise of standard deviation FRAC × RMS of each sensor's signal.
    #[arg(long, value_name = "FRAC")]
    pub noise: Option<f64>,
    /// Seed of the noise generator.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Set a parameter, e.g. `--set a_n1=450e13` or `--set a_n1="450 daN/um^2"` (repeatable).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Integrator steps per sample (overrides the model's `substeps`).
    #[arg(long)]
    pub substeps: Option<usize>,
}

/// `rfeid modal`.
#[derive(Debug, Args)]
pub struct ModalArgs {
    /// The model file (TOML).
    pub model: PathBuf,
    /// Set a parameter (repeatable), as for `simulate`.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Also print the mode shapes.
    #[arg(long)]
    pub shapes: bool,
}
