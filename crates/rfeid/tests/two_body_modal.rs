//! A two-body chain, ground – k1 – body 1 – k2 – body 2, against modal
//! superposition.
//!
//! Motion is along global X only: the bodies' centres and the elements lie on
//! the X axis, so no element or force has a moment arm, and the other ten
//! DOF stay exactly zero. Body 2's principal axes are a permutation of the
//! global ones (its X motion is its own u3), which checks the frame
//! bookkeeping. Damping is stiffness-proportional, `c_i = β k_i`, so
//! `C = β K` and the modes decouple exactly: each modal coordinate obeys
//! `η'' + β ω_i² η' + ω_i² η = φ_iᵀ F sin ωt` (mass-normalised φ_i), solved
//! in closed form by `common::sdof_forced`. The eigenproblem is solved here,
//! independently of the library, with nalgebra.
//!
//! Tolerances: DOP853 with 10 steps per sample is at rounding level
//! (see `sdof_closed_form.rs`), checked to 1e-12 of each signal's peak.
//! The default RK4 is held to its a-priori phase-error bound
//! `ω t (ω h)⁴ / 120` for the faster mode (ω₂ = 473 rad/s, h = 5e-5 s,
//! t = 0.25 s: 3.1e-7). It does better (7e-9) because the response is
//! mostly the forced motion at 45 Hz, not the free modes whose phase drifts.
use crate::common;

use common::*;
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use rfeid::simulation::modal::modal_analysis;
use rfeid::simulation::tableau::DOP853;
use rfeid::simulation::{Integrator, Simulator};
use std::f64::consts::PI;

const M1: f64 = 3.0;
const M2: f64 = 1.5;
const K1: f64 = 4.0e5;
const K2: f64 = 1.5e5;
const BETA: f64 = 1.0e-4;
const F0: f64 = 250.0;
const FREQ: f64 = 45.0;

/// The chain, driven on body 2 alone or, with `reaction`, by an exciter
/// between body 2 and body 1 (the force on body 2, its opposite on body 1).
fn chain_with(reaction: bool) -> String {
    let (c1, c2) = (BETA * K1, BETA * K2);
    let reaction = if reaction { "reaction = \"b1\"\n" } else { "" };
    format!(
        r#"
[simulation]
duration = 0.25
sample_rate = 2000.0

[[body]]
name = "b1"
mass = {M1:e}
inertia = [0.2, 0.3, 0.4]
com = [0.0, 0.0, 0.0]

[[body]]
name = "b2"
mass = {M2:e}
inertia = [0.05, 0.06, 0.07]
com = [1.0, 0.0, 0.0]
axes = [[0, 1, 0], [0, 0, 1], [1, 0, 0]]

[[element]]
name = "k1"
body = "b1"
to = "ground"
at = [-0.5, 0.0, 0.0]
ux = {{ k = {K1:e}, c = {c1:e} }}

[[element]]
name = "k2"
body = "b2"
to = "b1"
at = [0.5, 0.0, 0.0]
ux = {{ k = {K2:e}, c = {c2:e} }}

[[excitation]]
body = "b2"
{reaction}at = [1.3, 0.0, 0.0]
direction = [1, 0, 0]
signal = {{ type = "sine", amplitude = {F0:e}, frequency = {FREQ:e} }}

[[sensor]]
name = "x1"
body = "b1"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "displacement"

[[sensor]]
name = "x2"
body = "b2"
at = [1.7, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "displacement"

[[sensor]]
name = "v2"
body = "b2"
at = [1.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "velocity"

[[sensor]]
name = "a1"
body = "b1"
at = [0.2, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "acceleration"

[[sensor]]
name = "a2"
body = "b2"
at = [1.0, 0.0, 0.0]
direction = [-1, 0, 0]
quantity = "acceleration"
"#
    )
}

fn chain() -> String {
    chain_with(false)
}

/// Natural frequencies (rad/s) and mass-normalised shapes `[φ_1, φ_2]`
/// (columns) of `K φ = ω² M φ`, by increasing frequency.
fn modes() -> (Vec<f64>, DMatrix<f64>) {
    let k = DMatrix::from_row_slice(2, 2, &[K1 + K2, -K2, -K2, K2]);
    let s = DVector::from_vec(vec![1.0 / M1.sqrt(), 1.0 / M2.sqrt()]);
    let a = DMatrix::from_fn(2, 2, |i, j| s[i] * k[(i, j)] * s[j]);
    let eig = SymmetricEigen::new(a);
    let mut idx = [0, 1];
    idx.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let omega = idx.iter().map(|&i| eig.eigenvalues[i].sqrt()).collect();
    let phi = DMatrix::from_fn(2, 2, |r, c| s[r] * eig.eigenvectors[(r, idx[c])]);
    (omega, phi)
}

/// The exact sensor signals by modal superposition for the force amplitudes
/// `load` on bodies 1 and 2, sensor-major like `Response::values`.
fn exact(t: &[f64], load: [f64; 2]) -> Vec<Vec<f64>> {
    let (omega, phi) = modes();
    let w = 2.0 * PI * FREQ;
    let mut x = vec![[[0.0; 3]; 2]; t.len()]; // [sample][dof][x, v, a]
    for i in 0..2 {
        let f = phi[(0, i)] * load[0] + phi[(1, i)] * load[1]; // modal force φ_iᵀ P
        for (k, &tk) in t.iter().enumerate() {
            let (e, de, dde) = sdof_forced(
                1.0,
                BETA * omega[i] * omega[i],
                omega[i] * omega[i],
                f,
                w,
                tk,
            );
            for dof in 0..2 {
                x[k][dof][0] += phi[(dof, i)] * e;
                x[k][dof][1] += phi[(dof, i)] * de;
                x[k][dof][2] += phi[(dof, i)] * dde;
            }
        }
    }
    let col = |dof: usize, what: usize, sign: f64| x.iter().map(|s| sign * s[dof][what]).collect();
    vec![
        col(0, 0, 1.0),
        col(1, 0, 1.0),
        col(1, 1, 1.0),
        col(0, 2, 1.0),
        col(1, 2, -1.0),
    ]
}

fn check(integrator: Integrator, tol: f64) {
    check_case(false, integrator, tol);
}

fn check_case(reaction: bool, integrator: Integrator, tol: f64) {
    let model = model(&chain_with(reaction));
    let out = simulate_nominal(&model, Some(integrator));
    let load = if reaction { [-F0, F0] } else { [0.0, F0] };
    let reference = exact(&times(&model), load);
    for (c, r) in reference.iter().enumerate() {
        let name = &model.sensors[c].name;
        let err = rel_max_err(out.sensor(c), r);
        assert_within(
            &format!(
                "{name}, {}×{}",
                integrator.tableau.name, integrator.substeps
            ),
            err,
            tol,
        );
    }
}

#[test]
fn chain_matches_modal_superposition_to_rounding_with_dop853() {
    check(
        Integrator {
            tableau: DOP853,
            substeps: 10,
            locate_crossings: true,
        },
        1e-12,
    );
}

/// An exciter between the bodies (as in the knee–column benchmark) pushes
/// them apart: load `[−F0, F0]`.
#[test]
fn exciter_between_the_bodies_matches_modal_superposition() {
    check_case(
        true,
        Integrator {
            tableau: DOP853,
            substeps: 10,
            locate_crossings: true,
        },
        1e-12,
    );
}

#[test]
fn chain_matches_modal_superposition_with_default_rk4() {
    let model = model(&chain());
    let integrator = Simulator::new(&model).integrator();
    let h = 1.0 / (model.sampling.sample_rate * integrator.substeps as f64);
    let w = modes().0[1];
    check(
        integrator,
        w * model.sampling.duration * (w * h).powi(4) / 120.0,
    );
}

/// The library's modal analysis finds the same two modes: frequencies and
/// (exact, for proportional damping) damping ratios `ζ_i = β ω_i / 2` to
/// 1e-12 relative (an eigen-solve of a well-conditioned matrix), shapes to
/// 1e-13 up to sign (the two frequencies are far apart), and the ten
/// unrestrained DOF as zero-stiffness modes.
#[test]
fn modal_analysis_finds_the_chain_modes() {
    let model = model(&chain());
    let sim = Simulator::new(&model);
    let ma = modal_analysis(&sim, &model.nominal()).unwrap();
    let (omega, phi) = modes();
    assert_eq!(ma.modes.len(), 12);
    assert_eq!(ma.modes.iter().filter(|m| m.zero_stiffness).count(), 10);
    assert!(!ma.at_equilibrium);
    assert!(ma.zero_slope_components.is_empty());
    let found: Vec<_> = ma.modes.iter().filter(|m| !m.zero_stiffness).collect();
    for i in 0..2 {
        let f = omega[i] / (2.0 * PI);
        let zeta = BETA * omega[i] / 2.0;
        let m = found[i];
        let ef = (m.frequency_hz - f).abs() / f;
        let ez = (m.damping_ratio.unwrap() - zeta).abs() / zeta;
        assert_within(&format!("mode {i} frequency ({f:.3} Hz)"), ef, 1e-12);
        assert_within(&format!("mode {i} damping ratio ({zeta:.5})"), ez, 1e-12);
        // Body 1's X is its u1 (coordinate 0); body 2's X is its u3 (coordinate 8).
        let sign = m.shape[0].signum() * phi[(0, i)].signum();
        let es = (sign * m.shape[0] - phi[(0, i)])
            .abs()
            .max((sign * m.shape[8] - phi[(1, i)]).abs());
        assert_within(&format!("mode {i} shape"), es / phi.amax(), 1e-13);
        let rest: f64 = (0..12)
            .filter(|&j| j != 0 && j != 8)
            .map(|j| m.shape[j].abs())
            .sum();
        assert!(
            rest < 1e-12 * phi.amax(),
            "mode {i} moves other DOF: {rest:e}"
        );
    }
}
