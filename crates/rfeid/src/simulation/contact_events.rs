//! A contact's openings and closings located within a step (SPEC §1,
//! `law = "contact"`), as the power law's and Bouc–Wen's kinks are
//! (`stepper`): where its closure `s = δ − gap` changes sign, and where,
//! closed, its force `spring(s) + c ṡ` reaches zero (the damper's pull
//! meeting the spring's push). Each is located on the cubic Hermite
//! interpolant of the function's values and rates at the trial step's
//! ends (ṡ from the velocities, s̈ from the accelerations of the first and
//! the last stage); the pieces next to a located switch are evaluated on
//! their own side ([`set_contact_sides`]), and the sensitivities of the
//! velocities jump where the force does ([`contact_jumps`]).
use super::crossings::{cubic_roots, hermite, MERGE};
use super::madd::Madd;
use super::system::System;
use super::tangent::Tangent;
use super::workspace::Workspace;

/// What [`find_contact_crossings`] reads of a trial step: its length and
/// the accelerations at its two ends.
pub(super) struct TrialStep<'a> {
    /// The step h.
    pub h: f64,
    /// q̈ at the start (stage 0).
    pub acc0: &'a [f64],
    /// q̈ at the end (the last stage at c = 1, else stage 0's).
    pub acc1: &'a [f64],
}

/// Adds to `crossings` the fractions θ ∈ (0, 1) of the step at which a
/// contact opens or closes (its closure s changes sign, or closed, its
/// force reaches zero), and records them in `ws.contact_marks` (θ,
/// contact, whether of the force) with the interpolants' ends in
/// `ws.contact_ends`. The state at the step's ends is `ws.y`, `ws.y_new`.
pub(super) fn find_contact_crossings<M: Madd>(
    sys: &System<'_>,
    ws: &mut Workspace,
    step: &TrialStep<'_>,
    crossings: &mut Vec<f64>,
) {
    let n = sys.n;
    ws.contact_marks.clear();
    for (j, ct) in sys.contacts.iter().enumerate() {
        let c = &sys.comps[ct.comp];
        let s0 = ct.law.closure(c.rate::<M>(&ws.y[..n]));
        let s1 = ct.law.closure(c.rate::<M>(&ws.y_new[..n]));
        let (v0, v1) = (c.rate::<M>(&ws.y[n..]), c.rate::<M>(&ws.y_new[n..]));
        let (a0, a1) = (c.rate::<M>(step.acc0), c.rate::<M>(step.acc1));
        let h = step.h;
        let (f0, k0) = ct.law.raw(s0, v0);
        let (f1, k1) = ct.law.raw(s1, v1);
        let ends = [
            s0,
            h * v0,
            s1,
            h * v1,
            f0,
            h * (k0 * v0 + ct.law.damping() * a0),
            f1,
            h * (k1 * v1 + ct.law.damping() * a1),
        ];
        ws.contact_ends[j] = ends;
        let found = crossings.len();
        cubic_roots(ends[0], ends[1], ends[2], ends[3], crossings);
        ws.contact_marks
            .extend(crossings[found..].iter().map(|&t| (t, j, false)));
        if ct.law.damping() == 0.0 {
            // Without a damper the force is the spring's, zero with s.
            continue;
        }
        let found = crossings.len();
        cubic_roots(ends[4], ends[5], ends[6], ends[7], crossings);
        // Only where the contact is closed does its force switch.
        let closed = |t: &f64| hermite(ends[0], ends[1], ends[2], ends[3], *t) > 0.0;
        let mut k = found;
        while k < crossings.len() {
            match closed(&crossings[k]) {
                true => {
                    ws.contact_marks.push((crossings[k], j, true));
                    k += 1;
                }
                false => {
                    crossings.swap_remove(k);
                }
            }
        }
    }
}

/// Holds each contact for the whole of a step, as its trial, on the side
/// it is on at the step's start: acting (+1) if closed and pushing, else
/// not (−1). A step is evaluated on one side unless a switch is located in
/// it ([`set_contact_sides`]): a stage's state may stray across a switch
/// that the step's ends do not show, and a force switched at that stage
/// alone would make the response jump with the parameters.
///
/// Returns whether a side differs from the one stage 0 was evaluated on
/// (the last piece's of the step before), which must then be evaluated
/// again.
pub(super) fn start_contact_sides<M: Madd>(sys: &System<'_>, ws: &mut Workspace) -> bool {
    let n = sys.n;
    let mut changed = false;
    for (j, ct) in sys.contacts.iter().enumerate() {
        let c = &sys.comps[ct.comp];
        let s = ct.law.closure(c.rate::<M>(&ws.y[..n]));
        let (f, _) = ct.law.raw(s, c.rate::<M>(&ws.y[n..]));
        let side = if s > 0.0 && f > 0.0 { 1.0 } else { -1.0 };
        changed |= ws.contact_sides[j] != side;
        ws.contact_sides[j] = side;
        ws.contact_start_sides[j] = side;
    }
    changed
}

/// The side of each contact for the piece `(from, to)` of a split step: a
/// contact with an opening or closing located in the step is held acting
/// (+1) or not (−1) as its interpolants say at the piece's middle (closed,
/// and pushing); every other one stays on its side at the step's start
/// ([`start_contact_sides`]). The sides of the piece before are kept in
/// `ws.contact_sides_before`.
pub(super) fn set_contact_sides(ws: &mut Workspace, (from, to): (f64, f64)) {
    ws.contact_sides_before.copy_from_slice(&ws.contact_sides);
    ws.contact_sides.copy_from_slice(&ws.contact_start_sides);
    let theta = 0.5 * (from + to);
    for &(_, j, _) in &ws.contact_marks {
        let e = ws.contact_ends[j];
        let closed = hermite(e[0], e[1], e[2], e[3], theta) > 0.0;
        let pushing = hermite(e[4], e[5], e[6], e[7], theta) > 0.0;
        ws.contact_sides[j] = if closed && pushing { 1.0 } else { -1.0 };
    }
}

/// The jumps of the velocities' sensitivities where a piece of a split
/// step starts at a located closing at which the force jumps (the
/// damper's `c ṡ` on closing at a speed): the instant t* where the closure
/// g = s reaches zero moves with the parameters, `dt*/dx = −(∂g/∂x)/ṡ`
/// with `∂g/∂x = B Y_q + B ∂q₀/∂x − ∂gap/∂x`, and the accelerations jump
/// there by `−M⁻¹Bᵀ Δf`, so `ΔY_v = (q̈⁻ − q̈⁺) dt*/dx = −(−M⁻¹Bᵀ) Δf dt*/dx`.
/// Where the force is continuous (a located zero of the force) nothing
/// jumps.
pub(super) fn contact_jumps<M: Madd>(
    sys: &System<'_>,
    tangent: &Tangent,
    ws: &mut Workspace,
    from: f64,
) {
    let (n, w) = (sys.n, tangent.width);
    for (j, ct) in sys.contacts.iter().enumerate() {
        let (before, after) = (ws.contact_sides_before[j], ws.contact_sides[j]);
        let at_closure = (ws.contact_marks.iter())
            .any(|&(t, m, force)| m == j && !force && (t - from).abs() < MERGE);
        if before == after || !at_closure {
            continue;
        }
        let c = &sys.comps[ct.comp];
        let (d, v) = (c.rate::<M>(&ws.y[..n]), c.rate::<M>(&ws.y[n..]));
        let jump = ct.law.force_change(d, v, after) - ct.law.force_change(d, v, before);
        if jump == 0.0 || v == 0.0 {
            continue;
        }
        let (statics, gap) = tangent.contact_terms(j);
        for col in 0..w {
            let mut dg = statics.get(col).copied().unwrap_or(0.0);
            for (i, &b) in c.b.iter().enumerate() {
                dg += b * ws.sy[(c.off[i / 6] + i % 6) * w + col];
            }
            if gap.contains(&col) {
                dg -= 1.0;
            }
            let dt = -dg / v;
            for (i, &g) in c.g.iter().enumerate() {
                if g != 0.0 {
                    ws.sy[(n + c.off[i / 6] + i % 6) * w + col] -= g * jump * dt;
                }
            }
        }
    }
}
