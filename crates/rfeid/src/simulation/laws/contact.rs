//! The contact law (SPEC §1): a joint that carries force only while it is
//! closed, as a slideway or a bolted joint lifting off under tension, or a
//! pad separating, does. With s = δ − gap the closure,
//!
//! `f = spring(s) + c δ̇` while s > 0 and that force is compressive
//! (positive), else 0,
//!
//! with `spring(s) = k s`, or the power law `a (s/δ_ref)^m` (eq. 6). A
//! positive gap is open at δ = 0; a negative one is a preload (closed by
//! −gap at δ = 0). The law's own damping c acts only while the contact is
//! closed. The force is continuous where the spring closes from zero force
//! and has a kink there (its slope jumps from 0 to k); the damper's force
//! c δ̇ makes it jump on closing at a speed, which the integrator locates
//! (`stepper`).
use super::power::{power_law, Power, PowerSpring};
use super::{JointLaw, KeyDims, KeyReader, KeyRole, KeyUnit, Law, LawKey, ReadLaw};
use crate::model::Value;
use crate::units::Dimension;

/// A contact: a spring and a damper acting only while the joint is closed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// The spring while closed.
    pub spring: ContactSpring,
    /// The damping c while closed (N·s/m or N·m·s/rad); 0 when absent.
    pub c: Value,
    /// The gap (m, or rad): positive, open at δ = 0; negative, a preload.
    pub gap: Value,
}

/// The spring of a closed contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactSpring {
    /// `k s`.
    Linear(Value),
    /// `a (s/δ_ref)^m` (eq. 6).
    Power(Power),
}

/// The keys of a contact law a parameter may stand for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactKey {
    /// `k`, the closed contact's stiffness.
    Stiffness,
    /// `a`, the power law's coefficient.
    Coefficient,
    /// `m`, the power law's exponent.
    Exponent,
    /// `c`, the closed contact's damping.
    Damping,
    /// `gap`.
    Gap,
}

impl JointLaw for Contact {
    fn name(&self) -> &'static str {
        Self::NAME
    }
    fn formula(&self) -> String {
        let spring = match self.spring {
            ContactSpring::Linear(_) => "k s",
            ContactSpring::Power(p) if p.reference != 1.0 => "a(s/δ<sub>ref</sub>)<sup>m</sup>",
            ContactSpring::Power(_) => "a s<sup>m</sup>",
        };
        format!("contact {spring} + c δ̇ while closed (s = δ − gap > 0), else 0")
    }
    fn keys(&self) -> Vec<LawKey> {
        let key =
            |name, value, unit, key| LawKey::new(name, name, value, unit, KeyRole::Contact(key));
        let mut keys = match self.spring {
            ContactSpring::Linear(k) => {
                vec![key("k", k, KeyUnit::Stiffness, ContactKey::Stiffness)]
            }
            ContactSpring::Power(p) => {
                let mut keys = vec![
                    key("a", p.a, KeyUnit::Bare, ContactKey::Coefficient),
                    key("m", p.m, KeyUnit::Bare, ContactKey::Exponent),
                ];
                if p.reference != 1.0 {
                    keys.push(LawKey {
                        name: "reference",
                        symbol: "δ<sub>ref</sub>",
                        value: Value::Fixed(p.reference),
                        unit: KeyUnit::Length,
                        role: None,
                    });
                }
                keys
            }
        };
        if self.c != Value::Fixed(0.0) {
            keys.push(key("c", self.c, KeyUnit::Damping, ContactKey::Damping));
        }
        keys.push(key("gap", self.gap, KeyUnit::Length, ContactKey::Gap));
        keys
    }
    fn is_spring(&self, p: &[f64]) -> bool {
        match self.spring {
            ContactSpring::Linear(k) => k.eval(p) != 0.0,
            ContactSpring::Power(pw) => pw.a.eval(p) != 0.0,
        }
    }
    fn switches(&self) -> bool {
        true
    }
    fn owns_damping(&self) -> bool {
        true
    }
}

impl ReadLaw for Contact {
    const NAME: &'static str = "contact";
    const KEYS: &'static [&'static str] = &["k", "a", "m", "reference", "c", "gap"];
    const IMPLIED_BY: &'static [&'static str] = &["gap"];

    /// A spring `k`, or a power law `a`, `m` (and `reference`) as
    /// [`Power`] reads them; the damping `c` (0 when absent) and the `gap`
    /// (0 when absent).
    fn read<E>(keys: &mut dyn KeyReader<Error = E>) -> Result<Law, E> {
        let dims = KeyDims::of(keys.rotational());
        let power = keys.given("a") || keys.given("m");
        let spring = match (keys.given("k"), power) {
            (true, true) => {
                let other = if keys.given("a") { "a" } else { "m" };
                let message = "a contact's spring is k, or a and m, not both".to_string();
                return Err(keys.refuse(other, message));
            }
            (true, false) if keys.given("reference") => {
                let message =
                    "'reference' belongs to a power-law contact (a and m), not to k".into();
                return Err(keys.refuse("reference", message));
            }
            (true, false) => ContactSpring::Linear(keys.required("k", dims.stiffness)?),
            (false, true) => match Power::read(keys)? {
                Law::Power(p) => ContactSpring::Power(p),
                _ => unreachable!("the power law reads a power law"),
            },
            (false, false) => {
                let message = "a contact needs a spring: k, or a and m".to_string();
                return Err(keys.refuse("law", message));
            }
        };
        let c_dim = match keys.rotational() {
            true => Dimension::ROTATIONAL_DAMPING,
            false => Dimension::DAMPING,
        };
        let c = keys.value("c", c_dim)?.unwrap_or(Value::Fixed(0.0));
        let gap = keys.value("gap", dims.length)?.unwrap_or(Value::Fixed(0.0));
        Ok(Law::Contact(Contact { spring, c, gap }))
    }
}

/// A contact law with numbers in, and the static deformation a run moves
/// about (`preload`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ContactForce {
    /// The power law's spring (coefficient and exponent), or a linear
    /// spring as the power law of exponent 1.
    spring: PowerSpring,
    /// Whether the spring is linear (`k s`).
    linear: bool,
    /// The damping while closed.
    c: f64,
    /// The gap.
    gap: f64,
    /// The static deformation δ₀ the run moves about (0 without one).
    pub d0: f64,
    /// Whether the run moves about a static state (`System::set_reference`),
    /// whose force the accelerations take as zero; δ₀ may be 0 there and
    /// the force not (a preload balanced at q = 0).
    pub about_rest: bool,
}

/// A contact law evaluated at one deformation and rate.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct ContactAt {
    /// The force.
    pub force: f64,
    /// `∂f/∂δ`.
    pub slope: f64,
    /// `∂f/∂δ̇`.
    pub damping: f64,
    /// The closure s (0 when open).
    s: f64,
    /// The rate δ̇ (0 when open).
    v: f64,
    /// The spring's force at s.
    spring: f64,
}

impl ContactAt {
    /// An open contact: no force, every number zero.
    const ZERO: ContactAt = ContactAt {
        force: 0.0,
        slope: 0.0,
        damping: 0.0,
        s: 0.0,
        v: 0.0,
        spring: 0.0,
    };
}

impl ContactForce {
    /// The law `law` at the parameter values `p`.
    pub fn new(law: &Contact, p: &[f64]) -> ContactForce {
        let (spring, linear) = match law.spring {
            ContactSpring::Linear(k) => (PowerSpring::new(k.eval(p), 1.0, 1.0), true),
            ContactSpring::Power(pw) => (pw.spring(p), false),
        };
        ContactForce {
            spring,
            linear,
            c: law.c.eval(p),
            gap: law.gap.eval(p),
            d0: 0.0,
            about_rest: false,
        }
    }

    /// The spring's force and slope at the closure `s > 0`.
    #[inline]
    fn spring(&self, s: f64) -> (f64, f64) {
        match self.linear {
            true => (self.spring.coef * s, self.spring.coef),
            // Held acting past its closing, a power law stays at zero.
            false => power_law(self.spring.coef, self.spring.m, s.max(0.0)),
        }
    }

    /// The slope's derivative in δ at `at`: 0 for a linear spring,
    /// `m (m−1) coef s^(m−2)` for a power law.
    pub fn curvature(&self, at: &ContactAt) -> f64 {
        let m = self.spring.m;
        match self.linear || at.force == 0.0 || m == 1.0 || at.s <= 0.0 {
            true => 0.0,
            false => m * (m - 1.0) * self.spring.coef * super::powf_kept(at.s, m - 2.0),
        }
    }

    /// `(∂slope/∂key, ∂damping/∂key)` at `at`: the derivatives of the
    /// stiffness and damping a closed contact adds for small motions (the
    /// FRF's linearisation).
    pub fn small_motion_derivative(&self, at: &ContactAt, key: ContactKey) -> (f64, f64) {
        if at.force == 0.0 {
            return (0.0, 0.0);
        }
        let m = self.spring.m;
        match key {
            ContactKey::Stiffness => (1.0, 0.0),
            // Held acting past its closing (s ≤ 0), a power law's spring is
            // zero with its slope (`spring`), whatever a and m.
            ContactKey::Coefficient | ContactKey::Exponent if at.s <= 0.0 => (0.0, 0.0),
            ContactKey::Coefficient => (self.spring.per_a * power_law(1.0, m, at.s).1, 0.0),
            ContactKey::Exponent => (
                at.slope * (1.0 / m + super::ln_kept(at.s) - self.spring.ln_ref),
                0.0,
            ),
            ContactKey::Damping => (0.0, 1.0),
            ContactKey::Gap => (-self.curvature(at), 0.0),
        }
    }

    /// The law at the deformation `d` (absolute) and rate `v`.
    #[inline]
    pub fn at(&self, d: f64, v: f64) -> ContactAt {
        self.at_side(d, v, 0.0)
    }

    /// [`Self::at`] held acting (`side` > 0: the spring and the damper,
    /// whatever the signs of the closure and the force) or not (`side` < 0:
    /// no force), or on its own side (`side` 0: acting while closed and
    /// pushing): the side a piece of a split step is evaluated on next to
    /// a located opening or closing (`contact_events`), where rounding may
    /// leave either sign.
    #[inline]
    pub fn at_side(&self, d: f64, v: f64, side: f64) -> ContactAt {
        let s = d - self.gap;
        if side < 0.0 || (side == 0.0 && !(s > 0.0)) {
            return ContactAt::default();
        }
        let (spring, slope) = self.spring(s);
        let force = spring + self.c * v;
        if side == 0.0 && !(force > 0.0) {
            return ContactAt::default();
        }
        ContactAt {
            force,
            slope,
            damping: self.c,
            s,
            v,
            spring,
        }
    }

    /// The force of the spring and the damper, acting, and the spring's
    /// slope, at the closure `s` and rate `v`: the function whose zero,
    /// closed, opens the contact.
    #[inline]
    pub fn raw(&self, s: f64, v: f64) -> (f64, f64) {
        let (spring, slope) = self.spring(s);
        (spring + self.c * v, slope)
    }

    /// The damping c while closed.
    #[inline]
    pub fn damping(&self) -> f64 {
        self.c
    }

    /// The exponent of the spring (1 for a linear one).
    pub fn exponent(&self) -> f64 {
        self.spring.m
    }

    /// The closure `δ − gap` at the absolute deformation `d`.
    pub fn closure_at(&self, d: f64) -> f64 {
        d - self.gap
    }

    /// The closure `δ − gap` at the deformation `d` from the static one.
    #[inline]
    pub fn closure(&self, d: f64) -> f64 {
        self.d0 + d - self.gap
    }

    /// The force's change from the static one, at the deformation `d` from
    /// the static deformation and rate `v`: what the accelerations take
    /// about the static equilibrium (`preload`).
    #[inline]
    pub fn force_change(&self, d: f64, v: f64, side: f64) -> f64 {
        if !self.about_rest {
            return self.at_side(d, v, side).force;
        }
        self.at_side(self.d0 + d, v, side).force - self.at(self.d0, 0.0).force
    }

    /// `∂f/∂key` at `at` (the law evaluated at a state).
    #[inline]
    pub fn derivative(&self, at: &ContactAt, key: ContactKey) -> f64 {
        if at.force == 0.0 {
            return 0.0;
        }
        match key {
            ContactKey::Stiffness => at.s,
            ContactKey::Coefficient => {
                self.spring.per_a * power_law(1.0, self.spring.m, at.s.max(0.0)).0
            }
            ContactKey::Exponent if at.s <= 0.0 => 0.0,
            ContactKey::Exponent => at.spring * (super::ln_kept(at.s) - self.spring.ln_ref),
            ContactKey::Damping => at.v,
            ContactKey::Gap => -at.slope,
        }
    }
}

/// A contact law at a state of a run, with its state at the static
/// deformation the run moves about: what the sensitivities need
/// ([`ContactState::NONE`] for a component without one, every number
/// zero, as `FrictionAt::NONE`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ContactState {
    law: ContactForce,
    /// The law at the state.
    pub at: ContactAt,
    /// The law at rest at the static deformation (zero without one).
    rest: ContactAt,
}

impl ContactState {
    /// No contact.
    pub const NONE: ContactState = ContactState {
        law: ContactForce {
            spring: PowerSpring {
                coef: 0.0,
                m: 1.0,
                per_a: 1.0,
                ln_ref: 0.0,
            },
            linear: true,
            c: 0.0,
            gap: 0.0,
            d0: 0.0,
            about_rest: false,
        },
        at: ContactAt::ZERO,
        rest: ContactAt::ZERO,
    };

    /// The law `law` at the deformation `d` from the static one and the
    /// rate `rate()`, on `side` ([`ContactForce::at_side`]), or
    /// [`ContactState::NONE`].
    #[inline(always)]
    pub fn of(
        law: Option<&ContactForce>,
        (d, side): (f64, f64),
        rate: impl FnOnce() -> f64,
    ) -> ContactState {
        match law {
            Some(law) => ContactState::at(law, (d, side), rate()),
            None => ContactState::NONE,
        }
    }

    /// [`Self::of`] with a law, out of line: the kernels that inline
    /// [`Self::of`] are compiled once per size and kernel.
    #[inline(never)]
    fn at(law: &ContactForce, (d, side): (f64, f64), v: f64) -> ContactState {
        let rest = match law.about_rest {
            true => law.at(law.d0, 0.0),
            false => ContactAt::default(),
        };
        ContactState {
            law: *law,
            at: law.at_side(law.d0 + d, v, side),
            rest,
        }
    }

    /// The slope's change from the static one (which multiplies
    /// `B ∂q₀/∂x` about an equilibrium).
    #[inline]
    pub fn slope_change(&self) -> f64 {
        self.at.slope - self.rest.slope
    }

    /// `∂f/∂key` as its change from the static one.
    #[inline]
    pub fn derivative(&self, key: ContactKey) -> f64 {
        self.law.derivative(&self.at, key) - self.law.derivative(&self.rest, key)
    }
}

#[cfg(test)]
mod tests {
    use super::{Contact, ContactForce, ContactKey, ContactSpring};
    use crate::model::Value;
    use crate::simulation::laws::Power;

    fn law(spring: ContactSpring) -> Contact {
        Contact {
            spring,
            c: Value::Param(1),
            gap: Value::Param(2),
        }
    }

    /// Force, slopes and key derivatives against central differences, on
    /// both springs, closed; zero open and where the damper would pull.
    #[test]
    fn derivatives_match_central_differences() {
        let power = ContactSpring::Power(Power {
            a: Value::Param(0),
            m: Value::Param(3),
            reference: 1e-5,
        });
        let cases = [
            (
                ContactSpring::Linear(Value::Param(0)),
                vec![2e7, 300.0, -3e-6, 1.0],
            ),
            (power, vec![150.0, 200.0, 2e-6, 1.7]),
        ];
        for (spring, p) in cases {
            let contact = law(spring);
            let f = |p: &[f64], d: f64, v: f64| ContactForce::new(&contact, p).at(d, v).force;
            let (d, v) = (7e-6, -0.01);
            let at = ContactForce::new(&contact, &p).at(d, v);
            assert!(at.force > 0.0);
            let fd = (f(&p, d + 1e-10, v) - f(&p, d - 1e-10, v)) / 2e-10;
            assert!(
                (at.slope - fd).abs() < 1e-6 * at.slope.abs(),
                "{} {fd}",
                at.slope
            );
            let fv = (f(&p, d, v + 1e-6) - f(&p, d, v - 1e-6)) / 2e-6;
            assert!((at.damping - fv).abs() < 1e-6 * fv.abs());
            let keys = [
                (
                    0,
                    matches!(spring, ContactSpring::Linear(_)),
                    ContactKey::Stiffness,
                ),
                (
                    0,
                    matches!(spring, ContactSpring::Power(_)),
                    ContactKey::Coefficient,
                ),
                (
                    3,
                    matches!(spring, ContactSpring::Power(_)),
                    ContactKey::Exponent,
                ),
                (1, true, ContactKey::Damping),
                (2, true, ContactKey::Gap),
            ];
            for (i, applies, key) in keys.into_iter().filter(|k| k.1) {
                let _ = applies;
                let h = 1e-6 * p[i].abs();
                let (mut up, mut down) = (p.clone(), p.clone());
                up[i] += h;
                down[i] -= h;
                let fd = (f(&up, d, v) - f(&down, d, v)) / (2.0 * h);
                let exact = ContactForce::new(&contact, &p).derivative(&at, key);
                assert!(
                    (exact - fd).abs() < 1e-6 * fd.abs(),
                    "{key:?}: {exact} vs {fd}"
                );
            }
            // Open, and closed but pulled apart faster than the spring pushes.
            assert_eq!(f(&p, p[2] - 1e-7, 0.0), 0.0);
            assert_eq!(f(&p, p[2] + 1e-12, -1.0), 0.0);
        }
    }
}
