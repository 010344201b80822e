//! A simulated record, as `rfeid simulate` and the Python module's
//! `Model.simulate` make it: the steps chosen at the parameter values (the
//! choice's own run at the chosen steps is the record), and seeded noise if
//! asked for (white, or low-pass filtered as an anti-alias filter leaves
//! it; SPEC §3).
use super::{add_filtered_noise, add_noise, check_noise, NoiseError};
use crate::identification::options::OptionError;
use crate::model::Model;
#[cfg(doc)]
use crate::simulation::aliasing::above_nyquist_after;
use crate::simulation::aliasing::DeformationPeaks;
use crate::simulation::steps::integrator;
use crate::simulation::{Response, SampleView, SimulationError, Simulator};
use std::time::Duration;

/// Noise added to a simulated record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoiseSpec {
    /// σ as a fraction of each sensor's RMS (≥ 0).
    pub fraction: f64,
    /// The corner frequency (Hz) of the low-pass filter the noise passes,
    /// if any; white noise otherwise.
    pub corner: Option<f64>,
    /// The generator's seed.
    pub seed: u64,
}

/// Why a record could not be simulated.
#[derive(Debug, Clone, thiserror::Error)]
pub enum SimulatedError {
    /// The noise asked for cannot be made: a negative or non-finite
    /// fraction (`noise`), a corner frequency that is not a positive one
    /// (`noise_corner`), or noise this record cannot take (`noise`, with
    /// the sensor concerned named).
    #[error(transparent)]
    Option(OptionError),
    /// The steps could not be chosen at these values, or the run at the
    /// chosen steps (the record itself, which the choice computes) failed.
    #[error("choosing the integrator's steps: {0}")]
    Steps(SimulationError),
}

/// A simulated record with the simulator that made it.
#[derive(Debug)]
pub struct Simulated<'m> {
    /// The simulator, with the steps chosen.
    pub sim: Simulator<'m>,
    /// The response (with the noise, if asked for).
    pub response: Response,
    /// Wall time of the run alone.
    pub elapsed: Duration,
    /// Where the run deformed each power-law spring most (`None` without
    /// them), for [`above_nyquist_after`] without another run.
    pub peaks: Option<DeformationPeaks>,
}

/// Checks the noise's fraction (non-negative) and corner frequency
/// (positive, if given) before anything is simulated.
fn check_spec(n: &NoiseSpec) -> Result<(), SimulatedError> {
    if !(n.fraction >= 0.0 && n.fraction.is_finite()) {
        let detail = format!("{}: must be a non-negative fraction", n.fraction);
        return Err(SimulatedError::Option(OptionError::new("noise", detail)));
    }
    match n.corner.filter(|c| !(*c > 0.0 && c.is_finite())) {
        Some(c) => {
            let detail = format!("{c}: must be a positive frequency in Hz");
            Err(SimulatedError::Option(OptionError::new(
                "noise_corner",
                detail,
            )))
        }
        None => Ok(()),
    }
}

/// Simulates `model` at `params` (SI, one per parameter), with `noise` added
/// if given.
pub fn simulate_record<'m>(
    model: &'m Model,
    params: &[f64],
    noise: Option<&NoiseSpec>,
) -> Result<Simulated<'m>, SimulatedError> {
    if let Some(n) = noise {
        check_spec(n)?;
    }
    // The step choice ends with the run at the chosen steps and `params`:
    // that run is the record, and the peaks are watched along it.
    let mut peaks = DeformationPeaks::new(&Simulator::with_integrator(model, integrator(1)));
    let mut watch = |at: &SampleView<'_>| {
        if let Some(p) = peaks.as_mut() {
            p.observe(at)
        }
    };
    let (sim, (mut response, elapsed)) =
        Simulator::choose_watching(model, params, Some(&mut watch))
            .map_err(SimulatedError::Steps)?;
    if let Some(n) = noise {
        check_noise(&response, n.fraction).map_err(|source| {
            let sensor = match &source {
                NoiseError::Overflow { sensor, .. } | NoiseError::BelowRounding { sensor, .. } => {
                    model.sensors.get(*sensor).map(|s| s.name.clone())
                }
                NoiseError::BadFraction { .. } => None,
            };
            let sensor = sensor.map(|s| format!(" ('{s}')")).unwrap_or_default();
            let detail = format!(": {source}{sensor}");
            SimulatedError::Option(OptionError::new("noise", detail))
        })?;
        match n.corner {
            Some(corner) => {
                let rate = model.sampling.sample_rate;
                add_filtered_noise(&mut response, n.fraction, corner, rate, n.seed)
            }
            None => add_noise(&mut response, n.fraction, n.seed),
        }
    }
    Ok(Simulated {
        sim,
        response,
        elapsed,
        peaks,
    })
}
