//! The forward sensitivity equation's right-hand side element by element
//! (the sparse counterpart of `tangent`): for `Y = [Y_q; Y_v] = ∂y/∂x`,
//!
//! `∂q̈/∂x = Σ_i (−M⁻¹B_iᵀ) (f_i'(δ_i) B_i Y_q + c_i B_i Y_v + ∂f_i/∂x) + …`
//!
//! over the component rows i (eq. 2–7, 27–28), each touching at most 12
//! coordinates: about 36 multiply–adds per component and column instead of
//! the dense `2n²` per column. The mass, inertia and load terms are added by
//! the caller. Every column goes through the same operations in the same
//! order whatever the number of columns, so a column's values do not depend
//! on which other columns are computed with it.
use super::madd::Madd;
use super::sparse::SparseComp;
use super::structure::Usage;
use super::system::{power_law, System};
use super::tangent::force_derivative;

/// `dacc = Σ_i g_i (slope_i B_i Y_q + c_i B_i Y_v + ∂f_i/∂x)` (n rows of
/// `width`, a multiple of four) at the state `(q, v)`, for the
/// sensitivities `sy` (2n rows of `width`); `usages[i]` lists the
/// parameters (column, usage) acting on component i.
#[inline(always)]
pub(crate) fn sparse_tangent<M: Madd>(
    sys: &System<'_>,
    usages: &[Vec<(usize, Usage)>],
    (q, v): (&[f64], &[f64]),
    sy: &[f64],
    width: usize,
    dacc: &mut [f64],
) {
    let n = q.len();
    let (yq, yv) = sy[..2 * n * width].split_at(n * width);
    dacc.fill(0.0);
    for (comp, usages) in sys.comps.iter().zip(usages) {
        let [o0, o1] = comp.off;
        let mut d = [0.0; 2];
        for i in 0..6 {
            d[0] = M::madd(comp.b[i], q[o0 + i], d[0]);
            d[1] = M::madd(comp.b[6 + i], q[o1 + i], d[1]);
        }
        let d = d[0] + d[1];
        let slope = match comp.power {
            Some(p) => comp.k + power_law(p.coef, p.m, d).1,
            None => comp.k,
        };
        let rows = [o0, o1];
        let mut c0 = 0;
        while c0 + 8 <= width {
            component_columns::<M, 8>(comp, usages, (slope, d, v), rows, (yq, yv), width, c0, dacc);
            c0 += 8;
        }
        if c0 < width {
            component_columns::<M, 4>(comp, usages, (slope, d, v), rows, (yq, yv), width, c0, dacc);
        }
    }
}

/// Columns `c0..c0 + W` of one component's contribution to `dacc`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn component_columns<M: Madd, const W: usize>(
    comp: &SparseComp,
    usages: &[(usize, Usage)],
    (slope, d, v): (f64, f64, &[f64]),
    [o0, o1]: [usize; 2],
    (yq, yv): (&[f64], &[f64]),
    width: usize,
    c0: usize,
    dacc: &mut [f64],
) {
    // s = ∂f/∂x (explicit), then + slope B Y_q + c B Y_v, in two chains.
    let mut s = [0.0; W];
    let mut t = [0.0; W];
    for &(col, usage) in usages {
        if (c0..c0 + W).contains(&col) {
            s[col - c0] += force_derivative(usage, comp.power, d, || {
                let mut dv = [0.0; 2];
                for i in 0..6 {
                    dv[0] = M::madd(comp.b[i], v[o0 + i], dv[0]);
                    dv[1] = M::madd(comp.b[6 + i], v[o1 + i], dv[1]);
                }
                dv[0] + dv[1]
            });
        }
    }
    for j in 0..12 {
        let row = [o0, o1][j / 6] + j % 6;
        let (bs, bc) = (slope * comp.b[j], comp.c * comp.b[j]);
        let at = row * width + c0;
        let (xq, xv) = (&yq[at..at + W], &yv[at..at + W]);
        for l in 0..W {
            s[l] = M::madd(bs, xq[l], s[l]);
            t[l] = M::madd(bc, xv[l], t[l]);
        }
    }
    for l in 0..W {
        s[l] += t[l];
    }
    for j in 0..12 {
        let row = [o0, o1][j / 6] + j % 6;
        let at = row * width + c0;
        let out = &mut dacc[at..at + W];
        for l in 0..W {
            out[l] = M::madd(comp.g[j], s[l], out[l]);
        }
    }
}
