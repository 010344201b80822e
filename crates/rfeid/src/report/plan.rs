//! The LP_τ plan's criterion values sorted ("waterfall", eq. 18–19): how
//! many plan points came close to the best, where the local search started,
//! and which points failed to simulate.
use super::axis::{legend, Frame, Key, Scale};
use super::decimate::{min_max_points, path_data};
use super::fmt::sig;
use super::svg::{colour, dash, Anchor, Marker, Stroke, Svg, FONT_SIZE, HALO};
use crate::identification::result::PlanSummary;

/// Above this many points the sorted values are drawn as a line, not dots.
const MAX_DOTS: usize = 400;
/// Above this many failures they are drawn as one band, not crosses.
const MAX_CROSSES: usize = 200;

/// Light fill of the strip that holds the failed points.
const FAILED_FILL: &str = "#fbe5d9";

/// The waterfall: sorted finite J on a log axis (linear if some J ≤ 0),
/// failed points as crosses in a strip at the top, the start point(s)
/// ringed, and the final J as a dashed line. Abandoned points (their J
/// above the best ones', not computed) are counted in the title only.
pub(crate) fn plan_figure(plan: &PlanSummary, final_cost: f64) -> String {
    let ok = sorted_finite(plan);
    let shown = plan.costs.len() - plan.abandoned.len().min(plan.costs.len());
    let n_failed = shown.saturating_sub(ok.len());
    let abandoned = match plan.abandoned.len() {
        0 => String::new(),
        n => format!(", {n} abandoned"),
    };
    let title = format!(
        "LP_τ plan: criterion J at {} points, sorted ({} failed{abandoned})",
        plan.costs.len(),
        n_failed
    );
    let mut svg = Svg::new(860.0, 318.0, &title);
    let (frame, log) = plan_frame(&ok, shown, final_cost);
    plan_legend(&mut svg);
    let y_title = if log {
        "criterion J (log)"
    } else {
        "criterion J"
    };
    frame.axes(&mut svg, "plan points, sorted by J (rank)", y_title);
    failed_strip(&mut svg, &frame, ok.len(), ok.len() + n_failed);
    sorted_costs(&mut svg, &frame, &ok);
    final_cost_line(&mut svg, &frame, final_cost);
    start_rings(&mut svg, &frame, &ok, &plan.starts);
    svg.finish()
}

/// The plan points with a finite J, as (point, J), sorted by J.
fn sorted_finite(plan: &PlanSummary) -> Vec<(usize, f64)> {
    let mut ok: Vec<(usize, f64)> = plan
        .costs
        .iter()
        .enumerate()
        .filter_map(|(i, c)| c.filter(|v| v.is_finite()).map(|v| (i, v)))
        .collect();
    ok.sort_by(|a, b| a.1.total_cmp(&b.1));
    ok
}

/// The frame of ranks 1 … n_points against J, and whether J's axis is
/// logarithmic (when every J is positive).
fn plan_frame(ok: &[(usize, f64)], n_points: usize, final_cost: f64) -> (Frame, bool) {
    let n_total = n_points.max(1);
    let values = ok.iter().map(|p| p.1).chain([final_cost]);
    let all_positive = ok.iter().all(|p| p.1 > 0.0) && final_cost > 0.0;
    let (ys, log) = match Scale::log(values.clone()) {
        Some(s) if all_positive => (s, true),
        _ => (Scale::linear_padded(values, 0.05), false),
    };
    let frame = Frame {
        x: 72.0,
        y: 70.0,
        w: 740.0,
        h: 200.0,
        xs: Scale::linear(0.5, n_total as f64 + 0.5),
        ys,
    };
    (frame, log)
}

/// The legend above the failed strip.
fn plan_legend(svg: &mut Svg) {
    legend(
        svg,
        72.0,
        16.0,
        &[
            ("J at a plan point", Key::Point(Marker::Dot, colour::BLUE)),
            (
                "failed to simulate",
                Key::Point(Marker::Cross, colour::VERMILLION),
            ),
            (
                "local search start",
                Key::Point(Marker::Ring, colour::ORANGE),
            ),
            (
                "J at the estimate",
                Key::Line(Stroke::new(colour::GREEN, 1.5).dashed(dash::DASHED)),
            ),
        ],
    );
}

/// The strip above the frame holding the failed points, ranked after the
/// `n_ok` finite ones: crosses, or one band when there are many.
fn failed_strip(svg: &mut Svg, frame: &Frame, n_ok: usize, n_points: usize) {
    let n_failed = n_points - n_ok;
    let strip = (frame.y - 28.0, 22.0);
    svg.rect(
        frame.x,
        strip.0,
        frame.w,
        strip.1,
        FAILED_FILL,
        Some(Stroke::new(colour::INK, 0.6)),
    );
    svg.text(frame.x - 6.0, strip.0 + 15.0, "failed", Anchor::End);
    let ymid = strip.0 + 0.5 * strip.1;
    if n_failed == 0 {
        svg.text(frame.x + 8.0, strip.0 + 15.0, "none failed", Anchor::Start);
    } else if n_failed <= MAX_CROSSES {
        for r in n_ok..n_points {
            svg.marker(
                Marker::Cross,
                frame.px(r as f64 + 1.0),
                ymid,
                4.0,
                colour::VERMILLION,
            );
        }
    } else {
        let (a, b) = (frame.px(n_ok as f64 + 0.5), frame.px(n_points as f64 + 0.5));
        svg.rect(
            a,
            strip.0 + 3.0,
            b - a,
            strip.1 - 6.0,
            colour::VERMILLION,
            None,
        );
    }
    if n_failed > 0 {
        let label = format!("{n_failed} failed (J = +∞)");
        let x = frame.px(n_ok as f64 + 0.5) - 6.0;
        svg.text(x.max(frame.x + 120.0), strip.0 + 15.0, &label, Anchor::End);
    }
}

/// The sorted criterion values: dots, or a line when there are many.
fn sorted_costs(svg: &mut Svg, frame: &Frame, ok: &[(usize, f64)]) {
    let ranks: Vec<f64> = (1..=ok.len()).map(|r| r as f64).collect();
    let costs: Vec<f64> = ok.iter().map(|p| p.1).collect();
    if ok.len() <= MAX_DOTS {
        for (r, c) in ranks.iter().zip(&costs) {
            svg.marker(
                Marker::Dot,
                frame.px(*r),
                frame.py_clamped(*c),
                2.4,
                colour::BLUE,
            );
        }
    } else {
        let pts = min_max_points(&ranks, &costs, frame);
        svg.path(&path_data(&pts), Stroke::new(colour::BLUE, 1.6));
    }
}

/// The final J as a dashed line with its value.
fn final_cost_line(svg: &mut Svg, frame: &Frame, final_cost: f64) {
    if final_cost.is_finite() {
        let y = frame.py_clamped(final_cost);
        svg.line(
            frame.x,
            y,
            frame.x + frame.w,
            y,
            Stroke::new(colour::GREEN, 1.5).dashed(dash::DASHED),
        );
        svg.text_styled(
            frame.x + frame.w - 4.0,
            y - 5.0,
            &format!("estimate: J = {}", sig(final_cost, 4)),
            Anchor::End,
            FONT_SIZE,
            colour::INK,
            HALO,
        );
    }
}

/// The start points, ringed at their rank; the first three named.
fn start_rings(svg: &mut Svg, frame: &Frame, ok: &[(usize, f64)], starts: &[usize]) {
    for (k, s) in starts.iter().enumerate() {
        if let Some(rank) = ok.iter().position(|p| p.0 == *s) {
            let (x, y) = (frame.px(rank as f64 + 1.0), frame.py_clamped(ok[rank].1));
            svg.marker(Marker::Ring, x, y, 6.5, colour::ORANGE);
            if k < 3 {
                svg.text_styled(
                    x + 9.0,
                    y - 8.0 - 12.0 * k as f64,
                    &format!("start: plan point {}", s + 1),
                    Anchor::Start,
                    FONT_SIZE,
                    colour::INK,
                    HALO,
                );
            }
        }
    }
}
