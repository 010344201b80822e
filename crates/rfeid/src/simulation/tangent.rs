//! The forward sensitivity equation's right-hand side (eq. 27–28 need its
//! solution): for `Y = [Y_q; Y_v] = ∂y/∂x`,
//!
//! `∂q̈/∂x = J Y + E`,  `J = [−M⁻¹(K + Σ_p f_p'(δ_p) B_pᵀB_p) | −M⁻¹C]`,
//!
//! J being the Jacobian of the acceleration: the linear part plus each
//! power-law spring p's slope (eq. 2–6), a rank-one update per spring and
//! stage. E is the explicit dependence on the parameters. Its component
//! part, `−M⁻¹B_iᵀ ∂f_i/∂x` for the stiffness, damping and power-law
//! coefficients of each component i that x enters, is built parameter by
//! parameter (contiguous n-vectors of Eᵀ) and added as the product J Y is
//! stored, whose inner loop is a contiguous multiply–add over the
//! parameters; the mass, inertia and load terms are added after it.
//!
//! Rows of Y and of the result hold [`Tangent::width`] columns: r (and,
//! with contacts, the split column after them, [`Tangent::shift`]) rounded
//! up to a multiple of four, so the kernels run on whole vectors. The
//! padding columns start at zero and stay zero; the split column is zero
//! outside the steps split at a contact switch (`split_shifts`).
//!
//! About a static equilibrium q₀ (`preload`), Y is the deviation
//! `∂(q − q₀)/∂x` and the right-hand side its derivative: with
//! `K_t(q₀) ∂q₀/∂x + ∂f/∂x(q₀) = ∂M/∂x g` (the equilibrium's sensitivity)
//! subtracted, `−M⁻¹(K_t(q) Y_q + (K_t(q) − K_t(q₀)) ∂q₀/∂x + C Y_v +
//! ∂f/∂x(q) − ∂f/∂x(q₀) + ∂M/∂x q̈)` plus the loads' term. The slope changes
//! multiply the constant `B_p ∂q₀/∂x` of each power-law spring p.
use super::dim::Dim;
use super::force_derivative::force_derivative;
use super::laws::contact::{ContactForce, ContactState};
use super::laws::friction::{FrictionAt, FrictionForce};
use super::laws::power_law;
use super::laws::ContactKey;
use super::madd::Madd;
use super::preload::{power_change, Preload};
use super::sparse_tangent::{sparse_tangent, Entries};
use super::structure::{ComponentRow, HysteresisKey, Row, Structure, Usage};
use super::system::System;
use crate::model::{Law, PowerSpring, Segment};

/// A component row that enters the sensitivities beyond the dense linear
/// part: a power-law spring, or a component holding an identified parameter.
#[derive(Debug, Clone)]
struct Active {
    /// `B_i`, dense (n).
    b: Vec<f64>,
    /// `−M⁻¹ B_iᵀ`, dense (n).
    g: Vec<f64>,
    /// The power-law spring, if any.
    power: Option<PowerSpring>,
    /// The friction law, if any: its slope in δ̇ enters J's velocity half.
    friction: Option<FrictionForce>,
    /// The contact law, if any, with its index in [`System::contacts`]:
    /// its slopes enter both halves of J.
    contact: Option<(ContactForce, usize)>,
    /// Its static deformation.
    pre: Preload,
    /// `B_i ∂q₀/∂x` ([`static_columns`]).
    static_columns: Vec<f64>,
    /// Identified parameters acting here: (column, usage).
    usages: Vec<(usize, Usage)>,
}

/// The sensitivity right-hand side for one run: a model at one parameter
/// point and a list of identified parameters.
#[derive(Debug, Clone)]
pub(crate) struct Tangent {
    /// Columns per row of Y: the number of parameters (and the split
    /// column, [`Self::shift`]) rounded up to a multiple of four.
    pub width: usize,
    /// With contacts, the column after the parameters' that carries a
    /// split step's derivative in a located switch's instant
    /// (`split_shifts`); it enters no parameter's terms.
    pub shift: Option<usize>,
    active: Vec<Active>,
    /// Mass, inertia and amplitude parameters: (column, usage).
    others: Vec<(usize, Usage)>,
    /// Whether the system runs element by element ([`System::sparse`]);
    /// then `active` is empty and `component_usages` is used instead.
    sparse: bool,
    /// For each component row, the identified parameters acting there:
    /// (column, usage). Empty unless `sparse`.
    component_usages: Vec<Vec<(usize, Usage)>>,
    /// For each component row, `B_i ∂q₀/∂x` ([`static_columns`]). Empty
    /// unless `sparse`.
    component_statics: Vec<Vec<f64>>,
    /// For each component row, its nonzero entries for rows `width` long.
    /// Empty unless `sparse`.
    component_entries: Vec<Entries>,
    /// For each Bouc–Wen component ([`System::hysteresis`]), the
    /// identified parameters acting on its internal state: (column, key).
    hysteresis: Vec<Vec<(usize, HysteresisKey)>>,
    /// For each contact ([`System::contacts`]), `B ∂q₀/∂x` ([`static_columns`],
    /// empty without a static equilibrium moving with x) and the columns
    /// of the parameters acting on its law, with their keys: what the
    /// instant of a located opening or closing moves with
    /// (`contact_events`).
    contacts: Vec<ContactTerms>,
    /// 1 + the last coordinate whose acceleration the explicit terms E can
    /// move outside the system's reach (a component a parameter enters, or
    /// a load): with that reach, the rows of the sensitivities that can
    /// differ from zero ([`Self::reach`]).
    extent: usize,
}

/// A contact's `B ∂q₀/∂x` and the (column, key) of its law's parameters
/// ([`Tangent::contact_terms`]).
type ContactTerms = (Vec<f64>, Vec<(usize, ContactKey)>);

impl Tangent {
    /// Gathers the components and parameters of `sys` that the sensitivities
    /// to the parameters `wrt` need.
    pub fn new(sys: &System<'_>, wrt: &[usize]) -> Tangent {
        if wrt.is_empty() {
            return Tangent::empty(sys.sparse);
        }
        let (usages, others) = usages_by_component(sys.structure, wrt);
        let hysteresis = hysteresis_usages(sys, wrt);
        let shift = (!sys.contacts.is_empty()).then_some(wrt.len());
        let width = (wrt.len() + usize::from(shift.is_some())).next_multiple_of(4);
        let contacts = contact_terms(sys, &usages, wrt.len(), width);
        if sys.sparse {
            let mut t = Tangent::sparse(sys, wrt.len(), width, usages, others);
            t.hysteresis = hysteresis;
            t.contacts = contacts;
            t.shift = shift;
            return t;
        }
        let active = active_components(sys, wrt.len(), width, usages);
        Tangent {
            extent: explicit_extent(sys, &active, &others),
            contacts,
            shift,
            width,
            active,
            others,
            sparse: false,
            component_usages: Vec::new(),
            component_statics: Vec::new(),
            component_entries: Vec::new(),
            hysteresis,
        }
    }

    /// The right-hand side of sensitivities to no parameter.
    fn empty(sparse: bool) -> Tangent {
        Tangent {
            extent: 0,
            width: 0,
            shift: None,
            active: Vec::new(),
            others: Vec::new(),
            sparse,
            component_usages: Vec::new(),
            component_statics: Vec::new(),
            component_entries: Vec::new(),
            hysteresis: Vec::new(),
            contacts: Vec::new(),
        }
    }

    /// The right-hand side for the element-by-element kernel: every
    /// component row with its usages, static columns and entries.
    fn sparse(
        sys: &System<'_>,
        r: usize,
        width: usize,
        usages: Vec<Vec<(usize, Usage)>>,
        others: Vec<(usize, Usage)>,
    ) -> Tangent {
        let component_statics: Vec<Vec<f64>> = sys
            .structure
            .components
            .iter()
            .zip(&sys.comps)
            .map(|(c, comp)| {
                let moves = comp.power.is_some() || comp.contact.is_some();
                component_static_columns(sys, c, moves, r, width)
            })
            .collect();
        let component_entries = (sys.comps.iter().zip(&usages))
            .zip(&component_statics)
            .map(|((c, u), s)| Entries::new(c, width, u, s))
            .collect();
        Tangent {
            extent: sys.n,
            width,
            shift: None,
            active: Vec::new(),
            others,
            sparse: true,
            component_usages: usages,
            component_statics,
            component_entries,
            hysteresis: Vec::new(),
            contacts: Vec::new(),
        }
    }

    /// For each Bouc–Wen component, the identified parameters acting on its
    /// internal state: (column, key); empty without sensitivities.
    pub fn hysteresis_usages(&self) -> &[Vec<(usize, HysteresisKey)>] {
        &self.hysteresis
    }

    /// Contact j's `B ∂q₀/∂x` (empty without one) and the columns of its
    /// law's parameters, with their keys.
    pub fn contact_terms(&self, j: usize) -> (&[f64], &[(usize, ContactKey)]) {
        self.contacts
            .get(j)
            .map_or((&[][..], &[][..]), |(s, g)| (&s[..], &g[..]))
    }

    /// How many leading coordinates of each half of the sensitivities can
    /// differ from zero: the system's reach ([`System::active`]) or the
    /// explicit terms' extent, whichever is further, rounded up to an even
    /// count (the products go two rows at a time) and at most n. The rows
    /// past it start at zero and stay there: no acceleration, load or
    /// parameter acts on them, and M is diagonal. [`Self::apply`] computes
    /// only the rows before it, and the stepper combines only those.
    pub fn reach(&self, sys: &System<'_>) -> usize {
        let r = sys.active.max(self.extent);
        (r + r % 2).min(sys.n)
    }

    /// Scratch length that [`Self::apply`] needs for n coordinates: J
    /// (n × 2n) and Eᵀ (width × n).
    pub fn scratch_len(&self, n: usize) -> usize {
        match self.sparse {
            true => 0,
            false => 2 * n * n + self.width * n,
        }
    }

    /// `dacc = ∂q̈/∂x` (n rows of [`Self::width`]) at time t, state `y`
    /// (2n) with acceleration `acc` (n), for sensitivities `sy` (2n rows),
    /// each contact on its side in `contact_sides` ([`System::accel_with`]).
    /// `scratch` has [`Self::scratch_len`]. As for [`System::accel_with`],
    /// a fixed size D must not be given an element-by-element system.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn apply<M: Madd, D: Dim>(
        &self,
        sys: &System<'_>,
        (t, before): (f64, bool),
        (y, contact_sides): (&[f64], &[f64]),
        acc: &[f64],
        sy: &[f64],
        dacc: &mut [f64],
        (scratch, segments): (&mut [f64], &mut [Segment]),
    ) {
        let n = D::n(sys.n);
        let width = self.width;
        let (q, v) = y[..2 * n].split_at(n);
        let sy = &sy[..2 * n * width];
        let dacc = &mut dacc[..n * width];
        if D::SPARSE && self.sparse {
            let columns = (
                &self.component_usages[..],
                &self.component_statics[..],
                &self.component_entries[..],
            );
            sparse_tangent::<M>(sys, columns, (q, v, contact_sides), sy, width, dacc);
            self.add_others(sys, (t, before), acc, dacc, segments);
            return;
        }
        // Rows of J and of the result past the reach are zero: they are
        // neither computed nor read ([`Self::reach`]).
        let r = D::reach(self.reach(sys), n);
        let (jac, et) = scratch.split_at_mut(2 * n * n);
        let (jac, et) = (&mut jac[..2 * n * r], &mut et[..width * n]);

        // J: the linear part, plus f'(δ) (−M⁻¹B_pᵀ) B_p per power-law spring.
        // Eᵀ: per parameter, −M⁻¹B_iᵀ ∂f_i/∂x over the components it enters,
        // and the slope's change times B_p ∂q₀/∂x under a preload.
        jac.copy_from_slice(&sys.a_lin[..2 * n * r]);
        et.fill(0.0);
        for comp in &self.active {
            let (b, g) = (&comp.b[..n], &comp.g[..n]);
            let d = dot::<M>(b, q);
            if let Some(p) = comp.power {
                let slope = power_law(p.coef, p.m, comp.pre.d0 + d).1;
                add_rank_one::<M>(jac, n, (g, b), slope, 0);
                let change = match comp.static_columns.is_empty() {
                    true => 0.0,
                    false => power_change(p.coef, p.m, &comp.pre, d).1,
                };
                add_static_change::<M>(et, n, g, &comp.static_columns, change);
            }
            // δ̇ at first use, a closure by value for each: one lent as `&mut`
            // is called through a shim that may stay out of line, off FMA.
            let mut cached = None;
            let friction =
                FrictionAt::of(comp.friction.as_ref(), || rate_once::<M>(&mut cached, b, v));
            let side = match comp.contact {
                Some((_, j)) => contact_sides.get(j).copied().unwrap_or(0.0),
                None => 0.0,
            };
            let contact = ContactState::of(comp.contact.as_ref().map(|c| &c.0), (d, side), || {
                rate_once::<M>(&mut cached, b, v)
            });
            add_rank_one::<M>(jac, n, (g, b), contact.at.slope, 0);
            let change = contact.slope_change();
            add_static_change::<M>(et, n, g, &comp.static_columns, change);
            let slope = friction.slope() + contact.at.damping;
            add_rank_one::<M>(jac, n, (g, b), slope, 1);
            for &(col, usage) in &comp.usages {
                let laws = (comp.power, &friction, &contact);
                let rate = || rate_once::<M>(&mut cached, b, v);
                let f = force_derivative(usage, laws, &comp.pre, d, rate);
                axpy::<M>(f, g, &mut et[col * n..(col + 1) * n]);
            }
        }

        times_rows::<M>(jac, sy, et, (n, r, width), dacc);
        self.add_others(sys, (t, before), acc, dacc, segments);
    }

    /// Adds the mass, inertia and load terms of E to `dacc`; a load's shape
    /// comes from the excitation's kept `segments` ([`System::shape_kept`]).
    #[inline(always)]
    fn add_others(
        &self,
        sys: &System<'_>,
        (t, before): (f64, bool),
        acc: &[f64],
        dacc: &mut [f64],
        segments: &mut [Segment],
    ) {
        let width = self.width;
        for &(col, usage) in &self.others {
            let cell = |k: usize| k * width + col;
            match usage {
                Usage::Mass(b) => {
                    // (g − q̈)/m, or −q̈/m about the static equilibrium,
                    // whose sensitivity holds the weight's part.
                    let m = sys.model.bodies[b].mass.eval(&sys.params);
                    for k in 6 * b..6 * b + 3 {
                        dacc[cell(k)] += (sys.base[k] - acc[k]) / m;
                    }
                }
                Usage::Inertia(b, axis) => {
                    let k = 6 * b + 3 + axis;
                    dacc[cell(k)] -= acc[k] * sys.minv[k];
                }
                Usage::Amplitude(e, j) => {
                    let s = sys.shape_kept((e, j), (t, before), segments);
                    if s != 0.0 {
                        for (k, l) in sys.minv_loads[e].iter().enumerate() {
                            dacc[cell(k)] += s * l;
                        }
                    }
                }
                _ => {}
            }
        }
    }
}

/// Identified parameters acting at one place: (column, usage).
type ColumnUsages = Vec<(usize, Usage)>;

/// The usages of the parameters `wrt` (by column): per component row, and
/// the others (masses, inertias, amplitudes). Bouc–Wen keys act through the
/// internal state, not the component's force: they are in neither
/// ([`hysteresis_usages`]).
///
/// Usages per component first, so that the active components come in
/// component order whatever the order of `wrt`: a column's explicit terms
/// are then summed in the same order however it is asked for.
fn usages_by_component(structure: &Structure, wrt: &[usize]) -> (Vec<ColumnUsages>, ColumnUsages) {
    let mut usages = vec![Vec::new(); structure.components.len()];
    let mut others = Vec::new();
    for (col, &p) in wrt.iter().enumerate() {
        for &usage in &structure.usages[p] {
            match usage {
                Usage::Stiffness(i)
                | Usage::Damping(i)
                | Usage::PowerCoefficient(i)
                | Usage::PowerExponent(i)
                | Usage::Friction(i, _)
                | Usage::Contact(i, _) => usages[i].push((col, usage)),
                Usage::Hysteresis(..) => {}
                Usage::Mass(_) | Usage::Inertia(..) | Usage::Amplitude(..) => {
                    others.push((col, usage))
                }
            }
        }
    }
    (usages, others)
}

/// For each Bouc–Wen component of `sys`, the (column, key) of the
/// parameters `wrt` acting on its law, in column order.
fn hysteresis_usages(sys: &System<'_>, wrt: &[usize]) -> Vec<Vec<(usize, HysteresisKey)>> {
    sys.hysteresis
        .iter()
        .map(|row| {
            let mut keys = Vec::new();
            for (col, &p) in wrt.iter().enumerate() {
                for &usage in &sys.structure.usages[p] {
                    match usage {
                        Usage::Hysteresis(i, key) if i == row.comp => keys.push((col, key)),
                        _ => {}
                    }
                }
            }
            keys
        })
        .collect()
}

/// For each contact of `sys`, its `B ∂q₀/∂x` and the columns of its
/// law's parameters with their keys ([`Tangent::contact_terms`]), from the
/// usages per component.
fn contact_terms(
    sys: &System<'_>,
    usages: &[Vec<(usize, Usage)>],
    r: usize,
    width: usize,
) -> Vec<ContactTerms> {
    sys.contacts
        .iter()
        .map(|ct| {
            let row = &sys.structure.components[ct.comp].row;
            let keys = (usages[ct.comp].iter())
                .filter_map(|&(col, u)| match u {
                    Usage::Contact(_, key) => Some((col, key)),
                    _ => None,
                })
                .collect();
            (static_columns(sys, row, r, width), keys)
        })
        .collect()
}

/// A component's `B_i ∂q₀/∂x` ([`static_columns`]) if its slope moves
/// with the static deformation (`moves`: a power-law spring, a contact),
/// else empty.
fn component_static_columns(
    sys: &System<'_>,
    c: &ComponentRow,
    moves: bool,
    r: usize,
    width: usize,
) -> Vec<f64> {
    match moves {
        true => static_columns(sys, &c.row, r, width),
        false => Vec::new(),
    }
}

/// The components the dense kernel's sensitivities need beyond the linear
/// part: the power-law springs and those holding a parameter of `wrt`.
fn active_components(
    sys: &System<'_>,
    r: usize,
    width: usize,
    usages: Vec<Vec<(usize, Usage)>>,
) -> Vec<Active> {
    let n = sys.n;
    sys.structure
        .components
        .iter()
        .zip(usages)
        .zip(&sys.comps)
        .filter(|((c, u), _)| {
            matches!(c.law, Law::Power(_) | Law::Friction(_) | Law::Contact(_)) || !u.is_empty()
        })
        .map(|((c, usages), comp)| {
            let power = c.law.power_spring(&sys.params);
            let b = c.row.dense(n);
            Active {
                g: b.iter().zip(&sys.minv).map(|(b, m)| -b * m).collect(),
                b,
                power,
                friction: comp.friction.map(|j| sys.frictions[j as usize].law),
                contact: comp
                    .contact
                    .map(|j| (sys.contacts[j as usize].law, j as usize)),
                pre: comp
                    .power(&sys.powers)
                    .map_or_else(Preload::default, |p| p.pre),
                static_columns: component_static_columns(
                    sys,
                    c,
                    power.is_some() || comp.contact.is_some(),
                    r,
                    width,
                ),
                usages,
            }
        })
        .collect()
}

/// 1 + the last coordinate that the explicit terms of the parameters can
/// move, where the system's reach may not hold it ([`Tangent::reach`]):
/// the components in `active` (a power-law spring, or one a parameter
/// enters, whatever its coefficients' values) and the loads in `others`.
/// A mass's and an inertia's terms, `(g − q̈)/m` and `−q̈/m` per
/// coordinate, count nothing: they are zero past the system's reach, where
/// the weight and the acceleration are.
fn explicit_extent(sys: &System<'_>, active: &[Active], others: &[(usize, Usage)]) -> usize {
    let last = |v: &[f64]| v.iter().rposition(|x| *x != 0.0).map_or(0, |i| i + 1);
    // g = −M⁻¹b has b's nonzeros.
    let comps = active.iter().map(|c| last(&c.b));
    let others = others.iter().map(|&(_, usage)| match usage {
        Usage::Mass(_) | Usage::Inertia(..) => 0,
        Usage::Amplitude(e, _) => last(&sys.minv_loads[e]),
        // No other usage is among `others`; were one, every row.
        _ => sys.n,
    });
    comps.chain(others).max().unwrap_or(0).min(sys.n)
}

/// `J += slope · g bᵀ` in J's position half (`half` 0) or velocity half
/// (1); nothing for a zero slope.
#[inline(always)]
fn add_rank_one<M: Madd>(
    jac: &mut [f64],
    n: usize,
    (g, b): (&[f64], &[f64]),
    slope: f64,
    half: usize,
) {
    if slope == 0.0 {
        return;
    }
    for (k, row) in jac.chunks_exact_mut(2 * n).enumerate() {
        axpy::<M>(slope * g[k], b, &mut row[half * n..(half + 1) * n]);
    }
}

/// `Eᵀ[col] += change · w_col · g` for each column's `B ∂q₀/∂x` in
/// `statics` (a slope's change from the static one); nothing for a zero
/// change or without them.
#[inline(always)]
fn add_static_change<M: Madd>(et: &mut [f64], n: usize, g: &[f64], statics: &[f64], change: f64) {
    if change == 0.0 {
        return;
    }
    for (col, w) in et.chunks_exact_mut(n).zip(statics) {
        axpy::<M>(change * w, g, col);
    }
}

/// A component's rate `b · v`, computed at its first use into `cached`.
#[inline(always)]
fn rate_once<M: Madd>(cached: &mut Option<f64>, b: &[f64], v: &[f64]) -> f64 {
    *cached.get_or_insert_with(|| dot::<M>(b, v))
}

/// `a · x` for a of even length, in two partial sums.
#[inline(always)]
fn dot<M: Madd>(a: &[f64], x: &[f64]) -> f64 {
    let (mut s, mut t) = (0.0, 0.0);
    for (a, x) in a.chunks_exact(2).zip(x.chunks_exact(2)) {
        s = M::madd(a[0], x[0], s);
        t = M::madd(a[1], x[1], t);
    }
    s + t
}

/// `J Y + E` into the first `r` rows of `dacc` (rows `width` long), row by
/// row: the whole rows of J (`2n` long) when `r == n`, else only the
/// reached ones ([`Tangent::reach`]).
#[inline(always)]
fn times_rows<M: Madd>(
    jac: &[f64],
    sy: &[f64],
    et: &[f64],
    (n, r, width): (usize, usize, usize),
    dacc: &mut [f64],
) {
    for (k, (row, out)) in jac
        .chunks_exact(2 * n)
        .zip(dacc[..r * width].chunks_exact_mut(width))
        .enumerate()
    {
        match r == n {
            true => times_columns::<M>(row, sy, (et, n, k), width, out),
            false => times_reached::<M>(row, sy, (et, n, k), (width, r), out),
        }
    }
}

/// `out[c] = a · X[.., c] + Eᵀ[c][k]` for a row vector a (even length) and a
/// matrix X with rows `width` long (a multiple of four), sixteen (then
/// eight, four) columns at a time; `(et, n, k)` is Eᵀ with its row length
/// and the row k of E wanted.
#[inline(always)]
fn times_columns<M: Madd>(
    a: &[f64],
    x: &[f64],
    e: (&[f64], usize, usize),
    width: usize,
    out: &mut [f64],
) {
    let mut c0 = 0;
    while c0 + 16 <= width {
        row_times::<M, 16>(a, x, e, width, c0, out);
        c0 += 16;
    }
    if c0 + 8 <= width {
        row_times::<M, 8>(a, x, e, width, c0, out);
        c0 += 8;
    }
    if c0 < width {
        row_times::<M, 4>(a, x, e, width, c0, out);
    }
}

/// `out[c0..c0+W]` of [`times_columns`], two rows of X at a time in separate
/// accumulators so that the loop is not latency-bound.
#[inline(always)]
fn row_times<M: Madd, const W: usize>(
    a: &[f64],
    x: &[f64],
    (et, n, k): (&[f64], usize, usize),
    width: usize,
    c0: usize,
    out: &mut [f64],
) {
    // Every row read below (a.len() of them) lies inside x.
    let rows_fit = a.len().checked_mul(width).is_some_and(|len| len <= x.len());
    let e_fits = (c0 + W).checked_mul(n).is_some_and(|len| len <= et.len());
    assert!(c0 + W <= width && a.len() % 2 == 0 && rows_fit && k < n && e_fits);
    let (mut s, mut t) = ([0.0; W], [0.0; W]);
    // An index loop: written with `iter_mut().enumerate()` this compiles to
    // 10 % more instructions for the whole run (callgrind).
    #[allow(clippy::needless_range_loop)]
    for c in 0..W {
        // SAFETY: (c0 + c)·n + k < (c0 + W)·n ≤ et.len() (assert above).
        s[c] = unsafe { *et.get_unchecked((c0 + c) * n + k) };
    }
    for (j, c) in a.chunks_exact(2).enumerate() {
        let r0 = 2 * j * width + c0;
        let r1 = r0 + width;
        // SAFETY: r1 + W ≤ (2j + 2)·width ≤ a.len()·width ≤ x.len() (assert
        // above, with c0 + W ≤ width; the product does not overflow). Checked indexing here costs a third
        // of the loop's instructions.
        let (x0, x1) = unsafe { (x.get_unchecked(r0..r0 + W), x.get_unchecked(r1..r1 + W)) };
        for q in 0..W {
            s[q] = M::madd(c[0], x0[q], s[q]);
            t[q] = M::madd(c[1], x1[q], t[q]);
        }
    }
    let o = &mut out[c0..c0 + W];
    for q in 0..W {
        o[q] = s[q] + t[q];
    }
}

/// [`times_columns`] over the rows of X that can differ from zero: the
/// first `r` (even) of each half, as [`Tangent::reach`] gives them. The
/// skipped terms multiply rows of zeros, and the rest are summed in the
/// same two accumulators in the same order, so the result is the same (for
/// finite values: a non-finite entry of J times a zero row would be NaN).
#[inline(always)]
fn times_reached<M: Madd>(
    a: &[f64],
    x: &[f64],
    (et, n, k): (&[f64], usize, usize),
    (width, r): (usize, usize),
    out: &mut [f64],
) {
    for c0 in (0..width).step_by(4) {
        let mut s: [f64; 4] = std::array::from_fn(|c| et[(c0 + c) * n + k]);
        let mut t = [0.0; 4];
        for j in (0..r).step_by(2).chain((n..n + r).step_by(2)) {
            let x0 = &x[j * width + c0..][..4];
            let x1 = &x[(j + 1) * width + c0..][..4];
            for q in 0..4 {
                s[q] = M::madd(a[j], x0[q], s[q]);
                t[q] = M::madd(a[j + 1], x1[q], t[q]);
            }
        }
        for (q, o) in out[c0..c0 + 4].iter_mut().enumerate() {
            *o = s[q] + t[q];
        }
    }
}

/// `y += alpha · x` (x at least as long as y).
#[inline(always)]
fn axpy<M: Madd>(alpha: f64, x: &[f64], y: &mut [f64]) {
    let x = &x[..y.len()];
    for i in 0..y.len() {
        y[i] = M::madd(alpha, x[i], y[i]);
    }
}

/// `B ∂q₀/∂x` for the component row `row`: the static equilibrium's
/// sensitivities (`r` columns) seen by the row, zero-padded to `width`;
/// empty without them.
fn static_columns(sys: &System<'_>, row: &Row, r: usize, width: usize) -> Vec<f64> {
    if r == 0 || sys.static_dq.len() != sys.n * r {
        return Vec::new();
    }
    let mut w = vec![0.0; width];
    for (o, coefs) in &row.blocks {
        for (i, &c) in coefs.iter().enumerate() {
            let dq = &sys.static_dq[(o + i) * r..(o + i + 1) * r];
            for (w, s) in w.iter_mut().zip(dq) {
                *w += c * s;
            }
        }
    }
    w
}
