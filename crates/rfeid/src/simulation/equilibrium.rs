//! Static equilibrium under gravity and its parameter sensitivities.
//!
//! Solves `R(q) = K q + Σ_i B_iᵀ law_i(B_i q) − W = 0` (eq. 1 with q̈ = q̇ = 0,
//! W the body weights) by damped Newton iterations on the tangent stiffness
//! `K_t = ∂R/∂q`. A power-law spring has zero slope at δ = 0, so `K_t(0)` may
//! be singular; the iteration then starts with Levenberg damping. The
//! sensitivities follow from `K_t ∂q/∂x = −∂R/∂x`.
//!
//! A free direction (one no spring restrains, [`super::free`]) makes `K_t`
//! singular for every q. If the weights pull along it there is no
//! equilibrium, and the error names it
//! ([`SimulationError::FreeUnderGravity`]); otherwise the equilibrium is
//! unique up to the free motions, and is solved on their complement: with
//! N the mass-orthonormal basis of the free motions, each solve is with
//! `K_t + s M N Nᵀ M` (s a stiffness of the order of K_t's, in ω²), whose
//! solution of `K_t Δ = −R` for R with `Nᵀ R = 0` is the one with
//! `Nᵀ M Δ = 0`. The weights' part along the free motions (zero to 1e-9 of
//! them, else the error above) is dropped, and so is that of `∂R/∂x`: the
//! equilibrium found, and its sensitivities, are M-orthogonal to the free
//! motions.
use super::envelope::{EnvelopeCholesky, Ordering};
use super::free::{free_directions, FreeSet};
use super::laws::power_law;
use super::structure::Usage;
use super::system::System;
use super::SimulationError;
use nalgebra::{DMatrix, DVector};

/// Models up to this many coordinates (four bodies) solve with a dense LU;
/// larger ones with the envelope Cholesky factorisation (`envelope`), whose
/// cost grows with the coupling of the bodies rather than as n³.
const DENSE_UP_TO: usize = 24;

/// A factorisation of the tangent stiffness.
enum Factor<'o> {
    /// Dense LU with partial pivoting.
    Dense(nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>),
    /// Envelope Cholesky (symmetric positive definite).
    Envelope(EnvelopeCholesky<'o>),
}

impl<'o> Factor<'o> {
    /// Factorises the row-major `n × n` matrix `a`: in its envelope if an
    /// ordering is given and `a` is positive definite, else by dense LU
    /// (whose singularity shows in [`Factor::solve`]).
    fn new(n: usize, a: &[f64], ordering: Option<&'o Ordering>) -> Factor<'o> {
        match ordering.and_then(|o| EnvelopeCholesky::factor(o, a)) {
            Some(c) => Factor::Envelope(c),
            None => Factor::Dense(DMatrix::from_row_slice(n, n, a).lu()),
        }
    }

    /// Solves `A x = b` in place; false if A is singular.
    fn solve(&self, b: &mut [f64]) -> bool {
        match self {
            Factor::Envelope(c) => {
                c.solve(b);
                b.iter().all(|v| v.is_finite())
            }
            Factor::Dense(lu) => {
                let mut x = DVector::from_column_slice(b);
                if !lu.solve_mut(&mut x) {
                    return false;
                }
                b.copy_from_slice(x.as_slice());
                b.iter().all(|v| v.is_finite())
            }
        }
    }
}

/// A static equilibrium and its sensitivities.
#[derive(Debug, Clone)]
pub struct Equilibrium {
    /// Generalized coordinates at equilibrium.
    pub q: Vec<f64>,
    /// `∂q/∂x_j`, n × r row-major.
    pub dq: Vec<f64>,
    /// Newton iterations taken.
    pub iterations: usize,
}

/// The static residual `R(q)` (generalized elastic forces minus weights),
/// and for each row the sum of the magnitudes of its terms, the scale of its
/// rounding: a long chain of stiff elements carries many bodies' weight
/// through forces far above any one weight, and their sum cannot vanish to
/// better than a few ulps of them.
fn residual(sys: &System<'_>, q: &[f64], weights: &[f64]) -> (DVector<f64>, DVector<f64>) {
    let n = sys.n;
    let mut r = DVector::zeros(n);
    let mut size = DVector::zeros(n);
    for i in 0..n {
        let row = &sys.a_lin[i * 2 * n..i * 2 * n + n];
        let (mut kq, mut abs) = (0.0, 0.0);
        for (a, q) in row.iter().zip(q) {
            kq += a * q;
            abs += (a * q).abs();
        }
        let weight = weights[i];
        r[i] = -kq / sys.minv[i] - weight;
        size[i] = abs / sys.minv[i] + weight.abs();
    }
    let powers = sys
        .power
        .iter()
        .map(|pr| (&pr.row, power_law(pr.a, pr.m, pr.row.dot(q)).0));
    let contacts = sys.contacts_at(q).map(|(row, at)| (row, at.force));
    for (row, f) in powers.chain(contacts) {
        row.axpy(f, r.as_mut_slice());
        for (off, c) in &row.blocks {
            for (s, c) in size.as_mut_slice()[*off..*off + 6].iter_mut().zip(c) {
                *s += (c * f).abs();
            }
        }
    }
    (r, size)
}

/// Whether the residual is zero to the tolerance `tol` or to the rounding of
/// its terms (`size`, [`residual`]), whichever is larger.
fn balanced(res: &DVector<f64>, size: &DVector<f64>, tol: f64) -> bool {
    res.iter()
        .zip(size.iter())
        .all(|(r, s)| r.abs() <= tol.max(64.0 * f64::EPSILON * s))
}

// long-fn: numerical kernel (Newton's iteration for the static equilibrium)
/// Solves for the static equilibrium under gravity; `wrt` selects the
/// parameters whose sensitivities `∂q/∂x` are wanted. Newton's method stops
/// when every row of the residual is within 1e-13 of the largest weight, or
/// within 64 ulps of the sum of its terms' magnitudes where that is larger
/// (stiff chains carrying many bodies; see `residual`).
///
/// Fails with [`SimulationError::FreeUnderGravity`] if the weights pull
/// along a free direction (see the module documentation).
pub fn static_equilibrium(sys: &System<'_>, wrt: &[usize]) -> Result<Equilibrium, SimulationError> {
    let n = sys.n;
    let free = free_directions(sys);
    free.check_gravity(sys)?;
    let mut weights: Vec<f64> = (0..n).map(|i| sys.minv_gravity[i] / sys.minv[i]).collect();
    let weight_norm = weights.iter().fold(0.0, |m: f64, w| m.max(w.abs()));
    free.remove_force(&mut weights);
    let ordering = (n > DENSE_UP_TO).then(|| {
        let mut rows: Vec<Vec<usize>> = sys.power.iter().map(|p| p.row.coordinates()).collect();
        let contacts = sys
            .contacts
            .iter()
            .map(|c| &sys.structure.components[c.comp].row);
        rows.extend(contacts.map(|row| row.coordinates()));
        rows.extend(free.supports());
        Ordering::new(n, &sys.tangent_stiffness(&vec![0.0; n]), &rows)
    });
    let mut q = vec![0.0; n];
    let (mut res, mut size) = residual(sys, &q, &weights);
    let tol = 1e-13 * weight_norm.max(f64::MIN_POSITIVE);
    let mut mu = 0.0;
    let mut iterations = 0;
    while !balanced(&res, &size, tol) {
        iterations += 1;
        if iterations > 200 {
            return Err(SimulationError::NoEquilibrium {
                reason: format!(
                    "Newton did not converge in 200 iterations (residual {:.3e} N)",
                    res.amax()
                ),
            });
        }
        let mut kt = regular_tangent(sys, &free, &q);
        let scale = (0..n).map(|i| kt[i * n + i].abs()).fold(0.0_f64, f64::max);
        let scale = scale.max(f64::MIN_POSITIVE);
        let diagonal: Vec<f64> = (0..n).map(|i| kt[i * n + i]).collect();
        let mut accepted = false;
        for _ in 0..60 {
            for i in 0..n {
                kt[i * n + i] = diagonal[i] + mu * scale;
            }
            let mut step: Vec<f64> = res.iter().map(|v| -v).collect();
            if Factor::new(n, &kt, ordering.as_ref()).solve(&mut step) {
                let mut trial: Vec<f64> = q.iter().zip(&step).map(|(q, s)| q + s).collect();
                free.remove_motion(&mut trial);
                let (tres, tsize) = residual(sys, &trial, &weights);
                if tres.norm() < res.norm() && tres.iter().all(|v| v.is_finite()) {
                    q = trial;
                    (res, size) = (tres, tsize);
                    mu = if mu < 1e-12 { 0.0 } else { mu * 0.1 };
                    accepted = true;
                    break;
                }
            }
            mu = if mu == 0.0 { 1e-10 } else { mu * 10.0 };
        }
        if !accepted {
            return Err(SimulationError::NoEquilibrium {
                reason: format!(
                    "the model cannot carry its weight (residual {:.3e} N); is a body unsupported?",
                    res.amax()
                ),
            });
        }
    }

    let dq = sensitivities(sys, &free, ordering.as_ref(), &q, wrt)?;
    Ok(Equilibrium { q, dq, iterations })
}

/// A contact at the static equilibrium (`rfeid check`): its component row,
/// its closure `δ − gap` there and its force (0 when open).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactAtRest {
    /// The component's index in [`super::structure::Structure::components`].
    pub component: usize,
    /// `δ − gap` at the equilibrium: positive closed, else open.
    pub closure: f64,
    /// Its force there.
    pub force: f64,
}

/// Each contact of `sys` at its static equilibrium (at q = 0 for a model
/// that starts there, [`crate::model::Model::starts_at_equilibrium`]).
pub fn contacts_at_rest(sys: &System<'_>) -> Result<Vec<ContactAtRest>, SimulationError> {
    if sys.contacts.is_empty() {
        return Ok(Vec::new());
    }
    let q = static_equilibrium(sys, &[])?.q;
    Ok(sys
        .contacts
        .iter()
        .zip(sys.contacts_at(&q))
        .map(|(c, (row, at))| ContactAtRest {
            component: c.comp,
            closure: c.law.closure_at(row.dot(&q)),
            force: at.force,
        })
        .collect())
}

/// `∂q/∂x_j` for the parameters `wrt` at the equilibrium `q`, n × r
/// row-major: `K_t ∂q/∂x = −∂R/∂x`, solved on the complement of the free
/// motions (their part of `∂R/∂x` dropped).
fn sensitivities(
    sys: &System<'_>,
    free: &FreeSet,
    ordering: Option<&Ordering>,
    q: &[f64],
    wrt: &[usize],
) -> Result<Vec<f64>, SimulationError> {
    let (n, r) = (sys.n, wrt.len());
    let mut dq = vec![0.0; n * r];
    if r == 0 {
        return Ok(dq);
    }
    let factor = Factor::new(n, &regular_tangent(sys, free, q), ordering);
    let mut rhs = DMatrix::zeros(n, r);
    for (col, &p) in wrt.iter().enumerate() {
        for usage in &sys.structure.usages[p] {
            explicit(sys, *usage, q, &mut rhs, col);
        }
    }
    let mut x = vec![0.0; n];
    for j in 0..r {
        for (i, xi) in x.iter_mut().enumerate() {
            *xi = -rhs[(i, j)];
        }
        free.remove_force(&mut x);
        if !factor.solve(&mut x) {
            return Err(SimulationError::NoEquilibrium {
                reason: "the tangent stiffness at equilibrium is singular".into(),
            });
        }
        for (i, xi) in x.iter().enumerate() {
            dq[i * r + j] = *xi;
        }
    }
    Ok(dq)
}

/// The tangent stiffness `K_t(q)`, made regular along the free directions
/// by adding `s M N Nᵀ M` (see the module documentation), with `s` the
/// largest `K_t,ii / M_ii`: a stiffness like the stiffest of the model's.
fn regular_tangent(sys: &System<'_>, free: &FreeSet, q: &[f64]) -> Vec<f64> {
    let n = sys.n;
    let mut kt = sys.tangent_stiffness(q);
    if !free.is_empty() {
        let s = (0..n)
            .map(|i| (kt[i * n + i] * sys.minv[i]).abs())
            .fold(0.0_f64, f64::max);
        free.add_penalty(&mut kt, if s > 0.0 { s } else { 1.0 });
    }
    kt
}

/// `∂R/∂x` of one usage into column `col`.
fn explicit(sys: &System<'_>, usage: Usage, q: &[f64], rhs: &mut DMatrix<f64>, col: usize) {
    let comps = &sys.structure.components;
    let mut add = |row: &crate::simulation::structure::Row, f: f64| {
        for (off, c) in &row.blocks {
            for i in 0..6 {
                rhs[(off + i, col)] += c[i] * f;
            }
        }
    };
    match usage {
        Usage::Stiffness(i) => add(&comps[i].row, comps[i].row.dot(q)),
        Usage::PowerCoefficient(i) | Usage::PowerExponent(i) => {
            let Some(p) = comps[i].law.power_spring(&sys.params) else {
                return;
            };
            let d = comps[i].row.dot(q);
            let (f, _) = power_law(1.0, p.m, d);
            let force = match usage {
                Usage::PowerCoefficient(_) => p.per_a * f,
                _ if d == 0.0 => 0.0,
                _ => p.coef * f * (d.abs().ln() - p.ln_ref),
            };
            add(&comps[i].row, force);
        }
        Usage::Contact(i, key) => {
            let Some(j) = sys.comps[i].contact else {
                return;
            };
            let row = &sys.contacts[j as usize];
            let at = row.law.at(comps[i].row.dot(q), 0.0);
            add(&comps[i].row, row.law.derivative(&at, key));
        }
        Usage::Mass(b) => {
            for i in 0..3 {
                rhs[(6 * b + i, col)] -= sys.structure.gravity_local[b][i];
            }
        }
        // A friction force is zero at rest.
        // z = 0 at rest: a Bouc–Wen key does not act there either.
        Usage::Damping(_)
        | Usage::Friction(..)
        | Usage::Hysteresis(..)
        | Usage::Inertia(..)
        | Usage::Amplitude(..) => {}
    }
}
