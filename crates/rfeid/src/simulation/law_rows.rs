//! The components whose law the kernels evaluate beside their linear part
//! (friction, Bouc–Wen, contact), each as a [`LawRow`]: the component's index and
//! its law with numbers in. Their forces enter the accelerations as
//! `f (−M⁻¹B_iᵀ)` after either kernel; a Bouc–Wen law's state z also has
//! its rate and the sensitivities' terms (eq. 27–28 extended by the rows of
//! ∂z/∂x).
use super::laws::bouc_wen::{BoucWenLaw, Branch};
use super::laws::contact::ContactForce;
use super::laws::friction::FrictionForce;
use super::laws::Law;
use super::madd::Madd;
use super::sparse::SparseComp;
use super::structure::{ComponentRow, HysteresisKey};
use super::SimulationError;
use crate::model::Model;

/// A component of the kernels with a law of its own: its index in the
/// component list ([`SparseComp`], whose rows it uses) and its law.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LawRow<L> {
    /// The component's index.
    pub comp: usize,
    /// The law at the run's parameter values.
    pub law: L,
}

/// A friction component.
pub(crate) type FrictionRow = LawRow<FrictionForce>;

/// A Bouc–Wen component.
pub(crate) type HysteresisRow = LawRow<BoucWenLaw>;

/// A contact component.
pub(crate) type ContactRow = LawRow<ContactForce>;

/// The components of `components` (in order) whose law `pick` takes, with
/// that law at the run's parameter values (`pick` is given the element's
/// name for its errors).
fn law_rows<L>(
    model: &Model,
    components: &[ComponentRow],
    pick: impl Fn(&Law, &str) -> Option<Result<L, SimulationError>>,
) -> Result<Vec<LawRow<L>>, SimulationError> {
    let mut rows = Vec::new();
    for (i, c) in components.iter().enumerate() {
        if let Some(law) = pick(&c.law, &model.elements[c.element].name) {
            rows.push(LawRow { comp: i, law: law? });
        }
    }
    Ok(rows)
}

/// The friction components with their laws at the parameter values `p`.
pub(crate) fn friction_rows(
    model: &Model,
    components: &[ComponentRow],
    p: &[f64],
) -> Result<Vec<FrictionRow>, SimulationError> {
    law_rows(model, components, |law, element| match law {
        Law::Friction(fr) => Some(FrictionForce::new(fr, p, element)),
        _ => None,
    })
}

/// The Bouc–Wen components with their laws at the parameter values `p`.
pub(crate) fn hysteresis_rows(
    model: &Model,
    components: &[ComponentRow],
    p: &[f64],
) -> Result<Vec<HysteresisRow>, SimulationError> {
    law_rows(model, components, |law, element| match law {
        Law::BoucWen(bw) => Some(BoucWenLaw::new(bw, p, element)),
        _ => None,
    })
}

/// The contact components with their laws at the parameter values `p`.
pub(crate) fn contact_rows(
    model: &Model,
    components: &[ComponentRow],
    p: &[f64],
) -> Result<Vec<ContactRow>, SimulationError> {
    law_rows(model, components, |law, element| {
        let Law::Contact(c) = law else {
            return None;
        };
        let law = ContactForce::new(c, p);
        // A power law below m = 1 has an unbounded slope at closing.
        Some(match law.exponent() {
            m if m >= 1.0 => Ok(law),
            m => Err(SimulationError::BadExponent {
                element: element.to_owned(),
                value: m,
            }),
        })
    })
}

/// Adds `f (−M⁻¹B_iᵀ)` of component `c` to the accelerations `acc`.
#[inline(always)]
fn add_force<M: Madd>(c: &SparseComp, f: f64, acc: &mut [f64]) {
    let [o0, o1] = c.off;
    // A ground element's second block has zero coefficients.
    for i in 0..6 {
        acc[o0 + i] = M::madd(f, c.g[i], acc[o0 + i]);
    }
    for i in 0..6 {
        acc[o1 + i] = M::madd(f, c.g[6 + i], acc[o1 + i]);
    }
}

/// Adds each friction component's `φ(v) (−M⁻¹B_iᵀ)` to the accelerations
/// `acc` for the velocities `v` (after either kernel, which carry the
/// components' springs and dampers).
#[inline(always)]
pub(crate) fn friction_accel<M: Madd>(
    comps: &[SparseComp],
    frictions: &[FrictionRow],
    v: &[f64],
    acc: &mut [f64],
) {
    for fr in frictions {
        let c = &comps[fr.comp];
        add_force::<M>(c, fr.law.force(c.rate::<M>(v)), acc);
    }
}

/// Adds each contact component's force (its change from the static one)
/// times `−M⁻¹B_iᵀ` to the accelerations `acc`, for the state `y = [q; q̇]`,
/// each on its side in `sides` (empty: every one on its own,
/// [`ContactForce::at_side`]). Out of line: the kernels that inline it
/// are compiled once per size and kernel, and most models have no contact.
#[inline(never)]
pub(crate) fn contact_accel<M: Madd>(
    comps: &[SparseComp],
    contacts: &[ContactRow],
    (q, v): (&[f64], &[f64]),
    sides: &[f64],
    acc: &mut [f64],
) {
    for (j, row) in contacts.iter().enumerate() {
        let c = &comps[row.comp];
        let side = sides.get(j).copied().unwrap_or(0.0);
        let f = row.law.force_change(c.rate::<M>(q), c.rate::<M>(v), side);
        add_force::<M>(c, f, acc);
    }
}

/// Adds `z_j (−M⁻¹B_jᵀ)` of each Bouc–Wen component j to the accelerations
/// `acc`, for the internal states `z` (empty: z = 0).
#[inline(always)]
pub(crate) fn hysteresis_accel<M: Madd>(
    comps: &[SparseComp],
    rows: &[HysteresisRow],
    z: &[f64],
    acc: &mut [f64],
) {
    for (row, &z) in rows.iter().zip(z) {
        add_force::<M>(&comps[row.comp], z, acc);
    }
}

/// ż of each Bouc–Wen component into `zdot`, for the velocities `v` and
/// the internal states `z`, on the branches `branch`
/// ([`BoucWenLaw::on_branch`]).
#[inline(always)]
pub(crate) fn hysteresis_rates<M: Madd>(
    comps: &[SparseComp],
    rows: &[HysteresisRow],
    (v, z, branch): (&[f64], &[f64], &[Branch]),
    zdot: &mut [f64],
) {
    for (((row, &z), zd), &b) in rows.iter().zip(z).zip(zdot).zip(branch) {
        let v = comps[row.comp].rate::<M>(v);
        *zd = row.law.on_branch(v, z, b).rate();
    }
}

/// The Bouc–Wen terms of the sensitivities' right-hand side, for rows
/// `width` long: `dacc += Σ_j (−M⁻¹B_jᵀ) Y_z[j]` (n rows), and
/// `dz[j] = ∂ż/∂v B_j Y_v + ∂ż/∂z Y_z[j] + ∂ż_j/∂x` (one row per
/// component); `usages[j]` lists (column, key) of the parameters acting on
/// component j's law, evaluated on `branch[j]`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn hysteresis_tangent<M: Madd>(
    comps: &[SparseComp],
    rows: &[HysteresisRow],
    usages: &[Vec<(usize, HysteresisKey)>],
    (v, z, branch): (&[f64], &[f64], &[Branch]),
    (yv, yz): (&[f64], &[f64]),
    width: usize,
    dacc: &mut [f64],
    dz: &mut [f64],
) {
    for (j, row) in rows.iter().enumerate() {
        let c = &comps[row.comp];
        let yzj = &yz[j * width..(j + 1) * width];
        let out = &mut dz[j * width..(j + 1) * width];
        let at = row.law.on_branch(c.rate::<M>(v), z[j], branch[j]);
        let (sv, sz) = at.slopes();
        for (o, y) in out.iter_mut().zip(yzj) {
            *o = sz * y;
        }
        for (i, (&b, &g)) in c.b.iter().zip(&c.g).enumerate() {
            if b == 0.0 && g == 0.0 {
                continue;
            }
            let at = (c.off[i / 6] + i % 6) * width;
            let (yvi, acc) = (&yv[at..at + width], &mut dacc[at..at + width]);
            for l in 0..width {
                out[l] = M::madd(sv * b, yvi[l], out[l]);
                acc[l] = M::madd(g, yzj[l], acc[l]);
            }
        }
        for &(col, key) in &usages[j] {
            out[col] += at.derivative(key);
        }
    }
}
