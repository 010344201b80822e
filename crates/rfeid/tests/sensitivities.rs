//! Forward sensitivities against finite differences of `Simulator::run`.
//!
//! The sensitivity equations are integrated by the same Runge–Kutta stages as
//! the state, so they are the exact derivative of the discrete solution
//! (`simulation::run` module docs): they must agree with finite differences
//! of `run` up to the differencing error alone, whatever the integration
//! error. Each Jacobian column (all sensors and samples for one parameter)
//! is compared in units of its RMS, to 1e-6.
//!
//! The differences are the five-point stencil
//! `(y(x−2h) − 8y(x−h) + 8y(x+h) − y(x+2h)) / 12h`, whose error is
//! - truncation, `h⁴ y⁽⁵⁾ / 30`, and
//! - rounding, about `ε_y |y| / h`, with ε_y ≈ 1e-14 the relative rounding
//!   noise of a simulated signal after 10⁴ steps (1e-13 with gravity, where
//!   the dynamic part is a small difference from the static preload).
//!
//! Plain central differences with h = 1e-6 x were tried first: on the
//! knee–column their error falls exactly as 1/h from h = 1e-7 x to 1e-5 x
//! (it is rounding), reaching 3.5e-6 of the RMS for h_t3, the parameter
//! with least effect (|y| / |x ∂y/∂x| ≈ 600). The five-point stencil at
//! h = 1e-4 x keeps both errors near 1e-8 to 1e-7 (measured, printed), so
//! 1e-6 leaves a margin of 6 or more. The exception is a power-law exponent
//! m: the response depends on it through `|δ|^m` with |ln δ| ≈ 13 and through
//! the shift of a 570 Hz mode accumulated over 0.15 s (x ∂ phase/∂x ≈ 3000
//! rad), so its natural relative scale is ~3e-4 and its step is 1e-5 m.
use crate::common;
use crate::machine_tool;

use common::*;
use rfeid::io::model_file::load_model;
use rfeid::model::Model;
use rfeid::simulation::structure::Usage;
use rfeid::simulation::{Kernel, Response, Sensitivities, Simulator, Workspace};
use std::path::Path;

/// The relative step of the five-point stencil (see the module docs).
const REL_STEP: f64 = 1e-4;
/// The step for a power-law exponent (see the module docs).
const EXPONENT_REL_STEP: f64 = 1e-5;

fn sensitivities(sim: &Simulator<'_>, params: &[f64], wrt: &[usize]) -> (Response, Sensitivities) {
    let mut out = sim.response_buffer();
    let mut sens = Sensitivities {
        wrt: vec![],
        values: vec![],
    };
    sim.run_with_sensitivities(params, wrt, &mut Workspace::default(), &mut out, &mut sens)
        .unwrap();
    (out, sens)
}

/// For each parameter in `wrt`: the largest |forward − finite difference|
/// over the column, divided by the column's RMS.
fn compare_with_finite_differences(model: &Model, wrt: &[usize]) -> Vec<f64> {
    // Steps are split where a power-law deformation crosses zero; the split
    // instants move with the parameters and their derivative is left out of
    // the sensitivities (see `simulation::stepper`), a term of the order of
    // the local truncation error. With it, the stencil's own error and
    // rounding, the largest deviation measured on these models is 1.2e-6 of
    // a column's RMS (h_t3 of the knee–column); the bound is 2e-6. (Without
    // the splitting, the stages meet the kink of a·δ|δ| and the stencil's
    // truncation error grows to 6e-6: the located crossings also make the
    // response smoother in the parameters.)
    compare_with(model, &Simulator::new(model), wrt, 2e-6)
}

fn compare_with(model: &Model, sim: &Simulator<'_>, wrt: &[usize], tol: f64) -> Vec<f64> {
    compare_with_step(model, sim, wrt, tol, REL_STEP)
}

/// [`compare_with`] with the relative step `rel_step` for every parameter
/// but an exponent.
fn compare_with_step(
    model: &Model,
    sim: &Simulator<'_>,
    wrt: &[usize],
    tol: f64,
    rel_step: f64,
) -> Vec<f64> {
    let sim = sim.clone();
    let x = model.nominal();
    let (out, sens) = sensitivities(&sim, &x, wrt);
    assert_eq!(sens.wrt, wrt);
    let rows = out.values.len();
    assert_eq!(sens.values.len(), rows * wrt.len());

    // The response of a sensitivity run is the response of a plain run, bit for bit.
    let mut ws = Workspace::default();
    let mut plain = sim.response_buffer();
    sim.run(&x, &mut ws, &mut plain).unwrap();
    assert_eq!(plain, out);

    let mut errors = Vec::new();
    for (j, &p) in wrt.iter().enumerate() {
        let name = &model.parameters[p].name;
        let is_exponent = sim.structure().usages[p]
            .iter()
            .any(|u| matches!(u, Usage::PowerExponent(_)));
        let rel = if is_exponent {
            EXPONENT_REL_STEP
        } else {
            rel_step
        };
        let h = rel * x[p].abs();
        let mut at = |offset: f64| {
            let mut xp = x.clone();
            xp[p] = x[p] + offset * h;
            let mut y = sim.response_buffer();
            sim.run(&xp, &mut ws, &mut y).unwrap();
            y.values
        };
        let (y_2m, y_1m, y_1p, y_2p) = (at(-2.0), at(-1.0), at(1.0), at(2.0));
        let column: Vec<f64> = (0..rows).map(|i| sens.values[i * wrt.len() + j]).collect();
        let fd: Vec<f64> = (0..rows)
            .map(|i| (y_2m[i] - 8.0 * y_1m[i] + 8.0 * y_1p[i] - y_2p[i]) / (12.0 * h))
            .collect();
        let scale = rms(&column);
        assert!(scale > 0.0, "{name}: zero sensitivity");
        let err = column
            .iter()
            .zip(&fd)
            .fold(0.0, |m, (a, b)| f64::max(m, (a - b).abs()))
            / scale;
        assert_within(&format!("∂y/∂{name} (step {rel:e} x)"), err, tol);
        errors.push(err);
    }
    errors
}

fn knee_column() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    load_model(&path).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn knee_column_sensitivities_match_finite_differences() {
    let model = knee_column();
    let wrt = model.identified();
    assert_eq!(wrt.len(), 16);
    compare_with_finite_differences(&model, &wrt);
}

/// The columns do not depend on which other parameters are asked for, or in
/// what order (each column is computed independently; the reordering only
/// changes which lane of the blocked product a column lands in).
#[test]
fn columns_do_not_depend_on_the_order_of_wrt() {
    let model = knee_column();
    let sim = Simulator::new(&model);
    let x = model.nominal();
    let wrt = model.identified();
    let (_, all) = sensitivities(&sim, &x, &wrt);
    let picked = [wrt[13], wrt[2], wrt[7]];
    let (_, some) = sensitivities(&sim, &x, &picked);
    let rows = all.values.len() / wrt.len();
    for (jj, p) in picked.iter().enumerate() {
        let j = wrt.iter().position(|q| q == p).unwrap();
        let a: Vec<f64> = (0..rows).map(|i| all.values[i * wrt.len() + j]).collect();
        let b: Vec<f64> = (0..rows)
            .map(|i| some.values[i * picked.len() + jj])
            .collect();
        assert_within(
            &format!("column {}", model.parameters[*p].name),
            rel_max_err(&b, &a),
            1e-14,
        );
    }
}

/// A model where parameters enter every way they can: a body's mass and a
/// moment of inertia, a stiffness shared by several components, damping,
/// a power-law coefficient and exponent, an excitation amplitude (one
/// component of a multisine), with gravity, so that the run starts from a
/// static equilibrium that itself depends on the parameters (mass, the
/// stiffnesses, a and m): displacement sensors read from it.
///
/// The power-law supports are preloaded by the slide's weight (δ ≈ 1e-5 m)
/// and the dynamic motion is 20 times smaller, so δ never crosses zero and
/// the response is smooth in every parameter.
const EVERY_USAGE: &str = r#"
gravity = [0.0, 0.0, -9.81]

[simulation]
duration = 0.15
sample_rate = 2000.0

[[body]]
name = "table"
mass = "m_table"
inertia = ["J_table", 5.0, 7.0]
com = [0.0, 0.0, 0.3]

[[body]]
name = "slide"
mass = 20.0
inertia = [0.4, 0.5, "J_slide"]
com = [0.05, 0.1, 0.6]
axes = [[0, 1, 0], [-1, 0, 0], [0, 0, 1]]

[[element]]
name = "pad1"
body = "table"
to = "ground"
at = [-0.4, -0.3, 0.0]
ux = { k = "k_lat", c = 800.0 }
uy = { k = "k_lat", c = 800.0 }
uz = { k = "k_pad", c = "c_pad" }

[[element]]
name = "pad2"
body = "table"
to = "ground"
at = [0.4, -0.3, 0.0]
ux = { k = "k_lat", c = 800.0 }
uy = { k = "k_lat", c = 800.0 }
uz = { k = "k_pad", c = "c_pad" }

[[element]]
name = "pad3"
body = "table"
to = "ground"
at = [0.0, 0.4, 0.0]
ux = { k = "k_lat", c = 800.0 }
uy = { k = "k_lat", c = 800.0 }
uz = { k = "k_pad", c = "c_pad" }

[[element]]
name = "support1"
body = "slide"
to = "table"
at = [-0.1, 0.1, 0.5]
ux = { k = 2e7, c = 300.0 }
uy = { k = 2e7, c = 300.0 }
uz = { law = "power", a = "a_n", m = "m_n", c = "c_n" }

[[element]]
name = "support2"
body = "slide"
to = "table"
at = [0.2, 0.1, 0.5]
ux = { k = 2e7, c = 300.0 }
uy = { k = 2e7, c = 300.0 }
uz = { law = "power", a = "a_n", m = "m_n", c = "c_n" }
rx = { k = 5e4 }
ry = { k = 5e4, c = 3.0 }
rz = { k = 5e4 }

[[excitation]]
body = "slide"
reaction = "table"
at = [0.1, 0.15, 0.65]
direction = [0.3, -0.2, 1.0]
signal = { type = "multisine", components = [{ amplitude = "P1", frequency = 90.0 }, { amplitude = 15.0, frequency = 230.0, phase = 1.0 }] }

[[sensor]]
name = "slide_z"
body = "slide"
at = [0.1, 0.2, 0.6]
direction = [0.1, 0.1, 1.0]
quantity = "displacement"

[[sensor]]
name = "table_v"
body = "table"
at = [0.3, -0.2, 0.4]
direction = [1.0, 0.5, 0.5]
quantity = "velocity"

[[sensor]]
name = "slide_a"
body = "slide"
at = [0.0, 0.0, 0.7]
direction = [0.0, 1.0, 1.0]
quantity = "acceleration"

[[parameter]]
name = "m_table"
value = 150.0
min = 100.0
max = 200.0

[[parameter]]
name = "J_table"
value = 4.0
min = 2.0
max = 8.0

[[parameter]]
name = "J_slide"
value = 0.6
min = 0.3
max = 1.0

[[parameter]]
name = "k_lat"
value = 1.5e7
min = 1e7
max = 2e7

[[parameter]]
name = "k_pad"
value = 4e7
min = 2e7
max = 6e7

[[parameter]]
name = "c_pad"
value = 3000.0
min = 1000.0
max = 5000.0

[[parameter]]
name = "a_n"
value = 1e12
min = 5e11
max = 2e12

[[parameter]]
name = "m_n"
value = 2.0
min = 1.5
max = 3.0

[[parameter]]
name = "c_n"
value = 2000.0
min = 1000.0
max = 4000.0

[[parameter]]
name = "P1"
value = 30.0
min = 10.0
max = 50.0
"#;

#[test]
fn every_kind_of_parameter_usage_matches_finite_differences() {
    let model = model(EVERY_USAGE);
    let wrt = model.identified();
    assert_eq!(wrt.len(), 10);
    compare_with_finite_differences(&model, &wrt);
}

/// A column is the same to the last bit whatever the other columns and
/// their order: over seeded shuffles of the parameters (every kind of
/// usage; the pad damping here also damps the first pad's ux, so that other
/// parameters reach some of its components first), every column equals the
/// one computed in the model's order.
#[test]
fn every_kind_of_usage_in_any_order_gives_identical_columns() {
    let text = EVERY_USAGE.replacen(
        r#"ux = { k = "k_lat", c = 800.0 }"#,
        r#"ux = { k = "k_lat", c = "c_pad" }"#,
        1,
    );
    let model = model(&text);
    let sim = Simulator::new(&model);
    let x = model.nominal();
    let wrt = model.identified();
    let r = wrt.len();
    let (_, reference) = sensitivities(&sim, &x, &wrt);
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    for _ in 0..12 {
        // Fisher–Yates with a seeded xorshift.
        let mut order = wrt.clone();
        for i in (1..r).rev() {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            order.swap(i, (state % (i as u64 + 1)) as usize);
        }
        let (_, shuffled) = sensitivities(&sim, &x, &order);
        for (i, (row, other)) in reference
            .values
            .chunks_exact(r)
            .zip(shuffled.values.chunks_exact(r))
            .enumerate()
        {
            for (j, p) in wrt.iter().enumerate() {
                let k = order.iter().position(|q| q == p).unwrap();
                assert!(
                    row[j].to_bits() == other[k].to_bits(),
                    "observation {i}, parameter {} in order {order:?}: {} vs {}",
                    model.parameters[*p].name,
                    row[j],
                    other[k]
                );
            }
        }
    }
}

/// The same with the power-law exponent away from the fast paths for
/// m = 1 and m = 2 (the general `powf` branch).
#[test]
fn fractional_exponent_matches_finite_differences() {
    let text = EVERY_USAGE.replace("name = \"m_n\"\nvalue = 2.0", "name = \"m_n\"\nvalue = 1.7");
    let model = model(&text);
    let wrt = model.identified();
    compare_with_finite_differences(&model, &wrt);
}

/// The supports' law with a reference deformation δ_ref = 10 µm (the order
/// of their preload), m = 1.7: `a = 1e12 · δ_ref^m` N makes it the same
/// spring as [`EVERY_USAGE`]'s, so the response is the same to rounding;
/// the sensitivities to a (now a force) and to m (now about δ_ref) match
/// finite differences on the dense and the element-by-element kernels.
#[test]
fn reference_deformation_is_the_same_spring_and_matches_finite_differences() {
    let fractional =
        EVERY_USAGE.replace("name = \"m_n\"\nvalue = 2.0", "name = \"m_n\"\nvalue = 1.7");
    let a_ref = 1e12 * 1e-5f64.powf(1.7);
    let text = fractional
        .replace(r#"c = "c_n" }"#, r#"c = "c_n", reference = "10 um" }"#)
        .replace(
            "name = \"a_n\"\nvalue = 1e12\nmin = 5e11\nmax = 2e12",
            &format!(
                "name = \"a_n\"\nvalue = {a_ref:e}\nmin = {:e}\nmax = {:e}",
                a_ref / 2.0,
                a_ref * 2.0
            ),
        );
    assert_eq!(text.matches("reference = \"10 um\"").count(), 2);
    let (plain, model) = (model(&fractional), model(&text));
    let run = |m: &Model| {
        let sim = Simulator::new(m);
        let mut y = sim.response_buffer();
        sim.run(&m.nominal(), &mut Workspace::default(), &mut y)
            .unwrap();
        y.values
    };
    let (y0, y1) = (run(&plain), run(&model));
    let diff: Vec<f64> = y0.iter().zip(&y1).map(|(a, b)| a - b).collect();
    assert_within("relative RMS difference", rms(&diff) / rms(&y0), 1e-12);
    let wrt = model.identified();
    for kernel in [Kernel::Dense, Kernel::Sparse] {
        let mut sim = Simulator::new(&model);
        sim.set_kernel(kernel);
        compare_with(&model, &sim, &wrt, 2e-6);
    }
}

/// A generated 10-body machine tool (issue 12) with every place a parameter
/// can stand identified, run through the element-by-element kernels.
fn machine_tool_10() -> Model {
    let text = machine_tool::machine_tool_toml(10, usize::MAX);
    model(&text)
}

/// The element-by-element sensitivities (issue 12) on a 10-body machine
/// tool: a slideway normal's power-law coefficient and damping, tangential
/// stiffness and damping, isolation pads, and the joints of the flexible
/// bed and column. The step is 1e-3 x: at 1e-4 x the stencil's rounding
/// error reached 2.1e-6 of the RMS for a weak tangential damping (`ram_h_t4`,
/// no longer identified) and falls as 1/h (measured: 1.7e-7 at 1e-3 x for
/// `ram_h_t3`, the largest of these columns).
#[test]
fn machine_tool_sensitivities_match_finite_differences() {
    let model = machine_tool_10();
    let names = [
        "table_a_n1",
        "table_h_n2",
        "table_a_t3",
        "ram_a_n2",
        "ram_h_t3",
        "pad1_k_z",
        "pad2_c",
        "joint1_k_t",
        "joint6_k_r",
    ];
    let wrt: Vec<usize> = names
        .iter()
        .map(|n| {
            model
                .parameters
                .iter()
                .position(|p| p.name == *n)
                .unwrap_or_else(|| panic!("no parameter {n}"))
        })
        .collect();
    let mut sim = Simulator::new(&model);
    sim.set_kernel(Kernel::Sparse);
    let errors = compare_with_step(&model, &sim, &wrt, 2e-6, 1e-3);
    println!("machine tool, 10 bodies: {errors:?}");
}
