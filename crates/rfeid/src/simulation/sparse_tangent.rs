//! The forward sensitivity equation's right-hand side element by element
//! (the sparse counterpart of `tangent`): for `Y = [Y_q; Y_v] = ∂y/∂x`,
//!
//! `∂q̈/∂x = Σ_i (−M⁻¹B_iᵀ) (f_i'(δ_i) B_i Y_q + c_i B_i Y_v + ∂f_i/∂x) + …`
//!
//! over the component rows i (eq. 2–7, 27–28), each touching at most 12
//! coordinates: three multiply–adds per nonzero entry of B_i and column (at
//! most 36, about 12 for an element whose axes are its bodies') instead of
//! the dense `2n²` per column. The mass, inertia and load terms are added by
//! the caller. Every column goes through the same operations in the same
//! order whatever the number of columns, so a column's values do not depend
//! on which other columns are computed with it.
use super::force_derivative::force_derivative;
use super::laws::contact::ContactState;
use super::laws::friction::FrictionAt;
use super::laws::power_law;
use super::madd::Madd;
use super::preload::power_change;
use super::preload::Preload;
use super::sparse::{SparseComp, SparsePower};
use super::structure::Usage;
use super::system::System;

/// The identified parameters acting on one component: (column, usage).
pub(crate) type ComponentUsages = Vec<(usize, Usage)>;

/// A component's nonzero entries of B, in the order a dense loop visits
/// them, laid out for rows of the sensitivities `width` long: where each
/// entry's row starts (coordinate × width), and its entries of B and of
/// `−M⁻¹Bᵀ`. About a third of the entries are nonzero where an element's
/// axes are its bodies'; a skipped term would add an exact zero, so the
/// sums are unchanged. Built once per run, so that the kernel's inner
/// loops only load.
#[derive(Debug, Clone)]
pub(crate) struct Entries {
    at: [usize; 12],
    b: [f64; 12],
    g: [f64; 12],
    len: usize,
    /// Whether the component adds `k B Y_q + c B Y_v` alone: a linear
    /// spring and damper that no identified parameter enters, with no
    /// static columns. Its slopes are then its constant k and c, and the
    /// kernel skips its deformation and laws ([`linear_columns`]).
    linear: bool,
}

impl Entries {
    /// The entries of `comp` for rows `width` long; `usages` and `statics`
    /// are the component's (see [`sparse_tangent`]).
    pub fn new(
        comp: &SparseComp,
        width: usize,
        usages: &[(usize, Usage)],
        statics: &[f64],
    ) -> Entries {
        let laws = comp.power.is_some() || comp.friction.is_some() || comp.contact.is_some();
        let mut e = Entries {
            at: [0; 12],
            b: [0.0; 12],
            g: [0.0; 12],
            len: 0,
            linear: !laws && usages.is_empty() && statics.is_empty(),
        };
        for j in (0..12).filter(|&j| comp.b[j] != 0.0) {
            e.at[e.len] = (comp.off[j / 6] + j % 6) * width;
            e.b[e.len] = comp.b[j];
            e.g[e.len] = comp.g[j];
            e.len += 1;
        }
        e
    }

    /// `(row start, B entry, −M⁻¹Bᵀ entry)` of each nonzero entry.
    #[inline(always)]
    fn iter(&self) -> impl Iterator<Item = (usize, f64, f64)> + '_ {
        let at = &self.at[..self.len];
        at.iter()
            .zip(&self.b)
            .zip(&self.g)
            .map(|((a, b), g)| (*a, *b, *g))
    }
}

/// `dacc = Σ_i g_i (slope_i B_i Y_q + c_i B_i Y_v + ∂f_i/∂x)` (n rows of
/// `width`, a multiple of four) at the state `(q, v)` with each contact on
/// its side in `contact_sides` ([`System::accel_with`]), for the
/// sensitivities `sy` (2n rows of `width`); `usages[i]` lists the
/// parameters (column, usage) acting on component i, and `entries[i]` its
/// nonzero entries for rows `width` long. About a static equilibrium
/// (`preload`), `statics[i]` is `B_i ∂q₀/∂x` (empty if not needed), which
/// adds `g_i (slope_i − slope_i(δ₀)) B_i ∂q₀/∂x`.
#[inline(always)]
pub(crate) fn sparse_tangent<M: Madd>(
    sys: &System<'_>,
    (usages, statics, entries): (&[ComponentUsages], &[Vec<f64>], &[Entries]),
    (q, v, contact_sides): (&[f64], &[f64], &[f64]),
    sy: &[f64],
    width: usize,
    dacc: &mut [f64],
) {
    let n = q.len();
    let (yq, yv) = sy[..2 * n * width].split_at(n * width);
    dacc.fill(0.0);
    let per_component = usages.iter().zip(statics).zip(entries);
    for (comp, ((usages, statics), entries)) in sys.comps.iter().zip(per_component) {
        if entries.linear {
            // The same operations as below with no law, no explicit
            // dependence and no static change, so the same sums.
            let mut c0 = 0;
            while c0 + 8 <= width {
                linear_columns::<M, 8>(entries, (comp.k, comp.c), (yq, yv), c0, dacc);
                c0 += 8;
            }
            if c0 < width {
                linear_columns::<M, 4>(entries, (comp.k, comp.c), (yq, yv), c0, dacc);
            }
            continue;
        }
        let d = comp.rate::<M>(q);
        let power = comp.power(&sys.powers);
        let (slope, change) = match power {
            Some(&SparsePower { spring: p, pre }) => {
                let slope = comp.k + power_law(p.coef, p.m, pre.d0 + d).1;
                let change = match statics.is_empty() {
                    true => 0.0,
                    false => power_change(p.coef, p.m, &pre, d).1,
                };
                (slope, change)
            }
            None => (comp.k, 0.0),
        };
        // A friction law's slope in δ̇ adds to the damping, a contact's
        // slopes to both.
        let law = comp.friction.map(|j| &sys.frictions[j as usize].law);
        let friction = FrictionAt::of(law, || comp.rate::<M>(v));
        let (law, side) = match comp.contact {
            Some(j) => (
                Some(&sys.contacts[j as usize].law),
                contact_sides.get(j as usize).copied().unwrap_or(0.0),
            ),
            None => (None, 0.0),
        };
        let contact = ContactState::of(law, (d, side), || comp.rate::<M>(v));
        let damp = comp.c + friction.slope() + contact.at.damping;
        let slope = slope + contact.at.slope;
        let change = match statics.is_empty() {
            true => change,
            false => change + contact.slope_change(),
        };
        let explicit = Explicit {
            power,
            friction,
            contact,
            usages,
            d,
            v,
            change,
            statics,
        };
        let comp = (comp, entries);
        let mut c0 = 0;
        while c0 + 8 <= width {
            component_columns::<M, 8>(comp, &explicit, (slope, damp), (yq, yv), c0, dacc);
            c0 += 8;
        }
        if c0 < width {
            component_columns::<M, 4>(comp, &explicit, (slope, damp), (yq, yv), c0, dacc);
        }
    }
}

/// What a component adds to the sensitivities beside `slope B Y_q + c B
/// Y_v`: the explicit dependences on its parameters, and the slope's change
/// times `B ∂q₀/∂x` under a preload.
struct Explicit<'a> {
    /// The component's power-law spring, if any.
    power: Option<&'a SparsePower>,
    /// The component's friction law at its δ̇ ([`FrictionAt::NONE`]
    /// without one).
    friction: FrictionAt<'a>,
    /// The component's contact law at its state ([`ContactState::NONE`]
    /// without one).
    contact: ContactState,
    /// (column, usage) of the parameters acting on the component.
    usages: &'a [(usize, Usage)],
    /// Its deformation (from the static one, if any).
    d: f64,
    /// The velocities, for a damping's δ̇.
    v: &'a [f64],
    /// The slope's change from the static deformation.
    change: f64,
    /// `B ∂q₀/∂x` (width), or empty.
    statics: &'a [f64],
}

/// Columns `c0..c0 + W` of one component's contribution to `dacc`.
#[inline(always)]
fn component_columns<M: Madd, const W: usize>(
    (comp, entries): (&SparseComp, &Entries),
    e: &Explicit<'_>,
    (slope, damp): (f64, f64),
    (yq, yv): (&[f64], &[f64]),
    c0: usize,
    dacc: &mut [f64],
) {
    // s = ∂f/∂x (explicit), then + slope B Y_q + c B Y_v ([`add_columns`]).
    let mut s = [0.0; W];
    if e.change != 0.0 {
        for (s, w) in s.iter_mut().zip(&e.statics[c0..c0 + W]) {
            *s = e.change * w;
        }
    }
    let (d, v) = (e.d, e.v);
    for &(col, usage) in e.usages {
        if (c0..c0 + W).contains(&col) {
            let (spring, pre) = match e.power {
                Some(p) => (Some(p.spring), p.pre),
                None => (None, Preload::default()),
            };
            let laws = (spring, &e.friction, &e.contact);
            s[col - c0] += force_derivative(usage, laws, &pre, d, || comp.rate::<M>(v));
        }
    }
    add_columns::<M, W>(entries, (slope, damp), (yq, yv), (c0, s), dacc);
}

/// Columns `c0..c0 + W` of a linear component's contribution to `dacc`,
/// `g (k B Y_q + c B Y_v)` ([`Entries::linear`]): [`component_columns`]
/// without the explicit terms, which are zero for it.
#[inline(always)]
fn linear_columns<M: Madd, const W: usize>(
    entries: &Entries,
    (k, c): (f64, f64),
    (yq, yv): (&[f64], &[f64]),
    c0: usize,
    dacc: &mut [f64],
) {
    add_columns::<M, W>(entries, (k, c), (yq, yv), (c0, [0.0; W]), dacc);
}

/// `dacc += g (s + slope B Y_q + damp B Y_v)` for columns `c0..c0 + W`,
/// with `s` the explicit terms: the products in two chains, one per half
/// of Y, added at the end.
#[inline(always)]
fn add_columns<M: Madd, const W: usize>(
    entries: &Entries,
    (slope, damp): (f64, f64),
    (yq, yv): (&[f64], &[f64]),
    (c0, mut s): (usize, [f64; W]),
    dacc: &mut [f64],
) {
    let mut t = [0.0; W];
    for (at, b, _) in entries.iter() {
        let (bs, bc) = (slope * b, damp * b);
        let at = at + c0;
        let (xq, xv) = (&yq[at..at + W], &yv[at..at + W]);
        for l in 0..W {
            s[l] = M::madd(bs, xq[l], s[l]);
            t[l] = M::madd(bc, xv[l], t[l]);
        }
    }
    for l in 0..W {
        s[l] += t[l];
    }
    for (at, _, g) in entries.iter() {
        let at = at + c0;
        let out = &mut dacc[at..at + W];
        for l in 0..W {
            out[l] = M::madd(g, s[l], out[l]);
        }
    }
}
