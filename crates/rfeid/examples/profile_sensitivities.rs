//! Runs the knee–column simulation with its 16 sensitivities `REPS` times
//! (default 10; `PLAIN=1` for the run without sensitivities, `COLUMNS=k`
//! for the first k of them only) and prints the
//! mean time: a target for a profiler (`valgrind --tool=callgrind`).
//! `MODEL=path/to/model.toml` profiles another model (with the
//! sensitivities to its identified parameters).
use rfeid::io::model_file::load_model;
use rfeid::simulation::{Sensitivities, Simulator, Workspace};
use std::path::{Path, PathBuf};
use std::time::Instant;

fn main() {
    let path = std::env::var_os("MODEL").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml"),
        PathBuf::from,
    );
    let model = load_model(&path).expect("model");
    let sim = Simulator::new(&model);
    let (params, mut wrt) = (model.nominal(), model.identified());
    if let Some(k) = std::env::var("COLUMNS").ok().and_then(|v| v.parse().ok()) {
        wrt.truncate(k);
    }
    let (mut ws, mut out) = (Workspace::default(), sim.response_buffer());
    let mut sens = Sensitivities {
        wrt: Vec::new(),
        values: Vec::new(),
    };
    let reps: usize = std::env::var("REPS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(10);
    let plain = std::env::var_os("PLAIN").is_some();
    let t0 = Instant::now();
    for _ in 0..reps {
        if plain {
            sim.run(&params, &mut ws, &mut out).expect("runs");
        } else {
            sim.run_with_sensitivities(&params, &wrt, &mut ws, &mut out, &mut sens)
                .expect("runs");
        }
    }
    let with = match plain {
        true => "plain".to_string(),
        false => format!("with {} sensitivities", wrt.len()),
    };
    let ms = t0.elapsed().as_secs_f64() * 1e3 / reps as f64;
    println!("{ms:.1} ms per run, {with}");
}
