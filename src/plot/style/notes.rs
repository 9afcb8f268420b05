//! Notes layer, the top: framed notes over the emptiest corner of a chart.

use super::axes::*;
use super::legend::*;
use super::palette::*;
use super::text::*;
use crate::error::Result;
use crate::plot::erase::de;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

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
