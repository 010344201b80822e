//! The model linearised at rest, or at its static equilibrium under
//! gravity (eq. 1 with small motions about `q₀`):
//!
//! `M q̈ + C_t q̇ + K_t q = Σ_e L_e P_e(t)`,
//!
//! the same linearisation as [`crate::simulation::modal`], with every law's
//! small-motion part: a power-law spring (eq. 2–6) its slope
//! `m a |δ₀|^(m−1)` at the static deformation δ₀, a friction law (SPEC §1)
//! its slope `F(0)/v_s` in the velocity (a viscous damper: the smoothed sign
//! sticks for |v| ≪ v_s), a Bouc–Wen law `k + α` (z = α δ for small
//! motions from z = 0).
//!
//! The parameter derivatives of M, C_t and K_t are exact: each parameter
//! enters through its [`Usage`]s, and under gravity the static deformations
//! move with the parameters (`∂q₀/∂x` from [`static_equilibrium`]), which a
//! power law's slope feels through its curvature.
use crate::model::{Law, Model};
use crate::simulation::equilibrium::static_equilibrium;
use crate::simulation::laws::contact::ContactForce;
use crate::simulation::structure::{HysteresisKey, Row, Usage};
use crate::simulation::system::{add_outer, System};
use crate::simulation::{SimulationError, Simulator};

/// A parameter's effect on the linearised system: a sum of terms.
#[derive(Debug, Clone, PartialEq)]
pub enum Term {
    /// `∂K_t += k · row rowᵀ`, `∂C_t += c · row rowᵀ` for one component.
    Outer {
        /// The component's row of B.
        row: Row,
        /// Its stiffness' derivative.
        k: f64,
        /// Its damping's derivative.
        c: f64,
    },
    /// `∂M_ii += 1`: a mass or moment of inertia.
    Mass(usize),
}

/// The model linearised at a point, with the derivatives of its matrices
/// in the chosen parameters.
#[derive(Debug, Clone)]
pub struct Linearised {
    /// Number of generalized coordinates n.
    pub n: usize,
    /// The diagonal of M.
    pub mass: Vec<f64>,
    /// The tangent stiffness K_t, n × n row-major.
    pub stiffness: Vec<f64>,
    /// The tangent damping C_t, n × n row-major.
    pub damping: Vec<f64>,
    /// The generalized force of a unit excitation, per excitation.
    pub loads: Vec<Vec<f64>>,
    /// Whether the point is the static equilibrium under gravity (else rest).
    pub at_equilibrium: bool,
    /// For each parameter asked for, its terms.
    pub derivatives: Vec<Vec<Term>>,
    /// The power-law components with zero slope at the point (which add
    /// no stiffness there), as `element/component`.
    pub zero_slope: Vec<String>,
}

/// Linearises `model` at the parameter values `params` (all of them), at
/// rest or at its static equilibrium under gravity, with the derivatives
/// of the matrices in the parameters `wrt` (indices into
/// [`Model::parameters`]).
pub fn linearise(
    model: &Model,
    params: &[f64],
    wrt: &[usize],
) -> Result<Linearised, SimulationError> {
    let sim = Simulator::with_integrator(model, crate::simulation::steps::integrator(1));
    let sys = sim.system(params)?;
    let n = sys.n;
    let (q0, dq0) = match model.starts_at_equilibrium() {
        true => {
            let eq = static_equilibrium(&sys, wrt)?;
            (eq.q, eq.dq)
        }
        false => (vec![0.0; n], vec![0.0; n * wrt.len()]),
    };
    // The closed contacts at q0 are in both.
    let mut stiffness = sys.tangent_stiffness(&q0);
    let mut damping = sys.damping_matrix(&q0);
    for comp in &sim.structure().components {
        let (k, c) = comp.law.joint().small_motion(params);
        add_outer(&mut stiffness, n, &comp.row, k);
        add_outer(&mut damping, n, &comp.row, c);
    }
    let derivatives = wrt
        .iter()
        .enumerate()
        .map(|(col, &p)| {
            let dq: Vec<f64> = (0..n).map(|i| dq0[i * wrt.len() + col]).collect();
            terms(&sys, p, &q0, &dq)
        })
        .collect();
    Ok(Linearised {
        n,
        mass: sys.minv.iter().map(|m| 1.0 / m).collect(),
        stiffness,
        damping,
        loads: sim.structure().loads.clone(),
        at_equilibrium: model.starts_at_equilibrium(),
        derivatives,
        zero_slope: zero_slope(&sys, &q0),
    })
}

/// The power-law components with zero slope at `q0`.
fn zero_slope(sys: &System<'_>, q0: &[f64]) -> Vec<String> {
    let comps = &sys.structure.components;
    comps
        .iter()
        .filter(|c| {
            c.law
                .power_spring(&sys.params)
                .is_some_and(|s| power_slope(s.coef, s.m, c.row.dot(q0)) == 0.0)
        })
        .map(|c| {
            let el = &sys.model.elements[c.element].name;
            format!("{el}/{}", crate::model::COMPONENT_NAMES[c.dof])
        })
        .collect()
}

/// The terms of parameter `p` at the linearisation point `q0`, whose
/// derivative in p is `dq0`.
fn terms(sys: &System<'_>, p: usize, q0: &[f64], dq0: &[f64]) -> Vec<Term> {
    let comps = &sys.structure.components;
    let params = &sys.params;
    let mut out: Vec<Term> = Vec::new();
    let outer = |i: usize, k: f64, c: f64| Term::Outer {
        row: comps[i].row.clone(),
        k,
        c,
    };
    for usage in &sys.structure.usages[p] {
        match *usage {
            Usage::Stiffness(i) => out.push(outer(i, 1.0, 0.0)),
            Usage::Damping(i) => out.push(outer(i, 0.0, 1.0)),
            Usage::PowerCoefficient(i) | Usage::PowerExponent(i) => {
                let Some(s) = comps[i].law.power_spring(params) else {
                    continue;
                };
                let d = comps[i].row.dot(q0);
                let slope = power_slope(s.coef, s.m, d);
                let k = match usage {
                    Usage::PowerCoefficient(_) => s.per_a * power_slope(1.0, s.m, d),
                    _ if slope == 0.0 => 0.0,
                    // ∂/∂m of coef · m |δ|^(m−1), coef = a δ_ref^(−m).
                    _ => slope * (1.0 / s.m + d.abs().ln() - s.ln_ref),
                };
                out.push(outer(i, k, 0.0));
            }
            Usage::Friction(i, key) => {
                let Law::Friction(fr) = &comps[i].law else {
                    continue;
                };
                out.push(outer(i, 0.0, fr.rest_slope_derivative(params, key)));
            }
            Usage::Contact(i, key) => {
                let Law::Contact(ct) = &comps[i].law else {
                    continue;
                };
                let law = ContactForce::new(ct, params);
                let at = law.at(comps[i].row.dot(q0), 0.0);
                let (k, c) = law.small_motion_derivative(&at, key);
                out.push(outer(i, k, c));
            }
            Usage::Hysteresis(i, HysteresisKey::Alpha) => out.push(outer(i, 1.0, 0.0)),
            Usage::Mass(b) => out.extend((0..3).map(|a| Term::Mass(6 * b + a))),
            Usage::Inertia(b, axis) => out.push(Term::Mass(6 * b + 3 + axis)),
            Usage::Hysteresis(..) | Usage::Amplitude(..) => {}
        }
    }
    if dq0.iter().any(|v| *v != 0.0) {
        // The static deformations move with p: each power law's slope with them.
        for (i, comp) in comps.iter().enumerate() {
            let curvature = match &comp.law {
                Law::Contact(ct) => {
                    let law = ContactForce::new(ct, params);
                    law.curvature(&law.at(comp.row.dot(q0), 0.0))
                }
                law => match law.power_spring(params) {
                    Some(s) => power_curvature(s.coef, s.m, comp.row.dot(q0)),
                    None => continue,
                },
            };
            let k = curvature * comp.row.dot(dq0);
            if k != 0.0 {
                out.push(outer(i, k, 0.0));
            }
        }
    }
    out
}

/// The slope of `a sign(δ)|δ|^m`: `m a |δ|^(m−1)` (zero at δ = 0 for m > 1).
fn power_slope(a: f64, m: f64, d: f64) -> f64 {
    crate::simulation::system::power_law(a, m, d).1
}

/// The slope's derivative in δ: `m (m−1) a |δ|^(m−2) sign(δ)` (taken as
/// zero at δ = 0, where for m < 2 it is unbounded).
fn power_curvature(a: f64, m: f64, d: f64) -> f64 {
    if d == 0.0 || m == 1.0 {
        return 0.0;
    }
    m * (m - 1.0) * a * d.abs().powf(m - 2.0) * d.signum()
}
