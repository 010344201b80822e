//! The report of `rfeid design`: the candidate points on the bodies (a 3-D
//! view projected to SVG, placed and chosen sensors marked) and the
//! predicted relative standard errors, placed against chosen (the chosen
//! alone when no sensor is placed: they are compared with no sensor).
use super::fmt::sig;
use super::html::{table, CSS};
use super::svg::{colour, escape, Anchor, Marker, Stroke, Svg};
use crate::design::Design;
use crate::model::{Model, Sensor};
use nalgebra::Vector3;
use std::fmt::Write as _;

/// The report's files (name, text): `report.html`, `sensors.svg`,
/// `std-errors.svg`.
pub fn design_report_files(model: &Model, d: &Design, title: &str) -> Vec<(String, String)> {
    let sensors = sensors_figure(model, d);
    let bars = std_error_figure(d);
    let html = page(model, d, title);
    vec![
        ("report.html".into(), html),
        ("sensors.svg".into(), sensors),
        ("std-errors.svg".into(), bars),
    ]
}

/// An isometric projection: x to the lower right, y to the lower left, z up.
fn project(p: &Vector3<f64>) -> (f64, f64) {
    let c = std::f64::consts::FRAC_PI_6.cos();
    let s = std::f64::consts::FRAC_PI_6.sin();
    ((p.x - p.y) * c, p.z + (p.x + p.y) * s)
}

/// The bodies' centres, placed sensors, candidates and the chosen ones,
/// each sensor with a short arrow along its direction.
fn sensors_figure(model: &Model, d: &Design) -> String {
    let chosen = d.chosen.as_ref().map_or(&[][..], |c| c.chosen.as_slice());
    let mut points: Vec<Vector3<f64>> = model.bodies.iter().map(|b| b.com).collect();
    points.extend(model.sensors.iter().chain(&model.candidates).map(|s| s.at));
    let flat: Vec<(f64, f64)> = points.iter().map(project).collect();
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in &flat {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    let span = (x1 - x0).max(y1 - y0).max(1e-3);
    let (w, h, pad): (f64, f64, f64) = (720.0, 560.0, 60.0);
    let k = (w - 2.0 * pad).min(h - 2.0 * pad) / span;
    let to_px = |p: &Vector3<f64>| {
        let (x, y) = project(p);
        (pad + (x - x0) * k, h - pad - (y - y0) * k)
    };
    let arrow = 0.06 * span;
    let mut svg = Svg::new(w, h, "Sensor positions (isometric view)");
    legend(&mut svg);
    for b in &model.bodies {
        let (x, y) = to_px(&b.com);
        svg.marker(Marker::Ring, x, y, 9.0, colour::INK);
        svg.text(x + 12.0, y - 10.0, &b.name, Anchor::Start);
    }
    let mut draw = |s: &Sensor, col: &str, m: Marker, label: bool| {
        let (x, y) = to_px(&s.at);
        let (ax, ay) = to_px(&(s.at + s.direction * arrow));
        svg.line(x, y, ax, ay, Stroke::new(col, 1.2));
        svg.marker(m, x, y, 4.0, col);
        if label {
            svg.text(ax + 3.0, ay - 3.0, &s.name, Anchor::Start);
        }
    };
    for (i, s) in model.candidates.iter().enumerate() {
        if !chosen.contains(&i) {
            draw(s, "#9a9a9a", Marker::Ring, false);
        }
    }
    for s in &model.sensors {
        draw(s, colour::BLUE, Marker::Dot, true);
    }
    for &i in chosen {
        draw(
            &model.candidates[i],
            colour::VERMILLION,
            Marker::Diamond,
            true,
        );
    }
    svg.finish()
}

/// The legend of the sensor figure.
fn legend(svg: &mut Svg) {
    let items = [
        (Marker::Dot, colour::BLUE, "placed sensor"),
        (Marker::Diamond, colour::VERMILLION, "chosen candidate"),
        (Marker::Ring, "#9a9a9a", "other candidate"),
        (Marker::Ring, colour::INK, "body centre of mass"),
    ];
    for (j, (m, col, text)) in items.iter().enumerate() {
        let y = 22.0 + 16.0 * j as f64;
        svg.marker(*m, 18.0, y - 4.0, 4.0, col);
        svg.text(30.0, y, text, Anchor::Start);
    }
}

/// Bars of predicted relative standard errors (%), placed and chosen, one
/// row per parameter; the axis is logarithmic when they span a decade.
fn std_error_figure(d: &Design) -> String {
    let names = &d.parts.columns;
    let placed = d
        .placed
        .as_ref()
        .map_or(&[][..], |p| &p.relative_std_errors);
    let chosen = d.chosen.as_ref().map(|c| &c.prediction.relative_std_errors);
    let row_h = 26.0;
    let (label_w, bar_w, top) = (120.0, 520.0, 40.0);
    let h = top + row_h * names.len() as f64 + 30.0;
    let mut svg = Svg::new(
        label_w + bar_w + 120.0,
        h,
        "Predicted relative standard errors",
    );
    let all: Vec<f64> = placed
        .iter()
        .chain(chosen.into_iter().flatten())
        .map(|v| 100.0 * v)
        .filter(|v| v.is_finite() && *v > 0.0)
        .collect();
    let max = all.iter().copied().fold(0.0, f64::max).max(1e-12);
    let min = all.iter().copied().fold(f64::MAX, f64::min).min(max);
    let log = max / min > 10.0;
    let lo = if log {
        min.log10().floor().min(max.log10() - 1.0)
    } else {
        0.0
    };
    let frac = |v: f64| {
        if log {
            ((v.log10() - lo) / (max.log10() - lo)).clamp(0.0, 1.0)
        } else {
            (v / max).clamp(0.0, 1.0)
        }
    };
    svg.text(
        label_w,
        20.0,
        &format!(
            "relative standard error, % ({} axis); {}",
            if log { "logarithmic" } else { "linear" },
            match (d.placed.is_some(), chosen.is_some()) {
                (true, true) => "blue: placed sensors, vermillion: with the chosen ones",
                (true, false) => "blue: placed sensors",
                (false, _) => "vermillion: the chosen sensors (none placed)",
            }
        ),
        Anchor::Start,
    );
    for (j, name) in names.iter().enumerate() {
        let y = top + row_h * j as f64;
        svg.text(label_w - 8.0, y + 15.0, name, Anchor::End);
        let mut bar = |v: Option<&f64>, dy: f64, col: &str| {
            if let Some(v) = v.map(|v| 100.0 * v).filter(|v| v.is_finite() && *v > 0.0) {
                svg.rect(label_w, y + dy, bar_w * frac(v), 9.0, col, None);
                svg.text(
                    label_w + bar_w * frac(v) + 4.0,
                    y + dy + 8.0,
                    &sig(v, 3),
                    Anchor::Start,
                );
            }
        };
        bar(placed.get(j), 2.0, colour::BLUE);
        bar(chosen.and_then(|c| c.get(j)), 13.0, colour::VERMILLION);
    }
    svg.finish()
}

/// The page: the predictions as a table, the certificate, the figures.
fn page(model: &Model, d: &Design, title: &str) -> String {
    let mut out = String::new();
    let _ = write!(
        out,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>design: {t} — rfeid</title>\n<style>{CSS}</style>\n</head>\n<body>\n\
         <h1>Experiment design: {t}</h1>\n",
        t = escape(title)
    );
    summary_html(&mut out, model, d);
    let rows: Vec<Vec<String>> = d
        .parts
        .columns
        .iter()
        .enumerate()
        .map(|(j, n)| {
            let pct = |v: Option<&f64>| {
                v.filter(|v| v.is_finite())
                    .map_or("-".into(), |v| sig(100.0 * v, 3))
            };
            let mut row = vec![escape(n), sig(d.parts.values[j], 4)];
            if let Some(p) = &d.placed {
                row.push(pct(p.relative_std_errors.get(j)));
            }
            if let Some(c) = &d.chosen {
                row.push(pct(c.prediction.relative_std_errors.get(j)));
            }
            row
        })
        .collect();
    warnings_html(&mut out, d);
    let mut header = vec!["parameter", "value (SI)"];
    if d.placed.is_some() {
        header.push("rel. s.e. placed, %");
    }
    if d.chosen.is_some() {
        header.push("rel. s.e. chosen, %");
    }
    out.push_str(&table(&header, &rows, &[false, true, true, true], &[]));
    for (file, caption) in [
        (
            "sensors.svg",
            "Placed, candidate and chosen sensors on the bodies",
        ),
        ("std-errors.svg", "Predicted relative standard errors"),
    ] {
        let _ = writeln!(
            out,
            "<figure><img src=\"{file}\" alt=\"{caption}\"><figcaption>{caption}</figcaption></figure>"
        );
    }
    out.push_str("</body>\n</html>\n");
    out
}

/// The paragraphs on what is predicted: the placed sensors (or none: the
/// choice is then compared with no sensor), the chosen ones and the
/// certificate.
fn summary_html(out: &mut String, model: &Model, d: &Design) {
    let placed: Vec<String> = model.sensors.iter().map(|s| escape(&s.name)).collect();
    let _ = writeln!(
        out,
        "<p>Predicted at the parameters' values with each sensor's <code>noise</code> as its σ \
         (Cramér–Rao bound, eq. 26–29). Placed sensors: {}.</p>",
        match placed.is_empty() {
            true =>
                "none (every sensor is a candidate: the choice is compared with no sensor)".into(),
            false => placed.join(", "),
        }
    );
    if let Some(c) = &d.chosen {
        let from = match &d.placed {
            Some(p) => format!("rises from {:.3} to", p.log_det),
            None => "is".into(),
        };
        let _ = writeln!(
            out,
            "<p>Chosen: <b>{}</b>. log det F {from} {:.3}; no set of {} exceeds {:.3} \
             (convex relaxation), so the choice's D-efficiency is at least {:.4}.</p>",
            c.names
                .iter()
                .map(|n| escape(n))
                .collect::<Vec<_>>()
                .join(", "),
            c.prediction.log_det,
            c.chosen.len(),
            c.upper_bound,
            c.efficiency_at_least
        );
    }
}

/// The predictions' warnings (and why there are no standard errors), as
/// paragraphs.
fn warnings_html(out: &mut String, d: &Design) {
    for (what, p) in d
        .placed
        .as_ref()
        .map(|p| ("placed", p))
        .into_iter()
        .chain(d.chosen.as_ref().map(|c| ("chosen", &c.prediction)))
    {
        for w in crate::design::predict::warning_texts(&d.parts.columns, p) {
            let _ = writeln!(
                out,
                "<p class=\"flag\">warning ({what}): {}</p>",
                escape(&w)
            );
        }
    }
}
