//! The warnings of an identification, as values: what the run noticed that
//! does not by itself make the result suspect (the verdict says that), in
//! the order they arose. RESULT.json lists each as an object tagged by its
//! `kind`, with its values and its words in `message`.
use super::verdict::Reason;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use serde_json::{json, Value};
use std::fmt;

/// One warning of an identification.
#[derive(Debug, Clone, PartialEq)]
pub enum Warning {
    /// An identifiability warning of the Cramér–Rao analysis (eq. 26–29),
    /// worded as the verdict's reason.
    Identifiability(Reason),
    /// No local search from the plan ended where the fit passes the
    /// verdict's per-sensor checks, so automatic restarts ran.
    SideMinimum {
        /// The lowest J the searches from the plan reached.
        first_cost: f64,
        /// Restarts run.
        restarts: usize,
        /// The lowest J of an end that passes, if a restart found one (the
        /// side minima are then left out of the result).
        found: Option<f64>,
        /// Whether the restarts stopped because two came back to the lowest
        /// minimum (the model's best fit).
        agreed: bool,
    },
    /// No end passed the fit checks, and no restart ran: the bounds at the
    /// best end show that these parameters cannot be told apart, which no
    /// restart changes (the verdict names the combinations the data fix).
    RidgeNotRestarted {
        /// The lowest J the searches from the plan reached.
        first_cost: f64,
        /// The parameters that cannot be told apart.
        parameters: Vec<String>,
    },
    /// Fixed steps per sample whose estimated error at the estimate exceeds
    /// the tolerance.
    StepsTooCoarse {
        /// Steps per sample.
        substeps: usize,
        /// Estimated relative error.
        error: f64,
        /// The tolerance.
        tolerance: f64,
    },
    /// The simulation's accuracy at the estimate could not be checked.
    StepsUnchecked(crate::simulation::SimulationError),
    /// A mode above the Nyquist frequency at the estimate (the simulation
    /// module's words).
    AboveNyquist(String),
    /// A start's search on the first part of the record
    /// ([`crate::identification::pipeline::Settings::window`]) could not
    /// run; that start searched the whole record from where it was.
    WindowFailed {
        /// The fraction of the record.
        fraction: f64,
        /// Why.
        reason: super::termination::SolveError<crate::simulation::SimulationError>,
    },
    /// The profile likelihood's 95 % interval of a parameter differs from
    /// the Wald interval of its Cramér–Rao bound (eq. 26) by more than a
    /// third of its width or of either half-width: the criterion is not
    /// quadratic over the interval, and the standard error misstates the
    /// uncertainty ([`crate::identification::profile`]).
    ProfileDiffers {
        /// The parameter.
        parameter: String,
        /// The profile interval, SI.
        profile: [f64; 2],
        /// The Wald interval, SI.
        wald: [f64; 2],
    },
    /// A parameter's profile stays below the 95 % threshold up to the
    /// bounds listed: the data do not bound it there (practically
    /// non-identifiable).
    ProfileOpen {
        /// The parameter.
        parameter: String,
        /// The box's bounds it is open at, SI.
        bounds: Vec<f64>,
    },
    /// A parameter's profile ended below the threshold before its bound
    /// (its refits there failed, or the walk's points ran out), so that end
    /// of its interval is unknown.
    ProfileUnresolved {
        /// The parameter.
        parameter: String,
        /// `lower` or `upper`.
        side: String,
        /// The farthest value refitted, SI.
        last: f64,
    },
    /// The profiles could not be computed.
    ProfilesSkipped(String),
    /// A warning read back from a RESULT.json as it was written: its
    /// tagged object (or, in files written before warnings were tagged,
    /// its words).
    Recorded(Value),
}

impl Warning {
    /// The words of a profile's warning ([`Warning::is_profile`]); nothing
    /// for the others.
    fn fmt_profile(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::ProfileDiffers {
                parameter,
                profile: [lo, hi],
                wald: [wlo, whi],
            } => write!(
                f,
                "{parameter}: the profile likelihood's 95 % interval [{lo:.5e}, {hi:.5e}] differs \
                 from the Wald interval of its standard error [{wlo:.5e}, {whi:.5e}] by more than \
                 a third: the criterion is not quadratic there, trust the profile interval"
            ),
            Warning::ProfileOpen { parameter, bounds } => {
                let at: Vec<String> = bounds.iter().map(|b| format!("{b:.5e}")).collect();
                write!(
                    f,
                    "{parameter}: the profile likelihood stays below the 95 % threshold up to \
                     the box's bound {}: the data do not bound it there (practically \
                     non-identifiable)",
                    at.join(" and ")
                )
            }
            Warning::ProfileUnresolved {
                parameter,
                side,
                last,
            } => write!(
                f,
                "{parameter}: the profile ended at {last:.5e}, below the 95 % threshold and \
                 short of the box's bound (its refits failed beyond, or its points ran out), so \
                 the {side} end of its profile interval is unknown"
            ),
            Warning::ProfilesSkipped(reason) => write!(f, "no profiles: {reason}"),
            _ => Ok(()),
        }
    }

    /// Whether the warning is about a profile likelihood.
    pub fn is_profile(&self) -> bool {
        matches!(
            self,
            Warning::ProfileDiffers { .. }
                | Warning::ProfileOpen { .. }
                | Warning::ProfileUnresolved { .. }
                | Warning::ProfilesSkipped(_)
        )
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::Identifiability(r) => r.fmt(f),
            Warning::SideMinimum {
                first_cost,
                restarts,
                found: Some(best),
                ..
            } => write!(
                f,
                "the local search from the plan ended at J = {first_cost:.6e}, where the fit \
                 fails the verdict's per-sensor checks (a side minimum); {restarts} automatic \
                 restart(s) from the next-best distinct plan points found J = {best:.6e}, where \
                 it passes; the side minima are left out of the result"
            ),
            Warning::SideMinimum {
                first_cost,
                restarts,
                found: None,
                agreed: true,
            } => write!(
                f,
                "the local search from the plan ended at J = {first_cost:.6e}, where the fit fails \
                 the verdict's per-sensor checks; {restarts} automatic restart(s) from the \
                 next-best distinct plan points came back to the lowest minimum, so the \
                 restarts stopped: it is the model's best fit"
            ),
            Warning::SideMinimum {
                first_cost,
                restarts,
                found: None,
                agreed: false,
            } => write!(
                f,
                "the local search from the plan ended at J = {first_cost:.6e}, where the fit fails \
                 the verdict's per-sensor checks, and {restarts} automatic restart(s) from the \
                 next-best distinct plan points found no minimum where it passes"
            ),
            Warning::RidgeNotRestarted {
                first_cost,
                parameters,
            } => write!(
                f,
                "the local search from the plan ended at J = {first_cost:.6e}, where the fit fails \
                 the verdict's per-sensor checks; no automatic restart ran, because the bounds \
                 there show that {} cannot be told apart (a ridge of the criterion), which no \
                 restart changes: fix one of them (`set`) or add a test that separates them",
                parameters.join(", ")
            ),
            Warning::StepsTooCoarse {
                substeps,
                error,
                tolerance,
            } => write!(
                f,
                "the fixed {substeps} step(s) per sample give an estimated relative error of \
                 {error:.2e} at the estimate, more than the tolerance {tolerance:.1e}; leave \
                 `substeps` unset to have them chosen"
            ),
            Warning::StepsUnchecked(e) => write!(
                f,
                "the simulation's accuracy at the estimate could not be checked: {e}"
            ),
            Warning::WindowFailed { fraction, reason } => write!(
                f,
                "a start's search on the first {:.0} % of the record failed ({reason}); it \
                 searched the whole record from its plan point instead",
                fraction * 100.0
            ),
            w @ (Warning::ProfileDiffers { .. }
            | Warning::ProfileOpen { .. }
            | Warning::ProfileUnresolved { .. }
            | Warning::ProfilesSkipped(_)) => w.fmt_profile(f),
            Warning::AboveNyquist(text) => f.write_str(text),
            Warning::Recorded(v) => match v {
                Value::String(text) => f.write_str(text),
                v => f.write_str(v["message"].as_str().unwrap_or_default()),
            },
        }
    }
}

impl Warning {
    /// A warning in words alone (a recorded one of an older file).
    pub fn recorded(text: impl Into<String>) -> Warning {
        Warning::Recorded(Value::String(text.into()))
    }

    /// What RESULT.json records: `kind` (snake case), the warning's values,
    /// and its words in `message`.
    pub fn tagged(&self) -> Value {
        let mut v = match self {
            Warning::Recorded(v) => return v.clone(),
            Warning::Identifiability(r) => serde_json::to_value(r).unwrap_or(Value::Null),
            Warning::SideMinimum {
                first_cost,
                restarts,
                found,
                agreed,
            } => json!({"kind": "side_minimum", "first_cost": first_cost,
                "restarts": restarts, "found": found, "agreed": agreed}),
            Warning::RidgeNotRestarted {
                first_cost,
                parameters,
            } => json!({"kind": "ridge_not_restarted", "first_cost": first_cost,
                "parameters": parameters}),
            Warning::StepsTooCoarse {
                substeps,
                error,
                tolerance,
            } => json!({"kind": "steps_too_coarse", "substeps": substeps, "error": error,
                "tolerance": tolerance}),
            Warning::StepsUnchecked(_) => json!({"kind": "steps_unchecked"}),
            Warning::AboveNyquist(_) => json!({"kind": "above_nyquist"}),
            Warning::WindowFailed { fraction, .. } => {
                json!({"kind": "window_failed", "fraction": fraction})
            }
            Warning::ProfileDiffers {
                parameter,
                profile,
                wald,
            } => json!({"kind": "profile_differs", "parameter": parameter,
                "profile": profile, "wald": wald}),
            Warning::ProfileOpen { parameter, bounds } => {
                json!({"kind": "profile_open", "parameter": parameter, "bounds": bounds})
            }
            Warning::ProfileUnresolved {
                parameter,
                side,
                last,
            } => json!({"kind": "profile_unresolved", "parameter": parameter, "side": side,
                "last": last}),
            Warning::ProfilesSkipped(_) => json!({"kind": "profiles_skipped"}),
        };
        if let Value::Object(map) = &mut v {
            map.insert("message".into(), Value::String(self.to_string()));
        }
        v
    }
}

impl Serialize for Warning {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.tagged().serialize(s)
    }
}

impl<'de> Deserialize<'de> for Warning {
    /// A recorded warning: its tagged object, or its words.
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Value::deserialize(d)?;
        match &v {
            Value::String(_) => Ok(Warning::Recorded(v)),
            Value::Object(m) if m.get("message").is_some_and(Value::is_string) => {
                Ok(Warning::Recorded(v))
            }
            _ => Err(serde::de::Error::custom(
                "a warning is an object with `kind` and `message` (or, in older files, words)",
            )),
        }
    }
}
