//! Stage 7b, the profiles (when asked): for each chosen parameter, J
//! (eq. 16) minimised over the others at a grid of its values about the
//! estimate, by the pipeline's Levenberg–Marquardt on the final criterion
//! (weights, whitening, steps and experiments as the bounds took them),
//! and the likelihood-ratio interval beside the Wald interval of the
//! bounds (eq. 26–29; see [`crate::identification::profile`]).
//!
//! The grid: half the points each side of û_j, spanning
//! [`GRID_STD_ERRORS`] standard errors (or up to the box's bound if that is
//! nearer, or if there is no standard error), extended towards the bound
//! while the profile stays below the threshold. The parameters are
//! profiled in parallel; each profile's refits run in order, and a
//! simulation's numbers do not depend on its threads, so the result is the
//! same for any number of threads.
use super::bounds::Bounds;
use super::error::IdentifyError;
use super::settings::{Progress, Settings};
use crate::identification::lm::LevenbergMarquardt;
use crate::identification::output_error::OutputError;
use crate::identification::profile::walk::{walk_side, Refit, Side, SidePlan, Walk};
use crate::identification::profile::{
    interval_end, profile_warnings, threshold, ParameterProfile, ProfilePoint, GRID_STD_ERRORS,
};
use crate::identification::search::SearchOutcome;
use crate::identification::uncertainty::CramerRao;
use crate::identification::warning::Warning;
use rayon::prelude::*;

/// The columns to profile: those named in the settings' request (every
/// one if it names none), in the criterion's order; empty when none is
/// asked. A name that is not an identified parameter is an error
/// (`identify` checks before its plan, `finish` before its
/// searches).
pub(super) fn columns(
    problem: &OutputError<'_>,
    settings: &Settings,
) -> Result<Vec<usize>, IdentifyError> {
    let Some(request) = &settings.profiles else {
        return Ok(Vec::new());
    };
    let names: Vec<&str> = problem.columns().iter().map(|c| c.name.as_str()).collect();
    if let Some(unknown) = request
        .parameters
        .iter()
        .find(|p| !names.contains(&p.as_str()))
    {
        return Err(IdentifyError::UnknownProfileParameter {
            name: unknown.clone(),
            identified: names.join(", "),
        });
    }
    Ok((0..names.len())
        .filter(|&j| {
            request.parameters.is_empty() || request.parameters.iter().any(|p| p == names[j])
        })
        .collect())
}

/// What every profile of the run shares.
struct Shared<'a, 'm> {
    problem: &'a OutputError<'m>,
    lm: LevenbergMarquardt,
    best: &'a SearchOutcome,
    cramer_rao: Option<&'a CramerRao>,
    s2: f64,
    points: usize,
    progress: &'a dyn Progress,
}

/// The profiles of `columns` at the estimate `best`, and their warnings
/// (one [`Warning::ProfilesSkipped`] if s² is unknown).
pub(super) fn run(
    problem: &OutputError<'_>,
    settings: &Settings,
    columns: &[usize],
    best: &SearchOutcome,
    bounds: &Bounds,
    progress: &dyn Progress,
) -> (Vec<ParameterProfile>, Vec<Warning>) {
    let Some(request) = settings.profiles.as_ref().filter(|_| !columns.is_empty()) else {
        return (Vec::new(), Vec::new());
    };
    let Some(s2) = bounds.s2.filter(|s| s.is_finite() && *s > 0.0) else {
        let why = "the residual variance s² (eq. 29) at the estimate is unknown or zero";
        return (Vec::new(), vec![Warning::ProfilesSkipped(why.into())]);
    };
    let shared = Shared {
        problem,
        lm: LevenbergMarquardt::new(settings.lm.clone()),
        best,
        cramer_rao: bounds.cramer_rao.as_ref().ok(),
        s2,
        points: request.points,
        progress,
    };
    progress.profiles_started(columns.len());
    // As many profiles as threads or more: one profile per thread, each
    // simulating on its own (the sensitivities' column groups would only
    // integrate the state again per group); fewer: one after the other,
    // each simulation's groups in parallel. Either way the same numbers.
    let profiles: Vec<ParameterProfile> = match columns.len() >= rayon::current_num_threads() {
        true => columns
            .par_iter()
            .map(|&j| on_one_thread(|| shared.profile(j)))
            .collect(),
        false => columns.iter().map(|&j| shared.profile(j)).collect(),
    };
    let warnings = profiles.iter().flat_map(|p| p.warnings.clone()).collect();
    (profiles, warnings)
}

/// `f` in a pool of one thread, so that the simulations it runs see one
/// thread (`rayon::current_num_threads`); in the caller's if such a pool
/// cannot be started.
fn on_one_thread<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(pool) => pool.install(f),
        Err(_) => f(),
    }
}

impl Shared<'_, '_> {
    /// The profile of column `j`.
    fn profile(&self, j: usize) -> ParameterProfile {
        let u_hat = &self.best.u;
        let direction = self.direction(j);
        let walk = Walk {
            lm: &self.lm,
            u_hat,
            cost_hat: self.best.cost,
            index: j,
            threshold: threshold() * self.scale(j),
            direction: direction.as_deref(),
        };
        let observe = || {};
        let lower = walk_side(
            self.problem,
            &walk,
            &self.side_plan(j, Side::Lower),
            &observe,
        );
        let upper = walk_side(
            self.problem,
            &walk,
            &self.side_plan(j, Side::Upper),
            &observe,
        );
        let profile = self.record(j, &lower, &upper);
        self.progress.profile_done(&profile.name);
        profile
    }

    /// The scale of column j's ΔJ: s² (eq. 29), times the ratio κ_j of its
    /// variance to eq. 26's where the bounds take each sensor's own noise
    /// level ([`CramerRao::variance_ratio`]), so that the profile interval
    /// and the Wald interval estimate the same spread.
    fn scale(&self, j: usize) -> f64 {
        self.s2 * self.ratio(j)
    }

    /// κ_j ([`CramerRao::variance_ratio`]; 1 without bounds).
    fn ratio(&self, j: usize) -> f64 {
        self.cramer_rao.map_or(1.0, |c| c.variance_ratio(j))
    }

    /// The normalised standard error of column j (eq. 26, divided by
    /// `dx_j/du_j` at the estimate), if known and positive.
    fn std_error_u(&self, j: usize) -> Option<f64> {
        let dx_du = self.problem.maps()[j].derivative(self.best.u[j]);
        let s = self.cramer_rao?.std_errors[j] / dx_du;
        (s.is_finite() && s > 0.0).then_some(s)
    }

    /// One side's grid: half the points (the upper side the odd one), over
    /// [`GRID_STD_ERRORS`] standard errors or to the bound if nearer.
    fn side_plan(&self, j: usize, side: Side) -> SidePlan {
        let points = match side {
            Side::Lower => self.points / 2,
            Side::Upper => self.points - self.points / 2,
        };
        let to_bound = match side {
            Side::Lower => self.best.u[j],
            Side::Upper => 1.0 - self.best.u[j],
        };
        let span = self
            .std_error_u(j)
            .map_or(to_bound, |s| (GRID_STD_ERRORS * s).min(to_bound));
        SidePlan {
            side,
            step: span / points.max(1) as f64,
            points: if span > 0.0 { points } else { 0 },
            extra: points,
        }
    }

    /// `du_i/du_j` along the bounds' linearised profile: the regression of
    /// x_i on x_j in the covariance D² (eq. 26, with one s²: the
    /// criterion's curvature), `D²_ij / D²_jj`, in normalised coordinates.
    fn direction(&self, j: usize) -> Option<Vec<f64>> {
        let bounds = self.cramer_rao?;
        let c = bounds.pooled.as_ref().unwrap_or(&bounds.covariance);
        let dx_du = self.problem.dx_du(&self.best.u);
        let d: Vec<f64> = (0..c.nrows())
            .map(|i| match i == j {
                true => 0.0,
                false => c[(i, j)] / c[(j, j)] * dx_du[j] / dx_du[i],
            })
            .collect();
        d.iter().all(|v| v.is_finite()).then_some(d)
    }

    /// The refits of both sides as the result records them, with the
    /// intervals and warnings.
    fn record(&self, j: usize, lower: &[Refit], upper: &[Refit]) -> ParameterProfile {
        let problem = self.problem;
        let map = problem.maps()[j];
        let estimate = map.to_physical(self.best.u[j]);
        let at_estimate = ProfilePoint {
            value: estimate,
            criterion: Some(self.best.cost),
            parameters: problem.to_physical(&self.best.u),
            termination: Some(self.best.stop),
            iterations: self.best.iterations,
            failure: None,
        };
        let point = |r: &Refit| self.point(map.to_physical(r.at), r);
        let points: Vec<ProfilePoint> = lower
            .iter()
            .rev()
            .map(point)
            .chain(std::iter::once(at_estimate))
            .chain(upper.iter().map(point))
            .collect();
        let criterion = points
            .iter()
            .filter_map(|p| p.criterion)
            .fold(self.best.cost, f64::min);
        let std_error = self.cramer_rao.map(|c| c.std_errors[j]);
        let t = threshold();
        let outward = |refits: &[Refit]| -> Vec<(f64, Option<f64>)> {
            refits
                .iter()
                .map(|r| {
                    let d = r
                        .end
                        .as_ref()
                        .ok()
                        .map(|e| (e.cost - criterion) / self.scale(j));
                    (map.to_physical(r.at), d)
                })
                .collect()
        };
        let (lo, hi) = (map.to_physical(0.0), map.to_physical(1.0));
        let mut profile = ParameterProfile {
            name: problem.columns()[j].name.clone(),
            estimate,
            std_error,
            criterion,
            s2: self.s2,
            variance_ratio: self.ratio(j),
            threshold: t,
            wald: std_error.map(|s| [estimate - t.sqrt() * s, estimate + t.sqrt() * s]),
            lower: interval_end(estimate, &outward(lower), lo, t),
            upper: interval_end(estimate, &outward(upper), hi, t),
            points,
            warnings: Vec::new(),
        };
        profile.warnings = profile_warnings(&profile);
        profile
    }

    /// One refit as the result records it, at the held value `value` (SI).
    fn point(&self, value: f64, r: &Refit) -> ProfilePoint {
        match &r.end {
            Ok(e) => ProfilePoint {
                value,
                criterion: Some(e.cost),
                parameters: self.problem.to_physical(&e.u),
                termination: Some(e.stop),
                iterations: e.iterations,
                failure: None,
            },
            Err(why) => ProfilePoint {
                value,
                criterion: None,
                parameters: Vec::new(),
                termination: None,
                iterations: 0,
                failure: Some(why.clone()),
            },
        }
    }
}
