//! How many simulations a run took, counted where they happen.
//!
//! One simulation is one run of one experiment's record: a campaign's
//! criterion at one point costs as many simulations as it has experiments.
//! [`crate::identification::output_error::OutputError`] counts every
//! simulation it runs in a shared [`Counter`], so the stages of an
//! identification never add counts by hand.
use serde::{Deserialize, Serialize};
use std::ops::{Add, AddAssign, Sub};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// Simulations run: plain ones, ones with sensitivities, and how many of
/// either failed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Tally {
    /// Simulations of the response alone.
    pub simulations: usize,
    /// Simulations with sensitivities (a Jacobian).
    pub with_sensitivities: usize,
    /// Of both kinds, those that failed (recorded, not fatal).
    pub failed: usize,
}

impl Tally {
    /// `n` plain simulations, none failed.
    pub fn plain(n: usize) -> Tally {
        Tally {
            simulations: n,
            ..Tally::default()
        }
    }
}

impl Add for Tally {
    type Output = Tally;
    fn add(self, o: Tally) -> Tally {
        Tally {
            simulations: self.simulations + o.simulations,
            with_sensitivities: self.with_sensitivities + o.with_sensitivities,
            failed: self.failed + o.failed,
        }
    }
}

impl AddAssign for Tally {
    fn add_assign(&mut self, o: Tally) {
        *self = *self + o;
    }
}

impl Sub for Tally {
    type Output = Tally;
    /// The simulations between two readings of one [`Counter`].
    fn sub(self, o: Tally) -> Tally {
        Tally {
            simulations: self.simulations - o.simulations,
            with_sensitivities: self.with_sensitivities - o.with_sensitivities,
            failed: self.failed - o.failed,
        }
    }
}

/// A thread-safe running [`Tally`], shared by the clones of a problem. The
/// counts are sums, so they do not depend on the number of threads. It also
/// keeps what a run's `--timings` shows ([`Work`]): the time the
/// simulations took and the plan points abandoned, which are not results.
#[derive(Debug, Clone, Default)]
pub struct Counter(Arc<Counts>);

/// The counts behind a [`Counter`]: atomics, so that counting takes no
/// lock.
#[derive(Debug, Default)]
struct Counts {
    /// Plain simulations, with sensitivities, failed.
    tally: [AtomicUsize; 3],
    /// Nanoseconds of the plain ones and of those with sensitivities.
    nanos: [AtomicU64; 2],
    /// Evaluations stopped early (their running J past a limit).
    abandoned: AtomicUsize,
}

/// The simulations a criterion ran and the time they took, summed over the
/// evaluations (those side by side on several threads add up, so the sum
/// may exceed the wall time): where a run's time went. Not part of the
/// results (it depends on the threads and the machine).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Work {
    /// Simulations of the response alone (abandoned ones included).
    pub plain: usize,
    /// Their time, s.
    pub plain_seconds: f64,
    /// Simulations with sensitivities.
    pub with_sensitivities: usize,
    /// Their time, s.
    pub sensitivity_seconds: f64,
    /// Evaluations stopped before the record's end, their running J past
    /// the plan's limit.
    pub abandoned: usize,
}

impl Add for Work {
    type Output = Work;
    fn add(self, o: Work) -> Work {
        Work {
            plain: self.plain + o.plain,
            plain_seconds: self.plain_seconds + o.plain_seconds,
            with_sensitivities: self.with_sensitivities + o.with_sensitivities,
            sensitivity_seconds: self.sensitivity_seconds + o.sensitivity_seconds,
            abandoned: self.abandoned + o.abandoned,
        }
    }
}

impl Counter {
    /// Records `n` simulations (with sensitivities if `sensitivities`), of
    /// which `failed` failed.
    pub fn record(&self, n: usize, sensitivities: bool, failed: usize) {
        self.0.tally[usize::from(sensitivities)].fetch_add(n, Ordering::Relaxed);
        self.0.tally[2].fetch_add(failed, Ordering::Relaxed);
    }

    /// [`Counter::record`], with the time they took.
    pub fn record_timed(&self, n: usize, sensitivities: bool, failed: usize, took: Duration) {
        self.record(n, sensitivities, failed);
        let nanos = u64::try_from(took.as_nanos()).unwrap_or(u64::MAX);
        self.0.nanos[usize::from(sensitivities)].fetch_add(nanos, Ordering::Relaxed);
    }

    /// Records `n` evaluations abandoned (their simulations are recorded
    /// as such by [`Counter::record`]).
    pub fn record_abandoned(&self, n: usize) {
        self.0.abandoned.fetch_add(n, Ordering::Relaxed);
    }

    /// Adds a tally counted elsewhere (for instance the step checks' runs),
    /// and the time its plain simulations took.
    pub fn add(&self, t: Tally, took: Duration) {
        self.record_timed(t.simulations, false, t.failed, took);
        self.0.tally[1].fetch_add(t.with_sensitivities, Ordering::Relaxed);
    }

    /// The counts so far.
    pub fn read(&self) -> Tally {
        let t = &self.0.tally;
        Tally {
            simulations: t[0].load(Ordering::Relaxed),
            with_sensitivities: t[1].load(Ordering::Relaxed),
            failed: t[2].load(Ordering::Relaxed),
        }
    }

    /// The simulations so far and their time.
    pub fn work(&self) -> Work {
        let seconds = |i: usize| self.0.nanos[i].load(Ordering::Relaxed) as f64 * 1e-9;
        let t = self.read();
        Work {
            plain: t.simulations,
            plain_seconds: seconds(0),
            with_sensitivities: t.with_sensitivities,
            sensitivity_seconds: seconds(1),
            abandoned: self.0.abandoned.load(Ordering::Relaxed),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clones_share_the_count_and_differences_measure_a_stage() {
        let c = Counter::default();
        let d = c.clone();
        c.record(3, false, 1);
        let before = d.read();
        d.record(1, true, 0);
        d.add(Tally::plain(2), Duration::from_millis(3));
        d.record_abandoned(1);
        assert_eq!(
            c.read() - before,
            Tally {
                simulations: 2,
                with_sensitivities: 1,
                failed: 0
            }
        );
        assert_eq!(c.read().simulations, 5);
        assert_eq!(c.read().failed, 1);
        let w = c.work();
        assert_eq!((w.plain, w.with_sensitivities, w.abandoned), (5, 1, 1));
        assert!((w.plain_seconds - 3e-3).abs() < 1e-12);
    }
}
