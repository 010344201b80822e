//! Times one simulation with each kernel (`Auto`, `Dense`, `Sparse`) on the
//! knee–column and on generated machine tools of 2–8 bodies, plain and with
//! 16 sensitivities (medians of 5, in ms), with the sizes that
//! `simulation::sparse::prefer_sparse` weighs (coordinates, power laws,
//! groups of up to four components): the data its cost constants were
//! fitted to. `cargo run --release -p rfeid --example kernels`.
use rfeid::io::model_file::{load_model, parse_model};
use rfeid::model::{Law, Model};
use rfeid::simulation::{Kernel, Sensitivities, Simulator, Workspace};
use std::path::Path;

#[path = "../tests/machine_tool/mod.rs"]
mod machine_tool;
mod support;

/// Median of five timings of `f` after one untimed run, in ms.
fn median_ms(mut f: impl FnMut()) -> f64 {
    f();
    support::median_ms(5, f)
}

/// `(components, power laws, nonzero entries of B, groups of ≤ 4 components
/// sharing their blocks)` of a model.
fn sizes(sim: &Simulator<'_>) -> (usize, usize, usize, usize) {
    let comps = &sim.structure().components;
    let power = comps
        .iter()
        .filter(|c| matches!(c.law, Law::Power(_)))
        .count();
    let nonzeros = comps
        .iter()
        .flat_map(|c| c.row.blocks.iter().flat_map(|(_, b)| b.iter()))
        .filter(|x| **x != 0.0)
        .count();
    let (mut groups, mut lanes, mut last) = (0, 0, None);
    for c in comps {
        let offs: Vec<usize> = c.row.blocks.iter().map(|b| b.0).collect();
        if last.as_ref() == Some(&offs) && lanes < 4 {
            lanes += 1;
        } else {
            (groups, lanes, last) = (groups + 1, 1, Some(offs));
        }
    }
    (comps.len(), power, nonzeros, groups)
}

fn main() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    let mut models: Vec<(String, Model)> = vec![(
        "knee-column".into(),
        load_model(&path).expect("the example model loads"),
    )];
    for bodies in [2, 3, 4, 5, 6, 8] {
        let text = machine_tool::machine_tool_toml(bodies, 16);
        let model = parse_model(&text, Path::new("machine_tool.toml")).expect("generated model");
        models.push((format!("B = {bodies}"), model));
    }
    println!("model        n  comps power  nnz groups | plain ms: auto dense sparse | 16 sensitivities ms: auto dense sparse");
    for (name, model) in &models {
        let base = Simulator::new(model);
        let (params, wrt) = (model.nominal(), model.identified());
        let (comps, power, nonzeros, groups) = sizes(&base);
        let (mut plain, mut with) = (Vec::new(), Vec::new());
        for kernel in [Kernel::Auto, Kernel::Dense, Kernel::Sparse] {
            let mut sim = base.clone();
            sim.set_kernel(kernel);
            let (mut ws, mut out) = (Workspace::default(), sim.response_buffer());
            let mut sens = Sensitivities {
                wrt: Vec::new(),
                values: Vec::new(),
            };
            plain.push(median_ms(|| {
                sim.run(&params, &mut ws, &mut out).expect("runs");
            }));
            with.push(median_ms(|| {
                sim.run_with_sensitivities(&params, &wrt, &mut ws, &mut out, &mut sens)
                    .expect("runs");
            }));
        }
        println!(
            "{name:11} {:3} {comps:6} {power:5} {nonzeros:4} {groups:6} | {:8.2} {:5.2} {:6.2} | {:8.1} {:5.1} {:6.1}",
            model.bodies.len() * 6,
            plain[0],
            plain[1],
            plain[2],
            with[0],
            with[1],
            with[2]
        );
    }
}
