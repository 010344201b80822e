//! Each sensor's residual spectrum (Welch) against the spectrum of its noise
//! model, so a user sees at which frequencies the model misfits: where the
//! residuals rise above the noise model, the misfit is in the dynamics.
use super::axis::{legend, Frame, Key, Scale};
use super::svg::{colour, dash, Stroke, Svg};
use crate::identification::noise::SensorNoise;
use crate::measurement::spectrum::welch;

/// Samples per Welch segment.
const SEGMENT: usize = 1024;

/// One sensor's residuals `e` (from the first sample used) at `fs` Hz and
/// its noise model; `None` when the record is too short for a spectrum.
pub(crate) fn spectrum_figure(
    name: &str,
    unit: &str,
    e: &[f64],
    fs: f64,
    noise: Option<&SensorNoise>,
) -> Option<String> {
    let s = welch(e, fs, SEGMENT)?;
    let pairs: Vec<(f64, f64)> = s
        .frequencies
        .iter()
        .zip(&s.density)
        .skip(1)
        .map(|(f, d)| (*f, *d))
        .filter(|(_, d)| *d > 0.0)
        .collect();
    let model: Vec<(f64, f64)> = match noise {
        Some(n) => {
            let ar = n.ar_model();
            pairs
                .iter()
                .map(|(f, _)| (*f, ar.density(*f, fs)))
                .collect()
        }
        None => Vec::new(),
    };
    let ys = Scale::log(pairs.iter().chain(&model).map(|p| p.1))?;
    let title = format!("{name}: residual spectrum");
    let mut svg = Svg::new(860.0, 260.0, &title);
    let frame = Frame {
        x: 86.0,
        y: 30.0,
        w: 726.0,
        h: 180.0,
        xs: Scale::linear(0.0, fs / 2.0),
        ys,
    };
    let residual = Stroke::new(colour::BLUE, 1.0);
    let noise_stroke = Stroke::new(colour::VERMILLION, 1.4).dashed(dash::DASHED);
    let mut keys = vec![("residuals (Welch)", Key::Line(residual))];
    if !model.is_empty() {
        keys.push(("noise model", Key::Line(noise_stroke)));
    }
    legend(&mut svg, 86.0, 16.0, &keys);
    frame.axes(
        &mut svg,
        "frequency (Hz)",
        &format!("density ({unit}²/Hz, log)"),
    );
    let path = |pts: &[(f64, f64)]| {
        let px: Vec<(f64, f64)> = pts
            .iter()
            .map(|(f, d)| (frame.px(*f), frame.py_clamped(*d)))
            .collect();
        super::decimate::path_data(&px)
    };
    svg.path(&path(&pairs), residual);
    if !model.is_empty() {
        svg.path(&path(&model), noise_stroke);
    }
    Some(svg.finish())
}
