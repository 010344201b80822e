//! A function record by number or by name, as the model file writes it.
use serde::de::{self, Deserializer, Visitor};
use std::fmt;

/// A function record, by its 1-based number among the file's dataset-58
/// records, or by its name (ID line 1).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RecordRef {
    /// The n-th function record, counting from 1.
    Index(usize),
    /// The record whose ID line 1 is this (trimmed).
    Name(String),
}

impl fmt::Display for RecordRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RecordRef::Index(n) => write!(f, "{n}"),
            RecordRef::Name(s) => write!(f, "'{s}'"),
        }
    }
}

impl<'de> serde::Deserialize<'de> for RecordRef {
    /// From an integer ≥ 1 (`record = 3`) or a string (`record = "acc_x"`).
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = RecordRef;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a record number (1, 2, …) or a record name (ID line 1)")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<RecordRef, E> {
                if v < 1 {
                    return Err(E::custom(format!(
                        "record {v}: records are numbered from 1"
                    )));
                }
                self.visit_u64(v as u64)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<RecordRef, E> {
                match usize::try_from(v) {
                    Ok(n) if n >= 1 => Ok(RecordRef::Index(n)),
                    _ => Err(E::custom(format!(
                        "record {v}: records are numbered from 1"
                    ))),
                }
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<RecordRef, E> {
                if v.trim().is_empty() {
                    return Err(E::custom("an empty record name"));
                }
                Ok(RecordRef::Name(v.to_string()))
            }
        }
        d.deserialize_any(V)
    }
}
