//! The power-law spring `f = a · sign(δ) · (|δ|/δ_ref)^m` (eq. 6, extended
//! oddly; δ_ref = 1 m gives eq. 6 itself), the slideway contact law: the
//! model's law, what it says of itself, and its force and slope
//! ([`power_law`]), the kernels' fast path.
use super::{JointLaw, KeyDims, KeyReader, KeyRole, KeyUnit, Law, LawKey, ReadLaw};
use crate::model::Value;
use crate::units::Dimension;

/// A power-law spring.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Power {
    /// Coefficient a: N/m^m when δ_ref = 1 m, else the force at δ_ref.
    pub a: Value,
    /// Exponent m (usually 1–3).
    pub m: Value,
    /// The reference deformation δ_ref (m, or rad for a rotation); 1 by
    /// default. A δ_ref near the deformations of the tests decorrelates
    /// the estimates of a and m, which for δ in metres are nearly
    /// proportional in effect (∂f/∂m = f · ln(|δ|/δ_ref)).
    pub reference: f64,
}

impl Power {
    /// The spring at the parameter values `p`.
    #[inline]
    pub fn spring(&self, p: &[f64]) -> PowerSpring {
        PowerSpring::new(self.a.eval(p), self.m.eval(p), self.reference)
    }
}

impl JointLaw for Power {
    fn name(&self) -> &'static str {
        Self::NAME
    }
    fn formula(&self) -> String {
        match self.reference == 1.0 {
            true => "a·sign(δ)|δ|<sup>m</sup>".into(),
            false => "a·sign(δ)(|δ|/δ<sub>ref</sub>)<sup>m</sup>".into(),
        }
    }
    fn keys(&self) -> Vec<LawKey> {
        let mut keys = vec![
            LawKey::new("a", "a", self.a, KeyUnit::Bare, KeyRole::PowerCoefficient),
            LawKey::new("m", "m", self.m, KeyUnit::Bare, KeyRole::PowerExponent),
        ];
        if self.reference != 1.0 {
            keys.push(LawKey {
                name: "reference",
                symbol: "δ<sub>ref</sub>",
                value: Value::Fixed(self.reference),
                unit: KeyUnit::Length,
                role: None,
            });
        }
        keys
    }
    fn is_spring(&self, p: &[f64]) -> bool {
        self.a.eval(p) != 0.0
    }
}

impl ReadLaw for Power {
    const NAME: &'static str = "power";
    const KEYS: &'static [&'static str] = &["a", "m", "reference"];
    const IMPLIED_BY: &'static [&'static str] = &["a", "m"];

    /// The exponent `m ≥ 1`, the reference deformation (positive, 1 when
    /// absent) and `a ≥ 0`: with a reference deformation δ_ref, a is the
    /// force (moment) at δ_ref; without, a multiplies |δ|^m with δ in m
    /// (rad).
    fn read<E>(keys: &mut dyn KeyReader<Error = E>) -> Result<Law, E> {
        let dims = KeyDims::of(keys.rotational());
        let m = keys.required("m", Dimension::DIMENSIONLESS)?;
        let m_nominal = keys.nominal(m);
        let reference = match keys.number("reference", dims.length)? {
            None => 1.0,
            Some(r) if r > 0.0 => r,
            Some(r) => {
                let message = format!("the reference deformation must be positive (found {r})");
                return Err(keys.refuse("reference", message));
            }
        };
        let a_dim = if keys.rotational() {
            Dimension::MOMENT
        } else if keys.given("reference") {
            Dimension::FORCE
        } else {
            Dimension::FORCE.div(Dimension::LENGTH.powf(m_nominal))
        };
        let a = keys.required("a", a_dim)?;
        Ok(Law::Power(Power { a, m, reference }))
    }
}

/// A power-law spring `f = coef · sign(δ)|δ|^m` at given parameter values,
/// with what the derivatives with respect to a and m need (eq. 6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PowerSpring {
    /// `a · δ_ref^(−m)`, the coefficient of `sign(δ)|δ|^m` (SI).
    pub coef: f64,
    /// The exponent m.
    pub m: f64,
    /// `δ_ref^(−m)` = ∂coef/∂a.
    pub per_a: f64,
    /// `ln δ_ref`: ∂f/∂m = f · (ln|δ| − ln δ_ref).
    pub ln_ref: f64,
}

impl PowerSpring {
    /// The spring of coefficient `a`, exponent `m` and reference deformation
    /// `reference` (exactly eq. 6 for `reference` = 1).
    #[inline]
    pub fn new(a: f64, m: f64, reference: f64) -> PowerSpring {
        let per_a = reference.powf(-m);
        PowerSpring {
            coef: a * per_a,
            m,
            per_a,
            ln_ref: reference.ln(),
        }
    }
}

/// The force of the power law and its slope, `(a sign(δ)|δ|^m, m a |δ|^(m−1))`.
#[inline(never)]
pub fn power_law(a: f64, m: f64, d: f64) -> (f64, f64) {
    let ad = d.abs();
    if m == 2.0 {
        (a * d * ad, 2.0 * a * ad)
    } else if m == 3.0 {
        // A cubic spring (a Duffing oscillator's): products, not a power.
        (a * d * ad * ad, 3.0 * a * ad * ad)
    } else if m == 1.0 {
        (a * d, a)
    } else if m == 1.5 {
        // Hertz's exponent: a square root instead of a power, the same to
        // rounding and several times faster.
        let p = ad.sqrt();
        (a * p * d, a * m * p)
    } else if ad == 0.0 {
        (0.0, 0.0)
    } else {
        let p = super::powf_kept(ad, m - 1.0);
        (a * p * d, a * m * p)
    }
}

#[cfg(test)]
mod tests {
    use super::power_law;

    /// The exponents with products or a square root for the power agree
    /// with the general `powf` form to rounding, on both sides of δ = 0.
    #[test]
    fn special_exponents_match_the_general_power() {
        for m in [1.0, 1.5, 2.0, 3.0] {
            for d in [-2.7e-5, -0.31, 0.0, 4.2e-6, 1.9] {
                let (f, k) = power_law(7.3, m, d);
                let ad: f64 = d.abs();
                let p = ad.powf(m - 1.0);
                let (f0, k0) = (7.3 * p * d, 7.3 * m * p);
                assert!(
                    (f - f0).abs() <= 1e-14 * f0.abs(),
                    "m {m}, δ {d}: {f} vs {f0}"
                );
                assert!(
                    (k - k0).abs() <= 1e-14 * k0.abs(),
                    "m {m}, δ {d}: {k} vs {k0}"
                );
            }
        }
    }
}
