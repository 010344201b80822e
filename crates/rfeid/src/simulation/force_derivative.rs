//! The derivative of a component's force with respect to one parameter
//! ([`force_derivative`]), shared by the dense and the sparse tangents.
use super::laws::contact::ContactState;
use super::laws::friction::FrictionAt;
use super::preload::{exponent_change, power_change, Preload};
use super::structure::Usage;
use crate::model::PowerSpring;

/// `∂f_i/∂x` of a component's force `f_i = k δ + a sign(δ)|δ|^m + c δ̇`
/// (eq. 2–7) for the parameter x used as `usage`, at deformation `d` from
/// the static deformation `pre` (`preload`), as its change from there;
/// `rate` gives δ̇ (computed only for a damping key). `power` is the
/// component's power-law spring (always present for a power-law usage),
/// `friction` its friction law at δ̇ ([`FrictionAt::NONE`] without one),
/// `contact` its contact law at the state ([`ContactState::NONE`]).
#[inline(always)]
pub(super) fn force_derivative(
    usage: Usage,
    (power, friction, contact): (Option<PowerSpring>, &FrictionAt<'_>, &ContactState),
    pre: &Preload,
    d: f64,
    rate: impl FnOnce() -> f64,
) -> f64 {
    match (usage, power) {
        (Usage::Stiffness(_), _) => d,
        (Usage::Damping(_), _) => rate(),
        (Usage::PowerCoefficient(_), Some(p)) => p.per_a * power_change(1.0, p.m, pre, d).0,
        (Usage::PowerExponent(_), Some(p)) => exponent_change(p, pre, d),
        (Usage::PowerCoefficient(_) | Usage::PowerExponent(_), None) => 0.0,
        (Usage::Friction(_, key), _) => friction.derivative(key),
        (Usage::Contact(_, key), _) => contact.derivative(key),
        // Bouc–Wen keys act through the internal state's rate (`hysteresis`)
        // and are not passed here.
        (Usage::Hysteresis(..), _) => 0.0,
        (Usage::Mass(_) | Usage::Inertia(..) | Usage::Amplitude(..), _) => 0.0,
    }
}
