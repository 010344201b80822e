//! The paper's numerical example (§4) end to end: simulate the knee–column
//! benchmark, identify its 16 slideway parameters from the three knee
//! accelerations, and check the acceptance figures.
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use rfeid::identification::lm::LevenbergMarquardt;
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{identify, Settings, Silent};
use rfeid::identification::result::IdentificationResult;
use rfeid::io::model_file::load_model;
use rfeid::measurement::add_noise;
use rfeid::model::Model;
use rfeid::simulation::{Response, Simulator, Workspace};
use std::path::Path;

fn knee_column() -> Model {
    load_model(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml"))
        .expect("example loads")
}

fn data(model: &Model, noise: Option<(f64, u64)>) -> Response {
    let sim = Simulator::new(model);
    let mut out = sim.response_buffer();
    sim.run(&model.nominal(), &mut Workspace::default(), &mut out)
        .expect("simulates");
    if let Some((f, seed)) = noise {
        add_noise(&mut out, f, seed);
    }
    out
}

fn run(model: &Model, measured: Response) -> IdentificationResult {
    let settings = Settings {
        plan_points: 100,
        starts: 1,
        ..Settings::default()
    };
    identify(
        OutputError::new(Simulator::new(model), measured, 0),
        &settings,
        &Silent,
    )
    .expect("identifies")
}

/// Noise-free data: every parameter within 0.1 % of the truth (the paper:
/// ≤ 2.5 % on most, 11.4 % worst). The work is bounded too: a change that
/// doubles the iterations should fail here.
#[test]
fn noise_free_demo_recovers_every_parameter_within_a_tenth_of_a_percent() {
    let model = knee_column();
    let r = run(&model, data(&model, None));
    for p in &r.parameters {
        let err = (p.estimate - p.nominal).abs() / p.nominal;
        assert!(err < 1e-3, "{}: relative error {err:e}", p.name);
    }
    let worst = r
        .parameters
        .iter()
        .map(|p| ((p.estimate - p.nominal) / p.nominal).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "worst relative error {worst:e} after {} LM iterations",
        r.iterations
    );
    assert!(r.iterations <= 15, "{} LM iterations", r.iterations);
    // The work, not only the answer: 100 plan points, about one trial per
    // LM iteration, one Jacobian per accepted step plus the bounds (measured:
    // 107 simulations and 10 with sensitivities).
    assert!(r.simulations <= 125, "{} simulations", r.simulations);
    assert!(
        r.simulations_with_sensitivities <= 16,
        "{} simulations with sensitivities",
        r.simulations_with_sensitivities
    );
    assert_eq!(r.plan.failed, 0);
}

/// 2 % noise, seeds 1–5: at least 95 % of the 80 (parameter, seed) estimates
/// lie within 3 Cramér–Rao standard errors of the truth.
#[test]
fn noisy_demo_estimates_lie_within_three_standard_errors() {
    let model = knee_column();
    let (mut inside, mut total) = (0, 0);
    for seed in 1..=5 {
        let r = run(&model, data(&model, Some((0.02, seed))));
        for p in &r.parameters {
            let se = p.std_error.expect("standard errors");
            total += 1;
            if (p.estimate - p.nominal).abs() <= 3.0 * se {
                inside += 1;
            }
        }
    }
    eprintln!("{inside} of {total} estimates within 3 standard errors");
    assert_eq!(total, 80);
    assert!(
        inside as f64 >= 0.95 * total as f64,
        "{inside} of {total} within 3σ"
    );
}

/// Paper §4.2: Levenberg–Marquardt started from 20 random points of the box
/// reaches the truth within 0.1 % from at least 18 of them.
#[test]
fn lm_converges_from_random_starts() {
    let model = knee_column();
    let problem = OutputError::new(Simulator::new(&model), data(&model, None), 0);
    let truth: Vec<f64> = model
        .identified()
        .iter()
        .map(|&i| model.parameters[i].value)
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let starts: Vec<Vec<f64>> = (0..20)
        .map(|_| (0..16).map(|_| rng.random::<f64>()).collect())
        .collect();
    let reached: Vec<bool> = starts
        .par_iter()
        .map(
            |u0| match LevenbergMarquardt::default().minimize(&problem, u0) {
                Ok(r) => problem
                    .to_physical(&r.u)
                    .iter()
                    .zip(&truth)
                    .all(|(x, t)| ((x - t) / t).abs() < 1e-3),
                Err(_) => false,
            },
        )
        .collect();
    let ok = reached.iter().filter(|&&b| b).count();
    eprintln!("{ok} of 20 random starts reached the truth within 0.1 %");
    assert!(ok >= 18, "{ok} of 20 random starts reached the truth");
}

/// The paper's method, BFGS with finite-difference gradients (eq. 20–25),
/// reaches ≤ 1 % on every parameter of the noise-free demo.
#[test]
fn bfgs_reaches_one_percent_on_the_noise_free_demo() {
    use rfeid::identification::pipeline::Method;
    let model = knee_column();
    let settings = Settings {
        plan_points: 100,
        starts: 1,
        method: Method::Bfgs,
        ..Settings::default()
    };
    let r = identify(
        OutputError::new(Simulator::new(&model), data(&model, None), 0),
        &settings,
        &Silent,
    )
    .expect("identifies");
    let worst = r
        .parameters
        .iter()
        .map(|p| ((p.estimate - p.nominal) / p.nominal).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "BFGS: worst relative error {worst:e} after {} iterations",
        r.iterations
    );
    assert!(worst < 1e-2, "worst relative error {worst:e}");
}

/// The whole identification (plan, local search, bounds) gives bit-identical
/// results on one thread and on two.
#[test]
fn identification_does_not_depend_on_the_thread_count() {
    let model = knee_column();
    let measured = data(&model, Some((0.02, 7)));
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        let settings = Settings {
            plan_points: 24,
            starts: 2,
            ..Settings::default()
        };
        pool.install(|| {
            identify(
                OutputError::new(Simulator::new(&model), measured.clone(), 0),
                &settings,
                &Silent,
            )
        })
        .expect("identifies")
    };
    let (one, two) = (on(1), on(2));
    assert_eq!(one.criterion.to_bits(), two.criterion.to_bits());
    assert_eq!(one.plan.costs, two.plan.costs);
    // The same points abandoned (the plan's second batch has some).
    assert_eq!(one.plan.abandoned, two.plan.abandoned);
    assert!(!one.plan.abandoned.is_empty());
    for (a, b) in one.parameters.iter().zip(&two.parameters) {
        assert_eq!(a.estimate.to_bits(), b.estimate.to_bits(), "{}", a.name);
        assert_eq!(
            a.std_error.map(f64::to_bits),
            b.std_error.map(f64::to_bits),
            "{}",
            a.name
        );
    }
}

/// `--weights estimated`: with 2 % noise on every sensor, σ_c = 0.02·RMS_c,
/// so the estimated weights w_c = 1/σ_c² (scaled to a smallest of 1) follow
/// the ratios of the signals' mean squares, to within sampling error.
#[test]
fn estimated_weights_follow_each_sensors_noise() {
    use rfeid::identification::pipeline::Weighting;
    use rfeid::measurement::rms;
    let model = knee_column();
    let clean = data(&model, None);
    let measured = data(&model, Some((0.02, 11)));
    let settings = Settings {
        plan_points: 10,
        starts: 1,
        weighting: Weighting::EstimatedNoise,
        ..Settings::default()
    };
    let r = identify(
        OutputError::new(Simulator::new(&model), measured, 0),
        &settings,
        &Silent,
    )
    .expect("identifies");
    let inv_var: Vec<f64> = (0..3)
        .map(|c| 1.0 / (0.02 * rms(clean.sensor(c))).powi(2))
        .collect();
    let low = inv_var.iter().cloned().fold(f64::INFINITY, f64::min);
    for (c, (w, expect)) in r
        .weights
        .iter()
        .zip(inv_var.iter().map(|v| v / low))
        .enumerate()
    {
        // 3000 samples: the variance estimate is good to about 2·√(2/3000) ≈ 5 %.
        assert!(
            (w / expect - 1.0).abs() < 0.1,
            "sensor {c}: weight {w} vs {expect}"
        );
    }
    assert!(
        r.weights.iter().any(|w| *w > 10.0),
        "weights should differ: {:?}",
        r.weights
    );
}

/// `--from`: ignoring the first 50 ms (the start-up transient) still finds
/// the truth from noise-free data, from the remaining 2500 samples per sensor.
#[test]
fn fitting_from_a_later_time_uses_only_the_later_samples() {
    let model = knee_column();
    let settings = Settings {
        plan_points: 20,
        starts: 1,
        ..Settings::default()
    };
    let r = identify(
        OutputError::new(Simulator::new(&model), data(&model, None), 500),
        &settings,
        &Silent,
    )
    .expect("identifies");
    assert_eq!(r.observations, 3 * 2500);
    assert!((r.from - 0.05).abs() < 1e-12);
    for p in &r.parameters {
        let err = (p.estimate - p.nominal).abs() / p.nominal;
        assert!(err < 1e-3, "{}: relative error {err:e}", p.name);
    }
}
