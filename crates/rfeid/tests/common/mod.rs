//! Shared helpers for the integration tests: building models from TOML text,
//! running them, closed-form reference solutions and error measures.
#![allow(dead_code)]

use rfeid::io::model_file::parse_model;
use rfeid::model::Model;
use rfeid::simulation::{Integrator, Response, Sensitivities, Simulator, Workspace};
use std::path::Path;

/// Parses model text, panicking with the error's message on failure.
pub fn model(text: &str) -> Model {
    parse_model(text, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}"))
}

/// The five-point central difference `(y(x−2h) − 8 y(x−h) + 8 y(x+h) −
/// y(x+2h)) / 12h` of the response of `sim` to parameter `p` at `x`: the
/// reference for the sensitivities (error O(h⁴)).
pub fn five_point(
    sim: &Simulator<'_>,
    ws: &mut Workspace,
    x: &[f64],
    p: usize,
    h: f64,
) -> Vec<f64> {
    let mut at = |offset: f64| {
        let mut xp = x.to_vec();
        xp[p] += offset * h;
        let mut y = sim.response_buffer();
        sim.run(&xp, ws, &mut y).unwrap();
        y.values
    };
    let (a, b, c, d) = (at(-2.0), at(-1.0), at(1.0), at(2.0));
    (0..a.len())
        .map(|i| (a[i] - 8.0 * b[i] + 8.0 * c[i] - d[i]) / (12.0 * h))
        .collect()
}

/// The sensitivities of `sim`'s response at `x` to the parameters `wrt`,
/// one column (every sample of every sensor) per parameter, and the
/// response.
pub fn sensitivity_columns(
    sim: &Simulator<'_>,
    ws: &mut Workspace,
    x: &[f64],
    wrt: &[usize],
) -> (Response, Vec<Vec<f64>>) {
    let mut out = sim.response_buffer();
    let mut sens = Sensitivities {
        wrt: vec![],
        values: vec![],
    };
    sim.run_with_sensitivities(x, wrt, ws, &mut out, &mut sens)
        .unwrap();
    let rows = out.values.len();
    let columns = (0..wrt.len())
        .map(|j| (0..rows).map(|i| sens.values[i * wrt.len() + j]).collect())
        .collect();
    (out, columns)
}

/// The largest difference between a sensitivity column and its finite
/// difference `fd`, in units of the column's RMS.
pub fn column_error(col: &[f64], fd: &[f64]) -> f64 {
    let diff: Vec<f64> = col.iter().zip(fd).map(|(s, f)| s - f).collect();
    max_abs(&diff) / rms(col)
}

/// Asserts that the sensitivity columns of the dense kernel (the first half
/// of `columns`) and the element-by-element one (the second half, in the
/// same order) agree to 1e-9 of each column's RMS.
pub fn assert_kernels_agree(what: &str, columns: &[Vec<f64>]) {
    let half = columns.len() / 2;
    for (dense, sparse) in columns[..half].iter().zip(&columns[half..]) {
        let diff: Vec<f64> = dense.iter().zip(sparse).map(|(a, b)| a - b).collect();
        assert!(
            max_abs(&diff) <= 1e-9 * rms(dense),
            "{what}: the kernels differ"
        );
    }
}

/// Simulates `model` at `params` with the integrator `integrator` (or the
/// model's own settings).
pub fn simulate(model: &Model, params: &[f64], integrator: Option<Integrator>) -> Response {
    let sim = match integrator {
        Some(i) => Simulator::with_integrator(model, i),
        None => Simulator::new(model),
    };
    let mut ws = Workspace::default();
    let mut out = sim.response_buffer();
    sim.run(params, &mut ws, &mut out)
        .unwrap_or_else(|e| panic!("simulation failed: {e}"));
    out
}

/// Simulates at the nominal parameter values.
pub fn simulate_nominal(model: &Model, integrator: Option<Integrator>) -> Response {
    simulate(model, &model.nominal(), integrator)
}

/// Sample times t_k = k / rate.
pub fn times(model: &Model) -> Vec<f64> {
    (0..model.sampling.n_samples())
        .map(|k| model.sampling.time(k))
        .collect()
}

/// Largest absolute value.
pub fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// Root mean square.
pub fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

/// Largest |a − b| divided by the largest |b|: the error relative to the
/// signal's scale.
pub fn rel_max_err(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let d = a
        .iter()
        .zip(b)
        .fold(0.0, |m, (x, y)| f64::max(m, (x - y).abs()));
    d / max_abs(b)
}

/// Asserts that `err` is within `tol` and prints it in units of the
/// tolerance (scipy's style), so that a test's margin is visible in its output.
pub fn assert_within(what: &str, err: f64, tol: f64) {
    println!(
        "{what}: error {err:.3e} = {:.3} tol (tol {tol:.1e})",
        err / tol
    );
    assert!(
        err <= tol,
        "{what}: error {err:.3e} exceeds the tolerance {tol:.1e} ({:.1} tol)",
        err / tol
    );
}

/// The exact response of `m x'' + c x' + k x = F0 sin(ω t + φ)` from rest
/// (`x(0) = x'(0) = 0`), underdamped (ζ < 1): `(x, x', x'')` at t.
///
/// Steady state `A sin(ωt + φ) + B cos(ωt + φ)` with `A = F0 (k − mω²)/D`,
/// `B = −F0 c ω / D`, `D = (k − mω²)² + (cω)²`; the transient is the free
/// response that cancels its initial displacement and velocity
/// ([`sdof_free`]); the acceleration comes from the equation itself.
pub fn sdof_forced_phase(
    m: f64,
    c: f64,
    k: f64,
    f0: f64,
    omega: f64,
    phase: f64,
    t: f64,
) -> (f64, f64, f64) {
    let d = (k - m * omega * omega).powi(2) + (c * omega).powi(2);
    let a = f0 * (k - m * omega * omega) / d;
    let b = -f0 * c * omega / d;
    let steady = |t: f64| {
        let (s, co) = (omega * t + phase).sin_cos();
        (a * s + b * co, omega * (a * co - b * s))
    };
    let (x0, v0) = steady(0.0);
    let (xs, vs) = steady(t);
    let (xh, vh, _) = sdof_free(m, c, k, -x0, -v0, t);
    let (x, v) = (xs + xh, vs + vh);
    let acc = (f0 * (omega * t + phase).sin() - c * v - k * x) / m;
    (x, v, acc)
}

/// [`sdof_forced_phase`] with zero phase.
pub fn sdof_forced(m: f64, c: f64, k: f64, f0: f64, omega: f64, t: f64) -> (f64, f64, f64) {
    sdof_forced_phase(m, c, k, f0, omega, 0.0, t)
}

/// The free response of `m x'' + c x' + k x = 0` (ζ < 1) from `x(0) = x0`,
/// `x'(0) = v0`: `e^{−σt}(C1 cos ω_d t + C2 sin ω_d t)` with `σ = ζ ω_n`,
/// `C1 = x0`, `C2 = (v0 + σ x0) / ω_d`. Returns `(x, x', x'')`.
pub fn sdof_free(m: f64, c: f64, k: f64, x0: f64, v0: f64, t: f64) -> (f64, f64, f64) {
    let wn = (k / m).sqrt();
    let zeta = c / (2.0 * m * wn);
    assert!(zeta < 1.0, "sdof_free is for underdamped oscillators");
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let sigma = zeta * wn;
    let (c1, c2) = (x0, (v0 + sigma * x0) / wd);
    let (sd, cd) = (wd * t).sin_cos();
    let e = (-sigma * t).exp();
    let x = e * (c1 * cd + c2 * sd);
    let v = e * (-sigma * (c1 * cd + c2 * sd) + wd * (-c1 * sd + c2 * cd));
    (x, v, -(c * v + k * x) / m)
}
