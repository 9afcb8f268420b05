//! Axes layer, above text and numbers: charts with labelled axes and a light grid (linear,
//! equal-aspect, log10), their frame for the page, and the map from chart units to pixels.

use super::number::{decimals, num, pow10};
use super::palette::*;
use super::text::*;
use crate::error::{Error, Result};
use crate::plot::erase::de;
use crate::plot::geom::Win;
use crate::plot::view::Frame;
use crate::scenario::{FigureContext, TimeIndex};
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
    chart_with(area, fonts, axes, YAxis::Linear, None)
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
    chart_with(area, fonts, &axes, YAxis::Rows, None)
}

/// A chart whose y values are log10 of the quantity: the axis is linear in log10 and labelled
/// 10ᵏ at decades (with 2·10ᵏ, 5·10ᵏ and unlabelled 3, 4, 6, … ·10ᵏ lines when the window
/// spans fewer than three decades). The caller plots log10 values.
pub fn log_chart<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    axes: &Axes,
) -> Result<Chart<'a, DB>> {
    chart_with(area, fonts, axes, YAxis::Log, None)
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

/// The record's own time on a time axis and in the words of a figure (`data.t`, the report's
/// [`FigureContext::times`]): the one place a panel's step becomes the record's time. A panel
/// says how its steps count against the record's rows ([`TimeIndex`]: SCF, KF, conformal and
/// uniform count t = 1, 2, …, row t − 1; ubb counts k = 0, 1, …, row k, Tempo's y(k)); its
/// time charts ([`time_chart`]) then label their ticks with the record's time, its cursor and
/// notes say "t = 40 (1910)" ([`RecordTimes::at`]). Without record times (a simulation, a
/// record without `data.t`) every axis and every word is as it was.
#[derive(Debug, Clone, Copy)]
pub struct RecordTimes<'a> {
    labels: &'a [String],
    /// The step of the record's first row (1 for t = 1, 2, …; 0 for ubb's k): row i is step
    /// i + first_step.
    first_step: usize,
}

/// The x axis name of a time chart whose ticks read the record's own time. The record's
/// column name is not known (`data.t` holds the times only), so the axis says what they are and
/// where they come from; a narrow chart drops the parenthesis ([`without_qualifiers`]).
pub const RECORD_TIME_AXIS: &str = "time (the record's data.t)";

/// One tick of a time axis: position (steps), label (empty: a light grid line only), labelled
/// or not.
#[derive(Debug, Clone, PartialEq)]
pub struct TimeTick {
    pub at: f64,
    pub label: String,
    pub major: bool,
}

impl<'a> RecordTimes<'a> {
    /// The record times of a report's figure, for a panel counting its steps by `index`
    /// (`NotTime`: none).
    pub fn of(fig: &'a FigureContext, index: TimeIndex) -> RecordTimes<'a> {
        match index {
            TimeIndex::OneBased => RecordTimes {
                labels: &fig.times,
                first_step: 1,
            },
            TimeIndex::ZeroBased => RecordTimes {
                labels: &fig.times,
                first_step: 0,
            },
            TimeIndex::NotTime => RecordTimes {
                labels: &[],
                first_step: 1,
            },
        }
    }
    /// Whether the record has no times (the axes then count steps as before).
    pub fn is_empty(&self) -> bool {
        self.labels.is_empty()
    }
    /// The record's time at step `step`, if the record has one there.
    pub fn label(&self, step: usize) -> Option<&'a str> {
        step.checked_sub(self.first_step)
            .and_then(|row| self.labels.get(row))
            .map(String::as_str)
    }
    /// "t = 40 (1910)": a step with its record time, as titles, notes and cursors say it;
    /// "t = 40" where the record has no time.
    pub fn at(&self, symbol: &str, step: usize) -> String {
        match self.label(step) {
            Some(l) => format!("{symbol} = {step} ({l})"),
            None => format!("{symbol} = {step}"),
        }
    }
    /// The name of the x axis: [`RECORD_TIME_AXIS`] when the ticks read the record's time,
    /// else the panel's own (`plain`, which counts steps).
    pub fn axis_name<'b>(&self, plain: &'b str) -> &'b str {
        if self.is_empty() {
            plain
        } else {
            RECORD_TIME_AXIS
        }
    }
    /// The record's times as numbers (years, seconds), when every one is a finite number and
    /// they increase strictly; `None` for dates (or a report whose times are not in order).
    fn numbers(&self) -> Option<Vec<f64>> {
        let v: Vec<f64> = self
            .labels
            .iter()
            .map(|l| l.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
            .collect::<Option<_>>()?;
        v.windows(2).all(|w| w[0] < w[1]).then_some(v)
    }
    /// The ticks of a time axis over steps [x0, x1] with at most `max_labels` labels (at
    /// least 2). Where the record's times are numbers, the labels are at round values of
    /// the record's own time (1880, 1900, … for years; a tick between two rows sits where
    /// the time lies between theirs), with light lines between; otherwise (dates) at every
    /// 1st, 2nd, 5th, 10th, … row from the first shown, labelled with the row's time as
    /// written. Only inside the record's rows (no time is invented before or after it).
    pub fn ticks(&self, x0: f64, x1: f64, max_labels: usize) -> Vec<TimeTick> {
        let n = self.labels.len();
        if n == 0 || !(x0.is_finite() && x1.is_finite() && x1 >= x0) {
            return Vec::new();
        }
        let max_labels = max_labels.max(2);
        let base = self.first_step as f64;
        // The rows whose step lies in the window.
        let first = (x0 - base).ceil().max(0.0);
        let last = (x1 - base).floor().min((n - 1) as f64);
        if first > last {
            return Vec::new();
        }
        let (first, last) = (first as usize, last as usize);
        let Some(v) = self.numbers() else {
            // Dates: a nice number of rows apart, from the first row shown.
            let rows = last - first + 1;
            let step = nice_count(rows, max_labels);
            return (first..=last)
                .step_by(step)
                .map(|i| TimeTick {
                    at: i as f64 + base,
                    label: self.labels[i].clone(),
                    major: true,
                })
                .collect();
        };
        let (lo, hi) = (v[first], v[last]);
        if last == first {
            return vec![TimeTick {
                at: first as f64 + base,
                label: self.labels[first].clone(),
                major: true,
            }];
        }
        let whole = v.iter().all(|x| x.fract() == 0.0);
        let Some((step, minor)) = nice_step(hi - lo, max_labels, whole) else {
            return Vec::new();
        };
        let places = if step >= 1.0 {
            0
        } else {
            (-step.log10()).ceil().max(0.0) as usize
        };
        // The step of a time between rows i and i + 1, by its place between their times.
        let position = |x: f64| -> f64 {
            let i = v.partition_point(|&r| r <= x).clamp(1, n - 1) - 1;
            let f = ((x - v[i]) / (v[i + 1] - v[i])).clamp(0.0, 1.0);
            i as f64 + f + base
        };
        let per_major = (step / minor).round() as i64;
        let (k0, k1) = ((lo / minor).ceil() as i64, (hi / minor).floor() as i64);
        let mut out = Vec::new();
        for k in k0..=k1 {
            let x = k as f64 * minor;
            let major = k.rem_euclid(per_major) == 0;
            out.push(TimeTick {
                at: position(x),
                label: if major { num(x, places) } else { String::new() },
                major,
            });
        }
        out
    }
}

/// The step between labelled ticks over `span` with at most `max_labels` labels: 1, 2 or 5
/// times a power of ten (at least 1 for whole-number times such as years), and the step of
/// the light lines between them (a fifth of it, or half of a 2·10ᵏ; none finer than 1 for
/// whole numbers, nor more than 400 lines in all).
fn nice_step(span: f64, max_labels: usize, whole: bool) -> Option<(f64, f64)> {
    if !(span.is_finite() && span > 0.0) {
        return None;
    }
    let raw = span / max_labels as f64;
    let mut e = raw.log10().floor() as i32;
    let step = loop {
        let p = 10f64.powi(e);
        if let Some(m) = [1.0, 2.0, 5.0]
            .into_iter()
            .find(|m| span / (m * p) <= max_labels as f64)
        {
            break m * p;
        }
        e += 1;
    };
    let step = if whole { step.max(1.0) } else { step };
    let mantissa = (step / 10f64.powi(step.log10().floor() as i32)).round();
    let mut minor = if mantissa == 2.0 {
        step / 2.0
    } else {
        step / 5.0
    };
    if (whole && minor < 1.0) || span / minor > 400.0 {
        minor = step;
    }
    Some((step, minor))
}

/// Every `step`-th of `count` rows, `step` the least of 1, 2, 5, 10, 20, … leaving at most
/// `max_labels` of them.
fn nice_count(count: usize, max_labels: usize) -> usize {
    let mut p = 1usize;
    loop {
        for m in [1, 2, 5] {
            let step = m * p;
            if count.div_ceil(step) <= max_labels {
                return step;
            }
        }
        p = p.saturating_mul(10);
    }
}

/// A time chart ([`chart`]) whose x ticks read the record's own time ([`RecordTimes::ticks`])
/// when it has one; the panel passes the axis name of [`RecordTimes::axis_name`]. Without
/// record times it is [`chart`].
pub fn time_chart<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    axes: &Axes,
    record: &RecordTimes,
) -> Result<Chart<'a, DB>> {
    let record = (!record.is_empty()).then_some(record);
    chart_with(area, fonts, axes, YAxis::Linear, record)
}

fn chart_with<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    axes: &Axes,
    y_axis: YAxis,
    record: Option<&RecordTimes>,
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
    if record.is_some() {
        // The record's time: ticks, grid lines and labels drawn below, after the mesh.
        mesh.x_label_formatter(&no_label)
            .disable_x_mesh()
            .set_tick_mark_size(LabelAreaPosition::Bottom, 0);
        if axes.x_labels {
            mesh.x_desc(x_desc);
        }
    } else if axes.x_labels {
        mesh.x_desc(x_desc).x_label_formatter(&fx);
    } else {
        mesh.x_label_formatter(&no_label);
    }
    mesh.draw().map_err(de)?;
    if let Some(record) = record {
        record_ticks(area, &chart, &tick, record, axes.x_labels, pw)?;
    }
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

/// The x grid lines, tick marks and labels of a time chart that reads the record's time: as
/// many labels as fit side by side (the widest of the record's labels measured), light lines
/// between them where they are at least 6 pixels apart.
fn record_ticks<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &Chart<DB>,
    tick: &TextStyle,
    record: &RecordTimes,
    labelled: bool,
    pw: i32,
) -> Result<()> {
    let win = Win::of_chart(chart);
    let widest = record
        .labels
        .iter()
        .max_by_key(|l| l.chars().count())
        .map_or(Ok((0, 0)), |l| text_size(area, l, tick))?
        .0 as i32;
    let max_labels = (pw / (widest + 16).max(1)).clamp(2, (pw / 55).clamp(3, 10)) as usize;
    let ticks = record.ticks(win.x0, win.x1, max_labels);
    let minor_px = {
        let mut at: Vec<f64> = ticks.iter().map(|t| t.at).collect();
        at.dedup();
        let gap = at
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min);
        px(chart, (win.x0 + gap.min(win.x1 - win.x0), win.y0)).0 - px(chart, (win.x0, win.y0)).0
    };
    let root = chart.plotting_area().strip_coord_spec();
    for t in &ticks {
        if !t.major && minor_px < 6 {
            continue;
        }
        let bottom = px(chart, (t.at, win.y0));
        let top = px(chart, (t.at, win.y1));
        let color = if t.major { GRID } else { GRID_LIGHT };
        polyline(&root, &[top, (bottom.0, bottom.1 - 1)], &color, 1, None)?;
        if labelled && t.major {
            polyline(area, &[bottom, (bottom.0, bottom.1 + 5)], &MUTED, 1, None)?;
            text(
                area,
                &t.label,
                (bottom.0, bottom.1 + 10),
                tick,
                (HPos::Center, VPos::Top),
            )?;
        }
    }
    Ok(())
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
