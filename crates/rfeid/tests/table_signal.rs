//! A `table` excitation: samples from a CSV file next to the model (its path
//! is relative to the model file), linearly interpolated, 0 outside, scaled
//! by the amplitude.
//!
//! The table is a trapezoid, 0 → F over [0, t1], F until t2, back to 0 at t3,
//! so the interpolated force is exactly `A F/t1 (t − (t − t1)₊) − A F/(t3 −
//! t2) ((t − t2)₊ − (t − t3)₊)`, and the response of the single oscillator
//! (as in `sdof_closed_form.rs`) is the same combination of ramp responses
//! `r(t)`: particular `(t − c/k)/k` plus the free motion cancelling its
//! initial values. The kinks sit on integration step boundaries, so DOP853
//! keeps its order and matches to rounding: 1e-12 of the peak (measured
//! ~1e-14).
use crate::common;

use common::*;
use rfeid::io::model_file::load_model;
use rfeid::simulation::tableau::DOP853;
use rfeid::simulation::Integrator;

const M: f64 = 2.0;
const K: f64 = 2.0e5;
const C: f64 = 40.0;
const F: f64 = 150.0;
const A: f64 = 2.0;
const T: [f64; 3] = [0.02, 0.05, 0.08];

const MODEL: &str = r#"
[simulation]
duration = 0.25
sample_rate = 2000.0

[[body]]
name = "mass"
mass = 2.0
inertia = [0.1, 0.2, 0.3]
com = [0.0, 0.0, 0.0]

[[element]]
name = "spring"
body = "mass"
to = "ground"
at = [0.0, 0.0, 0.0]
ux = { k = 2.0e5, c = 40.0 }

[[excitation]]
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = { type = "table", file = "data/force.csv", column = "push", amplitude = 2.0 }

[[sensor]]
name = "x"
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "displacement"

[[sensor]]
name = "v"
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "velocity"

[[sensor]]
name = "a"
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "acceleration"
"#;

/// Response `(x, v)` to the unit ramp `f(t) = t` (0 before t = 0).
fn ramp(t: f64) -> (f64, f64) {
    if t <= 0.0 {
        return (0.0, 0.0);
    }
    let (xh, vh, _) = sdof_free(M, C, K, C / (K * K), -1.0 / K, t);
    ((t - C / K) / K + xh, 1.0 / K + vh)
}

fn force(t: f64) -> f64 {
    let p = |t: f64| t.max(0.0);
    A * F / T[0] * (p(t) - p(t - T[0])) - A * F / (T[2] - T[1]) * (p(t - T[1]) - p(t - T[2]))
}

fn exact(t: f64) -> (f64, f64, f64) {
    let s1 = A * F / T[0];
    let s2 = A * F / (T[2] - T[1]);
    let parts = [(s1, 0.0), (-s1, T[0]), (-s2, T[1]), (s2, T[2])];
    let (x, v) = parts.iter().fold((0.0, 0.0), |(x, v), (s, t0)| {
        let (rx, rv) = ramp(t - t0);
        (x + s * rx, v + s * rv)
    });
    (x, v, (force(t) - C * v - K * x) / M)
}

#[test]
fn table_force_matches_the_closed_form() {
    let dir = std::env::temp_dir().join(format!("rfeid-table-signal-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("data")).unwrap();
    std::fs::write(
        dir.join("data/force.csv"),
        format!(
            "time,other,push\n0,9,0\n{},9,{F}\n{},9,{F}\n{},9,0\n",
            T[0], T[1], T[2]
        ),
    )
    .unwrap();
    std::fs::write(dir.join("model.toml"), MODEL).unwrap();
    let model = load_model(&dir.join("model.toml"));
    std::fs::remove_dir_all(&dir).unwrap();
    let model = model.unwrap_or_else(|e| panic!("{e}"));

    let out = simulate_nominal(
        &model,
        Some(Integrator {
            tableau: DOP853,
            substeps: 10,
            locate_crossings: true,
        }),
    );
    let e: Vec<(f64, f64, f64)> = times(&model).into_iter().map(exact).collect();
    let pick = |f: fn(&(f64, f64, f64)) -> f64| e.iter().map(f).collect::<Vec<f64>>();
    let cols = [pick(|e| e.0), pick(|e| e.1), pick(|e| e.2)];
    for (c, want) in cols.iter().enumerate() {
        let err = rel_max_err(out.sensor(c), want);
        assert_within(
            &format!("table force, DOP853×10, {}", model.sensors[c].name),
            err,
            1e-12,
        );
    }
}
