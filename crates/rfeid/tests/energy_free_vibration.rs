//! Energy of an undamped body in free vibration after an impulse.
//!
//! One body (centre of mass at the origin, global axes) on three undamped
//! linear elements with rotated axes at off-centre points, so that all six
//! DOF are coupled. A half-sine impulse at an off-centre point along an
//! oblique direction excites every mode; afterwards the motion is free and
//! `E = ½ q̇ᵀ M q̇ + ½ qᵀ K q` is a constant of the exact motion.
//!
//! q and q̇ are read back exactly (linear combinations) from twelve sensors:
//! displacements and velocities along X, Y, Z at the centre, along X and Y
//! at (0, 0, 1) and along Y at (1, 0, 0), since a point ρ moves by
//! `u + φ × ρ`. K is assembled here from SPEC §1 (δ = Θ S(ρ) q),
//! independently of the library.
//!
//! What RK4 does to the energy is known exactly: for `ẏ = A y` one step is
//! `y ← P(hA) y`, `P(z) = 1 + z + z²/2 + z³/6 + z⁴/24`, and for an undamped
//! mode ω (a normal 2×2 block) it scales the mode's energy
//! `E_i = ½(η̇_i² + ω_i² η_i²)` by `|P(iωh)|² = 1 − (ωh)⁶/72 + (ωh)⁸/576`
//! per step. So the test checks
//! 1. each modal energy against that exact prediction, to 1e-11 of the total
//!    (rounding only: the states carry ~1e-15 relative rounding through 10⁴
//!    steps, and φ is read back as a difference of two readings; measured
//!    1.5e-12);
//! 2. the total energy's decay against its a-priori bound
//!    `n_steps (ω_max h)⁶ / 72` with ω_max h = 0.108 (2.1e-4 over 1 s;
//!    measured 9.4e-5, since not all the energy is in the fastest mode).
use crate::common;

use common::*;
use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Rotation3, SymmetricEigen, Vector3};

const MASS: f64 = 10.0;
const INERTIA: [f64; 3] = [0.3, 0.4, 0.5];
/// The springs: position, axes (roll, pitch, yaw), stiffness of ux, uy, uz.
const SPRINGS: [([f64; 3], [f64; 3], [f64; 3]); 3] = [
    ([0.3, 0.0, -0.1], [0.2, 0.1, -0.3], [1.0e6, 2.0e6, 1.5e6]),
    ([-0.15, 0.25, 0.05], [-0.5, 0.4, 0.1], [2.5e6, 0.8e6, 1.2e6]),
    ([-0.1, -0.3, 0.2], [0.0, -0.3, 0.7], [1.8e6, 1.1e6, 0.6e6]),
];
/// The impulse ends at t = 0.003 s; the free motion is checked from here on.
const FIRST_FREE_SAMPLE: usize = 5;

fn axes(rpy: [f64; 3]) -> Matrix3<f64> {
    *Rotation3::from_euler_angles(rpy[0], rpy[1], rpy[2]).matrix()
}

fn model_text() -> String {
    let mut s = String::from(
        r#"
[simulation]
duration = 1.0
sample_rate = 1000.0
substeps = 10

[[body]]
name = "b"
mass = 10.0
inertia = [0.3, 0.4, 0.5]
com = [0.0, 0.0, 0.0]

[[excitation]]
body = "b"
at = [0.2, -0.1, 0.15]
direction = [1.0, 0.7, -0.4]
signal = { type = "impulse", amplitude = 2000.0, t0 = 0.001, width = 0.002 }
"#,
    );
    for (i, (at, rpy, k)) in SPRINGS.iter().enumerate() {
        let e = axes(*rpy);
        let col = |j: usize| format!("[{:e}, {:e}, {:e}]", e[(0, j)], e[(1, j)], e[(2, j)]);
        s += &format!(
            "\n[[element]]\nname = \"s{i}\"\nbody = \"b\"\nto = \"ground\"\nat = [{:e}, {:e}, {:e}]\n\
             axes = [{}, {}, {}]\nux = {{ k = {:e} }}\nuy = {{ k = {:e} }}\nuz = {{ k = {:e} }}\n",
            at[0], at[1], at[2], col(0), col(1), col(2), k[0], k[1], k[2]
        );
    }
    for quantity in ["displacement", "velocity"] {
        for (name, at, dir) in [
            ("cx", "[0, 0, 0]", "[1, 0, 0]"),
            ("cy", "[0, 0, 0]", "[0, 1, 0]"),
            ("cz", "[0, 0, 0]", "[0, 0, 1]"),
            ("zx", "[0, 0, 1]", "[1, 0, 0]"),
            ("zy", "[0, 0, 1]", "[0, 1, 0]"),
            ("xy", "[1, 0, 0]", "[0, 1, 0]"),
        ] {
            s += &format!(
                "\n[[sensor]]\nname = \"{quantity}_{name}\"\nbody = \"b\"\nat = {at}\ndirection = {dir}\nquantity = \"{quantity}\"\n"
            );
        }
    }
    s
}

/// `[u1 u2 u3 φ1 φ2 φ3]` from the six readings (sensor order of `model_text`):
/// `w(0,0,1) = u + (φ2, −φ1, 0)`, `w(1,0,0) = u + (0, φ3, −φ2)`.
fn coordinates(r: [f64; 6]) -> DVector<f64> {
    DVector::from_vec(vec![
        r[0],
        r[1],
        r[2],
        r[1] - r[4],
        r[3] - r[0],
        r[5] - r[1],
    ])
}

/// K = Σ k_i B_iᵀ B_i with `B_i` the rows of `Θ S(ρ)` (SPEC §1, eq. 5).
fn stiffness() -> DMatrix<f64> {
    let mut k = DMatrix::zeros(6, 6);
    for (at, rpy, kk) in SPRINGS {
        let rho = Vector3::from(at);
        let mut s = Matrix6::identity();
        s.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(-rho.cross_matrix()));
        let theta = axes(rpy).transpose();
        let mut big = Matrix6::zeros();
        big.fixed_view_mut::<3, 3>(0, 0).copy_from(&theta);
        big.fixed_view_mut::<3, 3>(3, 3).copy_from(&theta);
        let b = big * s;
        for (dof, kd) in kk.iter().enumerate() {
            let row = b.row(dof).transpose();
            k += DMatrix::from_fn(6, 6, |i, j| kd * row[i] * row[j]);
        }
    }
    k
}

struct States {
    q: Vec<DVector<f64>>,
    v: Vec<DVector<f64>>,
}

fn states() -> (States, f64) {
    let model = model(&model_text());
    // The check is about RK4's known energy behaviour, so use RK4 explicitly
    // (the default method is DOP853). The model is linear: no crossings.
    let rk4 = rfeid::simulation::Integrator {
        tableau: rfeid::simulation::tableau::RK4,
        substeps: model.sampling.substeps.expect("the model fixes substeps"),
        locate_crossings: true,
    };
    let out = simulate_nominal(&model, Some(rk4));
    let n = model.sampling.n_samples();
    let read =
        |base: usize, k: usize| coordinates(std::array::from_fn(|c| out.sensor(base + c)[k]));
    let h = 1.0 / (model.sampling.sample_rate * model.sampling.substeps.expect("fixed") as f64);
    (
        States {
            q: (0..n).map(|k| read(0, k)).collect(),
            v: (0..n).map(|k| read(6, k)).collect(),
        },
        h,
    )
}

fn mass_diag() -> DVector<f64> {
    DVector::from_vec(vec![MASS, MASS, MASS, INERTIA[0], INERTIA[1], INERTIA[2]])
}

/// `|P(iωh)|²` for RK4.
fn rk4_gain(z: f64) -> f64 {
    let re = 1.0 - z * z / 2.0 + z.powi(4) / 24.0;
    let im = z - z.powi(3) / 6.0;
    re * re + im * im
}

#[test]
fn modal_energies_decay_exactly_as_rk4_predicts() {
    let (st, h) = states();
    let m = mass_diag();
    let msqrt = m.map(f64::sqrt);
    let k = stiffness();
    let a = DMatrix::from_fn(6, 6, |i, j| k[(i, j)] / (msqrt[i] * msqrt[j]));
    let eig = SymmetricEigen::new(a);
    let omega: Vec<f64> = eig.eigenvalues.iter().map(|l| l.sqrt()).collect();
    println!(
        "ω h = {:?}",
        omega.iter().map(|w| w * h).collect::<Vec<_>>()
    );
    // Modal coordinates η = Vᵀ M^{1/2} q.
    let modal = |q: &DVector<f64>, v: &DVector<f64>| -> Vec<f64> {
        let eta = eig.eigenvectors.transpose() * q.component_mul(&msqrt);
        let deta = eig.eigenvectors.transpose() * v.component_mul(&msqrt);
        (0..6)
            .map(|i| 0.5 * (deta[i] * deta[i] + omega[i] * omega[i] * eta[i] * eta[i]))
            .collect()
    };
    let e0 = modal(&st.q[FIRST_FREE_SAMPLE], &st.v[FIRST_FREE_SAMPLE]);
    let total0: f64 = e0.iter().sum();
    assert!(
        e0.iter().all(|&e| e > 1e-4 * total0),
        "every mode is excited: {e0:?}"
    );
    let steps_per_sample = 10;
    let mut worst: f64 = 0.0;
    for s in FIRST_FREE_SAMPLE..st.q.len() {
        let e = modal(&st.q[s], &st.v[s]);
        let steps = ((s - FIRST_FREE_SAMPLE) * steps_per_sample) as i32;
        let miss: f64 = (0..6)
            .map(|i| (e[i] - e0[i] * rk4_gain(omega[i] * h).powi(steps)).abs())
            .sum();
        worst = worst.max(miss / total0);
    }
    assert_within("modal energies vs |P(iωh)|^2n", worst, 1e-11);
}

#[test]
fn total_energy_is_conserved_to_the_rk4_bound() {
    let (st, h) = states();
    let m = mass_diag();
    let k = stiffness();
    let energy = |q: &DVector<f64>, v: &DVector<f64>| {
        0.5 * v.dot(&v.component_mul(&m)) + 0.5 * q.dot(&(&k * q))
    };
    let e0 = energy(&st.q[FIRST_FREE_SAMPLE], &st.v[FIRST_FREE_SAMPLE]);
    let mut worst: f64 = 0.0;
    for s in FIRST_FREE_SAMPLE..st.q.len() {
        worst = worst.max((energy(&st.q[s], &st.v[s]) / e0 - 1.0).abs());
    }
    let eig = SymmetricEigen::new(DMatrix::from_fn(6, 6, |i, j| {
        k[(i, j)] / (m[i] * m[j]).sqrt()
    }));
    let wmax = eig.eigenvalues.max().sqrt();
    let n_steps = ((st.q.len() - 1 - FIRST_FREE_SAMPLE) * 10) as f64;
    let bound = n_steps * (wmax * h).powi(6) / 72.0;
    assert_within("relative energy drift", worst, bound);
}
