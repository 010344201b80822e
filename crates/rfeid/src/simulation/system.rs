//! The equations of motion at one parameter point (eq. 1):
//!
//! `M q̈ + Bᵀ f(B q, B q̇) = P(t)`,  `f_i = law_i(δ_i) + c_i δ̇_i`,
//!
//! written as `q̈ = a(t, q, q̇)`. Linear springs and all dampers are folded
//! into dense `−M⁻¹K` and `−M⁻¹C` (the paper's K and C, and F_d); the
//! power-law springs (F_e, eq. 2–6) stay as rows. [`System::accel`] and
//! [`System::accel_tangent`] allocate nothing.
use super::madd::{Madd, Separate};
use super::structure::{Row, Structure, Usage};
use super::SimulationError;
use crate::model::{Law, Model, Signal};

/// A power-law spring row: `f = a · sign(δ) · |δ|^m`, `δ = row · q`.
#[derive(Debug, Clone)]
pub struct PowerRow {
    /// δ = row · q.
    pub row: Row,
    /// `M⁻¹ rowᵀ`, dense.
    pub minv_row: Vec<f64>,
    /// Coefficient a.
    pub a: f64,
    /// Exponent m ≥ 1.
    pub m: f64,
    /// Whether the law is non-smooth at δ = 0: `sign(δ)|δ|^m` is the
    /// polynomial δ^m for odd whole m, and non-smooth otherwise.
    pub kinked: bool,
}

/// The force of the power law and its slope, `(a sign(δ)|δ|^m, m a |δ|^(m−1))`.
#[inline]
pub fn power_law(a: f64, m: f64, d: f64) -> (f64, f64) {
    let ad = d.abs();
    if m == 2.0 {
        (a * d * ad, 2.0 * a * ad)
    } else if m == 1.0 {
        (a * d, a)
    } else if ad == 0.0 {
        (0.0, 0.0)
    } else {
        let p = ad.powf(m - 1.0);
        (a * p * d, a * m * p)
    }
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
    /// The same in 4-row panels (`[panel][column][4]`, zero-padded), so that
    /// [`System::accel`] keeps its accumulators in registers.
    a_panels: Vec<f64>,
    /// Power-law rows.
    pub power: Vec<PowerRow>,
    /// `M⁻¹ L_e` per excitation.
    pub minv_loads: Vec<Vec<f64>>,
    /// `M⁻¹ × weight` (constant), n.
    pub minv_gravity: Vec<f64>,
    /// Power-law rows of B in 4-row panels, `[panel][coordinate][4]`, zero-padded.
    power_b: Vec<f64>,
    /// `(a, m)` per power-law row, padded to whole panels with `(0, 2)`.
    power_am: Vec<(f64, f64)>,
    /// Per component row i: the nonzero entries of `M⁻¹ B_iᵀ` as (coordinate, value).
    comp_minv: Vec<Vec<(usize, f64)>>,
    /// Per component row: `(a, m)` of a power law (unused otherwise).
    comp_power: Vec<(f64, f64)>,
}

impl<'a> System<'a> {
    /// Evaluates every coefficient at the parameter values `params`.
    pub fn new(
        model: &'a Model,
        structure: &'a Structure,
        params: &[f64],
    ) -> Result<Self, SimulationError> {
        if let Some(i) = params.iter().position(|v| !v.is_finite()) {
            return Err(SimulationError::BadParameter {
                name: model.parameters[i].name.clone(),
                value: params[i],
            });
        }
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
        let mut k = vec![0.0; n * n];
        let mut c = vec![0.0; n * n];
        let mut power = Vec::new();
        let outer = |mat: &mut [f64], row: &Row, s: f64| {
            for (oi, ci) in &row.blocks {
                for (oj, cj) in &row.blocks {
                    for i in 0..6 {
                        for j in 0..6 {
                            mat[(oi + i) * n + oj + j] += s * ci[i] * cj[j];
                        }
                    }
                }
            }
        };
        for comp in &structure.components {
            let damping = comp.damping.eval(params);
            if damping != 0.0 {
                outer(&mut c, &comp.row, damping);
            }
            match comp.law {
                Law::None => {}
                Law::Linear { k: kv } => outer(&mut k, &comp.row, kv.eval(params)),
                Law::Power { a, m } => {
                    let m = m.eval(params);
                    if !(m >= 1.0) {
                        return Err(SimulationError::BadExponent {
                            element: model.elements[comp.element].name.clone(),
                            value: m,
                        });
                    }
                    let mut minv_row = comp.row.dense(n);
                    minv_row.iter_mut().zip(&minv).for_each(|(x, mi)| *x *= mi);
                    power.push(PowerRow {
                        row: comp.row.clone(),
                        minv_row,
                        a: a.eval(params),
                        m,
                        kinked: !(m.fract() == 0.0 && m % 2.0 == 1.0),
                    });
                }
            }
        }
        let mut a_lin = vec![0.0; n * 2 * n];
        for i in 0..n {
            for j in 0..n {
                a_lin[i * 2 * n + j] = -minv[i] * k[i * n + j];
                a_lin[i * 2 * n + n + j] = -minv[i] * c[i * n + j];
            }
        }
        let panels = n.div_ceil(4);
        let mut a_panels = vec![0.0; panels * 2 * n * 4];
        for i in 0..n {
            for j in 0..2 * n {
                a_panels[((i / 4) * 2 * n + j) * 4 + i % 4] = a_lin[i * 2 * n + j];
            }
        }
        let minv_loads = structure
            .loads
            .iter()
            .map(|l| l.iter().zip(&minv).map(|(x, m)| x * m).collect())
            .collect();
        let comp_minv = structure
            .components
            .iter()
            .map(|c| {
                c.row
                    .blocks
                    .iter()
                    .flat_map(|(off, co)| (0..6).map(move |i| (off + i, co[i])))
                    .filter(|(_, v)| *v != 0.0)
                    .map(|(k, v)| (k, v * minv[k]))
                    .collect()
            })
            .collect();
        let comp_power = structure
            .components
            .iter()
            .map(|c| match c.law {
                Law::Power { a, m } => (a.eval(params), m.eval(params)),
                _ => (0.0, 1.0),
            })
            .collect();
        let panels = power.len().div_ceil(4);
        let mut power_b = vec![0.0; panels * n * 4];
        let mut power_am = vec![(0.0, 2.0); panels * 4];
        for (k, pr) in power.iter().enumerate() {
            let dense = pr.row.dense(n);
            for (j, v) in dense.iter().enumerate() {
                power_b[((k / 4) * n + j) * 4 + k % 4] = *v;
            }
            power_am[k] = (pr.a, pr.m);
        }
        Ok(System {
            power_b,
            power_am,
            comp_minv,
            comp_power,
            structure,
            model,
            params: params.to_vec(),
            n,
            minv,
            a_lin,
            a_panels,
            power,
            minv_loads,
            minv_gravity,
        })
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

    /// `q̈ = a(t, q, q̇)` for the state `y = [q; q̇]` (length 2n), into `acc`
    /// (length n); `forces` are the excitation forces at t ([`System::forces`]).
    #[inline(always)]
    pub fn accel(&self, forces: &[f64], y: &[f64], acc: &mut [f64]) {
        self.accel_with::<Separate>(forces, y, acc)
    }

    /// [`System::accel`] with a chosen multiply–add.
    #[inline(always)]
    pub(crate) fn accel_with<M: Madd>(&self, forces: &[f64], y: &[f64], acc: &mut [f64]) {
        let n = self.n;
        let n2 = 2 * n;
        // [−M⁻¹K | −M⁻¹C] y in 4-row panels, accumulators in registers.
        for (p, panel) in self.a_panels.chunks_exact(4 * n2).enumerate() {
            // Two accumulator sets (even and odd columns) halve the add chain.
            let (mut s, mut t) = ([0.0; 4], [0.0; 4]);
            let mut cols = panel.chunks_exact(8).zip(y[..n2].chunks_exact(2));
            for (a, yj) in &mut cols {
                for i in 0..4 {
                    s[i] = M::madd(a[i], yj[0], s[i]);
                    t[i] = M::madd(a[4 + i], yj[1], t[i]);
                }
            }
            for i in 0..4 {
                s[i] += t[i];
            }
            let rows = &mut acc[4 * p..(4 * p + 4).min(n)];
            rows.iter_mut().zip(&s).for_each(|(r, v)| *r = *v);
        }
        acc.iter_mut()
            .zip(&self.minv_gravity)
            .for_each(|(a, g)| *a += g);
        for (l, &p) in self.minv_loads.iter().zip(forces) {
            if p != 0.0 {
                axpy(p, l, acc);
            }
        }
        // Power-law springs four at a time: δ = B q for the panel, then
        // q̈ −= M⁻¹ Bᵀ f(δ) (eq. 2–6).
        for (p, (panel, am)) in self
            .power_b
            .chunks_exact(4 * n)
            .zip(self.power_am.chunks_exact(4))
            .enumerate()
        {
            let mut d = [0.0; 4];
            for (b, &qj) in panel.chunks_exact(4).zip(&y[..n]) {
                for i in 0..4 {
                    d[i] = M::madd(b[i], qj, d[i]);
                }
            }
            // Only the real rows: the padding of the last panel has no
            // `minv_row` (and its δ is NaN once the state is).
            let rows = self.power.len() - 4 * p;
            for (i, &(a, m)) in am.iter().enumerate().take(rows) {
                let (f, _) = power_law(a, m, d[i]);
                if f != 0.0 {
                    let g = &self.power[4 * p + i].minv_row;
                    acc.iter_mut().zip(g).for_each(|(ai, gi)| *ai -= f * gi);
                }
            }
        }
    }

    /// The acceleration of the sensitivities: for `Y = ∂y/∂x` (2n × r,
    /// row-major, r = `wrt.len()`) computes `∂q̈/∂x = (∂a/∂y) Y + ∂a/∂x`
    /// into `dacc` (n × r, row-major). `acc` is `a(t, y)`, already computed.
    /// This is the forward sensitivity equation; applied inside the same
    /// Runge–Kutta stages it gives the exact derivative of the discrete
    /// solution.
    #[allow(clippy::too_many_arguments)]
    pub fn accel_tangent(
        &self,
        t: f64,
        y: &[f64],
        acc: &[f64],
        wrt: &[usize],
        sy: &[f64],
        dacc: &mut [f64],
        scratch: &mut [f64],
    ) {
        self.accel_tangent_with::<Separate>(t, y, acc, wrt, sy, dacc, scratch)
    }

    /// [`System::accel_tangent`] with a chosen multiply–add.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn accel_tangent_with<M: Madd>(
        &self,
        t: f64,
        y: &[f64],
        acc: &[f64],
        wrt: &[usize],
        sy: &[f64],
        dacc: &mut [f64],
        scratch: &mut [f64],
    ) {
        let n = self.n;
        let r = wrt.len();
        // Linear part: [−M⁻¹K | −M⁻¹C] Y.
        for i in 0..n {
            let out = &mut dacc[i * r..(i + 1) * r];
            let arow = &self.a_lin[i * 2 * n..(i + 1) * 2 * n];
            let mut c0 = 0;
            // Sixteen (then eight) parameters at a time, in two interleaved
            // accumulator chains, so that the loop is not latency-bound.
            while c0 + 16 <= r {
                row_times::<M, 16>(arow, sy, r, c0, out);
                c0 += 16;
            }
            while c0 + 8 <= r {
                row_times::<M, 8>(arow, sy, r, c0, out);
                c0 += 8;
            }
            // The rest one at a time, in the same order of operations, so a
            // column's value does not depend on how many columns there are.
            for c in c0..r {
                row_times::<M, 1>(arow, sy, r, c, out);
            }
        }
        // Power-law springs: −M⁻¹ rowᵀ f'(δ) (row · S).
        let w = &mut scratch[..r];
        for pr in &self.power {
            let d = pr.row.dot(&y[..n]);
            let (_, slope) = power_law(pr.a, pr.m, d);
            if slope == 0.0 {
                continue;
            }
            w.fill(0.0);
            for (off, c) in &pr.row.blocks {
                for (i, &ci) in c.iter().enumerate() {
                    if ci != 0.0 {
                        axpy(ci, &sy[(off + i) * r..(off + i + 1) * r], w);
                    }
                }
            }
            for (i, &g) in pr.minv_row.iter().enumerate() {
                if g != 0.0 {
                    axpy(-g * slope, w, &mut dacc[i * r..(i + 1) * r]);
                }
            }
        }
        // Explicit dependence on each parameter.
        for (col, &p) in wrt.iter().enumerate() {
            for usage in &self.structure.usages[p] {
                self.explicit(*usage, t, y, acc, col, r, dacc);
            }
        }
    }

    /// Adds `∂a/∂x` for one usage of a parameter into column `col` of `dacc`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn explicit(
        &self,
        usage: Usage,
        t: f64,
        y: &[f64],
        acc: &[f64],
        col: usize,
        r: usize,
        dacc: &mut [f64],
    ) {
        let n = self.n;
        let comps = &self.structure.components;
        // A component's force f contributes −M⁻¹ B_iᵀ f.
        let (i, force) = match usage {
            Usage::Stiffness(i) => (i, comps[i].row.dot(&y[..n])),
            Usage::Damping(i) => (i, comps[i].row.dot(&y[n..])),
            Usage::PowerCoefficient(i) => {
                let (_, m) = self.comp_power[i];
                (i, power_law(1.0, m, comps[i].row.dot(&y[..n])).0)
            }
            Usage::PowerExponent(i) => {
                let (a, m) = self.comp_power[i];
                let d = comps[i].row.dot(&y[..n]);
                let f = if d == 0.0 {
                    0.0
                } else {
                    a * power_law(1.0, m, d).0 * d.abs().ln()
                };
                (i, f)
            }
            Usage::Mass(b) => {
                let m = self.model.bodies[b].mass.eval(&self.params);
                for i in 0..3 {
                    let k = 6 * b + i;
                    dacc[k * r + col] += (self.minv_gravity[k] - acc[k]) / m;
                }
                return;
            }
            Usage::Inertia(b, axis) => {
                let k = 6 * b + 3 + axis;
                dacc[k * r + col] -= acc[k] * self.minv[k];
                return;
            }
            Usage::Amplitude(e, j) => {
                let s = self.model.excitations[e].signal.terms[j].shape.at(t);
                if s != 0.0 {
                    for (k, l) in self.minv_loads[e].iter().enumerate() {
                        dacc[k * r + col] += s * l;
                    }
                }
                return;
            }
        };
        if force != 0.0 {
            for &(k, g) in &self.comp_minv[i] {
                dacc[k * r + col] -= g * force;
            }
        }
    }

    /// The tangent stiffness `K_t = K + Σ f'(δ_i) B_iᵀ B_i` at `q` (dense n×n,
    /// row-major), used for static equilibrium and modal analysis.
    pub fn tangent_stiffness(&self, q: &[f64]) -> Vec<f64> {
        let n = self.n;
        let mut kt = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                kt[i * n + j] = -self.a_lin[i * 2 * n + j] / self.minv[i];
            }
        }
        for pr in &self.power {
            let (_, slope) = power_law(pr.a, pr.m, pr.row.dot(q));
            if slope == 0.0 {
                continue;
            }
            let dense = pr.row.dense(n);
            for i in 0..n {
                for j in 0..n {
                    kt[i * n + j] += slope * dense[i] * dense[j];
                }
            }
        }
        kt
    }

    /// For each component row, `Some((a, m))` for a power-law spring.
    pub fn power_components(&self) -> Vec<Option<(f64, f64)>> {
        self.structure
            .components
            .iter()
            .map(|c| match c.law {
                Law::Power { a, m } => Some((a.eval(&self.params), m.eval(&self.params))),
                _ => None,
            })
            .collect()
    }

    /// The damping matrix C (dense n×n, row-major).
    pub fn damping_matrix(&self) -> Vec<f64> {
        let n = self.n;
        let mut c = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                c[i * n + j] = -self.a_lin[i * 2 * n + n + j] / self.minv[i];
            }
        }
        c
    }
}

/// `out[c0..c0+W] = Σ_j arow[j] · sy[j, c0..c0+W]` for row-major `sy` with r columns.
#[inline(always)]
fn row_times<M: Madd, const W: usize>(
    arow: &[f64],
    sy: &[f64],
    r: usize,
    c0: usize,
    out: &mut [f64],
) {
    let (mut s, mut t) = ([0.0; W], [0.0; W]);
    let mut pairs = arow.chunks_exact(2);
    let mut j = 0;
    for a in &mut pairs {
        let x0 = &sy[j * r + c0..j * r + c0 + W];
        let x1 = &sy[(j + 1) * r + c0..(j + 1) * r + c0 + W];
        for k in 0..W {
            s[k] = M::madd(a[0], x0[k], s[k]);
            t[k] = M::madd(a[1], x1[k], t[k]);
        }
        j += 2;
    }
    if let [a] = pairs.remainder() {
        let x0 = &sy[j * r + c0..j * r + c0 + W];
        for k in 0..W {
            s[k] = M::madd(*a, x0[k], s[k]);
        }
    }
    for k in 0..W {
        out[c0 + k] = s[k] + t[k];
    }
}

#[inline(always)]
fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    y.iter_mut().zip(x).for_each(|(yi, xi)| *yi += alpha * xi);
}
