//! Digests of input files: FNV-1a 64 over their bytes. RESULT.json records
//! one per input file ([`InputDigests`]), so that a later report or
//! validation can refuse files that changed since the result was computed.
use crate::identification::result::InputDigests;
use crate::model::Model;
use std::path::{Path, PathBuf};

/// An input file that could not be read.
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct DigestError {
    /// The file.
    pub path: PathBuf,
    /// The cause.
    pub source: std::io::Error,
}

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

/// The bytes of `path`.
pub fn read_bytes(path: &Path) -> Result<Vec<u8>, DigestError> {
    std::fs::read(path).map_err(|source| DigestError {
        path: path.to_path_buf(),
        source,
    })
}

/// The digest of one file.
pub fn file_digest(path: &Path) -> Result<String, DigestError> {
    Ok(fnv1a(&[&read_bytes(path)?]))
}

/// The digests of a run's inputs: the model file at `model_path`, the
/// model's signal tables and the data files `data`.
pub fn input_digests(
    model_path: &Path,
    model: &Model,
    data: &[PathBuf],
) -> Result<InputDigests, DigestError> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_of_nothing_and_of_lengths() {
        // The offset basis for no parts; a part's length is hashed before
        // it, so ("ab", "") and ("a", "b") differ.
        assert_eq!(fnv1a(&[]), "cbf29ce484222325");
        assert_ne!(fnv1a(&[b"ab", b""]), fnv1a(&[b"a", b"b"]));
    }
}
