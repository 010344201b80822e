//! A run's output files: checked before any computation, written together
//! at the end or not at all (README, "Output files").
//!
//! A [`Plan`] lists every output (`-o`, `--report`, `--plot`,
//! `--json-file`) and every input of a run. [`Plan::check`] refuses, with
//! exit status 2, an output whose directory is missing or not writable, an
//! output that is one of the inputs (same device and inode) or holds one,
//! two outputs at one place, and more than one output on standard output.
//! The [`Checked`] plan then opens a [`Batch`] that writes each output to a
//! temporary beside its destination and commits them all at the end.
mod commit;
mod resolve;
pub mod signals;

pub use commit::Batch;
use resolve::{dir_destination, file_destination, identity, Destination};

use crate::diagnostics::Failure;
use std::path::{Path, PathBuf};

/// What an output is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// One file (or `-`, standard output).
    File,
    /// A report directory.
    Report,
}

/// One output of a run, as given.
#[derive(Debug, Clone)]
struct Output {
    flag: &'static str,
    path: PathBuf,
    kind: Kind,
}

/// The outputs and inputs of a run, before they are checked.
#[derive(Debug, Default)]
pub struct Plan {
    outputs: Vec<Output>,
    inputs: Vec<PathBuf>,
}

impl Plan {
    /// An empty plan.
    pub fn new() -> Self {
        Self::default()
    }

    /// A file the run reads; no output may be it.
    pub fn input(&mut self, path: &Path) -> &mut Self {
        self.inputs.push(path.to_path_buf());
        self
    }

    /// An output file given by option `flag`; `-` is standard output.
    pub fn file(&mut self, flag: &'static str, path: &Path) -> &mut Self {
        self.outputs.push(Output {
            flag,
            path: path.to_path_buf(),
            kind: Kind::File,
        });
        self
    }

    /// A report directory given by option `flag`.
    pub fn report(&mut self, flag: &'static str, path: &Path) -> &mut Self {
        self.outputs.push(Output {
            flag,
            path: path.to_path_buf(),
            kind: Kind::Report,
        });
        self
    }

    /// Checks every output against the rules; bad ones are exit status 2,
    /// naming the option and the path.
    pub fn check(&self) -> Result<Checked, Failure> {
        let mut dests: Vec<(Output, Destination)> = Vec::new();
        for o in &self.outputs {
            let bad =
                |why: String| Failure::input_msg(format!("{} {}: {why}", o.flag, o.path.display()));
            let d = match o.kind {
                Kind::File => file_destination(&o.path),
                Kind::Report => dir_destination(&o.path),
            }
            .map_err(bad)?;
            for input in &self.inputs {
                if collides(&d, input) {
                    return Err(bad(format!(
                        "is the input {}; refusing to overwrite an input",
                        input.display()
                    )));
                }
            }
            for (other, od) in &dests {
                if let Some(why) = clash(&d, od) {
                    return Err(bad(format!(
                        "{why} {} {}",
                        other.flag,
                        other.path.display()
                    )));
                }
            }
            dests.push((o.clone(), d));
        }
        Ok(Checked { dests })
    }
}

/// Whether writing `d` would overwrite or remove the input `input`.
fn collides(d: &Destination, input: &Path) -> bool {
    let Some(id) = identity(input) else {
        return false;
    };
    match d {
        Destination::Stdout => false,
        Destination::Special(p) | Destination::File { target: p, .. } => {
            identity(p).as_ref() == Some(&id)
        }
        Destination::Dir { target, .. } => rfeid::io::report_dir::holds(target, input),
    }
}

/// Why two outputs cannot both be written, if they cannot.
fn clash(a: &Destination, b: &Destination) -> Option<&'static str> {
    use Destination::*;
    match (a, b) {
        (Stdout, Stdout) => Some("goes to standard output, and so does"),
        (Special(x), Special(y)) if x == y => Some("is the same file as"),
        (File { target: x, .. }, File { target: y, .. }) if x == y => Some("is the same file as"),
        (Dir { target: d, .. }, File { target: f, .. })
        | (File { target: f, .. }, Dir { target: d, .. })
        | (Dir { target: d, .. }, Dir { target: f, .. })
            if f.starts_with(d) || d.starts_with(f) =>
        {
            Some("lies inside (or holds) the report directory of")
        }
        _ => None,
    }
}

/// A checked plan: where each output goes.
#[derive(Debug)]
pub struct Checked {
    dests: Vec<(Output, Destination)>,
}

impl Checked {
    /// Whether some output goes to standard output (tables then go to
    /// standard error).
    pub fn uses_stdout(&self) -> bool {
        self.dests.iter().any(|(_, d)| *d == Destination::Stdout)
    }

    /// Where the output of `flag` goes.
    fn destination(&self, flag: &str) -> Option<&(Output, Destination)> {
        self.dests.iter().find(|(o, _)| o.flag == flag)
    }

    /// A new batch of outputs.
    pub fn batch(&self) -> Batch<'_> {
        Batch::new(self)
    }
}
