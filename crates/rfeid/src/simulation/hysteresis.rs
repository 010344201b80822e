//! The Bouc–Wen law (SPEC §1): a component's force `k δ + z` with the
//! internal state z integrated with the motion,
//!
//! `ż = α v − β (γ |v| |z|^(n−1) z + d v |z|^n)`,  z(0) = 0,  v = δ̇,
//!
//! and its sensitivities (eq. 27–28 extended by the rows of ∂z/∂x). The
//! state vector of a run is `[q; q̇; z]`, one z per Bouc–Wen component in
//! component order; the spring k is in the kernels' linear part, z enters
//! the accelerations like a force `z (−M⁻¹B_iᵀ)` after either kernel.
use super::madd::Madd;
use super::sparse::SparseComp;
use super::structure::HysteresisKey;
use super::SimulationError;
use crate::model::{BoucWen, Law, Model};

/// A Bouc–Wen law with numbers in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BoucWenLaw {
    alpha: f64,
    beta: f64,
    gamma: f64,
    d: f64,
    n: f64,
}

/// A Bouc–Wen component of the kernels: its index in the component list
/// ([`SparseComp`], whose rows it uses) and its law.
#[derive(Debug, Clone, Copy)]
pub(crate) struct HysteresisRow {
    /// The component's index.
    pub comp: usize,
    /// The law at the run's parameter values.
    pub law: BoucWenLaw,
}

/// `(|z|^n, |z|^(n−1))`, exact for n = 1 (then `|z|^0 = 1`, also at z = 0).
#[inline(always)]
fn powers(z: f64, n: f64) -> (f64, f64) {
    let a = z.abs();
    if n == 1.0 {
        (a, 1.0)
    } else if a == 0.0 {
        (0.0, 0.0)
    } else {
        let p = a.powf(n);
        (p, p / a)
    }
}

/// `ln|z|` where `|z|^n` multiplies it (0 at z = 0, whose term vanishes).
#[inline(always)]
fn log_abs(z: f64) -> f64 {
    match z == 0.0 {
        true => 0.0,
        false => z.abs().ln(),
    }
}

impl BoucWenLaw {
    /// The law `bw` at the parameter values `p`, refusing an exponent below
    /// 1 (element `element`).
    pub fn new(bw: &BoucWen, p: &[f64], element: &str) -> Result<Self, SimulationError> {
        let n = bw.n.eval(p);
        if !(n >= 1.0) {
            return Err(SimulationError::BadExponent {
                element: element.to_owned(),
                value: n,
            });
        }
        Ok(BoucWenLaw {
            alpha: bw.alpha.eval(p),
            beta: bw.beta.eval(p),
            gamma: bw.gamma.eval(p),
            d: bw.d.eval(p),
            n,
        })
    }

    /// The law at velocity v and state z: the powers of |z| evaluated once,
    /// for the rate, the slopes and the derivatives there.
    #[inline(always)]
    pub fn at(&self, v: f64, z: f64) -> BoucWenAt<'_> {
        BoucWenAt {
            law: self,
            v,
            z,
            powers: powers(z, self.n),
        }
    }

    /// ż at velocity v and state z.
    #[inline(always)]
    pub fn rate(&self, v: f64, z: f64) -> f64 {
        self.at(v, z).rate()
    }
}

/// A Bouc–Wen law at one velocity and state ([`BoucWenLaw::at`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct BoucWenAt<'a> {
    law: &'a BoucWenLaw,
    v: f64,
    z: f64,
    /// `(|z|^n, |z|^(n−1))`.
    powers: (f64, f64),
}

impl BoucWenAt<'_> {
    /// `γ |v| |z|^(n−1) z + d v |z|^n`, the bracket of ż.
    #[inline(always)]
    fn bracket(&self) -> f64 {
        let (law, v, z, p) = (self.law, self.v, self.z, self.powers.0);
        law.gamma * v.abs() * p.copysign(z) + law.d * v * p
    }

    /// ż.
    #[inline(always)]
    pub fn rate(&self) -> f64 {
        self.law.alpha * self.v - self.law.beta * self.bracket()
    }

    /// `(∂ż/∂v, ∂ż/∂z)`.
    #[inline(always)]
    pub fn slopes(&self) -> (f64, f64) {
        let (law, v, z) = (self.law, self.v, self.z);
        let (p, q) = self.powers;
        let dv = law.alpha - law.beta * (law.gamma * p.copysign(z) * sign(v) + law.d * p);
        let dz = -law.beta * law.n * q * (law.gamma * v.abs() + law.d * v * sign(z));
        (dv, dz)
    }

    /// `∂ż/∂key`.
    #[inline(always)]
    pub fn derivative(&self, key: HysteresisKey) -> f64 {
        let (law, v, z, p) = (self.law, self.v, self.z, self.powers.0);
        match key {
            HysteresisKey::Alpha => v,
            HysteresisKey::Beta => -self.bracket(),
            HysteresisKey::Gamma => -law.beta * v.abs() * p.copysign(z),
            HysteresisKey::D => -law.beta * v * p,
            HysteresisKey::N => -law.beta * self.bracket() * log_abs(z),
        }
    }
}

/// `sign(x)` with `sign(0) = 0`.
#[inline(always)]
fn sign(x: f64) -> f64 {
    match x {
        x if x > 0.0 => 1.0,
        x if x < 0.0 => -1.0,
        _ => 0.0,
    }
}

/// The Bouc–Wen components of `model`'s component rows (in order) with
/// their laws at the parameter values `p`.
pub(crate) fn hysteresis_rows(
    model: &Model,
    components: &[super::structure::ComponentRow],
    p: &[f64],
) -> Result<Vec<HysteresisRow>, SimulationError> {
    let mut rows = Vec::new();
    for (i, c) in components.iter().enumerate() {
        if let Law::BoucWen(bw) = &c.law {
            let element = &model.elements[c.element].name;
            rows.push(HysteresisRow {
                comp: i,
                law: BoucWenLaw::new(bw, p, element)?,
            });
        }
    }
    Ok(rows)
}

/// Adds `z_j (−M⁻¹B_jᵀ)` of each Bouc–Wen component j to the accelerations
/// `acc`, for the internal states `z` (empty: z = 0).
#[inline(always)]
pub(crate) fn hysteresis_accel<M: Madd>(
    comps: &[SparseComp],
    rows: &[HysteresisRow],
    z: &[f64],
    acc: &mut [f64],
) {
    for (row, &z) in rows.iter().zip(z) {
        let c = &comps[row.comp];
        let [o0, o1] = c.off;
        for i in 0..6 {
            acc[o0 + i] = M::madd(z, c.g[i], acc[o0 + i]);
        }
        for i in 0..6 {
            acc[o1 + i] = M::madd(z, c.g[6 + i], acc[o1 + i]);
        }
    }
}

/// ż of each Bouc–Wen component into `zdot`, for the velocities `v` and
/// the internal states `z`.
#[inline(always)]
pub(crate) fn hysteresis_rates<M: Madd>(
    comps: &[SparseComp],
    rows: &[HysteresisRow],
    (v, z): (&[f64], &[f64]),
    zdot: &mut [f64],
) {
    for ((row, &z), zd) in rows.iter().zip(z).zip(zdot) {
        *zd = row.law.rate(comps[row.comp].rate::<M>(v), z);
    }
}

/// The Bouc–Wen terms of the sensitivities' right-hand side, for rows
/// `width` long: `dacc += Σ_j (−M⁻¹B_jᵀ) Y_z[j]` (n rows), and
/// `dz[j] = ∂ż/∂v B_j Y_v + ∂ż/∂z Y_z[j] + ∂ż_j/∂x` (one row per
/// component); `usages[j]` lists (column, key) of the parameters acting on
/// component j's law.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn hysteresis_tangent<M: Madd>(
    comps: &[SparseComp],
    rows: &[HysteresisRow],
    usages: &[Vec<(usize, HysteresisKey)>],
    (v, z): (&[f64], &[f64]),
    (yv, yz): (&[f64], &[f64]),
    width: usize,
    dacc: &mut [f64],
    dz: &mut [f64],
) {
    for (j, row) in rows.iter().enumerate() {
        let c = &comps[row.comp];
        let yzj = &yz[j * width..(j + 1) * width];
        let out = &mut dz[j * width..(j + 1) * width];
        let at = row.law.at(c.rate::<M>(v), z[j]);
        let (sv, sz) = at.slopes();
        for (o, y) in out.iter_mut().zip(yzj) {
            *o = sz * y;
        }
        for (i, (&b, &g)) in c.b.iter().zip(&c.g).enumerate() {
            if b == 0.0 && g == 0.0 {
                continue;
            }
            let at = (c.off[i / 6] + i % 6) * width;
            let (yvi, acc) = (&yv[at..at + width], &mut dacc[at..at + width]);
            for l in 0..width {
                out[l] = M::madd(sv * b, yvi[l], out[l]);
                acc[l] = M::madd(g, yzj[l], acc[l]);
            }
        }
        for &(col, key) in &usages[j] {
            out[col] += at.derivative(key);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law(n: f64) -> BoucWenLaw {
        BoucWenLaw {
            alpha: 5e4,
            beta: 1e3,
            gamma: 0.8,
            d: -1.1,
            n,
        }
    }

    /// The slopes and every key's derivative against central differences,
    /// away from the kinks at v = 0 and z = 0.
    #[test]
    fn derivatives_match_central_differences() {
        for n in [1.0, 1.5, 2.0] {
            let bw = law(n);
            for (v, z) in [(0.02, 3.0), (-0.03, 2.0), (0.01, -4.0), (-0.05, -1.5)] {
                let (sv, sz) = bw.at(v, z).slopes();
                let h = 1e-6;
                let fv = (bw.rate(v + h * v.abs(), z) - bw.rate(v - h * v.abs(), z))
                    / (2.0 * h * v.abs());
                let fz = (bw.rate(v, z + h) - bw.rate(v, z - h)) / (2.0 * h);
                assert!(
                    (sv - fv).abs() <= 1e-6 * sv.abs().max(1.0),
                    "∂v: {sv} vs {fv}"
                );
                assert!(
                    (sz - fz).abs() <= 1e-6 * sz.abs().max(1.0),
                    "∂z: {sz} vs {fz}"
                );
                for key in [
                    HysteresisKey::Alpha,
                    HysteresisKey::Beta,
                    HysteresisKey::Gamma,
                    HysteresisKey::D,
                    HysteresisKey::N,
                ] {
                    let at = |s: f64| {
                        let mut b = bw;
                        let x = match key {
                            HysteresisKey::Alpha => &mut b.alpha,
                            HysteresisKey::Beta => &mut b.beta,
                            HysteresisKey::Gamma => &mut b.gamma,
                            HysteresisKey::D => &mut b.d,
                            HysteresisKey::N => &mut b.n,
                        };
                        *x *= 1.0 + s;
                        b.rate(v, z)
                    };
                    let x0 = match key {
                        HysteresisKey::Alpha => bw.alpha,
                        HysteresisKey::Beta => bw.beta,
                        HysteresisKey::Gamma => bw.gamma,
                        HysteresisKey::D => bw.d,
                        HysteresisKey::N => bw.n,
                    };
                    let fd = (at(h) - at(-h)) / (2.0 * h * x0);
                    let exact = bw.at(v, z).derivative(key);
                    let tol = 1e-6 * exact.abs().max(1e-3);
                    assert!(
                        (exact - fd).abs() <= tol,
                        "{key:?}, n = {n}: {exact} vs {fd}"
                    );
                }
            }
        }
    }

    /// Under a constant velocity from z = 0, z tends to the plateau where
    /// ż = 0: for v > 0 and n = 1, `z = α / (β (γ + d))` (γ + d > 0), and
    /// the rate there is zero.
    #[test]
    fn the_plateau_is_where_the_rate_vanishes() {
        let bw = BoucWenLaw { d: 0.3, ..law(1.0) };
        let z = 5e4 / (1e3 * (0.8 + 0.3));
        assert!(bw.rate(0.01, z).abs() < 1e-9 * 5e4 * 0.01);
    }

    /// An exponent below 1 is refused as a bad value.
    #[test]
    fn an_exponent_below_one_is_refused() {
        use crate::model::Value;
        let bw = BoucWen {
            k: Value::Fixed(0.0),
            alpha: Value::Fixed(1.0),
            beta: Value::Fixed(1.0),
            gamma: Value::Fixed(1.0),
            d: Value::Fixed(1.0),
            n: Value::Fixed(0.5),
        };
        assert!(BoucWenLaw::new(&bw, &[], "e").unwrap_err().is_bad_values());
    }
}
