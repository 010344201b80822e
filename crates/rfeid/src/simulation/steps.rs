//! The number of integrator steps per sample, chosen from an error estimate.
//!
//! The simulator takes a fixed number s of equal steps per sample interval
//! (see [`super::run`]), so that the computed response is a smooth function
//! of the parameters. Which s is enough depends on the model's fastest modes
//! relative to the sample rate, so it is chosen here, by step doubling: the
//! response with s steps per sample is compared with the one with 2s; for a
//! method of order p the difference estimates the error of the coarser one
//! (the finer one's is 2^p times smaller). The error measure is the relative
//! RMS difference of each sensor's signal, the largest over the sensors,
//! which is what the benchmark's accuracy figures quote.
//!
//! If s steps miss the tolerance, the next s is predicted from the order
//! (`s (e/tol)^(1/p)`, with a margin) and checked again, so a choice costs
//! a few simulations: two (at 1 and 2 steps) when one step is enough, as on
//! the knee–column benchmark at 10 kHz. A run that diverges counts as
//! missing the tolerance, and the next s is at least four times larger and
//! large enough that the fastest linearised mode has ωh ≤ 1. The runs at
//! s and 2s are independent and run at the same time where a second thread
//! is free; the run that meets the tolerance is kept
//! ([`Simulator::choose_keeping`]), so a caller who wants the response there
//! does not simulate it again.
//!
//! During an identification the choice is made once and held fixed (the
//! criterion stays smooth), and checked again at the estimate
//! ([`crate::identification::identify`]).
use super::response::Response;
use super::simulator::Simulator;
use super::step_choice::StepChoice;
use super::workspace::Workspace;
use super::{SimulationError, DEFAULT_TABLEAU, MAX_SUBSTEPS};
use crate::model::Model;
use std::time::{Duration, Instant};

pub use super::integrator::integrator;
pub use super::modal::fastest_mode_hz;

/// The text of the `tolerance` range check.
pub fn tolerance_range_text() -> String {
    let r = super::TOLERANCE_RANGE;
    format!(
        "must be a relative error from {:e} to {:e}",
        r.start(),
        r.end()
    )
}

/// Relative RMS difference of `a` from `b`, the largest over the sensors.
///
/// Each sensor's RMS difference is divided by its RMS, but by no less than
/// 1e-3 of the largest RMS among the sensors of the same kind (a sensor that
/// by symmetry reads almost nothing would otherwise measure rounding noise
/// against rounding noise).
pub fn relative_difference(model: &Model, a: &Response, b: &Response) -> f64 {
    let rms = |x: &[f64]| (x.iter().map(|v| v * v).sum::<f64>() / x.len().max(1) as f64).sqrt();
    let scale: Vec<f64> = (0..b.n_sensors).map(|c| rms(b.sensor(c))).collect();
    let mut worst: f64 = 0.0;
    for c in 0..b.n_sensors {
        let kind = model.sensors[c].kind;
        let floor = (0..b.n_sensors)
            .filter(|&d| model.sensors[d].kind == kind)
            .map(|d| scale[d])
            .fold(0.0, f64::max)
            * 1e-3;
        let diff: Vec<f64> = a
            .sensor(c)
            .iter()
            .zip(b.sensor(c))
            .map(|(x, y)| x - y)
            .collect();
        let d = rms(&diff);
        if d == 0.0 {
            continue;
        }
        let e = d / scale[c].max(floor);
        // NaN (a non-finite signal) counts as infinitely wrong.
        worst = if e.is_nan() {
            f64::INFINITY
        } else {
            worst.max(e)
        };
    }
    worst
}

/// Runs the model at `params` with `substeps` steps per sample, and times
/// the run.
fn timed_run(
    model: &Model,
    params: &[f64],
    substeps: usize,
    ws: &mut Workspace,
) -> Result<(Response, Duration), SimulationError> {
    let sim = Simulator::with_integrator(model, integrator(substeps));
    let mut out = sim.response_buffer();
    let start = Instant::now();
    sim.run(params, ws, &mut out)?;
    Ok((out, start.elapsed()))
}

/// The runs with `substeps` and twice as many steps per sample, at the same
/// time where a second thread is free (each is independent of the other and
/// of the threads, so the results are the same either way).
fn run_pair(
    model: &Model,
    params: &[f64],
    substeps: usize,
) -> (
    Result<ChosenRun, SimulationError>,
    Result<ChosenRun, SimulationError>,
) {
    rayon::join(
        || timed_run(model, params, substeps, &mut Workspace::default()),
        || timed_run(model, params, 2 * substeps, &mut Workspace::default()),
    )
}

/// A response computed on the way to a step choice: the run at the chosen
/// steps and the parameters of the choice, and its wall time.
pub type ChosenRun = (Response, Duration);

/// The estimated relative RMS error of the response at `params` with
/// `substeps` steps per sample: its difference from the response with twice
/// as many.
pub fn estimate_error(
    model: &Model,
    params: &[f64],
    substeps: usize,
) -> Result<f64, SimulationError> {
    Ok(estimate_error_keeping(model, params, substeps)?.0)
}

/// [`estimate_error`], with the run at `substeps`.
fn estimate_error_keeping(
    model: &Model,
    params: &[f64],
    substeps: usize,
) -> Result<(f64, ChosenRun), SimulationError> {
    let (coarse, fine) = run_pair(model, params, substeps);
    let (coarse, fine) = (coarse?, fine?);
    Ok((relative_difference(model, &coarse.0, &fine.0), coarse))
}

/// The fewest steps per sample, from `from` on, whose estimated error at
/// `params` is within `tolerance` (see the module documentation).
///
/// Fails with [`SimulationError::Inaccurate`] if more than
/// [`MAX_SUBSTEPS`] would be needed, or with the simulation's own error if
/// the point cannot be simulated at all.
pub fn choose_steps(
    model: &Model,
    params: &[f64],
    tolerance: f64,
    from: usize,
) -> Result<StepChoice, SimulationError> {
    Ok(choose_steps_keeping(model, params, tolerance, from)?.0)
}

/// [`choose_steps`], with the run at the chosen steps.
fn choose_steps_keeping(
    model: &Model,
    params: &[f64],
    tolerance: f64,
    from: usize,
) -> Result<(StepChoice, ChosenRun), SimulationError> {
    let order = DEFAULT_TABLEAU.order as f64;
    let mut s = from.clamp(1, MAX_SUBSTEPS);
    // A response already computed, with its step count.
    let mut known: Option<(usize, ChosenRun)> = None;
    let mut runs = 0;
    loop {
        let (coarse, fine) = match known.take() {
            Some((k, r)) if k == s => {
                runs += 1;
                let fine = timed_run(model, params, 2 * s, &mut Workspace::default());
                (Ok(r), fine)
            }
            _ => {
                runs += 2;
                run_pair(model, params, s)
            }
        };
        let outcome = match (coarse, fine) {
            (Ok(c), Ok(f)) => {
                let e = relative_difference(model, &c.0, &f.0);
                if e <= tolerance {
                    let choice = StepChoice {
                        substeps: s,
                        automatic: true,
                        tolerance,
                        estimated_error: Some(e),
                        runs,
                    };
                    return Ok((choice, c));
                }
                known = Some((2 * s, f));
                Ok(e)
            }
            (Err(e), _) | (_, Err(e)) => Err(e),
        };
        let next = match &outcome {
            Ok(e) if e.is_finite() => {
                let predicted = s as f64 * (e / tolerance).powf(1.0 / order) * 1.1;
                (predicted.ceil() as usize).max(s + 1)
            }
            Ok(_) | Err(SimulationError::Diverged { .. }) => {
                // Unstable steps: at least ωh ≤ 1 for the fastest mode.
                let stable = fastest_mode_hz(model, params)
                    .map(|f| (2.0 * std::f64::consts::PI * f / model.sampling.sample_rate).ceil())
                    .unwrap_or(0.0);
                (4 * s).max(stable.min(MAX_SUBSTEPS as f64) as usize)
            }
            Err(e) => return Err(e.clone()),
        };
        if s == MAX_SUBSTEPS {
            return Err(match outcome {
                Ok(estimate) => SimulationError::Inaccurate {
                    substeps: s,
                    estimate,
                    tolerance,
                    fastest_hz: fastest_mode_hz(model, params),
                    sample_rate: model.sampling.sample_rate,
                },
                Err(e) => e,
            });
        }
        s = next.min(MAX_SUBSTEPS);
    }
}

impl<'m> Simulator<'m> {
    /// A simulator with the model's settings and the default method: the
    /// model's `substeps` if it fixes them, otherwise steps chosen for its
    /// `tolerance` at the nominal parameter values ([`Simulator::choose`]).
    /// If no step count meets the tolerance there (or the nominal point
    /// cannot be simulated at all), it takes [`MAX_SUBSTEPS`] steps and
    /// [`Simulator::steps`] has no error estimate; use
    /// [`Simulator::choose`] to have that as an error instead.
    pub fn new(model: &'m Model) -> Self {
        match model.sampling.substeps {
            Some(s) => Self::with_integrator(model, super::steps::integrator(s)),
            None => Self::choose(model, &model.nominal()).unwrap_or_else(|_| {
                let mut sim = Self::with_integrator(model, super::steps::integrator(MAX_SUBSTEPS));
                sim.steps.automatic = true;
                sim
            }),
        }
    }

    /// A simulator with the model's settings, its steps chosen (or, if the
    /// model fixes `substeps`, their error estimated) at `params`
    /// ([`super::steps::choose_steps`]).
    pub fn choose(model: &'m Model, params: &[f64]) -> Result<Self, SimulationError> {
        Ok(Self::choose_keeping(model, params)?.0)
    }

    /// [`Simulator::choose`], with the response at `params` that the choice
    /// computed on its way (the same, bit for bit, as
    /// [`Simulator::run`] of the returned simulator at `params`) and that
    /// run's wall time: a caller who wants that response need not simulate
    /// it again.
    pub fn choose_keeping(
        model: &'m Model,
        params: &[f64],
    ) -> Result<(Self, ChosenRun), SimulationError> {
        let tolerance = model.sampling.tolerance;
        let (steps, chosen) = match model.sampling.substeps {
            Some(s) => {
                let (e, chosen) = estimate_error_keeping(model, params, s.max(1))?;
                let choice = StepChoice {
                    substeps: s.max(1),
                    automatic: false,
                    tolerance,
                    estimated_error: Some(e),
                    runs: 2,
                };
                (choice, chosen)
            }
            None => choose_steps_keeping(model, params, tolerance, 1)?,
        };
        let mut sim = Self::with_integrator(model, super::steps::integrator(steps.substeps));
        sim.steps = steps;
        Ok((sim, chosen))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulation::test_models;

    /// Runs the model at `params` with `substeps` steps per sample.
    fn run(
        model: &Model,
        params: &[f64],
        substeps: usize,
        ws: &mut Workspace,
    ) -> Result<Response, SimulationError> {
        Ok(timed_run(model, params, substeps, ws)?.0)
    }

    /// The shared oscillator of natural frequency `f` Hz, driven at 30 Hz.
    fn oscillator(f: f64, rate: f64) -> Model {
        test_models::oscillator(f, 30.0, rate)
    }

    #[test]
    fn a_slow_mode_needs_one_step_and_a_fast_one_more() {
        let slow = oscillator(50.0, 1000.0);
        let c = choose_steps(&slow, &slow.nominal(), 1e-8, 1).unwrap();
        assert_eq!(c.substeps, 1, "{c:?}");
        let fast = oscillator(400.0, 1000.0);
        let c = choose_steps(&fast, &fast.nominal(), 1e-8, 1).unwrap();
        assert!(c.substeps > 1, "{c:?}");
        assert!(c.estimated_error.unwrap() <= 1e-8, "{c:?}");
    }

    #[test]
    fn the_kept_response_is_the_chosen_simulators_run_bit_for_bit() {
        // Chosen (a 400 Hz mode at 1 kHz needs more than one step per
        // sample) and fixed by the model.
        let chosen = oscillator(400.0, 1000.0);
        let mut fixed = chosen.clone();
        fixed.sampling.substeps = Some(5);
        for m in [chosen, fixed] {
            let p: Vec<f64> = m.nominal().iter().map(|v| v * 1.1).collect();
            let (sim, (kept, _)) = Simulator::choose_keeping(&m, &p).unwrap();
            let mut again = sim.response_buffer();
            sim.run(&p, &mut Workspace::default(), &mut again).unwrap();
            assert!(kept.values == again.values, "{:?}", sim.steps());
            assert_eq!(kept.n_samples, again.n_samples);
        }
    }

    #[test]
    fn the_chosen_steps_meet_the_tolerance_in_truth() {
        // The error against a much finer run, not just the estimate.
        let m = oscillator(400.0, 1000.0);
        let p = m.nominal();
        for tol in [1e-5, 1e-8] {
            let c = choose_steps(&m, &p, tol, 1).unwrap();
            let mut ws = Workspace::default();
            let chosen = run(&m, &p, c.substeps, &mut ws).unwrap();
            let fine = run(&m, &p, 8 * c.substeps, &mut ws).unwrap();
            let truth = relative_difference(&m, &chosen, &fine);
            assert!(
                truth <= tol,
                "tolerance {tol:e}: error {truth:e} with {c:?}"
            );
        }
    }

    #[test]
    fn unstable_steps_are_left_behind() {
        // ωh ≈ 19 at one step per sample: DOP853 diverges there.
        let m = oscillator(3000.0, 1000.0);
        let c = choose_steps(&m, &m.nominal(), 1e-8, 1).unwrap();
        assert!(c.substeps >= 19, "{c:?}");
    }

    #[test]
    fn beyond_the_step_limit_is_an_error_naming_the_fastest_mode() {
        // ωh ≈ 6e4 at one step per sample: even 1000 steps are unstable.
        let m = oscillator(1e7, 1000.0);
        let e = choose_steps(&m, &m.nominal(), 1e-8, 1).unwrap_err();
        assert!(matches!(e, SimulationError::Diverged { .. }), "{e}");
        assert!(e.to_string().contains("fastest mode"), "{e}");
        // The steps were chosen, not fixed: the advice is about `tolerance`.
        let text = e.to_string();
        assert!(text.contains("smaller `tolerance`"), "{e}");
        assert!(!text.contains("leave `substeps` unset"), "{e}");
    }
}
