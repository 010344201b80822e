//! Long signals as short paths: at most two points per pixel column (the
//! column's minimum and maximum, in time order), so peaks survive while a
//! 3000-sample record becomes a path of about one point per pixel; and
//! compact relative path data in tenths of a pixel.
use super::axis::Frame;
use super::svg::num;
use std::fmt::Write;

/// A sample's pixel position and its index.
type Sample = (f64, f64, usize);

/// Pixel positions of the samples `(x[k], y[k])` in `frame`, decimated to
/// each pixel column's extremes when there are more than two samples per
/// column. Non-finite samples are left out.
pub(crate) fn min_max_points(x: &[f64], y: &[f64], frame: &Frame) -> Vec<(f64, f64)> {
    let n = x.len().min(y.len());
    let all = (0..n)
        .filter(|&k| x[k].is_finite() && y[k].is_finite())
        .map(|k| (frame.px(x[k]), frame.py(y[k])));
    if n as f64 <= 2.0 * frame.w.max(1.0) {
        return all.collect();
    }
    let mut out = Vec::with_capacity(2 * frame.w as usize + 2);
    // (column, first point at the column's lowest y pixel, first at its highest)
    let mut current: Option<(i64, Sample, Sample)> = None;
    let flush = |out: &mut Vec<(f64, f64)>, lo: Sample, hi: Sample| {
        let (a, b) = if lo.2 <= hi.2 { (lo, hi) } else { (hi, lo) };
        out.push((a.0, a.1));
        if b.2 != a.2 {
            out.push((b.0, b.1));
        }
    };
    for (k, (px, py)) in all.enumerate() {
        let col = px.floor() as i64;
        match &mut current {
            Some((c, lo, hi)) if *c == col => {
                if py < lo.1 {
                    *lo = (px, py, k);
                }
                if py > hi.1 {
                    *hi = (px, py, k);
                }
            }
            _ => {
                if let Some((_, lo, hi)) = current {
                    flush(&mut out, lo, hi);
                }
                current = Some((col, (px, py, k), (px, py, k)));
            }
        }
    }
    if let Some((_, lo, hi)) = current {
        flush(&mut out, lo, hi);
    }
    out
}

/// A number of tenths as the shortest decimal: 12 → `1.2`, −5 → `-.5`.
fn tenths(d: i64) -> String {
    let (sign, a) = if d < 0 { ("-", -d) } else { ("", d) };
    match (a / 10, a % 10) {
        (0, 0) => "0".into(),
        (0, f) => format!("{sign}.{f}"),
        (i, 0) => format!("{sign}{i}"),
        (i, f) => format!("{sign}{i}.{f}"),
    }
}

/// SVG path data through `points`: an absolute move, then relative line
/// segments in tenths of a pixel (rounding does not accumulate: each step
/// is taken from the previous rounded position).
pub(crate) fn path_data(points: &[(f64, f64)]) -> String {
    let Some(&(x0, y0)) = points.first() else {
        return String::new();
    };
    let round = |v: f64| (v * 10.0).round() as i64;
    let (mut cx, mut cy) = (round(x0), round(y0));
    let mut d = String::with_capacity(points.len() * 8);
    let _ = write!(d, "M{} {}", num(cx as f64 / 10.0), num(cy as f64 / 10.0));
    if points.len() > 1 {
        d.push('l');
    }
    let mut first = true;
    for &(x, y) in &points[1..] {
        let (nx, ny) = (round(x), round(y));
        for (i, v) in [tenths(nx - cx), tenths(ny - cy)].into_iter().enumerate() {
            let leading = first && i == 0;
            if !leading && !v.starts_with('-') {
                d.push(' ');
            }
            d.push_str(&v);
        }
        first = false;
        (cx, cy) = (nx, ny);
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::axis::Scale;

    fn frame(w: f64) -> Frame {
        Frame {
            x: 0.0,
            y: 0.0,
            w,
            h: 100.0,
            xs: Scale::linear(0.0, 1.0),
            ys: Scale::linear(-1.0, 1.0),
        }
    }

    #[test]
    fn decimation_keeps_each_columns_extremes() {
        let n = 10_000;
        let x: Vec<f64> = (0..n).map(|k| k as f64 / n as f64).collect();
        let mut y: Vec<f64> = x.iter().map(|t| (40.0 * t).sin() * 0.5).collect();
        y[5000] = 1.0; // a spike must survive
        let f = frame(100.0);
        let p = min_max_points(&x, &y, &f);
        assert!(p.len() <= 200, "{} points", p.len());
        let top = p.iter().map(|q| q.1).fold(f64::INFINITY, f64::min);
        assert_eq!(top, f.py(1.0));
        assert!(p.windows(2).all(|w| w[0].0 <= w[1].0), "time order kept");
    }

    #[test]
    fn short_signals_are_not_decimated() {
        let x = [0.0, 0.5, 1.0];
        let y = [0.0, 1.0, 0.0];
        assert_eq!(min_max_points(&x, &y, &frame(100.0)).len(), 3);
    }

    #[test]
    fn path_data_is_relative_in_tenths() {
        let d = path_data(&[(1.0, 2.0), (2.25, 1.5), (2.25, 3.0)]);
        assert_eq!(d, "M1 2l1.3-.5 0 1.5");
        assert_eq!(tenths(-10), "-1");
        assert_eq!(tenths(0), "0");
    }
}
