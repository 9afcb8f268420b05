//! Legend layer, above the marks: entries and their swatches, laid out below, beside or over
//! the chart (in its emptiest corner); each box drawn is noted for the page's frame.

use super::axes::*;
use super::marks::*;
use super::palette::*;
use super::text::*;
use crate::error::Result;
use crate::plot::erase::de;
use crate::plot::geom::Win;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

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
