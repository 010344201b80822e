//! A `constant` excitation (SPEC §1): P(t) = A for t ≥ 0, a steady load
//! such as a force offset. On the single oscillator from rest it gives the
//! step response A/k + the free motion from x0 = −A/k, which the simulation
//! must match to rounding (the jump sits at t = 0, where the run starts).
use crate::common;

use common::*;
use rfeid::io::model_file::parse_model;
use std::path::Path;

const MODEL: &str = r#"
[simulation]
duration = 0.2
sample_rate = 2000.0
substeps = 8

[[body]]
name = "mass"
mass = 2.0
inertia = [0.1, 0.2, 0.3]
com = [0.0, 0.0, 0.0]

[[element]]
name = "spring"
body = "mass"
to = "ground"
at = [0.0, 0.0, 0.0]
ux = { k = 2.0e5, c = 40.0 }

[[parameter]]
name = "P0"
value = "-30 N"

[[excitation]]
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = { type = "constant", amplitude = "P0" }

[[sensor]]
name = "x"
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "displacement"
"#;

#[test]
fn a_constant_force_gives_the_step_response() {
    let model = model(MODEL);
    let out = simulate_nominal(&model, None);
    let (a, k) = (-30.0, 2.0e5);
    let exact: Vec<f64> = times(&model)
        .iter()
        .map(|&t| a / k + sdof_free(2.0, 40.0, k, -a / k, 0.0, t).0)
        .collect();
    assert_within("step response", rel_max_err(out.sensor(0), &exact), 1e-10);
}

#[test]
fn a_constant_takes_only_an_amplitude() {
    let bad = MODEL.replace(
        r#"{ type = "constant", amplitude = "P0" }"#,
        r#"{ type = "constant", amplitude = "P0", frequency = 0.0 }"#,
    );
    let e = parse_model(&bad, Path::new("m.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("signal.frequency") && e.contains("does not apply to a constant signal"),
        "{e}"
    );
    let bad = MODEL.replace(r#", amplitude = "P0" }"#, " }");
    let e = parse_model(&bad, Path::new("m.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("'amplitude' is missing"), "{e}");
}
