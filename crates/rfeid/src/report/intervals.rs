//! The parameters drawn as intervals inside their boxes: each parameter a
//! row, its box `[min, max]` normalised to [0, 1] (eq. 17), the nominal value
//! as a tick, the estimate as a dot with ±1 and ±3 standard-error whiskers
//! (eq. 26), and the reference value as a diamond.
use super::axis::{legend, Frame, Key, Scale};
use super::fmt::{sig, unit};
use super::svg::{colour, text_width, Anchor, Marker, Stroke, Svg, FONT_SIZE};
use crate::identification::result::ParameterEstimate;

/// Fill of a parameter's box.
const BOX_FILL: &str = "#d9d9d9";

/// The visible range around the box; whiskers beyond it end in an arrow.
const LO: f64 = -0.15;
const HI: f64 = 1.15;

/// `estimate ± se unit` in the parameter's display unit.
pub(crate) fn estimate_text(p: &ParameterEstimate) -> String {
    let s = p.unit_scale;
    let u = unit(&p.unit);
    let mut t = sig(p.estimate / s, 4);
    if let Some(se) = p.std_error {
        t.push_str(&format!(" ± {}", sig(se / s, 2)));
    }
    if !u.is_empty() {
        t.push(' ');
        t.push_str(&u);
    }
    t
}

/// An arrow head pointing left (`dir = −1`) or right (`dir = 1`) at (x, y).
fn arrow(svg: &mut Svg, x: f64, y: f64, dir: f64, c: &str) {
    let d = format!(
        "M{} {}l{} {}l{} {}",
        super::svg::num(x - 6.0 * dir),
        super::svg::num(y - 4.0),
        super::svg::num(6.0 * dir),
        "4",
        super::svg::num(-6.0 * dir),
        "4"
    );
    svg.path(&d, Stroke::new(c, 1.5));
}

/// Height of a parameter's row.
const ROW_H: f64 = 24.0;
/// Top of the rows.
const TOP: f64 = 56.0;

/// The interval chart.
pub(crate) fn interval_figure(params: &[ParameterEstimate], reference: Option<&[f64]>) -> String {
    let height = TOP + ROW_H * params.len() as f64 + 44.0;
    let mut svg = Svg::new(860.0, height, "Estimates within their boxes");
    let frame = interval_frame(params);
    let any_se = params.iter().any(|p| p.std_error.is_some());
    interval_legend(&mut svg, any_se, reference.is_some());
    interval_axes(&mut svg, &frame, params.len(), any_se);
    let right = frame.x + frame.w + 12.0;
    for (j, p) in params.iter().enumerate() {
        let reference = reference.and_then(|r| r.get(j)).copied();
        interval_row(&mut svg, &frame, j, p, reference);
        let y = TOP + ROW_H * (j as f64 + 0.5);
        svg.text(right, y + 4.0, &estimate_text(p), Anchor::Start);
    }
    svg.finish()
}

/// The frame of the rows: box positions across, one row per parameter,
/// leaving room for the names on the left.
fn interval_frame(params: &[ParameterEstimate]) -> Frame {
    let label_w = params
        .iter()
        .map(|p| text_width(&p.name, FONT_SIZE))
        .fold(40.0, f64::max)
        + 24.0;
    Frame {
        x: label_w,
        y: TOP,
        w: 630.0 - label_w.min(300.0),
        h: ROW_H * params.len() as f64,
        xs: Scale::Linear { lo: LO, hi: HI },
        ys: Scale::Linear {
            lo: 0.0,
            hi: params.len().max(1) as f64,
        },
    }
}

/// The legend: the whiskers if there are standard errors, the diamond if
/// there is a reference.
fn interval_legend(svg: &mut Svg, any_se: bool, with_reference: bool) {
    let mut items = vec![
        ("box", Key::Swatch(BOX_FILL)),
        ("nominal", Key::Tick(Stroke::new(colour::INK, 2.0))),
        ("estimate", Key::Point(Marker::Dot, colour::BLUE)),
    ];
    if any_se {
        items.push(("±1 s.e.", Key::Line(Stroke::new(colour::BLUE, 4.0))));
        items.push(("±3 s.e.", Key::Line(Stroke::new(colour::BLUE, 1.0))));
    }
    if with_reference {
        items.push(("reference", Key::Point(Marker::Diamond, colour::ORANGE)));
    }
    legend(svg, 16.0, 18.0, &items);
}

/// Every other row shaded, the axes, and the title of the estimates' column.
fn interval_axes(svg: &mut Svg, frame: &Frame, rows: usize, any_se: bool) {
    for j in (1..rows).step_by(2) {
        svg.rect(
            frame.x,
            TOP + ROW_H * j as f64,
            frame.w,
            ROW_H,
            "#f6f6f6",
            None,
        );
    }
    frame.axes_with(svg, "position in the box: 0 = min, 1 = max", "", 6, 0);
    let right = frame.x + frame.w + 12.0;
    svg.text_styled(
        right,
        TOP - 8.0,
        if any_se {
            "estimate ± s.e."
        } else {
            "estimate (no standard errors)"
        },
        Anchor::Start,
        FONT_SIZE,
        colour::INK,
        "font-weight=\"bold\"",
    );
}

/// Parameter j's row: its name, box, nominal tick, whiskers, reference
/// diamond and estimate dot.
fn interval_row(
    svg: &mut Svg,
    frame: &Frame,
    j: usize,
    p: &ParameterEstimate,
    reference: Option<f64>,
) {
    let x_of = |v: f64| frame.px(v.clamp(LO, HI));
    let y = TOP + ROW_H * (j as f64 + 0.5);
    let width = p.max - p.min;
    let norm = |x: f64| {
        if width > 0.0 {
            (x - p.min) / width
        } else {
            0.5
        }
    };
    svg.text(frame.x - 8.0, y + 4.0, &p.name, Anchor::End);
    svg.rect(
        x_of(0.0),
        y - 5.0,
        x_of(1.0) - x_of(0.0),
        10.0,
        BOX_FILL,
        None,
    );
    let nominal = x_of(norm(p.nominal));
    svg.line(
        nominal,
        y - 8.0,
        nominal,
        y + 8.0,
        Stroke::new(colour::INK, 2.0),
    );
    let e = norm(p.estimate);
    if let Some(se) = p.std_error.filter(|s| s.is_finite() && width > 0.0) {
        whiskers(svg, frame, y, e, se / width);
    }
    if let Some(r) = reference {
        svg.marker(Marker::Diamond, x_of(norm(r)), y, 6.0, colour::ORANGE);
    }
    svg.marker(Marker::Dot, x_of(e), y, 4.0, colour::BLUE);
}

/// The ±3 and ±1 standard-error whiskers about the normalised estimate e
/// (s: the standard error normalised), the outer ones ending in a tick, or
/// an arrow beyond the visible range.
fn whiskers(svg: &mut Svg, frame: &Frame, y: f64, e: f64, s: f64) {
    let x_of = |v: f64| frame.px(v.clamp(LO, HI));
    for (k, w) in [(3.0, 1.0), (1.0, 4.0)] {
        let (a, b) = (e - k * s, e + k * s);
        svg.line(x_of(a), y, x_of(b), y, Stroke::new(colour::BLUE, w));
        if k == 3.0 {
            for (v, dir) in [(a, -1.0), (b, 1.0)] {
                if !(LO..=HI).contains(&v) {
                    arrow(svg, x_of(v), y, dir, colour::BLUE);
                } else {
                    svg.line(
                        x_of(v),
                        y - 4.0,
                        x_of(v),
                        y + 4.0,
                        Stroke::new(colour::BLUE, 1.0),
                    );
                }
            }
        }
    }
}
