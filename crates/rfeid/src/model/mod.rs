//! The rigid-finite-element model (paper §2, eq. 1–9; SPEC §1).
//!
//! A [`Model`] is built and validated once, from a file
//! ([`crate::io::model_file`]) or in code, and everything downstream trusts
//! it. Values are SI. Any coefficient that may be identified is a [`Value`]:
//! a fixed number or a reference to a [`Parameter`].
mod column_name;
mod data_source;
mod edit;
mod experiment;
pub mod geometry;
mod record_ref;
pub mod set_values;
mod signal;

pub use column_name::ColumnName;
pub use data_source::{default_sources, DataSource};
pub use edit::{EditError, ParameterRef};
pub use experiment::{Experiment, Role};
pub use record_ref::RecordRef;
pub use signal::{
    BandLimited, BandLimitedError, FixedSignal, Interpolation, Segment, Shape, Signal, Term,
};

use nalgebra::{Matrix3, Vector3};

/// A coefficient of the model: a fixed number or a named parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A number, SI.
    Fixed(f64),
    /// The parameter with this index in [`Model::parameters`].
    Param(usize),
}

impl Value {
    /// The value for the parameter values `p` (indexed like [`Model::parameters`]).
    #[inline]
    pub fn eval(&self, p: &[f64]) -> f64 {
        match *self {
            Value::Fixed(v) => v,
            Value::Param(i) => p[i],
        }
    }

    /// The parameter this value stands for, if any.
    pub fn param(&self) -> Option<usize> {
        match *self {
            Value::Fixed(_) => None,
            Value::Param(i) => Some(i),
        }
    }
}

/// A rigid body (an RFE) with 6 degrees of freedom `[u1 u2 u3 φ1 φ2 φ3]`
/// along and about its principal central axes (eq. 1).
#[derive(Debug, Clone)]
pub struct Body {
    /// Unique name.
    pub name: String,
    /// Mass m, kg.
    pub mass: Value,
    /// Principal central moments of inertia J1, J2, J3, kg·m².
    pub inertia: [Value; 3],
    /// Centre of mass, global frame, m.
    pub com: Vector3<f64>,
    /// Principal axes as the columns of a rotation matrix R (global components).
    pub axes: Matrix3<f64>,
}

/// What the second end of a spring–damping element is attached to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Attachment {
    /// The body with this index in [`Model::bodies`].
    Body(usize),
    /// The ground, which does not move.
    Ground,
}

pub use crate::simulation::laws::{BoucWen, Friction, Law, Linear, Power, PowerSpring};

/// One component (one row of B) of a spring–damping element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Component {
    /// 0–2: translations `ux uy uz` along the element axes; 3–5: rotations `rx ry rz`.
    pub dof: usize,
    /// The spring.
    pub law: Law,
    /// Viscous damping c (N·s/m or N·m·s/rad), eq. 7–9.
    pub damping: Value,
}

/// Names of the six SDE components, indexed like [`Component::dof`].
pub const COMPONENT_NAMES: [&str; 6] = ["ux", "uy", "uz", "rx", "ry", "rz"];

/// A spring–damping element κ joining `body` (r) to `to` (p), eq. 2–9.
#[derive(Debug, Clone)]
pub struct Element {
    /// Unique name.
    pub name: String,
    /// Body r.
    pub body: usize,
    /// Body p or ground.
    pub to: Attachment,
    /// Position x_κ, global, m.
    pub at: Vector3<f64>,
    /// Element axes E_κ as columns (global components), right-handed orthonormal.
    pub axes: Matrix3<f64>,
    /// The components present.
    pub components: Vec<Component>,
}

/// A model parameter: a named number, identified when it has a box (eq. 17).
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    /// Unique name.
    pub name: String,
    /// Nominal value, SI.
    pub value: f64,
    /// Search box `[min, max]`, SI; `None` for a fixed parameter.
    pub bounds: Option<(f64, f64)>,
    /// How the search maps the box onto `[0, 1]` (eq. 17, or its
    /// logarithmic form); [`Scale::Linear`] for a fixed parameter.
    pub scale: Scale,
    /// How to show values to a person: a unit symbol and its SI scale.
    pub unit: DisplayUnit,
    /// Physical dimension, from the places the parameter is used.
    pub dimension: crate::units::Dimension,
    /// Identified once per fitted experiment (SPEC §5), reported as
    /// `name[experiment]`.
    pub per_experiment: bool,
}

/// How an identified parameter's box is mapped onto the normalised
/// coordinate `u ∈ [0, 1]` that the plan and the local search work in.
///
/// - `Linear`: `x = min + u (max − min)` (eq. 17);
/// - `Log`: `x = min (max/min)^u`, i.e. `ln x` linear in u: equal steps in u
///   are equal ratios of x, so a plan covers every decade of a wide box
///   alike, and the local search's steps are relative.
///
/// The default (see the model file's `scale`) is `Log` when `min > 0` and
/// `max/min ≥ 10`, `Linear` otherwise.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Scale {
    /// `x` linear in u.
    #[default]
    Linear,
    /// `ln x` linear in u (needs `min > 0`).
    Log,
}

impl Scale {
    /// The default scale of the box `[min, max]`: log when `min > 0` and
    /// `max/min ≥ 10`.
    pub fn default_for(min: f64, max: f64) -> Scale {
        if min > 0.0 && max >= 10.0 * min {
            Scale::Log
        } else {
            Scale::Linear
        }
    }

    /// `"linear"` or `"log"`, as in the model file.
    pub fn as_str(self) -> &'static str {
        match self {
            Scale::Linear => "linear",
            Scale::Log => "log",
        }
    }
}

/// A unit for showing numbers: `value_shown = value_si / scale`.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplayUnit {
    /// Symbol as the user wrote it, e.g. `daN/um^2`; empty for SI.
    pub symbol: String,
    /// SI value of one unit.
    pub scale: f64,
}

impl Default for DisplayUnit {
    fn default() -> Self {
        DisplayUnit {
            symbol: String::new(),
            scale: 1.0,
        }
    }
}

/// A force P(t) along a global unit direction at a point of a body, with
/// an optional equal and opposite reaction on a second body (SPEC §1).
#[derive(Debug, Clone)]
pub struct Excitation {
    /// Name (defaults to `excitation N`).
    pub name: String,
    /// The body the force acts on.
    pub body: usize,
    /// The body the reaction acts on.
    pub reaction: Option<usize>,
    /// Point of application, global, m.
    pub at: Vector3<f64>,
    /// Unit direction, global.
    pub direction: Vector3<f64>,
    /// P(t), N.
    pub signal: Signal,
}

/// What a sensor reads (eq. 15).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SensorKind {
    /// Displacement, m.
    Displacement,
    /// Velocity, m/s.
    Velocity,
    /// Acceleration, m/s².
    Acceleration,
}

impl SensorKind {
    /// The SI unit of the reading.
    pub fn unit(self) -> &'static str {
        match self {
            SensorKind::Displacement => "m",
            SensorKind::Velocity => "m/s",
            SensorKind::Acceleration => "m/s^2",
        }
    }
}

/// A sensor: the motion of a point of a body along a global unit direction.
#[derive(Debug, Clone)]
pub struct Sensor {
    /// Unique name; also the data column's name.
    pub name: String,
    /// The body.
    pub body: usize,
    /// The point, global, m.
    pub at: Vector3<f64>,
    /// Unit direction n, global.
    pub direction: Vector3<f64>,
    /// Displacement, velocity or acceleration.
    pub kind: SensorKind,
    /// Where its measured signal is in a data file (column, variable or
    /// record); by default the signal named like the sensor.
    pub data: DataSource,
    /// Calibration gain (SPEC §5): the reading is `gain · motion + offset`.
    pub gain: Value,
    /// Calibration offset, in the reading's unit.
    pub offset: Value,
    /// Standard deviation of its measurement noise, in the reading's unit
    /// (SPEC §6, for `rfeid design`; `identify` estimates the noise).
    pub noise: Option<f64>,
}

impl Sensor {
    /// Whether the sensor reads the motion itself (gain 1, offset 0).
    pub fn is_plain(&self) -> bool {
        self.gain == Value::Fixed(1.0) && self.offset == Value::Fixed(0.0)
    }
}

/// The sampling of a run: N = round(duration · rate) samples at t_k = k / rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sampling {
    /// Record length, s.
    pub duration: f64,
    /// Sample rate, Hz.
    pub sample_rate: f64,
    /// Integrator steps per sample interval, if fixed by the user (an expert
    /// override); `None`: chosen automatically to meet `tolerance`
    /// ([`crate::simulation::steps`]).
    pub substeps: Option<usize>,
    /// Relative RMS error of the simulated signals that the automatic steps
    /// aim at ([`crate::simulation::DEFAULT_TOLERANCE`] unless set).
    pub tolerance: f64,
}

impl Sampling {
    /// Number of samples N.
    pub fn n_samples(&self) -> usize {
        (self.duration * self.sample_rate).round() as usize
    }

    /// Time of sample k.
    pub fn time(&self, k: usize) -> f64 {
        k as f64 / self.sample_rate
    }

    /// The first sample at or after `from` seconds (`--from`, an
    /// experiment's `from`): sample k is at k / sample_rate, and a `from`
    /// within 10⁻⁹ of a sample's period of it counts as that sample.
    pub fn first_sample(&self, from: f64) -> usize {
        (from * self.sample_rate - 1e-9).ceil().max(0.0) as usize
    }

    /// The integrator's steps per sample in words: fixed, or automatic for
    /// the tolerance.
    pub fn steps_text(&self) -> String {
        match self.substeps {
            Some(s) => format!("{s} integrator step(s) per sample (fixed)"),
            None => format!(
                "integrator steps per sample chosen for a relative error of {:.0e}",
                self.tolerance
            ),
        }
    }
}

/// A validated RFE model with its experiment (excitations, sensors, sampling).
#[derive(Debug, Clone)]
pub struct Model {
    /// The rigid bodies; body b owns generalized coordinates `6b .. 6b + 6`.
    pub bodies: Vec<Body>,
    /// The spring–damping elements.
    pub elements: Vec<Element>,
    /// All parameters, fixed and identified.
    pub parameters: Vec<Parameter>,
    /// The excitation forces.
    pub excitations: Vec<Excitation>,
    /// The sensors.
    pub sensors: Vec<Sensor>,
    /// Places a sensor could go (`candidate = true`, SPEC §6): only
    /// `rfeid design` reads them; they are not measured.
    pub candidates: Vec<Sensor>,
    /// The sampling.
    pub sampling: Sampling,
    /// Gravity acceleration, global, m/s²; the run then starts from static equilibrium.
    pub gravity: Option<Vector3<f64>>,
    /// Files the model file read besides itself (signal tables), as opened.
    pub files: Vec<std::path::PathBuf>,
    /// Notes for the user from reading the model file (a signal table's
    /// time axis taken on the model's grid), each naming its file.
    pub notes: Vec<String>,
    /// The tests of a campaign (SPEC §5); empty for a model fitted to one
    /// data file.
    pub experiments: Vec<Experiment>,
}

impl Model {
    /// Number of generalized coordinates, 6 per body.
    pub fn n_dof(&self) -> usize {
        6 * self.bodies.len()
    }

    /// Whether a run starts from a static equilibrium rather than from
    /// q = 0: under gravity, and with a contact, whose gap or preload may
    /// hold a force at q = 0 that the other springs balance (SPEC §1).
    pub fn starts_at_equilibrium(&self) -> bool {
        self.gravity.is_some()
            || (self.elements.iter())
                .flat_map(|e| &e.components)
                .any(|c| matches!(c.law, Law::Contact(_)))
    }

    /// Nominal values of all parameters.
    pub fn nominal(&self) -> Vec<f64> {
        self.parameters.iter().map(|p| p.value).collect()
    }

    /// Indices of the identified parameters (those with a box), in file order.
    pub fn identified(&self) -> Vec<usize> {
        (0..self.parameters.len())
            .filter(|&i| self.parameters[i].bounds.is_some())
            .collect()
    }

    /// Index of the sensor with this name.
    pub fn sensor_index(&self, name: &str) -> Option<usize> {
        self.sensors.iter().position(|s| s.name == name)
    }

    /// Index of the parameter with this name.
    pub fn parameter_index(&self, name: &str) -> Option<usize> {
        self.parameters.iter().position(|p| p.name == name)
    }
}
