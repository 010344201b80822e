//! Multiply–add, separate or fused, chosen once per run by the CPU dispatch
//! in [`super::run`]: the kernels are generic over it, so each is compiled
//! once with `a·b + c` (two roundings) and once with a fused `fma` (one
//! rounding, half the instructions). A run uses one or the other throughout,
//! so its results do not depend on anything but the machine.

/// `a·b + c`.
pub(crate) trait Madd: Copy {
    /// `a·b + c`.
    fn madd(a: f64, b: f64, c: f64) -> f64;

    /// `a·b + c` in each of four lanes (one register's).
    #[inline(always)]
    fn madd4(a: [f64; 4], b: [f64; 4], c: [f64; 4]) -> [f64; 4] {
        std::array::from_fn(|l| Self::madd(a[l], b[l], c[l]))
    }
}

/// Separate multiply and add (any CPU).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Separate;

/// Fused multiply–add, used only by the kernels compiled for AVX2 and FMA,
/// which run only where the CPU has both (`run`).
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

    /// One `vfmadd…pd` on a 256-bit register (the compiler does not
    /// always combine the four lanes of the portable form into one).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn madd4(a: [f64; 4], b: [f64; 4], c: [f64; 4]) -> [f64; 4] {
        use std::arch::x86_64::{_mm256_fmadd_pd, _mm256_loadu_pd, _mm256_storeu_pd};
        let mut out = [0.0; 4];
        // SAFETY: `Fused` kernels run only on CPUs with AVX2 and FMA (see
        // the type), and the pointers are to four-element arrays.
        unsafe {
            let r = _mm256_fmadd_pd(
                _mm256_loadu_pd(a.as_ptr()),
                _mm256_loadu_pd(b.as_ptr()),
                _mm256_loadu_pd(c.as_ptr()),
            );
            _mm256_storeu_pd(out.as_mut_ptr(), r);
        }
        out
    }
}
