//! Profile likelihoods: the criterion J (eq. 16) minimised over the other
//! parameters at a grid of fixed values of one, and the likelihood-ratio
//! interval it gives beside the Wald interval of the Cramér–Rao bounds
//! (eq. 26–29).
//!
//! With Gaussian errors of variance σ² (eq. 12, 14), −2 ln L is `J/σ²` up to
//! a constant, so the likelihood-ratio statistic for x_j is
//! `(J_prof(x_j) − J_min)/σ²`, χ² with one degree of freedom. σ² is
//! estimated by the same s² as the bounds (eq. 29, weighted like J):
//!
//! ```text
//! I_95 = { x : J_prof(x) − J_min ≤ χ²₁(0.95) s² }
//! ```
//!
//! For a criterion quadratic in the parameters, `J_prof(x) − J_min =
//! s² (x − x̂)²/D²_jj` with D² the covariance of eq. 26, so I_95 is exactly
//! the Wald interval `x̂ ± z_0.975 √D²_jj`; where the two differ, the
//! criterion is not quadratic over the interval and the bounds' linearisation
//! misstates the uncertainty. An end that stays below the threshold up to
//! the box (eq. 17) is open: the data do not bound the parameter there.
//!
//! - [`pinned`]: the criterion with x_j held, a [`LeastSquares`] problem the
//!   solvers run on unchanged;
//! - [`walk`]: the refits along one side of the grid, each warm-started
//!   from the last;
//! - this module: the request, the recorded profile and its interval.
//!
//! [`LeastSquares`]: crate::identification::problem::LeastSquares
pub mod pinned;
pub mod walk;

use super::chi_square::chi_square_quantile;
use super::termination::StopReason;
use super::warning::Warning;
use serde::{Deserialize, Serialize};

/// Confidence level of the profile and Wald intervals.
pub const LEVEL: f64 = 0.95;
/// Grid points of each profile when not asked otherwise.
pub const DEFAULT_POINTS: usize = 20;
/// Fewest grid points of a profile: one each side of the estimate.
pub const MIN_POINTS: usize = 2;
/// Most grid points of a profile.
pub const MAX_POINTS: usize = 1000;
/// Half-width of the planned grid, in Wald standard errors (eq. 26): the
/// 95 % interval is ±1.96 of them for a quadratic criterion, so the grid
/// spans it with half again as margin.
pub const GRID_STD_ERRORS: f64 = 3.0;
/// Relative difference of a profile interval's half-width (or width) from
/// the Wald interval's above which they are said to differ.
pub const DIFFERENCE: f64 = 1.0 / 3.0;

/// `χ²₁(LEVEL)`, the likelihood-ratio threshold in units of s².
pub fn threshold() -> f64 {
    chi_square_quantile(LEVEL, 1)
}

/// Which parameters to profile, and on how many points.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ProfileRequest {
    /// Identified parameters by name (as RESULT.json names them, e.g.
    /// `a_n4` or `k[low]`); empty: every identified parameter.
    pub parameters: Vec<String>,
    /// Grid points of each profile ([`MIN_POINTS`] to [`MAX_POINTS`]),
    /// half each side of the estimate, before any extension to the box.
    pub points: usize,
}

impl Default for ProfileRequest {
    fn default() -> Self {
        ProfileRequest {
            parameters: Vec::new(),
            points: DEFAULT_POINTS,
        }
    }
}

/// Where one end of a profile interval lies.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum IntervalEnd {
    /// The profile crosses the threshold at `value` (interpolated linearly
    /// in the signed root `√(ΔJ/s²)`, exact for a quadratic criterion).
    Crossed {
        /// The end, SI.
        value: f64,
    },
    /// The profile stays below the threshold up to the box's `bound`: the
    /// data do not bound the parameter on this side (practically
    /// non-identifiable).
    Open {
        /// The box's bound, SI.
        bound: f64,
    },
    /// The refits on this side ended (failed, or the walk's points ran
    /// out) below the threshold before the bound, at `last`.
    Unresolved {
        /// The farthest point refitted, SI.
        last: f64,
    },
}

impl IntervalEnd {
    /// The crossing, if the profile crossed.
    pub fn value(&self) -> Option<f64> {
        match self {
            IntervalEnd::Crossed { value } => Some(*value),
            _ => None,
        }
    }
}

/// One refit of a profile.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProfilePoint {
    /// The held value of the parameter, SI.
    pub value: f64,
    /// J minimised over the other parameters (eq. 16); `None` if the refit
    /// failed.
    pub criterion: Option<f64>,
    /// Every identified parameter at the refit's end, SI, in the order of
    /// RESULT.json's `parameters` (the held one included); empty if the
    /// refit failed.
    pub parameters: Vec<f64>,
    /// Why the refit stopped (Levenberg–Marquardt); `None` if it failed.
    pub termination: Option<StopReason>,
    /// Iterations of the refit.
    pub iterations: usize,
    /// Why the refit failed, if it did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
}

/// The profile of one identified parameter and its intervals.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParameterProfile {
    /// The parameter's name.
    pub name: String,
    /// The estimate x̂, SI.
    pub estimate: f64,
    /// Its Cramér–Rao standard error (eq. 26), if the bounds were computed.
    pub std_error: Option<f64>,
    /// J_min, the criterion the profile's ΔJ are taken from: the estimate's,
    /// or a refit's if one went lower.
    pub criterion: f64,
    /// s² (eq. 29), as the bounds take it.
    pub s2: f64,
    /// κ, the estimate's variance over eq. 26's with the one s²
    /// ([`crate::identification::uncertainty::CramerRao::variance_ratio`]):
    /// 1 unless the bounds take each sensor's own noise level (equal
    /// weights, [`crate::identification::sensor_levels`]). ΔJ is scaled
    /// by κ s², so that the profile and Wald intervals estimate the same
    /// spread.
    #[serde(default = "one")]
    pub variance_ratio: f64,
    /// The threshold of ΔJ/s², χ²₁(0.95).
    pub threshold: f64,
    /// The Wald interval `x̂ ± √threshold · std_error`, SI (not clipped to
    /// the box).
    pub wald: Option<[f64; 2]>,
    /// The profile interval's lower end.
    pub lower: IntervalEnd,
    /// The profile interval's upper end.
    pub upper: IntervalEnd,
    /// The estimate and every refit, in increasing value.
    pub points: Vec<ProfilePoint>,
    /// What the profile shows ([`Warning::ProfileDiffers`],
    /// [`Warning::ProfileOpen`], [`Warning::ProfileUnresolved`]), also in
    /// the result's warnings.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<Warning>,
}

impl ParameterProfile {
    /// ΔJ/(κ s²) at each point, in the order of `points` (`None` where the
    /// refit failed).
    pub fn statistic(&self) -> Vec<Option<f64>> {
        self.points
            .iter()
            .map(|p| p.criterion.map(|c| (c - self.criterion) / self.scale()))
            .collect()
    }

    /// κ s², the scale of ΔJ.
    pub fn scale(&self) -> f64 {
        self.variance_ratio * self.s2
    }
}

/// κ of a profile written before it was recorded.
fn one() -> f64 {
    1.0
}

/// The end of the interval on one side: `outward` are the points of that
/// side as (value, ΔJ/s²) from the estimate `x_hat` outwards (`None` for a
/// failed refit), `bound` the box's end on that side.
pub fn interval_end(
    x_hat: f64,
    outward: &[(f64, Option<f64>)],
    bound: f64,
    threshold: f64,
) -> IntervalEnd {
    let mut inner = (x_hat, 0.0_f64);
    for &(x, d) in outward {
        let Some(d) = d else { continue };
        let d = d.max(0.0);
        if d >= threshold {
            let (r0, r1) = (inner.1.sqrt(), d.sqrt());
            let t = (threshold.sqrt() - r0) / (r1 - r0);
            return IntervalEnd::Crossed {
                value: inner.0 + t * (x - inner.0),
            };
        }
        inner = (x, d);
    }
    match inner.0 == bound {
        true => IntervalEnd::Open { bound },
        false => IntervalEnd::Unresolved { last: inner.0 },
    }
}

/// The warnings of a profile: open or unresolved ends, or an interval
/// whose width or either half-width differs from the Wald interval's by
/// more than [`DIFFERENCE`] of it.
pub fn profile_warnings(p: &ParameterProfile) -> Vec<Warning> {
    let mut out = Vec::new();
    let ends = [("lower", &p.lower), ("upper", &p.upper)];
    let open: Vec<f64> = ends
        .iter()
        .filter_map(|(_, e)| match e {
            IntervalEnd::Open { bound } => Some(*bound),
            _ => None,
        })
        .collect();
    if !open.is_empty() {
        out.push(Warning::ProfileOpen {
            parameter: p.name.clone(),
            bounds: open,
        });
    }
    for (side, e) in ends {
        if let IntervalEnd::Unresolved { last } = e {
            out.push(Warning::ProfileUnresolved {
                parameter: p.name.clone(),
                side: side.to_string(),
                last: *last,
            });
        }
    }
    if let (Some(lo), Some(hi), Some([wlo, whi])) = (p.lower.value(), p.upper.value(), p.wald) {
        let half = (whi - wlo) / 2.0;
        let differs = |a: f64, b: f64| (a - b).abs() > DIFFERENCE * b;
        if differs(hi - lo, whi - wlo)
            || differs(p.estimate - lo, half)
            || differs(hi - p.estimate, half)
        {
            out.push(Warning::ProfileDiffers {
                parameter: p.name.clone(),
                profile: [lo, hi],
                wald: [wlo, whi],
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quadratic_profile_crosses_where_the_wald_interval_ends() {
        // ΔJ/s² = ((x − 2)/0.5)²: the 95 % interval is 2 ± 1.96·0.5.
        let t = threshold();
        let side = |dir: f64| -> Vec<(f64, Option<f64>)> {
            (1..=10)
                .map(|k| {
                    let x = 2.0 + dir * 0.15 * k as f64;
                    (x, Some(((x - 2.0) / 0.5).powi(2)))
                })
                .collect()
        };
        let z = t.sqrt();
        let hi = interval_end(2.0, &side(1.0), 10.0, t).value().unwrap();
        let lo = interval_end(2.0, &side(-1.0), -10.0, t).value().unwrap();
        assert!((hi - (2.0 + z * 0.5)).abs() < 1e-12, "{hi}");
        assert!((lo - (2.0 - z * 0.5)).abs() < 1e-12, "{lo}");
        assert!((z - 1.959_963_984_540_054).abs() < 1e-9);
    }

    #[test]
    fn a_flat_side_is_open_at_its_bound_and_failures_are_skipped() {
        let t = threshold();
        let pts = [(1.0, Some(0.1)), (2.0, None), (3.0, Some(0.5))];
        assert_eq!(
            interval_end(0.0, &pts, 3.0, t),
            IntervalEnd::Open { bound: 3.0 }
        );
        assert_eq!(
            interval_end(0.0, &pts[..2], 3.0, t),
            IntervalEnd::Unresolved { last: 1.0 }
        );
        assert_eq!(
            interval_end(0.0, &[], 0.0, t),
            IntervalEnd::Open { bound: 0.0 }
        );
    }
}
