//! The joint laws of a component (eq. 2, 6; SPEC §1), one file each: what a
//! law is in a model ([`Law`], and its own struct), what it says of itself
//! ([`JointLaw`]: its name, formula and keys, how it acts at rest) and its
//! force with numbers in, shared by the kernels.
//!
//! A law describes itself through [`JointLaw`], so the model's usages of
//! parameters, `check`, the report and the FRF study ask it rather than
//! match on it. The kernels keep a fast path per law.
pub(crate) mod bouc_wen;
pub(crate) mod contact;
pub(crate) mod friction;
mod linear;
pub(crate) mod power;

pub use bouc_wen::{BoucWen, HysteresisKey};
pub use contact::{Contact, ContactKey, ContactSpring};
pub use friction::{Friction, FrictionKey};
pub use linear::Linear;
pub use power::{power_law, Power, PowerSpring};

use crate::model::Value;
use crate::units::Dimension;

/// The force law of one SDE component (eq. 2, 6; SPEC §1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Law {
    /// No spring: the component carries only its damping.
    None,
    /// `f = k δ`.
    Linear(Linear),
    /// `f = a · sign(δ) · (|δ|/δ_ref)^m`, the slideway contact law (eq. 6).
    Power(Power),
    /// Friction, a force of the component's velocity v = δ̇ (SPEC §1).
    Friction(Friction),
    /// Bouc–Wen hysteresis (SPEC §1), with an internal state z.
    BoucWen(BoucWen),
    /// A contact, acting only while closed (SPEC §1).
    Contact(Contact),
}

/// A component without a spring: its damper alone.
#[derive(Debug, Clone, Copy, PartialEq)]
struct NoSpring;

impl JointLaw for NoSpring {
    fn name(&self) -> &'static str {
        "none"
    }
    fn formula(&self) -> String {
        "no spring".into()
    }
    fn keys(&self) -> Vec<LawKey> {
        Vec::new()
    }
    fn is_spring(&self, _: &[f64]) -> bool {
        false
    }
}

impl Law {
    /// The law as a [`JointLaw`], to ask it what it is.
    pub fn joint(&self) -> &dyn JointLaw {
        match self {
            Law::None => &NoSpring,
            Law::Linear(l) => l,
            Law::Power(l) => l,
            Law::Friction(l) => l,
            Law::BoucWen(l) => l,
            Law::Contact(l) => l,
        }
    }

    /// The linear spring constant of this law at the parameter values `p`
    /// ([`JointLaw::linear_stiffness`]).
    pub fn linear_stiffness(&self, p: &[f64]) -> Option<f64> {
        self.joint().linear_stiffness(p)
    }

    /// The power-law spring of this law at the parameter values `p`, if it
    /// is one: the kernels' fast path.
    #[inline]
    pub fn power_spring(&self, p: &[f64]) -> Option<PowerSpring> {
        match self {
            Law::Power(pw) => Some(pw.spring(p)),
            _ => None,
        }
    }
}

/// What a joint law says of itself.
pub trait JointLaw {
    /// The law's name in a model file (`law = "…"`).
    fn name(&self) -> &'static str;

    /// The force in words for a report (HTML), e.g. `a·sign(δ)|δ|<sup>m</sup>`.
    fn formula(&self) -> String;

    /// The law's keys with their values, in a fixed order; a key left at
    /// the value its absence means is left out.
    fn keys(&self) -> Vec<LawKey>;

    /// The stiffness of the linear spring the law holds (k of a linear
    /// spring, the parallel k of friction and Bouc–Wen), which the kernels
    /// keep in their linear part; `None` for a law without one.
    fn linear_stiffness(&self, _p: &[f64]) -> Option<f64> {
        None
    }

    /// Whether the law restores like a spring at rest, at the parameter
    /// values `p` (a direction held by no spring is free).
    fn is_spring(&self, p: &[f64]) -> bool;

    /// The stiffness and damping the law adds for small motions about rest
    /// beyond its linear spring: `(k, c)`.
    fn small_motion(&self, _p: &[f64]) -> (f64, f64) {
        (0.0, 0.0)
    }

    /// Whether the force switches quickly with the velocity or an internal
    /// state (a near-kink the step-size windows cannot see).
    fn switches(&self) -> bool {
        false
    }

    /// Whether the law holds the component's damping `c` among its own keys
    /// (a contact's acts only while closed), the component then having none
    /// of its own.
    fn owns_damping(&self) -> bool {
        false
    }
}

/// One key of a law: its name in a model file, its symbol in a report, its
/// value, its unit and which parameter usage it is.
#[derive(Debug, Clone, Copy)]
pub struct LawKey {
    /// The key as a model file writes it.
    pub name: &'static str,
    /// Its symbol in a report (HTML).
    pub symbol: &'static str,
    /// Its value.
    pub value: Value,
    /// Its unit.
    pub unit: KeyUnit,
    /// What a parameter standing for it does; `None` for a key that
    /// cannot be a parameter.
    pub role: Option<KeyRole>,
}

/// What a parameter standing for a law's key does, which decides its
/// sensitivities' terms (the model's `Usage` of it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeyRole {
    /// A linear (or parallel) stiffness k, in the kernels' linear part.
    Stiffness,
    /// The power law's coefficient a.
    PowerCoefficient,
    /// The power law's exponent m.
    PowerExponent,
    /// A key of the friction force.
    Friction(FrictionKey),
    /// A key of the Bouc–Wen state's rate.
    Hysteresis(HysteresisKey),
    /// A key of a contact's force.
    Contact(ContactKey),
}

/// The unit of a law's key, for a translation or a rotation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeyUnit {
    /// N/m, or N·m/rad.
    Stiffness,
    /// N, or N·m.
    Force,
    /// m/s, or rad/s.
    Velocity,
    /// N·s/m, or N·m·s/rad.
    Damping,
    /// m, or rad.
    Length,
    /// A number whose unit depends on another key (or none).
    Bare,
}

impl KeyUnit {
    /// The unit's symbol for a translation (`rotational` false) or a
    /// rotation, as a report writes it.
    pub fn symbol(self, rotational: bool) -> &'static str {
        match (self, rotational) {
            (KeyUnit::Stiffness, false) => "N/m",
            (KeyUnit::Stiffness, true) => "N*m/rad",
            (KeyUnit::Force, false) => "N",
            (KeyUnit::Force, true) => "N*m",
            (KeyUnit::Velocity, false) => "m/s",
            (KeyUnit::Velocity, true) => "rad/s",
            (KeyUnit::Damping, false) => "N*s/m",
            (KeyUnit::Damping, true) => "N*m*s/rad",
            (KeyUnit::Length, false) => "m",
            (KeyUnit::Length, true) => "rad",
            (KeyUnit::Bare, _) => "",
        }
    }
}

impl LawKey {
    /// A key that a parameter may stand for.
    pub(crate) fn new(
        name: &'static str,
        symbol: &'static str,
        value: Value,
        unit: KeyUnit,
        role: KeyRole,
    ) -> LawKey {
        LawKey {
            name,
            symbol,
            value,
            unit,
            role: Some(role),
        }
    }
}

/// A component's table in a model file as a law reads it: each key with
/// the dimension the law gives it (and the key's rule), and the model's
/// parameters behind the values. The model-file builder implements it;
/// its errors name the file, the entry and the key.
pub trait KeyReader {
    /// The reader's error.
    type Error;
    /// Whether the component is a rotation (its keys in N·m and rad).
    fn rotational(&self) -> bool;
    /// Whether `key` is given.
    fn given(&self, key: &str) -> bool;
    /// `key`'s value, a number of dimension `dim` or a parameter, checked
    /// against the key's rule; `None` when absent.
    fn value(&mut self, key: &str, dim: Dimension) -> Result<Option<Value>, Self::Error>;
    /// `key`'s value, which the law needs.
    fn required(&mut self, key: &str, dim: Dimension) -> Result<Value, Self::Error>;
    /// `key`'s value as a number of dimension `dim` (no parameter);
    /// `None` when absent.
    fn number(&mut self, key: &str, dim: Dimension) -> Result<Option<f64>, Self::Error>;
    /// A value's nominal number: its own, or its parameter's.
    fn nominal(&self, v: Value) -> f64;
    /// The name of parameter `index`.
    fn parameter_name(&self, index: usize) -> String;
    /// Whether `key` is written with a unit, or names a parameter whose
    /// value or box is.
    fn has_unit(&self, key: &str) -> bool;
    /// A refusal of `key` (at its value when given, else at the
    /// component) saying `message`.
    fn refuse(&self, key: &str, message: String) -> Self::Error;
}

/// A law a model file can name: its name, its keys and how to read them.
pub trait ReadLaw {
    /// The name (`law = "…"`).
    const NAME: &'static str;
    /// The law's own keys (a component also takes `law` and `c`).
    const KEYS: &'static [&'static str];
    /// The keys that imply the law when a component names none.
    const IMPLIED_BY: &'static [&'static str];
    /// The law from a component's keys.
    fn read<E>(keys: &mut dyn KeyReader<Error = E>) -> Result<Law, E>;
}

/// One entry of [`readers`]: a law's name, keys and reader.
pub struct LawReader<E> {
    /// [`ReadLaw::NAME`].
    pub name: &'static str,
    /// [`ReadLaw::KEYS`].
    pub keys: &'static [&'static str],
    /// [`ReadLaw::IMPLIED_BY`].
    pub implied_by: &'static [&'static str],
    /// [`ReadLaw::read`].
    pub read: fn(&mut dyn KeyReader<Error = E>) -> Result<Law, E>,
}

impl<E> LawReader<E> {
    fn of<L: ReadLaw>() -> LawReader<E> {
        LawReader {
            name: L::NAME,
            keys: L::KEYS,
            implied_by: L::IMPLIED_BY,
            read: L::read::<E>,
        }
    }
}

/// Every law a model file can name, one line each. A component naming no
/// law takes the last one that a key it gives implies.
pub fn readers<E>() -> [LawReader<E>; 5] {
    [
        LawReader::of::<Linear>(),
        LawReader::of::<Power>(),
        LawReader::of::<Friction>(),
        LawReader::of::<BoucWen>(),
        LawReader::of::<Contact>(),
    ]
}

/// The dimensions of a law's keys on a translation (`rotational` false:
/// N, m) or a rotation (N·m, rad).
#[derive(Debug, Clone, Copy)]
pub struct KeyDims {
    /// A force (N or N·m).
    pub force: Dimension,
    /// A deformation (m or rad).
    pub length: Dimension,
    /// A stiffness (N/m or N·m/rad).
    pub stiffness: Dimension,
    /// A velocity (m/s or rad/s).
    pub velocity: Dimension,
}

impl KeyDims {
    /// The dimensions for a translation or a rotation.
    pub fn of(rotational: bool) -> KeyDims {
        match rotational {
            true => KeyDims {
                force: Dimension::MOMENT,
                length: Dimension::DIMENSIONLESS,
                stiffness: Dimension::MOMENT,
                velocity: Dimension::FREQUENCY,
            },
            false => KeyDims {
                force: Dimension::FORCE,
                length: Dimension::LENGTH,
                stiffness: Dimension::STIFFNESS,
                velocity: Dimension::LENGTH.div(Dimension::TIME),
            },
        }
    }
}

/// `x^y`, out of line: in the kernels, a law's `powf` inside a branch that
/// most components skip (a contact's, a Bouc–Wen state's) could otherwise be
/// hoisted out of it and run for every component (`ln(0)` included), as
/// some builds did (+34 % instructions on the knee–column's sensitivities).
/// A call is not moved out of its branch.
#[inline(never)]
pub(crate) fn powf_kept(x: f64, y: f64) -> f64 {
    x.powf(y)
}

/// `ln x`, out of line, as [`powf_kept`].
#[inline(never)]
pub(crate) fn ln_kept(x: f64) -> f64 {
    x.ln()
}

/// `e^x`, out of line, as [`powf_kept`].
#[inline(never)]
pub(crate) fn exp_kept(x: f64) -> f64 {
    x.exp()
}
