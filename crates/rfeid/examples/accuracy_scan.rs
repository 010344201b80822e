//! Scans integrator settings on the knee–column benchmark against the
//! independent reference (tests/data/knee_column_reference.csv): relative RMS
//! error per sensor and run time.
use rfeid::io::model_file::load_model;
use rfeid::io::timeseries::read_csv;
use rfeid::simulation::tableau::{DOP853, RK4};
use rfeid::simulation::{Integrator, Simulator, Workspace};
use std::path::Path;
use std::time::Instant;

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let model = load_model(&root.join("../../examples/knee-column/model.toml")).expect("model");
    let reference =
        read_csv(&root.join("tests/data/knee_column_reference.csv")).expect("reference");
    let params = model.nominal();
    for (tableau, substeps) in [(RK4, 10), (DOP853, 1), (DOP853, 2)] {
        let sim = Simulator::with_integrator(
            &model,
            Integrator {
                tableau,
                substeps,
                locate_crossings: true,
            },
        );
        let mut ws = Workspace::default();
        let mut out = sim.response_buffer();
        let t0 = Instant::now();
        let reps = 20;
        for _ in 0..reps {
            sim.run(&params, &mut ws, &mut out).expect("run");
        }
        let dt = t0.elapsed().as_secs_f64() / reps as f64;
        let errs: Vec<String> = model
            .sensors
            .iter()
            .enumerate()
            .map(|(c, s)| {
                let r = reference.column(&s.name).unwrap();
                let y = out.sensor(c);
                let num: f64 = y.iter().zip(r).map(|(a, b)| (a - b).powi(2)).sum();
                let den: f64 = r.iter().map(|b| b * b).sum();
                format!("{:.2e}", (num / den).sqrt())
            })
            .collect();
        println!(
            "{:7} x{substeps:2}: {:7.2} ms  rel RMS err {}",
            tableau.name,
            dt * 1e3,
            errs.join(" ")
        );
    }
}
