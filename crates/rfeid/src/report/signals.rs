//! Measured against model response for each sensor (the paper's Fig. 2),
//! with a zoomed window, and the residuals `measured − model`.
use super::axis::{finite_range, legend, Frame, Key, Scale};
use super::decimate::{min_max_points, path_data};
use super::fmt::{sig, unit};
use super::svg::{colour, dash, Anchor, Stroke, Svg};

/// One sensor's signals, as the figures need them.
pub(crate) struct Channel<'a> {
    /// Sensor name.
    pub name: &'a str,
    /// Unit of the reading, typeset (`m/s²`).
    pub unit: String,
    pub measured: &'a [f64],
    pub model: &'a [f64],
}

/// Looks of the two signals: distinct in colour and in dash.
fn measured_stroke() -> Stroke<'static> {
    Stroke::new(colour::BLUE, 1.5)
}
fn model_stroke() -> Stroke<'static> {
    Stroke::new(colour::VERMILLION, 1.3).dashed(dash::DASHED)
}

/// The unit of a sensor kind, typeset.
pub(crate) fn sensor_unit(kind: crate::model::SensorKind) -> String {
    unit(kind.unit())
}

/// Index of the first sample at or after `from`.
pub(crate) fn first_sample(time: &[f64], from: f64) -> usize {
    let tol = 1e-9 * time.last().map_or(1.0, |t| t.abs().max(1.0));
    time.partition_point(|&t| t < from - tol)
}

/// The zoom window `[start, end)`: about 5 % of the record (at least 20
/// samples) where the residual energy is largest among the fitted samples;
/// the record's end when the residuals vanish.
pub(crate) fn zoom_window(measured: &[f64], model: &[f64], first: usize) -> (usize, usize) {
    let n = measured.len().min(model.len());
    let w = ((0.05 * n as f64).round() as usize).max(20).min(n);
    let first = first.min(n.saturating_sub(w));
    let r2: Vec<f64> = (0..n)
        .map(|k| {
            let d = measured[k] - model[k];
            if d.is_finite() {
                d * d
            } else {
                0.0
            }
        })
        .collect();
    let mut sum: f64 = r2[first..first + w].iter().sum();
    let (mut best, mut best_sum) = (first, sum);
    for s in first + 1..=n - w {
        sum += r2[s + w - 1] - r2[s - 1];
        if sum > best_sum * (1.0 + 1e-12) {
            best = s;
            best_sum = sum;
        }
    }
    if !(best_sum > 0.0) {
        return (n - w, n);
    }
    (best, best + w)
}

/// Draws `x, y` as a decimated path in `frame`.
fn trace(svg: &mut Svg, frame: &Frame, x: &[f64], y: &[f64], stroke: Stroke) {
    svg.path(&path_data(&min_max_points(x, y, frame)), stroke);
}

/// Shades the part of `frame` between times `a` and `b`.
fn band(svg: &mut Svg, frame: &Frame, a: f64, b: f64, fill: &str) {
    let (xa, xb) = (
        frame.px(a).clamp(frame.x, frame.x + frame.w),
        frame.px(b).clamp(frame.x, frame.x + frame.w),
    );
    if xb > xa {
        svg.rect(xa, frame.y, xb - xa, frame.h, fill, None);
    }
}

/// Light fill of the zoom window and of the unfitted lead-in.
const ZOOM_FILL: &str = "#faf6c8";
const UNFITTED_FILL: &str = "#e6e6e6";

/// Measured and model response of one sensor: the whole record, and the
/// zoom window beside it.
pub(crate) fn fit_figure(time: &[f64], ch: &Channel, from: f64) -> String {
    let n = time.len();
    let first = first_sample(time, from);
    let (z0, z1) = zoom_window(ch.measured, ch.model, first);
    let title = format!("{}: measured and model response", ch.name);
    let mut svg = Svg::new(860.0, 262.0, &title);
    let (t0, t1) = finite_range(time.iter().copied());
    let full = Frame {
        x: 72.0,
        y: 38.0,
        w: 500.0,
        h: 176.0,
        xs: Scale::linear(t0, t1),
        ys: Scale::linear_padded(ch.measured.iter().chain(ch.model).copied(), 0.05),
    };
    let zt = &time[z0..z1];
    let zoom = Frame {
        x: 638.0,
        w: 200.0,
        xs: Scale::linear(zt[0], zt[zt.len() - 1]),
        ys: Scale::linear_padded(
            ch.measured[z0..z1].iter().chain(&ch.model[z0..z1]).copied(),
            0.08,
        ),
        ..full
    };
    let mut items = vec![
        ("measured", Key::Line(measured_stroke())),
        ("model at the estimate", Key::Line(model_stroke())),
        ("zoom window", Key::Swatch(ZOOM_FILL)),
    ];
    if first > 0 {
        items.push(("not fitted (before `from`)", Key::Swatch(UNFITTED_FILL)));
    }
    legend(&mut svg, 72.0, 16.0, &items);
    if first > 0 {
        band(&mut svg, &full, t0, time[first.min(n - 1)], UNFITTED_FILL);
    }
    band(&mut svg, &full, zt[0], zt[zt.len() - 1], ZOOM_FILL);
    let y_title = format!("{}, {}", ch.name, ch.unit);
    full.axes(&mut svg, "time t, s", &y_title);
    trace(&mut svg, &full, time, ch.measured, measured_stroke());
    trace(&mut svg, &full, time, ch.model, model_stroke());
    zoom.axes_with(&mut svg, "time t, s (zoom)", "", 3, 5);
    trace(&mut svg, &zoom, zt, &ch.measured[z0..z1], measured_stroke());
    trace(&mut svg, &zoom, zt, &ch.model[z0..z1], model_stroke());
    svg.text(
        zoom.x,
        zoom.y - 6.0,
        &format!("zoom: {}–{} s", sig(zt[0], 3), sig(zt[zt.len() - 1], 3)),
        Anchor::Start,
    );
    svg.finish()
}

/// Residuals `measured − model` of every sensor, one panel each, with each
/// sensor's RMS and largest residual over the fitted samples.
pub(crate) fn residual_figure(time: &[f64], channels: &[Channel], from: f64) -> String {
    let n = time.len();
    let first = first_sample(time, from);
    let panel_h = 96.0;
    let step = panel_h + 44.0;
    let height = 30.0 + step * channels.len() as f64 + 6.0;
    let mut svg = Svg::new(860.0, height, "Residuals, measured − model");
    let mut items = vec![(
        "measured − model",
        Key::Line(Stroke::new(colour::GREEN, 1.0)),
    )];
    if first > 0 {
        items.push(("not fitted (before `from`)", Key::Swatch(UNFITTED_FILL)));
    }
    legend(&mut svg, 72.0, 16.0, &items);
    let (t0, t1) = finite_range(time.iter().copied());
    for (c, ch) in channels.iter().enumerate() {
        let r: Vec<f64> = ch
            .measured
            .iter()
            .zip(ch.model)
            .map(|(a, b)| a - b)
            .collect();
        let used = &r[first.min(n)..];
        let rms = (used.iter().map(|v| v * v).sum::<f64>() / used.len().max(1) as f64).sqrt();
        let peak = used.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let signal = &ch.measured[first.min(n)..];
        let signal_rms =
            (signal.iter().map(|v| v * v).sum::<f64>() / signal.len().max(1) as f64).sqrt();
        let frame = Frame {
            x: 72.0,
            y: 44.0 + step * c as f64,
            w: 620.0,
            h: panel_h,
            xs: Scale::linear(t0, t1),
            ys: Scale::symmetric(r.iter().copied(), 0.08),
        };
        if first > 0 {
            band(&mut svg, &frame, t0, time[first.min(n - 1)], UNFITTED_FILL);
        }
        frame.axes_with(&mut svg, "time t, s", &ch.unit, 6, 4);
        svg.line(
            frame.x,
            frame.py(0.0),
            frame.x + frame.w,
            frame.py(0.0),
            Stroke::new(colour::INK, 0.8),
        );
        trace(&mut svg, &frame, time, &r, Stroke::new(colour::GREEN, 1.0));
        svg.text_styled(
            frame.x,
            frame.y - 6.0,
            ch.name,
            Anchor::Start,
            12.0,
            colour::INK,
            "font-weight=\"bold\"",
        );
        let right = frame.x + frame.w + 14.0;
        svg.text(
            right,
            frame.y + 12.0,
            &format!("RMS, {}", ch.unit),
            Anchor::Start,
        );
        svg.text(right, frame.y + 26.0, &sig(rms, 3), Anchor::Start);
        if signal_rms > 0.0 {
            let pct = format!("{} % of signal RMS", sig(100.0 * rms / signal_rms, 2));
            svg.text(right, frame.y + 40.0, &pct, Anchor::Start);
        }
        svg.text(right, frame.y + 62.0, "largest |r|", Anchor::Start);
        svg.text(right, frame.y + 76.0, &sig(peak, 3), Anchor::Start);
    }
    svg.finish()
}

/// Simulated responses, one panel per sensor, for `rfeid simulate --plot`:
/// `(name, unit, signal)` per sensor, all on the time axis `time`.
pub(crate) fn response_figure(time: &[f64], channels: &[(&str, String, &[f64])]) -> String {
    let panel_h = 110.0;
    let step = panel_h + 44.0;
    let height = 20.0 + step * channels.len() as f64 + 6.0;
    let mut svg = Svg::new(860.0, height, "Simulated response");
    let (t0, t1) = finite_range(time.iter().copied());
    for (c, (name, unit, y)) in channels.iter().enumerate() {
        let frame = Frame {
            x: 72.0,
            y: 30.0 + step * c as f64,
            w: 740.0,
            h: panel_h,
            xs: Scale::linear(t0, t1),
            ys: Scale::symmetric(y.iter().copied(), 0.08),
        };
        frame.axes_with(&mut svg, "time t, s", unit, 8, 4);
        trace(&mut svg, &frame, time, y, measured_stroke());
        let rms = (y.iter().map(|v| v * v).sum::<f64>() / y.len().max(1) as f64).sqrt();
        svg.text_styled(
            frame.x,
            frame.y - 6.0,
            &format!("{name}   (RMS {} {unit})", sig(rms, 3)),
            Anchor::Start,
            12.0,
            colour::INK,
            "font-weight=\"bold\"",
        );
    }
    svg.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zoom_window_finds_the_largest_residuals() {
        let n = 1000;
        let m: Vec<f64> = (0..n).map(|k| (k as f64 * 0.1).sin()).collect();
        let mut f = m.clone();
        f[700] += 1.0;
        let (a, b) = zoom_window(&m, &f, 0);
        assert_eq!(b - a, 50);
        assert!(a <= 700 && 700 < b);
        // No residual: the record's end.
        assert_eq!(zoom_window(&m, &m, 0), (950, 1000));
        // Samples before `first` are not candidates.
        f[10] += 5.0;
        let (a, _) = zoom_window(&m, &f, 100);
        assert!(a >= 100);
    }

    #[test]
    fn first_sample_tolerates_rounding() {
        let t: Vec<f64> = (0..10).map(|k| k as f64 * 0.1).collect();
        assert_eq!(first_sample(&t, 0.0), 0);
        assert_eq!(first_sample(&t, 0.3), 3);
    }
}
