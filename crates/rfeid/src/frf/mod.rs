//! Frequency response functions: what the identified joints predict, and
//! how sure that prediction is.
//!
//! - [`linear`]: the model linearised at rest or at its static equilibrium
//!   (eq. 1), with the exact derivatives of M, C_t and K_t in the parameters;
//! - [`response`]: the FRFs from each excitation to each sensor or point,
//!   and their exact parameter derivatives;
//! - [`band`]: 95 % bands from the estimate's Cramér–Rao covariance
//!   (eq. 26–29) by the delta method;
//! - [`measured`]: H1 and the coherence from a measured force and response;
//! - [`grid`]: the frequencies, fine enough for the sharpest resonance;
//! - [`estimate`]: a result's estimate and covariance for one experiment;
//! - [`study`]: all of it for the chosen pairs, as the command line and
//!   Python show it.
//!
//! A nonlinear joint's FRF is that of its linearisation: valid for motions
//! small against the deformations that change its slope.
pub mod band;
pub mod estimate;
pub mod grid;
pub mod linear;
pub mod measured;
pub mod response;
pub mod study;

pub use band::{band, Band, Z95};
pub use estimate::{at_estimate, AtEstimate};
pub use grid::{grid, Spacing};
pub use linear::{linearise, Linearised};
pub use measured::{default_segment, h1, MeasuredFrf};
pub use response::{frf, Frf, Output, C64};
pub use study::{frf_unit, study, DataSet, FrfRequest, FrfStudy};

/// Why an FRF could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FrfError {
    /// The linearisation failed (no static equilibrium, a bad value …).
    #[error("linearising the model: {0}")]
    Linearisation(#[from] crate::simulation::SimulationError),
    /// `K_t − ω² M + iω C_t` is singular at this frequency: an undamped
    /// mode exactly there, or a free motion at 0 Hz.
    #[error(
        "the linearised model has no finite response at {frequency} Hz (an undamped mode \
         there, or a free motion at 0 Hz)"
    )]
    Singular {
        /// The frequency, Hz.
        frequency: f64,
    },
    /// Welch's segment does not fit the record.
    #[error(
        "an H1 segment of {segment} samples needs a power of two from 8 up to the record's \
         {samples} samples, and a force and response of one length"
    )]
    Segment {
        /// The segment asked for.
        segment: usize,
        /// The record's samples.
        samples: usize,
    },
}

/// The model's FRFs at `params` from each excitation to each of `outputs`
/// at `frequencies` (Hz), differentiated in the parameters `wrt`:
/// [`linearise`] then [`frf`].
pub fn model_frf(
    model: &crate::model::Model,
    params: &[f64],
    wrt: &[usize],
    outputs: &[Output],
    frequencies: &[f64],
) -> Result<Frf, FrfError> {
    let lin = linearise(model, params, wrt)?;
    frf(&lin, outputs, params, wrt, frequencies)
}
