//! One explicit Runge–Kutta step of the state and, optionally, of its
//! sensitivities, with steps split at the zero crossings of power-law
//! deformations and at the kinks of the Bouc–Wen law (its component's
//! velocity or its state z changing sign).
//!
//! The force `a·sign(δ)|δ|^m` (m > 1) has a second derivative that jumps at
//! δ = 0. A step across such a point loses the method's order (local error
//! O(h⁴) whatever the order). So each step is first taken for the state
//! alone; if a power-law δ changes sign, the crossing instant is located on
//! the cubic Hermite interpolant of δ (from δ and δ̇ at both ends, error
//! O(h⁴) in δ) and the step is redone in pieces that end there. The
//! Bouc–Wen rate `ż = α v − β (γ |v| |z|^(n−1) z + d v |z|^n)` is continuous
//! but its slope jumps where v or z (n = 1) changes sign: the same split,
//! located on a quadratic ([`Stepper::find_hysteresis_crossings`]).
//!
//! The sensitivities go through the same stages: for a fixed split they are
//! the exact derivative of the discrete solution. A power law's δ = 0 is
//! taken as fixed, which changes them by the order of the local error only
//! (the exact flow does not depend on where a step is split); a Bouc–Wen
//! kink's and a contact switch's instants move with the parameters by
//! their own derivatives, and the sensitivities add the split step's
//! derivative in them ([`Stepper::event_jumps`], `contact_events`,
//! `split_shifts`).
use super::contact_events::{contact_instant_rates, contact_jumps, find_contact_crossings};
use super::contact_events::{moving_instant, set_contact_sides, start_contact_sides};
use super::contact_events::{TrialSens, TrialStep};
use super::crossings::{cubic_roots, hermite, hermite_root, hermite_slope, push_inside, MERGE};
use super::dim::Dim;
use super::law_rows::{hysteresis_accel, hysteresis_rates, hysteresis_tangent};
use super::laws::bouc_wen::Branch;
use super::madd::Madd;
use super::sines::StageSines;
use super::stage_sums::{accumulate, accumulate_halves, combine, combine_halves};
use super::stage_sums::{nonzero, Coefs};
use super::system::System;
use super::tableau::Tableau;
use super::tangent::Tangent;
use super::workspace::{InternalStates, Workspace};
use std::marker::PhantomData;

/// What a step needs: the equations, the method, the sensitivity columns.
pub(crate) struct Stepper<'a, M: Madd, D: Dim> {
    pub(super) sys: &'a System<'a>,
    pub(super) tab: &'a Tableau,
    pub(super) tangent: Tangent,
    /// The excitation at the stages by angle addition, when it is all sines.
    sines: Option<StageSines>,
    locate: bool,
    /// The last stage evaluated at the step's end (c = 1), if any: its
    /// accelerations estimate q̈ there for [`Stepper::find_hysteresis_crossings`].
    end_stage: Option<usize>,
    /// The nonzero `a_ij` of each stage, as (j, a_ij).
    a_nz: Vec<Coefs>,
    /// The nonzero `b_i`, as (i, b_i).
    b_nz: Coefs,
    kernel: PhantomData<(M, D)>,
}

impl<'a, M: Madd, D: Dim> Stepper<'a, M, D> {
    /// A stepper for one run with steps h, with the sensitivities to `wrt`
    /// (none if empty): allocates its coefficient lists, the sine rotations
    /// and the sensitivities' component data once.
    pub fn new(sys: &'a System<'a>, tab: &'a Tableau, h: f64, wrt: &[usize], locate: bool) -> Self {
        Stepper {
            sys,
            tab,
            tangent: Tangent::new(sys, wrt),
            sines: StageSines::new(sys.model, &sys.params, tab.c, h),
            locate,
            end_stage: (0..tab.stages()).rev().find(|&i| tab.c[i] == 1.0),
            a_nz: tab.a.iter().map(|r| nonzero(r)).collect(),
            b_nz: nonzero(tab.b),
            kernel: PhantomData,
        }
    }

    /// The length of a sensitivity row (see [`Tangent::width`]).
    pub fn width(&self) -> usize {
        self.tangent.width
    }

    /// The number of sine terms whose phases a step keeps (see [`StageSines`]).
    pub fn sine_terms(&self) -> usize {
        self.sines.as_ref().map_or(0, StageSines::len)
    }

    /// The scratch the sensitivities need (see [`Tangent::scratch_len`]).
    pub fn scratch_len(&self) -> usize {
        self.tangent.scratch_len(self.sys.n)
    }

    /// `F(t, y)` into stage 0, and its sensitivity if wanted.
    #[inline(always)]
    pub fn first_stage(&self, ws: &mut Workspace, t: f64, with_sens: bool) {
        let n = D::n(self.sys.n);
        let n2 = 2 * n;
        ws.y_stage[..n2].copy_from_slice(&ws.y);
        let nz = ws.z.y.len();
        ws.z.y_stage[..nz].copy_from_slice(&ws.z.y);
        if let Some(sines) = &self.sines {
            sines.start(t, &mut ws.phases, &mut ws.forces);
            (ws.forces_time, ws.phases_time, ws.forces_before) = (t, t, false);
        }
        self.derivative(ws, 0, t);
        if with_sens {
            self.first_sens_stage(ws, t);
        }
    }

    /// The sensitivities' stage 0 at t, from `sy`.
    #[inline(always)]
    fn first_sens_stage(&self, ws: &mut Workspace, t: f64) {
        ws.sy_stage.copy_from_slice(&ws.sy);
        ws.z.sy_stage.copy_from_slice(&ws.z.sy);
        self.sens_derivative(ws, 0, t);
    }

    /// Advances `y` (and `sy`) from t by h; stage 0 must hold `F(t, y)`.
    ///
    /// One loop over the step's pieces, so that the stages are compiled
    /// once per kernel (each call site of an inlined stage is a copy of the
    /// whole force and tangent code): the first pass is the trial step of
    /// the state alone; if a power-law deformation, or a Bouc–Wen
    /// velocity or state, changes sign in it, the step is redone in pieces
    /// ending at the crossings.
    #[inline(always)]
    pub fn step(&self, ws: &mut Workspace, t: f64, h: f64, with_sens: bool) {
        let mut split = false;
        let (mut from, mut piece) = (0.0, 0);
        // Stage 0 again where a contact's side differs from the one it was
        // evaluated on (one call site for the stages, see above).
        let mut refresh = !self.sys.contacts.is_empty() && start_contact_sides::<M>(self.sys, ws);
        let mut trial = false;
        loop {
            let last = !split || piece == ws.crossings.len();
            let to = if last { 1.0 } else { ws.crossings[piece] };
            let (ti, hi) = match split {
                true => (t + from * h, (to - from) * h),
                false => (t, h),
            };
            if split {
                // Each piece on its side of the kinks (Bouc–Wen).
                let z = &mut ws.z;
                z.branch_before.copy_from_slice(&z.branch);
                set_branches(z, (from, to));
                set_contact_sides(ws, (from, to));
                refresh |= piece == 0 && ws.contact_sides != ws.contact_start_sides;
                if ws.shift.instant.is_some() {
                    ws.shift.set_piece(piece, (from, to), h);
                }
            }
            if (split && piece > 0) || refresh {
                self.first_stage(ws, ti, false);
                if with_sens {
                    if split && piece > 0 {
                        self.event_jumps(ws, from);
                        contact_jumps::<M>(self.sys, &self.tangent, ws, (from, piece - 1));
                    }
                    self.first_sens_stage(ws, ti);
                }
                refresh = false;
            } else if split && ws.shift.on {
                // Stage 0 of the step's first piece, taken before the split.
                self.add_shift_terms(ws, 0, ti);
            }
            self.state_stages(ws, ti, hi);
            if !split && self.locate && self.find_crossings(ws, h) {
                // Redo the step in pieces ending at the crossings; with
                // sensitivities and a Bouc–Wen kink or a contact's switch
                // among them, after the trial step's sensitivities, from
                // which the located instants move (`kink_instant_rates`,
                // `contact_instant_rates`).
                split = true;
                trial = with_sens && ws.located_marks();
                if !trial {
                    continue;
                }
                ws.sy_start.copy_from_slice(&ws.sy);
                ws.z.sy_start.copy_from_slice(&ws.z.sy);
            }
            if with_sens {
                self.sens_stages(ws, ti, hi);
            }
            if trial {
                // The trial step's sensitivities give the kinks' and the
                // contacts' instants'.
                self.instant_rates(ws, h);
                std::mem::swap(&mut ws.sy, &mut ws.sy_start);
                std::mem::swap(&mut ws.z.sy, &mut ws.z.sy_start);
                trial = false;
                continue;
            }
            std::mem::swap(&mut ws.y, &mut ws.y_new);
            std::mem::swap(&mut ws.z.y, &mut ws.z.y_new);
            if last {
                if ws.shift.instant.is_some() {
                    self.apply_shift(ws, h);
                }
                ws.z.branch.fill(Branch::NATURAL);
                return;
            }
            from = to;
            piece += 1;
        }
    }

    /// Stage i's derivative from stage state i.
    #[inline(always)]
    fn derivative(&self, ws: &mut Workspace, i: usize, t: f64) {
        let n = D::n(self.sys.n);
        let n2 = 2 * n;
        let before = self.before(i);
        if t != ws.forces_time || before != ws.forces_before {
            self.sys
                .forces_kept(t, before, &mut ws.forces, &mut ws.segments);
            (ws.forces_time, ws.forces_before) = (t, before);
        }
        let ys = &ws.y_stage[i * n2..(i + 1) * n2];
        let ki = &mut ws.k[i * n2..(i + 1) * n2];
        ki[..n].copy_from_slice(&ys[n..]);
        let sides = &ws.contact_sides;
        (self.sys).accel_with::<M, D>(&ws.forces, ys, &mut ws.power_forces, sides, &mut ki[n..]);
        let nz = ws.z.y.len();
        if nz > 0 {
            // The Bouc–Wen forces z and the rates ż (`hysteresis`).
            let (comps, rows) = (&self.sys.comps[..], &self.sys.hysteresis[..]);
            let zs = &ws.z.y_stage[i * nz..(i + 1) * nz];
            hysteresis_accel::<M>(comps, rows, zs, &mut ki[n..]);
            let kz = &mut ws.z.k[i * nz..(i + 1) * nz];
            hysteresis_rates::<M>(comps, rows, (&ys[n..], zs, &ws.z.branch), kz);
        }
    }

    /// Whether stage i evaluates the excitation as the limit from before its
    /// instant: the stage at the step's end (c = 1) does, so that a step
    /// ending at a jump of the excitation sees the value before it.
    #[inline(always)]
    fn before(&self, i: usize) -> bool {
        i > 0 && self.tab.c[i] == 1.0
    }

    /// Stage i's sensitivity derivative from `sy_stage` and stage state i.
    #[inline(always)]
    fn sens_derivative(&self, ws: &mut Workspace, i: usize, t: f64) {
        let n = D::n(self.sys.n);
        let n2 = 2 * n;
        let w = self.tangent.width;
        let ys = &ws.y_stage[i * n2..(i + 1) * n2];
        let acc = &ws.k[i * n2 + n..(i + 1) * n2];
        let ksi = &mut ws.ks[i * n2 * w..(i + 1) * n2 * w];
        let (dq, dv) = ksi.split_at_mut(n * w);
        // Rows past the tangent's reach stay at the zeros `prepare` wrote:
        // they are neither written nor read, but for the sensors' readings,
        // which take them as the zeros they are.
        let r = D::reach(self.tangent.reach(self.sys), n);
        dq[..r * w].copy_from_slice(&ws.sy_stage[n * w..(n + r) * w]);
        self.tangent.apply::<M, D>(
            self.sys,
            (t, self.before(i)),
            (ys, &ws.contact_sides),
            acc,
            &ws.sy_stage,
            dv,
            (&mut ws.scratch, &mut ws.segments),
        );
        let nz = ws.z.y.len();
        if nz > 0 {
            let (comps, rows) = (&self.sys.comps[..], &self.sys.hysteresis[..]);
            let zs = &ws.z.y_stage[i * nz..(i + 1) * nz];
            let dz = &mut ws.z.ks[i * nz * w..(i + 1) * nz * w];
            let yv = &ws.sy_stage[n * w..2 * n * w];
            let usages = self.tangent.hysteresis_usages();
            let states = (&ys[n..], zs, &ws.z.branch[..]);
            hysteresis_tangent::<M>(comps, rows, usages, states, (yv, &ws.z.sy_stage), w, dv, dz);
        }
        if ws.shift.on {
            self.add_shift_terms(ws, i, t);
        }
    }

    /// Stages 1.. of the state and `y_new = y + h Σ b_i k_i`.
    #[inline(always)]
    fn state_stages(&self, ws: &mut Workspace, t: f64, h: f64) {
        let n = D::n(self.sys.n);
        let (n2, sizes) = (2 * n, (n, D::reach(self.sys.active, n)));
        for i in 1..self.tab.stages() {
            {
                let (done, rest) = ws.y_stage.split_at_mut(i * n2);
                combine_halves::<M>(&ws.y, &ws.k, &self.a_nz[i], h, sizes, &mut rest[..n2]);
                let _ = done;
            }
            let nz = ws.z.y.len();
            if nz > 0 {
                let z = &mut ws.z;
                let stage = &mut z.y_stage[i * nz..(i + 1) * nz];
                combine::<M>(&z.y, &z.k, &self.a_nz[i], h, nz, stage);
            }
            let ti = t + self.tab.c[i] * h;
            match &self.sines {
                Some(sines) if h == sines.h && ws.phases_time == t => {
                    sines.stage(i, &ws.phases, &mut ws.forces);
                    (ws.forces_time, ws.forces_before) = (ti, self.before(i));
                }
                _ => {}
            }
            self.derivative(ws, i, ti);
        }
        combine_halves::<M>(&ws.y, &ws.k, &self.b_nz, h, sizes, &mut ws.y_new);
        let nz = ws.z.y.len();
        if nz > 0 {
            combine::<M>(&ws.z.y, &ws.z.k, &self.b_nz, h, nz, &mut ws.z.y_new);
        }
    }

    /// Stages 1.. of the sensitivities (reusing the state's stage states)
    /// and `sy += h Σ b_i ks_i`.
    #[inline(always)]
    fn sens_stages(&self, ws: &mut Workspace, t: f64, h: f64) {
        let (n, w) = (D::n(self.sys.n), self.tangent.width);
        let len_z = ws.z.y.len() * self.tangent.width;
        // The rows the sensitivities reach, in each half ([`Tangent::reach`]).
        let r = D::reach(self.tangent.reach(self.sys), n);
        let halves = (n * w, r * w);
        for i in 1..self.tab.stages() {
            combine_halves::<M>(&ws.sy, &ws.ks, &self.a_nz[i], h, halves, &mut ws.sy_stage);
            if len_z > 0 {
                let z = &mut ws.z;
                combine::<M>(&z.sy, &z.ks, &self.a_nz[i], h, len_z, &mut z.sy_stage);
            }
            self.sens_derivative(ws, i, t + self.tab.c[i] * h);
        }
        accumulate_halves::<M>(&mut ws.sy, &ws.ks, &self.b_nz, h, halves);
        if len_z > 0 {
            accumulate::<M>(&mut ws.z.sy, &ws.z.ks, &self.b_nz, h, len_z);
        }
    }

    /// Fractions θ ∈ (0, 1) of the step at which a power-law
    /// deformation, or a contact's closure, changes sign, sorted, into
    /// `ws.crossings`.
    fn find_crossings(&self, ws: &mut Workspace, h: f64) -> bool {
        let n = D::n(self.sys.n);
        ws.crossings.clear();
        for pr in self.sys.power.iter().filter(|p| p.kinked) {
            // The state is the deviation from the static deformation.
            let d0 = pr.pre.d0 + pr.row.dot(&ws.y[..n]);
            let d1 = pr.pre.d0 + pr.row.dot(&ws.y_new[..n]);
            if !(d0 * d1 < 0.0) {
                continue;
            }
            let v0 = h * pr.row.dot(&ws.y[n..]);
            let v1 = h * pr.row.dot(&ws.y_new[n..]);
            push_inside(&mut ws.crossings, hermite_root(d0, v0, d1, v1));
        }
        if !self.sys.contacts.is_empty() {
            let n2 = 2 * n;
            let end = self.end_stage.unwrap_or(0);
            let mut crossings = std::mem::take(&mut ws.crossings);
            let k = std::mem::take(&mut ws.k);
            let step = TrialStep {
                h,
                acc0: &k[n..n2],
                acc1: &k[end * n2 + n..(end + 1) * n2],
            };
            find_contact_crossings::<M>(self.sys, ws, &step, &mut crossings);
            (ws.crossings, ws.k) = (crossings, k);
        }
        self.find_hysteresis_crossings(ws, h);
        ws.crossings.sort_by(f64::total_cmp);
        ws.crossings.dedup_by(|a, b| (*a - *b).abs() < MERGE);
        !ws.crossings.is_empty()
    }

    /// Adds to `ws.crossings` the fractions of the step at which a
    /// Bouc–Wen component's velocity v or state z changes sign: its rate
    /// has a kink in v (the term in |v|) and one in z (the term in |z|^n,
    /// whose slope jumps at z = 0 for n = 1). Each is located on the cubic
    /// Hermite interpolant of its values and rates at both ends: ż from the
    /// law, v̇ = B q̈ from stage 0 and from the last stage at the step's end
    /// (`end_stage`, an estimate good to O(h³)). Every sign change of the
    /// cubic counts, two or three in one step too: a reversal and its
    /// return within one step, missed, would cost O(h²) in the step.
    fn find_hysteresis_crossings(&self, ws: &mut Workspace, h: f64) {
        let n = D::n(self.sys.n);
        let (comps, rows) = (&self.sys.comps, &self.sys.hysteresis);
        let n2 = 2 * n;
        ws.z.marks.clear();
        ws.z.mark_rates.clear();
        let end_acc = match self.end_stage {
            Some(i) => &ws.k[i * n2 + n..(i + 1) * n2],
            None => &ws.k[n..n2],
        };
        for (j, row) in rows.iter().enumerate() {
            let c = &comps[row.comp];
            let v0 = c.rate::<M>(&ws.y[n..]);
            let v1 = c.rate::<M>(&ws.y_new[n..]);
            let a0 = h * c.rate::<M>(&ws.k[n..n2]);
            let a1 = h * c.rate::<M>(end_acc);
            let found = ws.crossings.len();
            cubic_roots(v0, a0, v1, a1, &mut ws.crossings);
            let z = &mut ws.z;
            z.marks
                .extend(ws.crossings[found..].iter().map(|&t| (t, j, false)));
            let (z0, z1) = (ws.z.y[j], ws.z.y_new[j]);
            let r0 = h * ws.z.k[j];
            let r1 = h * row.law.rate(v1, z1);
            let found = ws.crossings.len();
            cubic_roots(z0, r0, z1, r1, &mut ws.crossings);
            let z = &mut ws.z;
            z.marks
                .extend(ws.crossings[found..].iter().map(|&t| (t, j, true)));
            ws.z.ends[j] = [v0, a0, v1, a1, z0, r0, z1, r1];
        }
    }
}

impl<M: Madd, D: Dim> Stepper<'_, M, D> {
    /// The derivatives in the parameters of the instants located in a
    /// trial step whose sensitivities were just integrated: Bouc–Wen's
    /// kinks' ([`Self::kink_instant_rates`]) and the contacts' openings and
    /// closings' ([`contact_instant_rates`]), and the contact switch the
    /// split column follows. Out of line and cold, as they.
    #[cold]
    #[inline(never)]
    fn instant_rates(&self, ws: &mut Workspace, h: f64) {
        if !ws.z.marks.is_empty() {
            self.kink_instant_rates(ws, h);
        }
        if !ws.contact_marks.is_empty() {
            let end = self.end_stage.unwrap_or(0);
            let step = TrialSens { h, end };
            contact_instant_rates::<M>(self.sys, &self.tangent, ws, &step);
            if self.tangent.shift.is_some() {
                // The switch the split column follows (`split_shifts`).
                ws.shift.instant = moving_instant(self.sys, ws);
            }
        }
    }

    /// The derivatives in the parameters of each located Bouc–Wen kink's
    /// instant t* = t + θ h (`ws.z.marks`), into `ws.z.mark_rates`: θ is the
    /// root of the trial step's cubic p through the kink's value g (v or z)
    /// and rate at the step's ends (`find_hysteresis_crossings`), so
    /// `dt*/dx = −h (∂p/∂x)(θ) / p'(θ)`, where ∂p/∂x is the cubic through
    /// the derivatives of those four values: from the sensitivities at the
    /// step's start (`sy_start`), of its stage 0, of the trial step's end
    /// (`sy`, just integrated) and of its last stage (v̇) or of ż there.
    /// These are the derivatives of the located instants themselves, so the
    /// jumps ([`Self::event_jumps`]) make the sensitivities the derivative of
    /// the computed response, not only of the motion's (a first-order
    /// approximation, off by 2e-5 to 9e-5 of a column's RMS on the
    /// benchmark's law at its own steps). Out of line and cold: it runs at
    /// few steps, and kept out of the kernels it leaves their loops to
    /// the compiler as before.
    #[cold]
    #[inline(never)]
    fn kink_instant_rates(&self, ws: &mut Workspace, h: f64) {
        let n = D::n(self.sys.n);
        let (n2, w) = (2 * n, self.tangent.width);
        let (comps, rows) = (&self.sys.comps, &self.sys.hysteresis);
        let usages = self.tangent.hysteresis_usages();
        let end = self.end_stage.unwrap_or(0);
        let (sy, sy_start) = (&ws.sy[..], &ws.sy_start[..]);
        let (ks0, ks_end) = (&ws.ks[..n2 * w], &ws.ks[end * n2 * w..(end + 1) * n2 * w]);
        let z = &mut ws.z;
        z.mark_rates.clear();
        z.mark_rates.resize(z.marks.len() * w, 0.0);
        for (m, &(theta, j, is_z)) in z.marks.iter().enumerate() {
            let c = &comps[rows[j].comp];
            // The component's velocity row of sensitivities `s`, column col.
            let rate = |s: &[f64], col: usize| c.column_rate(s, n, w, col);
            let e = &z.ends[j];
            let e = if is_z { &e[4..] } else { &e[..4] };
            let slope = hermite_slope(e[0], e[1], e[2], e[3], theta);
            // ż at the trial step's end, as `find_hysteresis_crossings` took it.
            let v1 = c.rate::<M>(&ws.y_new[n..]);
            let at = rows[j].law.on_branch(v1, z.y_new[j], Branch::NATURAL);
            let (sv, sz) = at.slopes();
            let out = &mut z.mark_rates[m * w..(m + 1) * w];
            if slope == 0.0 || !slope.is_finite() {
                // A tangent root: the jump takes the motion's derivative.
                out.fill(f64::NAN);
                continue;
            }
            for (col, o) in out.iter_mut().enumerate() {
                let d = match is_z {
                    false => [
                        rate(sy_start, col),
                        h * rate(ks0, col),
                        rate(sy, col),
                        h * rate(ks_end, col),
                    ],
                    true => {
                        let s1 = z.sy[j * w + col];
                        let mut r1 = sv * rate(sy, col) + sz * s1;
                        for &(_, key) in usages[j].iter().filter(|u| u.0 == col) {
                            r1 += at.derivative(key);
                        }
                        [z.sy_start[j * w + col], h * z.ks[j * w + col], s1, h * r1]
                    }
                };
                *o = -h * hermite(d[0], d[1], d[2], d[3], theta) / slope;
            }
        }
    }

    /// The jumps of the Bouc–Wen states' sensitivities at a located kink at
    /// θ = `from`, between a piece and the next (stage 0 of the next in
    /// `ws.k`): the instant t* of the kink g = 0 (g the component's velocity
    /// v, or its state z) moves with the parameters, and the rate ż changes
    /// branch there: `Δs_z = (ż⁻ − ż⁺) dt*/dx`, with dt*/dx that of the
    /// located instant ([`Self::kink_instant_rates`]), or the motion's
    /// `−(∂g/∂y s)/ġ` for a branch changed where no kink of its value was
    /// located. ż is continuous across the kink, so the jump is of the order
    /// of the located instant's error; it is what makes the sensitivities the
    /// derivative of the computed response, whose split instants move with
    /// the parameters. Out of line and cold, as [`Self::kink_instant_rates`].
    #[cold]
    #[inline(never)]
    fn event_jumps(&self, ws: &mut Workspace, from: f64) {
        let n = D::n(self.sys.n);
        let w = self.tangent.width;
        let (comps, rows) = (&self.sys.comps, &self.sys.hysteresis);
        for (j, row) in rows.iter().enumerate() {
            let (before, after) = (ws.z.branch_before[j], ws.z.branch[j]);
            if (before.v, before.z) == (after.v, after.z) {
                continue;
            }
            let c = &comps[row.comp];
            let (v, z) = (c.rate::<M>(&ws.y[n..]), ws.z.y[j]);
            let rate = |b| row.law.on_branch(v, z, b).rate();
            let between = Branch {
                v: after.v,
                v_reach: after.v_reach,
                ..before
            };
            // The located instant's derivatives, if its kink is at `from`.
            let located = |is_z: bool| {
                let m = (ws.z.marks.iter())
                    .position(|&(t, k, of_z)| k == j && of_z == is_z && (t - from).abs() < MERGE)?;
                let rates = ws.z.mark_rates.get(m * w..(m + 1) * w)?;
                rates.iter().all(|r| r.is_finite()).then_some(rates)
            };
            let (rates_v, rates_z) = (located(false), located(true));
            let s_z = &mut ws.z.sy[j * w..(j + 1) * w];
            let v_dot = c.rate::<M>(&ws.k[n..2 * n]);
            let (at_before, at_between, at_after) = (rate(before), rate(between), rate(after));
            let jump = at_before - at_between;
            if before.v != after.v && jump != 0.0 {
                match rates_v {
                    Some(r) => (s_z.iter_mut().zip(r)).for_each(|(s, r)| *s += jump * r),
                    None if v_dot != 0.0 => {
                        for (col, s) in s_z.iter_mut().enumerate() {
                            *s -= jump * c.column_rate(&ws.sy, n, w, col) / v_dot;
                        }
                    }
                    None => {}
                }
            }
            let (jump, z_dot) = (at_between - at_after, ws.z.k[j]);
            if before.z != after.z && jump != 0.0 {
                match rates_z {
                    Some(r) => (s_z.iter_mut().zip(r)).for_each(|(s, r)| *s += jump * r),
                    None if z_dot != 0.0 => s_z.iter_mut().for_each(|s| *s -= jump * *s / z_dot),
                    None => {}
                }
            }
        }
    }
}

/// The branches of each Bouc–Wen component for the piece `(from, to)` of a
/// split step: a value whose kink was located at either end of the piece
/// is held on the piece's side, the sign there of its interpolant from the
/// trial step; every other value takes its own sign (a forced side where no
/// kink was located would misread a value that crosses unseen, as when a
/// trial step far off misses a crossing of a motion growing without bound).
fn set_branches(z: &mut InternalStates, (from, to): (f64, f64)) {
    let theta = 0.5 * (from + to);
    z.branch.fill(Branch::NATURAL);
    let at_end = |t: f64| (t - from).abs() < MERGE || (t - to).abs() < MERGE;
    for &(_, j, is_z) in z.marks.iter().filter(|m| at_end(m.0)) {
        let (e, b) = (&z.ends[j], &mut z.branch[j]);
        match is_z {
            false => {
                b.v = hermite(e[0], e[1], e[2], e[3], theta).signum();
                b.v_reach = f64::INFINITY;
            }
            true => {
                b.z = hermite(e[4], e[5], e[6], e[7], theta).signum();
                b.z_reach = f64::INFINITY;
            }
        }
    }
}
