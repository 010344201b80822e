//! The model file as written: serde structures with spans, no meaning yet.
use serde::Deserialize;
use toml::Spanned;

/// A number, or a string: a quantity with a unit (`"15 daN/um"`) or the
/// name of a parameter.
#[derive(Debug, Clone)]
pub enum RawNum {
    /// A bare number, SI.
    Num(f64),
    /// A quantity with a unit, or a parameter name.
    Text(String),
    /// `true` or `false`: never a valid value, but read so that the error
    /// can name the field and say what it takes
    /// ([`crate::io::model_file`]'s builder refuses it).
    Bool(bool),
}

/// Reads a number or a string, and says what it expected otherwise (an
/// untagged enum would only say that nothing matched).
impl<'de> Deserialize<'de> for RawNum {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = RawNum;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(
                    "a number, or a string holding a quantity with a unit (\"15 daN/um\") \
                     or a parameter's name",
                )
            }
            fn visit_f64<E>(self, v: f64) -> Result<RawNum, E> {
                Ok(RawNum::Num(v))
            }
            fn visit_i64<E>(self, v: i64) -> Result<RawNum, E> {
                Ok(RawNum::Num(v as f64))
            }
            fn visit_u64<E>(self, v: u64) -> Result<RawNum, E> {
                Ok(RawNum::Num(v as f64))
            }
            fn visit_bool<E>(self, v: bool) -> Result<RawNum, E> {
                Ok(RawNum::Bool(v))
            }
            fn visit_str<E>(self, v: &str) -> Result<RawNum, E> {
                Ok(RawNum::Text(v.to_string()))
            }
            fn visit_string<E>(self, v: String) -> Result<RawNum, E> {
                Ok(RawNum::Text(v))
            }
        }
        d.deserialize_any(Visitor)
    }
}

pub type SNum = Spanned<RawNum>;
pub type SVec = Spanned<Vec<SNum>>;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawFile {
    pub simulation: Option<Spanned<RawSimulation>>,
    pub gravity: Option<SVec>,
    #[serde(default)]
    pub body: Vec<Spanned<RawBody>>,
    #[serde(default)]
    pub element: Vec<Spanned<RawElement>>,
    #[serde(default)]
    pub parameter: Vec<Spanned<RawParameter>>,
    #[serde(default)]
    pub excitation: Vec<Spanned<RawExcitation>>,
    #[serde(default)]
    pub sensor: Vec<Spanned<RawSensor>>,
    #[serde(default)]
    pub experiment: Vec<Spanned<RawExperiment>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSimulation {
    pub duration: Option<SNum>,
    pub sample_rate: Option<SNum>,
    pub substeps: Option<Spanned<i64>>,
    pub tolerance: Option<SNum>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawBody {
    pub name: Option<Spanned<String>>,
    pub mass: Option<SNum>,
    pub inertia: Option<SVec>,
    pub com: Option<SVec>,
    pub axes: Option<Spanned<Vec<SVec>>>,
}

/// A component's table: its keys as written. Which keys it may hold is
/// its law's to say (`simulation::laws`), so any key is read here and the
/// builder refuses the ones the law does not take.
#[derive(Debug, Deserialize)]
#[serde(transparent)]
pub struct RawComponent {
    /// Each key with its value (the law's name is a text value).
    pub keys: std::collections::BTreeMap<Spanned<String>, SNum>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawElement {
    pub name: Option<Spanned<String>>,
    pub body: Option<Spanned<String>>,
    pub to: Option<Spanned<String>>,
    pub at: Option<SVec>,
    pub axes: Option<Spanned<Vec<SVec>>>,
    pub ux: Option<Spanned<RawComponent>>,
    pub uy: Option<Spanned<RawComponent>>,
    pub uz: Option<Spanned<RawComponent>>,
    pub rx: Option<Spanned<RawComponent>>,
    pub ry: Option<Spanned<RawComponent>>,
    pub rz: Option<Spanned<RawComponent>>,
}

impl RawElement {
    /// The six component slots in `ux … rz` order.
    pub fn components(&self) -> [&Option<Spanned<RawComponent>>; 6] {
        [&self.ux, &self.uy, &self.uz, &self.rx, &self.ry, &self.rz]
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawParameter {
    pub name: Option<Spanned<String>>,
    pub value: Option<SNum>,
    pub min: Option<SNum>,
    pub max: Option<SNum>,
    pub scale: Option<Spanned<String>>,
    pub per_experiment: Option<Spanned<bool>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawTone {
    pub amplitude: Option<SNum>,
    pub frequency: Option<SNum>,
    pub phase: Option<SNum>,
}

/// A signal table; which keys apply depends on `type` (checked when built).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSignal {
    #[serde(rename = "type")]
    pub kind: Option<Spanned<String>>,
    pub amplitude: Option<SNum>,
    pub frequency: Option<SNum>,
    pub phase: Option<SNum>,
    pub components: Option<Spanned<Vec<Spanned<RawTone>>>>,
    pub f0: Option<SNum>,
    pub f1: Option<SNum>,
    pub duration: Option<SNum>,
    pub t0: Option<SNum>,
    pub width: Option<SNum>,
    pub file: Option<Spanned<String>>,
    pub column: Option<Spanned<String>>,
    pub variable: Option<Spanned<String>>,
    pub interpolation: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawExcitation {
    pub name: Option<Spanned<String>>,
    pub body: Option<Spanned<String>>,
    pub reaction: Option<Spanned<String>>,
    pub at: Option<SVec>,
    pub direction: Option<SVec>,
    pub signal: Option<Spanned<RawSignal>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSensor {
    pub name: Option<Spanned<String>>,
    pub body: Option<Spanned<String>>,
    pub at: Option<SVec>,
    pub direction: Option<SVec>,
    pub quantity: Option<Spanned<String>>,
    pub data: Option<Spanned<crate::model::DataSource>>,
    pub gain: Option<SNum>,
    pub offset: Option<SNum>,
    pub noise: Option<SNum>,
    pub candidate: Option<Spanned<bool>>,
}

/// One test of a campaign (SPEC §5).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawExperiment {
    pub name: Option<Spanned<String>>,
    pub data: Option<Spanned<String>>,
    pub set: Option<Spanned<std::collections::BTreeMap<String, SNum>>>,
    pub from: Option<SNum>,
    pub duration: Option<SNum>,
    pub sample_rate: Option<SNum>,
    pub excitations: Option<Spanned<Vec<Spanned<String>>>>,
    pub sensors: Option<Spanned<Vec<Spanned<String>>>>,
    #[serde(rename = "use")]
    pub role: Option<Spanned<String>>,
    pub weight: Option<SNum>,
}

/// The file read loosely, every entry a plain table with its span: used only
/// to say which entry holds a key the strict structures above reject.
#[derive(Debug, Deserialize)]
pub struct LooseFile {
    pub simulation: Option<Spanned<toml::Table>>,
    #[serde(default)]
    pub body: Vec<Spanned<toml::Table>>,
    #[serde(default)]
    pub element: Vec<Spanned<toml::Table>>,
    #[serde(default)]
    pub parameter: Vec<Spanned<toml::Table>>,
    #[serde(default)]
    pub excitation: Vec<Spanned<toml::Table>>,
    #[serde(default)]
    pub sensor: Vec<Spanned<toml::Table>>,
    #[serde(default)]
    pub experiment: Vec<Spanned<toml::Table>>,
}
