//! Multiply–add, separate or fused, chosen once per run by the CPU dispatch
//! in [`super::run`]: the kernels are generic over it, so each is compiled
//! once with `a·b + c` (two roundings) and once with a fused `fma` (one
//! rounding, half the instructions). A run uses one or the other throughout,
//! so its results do not depend on anything but the machine.

/// `a·b + c`.
pub(crate) trait Madd: Copy {
    /// `a·b + c`.
    fn madd(a: f64, b: f64, c: f64) -> f64;
}

/// Separate multiply and add (any CPU).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Separate;

/// Fused multiply–add (only where the CPU has FMA: in software it is slow).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Fused;

impl Madd for Separate {
    #[inline(always)]
    fn madd(a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
}

impl Madd for Fused {
    #[inline(always)]
    fn madd(a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
}
