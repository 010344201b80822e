//! The verdict's thresholds, validated when set.
use crate::identification::settings::{at_least, in_unit_interval, positive, SettingsError};
use serde::{Deserialize, Serialize};

/// Thresholds of the verdict, validated when set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VerdictSettings {
    pub(super) bound_distance: f64,
    pub(super) minima_level: f64,
    pub(super) min_fit_percent: f64,
    pub(super) lags: usize,
    pub(super) whiteness_level: f64,
    pub(super) max_noise_ratio: f64,
    pub(super) exact_fit: f64,
}

impl Default for VerdictSettings {
    /// `bound_distance` 1e-3 (of the normalised width), `minima_level`
    /// 0.999, `min_fit_percent` 90, `lags` 20, `whiteness_level` 1e-6,
    /// `max_noise_ratio` 1.5, `exact_fit` 1e-6.
    fn default() -> Self {
        VerdictSettings {
            bound_distance: 1e-3,
            minima_level: 0.999,
            min_fit_percent: 90.0,
            lags: 20,
            whiteness_level: 1e-6,
            max_noise_ratio: 1.5,
            exact_fit: 1e-6,
        }
    }
}

impl VerdictSettings {
    /// The confidence level that sets when two ends are one minimum.
    pub fn minima_level(&self) -> f64 {
        self.minima_level
    }

    /// Distance from a bound, as a fraction of the normalised width, at or
    /// below which an estimate counts as on the bound, in (0, 1).
    pub fn with_bound_distance(mut self, value: f64) -> Result<Self, SettingsError> {
        self.bound_distance = in_unit_interval("bound_distance", value)?;
        Ok(self)
    }
    /// Confidence level whose χ² quantile separates distinct minima, in (0, 1).
    pub fn with_minima_level(mut self, value: f64) -> Result<Self, SettingsError> {
        self.minima_level = in_unit_interval("minima_level", value)?;
        Ok(self)
    }
    /// Fit (%) below which a sensor is poorly fitted (> 0).
    pub fn with_min_fit_percent(mut self, value: f64) -> Result<Self, SettingsError> {
        self.min_fit_percent = positive("min_fit_percent", value)?;
        Ok(self)
    }
    /// Lags of the Ljung–Box test (≥ 1).
    pub fn with_lags(mut self, value: usize) -> Result<Self, SettingsError> {
        self.lags = at_least("lags", value, 1, ">= 1")?;
        Ok(self)
    }
    /// p-value below which residuals are not white, in (0, 1).
    pub fn with_whiteness_level(mut self, value: f64) -> Result<Self, SettingsError> {
        self.whiteness_level = in_unit_interval("whiteness_level", value)?;
        Ok(self)
    }
    /// Residual variance over the first-difference noise level above which
    /// the residuals hold a systematic part (> 1).
    pub fn with_max_noise_ratio(mut self, value: f64) -> Result<Self, SettingsError> {
        let value = positive("max_noise_ratio", value)?;
        if value <= 1.0 {
            return Err(SettingsError {
                name: "max_noise_ratio",
                value,
                requirement: "> 1",
            });
        }
        self.max_noise_ratio = value;
        Ok(self)
    }
    /// Relative residual norm at or below which a sensor is fitted exactly,
    /// in (0, 1).
    pub fn with_exact_fit(mut self, value: f64) -> Result<Self, SettingsError> {
        self.exact_fit = in_unit_interval("exact_fit", value)?;
        Ok(self)
    }
}
