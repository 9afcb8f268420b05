//! Axes layer, above text and numbers: charts with labelled axes and a light grid (linear,
//! equal-aspect, log10), their frame for the page, and the map from chart units to pixels.

use super::number::{decimals, num, pow10};
use super::palette::*;
use super::text::*;
use crate::error::{Error, Result};
use crate::plot::erase::de;
use crate::plot::geom::Win;
use crate::plot::view::Frame;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

impl Win {
    /// The window of a chart.
    pub fn of_chart<DB: DrawingBackend>(chart: &Chart<DB>) -> Win {
        let (x, y) = (chart.x_range(), chart.y_range());
        Win::new((x.start, x.end), (y.start, y.end))
    }
}

/// Pixel positions of a chart-coordinate polyline, for choosing empty corners.
pub fn marks_of<DB: DrawingBackend>(chart: &Chart<DB>, pts: &[(f64, f64)]) -> Vec<(i32, i32)> {
    pts.iter().map(|&p| px(chart, p)).collect()
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
    chart_with(area, fonts, axes, YAxis::Linear)
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

/// A chart of rows (y = 0, 1, … one per row, named by the caller beside each): x labelled, the
/// y axis without numbers or name (the compare's intervals of a scalar state, side by side).
pub fn rows_chart<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    win: Win,
    x_desc: &str,
) -> Result<Chart<'a, DB>> {
    let axes = Axes {
        win,
        x_desc,
        y_desc: "",
        x_integer: false,
        equal: false,
        x_labels: true,
    };
    chart_with(area, fonts, &axes, YAxis::Rows)
}

/// A chart whose y values are log10 of the quantity: the axis is linear in log10 and labelled
/// 10ᵏ at decades (with 2·10ᵏ, 5·10ᵏ and unlabelled 3, 4, 6, … ·10ᵏ lines when the window
/// spans fewer than three decades). The caller plots log10 values.
pub fn log_chart<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    axes: &Axes,
) -> Result<Chart<'a, DB>> {
    chart_with(area, fonts, axes, YAxis::Log)
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

/// How a chart's y axis is labelled.
#[derive(Clone, Copy, PartialEq)]
enum YAxis {
    Linear,
    /// log10 values, labelled at decades.
    Log,
    /// Rows: no numbers (the caller names each row).
    Rows,
}

fn chart_with<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    axes: &Axes,
    y_axis: YAxis,
) -> Result<Chart<'a, DB>> {
    let log_y = y_axis == YAxis::Log;
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
    } else if y_axis == YAxis::Linear {
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
    // An axis name that does not fit even without its qualifiers is left out rather than cut
    // (a stack of short charts: each has its name as a heading above it).
    let y_desc = without_qualifiers(area, axes.y_desc, &desc, (ph + x_area / 2).max(0) as u32)?
        .unwrap_or_default();
    let x_desc =
        without_qualifiers(area, axes.x_desc, &desc, pw.max(0) as u32)?.unwrap_or_default();
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
        .x_labels(((pw / 55).clamp(3, 10)) as usize)
        .y_labels(((ph / 45).clamp(3, 12)) as usize)
        .max_light_lines(4)
        .light_line_style(GRID_LIGHT)
        .bold_line_style(GRID)
        .axis_style(MUTED);
    if log_y || y_axis == YAxis::Rows {
        // Log values get the decades' labels below; rows are named by the caller.
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
