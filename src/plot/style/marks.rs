//! Marks layer, above the axes: point markers, fills, polylines and bands in chart units
//! (clipped to the window), the time cursor and the hatch lines.

use super::axes::*;
use super::palette::*;
use super::text::*;
use crate::error::Result;
use crate::plot::erase::de;
use crate::plot::geom::Win;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

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
        if let Some(seg) = crate::plot::geom::clip_polyline(&[a, z], b)
            .into_iter()
            .next()
        {
            if seg.len() == 2 && (seg[0].0 - seg[1].0).abs() + (seg[0].1 - seg[1].1).abs() > 0.5 {
                out.push((seg[0], seg[1]));
            }
        }
    }
    out
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
    for piece in crate::plot::geom::clip_polyline(pts, &win) {
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

/// The box (x0, y0, x1, y1, absolute pixels) [`cursor`] draws its label in, for the labels
/// drawn after it to avoid; None when the cursor lies outside the window.
pub fn cursor_label_box<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart<DB>,
    fonts: &Fonts,
    x: f64,
    label: &str,
) -> Result<Option<(i32, i32, i32, i32)>> {
    let win = Win::of_chart(chart);
    if !(x >= win.x0 && x <= win.x1) {
        return Ok(None);
    }
    let top = px(chart, (x, win.y1));
    let (xr, _) = chart.plotting_area().get_pixel_range();
    let (tw, th) = text_size(root, label, &fonts.note())?;
    let (tw, th) = (tw as i32, th as i32);
    let (y0, y1) = (top.1 + 3, top.1 + 3 + th);
    Ok(Some(if top.0 + 4 + tw < xr.end {
        (top.0 + 4, y0, top.0 + 4 + tw, y1)
    } else {
        (top.0 - 4 - tw, y0, top.0 - 4, y1)
    }))
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
    // The label right of the line, or left of it near the right edge: where
    // [`cursor_label_box`] says, so that the labels drawn after it can avoid it.
    match cursor_label_box(root, chart, fonts, x, label)? {
        Some((x0, y0, _, _)) => text(
            root,
            label,
            (x0, y0),
            &fonts.note(),
            (HPos::Left, VPos::Top),
        ),
        None => Ok(()),
    }
}
