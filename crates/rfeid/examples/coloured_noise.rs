//! Coloured-noise cases of the knee–column benchmark, tabulated: for each
//! low-pass corner, noise level and seed, the RMS and largest |estimate −
//! truth| / standard error, the noise models' orders and the verdict; then
//! the totals over all cases.
//!
//! ```sh
//! cargo run --release -p rfeid --example coloured_noise -- [--seeds 10] [--corners 500,1000,2000] [--noise 0.01,0.02,0.03] [--white] [--exponent M]
//! ```
//!
//! The cases are those of `tests/coloured_cases` (identify's defaults),
//! each with its own noise stream (seed, level and corner);
//! `--white` models the noise as white (`--noise-model white`), for
//! comparison. A corner at or above 5000 Hz (the Nyquist frequency) adds
//! white noise. `--exponent M` identifies a wrong model from the same data:
//! the four slideway contacts' exponents fixed at M instead of 2 (its
//! verdicts should be suspect; its z-scores mean nothing).
#[path = "../tests/coloured_cases/mod.rs"]
mod coloured_cases;
#[path = "../tests/wide_cases/mod.rs"]
mod wide_cases;

use coloured_cases::{coloured_data, default_settings, knee_column, rms, run, z_scores};
use rfeid::identification::pipeline::NoiseModel;
use rfeid::identification::result::IdentificationResult;
use rfeid::identification::verdict::{is_fit_reason, Outcome};
use rfeid::model::{Law, Model, Power, Value};
use std::time::Instant;

fn list(v: String) -> Vec<f64> {
    v.split(',').map(|f| f.parse().expect("a number")).collect()
}

fn main() {
    let (mut seeds, mut corners, mut noises, mut white, mut exponent) = (
        10u64,
        vec![500.0, 1000.0, 2000.0],
        vec![0.01, 0.02, 0.03],
        false,
        None,
    );
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().expect("a value after the option");
        match a.as_str() {
            "--seeds" => seeds = value().parse().expect("a count"),
            "--corners" => corners = list(value()),
            "--noise" => noises = list(value()),
            "--white" => white = true,
            "--exponent" => exponent = Some(value().parse().expect("an exponent")),
            other => panic!("unknown argument {other}"),
        }
    }
    let model = knee_column();
    let fitted = exponent.map_or_else(|| model.clone(), |m| with_exponent(&model, m));
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
                let r = run(&fitted, data, &settings);
                let z = z_scores(&r);
                let orders: Vec<String> = r.noise.iter().map(|n| n.order.to_string()).collect();
                println!(
                    "{corner:9.0}  {noise:5.3}  {seed:4}  {:5.2}  {:7.2}  {:14}  {:11}  {:.2}",
                    rms(&z),
                    z.iter().cloned().fold(0.0, f64::max),
                    orders.join(","),
                    verdict(&r),
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

/// `model` with its power-law contacts' exponents fixed at `m`.
fn with_exponent(model: &Model, m: f64) -> Model {
    let mut wrong = model.clone();
    for c in wrong.elements.iter_mut().flat_map(|e| &mut e.components) {
        if let Law::Power(Power { m: e, .. }) = &mut c.law {
            *e = Value::Fixed(m);
        }
    }
    wrong
}

/// The verdict's outcome; a suspect one says whether the residual checks
/// failed too (`SUSPECT/fit`) or only other checks (bounds, minima, …).
fn verdict(r: &IdentificationResult) -> &'static str {
    let Some(v) = &r.verdict else {
        return "none";
    };
    match v.outcome() {
        Outcome::Trustworthy => "trustworthy",
        Outcome::ModelError => "MODEL ERROR",
        Outcome::Suspect if v.reasons.iter().any(is_fit_reason) => "SUSPECT/fit",
        Outcome::Suspect => "SUSPECT",
    }
}
