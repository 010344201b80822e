//! No temporary survives SIGINT, SIGTERM or SIGHUP. The signals are blocked
//! in every thread and taken by one thread (`sigwait`), which removes the
//! registered temporaries and ends the process with 128 + the signal's
//! number (130, 143, 129).
//!
//! Every step that creates or renames an output happens while holding the
//! registry's lock, and so does the clean-up: an interruption sees either no
//! output committed or all of them, and never a temporary being created
//! after it cleaned up.
use std::path::PathBuf;
use std::sync::{Mutex, MutexGuard};

/// The temporaries that exist now: files and directories to remove on an
/// interruption.
#[derive(Debug, Default)]
pub struct Registry {
    paths: Vec<PathBuf>,
    /// Outputs put in place so far (an interruption says how many).
    placed: usize,
}

impl Registry {
    /// Records a temporary that is about to be created.
    pub fn add(&mut self, path: PathBuf) {
        self.paths.push(path);
    }

    /// Counts an output put in place.
    pub fn placed(&mut self) {
        self.placed += 1;
    }

    /// Forgets a temporary (renamed into place or removed).
    pub fn forget(&mut self, path: &std::path::Path) {
        self.paths.retain(|p| p != path);
    }

    /// Removes every registered temporary.
    fn remove_all(&mut self) {
        for p in self.paths.drain(..) {
            remove_path(&p);
        }
    }
}

/// Removes a file or a directory tree, ignoring errors (it may not exist).
pub fn remove_path(p: &std::path::Path) {
    match std::fs::symlink_metadata(p) {
        Ok(m) if m.is_dir() => {
            let _ = std::fs::remove_dir_all(p);
        }
        Ok(_) => {
            let _ = std::fs::remove_file(p);
        }
        Err(_) => {}
    }
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    paths: Vec::new(),
    placed: 0,
});

/// The registry, locked. Hold it while creating, renaming or removing
/// temporaries.
pub fn lock() -> MutexGuard<'static, Registry> {
    REGISTRY.lock().unwrap_or_else(|e| e.into_inner())
}

/// Blocks SIGINT, SIGTERM and SIGHUP and starts the thread that handles
/// them. Call first thing in `main`, before any other thread exists, so that
/// every later thread inherits the mask.
#[cfg(unix)]
pub fn install() {
    // SAFETY: plain libc calls on a local, initialised signal set; at start-up
    // only this thread exists, so the mask covers every later thread.
    let set = unsafe {
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        for s in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
            libc::sigaddset(&mut set, s);
        }
        if libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut()) != 0 {
            return;
        }
        set
    };
    let spawned = std::thread::Builder::new()
        .name("signals".into())
        .stack_size(64 * 1024)
        .spawn(move || loop {
            let mut sig: libc::c_int = 0;
            // SAFETY: `set` is an initialised signal set and `sig` a valid
            // out-pointer.
            if unsafe { libc::sigwait(&set, &mut sig) } != 0 {
                continue;
            }
            let mut registry = lock();
            registry.remove_all();
            eprintln!("{}", interrupted_message(sig, registry.placed));
            std::process::exit(128 + sig);
        });
    if spawned.is_err() {
        // No handler thread: let the signals act as before.
        // SAFETY: as above.
        unsafe {
            libc::pthread_sigmask(libc::SIG_UNBLOCK, &set, std::ptr::null_mut());
        }
    }
}

/// What an interruption by `sig` says, with `placed` outputs already in
/// place (an interruption during the final renames waits for them).
#[cfg(unix)]
fn interrupted_message(sig: libc::c_int, placed: usize) -> String {
    let name = match sig {
        libc::SIGINT => "SIGINT",
        libc::SIGTERM => "SIGTERM",
        libc::SIGHUP => "SIGHUP",
        _ => "a signal",
    };
    let outputs = match placed {
        0 => "no output was written".to_string(),
        1 => "its output had been written".to_string(),
        n => format!("its {n} outputs had been written"),
    };
    format!(
        "rfeid: interrupted by {name} (exit status {}): {outputs}; temporaries removed",
        128 + sig
    )
}

/// No signal handling off Unix.
#[cfg(not(unix))]
pub fn install() {}

#[cfg(all(test, unix))]
mod tests {
    use super::interrupted_message;

    #[test]
    fn an_interruption_says_what_it_left() {
        let none = interrupted_message(libc::SIGINT, 0);
        assert!(
            none.contains("interrupted by SIGINT (exit status 130)"),
            "{none}"
        );
        assert!(none.contains("no output was written"), "{none}");
        let two = interrupted_message(libc::SIGTERM, 2);
        assert!(two.contains("SIGTERM (exit status 143)"), "{two}");
        assert!(two.contains("its 2 outputs had been written"), "{two}");
        let one = interrupted_message(libc::SIGHUP, 1);
        assert!(
            one.contains("SIGHUP (exit status 129): its output had been written"),
            "{one}"
        );
    }
}
