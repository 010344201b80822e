//! Where an output really goes: symbolic links followed, the directory
//! checked, special files recognised; and whether two paths are one file.
use std::fs::Metadata;
use std::path::{Path, PathBuf};

/// Most symbolic links followed in a chain (Linux's own limit).
const MAX_LINKS: usize = 40;

/// What an output path leads to, after following symbolic links.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Destination {
    /// `-`: standard output.
    Stdout,
    /// A character device or FIFO: written into, never replaced.
    Special(PathBuf),
    /// A regular file, new or replaced by rename; `mode` is the existing
    /// file's permission bits, which the new file gets.
    File {
        /// The final path (directory canonicalised, links followed).
        target: PathBuf,
        /// Permissions of the file being replaced.
        mode: Option<u32>,
    },
    /// A report directory, new or replaced as a whole.
    Dir {
        /// The final path (parent canonicalised, links followed).
        target: PathBuf,
        /// Whether a directory is there already.
        exists: bool,
    },
}

/// Follows symbolic links from `path` to the path that is finally opened
/// (which may not exist yet).
pub fn follow_links(path: &Path) -> Result<PathBuf, String> {
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let to = std::fs::read_link(&p).map_err(|e| e.to_string())?;
                p = match p.parent() {
                    Some(dir) if to.is_relative() => dir.join(to),
                    _ => to,
                };
            }
            _ => return Ok(p),
        }
    }
    Err("too many levels of symbolic links".into())
}

/// `path` with its directory made absolute and canonical; the directory
/// must exist and be writable.
fn settle(path: &Path) -> Result<PathBuf, String> {
    let name = path
        .file_name()
        .ok_or("names no file (it ends in '..' or is a root)")?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let meta = std::fs::metadata(dir).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            format!(
                "the directory {} does not exist (output directories are not created)",
                dir.display()
            )
        } else {
            format!("the directory {}: {e}", dir.display())
        }
    })?;
    if !meta.is_dir() {
        return Err(format!("{} is not a directory", dir.display()));
    }
    if !writable(dir) {
        return Err(format!("the directory {} is not writable", dir.display()));
    }
    let dir = std::fs::canonicalize(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    Ok(dir.join(name))
}

/// Where an output file named `path` goes.
pub fn file_destination(path: &Path) -> Result<Destination, String> {
    if path == Path::new("-") {
        return Ok(Destination::Stdout);
    }
    let target = follow_links(path)?;
    match std::fs::metadata(&target) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Destination::File {
            target: settle(&target)?,
            mode: None,
        }),
        Err(e) => Err(e.to_string()),
        Ok(m) if m.is_dir() => Err("is a directory".into()),
        Ok(m) if m.is_file() => {
            // The mode too: `access` says yes to root for any file, and a
            // read-only file is refused whoever runs.
            if !writable(&target) || read_only(&m) {
                return Err("the file is read-only".into());
            }
            Ok(Destination::File {
                target: settle(&target)?,
                mode: Some(mode_of(&m)),
            })
        }
        Ok(m) if is_writable_special(&m) => {
            if !writable(&target) {
                return Err("is not writable".into());
            }
            Ok(Destination::Special(target))
        }
        Ok(_) => Err("is a block device or socket; rfeid writes only into files, character devices and FIFOs".into()),
    }
}

/// Where a report directory named `path` goes. An existing directory is
/// replaced as a whole, so it must hold nothing but an earlier report.
pub fn dir_destination(path: &Path) -> Result<Destination, String> {
    if path == Path::new("-") {
        return Err("a report is a directory and cannot go to standard output".into());
    }
    let target = follow_links(path)?;
    match std::fs::metadata(&target) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Destination::Dir {
            target: settle(&target)?,
            exists: false,
        }),
        Err(e) => Err(e.to_string()),
        Ok(m) if m.is_dir() => {
            // The rules the Python module's `report` follows too.
            let canonical = rfeid::io::report_dir::check_existing(&target)?;
            settle(&canonical).map(|target| Destination::Dir {
                target,
                exists: true,
            })
        }
        Ok(_) => Err("exists and is not a directory".into()),
    }
}

/// Whether the process may write into `path` (`access(2)` with `W_OK`).
#[cfg(unix)]
pub fn writable(path: &Path) -> bool {
    use std::os::unix::ffi::OsStrExt;
    let Ok(c) = std::ffi::CString::new(path.as_os_str().as_bytes()) else {
        return false;
    };
    // SAFETY: `c` is a valid NUL-terminated string that outlives the call.
    unsafe { libc::access(c.as_ptr(), libc::W_OK) == 0 }
}

/// Whether the process may write into `path`.
#[cfg(not(unix))]
pub fn writable(path: &Path) -> bool {
    std::fs::metadata(path)
        .map(|m| !m.permissions().readonly())
        .unwrap_or(false)
}

/// Whether no one may write the file by its mode (or, off Unix, its
/// read-only attribute).
fn read_only(m: &Metadata) -> bool {
    m.permissions().readonly()
}

#[cfg(unix)]
fn mode_of(m: &Metadata) -> u32 {
    use std::os::unix::fs::PermissionsExt;
    m.permissions().mode() & 0o7777
}

#[cfg(not(unix))]
fn mode_of(_: &Metadata) -> u32 {
    0
}

#[cfg(unix)]
fn is_writable_special(m: &Metadata) -> bool {
    use std::os::unix::fs::FileTypeExt;
    let t = m.file_type();
    t.is_char_device() || t.is_fifo()
}

#[cfg(not(unix))]
fn is_writable_special(_: &Metadata) -> bool {
    false
}

/// Identity of an existing file: device and inode (links followed).
#[cfg(unix)]
pub fn identity(path: &Path) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

/// Identity of an existing file: its canonical path.
#[cfg(not(unix))]
pub fn identity(path: &Path) -> Option<PathBuf> {
    std::fs::canonicalize(path).ok()
}
