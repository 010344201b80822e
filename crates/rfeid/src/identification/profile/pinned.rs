//! A least-squares problem with one decision variable held: the criterion of
//! a profile (eq. 16 minimised over the other variables at a fixed x_j).
//!
//! [`Pinned`] forwards every evaluation to the inner problem with the held
//! coordinate put back in, and drops its column from the Jacobian (or from
//! the Jacobian's triangular factor, [`BlockedQr::without_column_into`], for
//! a problem that takes it by blocks), so that the solvers
//! ([`crate::identification::lm`]) run on it unchanged.
use crate::identification::blocked_qr::BlockedQr;
use crate::identification::problem::LeastSquares;
use nalgebra::DMatrix;

/// `problem` with its decision variable `index` held at `value` (normalised,
/// eq. 17); its decision variables are the others, in order.
#[derive(Debug)]
pub struct Pinned<'p, P> {
    inner: &'p P,
    index: usize,
    value: f64,
}

/// Why a coordinate cannot be held.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PinError {
    /// The index is not one of the problem's decision variables.
    #[error("variable {index} held, of a problem of {n} variables")]
    NoSuchVariable {
        /// The index asked for.
        index: usize,
        /// The problem's number of variables.
        n: usize,
    },
    /// Holding the only variable leaves nothing to minimise.
    #[error("the problem's only variable cannot be held")]
    OnlyVariable,
    /// The held value is not in the normalised box [0, 1].
    #[error("the held value {0} is not in [0, 1]")]
    OutsideBox(f64),
}

/// Scratch memory of one evaluation of a [`Pinned`] problem: the inner
/// problem's, the whole point, and the whole Jacobian or its factor.
#[derive(Debug)]
pub struct PinnedWorkspace<W> {
    inner: W,
    u: Vec<f64>,
    jac: DMatrix<f64>,
    qr: BlockedQr,
}

impl<'p, P: LeastSquares> Pinned<'p, P> {
    /// `inner` with variable `index` held at `value` ∈ [0, 1].
    pub fn new(inner: &'p P, index: usize, value: f64) -> Result<Self, PinError> {
        let n = inner.n_params();
        if index >= n {
            return Err(PinError::NoSuchVariable { index, n });
        }
        if n == 1 {
            return Err(PinError::OnlyVariable);
        }
        if !(0.0..=1.0).contains(&value) {
            return Err(PinError::OutsideBox(value));
        }
        Ok(Pinned {
            inner,
            index,
            value,
        })
    }

    /// The held variable's index in the inner problem.
    pub fn index(&self) -> usize {
        self.index
    }

    /// The held value (normalised).
    pub fn value(&self) -> f64 {
        self.value
    }

    /// The inner problem's point for the free variables `free` (length
    /// n − 1), into `full` (length n).
    pub fn expand(&self, free: &[f64], full: &mut [f64]) {
        let j = self.index;
        full[..j].copy_from_slice(&free[..j]);
        full[j] = self.value;
        full[j + 1..].copy_from_slice(&free[j..]);
    }

    /// The free variables of the inner problem's point `full`.
    pub fn reduce(&self, full: &[f64]) -> Vec<f64> {
        let mut free = full.to_vec();
        free.remove(self.index);
        free
    }
}

impl<P: LeastSquares> LeastSquares for Pinned<'_, P> {
    type Workspace = PinnedWorkspace<P::Workspace>;
    type Error = P::Error;

    fn n_params(&self) -> usize {
        self.inner.n_params() - 1
    }

    fn n_residuals(&self) -> usize {
        self.inner.n_residuals()
    }

    fn workspace(&self) -> Self::Workspace {
        let n = self.inner.n_params();
        let jac = match self.inner.jacobian_by_blocks() {
            true => DMatrix::zeros(0, 0),
            false => DMatrix::zeros(self.inner.n_residuals(), n),
        };
        PinnedWorkspace {
            inner: self.inner.workspace(),
            u: vec![0.0; n],
            jac,
            qr: BlockedQr::new(n),
        }
    }

    fn residuals(
        &self,
        ws: &mut Self::Workspace,
        u: &[f64],
        r: &mut [f64],
    ) -> Result<(), Self::Error> {
        self.expand(u, &mut ws.u);
        self.inner.residuals(&mut ws.inner, &ws.u, r)
    }

    fn residuals_jacobian(
        &self,
        ws: &mut Self::Workspace,
        u: &[f64],
        r: &mut [f64],
        jac: &mut DMatrix<f64>,
    ) -> Result<(), Self::Error> {
        self.expand(u, &mut ws.u);
        let shape = (self.inner.n_residuals(), self.inner.n_params());
        if ws.jac.shape() != shape {
            ws.jac = DMatrix::zeros(shape.0, shape.1);
        }
        self.inner
            .residuals_jacobian(&mut ws.inner, &ws.u, r, &mut ws.jac)?;
        let j = self.index;
        for (c, mut col) in jac.column_iter_mut().enumerate() {
            let src = if c < j { c } else { c + 1 };
            col.copy_from(&ws.jac.column(src));
        }
        Ok(())
    }

    fn jacobian_by_blocks(&self) -> bool {
        self.inner.jacobian_by_blocks()
    }

    fn residuals_factor(
        &self,
        ws: &mut Self::Workspace,
        u: &[f64],
        r: &mut [f64],
        qr: &mut BlockedQr,
    ) -> Result<(), Self::Error> {
        self.expand(u, &mut ws.u);
        self.inner
            .residuals_factor(&mut ws.inner, &ws.u, r, &mut ws.qr)?;
        ws.qr.without_column_into(self.index, qr);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// r_i = y_i − (a e^{−b t_i} + c t_i + a c): nonlinear in every
    /// variable, with an exact Jacobian.
    struct Curve {
        t: Vec<f64>,
        y: Vec<f64>,
        blocks: bool,
    }

    impl Curve {
        fn new(blocks: bool) -> Self {
            let t: Vec<f64> = (0..40).map(|i| i as f64 * 0.1).collect();
            let y = t.iter().map(|t| (0.3 * t).sin() + 1.0).collect();
            Curve { t, y, blocks }
        }
    }

    impl LeastSquares for Curve {
        type Workspace = ();
        type Error = std::fmt::Error;
        fn n_params(&self) -> usize {
            3
        }
        fn n_residuals(&self) -> usize {
            self.t.len()
        }
        fn workspace(&self) {}
        fn residuals(&self, _: &mut (), u: &[f64], r: &mut [f64]) -> Result<(), Self::Error> {
            for ((ri, t), y) in r.iter_mut().zip(&self.t).zip(&self.y) {
                *ri = y - (u[0] * (-u[1] * t).exp() + u[2] * t + u[0] * u[2]);
            }
            Ok(())
        }
        fn residuals_jacobian(
            &self,
            ws: &mut (),
            u: &[f64],
            r: &mut [f64],
            jac: &mut DMatrix<f64>,
        ) -> Result<(), Self::Error> {
            self.residuals(ws, u, r)?;
            for (i, t) in self.t.iter().enumerate() {
                let e = (-u[1] * t).exp();
                jac[(i, 0)] = -(e + u[2]);
                jac[(i, 1)] = u[0] * t * e;
                jac[(i, 2)] = -(t + u[0]);
            }
            Ok(())
        }
        fn jacobian_by_blocks(&self) -> bool {
            self.blocks
        }
    }

    const U: [f64; 3] = [0.7, 0.4, 0.2];

    #[test]
    fn the_jacobian_is_the_inner_one_without_the_held_column() {
        let inner = Curve::new(false);
        let mut whole = DMatrix::zeros(40, 3);
        let mut r_whole = vec![0.0; 40];
        inner
            .residuals_jacobian(&mut (), &U, &mut r_whole, &mut whole)
            .unwrap();
        for (j, &uj) in U.iter().enumerate() {
            let p = Pinned::new(&inner, j, uj).unwrap();
            let free = p.reduce(&U);
            let mut ws = p.workspace();
            let (mut r, mut jac) = (vec![0.0; 40], DMatrix::zeros(40, 2));
            p.residuals_jacobian(&mut ws, &free, &mut r, &mut jac)
                .unwrap();
            assert_eq!(r, r_whole);
            assert_eq!(jac, whole.clone().remove_column(j));
            let mut r2 = vec![0.0; 40];
            p.residuals(&mut ws, &free, &mut r2).unwrap();
            assert_eq!(r2, r_whole);
        }
    }

    #[test]
    fn the_factor_is_that_of_the_jacobian_without_the_held_column() {
        let inner = Curve::new(true);
        let mut whole = DMatrix::zeros(40, 3);
        let mut r_whole = vec![0.0; 40];
        inner
            .residuals_jacobian(&mut (), &U, &mut r_whole, &mut whole)
            .unwrap();
        for (j, &uj) in U.iter().enumerate() {
            let p = Pinned::new(&inner, j, uj).unwrap();
            let free = p.reduce(&U);
            let mut ws = p.workspace();
            let (mut r, mut qr) = (vec![0.0; 40], BlockedQr::new(7));
            p.residuals_factor(&mut ws, &free, &mut r, &mut qr).unwrap();
            let reduced = whole.clone().remove_column(j);
            let expected = BlockedQr::from_rows(&reduced, &r_whole, 8);
            let (rtr, rtr_expected) = (qr.r().tr_mul(qr.r()), reduced.tr_mul(&reduced));
            assert!((rtr - &rtr_expected).norm() <= 1e-12 * rtr_expected.norm());
            let g = qr.gradient();
            for (a, b) in g.iter().zip(expected.gradient()) {
                assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{a} {b}");
            }
            let ssr_total = qr.ssr_rest() + qr.qtr().iter().map(|v| v * v).sum::<f64>();
            let ssr: f64 = r_whole.iter().map(|v| v * v).sum();
            assert!((ssr_total - ssr).abs() <= 1e-12 * ssr);
            assert!((qr.ssr_rest() - expected.ssr_rest()).abs() <= 1e-10 * ssr);
            assert_eq!(qr.r()[(1, 0)], 0.0, "triangular");
        }
    }

    #[test]
    fn holding_a_variable_that_does_not_exist_is_an_error() {
        let inner = Curve::new(false);
        assert!(matches!(
            Pinned::new(&inner, 3, 0.5),
            Err(PinError::NoSuchVariable { index: 3, n: 3 })
        ));
        assert!(matches!(
            Pinned::new(&inner, 0, 1.5),
            Err(PinError::OutsideBox(_))
        ));
        assert!(matches!(
            Pinned::new(&inner, 0, f64::NAN),
            Err(PinError::OutsideBox(_))
        ));
    }
}
