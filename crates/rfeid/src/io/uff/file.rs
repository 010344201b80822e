//! The function records of a file, found by number or name.
use super::{UffError, UffRecord};
use crate::model::RecordRef;
use std::path::{Path, PathBuf};

/// The function records of a universal file.
#[derive(Debug, Clone, PartialEq)]
pub struct UffFile {
    pub(super) path: PathBuf,
    pub(super) records: Vec<UffRecord>,
}

impl UffFile {
    /// The file read.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The dataset-58 records in file order.
    pub fn records(&self) -> &[UffRecord] {
        &self.records
    }

    /// The record with this 1-based number.
    pub fn record(&self, number: usize) -> Option<&UffRecord> {
        number.checked_sub(1).and_then(|i| self.records.get(i))
    }

    /// The first record named `name` (ID line 1, trimmed).
    pub fn by_name(&self, name: &str) -> Option<&UffRecord> {
        self.records.iter().find(|r| r.name() == name)
    }

    /// The record `r` refers to, or an error: no such record (listing them),
    /// or a name that several records carry.
    pub fn find(&self, r: &RecordRef) -> Result<&UffRecord, UffError> {
        let found = match r {
            RecordRef::Index(n) => self.record(*n),
            RecordRef::Name(name) => {
                let all: Vec<&UffRecord> =
                    self.records.iter().filter(|x| x.name() == name).collect();
                if all.len() > 1 {
                    let nums: Vec<String> = all.iter().map(|x| x.number.to_string()).collect();
                    return Err(UffError::Ambiguous {
                        path: self.path.clone(),
                        name: name.clone(),
                        records: nums.join(", "),
                    });
                }
                all.first().copied()
            }
        };
        found.ok_or_else(|| UffError::UnknownRecord {
            path: self.path.clone(),
            wanted: r.to_string(),
            available: if self.records.is_empty() {
                "none".into()
            } else {
                let list: Vec<String> = self
                    .records
                    .iter()
                    .map(|x| format!("{} '{}'", x.number, x.name()))
                    .collect();
                list.join(", ")
            },
        })
    }

    /// As [`find`](Self::find), and the record must hold real data.
    pub fn real_record(&self, r: &RecordRef) -> Result<&UffRecord, UffError> {
        let rec = self.find(r)?;
        if rec.ordinate_type.is_complex() {
            return Err(UffError::Complex {
                path: self.path.clone(),
                record: rec.number,
                name: rec.name().to_string(),
                ordinate: rec.ordinate_type.to_string(),
            });
        }
        Ok(rec)
    }
}
