//! Times one simulation of generated machine-tool models (issue 12), plain
//! and with the sensitivities to their identified parameters, next to the
//! knee–column in the same run, and prints medians of `REPS` runs (default
//! 3) as a table: `cargo run --release -p rfeid --example scaling -- B:R …`
//! (default `2:16 5:16 10:16 20:16 50:16 10:4 10:64`).
use rfeid::io::model_file::{load_model, parse_model};
use rfeid::model::Model;
use rfeid::simulation::{Sensitivities, Simulator, Workspace};
use std::path::Path;

#[path = "../tests/machine_tool/mod.rs"]
mod machine_tool;
mod support;
use support::median_ms;

/// `(steps per sample, plain ms, with-sensitivities ms)` of one model.
fn time_model(model: &Model, reps: usize) -> (usize, f64, f64) {
    let sim = Simulator::new(model);
    let (params, wrt) = (model.nominal(), model.identified());
    let (mut ws, mut out) = (Workspace::default(), sim.response_buffer());
    let mut sens = Sensitivities {
        wrt: Vec::new(),
        values: Vec::new(),
    };
    let plain = median_ms(reps, || sim.run(&params, &mut ws, &mut out).expect("runs"));
    let with = median_ms(reps, || {
        sim.run_with_sensitivities(&params, &wrt, &mut ws, &mut out, &mut sens)
            .expect("runs")
    });
    (sim.steps().substeps, plain, with)
}

fn main() {
    let reps: usize = std::env::var("REPS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3)
        .max(1);
    let mut cases: Vec<(usize, usize)> = std::env::args()
        .skip(1)
        .filter_map(|a| {
            let (b, r) = a.split_once(':')?;
            Some((b.parse().ok()?, r.parse().ok()?))
        })
        .filter(|&(b, _)| b >= 2)
        .collect();
    if cases.is_empty() {
        cases = vec![
            (2, 16),
            (5, 16),
            (10, 16),
            (20, 16),
            (50, 16),
            (10, 4),
            (10, 64),
        ];
    }
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    let knee = load_model(&path).expect("the example model loads");
    let (_, knee_plain, knee_with) = time_model(&knee, reps);
    println!("knee–column: {knee_plain:.2} ms plain, {knee_with:.1} ms with 16 sensitivities (medians of {reps})");
    println!("bodies  DOF  r  steps/sample  plain ms  ×knee  with r ms  ×plain");
    for (bodies, params) in cases {
        let text = machine_tool::machine_tool_toml(bodies, params);
        let model = parse_model(&text, Path::new("machine_tool.toml")).expect("generated model");
        let r = model.identified().len();
        let (steps, plain, with) = time_model(&model, reps);
        println!(
            "{bodies:>6} {:>4} {r:>2} {steps:>13} {plain:>9.1} {:>6.1} {with:>10.1} {:>7.1}",
            6 * bodies,
            plain / knee_plain,
            with / plain
        );
    }
}
