//! A power-law spring with exponent m = 1 is the linear spring with k = a.
//!
//! `a · sign(δ) · |δ|¹ = a δ`, so the two models are the same equations of
//! motion. The library evaluates them differently (linear springs are folded
//! into a dense `−M⁻¹K`, power-law springs stay as rows), so the signals
//! agree to rounding, not bit for bit: 2e-14 of each signal's peak (ε ≈ 1e-16
//! per operation, a different summation order, 2000 steps; measured
//! 1e-15 to 3.4e-15, so 2e-14 keeps a margin of 6).
//! The same holds for the sensitivities to a and to k.
use crate::common;

use common::*;
use rfeid::simulation::{Sensitivities, Simulator, Workspace};

/// Two bodies on three pads, joined by an element whose normal component
/// is `joint`; the coefficient is the identified parameter "coef" and, for
/// the power law, the exponent is the parameter "expo" (fixed at 1).
fn model_text(joint: &str) -> String {
    let expo = if joint.contains("expo") {
        "[[parameter]]\nname = \"expo\"\nvalue = 1.0\n"
    } else {
        ""
    };
    format!(
        r#"
[simulation]
duration = 0.2
sample_rate = 1000.0

[[body]]
name = "base"
mass = 40.0
inertia = [1.0, 1.5, 2.0]
com = [0.0, 0.0, 0.2]

[[body]]
name = "slide"
mass = 8.0
inertia = [0.1, 0.2, 0.15]
com = [0.1, 0.3, 0.5]

[[element]]
name = "pad1"
body = "base"
to = "ground"
at = [-0.3, -0.3, 0.0]
ux = {{ k = 1e6, c = 500.0 }}
uy = {{ k = 1e6, c = 500.0 }}
uz = {{ k = 3e6, c = 900.0 }}

[[element]]
name = "pad2"
body = "base"
to = "ground"
at = [0.3, -0.3, 0.0]
ux = {{ k = 1e6, c = 500.0 }}
uy = {{ k = 1e6, c = 500.0 }}
uz = {{ k = 3e6, c = 900.0 }}

[[element]]
name = "pad3"
body = "base"
to = "ground"
at = [0.0, 0.4, 0.0]
ux = {{ k = 1e6, c = 500.0 }}
uy = {{ k = 1e6, c = 500.0 }}
uz = {{ k = 3e6, c = 900.0 }}

[[element]]
name = "joint"
body = "slide"
to = "base"
at = [0.1, 0.2, 0.45]
axes = [[0, 0.6, 0.8], [0, -0.8, 0.6], [1, 0, 0]]
ux = {joint}
uy = {{ k = 2e6, c = 300.0 }}
uz = {{ k = 2e6, c = 300.0 }}
rx = {{ k = 1e4 }}
ry = {{ k = 1e4 }}
rz = {{ k = 1e4 }}

[[parameter]]
name = "coef"
value = 5e6
min = 1e6
max = 1e7

{expo}
[[excitation]]
body = "slide"
reaction = "base"
at = [0.2, 0.3, 0.5]
direction = [1, 1, 2]
signal = {{ type = "chirp", amplitude = 500.0, f0 = 10.0, f1 = 400.0 }}

[[sensor]]
name = "acc"
body = "slide"
at = [0.0, 0.4, 0.6]
direction = [0, 1, 1]
quantity = "acceleration"

[[sensor]]
name = "disp"
body = "slide"
at = [0.1, 0.3, 0.5]
direction = [0, 0.6, 0.8]
quantity = "displacement"

[[sensor]]
name = "vel"
body = "base"
at = [0.3, 0.0, 0.3]
direction = [1, 0, 0]
quantity = "velocity"
"#
    )
}

const POWER: &str = r#"{ law = "power", a = "coef", m = "expo", c = 700.0 }"#;
const LINEAR: &str = r#"{ k = "coef", c = 700.0 }"#;

fn pair() -> (rfeid::model::Model, rfeid::model::Model) {
    (model(&model_text(POWER)), model(&model_text(LINEAR)))
}

#[test]
fn power_law_with_m_one_equals_the_linear_law() {
    let (power, linear) = pair();
    let a = simulate_nominal(&power, None);
    let b = simulate_nominal(&linear, None);
    for c in 0..a.n_sensors {
        let err = rel_max_err(a.sensor(c), b.sensor(c));
        assert_within(&format!("sensor {}", power.sensors[c].name), err, 2e-14);
    }
}

#[test]
fn sensitivity_to_a_with_m_one_equals_sensitivity_to_k() {
    let (power, linear) = pair();
    let coef = power.parameter_index("coef").unwrap();
    let sens = |m: &rfeid::model::Model| {
        let sim = Simulator::new(m);
        let mut out = sim.response_buffer();
        let mut s = Sensitivities {
            wrt: vec![],
            values: vec![],
        };
        sim.run_with_sensitivities(
            &m.nominal(),
            &[coef],
            &mut Workspace::default(),
            &mut out,
            &mut s,
        )
        .unwrap();
        s.values
    };
    let (a, b) = (sens(&power), sens(&linear));
    let n = power.sampling.n_samples();
    for c in 0..power.sensors.len() {
        let err = rel_max_err(&a[c * n..(c + 1) * n], &b[c * n..(c + 1) * n]);
        assert_within(&format!("∂{}/∂coef", power.sensors[c].name), err, 2e-14);
    }
}
