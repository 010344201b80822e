//! Buffers are reused between runs (identification runs thousands of them
//! without allocating): a `Workspace`, `Response` or `Sensitivities` left
//! over from a different model, a different parameter set or a failed run
//! must not change the next result, which is bit for bit that of fresh
//! buffers, with buffers of exactly the right size.
use crate::common;

use common::*;
use rfeid::io::model_file::load_model;
use rfeid::model::Model;
use rfeid::simulation::{Response, Sensitivities, Simulator, Workspace};
use std::path::Path;

fn knee_column() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    load_model(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// A small model: one body, two parameters, two sensors, 200 samples.
const SMALL: &str = r#"
[simulation]
duration = 0.1
sample_rate = 2000.0

[[body]]
name = "b"
mass = "m"
inertia = [1.0, 1.0, 1.0]
com = [0.0, 0.0, 0.0]

[[element]]
name = "s"
body = "b"
to = "ground"
at = [0.1, 0.0, 0.0]
ux = { k = "k", c = 50.0 }
uy = { k = 1e6 }
uz = { k = 1e6 }

[[parameter]]
name = "m"
value = 2.0
min = 1.0
max = 3.0

[[parameter]]
name = "k"
value = 1e6
min = 5e5
max = 2e6

[[excitation]]
body = "b"
at = [0.1, 0.1, 0.0]
direction = [1, 1, 0]
signal = { type = "sine", amplitude = 10.0, frequency = 60.0 }

[[sensor]]
name = "x"
body = "b"
at = [0.1, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "displacement"

[[sensor]]
name = "a"
body = "b"
at = [0.0, 0.2, 0.0]
direction = [0, 1, 0]
quantity = "acceleration"
"#;

fn fresh(model: &Model) -> (Response, Sensitivities) {
    let sim = Simulator::new(model);
    let mut out = sim.response_buffer();
    let mut sens = Sensitivities {
        wrt: vec![],
        values: vec![],
    };
    sim.run_with_sensitivities(
        &model.nominal(),
        &model.identified(),
        &mut Workspace::default(),
        &mut out,
        &mut sens,
    )
    .unwrap();
    (out, sens)
}

#[test]
fn buffers_left_over_from_another_model_do_not_matter() {
    let big = knee_column();
    let small = model(SMALL);
    let (big_out, big_sens) = fresh(&big);
    let (small_out, small_sens) = fresh(&small);

    // One set of buffers, used big → small → big → small.
    let mut ws = Workspace::default();
    let mut out = Response::zeros(0, 0);
    let mut sens = Sensitivities {
        wrt: vec![],
        values: vec![],
    };
    for (model, want_out, want_sens) in [
        (&big, &big_out, &big_sens),
        (&small, &small_out, &small_sens),
        (&big, &big_out, &big_sens),
        (&small, &small_out, &small_sens),
    ] {
        let sim = Simulator::new(model);
        sim.run_with_sensitivities(
            &model.nominal(),
            &model.identified(),
            &mut ws,
            &mut out,
            &mut sens,
        )
        .unwrap();
        assert_eq!(&out, want_out);
        assert_eq!(
            sens.values.len(),
            model.sensors.len() * model.sampling.n_samples() * model.identified().len(),
            "sensitivity matrix size"
        );
        assert_eq!(&sens, want_sens);
        sim.run(&model.nominal(), &mut ws, &mut out).unwrap();
        assert_eq!(&out, want_out);
    }
}

#[test]
fn a_failed_run_leaves_nothing_behind() {
    let small = model(SMALL);
    let (want, _) = fresh(&small);
    let sim = Simulator::new(&small);
    let mut ws = Workspace::default();
    let mut out = sim.response_buffer();
    // k = 1e14 on 1 kg at h = 5e-5 s: RK4 is far beyond its stability limit.
    assert!(sim.run(&[1.0, 1e14], &mut ws, &mut out).is_err());
    sim.run(&small.nominal(), &mut ws, &mut out).unwrap();
    assert_eq!(out, want);
}
