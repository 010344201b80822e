//! Where each sensor's measured signal lives in a data file.
use super::{Model, RecordRef};
use serde::de::{self, Deserializer, MapAccess, Visitor};
use std::fmt;

/// Where a sensor's signal lives: written in the model file as
/// `data = { column = "knee_ax" }`, `data = { variable = "acc_x" }`,
/// `data = { record = 3 }` or `data = { record = "acc_x" }`.
///
/// Names work in every format — a CSV column, a MAT-file variable, or a
/// universal-file record's ID line 1 — so one model file reads the same
/// data exported as CSV, `.mat` or UFF; the three words only say what the
/// writer had in mind. A record *number* needs a universal file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DataSource {
    /// A named column (CSV), or any named signal.
    Column(String),
    /// A named variable (MAT-file), or any named signal.
    Variable(String),
    /// A universal-file function record, by 1-based number or by name.
    Record(RecordRef),
}

impl DataSource {
    /// The default for a sensor without `data`: the signal named like it.
    pub fn for_sensor(sensor: &str) -> Self {
        DataSource::Column(sensor.to_string())
    }

    /// The signal's name, unless the source is a record number.
    pub fn name(&self) -> Option<&str> {
        match self {
            DataSource::Column(n) | DataSource::Variable(n) => Some(n),
            DataSource::Record(RecordRef::Name(n)) => Some(n),
            DataSource::Record(RecordRef::Index(_)) => None,
        }
    }

    /// Checks the source as written: a non-empty name, a record number
    /// from 1. For the model file's validation, with the sensor's entry.
    pub fn check(&self) -> Result<(), String> {
        match self {
            DataSource::Record(RecordRef::Index(0)) => {
                Err("record 0: records are numbered from 1".into())
            }
            _ if self.name().is_some_and(|n| n.trim().is_empty()) => {
                Err(format!("{self}: the name is empty"))
            }
            _ => Ok(()),
        }
    }

    /// The record this source names in a universal file.
    pub fn record_ref(&self) -> RecordRef {
        match self {
            DataSource::Record(r) => r.clone(),
            DataSource::Column(n) | DataSource::Variable(n) => RecordRef::Name(n.clone()),
        }
    }
}

impl fmt::Display for DataSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DataSource::Column(n) => write!(f, "column '{n}'"),
            DataSource::Variable(n) => write!(f, "variable '{n}'"),
            DataSource::Record(r) => write!(f, "record {r}"),
        }
    }
}

impl<'de> serde::Deserialize<'de> for DataSource {
    /// From a table with exactly one of the keys `column`, `variable`,
    /// `record`.
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = DataSource;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(
                    "a table with one key: { column = \"name\" }, { variable = \"name\" } \
                     or { record = 3 } / { record = \"name\" }",
                )
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<DataSource, A::Error> {
                let mut found: Option<(String, DataSource)> = None;
                while let Some(key) = map.next_key::<String>()? {
                    let value = match key.as_str() {
                        "column" => DataSource::Column(map.next_value()?),
                        "variable" => DataSource::Variable(map.next_value()?),
                        "record" => DataSource::Record(map.next_value()?),
                        other => {
                            return Err(de::Error::unknown_field(
                                other,
                                &["column", "variable", "record"],
                            ))
                        }
                    };
                    if let Some((first, _)) = &found {
                        return Err(de::Error::custom(format!(
                            "give one of column, variable or record, not both '{first}' and '{key}'"
                        )));
                    }
                    found = Some((key, value));
                }
                found.map(|(_, v)| v).ok_or_else(|| {
                    de::Error::custom("an empty table: give column, variable or record")
                })
            }
        }
        d.deserialize_map(V)
    }
}

/// The default sources of a model's sensors: each reads the signal named
/// like the sensor.
pub fn default_sources(model: &Model) -> Vec<DataSource> {
    model
        .sensors
        .iter()
        .map(|s| DataSource::for_sensor(&s.name))
        .collect()
}
