//! Coloured-noise cases of the knee–column benchmark, tabulated: for each
//! low-pass corner, noise level and seed, the RMS and largest |estimate −
//! truth| / standard error, the noise models' orders and the verdict; then
//! the totals over all cases.
//!
//! ```sh
//! cargo run --release -p rfeid --example coloured_noise -- [--seeds 10] [--corners 500,1000,2000] [--noise 0.01,0.02,0.03] [--white]
//! ```
//!
//! The cases are those of `tests/coloured_cases` (identify's defaults),
//! each with its own noise stream (seed, level and corner);
//! `--white` models the noise as white (`--noise-model white`), for
//! comparison. A corner at or above 5000 Hz (the Nyquist frequency) adds
//! white noise.
#[path = "../tests/coloured_cases/mod.rs"]
mod coloured_cases;

use coloured_cases::{coloured_data, default_settings, knee_column, rms, run, z_scores};
use rfeid::identification::pipeline::NoiseModel;
use std::time::Instant;

fn list(v: String) -> Vec<f64> {
    v.split(',').map(|f| f.parse().expect("a number")).collect()
}

fn main() {
    let (mut seeds, mut corners, mut noises, mut white) = (
        10u64,
        vec![500.0, 1000.0, 2000.0],
        vec![0.01, 0.02, 0.03],
        false,
    );
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().expect("a value after the option");
        match a.as_str() {
            "--seeds" => seeds = value().parse().expect("a count"),
            "--corners" => corners = list(value()),
            "--noise" => noises = list(value()),
            "--white" => white = true,
            other => panic!("unknown argument {other}"),
        }
    }
    let model = knee_column();
    let mut settings = default_settings();
    if white {
        settings.noise_model = NoiseModel::White;
    }
    println!("corner Hz  noise  seed  RMS z  worst z  AR orders       verdict      s");
    let (mut all, mut trusted, mut cases) = (Vec::new(), 0, 0);
    for (i, &corner) in corners.iter().enumerate() {
        for (j, &noise) in noises.iter().enumerate() {
            for seed in 1..=seeds {
                // Every case its own noise: the levels are not one record scaled.
                let stream = seed + 1000 * (j as u64 + 1) + 1_000_000 * (i as u64 + 1);
                let data = coloured_data(&model, noise, corner, stream);
                let t = Instant::now();
                let r = run(&model, data, &settings);
                let z = z_scores(&r);
                let orders: Vec<String> = r.noise.iter().map(|n| n.order.to_string()).collect();
                println!(
                    "{corner:9.0}  {noise:5.3}  {seed:4}  {:5.2}  {:7.2}  {:14}  {:11}  {:.2}",
                    rms(&z),
                    z.iter().cloned().fold(0.0, f64::max),
                    orders.join(","),
                    if r.is_suspect() {
                        "SUSPECT"
                    } else {
                        "trustworthy"
                    },
                    t.elapsed().as_secs_f64()
                );
                trusted += usize::from(!r.is_suspect());
                cases += 1;
                all.extend(z);
            }
        }
    }
    println!(
        "all {cases} cases: RMS z {:.3}, worst z {:.2}, {trusted} of {cases} trustworthy",
        rms(&all),
        all.iter().cloned().fold(0.0, f64::max)
    );
}
