//! The equations of motion (eq. 1) element by element, for large models.
//!
//! `q̈ = g + M⁻¹(P(t) − Bᵀ f(B q, B q̇))`: each component row of B couples at
//! most two bodies (two 6-blocks, `structure`), and M is diagonal, so one
//! acceleration costs a few dozen operations per component instead of the
//! dense kernel's `n (2n + …)` (`system`). Each component carries its whole
//! force `f_i = k_i δ_i + law_i(δ_i) + c_i δ̇_i` (eq. 2–7) and adds
//! `f_i · (−M⁻¹ B_iᵀ)` to the acceleration. The dense kernel is faster for a
//! few bodies; [`prefer_sparse`] chooses by the operation counts.
use super::madd::Madd;
use super::preload::{power_change, Preload};
use super::structure::{Row, Structure};
use crate::model::PowerSpring;

/// One component row with its coefficients at one parameter point,
/// starting on a cache line so that four-lane loads of its rows never
/// straddle two lines.
#[derive(Debug, Clone)]
#[repr(C, align(64))]
pub(crate) struct SparseComp {
    /// B_i, both blocks (12).
    pub b: [f64; 12],
    /// `−M⁻¹ B_iᵀ`, both blocks (12).
    pub g: [f64; 12],
    /// First coordinate of each of the (one or two) blocks; a ground
    /// element repeats its block with zero coefficients.
    pub off: [usize; 2],
    /// Linear stiffness k (0 for none or a power law).
    pub k: f64,
    /// Damping c.
    pub c: f64,
    /// The index of its power-law spring in the [`SparsePower`] list, if it
    /// has one (kept out of the component, which the kernels stream).
    pub power: Option<u32>,
    /// Bit j set where `b[j]` is nonzero: the entries a sensitivity kernel
    /// visits (about a third of them when the element's axes are the
    /// bodies'; a skipped term would add an exact zero).
    pub nonzero: u16,
}

impl SparseComp {
    /// The component's power-law spring in `powers`, if any.
    #[inline(always)]
    pub fn power<'p>(&self, powers: &'p [SparsePower]) -> Option<&'p SparsePower> {
        self.power.map(|j| &powers[j as usize])
    }
}

/// A power-law spring of the element-by-element kernels, in component order.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SparsePower {
    /// The spring.
    pub spring: PowerSpring,
    /// Its static deformation (zero without one).
    pub pre: Preload,
}

/// The components of `structure` with their coefficients, and their
/// power-law springs; `coef(i)` gives component i's `(k, c, spring)`.
pub(crate) fn sparse_components(
    structure: &Structure,
    minv: &[f64],
    coef: impl Fn(usize) -> (f64, f64, Option<PowerSpring>),
) -> (Vec<SparseComp>, Vec<SparsePower>) {
    let mut powers = Vec::new();
    let comps = structure
        .components
        .iter()
        .enumerate()
        .map(|(i, comp)| {
            let (k, c, spring) = coef(i);
            let power = spring.map(|spring| {
                powers.push(SparsePower {
                    spring,
                    pre: Preload::default(),
                });
                (powers.len() - 1) as u32
            });
            let mut off = [0; 2];
            let mut b = [0.0; 12];
            let mut g = [0.0; 12];
            for (s, (o, coefs)) in comp.row.blocks.iter().enumerate().take(2) {
                off[s] = *o;
                b[6 * s..6 * s + 6].copy_from_slice(coefs);
            }
            if comp.row.blocks.len() < 2 {
                off[1] = off[0];
            }
            let mut nonzero = 0;
            for (j, gj) in g.iter_mut().enumerate() {
                *gj = -b[j] * minv[off[j / 6] + j % 6];
                nonzero |= u16::from(b[j] != 0.0) << j;
            }
            SparseComp {
                off,
                b,
                g,
                k,
                c,
                power,
                nonzero,
            }
        })
        .collect();
    (comps, powers)
}

/// The ranges of consecutive components that share their blocks (one
/// element's components), as `(start, end)`.
pub(crate) fn element_ranges(comps: &[SparseComp]) -> Vec<(usize, usize)> {
    let mut ranges: Vec<(usize, usize)> = Vec::new();
    for (i, comp) in comps.iter().enumerate() {
        match ranges.last_mut() {
            Some(last) if comps[last.0].off == comp.off => last.1 = i + 1,
            _ => ranges.push((i, i + 1)),
        }
    }
    ranges
}

/// Whether the element-by-element kernel does fewer operations than the
/// dense one for `n` coordinates, `components` component rows of which
/// `power` are power laws, and `width` sensitivity columns (0 for none).
///
/// Per stage, the dense kernel multiplies `n × (2n + power)` (and, with
/// sensitivities, `n × 2n` per column); the sparse one about 40 operations
/// per component (and 36 per component and column), plus its scattered
/// memory access, counted as a factor of two.
pub(crate) fn prefer_sparse(n: usize, components: usize, power: usize, width: usize) -> bool {
    let dense = n * (2 * n + 2 * power) + width * 2 * n * n;
    let sparse = 2 * (40 * components + 36 * components * width);
    sparse < dense
}

/// `acc = base + M⁻¹(Σ_e L_e P_e − Σ_i B_iᵀ f_i)` for the state `y = [q;
/// q̇]`; `base` is `M⁻¹ × weight`, or zero for the deviation from the static
/// equilibrium, whose power-law forces are then changes (`preload`).
#[inline(always)]
pub(crate) fn sparse_accel<M: Madd>(
    (comps, powers, elements): (&[SparseComp], &[SparsePower], &[(usize, usize)]),
    base: &[f64],
    minv_loads: &[Row],
    forces: &[f64],
    y: &[f64],
    acc: &mut [f64],
) {
    let n = acc.len();
    let (q, v) = y[..2 * n].split_at(n);
    acc.copy_from_slice(&base[..n]);
    for (load, &p) in minv_loads.iter().zip(forces) {
        for (o, l) in &load.blocks {
            let a = &mut acc[*o..*o + 6];
            for i in 0..6 {
                a[i] = M::madd(l[i], p, a[i]);
            }
        }
    }
    // The components of one element are consecutive and share their
    // blocks: gather the blocks once, sum the element's forces in
    // registers, scatter once.
    for &(start, end) in elements {
        let [o0, o1] = comps[start].off;
        let (mut x, mut xv) = ([0.0; 12], [0.0; 12]);
        x[..6].copy_from_slice(&q[o0..o0 + 6]);
        x[6..].copy_from_slice(&q[o1..o1 + 6]);
        xv[..6].copy_from_slice(&v[o0..o0 + 6]);
        xv[6..].copy_from_slice(&v[o1..o1 + 6]);
        let mut fg = [0.0; 12];
        for comp in &comps[start..end] {
            // k δ + c δ̇ lane by lane, then one sum across the lanes.
            let (d, dv) = (lanes12::<M>(&comp.b, &x), lanes12::<M>(&comp.b, &xv));
            let mut lin = [0.0; 4];
            for j in 0..4 {
                lin[j] = M::madd(comp.c, dv[j], comp.k * d[j]);
            }
            let mut f = sum4(lin);
            if let Some(p) = comp.power(powers) {
                f += power_change(p.spring.coef, p.spring.m, &p.pre, sum4(d)).0;
            }
            for (a, g) in fg.iter_mut().zip(&comp.g) {
                *a = M::madd(f, *g, *a);
            }
        }
        for (a, f) in acc[o0..o0 + 6].iter_mut().zip(&fg[..6]) {
            *a += f;
        }
        for (a, f) in acc[o1..o1 + 6].iter_mut().zip(&fg[6..]) {
            *a += f;
        }
    }
}

/// `b · x` for 12-vectors as four interleaved partial sums (one SIMD
/// register's lanes), so that the products are not one dependent chain;
/// [`sum4`] adds them up.
#[inline(always)]
fn lanes12<M: Madd>(b: &[f64; 12], x: &[f64; 12]) -> [f64; 4] {
    let mut s = [0.0; 4];
    for (bc, xc) in b.chunks_exact(4).zip(x.chunks_exact(4)) {
        for j in 0..4 {
            s[j] = M::madd(bc[j], xc[j], s[j]);
        }
    }
    s
}

/// The sum of four lanes, pairwise.
#[inline(always)]
fn sum4(s: [f64; 4]) -> f64 {
    (s[0] + s[2]) + (s[1] + s[3])
}
