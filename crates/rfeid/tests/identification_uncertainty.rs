//! Cramér–Rao bounds (eq. 26–29) on linear models with closed-form answers.
#![allow(clippy::needless_range_loop)] // index loops mirror the formulas
use nalgebra::{DMatrix, DVector};
use rfeid::identification::uncertainty::{
    cramer_rao, cramer_rao_normalised, IdentifiabilityWarning, UncertaintyError,
    UncertaintySettings,
};

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs()
}

/// y = H x + e, H = [1 t] for t = 0..3: the straight-line fit, by hand.
#[test]
fn covariance_of_a_straight_line_fit_matches_the_closed_form() {
    let h = DMatrix::from_row_slice(4, 2, &[1.0, 0.0, 1.0, 1.0, 1.0, 2.0, 1.0, 3.0]);
    let x_true = DVector::from_column_slice(&[0.7, -0.2]);
    let e = DVector::from_column_slice(&[0.1, -0.2, 0.3, -0.1]);
    let y = &h * &x_true + &e;
    // Least-squares fit and its residual sum of squares.
    let x_hat = h.clone().svd(true, true).solve(&y, 1e-14).unwrap();
    let ssr = (&y - &h * &x_hat).norm_squared();
    // HᵀH = [[4, 6], [6, 14]], det 20, inverse [[0.7, −0.3], [−0.3, 0.2]];
    // s² = SSR / (N − r − 1) = SSR / 1.
    let s2 = ssr;
    let expected = [[0.7 * s2, -0.3 * s2], [-0.3 * s2, 0.2 * s2]];
    let cr = cramer_rao(&h, ssr, None, &UncertaintySettings::default()).unwrap();
    assert_eq!(cr.n_observations, 4);
    assert!(close(cr.s2, s2, 1e-15));
    for i in 0..2 {
        for j in 0..2 {
            assert!(
                close(cr.covariance[(i, j)], expected[i][j], 1e-12),
                "{}",
                cr.covariance
            );
        }
        assert!(close(cr.std_errors[i], expected[i][i].sqrt(), 1e-12));
        assert_eq!(cr.correlation[(i, i)], 1.0);
    }
    let corr = -0.3 / (0.7_f64 * 0.2).sqrt();
    assert!(close(cr.correlation[(0, 1)], corr, 1e-12));
    assert!(close(cr.correlation[(1, 0)], corr, 1e-12));
    assert!(cr.warnings.is_empty(), "{:?}", cr.warnings);
    // Scaled Fisher matrix [[1, c], [c, 1]], c = 6/√56: cond = (1+c)/(1−c).
    let c = 6.0 / 56f64.sqrt();
    assert!(close(cr.condition_number, (1.0 + c) / (1.0 - c), 1e-10));
    // Raw: eigenvalues of [[4, 6], [6, 14]] are 9 ± √61.
    let raw = (9.0 + 61f64.sqrt()) / (9.0 - 61f64.sqrt());
    assert!(close(cr.condition_number_raw, raw, 1e-10));
}

/// Columns in units 19 orders of magnitude apart (∂g/∂a ~ 1e-15 for
/// a ~ 1e15 N/m², ∂g/∂h ~ 1e-4 for h ~ 1e4 N·s/m) give the same answer,
/// scaled, to full precision.
#[test]
fn covariance_is_accurate_for_wildly_different_parameter_scales() {
    let h = DMatrix::from_row_slice(4, 2, &[1.0, 0.0, 1.0, 1.0, 1.0, 2.0, 1.0, 3.0]);
    let k = [1e-15, 1e-4];
    let hk = DMatrix::from_fn(4, 2, |i, j| h[(i, j)] * k[j]);
    let ssr = 0.5;
    let cr = cramer_rao(&hk, ssr, None, &UncertaintySettings::default()).unwrap();
    let base = [[0.7, -0.3], [-0.3, 0.2]];
    for i in 0..2 {
        for j in 0..2 {
            let expected = base[i][j] * ssr / (k[i] * k[j]);
            assert!(
                close(cr.covariance[(i, j)], expected, 1e-12),
                "{}",
                cr.covariance
            );
        }
    }
    assert!(close(cr.std_errors[0], (0.35f64).sqrt() * 1e15, 1e-12));
    // The scaled condition number ignores the units; the raw one does not.
    let c = 6.0 / 56f64.sqrt();
    assert!(close(cr.condition_number, (1.0 + c) / (1.0 - c), 1e-10));
    assert!(cr.condition_number_raw > 1e20);
}

#[test]
fn normalised_jacobian_gives_the_same_bounds() {
    // 3 parameters, N = 8; boxes of widths 2e15, 3, 5e4.
    let widths = [2e15, 3.0, 5e4];
    let hx = DMatrix::from_fn(8, 3, |i, j| {
        let t = i as f64 * 0.3;
        [(-t).exp() * 1e-15, (2.0 * t).sin(), t * t * 1e-4][j]
    });
    let hu = DMatrix::from_fn(8, 3, |i, j| -hx[(i, j)] * widths[j]);
    let settings = UncertaintySettings::default();
    let a = cramer_rao(&hx, 0.02, Some(&widths), &settings).unwrap();
    let b = cramer_rao_normalised(&hu, 0.02, &widths, &settings).unwrap();
    for i in 0..3 {
        for j in 0..3 {
            assert!(close(b.covariance[(i, j)], a.covariance[(i, j)], 1e-10));
        }
    }
}

#[test]
fn warnings_for_collinear_pairs_and_wide_standard_errors() {
    let c1 = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
    let c2 = [1.0, 2.001, 3.0, 3.999, 5.0, 6.002];
    let c3 = [1.0, 0.0, 1.0, 0.0, 1.0, 0.0];
    let h = DMatrix::from_fn(6, 3, |i, j| [c1[i], c2[i], c3[i]][j]);
    let widths = [1e3, 1e3, 1e-3];
    let cr = cramer_rao(&h, 0.1, Some(&widths), &UncertaintySettings::default()).unwrap();
    assert!(cr.correlation[(0, 1)] < -0.99);
    assert!(cr.warnings.iter().any(|w| matches!(
        w,
        IdentifiabilityWarning::StrongCorrelation { first: 0, second: 1, correlation, .. } if *correlation < -0.99
    )));
    // The combination the warning names, x0 − k x1, has the least variance
    // of all x0 − t x1 (var(t) = v00 − 2 t v01 + t² v11), and it is the one
    // stated, far below x0's own. (The direct form below cancels: its
    // relative rounding is about ε / (1 − ρ²), 1e-9 here.)
    let c = &cr.covariance;
    let rho = cr.correlation[(0, 1)];
    let tolerance = 100.0 * f64::EPSILON / (1.0 - rho * rho);
    let var = |t: f64| c[(0, 0)] - 2.0 * t * c[(0, 1)] + t * t * c[(1, 1)];
    let (k, se) = cr
        .warnings
        .iter()
        .find_map(|w| match w {
            IdentifiabilityWarning::StrongCorrelation {
                first: 0,
                second: 1,
                slope,
                combination_std_error,
                ..
            } => Some((*slope, *combination_std_error)),
            _ => None,
        })
        .unwrap();
    assert!(
        (var(k).sqrt() - se).abs() < tolerance * se,
        "{} vs {se}",
        var(k).sqrt()
    );
    for t in [0.99 * k, 1.01 * k] {
        assert!(var(t) > var(k));
    }
    assert!(se < 0.2 * cr.std_errors[0]);
    assert!(cr.warnings.iter().any(|w| matches!(
        w,
        IdentifiabilityWarning::StdErrorExceedsBox { index: 2, .. }
    )));
    assert!(!cr.warnings.iter().any(|w| matches!(
        w,
        IdentifiabilityWarning::StdErrorExceedsBox { index: 0 | 1, .. }
    )));
    // A threshold above |correlation| silences the warning.
    let above = 0.5 * (1.0 + cr.correlation[(0, 1)].abs());
    let loose = UncertaintySettings::default()
        .with_correlation_threshold(above)
        .unwrap();
    let cr = cramer_rao(&h, 0.1, None, &loose).unwrap();
    assert!(cr
        .warnings
        .iter()
        .all(|w| !matches!(w, IdentifiabilityWarning::StrongCorrelation { .. })));
}

#[test]
fn singular_fisher_matrix_names_the_parameters() {
    // Parameters 0 and 2 act identically (up to units).
    let h = DMatrix::from_fn(6, 3, |i, j| {
        let t = i as f64;
        [t, (t * 0.7).cos(), 1e-9 * t][j]
    });
    match cramer_rao(&h, 1.0, None, &UncertaintySettings::default()) {
        Err(UncertaintyError::Singular { parameters, .. }) => assert_eq!(parameters, vec![0, 2]),
        other => panic!("expected a singular Fisher matrix, got {other:?}"),
    }
    // A parameter the observations do not depend on at all.
    let mut h = DMatrix::from_fn(6, 3, |i, j| ((i + 1) as f64).powi(j as i32));
    h.column_mut(1).fill(0.0);
    assert_eq!(
        cramer_rao(&h, 1.0, None, &UncertaintySettings::default()),
        Err(UncertaintyError::Singular {
            parameters: vec![1],
            condition_number: f64::INFINITY
        })
    );
}

#[test]
fn invalid_inputs_are_typed_errors() {
    let s = UncertaintySettings::default();
    let h = DMatrix::from_fn(3, 2, |i, j| (i + j) as f64 + 1.0);
    assert_eq!(
        cramer_rao(&h, 1.0, None, &s),
        Err(UncertaintyError::TooFewObservations {
            n_observations: 3,
            n_parameters: 2
        })
    );
    let h = DMatrix::from_fn(5, 2, |i, j| ((i + 1) as f64).powi(j as i32));
    assert!(matches!(
        cramer_rao(&h, -1.0, None, &s),
        Err(UncertaintyError::InvalidSsr { .. })
    ));
    assert!(matches!(
        cramer_rao(&h, 1.0, Some(&[1.0]), &s),
        Err(UncertaintyError::BoxCountMismatch {
            expected: 2,
            got: 1
        })
    ));
    assert!(matches!(
        cramer_rao(&h, 1.0, Some(&[1.0, 0.0]), &s),
        Err(UncertaintyError::InvalidBoxWidth { index: 1, .. })
    ));
    let mut bad = h.clone();
    bad[(3, 1)] = f64::NAN;
    assert_eq!(
        cramer_rao(&bad, 1.0, None, &s),
        Err(UncertaintyError::NonFiniteJacobian { row: 3, column: 1 })
    );
    assert!(UncertaintySettings::default()
        .with_correlation_threshold(1.0)
        .is_err());
    assert!(UncertaintySettings::default()
        .with_condition_warning(0.5)
        .is_err());
}
