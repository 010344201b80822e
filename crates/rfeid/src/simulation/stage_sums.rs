//! The stage sums of an explicit Runge–Kutta step, `y + h Σ_j a_j k_j`
//! over the nonzero coefficients of a row of the tableau, for the state
//! (over the coordinates the motion reaches, `System::active`) and for the
//! sensitivities (over the rows they reach, `Tangent::reach`), with the sum
//! over the stages in registers and the bounds checked once per sum.
use super::madd::Madd;

/// The nonzero entries `(j, a_j)` of a row of coefficients, in increasing
/// j, with the number of stages they reach (the last j + 1), so that
/// [`stages_fit`] is one product rather than one per entry (it is checked
/// at every stage sum).
pub(super) struct Coefs {
    terms: Vec<(usize, f64)>,
    stages: usize,
}

impl std::ops::Deref for Coefs {
    type Target = [(usize, f64)];
    fn deref(&self) -> &[(usize, f64)] {
        &self.terms
    }
}

/// The nonzero entries of a row of coefficients.
pub(super) fn nonzero(row: &[f64]) -> Coefs {
    let terms: Vec<(usize, f64)> = (row.iter().enumerate())
        .filter(|(_, v)| **v != 0.0)
        .map(|(j, v)| (j, *v))
        .collect();
    let stages = terms.last().map_or(0, |(j, _)| j + 1);
    Coefs { terms, stages }
}

/// `out = y + h Σ_j a_j k_j` over the nonzero `(j, a_j)`, thirty-two (then
/// eight, one) elements at a time with the sum over the stages in registers
/// (one pass over the output, not one per stage).
#[inline(always)]
pub(super) fn combine<M: Madd>(
    y: &[f64],
    k: &[f64],
    a: &Coefs,
    h: f64,
    len: usize,
    out: &mut [f64],
) {
    combine_range::<M>(y, k, a, h, len, (0, len), out);
}

/// [`combine`] over the elements `from..to` of stages `len` long only.
#[inline(always)]
fn combine_range<M: Madd>(
    y: &[f64],
    k: &[f64],
    a: &Coefs,
    h: f64,
    len: usize,
    (from, to): (usize, usize),
    out: &mut [f64],
) {
    assert!(stages_fit(k, a, len) && to <= len && y.len() >= to && out.len() >= to);
    let mut e0 = from;
    // SAFETY (each call): the stages of `a` lie in `k` (asserted) and each
    // chunk ends within `to` ≤ len (the loop conditions).
    while e0 + 32 <= to {
        unsafe { combine_chunk::<M, 32>(y, k, a, h, len, e0, out) };
        e0 += 32;
    }
    while e0 + 8 <= to {
        unsafe { combine_chunk::<M, 8>(y, k, a, h, len, e0, out) };
        e0 += 8;
    }
    // The remainder, one element at a time.
    for e in e0..to {
        unsafe { combine_chunk::<M, 1>(y, k, a, h, len, e, out) };
    }
}

/// [`combine`] over two halves `half` long each (the state's `[q; q̇]`, or
/// the sensitivities' position and velocity rows), over the first `reach`
/// elements of each (all of them when `reach == half`): the coordinates
/// the motion reaches (`System::active`), or the sensitivities' rows
/// (`Tangent::reach`). The others stay at the zeros the workspace's
/// `prepare` wrote in y and k, and are left as they are (zero) in `out`.
#[inline(always)]
pub(super) fn combine_halves<M: Madd>(
    y: &[f64],
    k: &[f64],
    a: &Coefs,
    h: f64,
    (half, reach): (usize, usize),
    out: &mut [f64],
) {
    if reach == half {
        combine::<M>(y, k, a, h, 2 * half, out);
    } else {
        combine_range::<M>(y, k, a, h, 2 * half, (0, reach), out);
        combine_range::<M>(y, k, a, h, 2 * half, (half, half + reach), out);
    }
}

/// `y += h Σ_j a_j k_j`, like [`combine`].
#[inline(always)]
pub(super) fn accumulate<M: Madd>(y: &mut [f64], k: &[f64], a: &Coefs, h: f64, len: usize) {
    accumulate_range::<M>(y, k, a, h, len, (0, len));
}

/// [`accumulate`] over the first `reach` elements of each of two halves
/// `half` long, as [`combine_halves`].
#[inline(always)]
pub(super) fn accumulate_halves<M: Madd>(
    y: &mut [f64],
    k: &[f64],
    a: &Coefs,
    h: f64,
    (half, reach): (usize, usize),
) {
    if reach == half {
        accumulate::<M>(y, k, a, h, 2 * half);
    } else {
        accumulate_range::<M>(y, k, a, h, 2 * half, (0, reach));
        accumulate_range::<M>(y, k, a, h, 2 * half, (half, half + reach));
    }
}

/// [`accumulate`] over the elements `from..to` of stages `len` long only.
#[inline(always)]
fn accumulate_range<M: Madd>(
    y: &mut [f64],
    k: &[f64],
    a: &Coefs,
    h: f64,
    len: usize,
    (from, to): (usize, usize),
) {
    assert!(stages_fit(k, a, len) && to <= len && y.len() >= to);
    let mut e0 = from;
    // SAFETY: as in `combine_range`.
    while e0 + 32 <= to {
        unsafe { accumulate_chunk::<M, 32>(y, k, a, h, len, e0) };
        e0 += 32;
    }
    while e0 + 8 <= to {
        unsafe { accumulate_chunk::<M, 8>(y, k, a, h, len, e0) };
        e0 += 8;
    }
    for e in e0..to {
        unsafe { accumulate_chunk::<M, 1>(y, k, a, h, len, e) };
    }
}

/// Whether every stage j of `a` lies in `k`: `(j + 1)·len ≤ k.len()`.
#[inline(always)]
fn stages_fit(k: &[f64], a: &Coefs, len: usize) -> bool {
    (a.stages)
        .checked_mul(len)
        .is_some_and(|end| end <= k.len())
}

/// `out[e0..e0 + W] = y[e0..e0 + W] + h Σ_j a_j k_j[e0..e0 + W]`.
///
/// # Safety
/// As [`stage_sum`].
#[inline(always)]
unsafe fn combine_chunk<M: Madd, const W: usize>(
    y: &[f64],
    k: &[f64],
    a: &Coefs,
    h: f64,
    len: usize,
    e0: usize,
    out: &mut [f64],
) {
    // SAFETY: the caller's.
    let s = unsafe { stage_sum::<M, W>(k, a, len, e0) };
    let (yc, oc) = (&y[e0..e0 + W], &mut out[e0..e0 + W]);
    for q in 0..W {
        oc[q] = M::madd(h, s[q], yc[q]);
    }
}

/// `y[e0..e0 + W] += h Σ_j a_j k_j[e0..e0 + W]`.
///
/// # Safety
/// As [`stage_sum`].
#[inline(always)]
unsafe fn accumulate_chunk<M: Madd, const W: usize>(
    y: &mut [f64],
    k: &[f64],
    a: &Coefs,
    h: f64,
    len: usize,
    e0: usize,
) {
    // SAFETY: the caller's.
    let s = unsafe { stage_sum::<M, W>(k, a, len, e0) };
    let yc = &mut y[e0..e0 + W];
    for q in 0..W {
        yc[q] = M::madd(h, s[q], yc[q]);
    }
}

/// `Σ_j a_j k_j[e0 .. e0 + W]`, stage j being `k[j·len .. (j + 1)·len]`.
/// Unchecked: bounds checks here cost a third of the loop's instructions.
///
/// # Safety
/// `e0 + W ≤ len` and, for every `(j, _)` in `a`, `(j + 1)·len ≤ k.len()`
/// ([`stages_fit`]: `a.stages` is the last j + 1, and [`nonzero`], which
/// alone builds a [`Coefs`], keeps the terms in increasing j).
#[inline(always)]
unsafe fn stage_sum<M: Madd, const W: usize>(
    k: &[f64],
    a: &Coefs,
    len: usize,
    e0: usize,
) -> [f64; W] {
    debug_assert!(e0 + W <= len && stages_fit(k, a, len));
    let mut s = [0.0; W];
    for &(j, aj) in a.iter() {
        let start = j * len + e0;
        // SAFETY: start + W ≤ j·len + len ≤ k.len() by the preconditions.
        let kj = unsafe { k.get_unchecked(start..start + W) };
        for q in 0..W {
            s[q] = M::madd(aj, kj[q], s[q]);
        }
    }
    s
}
