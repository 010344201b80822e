//! The equations of motion (eq. 1) element by element, for large models.
//!
//! `q̈ = g + M⁻¹(P(t) − Bᵀ f(B q, B q̇))`: each component row of B couples at
//! most two bodies (two 6-blocks, `structure`), and M is diagonal, so one
//! acceleration costs a few dozen operations per component instead of the
//! dense kernel's `n (2n + …)` (`system`). Each component carries its whole
//! force `f_i = k_i δ_i + law_i(δ_i) + c_i δ̇_i` (eq. 2–7) and adds
//! `f_i · (−M⁻¹ B_iᵀ)` to the acceleration; the kernel takes the components
//! of an element four at a time, one per register lane ([`SparseGroup`]).
//! The dense kernel is faster for a few bodies; [`prefer_sparse`] chooses.
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
    /// The index of its friction law in the system's friction list, if it
    /// has one.
    pub friction: Option<u32>,
    /// The index of its contact law in the system's contact list, if it
    /// has one.
    pub contact: Option<u32>,
}

impl SparseComp {
    /// `B_i x` for a vector of coordinates x (the coordinates give δ, the
    /// velocities δ̇), in two partial sums, one per block.
    #[inline(always)]
    pub fn rate<M: Madd>(&self, x: &[f64]) -> f64 {
        let [o0, o1] = self.off;
        let mut d = [0.0; 2];
        for i in 0..6 {
            d[0] = M::madd(self.b[i], x[o0 + i], d[0]);
            d[1] = M::madd(self.b[6 + i], x[o1 + i], d[1]);
        }
        d[0] + d[1]
    }

    /// `B_i` times column `col` of the sensitivity rows `rows` (each
    /// `width` long) from row `first` on (0 for the coordinates', n for the
    /// velocities'), summed in the order of B's entries.
    #[inline(always)]
    pub fn column_rate(&self, rows: &[f64], first: usize, width: usize, col: usize) -> f64 {
        let mut g = 0.0;
        for (i, &b) in self.b.iter().enumerate() {
            g += b * rows[(first + self.off[i / 6] + i % 6) * width + col];
        }
        g
    }

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
            for (j, gj) in g.iter_mut().enumerate() {
                *gj = -b[j] * minv[off[j / 6] + j % 6];
            }
            SparseComp {
                off,
                b,
                g,
                k,
                c,
                power,
                friction: None,
                contact: None,
            }
        })
        .collect();
    (comps, powers)
}

/// Up to four components of one element (or of elements between the same
/// two bodies), transposed so that the kernel computes their four
/// deformations in the four lanes of one register: the accelerations' unit
/// of work ([`sparse_accel`]).
#[derive(Debug, Clone)]
#[repr(C, align(64))]
pub(crate) struct SparseGroup {
    /// `bt[j][l]`: entry j of lane l's row of B (zero in an unused lane).
    pub bt: [[f64; 4]; 12],
    /// Linear stiffness per lane.
    pub k: [f64; 4],
    /// Damping per lane.
    pub c: [f64; 4],
    /// `−M⁻¹ B_lᵀ` per lane, in register-sized pieces (zero in an unused
    /// lane).
    pub g: [[[f64; 4]; 3]; 4],
    /// The components' blocks ([`SparseComp::off`]).
    pub off: [usize; 2],
    /// Whether the second block is a body's (not a ground element's).
    pub second: bool,
    /// Whether any lane has a power-law spring.
    pub any_power: bool,
    /// The power-law spring of each lane in the [`SparsePower`] list.
    pub power: [Option<u32>; 4],
}

/// The components in groups of at most four consecutive ones that share
/// their blocks ([`SparseGroup`]).
pub(crate) fn sparse_groups(comps: &[SparseComp]) -> Vec<SparseGroup> {
    let mut groups: Vec<SparseGroup> = Vec::new();
    let mut lanes = 0;
    for comp in comps {
        match groups.last_mut() {
            Some(last) if last.off == comp.off && lanes < 4 => lanes += 1,
            _ => {
                groups.push(SparseGroup {
                    bt: [[0.0; 4]; 12],
                    k: [0.0; 4],
                    c: [0.0; 4],
                    g: [[[0.0; 4]; 3]; 4],
                    off: comp.off,
                    second: comp.off[1] != comp.off[0],
                    any_power: false,
                    power: [None; 4],
                });
                lanes = 1;
            }
        }
        let (group, l) = (groups.last_mut().expect("pushed"), lanes - 1);
        for (j, b) in comp.b.iter().enumerate() {
            group.bt[j][l] = *b;
        }
        group.k[l] = comp.k;
        group.c[l] = comp.c;
        for (j, g) in comp.g.iter().enumerate() {
            group.g[l][j / 4][j % 4] = *g;
        }
        group.power[l] = comp.power;
        group.any_power |= comp.power.is_some();
    }
    groups
}

/// Whether the element-by-element kernel is the faster one for `n`
/// coordinates with `power` power-law rows and `groups` [`SparseGroup`]s.
///
/// Costs per stage in units of the dense kernel's time per multiply–add,
/// fitted to timings of both kernels on the knee–column and on generated
/// machine tools of 2–8 bodies (`examples/kernels.rs`): `2n(n + power)` for
/// the dense kernel, 100 per group for the sparse one. The choice ignores
/// the sensitivities, so that a run's response is the same bit for bit with
/// or without them (a Jacobian and the criterion it is compared with come
/// from the same simulation); in those timings the kernel that is faster
/// for the state alone was also within 5 % of the faster with 16
/// sensitivities, or faster.
pub(crate) fn prefer_sparse(n: usize, power: usize, groups: usize) -> bool {
    100 * groups < 2 * n * (n + power)
}

/// `acc = base + M⁻¹(Σ_e L_e P_e − Σ_i B_iᵀ f_i)` for the state `y = [q;
/// q̇]`; `base` is `M⁻¹ × weight`, or zero for the deviation from the static
/// equilibrium, whose power-law forces are then changes (`preload`).
///
/// Per group of four components: δ and δ̇ in four lanes, block by block
/// (`δ = B_i⁽⁰⁾ q⁽⁰⁾ + B_i⁽¹⁾ q⁽¹⁾`, the sensitivity kernel's order), the forces
/// `f = k δ + c δ̇ (+ law(δ))` (eq. 2–7), then `Σ_l f_l (−M⁻¹ B_lᵀ)` added to
/// the two bodies' accelerations.
#[inline(always)]
pub(crate) fn sparse_accel<M: Madd>(
    (groups, powers): (&[SparseGroup], &[SparsePower]),
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
    for group in groups {
        let [o0, o1] = group.off;
        // A ground element's second block is zero: adding its zero terms
        // costs less than a branch.
        let (d0, dv0) = block_lanes::<M>(&group.bt[..6], &q[o0..o0 + 6], &v[o0..o0 + 6]);
        let (d1, dv1) = block_lanes::<M>(&group.bt[6..], &q[o1..o1 + 6], &v[o1..o1 + 6]);
        let (mut d, mut dv, mut kd) = ([0.0; 4], [0.0; 4], [0.0; 4]);
        for l in 0..4 {
            d[l] = d0[l] + d1[l];
            dv[l] = dv0[l] + dv1[l];
            kd[l] = group.k[l] * d[l];
        }
        let mut f = M::madd4(group.c, dv, kd);
        if group.any_power {
            for (f, (power, d)) in f.iter_mut().zip(group.power.iter().zip(d)) {
                if let Some(j) = power {
                    let p = &powers[*j as usize];
                    *f += power_change(p.spring.coef, p.spring.m, &p.pre, d).0;
                }
            }
        }
        let mut s = [[0.0; 4]; 3];
        for (f, g) in f.iter().zip(&group.g) {
            for (s, g) in s.iter_mut().zip(g) {
                *s = M::madd4([*f; 4], *g, *s);
            }
        }
        let s = s.as_flattened();
        for (a, s) in acc[o0..o0 + 6].iter_mut().zip(&s[..6]) {
            *a += s;
        }
        if group.second {
            for (a, s) in acc[o1..o1 + 6].iter_mut().zip(&s[6..]) {
                *a += s;
            }
        }
    }
}

/// `(Σ_i bt[i] x[i], Σ_i bt[i] v[i])` over one block's six coordinates, in
/// four lanes.
#[inline(always)]
fn block_lanes<M: Madd>(bt: &[[f64; 4]], x: &[f64], v: &[f64]) -> ([f64; 4], [f64; 4]) {
    let (mut d, mut dv) = ([0.0; 4], [0.0; 4]);
    for i in 0..6 {
        d = M::madd4(bt[i], [x[i]; 4], d);
        dv = M::madd4(bt[i], [v[i]; 4], dv);
    }
    (d, dv)
}
