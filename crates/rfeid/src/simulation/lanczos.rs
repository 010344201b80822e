//! The largest eigenvalue of a symmetric matrix by the Lanczos method, for
//! checks that need only the top of a spectrum (the fastest mode against
//! the Nyquist frequency): a few dozen products with the matrix instead of
//! a dense eigenvalue problem.
use nalgebra::{DMatrix, DVector, SymmetricEigen};

/// Stop when the top Ritz pair's residual `β_k |s_k|` is this small
/// relative to its value: the value is then exact to about its square.
const RESIDUAL: f64 = 1e-10;

/// How many steps between convergence checks.
const CHECK_EVERY: usize = 6;

/// A fixed start with every component nonzero and no pattern a symmetric
/// model could make orthogonal to its top mode (a SplitMix64 sequence).
fn start(n: usize) -> DVector<f64> {
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let v = DVector::from_fn(n, |_, _| {
        x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = x;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        0.5 + (z >> 11) as f64 / (1u64 << 53) as f64
    });
    let norm = v.norm();
    v / norm
}

/// The largest eigenvalue of the symmetric matrix `a`: Lanczos with full
/// reorthogonalisation, stopped when the top Ritz value's residual bound is
/// below [`RESIDUAL`] of it, or after n steps (then exact to rounding).
pub fn largest_eigenvalue(a: &DMatrix<f64>) -> f64 {
    let n = a.nrows();
    if n == 0 {
        return f64::NAN;
    }
    let mut basis: Vec<DVector<f64>> = vec![start(n)];
    let (mut alpha, mut beta) = (Vec::new(), Vec::new());
    loop {
        let j = basis.len() - 1;
        let mut w = a * &basis[j];
        alpha.push(w.dot(&basis[j]));
        // Twice against the whole basis keeps it orthogonal to rounding.
        for _ in 0..2 {
            for v in &basis {
                let c = w.dot(v);
                w.axpy(-c, v, 1.0);
            }
        }
        let b = w.norm();
        let steps = j + 1;
        let invariant = b <= f64::EPSILON * alpha.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        if steps == n || invariant || steps % CHECK_EVERY == 0 {
            let t = DMatrix::from_fn(steps, steps, |r, c| match r.abs_diff(c) {
                0 => alpha[r],
                1 => beta[r.min(c)],
                _ => 0.0,
            });
            let eig = SymmetricEigen::new(t);
            let top = eig.eigenvalues.imax();
            let theta = eig.eigenvalues[top];
            let residual = b * eig.eigenvectors[(steps - 1, top)].abs();
            if steps == n || invariant || residual <= RESIDUAL * theta.abs() {
                return theta;
            }
        }
        beta.push(b);
        basis.push(w / b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_top_of_a_random_spectrum_matches_the_dense_solver() {
        // A symmetric matrix with a cluster near its top and a wide spread
        // below it, rotated by a random orthogonal matrix.
        for n in [1, 2, 7, 60, 200] {
            let q = DMatrix::from_fn(n, n, |i, j| ((i * 31 + j * 17) % 23) as f64 - 11.0)
                .qr()
                .q();
            let d = DVector::from_fn(n, |i, _| match i {
                0 => 1000.0,
                1 => 999.9,
                i => (i as f64).sqrt() * 10.0,
            });
            let a = &q * DMatrix::from_diagonal(&d) * q.transpose();
            let a = (&a + a.transpose()) * 0.5;
            let dense = a.clone().symmetric_eigenvalues().max();
            let lanczos = largest_eigenvalue(&a);
            assert!(
                (lanczos - dense).abs() <= 1e-9 * dense,
                "n = {n}: {lanczos} against {dense}"
            );
        }
    }
}
