//! Response content that sampled data cannot show: natural frequencies of
//! the model at a parameter point, and excitation frequencies, above the
//! Nyquist frequency (half the sample rate).
//!
//! A power-law spring `a·sign(δ)|δ|^m` with m > 1 has zero slope at rest
//! (eq. 2–6): linearised there, the modes it restrains look slow or absent,
//! however stiff the joint becomes once it deforms. So the modes are also
//! taken along the simulated response: at the sample where each power-law
//! deformation is largest, the tangent stiffness `K_t(q)` gives the modes of
//! the motion about that state, and the highest of them is compared with
//! the Nyquist frequency. That costs one simulation without sensitivities
//! and one symmetric eigenvalue problem (values only) per distinct sample
//! among those states.
use super::modal::{highest_frequency_at, highest_frequency_of, rest_frequencies};
use super::run::{SampleView, Span};
use super::simulator::Simulator;
use super::structure::Row;
use super::workspace::Workspace;
use crate::model::{Law, Shape, COMPONENT_NAMES};
use rayon::prelude::*;

/// The fastest mode of the model linearised along its response.
#[derive(Debug, Clone, PartialEq)]
pub struct FastestMode {
    /// Its undamped natural frequency, Hz.
    pub frequency_hz: f64,
    /// The sample time of the state it was found at, s.
    pub time: f64,
    /// The power-law component most deformed there, as `element/component`.
    pub component: String,
}

/// The states along a run where each power-law deformation is largest,
/// gathered sample by sample ([`DeformationPeaks::observe`], for example as
/// the watcher of [`Simulator::choose_watching`]) so that no run is needed
/// for them alone.
#[derive(Debug, Clone)]
pub struct DeformationPeaks {
    /// The power-law components' indices in the structure.
    components: Vec<usize>,
    /// Their deformation rows.
    rows: Vec<Row>,
    /// Per component: the sample of its largest |δ| so far, and |δ| there.
    most: Vec<(usize, f64)>,
    /// The coordinates (from zero, not from the run's origin) at the
    /// samples still in `most`.
    states: Vec<(usize, Vec<f64>)>,
    /// Buffers of states no longer needed, for reuse.
    spare: Vec<Vec<f64>>,
    /// Scratch for them.
    q: Vec<f64>,
}

impl DeformationPeaks {
    /// A watcher for the runs of `sim`: `None` if the model has no
    /// power-law springs.
    pub fn new(sim: &Simulator<'_>) -> Option<Self> {
        let structure = sim.structure();
        let components: Vec<usize> = (0..structure.components.len())
            .filter(|&i| matches!(structure.components[i].law, Law::Power { .. }))
            .collect();
        if components.is_empty() {
            return None;
        }
        let rows = components
            .iter()
            .map(|&i| structure.components[i].row.clone())
            .collect();
        Some(DeformationPeaks {
            most: vec![(0, -1.0); components.len()],
            components,
            rows,
            q: vec![0.0; structure.n],
            states: Vec::new(),
            spare: Vec::new(),
        })
    }

    /// Takes a sample of the run; sample 0 starts over.
    pub fn observe(&mut self, at: &SampleView<'_>) {
        let k = at.sample;
        if k == 0 {
            self.most.iter_mut().for_each(|m| *m = (0, -1.0));
            self.spare.extend(self.states.drain(..).map(|(_, q)| q));
        }
        let n = self.q.len();
        self.q.copy_from_slice(&at.y[..n]);
        if !at.origin.is_empty() {
            self.q.iter_mut().zip(at.origin).for_each(|(q, o)| *q += o);
        }
        let mut kept = false;
        for (m, row) in self.most.iter_mut().zip(&self.rows) {
            let d = row.dot(&self.q).abs();
            if d > m.1 {
                *m = (k, d);
                kept = true;
            }
        }
        if kept {
            if self.states.len() > 2 * self.most.len() {
                // States no component refers to any more: their buffers
                // are reused, so that the watch does not allocate.
                let most = &self.most;
                let (keep, drop): (Vec<_>, Vec<_>) =
                    (self.states.drain(..)).partition(|(s, _)| most.iter().any(|m| m.0 == *s));
                self.states = keep;
                self.spare.extend(drop.into_iter().map(|(_, q)| q));
            }
            let mut q = self.spare.pop().unwrap_or_default();
            q.clone_from(&self.q);
            self.states.push((k, q));
        }
    }

    /// [`DeformationPeaks::fastest`] where it may exceed `limit` Hz, `None`
    /// where it cannot. Without a contact, a stiffening power law (m ≥ 1, a ≥ 0) is stiffest
    /// where it is most deformed, so the tangent with every such spring at
    /// its own largest deformation bounds the tangent at every state of
    /// the run (in the order of symmetric matrices), and its top frequency
    /// bounds theirs: one eigenvalue problem instead of one per state, and
    /// those only when the bound is above the limit.
    pub fn fastest_above(
        &self,
        sim: &Simulator<'_>,
        params: &[f64],
        limit: f64,
    ) -> Option<FastestMode> {
        let sys = sim.system(params).ok()?;
        let power = sys.power_components();
        // A contact's stiffness is not in the bound: without one only.
        let stiffening = sys.contacts.is_empty()
            && (self.components.iter())
                .all(|&c| power[c].is_some_and(|(a, m)| a >= 0.0 && m >= 1.0));
        if stiffening {
            let most: Vec<f64> = self.most.iter().map(|m| m.1.max(0.0)).collect();
            let bound = highest_frequency_of(&sys, &sys.tangent_at_deformations(&most));
            if bound <= limit {
                return None;
            }
        }
        self.fastest(sim, params).filter(|m| m.frequency_hz > limit)
    }

    /// The highest natural frequency of the model linearised at the
    /// states found, at `params`: one symmetric eigenvalue problem (values
    /// only) per distinct sample, solved in parallel.
    pub fn fastest(&self, sim: &Simulator<'_>, params: &[f64]) -> Option<FastestMode> {
        let model = sim.model();
        let sys = sim.system(params).ok()?;
        // Components most deformed at the same sample share one eigenproblem.
        let states: Vec<&(usize, Vec<f64>)> = (self.states.iter())
            .filter(|(s, _)| self.most.iter().any(|m| m.0 == *s))
            .collect();
        let highest: Vec<f64> = states
            .par_iter()
            .map(|(_, q)| highest_frequency_at(&sys, q))
            .collect();
        let mut fastest: Option<FastestMode> = None;
        for (&(k, _), &comp) in self.most.iter().zip(&self.components) {
            let Some(at) = states.iter().position(|s| s.0 == k) else {
                continue;
            };
            let f = highest[at];
            if f.is_finite() && fastest.as_ref().is_none_or(|m| f > m.frequency_hz) {
                let comp = &sim.structure().components[comp];
                fastest = Some(FastestMode {
                    frequency_hz: f,
                    time: model.sampling.time(k),
                    component: format!(
                        "{}/{}",
                        model.elements[comp.element].name, COMPONENT_NAMES[comp.dof]
                    ),
                });
            }
        }
        fastest
    }
}

/// The highest natural frequency of the model linearised along its response
/// at `params` (see the module documentation): `None` if the model has no
/// power-law springs, or if the simulation fails (which reports itself).
pub fn fastest_along_response(sim: &Simulator<'_>, params: &[f64]) -> Option<FastestMode> {
    let mut peaks = DeformationPeaks::new(sim)?;
    let mut out = sim.response_buffer();
    let mut watch = |at: &SampleView<'_>| peaks.observe(at);
    let mut span = Span {
        observer: Some(&mut watch),
        ..Span::default()
    };
    sim.run_span(params, &mut Workspace::default(), &mut out, &mut span)
        .ok()?;
    peaks.fastest(sim, params)
}

/// Warnings, in words, about content of the model's response at `params`
/// above the data's Nyquist frequency: modes linearised at rest (or at the
/// equilibrium under gravity) and along the response, and excitation
/// frequencies. None if there is none (or if the modal analysis fails; the
/// simulation reports that itself).
pub fn above_nyquist(sim: &Simulator<'_>, params: &[f64]) -> Vec<String> {
    let (rest, along) = rayon::join(
        || modes_at_rest(sim, params),
        || fastest_along_response(sim, params),
    );
    nyquist_warnings(sim, rest, along)
}

/// [`above_nyquist`] for the run whose deformation peaks are `peaks` (from
/// [`DeformationPeaks::new`], watching a run at the same `params`) and with
/// the modes at rest `rest` ([`modes_at_rest`] at `params`): no simulation
/// or modal analysis of its own.
pub fn above_nyquist_after(
    sim: &Simulator<'_>,
    params: &[f64],
    peaks: Option<&DeformationPeaks>,
    rest: Option<ModesAtRest>,
) -> Vec<String> {
    let nyquist = sim.model().sampling.sample_rate / 2.0;
    let along = peaks.and_then(|p| p.fastest_above(sim, params, nyquist));
    nyquist_warnings(sim, rest, along)
}

/// What the Nyquist check needs of the modes at rest (or at the
/// equilibrium under gravity): natural frequencies only, no shapes.
#[derive(Debug, Clone, PartialEq)]
pub struct ModesAtRest {
    /// The undamped natural frequencies, Hz (0 for zero-stiffness modes).
    pub frequencies_hz: Vec<f64>,
    /// How many of the zero ones are free, rigid-body motions.
    pub free: usize,
}

/// The modes at rest at `params` for [`above_nyquist_after`]: `None` if
/// the modal analysis fails (the simulation reports that itself).
pub fn modes_at_rest(sim: &Simulator<'_>, params: &[f64]) -> Option<ModesAtRest> {
    let (frequencies_hz, free) = rest_frequencies(sim, params).ok()?;
    Some(ModesAtRest {
        frequencies_hz,
        free,
    })
}

/// The warnings from the modes at rest and the fastest mode along the
/// response.
fn nyquist_warnings(
    sim: &Simulator<'_>,
    rest: Option<ModesAtRest>,
    along: Option<FastestMode>,
) -> Vec<String> {
    let model = sim.model();
    let nyquist = model.sampling.sample_rate / 2.0;
    let mut warnings = Vec::new();
    // Modes above the Nyquist frequency at rest: (how many, of how many
    // restrained ones, fastest, how many free ones at zero frequency).
    let at_rest = rest.map(|rest| {
        let above: Vec<f64> = (rest.frequencies_hz.into_iter())
            .filter(|f| *f > nyquist)
            .collect();
        let fastest = above.iter().cloned().fold(0.0, f64::max);
        (
            above.len(),
            sim.structure().n - rest.free,
            fastest,
            rest.free,
        )
    });
    let rest_text = |(above, of, fastest, free): (usize, usize, f64, usize)| {
        let aside = match free {
            0 => String::new(),
            f => format!(" (besides {f} free, rigid-body mode(s) at 0 Hz)"),
        };
        format!(
            "modes above it when linearised at rest: {above} of {of}{aside}, the fastest at \
             {fastest:.1} Hz"
        )
    };
    let along = along
        .filter(|m| m.frequency_hz > nyquist)
        .filter(|m| at_rest.is_none_or(|r| m.frequency_hz > r.2));
    let what = match (along, at_rest.filter(|r| r.0 > 0)) {
        (Some(m), rest) => Some(format!(
            "linearised along its response, the model has a mode at {:.1} Hz, above the data's \
             Nyquist frequency of {nyquist} Hz (at t = {:.4} s, where the power-law joint {} is \
             most deformed, so stiffest){}",
            m.frequency_hz,
            m.time,
            m.component,
            rest.map(|r| format!("; {}", rest_text(r)))
                .unwrap_or_default()
        )),
        (None, Some(r)) => Some(format!(
            "the data's Nyquist frequency is {nyquist} Hz: {}",
            rest_text(r)
        )),
        (None, None) => None,
    };
    if let Some(what) = what {
        warnings.push(format!(
            "{what}; the data cannot show that content, so the parameters that set those modes \
             rest on the rest of the response only (at these parameter values); sample faster if \
             you can"
        ));
    }
    for exc in &model.excitations {
        let highest = exc
            .signal
            .terms
            .iter()
            .filter_map(|t| match t.shape {
                Shape::Sine { frequency, .. } => Some(frequency.abs()),
                Shape::Chirp { f0, f1, .. } => Some(f0.abs().max(f1.abs())),
                Shape::Impulse { .. } | Shape::Constant | Shape::Table { .. } => None,
            })
            .fold(0.0, f64::max);
        if highest > nyquist {
            warnings.push(format!(
                "excitation '{}' reaches {highest} Hz, above the data's Nyquist frequency of \
                 {nyquist} Hz: the data cannot show the response at those frequencies",
                exc.name
            ));
        }
    }
    warnings
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::model_file::parse_model;
    use crate::model::Model;
    use crate::simulation::steps::fastest_mode_hz;
    use crate::simulation::test_models::oscillator;
    use crate::simulation::Workspace;
    use std::path::Path;

    /// A unit mass on a power-law spring `a·sign(x)|x|²` (zero slope at
    /// rest), driven by a sine of 1 N at 30 Hz, sampled at `rate` Hz.
    fn power_oscillator(a: f64, rate: f64) -> Model {
        let text = format!(
            "[simulation]\nduration = 0.05\nsample_rate = {rate}\n\n\
             [[body]]\nname = \"b\"\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\ncom = [0, 0, 0]\n\n\
             [[element]]\nname = \"s\"\nbody = \"b\"\nto = \"ground\"\nat = [0, 0, 0]\n\
             ux = {{ law = \"power\", a = {a}, m = 2.0, c = 1.0 }}\n\n\
             [[excitation]]\nname = \"p\"\nbody = \"b\"\nat = [0, 0, 0]\ndirection = [1, 0, 0]\n\
             signal = {{ type = \"sine\", amplitude = 1.0, frequency = 30.0 }}\n\n\
             [[sensor]]\nname = \"x\"\nbody = \"b\"\nat = [0, 0, 0]\ndirection = [1, 0, 0]\n\
             quantity = \"displacement\"\n"
        );
        parse_model(&text, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn a_power_law_springs_mode_is_taken_where_it_is_most_deformed() {
        // Closed form: the slope 2a|x| at the largest |x| of the simulated
        // displacement over a unit mass, ω² = 2a·max|x| (eq. 2–6).
        let a = 4e12;
        let m = power_oscillator(a, 4000.0);
        let sim = Simulator::new(&m);
        let mut out = sim.response_buffer();
        sim.run(&m.nominal(), &mut Workspace::default(), &mut out)
            .unwrap();
        let x_max = out.sensor(0).iter().fold(0.0_f64, |s, x| s.max(x.abs()));
        let f = (2.0 * a * x_max).sqrt() / (2.0 * std::f64::consts::PI);
        let found = fastest_along_response(&sim, &m.nominal()).unwrap();
        assert!(
            (found.frequency_hz - f).abs() <= 1e-12 * f,
            "{found:?} vs {f}"
        );
        assert_eq!(found.component, "s/ux");
        assert!(f > 100.0 && f < 1000.0, "{f}");
        // At rest the spring has no slope: nothing to warn about there.
        assert!(fastest_mode_hz(&m, &m.nominal()).unwrap() == 0.0);
        assert!(above_nyquist(&sim, &m.nominal()).is_empty());
        let slow = power_oscillator(a, 1.5 * f);
        let w = above_nyquist(&Simulator::new(&slow), &slow.nominal());
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains("along its response") && w[0].contains("s/ux"),
            "{w:?}"
        );
    }

    #[test]
    fn modes_and_excitations_above_nyquist_are_named() {
        let m = oscillator(100.0, 30.0, 1000.0);
        assert!(above_nyquist(&Simulator::new(&m), &m.nominal()).is_empty());
        let m = oscillator(700.0, 30.0, 1000.0);
        let w = above_nyquist(&Simulator::new(&m), &m.nominal());
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains("700.0 Hz") && w[0].contains("500 Hz"),
            "{w:?}"
        );
        let m = oscillator(100.0, 600.0, 1000.0);
        let w = above_nyquist(&Simulator::new(&m), &m.nominal());
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("excitation 'p' reaches 600 Hz"), "{w:?}");
    }

    #[test]
    fn the_bound_keeps_every_mode_above_the_limit() {
        // The knee–column's slideways are power laws (m = 1.5): the bound
        // from each at its own largest deformation must not fall below the
        // fastest mode at any single state of the run.
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/knee-column/model.toml");
        let m = crate::io::model_file::load_model(&path).expect("the example loads");
        let (sim, p) = (Simulator::new(&m), m.nominal());
        let mut peaks = DeformationPeaks::new(&sim).expect("power laws");
        let mut watch = |at: &SampleView<'_>| peaks.observe(at);
        let mut span = Span {
            observer: Some(&mut watch),
            ..Span::default()
        };
        let mut out = sim.response_buffer();
        sim.run_span(&p, &mut Workspace::default(), &mut out, &mut span)
            .unwrap();
        let exact = peaks.fastest(&sim, &p).unwrap();
        let f = exact.frequency_hz;
        assert_eq!(peaks.fastest_above(&sim, &p, 0.999 * f), Some(exact));
        assert_eq!(peaks.fastest_above(&sim, &p, f), None);
    }
}
