//! Command-line arguments.
use clap::{Args, Parser, Subcommand};
use rfeid::identification::options::{
    DEFAULT_FROM, DEFAULT_METHOD, DEFAULT_NOISE_MODEL, DEFAULT_PLAN, DEFAULT_STARTS,
};
use rfeid::identification::pipeline::{Method, NoiseModel};
use std::path::PathBuf;

/// Identify stiffness and damping of nonlinear machine-tool joints from
/// vibration tests (rigid-finite-element models).
#[derive(Debug, Parser)]
#[command(name = "rfeid", version, about, long_about = None)]
#[command(
    after_help = "Exit status: 0 success, 1 a computation failed, 2 bad input (arguments, model, data file or output location), 3 the identification's result was written but its verdict is suspect, 4 it was written and its verdict is model error, 130/143/129 interrupted (docs/reference/exit-status.md).\nOutputs: their directories must exist; inputs are never overwritten; all outputs of a run appear together or not at all; `-o -` writes to standard output (docs/reference/output-files.md)."
)]
pub struct Cli {
    /// The command.
    #[command(subcommand)]
    pub command: Command,
    /// Print nothing but results and errors (no progress, no notes).
    #[arg(long, short, global = true)]
    pub quiet: bool,
    /// Print machine-readable JSON on stdout instead of tables.
    #[arg(long, global = true)]
    pub json: bool,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Validate a model file and summarise it.
    #[command(after_help = "Example:\n  rfeid check examples/knee-column/model.toml")]
    Check(CheckArgs),
    /// Simulate the sensors' response at the parameters' nominal values and write CSV.
    #[command(
        after_help = "Example:\n  rfeid simulate examples/knee-column/model.toml -o knee.csv --noise 0.02 --seed 1\n  rfeid simulate model.toml -o stiff.csv --set a_n1=\"450 daN/um^2\"\n  rfeid simulate examples/knee-column-campaign/model.toml --experiment low -o low.csv"
    )]
    Simulate(SimulateArgs),
    /// Identify the parameters that have a box from measured signals.
    #[command(
        after_help = "Example:\n  rfeid simulate examples/knee-column/model.toml -o data.csv --noise 0.02 --seed 1\n  rfeid identify examples/knee-column/model.toml --data data.csv -o result.json\n  examples/knee-column-campaign/generate.sh && rfeid identify examples/knee-column-campaign/model.toml -o result.json   # a campaign: every [[experiment]]\n\nExit status: 0 trustworthy, 3 written but suspect, 4 written but model error (the verdict; --shard: 0), 1 a computation failed, 2 bad input, 130/143/129 interrupted (docs/reference/exit-status.md)."
    )]
    Identify(IdentifyArgs),
    /// The paper's example end to end: simulate the knee–column benchmark, then identify its 16 joint parameters.
    #[command(
        after_help = "Example:\n  rfeid demo\n  rfeid demo --noise 0.02 --seed 3 --timings\n\nExit status: 0 trustworthy, 3 written but suspect, 4 written but model error (the verdict), 1 a computation failed, 2 bad input, 130/143/129 interrupted (docs/reference/exit-status.md)."
    )]
    Demo(DemoArgs),
    /// Write the HTML report of an identification from its RESULT.json.
    #[command(
        after_help = "Example:\n  rfeid identify model.toml --data data.csv -o result.json\n  rfeid report result.json -o report/   # then open report/report.html"
    )]
    Report(ReportArgs),
    /// Merge the shard files of `identify --shard K/N` and finish the identification (local searches, bounds, verdict): the same result as one run.
    #[command(
        after_help = "Example:\n  rfeid identify model.toml --data data.csv --shard 0/2 -o shard-0.json\n  rfeid identify model.toml --data data.csv --shard 1/2 -o shard-1.json\n  rfeid merge shard-0.json shard-1.json -o result.json\n\nExit status: 0 trustworthy, 3 written but suspect, 4 written but model error (the verdict), 1 a computation failed, 2 bad input, 130/143/129 interrupted (docs/reference/exit-status.md)."
    )]
    Merge(MergeArgs),
    /// Check an identification on other data: simulate at the estimate and print the fit per sensor.
    #[command(
        after_help = "Example:\n  rfeid identify model.toml --data test1.csv -o result.json\n  rfeid validate model.toml result.json --data test2.csv --report check/\n  rfeid validate examples/knee-column-campaign/model.toml result.json   # every experiment\n  rfeid validate examples/knee-column-campaign/model.toml result.json --experiment low"
    )]
    Validate(ValidateArgs),
    /// Experiment design: predicted standard errors of a planned test, and the D-optimal choice of candidate sensors.
    #[command(
        after_help = "Example:\n  rfeid design examples/knee-column/model.toml\n  rfeid design examples/knee-column/model.toml --choose 3 --report design/\n  rfeid design examples/knee-column/model.toml --choose 3 --over-box 16 -o design.json"
    )]
    Design(DesignArgs),
    /// Natural frequencies, damping ratios and mode shapes of the linearised model.
    #[command(after_help = "Example:\n  rfeid modal examples/knee-column/model.toml")]
    Modal(ModalArgs),
    /// Frequency response functions of the linearised model, with a 95 % band from a result and the measured H1 and coherence.
    #[command(
        after_help = "The model is linearised at rest, or at its static equilibrium under gravity (as for `modal`): a nonlinear joint's FRF holds for small motions about that point.\n\nExamples:\n  rfeid frf examples/knee-column/model.toml --plot frf.svg\n  rfeid frf examples/knee-column/model.toml --result RESULT.json --data data.csv -o frf.csv --plot frf.svg\n  rfeid frf examples/knee-column/model.toml --at tool=knee@0.1,0.9,0.8/0,0,1"
    )]
    Frf(FrfArgs),
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
    /// Output CSV: a `time` column, then one column per sensor (SI units); `-` for standard output.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Add Gaussian noise of standard deviation FRAC × RMS of each sensor's signal.
    #[arg(long, value_name = "FRAC")]
    pub noise: Option<f64>,
    /// Pass the noise through a second-order Butterworth low-pass with its corner at HZ, as a data acquisition system's anti-alias filter leaves it (coloured noise; its standard deviation stays FRAC × RMS). Needs --noise.
    #[arg(long, value_name = "HZ", requires = "noise")]
    pub noise_corner: Option<f64>,
    /// Seed of the noise generator.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Set a parameter, e.g. `--set a_n1=450e13` or `--set a_n1="450 daN/um^2"` (repeatable).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Integrator accuracy.
    #[command(flatten)]
    pub steps: StepArgs,
    /// Also plot the responses to this SVG file (`-` for standard output).
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Simulate this `[[experiment]]` of the model file: its `set` values, sampling, excitations and sensors.
    #[arg(long, value_name = "NAME")]
    pub experiment: Option<String>,
}

/// `rfeid report`.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// RESULT.json written by `rfeid identify` or `rfeid demo -o`.
    pub result: PathBuf,
    /// Directory for report.html and the figures (SVG); its parent must exist, and an existing one is replaced whole.
    #[arg(short, long)]
    pub output: PathBuf,
}

/// `rfeid validate`.
#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// The model file (TOML) the result was identified with.
    pub model: PathBuf,
    /// RESULT.json written by `rfeid identify`; its `--set` values are applied again.
    pub result: PathBuf,
    /// Measured data to check against (CSV, MAT or UFF), on the model's sensors and sampling (or those of --experiment).
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// One experiment of the model file: its data, or with --data its settings. Default: every experiment.
    #[arg(long, value_name = "NAME")]
    pub experiment: Option<String>,
    /// Skip an initial transient: fit from this time in seconds (default: the experiment's `from`, else 0).
    #[arg(long, value_name = "S")]
    pub from: Option<f64>,
    /// Also write the HTML report of the result on these data (one data set only).
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
}

/// `rfeid design`.
#[derive(Debug, Args)]
pub struct DesignArgs {
    /// The model file (TOML); every placed sensor and candidate needs `noise` (docs/reference/model-file.md, [[sensor]]).
    pub model: PathBuf,
    /// Add the D-optimal K of the candidate sensors (`candidate = true`) to the placed ones.
    #[arg(long, value_name = "K")]
    pub choose: Option<usize>,
    /// Choose for the average over N LP_τ points of the parameter box (the values are not known before the test), and report how much the choice changes.
    #[arg(long = "over-box", value_name = "N")]
    pub over_box: Option<usize>,
    /// Design at other values than the model's (repeatable), as for `simulate`.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Write the design as JSON to this file (`-` for standard output).
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Also write an HTML report: the candidate points on the bodies, and the predicted relative standard errors.
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
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
    /// Also write frequencies, damping ratios and mode shapes to this JSON file (`-` for standard output).
    #[arg(long = "json-file", value_name = "FILE")]
    pub json_file: Option<PathBuf>,
}

/// What a point given with `frf --at` reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Quantity {
    /// Displacement: the dynamic compliance, m/N.
    Displacement,
    /// Velocity: the mobility, (m/s)/N.
    Velocity,
    /// Acceleration: the accelerance, (m/s²)/N.
    Acceleration,
}

/// How `frf`'s grid is spaced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SpacingArg {
    /// Evenly in log f (a Bode plot's).
    Log,
    /// Evenly in f.
    Linear,
}

/// `rfeid frf`.
#[derive(Debug, Args)]
pub struct FrfArgs {
    /// The model file (TOML).
    pub model: PathBuf,
    /// RESULT.json of `rfeid identify`: the FRFs at its estimate, with a 95 % band from its standard errors and correlations (delta method); its `--set` values are applied again.
    #[arg(long)]
    pub result: Option<PathBuf>,
    /// Measured data (CSV, MAT or UFF) on the model's sensors and sampling: each sensor's measured FRF (H1, Welch with Hann windows) and coherence, from the excitation's signal (a measured-force table, or the model's own signal).
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// The --data column (or variable, or record name) holding the excitation's measured force, for H1; the excitation is --excitation's, or the model's only one. Default: the excitation's own signal in the model.
    #[arg(long, value_name = "COLUMN", requires = "data")]
    pub force: Option<String>,
    /// One [[experiment]] of the model file: its settings, and without --data its data. Without it, a campaign's every experiment is measured over the model (each force level's H1 in turn).
    #[arg(long, value_name = "NAME")]
    pub experiment: Option<String>,
    /// The excitation the FRFs are from (default: every one of the model's).
    #[arg(long, value_name = "NAME")]
    pub excitation: Option<String>,
    /// Only the FRFs to this sensor (repeatable; default: every sensor).
    #[arg(long, value_name = "NAME")]
    pub sensor: Vec<String>,
    /// Also the FRF to a point: NAME=BODY@X,Y,Z/DX,DY,DZ, the point in global metres and the direction as global components (repeatable), e.g. tool=knee@0.1,0.9,0.8/0,0,1.
    #[arg(long, value_name = "NAME=BODY@X,Y,Z/DX,DY,DZ")]
    pub at: Vec<String>,
    /// What the --at points read.
    #[arg(long, value_enum, default_value = "displacement")]
    pub quantity: Quantity,
    /// Highest frequency, Hz (default: the Nyquist frequency of the model's sampling).
    #[arg(long, value_name = "HZ")]
    pub fmax: Option<f64>,
    /// Lowest frequency, Hz (default: a tenth of the lowest mode's on a log grid, fmax / points on a linear one).
    #[arg(long, value_name = "HZ")]
    pub fmin: Option<f64>,
    /// Frequencies on the model's grid, 2 to 100 000 (default: four in the half-power band of the sharpest mode on a log grid, 200 to 20 000; 1000 on a linear one). With one data set, Welch's grid is used instead, so that model and H1 share each row.
    #[arg(long, value_name = "N")]
    pub points: Option<usize>,
    /// How the model's grid is spaced.
    #[arg(long, value_enum, default_value = "log")]
    pub spacing: SpacingArg,
    /// Samples per Welch segment for H1, a power of two (default: the longest that gives 16 averages).
    #[arg(long, value_name = "N")]
    pub segment: Option<usize>,
    /// Use the data from this time in seconds (default: the experiment's `from`, else 0).
    #[arg(long, value_name = "S")]
    pub from: Option<f64>,
    /// Set a parameter (repeatable), as for `simulate`; with --result, only parameters it did not identify.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Write the FRFs as CSV, one row per pair, curve and frequency (`-` for standard output).
    #[arg(short, long, value_name = "FILE.csv")]
    pub output: Option<PathBuf>,
    /// Write the FRFs as JSON (`-` for standard output).
    #[arg(long = "json-file", value_name = "FILE")]
    pub json_file: Option<PathBuf>,
    /// Plot magnitude (log), phase and coherence of every pair to this SVG file.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
}

/// The integrator's accuracy, for every command that simulates.
#[derive(Debug, Args)]
pub struct StepArgs {
    /// Relative RMS error of the simulated signals that the integrator's steps per sample are
    /// chosen for (overrides the model's `tolerance`; default 1e-7, from 1e-13 to 1e-2).
    #[arg(long, value_name = "REL")]
    pub tolerance: Option<f64>,
    /// Fix the integrator's steps per sample instead (1 to 1000; overrides the model's
    /// `substeps` and the automatic choice).
    #[arg(long, value_name = "N")]
    pub substeps: Option<usize>,
}

/// Settings shared by `identify` and `demo`.
#[derive(Debug, Args)]
pub struct SearchArgs {
    /// Points of the LP_τ (Sobol) plan over the parameter box (1 to 1 000 000).
    #[arg(long, default_value_t = DEFAULT_PLAN)]
    pub plan: usize,
    /// Run the local search from the best K plan points and keep the best result (K ≤ 1000 and ≤ the plan).
    #[arg(long, default_value_t = DEFAULT_STARTS, value_name = "K")]
    pub starts: usize,
    /// Local search: Levenberg–Marquardt with exact sensitivities, or the paper's BFGS.
    #[arg(long, value_enum, default_value_t = MethodArg::of(DEFAULT_METHOD))]
    pub method: MethodArg,
    /// Sensor weights: equal (the paper's), or estimated from each sensor's residual variance. Default estimated for `identify` (valid standard errors when the sensors' noise levels differ), equal for `demo`.
    #[arg(long, value_enum)]
    pub weights: Option<WeightsArg>,
    /// How the noise is modelled with estimated weights: an autoregressive model per sensor, its order chosen from the residuals (coloured noise, as anti-alias filters leave it, gets honest standard errors; white noise gets order 0), or white noise (the paper's output error, eq. 12–16).
    #[arg(long, value_enum, default_value_t = NoiseModelArg::of(DEFAULT_NOISE_MODEL))]
    pub noise_model: NoiseModelArg,
    /// Worker threads (default: all cores; at most 1024). Results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Ignore the record before this time, s (the transient from an unknown initial state).
    #[arg(long, value_name = "SECONDS", default_value_t = DEFAULT_FROM)]
    pub from: f64,
    /// Print the wall time of each phase.
    #[arg(long)]
    pub timings: bool,
    /// Integrator accuracy.
    #[command(flatten)]
    pub steps: StepArgs,
    /// Each local search first fits this fraction of the record, then the whole record from there (0 ≤ FRACTION < 1; 0: off). Default 0.15 for `identify`, off for `demo`.
    #[arg(long, value_name = "FRACTION")]
    pub window: Option<f64>,
    /// The most memory a whole Jacobian (residual rows × parameters) may take, MiB (default 256). A larger one is never held whole: the simulation hands its rows over in blocks of samples to the Jacobian's triangular factor, which gives the same steps, estimates and standard errors to rounding. 0: always by blocks.
    #[arg(long, value_name = "MIB")]
    pub jacobian_memory: Option<usize>,
    /// Profile likelihoods.
    #[command(flatten)]
    pub profile: ProfileArgs,
}

/// Profile likelihoods after the bounds, for every command that identifies.
#[derive(Debug, Clone, Default, Args)]
pub struct ProfileArgs {
    /// After the bounds, the profile likelihood of each of these identified parameters (comma-separated, e.g. `--profiles a_n4,h_t3`; alone, every one): J minimised over the other parameters at a grid of its values about the estimate, and its 95 % likelihood-ratio interval beside the Wald interval of its standard error. Give NAMES with `=` when the model file follows (`--profiles=a_n4 model.toml`).
    #[arg(long, value_name = "NAMES", num_args = 0..=1, default_missing_value = "")]
    pub profiles: Option<String>,
    /// Grid points of each profile, half each side of the estimate, over ±3 standard errors (2 to 1000; default 20); a side still below the 95 % threshold at its last point is extended towards the box's bound.
    #[arg(long, value_name = "N", requires = "profiles")]
    pub profile_points: Option<usize>,
}

/// `--method`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum MethodArg {
    /// Levenberg–Marquardt.
    Lm,
    /// BFGS with finite-difference gradients (eq. 20–25).
    Bfgs,
}

impl MethodArg {
    /// The argument of the library's method.
    pub const fn of(m: Method) -> Self {
        match m {
            Method::Lm => MethodArg::Lm,
            Method::Bfgs => MethodArg::Bfgs,
        }
    }
}

impl NoiseModelArg {
    /// The argument of the library's noise model.
    pub const fn of(m: NoiseModel) -> Self {
        match m {
            NoiseModel::White => NoiseModelArg::White,
            NoiseModel::Autoregressive { .. } => NoiseModelArg::Ar,
        }
    }
}

/// `--noise-model`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum NoiseModelArg {
    /// An autoregressive model per sensor (order by BIC, at most 64).
    Ar,
    /// White noise per sensor.
    White,
}

/// `--weights`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum WeightsArg {
    /// w = 1 for every sensor.
    Equal,
    /// w = 1/σ² per sensor, estimated and iterated.
    Estimated,
}

/// `rfeid identify`.
#[derive(Debug, Args)]
pub struct IdentifyArgs {
    /// The model file (TOML); parameters with `min` and `max` are identified.
    pub model: PathBuf,
    /// Measured signals: CSV (`time` and one column per sensor), MATLAB .mat
    /// (v5; vectors by name and a `time` vector or `sample_rate`), or a
    /// universal file (.uff/.unv, dataset 58, ASCII or binary). A sensor's
    /// `data = { column | variable | record = … }` says where its signal is.
    /// Not with a model that lists `[[experiment]]` entries, which name
    /// their own data files.
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// Result file (JSON); `-` for standard output.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also write the HTML report (report.html and SVG figures) into this directory (its parent must exist; an existing report is replaced whole).
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
    /// Evaluate only shard K of N of the plan (points whose index mod N is K, K = 0 … N−1) and write them to `-o` as a shard file for `rfeid merge`; `auto` takes K and N from SLURM_ARRAY_TASK_ID (minus SLURM_ARRAY_TASK_MIN) and SLURM_ARRAY_TASK_COUNT. A shard file already at `-o` from the same run is resumed.
    #[arg(long, value_name = "K/N|auto", allow_hyphen_values = true)]
    pub shard: Option<String>,
    /// Fix a parameter for this run, e.g. `--set m=1.5` or `--set P0="20 daN"` (repeatable): it takes the value and is not identified, even if the model file gives it a box. RESULT.json records the settings, and `rfeid report` applies them again.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Where the local search starts: `plan`, the best `--starts` points of the LP_τ plan; or `values`, once from the identified parameters' `value`s in the model file, without the plan (only one point is evaluated, to check the problem): the minimum nearest the values.
    #[arg(long, value_enum, default_value_t = StartArg::Plan)]
    pub start: StartArg,
    /// Search settings.
    #[command(flatten)]
    pub search: SearchArgs,
}

/// `--start`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum StartArg {
    /// From the best points of the LP_τ plan.
    Plan,
    /// From the parameters' values in the model file.
    Values,
}

/// `rfeid merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The shard files of every shard of one run (`identify --shard K/N`).
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// Result file (JSON); `-` for standard output.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also write the HTML report into this directory.
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print the wall time of each phase.
    #[arg(long)]
    pub timings: bool,
    /// The model file, where the one the shards recorded is not found from
    /// here (the shards record it as `identify` was given it). Its hash must
    /// still match.
    #[arg(long, value_name = "MODEL")]
    pub model: Option<PathBuf>,
    /// The data file, where the one the shards recorded is not found from
    /// here. Its hash must still match.
    #[arg(long, value_name = "DATA")]
    pub data: Option<PathBuf>,
    /// Profile likelihoods.
    #[command(flatten)]
    pub profile: ProfileArgs,
}

/// `rfeid demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Add Gaussian noise of standard deviation FRAC × RMS to the simulated data.
    #[arg(long, value_name = "FRAC")]
    pub noise: Option<f64>,
    /// Seed of the noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Also write the result (JSON); `-` for standard output.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Also write the HTML report (report.html and SVG figures) into this directory (its parent must exist; an existing report is replaced whole).
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
    /// Search settings.
    #[command(flatten)]
    pub search: SearchArgs,
}
