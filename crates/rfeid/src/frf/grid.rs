//! The frequency grid of a model's FRF: log-spaced by default (a Bode
//! plot's), fine enough to resolve its sharpest resonance.
//!
//! A mode of frequency f and damping ratio ζ has a half-power bandwidth of
//! 2ζf; a log-spaced grid whose ratio between neighbours is `1 + ζ_min/2`
//! puts about four points in every mode's bandwidth.
use crate::model::Model;
use crate::simulation::modal::modal_analysis;
use crate::simulation::Simulator;

/// How the grid's points are spaced.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Spacing {
    /// Evenly in log f.
    Log,
    /// Evenly in f.
    Linear,
}

/// The most points a default grid takes.
pub const MAX_DEFAULT_POINTS: usize = 20_000;

/// A grid from `fmin` to `fmax` Hz. Defaults: `fmax` the Nyquist
/// frequency of the model's sampling; `fmin` a tenth of the lowest mode's
/// frequency (log) or `fmax / points` (linear); `points` as the module says
/// for the sharpest mode (log, 200 to [`MAX_DEFAULT_POINTS`]), or 1000
/// (linear). The modes are those at `params`; a model whose modal analysis
/// fails gets the 1000-point default.
pub fn grid(
    model: &Model,
    params: &[f64],
    fmin: Option<f64>,
    fmax: Option<f64>,
    points: Option<usize>,
    spacing: Spacing,
) -> Vec<f64> {
    let fmax = fmax.unwrap_or(model.sampling.sample_rate / 2.0);
    let modes = resonances(model, params);
    match spacing {
        Spacing::Linear => {
            let n = points.unwrap_or(1000).max(2);
            let fmin = fmin.unwrap_or(fmax / n as f64);
            let step = (fmax - fmin) / (n - 1) as f64;
            (0..n).map(|k| fmin + step * k as f64).collect()
        }
        Spacing::Log => {
            let lowest = modes.iter().map(|m| m.0).fold(f64::INFINITY, f64::min);
            let fmin = fmin
                .filter(|f| *f > 0.0)
                .unwrap_or(if lowest.is_finite() {
                    lowest / 10.0
                } else {
                    fmax / 1000.0
                })
                .min(fmax / 2.0);
            let zeta = modes.iter().map(|m| m.1).fold(0.05_f64, f64::min).max(1e-4);
            let sharp = ((fmax / fmin).ln() / (0.5 * zeta).ln_1p()).ceil() as usize;
            let n = points
                .unwrap_or(sharp.clamp(200, MAX_DEFAULT_POINTS))
                .max(2);
            let ratio = (fmax / fmin).ln() / (n - 1) as f64;
            (0..n).map(|k| fmin * (ratio * k as f64).exp()).collect()
        }
    }
}

/// The model's resonances at `params`: (frequency Hz, damping ratio) of
/// each mode with stiffness and positive damping.
fn resonances(model: &Model, params: &[f64]) -> Vec<(f64, f64)> {
    let sim = Simulator::with_integrator(model, crate::simulation::steps::integrator(1));
    let Ok(modal) = modal_analysis(&sim, params) else {
        return Vec::new();
    };
    modal
        .modes
        .iter()
        .filter(|m| !m.zero_stiffness && m.frequency_hz > 0.0)
        .filter_map(|m| Some((m.frequency_hz, m.damping_ratio.filter(|z| *z > 0.0)?)))
        .collect()
}
