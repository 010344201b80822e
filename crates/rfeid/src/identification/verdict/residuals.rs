//! The per-sensor checks of the residuals: fit, whiteness (Ljung–Box) and
//! noise level.
use super::input_test::input_statistic;
use super::reason::{Reason, SensorCheck};
use super::settings::VerdictSettings;
use super::FitSignal;
use crate::identification::chi_square::chi_square_sf;
use crate::measurement::spectrum::welch;
use crate::measurement::{misfit_and_spread, percent_fit};

/// Every sensor's checks, each failed one pushed to `reasons`.
pub(super) fn check_sensors(
    signals: &[FitSignal<'_>],
    s: &VerdictSettings,
    reasons: &mut Vec<Reason>,
) -> Vec<SensorCheck> {
    let mut checks = Vec::with_capacity(signals.len());
    let mut residual = Vec::new();
    for sig in signals {
        checks.push(check_sensor(sig, s, &mut residual, reasons));
    }
    checks
}

/// Whether the fit fails any per-sensor check of the verdict (poor fit,
/// residuals not white, residual variance beyond the noise level): a sign
/// of a side minimum, or of model error.
pub(crate) fn fit_fails(signals: &[FitSignal<'_>], s: &VerdictSettings) -> bool {
    let (mut residual, mut reasons) = (Vec::new(), Vec::new());
    signals.iter().any(|sig| {
        check_sensor(sig, s, &mut residual, &mut reasons);
        !reasons.is_empty()
    })
}

/// Whether the sensor is fitted to `exact_fit` of its signal's variation
/// (noise-free data: its residuals are rounding and integration error).
pub(crate) fn fitted_exactly(sig: &FitSignal<'_>, s: &VerdictSettings) -> bool {
    let (misfit, spread) = misfit_and_spread(sig.measured, sig.fitted);
    misfit <= s.exact_fit * spread
}

/// The fit, whiteness and noise-level checks of one sensor's measured and
/// fitted signals, the residual tests on what its noise model's filter
/// leaves; `residual` is scratch.
fn check_sensor(
    sig: &FitSignal<'_>,
    s: &VerdictSettings,
    residual: &mut Vec<f64>,
    reasons: &mut Vec<Reason>,
) -> SensorCheck {
    let (name, y, g) = (sig.sensor.clone(), sig.measured, sig.fitted);
    let before = reasons.len();
    let (misfit, spread) = misfit_and_spread(y, g);
    let fit_percent = percent_fit(misfit, spread);
    if fit_percent.is_none_or(|f| f < s.min_fit_percent) {
        reasons.push(Reason::PoorFit {
            sensor: name.clone(),
            fit_percent,
            threshold: s.min_fit_percent,
        });
    }
    let mut check = SensorCheck {
        sensor: name,
        fit_percent,
        ljung_box: None,
        p_value: None,
        noise_ratio: None,
        input_statistic: None,
        input_p_value: None,
        misfit_band: None,
        noise_order: None,
    };
    if misfit > s.exact_fit * spread {
        residual.clear();
        residual.extend(y.iter().zip(g).map(|(y, g)| y - g));
        sig.whitening.apply(residual);
        check.noise_order = Some(sig.whitening.order());
        residual_tests(sig, residual, s, &mut check, reasons);
    }
    if reasons.len() > before && sig.sample_rate > 0.0 {
        residual.clear();
        residual.extend(y.iter().zip(g).map(|(y, g)| y - g));
        check.misfit_band = welch(residual, sig.sample_rate, SEGMENT)
            .and_then(|spectrum| spectrum.peak_band())
            .map(|(peak, lo, hi)| [peak, lo, hi]);
    }
    check
}

/// Samples per segment of the residual spectra (a resolution of fs/1024).
const SEGMENT: usize = 1024;

/// The whiteness, noise-level and input tests on what the noise model
/// leaves of one sensor's residuals.
fn residual_tests(
    sig: &FitSignal<'_>,
    left: &[f64],
    s: &VerdictSettings,
    check: &mut SensorCheck,
    reasons: &mut Vec<Reason>,
) {
    let name = &check.sensor;
    if let Some(q) = ljung_box(left, s.lags) {
        let p = chi_square_sf(q, s.lags);
        (check.ljung_box, check.p_value) = (Some(q), Some(p));
        if p < s.whiteness_level {
            reasons.push(Reason::NotWhite {
                sensor: name.clone(),
                statistic: q,
                p_value: p,
                lags: s.lags,
                level: s.whiteness_level,
            });
        }
    }
    if let Some(ratio) = noise_ratio(left) {
        check.noise_ratio = Some(ratio);
        if ratio > s.max_noise_ratio {
            reasons.push(Reason::NoiseMismatch {
                sensor: name.clone(),
                ratio,
                threshold: s.max_noise_ratio,
            });
        }
    }
    if let Some((t, dof)) = input_statistic(left, sig.inputs) {
        let p = chi_square_sf(t, dof);
        (check.input_statistic, check.input_p_value) = (Some(t), Some(p));
        if p < s.whiteness_level {
            reasons.push(Reason::InputCorrelated {
                sensor: name.clone(),
                statistic: t,
                dof,
                p_value: p,
                level: s.whiteness_level,
            });
        }
    }
}

/// The Ljung–Box statistic `Q = n (n + 2) Σ_{k=1}^{h} ρ_k² / (n − k)` of
/// `e` (its mean removed), or `None` if the record is shorter than `2h + 2`
/// samples or constant.
pub fn ljung_box(e: &[f64], lags: usize) -> Option<f64> {
    let n = e.len();
    if n < 2 * lags + 2 {
        return None;
    }
    let mean = e.iter().sum::<f64>() / n as f64;
    let c0: f64 = e.iter().map(|v| (v - mean) * (v - mean)).sum();
    if c0 <= 0.0 {
        return None;
    }
    let mut q = 0.0;
    for k in 1..=lags {
        let ck: f64 = e[k..]
            .iter()
            .zip(e)
            .map(|(a, b)| (a - mean) * (b - mean))
            .sum();
        let rho = ck / c0;
        q += rho * rho / (n - k) as f64;
    }
    Some(n as f64 * (n as f64 + 2.0) * q)
}

/// `(Σ e² / n) / (Σ (Δe)² / (2 (n − 1)))`: about 1 for white residuals, large
/// when they hold a smooth part; `None` for fewer than 3 samples or
/// constant residuals.
pub fn noise_ratio(e: &[f64]) -> Option<f64> {
    let n = e.len();
    if n < 3 {
        return None;
    }
    let variance = e.iter().map(|v| v * v).sum::<f64>() / n as f64;
    let diff = e
        .windows(2)
        .map(|w| (w[1] - w[0]) * (w[1] - w[0]))
        .sum::<f64>()
        / (2.0 * (n - 1) as f64);
    (diff > 0.0).then(|| variance / diff)
}
