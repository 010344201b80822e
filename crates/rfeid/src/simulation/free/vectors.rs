//! Small vector operations of the free-space bases, in the mass-scaled
//! coordinates.

/// How far (in the unit mass-scaled norm) a candidate may lie outside the
/// null space and still be taken as one of its directions.
pub(super) const CONTAINED: f64 = 1e-6;

/// Gram–Schmidt (twice) on `vectors`, dropping those within [`CONTAINED`]
/// of the span of the ones before; the kept ones have unit norm.
pub(super) fn orthonormalise(vectors: impl IntoIterator<Item = Vec<f64>>) -> Vec<Vec<f64>> {
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for v in vectors {
        if let Some(u) = unit_residual(&basis, &v) {
            basis.push(u);
        }
    }
    basis
}

/// `v` less its projection on the orthonormal `basis`, normalised; `None`
/// if that leaves less than [`CONTAINED`] of `v`.
pub(super) fn unit_residual(basis: &[Vec<f64>], v: &[f64]) -> Option<Vec<f64>> {
    let norm = dot(v, v).sqrt();
    if !(norm > 0.0) {
        return None;
    }
    let mut r: Vec<f64> = v.iter().map(|x| x / norm).collect();
    for _ in 0..2 {
        for b in basis {
            let c = dot(b, &r);
            r.iter_mut().zip(b).for_each(|(r, b)| *r -= c * b);
        }
    }
    let left = dot(&r, &r).sqrt();
    (left > CONTAINED).then(|| r.iter().map(|x| x / left).collect())
}

/// The dot product.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}
