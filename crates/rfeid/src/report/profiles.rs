//! The profile likelihoods (`--profiles`): for each profiled parameter,
//! ΔJ/s² (ΔJ/(κ s²): [`ParameterProfile::variance_ratio`]) against its value, the χ²₁(0.95) threshold that bounds its
//! likelihood-ratio interval, the Wald parabola `((x − x̂)/σ)²` of its
//! Cramér–Rao standard error (eq. 26) for comparison, and the estimate.
use super::axis::{legend, Frame, Key, Scale};
use super::fmt::{sig, unit};
use super::svg::{colour, dash, Anchor, Marker, Stroke, Svg};
use crate::identification::profile::{IntervalEnd, ParameterProfile};

/// Points of the drawn Wald parabola.
const PARABOLA_POINTS: usize = 120;

/// The figure of one profile; `unit_scale` and `unit_symbol` are the
/// parameter's display unit (as in the parameter table).
pub(crate) fn profile_figure(p: &ParameterProfile, unit_scale: f64, unit_symbol: &str) -> String {
    let title = format!("Profile likelihood of {}", p.name);
    let mut svg = Svg::new(860.0, 290.0, &title);
    let stat = p.statistic();
    let show = |x: f64| x / unit_scale;
    let xs = Scale::linear_padded(p.points.iter().map(|q| show(q.value)), 0.02);
    let top = stat
        .iter()
        .flatten()
        .copied()
        .fold(1.3 * p.threshold, f64::max);
    let frame = Frame {
        x: 72.0,
        y: 40.0,
        w: 740.0,
        h: 196.0,
        xs,
        ys: Scale::linear(0.0, top),
    };
    let failed = stat.iter().any(Option::is_none);
    profile_legend(&mut svg, p.std_error.is_some(), failed);
    let u = unit(unit_symbol);
    let x_title = match u.is_empty() {
        true => p.name.clone(),
        false => format!("{} ({u})", p.name),
    };
    let y_title = match p.variance_ratio == 1.0 {
        true => "ΔJ / s²".to_string(),
        false => format!("ΔJ / (κ s²), κ = {}", sig(p.variance_ratio, 3)),
    };
    frame.axes(&mut svg, &x_title, &y_title);
    threshold_line(&mut svg, &frame, p.threshold);
    if let Some(se) = p.std_error {
        wald_parabola(&mut svg, &frame, show(p.estimate), show(se));
    }
    profile_curve(&mut svg, &frame, p, &stat, unit_scale);
    let x_hat = frame.px(show(p.estimate));
    svg.line(
        x_hat,
        frame.y,
        x_hat,
        frame.y + frame.h,
        Stroke::new(colour::BLACK, 1.0),
    );
    // At the top of the middle, where the profile is lowest.
    svg.text(
        frame.x + 0.5 * frame.w,
        frame.y + 16.0,
        &interval_text(p, unit_scale, &u),
        Anchor::Middle,
    );
    svg.finish()
}

/// The legend (the Wald parabola only with a standard error, the failed
/// refits' mark only if one failed).
fn profile_legend(svg: &mut Svg, with_wald: bool, failed: bool) {
    let mut items = vec![
        (
            "profile: J minimised over the others",
            Key::Line(Stroke::new(colour::BLUE, 1.4)),
        ),
        (
            "χ²₁(0.95) threshold",
            Key::Line(Stroke::new(colour::VERMILLION, 1.2).dashed(dash::DASHED)),
        ),
        ("estimate", Key::Tick(Stroke::new(colour::BLACK, 1.0))),
    ];
    if failed {
        items.push((
            "failed refit",
            Key::Point(Marker::Cross, colour::VERMILLION),
        ));
    }
    if with_wald {
        items.insert(
            1,
            (
                "Wald: ((x − x̂)/σ)²",
                Key::Line(Stroke::new(colour::ORANGE, 1.2).dashed(dash::DASHED)),
            ),
        );
    }
    legend(svg, 72.0, 16.0, &items);
}

/// The threshold as a dashed horizontal line.
fn threshold_line(svg: &mut Svg, frame: &Frame, threshold: f64) {
    let y = frame.py(threshold);
    svg.line(
        frame.x,
        y,
        frame.x + frame.w,
        y,
        Stroke::new(colour::VERMILLION, 1.2).dashed(dash::DASHED),
    );
}

/// The Wald parabola `((x − x̂)/σ)²` over the frame (display units).
fn wald_parabola(svg: &mut Svg, frame: &Frame, x_hat: f64, se: f64) {
    if !(se > 0.0 && se.is_finite()) {
        return;
    }
    let (lo, hi) = match frame.xs {
        Scale::Linear { lo, hi } => (lo, hi),
        _ => return,
    };
    let pts: Vec<(f64, f64)> = (0..=PARABOLA_POINTS)
        .map(|k| lo + (hi - lo) * k as f64 / PARABOLA_POINTS as f64)
        .map(|x| (frame.px(x), frame.py_clamped(((x - x_hat) / se).powi(2))))
        .collect();
    svg.path(
        &super::decimate::path_data(&pts),
        Stroke::new(colour::ORANGE, 1.2).dashed(dash::DASHED),
    );
}

/// The profile's points joined (through the failed ones, which are
/// crosses at the top).
fn profile_curve(
    svg: &mut Svg,
    frame: &Frame,
    p: &ParameterProfile,
    stat: &[Option<f64>],
    unit_scale: f64,
) {
    let pts: Vec<(f64, f64)> = p
        .points
        .iter()
        .zip(stat)
        .filter_map(|(q, d)| d.map(|d| (frame.px(q.value / unit_scale), frame.py_clamped(d))))
        .collect();
    svg.path(
        &super::decimate::path_data(&pts),
        Stroke::new(colour::BLUE, 1.4),
    );
    for &(x, y) in &pts {
        svg.marker(Marker::Dot, x, y, 2.6, colour::BLUE);
    }
    for q in p.points.iter().zip(stat).filter(|(_, d)| d.is_none()) {
        let x = frame.px(q.0.value / unit_scale);
        svg.marker(Marker::Cross, x, frame.y + 6.0, 4.0, colour::VERMILLION);
    }
}

/// `profile 95 %: lo … hi  Wald: lo … hi unit`.
fn interval_text(p: &ParameterProfile, unit_scale: f64, u: &str) -> String {
    let show = |x: f64| sig(x / unit_scale, 4);
    let end = |e: &IntervalEnd, side: &str| match e {
        IntervalEnd::Crossed { value } => show(*value),
        IntervalEnd::Open { .. } => format!("open at {side}"),
        IntervalEnd::Unresolved { last } => format!("? beyond {}", show(*last)),
    };
    let mut t = format!(
        "profile 95 %: {} … {}",
        end(&p.lower, "min"),
        end(&p.upper, "max")
    );
    if let Some([lo, hi]) = p.wald {
        t.push_str(&format!("   Wald: {} … {}", show(lo), show(hi)));
    }
    if !u.is_empty() {
        t.push(' ');
        t.push_str(u);
    }
    t
}
