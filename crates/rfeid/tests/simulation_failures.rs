//! Simulations that cannot succeed end in a typed error, quickly, never in a
//! panic, a hang or a silently wrong number (SPEC §2: "a parameter point
//! where the simulation fails or blows up is a valid answer … never a
//! crash").
//!
//! RK4 is stable for an undamped mode while `ω h < 2√2 ≈ 2.83`. With
//! `k = 1e12` on 1 kg (ω = 1e6 rad/s) and h = 1e-4 s, `ω h = 100` and each
//! step multiplies the motion by `|P(100i)| ≈ 100⁴/24 ≈ 4e6`: the state
//! overflows within the first samples, and the run must stop there, not
//! integrate the remaining 100 s of record.
use crate::common;

use common::*;
use rfeid::model::Model;
use rfeid::simulation::{Sensitivities, SimulationError, Simulator, Workspace};

/// One body on a spring `spring` to ground along X, driven along X, with a
/// record of 100 s (10⁵ samples, 10⁶ steps).
fn oscillator(spring: &str, extra: &str) -> String {
    format!(
        r#"{extra}
[simulation]
duration = 100.0
sample_rate = 1000.0

[[body]]
name = "b"
mass = "mass"
inertia = [1.0, 1.0, 1.0]
com = [0.0, 0.0, 0.0]

[[element]]
name = "s"
body = "b"
to = "ground"
at = [0.0, 0.0, 0.0]
ux = {spring}

[[parameter]]
name = "mass"
value = 1.0
min = 0.5
max = 2.0

[[excitation]]
body = "b"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = {{ type = "sine", amplitude = 10.0, frequency = 50.0 }}

[[sensor]]
name = "x"
body = "b"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "displacement"
"#
    )
}

/// One step per sample, fixed: the steps these tests are about.
fn one_step(model: &Model) -> Simulator<'_> {
    Simulator::with_integrator(model, rfeid::simulation::steps::integrator(1))
}

fn run(model: &Model, params: &[f64]) -> Result<(), SimulationError> {
    let sim = one_step(model);
    sim.run(
        params,
        &mut Workspace::default(),
        &mut sim.response_buffer(),
    )
}

fn run_sens(model: &Model, params: &[f64]) -> Result<(), SimulationError> {
    let sim = one_step(model);
    let mut sens = Sensitivities {
        wrt: vec![],
        values: vec![],
    };
    sim.run_with_sensitivities(
        params,
        &model.identified(),
        &mut Workspace::default(),
        &mut sim.response_buffer(),
        &mut sens,
    )
}

/// The divergence is reported at the sample where it is first seen: within
/// the first 10 ms of a 100 s record.
fn assert_diverged_early(r: Result<(), SimulationError>, what: &str) {
    match r {
        Err(e @ SimulationError::Diverged { time, .. }) => {
            println!("{what}: {e}");
            // The message names the fastest mode and what to do.
            let msg = e.to_string();
            assert!(
                msg.contains("fastest mode") && msg.contains("Hz") && msg.contains("substeps"),
                "{msg}"
            );
            assert!(time <= 0.01, "{what}: detected late, at t = {time} s");
        }
        other => panic!("{what}: expected Diverged, got {other:?}"),
    }
}

#[test]
fn a_stiff_spring_with_too_few_substeps_diverges_early() {
    let model = model(&oscillator("{ k = 1e12 }", ""));
    assert_diverged_early(run(&model, &model.nominal()), "run");
    assert_diverged_early(run_sens(&model, &model.nominal()), "run with sensitivities");
}

/// Just past the stability limit (ω h = 3, |P(3i)| = 1.505) the growth is
/// slow, but the state still passes the 1e6 bound within a few dozen samples.
#[test]
fn just_past_the_stability_limit_diverges() {
    let k = (3.0e4_f64).powi(2); // ω = 3e4 rad/s, h = 1e-4 s
    let model = model(&oscillator(&format!("{{ k = {k:e} }}"), ""));
    match run(&model, &model.nominal()) {
        Err(SimulationError::Diverged { time, .. }) => {
            println!("ω h = 3: diverged at t = {time} s");
            assert!(time < 0.1);
        }
        other => panic!("expected Diverged, got {other:?}"),
    }
}

/// A power-law spring `a |δ|³` with an absurd coefficient overflows to
/// infinity and NaN: the same error.
#[test]
fn an_overflowing_power_law_diverges() {
    let model = model(&oscillator(r#"{ law = "power", a = 1e30, m = 3.0 }"#, ""));
    assert_diverged_early(run(&model, &model.nominal()), "power law");
}

#[test]
fn non_finite_parameters_are_rejected_by_name() {
    let model = model(&oscillator("{ k = 1e6 }", ""));
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for r in [run(&model, &[bad]), run_sens(&model, &[bad])] {
            match r {
                Err(SimulationError::BadParameter { name, value }) => {
                    assert_eq!(name, "mass");
                    assert!(!value.is_finite());
                }
                other => panic!("expected BadParameter, got {other:?}"),
            }
        }
    }
}

#[test]
fn a_non_positive_mass_is_rejected() {
    let model = model(&oscillator("{ k = 1e6 }", ""));
    for bad in [0.0, -1.0] {
        assert_eq!(
            run(&model, &[bad]),
            Err(SimulationError::NonPositiveInertia {
                body: "b".into(),
                value: bad
            })
        );
    }
}

#[test]
fn an_exponent_below_one_is_rejected() {
    let text = oscillator(r#"{ law = "power", a = 1e10, m = "m" }"#, "").replace(
        "[[excitation]]",
        "[[parameter]]\nname = \"m\"\nvalue = 2.0\nmin = 1.0\nmax = 3.0\n\n[[excitation]]",
    );
    let model = model(&text);
    let mut p = model.nominal();
    p[1] = 0.5;
    assert_eq!(
        run(&model, &p),
        Err(SimulationError::BadExponent {
            element: "s".into(),
            value: 0.5
        })
    );
}

/// Gravity along Z on a body held only along X: no equilibrium exists. The
/// body is free along Z (no spring there), and the error says so, with the
/// pull of its weight (1 kg: 9.81 N), before any Newton iteration.
#[test]
fn an_unsupported_body_under_gravity_has_no_equilibrium() {
    let model = model(&oscillator("{ k = 1e6 }", "gravity = [0, 0, -9.81]"));
    match run(&model, &model.nominal()) {
        Err(SimulationError::FreeUnderGravity {
            body,
            direction,
            load,
            moment,
        }) => {
            assert_eq!(body, "b");
            assert_eq!(direction, "b is free along z");
            assert!((load.abs() - 9.81).abs() < 1e-12 && !moment, "{load}");
        }
        other => panic!("expected FreeUnderGravity, got {other:?}"),
    }
}

/// [`oscillator`] with a record of 1 s (10³ samples).
fn short(spring: &str) -> String {
    oscillator(spring, "").replace("duration = 100.0", "duration = 1.0")
}

/// A response the model itself drives beyond every bound (a Bouc–Wen law
/// with β < 0 feeds energy in; a force of 10³⁰⁰ N) is said to be the
/// model's at these values, not blamed on the steps chosen for
/// `tolerance`: no smaller tolerance would help (outside test, U5). Steps
/// that are unstable stay blamed on the steps.
#[test]
fn an_unbounded_response_is_not_blamed_on_the_steps() {
    let bouc_wen =
        r#"{ law = "bouc-wen", k = 5e4, alpha = 5e4, beta = -1e3, gamma = 0.8, d = -1.1 }"#;
    let cases = [
        short(bouc_wen),
        short("{ k = 1e6 }").replace("amplitude = 10.0", "amplitude = 1e300"),
    ];
    for text in &cases {
        let model = model(text);
        match Simulator::choose(&model, &model.nominal()) {
            // Told at the first pair of step counts whose paths agree: 1
            // and 4 steps per sample for the force, 4 and 16 for the
            // Bouc–Wen law, whose 1-step run strays near the blow-up.
            Err(
                e @ SimulationError::Unbounded {
                    substeps, finer, ..
                },
            ) => {
                assert!(substeps <= 4 && finer == 4 * substeps, "{substeps} {finer}");
                let msg = e.to_string();
                println!("{msg}");
                assert!(
                    msg.contains("grows without bound at these parameter values"),
                    "{msg}"
                );
                assert!(msg.contains("will not help"), "{msg}");
                assert!(!msg.contains("takes more steps"), "{msg}");
            }
            other => panic!("expected Unbounded, got {other:?}"),
        }
    }
    // A stiff spring (10¹² N/m on 1 kg, at 1 kHz) and a stiff cubic one
    // (zero stiffness at rest) diverge for the steps' sake.
    for spring in ["{ k = 1e12 }", r#"{ law = "power", a = 1e30, m = 3.0 }"#] {
        let model = model(
            &short(spring).replace("sample_rate = 1000.0", "sample_rate = 1000.0\nsubsteps = 1"),
        );
        let e = Simulator::choose(&model, &model.nominal())
            .map(|_| ())
            .unwrap_err();
        assert!(
            matches!(e, SimulationError::Diverged { .. }),
            "{spring}: {e}"
        );
    }
}
