//! A report directory's rules (README, "Output files"), shared by `rfeid
//! … --report DIR` and the Python module's `report(dir)`: an existing
//! directory is replaced as a whole, so it must hold nothing but an earlier
//! report, never an input; the new report is written beside it and swapped
//! in, the old one moved aside first, so old and new figures never mix.
use std::fs::OpenOptions;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// A report directory that cannot be written: refused by the rules, or a
/// failure of the file system.
#[derive(Debug, thiserror::Error)]
pub enum ReportDirError {
    /// The directory breaks a rule (it holds other files, an input, …).
    #[error("{dir}: {why}")]
    Refused {
        /// The directory as given.
        dir: PathBuf,
        /// What is wrong.
        why: String,
    },
    /// Reading or writing failed.
    #[error("{dir}: {source}")]
    Io {
        /// The directory as given.
        dir: PathBuf,
        /// The failure.
        source: std::io::Error,
    },
}

/// Names an rfeid report may hold: `report.html`, SVG figures, and hidden
/// temporaries an earlier, killed rfeid left (`.rfeid-…`, `.NAME.tmp-PID`).
pub fn is_report_file(name: &std::ffi::OsStr) -> bool {
    let name = name.to_string_lossy();
    let debris = name.starts_with(".rfeid-")
        || (name.starts_with('.')
            && name.rsplit_once(".tmp-").is_some_and(|(_, pid)| {
                !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit())
            }));
    name == "report.html" || name.ends_with(".svg") || debris
}

/// Checks an existing directory that a report would replace: it must hold
/// nothing but files of an earlier report and not be a root. Returns its
/// canonical path.
pub fn check_existing(dir: &Path) -> Result<PathBuf, String> {
    let entries = std::fs::read_dir(dir).map_err(|e| e.to_string())?;
    for entry in entries {
        let entry = entry.map_err(|e| e.to_string())?;
        let is_file = entry.file_type().map(|t| t.is_file()).unwrap_or(false);
        if !is_file || !is_report_file(&entry.file_name()) {
            return Err(format!(
                "the directory holds '{}', which is not part of an rfeid report; \
                 a report replaces its directory as a whole, so give a new or empty \
                 directory, or one holding an earlier report",
                entry.file_name().to_string_lossy()
            ));
        }
    }
    let canonical = std::fs::canonicalize(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    if canonical.parent().is_none() {
        return Err("is a root directory".into());
    }
    Ok(canonical)
}

/// Whether the report directory `target` (canonical) holds the file
/// `input`, which writing the report would remove.
pub fn holds(target: &Path, input: &Path) -> bool {
    std::fs::canonicalize(input)
        .map(|c| c.starts_with(target))
        .unwrap_or(false)
}

/// A short hidden name beside `target`, unique in this process.
pub fn temporary_beside(target: &Path) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let name = format!(".rfeid-{}-{n}.tmp", std::process::id());
    match target.parent() {
        Some(dir) => dir.join(name),
        None => PathBuf::from(name),
    }
}

/// Creates the directory `tmp` with `files` (name, text) in it, flushed to
/// disk.
pub fn fill(tmp: &Path, files: &[(String, String)]) -> std::io::Result<()> {
    std::fs::create_dir(tmp)?;
    for (name, text) in files {
        let mut f = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(tmp.join(name))?;
        f.write_all(text.as_bytes())?;
        f.sync_all()?;
    }
    std::fs::File::open(tmp)?.sync_all()
}

/// Puts the filled directory `tmp` at `target`; an existing report there
/// (`exists`) is first moved to `old`, then removed once the new one is in
/// place (best effort: a leftover `old` is a hidden `.rfeid-…` directory a
/// later report clears). On failure the old report is put back.
pub fn swap(tmp: &Path, target: &Path, exists: bool, old: &Path) -> std::io::Result<()> {
    if !exists {
        return std::fs::rename(tmp, target);
    }
    std::fs::rename(target, old)?;
    if let Err(e) = std::fs::rename(tmp, target) {
        let _ = std::fs::rename(old, target);
        return Err(e);
    }
    let _ = std::fs::remove_dir_all(old);
    Ok(())
}

/// Where the report directory `dir` goes: (its canonical path, whether it
/// exists), by the rules; symbolic links are followed.
fn destination(dir: &Path) -> Result<(PathBuf, bool), String> {
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => check_existing(dir).map(|c| (c, true)),
        Ok(_) => Err("exists and is not a directory".into()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            let name = dir
                .file_name()
                .ok_or("names no directory (it ends in '..' or is a root)")?;
            let parent = match dir.parent() {
                Some(p) if !p.as_os_str().is_empty() => p,
                _ => Path::new("."),
            };
            let parent = std::fs::canonicalize(parent).map_err(|e| {
                format!(
                    "the directory {}: {e} (its parent must exist)",
                    parent.display()
                )
            })?;
            Ok((parent.join(name), false))
        }
        Err(e) => Err(e.to_string()),
    }
}

/// Writes a report's `files` (name, text) into `dir` by the rules of
/// `--report DIR`: a new directory (its parent must exist), or one holding
/// only an earlier report, which is replaced as a whole; never one holding
/// any of `inputs`. Returns report.html's path.
pub fn write_report(
    dir: &Path,
    files: &[(String, String)],
    inputs: &[&Path],
) -> Result<PathBuf, ReportDirError> {
    let refused = |why: String| ReportDirError::Refused {
        dir: dir.to_path_buf(),
        why,
    };
    let (target, exists) = destination(dir).map_err(refused)?;
    if let Some(input) = inputs.iter().find(|i| holds(&target, i)) {
        return Err(refused(format!(
            "holds the input {}; refusing to overwrite an input",
            input.display()
        )));
    }
    let io = |source| ReportDirError::Io {
        dir: dir.to_path_buf(),
        source,
    };
    let tmp = temporary_beside(&target);
    let written =
        fill(&tmp, files).and_then(|()| swap(&tmp, &target, exists, &temporary_beside(&target)));
    if let Err(e) = written {
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(io(e));
    }
    Ok(dir.join("report.html"))
}
