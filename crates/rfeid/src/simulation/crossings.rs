//! Where a switching function crosses zero inside a step: the cubic
//! Hermite interpolant of its values and rates at the step's ends, and its
//! roots (the power law's δ = 0, Bouc–Wen's v and z, a contact's closure
//! and force; `stepper`, `contact_events`).

/// Crossings closer together than this fraction of a step are one split.
/// Every crossing is split off, however near a step's end: skipping those
/// near the ends would make the computed response jump when a crossing moves
/// past the threshold, and the criterion would no longer be smooth in the
/// parameters. (A split at θ → 0 or 1 tends continuously to no split.)
pub(super) const MERGE: f64 = 1e-12;

/// The cubic Hermite interpolant with values x0, x1 and slopes (per unit θ)
/// s0, s1 at θ.
pub(super) fn hermite(x0: f64, s0: f64, x1: f64, s1: f64, t: f64) -> f64 {
    let c3 = 2.0 * (x0 - x1) + s0 + s1;
    let c2 = 3.0 * (x1 - x0) - 2.0 * s0 - s1;
    x0 + t * (s0 + t * (c2 + t * c3))
}

/// The slope in θ of [`hermite`] at θ.
pub(super) fn hermite_slope(x0: f64, s0: f64, x1: f64, s1: f64, t: f64) -> f64 {
    let c3 = 2.0 * (x0 - x1) + s0 + s1;
    let c2 = 3.0 * (x1 - x0) - 2.0 * s0 - s1;
    s0 + t * (2.0 * c2 + 3.0 * t * c3)
}

/// Pushes every θ in (0, 1) where the cubic Hermite interpolant with values
/// x0, x1 and slopes (per unit θ) s0, s1 changes sign: the interval is cut
/// at the cubic's turning points, and each monotone piece that changes
/// sign holds one root, found by bisection.
pub(super) fn cubic_roots(x0: f64, s0: f64, x1: f64, s1: f64, crossings: &mut Vec<f64>) {
    // p(θ) = x0 + s0 θ + c2 θ² + c3 θ³.
    let c3 = 2.0 * (x0 - x1) + s0 + s1;
    let c2 = 3.0 * (x1 - x0) - 2.0 * s0 - s1;
    let p = |t: f64| hermite(x0, s0, x1, s1, t);
    // Turning points: roots of s0 + 2 c2 θ + 3 c3 θ².
    let (a, b, c) = (3.0 * c3, 2.0 * c2, s0);
    let mut cuts = [0.0, 1.0, 1.0, 1.0];
    let mut k = 1;
    if a != 0.0 {
        let disc = b * b - 4.0 * a * c;
        if disc > 0.0 {
            let r = disc.sqrt();
            let q = -0.5 * (b + b.signum() * r);
            for t in [q / a, if q != 0.0 { c / q } else { f64::NAN }] {
                if t > 0.0 && t < 1.0 {
                    cuts[k] = t;
                    k += 1;
                }
            }
        }
    } else if b != 0.0 {
        let t = -c / b;
        if t > 0.0 && t < 1.0 {
            cuts[k] = t;
            k += 1;
        }
    }
    cuts[1..=k].sort_by(f64::total_cmp);
    for w in cuts[..=k].windows(2) {
        let (lo, hi) = (w[0], w[1]);
        let (plo, phi) = (p(lo), p(hi));
        if plo * phi < 0.0 {
            let t = bracketed_root(|s| p(lo + s * (hi - lo)), plo < 0.0);
            push_inside(crossings, lo + t * (hi - lo));
        }
    }
}

/// Pushes θ if it is inside the step (0 < θ < 1).
pub(super) fn push_inside(crossings: &mut Vec<f64>, theta: f64) {
    if theta > 0.0 && theta < 1.0 {
        crossings.push(theta);
    }
}

/// The root in (0, 1) of the cubic Hermite interpolant with values d0, d1
/// and derivatives (per unit θ) v0, v1, where d0 and d1 differ in sign.
pub(super) fn hermite_root(d0: f64, v0: f64, d1: f64, v1: f64) -> f64 {
    let p = |s: f64| {
        let s2 = s * s;
        let s3 = s2 * s;
        (2.0 * s3 - 3.0 * s2 + 1.0) * d0
            + (s3 - 2.0 * s2 + s) * v0
            + (-2.0 * s3 + 3.0 * s2) * d1
            + (s3 - s2) * v1
    };
    bracketed_root(p, d0 < 0.0)
}

/// A root in (0, 1) of `p`, which changes sign there (`neg_at_lo`: p(0) <
/// 0), by bisection: an interpolant may have several roots, and any one
/// inside is as good (the sign change is what matters).
fn bracketed_root(p: impl Fn(f64) -> f64, neg_at_lo: bool) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if (p(mid) < 0.0) == neg_at_lo {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::{cubic_roots, hermite_root};

    #[test]
    fn cubic_roots_finds_every_crossing_inside_the_step() {
        // Values and slopes at 0 and 1 of a cubic p.
        let ends =
            |p: &dyn Fn(f64) -> f64, dp: &dyn Fn(f64) -> f64| (p(0.0), dp(0.0), p(1.0), dp(1.0));
        let found = |(x0, s0, x1, s1): (f64, f64, f64, f64)| {
            let mut out = Vec::new();
            cubic_roots(x0, s0, x1, s1, &mut out);
            out.sort_by(f64::total_cmp);
            out
        };
        // One root: (θ − 0.4)(θ + 2).
        let r = found(ends(&|t| (t - 0.4) * (t + 2.0), &|t| 2.0 * t + 1.6));
        assert_eq!(r.len(), 1);
        assert!((r[0] - 0.4).abs() < 1e-11);
        // A reversal and its return: (θ − 0.2)(θ − 0.7), the same sign at
        // both ends.
        let r = found(ends(&|t| (t - 0.2) * (t - 0.7), &|t| 2.0 * t - 0.9));
        assert_eq!(r.len(), 2);
        assert!((r[0] - 0.2).abs() < 1e-11 && (r[1] - 0.7).abs() < 1e-11);
        // Three: (θ − 0.1)(θ − 0.5)(θ − 0.9).
        let p = |t: f64| (t - 0.1) * (t - 0.5) * (t - 0.9);
        let dp = |t: f64| (t - 0.5) * (t - 0.9) + (t - 0.1) * (t - 0.9) + (t - 0.1) * (t - 0.5);
        let r = found(ends(&p, &dp));
        assert_eq!(r.len(), 3);
        for (got, want) in r.iter().zip([0.1, 0.5, 0.9]) {
            assert!((got - want).abs() < 1e-11, "{got} {want}");
        }
        // None: a parabola above zero.
        assert!(found(ends(&|t| (t - 0.5) * (t - 0.5) + 0.01, &|t| 2.0 * (t - 0.5))).is_empty());
    }

    #[test]
    fn hermite_root_finds_the_crossing_of_a_cubic() {
        // δ(θ) = (θ − 0.3)(1 + θ): values and derivatives at the ends.
        let (d0, v0) = (-0.3, 1.0 - 0.3);
        let (d1, v1) = (0.7 * 2.0, 2.0 * 1.0 + 1.0 - 0.3);
        assert!((hermite_root(d0, v0, d1, v1) - 0.3).abs() < 1e-11);
    }
}
