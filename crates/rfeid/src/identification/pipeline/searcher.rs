//! The local search as the stages call it: the chosen method
//! ([`crate::identification::search::LocalSearch`]) with progress, and a
//! start's search on a short window of the record first.
use super::error::{IdentifyError, SearchError};
use super::settings::{Progress, Settings};
use crate::identification::bfgs::Bfgs;
use crate::identification::lm::{LevenbergMarquardt, LmSettings};
use crate::identification::output_error::OutputError;
use crate::identification::problem::LeastSquares;
use crate::identification::search::{LocalSearch, Method, SearchOutcome};
use crate::identification::warning::Warning;
use crate::model::Model;
use crate::simulation::{Response, Simulator};
use rayon::prelude::*;
use std::sync::Mutex;
use std::time::Instant;

/// A search from a start run among others ([`Searcher::start_searches`]).
pub(super) struct Started {
    /// Its end, or why it has none.
    pub outcome: Result<SearchOutcome, SearchError>,
    /// The warnings it raised.
    pub warnings: Vec<Warning>,
    /// Its wall time, s.
    pub seconds: f64,
}

/// The settings of every local search of one run.
pub(super) struct Searcher<'s> {
    settings: &'s Settings,
    /// Levenberg–Marquardt on the window: it only has to bring the search
    /// into the whole record's basin, so it stops once the Gauss–Newton step
    /// would gain less than r residual variances there, the expected scatter
    /// of the window's own minimum about the truth (a χ² with r degrees of
    /// freedom), instead of polishing a minimum the whole record moves.
    window_lm: LmSettings,
    progress: &'s dyn Progress,
    /// Wall time of each search from a start, s, in order.
    times: Mutex<Vec<f64>>,
    /// Wall time of each restart run ahead whose end was not needed, s.
    discarded: Mutex<Vec<f64>>,
}

impl<'s> Searcher<'s> {
    /// The searches of `settings` on a problem of `r` parameters.
    pub fn new(
        settings: &'s Settings,
        r: usize,
        progress: &'s dyn Progress,
    ) -> Result<Self, IdentifyError> {
        Ok(Searcher {
            settings,
            window_lm: settings.lm.clone().with_decrement_tolerance(r as f64)?,
            progress,
            times: Mutex::new(Vec::new()),
            discarded: Mutex::new(Vec::new()),
        })
    }

    /// The wall time of each search from a start ([`Searcher::start_search`]),
    /// s, in the order they ran.
    pub fn times(&self) -> Vec<f64> {
        self.times.lock().map(|t| t.clone()).unwrap_or_default()
    }

    /// The wall time of each restart that ran ahead and whose end was not
    /// needed ([`Searcher::record`]), s.
    pub fn discarded(&self) -> Vec<f64> {
        self.discarded.lock().map(|t| t.clone()).unwrap_or_default()
    }

    /// The settings.
    pub fn settings(&self) -> &Settings {
        self.settings
    }

    /// What the caller watches.
    pub fn progress(&self) -> &dyn Progress {
        self.progress
    }

    /// One local search on the whole of `problem` from `u0` (again at the
    /// chosen steps if it fails at a search's fewer ones: `falling_back`).
    pub fn search(
        &self,
        problem: &OutputError<'_>,
        u0: &[f64],
    ) -> Result<SearchOutcome, SearchError> {
        Ok(self.refine(problem, u0)?.without_jacobian())
    }

    /// [`Searcher::search`], its outcome with the residuals and Jacobian
    /// it ended with ([`SearchOutcome::linearised`]), if any.
    pub fn refine(
        &self,
        problem: &OutputError<'_>,
        u0: &[f64],
    ) -> Result<SearchOutcome, SearchError> {
        falling_back(problem, |p| self.search_with(p, u0, &self.settings.lm))
    }

    fn search_with(
        &self,
        problem: &OutputError<'_>,
        u0: &[f64],
        lm: &LmSettings,
    ) -> Result<SearchOutcome, SearchError> {
        let mut observe = |it: usize, cost: f64| self.progress.iteration(it, cost);
        match self.settings.method {
            Method::Lm => LevenbergMarquardt::new(lm.clone()).search(problem, u0, &mut observe),
            Method::Bfgs => Bfgs::new(self.settings.bfgs.clone()).search(problem, u0, &mut observe),
        }
    }

    /// A search from a start: on the short window first if
    /// [`Settings::window`] says so, then on the whole record (each again at
    /// the chosen steps if it fails at a search's fewer ones). The tally
    /// includes both searches; the history is the last one's. A window
    /// search that fails is a warning, and the start searches the whole
    /// record from where it was.
    pub fn start_search(
        &self,
        problem: &OutputError<'_>,
        u0: &[f64],
        warnings: &mut Vec<Warning>,
    ) -> Result<SearchOutcome, SearchError> {
        let (outcome, seconds) = self.timed(problem, u0, warnings);
        self.record(seconds, true);
        outcome
    }

    /// [`Searcher::start_search`] from each of `starts` at once (rayon),
    /// each with its own warnings and wall time, s, none recorded: the
    /// caller keeps those it needs ([`Searcher::record`]). Each search runs
    /// as it would alone, so its end does not depend on the others or on
    /// the threads.
    pub fn start_searches(&self, problem: &OutputError<'_>, starts: &[&[f64]]) -> Vec<Started> {
        starts
            .par_iter()
            .map(|u0| {
                let mut warnings = Vec::new();
                let (outcome, seconds) = self.timed(problem, u0, &mut warnings);
                Started {
                    outcome,
                    warnings,
                    seconds,
                }
            })
            .collect()
    }

    /// Records the wall time of a search from a start, s, among the
    /// searches' (`kept`) or the discarded ones'.
    pub fn record(&self, seconds: f64, kept: bool) {
        let times = if kept { &self.times } else { &self.discarded };
        if let Ok(mut t) = times.lock() {
            t.push(seconds);
        }
    }

    /// [`Searcher::start_search`] with its wall time, s, not recorded.
    fn timed(
        &self,
        problem: &OutputError<'_>,
        u0: &[f64],
        warnings: &mut Vec<Warning>,
    ) -> (Result<SearchOutcome, SearchError>, f64) {
        let started = Instant::now();
        let outcome = self.start_search_untimed(problem, u0, warnings);
        (outcome, started.elapsed().as_secs_f64())
    }

    /// [`Searcher::start_search`] without its time.
    fn start_search_untimed(
        &self,
        problem: &OutputError<'_>,
        u0: &[f64],
        warnings: &mut Vec<Warning>,
    ) -> Result<SearchOutcome, SearchError> {
        let Some((short, fraction)) = self.window_model(problem) else {
            return self.search(problem, u0);
        };
        let window = window_problem(problem, &short);
        let on_window = falling_back(&window, |p| self.search_with(p, u0, &self.window_lm));
        let (u1, pre) = match on_window {
            Ok(s) => (s.u.clone(), Some(s.without_jacobian())),
            Err(reason) => {
                warnings.push(Warning::WindowFailed { fraction, reason });
                (u0.to_vec(), None)
            }
        };
        let mut s = self.search(problem, &u1)?;
        if let Some(pre) = pre {
            s.tally += pre.tally;
        }
        Ok(s)
    }

    /// The model of the first [`Settings::window`] of the record (from its
    /// first used sample), and the fraction; `None` when there is no window
    /// (none asked, a campaign, whose experiments have records of their own
    /// lengths, or a window as long as the record).
    fn window_model(&self, problem: &OutputError<'_>) -> Option<(Model, f64)> {
        let fraction = self.settings.window.filter(|f| *f > 0.0 && *f < 1.0)?;
        if problem.n_experiments() > 1 {
            return None;
        }
        let first = problem.experiment_first(0);
        let n = problem.experiment_measured(0).n_samples;
        let used = ((fraction * (n - first) as f64).ceil() as usize).max(problem.n_params() + 2);
        if first + used >= n {
            return None;
        }
        let n_w = first + used;
        let mut short = problem.model().clone();
        short.sampling.duration = n_w as f64 / short.sampling.sample_rate;
        (short.sampling.n_samples() == n_w).then_some((short, fraction))
    }
}

/// `search` on `problem`, and if it fails there at the fewer steps of a
/// search ([`OutputError::searching`]), again at the chosen steps (where
/// the fewer steps are unstable, say, as they can be far from the point
/// they were chosen at).
fn falling_back(
    problem: &OutputError<'_>,
    mut search: impl FnMut(&OutputError<'_>) -> Result<SearchOutcome, SearchError>,
) -> Result<SearchOutcome, SearchError> {
    match search(problem) {
        Err(_) if problem.searching() && !problem.cancel().is_set() => {
            search(&problem.at_chosen_steps())
        }
        outcome => outcome,
    }
}

/// The criterion on `short`'s part of `problem`'s record (a data file on
/// its own: one experiment), with the whole
/// record's weights, integrator and steps per sample (those of a search,
/// if it takes them), counted into
/// `problem`'s tally.
fn window_problem<'m>(problem: &OutputError<'_>, short: &'m Model) -> OutputError<'m> {
    let n_w = short.sampling.n_samples();
    let y = problem.experiment_measured(0);
    let mut values = Vec::with_capacity(y.n_sensors * n_w);
    for c in 0..y.n_sensors {
        values.extend_from_slice(&y.sensor(c)[..n_w]);
    }
    let truncated = Response {
        n_samples: n_w,
        n_sensors: y.n_sensors,
        values,
    };
    let whole = problem.experiment_simulator(0);
    let mut sim = Simulator::with_integrator(short, whole.integrator());
    sim.set_steps(whole.steps());
    if whole.searching() {
        sim.use_search_steps();
    }
    let mut window = OutputError::new(sim, truncated, problem.experiment_first(0));
    window.set_weighting(&problem.weighting());
    window.set_jacobian_memory(problem.jacobian_memory());
    window.count_into(problem);
    window
}
