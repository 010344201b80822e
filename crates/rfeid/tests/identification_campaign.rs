//! A campaign identified (SPEC §5): the knee–column example at three force
//! levels with the contact exponent m identified, its data simulated at the
//! model's values with 2 % seeded noise, fitted together at `rfeid
//! identify`'s default settings (sum of eq. 16 over the experiments, the
//! Cramér–Rao bounds of the stacked Jacobian, eq. 26–29).
use crate::wide_cases;

use nalgebra::DMatrix;
use rfeid::identification::output_error::{ExperimentData, OutputError};
use rfeid::identification::pipeline::{identify, Silent};
use rfeid::identification::problem::LeastSquares;
use rfeid::identification::result::IdentificationResult;
use rfeid::identification::tally::Tally;
use rfeid::io::model_file::load_model;
use rfeid::measurement::add_noise;
use rfeid::model::Model;
use rfeid::simulation::{Simulator, Workspace};
use std::path::Path;

fn campaign() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/knee-column-campaign/model.toml");
    load_model(&path).expect("the campaign example loads")
}

/// The experiments `which` of `model` (their models in `models`),
/// simulated at the model's values, with 2 % noise of seed `10 seed + e`
/// (as `generate.sh` does) when `seed` is given.
fn experiments<'m>(
    model: &Model,
    models: &'m [Model],
    which: &[usize],
    seed: Option<u64>,
) -> Vec<ExperimentData<'m>> {
    which
        .iter()
        .zip(models)
        .map(|(&e, m)| {
            let sim = Simulator::choose(m, &m.nominal()).expect("steps");
            let mut y = sim.response_buffer();
            sim.run(&m.nominal(), &mut Workspace::default(), &mut y)
                .expect("simulates");
            if let Some(seed) = seed {
                add_noise(&mut y, 0.02, 10 * seed + e as u64);
            }
            ExperimentData {
                name: model.experiments[e].name.clone(),
                sim,
                measured: y,
                first: 0,
                weight: 1.0,
            }
        })
        .collect()
}

/// The experiments `which` of `model` with 2 % noise, identified.
fn identify_experiments(model: &Model, which: &[usize], seed: u64) -> IdentificationResult {
    let models: Vec<Model> = which.iter().map(|&e| model.for_experiment(e)).collect();
    let parts = experiments(model, &models, which, Some(seed));
    let settings = wide_cases::default_settings();
    identify(OutputError::campaign(parts), &settings, &Silent).expect("identifies")
}

fn estimate<'a>(
    r: &'a IdentificationResult,
    name: &str,
) -> &'a rfeid::identification::result::ParameterEstimate {
    r.parameters.iter().find(|p| p.name == name).expect(name)
}

fn correlation(r: &IdentificationResult, a: &str, b: &str) -> f64 {
    let i = r.parameters.iter().position(|p| p.name == a).unwrap();
    let j = r.parameters.iter().position(|p| p.name == b).unwrap();
    r.correlation.as_ref().expect("correlations")[i][j]
}

/// Three force levels: every estimate within 3 standard errors, the
/// contact coefficients told apart from m (correlations well below the
/// verdict's 0.99: the law is written about δ_ref = 1 µm), a trustworthy
/// verdict, and standard errors of a_n1 and m at least twice smaller than
/// from the 100 daN test alone.
#[test]
fn three_force_levels_pin_down_coefficient_and_exponent() {
    let model = campaign();
    assert_eq!(model.experiments.len(), 3);
    let all = identify_experiments(&model, &[0, 1, 2], 1);
    let (z, worst) = wide_cases::worst_z(&all);
    println!("three levels: worst {z:.2} s.e. ({worst})");
    assert!(z <= 3.0, "{worst} is {z:.2} standard errors off");
    let verdict = all.verdict.as_ref().expect("a verdict");
    assert!(verdict.trustworthy, "{verdict:?}");
    for a in ["a_n1", "a_n2", "a_n3", "a_n4"] {
        let c = correlation(&all, a, "m");
        println!("corr({a}, m) = {c:+.3}");
        assert!(c.abs() < 0.9, "{a} and m correlate at {c}");
    }
    let one = identify_experiments(&model, &[2], 1);
    for p in ["a_n1", "m"] {
        let (s3, s1) = (
            estimate(&all, p).std_error.unwrap(),
            estimate(&one, p).std_error.unwrap(),
        );
        println!("s.e. of {p}: three levels {s3:e}, 100 daN alone {s1:e}");
        assert!(
            s1 > 2.0 * s3,
            "{p}: {s3:e} from three levels, {s1:e} from one"
        );
    }
}

/// Simulations are counted where they run: one per experiment and
/// evaluation (a criterion at one point of this three-experiment campaign
/// is three simulations), shared by the criterion's clones.
#[test]
fn a_campaign_counts_one_simulation_per_experiment() {
    let model = campaign();
    let which: Vec<usize> = (0..model.experiments.len()).collect();
    let models: Vec<Model> = which.iter().map(|&e| model.for_experiment(e)).collect();
    let parts = experiments(&model, &models, &which, None);
    let n = parts.len();
    assert_eq!(n, 3);
    let problem = OutputError::campaign(parts);
    let clone = problem.clone();
    assert_eq!(problem.tally(), Tally::default());
    let u = vec![0.5; problem.n_params()];
    let mut ws = problem.workspace();
    let mut r = vec![0.0; problem.n_residuals()];
    problem.residuals(&mut ws, &u, &mut r).unwrap();
    assert_eq!(problem.tally(), Tally::plain(n));
    let mut jac = DMatrix::zeros(problem.n_residuals(), problem.n_params());
    problem
        .residuals_jacobian(&mut ws, &u, &mut r, &mut jac)
        .unwrap();
    clone.simulate_all(&u).unwrap();
    // Clones share the count.
    assert_eq!(
        problem.tally(),
        Tally {
            simulations: 2 * n,
            with_sensitivities: n,
            failed: 0
        }
    );
    // A failed evaluation is counted as such: a parameter that is not a
    // number fails every experiment's simulation (a shared parameter).
    let mut bad = u.clone();
    bad[0] = f64::NAN;
    let before = problem.tally();
    assert!(problem.residuals(&mut ws, &bad, &mut r).is_err());
    assert_eq!(
        problem.tally() - before,
        Tally {
            simulations: n,
            with_sensitivities: 0,
            failed: n
        }
    );
}
