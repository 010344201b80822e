//! The element-by-element kernels (issue 12) against the dense ones: the
//! same equations (eq. 1–7) and sensitivities (eq. 27–28) summed in another
//! order, so responses and sensitivities agree to rounding, ≤ 1e-12
//! relative (RMS difference over RMS, per sensor and per column), on the
//! example models and generated machine tools of 2 to 20 bodies, and on
//! the generated chain, tower and gantry (a closed loop of joints).
//!
//! The generated models are under gravity: their springs carry tonnes
//! against a 20 N shaker. Both kernels integrate the motion about the
//! static equilibrium (`simulation::preload`), so their rounding is
//! relative to the motion, not to the weights. Measured (this test prints
//! them): at most 3.7e-14 for the examples' responses and 3.8e-14 for
//! their sensitivities, 3.8e-14 and 3.4e-14 for the generated models of 2
//! to 20 bodies. Written in the coordinates themselves, the
//! accelerations were small differences of weight-sized forces and the
//! kernels differed by 2.0e-12 to 7.5e-12. The chain, tower and gantry of
//! 10 bodies, with joints 10 times stiffer, differ by at most 6.2e-13
//! (responses) and 1.8e-13 (sensitivities).

use crate::machine_tool;

use machine_tool::{machine_toml, machine_tool_toml, Machine, Shape};
use rfeid::io::model_file::{load_model, parse_model};
use rfeid::model::Model;
use rfeid::simulation::{Kernel, Response, Sensitivities, Simulator, Workspace};
use std::path::Path;

fn example(name: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
        .join("model.toml");
    load_model(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// A generated machine tool over its first 0.1 s (1000 samples), so that
/// the dense kernels' sensitivities of the larger ones take a few seconds.
fn generated(bodies: usize, params: usize) -> Model {
    let text =
        machine_tool_toml(bodies, params).replace("duration = \"0.3 s\"", "duration = \"0.1 s\"");
    parse_model(&text, Path::new("machine_tool.toml")).unwrap_or_else(|e| panic!("{e}"))
}

/// Response and sensitivities to every identified parameter with `kernel`,
/// at the steps chosen for the model.
fn run(model: &Model, kernel: Kernel) -> (Response, Sensitivities) {
    let mut sim = Simulator::new(model);
    sim.set_kernel(kernel);
    let mut out = sim.response_buffer();
    let mut sens = Sensitivities {
        wrt: vec![],
        values: vec![],
    };
    let wrt = model.identified();
    let x = model.nominal();
    sim.run_with_sensitivities(&x, &wrt, &mut Workspace::default(), &mut out, &mut sens)
        .unwrap_or_else(|e| panic!("{kernel:?}: {e}"));
    (out, sens)
}

/// The largest relative RMS difference over the columns of two matrices
/// stored row-major with `cols` columns.
fn worst_column_difference(a: &[f64], b: &[f64], cols: usize) -> f64 {
    (0..cols)
        .map(|j| {
            let (mut diff, mut norm) = (0.0, 0.0);
            for (x, y) in a
                .iter()
                .skip(j)
                .step_by(cols)
                .zip(b.iter().skip(j).step_by(cols))
            {
                diff += (x - y) * (x - y);
                norm += y * y;
            }
            assert!(norm > 0.0, "column {j} is zero");
            (diff / norm).sqrt()
        })
        .fold(0.0, f64::max)
}

fn assert_kernels_agree(name: &str, model: &Model, bound: f64) {
    let (dense, dense_sens) = run(model, Kernel::Dense);
    let (sparse, sparse_sens) = run(model, Kernel::Sparse);
    // Sensor-major responses: the columns of the transposed view are sensors.
    let n_samples = dense.n_samples;
    let transpose = |r: &Response| -> Vec<f64> {
        (0..n_samples)
            .flat_map(|k| (0..r.n_sensors).map(move |c| (c, k)))
            .map(|(c, k)| r.values[c * n_samples + k])
            .collect()
    };
    let response =
        worst_column_difference(&transpose(&sparse), &transpose(&dense), dense.n_sensors);
    let r = dense_sens.wrt.len();
    let sensitivities = worst_column_difference(&sparse_sens.values, &dense_sens.values, r);
    println!("{name}: response {response:.1e}, sensitivities ({r} columns) {sensitivities:.1e}");
    assert!(
        response <= bound,
        "{name}: responses differ by {response:e}"
    );
    assert!(
        sensitivities <= bound,
        "{name}: sensitivities differ by {sensitivities:e}"
    );
}

#[test]
fn sparse_and_dense_kernels_agree_on_the_examples() {
    assert_kernels_agree("knee-column", &example("knee-column"), 1e-12);
    assert_kernels_agree("lathe", &example("lathe"), 1e-12);
}

#[test]
fn sparse_and_dense_kernels_agree_on_generated_machine_tools() {
    for (bodies, params) in [(2, 12), (3, 20), (5, 24), (10, 16), (20, 4)] {
        assert_kernels_agree(
            &format!("machine tool B = {bodies}"),
            &generated(bodies, params),
            1e-12,
        );
    }
}

/// The other shapes of the generator (issue 46), with their geometry varied
/// and their member joints 10 times stiffer: the gantry's cross-beam closes
/// a loop of joints, so its stiffness matrix is not a tree's.
#[test]
fn sparse_and_dense_kernels_agree_on_chains_towers_and_gantries() {
    for (shape, seed) in [(Shape::Chain, 1), (Shape::Tower, 2), (Shape::Gantry, 3)] {
        let machine = Machine {
            shape,
            bodies: 10,
            params: 12,
            stiffer: 10.0,
            seed,
        };
        let text = machine_toml(&machine).replace("duration = \"0.3 s\"", "duration = \"0.05 s\"");
        let model = parse_model(&text, Path::new("machine.toml")).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(model.bodies.len(), 10);
        assert_kernels_agree(&format!("{} B = 10", shape.name()), &model, 1e-12);
    }
}

/// On the element-by-element kernel, a component that no identified
/// parameter enters, with a linear law and no static columns, takes a
/// shorter path (`Entries::linear`) that must give the same sums as the
/// full one. Each column computed alone, where most components take the
/// short path, equals to the last bit the same column computed with all
/// sixteen, where the components of the other fifteen take the full one.
#[test]
fn a_column_alone_equals_the_same_column_among_all_to_the_last_bit() {
    let model = generated(5, 16);
    let mut sim = Simulator::new(&model);
    sim.set_kernel(Kernel::Sparse);
    let x = model.nominal();
    let run = |wrt: &[usize]| {
        let (mut out, mut ws) = (sim.response_buffer(), Workspace::default());
        let mut sens = Sensitivities {
            wrt: vec![],
            values: vec![],
        };
        sim.run_with_sensitivities(&x, wrt, &mut ws, &mut out, &mut sens)
            .unwrap_or_else(|e| panic!("{e}"));
        sens.values
    };
    let wrt = model.identified();
    let r = wrt.len();
    assert_eq!(r, 16);
    let all = run(&wrt);
    for (j, &p) in wrt.iter().enumerate() {
        let alone = run(&[p]);
        assert!(alone.iter().any(|v| *v != 0.0), "column {j} is zero");
        for (i, (a, b)) in alone.iter().zip(all.iter().skip(j).step_by(r)).enumerate() {
            assert!(
                a.to_bits() == b.to_bits(),
                "{}: observation {i}, {a} alone against {b} among all",
                model.parameters[p].name
            );
        }
    }
}
