//! The power-law spring force `a·sign(δ)|δ|^m` and its slope ([`power_law`]).
/// The force of the power law and its slope, `(a sign(δ)|δ|^m, m a |δ|^(m−1))`.
#[inline]
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
        let p = ad.powf(m - 1.0);
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
