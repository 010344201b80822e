//! Digests of input files ([`rfeid::io::digest`]) as the commands use
//! them. A shard file's run hash is one (`rfeid::io::shard_file::run_hash`);
//! RESULT.json records one per input file ([`InputDigests`]), so that
//! `report` and `validate` refuse files that changed since the result was
//! computed.
use crate::diagnostics::Failure;
use rfeid::identification::result::InputDigests;
use rfeid::io::digest;
use rfeid::model::Model;
use std::path::{Path, PathBuf};

/// The digest of one file.
fn file_digest(path: &Path) -> Result<String, Failure> {
    digest::file_digest(path).map_err(Failure::input_msg)
}

/// The digests of a run's inputs ([`digest::input_digests`]); an
/// unreadable file is bad input naming it.
pub fn input_digests(
    model_path: &Path,
    model: &Model,
    data: &[PathBuf],
) -> Result<InputDigests, Failure> {
    digest::input_digests(model_path, model, data).map_err(Failure::input_msg)
}

/// The first input that no longer holds what it held when the result was
/// computed (`recorded`; nothing to compare in results written before
/// digests were recorded), with what it is: the model file at
/// `model_path`, its signal tables, and the data files `data` (`None`: the
/// data are not compared, as `validate` compares with data of its own
/// choosing). `None` when every file is unchanged.
pub fn changed_input(
    recorded: Option<&InputDigests>,
    model_path: &Path,
    model: &Model,
    data: Option<&[PathBuf]>,
) -> Result<Option<(PathBuf, &'static str)>, Failure> {
    let Some(recorded) = recorded else {
        return Ok(None);
    };
    if file_digest(model_path)? != recorded.model || model.files.len() != recorded.tables.len() {
        return Ok(Some((model_path.to_path_buf(), "the model file")));
    }
    for (f, d) in model.files.iter().zip(&recorded.tables) {
        if &file_digest(f)? != d {
            return Ok(Some((f.clone(), "the signal table")));
        }
    }
    if let Some(data) = data {
        if data.len() != recorded.data.len() {
            return Ok(Some((model_path.to_path_buf(), "the model file")));
        }
        for (f, d) in data.iter().zip(&recorded.data) {
            if &file_digest(f)? != d {
                return Ok(Some((f.clone(), "the data file")));
            }
        }
    }
    Ok(None)
}

/// Refuses inputs that changed since `result_path` was computed
/// ([`changed_input`] with the data compared): a report would draw the
/// fit table of the old inputs beside signals of the new ones.
pub fn check_unchanged(
    result_path: &Path,
    recorded: Option<&InputDigests>,
    model_path: &Path,
    model: &Model,
    data: &[PathBuf],
) -> Result<(), Failure> {
    match changed_input(recorded, model_path, model, Some(data))? {
        None => Ok(()),
        Some((path, what)) => Err(Failure::input_msg(format!(
            "{}: {what} {} changed since the result was computed (its content differs from \
             what the result records), so the report would show the old fit beside the new \
             file: run `rfeid identify` again, or restore the file",
            result_path.display(),
            path.display()
        ))),
    }
}
