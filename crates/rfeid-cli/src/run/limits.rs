//! The limits of the search's size ([`rfeid::identification::options`])
//! and the worker threads.
use crate::diagnostics::Failure;
use rfeid::identification::options::SearchOptions;

use std::sync::OnceLock;

/// Checks the search's options against their limits before anything is
/// computed.
pub fn check_limits(o: &SearchOptions) -> Result<(), Failure> {
    o.check().map_err(super::failures::failure)
}

/// Starts the worker threads (`threads`, or one per core); a pool that
/// cannot be started (a process limit, say) is a clear error, exit 1.
///
/// A command calls this before any computation: the library's parallel
/// parts (the plan, the sensitivity groups, the step choice's two runs)
/// would otherwise start the default pool, and `--threads` could no longer
/// take effect. Later calls in the same process do nothing.
pub fn start_threads(threads: Option<usize>) -> Result<(), Failure> {
    static STARTED: OnceLock<()> = OnceLock::new();
    if STARTED.get().is_some() {
        return Ok(());
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build_global()
        .map_err(|e| {
            Failure::failed(format!(
                "could not start {} worker threads: {e}",
                threads.map_or("the".to_string(), |t| t.to_string())
            ))
        })?;
    let _ = STARTED.set(());
    Ok(())
}
