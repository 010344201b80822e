//! Writing a run's outputs together: each to a temporary beside its
//! destination, then all renamed into place in the order they were staged
//! (so the result, staged last, appears last). A batch dropped without
//! commit removes its temporaries.
use super::resolve::Destination;
use super::signals::{self, remove_path};
use super::Checked;
use crate::diagnostics::Failure;
use rfeid::io::report_dir::{fill, swap, temporary_beside};
use std::fs::OpenOptions;
use std::io::Write;
use std::path::{Path, PathBuf};

/// An output ready to be committed.
#[derive(Debug)]
enum Staged {
    /// Bytes for standard output.
    Stdout(Vec<u8>),
    /// Bytes for a character device or FIFO.
    Special { path: PathBuf, bytes: Vec<u8> },
    /// A written temporary file and where it goes.
    File { tmp: PathBuf, target: PathBuf },
    /// A written temporary directory and where it goes.
    Dir {
        tmp: PathBuf,
        target: PathBuf,
        exists: bool,
    },
}

/// The outputs of one run, staged and not yet committed.
#[derive(Debug)]
pub struct Batch<'a> {
    checked: &'a Checked,
    staged: Vec<Staged>,
}

/// A failure while writing outputs that passed the checks (a full disk, say).
fn write_failure(path: &Path, e: std::io::Error) -> Failure {
    Failure::failed(format!("writing {}: {e}", path.display()))
}

/// Writes `bytes` to a new file `path` and flushes it to disk.
fn create_file(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut f = OpenOptions::new().write(true).create_new(true).open(path)?;
    f.write_all(bytes)?;
    f.sync_all()
}

impl<'a> Batch<'a> {
    /// An empty batch for the outputs of `checked`.
    pub(super) fn new(checked: &'a Checked) -> Self {
        Batch {
            checked,
            staged: Vec::new(),
        }
    }

    fn destination(&self, flag: &str) -> Result<&'a Destination, Failure> {
        self.checked
            .destination(flag)
            .map(|(_, d)| d)
            .ok_or_else(|| Failure::failed(format!("internal: no checked output for {flag}")))
    }

    /// Stages the file output of `flag` with contents `bytes`.
    pub fn file(&mut self, flag: &str, bytes: Vec<u8>) -> Result<(), Failure> {
        let staged = match self.destination(flag)? {
            Destination::Stdout => Staged::Stdout(bytes),
            Destination::Special(p) => Staged::Special {
                path: p.clone(),
                bytes,
            },
            Destination::File { target, mode } => {
                let tmp = temporary_beside(target);
                let mut registry = signals::lock();
                registry.add(tmp.clone());
                let written = create_file(&tmp, &bytes).and_then(|()| match mode {
                    Some(m) => set_mode(&tmp, *m),
                    None => Ok(()),
                });
                if let Err(e) = written {
                    remove_path(&tmp);
                    registry.forget(&tmp);
                    return Err(write_failure(target, e));
                }
                Staged::File {
                    tmp,
                    target: target.clone(),
                }
            }
            Destination::Dir { .. } => {
                return Err(Failure::failed(format!("internal: {flag} is a directory")))
            }
        };
        self.staged.push(staged);
        Ok(())
    }

    /// Stages the report directory of `flag` with `files` (name, text).
    pub fn report(&mut self, flag: &str, files: &[(String, String)]) -> Result<(), Failure> {
        let Destination::Dir { target, exists } = self.destination(flag)? else {
            return Err(Failure::failed(format!(
                "internal: {flag} is not a directory"
            )));
        };
        let tmp = temporary_beside(target);
        let mut registry = signals::lock();
        registry.add(tmp.clone());
        let written = fill(&tmp, files);
        if let Err(e) = written {
            remove_path(&tmp);
            registry.forget(&tmp);
            return Err(write_failure(target, e));
        }
        self.staged.push(Staged::Dir {
            tmp,
            target: target.clone(),
            exists: *exists,
        });
        Ok(())
    }

    /// Puts every staged output in place, in staging order. An
    /// interruption waits until all are in place.
    pub fn commit(mut self) -> Result<(), Failure> {
        let mut registry = signals::lock();
        let staged = std::mem::take(&mut self.staged);
        let mut rest = staged.into_iter();
        while let Some(s) = rest.next() {
            let done = match &s {
                // A FIFO may block until someone reads it: don't hold up an
                // interruption meanwhile.
                Staged::Stdout(_) | Staged::Special { .. } => {
                    drop(registry);
                    let done = write_stream(&s);
                    registry = signals::lock();
                    done
                }
                _ => commit_one(&s, &mut registry),
            };
            if done.is_ok() {
                registry.placed();
            }
            if let Err(e) = done {
                // Leave nothing half-done behind: this one's and the
                // remaining temporaries go.
                for s in std::iter::once(s).chain(rest) {
                    discard(&s, &mut registry);
                }
                return Err(e);
            }
        }
        Ok(())
    }
}

/// Writes a staged output for standard output or a special file.
fn write_stream(s: &Staged) -> Result<(), Failure> {
    match s {
        Staged::Stdout(bytes) => {
            let mut out = std::io::stdout().lock();
            out.write_all(bytes)
                .and_then(|()| out.flush())
                .map_err(|e| write_failure(Path::new("standard output"), e))
        }
        Staged::Special { path, bytes } => OpenOptions::new()
            .write(true)
            .open(path)
            .and_then(|mut f| f.write_all(bytes))
            .map_err(|e| write_failure(path, e)),
        _ => Ok(()),
    }
}

/// Puts one staged file or directory in place.
fn commit_one(s: &Staged, registry: &mut signals::Registry) -> Result<(), Failure> {
    match s {
        Staged::Stdout(_) | Staged::Special { .. } => write_stream(s),
        Staged::File { tmp, target } => {
            std::fs::rename(tmp, target).map_err(|e| write_failure(target, e))?;
            registry.forget(tmp);
            sync_parent(target);
            Ok(())
        }
        Staged::Dir {
            tmp,
            target,
            exists,
        } => {
            if !*exists {
                std::fs::rename(tmp, target).map_err(|e| write_failure(target, e))?;
                registry.forget(tmp);
                sync_parent(target);
                return Ok(());
            }
            // The old report moves aside, the new one takes its place, then
            // the old one goes: old and new figures never mix.
            let old = temporary_beside(target);
            registry.add(old.clone());
            let swapped = swap(tmp, target, true, &old);
            registry.forget(&old);
            swapped.map_err(|e| write_failure(target, e))?;
            registry.forget(tmp);
            sync_parent(target);
            Ok(())
        }
    }
}

/// Flushes the directory entry of a renamed output to disk, as git and
/// SQLite do, so that a crash right after cannot lose the rename. Best
/// effort: not every file system can sync a directory.
fn sync_parent(target: &Path) {
    if let Some(dir) = target.parent() {
        if let Ok(d) = std::fs::File::open(dir) {
            let _ = d.sync_all();
        }
    }
}

/// Removes a staged output's temporary.
fn discard(s: &Staged, registry: &mut signals::Registry) {
    if let Staged::File { tmp, .. } | Staged::Dir { tmp, .. } = s {
        remove_path(tmp);
        registry.forget(tmp);
    }
}

impl Drop for Batch<'_> {
    fn drop(&mut self) {
        if self.staged.is_empty() {
            return;
        }
        let mut registry = signals::lock();
        for s in self.staged.drain(..) {
            discard(&s, &mut registry);
        }
    }
}

#[cfg(unix)]
fn set_mode(path: &Path, mode: u32) -> std::io::Result<()> {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode))
}

#[cfg(not(unix))]
fn set_mode(_: &Path, _: u32) -> std::io::Result<()> {
    Ok(())
}
