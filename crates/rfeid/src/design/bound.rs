//! How far a chosen set can be from the optimum: the convex relaxation of
//! Joshi & Boyd (2009, "Sensor selection via convex optimization"). With
//! the choice relaxed to weights `0 ≤ z_i ≤ 1`, `Σ z_i = K`, the criterion
//! `φ(z) = Σ_p log det (F_p + Σ z_i F_pi)` is concave, its maximum bounds
//! every set's from above, and for any feasible z
//!
//! ```text
//! max φ ≤ φ(z) + max_{z' feasible} ∇φ(z)ᵀ (z' − z),
//! ```
//!
//! the linear maximum being the sum of the K largest gradient entries
//! (`∂φ/∂z_i = Σ_p tr(M_p⁻¹ F_pi)`). Projected gradient ascent drives z
//! towards the maximum; the bound is valid at every iterate, and tight at
//! the end.
use nalgebra::DMatrix;

/// Iterations of the ascent at most.
const MAX_ITERATIONS: usize = 400;

/// The relaxed criterion and its gradient at z (`None` where a matrix is
/// not positive definite).
fn value_gradient(
    base: &[DMatrix<f64>],
    cand: &[Vec<DMatrix<f64>>],
    z: &[f64],
) -> Option<(f64, Vec<f64>)> {
    let mut value = 0.0;
    let mut grad = vec![0.0; z.len()];
    for (b, c) in base.iter().zip(cand) {
        let m = c.iter().zip(z).fold(b.clone(), |m, (f, &w)| m + f * w);
        let chol = m.cholesky()?;
        value += 2.0
            * chol
                .l_dirty()
                .diagonal()
                .iter()
                .map(|d| d.ln())
                .sum::<f64>();
        let inv = chol.inverse();
        for (g, f) in grad.iter_mut().zip(c) {
            *g += inv.component_mul(f).sum();
        }
    }
    value.is_finite().then_some((value, grad))
}

/// The projection of y onto `{0 ≤ z ≤ 1, Σ z = k}`: `clamp(y − τ, 0, 1)`
/// with τ found by bisection.
fn project(y: &[f64], k: f64) -> Vec<f64> {
    let total = |t: f64| y.iter().map(|v| (v - t).clamp(0.0, 1.0)).sum::<f64>();
    let (mut lo, mut hi) = (
        y.iter().copied().fold(f64::INFINITY, f64::min) - 1.0,
        y.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if total(mid) > k {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let t = 0.5 * (lo + hi);
    y.iter().map(|v| (v - t).clamp(0.0, 1.0)).collect()
}

/// The sum of the k largest entries.
fn top_sum(g: &[f64], k: usize) -> f64 {
    let mut s = g.to_vec();
    s.sort_by(|a, b| b.total_cmp(a));
    s.iter().take(k).sum()
}

/// An upper bound on the criterion of every K-set of the candidates
/// (`+∞` when even the relaxation is singular everywhere it starts).
pub fn upper_bound(base: &[DMatrix<f64>], cand: &[Vec<DMatrix<f64>>], k: usize) -> f64 {
    let n = cand.first().map_or(0, Vec::len);
    if n == 0 || k == 0 {
        return base.iter().map(super::choose::log_det).sum();
    }
    let mut z = vec![k as f64 / n as f64; n];
    let Some((mut value, mut grad)) = value_gradient(base, cand, &z) else {
        return f64::INFINITY;
    };
    let gap =
        |z: &[f64], g: &[f64]| top_sum(g, k) - z.iter().zip(g).map(|(a, b)| a * b).sum::<f64>();
    let mut bound = value + gap(&z, &grad);
    let mut step = 1.0 / grad.iter().fold(0.0f64, |m, g| m.max(g.abs())).max(1e-300);
    for _ in 0..MAX_ITERATIONS {
        if bound - value < 1e-9 * value.abs().max(1.0) {
            break;
        }
        // Backtracking on the projected step.
        let mut moved = false;
        for _ in 0..40 {
            let y: Vec<f64> = z.iter().zip(&grad).map(|(a, g)| a + step * g).collect();
            let trial = project(&y, k as f64);
            if let Some((v, g)) = value_gradient(base, cand, &trial) {
                if v >= value {
                    (z, value, grad) = (trial, v, g);
                    moved = true;
                    step *= 2.0;
                    break;
                }
            }
            step *= 0.5;
        }
        bound = bound.min(value + gap(&z, &grad));
        if !moved {
            break;
        }
    }
    bound
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_lands_in_the_capped_simplex() {
        let z = project(&[3.0, -1.0, 0.2, 0.4, 0.9], 2.0);
        assert!((z.iter().sum::<f64>() - 2.0).abs() < 1e-9);
        assert!(z.iter().all(|v| (0.0..=1.0).contains(v)));
        assert_eq!(z[0], 1.0);
        assert_eq!(z[1], 0.0);
    }
}
