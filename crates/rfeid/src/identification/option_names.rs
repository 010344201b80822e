//! The choices of an identification's options by name (`lm`, `estimated`,
//! `ar`, `plan`, …), as the command line, shard files and the Python
//! module spell them, and each choice read and written by its name in
//! files ([`serde`]), so every front end and file shares one spelling.
use crate::identification::options::OptionError;
use crate::identification::pipeline::{Method, NoiseModel, Start, Weighting};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// `method`'s values by name, as the command line, shard files and the
/// Python module spell them.
pub const METHODS: [(&str, Method); 2] = [("lm", Method::Lm), ("bfgs", Method::Bfgs)];
/// `weights`' values by name.
pub const WEIGHTS: [(&str, Weighting); 2] = [
    ("equal", Weighting::Equal),
    ("estimated", Weighting::EstimatedNoise),
];
/// `noise_model`'s values by name (`ar`: the default autoregressive model).
pub const NOISE_MODELS: [(&str, NoiseModel); 2] = [
    (
        "ar",
        NoiseModel::Autoregressive {
            max_order: crate::identification::noise::DEFAULT_MAX_ORDER,
        },
    ),
    ("white", NoiseModel::White),
];
/// `start`'s values by name.
pub const STARTS: [(&str, Start); 2] = [("plan", Start::Plan), ("values", Start::Values)];

/// The value named `value` among `choices` of option `option`; an unknown
/// name lists the choices.
pub fn named<T: Copy>(
    option: &'static str,
    value: &str,
    choices: &[(&str, T)],
) -> Result<T, OptionError> {
    choices
        .iter()
        .find(|(n, _)| *n == value)
        .map(|(_, v)| *v)
        .ok_or_else(|| {
            let names: Vec<&str> = choices.iter().map(|(n, _)| *n).collect();
            OptionError::new(
                option,
                format!("'{value}': must be one of {}", names.join(", ")),
            )
        })
}

/// The name of `value` among `choices` (`""` if absent).
pub fn name_of<T: PartialEq>(value: &T, choices: &[(&'static str, T)]) -> &'static str {
    choices
        .iter()
        .find(|(_, v)| v == value)
        .map_or("", |(n, _)| *n)
}

/// Writes `value` by its name among `table`, the choices of `option`.
fn write_name<T: PartialEq + std::fmt::Debug, S: Serializer>(
    value: &T,
    table: &[(&'static str, T)],
    option: &str,
    s: S,
) -> Result<S::Ok, S::Error> {
    match name_of(value, table) {
        "" => Err(serde::ser::Error::custom(format!(
            "{value:?} has no name among the choices of `{option}`"
        ))),
        name => s.serialize_str(name),
    }
}

/// Reads a choice of `option` by its name among `table`.
fn read_name<'de, T: Copy, D: Deserializer<'de>>(
    d: D,
    table: &[(&str, T)],
    option: &'static str,
) -> Result<T, D::Error> {
    let name = std::borrow::Cow::<str>::deserialize(d)?;
    named(option, &name, table).map_err(serde::de::Error::custom)
}

/// A noise model by its name in [`NOISE_MODELS`] (`#[serde(with)]`):
/// option files name it, where RESULT.json records the model itself.
pub mod noise_model_name {
    use super::*;

    /// Writes the noise model's name.
    pub fn serialize<S: Serializer>(m: &NoiseModel, s: S) -> Result<S::Ok, S::Error> {
        write_name(m, &NOISE_MODELS, "noise_model", s)
    }

    /// Reads a noise model by its name.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<NoiseModel, D::Error> {
        read_name(d, &NOISE_MODELS, "noise_model")
    }
}

impl Serialize for Weighting {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        write_name(self, &WEIGHTS, "weights", s)
    }
}

impl<'de> Deserialize<'de> for Weighting {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        read_name(d, &WEIGHTS, "weights")
    }
}

impl Serialize for Start {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        write_name(self, &STARTS, "start", s)
    }
}

impl<'de> Deserialize<'de> for Start {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        read_name(d, &STARTS, "start")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_choice_is_written_and_read_by_its_name() {
        for (name, m) in METHODS {
            assert_eq!(serde_json::to_string(&m).unwrap(), format!("\"{name}\""));
            assert_eq!(
                serde_json::from_str::<Method>(&format!("\"{name}\"")).unwrap(),
                m
            );
        }
        for (name, w) in WEIGHTS {
            assert_eq!(serde_json::to_value(w).unwrap(), name);
        }
        for (name, n) in NOISE_MODELS {
            let mut json = Vec::new();
            noise_model_name::serialize(&n, &mut serde_json::Serializer::new(&mut json)).unwrap();
            assert_eq!(json, format!("\"{name}\"").into_bytes());
            let read = noise_model_name::deserialize(serde_json::Value::from(name)).unwrap();
            assert_eq!(read, n);
        }
        for (name, s) in STARTS {
            assert_eq!(serde_json::to_value(s).unwrap(), name);
        }
        let e = serde_json::from_str::<Weighting>("\"heavy\"").unwrap_err();
        assert_eq!(
            e.to_string(),
            "`weights` 'heavy': must be one of equal, estimated"
        );
        let unnamed = NoiseModel::Autoregressive { max_order: 3 };
        let mut json = Vec::new();
        let mut ser = serde_json::Serializer::new(&mut json);
        assert!(noise_model_name::serialize(&unnamed, &mut ser).is_err());
    }
}
