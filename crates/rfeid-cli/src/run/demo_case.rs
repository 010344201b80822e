//! The built-in knee–column benchmark (SPEC §4): its model, its simulated
//! data, and how its reports name it.
use super::failures::noise_sensor;
use crate::diagnostics::{model_error, Failure};
use rfeid::identification::result::IdentificationResult;
use rfeid::io::model_file::parse_model;
use rfeid::measurement::{add_noise, check_noise};
use rfeid::model::Model;
use rfeid::simulation::{Response, Simulator, Workspace};
use std::path::Path;

/// The knee–column benchmark (SPEC §4), built into the binary.
const KNEE_COLUMN: &str = include_str!("../../../../examples/knee-column/model.toml");

/// The built-in knee–column model.
pub fn demo_model() -> Result<Model, Failure> {
    parse_model(KNEE_COLUMN, Path::new("examples/knee-column/model.toml")).map_err(model_error)
}

/// The demo's data: the model at its true (nominal) values, plus seeded noise.
pub fn demo_data(model: &Model, noise: Option<f64>, seed: u64) -> Result<Response, Failure> {
    let sim = Simulator::choose(model, &model.nominal())
        .map_err(|e| Failure::failed(format!("simulating the data failed: {e}")))?;
    let mut data = sim.response_buffer();
    sim.run(&model.nominal(), &mut Workspace::default(), &mut data)
        .map_err(|e| Failure::failed(format!("simulating the data failed: {e}")))?;
    if let Some(f) = noise {
        check_noise(&data, f)
            .map_err(|e| Failure::input_msg(format!("--noise: {}", noise_sensor(model, e))))?;
        add_noise(&mut data, f, seed);
    }
    Ok(data)
}

/// The demo's title.
pub fn demo_title(result: &IdentificationResult) -> String {
    match (result.source.demo_noise, result.source.demo_seed) {
        (Some(f), Some(seed)) => {
            format!("Knee–column benchmark, {}% noise (seed {seed})", 100.0 * f)
        }
        _ => "Knee–column benchmark, noise-free data".into(),
    }
}

/// The true values of the identified parameters (the model's nominal ones).
pub fn reference_of(model: &Model, result: &IdentificationResult) -> Vec<f64> {
    result
        .parameters
        .iter()
        .map(|p| {
            model
                .parameter_index(&p.name)
                .map(|i| model.parameters[i].value)
                .unwrap_or(f64::NAN)
        })
        .collect()
}
