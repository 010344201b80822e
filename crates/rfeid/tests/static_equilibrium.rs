//! Static equilibrium under gravity against hand calculations.
//!
//! The equilibrium is solved by Newton's method to a residual of 1e-13 of the
//! largest weight (or, where larger, 64 ulps of the sum of the magnitudes of
//! the residual's terms, as in case 4), which bounds the position error by
//! about 1e-13 of the deflection times the stiffness ratios here (< 10);
//! the coordinates are checked to 1e-12 relative. Newton's last step is quadratic, so the
//! measured errors are at rounding (≤ 5e-16). The iteration counts are
//! checked too (1 for linear springs; 8 measured for power laws).
//!
//! 1. A body on four equal vertical springs, centre of mass above the
//!    middle: it sinks by `m g / (4 k)` and does not tilt.
//! 2. The lever: the centre of mass off the middle by e along X, the springs
//!    at x = ±a stiffer on one side. Each side carries its share by the lever
//!    rule, `F_R = m g (a + e) / (2a)`, `F_L = m g (a − e) / (2a)`, so its
//!    springs sink by `w = F / (2 k_side)`; the body sinks and tilts about Y
//!    to match (`φ2 = (w_L − w_R) / (2a)` with downward w).
//! 3. A power-law support `a |δ|^m` at the centre of mass: `δ = (m g / a)^(1/m)`.
//!    Its slope is zero at δ = 0, so Newton starts on a singular tangent
//!    stiffness; linearised there, the vertical mode has `k_t = m a δ^(m−1)`.
//!
//! 4. A 50-body generated machine tool at 100 points of its parameter box:
//!    its columns carry tens of bodies' weight through stiff joints, so the
//!    residual's terms are far larger than any one weight and cancel only
//!    to their own rounding. Newton must stop there and report the
//!    equilibrium (it reported "cannot carry its weight" at a residual of
//!    4.4e-10 N for 30 of these points).
//!
//! A run starts from the equilibrium and displacement sensors read from it,
//! so without excitation every reading stays at rounding level; and for
//! linear springs gravity changes nothing else (superposition).
use crate::common;
use crate::machine_tool;

use common::*;
use machine_tool::machine_tool_toml;
use rfeid::identification::plan::lp_tau_plan;
use rfeid::io::model_file::parse_model;
use rfeid::model::Model;
use rfeid::simulation::equilibrium::{static_equilibrium, Equilibrium};
use rfeid::simulation::modal::modal_analysis;
use rfeid::simulation::Simulator;
use std::f64::consts::PI;

const G: f64 = 9.81;
const MASS: f64 = 120.0;
const A: f64 = 0.4;
const B: f64 = 0.3;

const SENSORS: &str = r#"
[[sensor]]
name = "z"
body = "table"
at = [0.2, 0.1, 0.0]
direction = [0, 0, 1]
quantity = "displacement"

[[sensor]]
name = "a"
body = "table"
at = [0.2, 0.1, 0.0]
direction = [0, 0.6, 0.8]
quantity = "acceleration"
"#;

/// A body (centre of mass at (e, 0, 0)) on springs at (±A, ±B, 0) with
/// vertical stiffness `k_right` at x = +A and `k_left` at x = −A, and
/// lateral stiffness `lateral` (none when 0).
fn on_springs(e: f64, k_right: f64, k_left: f64, lateral: f64, excitation: &str) -> String {
    let mut s = format!(
        r#"gravity = [0, 0, -{G:e}]

[simulation]
duration = 0.2
sample_rate = 1000.0

[[body]]
name = "table"
mass = {MASS:e}
inertia = [4.0, 5.0, 7.0]
com = [{e:e}, 0.0, 0.0]
{SENSORS}{excitation}"#
    );
    for (i, (x, y)) in [(A, B), (-A, B), (-A, -B), (A, -B)].iter().enumerate() {
        let k = if *x > 0.0 { k_right } else { k_left };
        let lat = if lateral > 0.0 {
            format!("ux = {{ k = {lateral:e} }}\nuy = {{ k = {lateral:e} }}\n")
        } else {
            String::new()
        };
        s += &format!(
            "\n[[element]]\nname = \"spring{i}\"\nbody = \"table\"\nto = \"ground\"\nat = [{x:e}, {y:e}, 0.0]\n{lat}uz = {{ k = {k:e}, c = 2000.0 }}\n"
        );
    }
    s
}

fn equilibrium(model: &Model) -> Equilibrium {
    let sim = Simulator::new(model);
    let sys = sim.system(&model.nominal()).unwrap();
    static_equilibrium(&sys, &[]).unwrap()
}

/// Largest |q − expected| relative to the largest |expected|.
fn q_error(q: &[f64], expected: [f64; 6]) -> f64 {
    rel_max_err(q, &expected)
}

#[test]
fn symmetric_springs_sink_by_mg_over_4k() {
    let k = 2.0e6;
    let model = model(&on_springs(0.0, k, k, 1.0e6, ""));
    let eq = equilibrium(&model);
    let expected = [0.0, 0.0, -MASS * G / (4.0 * k), 0.0, 0.0, 0.0];
    assert_within("q", q_error(&eq.q, expected), 1e-12);
    println!("Newton iterations: {}", eq.iterations);
    // A linear problem: one Newton step solves it.
    assert_eq!(eq.iterations, 1);
}

#[test]
fn the_lever_rule_gives_sink_and_tilt() {
    let (e, kr, kl) = (0.1, 3.0e6, 1.2e6);
    let model = model(&on_springs(e, kr, kl, 1.0e6, ""));
    let eq = equilibrium(&model);
    let f_right = MASS * G * (A + e) / (2.0 * A);
    let f_left = MASS * G * (A - e) / (2.0 * A);
    let (w_right, w_left) = (-f_right / (2.0 * kr), -f_left / (2.0 * kl));
    let phi2 = (w_left - w_right) / (2.0 * A);
    let u3 = w_right + phi2 * (A - e);
    let expected = [0.0, 0.0, u3, 0.0, phi2, 0.0];
    println!("u3 = {u3:e} m, φ2 = {phi2:e} rad");
    // φ2 · (lever arm ~0.4 m) and u3 are of similar size, so one relative
    // measure covers both.
    assert_within("q", q_error(&eq.q, expected), 1e-12);
    assert_eq!(eq.iterations, 1);
}

/// With only vertical springs, three DOF (x, y, rotation about Z) are not
/// restrained at all. Gravity does not load them, so the equilibrium is
/// still well defined (they stay at zero); the tangent stiffness is singular.
#[test]
fn free_lateral_dof_do_not_prevent_the_equilibrium() {
    let (e, kr, kl) = (0.1, 3.0e6, 1.2e6);
    let model = model(&on_springs(e, kr, kl, 0.0, ""));
    let eq = equilibrium(&model);
    let f_right = MASS * G * (A + e) / (2.0 * A);
    let f_left = MASS * G * (A - e) / (2.0 * A);
    let (w_right, w_left) = (-f_right / (2.0 * kr), -f_left / (2.0 * kl));
    let phi2 = (w_left - w_right) / (2.0 * A);
    let u3 = w_right + phi2 * (A - e);
    assert_within("q", q_error(&eq.q, [0.0, 0.0, u3, 0.0, phi2, 0.0]), 1e-12);
    println!("Newton iterations: {}", eq.iterations);
    // Two measured: the singular tangent is regularised once.
    assert!(eq.iterations <= 3, "{} iterations", eq.iterations);
}

/// A run from the equilibrium with no excitation stays there: the residual
/// left by Newton (≤ 1e-13 of the weight) moves the body by at most about
/// 1e-13 of its static deflection, and accelerates it by 1e-13 g.
#[test]
fn a_run_without_excitation_stays_at_equilibrium() {
    let model = model(&on_springs(0.1, 3.0e6, 1.2e6, 1.0e6, ""));
    let deflection = equilibrium(&model).q[2].abs();
    let out = simulate_nominal(&model, None);
    assert_within(
        "displacement / static deflection",
        max_abs(out.sensor(0)) / deflection,
        1e-12,
    );
    assert_within("acceleration / g", max_abs(out.sensor(1)) / G, 1e-12);
}

/// Linear springs: the response to a force, measured from the equilibrium,
/// is the same with or without gravity (to rounding: the state carries the
/// static offset, ~1e-5 m, while the dynamic part is ~1e-6 m, so a few ulps
/// of the offset are 1e-14 of the signal; tolerance 1e-12).
#[test]
fn gravity_does_not_change_the_linear_response_about_equilibrium() {
    let excitation = r#"
[[excitation]]
body = "table"
at = [0.3, -0.2, 0.1]
direction = [0.2, 0.1, 1.0]
signal = { type = "sine", amplitude = 800.0, frequency = 35.0 }
"#;
    let with = model(&on_springs(0.1, 3.0e6, 1.2e6, 1.0e6, excitation));
    let without =
        model(&on_springs(0.1, 3.0e6, 1.2e6, 1.0e6, excitation).replace("gravity", "# gravity"));
    assert!(without.gravity.is_none());
    let (a, b) = (
        simulate_nominal(&with, None),
        simulate_nominal(&without, None),
    );
    for c in 0..a.n_sensors {
        assert_within(
            &format!("sensor {c}"),
            rel_max_err(a.sensor(c), b.sensor(c)),
            1e-12,
        );
    }
}

/// A body on one power-law support at its centre of mass (and linear
/// springs for the other five DOF).
fn on_power_support(a: f64, m: f64) -> String {
    format!(
        r#"gravity = [0, 0, -{G:e}]

[simulation]
duration = 0.1
sample_rate = 1000.0

[[body]]
name = "table"
mass = {MASS:e}
inertia = [4.0, 5.0, 7.0]
com = [0.0, 0.0, 0.0]

[[element]]
name = "support"
body = "table"
to = "ground"
at = [0.0, 0.0, 0.0]
ux = {{ k = 1e6 }}
uy = {{ k = 1e6 }}
uz = {{ law = "power", a = {a:e}, m = {m:e}, c = 100.0 }}
rx = {{ k = 1e5 }}
ry = {{ k = 1e5 }}
rz = {{ k = 1e5 }}
{SENSORS}"#
    )
}

#[test]
fn power_law_support_sinks_by_the_root_of_mg_over_a() {
    for (a, m) in [(4.0e12, 2.0), (3.0e10, 1.5), (5.0e6, 1.0), (1.0e18, 3.0)] {
        let model = model(&on_power_support(a, m));
        let eq = equilibrium(&model);
        let delta = (MASS * G / a).powf(1.0 / m);
        let err = q_error(&eq.q, [0.0, 0.0, -delta, 0.0, 0.0, 0.0]);
        println!(
            "m = {m}: δ = {delta:e} m in {} Newton iterations",
            eq.iterations
        );
        assert_within(&format!("m = {m}: q"), err, 1e-12);
        // Newton from a singular start: 8 steps measured for m > 1 (1 for m = 1).
        assert!(eq.iterations <= 10, "{} iterations", eq.iterations);

        // Linearised at the equilibrium: k_t = m a δ^(m−1) = m · m g / δ.
        let ma = modal_analysis(&Simulator::new(&model), &model.nominal()).unwrap();
        assert!(ma.at_equilibrium);
        assert!(ma.zero_slope_components.is_empty());
        let kt = m * a * delta.powf(m - 1.0);
        let f = (kt / MASS).sqrt() / (2.0 * PI);
        let vertical = ma
            .modes
            .iter()
            .max_by(|x, y| x.shape[2].abs().total_cmp(&y.shape[2].abs()))
            .unwrap();
        let ef = (vertical.frequency_hz - f).abs() / f;
        assert_within(&format!("m = {m}: vertical frequency {f:.2} Hz"), ef, 1e-12);

        // And the run stays at the equilibrium.
        let out = simulate_nominal(&model, None);
        assert_within(
            &format!("m = {m}: displacement / δ"),
            max_abs(out.sensor(0)) / delta,
            1e-12,
        );
    }
}

/// A stack of `n` bodies (listed out of order, so that the solver's
/// ordering has work to do), each on the one below through a power-law
/// support at the common centre of mass, the lowest on the ground; the top
/// one is "table".
fn power_stack(n: usize, a: f64, m: f64) -> String {
    let name = |i: usize| match i {
        0 => "ground".to_string(),
        i if i == n => "table".to_string(),
        i => format!("b{i}"),
    };
    let mut s = format!(
        "gravity = [0, 0, -{G:e}]\n\n[simulation]\nduration = 0.1\nsample_rate = 1000.0\n{SENSORS}"
    );
    for i in (1..=n).map(|k| (k * 5) % n + 1) {
        s += &format!(
            "\n[[body]]\nname = \"{}\"\nmass = {MASS:e}\ninertia = [4.0, 5.0, 7.0]\ncom = [0.0, 0.0, 0.0]\n",
            name(i)
        );
    }
    for i in 1..=n {
        s += &format!(
            "\n[[element]]\nname = \"support{i}\"\nbody = \"{}\"\nto = \"{}\"\nat = [0.0, 0.0, 0.0]\n\
             ux = {{ k = 1e6 }}\nuy = {{ k = 1e6 }}\nuz = {{ law = \"power\", a = {a:e}, m = {m:e}, c = 100.0 }}\n\
             rx = {{ k = 1e5 }}\nry = {{ k = 1e5 }}\nrz = {{ k = 1e5 }}\n",
            name(i),
            name(i - 1)
        );
    }
    s
}

/// Seven bodies (42 coordinates: the large-model factorisation of the
/// tangent stiffness, `simulation::envelope`): support i carries the
/// bodies above it, `(n − i + 1) M g = a δ_i^m`, and body i sinks by
/// `Σ_{j ≤ i} δ_j`.
#[test]
fn a_stack_of_power_law_supports_sinks_support_by_support() {
    let (n, a, m) = (7, 4.0e12, 1.5);
    let model = model(&power_stack(n, a, m));
    let eq = equilibrium(&model);
    let mut sink = 0.0;
    let mut expected = vec![0.0; 6 * n];
    for i in 1..=n {
        sink += ((n - i + 1) as f64 * MASS * G / a).powf(1.0 / m);
        let name = if i == n {
            "table".into()
        } else {
            format!("b{i}")
        };
        let body = model.bodies.iter().position(|b| b.name == name).unwrap();
        expected[6 * body + 2] = -sink;
    }
    let err = rel_max_err(&eq.q, &expected);
    println!(
        "stack of {n}: top sinks {sink:e} m, error {err:.2e}, {} Newton iterations",
        eq.iterations
    );
    assert_within("q", err, 1e-12);
}

/// Case 4: every point of a plan over a 50-body machine tool's box has an
/// equilibrium, found where the residual is zero to the rounding of its
/// terms.
#[test]
fn a_long_stiff_chain_balances_at_every_plan_point() {
    let text = machine_tool_toml(50, 64);
    let model = parse_model(&text, std::path::Path::new("m50.toml")).expect("model");
    let sim = Simulator::new(&model);
    let wrt = model.identified();
    let plan = lp_tau_plan(wrt.len(), 100).expect("plan");
    let mut failures = Vec::new();
    for k in 0..plan.len() {
        let mut x = model.nominal();
        for (&p, u) in wrt.iter().zip(plan.point(k)) {
            let (lo, hi) = model.parameters[p].bounds.expect("box");
            x[p] = lo + u * (hi - lo);
        }
        let sys = sim.system(&x).expect("system");
        if let Err(e) = static_equilibrium(&sys, &[]) {
            failures.push(format!("point {k}: {e}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
