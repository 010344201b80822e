//! Times the pieces of one Runge–Kutta stage on the knee–column model.
use rfeid::io::model_file::load_model;
use rfeid::simulation::Simulator;
use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

fn main() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    let model = load_model(&path).expect("model");
    let sim = Simulator::new(&model);
    let sys = sim.system(&model.nominal()).expect("system");
    let n = sys.n;
    let y: Vec<f64> = (0..2 * n)
        .map(|i| 1e-7 * ((i as f64) * 0.7).sin())
        .collect();
    let mut acc = vec![0.0; n];
    let mut scratch = vec![0.0; sys.scratch_len()];
    let mut forces = vec![0.0; 1];
    let reps: usize = std::env::var("REPS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1_000_000);
    let t0 = Instant::now();
    for i in 0..reps {
        sys.accel(black_box(&forces), black_box(&y), &mut scratch, &mut acc);
        black_box(&acc);
        forces[0] = i as f64;
    }
    println!(
        "accel: {:.1} ns",
        t0.elapsed().as_secs_f64() * 1e9 / reps as f64
    );
    let t0 = Instant::now();
    for i in 0..reps {
        sys.forces(black_box(i as f64 * 1e-5), &mut forces);
        black_box(&forces);
    }
    println!(
        "forces: {:.1} ns",
        t0.elapsed().as_secs_f64() * 1e9 / reps as f64
    );
}
