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
//! The restarts that could all be needed run at the same time (rayon): as
//! many as must still agree. Their ends are then taken in turn, as one at
//! a time would take them; the ends after one that settles the restarts,
//! or from a start near an end taken before it in the batch, are left out
//! (and timed apart, [`crate::identification::result::Timings::discarded`]),
//! so the result is the one-at-a-time result whatever the threads. A search
//! mostly runs on one thread (one experiment, a few parameters), so two
//! searches at once take about the time of one on a 2-core machine.
//!
//! No restart runs when the bounds at the best end already show parameters
//! that cannot be told apart (a singular Fisher matrix, or correlations
//! beyond the warning threshold): the searches then end on a ridge of J at
//! points the noise picks, and no other start changes that. A warning says
//! so first, and the verdict names the combinations the data fix.
use super::bounds::{self, BoundsError};
use super::judge::fit_passes;
use super::plan_run::PlanRun;
use super::searcher::{Searcher, Started};
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
    let mut settled = false;
    while tried < s.restarts && !settled {
        // As many restarts at once as could all be needed: those that must
        // still agree, since one that passes ends the restarts.
        let count = (AGREEING - agreeing.0).min(s.restarts - tried);
        let picks = next_picks(plan, ends, &visited, position, count);
        let Some(last) = picks.last() else {
            break;
        };
        position = last.position + 1;
        let (first, of) = (ends.used.len() + tried, ends.used.len() + s.restarts);
        let started = search_picks(problem, searcher, plan, &picks, (first, of));
        let mut passed_over = false;
        for (pick, done) in picks.iter().zip(started) {
            let p = plan.plan.point(pick.index);
            // After a restart that settles them, or before a pick near an
            // end this batch found (one at a time, the restarts would have
            // passed it over, and the next batch looks from there), the
            // batch's ends are not needed.
            passed_over = passed_over || visited.iter().any(|v| distance(v, p) < DISTINCT);
            if settled || passed_over {
                searcher.record(done.seconds, false);
                position = position.min(pick.position);
                continue;
            }
            tried += 1;
            visited.push(p.to_vec());
            searcher.record(done.seconds, true);
            ends.warnings.extend(done.warnings);
            match done.outcome {
                Ok(e) => {
                    visited.push(e.u.clone());
                    let ok = passes(&e.u);
                    agreeing.count(problem, s, ends, e.cost);
                    ends.searches.push(e);
                    passed.push(ok);
                    settled = ok || agreeing.settled();
                }
                Err(e) => ends.failures.push(StartFailure {
                    plan_index: pick.index,
                    reason: e.to_string(),
                }),
            }
        }
    }
    judged(ends, passed, (first_cost, tried), agreeing.settled())
}

/// What the restarts did, as [`Warning::SideMinimum`] into `ends`, and
/// which searches (`passed` of each) are kept; `tried` restarts after a
/// first best J of `first_cost`.
fn judged(
    ends: &mut Ends,
    passed: Vec<bool>,
    (first_cost, tried): (f64, usize),
    settled: bool,
) -> Judged {
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
        agreed: !found && settled,
    });
    Judged {
        passed: found.then_some(passed),
    }
}

/// A plan point the restarts search from next.
struct Pick {
    /// Its index in the plan.
    index: usize,
    /// Its J.
    cost: f64,
    /// Its position in the plan's ranking.
    position: usize,
}

/// The next `count` plan points by J from ranking `position` on, each at
/// least [`DISTINCT`] from every point in `visited`, from each other and
/// from the starts: the restarts one at a time would take them in turn if
/// no search among them ended near a later one.
fn next_picks(
    plan: &mut PlanRun<'_, '_>,
    ends: &Ends,
    visited: &[Vec<f64>],
    mut position: usize,
    count: usize,
) -> Vec<Pick> {
    let mut picks: Vec<Pick> = Vec::with_capacity(count);
    while picks.len() < count {
        // The next point by J; abandoned points are evaluated to the end
        // first where they might rank before it.
        let Some((index, cost)) = plan.ranked(position) else {
            break;
        };
        let p = plan.plan.point(index);
        let near = |v: &[f64]| distance(v, p) < DISTINCT;
        let taken =
            visited.iter().any(|v| near(v)) || picks.iter().any(|q| near(plan.plan.point(q.index)));
        if !ends.used.contains(&index) && !taken {
            picks.push(Pick {
                index,
                cost,
                position,
            });
        }
        position += 1;
    }
    picks
}

/// The searches from `picks` at once, announced as searches `first`, … of
/// `of`.
fn search_picks(
    problem: &OutputError<'_>,
    searcher: &Searcher<'_>,
    plan: &PlanRun<'_, '_>,
    picks: &[Pick],
    (first, of): (usize, usize),
) -> Vec<Started> {
    for (k, pick) in picks.iter().enumerate() {
        searcher.progress().search_started(first + k, of, pick.cost);
    }
    let points: Vec<&[f64]> = picks.iter().map(|p| plan.plan.point(p.index)).collect();
    searcher.start_searches(problem, &points)
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
