//! The equations of motion at one parameter point (eq. 1):
//!
//! `M q̈ + Bᵀ f(B q, B q̇) = P(t)`,  `f_i = law_i(δ_i) + c_i δ̇_i`,
//!
//! written as `q̈ = a(t, q, q̇)`. Linear springs and all dampers are folded
//! into dense `−M⁻¹K` and `−M⁻¹C` (the paper's K and C, and F_d); the
//! power-law springs (F_e, eq. 2–6) stay as rows. [`System::accel`]
//! allocates nothing; the sensitivities' right-hand side is in `tangent`.
//! Runs under gravity move about the static equilibrium
//! (`System::set_reference`, `preload`).
use super::aligned::Aligned;
use super::dim::{Dim, Dynamic};
use super::law_rows::{contact_accel, contact_rows, ContactRow};
use super::law_rows::{friction_accel, friction_rows, hysteresis_rows, FrictionRow, HysteresisRow};
pub use super::laws::power_law;
use super::madd::{Madd, Separate};
use super::preload::{power_change, Preload};
use super::sparse::{prefer_sparse, sparse_accel, sparse_components, sparse_groups};
use super::sparse::{SparseComp, SparseGroup, SparsePower};
use super::structure::{Row, Structure};
use super::SimulationError;
use crate::model::{FixedSignal, Law, Model, Segment, Signal};

/// A power-law spring row: `f = a · sign(δ) · |δ|^m`, `δ = row · q`.
#[derive(Debug, Clone)]
pub struct PowerRow {
    /// δ = row · q.
    pub row: Row,
    /// Coefficient a of `sign(δ)|δ|^m`, δ in SI units (a · δ_ref^(−m) of
    /// the model's law).
    pub a: f64,
    /// Exponent m ≥ 1.
    pub m: f64,
    /// Whether the law is non-smooth at δ = 0: `sign(δ)|δ|^m` is the
    /// polynomial δ^m for odd whole m, and non-smooth otherwise.
    pub kinked: bool,
    /// The static deformation the run moves about (zero without one).
    pub(crate) pre: Preload,
}

/// The equations of motion with numbers in, ready to integrate.
#[derive(Debug, Clone)]
pub struct System<'a> {
    pub(crate) structure: &'a Structure,
    pub(crate) model: &'a Model,
    /// Parameter values (all parameters).
    pub(crate) params: Vec<f64>,
    /// n.
    pub n: usize,
    /// Diagonal of M⁻¹.
    pub minv: Vec<f64>,
    /// `[−M⁻¹K | −M⁻¹C]`, n × 2n, row-major; multiplies the state `[q; q̇]`.
    pub a_lin: Vec<f64>,
    /// `[−M⁻¹K | −M⁻¹C | −M⁻¹B_pᵀ | M⁻¹L]` in 4-row panels
    /// (`[panel][column][4]`, zero-padded): one product with
    /// `[q; q̇; f_p; P]`, started from the weight's `M⁻¹ × weight`
    /// ([`Self::gravity_panels`]), gives q̈ (eq. 1), accumulators in registers.
    a_ext: Aligned,
    /// Columns of `a_ext`: 2n, then one per power-law slot, then one per
    /// excitation.
    ext_cols: usize,
    /// `M⁻¹ × weight` in the same 4-row panels.
    gravity_panels: Vec<[f64; 4]>,
    /// When the motion reaches fewer than n coordinates ([`Self::active`]),
    /// the columns of `a_ext` it needs, in the same panels: q and q̇ of the
    /// reached coordinates (each padded to an even count, so that every
    /// column meets the accumulator it meets in `a_ext`), the power-law
    /// slots and the excitations; `reach_cols` of them, multiplying one
    /// vector `[q; q̇; f_p; P]` that short. Empty otherwise.
    a_reach: Aligned,
    /// Columns of `a_reach`.
    reach_cols: usize,
    /// Power-law rows.
    pub power: Vec<PowerRow>,
    /// `M⁻¹ L_e` per excitation.
    pub minv_loads: Vec<Vec<f64>>,
    /// `M⁻¹ × weight` (constant), n.
    pub minv_gravity: Vec<f64>,
    /// Power-law rows of B in 4-row panels, `[panel][coordinate][4]`, zero-padded.
    power_b: Aligned,
    /// `(a, m)` per power-law slot: the rows, padded to whole panels with `(0, 2)`.
    power_am: Vec<(f64, f64)>,
    /// The static deformation per power-law slot.
    power_pre: Vec<Preload>,
    /// Whether every power law is a square (m = 2), the slideways' usual
    /// law: the dense kernel's four lanes then run without branches.
    power_square: bool,
    /// Whether any power law has a static deformation to move about.
    power_preloaded: bool,
    /// The constant part of the acceleration: `M⁻¹ × weight`, or zero once
    /// the run moves about the static equilibrium, whose elastic forces
    /// balance the weights ([`Self::set_reference`]).
    pub(crate) base: Vec<f64>,
    /// The dense kernel's reach: 1 + the last coordinate whose acceleration
    /// can differ from zero (a term of K, C, the power laws, a load or the
    /// weight in its row); n with friction, hysteresis or contacts, or before the
    /// dense panels are built. A coordinate past it stays at rest from
    /// rest: its row of the accelerations is zero, and since M is diagonal
    /// and K, C and `B_pᵀ f(B_p q)` are symmetric in their coupling, so is
    /// its column in every other row. The kernels
    /// with [`super::dim::Reach`] or n at run time skip such coordinates.
    pub(crate) active: usize,
    /// Whether every coordinate is integrated whatever the rows say
    /// ([`Self::integrate_every_coordinate`]).
    every: bool,
    /// `∂q₀/∂x` of the static equilibrium moved about, n × r row-major
    /// (empty without one, or without sensitivities).
    pub(crate) static_dq: Vec<f64>,
    /// Whether [`Self::accel`] (and the sensitivities) run element by
    /// element (`sparse`) rather than on the dense panels above, which are
    /// then left empty.
    pub(crate) sparse: bool,
    /// Every component with its coefficients, for the sparse kernel.
    pub(crate) comps: Vec<SparseComp>,
    /// The power-law springs of `comps`, in component order (as `power`).
    pub(crate) powers: Vec<SparsePower>,
    /// `comps` in groups of four for the accelerations ([`sparse_groups`]).
    groups: Vec<SparseGroup>,
    /// `M⁻¹ L_e` per excitation by nonzero 6-blocks, for the sparse kernel.
    pub(crate) minv_load_blocks: Vec<Row>,
    /// The friction components, in component order: their forces are added
    /// after either kernel ([`friction_accel`]); their springs and dampers
    /// are in the kernels' linear parts.
    pub(crate) frictions: Vec<FrictionRow>,
    /// The excitation signals at the parameter values, one per excitation.
    pub(crate) signals: Vec<FixedSignal<'a>>,
    /// Whether every signal has one term (so one kept table segment each).
    one_term_each: bool,
    /// The Bouc–Wen components, in component order, each with an internal
    /// state z that the stepper integrates beside `[q; q̇]` (`hysteresis`).
    pub(crate) hysteresis: Vec<HysteresisRow>,
    /// The contact components, in component order: their forces are added
    /// after either kernel ([`contact_accel`]), as changes from the static
    /// ones about an equilibrium.
    pub(crate) contacts: Vec<ContactRow>,
}

impl<'a> System<'a> {
    /// Evaluates every coefficient at the parameter values `params`.
    pub fn new(
        model: &'a Model,
        structure: &'a Structure,
        params: &[f64],
    ) -> Result<Self, SimulationError> {
        check_finite(model, params)?;
        let n = structure.n;
        let (minv, minv_gravity) = inverse_masses(model, structure, params)?;
        let ComponentMatrices { k, c, power } = component_matrices(model, structure, params)?;
        let a_lin = linear_accel(n, &minv, &k, &c);
        let minv_loads: Vec<Vec<f64>> = structure
            .loads
            .iter()
            .map(|l| l.iter().zip(&minv).map(|(x, m)| x * m).collect())
            .collect();
        let (comps, powers) = sparse_components(structure, &minv, |i| {
            let comp = &structure.components[i];
            let k = comp.law.linear_stiffness(params).unwrap_or(0.0);
            (k, comp.damping.eval(params), comp.law.power_spring(params))
        });
        let minv_load_blocks = minv_loads.iter().map(|l| Row::from_dense(l)).collect();
        let frictions = friction_rows(model, &structure.components, params)?;
        let hysteresis = hysteresis_rows(model, &structure.components, params)?;
        let contacts = contact_rows(model, &structure.components, params)?;
        let mut comps = comps;
        for (j, fr) in frictions.iter().enumerate() {
            comps[fr.comp].friction = Some(j as u32);
        }
        for (j, row) in contacts.iter().enumerate() {
            comps[row.comp].contact = Some(j as u32);
        }
        let mut sys = System {
            power_b: Aligned::default(),
            power_am: Vec::new(),
            power_pre: Vec::new(),
            power_square: false,
            power_preloaded: false,
            base: minv_gravity.clone(),
            active: n,
            every: false,
            static_dq: Vec::new(),
            a_ext: Aligned::default(),
            ext_cols: 0,
            a_reach: Aligned::default(),
            reach_cols: 0,
            gravity_panels: Vec::new(),
            sparse: true,
            groups: sparse_groups(&comps),
            comps,
            powers,
            minv_load_blocks,
            frictions,
            hysteresis,
            contacts,
            one_term_each: model.excitations.iter().all(|e| e.signal.terms.len() == 1),
            signals: (model.excitations.iter())
                .map(|e| FixedSignal::new(&e.signal, params))
                .collect(),
            structure,
            model,
            params: params.to_vec(),
            n,
            minv,
            a_lin,
            power,
            minv_loads,
            minv_gravity,
        };
        sys.set_sparse(sys.prefers_sparse());
        Ok(sys)
    }

    /// Whether the element-by-element kernel is the faster one for this
    /// model ([`prefer_sparse`]).
    pub(crate) fn prefers_sparse(&self) -> bool {
        prefer_sparse(self.n, self.power.len(), self.groups.len())
    }

    /// Chooses the kernel: element by element (`sparse`) or dense panels,
    /// building the dense panels if they are wanted and not yet built.
    pub(crate) fn set_sparse(&mut self, sparse: bool) {
        self.sparse = sparse;
        if !sparse && self.ext_cols == 0 {
            self.build_dense();
        }
    }

    /// From now on, the state is the deviation `[q − q₀; q̇]` from the static
    /// equilibrium `q0` (whose sensitivities are `dq0`, n × r for the run's
    /// r parameters), and [`Self::accel`] computes the forces as changes
    /// from there (`preload`): the same accelerations, with rounding
    /// relative to the motion rather than to the weights.
    pub(crate) fn set_reference(&mut self, q0: &[f64], dq0: Vec<f64>) {
        // Both lists hold the power-law components in component order.
        for (row, p) in self.power.iter_mut().zip(&mut self.powers) {
            p.pre = Preload::new(p.spring.m, row.row.dot(q0));
            row.pre = p.pre;
        }
        for row in &mut self.contacts {
            row.law.d0 = self.structure.components[row.comp].row.dot(q0);
            row.law.about_rest = true;
        }
        self.base.fill(0.0);
        self.static_dq = dq0;
        if self.ext_cols != 0 {
            self.build_dense();
        }
    }

    /// The dense panels of the accelerations (see the fields).
    fn build_dense(&mut self) {
        let (n, minv, a_lin) = (self.n, &self.minv, &self.a_lin);
        let slots = 4 * self.power.len().div_ceil(4);
        let mut power_b = vec![0.0; slots * n];
        let mut power_am = vec![(0.0, 2.0); slots];
        let mut power_pre = vec![Preload::default(); slots];
        for (k, pr) in self.power.iter().enumerate() {
            power_pre[k] = pr.pre;
            let dense = pr.row.dense(n);
            for (j, v) in dense.iter().enumerate() {
                power_b[((k / 4) * n + j) * 4 + k % 4] = *v;
            }
            power_am[k] = (pr.a, pr.m);
        }
        // Column j of the extended matrix, row i.
        let ext_cols = 2 * n + slots + self.minv_loads.len();
        let column = |i: usize, j: usize| -> f64 {
            if j < 2 * n {
                a_lin[i * 2 * n + j]
            } else if j < 2 * n + slots {
                // −M⁻¹ B_kᵀ for power-law slot k (zero for the padding).
                let k = j - 2 * n;
                -power_b[((k / 4) * n + i) * 4 + k % 4] * minv[i]
            } else {
                self.minv_loads[j - 2 * n - slots][i]
            }
        };
        let panels = n.div_ceil(4);
        let mut a_ext = vec![0.0; panels * ext_cols * 4];
        let mut gravity_panels = vec![[0.0; 4]; panels];
        for i in 0..n {
            for j in 0..ext_cols {
                a_ext[((i / 4) * ext_cols + j) * 4 + i % 4] = column(i, j);
            }
            gravity_panels[i / 4][i % 4] = self.base[i];
        }
        self.active = self.reach(&a_ext, ext_cols);
        self.power_square = power_am.iter().all(|(_, m)| *m == 2.0);
        self.power_preloaded = power_pre.iter().any(|p| p.d0 != 0.0);
        (self.power_b, self.a_ext) = (Aligned::from_slice(&power_b), Aligned::from_slice(&a_ext));
        self.power_am = power_am;
        self.power_pre = power_pre;
        (self.ext_cols, self.gravity_panels) = (ext_cols, gravity_panels);
        self.build_reach();
    }

    /// `a_reach` from `a_ext` (see the field), when the reach is short.
    fn build_reach(&mut self) {
        let (n, na) = (self.n, self.active);
        let even = na + na % 2;
        if na == n {
            (self.a_reach, self.reach_cols) = (Aligned::default(), 0);
            return;
        }
        let cols = 2 * even + self.ext_cols - 2 * n;
        let ext_col = |c: usize| match c {
            c if c < even => c,
            c if c < 2 * even => n + c - even,
            c => 2 * n + c - 2 * even,
        };
        let (panels, width) = ((4 * na.div_ceil(4)).min(n).div_ceil(4), 4 * self.ext_cols);
        let mut a_reach = vec![0.0; panels * 4 * cols];
        for p in 0..panels {
            for c in 0..cols {
                let from = p * width + 4 * ext_col(c);
                a_reach[4 * (p * cols + c)..][..4].copy_from_slice(&self.a_ext[from..from + 4]);
            }
        }
        (self.a_reach, self.reach_cols) = (Aligned::from_slice(&a_reach), cols);
    }

    /// Integrates every coordinate from now on ([`Self::active`] n): for a
    /// run from a state that moves past the reach, which a run from rest
    /// never does (a caller's own [`super::SampleState`]).
    pub(crate) fn integrate_every_coordinate(&mut self) {
        self.every = true;
        self.active = self.n;
    }

    /// Whether the state `y = [q; q̇]` has a nonzero coordinate past
    /// [`Self::active`].
    pub(crate) fn moves_past_reach(&self, y: &[f64]) -> bool {
        let (n, a) = (self.n, self.active.min(self.n));
        y.get(a..n).is_some_and(|q| q.iter().any(|v| *v != 0.0))
            || y.get(n + a..2 * n)
                .is_some_and(|v| v.iter().any(|v| *v != 0.0))
    }

    /// [`Self::active`] from the dense panels `a_ext` (`ext_cols` columns)
    /// and the weight.
    fn reach(&self, a_ext: &[f64], ext_cols: usize) -> usize {
        let n = self.n;
        let laws =
            !self.frictions.is_empty() || !self.hysteresis.is_empty() || !self.contacts.is_empty();
        if self.every || laws {
            return n;
        }
        let moves = |i: usize| {
            self.base[i] != 0.0
                || (0..ext_cols).any(|j| a_ext[((i / 4) * ext_cols + j) * 4 + i % 4] != 0.0)
        };
        (0..n).rev().find(|&i| moves(i)).map_or(0, |i| i + 1)
    }

    /// The excitation signals.
    fn signals(&self) -> impl Iterator<Item = &Signal> {
        self.model.excitations.iter().map(|e| &e.signal)
    }

    /// The excitation forces P_e(t), one per excitation, into `forces`.
    #[inline(always)]
    pub fn forces(&self, t: f64, forces: &mut [f64]) {
        for (f, s) in forces.iter_mut().zip(self.signals()) {
            *f = s.at(t, &self.params);
        }
    }

    /// The excitation forces' rates dP_e/dt at t, as limits from before or
    /// after t ([`crate::model::Shape::rate_side`]), into `rates`.
    pub fn force_rates(&self, t: f64, before: bool, rates: &mut [f64]) {
        for (r, s) in rates.iter_mut().zip(self.signals()) {
            *r = s.rate_side(t, &self.params, before);
        }
    }

    /// The excitation forces as limits from before or after t
    /// ([`crate::model::Shape::at_side`]), into `forces`.
    #[inline(always)]
    pub fn forces_side(&self, t: f64, before: bool, forces: &mut [f64]) {
        for (f, s) in forces.iter_mut().zip(&self.signals) {
            *f = s.at_side(t, before);
        }
    }

    /// [`System::forces_side`] keeping each table's segment in `segments`
    /// ([`System::signal_terms`] long, see `FixedSignal::at_side_kept`):
    /// the same forces, found without a search at the stages of a step.
    #[inline(always)]
    pub(crate) fn forces_kept(
        &self,
        t: f64,
        before: bool,
        forces: &mut [f64],
        segments: &mut [Segment],
    ) {
        if self.one_term_each {
            // One term each (the usual case): signal e keeps segment e.
            for (e, s) in self.signals.iter().enumerate() {
                forces[e] = s.at_side_kept(t, before, &mut segments[e..e + 1]);
            }
            return;
        }
        let mut rest = segments;
        for (f, s) in forces.iter_mut().zip(&self.signals) {
            let (mine, others) = std::mem::take(&mut rest).split_at_mut(s.terms());
            *f = s.at_side_kept(t, before, mine);
            rest = others;
        }
    }

    /// The shape of term j of excitation e at t, from before or after t,
    /// with the segments [`System::forces_kept`] keeps: the same value as
    /// the shape's own ([`crate::model::Shape::at_side`]), found without a
    /// search where the forces' last lookup holds t.
    #[inline(always)]
    pub(crate) fn shape_kept(
        &self,
        (e, j): (usize, usize),
        (t, before): (f64, bool),
        segments: &mut [Segment],
    ) -> f64 {
        let first: usize = self.signals[..e].iter().map(FixedSignal::terms).sum();
        self.signals[e].shape_at_side_kept(j, t, before, &mut segments[first + j])
    }

    /// The number of terms of all the excitation signals.
    pub(crate) fn signal_terms(&self) -> usize {
        self.signals.iter().map(FixedSignal::terms).sum()
    }

    /// Scratch length that [`System::accel`] needs: the power-law slots,
    /// or the short vector of a short reach (see `a_reach`).
    pub fn scratch_len(&self) -> usize {
        self.power_am.len().max(self.reach_cols)
    }

    /// The number of internal states z: one per Bouc–Wen component.
    pub fn internal_states(&self) -> usize {
        self.hysteresis.len()
    }

    /// `q̈ = a(t, q, q̇)` for the state `y = [q; q̇]` (length 2n) with the
    /// Bouc–Wen states z = 0 (the stepper adds their forces), into `acc`
    /// (length n); `forces` are the excitation forces at t ([`System::forces`]),
    /// `scratch` is at least [`System::scratch_len`] long.
    #[inline(always)]
    pub fn accel(&self, forces: &[f64], y: &[f64], scratch: &mut [f64], acc: &mut [f64]) {
        self.accel_with::<Separate, Dynamic>(forces, y, scratch, &[], acc)
    }

    /// [`System::accel`] with a chosen multiply–add and size, and each
    /// contact on its side in `contact_sides` (empty: its own; `stepper`). The
    /// element-by-element kernel is compiled only with n at run time
    /// ([`Dim::SPARSE`]): a fixed size must not be given a system set to run
    /// element by element.
    #[inline(always)]
    pub(crate) fn accel_with<M: Madd, D: Dim>(
        &self,
        forces: &[f64],
        y: &[f64],
        scratch: &mut [f64],
        contact_sides: &[f64],
        acc: &mut [f64],
    ) {
        let n = D::n(self.n);
        let (y, acc) = (&y[..2 * n], &mut acc[..n]);
        if D::SPARSE && self.sparse {
            let (g, loads) = (&self.base, &self.minv_load_blocks);
            let comps = (&self.groups[..], &self.powers[..]);
            sparse_accel::<M>(comps, g, loads, forces, y, acc);
        } else {
            self.dense_accel::<M, D>(forces, y, scratch, acc);
        }
        if !self.frictions.is_empty() {
            friction_accel::<M>(&self.comps, &self.frictions, &y[n..], acc);
        }
        if !self.contacts.is_empty() {
            contact_accel::<M>(
                &self.comps,
                &self.contacts,
                y.split_at(n),
                contact_sides,
                acc,
            );
        }
    }

    /// The dense kernel of [`Self::accel_with`], without the friction forces.
    #[inline(always)]
    fn dense_accel<M: Madd, D: Dim>(
        &self,
        forces: &[f64],
        y: &[f64],
        scratch: &mut [f64],
        acc: &mut [f64],
    ) {
        let n = D::n(self.n);
        let na = D::reach(self.active, n);
        if na < n {
            self.reach_accel::<M, D>(forces, y, scratch, acc);
            return;
        }
        let slots = self.power_am.len();
        let fp = &mut scratch[..slots];
        self.power_law_forces::<M, D>(y, fp);
        // q̈ = base + [−M⁻¹K | −M⁻¹C | −M⁻¹B_pᵀ | M⁻¹L] [q; q̇; f; P].
        let (ny, nf) = (2 * n, slots);
        let width = 4 * self.ext_cols;
        for (p, (g, rows)) in (self.gravity_panels.iter())
            .zip(acc[..n].chunks_mut(4))
            .enumerate()
        {
            // Sliced by products: `chunks_exact` would divide at every call.
            let panel = &self.a_ext[p * width..(p + 1) * width];
            let (py, rest) = panel.split_at(4 * ny);
            let (pf, pl) = rest.split_at(4 * nf);
            // Two accumulator sets (even and odd columns) halve the add chain.
            let (mut s, mut t) = (*g, [0.0; 4]);
            panel_madd::<M>(py, y, &mut s, &mut t);
            panel_madd::<M>(pf, fp, &mut s, &mut t);
            panel_madd::<M>(pl, forces, &mut s, &mut t);
            for (r, (a, b)) in rows.iter_mut().zip(s.iter().zip(&t)) {
                *r = a + b;
            }
        }
    }

    /// [`Self::dense_accel`] when the motion reaches fewer than n
    /// coordinates: `[q; q̇; f_p; P]` of the reach gathered into `scratch`
    /// and multiplied by `a_reach` in one pass (one loop's set-up instead of
    /// four, which on a one-body model cost more than the products). The
    /// same sums in the same order as over `a_ext`, so the same results.
    #[inline(always)]
    fn reach_accel<M: Madd, D: Dim>(
        &self,
        forces: &[f64],
        y: &[f64],
        scratch: &mut [f64],
        acc: &mut [f64],
    ) {
        let n = D::n(self.n);
        let na = D::reach(self.active, n);
        let (even, slots) = (na + na % 2, self.power_am.len());
        let x = &mut scratch[..self.reach_cols];
        let (qv, rest) = x.split_at_mut(2 * even);
        let (fp, loads) = rest.split_at_mut(slots);
        qv[..na].copy_from_slice(&y[..na]);
        qv[even..even + na].copy_from_slice(&y[n..n + na]);
        if na < even {
            (qv[na], qv[even + na]) = (0.0, 0.0);
        }
        loads.copy_from_slice(&forces[..loads.len()]);
        self.power_law_forces::<M, D>(y, fp);
        let reached = (4 * na.div_ceil(4)).min(n);
        let width = 4 * self.reach_cols;
        for p in 0..reached.div_ceil(4) {
            let panel = &self.a_reach[p * width..(p + 1) * width];
            let (mut s, mut t) = (self.gravity_panels[p], [0.0; 4]);
            panel_madd::<M>(panel, x, &mut s, &mut t);
            for i in 0..4.min(reached - 4 * p) {
                acc[4 * p + i] = s[i] + t[i];
            }
        }
        // The coordinates out of reach have no acceleration.
        acc[reached..n].fill(0.0);
    }

    /// The power-law forces into `fp` (one per slot), four at a time:
    /// δ = B q for the panel, then f = a sign(δ)|δ|^m (eq. 2–6), as its
    /// change from the static deformation if there is one.
    #[inline(always)]
    fn power_law_forces<M: Madd, D: Dim>(&self, y: &[f64], fp: &mut [f64]) {
        let n = D::n(self.n);
        let na = D::reach(self.active, n);
        let mut live = self.power.len();
        for (((panel, am), pre), f) in self
            .power_b
            .chunks_exact(4 * n)
            .zip(self.power_am.chunks_exact(4))
            .zip(self.power_pre.chunks_exact(4))
            .zip(fp.chunks_exact_mut(4))
        {
            let mut d = [0.0; 4];
            for (b, &qj) in panel.chunks_exact(4).zip(&y[..na]) {
                for i in 0..4 {
                    d[i] = M::madd(b[i], qj, d[i]);
                }
            }
            if self.power_square && !self.power_preloaded {
                // square_change(0, d), the same bits in fewer operations.
                for i in 0..4 {
                    f[i] = am[i].0 * (d[i] * d[i].abs());
                }
            } else if self.power_square {
                for i in 0..4 {
                    f[i] = am[i].0 * square_change(pre[i].d0, d[i]);
                }
            } else {
                // The padding slots' forces are zero: only the power laws'
                // own slots cost a power (the Silverbox fills one of four).
                for i in 0..4 {
                    f[i] = match i < live {
                        true => power_change(am[i].0, am[i].1, &pre[i], d[i]).0,
                        false => 0.0,
                    };
                }
            }
            live = live.saturating_sub(4);
        }
    }
}

/// Refuses a parameter value that is not finite.
fn check_finite(model: &Model, params: &[f64]) -> Result<(), SimulationError> {
    if let Some(i) = params.iter().position(|v| !v.is_finite()) {
        return Err(SimulationError::BadParameter {
            name: model.parameters[i].name.clone(),
            value: params[i],
        });
    }
    Ok(())
}

/// The diagonal of M⁻¹ and the weights' `M⁻¹ × weight` (gravity in each
/// body's frame on its translations), refusing a mass or moment of inertia
/// that is not positive.
fn inverse_masses(
    model: &Model,
    structure: &Structure,
    params: &[f64],
) -> Result<(Vec<f64>, Vec<f64>), SimulationError> {
    let n = structure.n;
    let mut minv = vec![0.0; n];
    let mut minv_gravity = vec![0.0; n];
    for (b, body) in model.bodies.iter().enumerate() {
        let m = body.mass.eval(params);
        let j = body.inertia.map(|v| v.eval(params));
        for (i, &mi) in [m, m, m, j[0], j[1], j[2]].iter().enumerate() {
            if !(mi > 0.0) {
                return Err(SimulationError::NonPositiveInertia {
                    body: body.name.clone(),
                    value: mi,
                });
            }
            minv[6 * b + i] = 1.0 / mi;
        }
        for i in 0..3 {
            minv_gravity[6 * b + i] = structure.gravity_local[b][i];
        }
    }
    Ok((minv, minv_gravity))
}

/// `mat += s · rowᵀ row`, mat n × n row-major.
pub(crate) fn add_outer(mat: &mut [f64], n: usize, row: &Row, s: f64) {
    for (oi, ci) in &row.blocks {
        for (oj, cj) in &row.blocks {
            for i in 0..6 {
                for j in 0..6 {
                    mat[(oi + i) * n + oj + j] += s * ci[i] * cj[j];
                }
            }
        }
    }
}

/// The components' coefficients gathered: linear parts as matrices, power
/// laws as rows.
struct ComponentMatrices {
    /// Linear stiffness K, n × n, row-major.
    k: Vec<f64>,
    /// Damping C, n × n, row-major.
    c: Vec<f64>,
    /// The power-law rows.
    power: Vec<PowerRow>,
}

/// The linear stiffness K and damping C (n × n, row-major) and the
/// power-law rows, refusing an exponent below 1.
fn component_matrices(
    model: &Model,
    structure: &Structure,
    params: &[f64],
) -> Result<ComponentMatrices, SimulationError> {
    let n = structure.n;
    let mut k = vec![0.0; n * n];
    let mut c = vec![0.0; n * n];
    let mut power = Vec::new();
    for comp in &structure.components {
        let damping = comp.damping.eval(params);
        if damping != 0.0 {
            add_outer(&mut c, n, &comp.row, damping);
        }
        if let Some(kv) = comp.law.linear_stiffness(params) {
            add_outer(&mut k, n, &comp.row, kv);
        }
        match comp.law {
            Law::None | Law::Linear(_) | Law::Friction(_) | Law::BoucWen(_) | Law::Contact(_) => {}
            Law::Power(pw) => {
                let m = pw.m.eval(params);
                if !(m >= 1.0) {
                    return Err(SimulationError::BadExponent {
                        element: model.elements[comp.element].name.clone(),
                        value: m,
                    });
                }
                let spring = comp.law.power_spring(params).expect("a power law");
                power.push(PowerRow {
                    row: comp.row.clone(),
                    a: spring.coef,
                    m,
                    kinked: !(m.fract() == 0.0 && m % 2.0 == 1.0),
                    pre: Preload::default(),
                });
            }
        }
    }
    Ok(ComponentMatrices { k, c, power })
}

/// `[−M⁻¹K | −M⁻¹C]`, n × 2n, row-major.
fn linear_accel(n: usize, minv: &[f64], k: &[f64], c: &[f64]) -> Vec<f64> {
    let mut a_lin = vec![0.0; n * 2 * n];
    for i in 0..n {
        for j in 0..n {
            a_lin[i * 2 * n + j] = -minv[i] * k[i * n + j];
            a_lin[i * 2 * n + n + j] = -minv[i] * c[i * n + j];
        }
    }
    a_lin
}

/// `δ|δ| − δ₀|δ₀|` for `δ = δ₀ + d` without branches: `d (|δ| + |δ₀|)`
/// with the same sign at both ends (as in `preload`), the plain difference
/// otherwise, where it does not cancel.
#[inline(always)]
fn square_change(d0: f64, d: f64) -> f64 {
    let dd = d0 + d;
    let near = d * (dd.abs() + d0.abs());
    let far = dd * dd.abs() - d0 * d0.abs();
    if dd * d0 > 0.0 {
        near
    } else {
        far
    }
}

/// `s, t += Σ_j panel[j][..4] x_j` over the columns of a 4-row panel,
/// alternating between the two accumulators.
#[inline(always)]
fn panel_madd<M: Madd>(panel: &[f64], x: &[f64], s: &mut [f64; 4], t: &mut [f64; 4]) {
    let mut cols = panel.chunks_exact(8);
    let mut xs = x.chunks_exact(2);
    for (a, xj) in (&mut cols).zip(&mut xs) {
        for i in 0..4 {
            s[i] = M::madd(a[i], xj[0], s[i]);
            t[i] = M::madd(a[4 + i], xj[1], t[i]);
        }
    }
    if let ([a0, a1, a2, a3], [x0]) = (cols.remainder(), xs.remainder()) {
        for (i, a) in [a0, a1, a2, a3].into_iter().enumerate() {
            s[i] = M::madd(*a, *x0, s[i]);
        }
    }
}
