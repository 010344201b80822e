//! The friction law (SPEC §1) in whole simulations: sensitivities to every
//! key against finite differences on both kernels, over a record that
//! reverses direction many times (the smooth sign's steep part at v = 0 is
//! crossed at every reversal), the limits it must reach (Coulomb plus
//! viscous friction against the closed-form steady slide), and a law the
//! model does not use changing nothing.
use crate::common;

use common::*;
use rfeid::model::Model;
use rfeid::simulation::{Kernel, Sensitivities, Simulator, Workspace};

/// A carriage on a slideway with friction along x (and a weak spring, so
/// that a sine force makes it reverse 12 times), stiff guides in the other
/// directions; every friction key, the spring, the damping and the mass are
/// parameters. {LAW} is replaced by the friction keys under test.
const MODEL: &str = r#"
[simulation]
duration = 2.0
sample_rate = 1000.0

[[body]]
name = "carriage"
mass = "m"
inertia = [0.5, 0.8, 0.8]
com = [0.0, 0.0, 0.0]

[[element]]
name = "slideway"
body = "carriage"
to = "ground"
at = [0.1, 0.05, 0.0]
ux = { law = "friction", {LAW} }
uy = { k = "2e6 N/m", c = 200.0 }
uz = { k = "3e6 N/m", c = 200.0 }
rx = { k = "2e4 N*m/rad", c = 2.0 }
ry = { k = "3e4 N*m/rad", c = 2.0 }
rz = { k = "4e4 N*m/rad", c = 2.0 }

[[excitation]]
body = "carriage"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = { type = "multisine", components = [
    { amplitude = 80.0, frequency = 3.0 },
    { amplitude = 20.0, frequency = 7.0, phase = 1.0 },
] }

[[sensor]]
name = "x"
body = "carriage"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "displacement"

[[sensor]]
name = "a"
body = "carriage"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "acceleration"
"#;

/// The parameters (name, value, min, max), each added to a model that
/// names it.
const PARAMS: [(&str, &str, &str, &str); 8] = [
    ("m", "20 kg", "10.0", "40.0"),
    ("f", "30 N", "10.0", "60.0"),
    ("f_neg", "22 N", "10.0", "60.0"),
    ("fs", "45 N", "20.0", "90.0"),
    ("vs", "4 mm/s", "1e-3", "1e-2"),
    ("smoothing", "0.5 mm/s", "1e-4", "2e-3"),
    ("k", "500 N/m", "100.0", "1000.0"),
    ("c", "40 N*s/m", "10.0", "100.0"),
];

/// The friction keys of each law variant.
const LAWS: [(&str, &str); 4] = [
    (
        "symmetric",
        r#"f = "f", smoothing = "smoothing", k = "k", c = "c""#,
    ),
    (
        "asymmetric",
        r#"f = "f", f_neg = "f_neg", smoothing = "smoothing", k = "k", c = "c""#,
    ),
    (
        "Stribeck",
        r#"f = "f", fs = "fs", vs = "vs", smoothing = "smoothing", k = "k", c = "c""#,
    ),
    (
        "asymmetric Stribeck",
        r#"f = "f", f_neg = "f_neg", fs = "fs", vs = "vs", smoothing = "smoothing", k = "k""#,
    ),
];

fn friction_model(law: &str) -> Model {
    model(&with_parameters(MODEL.replace("{LAW}", law)))
}

/// The model text with the parameters it names.
fn with_parameters(text: String) -> String {
    let mut text = text;
    for (name, value, min, max) in PARAMS {
        if text.contains(&format!("\"{name}\"")) {
            text += &format!(
                "\n[[parameter]]\nname = \"{name}\"\nvalue = \"{value}\"\nmin = {min}\nmax = {max}\n"
            );
        }
    }
    text
}

/// The parameters a model uses (a parameter nothing uses has no effect).
fn used(model: &Model) -> Vec<usize> {
    let sim = Simulator::new(model);
    (0..model.parameters.len())
        .filter(|&p| !sim.structure().usages[p].is_empty())
        .collect()
}

/// The five-point stencil's relative step for a parameter. The Coulomb
/// forces move the stick–slip transitions, so the response is strongly
/// curved in them: at 1e-3, 1e-4 and 1e-5 the stencil's error for f falls
/// as h⁴ (0.48, 6.5e-5 and 6.3e-9 of the column's RMS, measured), so they
/// take 1e-5. The smoothing velocity has the weakest effect and rounding
/// dominates below 1e-4 (2.3e-6 at 1e-5), so it takes 1e-4.
fn step(name: &str) -> f64 {
    match name {
        "smoothing" => 1e-4,
        _ => 1e-5,
    }
}

/// Sensitivities to every used parameter against the five-point stencil
/// (steps: [`step`]), each column in units of its RMS, to 1e-6 (as
/// `tests/sensitivities.rs`), on both kernels; the kernels agree to
/// rounding.
#[test]
fn sensitivities_of_every_key_match_finite_differences_on_both_kernels() {
    for (name, law) in LAWS {
        let model = friction_model(law);
        let wrt = used(&model);
        let x = model.nominal();
        let mut columns = Vec::new();
        for kernel in [Kernel::Dense, Kernel::Sparse] {
            let mut sim = Simulator::new(&model);
            sim.set_kernel(kernel);
            let mut ws = Workspace::default();
            let mut out = sim.response_buffer();
            let mut sens = Sensitivities {
                wrt: vec![],
                values: vec![],
            };
            sim.run_with_sensitivities(&x, &wrt, &mut ws, &mut out, &mut sens)
                .unwrap();
            // The record reverses many times.
            let v: Vec<f64> = out.sensor(0).windows(2).map(|w| w[1] - w[0]).collect();
            let reversals = v.windows(2).filter(|w| w[0] * w[1] < 0.0).count();
            assert!(reversals >= 10, "{name}: {reversals} reversals");
            let rows = out.values.len();
            for (j, &p) in wrt.iter().enumerate() {
                let pname = &model.parameters[p].name;
                let h = step(pname) * x[p].abs();
                let col: Vec<f64> = (0..rows).map(|i| sens.values[i * wrt.len() + j]).collect();
                let fd = five_point(&sim, &mut ws, &x, p, h);
                let diff: Vec<f64> = col.iter().zip(&fd).map(|(s, f)| s - f).collect();
                let err = max_abs(&diff) / rms(&col);
                eprintln!("{name}, {kernel:?}, {pname}: {err:.2e} of the column's RMS");
                assert!(err < 1e-6, "{name}, {kernel:?}, {pname}: {err:.2e}");
                columns.push(col);
            }
        }
        assert_kernels_agree(name, &columns);
    }
}

/// The x equation alone, `m v̇ = P(t) − k x − c v − φ(v)` with the
/// asymmetric Stribeck law, by classical RK4 at 400 steps per sample: an
/// independent reference, converged to ~1e-12 of the response (steps 100×
/// shorter than the law's fastest time scale m v_s / f_s).
fn reference_slide(p: &[f64; 8], force: impl Fn(f64) -> f64, n: usize, rate: f64) -> Vec<f64> {
    let [m, f, f_neg, fs, vs, s, k, c] = *p;
    let phi = |v: f64| {
        let t = (v / s).tanh();
        let f0 = 0.5 * (f + f_neg) + 0.5 * (f - f_neg) * t;
        let e = (-(v / vs).powi(2)).exp();
        (f0 + (fs - f0) * e) * t
    };
    let rhs = |t: f64, x: f64, v: f64| (v, (force(t) - k * x - c * v - phi(v)) / m);
    let steps = 400;
    let h = 1.0 / (rate * steps as f64);
    let (mut x, mut v) = (0.0, 0.0);
    let mut out = vec![0.0];
    for i in 0..(n - 1) * steps {
        let t = i as f64 * h;
        let (k1x, k1v) = rhs(t, x, v);
        let (k2x, k2v) = rhs(t + h / 2.0, x + h / 2.0 * k1x, v + h / 2.0 * k1v);
        let (k3x, k3v) = rhs(t + h / 2.0, x + h / 2.0 * k2x, v + h / 2.0 * k2v);
        let (k4x, k4v) = rhs(t + h, x + h * k3x, v + h * k3v);
        x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        if (i + 1) % steps == 0 {
            out.push(x);
        }
    }
    out
}

/// Stick–slip under the multisine (the carriage stops and reverses at
/// every turn, spending its time near v = 0, where the smooth sign is
/// steepest): the automatic steps keep the displacement within the default
/// tolerance's promise (10 × 1e-7 of its RMS) of the reference, on both
/// kernels. The element sits at the centre of mass, so x is uncoupled.
#[test]
fn stick_slip_matches_an_independent_reference_within_the_tolerance() {
    let text = MODEL
        .replace("{LAW}", LAWS[3].1)
        .replace("at = [0.1, 0.05, 0.0]", "at = [0.0, 0.0, 0.0]");
    let model = model(&with_parameters(text));
    let p = [20.0, 30.0, 22.0, 45.0, 4e-3, 5e-4, 500.0, 0.0];
    let force = |t: f64| {
        use std::f64::consts::PI;
        80.0 * (2.0 * PI * 3.0 * t).sin() + 20.0 * (2.0 * PI * 7.0 * t + 1.0).sin()
    };
    let reference = reference_slide(&p, force, times(&model).len(), 1000.0);
    for kernel in [Kernel::Dense, Kernel::Sparse] {
        let mut sim = Simulator::new(&model);
        sim.set_kernel(kernel);
        let mut out = sim.response_buffer();
        sim.run(&model.nominal(), &mut Workspace::default(), &mut out)
            .unwrap();
        let diff: Vec<f64> = out
            .sensor(0)
            .iter()
            .zip(&reference)
            .map(|(a, b)| a - b)
            .collect();
        let err = rms(&diff) / rms(&reference);
        eprintln!("{kernel:?}: relative RMS error {err:.2e}");
        assert_within("stick–slip against the reference", err, 1e-6);
    }
}

/// Below the Coulomb force the carriage sticks: a constant force of half of
/// f moves it only by the creep the smooth sign allows, at the speed where
/// `f tanh(v / v_s) = P`: `v = v_s atanh(1/2)`.
#[test]
fn a_force_below_the_coulomb_force_sticks() {
    let text = MODEL
        .replace("{LAW}", r#"f = "30 N", smoothing = "0.1 mm/s""#)
        .replace("at = [0.1, 0.05, 0.0]", "at = [0.0, 0.0, 0.0]")
        .replace(
            r#"signal = { type = "multisine", components = [
    { amplitude = 80.0, frequency = 3.0 },
    { amplitude = 20.0, frequency = 7.0, phase = 1.0 },
] }"#,
            r#"signal = { type = "constant", amplitude = "15 N" }"#,
        );
    let model = model(&with_parameters(text));
    let out = simulate_nominal(&model, None);
    let creep = 0.5f64.atanh() * 1e-4 * 1.999;
    let last = *out.sensor(0).last().unwrap();
    assert_within("creep", (last - creep).abs() / creep, 1e-3);
}
