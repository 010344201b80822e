//! A minimal SVG writer: the few shapes the report's figures need, written
//! with presentation attributes only (no `<style>`, no ids), so that a figure
//! reads the same standalone and inlined many times into one HTML page.
//!
//! Coordinates are in CSS pixels of the figure's `viewBox` and are written
//! to 0.1 px. Text is laid out with a fixed-width estimate
//! ([`text_width`]) instead of font metrics: no font is loaded or needed, and
//! labels are placed with generous margins to absorb the estimate's error.
use std::fmt::Write;

/// Okabe–Ito colours (distinguishable with the common colour-vision
/// deficiencies), those the figures use, and neutral greys.
pub(crate) mod colour {
    pub const BLACK: &str = "#000000";
    pub const ORANGE: &str = "#E69F00";
    pub const GREEN: &str = "#009E73";
    pub const BLUE: &str = "#0072B2";
    pub const VERMILLION: &str = "#D55E00";
    /// Axis frames and tick labels.
    pub const INK: &str = "#333333";
    /// Grid lines.
    pub const GRID: &str = "#e4e4e4";
    /// A parameter's box, shaded regions.
    pub const SHADE: &str = "#ececec";
}

/// Dash patterns, so that lines stay apart in greyscale prints.
pub(crate) mod dash {
    pub const SOLID: &str = "";
    pub const DASHED: &str = "6 3";
}

/// Extra text attributes: a white outline under the glyphs, so a label
/// stays readable over lines and markers.
pub(crate) const HALO: &str =
    "stroke=\"#ffffff\" stroke-width=\"3\" stroke-linejoin=\"round\" paint-order=\"stroke\"";

/// Font stack of every figure; no font file is embedded or required.
pub(crate) const FONT: &str = "DejaVu Sans, Helvetica, Arial, sans-serif";
/// Default font size, px.
pub(crate) const FONT_SIZE: f64 = 11.0;

/// Estimated width of `text` at `size` px in a proportional sans-serif font:
/// 0.6 em per character, a slight overestimate for most labels.
pub(crate) fn text_width(text: &str, size: f64) -> f64 {
    0.6 * size * text.chars().count() as f64
}

/// A number as an SVG coordinate: one decimal, no trailing `.0`.
pub(crate) fn num(v: f64) -> String {
    let r = (v * 10.0).round() / 10.0;
    if r == r.trunc() {
        format!("{}", r as i64)
    } else {
        format!("{r:.1}")
    }
}

/// Escapes text for XML character data and attribute values.
pub(crate) fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for ch in text.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// Horizontal text alignment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Anchor {
    Start,
    Middle,
    End,
}

impl Anchor {
    fn as_str(self) -> &'static str {
        match self {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        }
    }
}

/// The look of a line: colour, width, dash pattern.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Stroke<'a> {
    pub colour: &'a str,
    pub width: f64,
    pub dash: &'a str,
}

impl<'a> Stroke<'a> {
    pub fn new(colour: &'a str, width: f64) -> Self {
        Stroke {
            colour,
            width,
            dash: dash::SOLID,
        }
    }

    pub fn dashed(mut self, dash: &'a str) -> Self {
        self.dash = dash;
        self
    }

    fn attributes(&self) -> String {
        let mut a = format!(
            "fill=\"none\" stroke=\"{}\" stroke-width=\"{}\"",
            self.colour,
            num(self.width)
        );
        if !self.dash.is_empty() {
            let _ = write!(a, " stroke-dasharray=\"{}\"", self.dash);
        }
        a
    }
}

/// Marker shapes for points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Marker {
    Dot,
    Ring,
    Cross,
    Diamond,
}

/// One SVG figure being written.
pub(crate) struct Svg {
    width: f64,
    height: f64,
    title: String,
    body: String,
}

impl Svg {
    /// An empty figure of `width × height` px with an accessible title.
    pub fn new(width: f64, height: f64, title: &str) -> Self {
        Svg {
            width,
            height,
            title: title.to_owned(),
            body: String::new(),
        }
    }

    /// A filled rectangle, optionally outlined.
    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, fill: &str, stroke: Option<Stroke>) {
        let _ = write!(
            self.body,
            "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{fill}\"",
            num(x),
            num(y),
            num(w.max(0.0)),
            num(h.max(0.0))
        );
        if let Some(s) = stroke {
            let _ = write!(
                self.body,
                " stroke=\"{}\" stroke-width=\"{}\"",
                s.colour,
                num(s.width)
            );
        }
        self.body.push_str("/>\n");
    }

    /// A straight line.
    pub fn line(&mut self, x1: f64, y1: f64, x2: f64, y2: f64, stroke: Stroke) {
        let _ = writeln!(
            self.body,
            "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" {}/>",
            num(x1),
            num(y1),
            num(x2),
            num(y2),
            stroke.attributes()
        );
    }

    /// A path with the given `d` attribute, stroked and not filled.
    pub fn path(&mut self, d: &str, stroke: Stroke) {
        if d.is_empty() {
            return;
        }
        let _ = writeln!(
            self.body,
            "<path d=\"{d}\" {} stroke-linejoin=\"round\"/>",
            stroke.attributes()
        );
    }

    /// A closed area with the given `d` attribute, filled and not stroked.
    pub fn area(&mut self, d: &str, fill: &str) {
        if d.is_empty() {
            return;
        }
        let _ = writeln!(
            self.body,
            "<path d=\"{d}z\" fill=\"{fill}\" stroke=\"none\"/>"
        );
    }

    /// A marker of `size` px (its half-width) at (x, y).
    pub fn marker(&mut self, m: Marker, x: f64, y: f64, size: f64, colour: &str) {
        let (xs, ys, s) = (num(x), num(y), size);
        match m {
            Marker::Dot => {
                let _ = writeln!(
                    self.body,
                    "<circle cx=\"{xs}\" cy=\"{ys}\" r=\"{}\" fill=\"{colour}\"/>",
                    num(s)
                );
            }
            Marker::Ring => {
                let _ = writeln!(
                    self.body,
                    "<circle cx=\"{xs}\" cy=\"{ys}\" r=\"{}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"2\"/>",
                    num(s)
                );
            }
            Marker::Cross => {
                let _ = writeln!(
                    self.body,
                    "<path d=\"M{} {}l{} {}m0 {}l{} {}\" stroke=\"{colour}\" stroke-width=\"2\" fill=\"none\"/>",
                    num(x - s),
                    num(y - s),
                    num(2.0 * s),
                    num(2.0 * s),
                    num(-2.0 * s),
                    num(-2.0 * s),
                    num(2.0 * s)
                );
            }
            Marker::Diamond => {
                let _ = writeln!(
                    self.body,
                    "<path d=\"M{} {}l{} {}l{} {}l{} {}z\" fill=\"{colour}\" stroke=\"#ffffff\" stroke-width=\"0.8\"/>",
                    num(x),
                    num(y - s),
                    num(s),
                    num(s),
                    num(-s),
                    num(s),
                    num(-s),
                    num(-s)
                );
            }
        }
    }

    /// Text with its baseline at y.
    pub fn text(&mut self, x: f64, y: f64, text: &str, anchor: Anchor) {
        self.text_styled(x, y, text, anchor, FONT_SIZE, colour::INK, "");
    }

    /// Text with a size, colour and extra attributes (e.g. `font-weight="bold"`).
    #[allow(clippy::too_many_arguments)]
    pub fn text_styled(
        &mut self,
        x: f64,
        y: f64,
        text: &str,
        anchor: Anchor,
        size: f64,
        fill: &str,
        extra: &str,
    ) {
        let _ = write!(self.body, "<text x=\"{}\" y=\"{}\"", num(x), num(y));
        if anchor != Anchor::Start {
            let _ = write!(self.body, " text-anchor=\"{}\"", anchor.as_str());
        }
        if size != FONT_SIZE {
            let _ = write!(self.body, " font-size=\"{}\"", num(size));
        }
        if fill != colour::INK {
            let _ = write!(self.body, " fill=\"{fill}\"");
        }
        if !extra.is_empty() {
            let _ = write!(self.body, " {extra}");
        }
        let _ = writeln!(self.body, ">{}</text>", escape(text));
    }

    /// Text rotated by −90° (reading upwards) centred on (x, y).
    pub fn text_vertical(&mut self, x: f64, y: f64, text: &str) {
        let _ = writeln!(
            self.body,
            "<text x=\"{0}\" y=\"{1}\" text-anchor=\"middle\" transform=\"rotate(-90 {0} {1})\">{2}</text>",
            num(x),
            num(y),
            escape(text)
        );
    }

    /// Text rotated by `angle` degrees about its anchor point.
    pub fn text_rotated(&mut self, x: f64, y: f64, text: &str, angle: f64, anchor: Anchor) {
        let _ = writeln!(
            self.body,
            "<text x=\"{0}\" y=\"{1}\" text-anchor=\"{3}\" transform=\"rotate({4} {0} {1})\">{2}</text>",
            num(x),
            num(y),
            escape(text),
            anchor.as_str(),
            num(angle)
        );
    }

    /// The finished document (no XML declaration, so it can be inlined).
    pub fn finish(self) -> String {
        let mut out = String::with_capacity(self.body.len() + 400);
        let _ = write!(
            out,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" \
             font-family=\"{FONT}\" font-size=\"{fs}\" role=\"img\" aria-label=\"{t}\">\n<title>{t}</title>\n\
             <rect width=\"{w}\" height=\"{h}\" fill=\"#ffffff\"/>\n",
            w = num(self.width),
            h = num(self.height),
            fs = num(FONT_SIZE),
            t = escape(&self.title),
        );
        out.push_str(&self.body);
        out.push_str("</svg>\n");
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_written_to_a_tenth_without_trailing_zeros() {
        assert_eq!(num(3.0), "3");
        assert_eq!(num(3.04), "3");
        assert_eq!(num(3.06), "3.1");
        assert_eq!(num(-0.25), "-0.3");
        assert_eq!(num(-12.0), "-12");
    }

    #[test]
    fn text_is_escaped() {
        assert_eq!(escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }
}
