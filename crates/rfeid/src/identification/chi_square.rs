//! The χ² distribution: survival function and quantile, for the verdict's
//! tests (Ljung–Box p-values, the noise threshold between distinct minima).
//!
//! ```text
//! P(χ²_k > x) = Q(k/2, x/2),     Q(a, x) = Γ(a, x) / Γ(a)
//! ```
//!
//! Q is evaluated as in Numerical Recipes (§6.2): the series of P = 1 − Q for
//! `x < a + 1`, Lentz's continued fraction of Q otherwise; ln Γ by Lanczos'
//! approximation (g = 7, 9 terms, relative error ≈ 1e-15). The quantile is
//! found by bisection on the survival function, which is monotone.

/// ln Γ(a) for a > 0 (Lanczos, g = 7, n = 9).
fn ln_gamma(a: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if a < 0.5 {
        // Reflection: Γ(a) Γ(1 − a) = π / sin(π a).
        return (std::f64::consts::PI / (std::f64::consts::PI * a).sin()).ln() - ln_gamma(1.0 - a);
    }
    let a = a - 1.0;
    let mut sum = C[0];
    for (i, c) in C.iter().enumerate().skip(1) {
        sum += c / (a + i as f64);
    }
    let t = a + G + 0.5;
    0.5 * (2.0 * std::f64::consts::PI).ln() + (a + 0.5) * t.ln() - t + sum.ln()
}

/// The regularised upper incomplete gamma function Q(a, x), a > 0, x ≥ 0.
fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let log_prefactor = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        // P(a, x) = e^{−x} x^a / Γ(a + 1) Σ x^n / ((a + 1) … (a + n)).
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..1000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-17 {
                break;
            }
        }
        1.0 - sum * log_prefactor.exp()
    } else {
        // Continued fraction of Q (modified Lentz).
        const TINY: f64 = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..1000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < TINY {
                d = TINY;
            }
            c = b + an / c;
            if c.abs() < TINY {
                c = TINY;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        log_prefactor.exp() * h
    }
}

/// P(χ²_k > x), the survival function of the χ² distribution with `k` ≥ 1
/// degrees of freedom (1 for x ≤ 0).
pub fn chi_square_sf(x: f64, k: usize) -> f64 {
    gamma_q(0.5 * k.max(1) as f64, 0.5 * x).clamp(0.0, 1.0)
}

/// The quantile χ²_k(p): the x with P(χ²_k ≤ x) = p, for 0 < p < 1 and k ≥ 1.
pub fn chi_square_quantile(p: f64, k: usize) -> f64 {
    let tail = 1.0 - p;
    // The mean plus enough standard deviations brackets any p ≤ 1 − 1e-15.
    let (mut lo, mut hi) = (0.0, 1.0);
    while chi_square_sf(hi, k) > tail {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if chi_square_sf(mid, k) > tail {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-14 * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// For even k = 2m the survival function is a finite sum:
    /// e^{−x/2} Σ_{i<m} (x/2)^i / i!.
    fn even_closed_form(x: f64, k: usize) -> f64 {
        let h = 0.5 * x;
        let (mut term, mut sum) = (1.0, 0.0);
        for i in 0..k / 2 {
            if i > 0 {
                term *= h / i as f64;
            }
            sum += term;
        }
        (-h).exp() * sum
    }

    #[test]
    fn survival_matches_the_closed_form_for_even_degrees_of_freedom() {
        for k in [2, 4, 10, 20, 40] {
            for x in [0.1, 1.0, 5.0, 19.0, 20.0, 21.0, 40.0, 80.0, 150.0] {
                let exact = even_closed_form(x, k);
                let got = chi_square_sf(x, k);
                let err = (got - exact).abs() / exact;
                assert!(err < 1e-12, "k = {k}, x = {x}: {got:e} vs {exact:e}");
            }
        }
    }

    #[test]
    fn quantiles_match_known_values() {
        // χ²_1(0.95) = 1.959963984540054².
        let z = 1.959_963_984_540_054_f64;
        assert!((chi_square_quantile(0.95, 1) - z * z).abs() < 1e-9);
        // χ²_2(p) = −2 ln(1 − p) exactly.
        for p in [0.5, 0.9, 0.999, 1.0 - 1e-6] {
            let exact = -2.0 * (1.0_f64 - p).ln();
            assert!((chi_square_quantile(p, 2) - exact).abs() < 1e-9 * exact);
        }
        // Round trip on odd and even degrees of freedom.
        for k in [1, 3, 7, 16, 33] {
            let x = chi_square_quantile(0.999, k);
            assert!((chi_square_sf(x, k) - 1e-3).abs() < 1e-12, "k = {k}");
        }
    }

    #[test]
    fn ln_gamma_matches_factorials() {
        let mut f = 1.0_f64;
        for n in 1..30 {
            f *= n as f64;
            assert!((ln_gamma(n as f64 + 1.0) - f.ln()).abs() < 1e-12 * f.ln().max(1.0));
        }
        // Γ(1/2) = √π.
        assert!((ln_gamma(0.5) - 0.5 * std::f64::consts::PI.ln()).abs() < 1e-14);
    }
}
