//! A long call from Python: the work runs on a thread of its own while the
//! calling thread waits without the GIL, waking every 50 ms to let Python
//! handle signals (Ctrl-C raises `KeyboardInterrupt` and cancels the work,
//! which stops within one simulation) and to show progress.
use super::errors::failed;
use pyo3::prelude::*;
use rfeid::identification::cancel::Cancel;
use rfeid::identification::pipeline::Progress;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

/// How often the waiting thread wakes.
const TICK: Duration = Duration::from_millis(50);

/// The search's progress as counters the worker sets and the waiting
/// thread reads.
#[derive(Debug, Default)]
pub struct Counters {
    /// Plan points in all.
    plan_total: AtomicUsize,
    /// Plan points done.
    plan_done: AtomicUsize,
    /// The local search running (from 1; 0: the plan).
    search: AtomicUsize,
    /// Local searches in all.
    searches: AtomicUsize,
    /// The search's iteration.
    iteration: AtomicUsize,
    /// J after it (f64 bits).
    cost: AtomicU64,
}

impl Counters {
    /// (plan points done, plan points, search, searches, iteration, J).
    fn snapshot(&self) -> (usize, usize, usize, usize, usize, f64) {
        let r = |a: &AtomicUsize| a.load(Ordering::Relaxed);
        (
            r(&self.plan_done),
            r(&self.plan_total),
            r(&self.search),
            r(&self.searches),
            r(&self.iteration),
            f64::from_bits(self.cost.load(Ordering::Relaxed)),
        )
    }
}

impl Progress for Counters {
    fn plan_started(&self, points: usize) {
        self.plan_total.store(points, Ordering::Relaxed);
    }
    fn plan_point(&self) {
        self.plan_done.fetch_add(1, Ordering::Relaxed);
    }
    fn search_started(&self, k: usize, of: usize, cost: f64) {
        self.search.store(k + 1, Ordering::Relaxed);
        self.searches.store(of, Ordering::Relaxed);
        self.iteration.store(0, Ordering::Relaxed);
        self.cost.store(cost.to_bits(), Ordering::Relaxed);
    }
    fn iteration(&self, iteration: usize, cost: f64) {
        self.iteration.store(iteration, Ordering::Relaxed);
        self.cost.store(cost.to_bits(), Ordering::Relaxed);
    }
}

/// Runs `work` on a thread of its own and waits for it without the GIL.
/// A signal handler that raises (Ctrl-C: `KeyboardInterrupt`), or a
/// `progress` callback that raises, sets `cancel`, waits for the work to
/// stop and raises that exception. `progress(done, total, search,
/// searches, iteration, cost)` is called every 50 ms and once at the end.
pub fn watched<T: Send>(
    py: Python<'_>,
    cancel: &Cancel,
    counters: &Counters,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let finished = (Mutex::new(false), Condvar::new());
    std::thread::scope(|s| {
        let handle = s.spawn(|| {
            let out = work();
            let (flag, wake) = &finished;
            *flag.lock().unwrap_or_else(|e| e.into_inner()) = true;
            wake.notify_all();
            out
        });
        let stop = loop {
            let done = py.detach(|| {
                let (flag, wake) = &finished;
                let guard = flag.lock().unwrap_or_else(|e| e.into_inner());
                let (guard, _) = wake
                    .wait_timeout_while(guard, TICK, |done| !*done)
                    .unwrap_or_else(|e| e.into_inner());
                *guard
            });
            if done || handle.is_finished() {
                break None;
            }
            let checked = py.check_signals().and_then(|_| match progress {
                Some(cb) => cb.call1(counters.snapshot()).map(|_| ()),
                None => Ok(()),
            });
            if let Err(e) = checked {
                cancel.set();
                break Some(e);
            }
        };
        let joined = py.detach(|| handle.join());
        if let Some(e) = stop {
            return Err(e);
        }
        let out = joined.map_err(|_| failed("internal error: the computation panicked"))?;
        if let Some(cb) = progress {
            cb.call1(counters.snapshot())?;
        }
        Ok(out)
    })
}
