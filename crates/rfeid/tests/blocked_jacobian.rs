//! The Jacobian's triangular factor accumulated by blocks of rows
//! (`identification::blocked_qr`, issue 12 §3) against the QR of the whole
//! Jacobian, and one linear problem whose whole Jacobian would exceed a
//! memory cap, solved within it.
use nalgebra::{DMatrix, DVector};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use rfeid::identification::blocked_qr::{jacobian_bytes, BlockedQr};
use rfeid::identification::uncertainty::{
    cramer_rao_blocked, cramer_rao_mapped, UncertaintySettings,
};

/// Seeded tall Jacobian with columns of norms 10⁻⁶ … 10⁶ and two nearly
/// parallel columns (correlation ≈ 0.999), and residuals.
fn tall_problem(n_rows: usize, n_cols: usize, seed: u64) -> (DMatrix<f64>, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut jac = DMatrix::from_fn(n_rows, n_cols, |_, _| StandardNormal.sample(&mut rng));
    for i in 0..n_rows {
        let e: f64 = StandardNormal.sample(&mut rng);
        jac[(i, 1)] = jac[(i, 0)] + 0.04 * e;
    }
    for j in 0..n_cols {
        let scale = 10f64.powf(-6.0 + 12.0 * j as f64 / (n_cols - 1) as f64);
        jac.column_mut(j).scale_mut(scale);
    }
    let res = (0..n_rows)
        .map(|_| StandardNormal.sample(&mut rng))
        .collect();
    (jac, res)
}

fn max_rel(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / x.abs().max(y.abs()).max(f64::MIN_POSITIVE))
        .fold(0.0, f64::max)
}

#[test]
fn blocked_factor_agrees_with_the_whole_jacobian() {
    let (jac, res) = tall_problem(3001, 12, 7);
    // The whole Jacobian, by nalgebra's QR.
    let qr = jac.clone().qr();
    let mut qtr = DVector::from_column_slice(&res);
    qr.q_tr_mul(&mut qtr);
    let mut full_step = -qtr.rows(0, 12).into_owned();
    assert!(qr.unpack_r().solve_upper_triangular_mut(&mut full_step));
    let full_gradient = jac.tr_mul(&DVector::from_column_slice(&res));
    let full_rest = {
        let fit = &jac * &full_step + DVector::from_column_slice(&res);
        fit.norm_squared()
    };
    for block_rows in [1, 64, 500, 5000] {
        let blocked = BlockedQr::from_rows(&jac, &res, block_rows);
        assert_eq!(blocked.rows(), 3001);
        let step = blocked.gauss_newton_step().expect("regular");
        let e_step = max_rel(full_step.as_slice(), &step);
        let e_grad = max_rel(full_gradient.as_slice(), &blocked.gradient());
        let e_rest = (blocked.ssr_rest() - full_rest).abs() / full_rest;
        let e_norm = max_rel(
            &jac.column_iter().map(|c| c.norm()).collect::<Vec<_>>(),
            &blocked.column_norms(),
        );
        eprintln!("blocks of {block_rows}: step {e_step:.1e}, Jᵀr {e_grad:.1e}, SSR {e_rest:.1e}, norms {e_norm:.1e}");
        assert!(e_step < 1e-11, "step differs by {e_step:e}");
        assert!(e_grad < 1e-12, "gradient differs by {e_grad:e}");
        assert!(e_rest < 1e-12, "SSR differs by {e_rest:e}");
        assert!(e_norm < 1e-12, "column norms differ by {e_norm:e}");
        // Cramér–Rao bounds (eq. 26) from the factor and from the whole H₁.
        let dx_du: Vec<f64> = (0..12).map(|j| 1.0 + j as f64).collect();
        let settings = UncertaintySettings::default();
        let whole = cramer_rao_mapped(&jac, full_rest, &dx_du, &dx_du, &settings).expect("regular");
        let part =
            cramer_rao_blocked(&blocked, full_rest, &dx_du, &dx_du, &settings).expect("regular");
        let e_se = max_rel(&whole.std_errors, &part.std_errors);
        let e_corr = (&whole.correlation - &part.correlation).amax();
        let e_cond =
            (whole.condition_number - part.condition_number).abs() / whole.condition_number;
        eprintln!("  s.e. {e_se:.1e}, correlation {e_corr:.1e}, condition {e_cond:.1e}");
        assert!(e_se < 1e-12, "standard errors differ by {e_se:e}");
        assert!(e_corr < 1e-12, "correlations differ by {e_corr:e}");
        assert!(e_cond < 1e-10, "condition numbers differ by {e_cond:e}");
        assert!(
            whole.correlation[(0, 1)].abs() > 0.99,
            "the near-parallel pair is seen"
        );
        assert_eq!(whole.n_observations, part.n_observations);
    }
}

#[test]
fn blocked_factor_rejects_what_the_whole_analysis_rejects() {
    let (mut jac, res) = tall_problem(200, 5, 3);
    jac.column_mut(3).fill(0.0);
    let blocked = BlockedQr::from_rows(&jac, &res, 32);
    let ones = [1.0; 5];
    let settings = UncertaintySettings::default();
    let whole = cramer_rao_mapped(&jac, 1.0, &ones, &ones, &settings).unwrap_err();
    let part = cramer_rao_blocked(&blocked, 1.0, &ones, &ones, &settings).unwrap_err();
    assert_eq!(whole, part);
    let few = BlockedQr::from_rows(&jac.rows(0, 6).into_owned(), &res[..6], 4);
    assert!(cramer_rao_blocked(&few, 1.0, &ones, &ones, &settings).is_err());
}

/// Memory allowed for the Jacobian in the large test.
const CAP_BYTES: usize = 128 << 20;

/// A linear model `y = J x* + e` of 200 000 observations (e.g. 4 sensors ×
/// 50 000 samples) and 96 parameters: its whole Jacobian (154 MB) exceeds
/// the cap, so it is generated and factorised 500 rows at a time (0.46 MB).
/// The estimate must land within 4 standard errors of x* for every parameter,
/// and the standard errors must match σ of the noise.
#[test]
fn large_problem_is_solved_within_the_memory_cap() {
    let (n_rows, n_cols, block_rows) = (200_000, 96, 500);
    assert!(jacobian_bytes(n_rows, n_cols) > CAP_BYTES);
    assert!(jacobian_bytes(block_rows + n_cols, n_cols) < CAP_BYTES / 100);
    let sigma = 0.01;
    let x_true: Vec<f64> = (0..n_cols).map(|j| 1.0 + 0.5 * (j as f64).sin()).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let mut qr = BlockedQr::new(n_cols);
    let mut block = DMatrix::zeros(block_rows, n_cols);
    let mut res = vec![0.0; block_rows];
    let mut start = 0;
    while start < n_rows {
        // Sensitivities like those of modes at distinct frequencies,
        // sampled at 10 kHz, each with its own scale.
        for i in 0..block_rows {
            let t = (start + i) as f64 * 1e-4;
            let mut y = 0.0;
            for j in 0..n_cols {
                let w = 2.0 * std::f64::consts::PI * (20.0 + 37.0 * j as f64);
                let v = (w * t + 0.3 * j as f64).sin()
                    * (-(t * (1.0 + j as f64 % 5.0))).exp()
                    * 10f64.powi(j as i32 % 7 - 3);
                block[(i, j)] = v;
                y += v * x_true[j];
            }
            let e: f64 = StandardNormal.sample(&mut rng);
            // Residual at x = 0: g(0) − y.
            res[i] = -(y + sigma * e);
        }
        qr.add_rows(&mut block, &mut res);
        start += block_rows;
    }
    assert_eq!(qr.rows(), n_rows);
    let x = qr.gauss_newton_step().expect("regular");
    let ones = vec![1.0; n_cols];
    let cr = cramer_rao_blocked(
        &qr,
        qr.ssr_rest(),
        &ones,
        &ones,
        &UncertaintySettings::default(),
    )
    .expect("regular");
    let s = cr.s2.sqrt();
    assert!(
        (s / sigma - 1.0).abs() < 0.01,
        "s = {s:e} for σ = {sigma:e}"
    );
    let worst = (0..n_cols)
        .map(|j| (x[j] - x_true[j]).abs() / cr.std_errors[j])
        .fold(0.0, f64::max);
    eprintln!("s = {s:.5e}, worst |x − x*| / s.e. = {worst:.2}");
    assert!(worst < 4.0, "an estimate is {worst} standard errors off");
}
