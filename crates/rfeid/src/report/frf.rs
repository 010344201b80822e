//! The FRF figure: magnitude on a log axis with the model's 95 % band and
//! the measured H1, the phase, and the coherence under them, all against
//! frequency. One figure per excitation–response pair.
use super::axis::{legend, Frame, Key, Scale};
use super::decimate::path_data;
use super::svg::{colour, Stroke, Svg};
use crate::frf::C64;

/// A measured FRF to draw: H1 and its coherence, at its frequencies.
#[derive(Debug, Clone, Copy)]
pub struct MeasuredCurve<'a> {
    /// Legend label (`measured`, or the experiment's name in a campaign);
    /// drawn where the coherence is at least [`MIN_COHERENCE`].
    pub label: &'a str,
    /// Frequencies, Hz.
    pub frequencies: &'a [f64],
    /// H1.
    pub h1: &'a [C64],
    /// γ².
    pub coherence: &'a [f64],
}

/// Everything one FRF figure shows.
#[derive(Debug, Clone)]
pub struct FrfFigure<'a> {
    /// The figure's title (`exciter → knee_ax`).
    pub title: String,
    /// The FRF's unit (`(m/s^2)/N`).
    pub unit: String,
    /// The model's frequencies, Hz.
    pub frequencies: &'a [f64],
    /// The model's FRF.
    pub model: &'a [C64],
    /// The 95 % band: magnitude's lower and upper bounds, phase's lower
    /// and upper bounds (degrees, unwrapped about the model's).
    pub band: Option<[Vec<f64>; 4]>,
    /// Measured FRFs (one per force level in a campaign).
    pub measured: Vec<MeasuredCurve<'a>>,
}

/// The coherence below which H1 is not drawn (the coherence panel shows
/// where).
pub const MIN_COHERENCE: f64 = 0.8;

/// The colours of the measured curves, in turn.
const MEASURED: [&str; 4] = [
    colour::BLACK,
    colour::ORANGE,
    colour::GREEN,
    colour::VERMILLION,
];

/// The figure as SVG; `None` when there is nothing positive to draw.
pub fn frf_figure(fig: &FrfFigure<'_>) -> Option<String> {
    let magnitudes = fig.model.iter().map(|h| h.norm());
    let measured = fig.measured.iter().flat_map(|m| {
        (m.h1.iter().zip(m.coherence))
            .filter(|(_, g)| **g >= MIN_COHERENCE)
            .map(|(h, _)| h.norm())
    });
    let band = fig
        .band
        .iter()
        .flat_map(|b| b[0].iter().chain(&b[1]).copied());
    let positive = magnitudes
        .chain(measured)
        .chain(band)
        .filter(|v| *v > 0.0 && v.is_finite());
    let ys = Scale::log(positive)?;
    let all = || {
        let measured = fig.measured.iter().flat_map(|m| m.frequencies.iter());
        fig.frequencies.iter().chain(measured).copied()
    };
    let top = all().fold(0.0, f64::max);
    let bottom = all().filter(|f| *f > 0.0).fold(f64::INFINITY, f64::min);
    // A grid over decades on a log axis (a Bode plot), else a linear one.
    let xs = match bottom > 0.0 && top >= 20.0 * bottom {
        true => Scale::log([bottom, top]).unwrap_or(Scale::linear(0.0, top)),
        false => Scale::linear(0.0, top),
    };
    let has_coherence = !fig.measured.is_empty();
    let height = if has_coherence { 560.0 } else { 440.0 };
    let mut svg = Svg::new(860.0, height, &fig.title);
    let frame = |y: f64, h: f64, ys: Scale| Frame {
        x: 86.0,
        y,
        w: 726.0,
        h,
        xs,
        ys,
    };
    let (mag, phase) = (
        frame(30.0, 220.0, ys),
        frame(290.0, 110.0, Scale::linear(-180.0, 180.0)),
    );
    let model_stroke = Stroke::new(colour::BLUE, 1.4);
    let mut keys = vec![("model (linearised)", Key::Line(model_stroke))];
    if fig.band.is_some() {
        keys.push(("95 % band", Key::Swatch(BAND_FILL)));
    }
    let measured_keys: Vec<(String, &str)> = (fig.measured.iter().enumerate())
        .map(|(i, m)| {
            (
                format!("H1 {} (γ² ≥ {MIN_COHERENCE})", m.label),
                MEASURED[i % MEASURED.len()],
            )
        })
        .collect();
    for (label, c) in &measured_keys {
        keys.push((label.as_str(), Key::Line(Stroke::new(c, 2.4))));
    }
    legend(&mut svg, 86.0, 16.0, &keys);
    svg.text(812.0, 16.0, &fig.title, super::svg::Anchor::End);
    draw_magnitude(&mut svg, &mag, fig);
    draw_phase(&mut svg, &phase, fig);
    if has_coherence {
        let coh = frame(440.0, 80.0, Scale::linear(0.0, 1.0));
        coh.axes_with(&mut svg, "frequency (Hz)", "coherence γ²", 6, 2);
        for (i, m) in fig.measured.iter().enumerate() {
            let pts: Vec<(f64, f64)> = (m.frequencies.iter().zip(m.coherence))
                .map(|(f, g)| (coh.px(*f), coh.py_clamped(*g)))
                .collect();
            svg.path(
                &path_data(&pts),
                Stroke::new(MEASURED[i % MEASURED.len()], 1.0),
            );
        }
    }
    Some(svg.finish())
}

/// The band's fill.
const BAND_FILL: &str = "#b9d3ea";

/// The magnitude panel: band, measured curves, model.
fn draw_magnitude(svg: &mut Svg, frame: &Frame, fig: &FrfFigure<'_>) {
    frame.axes_with(svg, "", &format!("|H| ({}, log)", fig.unit), 6, 5);
    if let Some(b) = &fig.band {
        let upper = fig.frequencies.iter().zip(&b[1]);
        let lower = fig.frequencies.iter().zip(&b[0]).rev();
        let pts: Vec<(f64, f64)> = upper
            .chain(lower)
            .map(|(f, v)| (frame.px(*f), frame.py_clamped(*v)))
            .collect();
        svg.area(&path_data(&pts), BAND_FILL);
    }
    for (i, m) in fig.measured.iter().enumerate() {
        // Broken where the coherence is too low for H1 to mean anything.
        let mut run: Vec<(f64, f64)> = Vec::new();
        let stroke = Stroke::new(MEASURED[i % MEASURED.len()], 2.4);
        for ((f, h), g) in m.frequencies.iter().zip(m.h1).zip(m.coherence) {
            if *g >= MIN_COHERENCE && h.norm() > 0.0 && h.norm().is_finite() {
                run.push((frame.px(*f), frame.py_clamped(h.norm())));
            } else {
                line(svg, &run, stroke);
                run.clear();
            }
        }
        line(svg, &run, stroke);
    }
    let pts: Vec<(f64, f64)> = (fig.frequencies.iter().zip(fig.model))
        .map(|(f, h)| (frame.px(*f), frame.py_clamped(h.norm())))
        .collect();
    line(svg, &pts, Stroke::new(colour::BLUE, 1.2));
}

/// The phase panel, in degrees within ±180: the measured H1 where it is
/// coherent, and the model. (The band's phase bounds are in the CSV and
/// JSON; drawn, they would hide the curves.)
fn draw_phase(svg: &mut Svg, frame: &Frame, fig: &FrfFigure<'_>) {
    let x_title = if fig.measured.is_empty() {
        "frequency (Hz)"
    } else {
        ""
    };
    frame.axes_with(svg, x_title, "phase (°)", 6, 4);
    for (i, m) in fig.measured.iter().enumerate() {
        let pts = (m.frequencies.iter().zip(m.h1).zip(m.coherence)).map(|((f, h), g)| {
            (*g >= MIN_COHERENCE && h.norm() > 0.0).then(|| (*f, h.arg().to_degrees()))
        });
        broken_path(
            svg,
            frame,
            pts,
            Stroke::new(MEASURED[i % MEASURED.len()], 2.4),
        );
    }
    let model =
        (fig.frequencies.iter().zip(fig.model)).map(|(f, h)| Some((*f, h.arg().to_degrees())));
    broken_path(svg, frame, model, Stroke::new(colour::BLUE, 1.2));
}

/// A phase curve through `points` (frequency, degrees), broken at a gap
/// (`None`) and where the phase wraps, so no line jumps across the panel.
fn broken_path(
    svg: &mut Svg,
    frame: &Frame,
    points: impl Iterator<Item = Option<(f64, f64)>>,
    stroke: Stroke<'_>,
) {
    let mut run: Vec<(f64, f64)> = Vec::new();
    let mut last: Option<f64> = None;
    for p in points {
        let wraps = matches!((p, last), (Some((_, v)), Some(l)) if (v - l).abs() > 180.0);
        if p.is_none() || wraps {
            line(svg, &run, stroke);
            run.clear();
        }
        last = p.map(|(_, v)| v);
        if let Some((f, v)) = p {
            run.push((frame.px(f), frame.py_clamped(v)));
        }
    }
    line(svg, &run, stroke);
}

/// A line through the pixel points `pts`, kept to each pixel column's
/// first, lowest and highest points (a Welch grid of a long record has
/// many per column; the peaks survive).
fn line(svg: &mut Svg, pts: &[(f64, f64)], stroke: Stroke<'_>) {
    let mut kept: Vec<(f64, f64)> = Vec::with_capacity(pts.len().min(3000));
    let mut column: Option<(i64, usize)> = None;
    for &(x, y) in pts {
        let c = x.floor() as i64;
        match column {
            Some((col, start)) if col == c => {
                let seen = &mut kept[start..];
                if seen.len() < 3 {
                    kept.push((x, y));
                } else if y < seen[1].1.min(seen[2].1) || y > seen[1].1.max(seen[2].1) {
                    // Replace the less extreme of the two kept after the first.
                    let (lo, hi) = if seen[1].1 <= seen[2].1 {
                        (1, 2)
                    } else {
                        (2, 1)
                    };
                    let k = if y < seen[lo].1 { lo } else { hi };
                    seen[k] = (x, y);
                }
            }
            _ => {
                column = Some((c, kept.len()));
                kept.push((x, y));
            }
        }
    }
    svg.path(&path_data(&kept), stroke);
}

/// An angle in degrees brought into (−180, 180].
pub fn wrap_degrees(v: f64) -> f64 {
    let w = (v + 180.0).rem_euclid(360.0) - 180.0;
    if w == -180.0 {
        180.0
    } else {
        w
    }
}

/// The figure of pair `p` of a study (see [`frf_figure`]).
pub fn pair_figure(study: &crate::frf::FrfStudy, p: usize) -> Option<String> {
    let pair = &study.pairs[p];
    let model: Vec<C64> = pair
        .real
        .iter()
        .zip(&pair.imag)
        .map(|(r, i)| C64::new(*r, *i))
        .collect();
    let h1: Vec<Vec<C64>> = (pair.measured.iter())
        .map(|m| {
            (m.real.iter().zip(&m.imag))
                .map(|(r, i)| C64::new(*r, *i))
                .collect()
        })
        .collect();
    let fig = FrfFigure {
        title: format!("{} → {}", pair.excitation, pair.output),
        unit: pair.unit.clone(),
        frequencies: &study.frequencies_hz,
        model: &model,
        band: pair.band.as_ref().map(|b| {
            [
                b.magnitude_lo.clone(),
                b.magnitude_hi.clone(),
                b.phase_lo_deg.clone(),
                b.phase_hi_deg.clone(),
            ]
        }),
        measured: (pair.measured.iter().zip(&h1))
            .map(|(m, h)| MeasuredCurve {
                label: &m.label,
                frequencies: &m.frequencies_hz,
                h1: h,
                coherence: &m.coherence,
            })
            .collect(),
    };
    frf_figure(&fig)
}

/// Every pair's figure of a study stacked into one SVG; `None` if none
/// could be drawn.
pub fn study_svg(study: &crate::frf::FrfStudy) -> Option<String> {
    let figures: Vec<String> = (0..study.pairs.len())
        .filter_map(|p| pair_figure(study, p))
        .collect();
    stack(&figures)
}

/// SVG figures one under another, each kept whole as a nested `<svg>`.
fn stack(figures: &[String]) -> Option<String> {
    let height = |f: &str| -> f64 {
        let start = f.find("height=\"").map(|i| i + 8).unwrap_or(0);
        f[start..]
            .split('"')
            .next()
            .and_then(|v| v.parse().ok())
            .unwrap_or(0.0)
    };
    if figures.len() <= 1 {
        return figures.first().cloned();
    }
    let total: f64 = figures.iter().map(|f| height(f)).sum();
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"860\" height=\"{total}\" viewBox=\"0 0 860 {total}\">\n"
    );
    let mut y = 0.0;
    for f in figures {
        out.push_str(&f.replacen("<svg ", &format!("<svg y=\"{y}\" "), 1));
        y += height(f);
    }
    out.push_str("</svg>\n");
    Some(out)
}

/// Why a report has no FRF figure.
pub(crate) const LEFT_OUT: &str = "No FRF: a campaign's, or a model's of more than 20 \
     bodies (its FRFs take long here: use rfeid frf), or one the linearisation failed for.";

/// The most coordinates a report's FRFs are computed for (20 bodies).
const REPORT_MAX_COORDINATES: usize = 120;

/// Points of a report's FRF grid.
const REPORT_POINTS: usize = 400;

/// The report's FRF figures: each excitation to each sensor, the model
/// linearised at the estimate with its 95 % band, over the measured H1 and
/// coherence (from the excitation's own signal). None for a campaign, a
/// model over [`REPORT_MAX_COORDINATES`], or a failed linearisation.
pub(crate) fn report_figures(input: &super::ReportInput<'_>) -> Vec<super::Figure> {
    use crate::frf::{at_estimate, grid, study, DataSet, FrfRequest, Output, Spacing};
    let (model, r) = (input.model, input.result);
    let single = r.experiments.is_empty() && input.measured.n_sensors == model.sensors.len();
    if !single || model.n_dof() > REPORT_MAX_COORDINATES || model.excitations.is_empty() {
        return Vec::new();
    }
    let Ok(at) = at_estimate(r, model, "") else {
        return Vec::new();
    };
    let frequencies = grid(
        model,
        &at.params,
        None,
        None,
        Some(REPORT_POINTS),
        Spacing::Log,
    );
    let request = FrfRequest {
        model,
        params: at.params,
        wrt: at.wrt,
        covariance: at.covariance.ok(),
        excitations: (0..model.excitations.len()).collect(),
        outputs: Output::sensors(model),
        frequencies,
    };
    let data = DataSet {
        label: "measured",
        model,
        measured: input.measured,
        first: model.sampling.first_sample(r.from),
        segment: None,
        force: None,
    };
    let Ok(s) = study(&request, &[data]) else {
        return Vec::new();
    };
    (0..s.pairs.len())
        .filter_map(|p| {
            let pair = &s.pairs[p];
            let svg = pair_figure(&s, p)?;
            Some(super::Figure {
                file: format!(
                    "frf_{}_{}.svg",
                    super::file_stem(&pair.excitation),
                    super::file_stem(&pair.output)
                ),
                section: "frf",
                caption: format!(
                    "FRF from {} to {}: the model linearised at {} at the estimate (blue) with \
                     its 95 % band from the standard errors (shaded), over the measured H1 \
                     (black) and its coherence γ². A nonlinear joint's FRF holds for small \
                     motions; H1 means something only where the test excited (γ² near 1).",
                    pair.excitation, pair.output, s.linearised_at
                ),
                svg,
            })
        })
        .collect()
}
