//! What the stages after the plan take from it ([`PlanRun`]): the points
//! the searches start from, the ranking the restarts walk, the plan's
//! simulations and its summary in RESULT.json.
//!
//! The ranking is exact as far as the walk goes: before it hands out a
//! point, every abandoned point that might rank before it (its lower bound
//! below the point's J) is evaluated to the end, at the plan's steps, by a
//! copy of the criterion as the plan had it (the searches change its
//! weights) counted apart; a merge takes those points' J from its shards
//! instead. Either way the same points are completed, so a merge still
//! equals the single run.
use super::batches::{PlanPoints, PointState};
use super::error::IdentifyError;
use super::plan::{evaluate_points, PointOutcome};
use super::settings::{Settings, Silent};
use crate::identification::output_error::OutputError;
use crate::identification::plan::{Plan, PlanError};
use crate::identification::problem::LeastSquares;
use crate::identification::result::PlanSummary;
use crate::identification::tally::{Tally, Work};
use std::time::Instant;

/// Where the J of an abandoned point comes from when the walk needs it.
enum Source<'m> {
    /// A copy of the plan's criterion, counted apart.
    Simulate(Box<OutputError<'m>>),
    /// The shards' outcomes of every point.
    Known(Vec<PointOutcome>),
}

/// The evaluated plan, checked, with the points the local searches start
/// from.
pub(super) struct PlanRun<'p, 'm> {
    /// The plan.
    pub plan: &'p Plan,
    /// Every point's state, in plan order.
    states: Vec<PointState>,
    /// The best `settings.starts` points (plan index, J), best first.
    pub starts: Vec<(usize, f64)>,
    /// The successful points by increasing J, ties in plan order.
    ranking: Vec<usize>,
    /// The abandoned points by increasing lower bound.
    abandoned: Vec<usize>,
    /// Where the J of an abandoned point comes from (none when nothing was
    /// abandoned).
    source: Option<Source<'m>>,
    /// Points evaluated to the end after the plan, and the time it took, s.
    completed: usize,
    completion_seconds: f64,
    n_experiments: usize,
}

impl<'p, 'm> PlanRun<'p, 'm> {
    /// Checks `points` against the plan and the problem (as the plan
    /// evaluated it) and ranks them; an error if they do not belong
    /// together or every point failed.
    pub fn new(
        problem: &OutputError<'m>,
        settings: &Settings,
        plan: &'p Plan,
        points: PlanPoints,
    ) -> Result<Self, IdentifyError> {
        let PlanPoints { states, known } = points;
        let n = plan.len();
        if states.len() != n
            || known.as_ref().is_some_and(|k| k.len() != n)
            || plan.dims() != problem.n_params()
        {
            return Err(IdentifyError::Plan(PlanError::DimensionMismatch {
                plan: plan.dims(),
                problem: problem.n_params(),
            }));
        }
        if states.iter().all(|s| matches!(s, PointState::Done(Err(_)))) {
            return Err(IdentifyError::AllPlanPointsFailed {
                points: n,
                first: first_failure(&states).unwrap_or_default(),
            });
        }
        let ranking = rank(&states);
        let starts = ranking
            .iter()
            .take(settings.starts)
            .map(|&k| (k, cost(&states[k])))
            .collect();
        let mut abandoned: Vec<usize> = (0..n).filter(|&k| above(&states[k]).is_some()).collect();
        let bound = |k: usize| above(&states[k]).unwrap_or(f64::INFINITY);
        abandoned.sort_by(|&a, &b| bound(a).total_cmp(&bound(b)));
        let source = match (known, abandoned.is_empty()) {
            (_, true) => None,
            (Some(k), false) => Some(Source::Known(k)),
            (None, false) => Some(Source::Simulate(Box::new(problem.counted_apart()))),
        };
        Ok(PlanRun {
            plan,
            states,
            starts,
            ranking,
            abandoned,
            source,
            completed: 0,
            completion_seconds: 0.0,
            n_experiments: problem.n_experiments(),
        })
    }

    /// The successful point at `position` of the ranking (by J, ties in
    /// plan order) and its J, or `None` past the last: the abandoned points
    /// that might rank before it are first evaluated to the end.
    pub fn ranked(&mut self, position: usize) -> Option<(usize, f64)> {
        loop {
            let next = self
                .ranking
                .get(position)
                .map(|&k| (k, cost(&self.states[k])));
            let bound = next.map_or(f64::INFINITY, |(_, c)| c);
            // J > above ≥ bound: such a point ranks after `next`.
            let pending = self
                .abandoned
                .partition_point(|&k| above(&self.states[k]).is_some_and(|a| a < bound));
            if pending == 0 {
                return next;
            }
            let points: Vec<usize> = self.abandoned.drain(..pending).collect();
            self.complete(&points);
        }
    }

    /// Evaluates the abandoned `points` to the end.
    fn complete(&mut self, points: &[usize]) {
        let started = Instant::now();
        let outcomes: Vec<PointOutcome> = match &self.source {
            Some(Source::Known(all)) => points.iter().map(|&k| all[k].clone()).collect(),
            Some(Source::Simulate(problem)) => {
                match evaluate_points(problem, self.plan, points, &Silent) {
                    Ok(e) => e.into_iter().map(|e| e.outcome).collect(),
                    Err(e) => vec![Err(e.to_string()); points.len()],
                }
            }
            None => vec![Err("no source of the plan's J".into()); points.len()],
        };
        for (&k, o) in points.iter().zip(outcomes) {
            self.states[k] = PointState::Done(o);
        }
        self.completed += points.len();
        self.ranking = rank(&self.states);
        self.completion_seconds += started.elapsed().as_secs_f64();
    }

    /// The simulations the plan took: each point simulates every
    /// experiment once, abandoned or not, and again if the restarts needed
    /// it to the end; a failed point counts one failure (a point that the
    /// searches' fewer steps could not simulate, evaluated again at the
    /// chosen ones, counts once).
    pub fn tally(&self) -> Tally {
        Tally {
            simulations: (self.plan.len() + self.completed) * self.n_experiments,
            with_sensitivities: 0,
            failed: self.failed(),
        }
    }

    /// The simulations run to complete abandoned points, and their time
    /// (for `--timings`), and the wall time the completions took, s.
    pub fn completion_work(&self) -> (Work, f64) {
        let work = match &self.source {
            Some(Source::Simulate(p)) => p.work(),
            _ => Work::default(),
        };
        (work, self.completion_seconds)
    }

    fn failed(&self) -> usize {
        self.states
            .iter()
            .filter(|s| matches!(s, PointState::Done(Err(_))))
            .count()
    }

    /// The plan as RESULT.json records it.
    pub fn summary(&self) -> PlanSummary {
        PlanSummary {
            points: self.plan.len(),
            failed: self.failed(),
            costs: self
                .states
                .iter()
                .map(|s| match s {
                    PointState::Done(Ok(c)) => Some(*c),
                    _ => None,
                })
                .collect(),
            starts: self.starts.iter().map(|s| s.0).collect(),
            first_failure: first_failure(&self.states),
            abandoned: (0..self.states.len())
                .filter(|&k| above(&self.states[k]).is_some())
                .collect(),
        }
    }
}

/// The J of a successful point (NaN otherwise: never asked).
fn cost(s: &PointState) -> f64 {
    match s {
        PointState::Done(Ok(c)) => *c,
        _ => f64::NAN,
    }
}

/// The lower bound of an abandoned point's J.
fn above(s: &PointState) -> Option<f64> {
    match s {
        PointState::Abandoned { above } => Some(*above),
        PointState::Done(_) => None,
    }
}

/// The successful points sorted by J; the sort is stable, so ties keep
/// plan order.
fn rank(states: &[PointState]) -> Vec<usize> {
    let mut ranking: Vec<usize> = (0..states.len())
        .filter(|&k| matches!(states[k], PointState::Done(Ok(_))))
        .collect();
    ranking.sort_by(|&a, &b| cost(&states[a]).total_cmp(&cost(&states[b])));
    ranking
}

fn first_failure(states: &[PointState]) -> Option<String> {
    states.iter().find_map(|s| match s {
        PointState::Done(Err(e)) => Some(e.clone()),
        _ => None,
    })
}

#[cfg(test)]
mod tests {
    use super::super::batches::{evaluate_abandoning, replay};
    use super::*;
    use crate::io::model_file::parse_model;
    use crate::simulation::{Simulator, Workspace};
    use std::path::Path;

    /// One body on a spring and damper to identify over wide boxes, driven
    /// by a chirp, 500 samples of its displacement.
    fn model() -> crate::model::Model {
        let text = "[simulation]\nduration = 0.05\nsample_rate = 10000.0\n\n\
             [[body]]\nname = \"b\"\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\ncom = [0, 0, 0]\n\n\
             [[element]]\nname = \"s\"\nbody = \"b\"\nto = \"ground\"\nat = [0, 0, 0]\n\
             ux = { k = \"k\", c = \"c\" }\n\n\
             [[excitation]]\nname = \"p\"\nbody = \"b\"\nat = [0, 0, 0]\ndirection = [1, 0, 0]\n\
             signal = { type = \"chirp\", amplitude = 1.0, f0 = 10.0, f1 = 800.0 }\n\n\
             [[sensor]]\nname = \"x\"\nbody = \"b\"\nat = [0, 0, 0]\ndirection = [1, 0, 0]\n\
             quantity = \"displacement\"\n\n\
             [[parameter]]\nname = \"k\"\nvalue = 4e6\nmin = 1e5\nmax = 1e8\nscale = \"log\"\n\n\
             [[parameter]]\nname = \"c\"\nvalue = 40.0\nmin = 1.0\nmax = 1000.0\nscale = \"log\"\n";
        parse_model(text, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}"))
    }

    /// The walk hands out the successful points in the order of the plan
    /// evaluated to the end, with the same J, though most were abandoned:
    /// simulating them when it reaches them, or taking them from the
    /// shards (a merge); both complete the same points.
    #[test]
    fn the_walk_past_the_kept_points_is_the_whole_ranking() {
        let m = model();
        let sim = Simulator::new(&m);
        let mut y = sim.response_buffer();
        sim.run(&m.nominal(), &mut Workspace::default(), &mut y)
            .unwrap();
        let problem = OutputError::new(sim, y, 0);
        let settings = Settings {
            plan_points: 48,
            starts: 1,
            ..Settings::default()
        };
        let plan = super::super::plan::plan(&problem, &settings).unwrap();
        let all: Vec<usize> = (0..plan.len()).collect();
        let whole = evaluate_points(&problem, &plan, &all, &Silent).unwrap();
        let states = evaluate_abandoning(&problem, &plan, 1, &Silent).unwrap();
        assert_eq!(replay(&whole, 1, problem.n_residuals()), states);
        let mut expected: Vec<(usize, f64)> = whole
            .iter()
            .enumerate()
            .filter_map(|(k, e)| e.outcome.as_ref().ok().map(|&c| (k, c)))
            .collect();
        expected.sort_by(|a, b| a.1.total_cmp(&b.1));
        let known = whole.iter().map(|e| e.outcome.clone()).collect();
        let mut summaries = Vec::new();
        for known in [None, Some(known)] {
            let points = PlanPoints {
                states: states.clone(),
                known,
            };
            let mut run = PlanRun::new(&problem, &settings, &plan, points).unwrap();
            let abandoned = run.summary().abandoned.len();
            assert!(abandoned >= 16, "{abandoned} abandoned");
            // The first few need nothing evaluated again.
            assert_eq!(run.ranked(0), Some(expected[0]));
            assert_eq!(run.completed, 0);
            let walked: Vec<(usize, f64)> = (0..).map_while(|p| run.ranked(p)).collect();
            assert_eq!(walked, expected);
            assert_eq!(run.completed, abandoned);
            assert_eq!(run.tally().simulations, plan.len() + abandoned);
            summaries.push(run.summary());
        }
        assert_eq!(summaries[0], summaries[1]);
        assert!(summaries[0].abandoned.is_empty());
    }
}
