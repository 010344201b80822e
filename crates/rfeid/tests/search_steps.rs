//! The plan and the searches take the fewer steps per sample that the step
//! choice kept for them (`StepChoice::search`, `simulation::steps`
//! "Searches"), and the estimate is refined at the chosen steps: the same
//! plan ranking and the same minimum as an identification at the chosen
//! steps throughout; a plan point that the fewer steps cannot simulate is
//! evaluated at the chosen ones.
use crate::common;

use common::{model, simulate_nominal};
use nalgebra::DMatrix;
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{evaluate_points, identify, plan, Settings, Silent};
use rfeid::identification::problem::{evaluate_cost, sum_of_squares, LeastSquares};
use rfeid::identification::result::IdentificationResult;
use rfeid::identification::sensor_levels::{with_sensor_levels, SensorRows};
use rfeid::identification::uncertainty::{cramer_rao_mapped, CramerRao, UncertaintySettings};
use rfeid::identification::warning::Warning;
use rfeid::io::model_file::load_model;
use rfeid::measurement::add_noise;
use rfeid::model::Model;
use rfeid::simulation::steps::estimate_error;
use rfeid::simulation::{Response, SearchSteps, Simulator, StepChoice};
use std::path::Path;

fn noisy(model: &Model, seed: u64) -> Response {
    let mut out = simulate_nominal(model, None);
    add_noise(&mut out, 0.01, seed);
    out
}

/// `sim` without the fewer steps for searches: every stage at the chosen.
fn without_search_steps(mut sim: Simulator<'_>) -> Simulator<'_> {
    let steps = sim.steps();
    sim.set_steps(StepChoice {
        search: None,
        ..steps
    });
    sim
}

#[test]
fn the_searches_take_fewer_steps_and_end_at_the_chosen_steps_minimum() {
    // The knee–column at a tolerance of 1e-10: one step per sample misses
    // it (2.1e-9 at the nominal point) but meets the searches' 1e-8.
    let mut m = load_model(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml"),
    )
    .expect("example loads");
    m.sampling.duration = 0.3;
    m.sampling.tolerance = 1e-10;
    let sim = Simulator::new(&m);
    let steps = sim.steps();
    assert!(steps.substeps >= 2, "{steps:?}");
    assert_eq!(steps.search.map(|s| s.substeps), Some(1), "{steps:?}");

    let data = noisy(&m, 3);
    let settings = Settings {
        plan_points: 32,
        starts: 2,
        ..Settings::default()
    };
    let run = |sim| -> IdentificationResult {
        identify(OutputError::new(sim, data.clone(), 0), &settings, &Silent).expect("identifies")
    };
    let (fewer, chosen) = (run(Simulator::new(&m)), run(without_search_steps(sim)));

    // Both end at the chosen steps; only the first took fewer before.
    let (a, b) = (fewer.simulation.unwrap(), chosen.simulation.unwrap());
    assert_eq!(a.substeps, b.substeps);
    assert_eq!(a.search.map(|s| s.substeps), Some(1), "{a:?}");
    assert_eq!(b.search, None, "{b:?}");
    // The plan ranks its points the same at one step per sample.
    assert_eq!(fewer.plan.starts, chosen.plan.starts);
    // (Where both have it: a point may be abandoned, its J above the best
    // ones', at one step per sample and not at the chosen ones, or the
    // other way round.)
    assert_eq!((fewer.plan.failed, chosen.plan.failed), (0, 0));
    let mut compared = 0;
    for (x, y) in fewer.plan.costs.iter().zip(&chosen.plan.costs) {
        if let (Some(x), Some(y)) = (x, y) {
            assert!((x - y).abs() <= 1e-6 * y, "plan J {x} against {y}");
            compared += 1;
        }
    }
    assert!(compared >= 16, "{compared} plan points compared");
    // The reported J and standard errors are the chosen steps' at the
    // estimate (the bounds from the refining search's Jacobian); one step
    // per sample gives another J.
    let x: Vec<f64> = fewer.parameters.iter().map(|p| p.estimate).collect();
    let criterion = |sim| OutputError::new(sim, data.clone(), 0);
    let at_chosen = criterion(without_search_steps(Simulator::new(&m)));
    let mut one = Simulator::new(&m);
    one.use_search_steps();
    let (j_chosen, j_one) = (cost_at(&at_chosen, &x), cost_at(&criterion(one), &x));
    println!(
        "J reported {:.15e}, at the chosen steps {j_chosen:.15e}, at one step {j_one:.15e}",
        fewer.criterion
    );
    assert!((fewer.criterion - j_chosen).abs() <= 1e-13 * j_chosen);
    assert!((j_one - j_chosen).abs() > 1e-11 * j_chosen);
    // Measured: the same bit for bit.
    let fresh = cramer_rao_at(&at_chosen, &x);
    for (p, se) in fewer.parameters.iter().zip(&fresh.std_errors) {
        let rel = (p.std_error.unwrap() - se).abs() / se;
        assert!(
            rel <= 1e-14,
            "{}: {} against {se} ({rel:e})",
            p.name,
            p.std_error.unwrap()
        );
    }
    // Each search stops within √0.05 = 0.22 standard errors of the chosen
    // steps' minimum (the Gauss–Newton decrement test), so the two
    // estimates are within 0.45 of each other.
    for (p, q) in fewer.parameters.iter().zip(&chosen.parameters) {
        let (sp, sq) = (p.std_error.unwrap(), q.std_error.unwrap());
        let apart = (p.estimate - q.estimate).abs() / sq;
        println!(
            "{}: {:.9e} ± {sp:.4e} / {:.9e} ± {sq:.4e}: {apart:.2e} s.e. apart",
            p.name, p.estimate, q.estimate
        );
        assert!(apart <= 0.45, "{}", p.name);
        assert!((sp - sq).abs() <= 1e-2 * sq, "{}", p.name);
    }
}

/// J (eq. 16) of `problem` at the physical values `x`.
fn cost_at(problem: &OutputError<'_>, x: &[f64]) -> f64 {
    let u = problem.to_normalised(x);
    let mut r = vec![0.0; problem.n_residuals()];
    evaluate_cost(problem, &mut problem.workspace(), &u, &mut r).expect("evaluates")
}

/// The Cramér–Rao bounds (eq. 26–29) of `problem` at the physical values
/// `x`, from a simulation with sensitivities there, with each sensor's own
/// noise level as equal weights take it.
fn cramer_rao_at(problem: &OutputError<'_>, x: &[f64]) -> CramerRao {
    let u = problem.to_normalised(x);
    let (n, r) = (problem.n_residuals(), problem.n_params());
    let (mut res, mut jac) = (vec![0.0; n], DMatrix::zeros(n, r));
    problem
        .residuals_jacobian(&mut problem.workspace(), &u, &mut res, &mut jac)
        .expect("simulates");
    let settings = UncertaintySettings::default();
    let (dx_du, widths) = (problem.dx_du(&u), problem.widths());
    let bounds =
        cramer_rao_mapped(&jac, sum_of_squares(&res), &dx_du, widths, &settings).expect("bounds");
    let sensors = SensorRows::split(&jac, &res, &problem.weight_samples());
    with_sensor_levels(bounds, &sensors, &dx_du, widths, &settings)
}

/// One mass on a spring whose stiffness the plan spans over a factor of
/// 30: at its nominal value one step per sample nearly meets the
/// tolerance; near the top of the box one step per sample diverges.
const OSCILLATOR: &str = r#"
[simulation]
duration = 0.4
sample_rate = 1000.0

[[body]]
name = "mass"
mass = 1.0
inertia = [0.1, 0.1, 0.1]
com = [0.0, 0.0, 0.0]

[[element]]
name = "spring"
body = "mass"
to = "ground"
at = [0.0, 0.0, 0.0]
ux = { k = "k", c = 20.0 }
uy = { k = 1.0e6, c = 20.0 }
uz = { k = 1.0e6, c = 20.0 }
rx = { k = 1.0e5, c = 2.0 }
ry = { k = 1.0e5, c = 2.0 }
rz = { k = 1.0e5, c = 2.0 }

[[parameter]]
name = "k"
value = 2.2e6
min = 2.2e6
max = 6.6e7

[[excitation]]
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
signal = { type = "chirp", amplitude = 100.0, f0 = 10.0, f1 = 300.0 }

[[sensor]]
name = "a"
body = "mass"
at = [0.0, 0.0, 0.0]
direction = [1, 0, 0]
quantity = "acceleration"
"#;

#[test]
fn a_plan_point_the_fewer_steps_cannot_simulate_is_evaluated_at_the_chosen_steps() {
    let mut m = model(OSCILLATOR);
    // ωh ≈ 1.5 at the nominal k: one step per sample is accurate to e1;
    // a tolerance of e1/10 takes more, and keeps one for the searches.
    let e1 = estimate_error(&m, &m.nominal(), 1).expect("one step runs");
    m.sampling.tolerance = e1 / 10.0;
    let sim = Simulator::new(&m);
    assert_eq!(
        sim.steps().search,
        Some(SearchSteps {
            substeps: 1,
            estimated_error: e1
        })
    );
    let data = noisy(&m, 1);
    let settings = Settings {
        plan_points: 16,
        starts: 1,
        ..Settings::default()
    };
    let problem = OutputError::new(sim.clone(), data.clone(), 0);
    let plan = plan(&problem, &settings).unwrap();
    let all: Vec<usize> = (0..plan.len()).collect();
    let fewer = evaluate_points(&problem, &plan, &all, &Silent).unwrap();
    let at = |substeps: usize| {
        let mut sim = sim.clone();
        sim.set_steps(StepChoice {
            substeps,
            search: None,
            ..sim.steps()
        });
        let p = OutputError::new(sim, data.clone(), 0);
        evaluate_points(&p, &plan, &all, &Silent).unwrap()
    };
    let (one, chosen) = (at(1), at(sim.steps().substeps));
    let diverged = one.iter().filter(|o| o.outcome.is_err()).count();
    // ωh up to 1.5·√30 ≈ 8 at one step: beyond DOP853's 5.95.
    assert!(diverged > 0 && diverged < plan.len(), "{one:?}");
    for k in 0..plan.len() {
        let expected = match &one[k].outcome {
            Ok(_) => &one[k].outcome,
            Err(_) => &chosen[k].outcome,
        };
        assert!(chosen[k].outcome.is_ok(), "point {k}: {:?}", chosen[k]);
        assert_eq!(&fewer[k].outcome, expected, "point {k}");
        // The reach is the first evaluation's, at the searches' steps.
        assert_eq!(fewer[k].reach, one[k].reach, "point {k}");
    }
    // The same problem already at the searches' steps falls back alike.
    let mut searching = problem.clone();
    searching.use_search_steps();
    assert!(searching.searching());
    assert_eq!(
        evaluate_points(&searching, &plan, &all, &Silent).unwrap(),
        fewer
    );
}

#[test]
fn a_search_the_fewer_steps_cannot_simulate_runs_at_the_chosen_steps() {
    // The data come from k = 5e7, where one step per sample diverges (ωh ≈
    // 7.1); the steps are chosen at the model's value, 2.2e6, where one
    // step is nearly enough and is kept for the searches. The plan's best
    // points and every search lie where only the chosen steps run.
    let mut m = model(OSCILLATOR);
    let e1 = estimate_error(&m, &m.nominal(), 1).expect("one step runs");
    m.sampling.tolerance = e1 / 10.0;
    let sim = Simulator::new(&m);
    assert_eq!(sim.steps().search.map(|s| s.substeps), Some(1));
    let k_true = 5e7;
    let mut truth = m.clone();
    truth.parameters[0].value = k_true;
    let data = noisy(&truth, 2);
    let settings = Settings {
        plan_points: 16,
        starts: 2,
        ..Settings::default()
    };
    let r = identify(OutputError::new(sim, data, 0), &settings, &Silent).expect("identifies");
    assert!(r.failed_starts.is_empty(), "{:?}", r.failed_starts);
    let k = &r.parameters[0];
    let se = k.std_error.unwrap();
    println!("k = {:.6e} ± {se:.3e} (truth {k_true:e})", k.estimate);
    assert!((k.estimate - k_true).abs() <= 3.0 * se, "{k:?}");
    // Only the mode above the Nyquist frequency is named, no failed window.
    assert!(
        r.warnings
            .iter()
            .all(|w| matches!(w, Warning::AboveNyquist(_))),
        "{:?}",
        r.warnings
    );
}
