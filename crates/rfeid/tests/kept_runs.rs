//! Runs kept between searches (`OutputError::keep_runs`): a search that
//! starts where the last one ended, under new sensor weights, takes its
//! first residuals and Jacobian from that one's runs. Its end is the same
//! bit for bit as with a new run, and it simulates once fewer; a clone, or
//! other steps per sample, keep nothing and simulate again. The last fit
//! (`OutputError::simulate_all`) is kept the same way.
use rfeid::identification::lm::{LevenbergMarquardt, LmResult};
use rfeid::identification::output_error::{ExperimentData, OutputError};
use rfeid::identification::problem::LeastSquares;
use rfeid::io::model_file::load_model;
use rfeid::measurement::add_noise;
use rfeid::model::Model;
use rfeid::simulation::{SimulationError, Simulator, StepChoice, Workspace};
use std::path::Path;

fn knee_column() -> Model {
    load_model(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml"))
        .expect("example loads")
}

/// The knee–column's criterion against its response with 2 % noise, one
/// experiment per seed of `seeds` (a campaign for several).
fn criterion<'m>(model: &'m Model, seeds: &[u64]) -> OutputError<'m> {
    let experiments = seeds
        .iter()
        .map(|&seed| {
            let sim = Simulator::new(model);
            let mut measured = sim.response_buffer();
            sim.run(&model.nominal(), &mut Workspace::default(), &mut measured)
                .expect("simulates");
            add_noise(&mut measured, 0.02, seed);
            ExperimentData {
                name: format!("e{seed}"),
                sim,
                measured,
                first: 0,
                weight: 1.0,
            }
        })
        .collect();
    OutputError::campaign(experiments)
}

fn search(problem: &OutputError<'_>, u0: &[f64]) -> LmResult<SimulationError> {
    LevenbergMarquardt::default()
        .minimize(problem, u0)
        .expect("the search runs")
}

/// Two searches on each of two criteria, one keeping its runs: the second
/// search starts where the first ended, under other sensor weights. The
/// second searches end the same bit for bit (point, J, residuals, Jacobian,
/// iterations), the keeping criterion with one run with sensitivities
/// fewer per experiment.
fn second_searches(seeds: &[u64]) {
    let model = knee_column();
    let (mut fresh, mut keeping) = (criterion(&model, seeds), criterion(&model, seeds));
    keeping.keep_runs(true);
    assert!(keeping.keeps_runs() && !fresh.keeps_runs());
    let u0 = vec![0.35; fresh.n_params()];
    let (a, b) = (search(&fresh, &u0), search(&keeping, &u0));
    assert_eq!(
        (a.u.clone(), a.cost),
        (b.u.clone(), b.cost),
        "first searches"
    );
    let weights: Vec<f64> = (0..fresh.weights().len())
        .map(|c| [1.0, 3.0, 0.5][c % 3])
        .collect();
    fresh.set_weights(&weights);
    keeping.set_weights(&weights);
    let (before_a, before_b) = (fresh.tally(), keeping.tally());
    assert_eq!(before_a, before_b);
    let (a2, b2) = (search(&fresh, &a.u), search(&keeping, &b.u));
    let (ran_a, ran_b) = (
        fresh.tally().with_sensitivities - before_a.with_sensitivities,
        keeping.tally().with_sensitivities - before_b.with_sensitivities,
    );
    eprintln!(
        "{} experiment(s): second search {} iterations, {ran_a} runs with sensitivities fresh, {ran_b} keeping",
        seeds.len(),
        a2.iterations
    );
    assert_eq!(a2.u, b2.u);
    assert_eq!(a2.cost.to_bits(), b2.cost.to_bits());
    assert_eq!(a2.residuals, b2.residuals);
    assert_eq!(a2.jacobian, b2.jacobian);
    assert_eq!(a2.history.len(), b2.history.len());
    assert_eq!(ran_b, ran_a - seeds.len(), "one run per experiment fewer");
}

#[test]
fn a_search_from_the_last_end_reuses_its_runs_bit_for_bit() {
    second_searches(&[1]);
}

#[test]
fn a_campaigns_search_from_the_last_end_reuses_every_experiments_runs() {
    second_searches(&[1, 2]);
}

/// A clone keeps no runs, and other steps per sample are another run: a
/// search there simulates again.
#[test]
fn a_clone_and_other_steps_keep_nothing() {
    let model = knee_column();
    let mut keeping = criterion(&model, &[1]);
    keeping.keep_runs(true);
    let u0 = vec![0.35; keeping.n_params()];
    let first = search(&keeping, &u0);
    let clone = keeping.clone();
    assert!(!clone.keeps_runs());
    let with_sens = |p: &OutputError<'_>| p.tally().with_sensitivities;
    let before = with_sens(&keeping);
    search(&clone, &first.u);
    assert!(with_sens(&keeping) > before, "the clone simulated");
    let before = with_sens(&keeping);
    let steps = keeping.experiment_simulator(0).steps();
    keeping.set_experiment_steps(
        0,
        StepChoice {
            substeps: steps.substeps + 1,
            ..steps
        },
    );
    let again = search(&keeping, &first.u);
    assert!(with_sens(&keeping) > before, "other steps simulated");
    assert!(again.cost.is_finite());
}

/// The residuals where the last run with sensitivities was kept (the
/// bounds' check at the estimate) are its response's, bit for bit those of
/// a plain run, with no simulation.
#[test]
fn residuals_at_a_kept_run_are_a_plain_runs_without_simulating() {
    let model = knee_column();
    let (fresh, mut keeping) = (criterion(&model, &[1, 2]), criterion(&model, &[1, 2]));
    keeping.keep_runs(true);
    let u0 = vec![0.35; fresh.n_params()];
    let end = search(&keeping, &u0);
    let n = fresh.n_residuals();
    let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
    fresh
        .residuals(&mut fresh.workspace(), &end.u, &mut a)
        .expect("simulates");
    let before = keeping.tally();
    keeping
        .residuals(&mut keeping.workspace(), &end.u, &mut b)
        .expect("kept");
    assert_eq!(keeping.tally(), before, "no simulation");
    assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()));
    assert_eq!(b, end.residuals);
}

/// A cancelled criterion fails at a kept run too, as at a new one.
#[test]
fn a_cancelled_criterion_fails_at_a_kept_run() {
    use rfeid::identification::cancel::Cancel;
    let model = knee_column();
    let mut keeping = criterion(&model, &[1]);
    keeping.keep_runs(true);
    let cancel = Cancel::default();
    keeping.set_cancel(cancel.clone());
    let u0 = vec![0.35; keeping.n_params()];
    let end = search(&keeping, &u0);
    cancel.set();
    let n = keeping.n_residuals();
    let mut r = vec![0.0; n];
    let failed = keeping.residuals(&mut keeping.workspace(), &end.u, &mut r);
    assert!(
        matches!(failed, Err(SimulationError::Cancelled)),
        "{failed:?}"
    );
}

/// A second fit at the same point (`OutputError::simulate_all`) takes the
/// first's responses, bit for bit, with no simulation. A clone, another
/// point and other steps per sample simulate again; a cancelled criterion
/// fails there as at a new point.
#[test]
fn a_fit_at_the_last_fits_point_takes_its_responses() {
    use rfeid::identification::cancel::Cancel;
    let model = knee_column();
    let mut problem = criterion(&model, &[1, 2]);
    let u = vec![0.4; problem.n_params()];
    let runs = |p: &OutputError<'_>| p.tally().simulations;
    let first = problem.simulate_all(&u).expect("simulates");
    let before = runs(&problem);
    let again = problem.simulate_all(&u).expect("kept");
    assert_eq!(runs(&problem), before, "no simulation");
    assert_eq!(bits(&first), bits(&again));
    problem.clone().simulate_all(&u).expect("simulates");
    assert_eq!(runs(&problem), before + 2, "the clone simulated");
    let mut other = u.clone();
    other[0] = 0.41;
    problem.simulate_all(&other).expect("simulates");
    assert_eq!(runs(&problem), before + 4, "another point simulated");
    let steps = problem.experiment_simulator(1).steps();
    problem.set_experiment_steps(
        1,
        StepChoice {
            substeps: steps.substeps + 1,
            ..steps
        },
    );
    problem.simulate_all(&other).expect("simulates");
    assert_eq!(runs(&problem), before + 6, "other steps simulated");
    let cancel = Cancel::default();
    problem.set_cancel(cancel.clone());
    cancel.set();
    let failed = problem.simulate_all(&other);
    assert!(
        matches!(failed, Err(SimulationError::Cancelled)),
        "{failed:?}"
    );
}

/// The fit at the end of a search whose runs are kept, at the chosen
/// steps, is the kept run's response: bit for bit a new run's, with no
/// simulation.
#[test]
fn the_fit_at_a_kept_run_is_its_response() {
    let model = knee_column();
    let (fresh, mut keeping) = (criterion(&model, &[1, 2]), criterion(&model, &[1, 2]));
    keeping.keep_runs(true);
    let u0 = vec![0.35; fresh.n_params()];
    let end = search(&keeping, &u0);
    let before = keeping.tally();
    let kept = keeping.simulate_all(&end.u).expect("kept");
    assert_eq!(keeping.tally(), before, "no simulation");
    let new = fresh.simulate_all(&end.u).expect("simulates");
    assert_eq!(bits(&kept), bits(&new));
}

/// The bits of every value of the responses `r`.
fn bits(r: &[rfeid::simulation::Response]) -> Vec<u64> {
    r.iter()
        .flat_map(|r| r.values.iter().map(|v| v.to_bits()))
        .collect()
}
