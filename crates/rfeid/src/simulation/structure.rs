//! Assembly of the parameter-independent maps (SPEC §1, eq. 4–5): the
//! deformation matrix B (δ = B q), the excitation maps and the sensor maps.
//!
//! Every row couples at most two bodies, so rows are stored as at most two
//! 6-blocks. Body b owns coordinates `6b .. 6b + 6`.
pub use super::laws::{bouc_wen::HysteresisKey, friction::FrictionKey};
use super::laws::{ContactKey, KeyRole};
use crate::model::geometry::{attachment, block_diag, point_direction_row};
use crate::model::{Attachment, Law, Model, SensorKind, Value};
use nalgebra::{Matrix3, Vector3};

/// A sparse row over the generalized coordinates by its nonzero 6-blocks:
/// one or two for a component, a load or a sensor.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// `(first coordinate, coefficients)` for each block.
    pub blocks: Vec<(usize, [f64; 6])>,
}

impl Row {
    /// The nonzero 6-blocks of a dense vector (body b's block starts at 6b).
    pub fn from_dense(v: &[f64]) -> Row {
        let blocks = v
            .chunks(6)
            .enumerate()
            .filter(|(_, c)| c.iter().any(|x| *x != 0.0))
            .map(|(b, c)| {
                let mut a = [0.0; 6];
                a[..c.len()].copy_from_slice(c);
                (6 * b, a)
            })
            .collect();
        Row { blocks }
    }

    /// `row · q`.
    #[inline(always)]
    pub fn dot(&self, q: &[f64]) -> f64 {
        // Two partial sums per block break the addition chain.
        let mut s = [0.0; 2];
        for (off, c) in &self.blocks {
            let x = &q[*off..*off + 6];
            s[0] += c[0] * x[0] + c[2] * x[2] + c[4] * x[4];
            s[1] += c[1] * x[1] + c[3] * x[3] + c[5] * x[5];
        }
        s[0] + s[1]
    }

    /// `out += alpha · rowᵀ`.
    #[inline]
    pub fn axpy(&self, alpha: f64, out: &mut [f64]) {
        for (off, c) in &self.blocks {
            for i in 0..6 {
                out[off + i] += alpha * c[i];
            }
        }
    }

    /// The coordinates the row touches.
    pub fn coordinates(&self) -> Vec<usize> {
        self.blocks
            .iter()
            .flat_map(|(off, _)| *off..*off + 6)
            .collect()
    }

    /// The row as a dense vector of length n.
    pub fn dense(&self, n: usize) -> Vec<f64> {
        let mut v = vec![0.0; n];
        self.axpy(1.0, &mut v);
        v
    }
}

/// One component of one element: its row of B and its coefficients.
#[derive(Debug, Clone)]
pub struct ComponentRow {
    /// Index of the element in [`Model::elements`].
    pub element: usize,
    /// Component 0–5 (`ux` … `rz`).
    pub dof: usize,
    /// δ_i = row · q (eq. 5).
    pub row: Row,
    /// The spring law.
    pub law: Law,
    /// The damping c_i.
    pub damping: Value,
}

/// One place where a parameter enters the equations of motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Usage {
    /// Stiffness k of linear component row i.
    Stiffness(usize),
    /// Damping c of component row i.
    Damping(usize),
    /// Coefficient a of power-law component row i.
    PowerCoefficient(usize),
    /// Exponent m of power-law component row i.
    PowerExponent(usize),
    /// A key of friction component row i (its `k` is a [`Usage::Stiffness`]).
    Friction(usize, FrictionKey),
    /// A key of Bouc–Wen component row i (its `k` is a [`Usage::Stiffness`]).
    Hysteresis(usize, HysteresisKey),
    /// A key of contact component row i.
    Contact(usize, ContactKey),
    /// Mass of body b.
    Mass(usize),
    /// Principal moment of inertia `axis` of body b.
    Inertia(usize, usize),
    /// Amplitude of term j of excitation e.
    Amplitude(usize, usize),
}

impl Usage {
    /// The usage of a parameter standing for a law's key of `role` in
    /// component row `i`.
    pub fn of(role: KeyRole, i: usize) -> Usage {
        match role {
            KeyRole::Stiffness => Usage::Stiffness(i),
            KeyRole::PowerCoefficient => Usage::PowerCoefficient(i),
            KeyRole::PowerExponent => Usage::PowerExponent(i),
            KeyRole::Friction(key) => Usage::Friction(i, key),
            KeyRole::Hysteresis(key) => Usage::Hysteresis(i, key),
            KeyRole::Contact(key) => Usage::Contact(i, key),
        }
    }
}

/// The parameter-independent structure of a model.
#[derive(Debug, Clone)]
pub struct Structure {
    /// Number of generalized coordinates n.
    pub n: usize,
    /// All components, in element order: the rows of B.
    pub components: Vec<ComponentRow>,
    /// Generalized force of a unit excitation, per excitation (dense, length n).
    pub loads: Vec<Vec<f64>>,
    /// Sensor maps: `y = h · q` (or q̇, q̈), per sensor, by the blocks of
    /// the body it sits on.
    pub sensors: Vec<(SensorKind, Row)>,
    /// Gravity in each body's frame, per body (zero without gravity).
    pub gravity_local: Vec<Vector3<f64>>,
    /// For each parameter, where it is used.
    pub usages: Vec<Vec<Usage>>,
}

impl Structure {
    /// Assembles B, the excitation maps and the sensor maps of a validated model.
    pub fn new(model: &Model) -> Structure {
        let n = model.n_dof();
        let components = component_rows(model);
        let loads = excitation_loads(model, n);
        let sensors = sensor_rows(model, n);
        let gravity_local = gravity_local(model);
        let usages = usages(model, &components);
        Structure {
            n,
            components,
            loads,
            sensors,
            gravity_local,
            usages,
        }
    }
}

/// The point x in body b's frame, from its centre of mass.
fn body_rho(model: &Model, b: usize, x: &Vector3<f64>) -> Vector3<f64> {
    let body = &model.bodies[b];
    body.axes.transpose() * (x - body.com)
}

/// The rows of B: one per component of each element, in element order.
fn component_rows(model: &Model) -> Vec<ComponentRow> {
    let mut components = Vec::new();
    for (ei, el) in model.elements.iter().enumerate() {
        // Θ_b S(ρ_b) for each end (eq. 4–5).
        let end = |b: usize| {
            let body = &model.bodies[b];
            let theta: Matrix3<f64> = el.axes.transpose() * body.axes;
            block_diag(&theta) * attachment(&body_rho(model, b, &el.at))
        };
        let ends: Vec<(usize, f64, nalgebra::Matrix6<f64>)> = std::iter::once((el.body, 1.0))
            .chain(match el.to {
                Attachment::Body(p) => Some((p, -1.0)),
                Attachment::Ground => None,
            })
            .map(|(b, sign)| (b, sign, end(b)))
            .collect();
        for comp in &el.components {
            let blocks = ends
                .iter()
                .map(|(b, sign, m)| {
                    let mut c = [0.0; 6];
                    for (j, cj) in c.iter_mut().enumerate() {
                        *cj = sign * m[(comp.dof, j)];
                    }
                    (6 * b, c)
                })
                .collect();
            components.push(ComponentRow {
                element: ei,
                dof: comp.dof,
                row: Row { blocks },
                law: comp.law,
                damping: comp.damping,
            });
        }
    }
    components
}

/// Adds `sign` times the generalized row of a point x of body b along d
/// (how a force there enters, or how a sensor there reads) to `out`.
fn point_row(
    model: &Model,
    b: usize,
    x: &Vector3<f64>,
    d: &Vector3<f64>,
    sign: f64,
    out: &mut [f64],
) {
    let body = &model.bodies[b];
    let h = point_direction_row(&body.axes, &body_rho(model, b, x), d);
    for i in 0..6 {
        out[6 * b + i] += sign * h[i];
    }
}

/// The generalized force of a unit excitation, per excitation (dense).
fn excitation_loads(model: &Model, n: usize) -> Vec<Vec<f64>> {
    model
        .excitations
        .iter()
        .map(|e| {
            let mut l = vec![0.0; n];
            point_row(model, e.body, &e.at, &e.direction, 1.0, &mut l);
            if let Some(r) = e.reaction {
                point_row(model, r, &e.at, &e.direction, -1.0, &mut l);
            }
            l
        })
        .collect()
}

/// The sensor maps, per sensor.
fn sensor_rows(model: &Model, n: usize) -> Vec<(SensorKind, Row)> {
    model
        .sensors
        .iter()
        .map(|s| {
            let mut h = vec![0.0; n];
            point_row(model, s.body, &s.at, &s.direction, 1.0, &mut h);
            (s.kind, Row::from_dense(&h))
        })
        .collect()
}

/// Gravity in each body's frame (zero without gravity).
fn gravity_local(model: &Model) -> Vec<Vector3<f64>> {
    let g = model.gravity.unwrap_or_else(Vector3::zeros);
    model
        .bodies
        .iter()
        .map(|b| b.axes.transpose() * g)
        .collect()
}

/// For each parameter, where it is used: in the component rows, the bodies
/// and the excitations.
fn usages(model: &Model, components: &[ComponentRow]) -> Vec<Vec<Usage>> {
    let mut usages = vec![Vec::new(); model.parameters.len()];
    let mut add = |v: &Value, u: Usage| {
        if let Value::Param(p) = v {
            usages[*p].push(u);
        }
    };
    for (i, c) in components.iter().enumerate() {
        for key in c.law.joint().keys() {
            if let Some(role) = key.role {
                add(&key.value, Usage::of(role, i));
            }
        }
        add(&c.damping, Usage::Damping(i));
    }
    for (b, body) in model.bodies.iter().enumerate() {
        add(&body.mass, Usage::Mass(b));
        for (axis, j) in body.inertia.iter().enumerate() {
            add(j, Usage::Inertia(b, axis));
        }
    }
    for (e, exc) in model.excitations.iter().enumerate() {
        for (j, term) in exc.signal.terms.iter().enumerate() {
            add(&term.amplitude, Usage::Amplitude(e, j));
        }
    }
    usages
}
