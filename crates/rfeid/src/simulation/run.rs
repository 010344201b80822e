//! Time integration with forward sensitivities.
//!
//! The state `y = [q; q̇]` is advanced by a fixed-step explicit Runge–Kutta
//! method, `substeps` equal steps per sample interval. With sensitivities,
//! the same stages also advance `Y = ∂y/∂x` through the forward sensitivity
//! equation `Ẏ = (∂F/∂y) Y + ∂F/∂x`. For an explicit method this is exactly
//! the derivative of the discrete solution, so the sensitivities agree with
//! central differences of [`Simulator::run`] to rounding, which is what a
//! Gauss–Newton or Levenberg–Marquardt step needs (eq. 26–28 use the same H₁).
//!
//! Steps are split where a power-law deformation crosses zero (the private
//! `stepper` module): there the force's second derivative jumps, and a step
//! across it would lose the method's order. With the splitting, the default,
//! DOP853 with one step per sample, agrees with an independent reference on
//! the knee–column benchmark to 2e-9 (relative RMS); without it, DOP853 needs
//! three steps per sample for 7e-7 and classical RK4 ten for 3e-7.
//!
//! The number of steps per sample is chosen from an error estimate for the
//! model's `tolerance` ([`super::steps`]) unless the model fixes `substeps`;
//! either way it is the same for every run of one [`Simulator`], so the
//! response is a smooth function of the parameters. A step count too small
//! for the model's fastest mode (ωh beyond DOP853's stability limit, about 3
//! for damped modes) ends in [`SimulationError::Diverged`], which names that
//! mode, never a hang.
use super::dim::{Dim, Dynamic, Fixed, Reach};
use super::equilibrium::static_equilibrium;
use super::integrator::Kernel;
use super::madd::{Fused, Madd, Separate};
use super::modal::fastest_mode_hz;
use super::response::Response;
use super::simulator::Simulator;
use super::stepper::Stepper;
use super::structure::Structure;
use super::system::System;
use super::workspace::Workspace;
use super::SimulationError;
use crate::model::SensorKind;

/// States beyond this magnitude (m, rad, m/s) count as a divergence.
const BLOW_UP: f64 = 1e6;

impl<'m> Simulator<'m> {
    /// The response and the sensitivities to `wrt` in one run, into `values`
    /// (sized for them).
    pub(crate) fn integrate_columns(
        &self,
        params: &[f64],
        wrt: &[usize],
        ws: &mut Workspace,
        out: &mut Response,
        values: &mut Vec<f64>,
    ) -> Result<(), SimulationError> {
        self.integrate(params, wrt, ws, out, Some(values), &mut Span::default())
    }

    /// The response and, when asked (`sens`), its sensitivities to `wrt`,
    /// over the samples of `span`, calling its observer at each.
    pub(super) fn integrate(
        &self,
        params: &[f64],
        wrt: &[usize],
        ws: &mut Workspace,
        out: &mut Response,
        sens: Option<&mut Vec<f64>>,
        span: &mut Span<'_>,
    ) -> Result<(), SimulationError> {
        let mut sys = self.system(params)?;
        sys.set_sparse(match self.kernel {
            Kernel::Auto => sys.prefers_sparse(),
            Kernel::Dense => false,
            Kernel::Sparse => true,
        });
        let from = span.start.as_ref().or(span.resume.as_ref().map(|(s, _)| s));
        if from.is_some_and(|s| sys.moves_past_reach(&s.y)) {
            sys.integrate_every_coordinate();
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            // SAFETY: the CPU supports AVX2 and FMA, checked just above.
            // Small models (up to four bodies) on the dense kernel get
            // kernels with n fixed (a generated 3-body model: 37 % fewer
            // instructions than with n at run time, callgrind). The
            // element-by-element kernel serves large models and is compiled
            // for n at run time only: with n fixed it saved 7 % of the
            // instructions on a 4-body model but cost a fifth of the
            // library's build time.
            return unsafe {
                match (sys.sparse, sys.n) {
                    (false, 6) if sys.active < 6 => {
                        self.integrate_avx2_fma::<Reach<6>>(sys, wrt, ws, out, sens, span)
                    }
                    (false, 6) => {
                        self.integrate_avx2_fma::<Fixed<6>>(sys, wrt, ws, out, sens, span)
                    }
                    (false, 12) => {
                        self.integrate_avx2_fma::<Fixed<12>>(sys, wrt, ws, out, sens, span)
                    }
                    (false, 18) => {
                        self.integrate_avx2_fma::<Fixed<18>>(sys, wrt, ws, out, sens, span)
                    }
                    (false, 24) => {
                        self.integrate_avx2_fma::<Fixed<24>>(sys, wrt, ws, out, sens, span)
                    }
                    _ => self.integrate_avx2_fma::<Dynamic>(sys, wrt, ws, out, sens, span),
                }
            };
        }
        self.integrate_generic::<Separate, Dynamic>(sys, wrt, ws, out, sens, span)
    }

    /// [`Self::integrate_generic`] compiled for AVX2 with fused multiply–add
    /// in the kernels (see `madd`), one function per size D. Results differ
    /// from the portable path's in the last bits, and are the same on every
    /// run of the same machine.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn integrate_avx2_fma<D: Dim>(
        &self,
        sys: System<'_>,
        wrt: &[usize],
        ws: &mut Workspace,
        out: &mut Response,
        sens: Option<&mut Vec<f64>>,
        span: &mut Span<'_>,
    ) -> Result<(), SimulationError> {
        self.integrate_generic::<Fused, D>(sys, wrt, ws, out, sens, span)
    }

    // long-fn: numerical kernel (the time-integration loop)
    /// The integration loop: steps the model `sys` (its kernel chosen)
    /// through the record, writing the response and, when asked, its
    /// sensitivities.
    #[inline(always)]
    fn integrate_generic<M: Madd, D: Dim>(
        &self,
        mut sys: System<'_>,
        wrt: &[usize],
        ws: &mut Workspace,
        out: &mut Response,
        mut sens: Option<&mut Vec<f64>>,
        span: &mut Span<'_>,
    ) -> Result<(), SimulationError> {
        let n = sys.n;
        let r = wrt.len();
        debug_assert!(D::SPARSE || !sys.sparse);
        let tab = &self.integrator.tableau;
        let sampling = self.model.sampling;
        let first = span.first_sample();
        let n_samples = span
            .samples
            .unwrap_or(usize::MAX)
            .min(sampling.n_samples().saturating_sub(first));
        let n_sensors = self.structure.sensors.len();
        out.n_samples = n_samples;
        out.n_sensors = n_sensors;
        out.values.resize(n_samples * n_sensors, 0.0);
        if n_samples == 0 {
            // A span past the record's end: nothing to record.
            return Ok(());
        }
        if r == 0 || span.start.is_some() {
            // Sensitivities to nothing (or from a state without them, not
            // `resume`): an empty matrix, and a plain run.
            sens = None;
        }
        let wrt = if sens.is_some() { wrt } else { &[] };
        // Under gravity, the run starts at rest in the static equilibrium
        // and integrates the deviation from it (`preload`): the state and
        // the sensitivities start at zero.
        if self.model.starts_at_equilibrium() {
            match span.equilibrium.as_deref().filter(|_| wrt.is_empty()) {
                Some(q) => sys.set_reference(q, Vec::new()),
                None => {
                    let eq = static_equilibrium(&sys, wrt)?;
                    sys.set_reference(&eq.q, eq.dq);
                    span.equilibrium = Some(eq.q);
                }
            }
            // About the equilibrium the weight no longer counts in the
            // reach: a caller's state may move past the shorter one.
            let from = span.start.as_ref().or(span.resume.as_ref().map(|(s, _)| s));
            if from.is_some_and(|s| sys.moves_past_reach(&s.y)) {
                sys.integrate_every_coordinate();
            }
        }
        let substeps = self.integrator.substeps;
        let h = 1.0 / (sampling.sample_rate * substeps as f64);
        let st = Stepper::<M, D>::new(&sys, tab, h, wrt, self.integrator.locate_crossings);
        let with_sens = sens.is_some();
        let (width, scratch) = match with_sens {
            true => (st.width(), st.scratch_len()),
            false => (0, 0),
        };
        ws.prepare(&sys, tab.stages(), (width, scratch), st.sine_terms());
        span.restore(ws);

        // Steps are counted from the run's first sample, and the record's
        // step index `step0 + step` gives the time: a run from rest has
        // `step0 = 0`, and the loop's counters do not depend on where a
        // block resumes (with them depending on it, the kernels no longer
        // knew that a run with sensitivities starts at sample 0, and a
        // 20-body model's runs with sensitivities took 20 % longer).
        let step0 = first * substeps;
        let total_steps = n_samples.saturating_sub(1) * substeps;
        span.notified = span.observer.is_some() || span.watch.is_some();
        let bps = &self.breakpoints;
        let margin = 1e-9 * h;
        let mut next_bp = 0;
        // One call site each for the first stage and the step (each is a
        // copy of the kernels): the loop visits the grid instants `step·h`
        // and, between them, the excitation's breakpoints, where a step is
        // split (fixed instants, so the response stays smooth in the
        // parameters).
        let (mut step, mut from, mut on_grid) = (0, 0.0, true);
        loop {
            let t = match on_grid {
                true => (step0 + step) as f64 * h,
                false => from,
            };
            st.first_stage(ws, t, with_sens);
            if on_grid {
                if step % substeps == 0 {
                    let k = step / substeps;
                    if ws.y.iter().any(|v| !(v.abs() < BLOW_UP)) {
                        return Err(self.diverged(&sys.params, t, substeps, ws));
                    }
                    record(
                        &self.structure,
                        &ws.y,
                        &ws.k[n..2 * n],
                        k,
                        n_samples,
                        &mut out.values,
                    );
                    if let Some(s) = sens.as_deref_mut() {
                        record_sens(
                            &self.structure,
                            &ws.sy,
                            &ws.ks[n * width..2 * n * width],
                            k,
                            n_samples,
                            (r, width),
                            s,
                        );
                    }
                    if span.notified {
                        span.notify(first + k, ws, out);
                    }
                }
                if step == total_steps {
                    break;
                }
                while next_bp < bps.len() && bps[next_bp] <= t + margin {
                    next_bp += 1;
                }
                from = t;
            }
            let t_end = (step0 + step + 1) as f64 * h;
            let split = next_bp < bps.len() && bps[next_bp] < t_end - margin;
            let dt = match (split, on_grid) {
                (true, _) => bps[next_bp] - from,
                (false, true) => h,
                (false, false) => t_end - from,
            };
            st.step(ws, from, dt, with_sens);
            if split {
                from = bps[next_bp];
                next_bp += 1;
                on_grid = false;
            } else {
                step += 1;
                on_grid = true;
            }
        }
        Ok(())
    }
}

/// A state of the motion at a sample: `y = [q; q̇]` (q measured from the
/// initial rest or equilibrium position) and the internal states z.
#[derive(Debug, Clone, PartialEq)]
pub struct SampleState {
    /// The sample's index in the record.
    pub sample: usize,
    /// `[q; q̇]`, 2n values.
    pub y: Vec<f64>,
    /// The Bouc–Wen internal states (empty without them).
    pub z: Vec<f64>,
}

/// A sample of a run as its watcher sees it.
#[derive(Debug, Clone, Copy)]
pub struct SampleView<'a> {
    /// The sample's index in the record.
    pub sample: usize,
    /// The coordinates the run starts from and measures q from: the static
    /// equilibrium under gravity; empty for rest at zero.
    pub origin: &'a [f64],
    /// `[q; q̇]`, 2n values.
    pub y: &'a [f64],
    /// The Bouc–Wen internal states (empty without them).
    pub z: &'a [f64],
    /// The run's sensor motions (before calibration), sensor by sensor,
    /// `stride` samples each from the run's first sample `first`.
    motion: &'a [f64],
    stride: usize,
    first: usize,
}

impl SampleView<'_> {
    /// Sensor `sensor`'s motion (before calibration) from the run's first
    /// sample up to this one.
    pub fn motion(&self, sensor: usize) -> &[f64] {
        let from = sensor * self.stride;
        &self.motion[from..from + self.sample - self.first + 1]
    }
}

/// What [`Simulator::run_watched`] asks after every few samples: given
/// the samples recorded and the readings so far, whether to stop.
pub type Watch<'a> = dyn FnMut(usize, &Response) -> bool + Send + 'a;

/// What part of the record a run covers, and who watches it. The default is
/// the whole record from rest, unobserved.
#[derive(Default)]
pub struct Span<'a> {
    /// Under gravity, the static equilibrium the run starts from (q
    /// measured from it): if given, it is used for a run without
    /// sensitivities instead of being solved for; otherwise the run leaves
    /// the one it solved here.
    pub equilibrium: Option<Vec<f64>>,
    /// Where the run starts: the state at a sample (then without
    /// sensitivities); `None` for rest (or the static equilibrium) at the
    /// first sample.
    pub start: Option<SampleState>,
    /// How many samples to record from the start (at most to the record's
    /// end); `None` for all of them.
    pub samples: Option<usize>,
    /// Called at each sample.
    pub observer: Option<&'a mut (dyn FnMut(&SampleView<'_>) + Send)>,
    /// Where a block of a run by blocks resumes (`blocks`): the state and
    /// the sensitivities to the same parameters at a sample; with `start`
    /// unset. (A run from `start` is plain.)
    pub(crate) resume: Option<(SampleState, SensitivityState)>,
    /// Asked after every [`Span::every`] samples short of the run's end,
    /// with the number of samples recorded and the run's readings so far
    /// (before calibration): `true` stops the run there
    /// ([`Simulator::run_watched`]).
    pub(crate) watch: Option<&'a mut Watch<'a>>,
    /// Samples between two calls of `watch`.
    pub(crate) every: usize,
    /// The samples recorded when `watch` is next asked (0: never).
    pub(crate) next_check: usize,
    /// Whether `watch` stopped the run.
    pub(crate) stopped: bool,
    /// Whether the loop calls `notify` at each sample (an observer or a
    /// watch; set by the run).
    pub(crate) notified: bool,
}

/// The sensitivities of the state at a sample, as a run with sensitivities
/// holds them (rows of its tangent's width), to continue that run from
/// there.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct SensitivityState {
    /// `∂[q; q̇]/∂x`, 2n rows.
    pub(crate) sy: Vec<f64>,
    /// `∂z/∂x` of the Bouc–Wen internal states (empty without them).
    pub(crate) z_sy: Vec<f64>,
}

impl Span<'_> {
    /// The record's index of the run's first sample.
    fn first_sample(&self) -> usize {
        match (&self.start, &self.resume) {
            (Some(s), _) | (None, Some((s, _))) => s.sample,
            (None, None) => 0,
        }
    }

    /// Puts the state at `start`, or the state and sensitivities at
    /// `resume`, into `ws` (outlined: the kernels only call it).
    #[inline(never)]
    fn restore(&self, ws: &mut Workspace) {
        let (state, sens) = match (&self.start, &self.resume) {
            (Some(s), _) => (s, None),
            (None, Some((s, sens))) => (s, Some(sens)),
            (None, None) => return,
        };
        ws.y.copy_from_slice(&state.y);
        ws.z.y.copy_from_slice(&state.z);
        if let Some(sens) = sens.filter(|_| !ws.sy.is_empty()) {
            ws.sy.copy_from_slice(&sens.sy);
            ws.z.sy.copy_from_slice(&sens.z_sy);
        }
    }

    /// Calls the observer with sample `sample` of the run in `ws`, and
    /// asks the watch whether to stop when it is due (not after the run's
    /// last sample, `out.n_samples`). To stop, the state is made NaN, so
    /// that the loop's own divergence check ends the run at the next
    /// sample, and `ws.stopped` tells it apart from a divergence: the
    /// kernels' loop is the same watched or not (an early return in it
    /// made the runs with sensitivities of a 2-body model 2.5 times
    /// slower). Outlined: the loop only tests `notified`.
    #[inline(never)]
    fn notify(&mut self, sample: usize, ws: &mut Workspace, out: &Response) {
        let samples = sample - self.first_sample() + 1;
        if samples == self.next_check && samples < out.n_samples {
            self.next_check += self.every.max(1);
            if let Some(watch) = self.watch.as_mut() {
                if watch(samples, out) {
                    self.stopped = true;
                    ws.stopped = true;
                    ws.y.fill(f64::NAN);
                }
            }
        }
        if self.observer.is_none() {
            return;
        }
        let first = self.first_sample();
        if let Some(observe) = self.observer.as_mut() {
            observe(&SampleView {
                sample,
                origin: self.equilibrium.as_deref().unwrap_or(&[]),
                y: &ws.y,
                z: &ws.z.y,
                motion: &out.values,
                stride: out.n_samples,
                first,
            });
        }
    }
}

impl Simulator<'_> {
    /// The error of a run whose state `y` left every bound at `time`,
    /// naming the model's fastest mode (outlined: the kernels' loop only
    /// calls it).
    #[cold]
    #[inline(never)]
    fn diverged(
        &self,
        params: &[f64],
        time: f64,
        substeps: usize,
        ws: &Workspace,
    ) -> SimulationError {
        if ws.stopped {
            // Not a divergence: a watch stopped the run (`Span::notify`).
            return SimulationError::Cancelled;
        }
        let y = &ws.y;
        let magnitude = match y.iter().all(|v| v.is_finite()) {
            true => y.iter().fold(0.0_f64, |m, v| m.max(v.abs())),
            false => f64::INFINITY,
        };
        SimulationError::Diverged {
            time,
            fastest_hz: fastest_mode_hz(self.model, params),
            sample_rate: self.model.sampling.sample_rate,
            substeps,
            fixed: self.model.sampling.substeps.is_some(),
            magnitude,
        }
    }
}

/// Writes the sensor readings of sample k. Displacements are measured from
/// the initial (equilibrium) position, which is where the state's
/// coordinates start.
#[inline(always)]
fn record(st: &Structure, y: &[f64], acc: &[f64], k: usize, n_samples: usize, out: &mut [f64]) {
    let n = st.n;
    for (c, (kind, h)) in st.sensors.iter().enumerate() {
        out[c * n_samples + k] = match kind {
            SensorKind::Displacement => h.dot(&y[..n]),
            SensorKind::Velocity => h.dot(&y[n..2 * n]),
            SensorKind::Acceleration => h.dot(acc),
        };
    }
}

/// Writes the sensitivities of sample k: r columns from rows `width` long.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn record_sens(
    st: &Structure,
    sy: &[f64],
    dacc: &[f64],
    k: usize,
    n_samples: usize,
    (r, width): (usize, usize),
    out: &mut [f64],
) {
    let n = st.n;
    for (c, (kind, h)) in st.sensors.iter().enumerate() {
        let dst = &mut out[(c * n_samples + k) * r..(c * n_samples + k + 1) * r];
        dst.fill(0.0);
        let coefs = h.blocks.iter().flat_map(|(o, c)| (*o..*o + 6).zip(c));
        for (i, &hi) in coefs.filter(|(_, c)| **c != 0.0) {
            let src = match kind {
                SensorKind::Displacement => &sy[i * width..i * width + r],
                SensorKind::Velocity => &sy[(n + i) * width..(n + i) * width + r],
                SensorKind::Acceleration => &dacc[i * width..i * width + r],
            };
            dst.iter_mut().zip(src).for_each(|(d, s)| *d += hi * s);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::model_file::load_model;
    use std::path::Path;

    /// The response and sensitivities of the knee–column example through the
    /// kernel variant `run`.
    fn knee_column_with(
        run: impl Fn(&Simulator<'_>, &[f64], &[usize], &mut Workspace, &mut Response, &mut Vec<f64>),
    ) -> (Vec<f64>, Vec<f64>) {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
        let model = load_model(&path).expect("the example loads");
        let sim = Simulator::new(&model);
        let (params, wrt) = (model.nominal(), model.identified());
        let (mut ws, mut out) = (Workspace::default(), sim.response_buffer());
        let mut sens = vec![0.0; out.values.len() * wrt.len()];
        run(&sim, &params, &wrt, &mut ws, &mut out, &mut sens);
        (out.values, sens)
    }

    /// The model's equations at `p` on the dense kernel.
    fn dense<'s>(sim: &'s Simulator<'_>, p: &[f64]) -> System<'s> {
        let mut sys = sim.system(p).expect("the example's parameters are valid");
        sys.set_sparse(false);
        sys
    }

    fn relative_rms_difference(a: &[f64], b: &[f64]) -> f64 {
        let diff: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
        let norm: f64 = a.iter().map(|x| x * x).sum();
        (diff / norm).sqrt()
    }

    #[test]
    fn fixed_size_kernels_equal_the_run_time_size_ones_bit_for_bit() {
        let fixed = knee_column_with(|sim, p, wrt, ws, out, s| {
            let span = &mut Span::default();
            sim.integrate_generic::<Separate, Fixed<12>>(dense(sim, p), wrt, ws, out, Some(s), span)
                .expect("runs")
        });
        let dynamic = knee_column_with(|sim, p, wrt, ws, out, s| {
            let span = &mut Span::default();
            sim.integrate_generic::<Separate, Dynamic>(dense(sim, p), wrt, ws, out, Some(s), span)
                .expect("runs")
        });
        assert!(fixed == dynamic);
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            // SAFETY: the CPU supports AVX2 and FMA, checked just above.
            let fused = |fixed: bool| {
                knee_column_with(|sim, p, wrt, ws, out, s| unsafe {
                    let span = &mut Span::default();
                    match fixed {
                        true => sim.integrate_avx2_fma::<Fixed<12>>(
                            dense(sim, p),
                            wrt,
                            ws,
                            out,
                            Some(s),
                            span,
                        ),
                        false => {
                            let sys = dense(sim, p);
                            sim.integrate_avx2_fma::<Dynamic>(sys, wrt, ws, out, Some(s), span)
                        }
                    }
                    .expect("runs")
                })
            };
            assert!(fused(true) == fused(false));
        }
    }

    #[test]
    fn fused_kernels_agree_with_the_portable_ones_to_rounding() {
        let portable = knee_column_with(|sim, p, wrt, ws, out, s| {
            let span = &mut Span::default();
            sim.integrate_generic::<Separate, Dynamic>(dense(sim, p), wrt, ws, out, Some(s), span)
                .expect("runs")
        });
        // Whatever the dispatch picks on this machine: AVX2 + FMA with n
        // fixed where the CPU has them (otherwise the portable path itself,
        // and the comparison is trivially met).
        let dispatched = knee_column_with(|sim, p, wrt, ws, out, s| {
            sim.integrate(p, wrt, ws, out, Some(s), &mut Span::default())
                .expect("runs")
        });
        let response = relative_rms_difference(&portable.0, &dispatched.0);
        let sensitivities = relative_rms_difference(&portable.1, &dispatched.1);
        // Measured: 1.0e-14 (response) and 1.3e-14 (sensitivities), the
        // rounding differences of one versus two roundings per multiply–add.
        assert!(response < 1e-10, "response differs by {response:e}");
        assert!(
            sensitivities < 1e-10,
            "sensitivities differ by {sensitivities:e}"
        );
    }
}

#[cfg(test)]
mod reach_tests {
    use super::super::tangent::Tangent;
    use super::*;
    use crate::io::model_file::parse_model;
    use std::path::Path;

    /// One body restrained by a linear and a cubic spring along x and
    /// driven along x, plus `extra` components on its own element.
    fn one_body(extra: &str) -> crate::model::Model {
        let text = one_body_text(extra);
        parse_model(&text, Path::new("one_body.toml")).unwrap_or_else(|e| panic!("{e}"))
    }

    /// The text of [`one_body`].
    fn one_body_text(extra: &str) -> String {
        format!(
            "[simulation]\nduration = 2.0\nsample_rate = 1000.0\nsubsteps = 1\n\n\
             [[body]]\nname = \"mass\"\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\ncom = [0, 0, 0]\n\n\
             [[element]]\nname = \"linear\"\nbody = \"mass\"\nto = \"ground\"\nat = [0, 0, 0]\n\
             ux = {{ k = \"k1\", c = 40.0 }}\n{extra}\n\
             [[element]]\nname = \"cubic\"\nbody = \"mass\"\nto = \"ground\"\nat = [0, 0, 0]\n\
             ux = {{ law = \"power\", a = \"k3\", m = 3.0 }}\n\n\
             [[excitation]]\nname = \"f\"\nbody = \"mass\"\nat = [0, 0, 0]\ndirection = [1, 0, 0]\n\
             signal = {{ type = \"chirp\", amplitude = 20.0, f0 = 5.0, f1 = 150.0 }}\n\n\
             [[sensor]]\nname = \"x\"\nbody = \"mass\"\nat = [0, 0, 0]\ndirection = [1, 0, 0]\n\
             quantity = \"acceleration\"\n\n\
             [[sensor]]\nname = \"y\"\nbody = \"mass\"\nat = [0, 0, 0]\ndirection = [0, 1, 0]\n\
             quantity = \"displacement\"\n\n\
             [[parameter]]\nname = \"k1\"\nvalue = 4e5\nmin = 1e5\nmax = 1e6\n\n\
             [[parameter]]\nname = \"k3\"\nvalue = 5e9\nmin = 1e9\nmax = 1e10\n"
        )
    }

    /// The response and sensitivities of `m`, and its system's reach.
    fn run(m: &crate::model::Model) -> (usize, Vec<f64>, Vec<f64>) {
        let sim = Simulator::new(m);
        let (p, wrt) = (m.nominal(), m.identified());
        let mut sys = sim.system(&p).unwrap();
        sys.set_sparse(false);
        let (mut ws, mut out) = (Workspace::default(), sim.response_buffer());
        let mut sens = vec![0.0; out.values.len() * wrt.len()];
        sim.integrate(
            &p,
            &wrt,
            &mut ws,
            &mut out,
            Some(&mut sens),
            &mut Span::default(),
        )
        .unwrap();
        (sys.active, out.values, sens)
    }

    /// A body that moves along x alone integrates its first coordinate only
    /// (`System::active` 1, the `Reach` kernel), and gives the same
    /// response, bit for bit, as the same body with its other five
    /// coordinates held by springs that nothing deflects (all six
    /// integrated, the `Fixed` kernel); so do its sensitivities.
    #[test]
    fn a_body_moving_along_x_alone_integrates_x_alone_with_the_same_result() {
        let (reach, alone, sens_alone) = run(&one_body(""));
        let held = "uy = { k = 1e5 }\nuz = { k = 1e5 }\nrx = { k = 1e3 }\n\
                    ry = { k = 1e3 }\nrz = { k = 1e3 }\n";
        let (all, with_springs, sens_springs) = run(&one_body(held));
        assert_eq!((reach, all), (1, 6));
        assert!(alone.iter().any(|v| *v != 0.0));
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&alone), bits(&with_springs));
        assert!(sens_alone.iter().any(|v| *v != 0.0));
        assert_eq!(bits(&sens_alone), bits(&sens_springs));
    }

    /// The sensitivities on the `Reach` kernel, which computes and combines
    /// only the rows the motion and the parameters reach
    /// (`Tangent::reach`), equal bit for bit those of the `Fixed` kernel,
    /// which integrates all six coordinates, on the same system: with the
    /// mass, the load's amplitude and a damping as parameters (reach 2 of
    /// 6), and with a spring at zero stiffness that couples x to rz (the
    /// reach 1, but its stiffness's sensitivity reaches rz, so all 6). The
    /// portable kernels and, where the CPU has them, the fused ones; and a
    /// workspace that ran the wider reach first gives the same too.
    #[test]
    fn the_reach_kernels_sensitivities_equal_the_whole_kernels_bit_for_bit() {
        let params = "[[parameter]]\nname = \"m\"\nvalue = 1.5\nmin = 1.0\nmax = 2.0\n\n\
                      [[parameter]]\nname = \"amp\"\nvalue = 20.0\nmin = 10.0\nmax = 30.0\n\n\
                      [[parameter]]\nname = \"c1\"\nvalue = 40.0\nmin = 10.0\nmax = 80.0\n\n";
        let coupling = "[[element]]\nname = \"arm\"\nbody = \"mass\"\nto = \"ground\"\n\
                        at = [0, 0.1, 0]\nux = { k = \"kc\" }\n\n\
                        [[parameter]]\nname = \"kc\"\nvalue = 0.0\nmin = 0.0\nmax = 1e5\n\n";
        let arm = "[[sensor]]\nname = \"arm\"\nbody = \"mass\"\nat = [0, 0.2, 0]\n\
                   direction = [1, 0, 0]\nquantity = \"displacement\"\n\n";
        let model = |extra: &str| {
            let text = one_body_text(&format!("{extra}{arm}"))
                .replace("mass = 1.0", "mass = \"m\"")
                .replace("amplitude = 20.0", "amplitude = \"amp\"")
                .replace("c = 40.0", "c = \"c1\"");
            parse_model(&text, Path::new("one_body.toml")).unwrap_or_else(|e| panic!("{e}"))
        };
        let differ = |a: &[f64], b: &[f64]| {
            (a.iter().zip(b))
                .filter(|(x, y)| x.to_bits() != y.to_bits())
                .count()
        };
        let coupled = model(&format!("{params}{coupling}"));
        for (m, reach) in [(model(params), 2), (coupled.clone(), 6)] {
            let wrt = m.identified();
            let whole = reach_run(&m, &wrt, Kernels::Fixed, &mut Workspace::default());
            let reached = reach_run(&m, &wrt, Kernels::Reach, &mut Workspace::default());
            assert_eq!(reached.2, reach);
            assert_eq!(differ(&reached.0, &whole.0), 0, "responses, reach {reach}");
            assert!(reached.1.iter().all(|v| v.is_finite()));
            assert_eq!(
                differ(&reached.1, &whole.1),
                0,
                "sensitivities, reach {reach}"
            );
            // Every parameter moves the response; kc through x and, with
            // the spring at zero, through rz, which the sensor at the arm's
            // end reads.
            let r = wrt.len();
            for j in 0..r {
                assert!(
                    reached.1.iter().skip(j).step_by(r).any(|v| *v != 0.0),
                    "column {j}"
                );
            }
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma")
            {
                let whole = reach_run(&m, &wrt, Kernels::FusedFixed, &mut Workspace::default());
                let reached = reach_run(&m, &wrt, Kernels::FusedReach, &mut Workspace::default());
                assert_eq!(differ(&reached.1, &whole.1), 0, "fused, reach {reach}");
            }
        }
        // The coupled model's m, amp and c1 alone reach 2 rows; after a run
        // that reached all 6 in the same workspace, the same as in a new one.
        let wrt = &coupled.identified()[..3];
        let mut ws = Workspace::default();
        let wide = reach_run(&coupled, &coupled.identified(), Kernels::Reach, &mut ws);
        let narrow = reach_run(&coupled, wrt, Kernels::Reach, &mut ws);
        let fresh = reach_run(&coupled, wrt, Kernels::Reach, &mut Workspace::default());
        assert_eq!((wide.2, narrow.2), (6, 2));
        assert_eq!(differ(&narrow.1, &fresh.1), 0, "a reused workspace");
    }

    /// The kernels [`reach_run`] can take.
    #[derive(Clone, Copy)]
    enum Kernels {
        Fixed,
        Reach,
        FusedFixed,
        FusedReach,
    }

    /// The response and the sensitivities to `wrt` of the one-body model
    /// `m` at its nominal values on the dense kernel `kernel`, in `ws`, and
    /// the tangent's reach.
    fn reach_run(
        m: &crate::model::Model,
        wrt: &[usize],
        kernel: Kernels,
        ws: &mut Workspace,
    ) -> (Vec<f64>, Vec<f64>, usize) {
        let sim = Simulator::new(m);
        let p = m.nominal();
        let mut sys = sim.system(&p).unwrap();
        sys.set_sparse(false);
        assert_eq!(sys.active, 1);
        let reach = Tangent::new(&sys, wrt).reach(&sys);
        let mut out = sim.response_buffer();
        let mut sens = vec![0.0; out.values.len() * wrt.len()];
        let (s, span) = (Some(&mut sens), &mut Span::default());
        match kernel {
            Kernels::Fixed => {
                sim.integrate_generic::<Separate, Fixed<6>>(sys, wrt, ws, &mut out, s, span)
            }
            Kernels::Reach => {
                sim.integrate_generic::<Separate, Reach<6>>(sys, wrt, ws, &mut out, s, span)
            }
            // SAFETY (both): the caller checked that the CPU has AVX2 and FMA.
            #[cfg(target_arch = "x86_64")]
            Kernels::FusedFixed => unsafe {
                sim.integrate_avx2_fma::<Fixed<6>>(sys, wrt, ws, &mut out, s, span)
            },
            #[cfg(target_arch = "x86_64")]
            Kernels::FusedReach => unsafe {
                sim.integrate_avx2_fma::<Reach<6>>(sys, wrt, ws, &mut out, s, span)
            },
            #[cfg(not(target_arch = "x86_64"))]
            _ => unreachable!("fused kernels only on x86_64"),
        }
        .unwrap();
        (out.values, sens, reach)
    }

    /// A run from a caller's state that moves past the reach (here the body
    /// drifting along y at 1 m/s, which nothing restrains) integrates every
    /// coordinate: y advances as q̇ t.
    #[test]
    fn a_start_that_moves_past_the_reach_integrates_every_coordinate() {
        let out = drifting(&one_body(""), 1);
        let drift = out.sensor(1)[200];
        assert!((drift - 0.2).abs() < 1e-12, "q_y after 0.2 s: {drift}");
    }

    /// The run of `m` from sample 100 to 300 from rest but for a velocity
    /// of 1 m/s along `coordinate`.
    fn drifting(m: &crate::model::Model, coordinate: usize) -> Response {
        let sim = Simulator::new(m);
        let mut y = vec![0.0; 12];
        y[6 + coordinate] = 1.0;
        let mut span = Span {
            start: Some(SampleState {
                sample: 100,
                y,
                z: Vec::new(),
            }),
            samples: Some(201),
            ..Span::default()
        };
        let mut out = Response::zeros(0, 0);
        sim.run_span(&m.nominal(), &mut Workspace::default(), &mut out, &mut span)
            .unwrap();
        out
    }

    /// The same under a weight whose component along the drift is within
    /// the equilibrium's tolerance (1e-12 of g along z, which nothing
    /// restrains): that component makes z part of the reach at first, but
    /// not once the run moves about the static equilibrium, whose reference
    /// takes the weight away. The start is checked again then, and z still
    /// advances as q̇ t.
    #[test]
    fn a_start_past_the_reach_about_the_equilibrium_integrates_every_coordinate() {
        let z = "[[sensor]]\nname = \"z\"\nbody = \"mass\"\nat = [0, 0, 0]\n\
                 direction = [0, 0, 1]\nquantity = \"displacement\"\n\n";
        let text = format!("gravity = [-9.81, 0.0, 1e-12]\n{}", one_body_text(z));
        let m = parse_model(&text, Path::new("one_body.toml")).unwrap_or_else(|e| panic!("{e}"));
        let out = drifting(&m, 2);
        // The sensor z comes first: it is added with the first element.
        let drift = out.sensor(0)[200];
        assert!((drift - 0.2).abs() < 1e-9, "q_z after 0.2 s: {drift}");
    }
}
