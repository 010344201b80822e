//! Whether the FRF's 95 % band (delta method on the Cramér–Rao covariance,
//! `rfeid::frf::band`) is honest: over 200 seeds of the knee–column with 2 %
//! noise (each sensor's noise 2 % of its own RMS), identified from the
//! parameters' values, how often the true FRF lies inside the band at the
//! first two resonance peaks and three more frequencies; beside it, how
//! the estimates' errors compare with their standard errors (the z-scores'
//! spread per parameter, 1 if they are right). Both weightings: `identify`'s
//! default (each sensor weighted by its estimated noise, autoregressive
//! noise model) and `demo`'s (the paper's equal weights, eq. 14). Slow (200
//! identifications each): run by hand with
//! `cargo test --release -p rfeid --test integration -- frf_coverage --ignored --nocapture`.
//!
//! Measured (2026-11-28, 200 seeds each): estimated weights 92–95 % at the
//! five frequencies, z-score spreads 0.92–1.11; equal weights 92–94.5 %,
//! 0.89–1.09. Before the equal weights' bounds took each sensor's own noise
//! level (`rfeid::identification::sensor_levels`), eq. 26's single s² gave
//! 80.5–94 % and spreads of 0.5–1.4 there.
use rayon::prelude::*;
use rfeid::frf::{at_estimate, band, model_frf, Output, Z95};
use rfeid::identification::options::SearchOptions;
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{identify, Silent, Start, Weighting};
use rfeid::io::model_file::load_model;
use rfeid::measurement::add_noise;
use rfeid::simulation::{Simulator, Workspace};
use std::path::Path;

/// The first two resonances of the knee–column at rest (modes 1 and 2,
/// `rfeid modal`), a mode between them and two above.
const FREQUENCIES: [f64; 5] = [22.585, 26.561, 45.209, 53.232, 84.354];

/// Seeds per weighting.
const SEEDS: u64 = 200;

/// One seed: whether each sensor's band holds the true |H| at each
/// frequency, and each parameter's z-score `(x̂ − x) / s.e.`.
type Seed = (Vec<Vec<bool>>, Vec<f64>);

#[test]
#[ignore = "200 identifications: run by hand"]
fn with_estimated_weights_the_band_covers_the_true_frf_in_95_percent_of_seeds() {
    coverage(None);
}

#[test]
#[ignore = "200 identifications: run by hand"]
fn with_equal_weights_the_band_covers_the_true_frf_in_95_percent_of_seeds() {
    coverage(Some(Weighting::Equal));
}

/// The coverage and z-scores over [`SEEDS`] seeds with `weights`
/// (`None`: `identify`'s default), printed; asserts 92–98 % at the first
/// two resonances.
fn coverage(weights: Option<Weighting>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
    let model = load_model(&path).unwrap();
    let outputs = Output::sensors(&model);
    let truth = model_frf(&model, &model.nominal(), &[], &outputs, &FREQUENCIES).unwrap();
    let sim = Simulator::new(&model);
    let mut clean = sim.response_buffer();
    sim.run(&model.nominal(), &mut Workspace::default(), &mut clean)
        .unwrap();
    let settings = SearchOptions {
        start: Start::Values,
        weights,
        ..SearchOptions::default()
    }
    .settings();
    let runs: Vec<Seed> = (1..=SEEDS)
        .into_par_iter()
        .map(|seed| {
            let mut data = clean.clone();
            add_noise(&mut data, 0.02, seed);
            let problem = OutputError::new(Simulator::new(&model), data, 0);
            let r = identify(problem, &settings, &Silent).unwrap();
            let at = at_estimate(&r, &model, "").unwrap();
            let cov = at.covariance.unwrap();
            let est = model_frf(&model, &at.params, &at.wrt, &outputs, &FREQUENCIES).unwrap();
            let inside = (0..outputs.len())
                .map(|s| {
                    let p = est.pair(0, s);
                    let b = band(&est, p, &cov);
                    (0..FREQUENCIES.len())
                        .map(|k| {
                            let (h, t) = (est.values[p][k].norm(), truth.values[p][k].norm());
                            (t / h).ln().abs() <= Z95 * b.log_magnitude_sd[k]
                        })
                        .collect()
                })
                .collect();
            let z = (r.parameters.iter())
                .map(|p| (p.estimate - p.nominal) / p.std_error.unwrap())
                .collect();
            (inside, z)
        })
        .collect();
    let rate = |s: usize, k: usize| runs.iter().filter(|x| x.0[s][k]).count() as f64 / SEEDS as f64;
    eprintln!("weights {weights:?}: coverage of the true |H| by the 95 % band, {SEEDS} seeds:");
    for (s, out) in outputs.iter().enumerate() {
        let row: Vec<String> = (0..FREQUENCIES.len())
            .map(|k| format!("{:.1} Hz {:.1} %", FREQUENCIES[k], 100.0 * rate(s, k)))
            .collect();
        eprintln!("  {:<8} {}", out.name, row.join(", "));
    }
    let identified = model.identified();
    eprintln!("z-scores (x̂ − x)/s.e. per parameter: mean, standard deviation");
    for (j, &i) in identified.iter().enumerate() {
        let z: Vec<f64> = runs.iter().map(|x| x.1[j]).collect();
        let mean = z.iter().sum::<f64>() / z.len() as f64;
        let sd = (z.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (z.len() - 1) as f64).sqrt();
        eprintln!("  {:<6} {mean:+.2} {sd:.2}", model.parameters[i].name);
    }
    for (s, output) in outputs.iter().enumerate() {
        for (k, f) in FREQUENCIES.iter().take(2).enumerate() {
            let c = rate(s, k);
            assert!(
                (0.92..=0.98).contains(&c),
                "{} at {f} Hz: coverage {:.1} %",
                output.name,
                100.0 * c
            );
        }
    }
}
