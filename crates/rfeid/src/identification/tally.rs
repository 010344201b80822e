//! How many simulations a run took, counted where they happen.
//!
//! One simulation is one run of one experiment's record: a campaign's
//! criterion at one point costs as many simulations as it has experiments.
//! [`crate::identification::output_error::OutputError`] counts every
//! simulation it runs in a shared [`Counter`], so the stages of an
//! identification never add counts by hand.
use serde::{Deserialize, Serialize};
use std::ops::{Add, AddAssign, Sub};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

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
/// counts are sums, so they do not depend on the number of threads.
#[derive(Debug, Clone, Default)]
pub struct Counter(Arc<[AtomicUsize; 3]>);

impl Counter {
    /// Records `n` simulations (with sensitivities if `sensitivities`), of
    /// which `failed` failed.
    pub fn record(&self, n: usize, sensitivities: bool, failed: usize) {
        self.0[usize::from(sensitivities)].fetch_add(n, Ordering::Relaxed);
        self.0[2].fetch_add(failed, Ordering::Relaxed);
    }

    /// Adds a tally counted elsewhere (for instance the step checks' runs).
    pub fn add(&self, t: Tally) {
        self.0[0].fetch_add(t.simulations, Ordering::Relaxed);
        self.0[1].fetch_add(t.with_sensitivities, Ordering::Relaxed);
        self.0[2].fetch_add(t.failed, Ordering::Relaxed);
    }

    /// The counts so far.
    pub fn read(&self) -> Tally {
        Tally {
            simulations: self.0[0].load(Ordering::Relaxed),
            with_sensitivities: self.0[1].load(Ordering::Relaxed),
            failed: self.0[2].load(Ordering::Relaxed),
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
        d.add(Tally::plain(2));
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
    }
}
