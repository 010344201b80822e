//! Free directions: motions that no spring restrains (SPEC §1: "a direction
//! with no component is free").
//!
//! A motion v of the generalized coordinates is free when every spring row
//! of B has `b_i · v = 0`: a component with a linear, power-law or friction
//! spring of nonzero coefficient. Dampers and friction forces do not count,
//! since they vanish at rest and so restore nothing. The free directions are
//! the null space of
//!
//! ```text
//! G = Σ_i b̃_i b̃_iᵀ,   b̃_i = L⁻¹ b_i / |L⁻¹ b_i|,   M = L Lᵀ,
//! ```
//!
//! in the mass-scaled coordinates `x = Lᵀ q`, where rows of any stiffness
//! and units weigh alike (a 0.1 Hz mount beside a 10 kHz joint is not
//! mistaken for a free direction). The null space comes from the envelope
//! factorisation's zero pivots (`envelope::null_space`), and is
//! then expressed in words (`basis`, `motion`): translations of one body along the global axes,
//! rotations about global axes through its centre of mass or through the
//! points of the elements that touch it, then the same for each group of
//! bodies that springs join; whatever remains is described body by body.
//!
//! Free directions are not an error: a prismatic axis is driven along one.
//! But a static equilibrium exists only if the weights do no work along
//! them (`Nᵀ W = 0`); it is then unique up to the free motions, and solved
//! on their complement (see [`super::equilibrium`]).
mod basis;
mod gram;
mod motion;
#[cfg(test)]
mod tests;
mod vectors;

use super::envelope::{null_space, Ordering};
use super::system::System;
use super::SimulationError;
use crate::model::Model;
use basis::describe_space;
use gram::spring_gram;
use nalgebra::Vector3;
use vectors::{orthonormalise, unit_residual};

pub use motion::{FreeDirection, Motion};

/// The relative pivot below which a direction of `G` counts as free.
const PIVOT_TOLERANCE: f64 = 1e-9;

/// The free directions of a model at some parameter values.
#[derive(Debug, Clone, Default)]
pub struct FreeSet {
    /// The directions, described (independent, not orthogonal).
    pub directions: Vec<FreeDirection>,
    /// An orthonormal basis of the same space in mass-scaled coordinates
    /// `x = Lᵀ q`.
    orthonormal: Vec<Vec<f64>>,
    /// `√m_i` per coordinate (the diagonal of L).
    sqrt_m: Vec<f64>,
}

/// The free directions of the system (see the module documentation).
pub fn free_directions(sys: &System<'_>) -> FreeSet {
    let n = sys.n;
    let sqrt_m: Vec<f64> = sys.minv.iter().map(|v| 1.0 / v.sqrt()).collect();
    let g = spring_gram(sys, &sqrt_m);
    let ordering = Ordering::new(n, &g, &[]);
    // G is a sum of outer products: semidefinite, so `None` (a pivot
    // negative beyond rounding) cannot happen; were it to, every
    // coordinate counts as restrained rather than any as free. The null
    // vectors are in the mass-scaled coordinates G acts on.
    let raw = null_space(&ordering, &g, PIVOT_TOLERANCE).unwrap_or_default();
    let orthonormal = orthonormalise(raw);
    if orthonormal.is_empty() {
        return FreeSet {
            sqrt_m,
            ..FreeSet::default()
        };
    }
    let directions = describe_space(sys, &orthonormal, &sqrt_m);
    FreeSet {
        directions,
        orthonormal,
        sqrt_m,
    }
}

/// The pull of gravity along a free direction: where it is not zero, no
/// static equilibrium exists.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GravityLoad {
    /// The direction, an index into [`FreeSet::directions`].
    pub direction: usize,
    /// The weights' generalized force along its unit shape: N along a
    /// translation, N·m about a rotation.
    pub load: f64,
}

impl FreeSet {
    /// Whether no direction is free.
    pub fn is_empty(&self) -> bool {
        self.directions.is_empty()
    }

    /// The number of free directions (the dimension of the free space).
    pub fn len(&self) -> usize {
        self.directions.len()
    }

    /// Each direction in words (see [`FreeDirection::describe`]).
    pub fn descriptions(&self, model: &Model) -> Vec<String> {
        self.directions.iter().map(|d| d.describe(model)).collect()
    }

    /// An orthonormal basis of the free space in the mass-scaled
    /// coordinates `x = Lᵀ q` (`x_i = √m_i q_i`).
    pub fn orthonormal(&self) -> &[Vec<f64>] {
        &self.orthonormal
    }

    /// An orthonormal basis (mass-scaled coordinates) of the part of the
    /// span of `vectors` (mass-scaled) orthogonal to the free space.
    pub fn complement(&self, vectors: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let mut basis = self.orthonormal.clone();
        for v in vectors {
            if let Some(u) = unit_residual(&basis, v) {
                basis.push(u);
            }
        }
        basis.split_off(self.orthonormal.len())
    }

    /// The coordinates each basis vector touches: the pattern that
    /// [`Self::add_penalty`] adds to a matrix.
    pub(crate) fn supports(&self) -> Vec<Vec<usize>> {
        self.orthonormal
            .iter()
            .map(|x| (0..x.len()).filter(|&i| x[i] != 0.0).collect())
            .collect()
    }

    /// Removes from the generalized force `f` its part along the free
    /// directions, `f − M N Nᵀ f` (N the mass-orthonormal basis): what is
    /// left does no work along any free motion.
    pub(crate) fn remove_force(&self, f: &mut [f64]) {
        for x in &self.orthonormal {
            let c: f64 = x
                .iter()
                .zip(f.iter())
                .zip(&self.sqrt_m)
                .map(|((x, f), s)| x * f / s)
                .sum();
            for ((f, x), s) in f.iter_mut().zip(x).zip(&self.sqrt_m) {
                *f -= c * x * s;
            }
        }
    }

    /// Removes from the coordinates `q` their free part, `q − N Nᵀ M q`:
    /// what is left is M-orthogonal to every free motion.
    pub(crate) fn remove_motion(&self, q: &mut [f64]) {
        for x in &self.orthonormal {
            let c: f64 = x
                .iter()
                .zip(q.iter())
                .zip(&self.sqrt_m)
                .map(|((x, q), s)| x * q * s)
                .sum();
            for ((q, x), s) in q.iter_mut().zip(x).zip(&self.sqrt_m) {
                *q -= c * x / s;
            }
        }
    }

    /// Adds `s · M N Nᵀ M` to the row-major `n × n` matrix `k`: a stiffness
    /// `s` (in ω², rad²/s²) along each free motion and none elsewhere, so
    /// that a tangent stiffness singular only along them becomes regular
    /// with the same solutions on their complement.
    pub(crate) fn add_penalty(&self, k: &mut [f64], s: f64) {
        let n = self.sqrt_m.len();
        for x in &self.orthonormal {
            let support: Vec<usize> = (0..n).filter(|&i| x[i] != 0.0).collect();
            for &i in &support {
                let xi = s * x[i] * self.sqrt_m[i];
                for &j in &support {
                    k[i * n + j] += xi * x[j] * self.sqrt_m[j];
                }
            }
        }
    }

    /// The free direction along which the weights pull hardest, if any
    /// does beyond 1e-9 of the weights moving with it (rounding of a
    /// gravity vector given exactly perpendicular is far below that).
    pub fn gravity_load(&self, sys: &System<'_>) -> Option<GravityLoad> {
        let gravity = &sys.structure.gravity_local;
        let mut worst: Option<GravityLoad> = None;
        for (d, dir) in self.directions.iter().enumerate() {
            let (mut load, mut scale) = (0.0, 0.0);
            for (b, g) in gravity.iter().enumerate() {
                let m = 1.0 / sys.minv[6 * b];
                let u = Vector3::new(dir.shape[6 * b], dir.shape[6 * b + 1], dir.shape[6 * b + 2]);
                load += m * u.dot(g);
                scale += m * u.norm() * g.norm();
            }
            let loaded = load.abs() > 1e-9 * scale;
            if loaded && worst.is_none_or(|w| load.abs() > w.load.abs()) {
                worst = Some(GravityLoad { direction: d, load });
            }
        }
        worst
    }
}

impl FreeSet {
    /// Whether no motion along a free direction can ever start: every
    /// element's row, damper and friction rows included, is orthogonal to
    /// each free motion v (`b · v = 0`), and so is every excitation's load
    /// (`l · v = 0`) and the weights. Then `vᵀ M q̈ = 0` at every state, a
    /// run from rest never moves along v, and neither does the error of its
    /// steps (an explicit Runge–Kutta step keeps linear invariants): such
    /// directions, say the five unrestrained and unloaded coordinates of a
    /// one-body model driven and restrained along x alone, are not where a
    /// step error can add up. Zero means below 1e-9 of `|b| |v|`.
    pub fn inert(&self, sys: &System<'_>) -> bool {
        let orthogonal = |row: &[f64], v: &[f64]| {
            let (dot, rr, vv) = (row.iter().zip(v)).fold((0.0, 0.0, 0.0), |(d, r, w), (a, b)| {
                (d + a * b, r + a * a, w + b * b)
            });
            dot.abs() <= 1e-9 * (rr * vv).sqrt()
        };
        let n = self.sqrt_m.len();
        let rows: Vec<Vec<f64>> = (sys.structure.components.iter())
            .map(|c| c.row.dense(n))
            .chain(sys.structure.loads.iter().cloned())
            .collect();
        let still = self.orthonormal.iter().all(|x| {
            let v: Vec<f64> = x.iter().zip(&self.sqrt_m).map(|(x, s)| x / s).collect();
            rows.iter().all(|row| orthogonal(row, &v))
        });
        still && self.gravity_load(sys).is_none()
    }

    /// [`SimulationError::FreeUnderGravity`] naming the free direction the
    /// weights pull along hardest, if any ([`Self::gravity_load`]).
    pub fn check_gravity(&self, sys: &System<'_>) -> Result<(), SimulationError> {
        let Some(pull) = self.gravity_load(sys) else {
            return Ok(());
        };
        let dir = &self.directions[pull.direction];
        let body = dir.motions.first().map_or(0, |(b, _)| *b);
        Err(SimulationError::FreeUnderGravity {
            body: sys.model.bodies[body].name.clone(),
            direction: dir.sentence(sys.model),
            load: pull.load,
            moment: dir.rotates(),
        })
    }
}
