//! Steps split at the excitation's kinks and jumps.
//!
//! The model is `examples/lathe` (three bodies, eight power-law slideway
//! normals with m = 1.5 under gravity) with its chirp ending at 0.2 s, in the
//! middle of the record and between two samples, and a half-sine impulse on
//! the carriage that starts and ends between samples: the excitation's
//! derivative jumps at the impulse's start and end and the force itself
//! jumps at the chirp's end. A step across such an instant would fall to
//! first or second order there.
//!
//! The reference is rfeid itself at 64 steps per sample, checked to have
//! converged (64 and 128 steps agree to far below the tolerance checked).
//! It is an honest reference for the time discretisation, which is what is
//! tested here; the assembly of the equations is checked against an
//! independent implementation in `knee_column_reference.rs`.
use crate::common;

use common::*;
use rfeid::io::model_file::parse_model;
use rfeid::model::Model;
use rfeid::simulation::steps::{integrator, relative_difference};
use rfeid::simulation::Simulator;
use std::path::Path;

fn lathe_with_impulse() -> Model {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = root.join("../../examples/lathe/model.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let chirp = r#"signal = { type = "chirp", amplitude = "200 N", f0 = "20 Hz", f1 = "600 Hz" }"#;
    assert!(text.contains(chirp), "the example's chirp changed");
    let text = text.replace(
        chirp,
        &format!(
            "{}\n\n[[excitation]]\nname = \"knock\"\nbody = \"carriage\"\nat = [0.0, 0.0, 1.2]\n\
             direction = [0.3, 1.0, 0.2]\n\
             signal = {{ type = \"impulse\", amplitude = \"500 N\", t0 = \"50.03 ms\", width = \"1.7 ms\" }}",
            chirp.replace("f1 = \"600 Hz\" }", "f1 = \"600 Hz\", duration = \"0.20007 s\" }")
        ),
    );
    parse_model(&text, &path).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn impulse_and_chirp_end_reach_1e_7_at_default_settings() {
    let model = lathe_with_impulse();
    let fine = simulate_nominal(&model, Some(integrator(64)));
    let finer = simulate_nominal(&model, Some(integrator(128)));
    let converged = relative_difference(&model, &fine, &finer);
    println!("64 vs 128 steps per sample: {converged:.2e}");
    assert!(converged < 1e-9, "{converged:e}");

    let sim = Simulator::new(&model);
    let steps = sim.steps();
    let default = simulate_nominal(&model, None);
    let error = relative_difference(&model, &default, &fine);
    println!(
        "default: {} step(s) per sample, estimated {:.2e}, error {error:.2e}",
        steps.substeps,
        steps.estimated_error.unwrap_or(f64::NAN)
    );
    assert_within("default settings", error, 1e-7);
}
