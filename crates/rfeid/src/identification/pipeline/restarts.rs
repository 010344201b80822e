//! Stage 4, the restarts ([`super::Settings::restarts`]): if no search
//! ends where the fit passes the verdict's per-sensor checks, further
//! searches start from the best remaining plan points (by J) that lie at
//! least [`DISTINCT`] from every start and end so far, one at a time, until
//! one passes, the restarts run out, or [`AGREEING`] restarts come back to
//! the lowest minimum found so far (within the verdict's minima threshold).
//! Deterministic: the candidates follow the
//! plan's ranking, exact as far as it goes (abandoned points that might
//! rank before a candidate are evaluated to the end first: `plan_run`).
//!
//! No restart runs when the bounds at the best end already show parameters
//! that cannot be told apart (a singular Fisher matrix, or correlations
//! beyond the warning threshold): the searches then end on a ridge of J at
//! points the noise picks, and no other start changes that. A warning says
//! so first, and the verdict names the combinations the data fix.
use super::bounds::{self, BoundsError};
use super::judge::fit_passes;
use super::plan_run::PlanRun;
use super::searcher::Searcher;
use super::settings::Start;
use super::starts::Ends;
use crate::identification::output_error::OutputError;
use crate::identification::problem::LeastSquares;
use crate::identification::result::StartFailure;
use crate::identification::uncertainty::{IdentifiabilityWarning, UncertaintyError};
use crate::identification::verdict::minima_threshold;
use crate::identification::warning::Warning;

/// Plan points closer than this (RMS over the normalised coordinates) to a
/// start or an end already searched are not restarted from: they would most
/// likely end in the same minimum.
const DISTINCT: f64 = 0.1;

/// Restarts that end in the lowest minimum so far (within the verdict's
/// minima threshold) after which the restarts stop: distinct starts agree
/// that the fit is the model's best, and the misfit is model error, not a
/// wrong minimum. An end above it does not count: it says the criterion has
/// side minima, and a lower one may still be found.
const AGREEING: usize = 2;

/// Which ends the restarts judged side minima.
#[derive(Debug, Default)]
pub(super) struct Judged {
    /// When a restart found an end that passes the fit checks: whether
    /// each search (in order) passes, so that the side minima are left out.
    pub passed: Option<Vec<bool>>,
}

impl Judged {
    /// Whether search `k` is kept (not a side minimum left behind).
    pub fn keeps(&self, k: usize) -> bool {
        self.passed.as_ref().is_none_or(|p| p[k])
    }
}

/// Runs the restarts, appending their searches, failures and warning to
/// `ends`.
pub(super) fn run(
    problem: &OutputError<'_>,
    searcher: &Searcher<'_>,
    plan: &mut PlanRun<'_, '_>,
    ends: &mut Ends,
) -> Judged {
    let s = searcher.settings();
    if s.start == Start::Values || s.restarts == 0 {
        return Judged::default();
    }
    let passes = |u: &[f64]| fit_passes(problem, &s.verdict, s.noise_model, u);
    let mut passed: Vec<bool> = ends.searches.iter().map(|e| passes(&e.u)).collect();
    if passed.iter().any(|&p| p) || ends.searches.is_empty() {
        return Judged::default();
    }
    let first_cost = lowest(ends.searches.iter().map(|e| e.cost));
    if let Some(warning) = ridge(problem, s, ends, first_cost) {
        ends.restart_warning = Some(warning);
        return Judged::default();
    }
    let mut visited = starts_and_ends(plan, ends);
    let mut tried = 0;
    let mut agreeing = Agreement::default();
    let mut position = 0;
    while tried < s.restarts {
        // The next point by J; abandoned points are evaluated to the end
        // first where they might rank before it.
        let Some((idx, cost)) = plan.ranked(position) else {
            break;
        };
        position += 1;
        let p = plan.plan.point(idx);
        if ends.used.contains(&idx) || visited.iter().any(|v| distance(v, p) < DISTINCT) {
            continue;
        }
        tried += 1;
        visited.push(p.to_vec());
        searcher.progress().search_started(
            ends.used.len() + tried - 1,
            ends.used.len() + s.restarts,
            cost,
        );
        match searcher.start_search(problem, p, &mut ends.warnings) {
            Ok(e) => {
                visited.push(e.u.clone());
                let ok = passes(&e.u);
                agreeing.count(problem, s, ends, e.cost);
                ends.searches.push(e);
                passed.push(ok);
                if ok || agreeing.settled() {
                    break;
                }
            }
            Err(e) => ends.failures.push(StartFailure {
                plan_index: idx,
                reason: e.to_string(),
            }),
        }
    }
    let found = passed.iter().any(|&p| p);
    let best = lowest(
        ends.searches
            .iter()
            .zip(&passed)
            .filter(|(_, p)| **p)
            .map(|(e, _)| e.cost),
    );
    ends.restart_warning = Some(Warning::SideMinimum {
        first_cost,
        restarts: tried,
        found: found.then_some(best),
        agreed: !found && agreeing.settled(),
    });
    Judged {
        passed: found.then_some(passed),
    }
}

/// The points searched from and the searches' ends so far.
fn starts_and_ends(plan: &PlanRun<'_, '_>, ends: &Ends) -> Vec<Vec<f64>> {
    let starts = ends.used.iter().map(|&i| plan.plan.point(i).to_vec());
    starts
        .chain(ends.searches.iter().map(|e| e.u.clone()))
        .collect()
}

/// [`Warning::RidgeNotRestarted`] naming the parameters that cannot be
/// told apart at the best end (by J, `first_cost`), when its bounds show
/// any: a singular Fisher matrix, or correlations beyond the warning
/// threshold. Restarts cannot help there: every start ends on the same
/// ridge, at a point the noise chooses.
fn ridge(
    problem: &OutputError<'_>,
    s: &super::Settings,
    ends: &Ends,
    first_cost: f64,
) -> Option<Warning> {
    let best = ends
        .searches
        .iter()
        .min_by(|a, b| a.cost.total_cmp(&b.cost))?;
    // Whether parameters can be told apart is the Fisher matrix's shape:
    // eq. 26 with one s² is enough.
    let bounds = bounds::at(
        problem,
        &best.u,
        best.linearised.as_ref(),
        &s.uncertainty,
        false,
    );
    let mut involved: Vec<usize> = match bounds.cramer_rao {
        Ok(c) => c
            .warnings
            .iter()
            .flat_map(|w| match w {
                IdentifiabilityWarning::StrongCorrelation { first, second, .. } => {
                    vec![*first, *second]
                }
                _ => Vec::new(),
            })
            .collect(),
        Err(BoundsError::Analysis(UncertaintyError::Singular { parameters, .. })) => parameters,
        Err(_) => Vec::new(),
    };
    involved.sort_unstable();
    involved.dedup();
    let columns = problem.columns();
    let parameters = involved.iter().map(|&j| columns[j].name.clone()).collect();
    (!involved.is_empty()).then_some(Warning::RidgeNotRestarted {
        first_cost,
        parameters,
    })
}

/// Restarts that came back to the lowest minimum so far: [`AGREEING`] of
/// them say the fit is the model's best.
#[derive(Debug, Default)]
struct Agreement(usize);

impl Agreement {
    /// Counts a restart that ended at J = `cost`, against the ends so far.
    fn count(&mut self, problem: &OutputError<'_>, s: &super::Settings, ends: &Ends, cost: f64) {
        let lowest_so_far = lowest(ends.searches.iter().map(|e| e.cost));
        let (r, n) = (problem.n_params(), problem.n_residuals());
        let level = minima_threshold(lowest_so_far, r, n, s.verdict.minima_level());
        if cost < lowest_so_far - level {
            // A lower minimum: it has yet to be confirmed.
            self.0 = 0;
        } else if cost <= lowest_so_far + level {
            self.0 += 1;
        }
    }

    /// Whether enough restarts agree.
    fn settled(&self) -> bool {
        self.0 >= AGREEING
    }
}

fn lowest(costs: impl Iterator<Item = f64>) -> f64 {
    costs.fold(f64::INFINITY, f64::min)
}

/// RMS distance of two normalised points.
fn distance(a: &[f64], b: &[f64]) -> f64 {
    (a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>() / a.len() as f64).sqrt()
}
