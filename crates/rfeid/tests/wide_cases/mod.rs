//! Wide-box identification cases (issue 8 §2), shared by the test
//! `identification_global.rs` and the example `wide_boxes`: one of the
//! example models with every identified parameter's box `factor` wide
//! (max = factor · min) and its true value at a seeded random log position
//! p ∈ [0.15, 0.85] of it (`min = v/f^p`, `max = v·f^(1−p)`, log scale),
//! noisy data simulated at the truth, and the identification at the
//! command line's default settings.
#![allow(dead_code)]
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{identify, Settings, Silent, Weighting, DEFAULT_RESTARTS};
use rfeid::identification::result::IdentificationResult;
use rfeid::io::model_file::load_model;
use rfeid::measurement::add_noise;
use rfeid::model::{Model, Scale};
use rfeid::simulation::{Response, Simulator, Workspace};
use std::path::{Path, PathBuf};

/// The example models, by name under `examples/`.
pub const MODELS: [&str; 3] = ["knee-column", "lathe", "tailstock"];

/// The path of example model `name`.
pub fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
        .join("model.toml")
}

/// The model at `path` with every identified box `factor` wide around its
/// value, at log positions drawn from `seed`.
pub fn widened(path: &Path, factor: f64, seed: u64) -> Model {
    let mut model = load_model(path).unwrap_or_else(|e| panic!("{e}"));
    let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_mul(1_000_003) ^ factor.to_bits());
    for p in &mut model.parameters {
        if p.bounds.is_some() {
            let pos: f64 = rng.random_range(0.15..0.85);
            p.bounds = Some((p.value / factor.powf(pos), p.value * factor.powf(1.0 - pos)));
            p.scale = Scale::Log;
        }
    }
    model
}

/// Data simulated at the model's values with `noise` (fraction of each
/// sensor's RMS) drawn from `seed`.
pub fn data(model: &Model, noise: f64, seed: u64) -> Response {
    let sim = Simulator::new(model);
    let mut out = sim.response_buffer();
    sim.run(&model.nominal(), &mut Workspace::default(), &mut out)
        .expect("the truth simulates");
    add_noise(&mut out, noise, seed);
    out
}

/// The command line's defaults (`rfeid identify` without options):
/// a 100-point plan, one start, `--window 0.15`, the automatic restarts,
/// sensor weights estimated from the residuals (`--weights estimated`).
pub fn default_settings() -> Settings {
    Settings {
        plan_points: 100,
        starts: 1,
        window: Some(0.15),
        restarts: DEFAULT_RESTARTS,
        weighting: Weighting::EstimatedNoise,
        ..Settings::default()
    }
}

/// Identifies `model`'s parameters from `data` as `rfeid identify` does:
/// steps chosen at the nominal values, then the pipeline.
pub fn run(model: &Model, data: Response, settings: &Settings) -> IdentificationResult {
    let sim = Simulator::choose(model, &model.nominal()).expect("steps");
    identify(OutputError::new(sim, data, 0), settings, &Silent).expect("identifies")
}

/// The largest |estimate − truth| in standard errors and its parameter
/// (∞ without standard errors).
pub fn worst_z(r: &IdentificationResult) -> (f64, String) {
    r.parameters
        .iter()
        .map(|p| match p.std_error {
            Some(s) => ((p.estimate - p.nominal).abs() / s, p.name.clone()),
            None => (f64::INFINITY, p.name.clone()),
        })
        .fold((0.0, String::new()), |a, b| if b.0 > a.0 { b } else { a })
}

/// The model file at `path` with the boxes of `wide` (same parameters) as
/// SI numbers, for `rfeid identify` runs of the same case.
pub fn widened_text(path: &Path, wide: &Model) -> String {
    let text = std::fs::read_to_string(path).expect("the model file reads");
    let mut blocks = text.split("[[parameter]]");
    let mut out = blocks.next().expect("a model").to_string();
    for block in blocks {
        let name = block
            .lines()
            .find_map(|l| l.trim().strip_prefix("name = "))
            .expect("a name")
            .trim_matches('"');
        let p = wide
            .parameters
            .iter()
            .find(|p| p.name == name)
            .expect("the parameter");
        let edited: Vec<String> = block
            .lines()
            .map(|l| match (p.bounds, l.trim_start()) {
                (Some((lo, _)), t) if t.starts_with("min = ") => format!("min = {lo:e}"),
                (Some((_, hi)), t) if t.starts_with("max = ") => format!("max = {hi:e}"),
                _ => l.to_string(),
            })
            .collect();
        out.push_str("[[parameter]]");
        out.push_str(&edited.join("\n"));
    }
    out
}
