//! FRFs of the linearised model (`rfeid::frf`): a one-mass oscillator
//! against its closed form, exact parameter derivatives against central
//! differences (at rest and at a static equilibrium under gravity), and the
//! knee–column's FRF against the steady state of simulated small sines.
use crate::common;

use nalgebra::Complex;
use rfeid::frf::{linearise, model_frf, Output, C64};
use rfeid::io::model_file::load_model;
use rfeid::model::{Model, SensorKind};
use rfeid::simulation::{Simulator, Workspace};
use std::f64::consts::TAU;
use std::path::Path;

/// A mass m on a spring k and damper c to ground along X, the parameters
/// named `m`, `k` and `c`, read as displacement, velocity and acceleration.
fn sdof() -> Model {
    common::model(
        r#"
[simulation]
duration = 0.25
sample_rate = 2000.0

[[body]]
name = "mass"
mass = "m"
inertia = [0.1, 0.2, 0.3]
com = [0.1, 0.2, 0.3]

[[element]]
name = "spring"
body = "mass"
to = "ground"
at = [0.1, 0.2, 0.3]
ux = { k = "k", c = "c" }

[[excitation]]
body = "mass"
at = [0.1, 0.2, 0.3]
direction = [1, 0, 0]
signal = { type = "sine", amplitude = 1.0, frequency = 30.0 }

[[sensor]]
name = "x"
body = "mass"
at = [0.1, 0.2, 0.3]
direction = [1, 0, 0]
quantity = "displacement"

[[sensor]]
name = "v"
body = "mass"
at = [0.1, 0.2, 0.3]
direction = [1, 0, 0]
quantity = "velocity"

[[sensor]]
name = "a"
body = "mass"
at = [0.1, 0.2, 0.3]
direction = [1, 0, 0]
quantity = "acceleration"

[[parameter]]
name = "m"
value = 2.0
min = 1.0
max = 4.0

[[parameter]]
name = "k"
value = 2.0e5
min = 1.0e5
max = 4.0e5

[[parameter]]
name = "c"
value = 40.0
min = 20.0
max = 80.0
"#,
    )
}

/// `H = (iω)^k / (k − ω² m + iω c)` and its derivatives in m, k and c
/// (`∂H = −H² ∂Z / (iω)^k`), against the linearised model's to 1e-10.
#[test]
fn one_mass_oscillator_matches_its_closed_form() {
    let model = sdof();
    let (m, k, c) = (2.0, 2.0e5, 40.0);
    let freqs: Vec<f64> = (1..=60).map(|i| 1.7 * i as f64).collect();
    let outputs = Output::sensors(&model);
    let got = model_frf(&model, &model.nominal(), &[0, 1, 2], &outputs, &freqs).unwrap();
    for (f_i, &f) in freqs.iter().enumerate() {
        let w = TAU * f;
        let z = Complex::new(k - w * w * m, w * c);
        let g = Complex::new(1.0, 0.0) / z;
        let dz = [
            Complex::new(-w * w, 0.0),
            Complex::new(1.0, 0.0),
            Complex::new(0.0, w),
        ];
        for (s, factor) in [
            Complex::new(1.0, 0.0),
            Complex::new(0.0, w),
            Complex::new(-w * w, 0.0),
        ]
        .into_iter()
        .enumerate()
        {
            let h = factor * g;
            let pair = got.pair(0, s);
            let rel = (got.values[pair][f_i] - h).norm() / h.norm();
            assert!(rel < 1e-10, "sensor {s} at {f} Hz: relative error {rel:e}");
            for (j, dzj) in dz.iter().enumerate() {
                let want = -factor * g * g * dzj;
                let have = got.derivatives[pair][f_i * 3 + j];
                let rel = (have - want).norm() / want.norm();
                assert!(rel < 1e-10, "∂H/∂x{j}, sensor {s}, {f} Hz: {rel:e}");
            }
        }
    }
}

/// The knee–column example.
fn knee_column() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    load_model(&path).expect("example loads")
}

/// The lathe example: power-law slideways preloaded by gravity.
fn lathe() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/lathe/model.toml");
    load_model(&path).expect("example loads")
}

/// `∂H/∂x_j` of every pair at a few frequencies against the five-point
/// central difference `(H(x−2h) − 8H(x−h) + 8H(x+h) − H(x+2h)) / 12h`,
/// h = 1e-4 |x_j| (or of the box width, if larger): no integrator is
/// involved, the linearised matrices are smooth in x. Its truncation error
/// is O(h⁴) times H's fifth derivative, which for an exponent carries
/// (ln|δ|)⁵ ≈ 2e5: 1e-11 here; its rounding, that of H over h (H's solve
/// near a resonance loses digits to Z's condition; under gravity the static
/// equilibrium is solved to 1e-13 of the weights). Each error is measured
/// against the largest |∂H/∂x_j| over the frequencies; measured, the worst
/// is 2e-8 at rest and 3.2e-7 for the preloaded exponent.
fn check_derivatives(model: &Model, frequencies: &[f64]) {
    let x = model.nominal();
    let wrt: Vec<usize> = (0..x.len())
        .filter(|&i| model.parameters[i].bounds.is_some())
        .collect();
    let outputs = Output::sensors(model);
    let exact = model_frf(model, &x, &wrt, &outputs, frequencies).unwrap();
    let scale: Vec<f64> = exact.values.iter().map(|v| max_norm(v)).collect();
    let mut worst = 0.0_f64;
    for (j, &p) in wrt.iter().enumerate() {
        let (lo, hi) = model.parameters[p].bounds.unwrap();
        let size = x[p].abs().max(hi - lo);
        let h = 1e-4 * size;
        let at = |s: f64| {
            let mut xs = x.clone();
            xs[p] += s * h;
            model_frf(model, &xs, &[], &outputs, frequencies).unwrap()
        };
        let stencil = [(-2.0, 1.0), (-1.0, -8.0), (1.0, 8.0), (2.0, -1.0)];
        let runs: Vec<_> = stencil.iter().map(|(s, w)| (at(*s), *w)).collect();
        for (pair, scale) in scale.iter().enumerate() {
            // The largest |∂H/∂x_j| over the frequencies, or for a parameter
            // H barely depends on, a thousandth of |H| per its size.
            let dmax = (0..frequencies.len())
                .map(|k| exact.derivatives[pair][k * wrt.len() + j].norm())
                .fold(1e-3 * scale / size, f64::max);
            for (k, f) in frequencies.iter().enumerate() {
                let fd = runs
                    .iter()
                    .map(|(r, w)| r.values[pair][k] * *w)
                    .sum::<C64>()
                    / (12.0 * h);
                let d = exact.derivatives[pair][k * wrt.len() + j];
                let err = (d - fd).norm() / dmax;
                worst = worst.max(err);
                assert!(
                    err < 1e-6,
                    "{}: pair {pair}, {f} Hz: exact {d}, difference {fd}",
                    model.parameters[p].name,
                );
            }
        }
    }
    eprintln!("largest scaled derivative error: {worst:.2e}");
}

fn max_norm(v: &[C64]) -> f64 {
    v.iter().fold(0.0, |m, h| m.max(h.norm()))
}

#[test]
fn derivatives_at_rest_match_central_differences() {
    check_derivatives(&knee_column(), &[10.0, 22.585, 53.0, 120.0, 490.0]);
}

/// Under gravity the slideways' slopes depend on the static deformations,
/// which move with every parameter: the chain rule through `∂q₀/∂x`.
#[test]
fn derivatives_at_the_static_equilibrium_match_central_differences() {
    let model = lathe();
    assert!(
        linearise(&model, &model.nominal(), &[])
            .unwrap()
            .at_equilibrium
    );
    check_derivatives(&model, &[15.0, 60.0, 140.0, 400.0]);
}

/// Amplitude and phase of the sinusoid of frequency f in `y` (sampled at
/// `rate`) from its last `periods` whole periods, by least squares on
/// `a cos ωt + b sin ωt + c`: the complex amplitude `a − i b`.
fn steady_amplitude(y: &[f64], rate: f64, f: f64, periods: usize) -> C64 {
    let n = ((periods as f64 / f) * rate).round() as usize;
    let start = y.len() - n;
    let w = TAU * f;
    let mut ata = nalgebra::Matrix3::<f64>::zeros();
    let mut aty = nalgebra::Vector3::<f64>::zeros();
    for (k, v) in y.iter().enumerate().skip(start) {
        let t = k as f64 / rate;
        let a = nalgebra::Vector3::new((w * t).cos(), (w * t).sin(), 1.0);
        ata += a * a.transpose();
        aty += a * *v;
    }
    let s = ata.lu().solve(&aty).unwrap();
    Complex::new(s[0], -s[1])
}

/// The knee–column at rest, driven by a sine of 1e-4 N (deformations near
/// 1e-12 m, where the slideways' power laws add a stiffness a·|δ| of about
/// 1e-5 of the tangential springs'), simulated for 6 s (the slowest mode's
/// envelope decays by e^-17 by then) at 20 frequencies: the steady state's
/// amplitude and phase over its last periods against the FRF (the sine
/// `A sin ωt` has the complex amplitude −iA). Within 0.5 % in magnitude
/// and 0.5° in phase, except near antiresonances (|H| below 5 % of the
/// sensor's largest over the grid, where a small absolute error is a large
/// relative one).
#[test]
fn knee_column_frf_is_the_steady_state_of_small_sines() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml"),
    )
    .unwrap();
    let freqs: Vec<f64> = (0..20).map(|i| 12.0 * 1.2_f64.powi(i)).collect();
    let base = knee_column();
    let outputs = Output::sensors(&base);
    let frf = model_frf(&base, &base.nominal(), &[], &outputs, &freqs).unwrap();
    let amp = 1e-4;
    let mut worst = (0.0_f64, 0.0_f64);
    for (k, &f) in freqs.iter().enumerate() {
        let body = text
            .replace(r#"duration = "0.3 s""#, r#"duration = "6 s""#)
            .replace(
                r#"signal = { type = "sine", amplitude = "100 daN", frequency = "80 Hz" }"#,
                &format!(r#"signal = {{ type = "sine", amplitude = {amp:e}, frequency = {f:e} }}"#),
            );
        assert_ne!(body, text);
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column");
        let model = rfeid::io::model_file::parse_model(&body, &dir.join("model.toml")).unwrap();
        let sim = Simulator::new(&model);
        let mut out = sim.response_buffer();
        sim.run(&model.nominal(), &mut Workspace::default(), &mut out)
            .unwrap();
        for (s, output) in outputs.iter().enumerate() {
            let h = frf.values[frf.pair(0, s)][k];
            if h.norm() < 0.05 * max_norm(&frf.values[frf.pair(0, s)]) {
                continue;
            }
            let periods = (f * 0.5).ceil() as usize;
            let measured = steady_amplitude(out.sensor(s), model.sampling.sample_rate, f, periods)
                / Complex::new(0.0, -amp);
            let mag = (measured.norm() / h.norm() - 1.0).abs();
            let phase = (measured / h).arg().to_degrees().abs();
            worst = (worst.0.max(mag), worst.1.max(phase));
            assert!(
                mag < 5e-3 && phase < 0.5,
                "{} at {f:.2} Hz: magnitude off by {:.3} %, phase by {phase:.3}°",
                output.name,
                100.0 * mag
            );
        }
    }
    eprintln!(
        "worst: magnitude {:.2e} %, phase {:.2e}°",
        100.0 * worst.0,
        worst.1
    );
}

/// A point given by position and direction reads what a sensor there reads.
#[test]
fn a_point_reads_like_the_sensor_at_it() {
    let model = knee_column();
    let s = &model.sensors[0];
    let point = Output::point(
        &model,
        "p",
        s.body,
        s.at,
        3.0 * s.direction,
        SensorKind::Acceleration,
    );
    let sensors = Output::sensors(&model);
    for (a, b) in point.row.iter().zip(&sensors[0].row) {
        assert!((a - b).abs() < 1e-15);
    }
}

/// An example's model text, with `edit` applied.
fn example_with(name: &str, edit: impl Fn(String) -> String) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
        .join("model.toml");
    let text = edit(std::fs::read_to_string(&path).unwrap());
    rfeid::io::model_file::parse_model(&text, &path).unwrap()
}

/// The exponent of a preloaded power law: `∂/∂m` of its slope and of the
/// static deformations.
#[test]
fn exponent_derivatives_under_gravity_match_central_differences() {
    let model = example_with("lathe", |t| {
        t.replace("m = 1.5", r#"m = "m_exp""#)
            + "\n[[parameter]]\nname = \"m_exp\"\nvalue = 1.5\nmin = 1.2\nmax = 2.0\n"
    });
    check_derivatives(&model, &[15.0, 60.0, 140.0, 400.0]);
}

/// Friction linearised at rest is a viscous damper `F(0)/v_s`; Bouc–Wen a
/// spring `k + α`: their keys' derivatives.
#[test]
fn friction_and_hysteresis_derivatives_match_central_differences() {
    check_derivatives(&example_with("feed-axis", |t| t), &[2.0, 20.0, 80.0]);
    check_derivatives(&example_with("bouc-wen", |t| t), &[5.0, 30.0, 120.0]);
}
