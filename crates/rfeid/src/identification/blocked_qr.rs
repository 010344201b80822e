//! The triangular factor of a tall Jacobian, accumulated from blocks of rows,
//! so that the N × r Jacobian of a large problem is never held whole.
//!
//! Levenberg–Marquardt ([`crate::identification::lm`]) and the Cramér–Rao
//! bounds (eq. 26–29, [`crate::identification::uncertainty`]) use the
//! Jacobian only through `J = Q R` and `Qᵀ r`: the step solves
//! `(JᵀJ + λD²) δ = −Jᵀr` as `[R; √λ D] δ ≈ [−Qᵀr; 0]`, and `H₁ᵀH₁ = RᵀR`.
//! Both R (r × r) and the first r entries of `Qᵀ r` can be built one block of
//! rows at a time:
//!
//! ```text
//! [R_k ; J_{k+1}] = Q' R_{k+1},      z_{k+1} = first r of Q'ᵀ [z_k ; r_{k+1}]
//! ```
//!
//! by r Householder reflections that each touch one row of R and the block
//! (cost `2 b r²` per block of b rows, `2 N r²` in all, as for the QR of the
//! whole J). Unlike accumulating `JᵀJ` and `Jᵀr`, this does not square the
//! condition number, which joint parameters make as large as 10⁸. Memory is
//! `r² + b r` numbers instead of `N r`: for 5 tests × 6 sensors × 50 000
//! samples and r = 200 parameters, 0.73 MB with blocks of 256 rows instead of
//! 2.4 GB.
//!
//! The blocks are taken in row order by one thread, so the result is the same
//! bit for bit whatever the number of threads that produced the rows.
use nalgebra::DMatrix;

/// Bytes of an `n_rows × n_cols` Jacobian of `f64`, saturating.
pub fn jacobian_bytes(n_rows: usize, n_cols: usize) -> usize {
    n_rows.saturating_mul(n_cols).saturating_mul(8)
}

/// Upper-triangular R and `Qᵀ r` of a tall Jacobian, built from its row
/// blocks in order (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct BlockedQr {
    /// Upper-triangular factor (r × r; zero below the diagonal).
    r: DMatrix<f64>,
    /// The first r entries of `Qᵀ res`.
    qtr: Vec<f64>,
    /// `‖res‖²` not explained by the column space so far (the SSR of the
    /// linear least-squares fit of the rows taken).
    ssr_rest: f64,
    /// Rows taken so far.
    rows: usize,
    /// The first row taken with a NaN or infinite entry (in J or res).
    first_non_finite: Option<usize>,
}

impl BlockedQr {
    /// An empty factor for `n_cols` columns.
    pub fn new(n_cols: usize) -> Self {
        BlockedQr {
            r: DMatrix::zeros(n_cols, n_cols),
            qtr: vec![0.0; n_cols],
            ssr_rest: 0.0,
            rows: 0,
            first_non_finite: None,
        }
    }

    /// Empties the factor for new rows of the same columns, keeping its
    /// memory.
    pub fn clear(&mut self) {
        self.r.fill(0.0);
        self.qtr.fill(0.0);
        self.ssr_rest = 0.0;
        self.rows = 0;
        self.first_non_finite = None;
    }

    /// The first row taken (counted from 0 in the order taken) with a NaN
    /// or infinite entry in J or in the residuals; the factor is then
    /// meaningless.
    pub fn first_non_finite_row(&self) -> Option<usize> {
        self.first_non_finite
    }

    /// Number of columns r.
    pub fn n_cols(&self) -> usize {
        self.qtr.len()
    }

    /// Rows taken so far (N once every block is in).
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// The upper-triangular factor R of `J = Q R` (r × r).
    pub fn r(&self) -> &DMatrix<f64> {
        &self.r
    }

    /// The first r entries of `Qᵀ res` for the residuals `res` taken.
    pub fn qtr(&self) -> &[f64] {
        &self.qtr
    }

    /// `min_δ ‖J δ − res‖²` over the rows taken: the part of `‖res‖²` the
    /// columns of J cannot explain.
    pub fn ssr_rest(&self) -> f64 {
        self.ssr_rest
    }

    /// Euclidean norms of the columns of J (equal to those of R).
    pub fn column_norms(&self) -> Vec<f64> {
        self.r.column_iter().map(|c| c.norm()).collect()
    }

    /// `Jᵀ res = Rᵀ (Qᵀ res)`: half the gradient of `Σ res²` (eq. 16) with
    /// respect to the columns' variables.
    pub fn gradient(&self) -> Vec<f64> {
        (0..self.n_cols())
            .map(|j| (0..=j).map(|i| self.r[(i, j)] * self.qtr[i]).sum())
            .collect()
    }

    /// The Gauss–Newton step `δ = argmin ‖J δ + res‖²`, from `R δ = −Qᵀ res`;
    /// `None` if R is singular (a zero on its diagonal) or the step is not
    /// finite.
    pub fn gauss_newton_step(&self) -> Option<Vec<f64>> {
        let mut delta =
            nalgebra::DVector::from_iterator(self.n_cols(), self.qtr.iter().map(|v| -v));
        if !self.r.solve_upper_triangular_mut(&mut delta) {
            return None;
        }
        delta
            .iter()
            .all(|v| v.is_finite())
            .then(|| delta.as_slice().to_vec())
    }

    /// Takes the next rows: `block` (b × r) of J and `res` (b) of the
    /// residuals. Both are used as scratch and left overwritten. Does not
    /// allocate.
    ///
    /// # Panics
    /// If `block` does not have r columns or `res` does not have one entry
    /// per row of `block` (a programming error).
    pub fn add_rows(&mut self, block: &mut DMatrix<f64>, res: &mut [f64]) {
        let n = self.n_cols();
        assert_eq!(block.ncols(), n, "block columns");
        assert_eq!(block.nrows(), res.len(), "block rows");
        let b = res.len();
        if self.first_non_finite.is_none() {
            self.first_non_finite = (0..b)
                .find(|&i| !res[i].is_finite() || block.row(i).iter().any(|v| !v.is_finite()))
                .map(|i| self.rows + i);
        }
        self.rows += b;
        if b == 0 {
            return;
        }
        let data = block.as_mut_slice();
        for j in 0..n {
            // Householder reflection zeroing block column j against R[j, j].
            let (head, rest) = data.split_at_mut((j + 1) * b);
            let vj = &mut head[j * b..];
            let x0 = self.r[(j, j)];
            let tail: f64 = vj.iter().map(|v| v * v).sum();
            if tail == 0.0 {
                continue;
            }
            let norm = (x0 * x0 + tail).sqrt();
            let alpha = if x0 > 0.0 { -norm } else { norm };
            let v0 = x0 - alpha;
            let vtv = v0 * v0 + tail;
            self.r[(j, j)] = alpha;
            for (k, ck) in (j + 1..n).zip(rest.chunks_exact_mut(b)) {
                let s = v0 * self.r[(j, k)] + dot(vj, ck);
                let f = 2.0 * s / vtv;
                self.r[(j, k)] -= f * v0;
                for (c, v) in ck.iter_mut().zip(vj.iter()) {
                    *c -= f * v;
                }
            }
            let s = v0 * self.qtr[j] + dot(vj, res);
            let f = 2.0 * s / vtv;
            self.qtr[j] -= f * v0;
            for (c, v) in res.iter_mut().zip(vj.iter()) {
                *c -= f * v;
            }
            vj.fill(0.0);
        }
        self.ssr_rest += res.iter().map(|v| v * v).sum::<f64>();
    }

    /// The factor of the same rows with column `j` left out, into `out`
    /// (resized if it has not `n_cols − 1` columns): R without its column j
    /// is upper Hessenberg from column j on, and Givens rotations of rows
    /// j … r−1 make it triangular again; `Qᵀ res` takes the same rotations,
    /// and its last entry, which no remaining column explains, joins
    /// [`BlockedQr::ssr_rest`]. Without column j, `J = Q R` becomes the
    /// Jacobian of the other variables (a profile's problem with x_j held,
    /// eq. 16). Does nothing if `j` is not a column.
    pub fn without_column_into(&self, j: usize, out: &mut BlockedQr) {
        let n = self.n_cols();
        if j >= n {
            return;
        }
        if out.n_cols() + 1 != n {
            *out = BlockedQr::new(n - 1);
        }
        // The first r − 1 rows of R without its column j.
        let mut h = std::mem::take(&mut out.r);
        if h.shape() != (n - 1, n - 1) {
            h = DMatrix::zeros(n - 1, n - 1);
        }
        let mut z = std::mem::take(&mut out.qtr);
        z.clear();
        z.extend_from_slice(&self.qtr);
        let mut rest = self.ssr_rest;
        for c in 0..n - 1 {
            let src = if c < j { c } else { c + 1 };
            for i in 0..n - 1 {
                h[(i, c)] = self.r[(i, src)];
            }
        }
        // Row i + 1 of R without column j at column k: the last row (n − 1)
        // is not kept in `h`; it is still R's own when the last rotation
        // reads it, and what that rotation leaves in it is zero.
        let below = |h: &DMatrix<f64>, c: usize, k: usize| match c + 1 < n - 1 {
            true => h[(c + 1, k)],
            false => self.r[(n - 1, k + 1)],
        };
        for c in j..n - 1 {
            let (top, low) = (h[(c, c)], below(&h, c, c));
            let norm = top.hypot(low);
            if norm == 0.0 {
                continue;
            }
            let (cs, sn) = (top / norm, low / norm);
            for k in c..n - 1 {
                let (a, b) = (h[(c, k)], below(&h, c, k));
                h[(c, k)] = cs * a + sn * b;
                if c + 1 < n - 1 {
                    h[(c + 1, k)] = cs * b - sn * a;
                }
            }
            let (a, b) = (z[c], z[c + 1]);
            z[c] = cs * a + sn * b;
            z[c + 1] = cs * b - sn * a;
        }
        rest += z[n - 1] * z[n - 1];
        z.truncate(n - 1);
        for c in 0..n - 1 {
            for i in c + 1..n - 1 {
                h[(i, c)] = 0.0;
            }
        }
        out.r = h;
        out.qtr = z;
        out.ssr_rest = rest;
        out.rows = self.rows;
        out.first_non_finite = self.first_non_finite;
    }

    /// Builds the factor of a whole Jacobian `jac` with residuals `res`, in
    /// blocks of `block_rows` rows (≥ 1), copying each block into one
    /// scratch matrix.
    pub fn from_rows(jac: &DMatrix<f64>, res: &[f64], block_rows: usize) -> Self {
        let (n_rows, n_cols) = jac.shape();
        let b = block_rows.max(1);
        let mut qr = BlockedQr::new(n_cols);
        let mut block = DMatrix::zeros(b, n_cols);
        let mut rb = vec![0.0; b];
        let mut start = 0;
        while start < n_rows {
            let len = b.min(n_rows - start);
            if len < b {
                block = DMatrix::zeros(len, n_cols);
                rb.truncate(len);
            }
            block.copy_from(&jac.rows(start, len));
            rb.copy_from_slice(&res[start..start + len]);
            qr.add_rows(&mut block, &mut rb);
            start += len;
        }
        qr
    }
}

/// `Σ a_i b_i` in index order.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0, |acc, (x, y)| acc + x * y)
}
