//! A contact's openings and closings located within a step (SPEC §1,
//! `law = "contact"`), as the power law's and Bouc–Wen's kinks are
//! (`stepper`): where its closure `s = δ − gap` changes sign, and where,
//! closed, its force `spring(s) + c ṡ` reaches zero (the damper's pull
//! meeting the spring's push). Each is located on the cubic Hermite
//! interpolant of the function's values and rates at the trial step's
//! ends (ṡ from the velocities, s̈ from the accelerations of the first and
//! the last stage); the pieces next to a located switch are evaluated on
//! their own side ([`set_contact_sides`]), and the sensitivities take the
//! split step's derivative in each located instant ([`contact_jumps`],
//! `split_shifts`).
use super::crossings::{cubic_roots, hermite, hermite_slope, MERGE};
use super::laws::contact::{ContactAt, ContactForce};
use super::laws::ContactKey;
use super::madd::Madd;
use super::sparse::SparseComp;
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

/// The first of a split step's crossings (its index in `ws.crossings`) at
/// which a contact switches side, as [`set_contact_sides`] will hold it on
/// the pieces before and after: the instant the split column follows
/// (`split_shifts`). Out of line and cold: it runs at a located switch.
#[cold]
#[inline(never)]
pub(super) fn moving_instant(sys: &System<'_>, ws: &Workspace) -> Option<usize> {
    let side = |j: usize, theta: f64| {
        let e = ws.contact_ends[j];
        let closed = hermite(e[0], e[1], e[2], e[3], theta) > 0.0;
        let pushing = hermite(e[4], e[5], e[6], e[7], theta) > 0.0;
        closed && pushing
    };
    let cr = &ws.crossings;
    (0..cr.len()).find(|&k| {
        let before = 0.5 * (if k == 0 { 0.0 } else { cr[k - 1] } + cr[k]);
        let after = 0.5 * (cr[k] + cr.get(k + 1).copied().unwrap_or(1.0));
        let at = |&&(t, _, _): &&(f64, usize, bool)| (t - cr[k]).abs() < MERGE;
        (ws.contact_marks.iter().filter(at))
            .any(|&(_, j, _)| j < sys.contacts.len() && side(j, before) != side(j, after))
    })
}

/// The derivative in one parameter column of a contact's switching
/// function at a state: its closure s (`of_force` false) or its force
/// `f(s) + c ṡ`, the law held acting there (`at`), from the column's
/// `s_q = B ∂q₀/∂x + B Y_q` and `s_v = B Y_v` and the law's keys in that
/// column (`keys`).
fn switch_derivative(
    law: &ContactForce,
    at: &ContactAt,
    of_force: bool,
    (s_q, s_v): (f64, f64),
    keys: impl Iterator<Item = ContactKey>,
) -> f64 {
    let mut dg = match of_force {
        false => s_q,
        true => at.slope * s_q + law.damping() * s_v,
    };
    for key in keys {
        dg += match (of_force, key) {
            (false, ContactKey::Gap) => -1.0,
            (false, _) => 0.0,
            (true, key) => law.derivative(at, key),
        };
    }
    dg
}

/// A located switch of a contact at the start of a piece
/// ([`contact_jumps`]): the law there, held acting, and how its instant
/// moves.
struct Switch<'a> {
    law: &'a ContactForce,
    comp: &'a SparseComp,
    /// `B ∂q₀/∂x` and the law's keys' columns ([`Tangent::contact_terms`]).
    terms: (&'a [f64], &'a [(usize, ContactKey)]),
    at: ContactAt,
    /// Whether the switch is the force's zero, not the closure's.
    of_force: bool,
    /// The switching function's rate ġ.
    g_dot: f64,
    /// Its index in `ws.contact_marks`.
    mark: usize,
}

impl Switch<'_> {
    /// dt*/dx in column `col` (rows of width `w`, n coordinates): the
    /// located instant's own (`contact_instant_rates`), else the motion's
    /// `−(∂g/∂x)/ġ` from the sensitivities at the piece's start, else NaN
    /// (ġ = 0: no derivative).
    fn rate(&self, ws: &Workspace, (n, w, col): (usize, usize, usize)) -> f64 {
        match ws.contact_mark_rates.get(self.mark * w + col) {
            Some(&rate) if rate.is_finite() => rate,
            _ if self.g_dot == 0.0 || !self.g_dot.is_finite() => f64::NAN,
            _ => {
                let (statics, keys) = self.terms;
                let stat = statics.get(col).copied().unwrap_or(0.0);
                let s = (
                    stat + self.comp.column_rate(&ws.sy, 0, w, col),
                    self.comp.column_rate(&ws.sy, n, w, col),
                );
                let in_col = keys.iter().filter(|u| u.0 == col).map(|u| u.1);
                -switch_derivative(self.law, &self.at, self.of_force, s, in_col) / self.g_dot
            }
        }
    }
}

/// What [`contact_instant_rates`] reads of a trial step whose
/// sensitivities were integrated: its length, and the stage indices of the
/// accelerations at its ends ([`TrialStep`]).
pub(super) struct TrialSens {
    /// The step h.
    pub h: f64,
    /// The stage whose rates are the step end's (the last stage at c = 1,
    /// else stage 0).
    pub end: usize,
}

/// The derivatives in the parameters of each located opening or closing's
/// instant t* = t + θ h (`ws.contact_marks`), into
/// `ws.contact_mark_rates`: θ is the root of the cubic p through the
/// switching function's values and rates at the trial step's ends
/// ([`find_contact_crossings`]), so `dt*/dx = −h (∂p/∂x)(θ) / p'(θ)`, where
/// ∂p/∂x is the cubic through the derivatives of those four values, from
/// the sensitivities at the step's start (`sy_start`), of its stage 0, at
/// the trial step's end (`sy`, just integrated) and of its last stage.
/// These are the derivatives of the located instants themselves, not only
/// of the motion's ([`contact_jumps`]). Out of line and cold, as Bouc–Wen's
/// (`Stepper::kink_instant_rates`).
#[cold]
#[inline(never)]
pub(super) fn contact_instant_rates<M: Madd>(
    sys: &System<'_>,
    tangent: &Tangent,
    ws: &mut Workspace,
    step: &TrialSens,
) {
    let (n, w, h) = (sys.n, tangent.width, step.h);
    let n2 = 2 * n;
    let (sy, sy_start) = (&ws.sy[..], &ws.sy_start[..]);
    let ks0 = &ws.ks[..n2 * w];
    let ks1 = &ws.ks[step.end * n2 * w..(step.end + 1) * n2 * w];
    let (acc0, acc1) = (&ws.k[n..n2], &ws.k[step.end * n2 + n..(step.end + 1) * n2]);
    ws.contact_mark_rates.clear();
    ws.contact_mark_rates
        .resize(ws.contact_marks.len() * w, 0.0);
    for (m, &(theta, j, of_force)) in ws.contact_marks.iter().enumerate() {
        let (ct, ends) = (&sys.contacts[j], &ws.contact_ends[j]);
        let c = &sys.comps[ct.comp];
        let e = if of_force { &ends[4..] } else { &ends[..4] };
        let slope = hermite_slope(e[0], e[1], e[2], e[3], theta);
        if slope == 0.0 || !slope.is_finite() {
            // A tangent root: no derivative of its own; the jump takes the
            // motion's (`contact_jumps`).
            ws.contact_mark_rates[m * w..(m + 1) * w].fill(f64::NAN);
            continue;
        }
        // The law at each end, acting, and the acceleration of its closure.
        let law = &ct.law;
        let end = |y: &[f64], acc: &[f64]| {
            let (d, v) = (c.rate::<M>(&y[..n]), c.rate::<M>(&y[n..]));
            (law.at_side(law.d0 + d, v, 1.0), v, c.rate::<M>(acc))
        };
        let ends = [end(&ws.y, acc0), end(&ws.y_new, acc1)];
        let (statics, keys) = tangent.contact_terms(j);
        let out = &mut ws.contact_mark_rates[m * w..(m + 1) * w];
        for (col, o) in out.iter_mut().enumerate() {
            let stat = statics.get(col).copied().unwrap_or(0.0);
            let mut d = [0.0; 4];
            for (i, (s, ks)) in [(sy_start, ks0), (sy, ks1)].into_iter().enumerate() {
                let (at, v, a) = ends[i];
                let s_q = stat + c.column_rate(s, 0, w, col);
                let (s_v, s_a) = (c.column_rate(s, n, w, col), c.column_rate(ks, n, w, col));
                let in_col = || keys.iter().filter(|u| u.0 == col).map(|u| u.1);
                let value = switch_derivative(law, &at, of_force, (s_q, s_v), in_col());
                let mut rate = match of_force {
                    false => s_v,
                    true => law.curvature(&at) * s_q * v + at.slope * s_v + law.damping() * s_a,
                };
                for key in in_col().filter(|_| of_force) {
                    let (d_slope, d_damping) = law.small_motion_derivative(&at, key);
                    rate += d_slope * v + d_damping * a;
                }
                d[2 * i] = value;
                d[2 * i + 1] = h * rate;
            }
            *o = -h * hermite(d[0], d[1], d[2], d[3], theta) / slope;
        }
    }
}

/// The jumps of the velocities' sensitivities where a piece of a split
/// step starts at a located opening or closing of a contact. The instant
/// t* where the switching function g reaches zero moves with the
/// parameters, `dt*/dx = −(∂g/∂x)/ġ`, and the accelerations jump there by
/// `−M⁻¹Bᵀ Δf`, so `ΔY_v = (q̈⁻ − q̈⁺) dt*/dx = −(−M⁻¹Bᵀ) Δf dt*/dx`.
/// - At a closing, g is the closure s = δ − gap: `∂g/∂x = B ∂q₀/∂x +
///   B Y_q − ∂gap/∂x`, ġ = ṡ, and the force jumps by the damper's `c ṡ`.
/// - At a zero of the force, g is the force `f(s) + c ṡ`: `∂g/∂x =
///   f'(s) (B ∂q₀/∂x + B Y_q) + c B Y_v + ∂f/∂key`, `ġ = f'(s) ṡ + c s̈`
///   (s̈ from stage 0 of the piece after). The force is continuous there,
///   so Δf is only the computed force at the piece's start, of the order of
///   the located instant's error; it is what makes the sensitivities the
///   derivative of the computed response, whose split instants move with
///   the parameters (as Bouc–Wen's kinks, `stepper`).
///
/// These are the jump conditions of the flow. The step's first switch that
/// moves ([`moving_instant`], the crossing `index`) takes instead the
/// pieces' own derivative in its instant, carried by the split column
/// (`split_shifts`): here only its dt*/dx is kept, into `ws.shift.rates`.
/// A further contact switching at that instant is moved by the split
/// column with that dt*/dx, and by its jump condition with the difference
/// from its own. Out of line: it runs at the pieces of split steps only.
#[inline(never)]
pub(super) fn contact_jumps<M: Madd>(
    sys: &System<'_>,
    tangent: &Tangent,
    ws: &mut Workspace,
    (from, index): (f64, usize),
) {
    let followed = ws.shift.instant == Some(index);
    let (n, w) = (sys.n, tangent.width);
    for (j, ct) in sys.contacts.iter().enumerate() {
        let (before, after) = (ws.contact_sides_before[j], ws.contact_sides[j]);
        let mark =
            (ws.contact_marks.iter()).position(|&(t, m, _)| m == j && (t - from).abs() < MERGE);
        let Some(mark) = mark.filter(|_| before != after) else {
            continue;
        };
        let of_force = ws.contact_marks[mark].2;
        let c = &sys.comps[ct.comp];
        let (d, v) = (c.rate::<M>(&ws.y[..n]), c.rate::<M>(&ws.y[n..]));
        let jump = ct.law.force_change(d, v, after) - ct.law.force_change(d, v, before);
        let at = ct.law.at_side(ct.law.d0 + d, v, 1.0);
        let g_dot = match of_force {
            false => v,
            true => at.slope * v + ct.law.damping() * c.rate::<M>(&ws.k[n..2 * n]),
        };
        let switch = Switch {
            law: &ct.law,
            comp: c,
            terms: tangent.contact_terms(j),
            at,
            of_force,
            g_dot,
            mark,
        };
        if followed && ws.shift.rates.is_empty() {
            // The split column carries the switches at this instant
            // (`split_shifts`), moving with this one's dt*/dx.
            let mut rates = std::mem::take(&mut ws.shift.rates);
            rates.extend((0..w).map(|col| switch.rate(ws, (n, w, col))));
            ws.shift.rates = rates;
            continue;
        }
        if jump == 0.0 || g_dot == 0.0 || !g_dot.is_finite() {
            continue;
        }
        for col in 0..w {
            let mut dt = switch.rate(ws, (n, w, col));
            if followed {
                // A further contact switching at the followed instant: the
                // split column moves it with the first one's dt*/dx, the
                // jump condition by the rest of its own.
                let first = ws.shift.rates[col];
                if first.is_finite() {
                    dt -= first;
                }
            }
            if !dt.is_finite() {
                continue;
            }
            for (i, &g) in c.g.iter().enumerate() {
                if g != 0.0 {
                    ws.sy[(n + c.off[i / 6] + i % 6) * w + col] -= g * jump * dt;
                }
            }
        }
    }
}
