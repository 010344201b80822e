//! Many candidates on one body, at the cost of six. A sensor's reading is
//! `h · q_b` (or its rates) with `h` the six-entry row of its point and
//! direction on body b's coordinates, so the reading of any point and
//! direction is a fixed combination of six readings whose rows span the
//! body's six coordinates (the centre of mass along x, y, z, and three
//! points one metre from it). With each basis reading's sensitivity rows
//! `B_k`, the blocks `T_kl = B_kᵀB_l` are summed once over the record, and
//! a candidate with combination `c` has the information
//! `Σ_kl c_k c_l T_kl / σ²`: O(36 r²) per candidate, whatever the record's
//! length.
use crate::model::geometry::point_direction_row;
use crate::model::{DataSource, Model, Sensor, SensorKind, Value};
use nalgebra::{DMatrix, Matrix6, Vector3, Vector6};

/// Candidates of one body and quantity read through a basis.
#[derive(Debug, Clone)]
pub struct Group {
    /// The six basis sensors.
    pub basis: Vec<Sensor>,
    /// Each member: its candidate index and its combination of the basis.
    pub members: Vec<(usize, [f64; 6])>,
}

/// How the candidates are read: one by one (`direct`, candidate indices)
/// or through their body's basis (`groups`).
#[derive(Debug, Clone, Default)]
pub struct Layout {
    /// Candidates simulated as sensors of their own.
    pub direct: Vec<usize>,
    /// Candidates read through a basis.
    pub groups: Vec<Group>,
}

impl Layout {
    /// The sensors to simulate besides the placed ones: the direct
    /// candidates, then each group's basis.
    pub fn sensors(&self, model: &Model) -> Vec<Sensor> {
        self.direct
            .iter()
            .map(|&i| model.candidates[i].clone())
            .chain(self.groups.iter().flat_map(|g| g.basis.iter().cloned()))
            .collect()
    }
}

/// The row of sensor `s` on its body's six coordinates.
fn row(model: &Model, s: &Sensor) -> Vector6<f64> {
    let body = &model.bodies[s.body];
    let rho = body.axes.transpose() * (s.at - body.com);
    Vector6::from_row_slice(&point_direction_row(&body.axes, &rho, &s.direction))
}

/// A basis sensor of body `b`: at `at` along `direction`, reading `kind`,
/// unit noise.
fn basis_sensor(model: &Model, b: usize, k: usize, kind: SensorKind) -> Sensor {
    let c = model.bodies[b].com;
    let e = |i: usize| Vector3::ith(i, 1.0);
    // The centre along x, y, z; then one metre along y read along z, along
    // z read along x, along x read along y: together every coordinate.
    let (at, direction) = match k {
        0..=2 => (c, e(k)),
        3 => (c + e(1), e(2)),
        4 => (c + e(2), e(0)),
        _ => (c + e(0), e(1)),
    };
    let name = format!("\u{1}basis {b} {k}");
    Sensor {
        data: DataSource::for_sensor(&name),
        name,
        body: b,
        at,
        direction,
        kind,
        gain: Value::Fixed(1.0),
        offset: Value::Fixed(0.0),
        noise: Some(1.0),
    }
}

/// Groups the candidates: a body and quantity with more than six plain
/// candidates (gain 1, offset 0) is read through a basis, the others one
/// by one. `basis = false` reads every one directly (for the tests that
/// compare the two).
pub fn layout(model: &Model, basis: bool) -> Layout {
    let mut out = Layout::default();
    let mut keys: Vec<(usize, SensorKind)> = Vec::new();
    for s in model.candidates.iter().filter(|s| s.is_plain()) {
        if !keys.contains(&(s.body, s.kind)) {
            keys.push((s.body, s.kind));
        }
    }
    let mut grouped = vec![false; model.candidates.len()];
    for (b, kind) in keys {
        let members: Vec<usize> = (0..model.candidates.len())
            .filter(|&i| {
                let s = &model.candidates[i];
                s.body == b && s.kind == kind && s.is_plain()
            })
            .collect();
        if !basis || members.len() <= 6 {
            continue;
        }
        let sensors: Vec<Sensor> = (0..6).map(|k| basis_sensor(model, b, k, kind)).collect();
        let h = Matrix6::from_columns(&sensors.iter().map(|s| row(model, s)).collect::<Vec<_>>());
        let Some(lu) = Some(h.lu()).filter(|lu| lu.is_invertible()) else {
            continue;
        };
        let members = members
            .into_iter()
            .map(|i| {
                grouped[i] = true;
                let c = lu
                    .solve(&row(model, &model.candidates[i]))
                    .expect("invertible");
                (i, [c[0], c[1], c[2], c[3], c[4], c[5]])
            })
            .collect();
        out.groups.push(Group {
            basis: sensors,
            members,
        });
    }
    out.direct = (0..model.candidates.len())
        .filter(|&i| !grouped[i])
        .collect();
    out
}

/// A group's members' information from its basis rows `blocks[k]`
/// (unweighted), in units of the common noise variance σ₀²
/// ([`super::fisher::FisherParts::noise_scale`]): `Σ_kl c_k c_l B_kᵀB_l
/// (σ₀/σ)²`, in the group's member order.
pub fn member_shares(
    model: &Model,
    g: &Group,
    blocks: &[nalgebra::DMatrixView<f64>],
    noise_scale: f64,
) -> Vec<(usize, DMatrix<f64>)> {
    let r = blocks[0].ncols();
    let mut t = vec![DMatrix::zeros(r, r); 36];
    for k in 0..6 {
        for l in k..6 {
            let p = blocks[k].transpose() * blocks[l];
            t[6 * l + k] = p.transpose();
            t[6 * k + l] = p;
        }
    }
    g.members
        .iter()
        .map(|&(i, c)| {
            let w = model.candidates[i]
                .noise
                .map_or(0.0, |s| (noise_scale / s).powi(2));
            let mut f = DMatrix::zeros(r, r);
            for k in 0..6 {
                for l in 0..6 {
                    f += &t[6 * k + l] * (w * c[k] * c[l]);
                }
            }
            (i, f)
        })
        .collect()
}
