//! Sensitivities to many parameters are integrated in groups of
//! columns in parallel (issue 12, `simulation::columns`): the result does
//! not depend on the number of threads, nor on the grouping, bit for bit.
use crate::common;
use crate::machine_tool;

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

/// A 10-body machine tool over 0.05 s with `params` identified parameters.
fn short_machine_tool(params: usize) -> Model {
    let text = machine_tool::machine_tool_toml(10, params).replace("\"0.3 s\"", "\"0.05 s\"");
    let model = model(&text);
    assert_eq!(model.identified().len(), params);
    model
}

/// The run with sensitivities to every identified parameter on one thread,
/// checked to be the same bit for bit on each of `threads`.
fn same_on_threads(
    sim: &Simulator<'_>,
    model: &Model,
    threads: &[usize],
) -> (Response, Sensitivities) {
    let wrt = model.identified();
    let one = in_pool(1, || run(sim, model, &wrt));
    for &t in threads {
        let many = in_pool(t, || run(sim, model, &wrt));
        assert!(one == many, "{t} threads differ from one");
    }
    one
}

#[test]
fn many_sensitivities_are_identical_for_any_thread_count_and_grouping() {
    // A 10-body machine tool over 0.05 s with 40 identified parameters:
    // three groups of columns (16, 16, 8).
    let model = short_machine_tool(40);
    let wrt = model.identified();
    let sim = Simulator::new(&model);
    let one = same_on_threads(&sim, &model, &[2, 3]);
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
    let model = short_machine_tool(16);
    same_on_threads(&Simulator::new(&model), &model, &[2, 4]);
}
