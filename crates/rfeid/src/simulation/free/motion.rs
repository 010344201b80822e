//! One free direction: each body's rigid motion in global terms, and the
//! direction in words.
use super::vectors::CONTAINED;
use crate::model::{Attachment, Model};
use nalgebra::Vector3;

/// How one body moves along a free direction, in global terms.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    /// A translation along a unit direction.
    Translation {
        /// The direction (global, unit, largest component positive).
        direction: Vector3<f64>,
    },
    /// A rotation about an axis, with an advance along it per radian (a
    /// screw motion; 0 for a pure rotation).
    Rotation {
        /// The axis (global, unit, largest component positive).
        axis: Vector3<f64>,
        /// The point of the axis nearest to the body's centre of mass.
        through: Vector3<f64>,
        /// The translation along the axis per radian, m/rad.
        advance: f64,
    },
}

/// One free direction: a motion of one or more bodies that no spring resists.
#[derive(Debug, Clone, PartialEq)]
pub struct FreeDirection {
    /// The motion in generalized coordinates (n): a unit translation (the
    /// largest of any body's) or a unit rotation (likewise).
    pub shape: Vec<f64>,
    /// Each moving body and its motion, in body order.
    pub motions: Vec<(usize, Motion)>,
}

/// Body b's block of `shape` in global terms: its centre of mass's
/// translation U and its rotation Φ.
fn global_motion(model: &Model, b: usize, shape: &[f64]) -> (Vector3<f64>, Vector3<f64>) {
    let r = &model.bodies[b].axes;
    let block = &shape[6 * b..6 * b + 6];
    (
        r * Vector3::new(block[0], block[1], block[2]),
        r * Vector3::new(block[3], block[4], block[5]),
    )
}

/// Body b's share of `shape` in the mass-scaled norm: (all, rotation only).
fn body_size(shape: &[f64], sqrt_m: &[f64], b: usize) -> (f64, f64) {
    let sq = |i: usize| (shape[i] * sqrt_m[i]).powi(2);
    let rot: f64 = (6 * b + 3..6 * b + 6).map(sq).sum();
    let all: f64 = rot + (6 * b..6 * b + 3).map(sq).sum::<f64>();
    (all.sqrt(), rot.sqrt())
}

/// A free direction from its shape: each moving body's motion, and the
/// shape scaled to a unit translation, or a unit rotation if any body
/// rotates.
pub(super) fn direction(model: &Model, mut shape: Vec<f64>, sqrt_m: &[f64]) -> FreeDirection {
    let sizes: Vec<(f64, f64)> = (0..model.bodies.len())
        .map(|b| body_size(&shape, sqrt_m, b))
        .collect();
    let largest = sizes.iter().fold(0.0_f64, |m, s| m.max(s.0));
    let moving: Vec<usize> = (0..sizes.len())
        .filter(|&b| sizes[b].0 > CONTAINED * largest)
        .collect();
    let rotates = |b: usize| sizes[b].1 > CONTAINED * sizes[b].0;
    let any_rotation = moving.iter().any(|&b| rotates(b));
    let scale = moving
        .iter()
        .map(|&b| {
            let (u, phi) = global_motion(model, b, &shape);
            if any_rotation {
                phi.norm()
            } else {
                u.norm()
            }
        })
        .fold(0.0, f64::max);
    if scale > 0.0 {
        shape.iter_mut().for_each(|v| *v /= scale);
    }
    let motions = moving
        .into_iter()
        .map(|b| {
            let (u, phi) = global_motion(model, b, &shape);
            let motion = if rotates(b) {
                let w2 = phi.norm_squared();
                Motion::Rotation {
                    axis: canonical(phi),
                    through: model.bodies[b].com + phi.cross(&u) / w2,
                    advance: u.dot(&phi) / w2,
                }
            } else {
                Motion::Translation {
                    direction: canonical(u),
                }
            };
            (b, motion)
        })
        .collect();
    FreeDirection { shape, motions }
}

/// A unit vector along `v` with its largest component positive, and
/// components within rounding of zero set to zero.
fn canonical(v: Vector3<f64>) -> Vector3<f64> {
    let mut u = v / v.norm();
    let big = u
        .iter()
        .fold(0.0_f64, |m, c| if c.abs() > m.abs() { *c } else { m });
    if big < 0.0 {
        u = -u;
    }
    u.apply(|c| {
        if c.abs() < 1e-12 {
            *c = 0.0
        }
    });
    u
}

impl FreeDirection {
    /// Whether any body rotates in this direction.
    pub fn rotates(&self) -> bool {
        self.motions
            .iter()
            .any(|(_, m)| matches!(m, Motion::Rotation { .. }))
    }

    /// The direction in words, e.g. `carriage: free along x`, `carriage and
    /// slide together: free along (0.7071, 0.7071, 0)`, `spindle: free to
    /// rotate about z through (0, 0, 1.2)`, `slide: free along (0.6, 0.8,
    /// 0) relative to arm` (an element joins it to a body that stays), or
    /// body by body when they move differently (`free together: carriage
    /// along x, slide about z …`).
    pub fn describe(&self, model: &Model) -> String {
        match self.parts(model) {
            (who, Some(what), _) => format!("{who}: free {what}"),
            (who, None, _) => format!("free together: {who}"),
        }
    }

    /// The direction as a sentence, e.g. `carriage is free along x`,
    /// `carriage and slide together are free along x`.
    pub fn sentence(&self, model: &Model) -> String {
        match self.parts(model) {
            (who, Some(what), false) => format!("{who} is free {what}"),
            (who, Some(what), true) => format!("{who} are free {what}"),
            (who, None, _) => format!("{who} are free together"),
        }
    }

    /// Who moves, how (None when the bodies move differently: then `who`
    /// says how each moves), and whether `who` is plural.
    fn parts(&self, model: &Model) -> (String, Option<String>, bool) {
        let name = |b: usize| model.bodies[b].name.as_str();
        let Some(&(first, motion)) = self.motions.first() else {
            return ("nothing".into(), Some("(no motion)".into()), false);
        };
        if !self.motions.iter().all(|(_, m)| same_motion(m, &motion)) {
            let each: Vec<String> = self
                .motions
                .iter()
                .map(|(b, m)| format!("{} {}", name(*b), motion_text(m)))
                .collect();
            return (each.join(", "), None, true);
        }
        let what = match motion {
            Motion::Translation { .. } => motion_text(&motion),
            Motion::Rotation { .. } => format!("to rotate {}", motion_text(&motion)),
        } + &self.relative_to(model);
        if self.motions.len() == 1 {
            return (name(first).to_string(), Some(what), false);
        }
        let names: Vec<&str> = self.motions.iter().map(|(b, _)| name(*b)).collect();
        let (last, rest) = names.split_last().expect("two or more");
        let who = format!("{} and {last} together", rest.join(", "));
        (who, Some(what), true)
    }
}

impl FreeDirection {
    /// ` relative to arm` (and more names) when elements join the moving
    /// bodies to bodies that stay still in this direction; empty when only
    /// the ground holds them.
    fn relative_to(&self, model: &Model) -> String {
        let moves = |b: usize| self.motions.iter().any(|(m, _)| *m == b);
        let mut still: Vec<usize> = Vec::new();
        for e in &model.elements {
            let Attachment::Body(to) = e.to else { continue };
            let other = match (moves(e.body), moves(to)) {
                (true, false) => to,
                (false, true) => e.body,
                _ => continue,
            };
            if !still.contains(&other) {
                still.push(other);
            }
        }
        let names: Vec<&str> = still
            .iter()
            .map(|&b| model.bodies[b].name.as_str())
            .collect();
        match names.split_last() {
            None => String::new(),
            Some((only, [])) => format!(" relative to {only}"),
            Some((last, rest)) => format!(" relative to {} and {last}", rest.join(", ")),
        }
    }
}

/// Whether two bodies' motions are one rigid motion: the same translation,
/// or rotations about the same line with the same advance.
fn same_motion(a: &Motion, b: &Motion) -> bool {
    match (a, b) {
        (Motion::Translation { direction: d }, Motion::Translation { direction: e }) => {
            (d - e).norm() < 1e-9
        }
        (
            Motion::Rotation {
                axis,
                through,
                advance,
            },
            Motion::Rotation {
                axis: a2,
                through: t2,
                advance: v2,
            },
        ) => {
            let scale = 1.0 + through.norm().max(t2.norm());
            (axis - a2).norm() < 1e-9
                && (t2 - through).cross(axis).norm() < 1e-9 * scale
                && (advance - v2).abs() < 1e-9 * scale
        }
        _ => false,
    }
}

/// One body's motion in words: `along x`, `about z through (0, 0, 1.2)`,
/// with a screw's advance.
fn motion_text(m: &Motion) -> String {
    match m {
        Motion::Translation { direction } => format!("along {}", axis_text(direction)),
        Motion::Rotation {
            axis,
            through,
            advance,
        } => {
            let mut s = format!("about {} through {}", axis_text(axis), point_text(through));
            if advance.abs() > 1e-9 * (1.0 + through.norm()) {
                s += &format!(", advancing {} m/rad along it", number(*advance));
            }
            s
        }
    }
}

/// A unit direction: `x`, `y` or `z` for a global axis, else its components.
fn axis_text(u: &Vector3<f64>) -> String {
    for (i, name) in ["x", "y", "z"].iter().enumerate() {
        if (u[i] - 1.0).abs() < 1e-9 {
            return (*name).to_string();
        }
    }
    point_text(u)
}

/// A vector as `(x, y, z)`, four significant digits.
fn point_text(p: &Vector3<f64>) -> String {
    format!("({}, {}, {})", number(p.x), number(p.y), number(p.z))
}

/// A number to four significant digits, without trailing zeros; rounding
/// of zero (below 1e-12) as 0.
fn number(v: f64) -> String {
    if v.abs() < 1e-12 {
        return "0".into();
    }
    let digits = (3 - v.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.digits$}");
    match s.contains('.') {
        true => s.trim_end_matches('0').trim_end_matches('.').to_string(),
        false => s,
    }
}
