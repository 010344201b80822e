//! Validation of solver settings, shared by every solver's settings type.

/// A solver setting was given a value outside its valid range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("invalid setting `{name}` = {value}: must be {requirement}")]
pub struct SettingsError {
    /// Name of the setting (as in its `with_*` method).
    pub name: &'static str,
    /// The rejected value.
    pub value: f64,
    /// What the value must be, in words.
    pub requirement: &'static str,
}

/// `value` must be finite and > 0.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, SettingsError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(SettingsError {
            name,
            value,
            requirement: "finite and > 0",
        })
    }
}

/// `value` must lie in the open interval (0, 1).
pub(crate) fn in_unit_interval(name: &'static str, value: f64) -> Result<f64, SettingsError> {
    if value > 0.0 && value < 1.0 {
        Ok(value)
    } else {
        Err(SettingsError {
            name,
            value,
            requirement: "in the open interval (0, 1)",
        })
    }
}

/// A count must be ≥ `min`.
pub(crate) fn at_least(
    name: &'static str,
    value: usize,
    min: usize,
    requirement: &'static str,
) -> Result<usize, SettingsError> {
    if value >= min {
        Ok(value)
    } else {
        Err(SettingsError {
            name,
            value: value as f64,
            requirement,
        })
    }
}
