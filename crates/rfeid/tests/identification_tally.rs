//! Simulations are counted where they run: one per experiment and
//! evaluation, in a campaign too (a criterion at one point of a
//! three-experiment campaign is three simulations).
use nalgebra::DMatrix;
use rfeid::identification::output_error::{ExperimentData, OutputError};
use rfeid::identification::problem::LeastSquares;
use rfeid::identification::tally::Tally;
use rfeid::io::model_file::load_model;
use rfeid::model::Model;
use rfeid::simulation::{Simulator, Workspace};
use std::path::Path;

fn campaign() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/knee-column-campaign/model.toml");
    load_model(&path).expect("the campaign example loads")
}

#[test]
fn a_campaign_counts_one_simulation_per_experiment() {
    let model = campaign();
    let models: Vec<Model> = (0..model.experiments.len())
        .map(|e| model.for_experiment(e))
        .collect();
    let parts: Vec<ExperimentData> = models
        .iter()
        .enumerate()
        .map(|(e, m)| {
            let sim = Simulator::choose(m, &m.nominal()).expect("steps");
            let mut y = sim.response_buffer();
            sim.run(&m.nominal(), &mut Workspace::default(), &mut y)
                .expect("simulates");
            ExperimentData {
                name: model.experiments[e].name.clone(),
                sim,
                measured: y,
                first: 0,
                weight: 1.0,
            }
        })
        .collect();
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
