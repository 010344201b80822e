//! The free space in describable directions: candidate rigid motions
//! (translations along the global axes and along the axes of the elements
//! that touch them, rotations about the global axes through a centre of
//! mass or an element's point, of one body or of a group that springs join)
//! that lie in it, then the rest of a basis. A body sliding along a skewed
//! element's axis relative to another body is thus one direction of its
//! own, not mixed with the other's motions.
use super::gram::has_spring;
use super::motion::{direction, FreeDirection};
use super::vectors::{unit_residual, CONTAINED};
use crate::model::{Attachment, Model};
use crate::simulation::system::System;
use nalgebra::{Matrix3, Vector3};

/// The free space spanned by `orthonormal` (mass-scaled) as described
/// directions: the candidates of [`candidates`] that lie in it, then the
/// rest of a basis.
pub(super) fn describe_space(
    sys: &System<'_>,
    orthonormal: &[Vec<f64>],
    sqrt_m: &[f64],
) -> Vec<FreeDirection> {
    let k = orthonormal.len();
    let mut taken: Vec<Vec<f64>> = Vec::new();
    let mut shapes: Vec<Vec<f64>> = Vec::new();
    for c in candidates(sys, orthonormal, sqrt_m) {
        if taken.len() == k {
            break;
        }
        let x: Vec<f64> = c.iter().zip(sqrt_m).map(|(c, s)| c * s).collect();
        let inside = unit_residual(orthonormal, &x).is_none();
        if inside {
            if let Some(u) = unit_residual(&taken, &x) {
                taken.push(u);
                shapes.push(c);
            }
        }
    }
    for x in orthonormal {
        if taken.len() == k {
            break;
        }
        if let Some(u) = unit_residual(&taken, x) {
            shapes.push(u.iter().zip(sqrt_m).map(|(u, s)| u / s).collect());
            taken.push(u);
        }
    }
    shapes
        .into_iter()
        .map(|s| direction(sys.model, s, sqrt_m))
        .collect()
}

/// The rotation of a rigid motion about the unit global `axis` through
/// `point`, as body b's block `[u; φ]` in its own axes.
fn rotation_block(model: &Model, b: usize, axis: &Vector3<f64>, point: &Vector3<f64>) -> [f64; 6] {
    let body = &model.bodies[b];
    let r: &Matrix3<f64> = &body.axes;
    let u = r.transpose() * axis.cross(&(body.com - point));
    let phi = r.transpose() * axis;
    [u.x, u.y, u.z, phi.x, phi.y, phi.z]
}

/// Candidate free motions, in generalized coordinates: for each body that
/// moves in the free space, and then for each group of bodies joined by
/// springs, translations along the global axes and the axes of the
/// elements touching it, and rotations about the global axes through the
/// centre of mass and the points of the elements touching it.
fn candidates(sys: &System<'_>, orthonormal: &[Vec<f64>], sqrt_m: &[f64]) -> Vec<Vec<f64>> {
    let model = sys.model;
    let n = sys.n;
    let bodies = model.bodies.len();
    let moving: Vec<bool> = (0..bodies)
        .map(|b| (6 * b..6 * b + 6).any(|i| orthonormal.iter().any(|x| x[i].abs() > CONTAINED)))
        .collect();
    let mut groups: Vec<Vec<usize>> = (0..bodies)
        .filter(|&b| moving[b])
        .map(|b| vec![b])
        .collect();
    groups.extend(spring_groups(sys).into_iter().filter(|g| g.len() > 1));
    let axes = [Vector3::x(), Vector3::y(), Vector3::z()];
    let mut out = Vec::new();
    for group in groups {
        let mass: f64 = group.iter().map(|&b| sqrt_m[6 * b].powi(2)).sum();
        let com = group
            .iter()
            .map(|&b| model.bodies[b].com * sqrt_m[6 * b].powi(2))
            .sum::<Vector3<f64>>()
            / mass;
        let mut points = vec![com];
        let mut directions = axes.to_vec();
        for e in &model.elements {
            let touches = group.contains(&e.body)
                || matches!(e.to, Attachment::Body(p) if group.contains(&p));
            if touches && !points.contains(&e.at) {
                points.push(e.at);
            }
            if touches {
                for d in e.axes.column_iter().map(|c| c.into_owned()) {
                    if directions.iter().all(|o| o.cross(&d).norm() > 1e-9) {
                        directions.push(d);
                    }
                }
            }
        }
        for axis in &directions {
            let mut v = vec![0.0; n];
            for &b in &group {
                let local = model.bodies[b].axes.transpose() * axis;
                v[6 * b..6 * b + 3].copy_from_slice(local.as_slice());
            }
            out.push(v);
        }
        for point in &points {
            for axis in &axes {
                let mut v = vec![0.0; n];
                for &b in &group {
                    v[6 * b..6 * b + 6].copy_from_slice(&rotation_block(model, b, axis, point));
                }
                out.push(v);
            }
        }
    }
    out
}

/// The groups of bodies that spring components join (ground apart), each
/// sorted, in order of their first body.
fn spring_groups(sys: &System<'_>) -> Vec<Vec<usize>> {
    let model = sys.model;
    let bodies = model.bodies.len();
    let mut parent: Vec<usize> = (0..bodies).collect();
    fn root(parent: &mut [usize], mut b: usize) -> usize {
        while parent[b] != b {
            parent[b] = parent[parent[b]];
            b = parent[b];
        }
        b
    }
    for comp in &sys.structure.components {
        let e = &model.elements[comp.element];
        if let Attachment::Body(p) = e.to {
            if has_spring(&comp.law, &sys.params) {
                let (a, b) = (root(&mut parent, e.body), root(&mut parent, p));
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut index = vec![usize::MAX; bodies];
    for b in 0..bodies {
        let r = root(&mut parent, b);
        if index[r] == usize::MAX {
            index[r] = groups.len();
            groups.push(Vec::new());
        }
        groups[index[r]].push(b);
    }
    groups
}
