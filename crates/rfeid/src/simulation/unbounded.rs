//! Telling a response the model drives beyond every bound from steps that
//! are unstable.
//!
//! A run whose state passes the divergence bound ends in
//! [`SimulationError::Diverged`], which blames the steps. Unstable steps
//! grow through the method's amplification per step, which changes with the
//! step's length; a response the model itself drives past the bound (a
//! Bouc–Wen law that feeds energy in, a force of 10³⁰⁰ N) passes it at the
//! same sample, along the same path, whatever the step. So the run is made
//! again, once, at [`FINER`] times the steps per sample (and at the steps it
//! diverged at, to follow its path). The failure is
//! [`SimulationError::Unbounded`] only when
//!
//! - the model's fastest linearised mode is resolved at the finer steps
//!   (ωh ≤ 1, well inside the method's stability region), and
//! - both runs pass the bound at the same sample, with the same state there
//!   (to 10⁻³, relative), or along the same path up to it: the sample
//!   before agrees to 50 % and the one before that to 5 %. Near a
//!   finite-time blow-up the coarser run's error grows fast: a Bouc–Wen
//!   law with β < 0 on 1 kg at 1 and 4 steps per sample differs by 13 % one
//!   sample before and 1.5 % two samples before (on 20 kg: 3 % and
//!   3·10⁻⁴), while the time it passes the bound is the same at 1 to 1000
//!   steps per sample. Unstable steps, by contrast, have grown their own
//!   motion to within a few amplifications of 10⁶ there, which the finer
//!   steps do not share.
//!
//! Otherwise it stays `Diverged`. A stiff nonlinear spring (a power law of
//! enormous coefficient, whose stiffness at rest is zero) blows up from the
//! first step at both step lengths, but from rest and with states that
//! differ by orders of magnitude: it stays `Diverged`. The step choice
//! checks each divergence (the fewest steps may stray near a blow-up, and
//! the next pair then tells); a check costs at most the two runs up to the
//! divergence, and spares the step choice its runs at up to 1000 steps per
//! sample, which a smaller tolerance would have asked for in vain.
use super::integrator::integrator;
use super::run::{SampleView, Span};
use super::simulator::Simulator;
use super::workspace::Workspace;
use super::{SimulationError, MAX_SUBSTEPS};
use crate::model::Model;

/// The finer run's steps per sample, as a multiple of the diverged run's.
const FINER: usize = 4;

/// Relative agreement of the states where both runs pass the bound.
const SAME: f64 = 1e-3;

/// Relative agreement of the states one and two samples before.
const ON_PATH: [f64; 2] = [0.5, 0.05];

/// [`SimulationError::Unbounded`] when the divergence `e` (of a run of
/// `model` at `params`) is the model's response rather than the steps'
/// (module documentation); `None` for any other error, or when it may be
/// the steps'.
pub(super) fn unbounded(
    model: &Model,
    params: &[f64],
    e: &SimulationError,
) -> Option<SimulationError> {
    let &SimulationError::Diverged {
        time,
        fastest_hz,
        sample_rate,
        substeps,
        ..
    } = e
    else {
        return None;
    };
    let finer = (FINER * substeps).min(MAX_SUBSTEPS);
    let resolved = fastest_hz
        .is_none_or(|f| 2.0 * std::f64::consts::PI * f / (sample_rate * finer as f64) <= 1.0);
    if finer == substeps || !resolved {
        return None;
    }
    let coarse = path(model, params, substeps)?;
    let fine = path(model, params, finer)?;
    let same = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol * a.abs().max(b.abs());
    let finite = coarse.end.is_finite() && fine.end.is_finite();
    let at_divergence = finite && same(coarse.end, fine.end, SAME);
    let common = coarse.samples.len().min(fine.samples.len());
    let on_path = common >= 2
        && ON_PATH.iter().enumerate().all(|(back, &tol)| {
            let (a, b) = (
                coarse.samples[common - 1 - back],
                fine.samples[common - 1 - back],
            );
            a > 0.0 && same(a, b, tol)
        });
    let same_sample = ((coarse.time - fine.time) * sample_rate).abs() < 0.5;
    (same_sample && (at_divergence || on_path)).then_some(SimulationError::Unbounded {
        time,
        substeps,
        finer,
    })
}

/// A diverged run's path: the largest |state| at each sample before the
/// divergence, and where and at what size it passed the bound.
struct Path {
    samples: Vec<f64>,
    time: f64,
    end: f64,
}

/// The run of `model` at `params` with `substeps` steps per sample, if it
/// diverges; `None` if it does not (or fails otherwise).
fn path(model: &Model, params: &[f64], substeps: usize) -> Option<Path> {
    let sim = Simulator::with_integrator(model, integrator(substeps));
    let mut samples = Vec::new();
    let mut observer = |at: &SampleView<'_>| {
        samples.push(at.y.iter().fold(0.0_f64, |m, v| m.max(v.abs())));
    };
    let mut span = Span {
        observer: Some(&mut observer),
        ..Span::default()
    };
    let run = sim.run_span(
        params,
        &mut Workspace::default(),
        &mut sim.response_buffer(),
        &mut span,
    );
    match run {
        Err(SimulationError::Diverged {
            time, magnitude, ..
        }) => Some(Path {
            samples,
            time,
            end: magnitude,
        }),
        _ => None,
    }
}
