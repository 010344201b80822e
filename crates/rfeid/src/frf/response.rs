//! Frequency response functions of the linearised model ([`super::linear`])
//! and their exact derivatives in the parameters.
//!
//! With `Z(ω) = K_t − ω² M + iω C_t` (complex symmetric), the response of
//! output s to a unit harmonic force of excitation e is
//! `H_se(ω) = g_s (iω)^k h_sᵀ Z⁻¹ L_e`, k = 0, 1, 2 for a displacement,
//! velocity or acceleration reading, `g_s` the sensor's gain. Its derivative
//! in a parameter x follows from `∂Z⁻¹ = −Z⁻¹ (∂Z) Z⁻¹` and the symmetry of
//! Z: `∂H_se = −g_s (iω)^k (Z⁻¹ h_s)ᵀ (∂Z) (Z⁻¹ L_e)`, one factorisation
//! of Z per frequency for every pair and every parameter.
use super::linear::{Linearised, Term};
use super::FrfError;
use crate::model::{Model, SensorKind, Value};
use crate::simulation::structure::Row;
use nalgebra::{Complex, DMatrix, DVector};
use rayon::prelude::*;

/// A complex number.
pub type C64 = Complex<f64>;

/// Where a response is read: a sensor of the model or a point of a body.
#[derive(Debug, Clone, PartialEq)]
pub struct Output {
    /// Its name (the sensor's, or the one given to the point).
    pub name: String,
    /// What it reads.
    pub kind: SensorKind,
    /// Its generalized row: the reading is `row · q` (or q̇, q̈).
    pub row: Vec<f64>,
    /// Its calibration gain (1 for a point).
    pub gain: Value,
}

impl Output {
    /// The model's sensors, in order.
    pub fn sensors(model: &Model) -> Vec<Output> {
        let structure = crate::simulation::structure::Structure::new(model);
        model
            .sensors
            .iter()
            .zip(&structure.sensors)
            .map(|(s, (kind, row))| Output {
                name: s.name.clone(),
                kind: *kind,
                row: row.dense(model.n_dof()),
                gain: s.gain,
            })
            .collect()
    }

    /// The motion of the point `at` (global, m) of body `body` along the
    /// direction `direction` (global, normalised here).
    pub fn point(
        model: &Model,
        name: &str,
        body: usize,
        at: nalgebra::Vector3<f64>,
        direction: nalgebra::Vector3<f64>,
        kind: SensorKind,
    ) -> Output {
        let b = &model.bodies[body];
        let rho = b.axes.transpose() * (at - b.com);
        let h = crate::model::geometry::point_direction_row(&b.axes, &rho, &direction.normalize());
        let mut row = vec![0.0; model.n_dof()];
        row[6 * body..6 * body + 6].copy_from_slice(&h);
        Output {
            name: name.to_owned(),
            kind,
            row,
            gain: Value::Fixed(1.0),
        }
    }
}

/// FRFs from every excitation to every output on a frequency grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Frf {
    /// Frequencies, Hz.
    pub frequencies: Vec<f64>,
    /// Number of outputs; pair `e · outputs + s` is excitation e to output s.
    pub outputs: usize,
    /// `H` per pair, per frequency: reading per newton of the excitation.
    pub values: Vec<Vec<C64>>,
    /// `∂H/∂x_j` per pair, frequency-major (`[f · r + j]`), for the r
    /// parameters the linearisation was given; empty without them.
    pub derivatives: Vec<Vec<C64>>,
    /// r.
    pub parameters: usize,
}

impl Frf {
    /// The pair of excitation `e` and output `s`.
    pub fn pair(&self, e: usize, s: usize) -> usize {
        e * self.outputs + s
    }
}

/// The FRFs of `lin` from each excitation to each output at `frequencies`
/// (Hz), with the outputs' gains at `params`, and their derivatives in the
/// linearisation's parameters `wrt` (those [`super::linear::linearise`] was
/// given, in order: a gain that is one of them is differentiated too).
pub fn frf(
    lin: &Linearised,
    outputs: &[Output],
    params: &[f64],
    wrt: &[usize],
    frequencies: &[f64],
) -> Result<Frf, FrfError> {
    let (ne, ns, r) = (lin.loads.len(), outputs.len(), lin.derivatives.len());
    let rows: Vec<Row> = outputs.iter().map(|o| Row::from_dense(&o.row)).collect();
    let per_frequency: Vec<(Vec<C64>, Vec<C64>)> = frequencies
        .par_iter()
        .map(|&f| at_frequency(lin, outputs, &rows, params, wrt, f))
        .collect::<Result<_, _>>()?;
    let pairs = ne * ns;
    let mut values = vec![Vec::with_capacity(frequencies.len()); pairs];
    let mut derivatives = vec![Vec::with_capacity(frequencies.len() * r); pairs];
    for (h, dh) in per_frequency {
        for p in 0..pairs {
            values[p].push(h[p]);
            derivatives[p].extend_from_slice(&dh[p * r..(p + 1) * r]);
        }
    }
    Ok(Frf {
        frequencies: frequencies.to_vec(),
        outputs: ns,
        values,
        derivatives,
        parameters: r,
    })
}

/// H for every pair at one frequency, and `∂H/∂x_j` pair-major.
fn at_frequency(
    lin: &Linearised,
    outputs: &[Output],
    rows: &[Row],
    params: &[f64],
    wrt: &[usize],
    f: f64,
) -> Result<(Vec<C64>, Vec<C64>), FrfError> {
    let n = lin.n;
    let w = std::f64::consts::TAU * f;
    let z = DMatrix::from_fn(n, n, |i, j| {
        let m = if i == j { lin.mass[i] } else { 0.0 };
        C64::new(
            lin.stiffness[i * n + j] - w * w * m,
            w * lin.damping[i * n + j],
        )
    });
    let lu = z.lu();
    let solve = |b: &[f64]| -> Result<DVector<C64>, FrfError> {
        let rhs = DVector::from_iterator(n, b.iter().map(|v| C64::new(*v, 0.0)));
        match lu.solve(&rhs) {
            Some(x) if x.iter().all(|v| v.re.is_finite() && v.im.is_finite()) => Ok(x),
            _ => Err(FrfError::Singular { frequency: f }),
        }
    };
    let xs: Vec<DVector<C64>> = lin
        .loads
        .iter()
        .map(|l| solve(l))
        .collect::<Result<_, _>>()?;
    let ys: Vec<DVector<C64>> = outputs
        .iter()
        .map(|o| solve(&o.row))
        .collect::<Result<_, _>>()?;
    let r = lin.derivatives.len();
    let (mut h, mut dh) = (Vec::new(), Vec::new());
    for x in &xs {
        for (s, (out, y)) in outputs.iter().zip(&ys).enumerate() {
            let gain = out.gain.eval(params);
            let factor = gain * reading_factor(out.kind, w);
            let value = factor * complex_dot(&rows[s], x);
            h.push(value);
            for (j, terms) in lin.derivatives.iter().enumerate() {
                let mut d = -factor * contract(terms, x, y, w);
                if out.gain.param().is_some_and(|g| g == wrt[j]) && gain != 0.0 {
                    d += value / gain;
                }
                dh.push(d);
            }
        }
    }
    debug_assert_eq!(dh.len(), h.len() * r);
    Ok((h, dh))
}

/// `(iω)^k` of a reading: 1, iω or −ω².
fn reading_factor(kind: SensorKind, w: f64) -> C64 {
    match kind {
        SensorKind::Displacement => C64::new(1.0, 0.0),
        SensorKind::Velocity => C64::new(0.0, w),
        SensorKind::Acceleration => C64::new(-w * w, 0.0),
    }
}

/// `row · x` for a complex x.
fn complex_dot(row: &Row, x: &DVector<C64>) -> C64 {
    let mut s = C64::new(0.0, 0.0);
    for (off, c) in &row.blocks {
        for (i, ci) in c.iter().enumerate() {
            s += x[off + i] * *ci;
        }
    }
    s
}

/// `yᵀ (∂Z) x` for the terms of one parameter at ω = `w`.
fn contract(terms: &[Term], x: &DVector<C64>, y: &DVector<C64>, w: f64) -> C64 {
    terms
        .iter()
        .map(|t| match t {
            Term::Outer { row, k, c } => {
                C64::new(*k, w * c) * complex_dot(row, x) * complex_dot(row, y)
            }
            Term::Mass(i) => -w * w * x[*i] * y[*i],
        })
        .sum()
}
