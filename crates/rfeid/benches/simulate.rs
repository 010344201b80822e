//! One knee–column simulation (SPEC §4), with and without the sensitivities
//! to its 16 identified parameters. Run with `cargo bench -p rfeid`; pin to
//! one core with `taskset -c 0` for the single-core figures.
use criterion::{criterion_group, criterion_main, Criterion};
use rfeid::io::model_file::load_model;
use rfeid::simulation::{Sensitivities, Simulator, Workspace};
use std::path::Path;

fn knee_column(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    let model = load_model(&path).expect("the example model loads");
    let sim = Simulator::new(&model);
    let params = model.nominal();
    let wrt = model.identified();
    let mut ws = Workspace::default();
    let mut out = sim.response_buffer();
    let mut sens = Sensitivities {
        wrt: Vec::new(),
        values: Vec::new(),
    };
    let mut group = c.benchmark_group("knee_column");
    group.sample_size(20);
    group.bench_function("simulate", |b| {
        b.iter(|| sim.run(&params, &mut ws, &mut out).expect("runs"))
    });
    group.bench_function("simulate_with_16_sensitivities", |b| {
        b.iter(|| {
            sim.run_with_sensitivities(&params, &wrt, &mut ws, &mut out, &mut sens)
                .expect("runs")
        })
    });
    group.finish();
}

criterion_group!(benches, knee_column);
criterion_main!(benches);
