//! The BFGS of eq. 20–25 (finite-difference gradients, line search, box) on
//! test problems with exact answers, with iteration budgets.
#![allow(clippy::needless_range_loop)] // index loops mirror the formulas
use crate::problems;

use nalgebra::{DMatrix, DVector};
use problems::{
    exp_decay, linear, rosenbrock, to_normalised, Diverged, FnProblem, EXP_BOX, EXP_TRUE,
};
use rfeid::identification::bfgs::{Bfgs, BfgsResult, BfgsSettings};
use rfeid::identification::problem::EvalError;
use rfeid::identification::termination::{SolveError, StopReason};

fn report<E>(name: &str, r: &BfgsResult<E>) {
    eprintln!(
        "{name}: {} after {} iterations, {} evaluations ({} gradients, {} in line searches), {} failed, J = {:e}, u = {:?}",
        r.stop_reason,
        r.iterations,
        r.cost_evaluations,
        r.gradient_evaluations,
        r.line_search_evaluations,
        r.failed_evaluations,
        r.cost,
        r.u
    );
}

#[test]
fn bfgs_fits_exponential_decay() {
    let problem = exp_decay();
    let exact = to_normalised(&EXP_TRUE, &EXP_BOX);
    for u0 in [[0.1, 0.9], [0.9, 0.05], [0.5, 0.5]] {
        let result = Bfgs::default().minimize(&problem, &u0).unwrap();
        report("exp decay", &result);
        assert!(result.stop_reason.is_converged(), "{}", result.stop_reason);
        for j in 0..2 {
            assert!((result.u[j] - exact[j]).abs() < 1e-6, "{:?}", result.u);
        }
        assert!(result.iterations <= 60, "{} iterations", result.iterations);
        assert_eq!(result.failed_evaluations, 0);
        assert!(result.history.windows(2).all(|w| w[1].cost < w[0].cost));
        assert_eq!(
            result.cost_evaluations,
            1 + 4 * result.gradient_evaluations + result.line_search_evaluations
        );
    }
}

/// A least-squares quadratic in 4 variables with a non-zero residual at its
/// minimum, which lies inside the box.
fn quadratic() -> (FnProblem, Vec<f64>) {
    let a = vec![
        2.0, 0.3, -0.5, 0.1, //
        0.4, 1.5, 0.2, -0.3, //
        -0.2, 0.6, 3.0, 0.5, //
        0.1, -0.4, 0.3, 0.8, //
        1.0, 1.0, 0.0, 0.0, //
        0.0, 0.5, 0.5, 1.0,
    ];
    let b = vec![0.9, 1.1, 1.6, 0.5, 0.8, 1.2];
    let am = DMatrix::from_row_slice(6, 4, &a);
    let exact = am
        .clone()
        .svd(true, true)
        .solve(&DVector::from_column_slice(&b), 1e-14)
        .unwrap();
    (linear(a, b, 4), exact.iter().copied().collect())
}

#[test]
fn bfgs_minimises_a_quadratic_in_about_n_iterations() {
    let (problem, exact) = quadratic();
    assert!(exact.iter().all(|&x| x > 0.05 && x < 0.95), "{exact:?}");
    let result = Bfgs::default().minimize(&problem, &[0.5; 4]).unwrap();
    report("quadratic", &result);
    assert_eq!(result.stop_reason, StopReason::ConvergedGradient);
    for j in 0..4 {
        assert!(
            (result.u[j] - exact[j]).abs() < 1e-7,
            "{:?} vs {exact:?}",
            result.u
        );
    }
    assert!(
        result.iterations <= 4 + 2,
        "{} iterations",
        result.iterations
    );
}

#[test]
fn bfgs_paper_variant_without_scaling_also_converges() {
    let (problem, exact) = quadratic();
    let settings = BfgsSettings::default().with_scale_initial_inverse_hessian(false);
    let result = Bfgs::new(settings).minimize(&problem, &[0.5; 4]).unwrap();
    report("quadratic, B0 = I", &result);
    assert!(result.stop_reason.is_converged());
    for j in 0..4 {
        assert!((result.u[j] - exact[j]).abs() < 1e-7);
    }
    assert!(
        result.iterations <= 4 + 2,
        "{} iterations",
        result.iterations
    );
}

#[test]
fn bfgs_solves_rosenbrock_in_a_box() {
    let result = Bfgs::default()
        .minimize(&rosenbrock(), &[0.2, 0.75])
        .unwrap();
    report("rosenbrock", &result);
    assert!(result.stop_reason.is_converged(), "{}", result.stop_reason);
    assert!((result.u[0] - 0.75).abs() < 1e-6 && (result.u[1] - 0.75).abs() < 1e-6);
    assert!(result.iterations <= 100, "{} iterations", result.iterations);
}

#[test]
fn bfgs_stops_on_the_bound_when_the_optimum_is_outside() {
    let problem = linear(vec![1.0, 0.0, 0.0, 1.0, 0.0, 0.0], vec![1.5, 0.3, -0.1], 2);
    let result = Bfgs::default().minimize(&problem, &[0.5, 0.5]).unwrap();
    report("outside", &result);
    assert_eq!(result.u[0], 1.0);
    assert!((result.u[1] - 0.3).abs() < 1e-7);
    assert!(result.stop_reason.is_converged(), "{}", result.stop_reason);
    let pg = result.projected_gradient.unwrap();
    assert_eq!(pg[0], 0.0);
    assert!(result.iterations <= 10);
}

#[test]
fn bfgs_survives_a_failing_region() {
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
    let result = Bfgs::default().minimize(&problem, &[0.5]).unwrap();
    report("failing region", &result);
    assert!(result.failed_evaluations > 0);
    assert!(matches!(
        result.last_failure,
        Some(EvalError::Problem(Diverged(_)))
    ));
    assert!(result.u[0] <= 0.95 && result.u[0] > 0.9, "{:?}", result.u);
    assert!(
        matches!(
            result.stop_reason,
            StopReason::EvaluationFailures
                | StopReason::GradientUnavailable
                | StopReason::ConvergedStep
        ),
        "{}",
        result.stop_reason
    );
}

#[test]
fn bfgs_is_bit_identical_for_any_thread_count() {
    let problem = exp_decay();
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| Bfgs::default().minimize(&problem, &[0.1, 0.9]).unwrap())
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one.history, two.history);
    assert_eq!(one.u, two.u);
}

#[test]
fn bfgs_observer_and_limits() {
    let settings = BfgsSettings::default().with_max_iterations(2).unwrap();
    let mut seen = Vec::new();
    let result = Bfgs::new(settings)
        .minimize_observed(&rosenbrock(), &[0.2, 0.75], &mut |k, _| seen.push(k))
        .unwrap();
    assert_eq!(result.stop_reason, StopReason::MaxIterations);
    assert_eq!(seen, vec![0, 1, 2]);
    assert!(matches!(
        Bfgs::default().minimize(&rosenbrock(), &[0.2]),
        Err(SolveError::StartDimension {
            expected: 2,
            got: 1
        })
    ));
    assert!(BfgsSettings::default().with_fd_step(0.5).is_err());
    assert!(BfgsSettings::default().with_initial_step(1.0).is_err());
    assert!(BfgsSettings::default()
        .with_line_search_max_evaluations(1)
        .is_err());
}

#[test]
fn bfgs_finds_a_constrained_optimum_on_a_face() {
    let (problem, exact) = problems::correlated_face();
    for u0 in [[1.0, 1.0], [0.0, 0.0], [0.5, 0.5]] {
        let result = Bfgs::default().minimize(&problem, &u0).unwrap();
        report("face", &result);
        assert!(result.stop_reason.is_converged(), "{}", result.stop_reason);
        assert_eq!(result.u[0], 1.0);
        assert!(
            (result.u[1] - exact[1]).abs() < 1e-6,
            "{:?} vs {exact:?}",
            result.u
        );
        assert!(result.iterations <= 20);
    }
}
