//! The local search's history: J per iteration, and each parameter's
//! trajectory normalised to its box (eq. 17), as small multiples.
use super::axis::{legend, Frame, Key, Scale};
use super::fmt::sig;
use super::svg::{colour, dash, Anchor, Marker, Stroke, Svg};
use crate::identification::result::{Iterate, ParameterEstimate};

/// Ticks wanted on an iteration axis: no fractional iterations.
fn iteration_ticks(last: usize) -> usize {
    last.clamp(1, 6)
}

/// J per iteration on a log axis (linear if some J ≤ 0).
pub(crate) fn cost_figure(history: &[Iterate], method: &str) -> String {
    let title = format!("Local search ({method}): criterion J per iteration");
    let mut svg = Svg::new(860.0, 250.0, &title);
    let last = history.iter().map(|h| h.iteration).max().unwrap_or(0);
    let costs = history.iter().map(|h| h.cost);
    let (ys, log) = match Scale::log(costs.clone()) {
        Some(s) if history.iter().all(|h| h.cost > 0.0) => (s, true),
        _ => (Scale::linear_padded(costs, 0.05), false),
    };
    let frame = Frame {
        x: 72.0,
        y: 30.0,
        w: 740.0,
        h: 176.0,
        xs: Scale::linear(0.0, last as f64),
        ys,
    };
    legend(
        &mut svg,
        72.0,
        16.0,
        &[(
            "J after each iteration (0 = start)",
            Key::Point(Marker::Dot, colour::BLUE),
        )],
    );
    let y_title = if log {
        "criterion J (log)"
    } else {
        "criterion J"
    };
    frame.axes_with(&mut svg, "iteration", y_title, iteration_ticks(last), 5);
    let pts: Vec<(f64, f64)> = history
        .iter()
        .map(|h| (frame.px(h.iteration as f64), frame.py_clamped(h.cost)))
        .collect();
    svg.path(
        &super::decimate::path_data(&pts),
        Stroke::new(colour::BLUE, 1.2),
    );
    if pts.len() <= 200 {
        for (x, y) in pts {
            svg.marker(Marker::Dot, x, y, 3.0, colour::BLUE);
        }
    }
    if let (Some(a), Some(b)) = (history.first(), history.last()) {
        svg.text(
            frame.x + frame.w - 4.0,
            frame.y + 16.0,
            &format!("J: {} → {}", sig(a.cost, 4), sig(b.cost, 4)),
            Anchor::End,
        );
    }
    svg.finish()
}

/// Columns of the small multiples.
const COLUMNS: usize = 4;

/// Each parameter's trajectory, normalised to its box `(x − min)/(max − min)`,
/// one small panel per parameter, with the reference value if given.
pub(crate) fn trajectory_figure(
    history: &[Iterate],
    params: &[ParameterEstimate],
    reference: Option<&[f64]>,
) -> String {
    let rows = params.len().div_ceil(COLUMNS).max(1);
    let height = 36.0 + CELL.1 * rows as f64;
    let mut svg = Svg::new(
        860.0,
        height,
        "Parameter trajectories, normalised to their boxes",
    );
    trajectory_legend(&mut svg, reference.is_some());
    let last = history.iter().map(|h| h.iteration).max().unwrap_or(0);
    for (j, p) in params.iter().enumerate() {
        let frame = panel_frame(&mut svg, j, p, last);
        let reference = reference.and_then(|r| r.get(j)).copied();
        panel_trajectory(&mut svg, &frame, history, j, p, reference);
    }
    svg.finish()
}

/// Width and height of a small panel's cell.
const CELL: (f64, f64) = (205.0, 124.0);

/// The legend of the trajectories (with the reference's line if there is one).
fn trajectory_legend(svg: &mut Svg, with_reference: bool) {
    let mut items = vec![
        (
            "parameter: 0 = box min, 1 = box max",
            Key::Line(Stroke::new(colour::BLUE, 1.4)),
        ),
        ("box", Key::Swatch(colour::SHADE)),
    ];
    if with_reference {
        items.push((
            "reference",
            Key::Line(Stroke::new(colour::BLACK, 1.2).dashed(dash::DASHED)),
        ));
    }
    legend(svg, 40.0, 16.0, &items);
}

/// Parameter j's panel: its frame over iterations 0 … last, the box shaded,
/// its axes and its name.
fn panel_frame(svg: &mut Svg, j: usize, p: &ParameterEstimate, last: usize) -> Frame {
    let (pw, ph) = (150.0, 72.0);
    let (row, col) = (j / COLUMNS, j % COLUMNS);
    let frame = Frame {
        x: 40.0 + CELL.0 * col as f64,
        y: 56.0 + CELL.1 * row as f64,
        w: pw,
        h: ph,
        xs: Scale::linear(0.0, last as f64),
        ys: Scale::Linear { lo: -0.1, hi: 1.1 },
    };
    svg.rect(
        frame.x,
        frame.py(1.0),
        frame.w,
        frame.py(0.0) - frame.py(1.0),
        colour::SHADE,
        None,
    );
    frame.axes_with(svg, "", "", iteration_ticks(last).min(3), 2);
    svg.text_styled(
        frame.x,
        frame.y - 6.0,
        &p.name,
        Anchor::Start,
        11.0,
        colour::INK,
        "font-weight=\"bold\"",
    );
    frame
}

/// Parameter j's marks in its panel: the reference's line, the trajectory
/// in the search's own coordinate (linear or logarithmic in the box) with
/// its last point, and the axis title.
fn panel_trajectory(
    svg: &mut Svg,
    frame: &Frame,
    history: &[Iterate],
    j: usize,
    p: &ParameterEstimate,
    reference: Option<f64>,
) {
    let map = crate::identification::box_map::BoxMap::new(p.min, p.max, p.scale);
    let norm = |x: f64| {
        if p.max > p.min {
            map.to_normalised(x)
        } else {
            0.5
        }
    };
    if let Some(r) = reference {
        let y = frame.py_clamped(norm(r));
        svg.line(
            frame.x,
            y,
            frame.x + frame.w,
            y,
            Stroke::new(colour::BLACK, 1.2).dashed(dash::DASHED),
        );
    }
    let pts: Vec<(f64, f64)> = history
        .iter()
        .filter_map(|h| h.parameters.get(j).map(|x| (h.iteration, *x)))
        .map(|(it, x)| (frame.px(it as f64), frame.py_clamped(norm(x))))
        .collect();
    svg.path(
        &super::decimate::path_data(&pts),
        Stroke::new(colour::BLUE, 1.4),
    );
    if let Some(&(x, y)) = pts.last() {
        svg.marker(Marker::Dot, x, y, 2.6, colour::BLUE);
    }
    svg.text(
        frame.x + frame.w * 0.5,
        frame.y + frame.h + 30.0,
        "iteration",
        Anchor::Middle,
    );
}
