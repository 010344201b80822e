//! The forward sensitivity equation's right-hand side (eq. 27–28 need its
//! solution): for `Y = ∂y/∂x`,
//!
//! `∂q̈/∂x = [−M⁻¹K | −M⁻¹C] Y − Σ_i M⁻¹B_iᵀ w_i + (mass, inertia, load terms)`,
//!
//! where for each component i that is a power-law spring or holds an
//! identified parameter, `w_i = f_i'(δ_i) B_i Y_q + ∂f_i/∂x` is a row over
//! the parameters (eq. 2–6: f_i = a δ|δ|^(m−1) + c δ̇, or k δ + c δ̇).
//! Gathering each component's terms into one row and scattering it once
//! through the sparse `M⁻¹B_iᵀ` keeps every inner loop a contiguous
//! multiply–add over the parameters.
//!
//! Rows of Y and of the result hold [`Tangent::width`] columns: r rounded up
//! to a multiple of four, so the kernels run on whole vectors. The padding
//! columns start at zero and stay zero.
use super::dim::Dim;
use super::madd::Madd;
use super::structure::{Row, Usage};
use super::system::{power_law, System};
use crate::model::Law;

/// A component row that enters the sensitivities beyond the dense linear
/// part: a power-law spring, or a component holding an identified parameter.
#[derive(Debug, Clone)]
struct Active {
    /// `δ_i = B_i q`.
    row: Row,
    /// The nonzero entries of `B_i`, as (coordinate, value).
    b: Vec<(usize, f64)>,
    /// The nonzero entries of `M⁻¹ B_iᵀ`, as (coordinate, value).
    g: Vec<(usize, f64)>,
    /// `(a, m)` of a power-law spring.
    power: Option<(f64, f64)>,
    /// Identified parameters acting here: (column, usage).
    usages: Vec<(usize, Usage)>,
}

/// The sensitivity right-hand side for one run: a model at one parameter
/// point and a list of identified parameters.
#[derive(Debug, Clone)]
pub(crate) struct Tangent {
    /// Columns per row of Y: the number of parameters rounded up to a
    /// multiple of four.
    pub width: usize,
    active: Vec<Active>,
    /// Mass, inertia and amplitude parameters: (column, usage).
    others: Vec<(usize, Usage)>,
}

/// The nonzero entries of a row, scaled per coordinate.
fn nonzero(row: &Row, scale: &[f64]) -> Vec<(usize, f64)> {
    row.blocks
        .iter()
        .flat_map(|(off, c)| (0..6).map(move |i| (off + i, c[i])))
        .filter(|(_, v)| *v != 0.0)
        .map(|(k, v)| (k, v * scale[k]))
        .collect()
}

impl Tangent {
    /// Gathers the components and parameters of `sys` that the sensitivities
    /// to the parameters `wrt` need.
    pub fn new(sys: &System<'_>, wrt: &[usize]) -> Tangent {
        let structure = sys.structure;
        let ones = vec![1.0; sys.n];
        let mut active: Vec<Active> = Vec::new();
        let mut others = Vec::new();
        let mut slot = vec![None; structure.components.len()];
        let mut activate = |i: usize, active: &mut Vec<Active>| -> usize {
            *slot[i].get_or_insert_with(|| {
                let c = &structure.components[i];
                let power = match c.law {
                    Law::Power { a, m } => Some((a.eval(&sys.params), m.eval(&sys.params))),
                    _ => None,
                };
                active.push(Active {
                    row: c.row.clone(),
                    b: nonzero(&c.row, &ones),
                    g: nonzero(&c.row, &sys.minv),
                    power,
                    usages: Vec::new(),
                });
                active.len() - 1
            })
        };
        for (i, c) in structure.components.iter().enumerate() {
            if matches!(c.law, Law::Power { .. }) {
                activate(i, &mut active);
            }
        }
        for (col, &p) in wrt.iter().enumerate() {
            for &usage in &structure.usages[p] {
                match usage {
                    Usage::Stiffness(i)
                    | Usage::Damping(i)
                    | Usage::PowerCoefficient(i)
                    | Usage::PowerExponent(i) => {
                        let k = activate(i, &mut active);
                        active[k].usages.push((col, usage));
                    }
                    Usage::Mass(_) | Usage::Inertia(..) | Usage::Amplitude(..) => {
                        others.push((col, usage))
                    }
                }
            }
        }
        Tangent {
            width: wrt.len().next_multiple_of(4),
            active,
            others,
        }
    }

    /// `dacc = ∂q̈/∂x` (n rows of [`Self::width`]) at time t, state `y`
    /// (2n) with acceleration `acc` (n), for sensitivities `sy` (2n rows).
    /// `w` is scratch of length [`Self::width`].
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn apply<M: Madd, D: Dim>(
        &self,
        sys: &System<'_>,
        t: f64,
        y: &[f64],
        acc: &[f64],
        sy: &[f64],
        dacc: &mut [f64],
        w: &mut [f64],
    ) {
        let n = D::n(sys.n);
        let width = self.width;
        let (q, v) = y[..2 * n].split_at(n);
        let sy = &sy[..2 * n * width];
        let dacc = &mut dacc[..n * width];
        let w = &mut w[..width];

        // [−M⁻¹K | −M⁻¹C] Y, sixteen (then eight, four) columns at a time.
        for (arow, out) in sys
            .a_lin
            .chunks_exact(2 * n)
            .zip(dacc.chunks_exact_mut(width))
        {
            let mut c0 = 0;
            while c0 + 16 <= width {
                row_times::<M, 16>(arow, sy, width, c0, out);
                c0 += 16;
            }
            if c0 + 8 <= width {
                row_times::<M, 8>(arow, sy, width, c0, out);
                c0 += 8;
            }
            if c0 < width {
                row_times::<M, 4>(arow, sy, width, c0, out);
            }
        }

        // − M⁻¹B_iᵀ w_i per component.
        for comp in &self.active {
            let d = comp.row.dot(q);
            let mut any = false;
            w.fill(0.0);
            if let Some((a, m)) = comp.power {
                let (_, slope) = power_law(a, m, d);
                if slope != 0.0 {
                    for &(k, b) in &comp.b {
                        axpy::<M>(slope * b, &sy[k * width..(k + 1) * width], w);
                    }
                    any = true;
                }
            }
            for &(col, usage) in &comp.usages {
                let f = match usage {
                    Usage::Stiffness(_) => d,
                    Usage::Damping(_) => comp.row.dot(v),
                    Usage::PowerCoefficient(_) => {
                        let (_, m) = comp.power.unwrap_or((0.0, 1.0));
                        power_law(1.0, m, d).0
                    }
                    Usage::PowerExponent(_) => {
                        let (a, m) = comp.power.unwrap_or((0.0, 1.0));
                        exponent_derivative(a, m, d)
                    }
                    Usage::Mass(_) | Usage::Inertia(..) | Usage::Amplitude(..) => 0.0,
                };
                w[col] += f;
                any |= f != 0.0;
            }
            if any {
                for &(k, g) in &comp.g {
                    axpy::<M>(-g, w, &mut dacc[k * width..(k + 1) * width]);
                }
            }
        }

        for &(col, usage) in &self.others {
            let cell = |k: usize| k * width + col;
            match usage {
                Usage::Mass(b) => {
                    let m = sys.model.bodies[b].mass.eval(&sys.params);
                    for k in 6 * b..6 * b + 3 {
                        dacc[cell(k)] += (sys.minv_gravity[k] - acc[k]) / m;
                    }
                }
                Usage::Inertia(b, axis) => {
                    let k = 6 * b + 3 + axis;
                    dacc[cell(k)] -= acc[k] * sys.minv[k];
                }
                Usage::Amplitude(e, j) => {
                    let s = sys.model.excitations[e].signal.terms[j].shape.at(t);
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

/// `out[c0..c0+W] = Σ_j arow[j] · sy[j][c0..c0+W]`, rows of `sy` `width`
/// long, two rows at a time in separate accumulators so that the loop is
/// not latency-bound.
#[inline(always)]
fn row_times<M: Madd, const W: usize>(
    arow: &[f64],
    sy: &[f64],
    width: usize,
    c0: usize,
    out: &mut [f64],
) {
    assert!(c0 + W <= width && arow.len() % 2 == 0);
    let (mut s, mut t) = ([0.0; W], [0.0; W]);
    for (a, rows) in arow.chunks_exact(2).zip(sy.chunks_exact(2 * width)) {
        let (x0, x1) = (&rows[c0..c0 + W], &rows[width + c0..width + c0 + W]);
        for k in 0..W {
            s[k] = M::madd(a[0], x0[k], s[k]);
            t[k] = M::madd(a[1], x1[k], t[k]);
        }
    }
    for k in 0..W {
        out[c0 + k] = s[k] + t[k];
    }
}

/// `∂f/∂m = a sign(δ)|δ|^m ln|δ|` of a power law. Kept out of line: inlined,
/// the compiler may hoist the logarithm out of the branch that needs it and
/// pay for it on every component of every stage.
#[inline(never)]
fn exponent_derivative(a: f64, m: f64, d: f64) -> f64 {
    if d == 0.0 {
        0.0
    } else {
        a * power_law(1.0, m, d).0 * d.abs().ln()
    }
}

/// `y += alpha · x` (equal lengths).
#[inline(always)]
fn axpy<M: Madd>(alpha: f64, x: &[f64], y: &mut [f64]) {
    let x = &x[..y.len()];
    for i in 0..y.len() {
        y[i] = M::madd(alpha, x[i], y[i]);
    }
}
