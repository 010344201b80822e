//! The friction law (SPEC §1) at one parameter point: its force as a
//! function of the component's velocity v = δ̇, the force's slope in v (the
//! sensitivities' Jacobian, eq. 27–28) and its derivatives with respect to
//! each key, shared by the dense and the element-by-element kernels.
//!
//! `φ(v) = F(v) tanh(v / v_s)`, `F = F₀ (1 − e) + f_s e`,
//! `F₀ = ½(f + f_neg) + ½(f − f_neg) tanh(v / v_s)`, `e = exp(−(v / v_s')²)`
//! (e = 0 without Stribeck's peak). Every term is smooth in v and in the
//! keys, so the integrator keeps its order through v = 0 and the criterion
//! stays smooth in the parameters.
use super::{JointLaw, KeyDims, KeyReader, KeyRole, KeyUnit, Law, LawKey, ReadLaw};
use crate::model::Value;
use crate::simulation::SimulationError;

/// The friction law of one component (SPEC §1): the Coulomb force F
/// smoothed by `tanh(v / v_s)`, asymmetric with `f_neg`, with Stribeck's
/// peak `F(v) = F₀(v) + (f_s − F₀(v)) exp(−(v/v_s')²)`, and a parallel
/// spring k. The component's `c` adds viscous friction.
///
/// An asymmetric Coulomb force switches smoothly with the same sign
/// function, `F₀(v) = ½(f + f_neg) + ½(f − f_neg) tanh(v / v_s)`: f for
/// v ≫ v_s, f_neg for v ≪ −v_s, and the force stays smooth in v (a step
/// across v = 0 keeps the integrator's order).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Friction {
    /// Parallel stiffness k (N/m or N·m/rad); 0 when absent.
    pub k: Value,
    /// Coulomb force f for v > 0 (N, or N·m for a rotation).
    pub f: Value,
    /// Coulomb force for v < 0; f when absent (symmetric friction).
    pub f_neg: Option<Value>,
    /// Stribeck: the static (break-away) force f_s and its velocity v_s'.
    pub stribeck: Option<(Value, Value)>,
    /// The smoothing velocity v_s of the sign (m/s or rad/s).
    pub smoothing: Value,
}

impl JointLaw for Friction {
    fn name(&self) -> &'static str {
        Self::NAME
    }
    fn formula(&self) -> String {
        "friction F(v)·tanh(v/v<sub>s</sub>)".into()
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
        keys.push(LawKey::new(
            "f",
            "f",
            self.f,
            KeyUnit::Force,
            KeyRole::Friction(FrictionKey::Coulomb),
        ));
        if let Some(f_neg) = self.f_neg {
            keys.push(LawKey::new(
                "f_neg",
                "f<sub>neg</sub>",
                f_neg,
                KeyUnit::Force,
                KeyRole::Friction(FrictionKey::CoulombNegative),
            ));
        }
        if let Some((fs, vs)) = self.stribeck {
            keys.push(LawKey::new(
                "fs",
                "f<sub>s</sub>",
                fs,
                KeyUnit::Force,
                KeyRole::Friction(FrictionKey::Static),
            ));
            keys.push(LawKey::new(
                "vs",
                "v<sub>s</sub>'",
                vs,
                KeyUnit::Velocity,
                KeyRole::Friction(FrictionKey::StribeckVelocity),
            ));
        }
        keys.push(LawKey::new(
            "smoothing",
            "v<sub>s</sub>",
            self.smoothing,
            KeyUnit::Velocity,
            KeyRole::Friction(FrictionKey::Smoothing),
        ));
        keys
    }
    fn linear_stiffness(&self, p: &[f64]) -> Option<f64> {
        Some(self.k.eval(p))
    }
    fn is_spring(&self, p: &[f64]) -> bool {
        self.k.eval(p) != 0.0
    }
    /// At rest the force's slope `F(0)/v_s` is a damping.
    fn small_motion(&self, p: &[f64]) -> (f64, f64) {
        (0.0, self.at_rest(p).slope)
    }
    fn switches(&self) -> bool {
        true
    }
}

impl ReadLaw for Friction {
    const NAME: &'static str = "friction";
    const KEYS: &'static [&'static str] = &["k", "f", "f_neg", "fs", "vs", "smoothing"];
    const IMPLIED_BY: &'static [&'static str] = &["f"];

    /// A Coulomb force `f ≥ 0`, optional `f_neg ≥ 0`, Stribeck's `fs` and
    /// `vs` together, the smoothing velocity (default 1 mm/s, or 1 mrad/s
    /// for a rotation) and an optional parallel spring `k`.
    fn read<E>(keys: &mut dyn KeyReader<Error = E>) -> Result<Law, E> {
        let dims = KeyDims::of(keys.rotational());
        let f = keys.required("f", dims.force)?;
        let f_neg = keys.value("f_neg", dims.force)?;
        let stribeck = match (keys.given("fs"), keys.given("vs")) {
            (true, true) => {
                let fs = keys.required("fs", dims.force)?;
                Some((fs, keys.required("vs", dims.velocity)?))
            }
            (false, false) => None,
            (fs, _) => {
                let (given, other) = if fs { ("fs", "vs") } else { ("vs", "fs") };
                let message = format!("Stribeck friction needs both fs and vs: add '{other}'");
                return Err(keys.refuse(given, message));
            }
        };
        let smoothing = keys.value("smoothing", dims.velocity)?;
        let k = keys.value("k", dims.stiffness)?;
        Ok(Law::Friction(Friction {
            k: k.unwrap_or(Value::Fixed(0.0)),
            f,
            f_neg,
            stribeck,
            smoothing: smoothing.unwrap_or(Value::Fixed(1e-3)),
        }))
    }
}

/// A friction law's force slope at v = 0 and what its derivatives in the
/// keys need.
struct AtRest {
    /// `F(0) / v_s`.
    slope: f64,
    /// `F(0)`: f_s with Stribeck's peak, else ½(f + f_neg).
    f_rest: f64,
    /// `1 / v_s`.
    inv_s: f64,
}

impl Friction {
    /// [`AtRest`] at the parameter values `p`.
    fn at_rest(&self, p: &[f64]) -> AtRest {
        let f = self.f.eval(p);
        let f_neg = self.f_neg.map_or(f, |v| v.eval(p));
        let inv_s = 1.0 / self.smoothing.eval(p);
        let f_rest = match self.stribeck {
            Some((fs, _)) => fs.eval(p),
            None => 0.5 * (f + f_neg),
        };
        AtRest {
            slope: f_rest * inv_s,
            f_rest,
            inv_s,
        }
    }

    /// `∂(F(0)/v_s)/∂key` at the parameter values `p`: the derivative of
    /// the small-motion damping ([`JointLaw::small_motion`]).
    pub fn rest_slope_derivative(&self, p: &[f64], key: FrictionKey) -> f64 {
        let at = self.at_rest(p);
        let (stribeck, asymmetric) = (self.stribeck.is_some(), self.f_neg.is_some());
        match key {
            FrictionKey::Coulomb if stribeck => 0.0,
            FrictionKey::Coulomb if asymmetric => 0.5 * at.inv_s,
            FrictionKey::Coulomb => at.inv_s,
            FrictionKey::CoulombNegative if stribeck => 0.0,
            FrictionKey::CoulombNegative => 0.5 * at.inv_s,
            FrictionKey::Static => at.inv_s,
            FrictionKey::StribeckVelocity => 0.0,
            FrictionKey::Smoothing => -at.f_rest * at.inv_s * at.inv_s,
        }
    }
}

/// The keys of a friction law (SPEC §1) a parameter may stand for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrictionKey {
    /// `f`, the Coulomb force (for v > 0 when `f_neg` is given).
    Coulomb,
    /// `f_neg`, the Coulomb force for v < 0.
    CoulombNegative,
    /// `fs`, Stribeck's break-away force.
    Static,
    /// `vs`, Stribeck's velocity.
    StribeckVelocity,
    /// `smoothing`, the velocity of the smooth sign.
    Smoothing,
}

/// A friction law with numbers in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FrictionForce {
    /// `½(f + f_neg)`.
    mean: f64,
    /// `½(f − f_neg)`.
    half: f64,
    /// Whether f_neg is f itself (no `f_neg` key).
    symmetric: bool,
    /// Whether Stribeck's peak is present.
    stribeck: bool,
    /// The break-away force f_s.
    fs: f64,
    /// `1 / v_s'` (Stribeck's velocity).
    inv_vs: f64,
    /// `1 / v_s` (the smoothing velocity).
    inv_s: f64,
}

/// The terms every evaluation shares at velocity v.
#[derive(Debug, Clone, Copy)]
struct Terms {
    /// `tanh(v / v_s)`.
    t: f64,
    /// Stribeck's `exp(−(v / v_s')²)`, 0 without it.
    e: f64,
    /// F₀(v).
    f0: f64,
    /// F(v).
    f: f64,
}

impl FrictionForce {
    /// The law `fr` at the parameter values `p`, refusing a negative force
    /// or a velocity scale that is not positive (element `element`).
    pub fn new(fr: &Friction, p: &[f64], element: &str) -> Result<Self, SimulationError> {
        let bad = |key: &'static str, value: f64| SimulationError::BadFriction {
            element: element.to_owned(),
            key,
            value,
        };
        let f = fr.f.eval(p);
        let f_neg = fr.f_neg.map_or(f, |v| v.eval(p));
        let s = fr.smoothing.eval(p);
        let (fs, vs) = fr
            .stribeck
            .map_or((0.0, 1.0), |(a, b)| (a.eval(p), b.eval(p)));
        for (key, value) in [("f", f), ("f_neg", f_neg), ("fs", fs)] {
            if !(value >= 0.0) {
                return Err(bad(key, value));
            }
        }
        for (key, value) in [("smoothing", s), ("vs", vs)] {
            if !(value > 0.0) {
                return Err(bad(key, value));
            }
        }
        Ok(FrictionForce {
            mean: 0.5 * (f + f_neg),
            half: 0.5 * (f - f_neg),
            symmetric: fr.f_neg.is_none(),
            stribeck: fr.stribeck.is_some(),
            fs,
            inv_vs: 1.0 / vs,
            inv_s: 1.0 / s,
        })
    }

    /// The terms at velocity v.
    #[inline(always)]
    fn terms(&self, v: f64) -> Terms {
        let t = (v * self.inv_s).tanh();
        let f0 = self.mean + self.half * t;
        let (e, f) = match self.stribeck {
            true => {
                let x = v * self.inv_vs;
                let e = super::exp_kept(-x * x);
                (e, f0 + (self.fs - f0) * e)
            }
            false => (0.0, f0),
        };
        Terms { t, e, f0, f }
    }

    /// The law at velocity v: its terms evaluated once, for the force, the
    /// slope and the derivatives there.
    #[inline(always)]
    pub fn at(&self, v: f64) -> FrictionAt<'_> {
        FrictionAt {
            law: self,
            v,
            terms: self.terms(v),
        }
    }

    /// The force φ(v).
    #[inline(always)]
    pub fn force(&self, v: f64) -> f64 {
        self.at(v).force()
    }
}

/// A friction law at one velocity ([`FrictionForce::at`]), or
/// [`FrictionAt::NONE`] for a component without one.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FrictionAt<'a> {
    law: &'a FrictionForce,
    v: f64,
    terms: Terms,
}

/// A law of zero force: every number in it zero.
const NO_FRICTION: FrictionForce = FrictionForce {
    mean: 0.0,
    half: 0.0,
    symmetric: true,
    stribeck: false,
    fs: 0.0,
    inv_vs: 0.0,
    inv_s: 0.0,
};

impl FrictionAt<'static> {
    /// No friction: force, slope and every derivative zero, from terms
    /// that are all defined.
    ///
    /// The kernels take this rather than an `Option`: a `None` leaves the
    /// terms undefined, the compiler hoists the (cheap, pure) derivative
    /// arithmetic out of the kernels' loops and runs it on whatever a
    /// register holds, and a subnormal there costs a microcode assist per
    /// operation. That made every run with sensitivities of a model
    /// without friction 3.5 times slower (docs/benchmarks.md).
    pub const NONE: FrictionAt<'static> = FrictionAt {
        law: &NO_FRICTION,
        v: 0.0,
        terms: Terms {
            t: 0.0,
            e: 0.0,
            f0: 0.0,
            f: 0.0,
        },
    };
}

impl<'a> FrictionAt<'a> {
    /// The law `law` at the velocity `rate()` (evaluated only with a law),
    /// or [`FrictionAt::NONE`] without one.
    #[inline(always)]
    pub fn of(law: Option<&'a FrictionForce>, rate: impl FnOnce() -> f64) -> FrictionAt<'a> {
        match law {
            Some(law) => law.at(rate()),
            None => FrictionAt::NONE,
        }
    }

    /// The force φ(v).
    #[inline(always)]
    pub fn force(&self) -> f64 {
        let Terms { t, f, .. } = self.terms;
        f * t
    }

    /// `dφ/dv`: the component's tangent damping.
    #[inline(always)]
    pub fn slope(&self) -> f64 {
        let (law, v) = (self.law, self.v);
        let Terms { t, e, f0, f } = self.terms;
        let dt = (1.0 - t * t) * law.inv_s;
        let df0 = law.half * dt;
        let df = match law.stribeck {
            true => df0 * (1.0 - e) + (law.fs - f0) * (-2.0 * v * law.inv_vs * law.inv_vs * e),
            false => df0,
        };
        df * t + f * dt
    }

    /// `∂φ/∂key` at velocity v.
    #[inline(always)]
    pub fn derivative(&self, key: FrictionKey) -> f64 {
        let (law, v) = (self.law, self.v);
        let Terms { t, e, f0, f } = self.terms;
        match key {
            FrictionKey::Coulomb if law.symmetric => (1.0 - e) * t,
            FrictionKey::Coulomb => (1.0 - e) * t * 0.5 * (1.0 + t),
            FrictionKey::CoulombNegative => (1.0 - e) * t * 0.5 * (1.0 - t),
            FrictionKey::Static => e * t,
            FrictionKey::StribeckVelocity => {
                // ∂e/∂v_s' = 2 e v² / v_s'³.
                let x = v * law.inv_vs;
                (law.fs - f0) * t * 2.0 * e * x * x * law.inv_vs
            }
            FrictionKey::Smoothing => {
                // ∂t/∂v_s = −(v / v_s²)(1 − t²); φ depends on t through F₀ too.
                let dt = -v * law.inv_s * law.inv_s * (1.0 - t * t);
                (f + t * (1.0 - e) * law.half) * dt
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Value;

    fn law(f_neg: Option<f64>, stribeck: Option<(f64, f64)>) -> (Friction, Vec<f64>) {
        // Every key a parameter, so that each can be perturbed.
        let p = vec![0.0, 40.0, f_neg.unwrap_or(0.0), 0.0, 0.0, 2e-3];
        let mut p = p;
        let stribeck = stribeck.map(|(fs, vs)| {
            p[3] = fs;
            p[4] = vs;
            (Value::Param(3), Value::Param(4))
        });
        let fr = Friction {
            k: Value::Param(0),
            f: Value::Param(1),
            f_neg: f_neg.map(|_| Value::Param(2)),
            stribeck,
            smoothing: Value::Param(5),
        };
        (fr, p)
    }

    /// The slope and every key's derivative against central differences.
    #[test]
    fn derivatives_match_central_differences() {
        let keys = [
            (FrictionKey::Coulomb, 1),
            (FrictionKey::CoulombNegative, 2),
            (FrictionKey::Static, 3),
            (FrictionKey::StribeckVelocity, 4),
            (FrictionKey::Smoothing, 5),
        ];
        for (f_neg, stribeck) in [
            (None, None),
            (Some(25.0), None),
            (None, Some((60.0, 5e-3))),
            (Some(25.0), Some((60.0, 5e-3))),
        ] {
            let (fr, p) = law(f_neg, stribeck);
            let at = |p: &[f64]| FrictionForce::new(&fr, p, "e").unwrap();
            let ff = at(&p);
            for v in [-3e-2, -4e-3, -1e-3, -1e-4, 0.0, 2e-4, 1.5e-3, 6e-3, 5e-2] {
                let h = 1e-7;
                let fd = (ff.force(v + h) - ff.force(v - h)) / (2.0 * h);
                let scale = 40.0 / 2e-3;
                assert!(
                    (ff.at(v).slope() - fd).abs() <= 1e-6 * scale,
                    "slope at {v}"
                );
                for &(key, i) in &keys {
                    let used = match key {
                        FrictionKey::CoulombNegative => f_neg.is_some(),
                        FrictionKey::Static | FrictionKey::StribeckVelocity => stribeck.is_some(),
                        _ => true,
                    };
                    if !used {
                        continue;
                    }
                    let h = 1e-6 * p[i];
                    let (mut up, mut down) = (p.clone(), p.clone());
                    up[i] += h;
                    down[i] -= h;
                    let fd = (at(&up).force(v) - at(&down).force(v)) / (2.0 * h);
                    let exact = ff.at(v).derivative(key);
                    let tol = 1e-7 * (1.0 + fd.abs()) * (60.0 / p[i]).max(1.0);
                    assert!(
                        (exact - fd).abs() <= tol,
                        "{key:?} at v = {v}: {exact} vs {fd}"
                    );
                }
            }
        }
    }

    /// Far from v = 0 the force is the Coulomb force of each side, and the
    /// Stribeck peak has decayed; at v = 0 it is zero.
    #[test]
    fn limits_are_the_coulomb_forces() {
        let (fr, p) = law(Some(25.0), Some((60.0, 5e-3)));
        let ff = FrictionForce::new(&fr, &p, "e").unwrap();
        assert_eq!(ff.force(0.0), 0.0);
        assert!((ff.force(1.0) - 40.0).abs() < 1e-12);
        assert!((ff.force(-1.0) + 25.0).abs() < 1e-12);
        // Near v_s' the force exceeds the Coulomb force (the peak).
        assert!(ff.force(4e-3) > 40.0);
    }

    /// A negative force or a velocity scale that is not positive is a bad
    /// value, named.
    #[test]
    fn bad_values_are_refused() {
        let (fr, mut p) = law(None, Some((60.0, 5e-3)));
        p[5] = 0.0;
        let e = FrictionForce::new(&fr, &p, "slide").unwrap_err();
        assert!(e.is_bad_values());
        assert!(e.to_string().contains("slide") && e.to_string().contains("smoothing"));
        p[5] = 1e-3;
        p[1] = -1.0;
        assert!(FrictionForce::new(&fr, &p, "slide").is_err());
    }
}
