//! What the criterion counts of its simulations: how many, of which kind,
//! how many failed ([`Tally`], part of the results), and the time they took
//! and the evaluations abandoned ([`Work`], for `--timings`).
use super::OutputError;
use crate::identification::tally::{Counter, Tally, Work};
use crate::simulation::SimulationError;
use std::time::{Duration, Instant};

impl OutputError<'_> {
    /// The simulations run through this criterion so far (its clones and
    /// the criteria that [`OutputError::count_into`] joined included).
    pub fn tally(&self) -> Tally {
        self.counter.read()
    }

    /// [`OutputError::tally`] with the time the simulations took, summed
    /// over the threads, and the evaluations abandoned.
    pub fn work(&self) -> Work {
        self.counter.work()
    }

    /// Records simulations run on this criterion's models elsewhere (the
    /// step checks), and the time they took.
    pub fn record(&self, t: Tally, took: Duration) {
        self.counter.add(t, took);
    }

    /// Counts this criterion's simulations into `other`'s tally from now
    /// on (a criterion on part of the record, say), and stops when `other`
    /// is cancelled.
    pub fn count_into(&mut self, other: &OutputError<'_>) {
        self.counter = other.counter.clone();
        self.cancel = other.cancel.clone();
    }

    /// A clone that counts its simulations apart from this criterion's
    /// (and is still cancelled with it).
    pub fn counted_apart(&self) -> Self {
        let mut apart = self.clone();
        apart.counter = Counter::default();
        apart
    }

    /// Counts the outcome of simulating every experiment once, which took
    /// from `since` until now.
    pub(super) fn count<T>(
        &self,
        results: &[Result<T, SimulationError>],
        sensitivities: bool,
        since: Instant,
    ) {
        let failed = results.iter().filter(|r| r.is_err()).count();
        self.counter
            .record_timed(results.len(), sensitivities, failed, since.elapsed());
    }

    /// Counts `n` plain simulations, `failed` of them failed, which took
    /// from `since` until now.
    pub(super) fn count_runs(&self, n: usize, failed: usize, since: Instant) {
        self.counter.record_timed(n, false, failed, since.elapsed());
    }

    /// Counts `n` evaluations abandoned.
    pub(super) fn count_abandoned(&self, n: usize) {
        self.counter.record_abandoned(n);
    }
}
