//! Sine excitations at the stages of a step, by angle addition.
//!
//! A step of the default method evaluates the excitation at twelve instants
//! `t + c_i h`. When every excitation term is a sine `A sin(ωt + φ)` (the
//! benchmark's exciter, and any multisine), the phase at the step's start is
//! computed once, `(sin θ, cos θ)` with `θ = ωt + φ`, and each stage follows
//! from `sin(θ + ω c_i h) = sin θ cos(ω c_i h) + cos θ sin(ω c_i h)`, with the
//! rotations precomputed for the run's step h. That replaces eleven sines per
//! term and step by four multiply–adds each, with an error of a few units in
//! the last place (the direct evaluation's own argument `ωt`, up to a few
//! hundred radians, is rounded more coarsely than that). Steps of another
//! length (the pieces of a step split at a zero crossing) and other signal
//! kinds are evaluated directly.
use crate::model::{Model, Shape};
use std::f64::consts::PI;

/// One sine term of one excitation.
#[derive(Debug, Clone, Copy)]
struct SineTerm {
    /// Index of the excitation.
    excitation: usize,
    /// Amplitude A at the run's parameter values.
    amplitude: f64,
    /// 2π f.
    omega: f64,
    /// φ.
    phase: f64,
}

/// The sine terms of a model and their per-stage rotations for one step
/// length.
#[derive(Debug, Clone)]
pub(crate) struct StageSines {
    /// The step length the rotations are for.
    pub h: f64,
    terms: Vec<SineTerm>,
    /// `(cos ω c_i h, sin ω c_i h)`, stage-major (stage i, then term).
    rotations: Vec<(f64, f64)>,
}

impl StageSines {
    /// The rotations for stages at `c_i h`, or `None` unless every term of
    /// every excitation is a sine.
    pub fn new(model: &Model, params: &[f64], c: &[f64], h: f64) -> Option<StageSines> {
        let mut terms = Vec::new();
        for (e, exc) in model.excitations.iter().enumerate() {
            if exc.signal.terms.is_empty() {
                return None;
            }
            for term in &exc.signal.terms {
                let Shape::Sine { frequency, phase } = term.shape else {
                    return None;
                };
                terms.push(SineTerm {
                    excitation: e,
                    amplitude: term.amplitude.eval(params),
                    omega: 2.0 * PI * frequency,
                    phase,
                });
            }
        }
        let rotations = c
            .iter()
            .flat_map(|ci| terms.iter().map(move |s| (s.omega * (ci * h)).sin_cos()))
            .map(|(sin, cos)| (cos, sin))
            .collect();
        Some(StageSines {
            h,
            terms,
            rotations,
        })
    }

    /// The number of terms (the length of a phase buffer).
    pub fn len(&self) -> usize {
        self.terms.len()
    }

    /// `(sin θ, cos θ)` of each term at t, into `phases`, and the forces at t.
    pub fn start(&self, t: f64, phases: &mut [(f64, f64)], forces: &mut [f64]) {
        for (k, (s, p)) in self.terms.iter().zip(phases.iter_mut()).enumerate() {
            // The argument as `Shape::at` forms it, so that the forces at the
            // step's start (and so at every sample) are the direct ones.
            *p = (s.omega * t + s.phase).sin_cos();
            self.add(k, s.amplitude * p.0, forces);
        }
    }

    /// Term k's value into its excitation's force: the first term of an
    /// excitation (every excitation has one, and they come in order) sets it.
    #[inline(always)]
    fn add(&self, k: usize, value: f64, forces: &mut [f64]) {
        let e = self.terms[k].excitation;
        if k == 0 || self.terms[k - 1].excitation != e {
            forces[e] = value;
        } else {
            forces[e] += value;
        }
    }

    /// The forces at stage i of a step of length [`Self::h`] whose start
    /// gave `phases`.
    #[inline(always)]
    pub fn stage(&self, i: usize, phases: &[(f64, f64)], forces: &mut [f64]) {
        let rotations = &self.rotations[i * self.terms.len()..(i + 1) * self.terms.len()];
        for (k, ((s, &(sin, cos)), &(rc, rs))) in
            self.terms.iter().zip(phases).zip(rotations).enumerate()
        {
            self.add(k, s.amplitude * (sin * rc + cos * rs), forces);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::StageSines;
    use crate::io::model_file::parse_model;
    use crate::simulation::tableau::DOP853;
    use std::path::Path;

    const MODEL: &str = r#"
[simulation]
duration = 1.0
sample_rate = 1000.0

[[body]]
name = "b"
mass = 1.0
inertia = [1.0, 1.0, 1.0]
com = [0.0, 0.0, 0.0]

[[element]]
name = "e"
body = "b"
to = "ground"
at = [0.0, 0.0, 0.0]
ux = { k = 1.0e4 }

[[excitation]]
body = "b"
at = [0.0, 0.0, 0.0]
direction = [1.0, 0.0, 0.0]
signal = { type = "multisine", components = [{ amplitude = 3.0, frequency = 80.0 }, { amplitude = 2.0, frequency = 1234.5, phase = 0.7 }] }

[[excitation]]
body = "b"
at = [0.0, 0.0, 0.0]
direction = [0.0, 1.0, 0.0]
signal = { type = "sine", amplitude = 5.0, frequency = 45.0 }

[[sensor]]
name = "x"
body = "b"
at = [0.0, 0.0, 0.0]
direction = [1.0, 0.0, 0.0]
quantity = "displacement"
"#;

    /// Every stage of steps up to t = 10 s (arguments up to 8e4 rad) against
    /// the direct evaluation of the signals.
    #[test]
    fn stage_forces_match_the_direct_signal_values() {
        let model = parse_model(MODEL, Path::new("sines.toml")).expect("parses");
        let params = model.nominal();
        let h = 1e-3;
        let sines = StageSines::new(&model, &params, DOP853.c, h).expect("all sines");
        let mut phases = vec![(0.0, 0.0); sines.len()];
        let (mut forces, mut worst) = (vec![0.0; 2], 0.0_f64);
        for step in [0_usize, 1, 17, 299, 3000, 9999] {
            let t = step as f64 * h;
            sines.start(t, &mut phases, &mut forces);
            for (i, &ci) in DOP853.c.iter().enumerate() {
                sines.stage(i, &phases, &mut forces);
                for (e, exc) in model.excitations.iter().enumerate() {
                    let direct = exc.signal.at(t + ci * h, &params);
                    worst = worst.max((forces[e] - direct).abs());
                }
            }
        }
        // Both carry the rounding of the argument ωt (≤ 8e4 rad · 1.1e-16);
        // the amplitudes are at most 5. Measured: 1.8e-11.
        assert!(worst < 5.0 * 8e4 * 4e-16, "worst difference {worst:e}");
    }
}
