//! The Bouc–Wen law (SPEC §1): a component's force `k δ + z` with the
//! internal state z integrated with the motion,
//!
//! `ż = α v − β (γ |v| |z|^(n−1) z + d v |z|^n)`,  z(0) = 0,  v = δ̇,
//!
//! and its sensitivities (eq. 27–28 extended by the rows of ∂z/∂x). The
//! state vector of a run is `[q; q̇; z]`, one z per Bouc–Wen component in
//! component order; the spring k is in the kernels' linear part, z enters
//! the accelerations like a force `z (−M⁻¹B_iᵀ)` after either kernel.
use super::{JointLaw, KeyDims, KeyReader, KeyRole, KeyUnit, Law, LawKey, ReadLaw};
use crate::model::Value;
use crate::simulation::SimulationError;
use crate::units::Dimension;

/// The Bouc–Wen law of one component (SPEC §1): the force `k δ + z`, with
/// `ż = α v − β (γ |v| |z|^(n−1) z + d v |z|^n)`, z(0) = 0, v = δ̇.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoucWen {
    /// The elastic stiffness k (N/m or N·m/rad); 0 when absent.
    pub k: Value,
    /// α (N/m or N·m/rad): ż = α v for z = 0.
    pub alpha: Value,
    /// β, the scale of the hysteretic terms.
    pub beta: Value,
    /// γ, the term in |v|.
    pub gamma: Value,
    /// d (the benchmark's δ), the term in v.
    pub d: Value,
    /// The exponent n ≥ 1 (default 1).
    pub n: Value,
}

impl JointLaw for BoucWen {
    fn name(&self) -> &'static str {
        Self::NAME
    }
    fn formula(&self) -> String {
        "Bouc–Wen k δ + z, ż = α v − β(γ|v||z|<sup>n−1</sup>z + d v|z|<sup>n</sup>)".into()
    }
    fn keys(&self) -> Vec<LawKey> {
        let mut keys = Vec::new();
        if self.k != Value::Fixed(0.0) {
            keys.push(LawKey::new(
                "k",
                "k",
                self.k,
                KeyUnit::Stiffness,
                KeyRole::Stiffness,
            ));
        }
        let hysteresis =
            |name, symbol, value, unit, usage| LawKey::new(name, symbol, value, unit, usage);
        keys.extend([
            hysteresis(
                "alpha",
                "α",
                self.alpha,
                KeyUnit::Stiffness,
                KeyRole::Hysteresis(HysteresisKey::Alpha),
            ),
            hysteresis(
                "beta",
                "β",
                self.beta,
                KeyUnit::Bare,
                KeyRole::Hysteresis(HysteresisKey::Beta),
            ),
            hysteresis(
                "gamma",
                "γ",
                self.gamma,
                KeyUnit::Bare,
                KeyRole::Hysteresis(HysteresisKey::Gamma),
            ),
            hysteresis(
                "d",
                "d",
                self.d,
                KeyUnit::Bare,
                KeyRole::Hysteresis(HysteresisKey::D),
            ),
            hysteresis(
                "n",
                "n",
                self.n,
                KeyUnit::Bare,
                KeyRole::Hysteresis(HysteresisKey::N),
            ),
        ]);
        keys
    }
    fn linear_stiffness(&self, p: &[f64]) -> Option<f64> {
        Some(self.k.eval(p))
    }
    /// At rest z = 0 and ż = α v: the hysteresis restores like a spring α.
    fn is_spring(&self, p: &[f64]) -> bool {
        self.k.eval(p) != 0.0 || self.alpha.eval(p) != 0.0
    }
    fn small_motion(&self, p: &[f64]) -> (f64, f64) {
        (self.alpha.eval(p), 0.0)
    }
    fn switches(&self) -> bool {
        true
    }
}

impl ReadLaw for BoucWen {
    const NAME: &'static str = "bouc-wen";
    const KEYS: &'static [&'static str] = &["k", "alpha", "beta", "gamma", "d", "n"];
    const IMPLIED_BY: &'static [&'static str] = &["alpha"];

    /// `alpha`, `beta`, `gamma` and `d` required, the exponent `n ≥ 1`
    /// (default 1), an optional spring `k ≥ 0`. β's unit follows n: `ż` is
    /// a force per second, so β γ |v| |z|^n is too (β in 1/m for n = 1).
    fn read<E>(keys: &mut dyn KeyReader<Error = E>) -> Result<Law, E> {
        let dims = KeyDims::of(keys.rotational());
        let n = keys.value("n", Dimension::DIMENSIONLESS)?;
        let n = n.unwrap_or(Value::Fixed(1.0));
        let alpha = keys.required("alpha", dims.stiffness)?;
        let beta_dim = dims.force.powf(1.0 - keys.nominal(n)).div(dims.length);
        let beta = beta(keys, n, beta_dim)?;
        let gamma = keys.required("gamma", Dimension::DIMENSIONLESS)?;
        let d = keys.required("d", Dimension::DIMENSIONLESS)?;
        let k = keys.value("k", dims.stiffness)?;
        Ok(Law::BoucWen(BoucWen {
            k: k.unwrap_or(Value::Fixed(0.0)),
            alpha,
            beta,
            gamma,
            d,
            n,
        }))
    }
}

/// Bouc–Wen's β, of dimension `dim`: N^(1−n)/m at n's value (1/m for
/// n = 1). With n a parameter, whose value the search, `--set` or an
/// experiment's `set` changes, a unit would mean a different β at each n:
/// β is then a bare number (or a parameter with bare numbers), taken in N
/// and m (N·m and rad for a rotation) at every n, and a unit is refused
/// saying so.
fn beta<E>(keys: &mut dyn KeyReader<Error = E>, n: Value, dim: Dimension) -> Result<Value, E> {
    if let Value::Param(ni) = n {
        if keys.given("beta") && keys.has_unit("beta") {
            let si = match keys.rotational() {
                true => "N·m and rad",
                false => "N and m",
            };
            let message = format!(
                "n is the parameter '{}', so beta's unit, N^(1−n)/m ({dim} at n = {}), changes \
                 with n: write beta (or its parameter's value, min and max) as a bare number, \
                 taken in {si} at every n",
                keys.parameter_name(ni),
                keys.nominal(n)
            );
            return Err(keys.refuse("beta", message));
        }
    }
    keys.required("beta", dim)
}

/// The keys of a Bouc–Wen law (SPEC §1) that enter its internal state's
/// rate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HysteresisKey {
    /// `alpha`.
    Alpha,
    /// `beta`.
    Beta,
    /// `gamma`.
    Gamma,
    /// `d`.
    D,
    /// `n`, the exponent.
    N,
}

/// A Bouc–Wen law with numbers in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BoucWenLaw {
    alpha: f64,
    beta: f64,
    gamma: f64,
    d: f64,
    n: f64,
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
        let p = super::powf_kept(a, n);
        (p, p / a)
    }
}

/// `ln|z|` where `|z|^n` multiplies it (0 at z = 0, whose term vanishes).
#[inline(always)]
fn log_abs(z: f64) -> f64 {
    match z == 0.0 {
        true => 0.0,
        false => super::ln_kept(z.abs()),
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
        self.on_branch(v, z, Branch::NATURAL)
    }

    /// The law at v and z on the branches `b` ([`Branch`]): |v| taken as
    /// `s_v v` and sign(v) as s_v, likewise z (for n = 1, whose |z| has the
    /// kink). Within a piece of a step split at a kink, every stage is
    /// evaluated on the piece's side, as the smooth law of that side
    /// continued a little past it: a stage state that strays across the
    /// kink by the step's error would otherwise change the slope by the
    /// whole jump, and the sensitivities with it.
    #[inline(always)]
    pub fn on_branch(&self, v: f64, z: f64, b: Branch) -> BoucWenAt<'_> {
        let sv = Branch::side(b.v, v, b.v_reach);
        let s_z = Branch::side(b.z, z, b.z_reach);
        let (sz, powers) = if s_z != sign(z) && self.n == 1.0 {
            (s_z, (s_z * z, 1.0))
        } else {
            (sign(z), powers(z, self.n))
        };
        BoucWenAt {
            law: self,
            v,
            av: sv * v,
            sv,
            sz,
            z,
            powers,
        }
    }

    /// ż at velocity v and state z.
    #[inline(always)]
    pub fn rate(&self, v: f64, z: f64) -> f64 {
        self.at(v, z).rate()
    }
}

/// The sides of a Bouc–Wen law's kinks to evaluate it on: the signs taken
/// for v and z (0: the value's own sign), each held while the value is on
/// that side or strays past the kink by at most its reach. A stage farther
/// across is on the other side indeed (a step whose trial was far off, as
/// when the motion grows without bound) and takes its own sign.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Branch {
    /// The sign taken for v.
    pub v: f64,
    /// The sign taken for z.
    pub z: f64,
    /// How far past v = 0 the sign holds.
    pub v_reach: f64,
    /// How far past z = 0 the sign holds.
    pub z_reach: f64,
}

impl Branch {
    /// Each value's own sign.
    pub const NATURAL: Branch = Branch {
        v: 0.0,
        z: 0.0,
        v_reach: 0.0,
        z_reach: 0.0,
    };

    /// The sign to take for x: `s` while x is on its side or within
    /// `reach` of 0, else x's own.
    #[inline(always)]
    fn side(s: f64, x: f64, reach: f64) -> f64 {
        let own = sign(x);
        if s != 0.0 && own != s && x.abs() <= reach {
            s
        } else {
            own
        }
    }
}

/// A Bouc–Wen law at one velocity and state ([`BoucWenLaw::at`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct BoucWenAt<'a> {
    law: &'a BoucWenLaw,
    v: f64,
    /// |v| (on its branch).
    av: f64,
    /// sign(v) (on its branch).
    sv: f64,
    /// sign(z) (on its branch).
    sz: f64,
    z: f64,
    /// `(|z|^n, |z|^(n−1))`.
    powers: (f64, f64),
}

impl BoucWenAt<'_> {
    /// `γ |v| |z|^(n−1) z + d v |z|^n`, the bracket of ż.
    #[inline(always)]
    fn bracket(&self) -> f64 {
        let (law, v, p) = (self.law, self.v, self.powers.0);
        law.gamma * self.av * (self.sz * p) + law.d * v * p
    }

    /// ż.
    #[inline(always)]
    pub fn rate(&self) -> f64 {
        self.law.alpha * self.v - self.law.beta * self.bracket()
    }

    /// `(∂ż/∂v, ∂ż/∂z)`.
    #[inline(always)]
    pub fn slopes(&self) -> (f64, f64) {
        let (law, v) = (self.law, self.v);
        let (p, q) = self.powers;
        let dv = law.alpha - law.beta * (law.gamma * (self.sz * p) * self.sv + law.d * p);
        let dz = -law.beta * law.n * q * (law.gamma * self.av + law.d * v * self.sz);
        (dv, dz)
    }

    /// `∂ż/∂key`.
    #[inline(always)]
    pub fn derivative(&self, key: HysteresisKey) -> f64 {
        let (law, v, z, p) = (self.law, self.v, self.z, self.powers.0);
        match key {
            HysteresisKey::Alpha => v,
            HysteresisKey::Beta => -self.bracket(),
            HysteresisKey::Gamma => -law.beta * self.av * (self.sz * p),
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
