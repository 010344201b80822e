//! The plan's early abandoning is exact: on a wide box, with points
//! abandoned, the best points and their J are those of the plan evaluated
//! to the end, bit for bit, on one thread and on two; a merge's replay of
//! points evaluated to the end abandons the same ones; and the running J
//! it stops on is a lower bound of J under sensor weights and whitening.
use crate::wide_cases::{data, example, widened};
use rfeid::identification::noise::ar::Whitener;
use rfeid::identification::noise::SensorWeighting;
use rfeid::identification::output_error::OutputError;
use rfeid::identification::pipeline::{
    evaluate_abandoning, evaluate_points, plan, replay, Evaluated, PointState, Settings, Silent,
};
use rfeid::identification::problem::{evaluate_cost, LeastSquares};
use rfeid::simulation::Simulator;

/// The best `keep` successful points, (index, J bits), best first, ties
/// in plan order.
fn best(outcomes: &[Option<f64>], keep: usize) -> Vec<(usize, u64)> {
    let mut ok: Vec<(usize, f64)> = outcomes
        .iter()
        .enumerate()
        .filter_map(|(k, c)| c.map(|c| (k, c)))
        .collect();
    ok.sort_by(|a, b| a.1.total_cmp(&b.1));
    ok.into_iter()
        .take(keep)
        .map(|(k, c)| (k, c.to_bits()))
        .collect()
}

#[test]
fn abandoning_keeps_the_best_points_and_their_j_bit_for_bit() {
    // The lathe (9 parameters, 1500 samples) on boxes 10 times wide.
    let model = widened(&example("lathe"), 10.0, 3);
    let measured = data(&model, 0.01, 5);
    let problem = OutputError::new(Simulator::new(&model), measured, 0);
    let settings = Settings {
        plan_points: 48,
        starts: 1,
        restarts: 2,
        ..Settings::default()
    };
    let keep = settings.starts + settings.restarts;
    let plan = plan(&problem, &settings).unwrap();
    let all: Vec<usize> = (0..plan.len()).collect();
    let whole = evaluate_points(&problem, &plan, &all, &Silent).unwrap();
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| evaluate_abandoning(&problem, &plan, keep, &Silent).unwrap())
    };
    let states = on(2);
    assert_eq!(states, on(1), "the threads changed what was abandoned");
    let abandoned = states
        .iter()
        .filter(|s| matches!(s, PointState::Abandoned { .. }))
        .count();
    assert!(abandoned >= 16, "{abandoned} of 48 abandoned");
    let full: Vec<Option<f64>> = whole.iter().map(|e| e.outcome.clone().ok()).collect();
    let kept: Vec<Option<f64>> = states
        .iter()
        .map(|s| match s {
            PointState::Done(Ok(c)) => Some(*c),
            _ => None,
        })
        .collect();
    assert_eq!(best(&kept, keep), best(&full, keep));
    let kth = f64::from_bits(best(&full, keep)[keep - 1].1);
    for (k, (s, e)) in states.iter().zip(&whole).enumerate() {
        match s {
            // Evaluated to the end: what the whole evaluation gave.
            PointState::Done(o) => assert_eq!(o, &e.outcome, "point {k}"),
            // Abandoned: J (if any) above its bound and the keep-th best.
            PointState::Abandoned { above } => {
                if let Ok(j) = e.outcome {
                    assert!(j > *above && *above >= kth, "point {k}: {j} {above} {kth}");
                }
            }
        }
    }
    // A merge replays the batches on the shards' whole evaluations.
    assert_eq!(replay(&whole, keep, problem.n_residuals()), states);
}

/// With sensor weights and whitening filters, a whole evaluation's J is
/// the criterion's own bit for bit, and the running J its checks saw
/// never exceeds it beyond rounding.
#[test]
fn the_running_j_is_a_lower_bound_under_weights_and_whitening() {
    let model = widened(&example("lathe"), 10.0, 4);
    let measured = data(&model, 0.01, 6);
    let mut problem = OutputError::new(Simulator::new(&model), measured, 0);
    let sensors = problem.weights().len();
    problem.set_weighting(&SensorWeighting {
        weights: (0..sensors).map(|c| 1.0 + 0.5 * c as f64).collect(),
        filters: (0..sensors)
            .map(|c| Whitener::new(&[-0.9 + 0.1 * c as f64, 0.2]))
            .collect(),
    });
    let plan = plan(
        &problem,
        &Settings {
            plan_points: 8,
            starts: 1,
            ..Settings::default()
        },
    )
    .unwrap();
    let all: Vec<usize> = (0..plan.len()).collect();
    let whole: Vec<Evaluated> = evaluate_points(&problem, &plan, &all, &Silent).unwrap();
    let (mut ws, mut r) = (problem.workspace(), vec![0.0; problem.n_residuals()]);
    let margin = 1.0 + 4.0 * problem.n_residuals() as f64 * f64::EPSILON;
    for (k, e) in whole.iter().enumerate() {
        let own =
            evaluate_cost(&problem, &mut ws, plan.point(k), &mut r).map_err(|e| e.to_string());
        assert_eq!(e.outcome, own, "point {k}");
        let j = own.expect("the lathe simulates");
        assert!(
            e.reach > 0.1 * j && e.reach <= j * margin,
            "point {k}: {} {j}",
            e.reach
        );
    }
}
