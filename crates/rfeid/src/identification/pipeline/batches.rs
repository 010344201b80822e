//! The plan evaluated in batches, abandoning the points that cannot be
//! among the best ones ("early abandoning").
//!
//! The plan only ranks its points: the searches start from the best
//! [`keep`] (the starts, then the restarts). J is a sum of squares over the
//! samples (eq. 13), so a point whose running sum already exceeds the
//! `keep`-th best complete J cannot be among them, and its simulation stops
//! there ([`crate::identification::output_error::Watched`]).
//!
//! The points are evaluated in fixed batches in plan order (the first of
//! at least `keep` points), and the limit of a batch is the `keep`-th best
//! J of the batches before it (infinite while they hold fewer than `keep`
//! successful points), raised by a margin that covers the rounding of the
//! running sum, which is summed in another order than J: a relative
//! `4 N ε` for N residuals, above the `(N − 1) u` that bounds either sum's
//! relative rounding error (ε = 2u). The limit changes only between
//! batches, so which points are abandoned depends on the plan and the data
//! alone, not on the threads or their timing.
//!
//! Exact for the ranking: a point abandoned in a batch has J above that
//! batch's threshold, which is at least the final `keep`-th best J, so the
//! best `keep` points are the same points with the same J as if every
//! point had been evaluated to the end, and so are their ties (in plan
//! order). A point abandoned is neither a J nor a failure: a point that
//! would have failed later is reported as abandoned, as is every point
//! abandoned (`plan.abandoned` of RESULT.json). The restarts may look
//! deeper than `keep`; those points are evaluated to the end when the walk
//! reaches them (`plan_run`).
use super::error::IdentifyError;
use super::plan::{evaluate_within, Evaluated, PointOutcome};
use super::settings::{Progress, Settings};
use crate::identification::output_error::OutputError;
use crate::identification::plan::Plan;
use crate::identification::problem::LeastSquares;

/// Points of every batch after the first (the first has at least
/// [`keep`]): small enough that the limit follows the best points closely,
/// large enough that the threads rarely wait for one another at a batch's
/// end.
const BATCH: usize = 16;

/// A plan point as the run knows it.
#[derive(Debug, Clone, PartialEq)]
pub enum PointState {
    /// Evaluated to the end: J, or why it failed.
    Done(PointOutcome),
    /// Abandoned: its running J passed its batch's limit, so its J is
    /// above `above`, the `keep`-th best J of the batches before it.
    Abandoned {
        /// A strict lower bound of its J.
        above: f64,
    },
}

/// The plan's points as the stages after it take them.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanPoints {
    /// Every point's state, in plan order.
    pub states: Vec<PointState>,
    /// For a merge: every point's outcome, the abandoned ones' included
    /// (the shards evaluated them to the end), so that a restart that
    /// needs one takes it instead of simulating it again.
    pub known: Option<Vec<PointOutcome>>,
}

impl PlanPoints {
    /// Points all evaluated to the end (nothing abandoned).
    pub fn whole(outcomes: Vec<PointOutcome>) -> Self {
        PlanPoints {
            states: outcomes.into_iter().map(PointState::Done).collect(),
            known: None,
        }
    }
}

/// How many of the plan's best points must be exact: the local searches'
/// starts and the restarts'.
pub fn keep(settings: &Settings) -> usize {
    settings.starts + settings.restarts
}

/// The limits of the batches: the `keep` best complete J so far.
struct Limit {
    keep: usize,
    /// The best J so far, ascending, at most `keep`.
    best: Vec<f64>,
    /// The relative margin for the rounding of the running sums.
    margin: f64,
}

impl Limit {
    fn new(keep: usize, n_residuals: usize) -> Self {
        Limit {
            keep: keep.max(1),
            best: Vec::new(),
            margin: 4.0 * n_residuals as f64 * f64::EPSILON,
        }
    }

    /// The `keep`-th best J so far (+∞ while there are fewer).
    fn level(&self) -> f64 {
        match self.best.len() < self.keep {
            true => f64::INFINITY,
            false => self.best[self.keep - 1],
        }
    }

    /// The limit of the next batch's running sums.
    fn limit(&self) -> f64 {
        let level = self.level();
        level + level * self.margin
    }

    /// Takes a complete J into the best ones.
    fn add(&mut self, cost: f64) {
        let at = self.best.partition_point(|&b| b <= cost);
        if at < self.keep {
            self.best.insert(at, cost);
            self.best.truncate(self.keep);
        }
    }

    /// Takes a batch's outcomes into the best ones.
    fn add_all<'a>(&mut self, outcomes: impl Iterator<Item = &'a PointState>) {
        for o in outcomes {
            if let PointState::Done(Ok(cost)) = o {
                self.add(*cost);
            }
        }
    }
}

/// The batches of a plan of `points`, in plan order: the first of
/// `max(keep, BATCH)` points, then [`BATCH`] each.
fn batches(points: usize, keep: usize) -> impl Iterator<Item = std::ops::Range<usize>> {
    let first = keep.max(BATCH).min(points);
    std::iter::once(0..first).chain(
        (first..points)
            .step_by(BATCH)
            .map(move |a| a..(a + BATCH).min(points)),
    )
}

/// J at every point of `plan`, batch by batch, abandoning those that cannot
/// be among the best `keep` (module documentation).
pub fn evaluate_abandoning(
    problem: &OutputError<'_>,
    plan: &Plan,
    keep: usize,
    progress: &dyn Progress,
) -> Result<Vec<PointState>, IdentifyError> {
    let mut limit = Limit::new(keep, problem.n_residuals());
    let mut states = Vec::with_capacity(plan.len());
    for batch in batches(plan.len(), keep) {
        let indices: Vec<usize> = batch.collect();
        let above = limit.level();
        let got = evaluate_within(problem, plan, &indices, limit.limit(), progress)?;
        let from = states.len();
        states.extend(got.into_iter().map(|e| match e {
            Some(e) => PointState::Done(e.outcome),
            None => PointState::Abandoned { above },
        }));
        limit.add_all(states[from..].iter());
        if problem.cancel().is_set() {
            break;
        }
    }
    Ok(states)
}

/// What [`evaluate_abandoning`] gives from points evaluated to the end (a
/// merge's, from its shards): a point is abandoned there if and only if
/// its reach exceeds its batch's limit. A point without a reach (a shard
/// written before reaches were recorded) is never abandoned.
pub fn replay(points: &[Evaluated], keep: usize, n_residuals: usize) -> Vec<PointState> {
    let mut limit = Limit::new(keep, n_residuals);
    let mut states = Vec::with_capacity(points.len());
    for batch in batches(points.len(), keep) {
        let (above, at) = (limit.level(), limit.limit());
        let from = states.len();
        states.extend(points[batch].iter().map(|e| match e.reach > at {
            true => PointState::Abandoned { above },
            false => PointState::Done(e.outcome.clone()),
        }));
        limit.add_all(states[from..].iter());
    }
    states
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batches_cover_the_plan_once_in_order() {
        for (points, keep) in [(0, 9), (5, 9), (16, 9), (100, 9), (100, 40), (33, 1)] {
            let all: Vec<usize> = batches(points, keep).flatten().collect();
            assert_eq!(all, (0..points).collect::<Vec<_>>(), "{points} {keep}");
            let sizes: Vec<usize> = batches(points, keep).map(|b| b.len()).collect();
            assert!(sizes[0] >= keep.min(points) && sizes[0] >= BATCH.min(points));
            assert!(sizes[1..].iter().all(|&s| (1..=BATCH).contains(&s)));
        }
    }

    #[test]
    fn the_limit_is_the_keep_th_best_with_its_margin() {
        let mut l = Limit::new(3, 1000);
        assert_eq!(l.limit(), f64::INFINITY);
        for c in [5.0, 1.0, 4.0, 9.0, 1.0] {
            l.add(c);
        }
        assert_eq!(l.best, [1.0, 1.0, 4.0]);
        assert_eq!(l.level(), 4.0);
        assert!(l.limit() > 4.0 && l.limit() < 4.0 * (1.0 + 1e-12));
    }

    /// A replay abandons exactly the points whose reach passes the limit
    /// of their batch, and never the first batch's.
    #[test]
    fn a_replay_abandons_by_reach_after_the_first_batch() {
        let points: Vec<Evaluated> = (0..40)
            .map(|k| {
                let cost = (40 - k) as f64;
                Evaluated {
                    outcome: Ok(cost),
                    reach: cost * 0.5,
                }
            })
            .collect();
        let states = replay(&points, 2, 10);
        assert!(states[..16]
            .iter()
            .all(|s| matches!(s, PointState::Done(_))));
        // After the first batch the 2nd best is 26: the reach 12 of J = 24
        // passes nothing, the reach 13.5 of J = 27 is no more than 26 either.
        assert!(states[16..]
            .iter()
            .all(|s| matches!(s, PointState::Done(_))));
        let far: Vec<Evaluated> = points
            .iter()
            .map(|e| Evaluated {
                reach: e.reach * 4.0,
                ..e.clone()
            })
            .collect();
        let states = replay(&far, 2, 10);
        // J = 24 (point 16): reach 48 > 26, abandoned above 26.
        assert_eq!(states[16], PointState::Abandoned { above: 26.0 });
        assert!(states[..16]
            .iter()
            .all(|s| matches!(s, PointState::Done(_))));
    }
}
