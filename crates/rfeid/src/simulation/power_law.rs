//! The power-law spring force `a·sign(δ)|δ|^m` and its slope ([`power_law`]).
/// The force of the power law and its slope, `(a sign(δ)|δ|^m, m a |δ|^(m−1))`.
#[inline]
pub fn power_law(a: f64, m: f64, d: f64) -> (f64, f64) {
    let ad = d.abs();
    if m == 2.0 {
        (a * d * ad, 2.0 * a * ad)
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
        let p = ad.powf(m - 1.0);
        (a * p * d, a * m * p)
    }
}
