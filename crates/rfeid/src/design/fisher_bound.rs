//! The Cramér–Rao bound (eq. 26–29) of a design's Fisher matrix: the
//! noise is known, so s² is not estimated from residuals.
use crate::identification::uncertainty::{
    check_no_zero_column, check_widths, from_scaled_factor, CramerRao, UncertaintyError,
    UncertaintySettings,
};
use nalgebra::DMatrix;

/// [`cramer_rao_mapped`](crate::identification::uncertainty::cramer_rao_mapped) from the Fisher matrix `F = H₁ᵀH₁` itself, its
/// rows already divided by each observation's noise standard deviation, so
/// that s² = 1 (eq. 26 with the noise known: the prediction of an
/// experiment design). `n_obs` is the number of observations it sums;
/// `dx_du` the chain-rule factors of its coordinate, `box_widths` serve the
/// standard-error-versus-box warning; F may be given as `F·s²` with
/// `noise_variance` s² (1: F itself), the covariance then `s² (F·s²)⁻¹`.
/// F is scaled to unit diagonal and factored by its symmetric eigendecomposition (`F_s = RᵀR`, `R = Λ^½
/// Vᵀ`). An eigenvalue of F_s is accurate only to about r·ε·λ_max, so the
/// singular test is `λ ≤ max(tol², 100 r ε) λ_max` (tol the singular
/// tolerance on singular values): a singular F is
/// [`UncertaintyError::Singular`] with the parameters involved.
pub fn cramer_rao_fisher(
    fisher: &DMatrix<f64>,
    n_obs: usize,
    dx_du: &[f64],
    box_widths: &[f64],
    noise_variance: f64,
    settings: &UncertaintySettings,
) -> Result<CramerRao, UncertaintyError> {
    let r = fisher.ncols();
    if r == 0 {
        return Err(UncertaintyError::NoParameters);
    }
    check_widths(r, Some(box_widths))?;
    check_widths(r, Some(dx_du))?;
    let norms: Vec<f64> = (0..r).map(|j| fisher[(j, j)].max(0.0).sqrt()).collect();
    check_no_zero_column(&norms)?;
    let scaled = DMatrix::from_fn(r, r, |i, j| {
        0.5 * (fisher[(i, j)] + fisher[(j, i)]) / (norms[i] * norms[j])
    });
    if let Some((row, column)) = (0..r)
        .flat_map(|i| (0..r).map(move |j| (i, j)))
        .find(|&(i, j)| !scaled[(i, j)].is_finite())
    {
        return Err(UncertaintyError::NonFiniteJacobian { row, column });
    }
    let eig = scaled.symmetric_eigen();
    let top = eig.eigenvalues.max();
    let floor = settings
        .singular_tolerance()
        .powi(2)
        .max(100.0 * r as f64 * f64::EPSILON)
        * top;
    if eig.eigenvalues.iter().any(|&l| l <= floor) {
        let v = &eig.eigenvectors;
        let mut parameters: Vec<usize> = (0..r)
            .filter(|&k| eig.eigenvalues[k] <= floor)
            .flat_map(|k| (0..r).filter(move |&j| v[(j, k)].abs() >= 0.1))
            .collect();
        parameters.sort_unstable();
        parameters.dedup();
        let low = eig.eigenvalues.min().max(0.0);
        return Err(UncertaintyError::Singular {
            parameters,
            condition_number: if low > 0.0 { top / low } else { f64::INFINITY },
        });
    }
    let rs = DMatrix::from_fn(r, r, |k, j| {
        eig.eigenvalues[k].sqrt() * eig.eigenvectors[(j, k)]
    });
    let factors: Vec<f64> = dx_du.iter().map(|d| 1.0 / d).collect();
    // s² = ssr / (n − r − 1) = noise_variance.
    let (ssr, widths) = (noise_variance, Some(box_widths));
    let mut bounds = from_scaled_factor(rs, &norms, r + 2, &factors, ssr, widths, settings)?;
    bounds.n_observations = n_obs;
    Ok(bounds)
}
