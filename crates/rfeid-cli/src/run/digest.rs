//! Digests of input files: FNV-1a 64 over their bytes. A shard file's run
//! hash is one ([`super::shard_file::run_hash`]); RESULT.json records one
//! per input file ([`InputDigests`]), so that `report` and `validate` refuse
//! files that changed since the result was computed.
use crate::diagnostics::Failure;
use rfeid::identification::result::InputDigests;
use rfeid::model::Model;
use std::path::{Path, PathBuf};

/// FNV-1a 64 of `parts`, each preceded by its length, in hex.
pub fn fnv1a(parts: &[&[u8]]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for part in parts {
        for b in (part.len() as u64).to_le_bytes().iter().chain(part.iter()) {
            h ^= *b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    format!("{h:016x}")
}

/// The bytes of `path`; an unreadable file is bad input naming it.
pub fn read_bytes(path: &Path) -> Result<Vec<u8>, Failure> {
    std::fs::read(path).map_err(|e| Failure::input_msg(format!("{}: {e}", path.display())))
}

/// The digest of one file.
fn file_digest(path: &Path) -> Result<String, Failure> {
    Ok(fnv1a(&[&read_bytes(path)?]))
}

/// The digests of a run's inputs: the model file at `model_path`, the
/// model's signal tables and the data files `data`.
pub fn input_digests(
    model_path: &Path,
    model: &Model,
    data: &[PathBuf],
) -> Result<InputDigests, Failure> {
    Ok(InputDigests {
        model: file_digest(model_path)?,
        tables: model
            .files
            .iter()
            .map(|f| file_digest(f))
            .collect::<Result<_, _>>()?,
        data: data
            .iter()
            .map(|f| file_digest(f))
            .collect::<Result<_, _>>()?,
    })
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
