//! The forward sensitivity equation's right-hand side (eq. 27–28 need its
//! solution): for `Y = ∂y/∂x`,
//!
//! `∂q̈/∂x = [−M⁻¹K | −M⁻¹C] Y − Σ_i M⁻¹B_iᵀ w_i + (mass, inertia, load terms)`,
//!
//! where for each component i that is a power-law spring or holds an
//! identified parameter, `w_i = f_i'(δ_i) B_i Y_q + ∂f_i/∂x` is a row over
//! the parameters (eq. 2–6: f_i = a δ|δ|^(m−1) + c δ̇, or k δ + c δ̇).
//! With these rows stacked as W, the whole right-hand side is one dense
//! product `[−M⁻¹K | −M⁻¹C | −M⁻¹Bᵀ] [Y; W]`, whose inner loop is a
//! contiguous multiply–add over the parameters.
//!
//! Rows of Y and of the result hold [`Tangent::width`] columns: r rounded up
//! to a multiple of four, so the kernels run on whole vectors. The padding
//! columns start at zero and stay zero.
use super::dim::Dim;
use super::madd::Madd;
use super::structure::Usage;
use super::system::{power_law, System};
use crate::model::Law;

/// A component row that enters the sensitivities beyond the dense linear
/// part: a power-law spring, or a component holding an identified parameter.
#[derive(Debug, Clone)]
struct Active {
    /// `B_i`, dense (n).
    b: Vec<f64>,
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
    /// `[−M⁻¹K | −M⁻¹C | −M⁻¹B_aᵀ]` over the active components a, n rows of
    /// [`Self::ext_cols`], row-major: multiplies `[Y; W]`.
    ext: Vec<f64>,
    /// 2n plus [`Self::w_rows`].
    ext_cols: usize,
    /// Rows of W: the active components rounded up to even.
    w_rows: usize,
    /// Mass, inertia and amplitude parameters: (column, usage).
    others: Vec<(usize, Usage)>,
}

impl Tangent {
    /// Gathers the components and parameters of `sys` that the sensitivities
    /// to the parameters `wrt` need.
    pub fn new(sys: &System<'_>, wrt: &[usize]) -> Tangent {
        let structure = sys.structure;
        let n = sys.n;
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
                    b: c.row.dense(n),
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
        let w_rows = active.len().next_multiple_of(2);
        let ext_cols = 2 * n + w_rows;
        let mut ext = vec![0.0; n * ext_cols];
        for (i, row) in ext.chunks_exact_mut(ext_cols).enumerate() {
            row[..2 * n].copy_from_slice(&sys.a_lin[i * 2 * n..(i + 1) * 2 * n]);
            for (a, comp) in active.iter().enumerate() {
                row[2 * n + a] = -sys.minv[i] * comp.b[i];
            }
        }
        Tangent {
            width: wrt.len().next_multiple_of(4),
            active,
            ext,
            ext_cols,
            w_rows,
            others,
        }
    }

    /// Scratch length that [`Self::apply`] needs: the rows of W.
    pub fn scratch_len(&self) -> usize {
        self.w_rows * self.width
    }

    /// `dacc = ∂q̈/∂x` (n rows of [`Self::width`]) at time t, state `y`
    /// (2n) with acceleration `acc` (n), for sensitivities `sy` (2n rows).
    /// `w` is scratch of [`Self::scratch_len`], zero-filled once by the
    /// caller (its padding row is never written).
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

        // W: one row per active component.
        for (comp, wrow) in self.active.iter().zip(w.chunks_exact_mut(width)) {
            let b = &comp.b[..n];
            let d = dot::<M>(b, q);
            let slope = match comp.power {
                Some((a, m)) => power_law(a, m, d).1,
                None => 0.0,
            };
            if slope != 0.0 {
                // f'(δ) B_i Y_q.
                times_columns::<M>(b, &[], &sy[..n * width], &[], width, wrow);
                wrow.iter_mut().for_each(|x| *x *= slope);
            } else {
                wrow.fill(0.0);
            }
            for &(col, usage) in &comp.usages {
                wrow[col] += match usage {
                    Usage::Stiffness(_) => d,
                    Usage::Damping(_) => dot::<M>(b, v),
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
            }
        }

        // [−M⁻¹K | −M⁻¹C | −M⁻¹Bᵀ] [Y; W].
        for (row, out) in self
            .ext
            .chunks_exact(self.ext_cols)
            .zip(dacc.chunks_exact_mut(width))
        {
            let (ry, rw) = row.split_at(2 * n);
            times_columns::<M>(ry, rw, sy, w, width, out);
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

/// `a · x` for a of even length, in two partial sums.
#[inline(always)]
fn dot<M: Madd>(a: &[f64], x: &[f64]) -> f64 {
    let (mut s, mut t) = (0.0, 0.0);
    for (a, x) in a.chunks_exact(2).zip(x.chunks_exact(2)) {
        s = M::madd(a[0], x[0], s);
        t = M::madd(a[1], x[1], t);
    }
    s + t
}

/// `out = a · X + b · Z` for row vectors a, b and matrices X, Z with rows
/// `width` long (`width` a multiple of four), sixteen (then eight, four)
/// columns at a time.
#[inline(always)]
fn times_columns<M: Madd>(
    a: &[f64],
    b: &[f64],
    x: &[f64],
    z: &[f64],
    width: usize,
    out: &mut [f64],
) {
    let mut c0 = 0;
    while c0 + 16 <= width {
        row_times::<M, 16>(a, b, x, z, width, c0, out);
        c0 += 16;
    }
    if c0 + 8 <= width {
        row_times::<M, 8>(a, b, x, z, width, c0, out);
        c0 += 8;
    }
    if c0 < width {
        row_times::<M, 4>(a, b, x, z, width, c0, out);
    }
}

/// `out[c0..c0+W] = Σ_j a_j x[j][c0..c0+W] + Σ_j b_j z[j][c0..c0+W]`, two
/// rows at a time in separate accumulators so that the loop is not
/// latency-bound. `a` and `b` have even lengths or `b` is empty.
#[inline(always)]
fn row_times<M: Madd, const W: usize>(
    a: &[f64],
    b: &[f64],
    x: &[f64],
    z: &[f64],
    width: usize,
    c0: usize,
    out: &mut [f64],
) {
    assert!(c0 + W <= width);
    let (mut s, mut t) = ([0.0; W], [0.0; W]);
    for (coef, rows) in [(a, x), (b, z)] {
        // Two rows at a time, walking down `rows` (`split_at`, not
        // `chunks_exact`, which would divide by the run-time width).
        let mut pairs = coef.chunks_exact(2);
        let mut rest = rows;
        for c in &mut pairs {
            let (r, tail) = rest.split_at(2 * width);
            rest = tail;
            let (x0, x1) = (&r[c0..c0 + W], &r[width + c0..width + c0 + W]);
            for k in 0..W {
                s[k] = M::madd(c[0], x0[k], s[k]);
                t[k] = M::madd(c[1], x1[k], t[k]);
            }
        }
        if let [c] = pairs.remainder() {
            let x0 = &rest[c0..c0 + W];
            for k in 0..W {
                s[k] = M::madd(*c, x0[k], s[k]);
            }
        }
    }
    let o = &mut out[c0..c0 + W];
    for k in 0..W {
        o[k] = s[k] + t[k];
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
