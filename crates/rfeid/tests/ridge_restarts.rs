//! Restarts only where they can help: when no end passes the fit checks
//! and the bounds at the best end already show parameters that cannot be
//! told apart, no automatic restart runs (a warning names them); without
//! such a ridge the same misfit gets its restarts.
//!
//! The model is a 10 kg body on a spring–damper to the ground along x,
//! driven by a chirp and observed by an accelerometer. The data come from
//! a body of 11 kg (model error: no stiffness or damping fits them, so every
//! end fails the checks). The ridge: the spring is split into two springs
//! in parallel, `k1a` and `k1b`, which act only as their sum.
use crate::common;

use common::model;
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{identify, Settings, Silent, DEFAULT_RESTARTS};
use rfeid::identification::warning::Warning;
use rfeid::measurement::add_noise;
use rfeid::model::Model;
use rfeid::simulation::{Response, Simulator, Workspace};

/// The body of `mass` kg on the spring(s) `springs` (element tables).
fn body(mass: f64, springs: &str, parameters: &str) -> Model {
    model(&format!(
        r#"
[simulation]
duration = 0.5
sample_rate = 1000.0

[[body]]
name = "table"
mass = {mass:e}
inertia = [0.1, 0.1, 0.1]
com = [0.0, 0.0, 0.0]
{springs}
[[excitation]]
body = "table"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = {{ type = "chirp", amplitude = 50.0, f0 = 5.0, f1 = 150.0 }}

[[sensor]]
name = "a"
body = "table"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "acceleration"

[[parameter]]
name = "c"
value = 120.0
min = 40.0
max = 400.0
{parameters}"#
    ))
}

fn spring(name: &str, k: &str, c: &str) -> String {
    format!(
        "
[[element]]
name = \"{name}\"
body = \"table\"
to = \"ground\"
at = [0.0, 0.0, 0.0]
ux = {{ k = {k}, c = {c} }}
uy = {{ k = 1e6 }}
uz = {{ k = 1e6 }}
rx = {{ k = 1e4 }}
ry = {{ k = 1e4 }}
rz = {{ k = 1e4 }}
"
    )
}

fn parameter(name: &str, value: f64, min: f64, max: f64) -> String {
    format!("\n[[parameter]]\nname = \"{name}\"\nvalue = {value:e}\nmin = {min:e}\nmax = {max:e}\n")
}

/// One spring `k` (4e5 N/m) and the damper `c`.
fn single(mass: f64) -> Model {
    body(
        mass,
        &spring("foot", "\"k\"", "\"c\""),
        &parameter("k", 4.0e5, 1.0e5, 1.0e6),
    )
}

/// Two springs `k1a` and `k1b` in parallel (2e5 N/m each) and the damper.
fn split() -> Model {
    let springs = spring("foot_a", "\"k1a\"", "\"c\"") + &spring("foot_b", "\"k1b\"", "1.0");
    let parameters = parameter("k1a", 2.0e5, 0.5e5, 5.0e5) + &parameter("k1b", 2.0e5, 0.5e5, 5.0e5);
    body(10.0, &springs, &parameters)
}

/// The 11 kg body's response with 1 % white noise.
fn data() -> Response {
    let m = single(11.0);
    let sim = Simulator::new(&m);
    let mut out = sim.response_buffer();
    sim.run(&m.nominal(), &mut Workspace::default(), &mut out)
        .expect("the truth simulates");
    add_noise(&mut out, 0.01, 5);
    out
}

fn restart_warning(m: &Model) -> Warning {
    let settings = Settings {
        plan_points: 32,
        starts: 1,
        restarts: DEFAULT_RESTARTS,
        ..Settings::default()
    };
    let problem = OutputError::new(Simulator::new(m), data(), 0);
    let r = identify(problem, &settings, &Silent).expect("identifies");
    let v = r.verdict.as_ref().expect("a verdict");
    assert!(!v.trustworthy, "a 10 kg model of an 11 kg body");
    r.warnings
        .iter()
        .find(|w| {
            matches!(
                w,
                Warning::SideMinimum { .. } | Warning::RidgeNotRestarted { .. }
            )
        })
        .cloned()
        .expect("the fit fails its checks, so the restarts stage says what it did")
}

#[test]
fn a_ridge_gets_no_restart_and_is_named() {
    match restart_warning(&split()) {
        Warning::RidgeNotRestarted { parameters, .. } => {
            assert_eq!(parameters, ["k1a", "k1b"]);
        }
        w => panic!("restarted on a ridge: {w}"),
    }
}

#[test]
fn the_same_misfit_without_a_ridge_is_restarted() {
    match restart_warning(&single(10.0)) {
        Warning::SideMinimum { restarts, .. } => assert!(restarts >= 1, "{restarts}"),
        w => panic!("no restart without a ridge: {w}"),
    }
}

/// A singular Fisher matrix (the two springs act only as their sum) is
/// reported with the parameters' names, in RESULT.json's
/// `uncertainty_error` and in the verdict's reason, not by their indices.
#[test]
fn a_singular_fisher_matrix_names_its_parameters() {
    let settings = Settings {
        plan_points: 32,
        starts: 1,
        ..Settings::default()
    };
    let m = split();
    let problem = OutputError::new(Simulator::new(&m), data(), 0);
    let r = identify(problem, &settings, &Silent).expect("identifies");
    let named = "k1a, k1b cannot be told apart";
    let e = r.uncertainty_error.as_deref().expect("no standard errors");
    assert!(e.contains(named), "{e}");
    let reasons: Vec<String> = r
        .verdict
        .as_ref()
        .expect("a verdict")
        .reasons
        .iter()
        .map(|x| x.to_string())
        .collect();
    assert!(reasons.iter().any(|x| x.contains(named)), "{reasons:?}");
}

/// The restarts run as many at a time as could all be needed (two, until
/// one of them settles the misfit as the model's best); each ends as it
/// would alone, and the ends are taken in the one-at-a-time order. So the
/// result is the same on one thread as on two, bit for bit: estimates,
/// standard errors, the simulations counted, the warnings.
#[test]
fn restarts_run_together_end_as_on_one_thread() {
    let m = single(10.0);
    let settings = Settings {
        plan_points: 32,
        starts: 1,
        restarts: DEFAULT_RESTARTS,
        ..Settings::default()
    };
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a pool");
        pool.install(|| {
            let problem = OutputError::new(Simulator::new(&m), data(), 0);
            identify(problem, &settings, &Silent).expect("identifies")
        })
    };
    let (one, two) = (on(1), on(2));
    let restarts = one.warnings.iter().find_map(|w| match w {
        Warning::SideMinimum {
            restarts, agreed, ..
        } => Some((*restarts, *agreed)),
        _ => None,
    });
    assert_eq!(restarts, Some((2, true)), "two restarts that agree");
    // Everything but the timings and the thread count.
    let result = |r: &rfeid::identification::result::IdentificationResult| {
        let mut v = serde_json::to_value(r).expect("serialises");
        let o = v.as_object_mut().expect("an object");
        o.remove("timings");
        o.remove("threads");
        v
    };
    assert_eq!(result(&one), result(&two));
    assert_eq!(one.timings.searches.len(), 3);
    assert_eq!(two.timings.searches.len(), 3);
}
