//! The correlation matrix of the estimates as a heat map, on a diverging
//! scale from −1 (blue) through 0 (white) to +1 (red) (ColorBrewer RdBu,
//! safe for the common colour-vision deficiencies). The values are printed
//! in the cells for up to [`MAX_PRINTED`] parameters, so the sign survives a
//! greyscale print. The outlined cells are exactly the pairs the verdict
//! (and the warnings) name: the same test, on the same numbers.
use super::axis::legend;
use super::axis::Key;
use super::svg::{colour, text_width, Anchor, Stroke, Svg, FONT_SIZE};
use crate::identification::result::IdentificationResult;

/// Largest matrix whose values are printed in the cells.
pub(crate) const MAX_PRINTED: usize = 20;

/// The warning threshold of results written before verdicts existed (the
/// default of [`crate::identification::uncertainty::UncertaintySettings`]).
const DEFAULT_THRESHOLD: f64 = 0.99;

/// The pairs (i < j) the result warns about, and the threshold: from the
/// verdict, or for an older result the default test `|ρ| > 0.99`.
pub(crate) fn warned_pairs(
    r: &IdentificationResult,
    corr: &[Vec<f64>],
) -> (Vec<(usize, usize)>, f64) {
    if let Some(v) = &r.verdict {
        return (v.correlated_pairs(), v.correlation_threshold);
    }
    let mut pairs = Vec::new();
    for (i, row) in corr.iter().enumerate() {
        for (j, &c) in row.iter().enumerate().skip(i + 1) {
            if c.abs() > DEFAULT_THRESHOLD {
                pairs.push((i, j));
            }
        }
    }
    (pairs, DEFAULT_THRESHOLD)
}

/// Anchors of the diverging scale: (value, RGB).
const ANCHORS: [(f64, [u8; 3]); 7] = [
    (-1.0, [0x21, 0x66, 0xac]),
    (-0.6, [0x67, 0xa9, 0xcf]),
    (-0.25, [0xd1, 0xe5, 0xf0]),
    (0.0, [0xf7, 0xf7, 0xf7]),
    (0.25, [0xfd, 0xdb, 0xc7]),
    (0.6, [0xef, 0x8a, 0x62]),
    (1.0, [0xb2, 0x18, 0x2b]),
];

/// The colour of correlation `r` (grey for a non-finite value).
pub(crate) fn diverging(r: f64) -> String {
    if !r.is_finite() {
        return "#bbbbbb".into();
    }
    let r = r.clamp(-1.0, 1.0);
    let k = ANCHORS
        .windows(2)
        .position(|w| r <= w[1].0)
        .unwrap_or(ANCHORS.len() - 2);
    let ((a, ca), (b, cb)) = (ANCHORS[k], ANCHORS[k + 1]);
    let t = (r - a) / (b - a);
    let mix = |i: usize| (ca[i] as f64 + t * (cb[i] as f64 - ca[i] as f64)).round() as u8;
    format!("#{:02x}{:02x}{:02x}", mix(0), mix(1), mix(2))
}

/// Two decimals with a typographic minus; `1` on the diagonal.
fn cell_text(r: f64) -> String {
    if !r.is_finite() {
        return "?".into();
    }
    let s = format!("{r:.2}");
    let s = if s == "-0.00" { "0.00".to_owned() } else { s };
    s.replace('-', "−")
}

/// The place of the heat map's cells on the page.
#[derive(Debug, Clone, Copy)]
struct Grid {
    /// Left edge of the cells.
    x0: f64,
    /// Top edge of the cells.
    y0: f64,
    /// Side of a cell.
    cell: f64,
    /// Side of the whole grid.
    size: f64,
}

/// The heat map of `corr` (r × r) with `names` on both axes; the cells of
/// `pairs` (i < j, both triangles) are outlined as beyond `threshold`.
pub(crate) fn correlation_figure(
    corr: &[Vec<f64>],
    names: &[String],
    pairs: &[(usize, usize)],
    threshold: f64,
) -> String {
    let n = corr.len().max(1);
    let grid = grid_layout(n, names);
    let bar_x = grid.x0 + grid.size + 40.0;
    let width = (bar_x + 90.0).max(400.0);
    let height = grid.y0 + grid.size + 24.0;
    let mut svg = Svg::new(width, height, "Correlation matrix of the estimates");
    let key = format!("|correlation| > {threshold}: warned about");
    legend(
        &mut svg,
        16.0,
        18.0,
        &[(key.as_str(), Key::Line(Stroke::new(colour::BLACK, 2.0)))],
    );
    heat_map_cells(&mut svg, grid, corr, names, n <= MAX_PRINTED);
    outline_pairs(&mut svg, grid, pairs);
    colour_bar(&mut svg, grid, bar_x);
    svg.finish()
}

/// The cells' size and place for an n × n map, leaving room for `names`.
fn grid_layout(n: usize, names: &[String]) -> Grid {
    let cell = (560.0 / n as f64).clamp(10.0, 40.0);
    let label_w = names
        .iter()
        .map(|s| text_width(s, FONT_SIZE))
        .fold(20.0, f64::max)
        + 12.0;
    let (x0, y0) = (label_w + 10.0, 40.0 + label_w);
    Grid {
        x0,
        y0,
        cell,
        size: cell * n as f64,
    }
}

/// The names along both axes and the coloured cells, with their values
/// printed if `printed`.
fn heat_map_cells(svg: &mut Svg, g: Grid, corr: &[Vec<f64>], names: &[String], printed: bool) {
    let (x0, y0, cell) = (g.x0, g.y0, g.cell);
    let font = (0.3 * cell).min(10.0);
    for (i, row) in corr.iter().enumerate() {
        let name = names.get(i).map(String::as_str).unwrap_or("?");
        let yc = y0 + cell * (i as f64 + 0.5);
        svg.text(x0 - 6.0, yc + 4.0, name, Anchor::End);
        let xc = x0 + cell * (i as f64 + 0.5);
        svg.text_rotated(xc + 4.0, y0 - 6.0, name, -90.0, Anchor::Start);
        for (j, &r) in row.iter().enumerate() {
            let (x, y) = (x0 + cell * j as f64, y0 + cell * i as f64);
            svg.rect(x, y, cell, cell, &diverging(r), None);
            if printed {
                let ink = if r.abs() > 0.6 {
                    "#ffffff"
                } else {
                    colour::BLACK
                };
                let text = if i == j { "1".to_owned() } else { cell_text(r) };
                svg.text_styled(
                    x + 0.5 * cell,
                    y + 0.5 * cell + 0.35 * font,
                    &text,
                    Anchor::Middle,
                    font,
                    ink,
                    "",
                );
            }
        }
    }
}

/// The warned pairs outlined in both triangles (after all cells so no fill
/// covers them), and the grid's border.
fn outline_pairs(svg: &mut Svg, g: Grid, pairs: &[(usize, usize)]) {
    for &(a, b) in pairs {
        for (i, j) in [(a, b), (b, a)] {
            svg.rect(
                g.x0 + g.cell * j as f64 + 1.0,
                g.y0 + g.cell * i as f64 + 1.0,
                g.cell - 2.0,
                g.cell - 2.0,
                "none",
                Some(Stroke::new(colour::BLACK, 2.0)),
            );
        }
    }
    svg.rect(
        g.x0,
        g.y0,
        g.size,
        g.size,
        "none",
        Some(Stroke::new(colour::INK, 1.0)),
    );
}

/// The colour bar at `bar_x`, as tall as the grid, with its ticks.
fn colour_bar(svg: &mut Svg, g: Grid, bar_x: f64) {
    let (y0, grid) = (g.y0, g.size);
    let steps = 40;
    let h = grid / steps as f64;
    for k in 0..steps {
        let r = 1.0 - 2.0 * (k as f64 + 0.5) / steps as f64;
        svg.rect(bar_x, y0 + h * k as f64, 16.0, h + 0.3, &diverging(r), None);
    }
    svg.rect(
        bar_x,
        y0,
        16.0,
        grid,
        "none",
        Some(Stroke::new(colour::INK, 0.8)),
    );
    for (v, label) in [
        (-1.0, "−1"),
        (-0.5, "−0.5"),
        (0.0, "0"),
        (0.5, "0.5"),
        (1.0, "1"),
    ] {
        let y = y0 + grid * (1.0 - v) / 2.0;
        svg.line(
            bar_x + 16.0,
            y,
            bar_x + 20.0,
            y,
            Stroke::new(colour::INK, 1.0),
        );
        svg.text(bar_x + 23.0, y + 4.0, label, Anchor::Start);
    }
    svg.text_vertical(bar_x + 64.0, y0 + 0.5 * grid, "correlation");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diverging_scale_ends_and_middle() {
        assert_eq!(diverging(-1.0), "#2166ac");
        assert_eq!(diverging(0.0), "#f7f7f7");
        assert_eq!(diverging(1.0), "#b2182b");
        assert_eq!(diverging(2.0), "#b2182b");
        assert_eq!(diverging(f64::NAN), "#bbbbbb");
    }

    #[test]
    fn cells_print_two_decimals_with_a_real_minus() {
        assert_eq!(cell_text(-0.934), "−0.93");
        assert_eq!(cell_text(-0.0001), "0.00");
    }
}
