//! LP_τ plans (eq. 18–19) against an independently generated table, and
//! reproducible parallel plan evaluation.
#![allow(clippy::needless_range_loop)] // index loops mirror the formulas
use crate::problems;

use problems::{exp_decay, Diverged, FnProblem};
use rfeid::identification::plan::{lp_tau_plan, LpTau, PlanError, MAX_DIMENSIONS};
use rfeid::identification::plan_eval::evaluate_plan;
use rfeid::identification::problem::EvalError;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

fn reference_csv() -> Vec<Vec<f64>> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/sobol/sobol_joe_kuo_natural_d20_n1024.csv");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    assert!(header.starts_with("index,x1,"));
    lines
        .enumerate()
        .map(|(row, line)| {
            let fields: Vec<f64> = line.split(',').map(|f| f.trim().parse().unwrap()).collect();
            assert_eq!(fields[0], row as f64, "rows must be in index order");
            assert_eq!(fields.len(), 21);
            fields[1..].to_vec()
        })
        .collect()
}

#[test]
fn sobol_matches_joe_kuo_reference_exactly() {
    let reference = reference_csv();
    assert_eq!(reference.len(), 1024);
    let generator = LpTau::new(20).unwrap();
    // Point 0 is the origin (skipped by plans, but the generator knows it).
    let mut p = vec![0.0; 20];
    generator.point_into(0, &mut p);
    assert_eq!(p, reference[0]);
    // Plan point i is Sobol point i, bit for bit.
    let plan = lp_tau_plan(20, 1023).unwrap();
    assert_eq!(plan.len(), 1023);
    for k in 0..plan.len() {
        let i = plan.sobol_index(k) as usize;
        assert_eq!(i, k + 1);
        for j in 0..20 {
            assert!(
                plan.point(k)[j].to_bits() == reference[i][j].to_bits(),
                "point {i}, coordinate {}: {} != {}",
                j + 1,
                plan.point(k)[j],
                reference[i][j]
            );
        }
    }
}

#[test]
fn lower_dimensional_plans_are_projections() {
    let reference = reference_csv();
    let plan = lp_tau_plan(3, 100).unwrap();
    for (k, p) in plan.iter().enumerate() {
        assert_eq!(p, &reference[k + 1][..3]);
    }
}

#[test]
fn extending_a_plan_keeps_its_first_points() {
    let generator = LpTau::new(16).unwrap();
    let short = generator.plan(100).unwrap();
    let long = generator.plan(1000).unwrap();
    for k in 0..100 {
        assert_eq!(short.point(k), long.point(k));
    }
    // The extension by 900 points equals the tail of the long plan.
    let extension = generator.plan_range(101, 900).unwrap();
    for k in 0..900 {
        assert_eq!(extension.sobol_index(k), 101 + k as u64);
        assert_eq!(extension.point(k), long.point(100 + k));
    }
}

#[test]
fn plan_points_lie_in_the_open_box() {
    let plan = lp_tau_plan(MAX_DIMENSIONS, 64).unwrap();
    assert!(plan.iter().flatten().all(|&x| (0.0..1.0).contains(&x)));
    assert!(plan.point(0).iter().all(|&x| x == 0.5));
}

#[test]
fn bad_plan_requests_are_errors() {
    assert_eq!(lp_tau_plan(0, 10), Err(PlanError::NoDimensions));
    assert_eq!(lp_tau_plan(3, 0), Err(PlanError::NoPoints));
    assert_eq!(
        lp_tau_plan(MAX_DIMENSIONS + 1, 10),
        Err(PlanError::TooManyDimensions {
            requested: MAX_DIMENSIONS + 1,
            max: MAX_DIMENSIONS
        })
    );
    let g = LpTau::new(2).unwrap();
    assert!(matches!(
        g.plan_range(0, 5),
        Err(PlanError::IndexOutOfRange { .. })
    ));
    assert!(matches!(
        g.plan_range(1 << 53, 1),
        Err(PlanError::IndexOutOfRange { .. })
    ));
}

/// Exponential fit that "diverges" when the rate parameter u₂ > 0.8.
fn exp_decay_failing() -> FnProblem {
    let mut p = exp_decay();
    let inner = std::mem::replace(&mut p.residuals, Box::new(|_, _| Ok(())));
    p.residuals = Box::new(move |u, r| {
        if u[1] > 0.8 {
            return Err(Diverged(u.to_vec()));
        }
        inner(u, r)
    });
    p
}

#[test]
fn plan_evaluation_is_bit_identical_for_any_thread_count() {
    let problem = exp_decay_failing();
    let plan = lp_tau_plan(2, 257).unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let calls = AtomicUsize::new(0);
        let progress = || {
            calls.fetch_add(1, Ordering::Relaxed);
        };
        let evaluation = pool.install(|| evaluate_plan(&problem, &plan, Some(&progress)).unwrap());
        assert_eq!(calls.load(Ordering::Relaxed), plan.len());
        evaluation
    };
    let one = run(1);
    let two = run(2);
    assert_eq!(one.ranking, two.ranking);
    assert_eq!(one.n_failed, two.n_failed);
    for (a, b) in one.outcomes.iter().zip(&two.outcomes) {
        match (a, b) {
            (Ok(a), Ok(b)) => assert_eq!(a.to_bits(), b.to_bits()),
            (Err(a), Err(b)) => assert_eq!(a, b),
            _ => panic!("outcomes differ: {a:?} vs {b:?}"),
        }
    }
    // About a fifth of the points fail (u₂ > 0.8); they are counted, kept
    // with their error, and ranked last.
    let expected_failed = plan.iter().filter(|p| p[1] > 0.8).count();
    assert!(expected_failed > 30);
    assert_eq!(one.n_failed, expected_failed);
    for &k in &one.ranking[..plan.len() - expected_failed] {
        assert!(one.outcomes[k].is_ok());
    }
    for &k in &one.ranking[plan.len() - expected_failed..] {
        assert!(matches!(
            one.outcomes[k],
            Err(EvalError::Problem(Diverged(_)))
        ));
    }
    let costs: Vec<f64> = one.best_few(usize::MAX).iter().map(|b| b.1).collect();
    assert!(costs.windows(2).all(|w| w[0] <= w[1]));
    let (best, best_cost) = one.best().unwrap();
    assert_eq!(best, one.ranking[0]);
    assert_eq!(best_cost, costs[0]);
    assert!(!one.all_failed());
}

#[test]
fn plan_dimension_must_match_the_problem() {
    let plan = lp_tau_plan(3, 4).unwrap();
    assert_eq!(
        evaluate_plan(&exp_decay(), &plan, None).unwrap_err(),
        PlanError::DimensionMismatch {
            plan: 3,
            problem: 2
        }
    );
}

#[test]
fn an_extended_evaluation_equals_a_fresh_one() {
    let problem = exp_decay_failing();
    let generator = LpTau::new(2).unwrap();
    let mut evaluation = evaluate_plan(&problem, &generator.plan(50).unwrap(), None).unwrap();
    let extension = generator.plan_range(51, 150).unwrap();
    evaluation
        .append(evaluate_plan(&problem, &extension, None).unwrap())
        .unwrap();
    let fresh = evaluate_plan(&problem, &generator.plan(200).unwrap(), None).unwrap();
    assert_eq!(evaluation.plan, fresh.plan);
    assert_eq!(evaluation.outcomes, fresh.outcomes);
    assert_eq!(evaluation.ranking, fresh.ranking);
    assert_eq!(evaluation.n_failed, fresh.n_failed);
    // A plan that does not continue is refused.
    let gap = evaluate_plan(&problem, &generator.plan_range(300, 5).unwrap(), None).unwrap();
    assert!(matches!(
        evaluation.append(gap),
        Err(PlanError::NotContiguous {
            first: 300,
            expected: 201,
            ..
        })
    ));
}
