//! Generated machine-tool models (issue 12) of B = 2, 10 and 50 bodies:
//! one simulation at the steps chosen for the default tolerance, with and
//! without sensitivities, next to the knee–column benchmark for ratios
//! measured in the same run. Run with
//! `cargo bench -p rfeid --bench machine_tool`.
use criterion::{criterion_group, criterion_main, Criterion};
use rfeid::io::model_file::{load_model, parse_model};
use rfeid::model::Model;
use rfeid::simulation::{Kernel, Sensitivities, Simulator, Workspace};
use std::path::Path;
use std::time::Duration;

#[path = "../tests/machine_tool/mod.rs"]
mod machine_tool;

/// Benchmarks one simulation of `model`, plain and with the sensitivities to
/// its identified parameters, as `name/simulate` and
/// `name/simulate_with_R_sensitivities`.
fn bench_model(c: &mut Criterion, name: &str, model: &Model) {
    let sim = Simulator::new(model);
    let params = model.nominal();
    let wrt = model.identified();
    let mut ws = Workspace::default();
    let mut out = sim.response_buffer();
    let mut sens = Sensitivities {
        wrt: Vec::new(),
        values: Vec::new(),
    };
    eprintln!(
        "{name}: {} bodies, {} parameters, {} steps per sample",
        model.bodies.len(),
        wrt.len(),
        sim.steps().substeps
    );
    let mut group = c.benchmark_group(name);
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(3));
    group.bench_function("simulate", |b| {
        b.iter(|| sim.run(&params, &mut ws, &mut out).expect("runs"))
    });
    let label = format!("simulate_with_{}_sensitivities", wrt.len());
    group.bench_function(label, |b| {
        b.iter(|| {
            sim.run_with_sensitivities(&params, &wrt, &mut ws, &mut out, &mut sens)
                .expect("runs")
        })
    });
    if model.bodies.len() >= 10 {
        // Today's dense kernel on the same model, for the gain.
        let mut dense = sim.clone();
        dense.set_kernel(Kernel::Dense);
        group.bench_function("simulate_dense", |b| {
            b.iter(|| dense.run(&params, &mut ws, &mut out).expect("runs"))
        });
    }
    group.finish();
}

fn machine_tools(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    let knee = load_model(&path).expect("the example model loads");
    bench_model(c, "knee_column_reference", &knee);
    for (bodies, params) in [(2, 16), (10, 16), (50, 64)] {
        let text = machine_tool::machine_tool_toml(bodies, params);
        let model = parse_model(&text, Path::new("machine_tool.toml")).expect("generated model");
        bench_model(c, &format!("machine_tool_{bodies}"), &model);
    }
}

criterion_group!(benches, machine_tools);
criterion_main!(benches);
