//! Coloured-noise cases of the knee–column benchmark: the example model's
//! truth simulated, Gaussian noise of a fraction of each sensor's RMS passed
//! through a second-order low-pass (an anti-alias filter) added, and the
//! whole `rfeid identify` pipeline at its defaults run on it; shared by
//! `tests/identification_coloured_noise.rs` and `examples/coloured_noise.rs`.
#![allow(dead_code)]
use crate::wide_cases;

use rfeid::identification::result::IdentificationResult;
use rfeid::measurement::add_filtered_noise;
use rfeid::model::Model;
use rfeid::simulation::{Response, Simulator, Workspace};

pub use wide_cases::{default_settings, example, run};

/// The knee–column example model.
pub fn knee_column() -> Model {
    rfeid::io::model_file::load_model(&example("knee-column")).expect("the example loads")
}

/// The truth of `model` with `fraction` noise low-passed at `corner` Hz.
pub fn coloured_data(model: &Model, fraction: f64, corner: f64, seed: u64) -> Response {
    let sim = Simulator::new(model);
    let mut out = sim.response_buffer();
    sim.run(&model.nominal(), &mut Workspace::default(), &mut out)
        .expect("the truth simulates");
    add_filtered_noise(&mut out, fraction, corner, model.sampling.sample_rate, seed);
    out
}

/// Every estimate's |estimate − truth| / standard error (∞ without one).
pub fn z_scores(r: &IdentificationResult) -> Vec<f64> {
    r.parameters
        .iter()
        .map(|p| match p.std_error {
            Some(s) if s > 0.0 => (p.estimate - p.nominal).abs() / s,
            _ => f64::INFINITY,
        })
        .collect()
}

/// The root mean square of `z`.
pub fn rms(z: &[f64]) -> f64 {
    (z.iter().map(|v| v * v).sum::<f64>() / z.len().max(1) as f64).sqrt()
}
