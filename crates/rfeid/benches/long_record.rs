//! One simulation of a one-body model with a long tabulated input: the
//! Silverbox example (105 712 samples of a measured voltage, a linear and a
//! cubic spring; `data/silverbox`), at the steps its tolerance
//! chooses. Criterion's throughput is in steps, so the time per step is
//! 1 / (elements per second). Run with `cargo bench -p rfeid --bench
//! long_record`.
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use rfeid::io::model_file::load_model;
use rfeid::simulation::{Simulator, Workspace};
use std::path::Path;

fn silverbox(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/silverbox/model.toml");
    let model = match load_model(&path) {
        Ok(model) => model,
        Err(e) => {
            eprintln!("skipped: the Silverbox example does not load ({e})");
            return;
        }
    };
    let sim = Simulator::new(&model);
    let params = model.nominal();
    let (mut ws, mut out) = (Workspace::default(), sim.response_buffer());
    let steps = (model.sampling.n_samples() - 1) * sim.steps().substeps;
    let mut group = c.benchmark_group("one_body_long_table");
    group.sample_size(20);
    group.throughput(Throughput::Elements(steps as u64));
    group.bench_function("simulate", |b| {
        b.iter(|| sim.run(&params, &mut ws, &mut out).expect("runs"))
    });
    group.finish();
}

criterion_group!(benches, silverbox);
criterion_main!(benches);
