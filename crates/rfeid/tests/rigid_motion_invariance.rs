//! Moving a whole model rigidly in space does not change what it measures.
//!
//! A two-body model with every kind of geometry (rotated body and element
//! axes, off-centre attachments, six-component joint with a power-law
//! spring, an exciter between the bodies, oblique sensors of all three
//! quantities, optionally gravity) is rotated by random rotations and
//! translated by random offsets: every point `x → R x + t`, every direction
//! and axis `d → R d`, gravity `g → R g`. The sensors, rotated with
//! everything, must read the same signals. The computation is the same up to
//! rounding of the transformed inputs (written to the file to full
//! precision) and of the re-orthonormalised axes, so the signals must agree
//! to rounding: 1e-13 of their peak. Rounding of order ε ≈ 1e-16 in the
//! geometry, carried through 2000 integration steps, gives the measured
//! 1.2e-14 to 1.8e-14 (worst of five motions); 1e-13 leaves a factor 5.
use crate::common;

use common::*;
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3, Vector4};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// A rigid motion `x → R x + t`.
struct Motion {
    r: Matrix3<f64>,
    t: Vector3<f64>,
}

impl Motion {
    fn identity() -> Self {
        Motion {
            r: Matrix3::identity(),
            t: Vector3::zeros(),
        }
    }
    fn point(&self, x: [f64; 3]) -> String {
        vec3(&(self.r * Vector3::from(x) + self.t))
    }
    fn dir(&self, d: [f64; 3]) -> String {
        vec3(&(self.r * Vector3::from(d)))
    }
    fn axes(&self, e: Matrix3<f64>) -> String {
        let m = self.r * e;
        format!(
            "[{}, {}, {}]",
            vec3(&m.column(0).into()),
            vec3(&m.column(1).into()),
            vec3(&m.column(2).into())
        )
    }
}

/// A vector to full (round-trip) precision.
fn vec3(v: &Vector3<f64>) -> String {
    format!("[{:e}, {:e}, {:e}]", v.x, v.y, v.z)
}

fn frame(roll: f64, pitch: f64, yaw: f64) -> Matrix3<f64> {
    *Rotation3::from_euler_angles(roll, pitch, yaw).matrix()
}

/// The model, moved by `m`.
fn model_text(m: &Motion, gravity: bool) -> String {
    let g = if gravity {
        format!("gravity = {}\n", m.dir([0.0, 0.0, -9.81]))
    } else {
        String::new()
    };
    let pad = |name: &str, at: [f64; 3], axes: Matrix3<f64>, k: f64| {
        format!(
            r#"
[[element]]
name = "{name}"
body = "base"
to = "ground"
at = {}
axes = {}
ux = {{ k = {k:e}, c = 300.0 }}
uy = {{ k = {:e}, c = 200.0 }}
uz = {{ k = {:e}, c = 500.0 }}
"#,
            m.point(at),
            m.axes(axes),
            0.7 * k,
            2.0 * k
        )
    };
    format!(
        r#"{g}
[simulation]
duration = 0.1
sample_rate = 2000.0

[[body]]
name = "base"
mass = 50.0
inertia = [2.0, 3.0, 4.0]
com = {}
axes = {}

[[body]]
name = "head"
mass = 10.0
inertia = [0.3, 0.4, 0.5]
com = {}
axes = {}
{}{}{}
[[element]]
name = "joint"
body = "head"
to = "base"
at = {}
axes = {}
ux = {{ law = "power", a = 2.0e12, m = 2.0, c = 800.0 }}
uy = {{ k = 3.0e6, c = 400.0 }}
uz = {{ k = 4.0e6 }}
rx = {{ k = 2.0e4, c = 5.0 }}
ry = {{ k = 3.0e4 }}
rz = {{ k = 1.0e4, c = 2.0 }}

[[element]]
name = "preload"
body = "head"
to = "base"
at = {}
axes = {}
ux = {{ k = 1.0e5 }}

[[excitation]]
body = "head"
reaction = "base"
at = {}
direction = {}
signal = {{ type = "multisine", components = [{{ amplitude = 300.0, frequency = 60.0 }}, {{ amplitude = 150.0, frequency = 170.0, phase = 0.4 }}] }}

[[excitation]]
body = "base"
at = {}
direction = {}
signal = {{ type = "chirp", amplitude = 400.0, f0 = 20.0, f1 = 300.0 }}

[[sensor]]
name = "head_acc"
body = "head"
at = {}
direction = {}
quantity = "acceleration"

[[sensor]]
name = "base_disp"
body = "base"
at = {}
direction = {}
quantity = "displacement"

[[sensor]]
name = "head_vel"
body = "head"
at = {}
direction = {}
quantity = "velocity"

[[sensor]]
name = "head_disp"
body = "head"
at = {}
direction = {}
quantity = "displacement"
"#,
        m.point([0.1, -0.2, 0.3]),
        m.axes(frame(0.3, -0.5, 1.1)),
        m.point([0.4, 0.3, 0.9]),
        m.axes(frame(-0.8, 0.2, 0.4)),
        pad("pad1", [-0.3, -0.4, 0.0], frame(0.1, 0.2, 0.3), 2.0e6),
        pad("pad2", [0.4, -0.3, 0.05], frame(-0.4, 0.0, 0.9), 3.0e6),
        pad("pad3", [0.0, 0.5, -0.02], frame(0.0, 0.7, -0.2), 2.5e6),
        m.point([0.3, 0.1, 0.7]),
        m.axes(frame(0.6, -0.1, 0.2)),
        m.point([0.5, 0.4, 1.0]),
        m.axes(Matrix3::identity()),
        m.point([0.2, 0.2, 0.8]),
        m.dir([1.0, -2.0, 0.5]),
        m.point([-0.1, 0.3, 0.4]),
        m.dir([0.0, 1.0, 1.0]),
        m.point([0.6, 0.1, 1.1]),
        m.dir([0.3, 0.4, -0.5]),
        m.point([-0.2, 0.1, 0.4]),
        m.dir([1.0, 1.0, 1.0]),
        m.point([0.5, 0.5, 1.0]),
        m.dir([0.0, 0.0, 1.0]),
        m.point([0.35, 0.05, 0.75]),
        m.dir([1.0, 0.0, 0.0]),
    )
}

fn random_motion(rng: &mut ChaCha8Rng, translate: bool) -> Motion {
    let q = Vector4::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal));
    let r = *UnitQuaternion::from_quaternion(nalgebra::Quaternion::from(q))
        .to_rotation_matrix()
        .matrix();
    let t = if translate {
        Vector3::from_fn(|_, _| rng.random_range(-10.0..10.0))
    } else {
        Vector3::zeros()
    };
    Motion { r, t }
}

/// Largest difference between two responses, per sensor, relative to the
/// sensor's peak.
fn difference(a: &rfeid::simulation::Response, b: &rfeid::simulation::Response) -> f64 {
    (0..a.n_sensors)
        .map(|c| rel_max_err(a.sensor(c), b.sensor(c)))
        .fold(0.0, f64::max)
}

fn check(gravity: bool, rotate: bool, translate: bool, seed: u64) {
    let reference = simulate_nominal(&model(&model_text(&Motion::identity(), gravity)), None);
    for c in 0..reference.n_sensors {
        assert!(
            max_abs(reference.sensor(c)) > 0.0,
            "sensor {c} reads nothing"
        );
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut worst: f64 = 0.0;
    for _ in 0..5 {
        let mut m = random_motion(&mut rng, translate);
        if !rotate {
            m.r = Matrix3::identity();
        }
        let moved = simulate_nominal(&model(&model_text(&m, gravity)), None);
        worst = worst.max(difference(&moved, &reference));
    }
    assert_within(
        &format!("gravity {gravity}, rotate {rotate}, translate {translate}: worst of 5"),
        worst,
        1e-13,
    );
}

#[test]
fn the_unmoved_model_reads_the_same_bit_for_bit() {
    let a = simulate_nominal(&model(&model_text(&Motion::identity(), false)), None);
    let b = simulate_nominal(&model(&model_text(&Motion::identity(), false)), None);
    assert_eq!(a, b);
}

#[test]
fn rotation_does_not_change_the_readings() {
    check(false, true, false, 1);
}

#[test]
fn translation_does_not_change_the_readings() {
    check(false, false, true, 2);
}

#[test]
fn rigid_motion_does_not_change_the_readings_under_gravity() {
    check(true, true, true, 3);
}

/// The control: leaving one element's axes unrotated (the mistake this
/// test's first draft made) changes the readings by far more than the
/// tolerance, so the comparison above is not vacuous.
#[test]
fn a_partial_rotation_does_change_the_readings() {
    let reference = simulate_nominal(&model(&model_text(&Motion::identity(), false)), None);
    let m = random_motion(&mut ChaCha8Rng::seed_from_u64(1), false);
    let text = model_text(&m, false);
    let start = text.find("name = \"preload\"").unwrap();
    let line = start + text[start..].find("axes = ").unwrap();
    let end = line + text[line..].find('\n').unwrap();
    let text = format!("{}{}", &text[..line], &text[end..]);
    let moved = simulate_nominal(&model(&text), None);
    let d = difference(&moved, &reference);
    println!("partial rotation: difference {d:.3e}");
    assert!(d > 1e-3);
}
