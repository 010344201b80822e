//! The limits of the search's size and the worker threads.
use crate::cli::SearchArgs;
use crate::diagnostics::Failure;

/// Most plan points `--plan` may ask for: a plan of 10⁶ points of a
/// 1000-parameter model holds 8 GB of coordinates, so larger plans are a
/// mistake rather than a wish.
pub const MAX_PLAN: usize = 1_000_000;
/// Most local searches `--starts` may ask for.
pub const MAX_STARTS: usize = 1000;
/// Most worker threads `--threads` may ask for.
pub const MAX_THREADS: usize = 1024;

/// Checks `--plan`, `--starts` and `--threads` against their limits before
/// anything is computed.
pub fn check_limits(a: &SearchArgs) -> Result<(), Failure> {
    if !(1..=MAX_PLAN).contains(&a.plan) {
        return Err(Failure::input_msg(format!(
            "--plan {}: must be 1 to {MAX_PLAN}",
            a.plan
        )));
    }
    if !(1..=MAX_STARTS.min(a.plan)).contains(&a.starts) {
        return Err(Failure::input_msg(format!(
            "--starts {}: must be 1 to the plan size ({}) and at most {MAX_STARTS}",
            a.starts, a.plan
        )));
    }
    if let Some(t) = a.threads {
        if !(1..=MAX_THREADS).contains(&t) {
            return Err(Failure::input_msg(format!(
                "--threads {t}: must be 1 to {MAX_THREADS}"
            )));
        }
    }
    Ok(())
}

/// Starts the worker threads (`threads`, or one per core); a pool that
/// cannot be started (a process limit, say) is a clear error, exit 1.
pub fn start_threads(threads: Option<usize>) -> Result<(), Failure> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build_global()
        .map_err(|e| {
            Failure::failed(format!(
                "could not start {} worker threads: {e}",
                threads.map_or("the".to_string(), |t| t.to_string())
            ))
        })
}
