//! Axes: linear and logarithmic scales with "nice" ticks (steps of 1, 2 or 5
//! times a power of ten), plot frames, and legends.
use super::fmt::{minus, sig, superscript};
use super::svg::{colour, text_width, Anchor, Marker, Stroke, Svg, FONT_SIZE};

/// A map from data values to the unit interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Scale {
    /// `lo ↦ 0`, `hi ↦ 1`.
    Linear { lo: f64, hi: f64 },
    /// `10^lo ↦ 0`, `10^hi ↦ 1` (the fields are decimal logarithms).
    Log { lo: f64, hi: f64 },
}

impl Scale {
    /// A linear scale over `[lo, hi]`; a degenerate or non-finite range is
    /// widened to something drawable.
    pub fn linear(lo: f64, hi: f64) -> Self {
        let (lo, hi) = match (lo.is_finite(), hi.is_finite()) {
            (true, true) => (lo.min(hi), lo.max(hi)),
            (true, false) => (lo, lo),
            (false, true) => (hi, hi),
            (false, false) => (0.0, 1.0),
        };
        if hi - lo > 1e-300 && (hi - lo) > 1e-12 * lo.abs().max(hi.abs()) {
            Scale::Linear { lo, hi }
        } else {
            let half = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
            Scale::Linear {
                lo: lo - half,
                hi: hi + half,
            }
        }
    }

    /// A linear scale over the data's range with `pad` (a fraction of the
    /// range) added on each side.
    pub fn linear_padded(values: impl IntoIterator<Item = f64>, pad: f64) -> Self {
        let (lo, hi) = finite_range(values);
        let span = hi - lo;
        Scale::linear(lo - pad * span, hi + pad * span)
    }

    /// A linear scale symmetric about zero covering the data.
    pub fn symmetric(values: impl IntoIterator<Item = f64>, pad: f64) -> Self {
        let (lo, hi) = finite_range(values);
        let m = lo.abs().max(hi.abs()) * (1.0 + pad);
        Scale::linear(-m, m)
    }

    /// A logarithmic scale covering the positive data, padded by a tenth of
    /// a decade on each side. `None` when no value is positive and finite.
    pub fn log(values: impl IntoIterator<Item = f64>) -> Option<Self> {
        let (lo, hi) = finite_range(values.into_iter().filter(|v| *v > 0.0));
        if !(lo > 0.0) {
            return None;
        }
        let (mut a, mut b) = (lo.log10(), hi.log10());
        if b - a < 0.5 {
            let mid = 0.5 * (a + b);
            a = mid - 0.25;
            b = mid + 0.25;
        }
        Some(Scale::Log {
            lo: a - 0.1,
            hi: b + 0.1,
        })
    }

    /// Where `v` falls, 0 at the low end and 1 at the high end (not clamped).
    pub fn frac(&self, v: f64) -> f64 {
        match *self {
            Scale::Linear { lo, hi } => (v - lo) / (hi - lo),
            Scale::Log { lo, hi } => {
                if v > 0.0 {
                    (v.log10() - lo) / (hi - lo)
                } else {
                    f64::NEG_INFINITY
                }
            }
        }
    }

    /// Unlabelled minor ticks: 2–9 × 10ⁿ on a log scale of at most six
    /// decades; none on a linear scale.
    pub fn minor_ticks(&self) -> Vec<f64> {
        let Scale::Log { lo, hi } = *self else {
            return Vec::new();
        };
        if hi - lo > 6.0 {
            return Vec::new();
        }
        let mut out = Vec::new();
        for d in (lo.floor() as i32)..=(hi.ceil() as i32) {
            for m in 2..=9 {
                let v = m as f64 * 10f64.powi(d);
                if (lo..=hi).contains(&v.log10()) {
                    out.push(v);
                }
            }
        }
        out
    }

    /// About `target` ticks with their labels.
    pub fn ticks(&self, target: usize) -> Ticks {
        match *self {
            Scale::Linear { lo, hi } => linear_ticks(lo, hi, target),
            Scale::Log { lo, hi } => log_ticks(lo, hi),
        }
    }
}

/// The range of the finite values, `(NaN, NaN)` if there are none.
pub(crate) fn finite_range(values: impl IntoIterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        if v.is_finite() {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    if lo > hi {
        (f64::NAN, f64::NAN)
    } else {
        (lo, hi)
    }
}

/// Tick positions and labels; `factor` is a common power of ten taken out
/// of the labels (`×10⁻³`), to be added to the axis title.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Ticks {
    pub values: Vec<f64>,
    pub labels: Vec<String>,
    pub factor: Option<String>,
}

/// A step of 1, 2 or 5 × 10ⁿ giving about `target` intervals over `span`.
pub(crate) fn nice_step(span: f64, target: usize) -> f64 {
    let raw = span / target.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let norm = raw / mag;
    let m = if norm < 1.5 {
        1.0
    } else if norm < 3.5 {
        2.0
    } else if norm < 7.5 {
        5.0
    } else {
        10.0
    };
    m * mag
}

fn linear_ticks(lo: f64, hi: f64, target: usize) -> Ticks {
    let step = nice_step(hi - lo, target);
    let big = lo.abs().max(hi.abs());
    // Engineering exponent taken out of the labels for very large or small values.
    let exp = if !(1e-2..1e4).contains(&big) {
        3 * (big.log10().floor() as i32).div_euclid(3)
    } else {
        0
    };
    let scale = 10f64.powi(exp);
    let decimals = (-((step / scale).log10() + 1e-9).floor()).max(0.0) as usize;
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    let mut values = Vec::new();
    let mut labels = Vec::new();
    for k in first..=last {
        let v = k as f64 * step;
        let mut s = format!("{:.*}", decimals, v / scale);
        if s.trim_start_matches('-')
            .chars()
            .all(|c| c == '0' || c == '.')
        {
            s = s.trim_start_matches('-').to_owned();
        }
        values.push(v);
        labels.push(minus(&s));
    }
    Ticks {
        values,
        labels,
        factor: (exp != 0).then(|| format!("×10{}", superscript(exp))),
    }
}

fn log_ticks(lo: f64, hi: f64) -> Ticks {
    let (a, b) = (lo.ceil() as i32, hi.floor() as i32);
    let decades = b - a + 1;
    let mut values = Vec::new();
    let mut labels = Vec::new();
    if decades <= 1 {
        // Less than two labelled decades: 1, 2, 5 per decade.
        for d in (lo.floor() as i32)..=(hi.ceil() as i32) {
            for m in [1.0, 2.0, 5.0] {
                let v = m * 10f64.powi(d);
                let l = v.log10();
                if l >= lo && l <= hi {
                    values.push(v);
                    labels.push(sig(v, 1));
                }
            }
        }
    } else {
        let every = ((decades as f64) / 7.0).ceil().max(1.0) as i32;
        for d in a..=b {
            if (d - a) % every == 0 {
                values.push(10f64.powi(d));
                labels.push(format!("10{}", superscript(d)));
            }
        }
    }
    Ticks {
        values,
        labels,
        factor: None,
    }
}

/// A rectangular plot area with its x and y scales.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frame {
    pub x: f64,
    pub y: f64,
    pub w: f64,
    pub h: f64,
    pub xs: Scale,
    pub ys: Scale,
}

impl Frame {
    /// Horizontal pixel of data value `v`.
    pub fn px(&self, v: f64) -> f64 {
        self.x + self.xs.frac(v) * self.w
    }

    /// Vertical pixel of data value `v` (up is larger).
    pub fn py(&self, v: f64) -> f64 {
        self.y + self.h - self.ys.frac(v) * self.h
    }

    /// `py` kept inside the frame.
    pub fn py_clamped(&self, v: f64) -> f64 {
        let p = self.py(v);
        if p.is_nan() {
            self.y + self.h
        } else {
            p.clamp(self.y, self.y + self.h)
        }
    }

    /// Grid, frame, tick labels and axis titles. An empty title is left out;
    /// a common factor of the tick labels is appended to its title.
    pub fn axes(&self, svg: &mut Svg, x_title: &str, y_title: &str) {
        self.axes_with(svg, x_title, y_title, 6, 5);
    }

    /// [`Frame::axes`] with the number of ticks wanted on each axis (0: none).
    pub fn axes_with(
        &self,
        svg: &mut Svg,
        x_title: &str,
        y_title: &str,
        x_ticks: usize,
        y_ticks: usize,
    ) {
        let xt = ticks_or_none(&self.xs, x_ticks);
        let yt = ticks_or_none(&self.ys, y_ticks);
        self.grid(svg, &xt, &yt);
        self.border(svg, y_ticks > 0);
        self.x_tick_labels(svg, &xt);
        let label_width = self.y_tick_labels(svg, &yt);
        let title = |t: &str, f: &Option<String>| match f {
            Some(f) if !t.is_empty() => format!("{t} ({f})"),
            _ => t.to_owned(),
        };
        if !x_title.is_empty() {
            svg.text(
                self.x + 0.5 * self.w,
                self.y + self.h + 31.0,
                &title(x_title, &xt.factor),
                Anchor::Middle,
            );
        }
        if !y_title.is_empty() {
            svg.text_vertical(
                self.x - label_width - 14.0,
                self.y + 0.5 * self.h,
                &title(y_title, &yt.factor),
            );
        }
    }

    /// The grid lines at the ticks inside the frame.
    fn grid(&self, svg: &mut Svg, xt: &Ticks, yt: &Ticks) {
        let grid = Stroke::new(colour::GRID, 1.0);
        let (bottom, right) = (self.y + self.h, self.x + self.w);
        for v in &xt.values {
            let p = self.px(*v);
            if p >= self.x - 0.5 && p <= right + 0.5 {
                svg.line(p, self.y, p, bottom, grid);
            }
        }
        for v in &yt.values {
            let p = self.py(*v);
            if p >= self.y - 0.5 && p <= bottom + 0.5 {
                svg.line(self.x, p, right, p, grid);
            }
        }
    }

    /// The frame's border, with the vertical axis's minor ticks if `minor`.
    fn border(&self, svg: &mut Svg, minor: bool) {
        let ink = Stroke::new(colour::INK, 1.0);
        let bottom = self.y + self.h;
        svg.rect(self.x, self.y, self.w, self.h, "none", Some(ink));
        if minor {
            for v in self.ys.minor_ticks() {
                let p = self.py(v);
                if p >= self.y && p <= bottom {
                    svg.line(self.x - 2.5, p, self.x, p, ink);
                }
            }
        }
    }

    /// The horizontal axis's ticks and their labels.
    fn x_tick_labels(&self, svg: &mut Svg, xt: &Ticks) {
        let ink = Stroke::new(colour::INK, 1.0);
        let (bottom, right) = (self.y + self.h, self.x + self.w);
        for (v, l) in xt.values.iter().zip(&xt.labels) {
            let p = self.px(*v);
            if p >= self.x - 0.5 && p <= right + 0.5 {
                svg.line(p, bottom, p, bottom + 4.0, ink);
                svg.text(p, bottom + 15.0, l, Anchor::Middle);
            }
        }
    }

    /// The vertical axis's ticks and their labels; returns the widest
    /// label's width.
    fn y_tick_labels(&self, svg: &mut Svg, yt: &Ticks) -> f64 {
        let ink = Stroke::new(colour::INK, 1.0);
        let bottom = self.y + self.h;
        let mut label_width: f64 = 0.0;
        for (v, l) in yt.values.iter().zip(&yt.labels) {
            let p = self.py(*v);
            if p >= self.y - 0.5 && p <= bottom + 0.5 {
                svg.line(self.x - 4.0, p, self.x, p, ink);
                svg.text(self.x - 6.0, p + 4.0, l, Anchor::End);
                label_width = label_width.max(text_width(l, FONT_SIZE));
            }
        }
        label_width
    }
}

/// About `count` ticks of `scale`, or none for a count of 0.
fn ticks_or_none(scale: &Scale, count: usize) -> Ticks {
    if count == 0 {
        Ticks {
            values: Vec::new(),
            labels: Vec::new(),
            factor: None,
        }
    } else {
        scale.ticks(count)
    }
}

/// What a legend entry shows.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Key<'a> {
    Line(Stroke<'a>),
    /// A short vertical line, as a tick mark in the plot.
    Tick(Stroke<'a>),
    Point(Marker, &'a str),
    Swatch(&'a str),
}

/// A row of legend entries starting at (x, y) (y is the text baseline).
/// Returns the x after the last entry.
pub(crate) fn legend(svg: &mut Svg, x: f64, y: f64, items: &[(&str, Key)]) -> f64 {
    let mut cx = x;
    for (label, key) in items {
        match *key {
            Key::Line(s) => svg.line(cx, y - 4.0, cx + 24.0, y - 4.0, s),
            Key::Tick(s) => svg.line(cx + 12.0, y - 11.0, cx + 12.0, y + 3.0, s),
            Key::Point(m, c) => svg.marker(m, cx + 12.0, y - 4.0, 4.0, c),
            Key::Swatch(fill) => svg.rect(
                cx + 4.0,
                y - 10.0,
                16.0,
                11.0,
                fill,
                Some(Stroke::new(colour::INK, 0.5)),
            ),
        }
        svg.text(cx + 29.0, y, label, Anchor::Start);
        cx += 29.0 + text_width(label, FONT_SIZE) + 14.0;
    }
    cx
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_ticks_are_nice_and_inside() {
        let t = Scale::linear(0.0, 0.3).ticks(6);
        assert_eq!(t.values.len(), 7);
        assert_eq!(t.labels[1], "0.05");
        assert!(t.factor.is_none());
        let t = Scale::linear(-2.2e-3, 2.2e-3).ticks(4);
        assert_eq!(t.factor.as_deref(), Some("×10⁻³"));
        assert!(t.labels.contains(&"−2".to_owned()));
        assert!(t.labels.contains(&"0".to_owned()));
    }

    #[test]
    fn log_ticks_label_decades() {
        let s = Scale::log([1e-6, 3e-2]).expect("positive");
        let t = s.ticks(5);
        assert!(t.labels.contains(&"10⁻⁴".to_owned()), "{:?}", t.labels);
        assert!(Scale::log([0.0, -1.0]).is_none());
        let narrow = Scale::log([2.0, 3.0]).expect("positive").ticks(5);
        assert!(
            narrow.labels.contains(&"2".to_owned()),
            "{:?}",
            narrow.labels
        );
    }

    #[test]
    fn degenerate_ranges_are_widened() {
        let Scale::Linear { lo, hi } = Scale::linear(5.0, 5.0) else {
            unreachable!()
        };
        assert!(lo < 5.0 && hi > 5.0);
    }
}
