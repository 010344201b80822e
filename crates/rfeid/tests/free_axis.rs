//! A free axis (SPEC §1: "a direction with no component is free"): a
//! carriage on a feed axis, held by a slideway with stiff springs in y, z,
//! rx, ry, rz and, along x, by a damper only or by nothing, driven along x.
//!
//! Before, the static equilibrium's sensitivities (and so `identify` and
//! `design` under gravity) failed with "the tangent stiffness at equilibrium
//! is singular", and gravity along the free axis ended in "the model cannot
//! carry its weight; is a body unsupported?". Checked here against exact
//! answers:
//!
//! 1. The free direction found is the carriage's translation along x.
//! 2. Under gravity perpendicular to it the equilibrium exists: the carriage
//!    sinks by `m g / k_z` and does not move along x; `∂q_z/∂k_z = m g / k_z²`.
//! 3. Gravity with a component along x is an error naming the carriage, the
//!    direction and the pull `m g_x`.
//! 4. A constant force F on the free mass: `x = F t² / (2m)`, `ẍ = F / m`;
//!    with the damper c: `x(t) = (F/c)(t − (m/c)(1 − e^(−ct/m)))`, the same
//!    under gravity (the run moves about the equilibrium), and the
//!    sensitivity to c against the closed form's derivative.
//! 5. The modal analysis reports the free mode first, at zero frequency,
//!    named, and the other five modes as before.
use crate::common;

use common::*;
use rfeid::model::Model;
use rfeid::simulation::equilibrium::static_equilibrium;
use rfeid::simulation::free::{free_directions, Motion};
use rfeid::simulation::modal::{modal_analysis, rest_frequencies};
use rfeid::simulation::steps::integrator;
use rfeid::simulation::{Sensitivities, SimulationError, Simulator, Workspace};

const MASS: f64 = 50.0;
const FORCE: f64 = 30.0;
const C_X: f64 = 200.0;
const K_Z: f64 = 2.0e8;
const G: f64 = 9.81;

/// The carriage (50 kg, centre of mass (0, 0, 0.2)) on a slideway at its
/// centre of mass (so that x decouples from the rotations), with `ux` as
/// the x component (empty: none, and no parameter c_x), a constant force
/// FORCE along x at the centre of mass, and `gravity` on top when given.
fn carriage(ux: &str, gravity: Option<[f64; 3]>) -> Model {
    let top = gravity.map_or(String::new(), |g| {
        format!("gravity = [{}, {}, {}]\n", g[0], g[1], g[2])
    });
    // The damper's parameter, only where it is used.
    let c_x = match ux.contains("c_x") {
        true => {
            format!("[[parameter]]\nname = \"c_x\"\nvalue = {C_X}\nmin = 100.0\nmax = 400.0\n\n")
        }
        false => String::new(),
    };
    model(&format!(
        r#"{top}
[simulation]
duration = "0.5 s"
sample_rate = "1 kHz"

[[body]]
name = "carriage"
mass = {MASS}
inertia = [1.0, 1.5, 2.0]
com = [0.0, 0.0, 0.2]

{c_x}[[parameter]]
name = "k_y"
value = 1e8
min = 5e7
max = 2e8

[[parameter]]
name = "k_z"
value = {K_Z}

[[element]]
name = "slideway"
body = "carriage"
to = "ground"
at = [0.0, 0.0, 0.2]
{ux}
uy = {{ k = "k_y", c = 2000.0 }}
uz = {{ k = "k_z", c = 2000.0 }}
rx = {{ k = 1e6, c = 50.0 }}
ry = {{ k = 1e6, c = 50.0 }}
rz = {{ k = 1e6, c = 50.0 }}

[[excitation]]
name = "feed"
body = "carriage"
at = [0.0, 0.0, 0.2]
direction = [1, 0, 0]
signal = {{ type = "constant", amplitude = {FORCE} }}

[[sensor]]
name = "x"
body = "carriage"
at = [0.0, 0.0, 0.2]
direction = [1, 0, 0]
quantity = "displacement"

[[sensor]]
name = "ax"
body = "carriage"
at = [0.0, 0.0, 0.2]
direction = [1, 0, 0]
quantity = "acceleration"
"#
    ))
}

/// The damper-only x component.
const DAMPER: &str = r#"ux = { c = "c_x" }"#;

/// An empty sensitivities buffer.
fn no_sensitivities() -> Sensitivities {
    Sensitivities {
        wrt: Vec::new(),
        values: Vec::new(),
    }
}

/// The index of parameter `name`.
fn param(model: &Model, name: &str) -> usize {
    model
        .parameters
        .iter()
        .position(|p| p.name == name)
        .unwrap()
}

#[test]
fn the_free_direction_is_the_carriage_along_x() {
    for ux in ["", DAMPER] {
        let m = carriage(ux, None);
        let sim = Simulator::with_integrator(&m, integrator(1));
        let sys = sim.system(&m.nominal()).unwrap();
        let free = free_directions(&sys);
        assert_eq!(free.len(), 1, "ux = {ux:?}");
        let d = &free.directions[0];
        assert_eq!(d.motions.len(), 1);
        assert_eq!(d.motions[0].0, 0);
        let Motion::Translation { direction } = d.motions[0].1 else {
            panic!("{d:?}")
        };
        assert!((direction - nalgebra::Vector3::x()).norm() < 1e-15);
        assert_eq!(d.describe(&m), "carriage: free along x");
        // The shape is a unit translation of the carriage along x.
        let mut unit = vec![0.0; 6];
        unit[0] = 1.0;
        assert!(d
            .shape
            .iter()
            .zip(&unit)
            .all(|(a, b)| (a - b).abs() < 1e-15));
    }
}

#[test]
fn under_gravity_perpendicular_to_it_the_equilibrium_exists() {
    let m = carriage(DAMPER, Some([0.0, 0.0, -G]));
    let sim = Simulator::with_integrator(&m, integrator(1));
    let sys = sim.system(&m.nominal()).unwrap();
    let wrt = [param(&m, "k_z"), param(&m, "k_y"), param(&m, "c_x")];
    let eq = static_equilibrium(&sys, &wrt).expect("an equilibrium");
    let sink = -MASS * G / K_Z;
    assert_within("sink along z", (eq.q[2] - sink).abs() / sink.abs(), 1e-12);
    for i in [0, 1, 3, 4, 5] {
        assert!(eq.q[i].abs() <= 1e-12 * sink.abs(), "q[{i}] = {}", eq.q[i]);
    }
    assert_eq!(eq.iterations, 1, "a linear model takes one Newton step");
    // ∂q_z/∂k_z = m g / k_z²; nothing else moves with any parameter.
    let dz = MASS * G / (K_Z * K_Z);
    assert_within("∂q_z/∂k_z", (eq.dq[2 * 3] - dz).abs() / dz, 1e-12);
    for (i, v) in eq.dq.iter().enumerate().filter(|(i, _)| *i != 6) {
        assert!(v.abs() <= 1e-12 * dz, "dq[{i}] = {v}");
    }
    // The sensitivities a local search needs (they failed before).
    let mut out = sim.response_buffer();
    let mut sens = no_sensitivities();
    sim.run_with_sensitivities(
        &m.nominal(),
        &wrt,
        &mut Workspace::default(),
        &mut out,
        &mut sens,
    )
    .expect("a run with sensitivities under gravity");
}

#[test]
fn gravity_along_it_is_an_error_naming_the_body_and_direction() {
    // A slope of about 5.9°: g_x = −1 m/s².
    let m = carriage(DAMPER, Some([-1.0, 0.0, -9.76]));
    let sim = Simulator::with_integrator(&m, integrator(1));
    let sys = sim.system(&m.nominal()).unwrap();
    let e = static_equilibrium(&sys, &[]).unwrap_err();
    match &e {
        SimulationError::FreeUnderGravity {
            body,
            direction,
            load,
            moment,
        } => {
            assert_eq!(body, "carriage");
            assert_eq!(direction, "carriage is free along x");
            assert!((load.abs() - MASS).abs() < 1e-9, "{load}");
            assert!(!moment);
        }
        other => panic!("{other:?}"),
    }
    assert!(
        e.is_bad_values(),
        "the model's fault, not the computation's"
    );
    let text = e.to_string();
    assert!(
        text.contains("50.00 N") && text.contains("no spring"),
        "{text}"
    );
    // A run says the same.
    let run = sim.run(
        &m.nominal(),
        &mut Workspace::default(),
        &mut sim.response_buffer(),
    );
    assert_eq!(run.unwrap_err(), e);
}

#[test]
fn a_free_mass_under_a_constant_force_accelerates_uniformly() {
    let m = carriage("", None);
    let out = simulate_nominal(&m, None);
    let t = times(&m);
    let x: Vec<f64> = t.iter().map(|t| FORCE * t * t / (2.0 * MASS)).collect();
    assert_within("x = F t² / (2m)", rel_max_err(out.sensor(0), &x), 1e-12);
    let a = vec![FORCE / MASS; t.len()];
    assert_within("ẍ = F / m", rel_max_err(out.sensor(1), &a), 1e-12);
}

/// `x(t) = (F/c)(t − (m/c)(1 − e^(−ct/m)))`, the damped free mass from rest.
fn damped(c: f64, t: f64) -> f64 {
    let tau = MASS / c;
    (FORCE / c) * (t + tau * (-t / tau).exp_m1())
}

#[test]
fn a_damped_free_mass_under_a_constant_force_matches_its_closed_form() {
    for gravity in [None, Some([0.0, 0.0, -G])] {
        let m = carriage(DAMPER, gravity);
        let sim = Simulator::new(&m);
        let t = times(&m);
        let x: Vec<f64> = t.iter().map(|&t| damped(C_X, t)).collect();
        let c = param(&m, "c_x");
        let mut out = sim.response_buffer();
        let mut sens = no_sensitivities();
        let mut ws = Workspace::default();
        sim.run_with_sensitivities(&m.nominal(), &[c], &mut ws, &mut out, &mut sens)
            .unwrap();
        let what = format!("x(t) with gravity {gravity:?}");
        assert_within(&what, rel_max_err(out.sensor(0), &x), 1e-10);
        // ∂x/∂c against a central difference of the closed form (its own
        // error is about (h/c)² = 1e-8 of the derivative).
        let h = 1e-4 * C_X;
        let dx: Vec<f64> = t
            .iter()
            .map(|&t| (damped(C_X + h, t) - damped(C_X - h, t)) / (2.0 * h))
            .collect();
        let n = t.len();
        let computed: Vec<f64> = (0..n).map(|k| sens.values[k]).collect();
        assert_within("∂x/∂c", rel_max_err(&computed, &dx), 1e-7);
    }
}

#[test]
fn the_frequencies_alone_are_the_modal_analysis_ones() {
    // `rest_frequencies` (eigenvalues only, for the Nyquist check) against
    // the full modal analysis: the same frequencies, and the free mode
    // counted as free.
    for gravity in [None, Some([0.0, 0.0, -G])] {
        let m = carriage(DAMPER, gravity);
        let sim = Simulator::new(&m);
        let modal = modal_analysis(&sim, &m.nominal()).unwrap();
        let (mut alone, free) = rest_frequencies(&sim, &m.nominal()).unwrap();
        alone.sort_by(f64::total_cmp);
        let mut full: Vec<f64> = modal.modes.iter().map(|m| m.frequency_hz).collect();
        full.sort_by(f64::total_cmp);
        assert_eq!(alone.len(), full.len());
        for (a, f) in alone.iter().zip(&full) {
            assert!(
                (a - f).abs() <= 1e-12 * full[5],
                "{alone:?} against {full:?}"
            );
        }
        assert_eq!(free, 1);
    }
}

#[test]
fn the_modes_name_the_free_one() {
    for gravity in [None, Some([0.0, 0.0, -G])] {
        let m = carriage(DAMPER, gravity);
        let modal = modal_analysis(&Simulator::new(&m), &m.nominal()).unwrap();
        assert_eq!(modal.free_directions, ["carriage: free along x"]);
        let first = &modal.modes[0];
        assert_eq!(first.frequency_hz, 0.0);
        assert!(first.zero_stiffness);
        assert_eq!(first.free.as_deref(), Some("carriage: free along x"));
        // Mass-normalised: 1/√m along x.
        assert!((first.shape[0] - 1.0 / MASS.sqrt()).abs() < 1e-15);
        // The others are the restrained modes: k_z = 2e8 on 50 kg is
        // √(k/m)/2π = 318.31 Hz.
        assert!(modal.modes[1..]
            .iter()
            .all(|m| m.free.is_none() && !m.zero_stiffness));
        let z = (K_Z / MASS).sqrt() / (2.0 * std::f64::consts::PI);
        let found = modal
            .modes
            .iter()
            .any(|m| (m.frequency_hz - z).abs() < 1e-9 * z);
        assert!(
            found,
            "{:?}",
            modal
                .modes
                .iter()
                .map(|m| m.frequency_hz)
                .collect::<Vec<_>>()
        );
    }
}
