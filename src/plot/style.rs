//! The shared look of every figure: colorblind-safe palette (Okabe–Ito), fonts, line styles,
//! number formatting, the title block, the legend and the axes.
//!
//! Conventions every panel follows: KF is vermillion and dashed, SCF is blue and solid (with a
//! light fill), the truth is black, measurements are grey dots, the time cursor is a grey
//! dotted line. Sizes are in CSS pixels of the backend (the wasm bindings hand the figure a
//! backend of the canvas' CSS size and scale the context by devicePixelRatio).

use super::de;
use super::geom::Win;
use super::Frame;
use crate::error::{Error, Result};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// KF: vermillion (drawn dashed).
pub const KF: RGBColor = RGBColor(213, 94, 0);
/// SCF: blue (drawn solid, light fill).
pub const SCF: RGBColor = RGBColor(0, 114, 178);
/// True state and trajectory.
pub const TRUTH: RGBColor = RGBColor(0, 0, 0);
/// Measurements.
pub const MEASURE: RGBColor = RGBColor(125, 125, 125);
/// Reference lines (the level α): bluish green.
pub const REFERENCE: RGBColor = RGBColor(0, 158, 115);
/// Time cursor.
pub const CURSOR: RGBColor = RGBColor(120, 120, 120);
pub const TEXT: RGBColor = RGBColor(25, 25, 25);
pub const MUTED: RGBColor = RGBColor(85, 85, 85);
pub const GRID: RGBColor = RGBColor(222, 222, 222);
pub const GRID_LIGHT: RGBColor = RGBColor(240, 240, 240);
pub const FRAME: RGBColor = RGBColor(190, 190, 190);

/// LSCR region X̂ (outline) and its light tint.
pub const LSCR: RGBColor = RGBColor(20, 20, 20);
pub const LSCR_TINT: RGBColor = RGBColor(240, 228, 66);
/// BLUE estimate and ellipse (the SCF blue: both are "the estimator that knows the noise").
pub const BLUE_EST: RGBColor = SCF;
/// Hatch colours of the areas excluded by X̂_1, X̂_2, … (Okabe–Ito bluish green, reddish
/// purple, orange, sky blue; cycled with the directions of [`hatch_dir`]).
pub const HATCH: [RGBColor; 4] = [
    RGBColor(0, 150, 110),
    RGBColor(175, 60, 135),
    RGBColor(210, 140, 0),
    RGBColor(70, 160, 220),
];

/// Curves indexed by i (σ₁, σ₂, … of the GLLS figures): Okabe–Ito blue, vermillion, bluish
/// green, reddish purple, orange, sky blue, then black; cycled.
pub const SERIES: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

/// Colour of curve i (0-based).
pub fn series_color(i: usize) -> RGBColor {
    SERIES[i % SERIES.len()]
}

/// GLLS: the (G)LLS estimator (blue), the state-noise estimator (vermillion), the
/// regularized estimator and the projected truth (reddish purple), the guaranteed ball (blue,
/// light fill) and the interval box (bluish green).
pub const GLLS_EST: RGBColor = RGBColor(0, 114, 178);
pub const STATE_NOISE: RGBColor = RGBColor(213, 94, 0);
pub const REGULARIZED: RGBColor = RGBColor(204, 121, 167);
pub const BALL: RGBColor = RGBColor(0, 114, 178);
pub const INTERVAL_BOX: RGBColor = RGBColor(0, 158, 115);
/// Uniform-innovation panels (Pavelková): the LP (MAP) estimate blue like every estimator that
/// knows the noise's shape, the KF with variances r²/3 vermillion dashed, the ranges over the
/// LP's optimal face reddish purple, the consistent-state polygon bluish green, the sliding
/// window a grey band.
pub const UNIFORM_LP: RGBColor = RGBColor(0, 114, 178);
pub const FACE: RGBColor = RGBColor(204, 121, 167);
pub const POLYGON: RGBColor = RGBColor(0, 158, 115);
pub const WINDOW: RGBColor = RGBColor(160, 160, 160);
/// The floating-point floor (grey band).
pub const FLOOR: RGBColor = RGBColor(150, 150, 150);

/// Colour of the hatching of group l (0-based).
pub fn hatch_color(l: usize) -> RGBColor {
    HATCH[l % HATCH.len()]
}

/// Unit direction in screen pixels (y down) of the hatch lines of group l: "\\", "/", "—",
/// "|", then the same four again (drawn with a half-spacing offset so they interleave).
pub fn hatch_dir(l: usize) -> (f64, f64) {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    match l % 4 {
        0 => (h, h),
        1 => (h, -h),
        2 => (1.0, 0.0),
        _ => (0.0, 1.0),
    }
}

/// Dash and gap of KF lines, in pixels.
pub const DASH: (i32, i32) = (8, 5);
/// Dot and gap of the time cursor.
pub const DOT: (i32, i32) = (2, 4);

/// Text sizes in CSS pixels, whatever the backend, and whether the figure is small.
///
/// plotters hands a font size to the SVG backend as `font-size: size / 1.24` but to the canvas
/// as `size` px; both measure text consistently with how they render it. To get the same
/// on-screen sizes from both, the nominal size is scaled by 1.24 for SVG.
#[derive(Debug, Clone, Copy)]
pub struct Fonts {
    scale: f64,
    /// Small figure (narrower than 640 or lower than 400 px): smaller text, fewer subtitle
    /// lines, legend over the chart.
    pub compact: bool,
}

impl Fonts {
    /// The fonts for backend type `DB` and a figure of `size` pixels.
    pub fn for_backend<DB: DrawingBackend>(size: (u32, u32)) -> Fonts {
        let svg = std::any::type_name::<DB>().contains("SVGBackend");
        Fonts {
            scale: if svg { 1.24 } else { 1.0 },
            compact: size.0 < 640 || size.1 < 400,
        }
    }
    fn pick(&self, normal: f64, small: f64) -> f64 {
        if self.compact {
            small
        } else {
            normal
        }
    }
    /// Regular text of `px` CSS pixels.
    pub fn px(&self, px: f64) -> TextStyle<'static> {
        ("sans-serif", px * self.scale).into_font().color(&TEXT)
    }
    pub fn bold(&self, px: f64) -> TextStyle<'static> {
        ("sans-serif", px * self.scale, FontStyle::Bold)
            .into_font()
            .color(&TEXT)
    }
    pub fn title(&self) -> TextStyle<'static> {
        self.bold(self.pick(17.0, 14.0))
    }
    pub fn subtitle(&self) -> TextStyle<'static> {
        self.px(self.pick(13.0, 11.5)).color(&MUTED)
    }
    pub fn axis(&self) -> TextStyle<'static> {
        self.px(self.pick(14.0, 12.0))
    }
    pub fn tick(&self) -> TextStyle<'static> {
        self.px(self.pick(12.0, 10.5)).color(&MUTED)
    }
    pub fn legend(&self) -> TextStyle<'static> {
        self.px(self.pick(13.0, 11.5))
    }
    pub fn note(&self) -> TextStyle<'static> {
        self.px(self.pick(12.0, 10.5)).color(&MUTED)
    }
    /// Labels on the chart ("A", "B").
    pub fn tag(&self) -> TextStyle<'static> {
        self.bold(self.pick(14.0, 12.0))
    }
}

/// Text width and height in pixels as the backend measures it.
pub fn text_size<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    style: &TextStyle,
) -> Result<(u32, u32)> {
    if text.is_empty() {
        return Ok((0, 0));
    }
    area.estimate_text_size(text, style).map_err(de)
}

/// Draw `text` with its `anchor` at absolute pixel `pos` of `area`'s backend.
pub fn text<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    s: &str,
    pos: (i32, i32),
    style: &TextStyle,
    anchor: (HPos, VPos),
) -> Result<()> {
    if s.is_empty() {
        return Ok(());
    }
    let (bx, by) = area.get_base_pixel();
    area.draw(&Text::new(
        s.to_string(),
        (pos.0 - bx, pos.1 - by),
        style.pos(Pos::new(anchor.0, anchor.1)),
    ))
    .map_err(de)
}

/// Greedy line breaking: first at " · " separators, then at spaces.
pub fn wrap<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    s: &str,
    style: &TextStyle,
    max_w: u32,
) -> Result<Vec<String>> {
    let mut lines = Vec::new();
    for para in s.split('\n') {
        let mut cur = String::new();
        for piece in para.split(" · ") {
            let cand = if cur.is_empty() {
                piece.to_string()
            } else {
                format!("{cur} · {piece}")
            };
            if text_size(area, &cand, style)?.0 <= max_w {
                cur = cand;
                continue;
            }
            if !cur.is_empty() {
                lines.push(std::mem::take(&mut cur));
            }
            // The piece alone: break at spaces if needed.
            for word in piece.split(' ') {
                let cand = if cur.is_empty() {
                    word.to_string()
                } else {
                    format!("{cur} {word}")
                };
                if cur.is_empty() || text_size(area, &cand, style)?.0 <= max_w {
                    cur = cand;
                } else {
                    lines.push(std::mem::replace(&mut cur, word.to_string()));
                }
            }
        }
        if !cur.is_empty() {
            lines.push(cur);
        }
    }
    Ok(lines)
}

/// Outer padding of a figure.
pub const PAD: i32 = 12;

/// Draw the title (one line, shortened if needed) and the wrapped subtitle at the top of
/// `root`; returns the area below. Subtitle lines beyond the room of the figure are dropped
/// (put the important facts first).
pub fn title_block<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    title: &str,
    subtitle: &str,
) -> Result<DrawingArea<DB, Shift>> {
    let (w, h) = root.dim_in_pixel();
    let (x0, y0) = root.get_base_pixel();
    let pad = if fonts.compact { PAD / 2 } else { PAD };
    let max_w = (w as i32 - 2 * pad).max(40) as u32;
    let mut y = y0 + pad;
    let ts = fonts.title();
    // Up to two lines of title before anything is cut: the page's 2 × 2 grids give a panel
    // about 480 px at 1366 px, narrower than most titles.
    let lines = wrap(root, title, &ts, max_w)?;
    for (i, line) in lines.iter().take(2).enumerate() {
        let line = if i == 1 && lines.len() > 2 {
            shorten(root, rest_after(title, &lines[..1]), &ts, max_w)?
        } else {
            line.clone()
        };
        text(root, &line, (x0 + pad, y), &ts, (HPos::Left, VPos::Top))?;
        y += text_size(root, &line, &ts)?.1 as i32 + 2;
    }
    y += 2;
    // A figure taller than wide (a phone's) has height to spare for the notes.
    let max_lines = if h < 300 {
        1
    } else if h > w {
        4
    } else if h < 450 || fonts.compact {
        2
    } else {
        4
    };
    let ss = fonts.subtitle();
    let lines = wrap(root, subtitle, &ss, max_w)?;
    for (i, line) in lines.iter().take(max_lines).enumerate() {
        // The last line that fits says, with "…", that the notes go on (in the report).
        let line = if i + 1 == max_lines && lines.len() > max_lines {
            shorten(root, rest_after(subtitle, &lines[..i]), &ss, max_w)?
        } else {
            line.clone()
        };
        text(root, &line, (x0 + pad, y), &ss, (HPos::Left, VPos::Top))?;
        y += text_size(root, &line, &ss)?.1 as i32 + 3;
    }
    let used = (y - y0 + 2).max(0);
    Ok(root.split_vertically(used).1)
}

/// What of `s` follows its first wrapped `lines` (as [`wrap`] made them), with its separators
/// (" · ", spaces) kept, so a shortened last line reads as the text does.
fn rest_after<'a>(s: &'a str, lines: &[String]) -> &'a str {
    let mut rest = s;
    for line in lines {
        rest = rest.trim_start_matches([' ', '·', '\n']);
        rest = rest.strip_prefix(line.as_str()).unwrap_or(rest);
    }
    rest.trim_start_matches([' ', '·', '\n'])
}

/// `s`, cut with "…" to fit `max_w`.
pub fn shorten<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    s: &str,
    style: &TextStyle,
    max_w: u32,
) -> Result<String> {
    if text_size(area, s, style)?.0 <= max_w {
        return Ok(s.to_string());
    }
    let chars: Vec<char> = s.chars().collect();
    let (mut lo, mut hi) = (0, chars.len());
    while lo < hi {
        let mid = (lo + hi).div_ceil(2);
        let cand: String = chars[..mid].iter().collect::<String>() + "…";
        if text_size(area, &cand, style)?.0 <= max_w {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    Ok(chars[..lo]
        .iter()
        .collect::<String>()
        .trim_end()
        .to_string()
        + "…")
}

/// Point markers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Marker {
    Plus,
    Cross,
    Dot,
    Ring,
    /// ◇ (LSCR paper: the true state), hollow.
    Diamond,
    /// ⋆ (LSCR paper: the BLUE / Kalman estimate), filled.
    Star,
}

/// What a legend entry shows next to its label.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Swatch {
    Line {
        color: RGBColor,
        dashed: bool,
        width: u32,
    },
    /// A region boundary (optionally with the light fill).
    Region {
        color: RGBColor,
        dashed: bool,
        fill: bool,
    },
    Marker {
        shape: Marker,
        color: RGBColor,
        size: i32,
    },
    /// A region outline over its own tint (the LSCR region X̂).
    Tinted { line: RGBColor, tint: RGBAColor },
    /// A small box hatched like the area excluded by group `group` (see [`hatch_dir`]).
    Hatch { color: RGBColor, group: usize },
    /// No swatch: a note in the legend.
    None,
}

/// One legend line.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    pub label: String,
    pub swatch: Swatch,
    /// Left out of the legend of small figures.
    pub minor: bool,
}

impl Entry {
    pub fn new(label: impl Into<String>, swatch: Swatch) -> Self {
        Entry {
            label: label.into(),
            swatch,
            minor: false,
        }
    }
    /// The same entry, left out of small figures' legends.
    pub fn minor(mut self) -> Self {
        self.minor = true;
        self
    }
}

/// The light fill of SCF regions and bands.
pub fn fill(color: &RGBColor) -> ShapeStyle {
    color.mix(0.13).filled()
}

/// Draw a marker at an absolute pixel position.
pub fn marker<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    p: (i32, i32),
    shape: Marker,
    color: &RGBColor,
    size: i32,
) -> Result<()> {
    let (bx, by) = root.get_base_pixel();
    let (x, y) = (p.0 - bx, p.1 - by);
    let s = size;
    let st = color.stroke_width(2);
    match shape {
        Marker::Plus => {
            root.draw(&PathElement::new(vec![(x - s, y), (x + s, y)], st))
                .map_err(de)?;
            root.draw(&PathElement::new(vec![(x, y - s), (x, y + s)], st))
                .map_err(de)
        }
        Marker::Cross => {
            let d = (s as f64 * 0.75).round() as i32;
            root.draw(&PathElement::new(vec![(x - d, y - d), (x + d, y + d)], st))
                .map_err(de)?;
            root.draw(&PathElement::new(vec![(x - d, y + d), (x + d, y - d)], st))
                .map_err(de)
        }
        Marker::Dot => root
            .draw(&Circle::new((x, y), s.max(1) as u32, color.filled()))
            .map_err(de),
        Marker::Ring => root
            .draw(&Circle::new((x, y), s.max(1) as u32, color.stroke_width(2)))
            .map_err(de),
        Marker::Diamond => {
            // Hollow, as in the paper, so an estimate under it stays visible.
            let d = s + 1;
            let pts = vec![(x, y - d), (x + d, y), (x, y + d), (x - d, y), (x, y - d)];
            root.draw(&PathElement::new(pts, st)).map_err(de)
        }
        Marker::Star => {
            // Five points, outer radius s + 2, inner 0.45 of it.
            let ro = (s + 2) as f64;
            let pts: Vec<(i32, i32)> = (0..10)
                .map(|k| {
                    let r = if k % 2 == 0 { ro } else { 0.45 * ro };
                    let a = std::f64::consts::PI * (k as f64 / 5.0 - 0.5);
                    (
                        x + (r * a.cos()).round() as i32,
                        y + (r * a.sin()).round() as i32,
                    )
                })
                .collect();
            root.draw(&Polygon::new(pts.clone(), color.filled()))
                .map_err(de)?;
            let mut closed = pts;
            closed.push(closed[0]);
            root.draw(&PathElement::new(closed, WHITE.stroke_width(1)))
                .map_err(de)
        }
    }
}

/// Dots at chart coordinates inside the window, one per pixel position.
pub fn dots<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart<DB>,
    pts: &[(f64, f64)],
    color: &RGBColor,
    radius: i32,
) -> Result<()> {
    let win = Win::of_chart(chart);
    let mut seen = std::collections::HashSet::new();
    for &p in pts {
        if win.contains(p.0, p.1) {
            let q = px(chart, p);
            if seen.insert(q) {
                marker(root, q, Marker::Dot, color, radius)?;
            }
        }
    }
    Ok(())
}

/// A polyline in absolute pixels, solid or dashed.
pub fn polyline<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    pts: &[(i32, i32)],
    color: &RGBColor,
    width: u32,
    dash: Option<(i32, i32)>,
) -> Result<()> {
    if pts.len() < 2 {
        return Ok(());
    }
    let (bx, by) = root.get_base_pixel();
    let rel: Vec<(i32, i32)> = thin(pts).iter().map(|(x, y)| (x - bx, y - by)).collect();
    let st = color.stroke_width(width);
    match dash {
        None => root.draw(&PathElement::new(rel, st)).map_err(de),
        Some((a, b)) => root
            .draw(&plotters::element::DashedPathElement::new(rel, a, b, st))
            .map_err(de),
    }
}

/// Drop pixel points that change nothing: repeats, and within a run of points on one pixel
/// column all but the first, lowest, highest and last (long time series stay the same picture
/// with a few points per column).
pub fn thin(pts: &[(i32, i32)]) -> Vec<(i32, i32)> {
    let mut out: Vec<(i32, i32)> = Vec::with_capacity(pts.len().min(4096));
    let mut i = 0;
    while i < pts.len() {
        let x = pts[i].0;
        let mut j = i;
        while j + 1 < pts.len() && pts[j + 1].0 == x {
            j += 1;
        }
        let run = &pts[i..=j];
        if run.len() <= 4 {
            out.extend_from_slice(run);
        } else {
            let (mut lo, mut hi) = (0, 0);
            for (k, p) in run.iter().enumerate() {
                if p.1 < run[lo].1 {
                    lo = k;
                }
                if p.1 > run[hi].1 {
                    hi = k;
                }
            }
            let mut keep = vec![0, lo, hi, run.len() - 1];
            keep.sort_unstable();
            keep.dedup();
            out.extend(keep.into_iter().map(|k| run[k]));
        }
        i = j + 1;
    }
    out.dedup();
    out
}

const SWATCH_W: i32 = 34;
const SWATCH_GAP: i32 = 8;
const LEGEND_PAD: i32 = 10;

fn draw_swatch<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    swatch: Swatch,
    x: i32,
    yc: i32,
) -> Result<()> {
    match swatch {
        Swatch::Line {
            color,
            dashed,
            width,
        } => polyline(
            root,
            &[(x, yc), (x + SWATCH_W, yc)],
            &color,
            width,
            dashed.then_some(DASH),
        ),
        Swatch::Region {
            color,
            dashed,
            fill: f,
        } => {
            let (x0, x1, y0, y1) = (x + 2, x + SWATCH_W - 2, yc - 7, yc + 7);
            if f {
                let (bx, by) = root.get_base_pixel();
                root.draw(&Rectangle::new(
                    [(x0 - bx, y0 - by), (x1 - bx, y1 - by)],
                    fill(&color),
                ))
                .map_err(de)?;
            }
            polyline(
                root,
                &[(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)],
                &color,
                2,
                dashed.then_some((6, 4)),
            )
        }
        Swatch::Marker { shape, color, size } => {
            marker(root, (x + SWATCH_W / 2, yc), shape, &color, size)
        }
        Swatch::Tinted { line, tint } => {
            let (x0, x1, y0, y1) = (x + 2, x + SWATCH_W - 2, yc - 7, yc + 7);
            let (bx, by) = root.get_base_pixel();
            root.draw(&Rectangle::new(
                [(x0 - bx, y0 - by), (x1 - bx, y1 - by)],
                tint.filled(),
            ))
            .map_err(de)?;
            polyline(
                root,
                &[(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)],
                &line,
                2,
                None,
            )
        }
        Swatch::Hatch { color, group } => {
            let (x0, x1, y0, y1) = (x + 2, x + SWATCH_W - 2, yc - 7, yc + 7);
            let win = Win::new((x0 as f64, x1 as f64), (y0 as f64, y1 as f64));
            for (a, b) in hatch_lines(&win, group, 5.0) {
                polyline(
                    root,
                    &[
                        (a.0.round() as i32, a.1.round() as i32),
                        (b.0.round() as i32, b.1.round() as i32),
                    ],
                    &color,
                    1,
                    None,
                )?;
            }
            polyline(
                root,
                &[(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)],
                &color,
                1,
                None,
            )
        }
        Swatch::None => Ok(()),
    }
}

/// The hatch lines of group l across a pixel box (screen coordinates, y down), `spacing`
/// pixels apart, as segments clipped to the box: the lines {p : n·p = c} with n normal to
/// [`hatch_dir`], c on a grid fixed in the backend's pixels (so neighbouring boxes line up),
/// shifted by half a spacing for groups 4…7.
pub fn hatch_lines(b: &Win, group: usize, spacing: f64) -> Vec<((f64, f64), (f64, f64))> {
    let d = hatch_dir(group);
    let n = (-d.1, d.0);
    let phase = if (group / 4) % 2 == 1 {
        0.5 * spacing
    } else {
        0.0
    };
    let corners = [(b.x0, b.y0), (b.x1, b.y0), (b.x0, b.y1), (b.x1, b.y1)];
    let cs: Vec<f64> = corners.iter().map(|p| n.0 * p.0 + n.1 * p.1).collect();
    let (cmin, cmax) = cs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, z), &c| {
            (a.min(c), z.max(c))
        });
    let mut out = Vec::new();
    if !(spacing > 0.0 && cmin.is_finite() && cmax.is_finite()) {
        return out;
    }
    let mut k = ((cmin - phase) / spacing).ceil();
    // Far more lines than any box needs means a degenerate box: draw none.
    if (cmax - cmin) / spacing > 20_000.0 {
        return out;
    }
    while k * spacing + phase <= cmax {
        let c = k * spacing + phase;
        k += 1.0;
        // A point of the line, then clip the long segment through it.
        let p = (n.0 * c, n.1 * c);
        let far = (b.x1 - b.x0).abs()
            + (b.y1 - b.y0).abs()
            + (p.0 - b.x0).abs()
            + (p.1 - b.y0).abs()
            + 1.0;
        let a = (p.0 - far * d.0, p.1 - far * d.1);
        let z = (p.0 + far * d.0, p.1 + far * d.1);
        if let Some(seg) = super::geom::clip_polyline(&[a, z], b).into_iter().next() {
            if seg.len() == 2 && (seg[0].0 - seg[1].0).abs() + (seg[0].1 - seg[1].1).abs() > 0.5 {
                out.push((seg[0], seg[1]));
            }
        }
    }
    out
}

thread_local! {
    /// The legend boxes drawn since [`legend_boxes_clear`] (absolute backend pixels).
    static LEGEND_BOXES: std::cell::RefCell<Vec<(i32, i32, i32, i32)>> = const { std::cell::RefCell::new(Vec::new()) };
}

fn note_legend_box(b: (i32, i32, i32, i32)) {
    LEGEND_BOXES.with(|v| v.borrow_mut().push(b));
}

pub(crate) fn legend_boxes_clear() {
    LEGEND_BOXES.with(|v| v.borrow_mut().clear());
}

pub(crate) fn legend_boxes_take() -> Vec<(i32, i32, i32, i32)> {
    LEGEND_BOXES.with(|v| std::mem::take(&mut *v.borrow_mut()))
}

/// Where the legend went.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LegendSide {
    Right,
    Bottom,
    /// Not drawn yet: [`overlay_legend`] draws it over the chart once the chart exists.
    Overlay,
}

struct LegendMetrics {
    sizes: Vec<(u32, u32)>,
    line_h: i32,
    col_w: i32,
}

fn metrics<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    entries: &[Entry],
) -> Result<LegendMetrics> {
    let (style, note) = (fonts.legend(), fonts.note());
    let mut sizes = Vec::with_capacity(entries.len());
    for e in entries {
        let st = if e.swatch == Swatch::None {
            &note
        } else {
            &style
        };
        sizes.push(text_size(area, &e.label, st)?);
    }
    let gap = if fonts.compact { 5 } else { 8 };
    let line_h = sizes.iter().map(|s| s.1 as i32).max().unwrap_or(14).max(12) + gap;
    let col_w = (0..entries.len())
        .map(|i| item_w(entries, &sizes, i))
        .max()
        .unwrap_or(0)
        + 2 * LEGEND_PAD;
    Ok(LegendMetrics {
        sizes,
        line_h,
        col_w,
    })
}

fn item_w(entries: &[Entry], sizes: &[(u32, u32)], i: usize) -> i32 {
    let sw = if entries[i].swatch == Swatch::None {
        0
    } else {
        SWATCH_W + SWATCH_GAP
    };
    sw + sizes[i].0 as i32
}

/// A column of entries in a framed box with its top-left corner at (lx, ly).
fn legend_box<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    entries: &[Entry],
    m: &LegendMetrics,
    (lx, ly): (i32, i32),
    background: bool,
) -> Result<()> {
    let box_h = m.line_h * entries.len() as i32 + 2 * LEGEND_PAD - 6;
    note_legend_box((lx, ly, lx + m.col_w, ly + box_h));
    if background {
        let (bx, by) = area.get_base_pixel();
        area.draw(&Rectangle::new(
            [(lx - bx, ly - by), (lx + m.col_w - bx, ly + box_h - by)],
            WHITE.mix(0.9).filled(),
        ))
        .map_err(de)?;
    }
    polyline(
        area,
        &[
            (lx, ly),
            (lx + m.col_w, ly),
            (lx + m.col_w, ly + box_h),
            (lx, ly + box_h),
            (lx, ly),
        ],
        &FRAME,
        1,
        None,
    )?;
    let (style, note) = (fonts.legend(), fonts.note());
    for (k, e) in entries.iter().enumerate() {
        let yc = ly + LEGEND_PAD + m.line_h * k as i32 + m.line_h / 2 - 3;
        draw_swatch(area, e.swatch, lx + LEGEND_PAD, yc)?;
        let (tx, st) = if e.swatch == Swatch::None {
            (lx + LEGEND_PAD, &note)
        } else {
            (lx + LEGEND_PAD + SWATCH_W + SWATCH_GAP, &style)
        };
        text(area, &e.label, (tx, yc), st, (HPos::Left, VPos::Center))?;
    }
    Ok(())
}

/// The title block (notes joined by " · " as its subtitle), then the legend: the area left for
/// the charts and where the legend went.
pub fn titled_legend<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    title: &str,
    notes: &[String],
    entries: &[Entry],
) -> Result<(DrawingArea<DB, Shift>, LegendSide)> {
    let area = title_block(root, fonts, title, &notes.join(" · "))?;
    legend(&area, fonts, entries)
}

/// Lay out the legend beside (wide figures) or below (tall ones) the chart, or leave it for
/// [`overlay_legend`] (small figures); returns the area left for the chart.
pub fn legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    entries: &[Entry],
) -> Result<(DrawingArea<DB, Shift>, LegendSide)> {
    let (w, h) = area.dim_in_pixel();
    let kept = shown_entries(fonts, entries);
    let entries = kept.as_slice();
    if entries.is_empty() {
        return Ok((area.clone(), LegendSide::Right));
    }
    let m = metrics(area, fonts, entries)?;
    let (x0, y0) = area.get_base_pixel();
    if w >= 560 && (m.col_w as f64) <= 0.34 * w as f64 {
        // Right column, top-aligned with the plotting area.
        let (chart, _) = area.split_horizontally(w as i32 - m.col_w - PAD);
        legend_box(
            area,
            fonts,
            entries,
            &m,
            (x0 + w as i32 - m.col_w - PAD, y0 + 12),
            false,
        )?;
        return Ok((chart, LegendSide::Right));
    }
    // Rows below the chart, if the chart keeps at least 60 % of the height.
    let avail = w as i32 - 2 * PAD;
    let mut rows: Vec<Vec<usize>> = vec![vec![]];
    let mut used = 0;
    for i in 0..entries.len() {
        let iw = item_w(entries, &m.sizes, i) + 18;
        if used > 0 && used + iw > avail {
            rows.push(vec![]);
            used = 0;
        }
        used += iw;
        if let Some(r) = rows.last_mut() {
            r.push(i);
        }
    }
    let leg_h = m.line_h * rows.len() as i32 + 8;
    // Over the chart only when below it would leave the chart too little height (under 60 %,
    // or under 150 px for its axes and ticks): a phone's figure (taller than wide) keeps its
    // legend below, a thumbnail overlays it.
    if fonts.compact && ((leg_h as f64) > 0.4 * h as f64 || (h as i32) - leg_h < 150) {
        return Ok((area.clone(), LegendSide::Overlay));
    }
    let split = (h as i32 - leg_h - PAD / 2).max(0);
    let (chart, _) = area.split_vertically(split);
    let widest = rows
        .iter()
        .map(|row| {
            row.iter()
                .map(|&i| item_w(entries, &m.sizes, i) + 18)
                .sum::<i32>()
        })
        .max()
        .unwrap_or(0);
    note_legend_box((
        x0 + PAD,
        y0 + split + 4,
        x0 + PAD + widest - 18,
        y0 + split + 4 + m.line_h * rows.len() as i32,
    ));
    let (style, note) = (fonts.legend(), fonts.note());
    for (r, row) in rows.iter().enumerate() {
        let yc = y0 + split + 4 + m.line_h * r as i32 + m.line_h / 2;
        let mut x = x0 + PAD;
        for &i in row {
            draw_swatch(area, entries[i].swatch, x, yc)?;
            let (tx, st) = if entries[i].swatch == Swatch::None {
                (x, &note)
            } else {
                (x + SWATCH_W + SWATCH_GAP, &style)
            };
            text(
                area,
                &entries[i].label,
                (tx, yc),
                st,
                (HPos::Left, VPos::Center),
            )?;
            x += item_w(entries, &m.sizes, i) + 18;
        }
    }
    Ok((chart, LegendSide::Bottom))
}

/// A legend column at the right of `area` when it takes at most `max_frac` of the width (for
/// small figures whose chart is limited by its height, e.g. equal scales); `None` when it does
/// not fit (then use [`legend`]).
pub fn legend_beside<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    entries: &[Entry],
    max_frac: f64,
) -> Result<Option<DrawingArea<DB, Shift>>> {
    let (w, _) = area.dim_in_pixel();
    let kept = shown_entries(fonts, entries);
    let entries = kept.as_slice();
    if entries.is_empty() {
        return Ok(Some(area.clone()));
    }
    let m = metrics(area, fonts, entries)?;
    if (m.col_w as f64) > max_frac * w as f64 {
        return Ok(None);
    }
    let (x0, y0) = area.get_base_pixel();
    let pad = if fonts.compact { PAD / 2 } else { PAD };
    let (chart, _) = area.split_horizontally(w as i32 - m.col_w - pad);
    legend_box(
        area,
        fonts,
        entries,
        &m,
        (x0 + w as i32 - m.col_w - pad, y0 + 8),
        false,
    )?;
    Ok(Some(chart))
}

/// [`titled_legend`] for an equal-scale chart: on small figures the chart is limited by its
/// height, so the legend goes beside it when it takes at most 45 % of the width.
pub fn titled_legend_beside<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    title: &str,
    notes: &[String],
    entries: &[Entry],
) -> Result<(DrawingArea<DB, Shift>, LegendSide)> {
    let area = title_block(root, fonts, title, &notes.join(" · "))?;
    match fonts
        .compact
        .then(|| legend_beside(&area, fonts, entries, 0.45))
        .transpose()?
        .flatten()
    {
        Some(a) => Ok((a, LegendSide::Right)),
        None => legend(&area, fonts, entries),
    }
}

/// The entries a figure of this size shows.
fn shown_entries(fonts: &Fonts, entries: &[Entry]) -> Vec<Entry> {
    entries
        .iter()
        .filter(|e| !(fonts.compact && e.minor))
        .cloned()
        .collect()
}

/// The corner of the plotting area (top-right, top-left, bottom-right, bottom-left) where a
/// `size` box covers the fewest of `marks` (absolute pixels).
pub fn emptiest_corner<DB: DrawingBackend>(
    chart: &Chart<DB>,
    size: (i32, i32),
    marks: &[(i32, i32)],
) -> (i32, i32) {
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let (w, h) = size;
    let corners = [
        (xr.end - w - 8, yr.start + 8),
        (xr.start + 8, yr.start + 8),
        (xr.end - w - 8, yr.end - h - 8),
        (xr.start + 8, yr.end - h - 8),
    ];
    let count = |c: &(i32, i32)| {
        marks
            .iter()
            .filter(|p| {
                p.0 >= c.0 - 6 && p.0 <= c.0 + w + 6 && p.1 >= c.1 - 6 && p.1 <= c.1 + h + 6
            })
            .count()
    };
    corners
        .iter()
        .copied()
        .min_by_key(count)
        .unwrap_or(corners[0])
}

/// Draw a legend left for later ([`LegendSide::Overlay`]) over the emptiest corner of the chart.
pub fn overlay_legend<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart<DB>,
    fonts: &Fonts,
    entries: &[Entry],
    side: LegendSide,
    marks: &[(i32, i32)],
) -> Result<()> {
    let kept = shown_entries(fonts, entries);
    let entries = kept.as_slice();
    if side != LegendSide::Overlay || entries.is_empty() {
        return Ok(());
    }
    let m = metrics(root, fonts, entries)?;
    let box_h = m.line_h * entries.len() as i32 + 2 * LEGEND_PAD - 6;
    let at = emptiest_corner(chart, (m.col_w, box_h), marks);
    legend_box(root, fonts, entries, &m, at, true)
}

/// Pixel positions of a chart-coordinate polyline, for choosing empty corners.
pub fn marks_of<DB: DrawingBackend>(chart: &Chart<DB>, pts: &[(f64, f64)]) -> Vec<(i32, i32)> {
    pts.iter().map(|&p| px(chart, p)).collect()
}

/// Decimals that make ticks over `span` distinct (about 8 ticks).
pub fn decimals(span: f64) -> usize {
    if !(span.is_finite() && span > 0.0) {
        return 2;
    }
    let step = span / 8.0;
    (-(step.log10().floor())).clamp(0.0, 8.0) as usize
}

/// A number for a label: fixed decimals, typographic minus, no "−0".
pub fn num(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    let neg_zero = s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.');
    if neg_zero {
        s[1..].to_string()
    } else if let Some(rest) = s.strip_prefix('-') {
        format!("−{rest}")
    } else {
        s
    }
}

/// A number with about 3 significant digits.
pub fn sig(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return num(v, 0);
    }
    let d = (2.0 - v.abs().log10().floor()).clamp(0.0, 8.0) as usize;
    let s = num(v, d);
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A number for prose: 3 significant digits, or "2.17 × 10⁻⁵" for tiny and huge magnitudes.
pub fn sci(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-3..1e5).contains(&a) {
        return sig(v);
    }
    let e = a.log10().floor() as i32;
    let m = v / 10f64.powi(e);
    format!("{} × 10{}", num(m, 2), sup(e))
}

/// Unicode superscript of an integer (−5 → "⁻⁵").
pub fn sup(e: i32) -> String {
    e.to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            d => char::from_u32(0x2070 + d.to_digit(10).unwrap_or(0)).unwrap_or(d),
        })
        .collect()
}

/// A power of ten for a log axis: "10⁻³".
pub fn pow10(e: i32) -> String {
    format!("10{}", sup(e))
}

/// Unicode subscript of a number (t = 40 → "₄₀").
pub fn sub(n: usize) -> String {
    n.to_string()
        .chars()
        .map(|c| char::from_u32(0x2080 + c.to_digit(10).unwrap_or(0)).unwrap_or(c))
        .collect()
}

/// α as a percentage ("95 %").
pub fn pct(alpha: f64) -> String {
    let p = alpha * 100.0;
    if (p - p.round()).abs() < 1e-9 {
        format!("{} %", p.round())
    } else {
        format!("{} %", sig(p))
    }
}

/// A 2-D chart with f64 axes.
pub type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Axes of a chart.
pub struct Axes<'s> {
    pub win: Win,
    pub x_desc: &'s str,
    pub y_desc: &'s str,
    /// Integer ticks only on x (time).
    pub x_integer: bool,
    /// Same scale on both axes (the window grows to fit the pixel aspect).
    pub equal: bool,
    /// Draw the x tick labels and description (false for the upper panels of a stack).
    pub x_labels: bool,
}

const M_TOP: i32 = 12;
const M_RIGHT: i32 = 22;
const M_LEFT: i32 = 6;
const M_BOTTOM: i32 = 4;

/// Build a chart with labelled axes and a light grid on `area`; the window of `axes` may grow
/// (equal aspect).
pub fn chart<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    axes: &Axes,
) -> Result<Chart<'a, DB>> {
    chart_with(area, fonts, axes, false)
}

/// A marker at chart point `p` when it lies in the chart's window (its pixel joins `marks`, so
/// the overlay legend avoids it); false when it lies outside, for the caller to say so.
pub fn marker_inside<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart<DB>,
    p: (f64, f64),
    shape: Marker,
    color: &RGBColor,
    marks: &mut Vec<(i32, i32)>,
) -> Result<bool> {
    if !Win::of_chart(chart).contains(p.0, p.1) {
        return Ok(false);
    }
    let q = px(chart, p);
    marks.push(q);
    marker(root, q, shape, color, 5)?;
    Ok(true)
}

/// [`marker_inside`] for each `(point, shape, color, name)` in turn: the names of the points
/// outside the window, for the caller to say so.
pub fn markers_inside<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart<DB>,
    points: &[((f64, f64), Marker, RGBColor, &'static str)],
    marks: &mut Vec<(i32, i32)>,
) -> Result<Vec<&'static str>> {
    let mut outside = Vec::new();
    for &(p, shape, color, what) in points {
        if !marker_inside(root, chart, p, shape, &color, marks)? {
            outside.push(what);
        }
    }
    Ok(outside)
}

/// A chart of a state plane: both axes in the same units, so they share one scale (a disk
/// stays round) and the window grows to the pixel aspect.
pub fn equal_chart<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    win: Win,
    x_desc: &str,
    y_desc: &str,
) -> Result<Chart<'a, DB>> {
    let axes = Axes {
        win,
        x_desc,
        y_desc,
        x_integer: false,
        equal: true,
        x_labels: true,
    };
    chart(area, fonts, &axes)
}

/// A chart whose y values are log10 of the quantity: the axis is linear in log10 and labelled
/// 10ᵏ at decades (with 2·10ᵏ, 5·10ᵏ and unlabelled 3, 4, 6, … ·10ᵏ lines when the window
/// spans fewer than three decades). The caller plots log10 values.
pub fn log_chart<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    axes: &Axes,
) -> Result<Chart<'a, DB>> {
    chart_with(area, fonts, axes, true)
}

/// One tick of a log axis: position (log10), label (empty: grid line only), decade or not.
#[derive(Debug, Clone, PartialEq)]
pub struct LogTick {
    pub at: f64,
    pub label: String,
    pub major: bool,
}

/// A value 10^e·m for a log-axis label: plain decimals between 10⁻³ and 10⁴, "2·10⁻⁵" outside.
fn log_label(m: u32, e: i32) -> String {
    if (-3..4).contains(&e) {
        let v = m as f64 * 10f64.powi(e);
        num(v, (-e).max(0) as usize)
    } else if m == 1 {
        pow10(e)
    } else {
        format!("{m}·{}", pow10(e))
    }
}

/// The ticks of a log axis over [lo, hi] (log10 units) on `px` pixels.
pub fn log_ticks(lo: f64, hi: f64, px: i32) -> Vec<LogTick> {
    let mut out = Vec::new();
    if !(lo.is_finite() && hi.is_finite() && hi > lo) {
        return out;
    }
    let span = hi - lo;
    let max_labels = ((px / 28).clamp(3, 12)) as f64;
    let (k0, k1) = (lo.floor() as i64, hi.ceil() as i64);
    if span >= 3.0 || k1 - k0 > 400 {
        // Decades, every `step`-th labelled.
        let step = [1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0]
            .into_iter()
            .find(|d| span / d <= max_labels)
            .unwrap_or(1000.0) as i64;
        let per_decade = px as f64 / span;
        for k in k0..=k1 {
            let at = k as f64;
            if at < lo || at > hi {
                continue;
            }
            let labelled = k.rem_euclid(step) == 0;
            if labelled || span <= 80.0 {
                out.push(LogTick {
                    at,
                    label: if labelled {
                        pow10(k as i32)
                    } else {
                        String::new()
                    },
                    major: labelled,
                });
            }
            if step == 1 && per_decade > 70.0 {
                for m in 2..10 {
                    let at = k as f64 + (m as f64).log10();
                    if at > lo && at < hi {
                        out.push(LogTick {
                            at,
                            label: String::new(),
                            major: false,
                        });
                    }
                }
            }
        }
        return out;
    }
    // Fewer than three decades: 1, 2, 5 labelled, the other mantissas as light lines; all
    // labelled when that leaves fewer than three labels.
    let mut all = Vec::new();
    for k in k0..=k1 {
        for m in 1..10u32 {
            let at = k as f64 + (m as f64).log10();
            if at >= lo - 1e-12 && at <= hi + 1e-12 {
                all.push((at, m, k as i32));
            }
        }
    }
    let main = all.iter().filter(|t| matches!(t.1, 1 | 2 | 5)).count();
    let dense = main < 3;
    // Drop labels closer than ~16 px.
    let mut last = f64::NEG_INFINITY;
    for (at, m, e) in all {
        let want = dense || matches!(m, 1 | 2 | 5);
        let room = (at - last) / span * px as f64 >= 16.0;
        let label = if want && room {
            last = at;
            log_label(m, e)
        } else {
            String::new()
        };
        out.push(LogTick {
            at,
            label,
            major: m == 1,
        });
    }
    out
}

fn chart_with<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    axes: &Axes,
    log_y: bool,
) -> Result<Chart<'a, DB>> {
    let mut win = axes.win;
    let yd = decimals(win.y1 - win.y0);
    let tick = fonts.tick();
    let desc = fonts.axis();
    let desc_h = text_size(area, "Xg", &desc)?.1 as i32;
    let tick_h = text_size(area, "0", &tick)?.1 as i32;
    let x_area = if axes.x_labels {
        tick_h + desc_h + 22
    } else {
        10
    };
    let (w, h) = area.dim_in_pixel();
    let ph = h as i32 - x_area - M_TOP - M_BOTTOM;
    let ticks = if log_y {
        log_ticks(win.y0, win.y1, ph)
    } else {
        Vec::new()
    };
    let mut yw = 0;
    if log_y {
        for t in &ticks {
            yw = yw.max(text_size(area, &t.label, &tick)?.0 as i32);
        }
    } else {
        for v in [win.y0, win.y1, 0.5 * (win.y0 + win.y1)] {
            yw = yw.max(text_size(area, &num(v, yd), &tick)?.0 as i32);
        }
    }
    let y_area = yw + desc_h + 20;
    let pw = w as i32 - y_area - M_LEFT - M_RIGHT;
    if pw < 40 || ph < 30 {
        return Err(Error::field(
            "size",
            format!("{w} × {h} pixels leave no room for the chart: make the figure larger"),
        ));
    }
    if axes.equal {
        win = win.equal_aspect(pw as f64, ph as f64);
    }
    // Decimals of the x ticks from the final window (equal aspect may have widened it).
    let xd = if axes.x_integer {
        0
    } else {
        decimals(win.x1 - win.x0)
    };
    let y_desc = shorten(area, axes.y_desc, &desc, (ph + x_area / 2).max(40) as u32)?;
    let x_desc = shorten(area, axes.x_desc, &desc, pw.max(40) as u32)?;
    let mut chart = ChartBuilder::on(area)
        .margin_top(M_TOP)
        .margin_right(M_RIGHT)
        .margin_left(M_LEFT)
        .margin_bottom(M_BOTTOM)
        .x_label_area_size(x_area)
        .y_label_area_size(y_area)
        .build_cartesian_2d(win.x0..win.x1, win.y0..win.y1)
        .map_err(de)?;
    let fx = move |v: &f64| {
        if axes.x_integer && (v - v.round()).abs() > 1e-6 {
            String::new()
        } else {
            num(*v, xd)
        }
    };
    let fy = move |v: &f64| num(*v, yd);
    let no_label = |_: &f64| String::new();
    let mut mesh = chart.configure_mesh();
    mesh.y_desc(y_desc)
        .label_style(tick.clone())
        .axis_desc_style(desc.clone())
        .x_labels(10)
        .y_labels(((ph / 45).clamp(3, 12)) as usize)
        .max_light_lines(4)
        .light_line_style(GRID_LIGHT)
        .bold_line_style(GRID)
        .axis_style(MUTED);
    if log_y {
        mesh.y_label_formatter(&no_label)
            .disable_y_mesh()
            .set_tick_mark_size(LabelAreaPosition::Left, 0);
    } else {
        mesh.y_label_formatter(&fy);
    }
    if axes.x_labels {
        mesh.x_desc(x_desc).x_label_formatter(&fx);
    } else {
        mesh.x_label_formatter(&no_label);
    }
    mesh.draw().map_err(de)?;
    if log_y {
        // The grid lines and labels of the decades (under everything drawn later).
        let (xr, _) = chart.plotting_area().get_pixel_range();
        let root = chart.plotting_area().strip_coord_spec();
        let parent = area;
        for t in &ticks {
            let a = px(&chart, (win.x0, t.at));
            let b = (xr.end - 1, a.1);
            let a = (xr.start, a.1);
            let color = if t.major { GRID } else { GRID_LIGHT };
            polyline(&root, &[a, b], &color, 1, None)?;
            if !t.label.is_empty() {
                polyline(parent, &[(a.0 - 5, a.1), (a.0, a.1)], &MUTED, 1, None)?;
                text(
                    parent,
                    &t.label,
                    (a.0 - 8, a.1),
                    &tick,
                    (HPos::Right, VPos::Center),
                )?;
            }
        }
    }
    Ok(chart)
}

/// The frame (ranges and pixel box) of a chart.
pub fn frame_of<DB: DrawingBackend>(chart: &Chart<DB>, x_label: &str, y_label: &str) -> Frame {
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let (x, y) = (chart.x_range(), chart.y_range());
    Frame {
        x_range: (x.start, x.end),
        y_range: (y.start, y.end),
        plot_area: (xr.start, yr.start, xr.end, yr.end),
        x_label: x_label.to_string(),
        y_label: y_label.to_string(),
        more: vec![],
        legends: vec![],
    }
}

/// Map chart coordinates to absolute backend pixels.
pub fn px<DB: DrawingBackend>(chart: &Chart<DB>, p: (f64, f64)) -> (i32, i32) {
    chart.backend_coord(&p)
}

/// Draw a polyline given in chart coordinates, clipped to the chart's window.
pub fn path<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart<DB>,
    pts: &[(f64, f64)],
    color: &RGBColor,
    width: u32,
    dash: Option<(i32, i32)>,
) -> Result<()> {
    let win = Win::of_chart(chart);
    for piece in super::geom::clip_polyline(pts, &win) {
        let p: Vec<(i32, i32)> = piece.iter().map(|&q| px(chart, q)).collect();
        polyline(root, &p, color, width, dash)?;
    }
    Ok(())
}

/// A closed region boundary (chart coordinates), optionally filled; clipped to the window.
pub fn region<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart<DB>,
    boundary: &[(f64, f64)],
    color: &RGBColor,
    dashed: bool,
    filled: bool,
) -> Result<()> {
    if boundary.is_empty() {
        return Ok(());
    }
    let mut closed = boundary.to_vec();
    closed.push(boundary[0]);
    let win = Win::of_chart(chart);
    if filled && closed.iter().all(|&(x, y)| win.contains(x, y)) {
        let (bx, by) = root.get_base_pixel();
        let p: Vec<(i32, i32)> = closed
            .iter()
            .map(|&q| {
                let (x, y) = px(chart, q);
                (x - bx, y - by)
            })
            .collect();
        root.draw(&Polygon::new(p, fill(color))).map_err(de)?;
    }
    path(
        root,
        chart,
        &closed,
        color,
        2,
        if dashed { Some(DASH) } else { None },
    )
}

/// A filled band between `lo` and `hi` over `xs` (chart coordinates, inside the window).
pub fn band<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart<DB>,
    xs: &[f64],
    lo: &[f64],
    hi: &[f64],
    color: &RGBColor,
) -> Result<()> {
    if xs.len() < 2 {
        return Ok(());
    }
    let (bx, by) = root.get_base_pixel();
    let win = Win::of_chart(chart);
    let clamp = |x: f64, y: f64| px(chart, (x.clamp(win.x0, win.x1), y.clamp(win.y0, win.y1)));
    let mut p: Vec<(i32, i32)> = Vec::with_capacity(2 * xs.len());
    for (x, y) in xs.iter().zip(hi) {
        p.push(clamp(*x, *y));
    }
    for (x, y) in xs.iter().zip(lo).rev() {
        p.push(clamp(*x, *y));
    }
    let n = p.len() / 2;
    let mut edge = thin(&p[..n]);
    edge.extend(thin(&p[n..]));
    let p: Vec<(i32, i32)> = edge.into_iter().map(|(x, y)| (x - bx, y - by)).collect();
    root.draw(&Polygon::new(p, fill(color))).map_err(de)
}

/// A vertical time cursor with its label at the top of the plotting area.
pub fn cursor<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart<DB>,
    fonts: &Fonts,
    x: f64,
    label: &str,
) -> Result<()> {
    let win = Win::of_chart(chart);
    if !(x >= win.x0 && x <= win.x1) {
        return Ok(());
    }
    let (top, bottom) = (px(chart, (x, win.y1)), px(chart, (x, win.y0)));
    polyline(root, &[top, bottom], &CURSOR, 1, Some((5, 4)))?;
    let (xr, _) = chart.plotting_area().get_pixel_range();
    let style = fonts.note();
    let tw = text_size(root, label, &style)?.0 as i32;
    // Label right of the line, or left of it near the right edge.
    if top.0 + 4 + tw < xr.end {
        text(
            root,
            label,
            (top.0 + 4, top.1 + 3),
            &style,
            (HPos::Left, VPos::Top),
        )
    } else {
        text(
            root,
            label,
            (top.0 - 4, top.1 + 3),
            &style,
            (HPos::Right, VPos::Top),
        )
    }
}

/// [`note_box`] in the text ink with a frame-grey border.
pub fn chart_notes<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart<DB>,
    fonts: &Fonts,
    lines: &[String],
    marks: &mut Vec<(i32, i32)>,
) -> Result<()> {
    note_box(root, chart, fonts, lines, marks, &TEXT, &FRAME)
}

/// Notes in a framed box over the emptiest corner of a chart, wrapped to its width, in `ink`
/// with a `border`; their pixels join `marks` (so legends avoid them).
pub fn note_box<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart<DB>,
    fonts: &Fonts,
    lines: &[String],
    marks: &mut Vec<(i32, i32)>,
    ink: &RGBColor,
    border: &RGBColor,
) -> Result<()> {
    if lines.is_empty() {
        return Ok(());
    }
    let st = fonts.legend().color(ink);
    let (xr, _) = chart.plotting_area().get_pixel_range();
    let max_w = ((xr.end - xr.start) as u32).saturating_sub(28).max(60);
    let mut wrapped = Vec::new();
    for l in lines {
        wrapped.extend(wrap(root, l, &st, max_w)?);
    }
    let (mut w, mut h) = (0, 0);
    for s in &wrapped {
        let (tw, th) = text_size(root, s, &st)?;
        w = w.max(tw as i32);
        h += th as i32 + 4;
    }
    let (bw, bh) = (w + 12, h + 8);
    let at = emptiest_corner(chart, (bw, bh), marks);
    let (bx, by) = root.get_base_pixel();
    root.draw(&Rectangle::new(
        [(at.0 - bx, at.1 - by), (at.0 + bw - bx, at.1 + bh - by)],
        WHITE.mix(0.92).filled(),
    ))
    .map_err(de)?;
    polyline(
        root,
        &[
            at,
            (at.0 + bw, at.1),
            (at.0 + bw, at.1 + bh),
            (at.0, at.1 + bh),
            at,
        ],
        border,
        1,
        None,
    )?;
    let mut y = at.1 + 6;
    for s in &wrapped {
        text(root, s, (at.0 + 6, y), &st, (HPos::Left, VPos::Top))?;
        y += text_size(root, s, &st)?.1 as i32 + 4;
    }
    for k in 0..6 {
        for yy in [at.1 + 2, at.1 + bh / 2, at.1 + bh - 2] {
            marks.push((at.0 + k * bw / 5, yy));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::rest_after;

    #[test]
    fn the_rest_of_a_wrapped_text_keeps_its_separators() {
        let s = "in ball: yes, in box: yes · n = 3: projection on x₂, x₃ · more";
        // Broken at words inside the first piece, then at a " · ".
        let lines = ["in ball: yes,".to_string(), "in box: yes".to_string()];
        assert_eq!(
            rest_after(s, &lines[..1]),
            "in box: yes · n = 3: projection on x₂, x₃ · more"
        );
        assert_eq!(rest_after(s, &lines), "n = 3: projection on x₂, x₃ · more");
        assert_eq!(rest_after(s, &[]), s);
    }
}
