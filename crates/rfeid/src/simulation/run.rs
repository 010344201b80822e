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
use super::columns::group_size;
use super::dim::{Dim, Dynamic, Fixed};
use super::equilibrium::static_equilibrium;
use super::madd::{Fused, Madd, Separate};
use super::stepper::Stepper;
pub use super::stepper::Workspace;
use super::steps::{choose_steps, estimate_error, fastest_mode_hz, StepChoice};
use super::structure::{Row, Structure};
use super::system::System;
use super::tableau::Tableau;
use super::{SimulationError, MAX_SUBSTEPS};
use crate::model::{Model, SensorKind};

/// States beyond this magnitude (m, rad, m/s) count as a divergence.
const BLOW_UP: f64 = 1e6;

/// Simulated sensor signals: `values[c * n_samples + k]` is sensor c at sample k.
#[derive(Debug, Clone, PartialEq)]
pub struct Response {
    /// Number of samples N.
    pub n_samples: usize,
    /// Number of sensors.
    pub n_sensors: usize,
    /// Sensor-major signals.
    pub values: Vec<f64>,
}

impl Response {
    /// An all-zero response of the given shape.
    pub fn zeros(n_sensors: usize, n_samples: usize) -> Self {
        Response {
            n_samples,
            n_sensors,
            values: vec![0.0; n_sensors * n_samples],
        }
    }

    /// The signal of sensor c.
    pub fn sensor(&self, c: usize) -> &[f64] {
        &self.values[c * self.n_samples..(c + 1) * self.n_samples]
    }
}

/// Sensitivities of every sensor sample to the parameters `wrt`:
/// `values[(c * n_samples + k) * wrt.len() + j] = ∂y_ck / ∂x_j` (eq. 27–28).
#[derive(Debug, Clone, PartialEq)]
pub struct Sensitivities {
    /// Parameter indices (into [`Model::parameters`]) of the columns.
    pub wrt: Vec<usize>,
    /// Row-major (observation × parameter).
    pub values: Vec<f64>,
}

/// Integrator settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Integrator {
    /// The Runge–Kutta method.
    pub tableau: Tableau,
    /// Steps per sample interval (≥ 1).
    pub substeps: usize,
    /// Split steps at the zero crossings of power-law deformations, where
    /// the force's second derivative jumps, so the method keeps its order.
    pub locate_crossings: bool,
}

/// Which kernel evaluates the equations of motion and their sensitivities.
/// Both give the same results to rounding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kernel {
    /// The one with fewer operations for the model's size (the default):
    /// dense for a few bodies, element by element for many.
    #[default]
    Auto,
    /// Dense matrices in register panels (`system`), fastest for a few bodies.
    Dense,
    /// Element by element (`sparse`): cost grows with the number of
    /// components, not with n².
    Sparse,
}

/// Simulates one model at any parameter point.
#[derive(Debug, Clone)]
pub struct Simulator<'m> {
    model: &'m Model,
    kernel: Kernel,
    structure: Structure,
    integrator: Integrator,
    steps: StepChoice,
    /// Instants where the excitation has a kink or a jump, sorted, within
    /// the record: steps are split there.
    breakpoints: Vec<f64>,
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
        let tolerance = model.sampling.tolerance;
        let steps = match model.sampling.substeps {
            Some(s) => StepChoice {
                substeps: s.max(1),
                automatic: false,
                tolerance,
                estimated_error: Some(estimate_error(model, params, s.max(1))?),
                runs: 2,
            },
            None => choose_steps(model, params, tolerance, 1)?,
        };
        let mut sim = Self::with_integrator(model, super::steps::integrator(steps.substeps));
        sim.steps = steps;
        Ok(sim)
    }

    /// A simulator with explicit integrator settings (fixed steps, no
    /// error estimate).
    pub fn with_integrator(model: &'m Model, integrator: Integrator) -> Self {
        let integrator = Integrator {
            substeps: integrator.substeps.max(1),
            ..integrator
        };
        let end = model
            .sampling
            .time(model.sampling.n_samples().saturating_sub(1));
        let mut breakpoints: Vec<f64> = model
            .excitations
            .iter()
            .flat_map(|e| &e.signal.terms)
            .flat_map(|term| term.shape.breakpoints())
            .filter(|t| *t > 0.0 && *t < end)
            .collect();
        breakpoints.sort_by(f64::total_cmp);
        breakpoints.dedup();
        Simulator {
            model,
            kernel: Kernel::Auto,
            structure: Structure::new(model),
            breakpoints,
            integrator,
            steps: StepChoice {
                substeps: integrator.substeps,
                automatic: false,
                tolerance: model.sampling.tolerance,
                estimated_error: None,
                runs: 0,
            },
        }
    }

    /// Uses `kernel` from now on (see [`Kernel`]).
    pub fn set_kernel(&mut self, kernel: Kernel) {
        self.kernel = kernel;
    }

    /// The kernel setting.
    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// How the steps per sample were chosen, and their estimated error.
    pub fn steps(&self) -> StepChoice {
        self.steps
    }

    /// Takes `steps.substeps` steps per sample from now on, recording `steps`.
    pub fn set_steps(&mut self, steps: StepChoice) {
        self.integrator.substeps = steps.substeps.max(1);
        self.steps = StepChoice {
            substeps: self.integrator.substeps,
            ..steps
        };
    }

    /// The model.
    pub fn model(&self) -> &'m Model {
        self.model
    }

    /// The assembled structure (B, excitation and sensor maps).
    pub fn structure(&self) -> &Structure {
        &self.structure
    }

    /// The integrator settings.
    pub fn integrator(&self) -> Integrator {
        self.integrator
    }

    /// The equations of motion at parameter values `params`.
    pub fn system(&self, params: &[f64]) -> Result<System<'_>, SimulationError> {
        System::new(self.model, &self.structure, params)
    }

    /// Simulates at `params` (all parameters, SI) into `out`.
    pub fn run(
        &self,
        params: &[f64],
        ws: &mut Workspace,
        out: &mut Response,
    ) -> Result<(), SimulationError> {
        self.integrate(params, &[], ws, out, None)?;
        super::calibration::apply(self.model, params, &[], out, None);
        Ok(())
    }

    /// Simulates at `params` and computes the sensitivities of every sample to
    /// the parameters `wrt` (indices into [`Model::parameters`]).
    pub fn run_with_sensitivities(
        &self,
        params: &[f64],
        wrt: &[usize],
        ws: &mut Workspace,
        out: &mut Response,
        sens: &mut Sensitivities,
    ) -> Result<(), SimulationError> {
        sens.wrt.clear();
        sens.wrt.extend_from_slice(wrt);
        sens.values.clear();
        // Sized from the model, not from `out`, which may be a reused buffer
        // of another shape (`integrate` resizes it).
        let rows = self.model.sensors.len() * self.model.sampling.n_samples();
        sens.values.resize(rows * wrt.len(), 0.0);
        let size = group_size(wrt.len(), rayon::current_num_threads());
        if wrt.len() > size {
            let mut groups = std::mem::take(&mut ws.groups);
            let columns = (wrt, size);
            let result = self.integrate_groups(params, columns, &mut groups, out, &mut sens.values);
            ws.groups = groups;
            result?;
        } else {
            self.integrate(params, wrt, ws, out, Some(&mut sens.values))?;
        }
        super::calibration::apply(self.model, params, wrt, out, Some(&mut sens.values));
        Ok(())
    }

    /// The generalized coordinates along the response at `params`, for
    /// analyses of the trajectory (not for the hot path): `values[i *
    /// n_samples + k]` is `q_i(t_k) − q_i(0)`, the initial state being rest
    /// or the static equilibrium under gravity. The same steps as
    /// [`Simulator::run`], with one displacement reading per coordinate.
    pub fn coordinates(
        &self,
        params: &[f64],
        ws: &mut Workspace,
    ) -> Result<Response, SimulationError> {
        let n = self.structure.n;
        let mut probe = self.clone();
        probe.structure.sensors = (0..n)
            .map(|i| {
                let mut h = [0.0; 6];
                h[i % 6] = 1.0;
                let row = Row {
                    blocks: vec![(i - i % 6, h)],
                };
                (SensorKind::Displacement, row)
            })
            .collect();
        let mut out = Response::zeros(n, self.model.sampling.n_samples());
        probe.integrate(params, &[], ws, &mut out, None)?;
        Ok(out)
    }

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
        self.integrate(params, wrt, ws, out, Some(values))
    }

    /// A response buffer of the right shape.
    pub fn response_buffer(&self) -> Response {
        Response::zeros(self.model.sensors.len(), self.model.sampling.n_samples())
    }

    fn integrate(
        &self,
        params: &[f64],
        wrt: &[usize],
        ws: &mut Workspace,
        out: &mut Response,
        sens: Option<&mut Vec<f64>>,
    ) -> Result<(), SimulationError> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            // SAFETY: the CPU supports AVX2 and FMA, checked just above.
            // Small models (up to four bodies) get kernels with n fixed.
            return unsafe {
                match self.structure.n {
                    6 => self.integrate_avx2_fma::<Fixed<6>>(params, wrt, ws, out, sens),
                    12 => self.integrate_avx2_fma::<Fixed<12>>(params, wrt, ws, out, sens),
                    18 => self.integrate_avx2_fma::<Fixed<18>>(params, wrt, ws, out, sens),
                    24 => self.integrate_avx2_fma::<Fixed<24>>(params, wrt, ws, out, sens),
                    _ => self.integrate_avx2_fma::<Dynamic>(params, wrt, ws, out, sens),
                }
            };
        }
        self.integrate_generic::<Separate, Dynamic>(params, wrt, ws, out, sens)
    }

    /// [`Self::integrate_generic`] compiled for AVX2 with fused multiply–add
    /// in the kernels (see `madd`), one function per size D. Results differ
    /// from the portable path's in the last bits, and are the same on every
    /// run of the same machine.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn integrate_avx2_fma<D: Dim>(
        &self,
        params: &[f64],
        wrt: &[usize],
        ws: &mut Workspace,
        out: &mut Response,
        sens: Option<&mut Vec<f64>>,
    ) -> Result<(), SimulationError> {
        self.integrate_generic::<Fused, D>(params, wrt, ws, out, sens)
    }

    #[inline(always)]
    fn integrate_generic<M: Madd, D: Dim>(
        &self,
        params: &[f64],
        wrt: &[usize],
        ws: &mut Workspace,
        out: &mut Response,
        mut sens: Option<&mut Vec<f64>>,
    ) -> Result<(), SimulationError> {
        let mut sys = self.system(params)?;
        let n = sys.n;
        let r = wrt.len();
        sys.set_sparse(match self.kernel {
            Kernel::Auto => sys.prefers_sparse(),
            Kernel::Dense => false,
            Kernel::Sparse => true,
        });
        let tab = &self.integrator.tableau;
        let sampling = self.model.sampling;
        let n_samples = sampling.n_samples();
        let n_sensors = self.structure.sensors.len();
        out.n_samples = n_samples;
        out.n_sensors = n_sensors;
        out.values.resize(n_samples * n_sensors, 0.0);
        if r == 0 {
            // Sensitivities to nothing: an empty matrix, and a plain run.
            sens = None;
        }
        let wrt = if sens.is_some() { wrt } else { &[] };
        // Under gravity, the run starts at rest in the static equilibrium
        // and integrates the deviation from it (`preload`): the state and
        // the sensitivities start at zero.
        if self.model.gravity.is_some() {
            let eq = static_equilibrium(&sys, wrt)?;
            sys.set_reference(&eq.q, eq.dq);
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

        let total_steps = n_samples.saturating_sub(1) * substeps;
        let bps = &self.breakpoints;
        let mut next_bp = 0;
        for step in 0..=total_steps {
            let t = step as f64 * h;
            st.first_stage(ws, t, with_sens);
            if step % substeps == 0 {
                let k = step / substeps;
                if ws.y.iter().any(|v| !(v.abs() < BLOW_UP)) {
                    return Err(SimulationError::Diverged {
                        time: t,
                        fastest_hz: fastest_mode_hz(self.model, params),
                        sample_rate: sampling.sample_rate,
                        substeps,
                    });
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
            }
            if step == total_steps {
                break;
            }
            // Split the step at the excitation's breakpoints inside it (fixed
            // instants, so the response stays smooth in the parameters).
            let t_end = (step + 1) as f64 * h;
            let margin = 1e-9 * h;
            while next_bp < bps.len() && bps[next_bp] <= t + margin {
                next_bp += 1;
            }
            let mut from = t;
            while next_bp < bps.len() && bps[next_bp] < t_end - margin {
                let to = bps[next_bp];
                st.step(ws, from, to - from, with_sens);
                st.first_stage(ws, to, with_sens);
                from = to;
                next_bp += 1;
            }
            match from == t {
                true => st.step(ws, t, h, with_sens),
                false => st.step(ws, from, t_end - from, with_sens),
            }
        }
        Ok(())
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

    fn relative_rms_difference(a: &[f64], b: &[f64]) -> f64 {
        let diff: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
        let norm: f64 = a.iter().map(|x| x * x).sum();
        (diff / norm).sqrt()
    }

    #[test]
    fn fixed_size_kernels_equal_the_run_time_size_ones_bit_for_bit() {
        let fixed = knee_column_with(|sim, p, wrt, ws, out, s| {
            sim.integrate_generic::<Separate, Fixed<12>>(p, wrt, ws, out, Some(s))
                .expect("runs")
        });
        let dynamic = knee_column_with(|sim, p, wrt, ws, out, s| {
            sim.integrate_generic::<Separate, Dynamic>(p, wrt, ws, out, Some(s))
                .expect("runs")
        });
        assert!(fixed == dynamic);
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            // SAFETY: the CPU supports AVX2 and FMA, checked just above.
            let fused = |fixed: bool| {
                knee_column_with(|sim, p, wrt, ws, out, s| unsafe {
                    match fixed {
                        true => sim.integrate_avx2_fma::<Fixed<12>>(p, wrt, ws, out, Some(s)),
                        false => sim.integrate_avx2_fma::<Dynamic>(p, wrt, ws, out, Some(s)),
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
            sim.integrate_generic::<Separate, Dynamic>(p, wrt, ws, out, Some(s))
                .expect("runs")
        });
        // Whatever the dispatch picks on this machine: AVX2 + FMA with n
        // fixed where the CPU has them (otherwise the portable path itself,
        // and the comparison is trivially met).
        let dispatched = knee_column_with(|sim, p, wrt, ws, out, s| {
            sim.integrate(p, wrt, ws, out, Some(s)).expect("runs")
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
