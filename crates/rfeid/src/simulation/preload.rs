//! Motion about the static equilibrium, without cancellation.
//!
//! Under gravity the springs carry the weights: at the static equilibrium
//! q₀ the elastic forces `K q₀ + Σ B_pᵀ law_p(B_p q₀)` balance tonnes, while
//! a shaker moves the structure by a few newtons' worth. Written in q, every
//! acceleration (eq. 1) is a small difference of weight-sized forces, and
//! its rounding, relative to the weights, is thousands of times the
//! rounding relative to the motion. So runs under gravity integrate the
//! deviation `x = q − q₀` (and the sensitivities `∂x/∂θ = ∂q/∂θ − ∂q₀/∂θ`):
//! the linear forces become `K x`, each power law's force its change
//! `law(δ₀ + d) − law(δ₀)` with `d = B_p x`, evaluated below in forms free of
//! cancellation, and the weights drop out with the static forces they
//! balance. Mathematically nothing changes; the rounding becomes relative
//! to the motion.
use super::laws::power_law;
use crate::model::PowerSpring;

/// A power-law spring at its static deformation δ₀, for unit coefficient.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Preload {
    /// δ₀ (0 without gravity).
    pub d0: f64,
    /// `sign(δ₀)|δ₀|^m`.
    pub u0: f64,
    /// `m |δ₀|^(m−1)`, the slope at δ₀.
    pub slope0: f64,
    /// `√|δ₀|`.
    pub root0: f64,
}

impl Preload {
    /// The spring of exponent `m` at the deformation `d0`.
    pub fn new(m: f64, d0: f64) -> Preload {
        let (u0, slope0) = power_law(1.0, m, d0);
        Preload {
            d0,
            u0,
            slope0,
            root0: d0.abs().sqrt(),
        }
    }
}

/// The changes of the force `a sign(δ)|δ|^m` and of its slope from δ₀ to
/// `δ₀ + d` (eq. 2–6), each to a few roundings of itself however large the
/// preload. With the same sign at both ends, for `s = sign(δ₀)`:
/// - m = 2: `a d (|δ| + |δ₀|)` and `2 a s d`;
/// - m = 1.5: `a (d p + δ₀ Δp)` and `1.5 a Δp`, with `p = √|δ|` and
///   `Δp = p − p₀ = s d / (p + p₀)`;
/// - any m: `a u₀ expm1(m l)` and `a slope₀ expm1((m − 1) l)`, with
///   `l = ln1p(d / δ₀)`.
///
/// Across zero (or without a preload) the two ends have opposite signs,
/// and the plain difference does not cancel. With δ₀ = 0 the change is
/// exactly the force `law(d)`.
#[inline(always)]
pub(crate) fn power_change(a: f64, m: f64, pre: &Preload, d: f64) -> (f64, f64) {
    let d0 = pre.d0;
    let dd = d0 + d;
    if dd * d0 > 0.0 {
        let s = if d0 > 0.0 { 1.0 } else { -1.0 };
        if m == 2.0 {
            return (a * d * (dd.abs() + d0.abs()), 2.0 * a * s * d);
        }
        if m == 1.5 {
            let p = dd.abs().sqrt();
            let dp = s * d / (p + pre.root0);
            return (a * (d * p + d0 * dp), 1.5 * a * dp);
        }
    }
    other_change(a, m, pre, d)
}

/// [`power_change`] for the rarer cases, out of line so that the common
/// ones stay small in the kernels' loops (and the general exponent's
/// `powf` is not hoisted out of its branch into them): no preload, m = 1,
/// a change of sign, and exponents other than 2 and 1.5.
#[inline(never)]
fn other_change(a: f64, m: f64, pre: &Preload, d: f64) -> (f64, f64) {
    let d0 = pre.d0;
    let dd = d0 + d;
    if d0 == 0.0 {
        let (f, slope) = power_law(a, m, d);
        (f, slope - a * pre.slope0)
    } else if m == 1.0 {
        (a * d, 0.0)
    } else if !(dd * d0 > 0.0) {
        let (f, slope) = power_law(a, m, dd);
        (f - a * pre.u0, slope - a * pre.slope0)
    } else {
        let l = (d / d0).ln_1p();
        let f = a * pre.u0 * (m * l).exp_m1();
        (f, a * pre.slope0 * ((m - 1.0) * l).exp_m1())
    }
}

/// `∂f/∂m = coef sign(δ)|δ|^m (ln|δ| − ln δ_ref)` of a power law (eq. 6).
/// Kept out of line: inlined, the compiler may hoist the logarithm out of
/// the branch that needs it and pay for it on every component of every
/// stage.
#[inline(never)]
pub(crate) fn exponent_derivative(p: PowerSpring, d: f64) -> f64 {
    if d == 0.0 {
        0.0
    } else {
        p.coef * power_law(1.0, p.m, d).0 * (d.abs().ln() - p.ln_ref)
    }
}

/// The change of [`exponent_derivative`] from δ₀ to `δ₀ + d`: with the same
/// sign at both ends, `coef (Δu (ln|δ| − ln δ_ref) + u₀ ln1p(d / δ₀))`,
/// `Δu` the change of `sign(δ)|δ|^m` ([`power_change`]).
#[inline(never)]
pub(crate) fn exponent_change(p: PowerSpring, pre: &Preload, d: f64) -> f64 {
    let (d0, dd) = (pre.d0, pre.d0 + d);
    if !(dd * d0 > 0.0) {
        return exponent_derivative(p, dd) - exponent_derivative(p, d0);
    }
    let du = power_change(1.0, p.m, pre, d).0;
    p.coef * (du * (dd.abs().ln() - p.ln_ref) + pre.u0 * (d / d0).ln_1p())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The change in double-double arithmetic would be the reference; a
    /// simpler exact check: with δ₀ and d small integers scaled by a power
    /// of two, `law(δ₀ + d) − law(δ₀)` is exact in f64 for m = 2, and the
    /// other forms agree with extended differences to a few roundings.
    #[test]
    fn changes_match_the_plain_difference_where_it_is_exact() {
        let scale = 2f64.powi(-20);
        for (d0, d) in [
            (3.0, 1.0),
            (-5.0, 2.0),
            (4.0, -7.0),
            (0.0, 3.0),
            (6.0, -6.0),
        ] {
            let (d0, d) = (d0 * scale, d * scale);
            let pre = Preload::new(2.0, d0);
            let (f, s) = power_change(1.5, 2.0, &pre, d);
            let (f1, s1) = power_law(1.5, 2.0, d0 + d);
            let (f0, s0) = power_law(1.5, 2.0, d0);
            assert_eq!(f, f1 - f0, "force at δ₀ = {d0:e}, d = {d:e}");
            assert_eq!(s, s1 - s0, "slope at δ₀ = {d0:e}, d = {d:e}");
        }
    }

    /// Small changes under a large preload: against the first two terms of
    /// the Taylor series, `law'(δ₀) d + law''(δ₀) d²/2`, whose truncation
    /// (`~d³`) is far below rounding here. The plain difference would be
    /// off by about `ε law(δ₀)`, a relative error of `ε δ₀ / d` = 1e-10.
    #[test]
    fn small_changes_under_a_large_preload_keep_their_precision() {
        for m in [1.5, 2.0, 1.25, 10.0 / 9.0, 3.0] {
            for d0 in [2e-4_f64, -3e-5] {
                let d = d0.abs() * 1e-6;
                let pre = Preload::new(m, d0);
                let (f, s) = power_change(7.0, m, &pre, d);
                let ad0: f64 = d0.abs();
                let slope = 7.0 * m * ad0.powf(m - 1.0);
                let curvature = 7.0 * m * (m - 1.0) * ad0.powf(m - 2.0) * d0.signum();
                let third = 7.0 * m * (m - 1.0) * (m - 2.0) * ad0.powf(m - 3.0);
                let fourth = third * (m - 3.0) / d0;
                let force = slope * d + curvature * d * d / 2.0 + third * d * d * d / 6.0;
                let dslope = curvature * d + third * d * d / 2.0 + fourth * d * d * d / 6.0;
                assert!(
                    ((f - force) / force).abs() < 1e-14,
                    "m = {m}, δ₀ = {d0}: force {f:e} vs {force:e}"
                );
                assert!(
                    ((s - dslope) / dslope).abs() < 1e-12,
                    "m = {m}, δ₀ = {d0}: slope {s:e} vs {dslope:e}"
                );
            }
        }
    }

    /// The exponent derivative's change against its Taylor series in d:
    /// `∂/∂δ [coef u (ln|δ| − L)] = coef (u' (ln|δ| − L) + u / δ)`.
    #[test]
    fn the_exponent_derivative_change_keeps_its_precision() {
        let p = PowerSpring::new(3.0, 1.7, 1e-5);
        for d0 in [4e-5_f64, -2e-4] {
            let d = d0.abs() * 1e-7;
            let pre = Preload::new(p.m, d0);
            let change = exponent_change(p, &pre, d);
            let (u, du) = power_law(1.0, p.m, d0);
            let ln = d0.abs().ln() - p.ln_ref;
            let first = p.coef * (du * ln + u / d0);
            let relative = (change - first * d) / (first * d);
            // The second-order term is about d/δ₀ = 1e-7 of the first.
            assert!(relative.abs() < 1e-6, "δ₀ = {d0}: {relative:e}");
            // And the plain difference loses about ε δ₀ / d of it.
            let plain = exponent_derivative(p, d0 + d) - exponent_derivative(p, d0);
            assert!((change - plain).abs() <= 1e-7 * (first * d).abs());
        }
    }
}
