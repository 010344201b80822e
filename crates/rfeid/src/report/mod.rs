//! A self-contained HTML report of an identification: one file, every
//! figure an inline SVG, no network, no JavaScript, readable in any browser
//! and printable. Each figure is also written as a standalone `.svg`.
//!
//! The page, in order: a summary (converged or not, J, s², N, the worst
//! error against a reference if one is given, timings); the identifiability
//! warnings; the parameter table with the estimates drawn inside their boxes
//! with ±1 and ±3 Cramér–Rao standard errors (eq. 26), and each profile
//! likelihood asked for (ΔJ/s² against the χ²₁(0.95) threshold and the Wald
//! parabola of the standard error); measured against model
//! response for each sensor (the paper's Fig. 2) with a zoomed window where
//! the residuals are largest; the residuals and their spectra against each
//! sensor's noise model; the LP_τ plan's criterion values
//! sorted, failed points marked (eq. 18–19); the local search history; the
//! correlation matrix as a heat map; the model.
//!
//! The figures are drawn by a small SVG writer in this module (`svg.rs`,
//! `axis.rs`) rather than a plotting crate: text is placed with a fixed-width
//! estimate, so no font file, font rasteriser or C library is involved, and
//! long signals are decimated to each pixel column's extremes
//! (`decimate.rs`) so the knee–column report stays well under 300 KB.
//!
//! The residual spectra set each sensor's residuals against its noise
//! model: where they rise above it, the model misfits the dynamics.
//!
//! Caveat: the standard errors and correlations shown are those of the
//! result (Cramér–Rao bounds under each sensor's noise model), which assume
//! a correct model; the verdict tests that, and labels the standard errors
//! as covering the noise only when it finds model error.
pub mod at_estimate;
mod axis;
mod correlation;
mod decimate;
pub mod design;
mod fmt;
pub mod frf;
mod history;
mod html;
mod intervals;
mod model_summary;
mod plan;
mod profiles;
mod signals;
mod spectra;
mod svg;

use crate::identification::result::IdentificationResult;
use crate::model::Model;
use crate::simulation::Response;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Everything a report shows.
pub struct ReportInput<'a> {
    /// Heading, e.g. "knee–column benchmark, 2 % noise, seed 1".
    pub title: String,
    /// The model (bodies, elements, sensors, parameters with boxes).
    pub model: &'a Model,
    /// The identification's outcome.
    pub result: &'a IdentificationResult,
    /// Sample instants, s.
    pub time: &'a [f64],
    /// Measured signals, sensor-major, in the order of `result.sensors`.
    pub measured: &'a Response,
    /// Model response at the estimate, shaped like `measured`.
    pub fitted: &'a Response,
    /// "Actual" values of the identified parameters (e.g. a demo's truth),
    /// SI, in the order of `result.parameters`.
    pub reference: Option<&'a [f64]>,
}

/// The files a report consists of.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReportFiles {
    /// `DIR/report.html`, with every figure inline.
    pub html: PathBuf,
    /// The same figures as standalone SVG files, in page order.
    pub figures: Vec<PathBuf>,
}

/// Why a report could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// Two inputs that must agree in size do not.
    #[error("{what}: expected {expected}, found {found}")]
    Mismatch {
        /// Which size, e.g. "samples in the fitted response".
        what: &'static str,
        /// The size the other inputs imply.
        expected: usize,
        /// The size given.
        found: usize,
    },
    /// The record is too short to draw.
    #[error("the record has {samples} samples; a report needs at least 2")]
    TooFewSamples {
        /// Samples given.
        samples: usize,
    },
    /// The report directory could not be created.
    #[error("cannot create the report directory {path}: {source}")]
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// A report file could not be written.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
}

/// The section headings of the page, in order, with their anchors.
pub const SECTIONS: [(&str, &str); 10] = [
    ("summary", "Summary"),
    ("warnings", "Identifiability warnings"),
    ("parameters", "Parameters"),
    ("response", "Measured and model response"),
    ("residuals", "Residuals"),
    ("frf", "Frequency response"),
    ("plan", "LP_τ plan"),
    ("history", "Local search history"),
    ("correlation", "Correlation of the estimates"),
    ("model", "Model"),
];

/// One figure: its file name, the section it belongs to, a caption, the SVG.
pub(crate) struct Figure {
    pub file: String,
    pub section: &'static str,
    pub caption: String,
    pub svg: String,
}

/// Checks that the inputs agree in size.
fn check(input: &ReportInput) -> Result<(), ReportError> {
    let r = input.result;
    let n = input.time.len();
    if n < 2 {
        return Err(ReportError::TooFewSamples { samples: n });
    }
    let same = |what, expected: usize, found: usize| {
        if expected == found {
            Ok(())
        } else {
            Err(ReportError::Mismatch {
                what,
                expected,
                found,
            })
        }
    };
    same(
        "samples in the measured response",
        n,
        input.measured.n_samples,
    )?;
    same("samples in the fitted response", n, input.fitted.n_samples)?;
    same(
        "sensors in the measured response",
        r.sensors.len(),
        input.measured.n_sensors,
    )?;
    same(
        "sensors in the fitted response",
        r.sensors.len(),
        input.fitted.n_sensors,
    )?;
    same(
        "values in the measured response",
        n * r.sensors.len(),
        input.measured.values.len(),
    )?;
    same(
        "values in the fitted response",
        n * r.sensors.len(),
        input.fitted.values.len(),
    )?;
    if let Some(reference) = input.reference {
        same(
            "reference values (one per identified parameter)",
            r.parameters.len(),
            reference.len(),
        )?;
    }
    if let Some(c) = &r.correlation {
        same(
            "rows of the correlation matrix",
            r.parameters.len(),
            c.len(),
        )?;
        for row in c {
            same(
                "columns of the correlation matrix",
                r.parameters.len(),
                row.len(),
            )?;
        }
    }
    Ok(())
}

/// A file name made of ASCII letters, digits, `-` and `_`, at most
/// [`STEM_CHARS`] of them: a sensor or experiment name may be longer than a
/// file system allows a file name to be (the figures are numbered, so
/// shortened names do not collide).
fn file_stem(name: &str) -> String {
    name.chars()
        .take(STEM_CHARS)
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The most characters of a name a figure's file name keeps.
const STEM_CHARS: usize = 64;

/// Every figure of the report, in page order.
pub(crate) fn figures(input: &ReportInput) -> Vec<Figure> {
    let r = input.result;
    let mut out = vec![parameters_figure(input)];
    out.extend(profile_figures(r));
    let channels = channels(input);
    out.extend(response_figures(input, &channels));
    out.push(Figure {
        file: "residuals.svg".into(),
        section: "residuals",
        caption: "Residuals measured − model for each sensor, with their RMS and largest \
                  magnitude over the fitted samples."
            .into(),
        svg: signals::residual_figure(input.time, &channels, r.from),
    });
    out.extend(spectrum_figures(input, &channels));
    out.extend(frf::report_figures(input));
    out.push(Figure {
        file: "plan.svg".into(),
        section: "plan",
        caption: "Criterion J at each LP_τ plan point, sorted (\"waterfall\"); failed points \
                  as crosses in the top strip, the local search's start point(s) ringed, the \
                  final J dashed."
            .into(),
        svg: plan::plan_figure(&r.plan, r.criterion),
    });
    out.extend(history_figures(input));
    out.extend(correlation_figure(r));
    out
}

/// The estimates within their boxes.
fn parameters_figure(input: &ReportInput) -> Figure {
    Figure {
        file: "parameters.svg".into(),
        section: "parameters",
        caption: "Each estimate (dot) inside its box (grey bar, normalised to 0 = min, 1 = max), \
                  with ±1 (thick) and ±3 (thin) standard errors; the nominal value as a tick"
            .to_owned()
            + if input.reference.is_some() {
                ", the reference as a diamond."
            } else {
                "."
            },
        svg: intervals::interval_figure(&input.result.parameters, input.reference),
    }
}

/// Each sensor of the result with its unit, measured and model signals.
fn channels<'a>(input: &ReportInput<'a>) -> Vec<signals::Channel<'a>> {
    input
        .result
        .sensors
        .iter()
        .enumerate()
        .map(|(c, name)| signals::Channel {
            name,
            unit: input
                .model
                .sensor_index(name.split('[').next().unwrap_or(name))
                .map(|i| signals::sensor_unit(input.model.sensors[i].kind))
                .unwrap_or_default(),
            measured: input.measured.sensor(c),
            model: input.fitted.sensor(c),
        })
        .collect()
}

/// One figure per sensor: measured and model signals.
fn response_figures(input: &ReportInput, channels: &[signals::Channel]) -> Vec<Figure> {
    channels
        .iter()
        .enumerate()
        .map(|(c, ch)| Figure {
            file: format!("response-{}-{}.svg", c + 1, file_stem(ch.name)),
            section: "response",
            caption: format!(
                "{}: measured (solid) and model at the estimate (dashed); right, the window \
                 of about 5 % of the record where the residuals are largest.",
                ch.name
            ),
            svg: signals::fit_figure(input.time, ch, input.result.from),
        })
        .collect()
}

/// One figure per sensor: its residual spectrum against its noise model
/// (none for a record too short for a spectrum).
fn spectrum_figures(input: &ReportInput, channels: &[signals::Channel]) -> Vec<Figure> {
    let r = input.result;
    let first = signals::first_sample(input.time, r.from);
    let fs = input.model.sampling.sample_rate;
    channels
        .iter()
        .enumerate()
        .filter_map(|(c, ch)| {
            let e: Vec<f64> = ch.measured[first.min(ch.measured.len())..]
                .iter()
                .zip(&ch.model[first.min(ch.model.len())..])
                .map(|(y, g)| y - g)
                .collect();
            let noise = r.noise.iter().find(|n| n.sensor == ch.name);
            let svg = spectra::spectrum_figure(ch.name, &ch.unit, &e, fs, noise)?;
            Some(Figure {
                file: format!("spectrum-{}-{}.svg", c + 1, file_stem(ch.name)),
                section: "residuals",
                caption: format!(
                    "{}: spectral density of the residuals (Welch, Hann segments of up to \
                     1024 samples) and of the sensor's noise model; where the residuals rise \
                     above the noise model, the model misfits the dynamics.",
                    ch.name
                ),
                svg,
            })
        })
        .collect()
}

/// One figure per profiled parameter (`--profiles`), in the parameters
/// section.
fn profile_figures(r: &IdentificationResult) -> Vec<Figure> {
    r.profiles
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let est = r.parameters.iter().find(|e| e.name == p.name);
            let (scale, symbol) = est.map_or((1.0, ""), |e| (e.unit_scale, e.unit.as_str()));
            Figure {
                file: format!("profile-{:02}-{}.svg", k + 1, file_stem(&p.name)),
                section: "parameters",
                caption: format!(
                    "Profile likelihood of {}: J minimised over the other parameters at each \
                     held value, as ΔJ/s² (s² of eq. 29); its 95 % interval is where it stays \
                     below the χ²₁(0.95) = {:.2} line. The dashed parabola is the Wald \
                     approximation of the Cramér–Rao standard error (eq. 26): where the two \
                     part, the standard error misstates the uncertainty.",
                    p.name, p.threshold
                ),
                svg: profiles::profile_figure(p, scale, symbol),
            }
        })
        .collect()
}

/// The local search's criterion and parameter trajectories (none without
/// a history).
fn history_figures(input: &ReportInput) -> Vec<Figure> {
    let r = input.result;
    if r.history.is_empty() {
        return Vec::new();
    }
    vec![
        Figure {
            file: "history-cost.svg".into(),
            section: "history",
            caption: "Criterion J after each iteration of the local search that gave the \
                      estimate."
                .into(),
            svg: history::cost_figure(&r.history, &r.method.to_string()),
        },
        Figure {
            file: "history-parameters.svg".into(),
            section: "history",
            caption: "Each parameter's trajectory over the iterations, normalised to its box \
                      (logarithmically for a log scale, as the search saw it)."
                .into(),
            svg: history::trajectory_figure(&r.history, &r.parameters, input.reference),
        },
    ]
}

/// The correlation heat map, if the result has a correlation matrix.
fn correlation_figure(r: &IdentificationResult) -> Option<Figure> {
    let corr = r.correlation.as_ref()?;
    let names: Vec<String> = r.parameters.iter().map(|p| p.name.clone()).collect();
    let (pairs, threshold) = correlation::warned_pairs(r, corr);
    Some(Figure {
        file: "correlation.svg".into(),
        section: "correlation",
        caption: format!(
            "Correlation of the estimates (from the Cramér–Rao bound): −1 blue, \
             0 white, +1 red; the pairs the verdict warns about (|ρ| > {threshold}) \
             outlined."
        ),
        svg: correlation::correlation_figure(corr, &names, &pairs, threshold),
    })
}

/// The report as one HTML document.
pub fn render_html(input: &ReportInput) -> Result<String, ReportError> {
    check(input)?;
    Ok(html::page(input, &figures(input)))
}

/// The report's files in memory: each figure as (`NAME.svg`, text), then
/// (`report.html`, text) last.
pub fn report_files(input: &ReportInput) -> Result<Vec<(String, String)>, ReportError> {
    check(input)?;
    let figs = figures(input);
    let mut out: Vec<(String, String)> = figs
        .iter()
        .map(|f| {
            (
                f.file.clone(),
                format!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n{}", f.svg),
            )
        })
        .collect();
    out.push(("report.html".into(), html::page(input, &figs)));
    Ok(out)
}

/// Writes `dir/report.html` and each figure as `dir/NAME.svg`, creating
/// `dir` if needed; each file appears whole or not at all.
pub fn write_report(dir: &Path, input: &ReportInput) -> Result<ReportFiles, ReportError> {
    check(input)?;
    std::fs::create_dir_all(dir).map_err(|source| ReportError::CreateDir {
        path: dir.to_owned(),
        source,
    })?;
    let figs = figures(input);
    let write = |path: PathBuf, text: &str| -> Result<PathBuf, ReportError> {
        crate::io::atomic::write_atomically(&path, |w| w.write_all(text.as_bytes())).map_err(
            |source| ReportError::Write {
                path: path.clone(),
                source,
            },
        )?;
        Ok(path)
    };
    let mut figures = Vec::with_capacity(figs.len());
    for f in &figs {
        let svg = format!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n{}", f.svg);
        figures.push(write(dir.join(&f.file), &svg)?);
    }
    let html = write(dir.join("report.html"), &html::page(input, &figs))?;
    Ok(ReportFiles { html, figures })
}

/// An SVG of simulated sensor signals, one panel per sensor (for
/// `rfeid simulate --plot`). `response` must have the model's sensors.
pub fn response_svg(model: &Model, time: &[f64], response: &Response) -> String {
    let channels: Vec<(&str, String, &[f64])> = model
        .sensors
        .iter()
        .enumerate()
        .map(|(c, s)| {
            (
                s.name.as_str(),
                signals::sensor_unit(s.kind),
                response.sensor(c),
            )
        })
        .collect();
    signals::response_figure(time, &channels)
}

#[cfg(test)]
mod file_name_tests {
    use super::file_stem;

    #[test]
    fn names_become_short_plain_file_stems() {
        assert_eq!(file_stem("knee_ax[low]"), "knee_ax_low_");
        let long = "é".repeat(300);
        assert_eq!(file_stem(&long), "_".repeat(64));
    }
}
