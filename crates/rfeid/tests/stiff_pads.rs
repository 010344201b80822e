//! A stiff model: the knee–column with isolation pads 100 times stiffer
//! (2e9 and 6e9 N/m), whose fastest modes move far up. At default settings
//! the automatic steps must keep it within 1e-6 of a converged fine-step run
//! (rfeid at 64 steps per sample, checked against 128), quickly.
use crate::common;

use common::*;
use rfeid::io::model_file::parse_model;
use rfeid::simulation::steps::{integrator, relative_difference};
use rfeid::simulation::Simulator;
use std::path::Path;
use std::time::Instant;

#[test]
fn pads_100_times_stiffer_stay_accurate_at_default_settings() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = root.join("../../examples/knee-column/model.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let stiff = text
        .replace("k = \"2.0e7 N/m\"", "k = \"2.0e9 N/m\"")
        .replace("k = \"6.0e7 N/m\"", "k = \"6.0e9 N/m\"");
    assert_eq!(
        stiff.matches("e9 N/m").count(),
        12,
        "the example's pads changed"
    );
    for rate in ["10 kHz", "1 kHz"] {
        let text = stiff.replace(
            "sample_rate = \"10 kHz\"",
            &format!("sample_rate = \"{rate}\""),
        );
        let model = parse_model(&text, &path).unwrap_or_else(|e| panic!("{e}"));
        check(&model, rate);
    }
}

fn check(model: &rfeid::model::Model, rate: &str) {
    let start = Instant::now();
    let sim = Simulator::new(model);
    let default = simulate_nominal(model, None);
    let seconds = start.elapsed().as_secs_f64();
    let steps = sim.steps();

    let fine = simulate_nominal(model, Some(integrator(64)));
    let finer = simulate_nominal(model, Some(integrator(128)));
    let converged = relative_difference(model, &fine, &finer);
    assert!(converged < 1e-9, "fine-step reference: {converged:e}");
    let error = relative_difference(model, &default, &fine);
    println!(
        "stiff pads at {rate}: {} step(s) per sample, estimated {:.2e}, error {error:.2e}, \
         choice and run {seconds:.2} s (release build, loaded machine)",
        steps.substeps,
        steps.estimated_error.unwrap_or(f64::NAN)
    );
    assert_within("stiff pads, default settings", error, 1e-6);
    assert!(seconds < 10.0, "took {seconds} s");
}
