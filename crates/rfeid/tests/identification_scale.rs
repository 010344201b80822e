//! Parameter scales: the model file's `scale` and its default, the map
//! between a wide box and the normalised coordinate, and what must not
//! depend on the choice: J at a physical point, the Cramér–Rao standard
//! errors at a physical point, and the estimate itself.
use crate::common;

use common::model;
use nalgebra::DMatrix;
use rfeid::identification::box_map::BoxMap;
use rfeid::identification::lm::LmSettings;
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{identify, Settings, Silent};
use rfeid::identification::problem::{sum_of_squares, LeastSquares};
use rfeid::identification::uncertainty::{cramer_rao_mapped, UncertaintySettings};
use rfeid::io::model_file::parse_model;
use rfeid::measurement::add_noise;
use rfeid::model::{Model, Scale};
use rfeid::simulation::{Response, Simulator, Workspace};
use std::path::Path;

/// A two-body chain (as in the verdict tests) with k1 in a box two decades
/// wide and c1 in one decade; `scales` is inserted into both parameters
/// (e.g. `scale = "log"`), or nothing for the default.
fn chain(k1_scale: &str, c1_scale: &str) -> String {
    format!(
        r#"
[simulation]
duration = 0.5
sample_rate = 1000.0

[[body]]
name = "base"
mass = 10.0
inertia = [0.1, 0.1, 0.1]
com = [0.0, 0.0, 0.0]

[[body]]
name = "slide"
mass = 5.0
inertia = [0.05, 0.05, 0.05]
com = [0.0, 0.0, 0.0]

[[element]]
name = "foot"
body = "base"
to = "ground"
at = [0.0, 0.0, 0.0]
ux = {{ k = "k1", c = "c1" }}

[[element]]
name = "guide"
body = "slide"
to = "base"
at = [0.0, 0.0, 0.0]
ux = {{ k = 2.5e5, c = 60.0 }}

[[excitation]]
body = "slide"
reaction = "base"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = {{ type = "chirp", amplitude = 50.0, f0 = 5.0, f1 = 150.0 }}

[[sensor]]
name = "base_a"
body = "base"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "acceleration"

[[sensor]]
name = "slide_a"
body = "slide"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "acceleration"

[[parameter]]
name = "k1"
value = 4.0e5
min = 1.0e4
max = 1.0e6
{k1_scale}

[[parameter]]
name = "c1"
value = 120.0
min = 30.0
max = 300.0
{c1_scale}
"#
    )
}

fn data(m: &Model, seed: u64) -> Response {
    let sim = Simulator::new(m);
    let mut out = sim.response_buffer();
    sim.run(&m.nominal(), &mut Workspace::default(), &mut out)
        .expect("simulates");
    add_noise(&mut out, 0.01, seed);
    out
}

#[test]
fn boxes_a_decade_wide_or_more_default_to_log() {
    let m = model(&chain("", ""));
    let scale = |name: &str| m.parameters[m.parameter_index(name).unwrap()].scale;
    assert_eq!(scale("k1"), Scale::Log, "max/min = 100");
    assert_eq!(scale("c1"), Scale::Log, "max/min = 10 exactly");
    let m = model(&chain(r#"scale = "linear""#, ""));
    assert_eq!(
        m.parameters[m.parameter_index("k1").unwrap()].scale,
        Scale::Linear
    );
    assert_eq!(Scale::default_for(1.0, 9.99), Scale::Linear);
    assert_eq!(Scale::default_for(-1.0, 100.0), Scale::Linear);
    assert_eq!(Scale::default_for(0.0, 100.0), Scale::Linear);
}

#[test]
fn a_bad_scale_names_the_parameter_and_the_field() {
    let cases = [
        (chain(r#"scale = "decibel""#, ""), "unknown scale 'decibel'"),
        (
            chain("", r#"scale = "log""#).replace("min = 30.0", "min = 0.0"),
            "a log scale needs min > 0",
        ),
    ];
    for (text, message) in cases {
        let e = parse_model(&text, Path::new("m.toml")).expect_err("refused");
        assert_eq!(e.field, "scale", "{}", e.message);
        assert!(e.entry.starts_with("parameter"), "{}", e.entry);
        assert!(e.message.contains(message), "{}", e.message);
        assert!(e.span.is_some());
    }
    // A scale on a fixed parameter means nothing: refused.
    let text = chain("", "").replace(
        "ux = { k = 2.5e5, c = 60.0 }",
        "ux = { k = \"k2\", c = 60.0 }",
    ) + "\n[[parameter]]\nname = \"k2\"\nvalue = 2.5e5\nscale = \"log\"\n";
    let e = parse_model(&text, Path::new("m.toml")).expect_err("refused");
    assert_eq!(
        (e.field.as_str(), e.entry.as_str()),
        ("scale", "parameter \"k2\"")
    );
}

#[test]
fn a_wide_log_box_round_trips() {
    let m = BoxMap::new(1e-3, 1e9, Scale::Log);
    for k in 0..=1000 {
        let u = k as f64 / 1000.0;
        let x = m.to_physical(u);
        assert!((1e-3..=1e9).contains(&x));
        assert!((m.to_normalised(x) - u).abs() < 4e-15, "u = {u}");
    }
    for e in -3..=9 {
        let x = 10f64.powi(e);
        let back = m.to_physical(m.to_normalised(x));
        assert!((back / x - 1.0).abs() < 1e-13, "x = {x:e}: {back:e}");
    }
    // Equal steps in u are equal ratios: 12 decades over [0, 1].
    assert!((m.to_physical(0.25) / 1e0 - 1.0).abs() < 1e-13);
}

/// The problem of `text` evaluated at the physical point `x`: (J, Jacobian
/// in u, dx/du).
fn at(text: &str, measured: &Response, x: &[f64]) -> (f64, DMatrix<f64>, Vec<f64>) {
    let m = model(text);
    let p = OutputError::new(Simulator::new(&m), measured.clone(), 0);
    let u = p.to_normalised(x);
    let mut ws = p.workspace();
    let mut r = vec![0.0; p.n_residuals()];
    let mut jac = DMatrix::zeros(p.n_residuals(), p.n_params());
    p.residuals_jacobian(&mut ws, &u, &mut r, &mut jac)
        .expect("simulates");
    (sum_of_squares(&r), jac, p.dx_du(&u))
}

#[test]
fn j_and_the_standard_errors_at_a_point_do_not_depend_on_the_scale() {
    let truth = model(&chain("", ""));
    let measured = data(&truth, 1);
    let x = [3.1e5, 95.0];
    let (j_log, jac_log, d_log) = at(&chain("", ""), &measured, &x);
    let (j_lin, jac_lin, d_lin) = at(
        &chain(r#"scale = "linear""#, r#"scale = "linear""#),
        &measured,
        &x,
    );
    // The same physical point up to the round trip of x through u.
    assert!((j_log / j_lin - 1.0).abs() < 1e-11, "{j_log} vs {j_lin}");
    // The Jacobians differ by the chain-rule factors only.
    for j in 0..2 {
        let ratio = d_log[j] / d_lin[j];
        for i in (0..jac_log.nrows()).step_by(37) {
            let (a, b) = (jac_log[(i, j)], jac_lin[(i, j)] * ratio);
            assert!(
                (a - b).abs() <= 1e-9 * b.abs().max(1e-300) + 1e-30,
                "({i}, {j})"
            );
        }
    }
    let widths = [1.0e6 - 1.0e4, 300.0 - 30.0];
    let s = UncertaintySettings::default();
    let cr_log = cramer_rao_mapped(&jac_log, j_log, &d_log, &widths, &s).expect("regular");
    let cr_lin = cramer_rao_mapped(&jac_lin, j_lin, &d_lin, &widths, &s).expect("regular");
    for j in 0..2 {
        let (a, b) = (cr_log.std_errors[j], cr_lin.std_errors[j]);
        assert!(
            (a / b - 1.0).abs() < 1e-9,
            "standard error {j}: {a:e} vs {b:e}"
        );
    }
    assert!((cr_log.correlation[(0, 1)] - cr_lin.correlation[(0, 1)]).abs() < 1e-9);
}

#[test]
fn the_log_jacobian_matches_central_differences_in_u() {
    let truth = model(&chain("", ""));
    let measured = data(&truth, 2);
    let p = OutputError::new(Simulator::new(&truth), measured, 0);
    let u = [0.41, 0.63];
    let mut ws = p.workspace();
    let n = p.n_residuals();
    let (mut r, mut rp, mut rm) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut jac = DMatrix::zeros(n, 2);
    p.residuals_jacobian(&mut ws, &u, &mut r, &mut jac)
        .expect("simulates");
    for j in 0..2 {
        let h = 1e-6;
        let (mut up, mut um) = (u, u);
        up[j] += h;
        um[j] -= h;
        p.residuals(&mut ws, &up, &mut rp).expect("simulates");
        p.residuals(&mut ws, &um, &mut rm).expect("simulates");
        let scale = jac.column(j).norm();
        let err = (0..n)
            .map(|i| ((rp[i] - rm[i]) / (2.0 * h) - jac[(i, j)]).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-5 * scale, "column {j}: {err:e} of {scale:e}");
    }
}

#[test]
fn the_estimate_and_its_standard_errors_do_not_depend_on_the_scale() {
    let truth = model(&chain("", ""));
    let measured = data(&truth, 3);
    // Both searches polished to the other tolerances, so that the minima
    // themselves are compared: the default stops within 0.22 standard
    // errors of the minimum (`LmSettings::with_decrement_tolerance`).
    let settings = Settings {
        plan_points: 32,
        starts: 2,
        lm: LmSettings::default()
            .with_decrement_tolerance(f64::MIN_POSITIVE)
            .unwrap(),
        ..Settings::default()
    };
    let run = |text: &str| {
        let m = model(text);
        identify(
            OutputError::new(Simulator::new(&m), measured.clone(), 0),
            &settings,
            &Silent,
        )
        .expect("identifies")
    };
    let log = run(&chain("", ""));
    let lin = run(&chain(r#"scale = "linear""#, r#"scale = "linear""#));
    assert_eq!(log.parameters[0].scale, Scale::Log);
    assert_eq!(lin.parameters[0].scale, Scale::Linear);
    for (a, b) in log.parameters.iter().zip(&lin.parameters) {
        let se = a.std_error.expect("bounds");
        // The same minimum, to far below its standard error.
        assert!(
            (a.estimate - b.estimate).abs() < 1e-4 * se,
            "{}: {} vs {} (s.e. {se:e})",
            a.name,
            a.estimate,
            b.estimate
        );
        let rel = (se / b.std_error.expect("bounds") - 1.0).abs();
        assert!(rel < 1e-4, "{}: standard errors differ by {rel:e}", a.name);
        // Within 3 standard errors of the truth.
        assert!((a.estimate - a.nominal).abs() < 3.0 * se, "{}", a.name);
    }
    assert!((log.criterion / lin.criterion - 1.0).abs() < 1e-9);
    // RESULT.json states the scale.
    let json = serde_json::to_value(&log).expect("serialises");
    assert_eq!(json["parameters"][0]["scale"], "log");
}
