//! Levenberg–Marquardt on test problems with exact answers, with iteration
//! budgets (a change that doubles the work should fail here).
#![allow(clippy::needless_range_loop)] // index loops mirror the formulas
use crate::problems;

use problems::{
    exp_decay, linear, noisy_exp_decay, rosenbrock, to_normalised, Diverged, FnProblem, EXP_BOX,
    EXP_TRUE,
};
use rfeid::identification::lm::{LevenbergMarquardt, LmSettings};
use rfeid::identification::problem::EvalError;
use rfeid::identification::termination::{SolveError, StopReason};

fn report<E>(name: &str, r: &rfeid::identification::lm::LmResult<E>) {
    eprintln!(
        "{name}: {} after {} iterations, {} residual + {} Jacobian evaluations, {} failed, J = {:e}, u = {:?}",
        r.stop_reason,
        r.iterations,
        r.residual_evaluations,
        r.jacobian_evaluations,
        r.failed_evaluations,
        r.cost,
        r.u
    );
}

#[test]
fn lm_fits_exponential_decay_exactly() {
    let problem = exp_decay();
    let exact = to_normalised(&EXP_TRUE, &EXP_BOX);
    for u0 in [[0.1, 0.9], [0.9, 0.05], [0.5, 0.5]] {
        let result = LevenbergMarquardt::default()
            .minimize(&problem, &u0)
            .unwrap();
        report("exp decay", &result);
        assert!(result.stop_reason.is_converged(), "{}", result.stop_reason);
        for j in 0..2 {
            assert!((result.u[j] - exact[j]).abs() < 1e-10, "{:?}", result.u);
        }
        assert!(result.cost < 1e-20);
        assert!(result.iterations <= 15, "{} iterations", result.iterations);
        assert_eq!(result.failed_evaluations, 0);
        assert_eq!(result.history[0].u, u0.to_vec());
        // Each accepted iterate decreases J.
        assert!(result.history.windows(2).all(|w| w[1].cost < w[0].cost));
        // The Jacobian belongs to the final point.
        let mut jac = nalgebra::DMatrix::zeros(30, 2);
        (problem.jacobian)(&result.u, &mut jac);
        assert_eq!(jac, result.jacobian);
    }
}

#[test]
fn lm_solves_rosenbrock_in_a_box() {
    // Start at the classic (−1.2, 1).
    let result = LevenbergMarquardt::default()
        .minimize(&rosenbrock(), &[0.2, 0.75])
        .unwrap();
    report("rosenbrock", &result);
    assert!(result.stop_reason.is_converged());
    assert!((result.u[0] - 0.75).abs() < 1e-10 && (result.u[1] - 0.75).abs() < 1e-10);
    assert!(result.iterations <= 25, "{} iterations", result.iterations);
}

#[test]
fn lm_stops_on_the_bound_when_the_optimum_is_outside() {
    // r = (u1 − 1.5, u2 − 0.3, 0.1): the unconstrained optimum u1 = 1.5 lies
    // outside the box; the constrained one is (1, 0.3), J = 0.25 + 0.01.
    let problem = linear(vec![1.0, 0.0, 0.0, 1.0, 0.0, 0.0], vec![1.5, 0.3, -0.1], 2);
    let result = LevenbergMarquardt::default()
        .minimize(&problem, &[0.5, 0.5])
        .unwrap();
    report("outside", &result);
    assert_eq!(result.u[0], 1.0);
    // ConvergedCost stops when J no longer decreases by 1e-12 relative; the
    // remaining error of u2 is then ~ sqrt(1e-12 J) at most.
    assert!((result.u[1] - 0.3).abs() < 1e-6);
    assert!((result.cost - 0.26).abs() < 1e-12);
    assert!(result.stop_reason.is_converged(), "{}", result.stop_reason);
    assert!(result.iterations <= 10);
}

#[test]
fn lm_survives_a_failing_region() {
    // Optimum at u = 1.2 (outside), the model "diverges" for u > 0.95:
    // the search must stop inside the feasible region and count failures.
    let inner = linear(vec![1.0], vec![1.2], 1);
    let problem = FnProblem {
        n: 1,
        m: 1,
        residuals: Box::new(move |u, r| {
            if u[0] > 0.95 {
                Err(Diverged(u.to_vec()))
            } else {
                (inner.residuals)(u, r)
            }
        }),
        jacobian: Box::new(|_, jac| jac[(0, 0)] = 1.0),
    };
    let result = LevenbergMarquardt::default()
        .minimize(&problem, &[0.5])
        .unwrap();
    report("failing region", &result);
    assert!(result.failed_evaluations > 0);
    assert!(matches!(
        result.last_failure,
        Some(EvalError::Problem(Diverged(_)))
    ));
    assert!(result.u[0] <= 0.95 && result.u[0] > 0.9, "{:?}", result.u);
    assert_eq!(result.stop_reason, StopReason::EvaluationFailures);
}

#[test]
fn lm_reports_a_failed_start_and_bad_start_points() {
    let problem = FnProblem {
        n: 1,
        m: 1,
        residuals: Box::new(|u, _| Err(Diverged(u.to_vec()))),
        jacobian: Box::new(|_, _| {}),
    };
    let lm = LevenbergMarquardt::default();
    assert!(matches!(
        lm.minimize(&problem, &[0.5]),
        Err(SolveError::StartFailed(EvalError::Problem(_)))
    ));
    assert!(matches!(
        lm.minimize(&problem, &[0.5, 0.5]),
        Err(SolveError::StartDimension {
            expected: 1,
            got: 2
        })
    ));
    assert!(matches!(
        lm.minimize(&problem, &[1.5]),
        Err(SolveError::StartOutsideBox { index: 0, .. })
    ));
    assert!(matches!(
        lm.minimize(&problem, &[f64::NAN]),
        Err(SolveError::StartOutsideBox { index: 0, .. })
    ));
}

#[test]
fn lm_non_finite_residuals_count_as_failures() {
    // r = atan(10 (u − 0.2)), NaN for u > 0.5: from u = 0 the Gauss–Newton
    // step overshoots to 0.55, where the residual is NaN.
    let problem = FnProblem {
        n: 1,
        m: 1,
        residuals: Box::new(|u, r| {
            r[0] = if u[0] <= 0.5 {
                (10.0 * (u[0] - 0.2)).atan()
            } else {
                f64::NAN
            };
            Ok(())
        }),
        jacobian: Box::new(|u, jac| {
            let z = 10.0 * (u[0] - 0.2);
            jac[(0, 0)] = 10.0 / (1.0 + z * z);
        }),
    };
    let result = LevenbergMarquardt::default()
        .minimize(&problem, &[0.0])
        .unwrap();
    report("non-finite", &result);
    assert!(result.stop_reason.is_converged());
    assert!((result.u[0] - 0.2).abs() < 1e-12);
    assert!(result.failed_evaluations >= 1);
    assert_eq!(result.last_failure, Some(EvalError::NonFinite { index: 0 }));
}

#[test]
fn lm_observer_sees_every_iteration_and_iteration_limit_holds() {
    let settings = LmSettings::default().with_max_iterations(3).unwrap();
    let mut seen = Vec::new();
    let result = LevenbergMarquardt::new(settings)
        .minimize_observed(&rosenbrock(), &[0.2, 0.75], &mut |k, cost| {
            seen.push((k, cost))
        })
        .unwrap();
    assert_eq!(result.stop_reason, StopReason::MaxIterations);
    assert_eq!(result.iterations, 3);
    assert_eq!(
        seen.iter().map(|s| s.0).collect::<Vec<_>>(),
        vec![0, 1, 2, 3]
    );
    assert_eq!(seen.last().unwrap().1, result.cost);
}

#[test]
fn lm_settings_are_validated() {
    assert!(LmSettings::default().with_max_iterations(0).is_err());
    assert!(LmSettings::default().with_step_tolerance(-1.0).is_err());
    assert!(LmSettings::default().with_cost_tolerance(f64::NAN).is_err());
    assert!(LmSettings::default().with_initial_damping(1e20).is_err());
    let e = LmSettings::default()
        .with_gradient_tolerance(0.0)
        .unwrap_err();
    assert_eq!(e.name, "gradient_tolerance");
}

#[test]
fn lm_finds_a_constrained_optimum_on_a_face() {
    let (problem, exact) = problems::correlated_face();
    for u0 in [[1.0, 1.0], [0.0, 0.0], [0.5, 0.5]] {
        let result = LevenbergMarquardt::default()
            .minimize(&problem, &u0)
            .unwrap();
        report("face", &result);
        assert!(result.stop_reason.is_converged(), "{}", result.stop_reason);
        assert_eq!(result.u[0], 1.0);
        assert!(
            (result.u[1] - exact[1]).abs() < 1e-6,
            "{:?} vs {exact:?}",
            result.u
        );
        assert!(result.iterations <= 10);
    }
}

/// Convergence in standard errors (`LmSettings::with_decrement_tolerance`):
/// on noisy data the default search stops once the Gauss–Newton step would
/// lower J by less than 0.05 residual variances, which puts it within
/// √0.05 ≈ 0.22 standard errors (eq. 26's metric) of the minimum that a
/// search with the test off polishes to the other tolerances.
#[test]
fn lm_stops_within_a_fraction_of_a_standard_error_on_noisy_data() {
    let problem = noisy_exp_decay(0.05);
    let u0 = [0.9, 0.05];
    let fast = LevenbergMarquardt::default()
        .minimize(&problem, &u0)
        .unwrap();
    report("noisy exp decay, default", &fast);
    let off = LmSettings::default()
        .with_decrement_tolerance(f64::MIN_POSITIVE)
        .unwrap();
    let tight = LevenbergMarquardt::new(off)
        .minimize(&problem, &u0)
        .unwrap();
    report("noisy exp decay, test off", &tight);
    assert_eq!(fast.stop_reason, StopReason::ConvergedDecrement);
    assert!(fast.stop_reason.is_converged());
    assert!(
        tight.stop_reason.is_converged() && tight.stop_reason != StopReason::ConvergedDecrement
    );
    let s2 = tight.cost / (problem.m - problem.n) as f64;
    let d = nalgebra::DVector::from_iterator(2, fast.u.iter().zip(&tight.u).map(|(a, b)| a - b));
    let distance2 = (&tight.jacobian * d).norm_squared() / s2;
    eprintln!(
        "distance² {distance2:.3e} standard errors², {} against {} iterations",
        fast.iterations, tight.iterations
    );
    assert!(distance2 <= 0.05, "{distance2}");
    assert!(fast.iterations < tight.iterations);
}
