//! An FRF study as a user asks for it: the model's FRFs from the chosen
//! excitations to every sensor and point, with a 95 % band when the
//! parameters come with a covariance, and the measured H1 and coherence of
//! each data set given; in numbers ready to print, plot and write.
use super::band::{band, Z95};
use super::linear::{linearise, Linearised};
use super::measured::{default_segment, h1, MeasuredFrf};
use super::response::{frf, Output};
use super::FrfError;
use crate::model::{Model, SensorKind};
use crate::simulation::Response;
use nalgebra::DMatrix;
use serde::Serialize;

/// What to compute.
#[derive(Debug, Clone)]
pub struct FrfRequest<'a> {
    /// The model.
    pub model: &'a Model,
    /// All its parameter values.
    pub params: Vec<f64>,
    /// The parameters the band accounts for, and their covariance (SI);
    /// empty and `None` for no band.
    pub wrt: Vec<usize>,
    /// Their covariance.
    pub covariance: Option<DMatrix<f64>>,
    /// The excitations the FRFs are from (indices into the model's).
    pub excitations: Vec<usize>,
    /// Where the responses are read.
    pub outputs: Vec<Output>,
    /// The frequencies, Hz.
    pub frequencies: Vec<f64>,
}

/// One data set for the measured FRF: its model (an experiment's settings
/// applied), its measured sensors and the first sample to use.
#[derive(Debug, Clone, Copy)]
pub struct DataSet<'a> {
    /// Its label (the experiment's name, or `measured`).
    pub label: &'a str,
    /// The model as it saw the test (sampling, excitation signals).
    pub model: &'a Model,
    /// The measured sensors, on that model's sensors and sampling.
    pub measured: &'a Response,
    /// The first sample used (a transient skipped).
    pub first: usize,
    /// Samples per Welch segment (None: [`default_segment`]).
    pub segment: Option<usize>,
    /// A measured force and the excitation it measures (index into the
    /// model's), on the data's sampling: H1 of that excitation is from it,
    /// and no other excitation's is computed. Without it, each
    /// excitation's H1 is from its own signal in the model (a table of the
    /// data's force, or the signal the test applied).
    pub force: Option<(usize, &'a [f64])>,
}

/// The 95 % band of one FRF.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BandCurves {
    /// Lower and upper bounds of |H|.
    pub magnitude_lo: Vec<f64>,
    /// Upper bound of |H|.
    pub magnitude_hi: Vec<f64>,
    /// Lower bound of the phase, degrees (about the model's, unwrapped).
    pub phase_lo_deg: Vec<f64>,
    /// Upper bound of the phase, degrees.
    pub phase_hi_deg: Vec<f64>,
}

/// A measured FRF of one pair.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeasuredCurves {
    /// The data set's label.
    pub label: String,
    /// Welch's frequencies, Hz.
    pub frequencies_hz: Vec<f64>,
    /// |H1|.
    pub magnitude: Vec<f64>,
    /// arg H1, degrees.
    pub phase_deg: Vec<f64>,
    /// Re H1.
    pub real: Vec<f64>,
    /// Im H1.
    pub imag: Vec<f64>,
    /// γ².
    pub coherence: Vec<f64>,
    /// The normalised random error ε of |H1| ([`super::measured`]).
    pub random_error: Vec<f64>,
    /// Segments averaged.
    pub segments: usize,
    /// Samples per segment.
    pub segment: usize,
    /// The frequency resolution, Hz: the rate over the segment.
    pub resolution_hz: f64,
}

/// One excitation–output pair.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PairCurves {
    /// The excitation's name.
    pub excitation: String,
    /// The output's name.
    pub output: String,
    /// The FRF's unit: the reading's per newton.
    pub unit: String,
    /// The model's |H|.
    pub magnitude: Vec<f64>,
    /// The model's arg H, degrees.
    pub phase_deg: Vec<f64>,
    /// Its real part.
    pub real: Vec<f64>,
    /// Its imaginary part.
    pub imag: Vec<f64>,
    /// The 95 % band, when the request had a covariance.
    pub band: Option<BandCurves>,
    /// Measured FRFs, one per data set.
    pub measured: Vec<MeasuredCurves>,
}

/// The study's result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrfStudy {
    /// `rest` or `static equilibrium`.
    pub linearised_at: String,
    /// What the linearisation keeps of each nonlinear law, in words.
    pub notes: Vec<String>,
    /// The model's frequencies, Hz.
    pub frequencies_hz: Vec<f64>,
    /// Every pair, excitation-major.
    pub pairs: Vec<PairCurves>,
}

/// The unit of an FRF reading `kind` per newton.
pub fn frf_unit(kind: SensorKind) -> &'static str {
    match kind {
        SensorKind::Displacement => "m/N",
        SensorKind::Velocity => "(m/s)/N",
        SensorKind::Acceleration => "(m/s^2)/N",
    }
}

/// Computes the study: the model's FRFs (and band), and each data set's H1
/// for the same pairs.
pub fn study(req: &FrfRequest<'_>, data: &[DataSet<'_>]) -> Result<FrfStudy, FrfError> {
    let lin = linearise(req.model, &req.params, &req.wrt)?;
    let all = frf(&lin, &req.outputs, &req.params, &req.wrt, &req.frequencies)?;
    let mut pairs = Vec::new();
    for &e in &req.excitations {
        for (s, out) in req.outputs.iter().enumerate() {
            let p = all.pair(e, s);
            let h = &all.values[p];
            let band = req.covariance.as_ref().map(|cov| {
                let b = band(&all, p, cov);
                let mag: Vec<f64> = h.iter().map(|v| v.norm()).collect();
                let (magnitude_lo, magnitude_hi) = b.magnitude_bounds(&mag, Z95);
                let (phase_lo_deg, phase_hi_deg) = (h.iter().zip(&b.phase_sd))
                    .map(|(v, sd)| {
                        let (c, w) = (v.arg().to_degrees(), (Z95 * sd).to_degrees());
                        (c - w, c + w)
                    })
                    .unzip();
                BandCurves {
                    magnitude_lo,
                    magnitude_hi,
                    phase_lo_deg,
                    phase_hi_deg,
                }
            });
            let range = (req.frequencies.first(), req.frequencies.last());
            let measured = data
                .iter()
                .filter_map(|d| measured_pair(d, e, out, &req.params).transpose())
                .map(|m| m.map(|m| within(m, range)))
                .collect::<Result<_, _>>()?;
            pairs.push(PairCurves {
                excitation: req.model.excitations[e].name.clone(),
                output: out.name.clone(),
                unit: frf_unit(out.kind).to_owned(),
                magnitude: h.iter().map(|v| v.norm()).collect(),
                phase_deg: h.iter().map(|v| v.arg().to_degrees()).collect(),
                real: h.iter().map(|v| v.re).collect(),
                imag: h.iter().map(|v| v.im).collect(),
                band,
                measured,
            });
        }
    }
    Ok(FrfStudy {
        linearised_at: if lin.at_equilibrium {
            "static equilibrium"
        } else {
            "rest"
        }
        .into(),
        notes: notes(req.model, &lin),
        frequencies_hz: req.frequencies.clone(),
        pairs,
    })
}

/// H1 of data set `d` from excitation e to the output `out` (a sensor of
/// the data's model, by name), or `None` when the data do not hold it.
fn measured_pair(
    d: &DataSet<'_>,
    e: usize,
    out: &Output,
    params: &[f64],
) -> Result<Option<MeasuredCurves>, FrfError> {
    let Some(c) = d.model.sensors.iter().position(|x| x.name == out.name) else {
        return Ok(None);
    };
    let Some(exc) = d.model.excitations.get(e) else {
        return Ok(None);
    };
    let n = d.measured.n_samples;
    let u: Vec<f64> = match d.force {
        Some((f, _)) if f != e => return Ok(None),
        Some((_, force)) => force[d.first.min(force.len())..].to_vec(),
        None => (d.first..n)
            .map(|k| exc.signal.at(d.model.sampling.time(k), params))
            .collect(),
    };
    let y = &d.measured.sensor(c)[d.first..];
    let segment = d.segment.unwrap_or_else(|| default_segment(y.len()));
    let m: MeasuredFrf = h1(&u, y, d.model.sampling.sample_rate, segment)?;
    Ok(Some(MeasuredCurves {
        label: d.label.to_owned(),
        magnitude: m.h1.iter().map(|v| v.norm()).collect(),
        phase_deg: m.h1.iter().map(|v| v.arg().to_degrees()).collect(),
        real: m.h1.iter().map(|v| v.re).collect(),
        imag: m.h1.iter().map(|v| v.im).collect(),
        frequencies_hz: m.frequencies,
        coherence: m.coherence,
        random_error: m.random_error,
        segments: m.segments,
        segment,
        resolution_hz: d.model.sampling.sample_rate / segment as f64,
    }))
}

/// The curve `m` kept to the model's frequencies' range (all of it for no
/// range).
fn within(mut m: MeasuredCurves, range: (Option<&f64>, Option<&f64>)) -> MeasuredCurves {
    let (Some(&lo), Some(&hi)) = range else {
        return m;
    };
    // A tolerance of rounding, so that Welch's own grid keeps its ends.
    let keep: Vec<bool> = (m.frequencies_hz.iter())
        .map(|f| *f >= lo * (1.0 - 1e-12) && *f <= hi * (1.0 + 1e-12))
        .collect();
    let cut = |v: &mut Vec<f64>| {
        let mut k = keep.iter();
        v.retain(|_| *k.next().unwrap_or(&false));
    };
    for v in [
        &mut m.frequencies_hz,
        &mut m.magnitude,
        &mut m.phase_deg,
        &mut m.real,
        &mut m.imag,
        &mut m.coherence,
        &mut m.random_error,
    ] {
        cut(v);
    }
    m
}

/// What the linearisation keeps of the nonlinear laws, in words.
fn notes(model: &Model, lin: &Linearised) -> Vec<String> {
    let mut notes = Vec::new();
    if !lin.zero_slope.is_empty() {
        notes.push(format!(
            "these power-law springs have zero slope at the linearisation point and add no \
             stiffness to it: {} (their stiffness grows with deformation; under gravity the \
             model is linearised at its static equilibrium, where they carry its weight)",
            lin.zero_slope.join(", ")
        ));
    }
    let laws = |name: &str| -> Vec<String> {
        model
            .elements
            .iter()
            .flat_map(|el| el.components.iter().map(move |c| (el, c)))
            .filter(|(_, c)| c.law.joint().name() == name)
            .map(|(el, c)| format!("{}/{}", el.name, crate::model::COMPONENT_NAMES[c.dof]))
            .collect()
    };
    let friction = laws("friction");
    if !friction.is_empty() {
        notes.push(format!(
            "friction at rest is linearised as a viscous damper F(0)/v_s (the smoothed sign \
             sticks for velocities well below v_s): {}",
            friction.join(", ")
        ));
    }
    let hysteresis = laws("bouc-wen");
    if !hysteresis.is_empty() {
        notes.push(format!(
            "Bouc–Wen laws are linearised as springs k + α (z = α δ for small motions): {}",
            hysteresis.join(", ")
        ));
    }
    notes.push(
        "the FRF is that of the model linearised there: it holds for motions small against \
         the deformations that change a nonlinear joint's slope"
            .into(),
    );
    notes
}
