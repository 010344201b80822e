//! Cholesky factorisation of a symmetric positive-definite matrix within
//! its envelope, after a reverse Cuthill–McKee ordering: the tangent
//! stiffness of the static equilibrium (eq. 1 with q̈ = q̇ = 0) of a large
//! model.
//!
//! Each element couples two bodies, so the stiffness is block-sparse; a
//! chain of rigid elements numbered along the chain has a narrow band. The
//! factor L of `P A Pᵀ = L Lᵀ` has no nonzero left of the first nonzero of
//! each row (the envelope, George & Liu 1981, ch. 4), so a factorisation
//! costs `Σ_i w_i²` (w_i the row's width) instead of the dense `n³/3`. The
//! ordering (Cuthill & McKee 1969, reversed) narrows the envelope of any
//! numbering of the bodies.

/// A coordinate ordering for the nonzero pattern of a symmetric matrix.
#[derive(Debug, Clone)]
pub(crate) struct Ordering {
    /// `perm[i]`: the original index of the i-th reordered coordinate.
    perm: Vec<usize>,
    /// `first[i]`: the first column of row i's envelope (reordered).
    first: Vec<usize>,
}

impl Ordering {
    /// The reverse Cuthill–McKee ordering of the `n × n` row-major matrix
    /// `a`'s nonzero pattern (entries exactly 0 are absent; `a` is taken as
    /// symmetric in pattern), with `extra` rows (lists of coordinates) whose
    /// outer products are added to the pattern.
    pub fn new(n: usize, a: &[f64], extra: &[Vec<usize>]) -> Ordering {
        let mut adjacent: Vec<Vec<usize>> = (0..n)
            .map(|i| (0..n).filter(|&j| j != i && a[i * n + j] != 0.0).collect())
            .collect();
        for coords in extra {
            for &i in coords {
                adjacent[i].extend(coords.iter().copied().filter(|&j| j != i));
            }
        }
        for list in &mut adjacent {
            list.sort_unstable();
            list.dedup();
        }
        let mut order = Vec::with_capacity(n);
        let mut placed = vec![false; n];
        // Each connected part from a node of least degree, breadth first,
        // neighbours by increasing degree.
        while order.len() < n {
            let start = (0..n)
                .filter(|&i| !placed[i])
                .min_by_key(|&i| adjacent[i].len())
                .expect("an unplaced node remains");
            placed[start] = true;
            let mut head = order.len();
            order.push(start);
            while head < order.len() {
                let node = order[head];
                head += 1;
                let mut next: Vec<usize> = adjacent[node]
                    .iter()
                    .copied()
                    .filter(|&j| !placed[j])
                    .collect();
                next.sort_by_key(|&j| (adjacent[j].len(), j));
                for j in next {
                    placed[j] = true;
                    order.push(j);
                }
            }
        }
        order.reverse();
        let mut position = vec![0; n];
        for (i, &p) in order.iter().enumerate() {
            position[p] = i;
        }
        let first = (0..n)
            .map(|i| {
                adjacent[order[i]]
                    .iter()
                    .map(|&j| position[j])
                    .fold(i, usize::min)
            })
            .collect();
        Ordering { perm: order, first }
    }

    /// Where each row of a factor within the envelope starts when the rows
    /// (`first_i ..= i`) are stored one after another; the last entry is the
    /// number of stored entries.
    fn row_starts(&self) -> Vec<usize> {
        let mut start = Vec::with_capacity(self.first.len() + 1);
        start.push(0);
        for (i, &f) in self.first.iter().enumerate() {
            start.push(start[i] + i + 1 - f);
        }
        start
    }

    /// The number of stored entries of the factor.
    #[cfg(test)]
    pub fn envelope_size(&self) -> usize {
        self.first.iter().enumerate().map(|(i, f)| i + 1 - f).sum()
    }
}

/// The factor L of `P A Pᵀ = L Lᵀ`, row by row within the envelope.
#[derive(Debug, Clone)]
pub(crate) struct EnvelopeCholesky<'o> {
    ordering: &'o Ordering,
    /// Row i's entries `L[i][first_i ..= i]`, rows one after another.
    values: Vec<f64>,
    /// Start of each row in `values`.
    start: Vec<usize>,
}

impl<'o> EnvelopeCholesky<'o> {
    /// Factorises the row-major `n × n` matrix `a` (its lower triangle is
    /// read), whose nonzero pattern `ordering` was made for; `None` if it is
    /// not numerically positive definite.
    pub fn factor(ordering: &'o Ordering, a: &[f64]) -> Option<EnvelopeCholesky<'o>> {
        let (perm, first) = (&ordering.perm, &ordering.first);
        let n = perm.len();
        let start = ordering.row_starts();
        let mut values = vec![0.0; start[n]];
        for i in 0..n {
            let (fi, si) = (first[i], start[i]);
            for j in fi..=i {
                // A's entry in the lower triangle of the reordered matrix.
                let (r, c) = (perm[i].max(perm[j]), perm[i].min(perm[j]));
                let mut s = a[r * n + c];
                let fj = first[j];
                let from = fi.max(fj);
                let (li, lj) = (&values[si..], &values[start[j]..]);
                for k in from..j {
                    s -= li[k - fi] * lj[k - fj];
                }
                if j < i {
                    values[si + j - fi] = s / values[start[j] + j - fj];
                } else if s > 0.0 && s.is_finite() {
                    values[si + i - fi] = s.sqrt();
                } else {
                    return None;
                }
            }
        }
        Some(EnvelopeCholesky {
            ordering,
            values,
            start,
        })
    }

    /// Solves `A x = b` in place.
    pub fn solve(&self, b: &mut [f64]) {
        let (perm, first) = (&self.ordering.perm, &self.ordering.first);
        let n = perm.len();
        let mut y: Vec<f64> = perm.iter().map(|&p| b[p]).collect();
        for i in 0..n {
            let row = &self.values[self.start[i]..self.start[i + 1]];
            let fi = first[i];
            let mut s = y[i];
            for k in fi..i {
                s -= row[k - fi] * y[k];
            }
            y[i] = s / row[i - fi];
        }
        for i in (0..n).rev() {
            let row = &self.values[self.start[i]..self.start[i + 1]];
            let fi = first[i];
            y[i] /= row[i - fi];
            let yi = y[i];
            for k in fi..i {
                y[k] -= row[k - fi] * yi;
            }
        }
        for (i, &p) in perm.iter().enumerate() {
            b[p] = y[i];
        }
    }
}

// long-fn: numerical kernel (envelope LDLᵀ with zero-pivot detection)
/// A basis of the null space of the symmetric positive semidefinite
/// row-major `n × n` matrix `a` (pattern as `ordering`), by the zero-pivot
/// method of finite-element codes for rigid-body modes (Farhat & Géradin
/// 1998): in `P A Pᵀ = L D Lᵀ`, a pivot `D_ii ≤ tol · A_ii` marks coordinate
/// i as dependent; its column of L is dropped (in a semidefinite matrix the
/// rest of that column of the Schur complement vanishes with its pivot),
/// and each marked i gives the null vector v with `Lᵀ v = e_i`, since then
/// `A v = L D e_i = 0`. The vectors are independent (v_j = δ_ij on the
/// marked coordinates) but not orthogonal. `None` if a pivot is negative
/// beyond rounding (the matrix is not semidefinite).
pub(crate) fn null_space(ordering: &Ordering, a: &[f64], tol: f64) -> Option<Vec<Vec<f64>>> {
    let (perm, first) = (&ordering.perm, &ordering.first);
    let n = perm.len();
    let start = ordering.row_starts();
    // Row i holds L[i][first_i .. i] and D_i in place of the unit diagonal.
    let mut values = vec![0.0; start[n]];
    let mut dropped = vec![false; n];
    for i in 0..n {
        let (fi, si) = (first[i], start[i]);
        for j in fi..=i {
            let (r, c) = (perm[i].max(perm[j]), perm[i].min(perm[j]));
            let mut s = a[r * n + c];
            let fj = first[j];
            for k in fi.max(fj)..j {
                let (lik, ljk) = (values[si + k - fi], values[start[j] + k - fj]);
                s -= lik * ljk * values[start[k + 1] - 1];
            }
            if j < i {
                let dj = values[start[j + 1] - 1];
                values[si + j - fi] = if dropped[j] { 0.0 } else { s / dj };
            } else if !(s.is_finite() && s >= -tol * a[r * n + c].abs()) {
                return None;
            } else if s <= tol * a[r * n + c].abs() {
                dropped[i] = true;
                values[si + i - fi] = 1.0;
            } else {
                values[si + i - fi] = s;
            }
        }
    }
    let mut basis = Vec::new();
    for m in (0..n).filter(|&m| dropped[m]) {
        // Lᵀ y = e_m (unit diagonal), back substitution by rows of L.
        let mut y = vec![0.0; n];
        y[m] = 1.0;
        for i in (0..=m).rev() {
            let yi = y[i];
            if yi == 0.0 {
                continue;
            }
            let fi = first[i];
            for k in fi..i {
                y[k] -= values[start[i] + k - fi] * yi;
            }
        }
        let mut v = vec![0.0; n];
        for (i, &p) in perm.iter().enumerate() {
            v[p] = y[i];
        }
        basis.push(v);
    }
    Some(basis)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symmetric positive-definite block-tridiagonal matrix with its bodies
    /// numbered out of chain order, and a rank-one extra row.
    fn chain(blocks: usize) -> (usize, Vec<f64>) {
        let n = 3 * blocks;
        let mut a = vec![0.0; n * n];
        let order: Vec<usize> = (0..blocks).map(|b| (b * 7) % blocks).collect();
        for w in order.windows(2) {
            for i in 0..3 {
                for j in 0..3 {
                    let (p, q) = (3 * w[0] + i, 3 * w[1] + j);
                    let v = 1.0 + 0.1 * (i + 2 * j) as f64;
                    a[p * n + q] -= v;
                    a[q * n + p] -= v;
                }
            }
        }
        for i in 0..n {
            let off: f64 = (0..n).filter(|&j| j != i).map(|j| a[i * n + j].abs()).sum();
            a[i * n + i] = off + 1.0 + i as f64 * 0.01;
        }
        (n, a)
    }

    #[test]
    fn solves_like_dense_lu_with_a_small_envelope() {
        let (n, mut a) = chain(11);
        let extra = vec![0, 5, n - 1];
        for &i in &extra {
            for &j in &extra {
                a[i * n + j] += 0.5;
            }
        }
        let ord = Ordering::new(n, &a, &[extra]);
        let chol = EnvelopeCholesky::factor(&ord, &a).expect("positive definite");
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.3).sin()).collect();
        let mut x = b.clone();
        chol.solve(&mut x);
        let dense = nalgebra::DMatrix::from_row_slice(n, n, &a);
        let reference = dense
            .lu()
            .solve(&nalgebra::DVector::from_column_slice(&b))
            .expect("regular");
        for i in 0..n {
            assert!(
                (x[i] - reference[i]).abs() <= 1e-13 * reference.amax(),
                "x[{i}]"
            );
        }
        assert!(ord.envelope_size() < n * (n + 1) / 2);
    }

    #[test]
    fn finds_the_null_space_of_a_semidefinite_matrix() {
        // The Laplacian of two separate paths (0–1–2–3 and 4–5–6), numbered
        // out of order: a null space of the constants on each path.
        let n = 7;
        let mut a = vec![0.0; n * n];
        for (i, j) in [(0, 2), (2, 1), (1, 3), (4, 6), (6, 5)] {
            a[i * n + i] += 1.0;
            a[j * n + j] += 1.0;
            a[i * n + j] -= 1.0;
            a[j * n + i] -= 1.0;
        }
        let ord = Ordering::new(n, &a, &[]);
        let basis = null_space(&ord, &a, 1e-9).expect("semidefinite");
        assert_eq!(basis.len(), 2);
        for v in &basis {
            for i in 0..n {
                let av: f64 = (0..n).map(|j| a[i * n + j] * v[j]).sum();
                assert!(av.abs() < 1e-14, "{v:?}");
            }
        }
        // A regular matrix has none; an indefinite one is refused.
        let (m, b) = chain(5);
        assert!(null_space(&Ordering::new(m, &b, &[]), &b, 1e-9)
            .unwrap()
            .is_empty());
        let c = [1.0, 2.0, 2.0, 1.0];
        assert!(null_space(&Ordering::new(2, &c, &[]), &c, 1e-9).is_none());
    }

    #[test]
    fn rejects_an_indefinite_matrix() {
        let a = [1.0, 2.0, 2.0, 1.0];
        let ord = Ordering::new(2, &a, &[]);
        assert!(EnvelopeCholesky::factor(&ord, &a).is_none());
    }
}
