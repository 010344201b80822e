//! Sensitivities to many parameters are integrated in groups of
//! columns in parallel (issue 12, `simulation::columns`): the result does
//! not depend on the number of threads, nor on the grouping, bit for bit.
mod common;
mod machine_tool;

use common::model;
use rfeid::model::Model;
use rfeid::simulation::{Response, Sensitivities, Simulator, Workspace};

fn run(sim: &Simulator<'_>, model: &Model, wrt: &[usize]) -> (Response, Sensitivities) {
    let mut out = sim.response_buffer();
    let mut sens = Sensitivities {
        wrt: vec![],
        values: vec![],
    };
    let x = model.nominal();
    sim.run_with_sensitivities(&x, wrt, &mut Workspace::default(), &mut out, &mut sens)
        .unwrap_or_else(|e| panic!("{e}"));
    (out, sens)
}

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(f)
}

#[test]
fn many_sensitivities_are_identical_for_any_thread_count_and_grouping() {
    // A 10-body machine tool over 0.05 s with 40 identified parameters:
    // three groups of columns (16, 16, 8).
    let text = machine_tool::machine_tool_toml(10, 40).replace("\"0.3 s\"", "\"0.05 s\"");
    let model = model(&text);
    let wrt = model.identified();
    assert_eq!(wrt.len(), 40);
    let sim = Simulator::new(&model);
    let one = in_pool(1, || run(&sim, &model, &wrt));
    for threads in [2, 3] {
        let many = in_pool(threads, || run(&sim, &model, &wrt));
        assert!(one == many, "{threads} threads differ from one");
    }
    // Each group alone (one run, no grouping) gives the same columns, and
    // so does a group that straddles two of the fixed groups.
    let r = wrt.len();
    for cols in [0..16, 16..32, 32..40, 10..22] {
        let (out, part) = run(&sim, &model, &wrt[cols.clone()]);
        assert!(out == one.0, "the response of columns {cols:?} differs");
        let w = cols.len();
        for (row, got) in part.values.chunks_exact(w).enumerate() {
            assert!(
                got == &one.1.values[row * r + cols.start..row * r + cols.end],
                "columns {cols:?} differ at row {row}"
            );
        }
    }
}

#[test]
fn sixteen_sensitivities_split_over_two_threads_are_identical() {
    // 16 columns: one run of 16 on one thread, two groups of 8 on two, and
    // four groups of 4 on four (`simulation::columns::group_size`).
    let text = machine_tool::machine_tool_toml(10, 16).replace("\"0.3 s\"", "\"0.05 s\"");
    let model = model(&text);
    let wrt = model.identified();
    assert_eq!(wrt.len(), 16);
    let sim = Simulator::new(&model);
    let one = in_pool(1, || run(&sim, &model, &wrt));
    for threads in [2, 4] {
        let many = in_pool(threads, || run(&sim, &model, &wrt));
        assert!(one == many, "{threads} threads differ from one");
    }
}
