//! The time-series panels of a uniform-innovation report (Pavelková, "Estimation of LU model with uniform
//! innovations", Section 5): Fig. 1 (`ustates`: states, LP and KF estimates and their errors,
//! the optimal-face ranges of the window at the cursor), Fig. 2 (`uoutput`: the output, its
//! one-step prediction and the prediction error) with what every uniform panel
//! shares: the names of all four, the check of the report's uniform part ([`check`], [`U`]),
//! the grid of charts and the time axis with its cursor and window band. Fig. 3 (`uparams`:
//! the entries of Â and the half-widths x̂ᵣ, ŷᵣ over time with the true values dashed) is drawn
//! in `params.rs`, the consistent-state polygon (`upolygon`) in `polygon.rs`.
//!
//! Every time chart spans t = 0 … T and carries the cursor at the report's window time
//! (`at.time`, or the view's time); the grey band marks the sliding window x_{first−1} … x_t
//! whose LP the report solved there.
//!
//! A report on the user's data has no truth: no true curves or values, no KF (it needs the
//! true Θ and half-widths), and the error charts say why they are empty.

use crate::error::{Error, Result};
use crate::plot::figures::{Area, Request};
use crate::plot::geom::Win;
use crate::plot::style::{
    self, sig, sub, Axes, Entry, Fonts, LegendSide, RecordTimes, Swatch, FACE, KF, TRUTH,
    UNIFORM_LP, WINDOW,
};
use crate::plot::view::PanelSpec;
use crate::plot::view::{Frame, Panel, View};
use crate::scenario::{FigureContext, Report, TimeIndex, UniformReport};
use crate::uniform::Joint;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

/// Uniform-innovation paper, Fig. 1: states, LP and KF estimates, estimation errors and
/// the optimal-face ranges of the window at the cursor.
pub(crate) static STATES: PanelSpec = PanelSpec::new(
    "ustates",
    "states, LP and Kalman estimates and their errors over time (uniform Fig. 1)",
);
/// Uniform-innovation paper, Fig. 2: the output, its one-step prediction and the error.
pub(crate) static OUTPUT: PanelSpec = PanelSpec::new(
    "uoutput",
    "output, its one-step prediction and the prediction error (uniform Fig. 2)",
);
/// Uniform-innovation paper, Fig. 3: the entries of Â and the half-widths over time.
pub(crate) static PARAMS: PanelSpec = PanelSpec::new(
    "uparams",
    "entries of Â and the estimated half-widths over time (uniform Fig. 3)",
);
/// The states consistent with the window at the cursor (a polygon in the plane
/// components) with the truth, the LP and KF estimates and the optimal-face box.
pub(crate) static POLYGON: PanelSpec = PanelSpec::new("upolygon", "consistent-state polygon at the time cursor with the truth, LP and Kalman estimates and the optimal-face box");

/// The report's uniform part, or an error naming the panel.
pub fn uniform_of(report: &Report, panel: Panel) -> Result<&UniformReport> {
    report.uniform.as_ref().ok_or_else(|| {
        let choose = if report.lscr.is_some() {
            "choose region"
        } else if report.glls.is_some() {
            "choose singular, index, plane or precision"
        } else {
            "choose state, series or coverage"
        };
        Error::field(
            "panel",
            format!(
                "\"{}\" draws a uniform-innovation figure, but this report (method \"{}\") has no uniform part: {choose}",
                panel.name(),
                report.method
            ),
        )
    })
}

fn finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

fn rows_ok(rows: &[Vec<f64>], r: usize, c: usize) -> bool {
    rows.len() == r && rows.iter().all(|row| row.len() == c && finite(row))
}

/// A checked uniform report and the shown time.
pub(crate) struct U<'a> {
    pub u: &'a UniformReport,
    /// State and output dimensions, number of steps T.
    pub n: usize,
    pub m: usize,
    pub steps: usize,
    /// Cursor, 1 ≤ t ≤ T.
    pub t: usize,
    /// x_0 … x_T when simulated.
    pub truth: Option<&'a [Vec<f64>]>,
    /// KF estimates x_1 … x_T when simulated.
    pub kf: Option<&'a [Vec<f64>]>,
    /// The record's own time at t = 1 … T (row t − 1 of the user's data; none simulated).
    pub record: RecordTimes<'a>,
}

impl U<'_> {
    /// The estimator's name as the paper calls it.
    pub fn estimator(&self) -> &'static str {
        match self.u.estimator {
            Joint::States if self.truth.is_none() => "state LP with the model's Θ (Section 3.3)",
            Joint::States => "state LP with the true Θ (Section 3.3)",
            Joint::Parameters => "parameter LP with the states known (Section 3.4)",
            Joint::Expansion => "expansion-based joint estimation (Section 4.2)",
            Joint::Swapping => "swapping-based joint estimation (Section 4.1)",
        }
    }
    /// Whether the report is on the user's data (no truth).
    pub fn is_data(&self) -> bool {
        self.truth.is_none()
    }
    /// Whether the window at the cursor is the report's (then its face and polygon apply).
    pub fn at_window(&self) -> bool {
        self.t == self.u.at.time
    }
    /// The x axis name of every time chart: [`TIME`], or the record's time.
    pub fn time_name(&self) -> &'static str {
        self.record.axis_name(TIME)
    }
    /// Axes of a time chart: t = 0 … T in whole steps on x, `y_desc` on y.
    pub fn time_axes<'s>(&self, win: Win, y_desc: &'s str, x_labels: bool) -> Axes<'s> {
        Axes {
            win,
            x_desc: self.time_name(),
            y_desc,
            x_integer: true,
            equal: false,
            x_labels,
        }
    }
}

/// Check every array the panels index, so drawing never panics on a broken report.
pub(crate) fn check<'a>(report: &'a Report, view: &View, panel: Panel) -> Result<U<'a>> {
    let u = uniform_of(report, panel)?;
    let n = u.n;
    let steps = u.steps.len();
    let m = u.steps.first().map_or(0, |s| s.yr.len());
    let bad = |what: &str| Err(Error::field("report.uniform", what.to_string()));
    if n == 0 || steps == 0 || m == 0 {
        return bad("has no states, outputs or time steps to draw");
    }
    let step_ok = |k: usize| {
        let s = &u.steps[k];
        s.t == k + 1
            && s.x.len() == n
            && finite(&s.x)
            && s.xr.len() == n
            && finite(&s.xr)
            && s.yr.len() == m
            && finite(&s.yr)
            && s.y_pred.len() == m
            && finite(&s.y_pred)
            && rows_ok(&s.a, n, n)
    };
    if !(0..steps).all(step_ok) {
        return bad("holds steps of the wrong dimension, out of order or with non-finite numbers");
    }
    if u.y.len() != steps + 1 || !rows_ok(&u.y[1..], steps, m) {
        return bad("must hold y_1 … y_T (index 0 unused) of the outputs' dimension");
    }
    if u.kf.as_ref().is_some_and(|kf| !rows_ok(kf, steps, n)) {
        return bad("must hold one KF estimate x_1 … x_T per step");
    }
    if let Some(x) = &u.x_true {
        if !rows_ok(x, steps + 1, n) {
            return bad("must hold the true states x_0 … x_T");
        }
    }
    if u.theta_true
        .as_ref()
        .is_some_and(|th| !rows_ok(&th[0], n, n))
        || u.xr_true
            .as_ref()
            .is_some_and(|v| v.len() != n || !finite(v))
    {
        return bad("must hold the true A (n × n) and half-widths x_r (n)");
    }
    if u.yr_true
        .as_ref()
        .is_some_and(|v| v.len() != m || !finite(v))
    {
        return bad("must hold the true half-widths y_r (one per output)");
    }
    let at = &u.at;
    if !(1..=steps).contains(&at.time) || at.first == 0 || at.first > at.time {
        return Err(Error::field(
            "report.uniform.at",
            format!("must have 1 ≤ first ≤ time ≤ {steps}"),
        ));
    }
    let states = at.time - at.first + 2;
    if !rows_ok(&at.face_lo, states, n) || !rows_ok(&at.face_hi, states, n) {
        return Err(Error::field(
            "report.uniform.at",
            "must hold the optimal-face ranges of x_time … x_{first−1}",
        ));
    }
    if at
        .polygon
        .as_ref()
        .is_some_and(|p| p.vertices.iter().any(|v| !finite(v)))
    {
        return Err(Error::field(
            "report.uniform.at.polygon",
            "holds non-finite vertices",
        ));
    }
    let t = view.time.unwrap_or(at.time);
    if !(1..=steps).contains(&t) {
        return Err(Error::field(
            if view.time.is_some() {
                "time"
            } else {
                "report.uniform.at.time"
            },
            format!(
                "must be a whole number from 1 to {steps} (the report's time steps), found {t}"
            ),
        ));
    }
    Ok(U {
        u,
        n,
        m,
        steps,
        t,
        truth: u.x_true.as_deref(),
        kf: u.kf.as_deref(),
        record: RecordTimes::of(&report.figure, TimeIndex::OneBased),
    })
}

/// How the rows of a time figure fit its height.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Layout {
    /// One row above the other (x labels on the last only).
    Stacked,
    /// Low figures with one column: the rows side by side.
    SideBySide,
    /// Low figures with several columns: the first row only.
    TopOnly,
}

impl Layout {
    /// The layout of a figure `w` × `h` with `cols` columns per row.
    pub fn of(w: u32, h: u32, cols: usize) -> Layout {
        if h >= 360 {
            Layout::Stacked
        } else if cols == 1 && w >= 400 {
            Layout::SideBySide
        } else {
            Layout::TopOnly
        }
    }
    /// Whether row `row` of `rows` carries x labels.
    pub fn x_labels(&self, row: usize, rows: usize) -> bool {
        *self != Layout::Stacked || row + 1 == rows
    }
}

/// Title block (the figure's name `what` or `default`, see [`U::title`]), legend, then `weights.len()` rows of `cols` areas (heights in proportion), laid
/// out by `layout`: `cells[row][col]`, `None` for a row left out.
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
pub(crate) fn grid<DB: DrawingBackend>(
    root: &Area<DB>,
    fig: &FigureContext,
    fonts: &Fonts,
    [what, default]: [&str; 2],
    notes: &[String],
    entries: &[Entry],
    weights: &[i32],
    cols: usize,
    layout: Layout,
) -> Result<(Vec<Vec<Option<Area<DB>>>>, LegendSide)> {
    let title = style::title(fig, fonts, what, default);
    let (area, side) = style::titled_legend(root, fonts, &title, notes, entries)?;
    let (_, h) = area.dim_in_pixel();
    let cols = cols.max(1);
    let mut cells: Vec<Vec<Option<Area<DB>>>> = vec![vec![None; cols]; weights.len()];
    match layout {
        Layout::Stacked => {
            let total: i32 = weights.iter().sum::<i32>().max(1);
            let mut rest = area;
            for (k, w) in weights.iter().enumerate() {
                let part = if k + 1 == weights.len() {
                    rest.clone()
                } else {
                    let (a, b) = rest.split_vertically(h as i32 * w / total);
                    rest = b;
                    a
                };
                for (c, a) in part.split_evenly((1, cols)).into_iter().enumerate() {
                    cells[k][c] = Some(a);
                }
            }
        }
        Layout::SideBySide => {
            for (k, a) in area
                .split_evenly((1, weights.len()))
                .into_iter()
                .enumerate()
            {
                cells[k][0] = Some(a);
            }
        }
        Layout::TopOnly => {
            for (c, a) in area.split_evenly((1, cols)).into_iter().enumerate() {
                cells[0][c] = Some(a);
            }
        }
    }
    Ok((cells, side))
}

/// A time chart on `part` (its ticks reading the record's time when it has one), with an
/// optional bold heading above its plotting area.
pub(crate) fn cell<'a, DB: DrawingBackend>(
    root: &Area<DB>,
    part: &Area<DB>,
    fonts: &Fonts,
    heading: Option<&str>,
    axes: &Axes,
    record: &RecordTimes,
) -> Result<style::Chart<'a, DB>> {
    let hs = fonts.bold(if fonts.compact { 11.5 } else { 13.0 });
    let part = match heading {
        Some(_) => {
            let hh = style::text_size(part, "Xg", &hs)?.1 as i32 + 6;
            part.split_vertically(hh).1
        }
        None => part.clone(),
    };
    let chart = style::time_chart(&part, fonts, axes, record)?;
    if let Some(hd) = heading {
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let head = style::shorten(root, hd, &hs, (xr.end - xr.start).max(40) as u32)?;
        style::text(
            root,
            &head,
            (xr.start, yr.start - 12),
            &hs,
            (HPos::Left, VPos::Bottom),
        )?;
    }
    Ok(chart)
}

/// Legend labels and axis names: short unless the figure is wide.
pub(crate) fn short_labels<DB: DrawingBackend>(root: &Area<DB>, fonts: &Fonts) -> bool {
    fonts.compact || root.dim_in_pixel().0 < 800
}

/// How many of `total` charts stand side by side (narrow figures show as many as fit, ≥ 200 px
/// each) and how their rows are laid out.
pub(crate) fn columns<DB: DrawingBackend>(root: &Area<DB>, total: usize) -> (usize, Layout) {
    let (w, h) = root.dim_in_pixel();
    let cols = ((w as usize / 200).max(1)).min(total);
    (cols, Layout::of(w, h, cols))
}

/// The grid of Figs. 1 and 2: a chart per component (`what`: as many of `total` as fit side by
/// side) above its error chart. The notes say first what a small figure leaves out: the
/// components beyond those shown, and the error row (`Layout::TopOnly`).
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
fn values_over_errors<DB: DrawingBackend>(
    root: &Area<DB>,
    fig: &FigureContext,
    fonts: &Fonts,
    title: [&str; 2],
    mut notes: Vec<String>,
    entries: &[Entry],
    total: usize,
    what: &str,
) -> Result<(Vec<Vec<Option<Area<DB>>>>, LegendSide, Layout)> {
    let (cols, layout) = columns(root, total);
    if cols < total {
        notes.insert(
            0,
            format!("{cols} of {total} {what} (widen the figure for all)"),
        );
    }
    if layout == Layout::TopOnly {
        notes.insert(0, "enlarge the figure for the errors".to_string());
    }
    let (rows, side) = grid(
        root,
        fig,
        fonts,
        title,
        &notes,
        entries,
        &[3, 2],
        cols,
        layout,
    )?;
    Ok((rows, side, layout))
}

/// The x axis of every time chart (without record times).
pub(crate) const TIME: &str = "time t";

/// A horizontal line at `y` across the time window `win` (zero, a bound, a true value).
pub(crate) fn level<DB: DrawingBackend>(
    root: &Area<DB>,
    chart: &style::Chart<DB>,
    win: Win,
    y: f64,
    color: &RGBColor,
    width: u32,
    dash: Option<(i32, i32)>,
) -> Result<()> {
    style::path(root, chart, &[(win.x0, y), (win.x1, y)], color, width, dash)
}

/// The frames of a figure as one: the first, with the others, top to bottom, in `more`.
pub(crate) fn stacked(frames: impl Iterator<Item = Frame>) -> Option<Frame> {
    let mut frames = frames;
    let mut first = frames.next()?;
    first.more = frames.collect();
    Some(first)
}

/// The y window of a time chart holding `ys`, padded.
pub(crate) fn time_win(steps: usize, ys: impl Iterator<Item = f64>) -> Win {
    Win::time((0.0, steps.max(1) as f64), ys)
}

/// The sliding window x_{first−1} … x_time as a grey band behind a time chart.
pub(crate) fn window_band<DB: DrawingBackend>(
    root: &Area<DB>,
    chart: &style::Chart<DB>,
    u: &U,
) -> Result<()> {
    if !u.at_window() {
        return Ok(());
    }
    let w = Win::of_chart(chart);
    let (a, b) = ((u.u.at.first - 1) as f64, u.u.at.time as f64);
    style::band(root, chart, &[a, b], &[w.y0, w.y0], &[w.y1, w.y1], &WINDOW)
}

/// The time cursor (labelled on the top row only, with the record's time).
pub(crate) fn cursor<DB: DrawingBackend>(
    root: &Area<DB>,
    chart: &style::Chart<DB>,
    fonts: &Fonts,
    u: &U,
    label: bool,
) -> Result<()> {
    let t = u.t;
    let l = if label {
        u.record.at("t", t)
    } else {
        String::new()
    };
    style::cursor(root, chart, fonts, t as f64, &l)
}

/// "x₁", or "x" for a scalar state.
fn xsym(n: usize, i: usize) -> String {
    if n == 1 {
        "x".into()
    } else {
        format!("x{}", sub(i + 1))
    }
}

fn ysym(m: usize, j: usize) -> String {
    if m == 1 {
        "y".into()
    } else {
        format!("y{}", sub(j + 1))
    }
}

/// The window's legend entry ("window ∂ = 5 at t = 120").
fn window_entry(u: &U, short: bool) -> Entry {
    Entry::new(
        if short {
            format!("window at {}", u.record.at("t", u.u.at.time))
        } else {
            format!(
                "sliding window x{}…x{} at {} (∂ = {})",
                sub(u.u.at.first - 1),
                sub(u.u.at.time),
                u.record.at("t", u.u.at.time),
                u.u.window
            )
        },
        Swatch::Region {
            color: WINDOW,
            dashed: false,
            fill: true,
        },
    )
    .minor()
}

// ------------------------------------------------------------------ Fig. 1: states

/// The "ustates" panel — Fig. 1: per state component, the truth, the LP and KF estimates with the
/// optimal-face ranges of the window at the cursor, and below the estimation errors.
pub fn draw_states<DB: DrawingBackend>(root: &Area<DB>, request: &Request) -> Result<Frame> {
    let (report, view, fonts) = (request.report, request.view, request.fonts);
    let u = check(report, view, Panel::of(&STATES))?;
    let (n, steps, t) = (u.n, u.steps, u.t);
    let short = short_labels(root, &fonts);
    let at = &u.u.at;
    let lp = |s: usize, i: usize| u.u.steps[s - 1].x[i];
    let kf = |s: usize, i: usize| u.kf.map(|k| k[s - 1][i]);
    let truth = |s: usize, i: usize| u.truth.map(|x| x[s][i]);

    let mut entries = Vec::new();
    if u.truth.is_some() {
        entries.push(Entry::new(
            if short {
                "true xₜ"
            } else {
                "true state xₜ"
            },
            Swatch::Line {
                color: TRUTH,
                dashed: false,
                width: 2,
            },
        ));
    }
    entries.push(Entry::new(
        if short {
            "LP estimate x̂ₜ"
        } else {
            "LP (MAP) estimate x̂ₜ of the window at t"
        },
        Swatch::Line {
            color: UNIFORM_LP,
            dashed: false,
            width: 2,
        },
    ));
    if u.kf.is_some() {
        entries.push(Entry::new(
            if short {
                "KF (true Θ)"
            } else {
                "KF with the true Θ and variances r²/3"
            },
            Swatch::Line {
                color: KF,
                dashed: true,
                width: 2,
            },
        ));
    }
    if u.at_window() {
        entries.push(Entry::new(
            if short {
                "optimal-face range"
            } else {
                "range over the LP's optimal face (window at the cursor)"
            },
            Swatch::Line {
                color: FACE,
                dashed: false,
                width: 3,
            },
        ));
        entries.push(window_entry(&u, short));
    }
    let mut notes = vec![format!("{}, window ∂ = {}", u.estimator(), u.u.window)];
    if u.is_data() {
        notes.push(if short {
            "your data: no true states, no errors".to_string()
        } else {
            "your data: no true states, so no errors and no KF (it needs the true Θ and half-widths)"
                .to_string()
        });
    }
    if let (Some(a), Some(b)) = (u.u.rms_lp, u.u.rms_kf) {
        notes.push(format!(
            "RMS error ‖x̂ₜ − xₜ‖ over t = {} … {steps}: LP {}, KF {}",
            u.u.window.min(steps),
            sig(a),
            sig(b)
        ));
    }
    if u.at_window() {
        notes.push(format!(
            "bars at t = {} … {}: each entry's range over the optimal face of the LP at t = {}",
            at.first - 1,
            at.time,
            at.time
        ));
    } else {
        notes.push(format!(
            "t = {t}: the window's optimal face is not in this report (it holds t = {})",
            at.time
        ));
    }
    let (rows, side, layout) = values_over_errors(
        root,
        &report.figure,
        &fonts,
        [
            "Fig. 1: states and estimation errors",
            "Estimated states and estimation errors (Pavelková, Fig. 1)",
        ],
        notes,
        &entries,
        n,
        "components",
    )?;
    let mut frames = Vec::new();
    let mut err_frames = Vec::new();
    for i in 0..rows[0].len() {
        let (Some(top), bottom) = (&rows[0][i], &rows[1][i]) else {
            continue;
        };
        let sym = xsym(n, i);
        let name = match report.figure.names.get(i) {
            Some(s) if !s.is_empty() => format!("{sym}: {s}"),
            _ if n == 1 => "state x".to_string(),
            _ => format!("state component {sym}"),
        };
        // Face bars: x_{time−k} for k = 0 … time − first + 1.
        let bars: Vec<(f64, f64, f64)> = if u.at_window() {
            (0..at.face_lo.len())
                .map(|k| {
                    let (a, b) = (at.face_lo[k][i], at.face_hi[k][i]);
                    ((at.time - k) as f64, a.min(b), a.max(b))
                })
                .collect()
        } else {
            Vec::new()
        };
        let truth_pts: Vec<(f64, f64)> = (0..=steps)
            .filter_map(|s| Some((s as f64, truth(s, i)?)))
            .collect();
        let lp_pts: Vec<(f64, f64)> = (1..=steps).map(|s| (s as f64, lp(s, i))).collect();
        let kf_pts: Vec<(f64, f64)> = (1..=steps)
            .filter_map(|s| Some((s as f64, kf(s, i)?)))
            .collect();
        let win = time_win(
            steps,
            truth_pts
                .iter()
                .chain(&lp_pts)
                .chain(&kf_pts)
                .map(|p| p.1)
                .chain(bars.iter().flat_map(|b| [b.1, b.2])),
        );
        let yd = if short {
            sym.clone()
        } else {
            format!("{sym} (state)")
        };
        let chart = cell(
            root,
            top,
            &fonts,
            Some(&name),
            &u.time_axes(win, &yd, layout.x_labels(0, 2)),
            &u.record,
        )?;
        window_band(root, &chart, &u)?;
        style::path(root, &chart, &truth_pts, &TRUTH, 2, None)?;
        style::path(root, &chart, &kf_pts, &KF, 2, Some(style::DASH))?;
        style::path(root, &chart, &lp_pts, &UNIFORM_LP, 2, None)?;
        for &(x, a, b) in &bars {
            face_bar(root, &chart, x, a, b)?;
        }
        cursor(root, &chart, &fonts, &u, true)?;
        let mut marks = style::marks_of(&chart, &truth_pts);
        marks.extend(style::marks_of(&chart, &lp_pts));
        marks.extend(style::marks_of(&chart, &kf_pts));
        if i == 0 {
            style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
        }
        frames.push(style::frame_of(&chart, TIME, &yd));

        // Errors.
        let Some(bottom) = bottom else { continue };
        let err = |f: &dyn Fn(usize) -> f64| -> Vec<(f64, f64)> {
            (1..=steps)
                .filter_map(|s| Some((s as f64, f(s) - truth(s, i)?)))
                .collect()
        };
        let lp_err = err(&|s| lp(s, i));
        let kf_err: Vec<(f64, f64)> = (1..=steps)
            .filter_map(|s| Some((s as f64, kf(s, i)? - truth(s, i)?)))
            .collect();
        let win = time_win(
            steps,
            lp_err
                .iter()
                .chain(&kf_err)
                .map(|p| p.1)
                .chain(std::iter::once(0.0)),
        );
        let yd = if short {
            "error".to_string()
        } else {
            format!("error x̂{} − {sym}", &sym[1..])
        };
        let side_heading = format!("error of {sym}");
        let chart = cell(
            root,
            bottom,
            &fonts,
            (layout == Layout::SideBySide).then_some(side_heading.as_str()),
            &u.time_axes(win, &yd, true),
            &u.record,
        )?;
        window_band(root, &chart, &u)?;
        level(root, &chart, win, 0.0, &TRUTH, 1, None)?;
        style::path(root, &chart, &kf_err, &KF, 2, Some(style::DASH))?;
        style::path(root, &chart, &lp_err, &UNIFORM_LP, 2, None)?;
        cursor(root, &chart, &fonts, &u, false)?;
        if lp_err.is_empty() {
            let (xr, yr) = chart.plotting_area().get_pixel_range();
            style::text(
                root,
                "no true states: no errors",
                ((xr.start + xr.end) / 2, (yr.start + yr.end) / 2),
                &fonts.note(),
                (HPos::Center, VPos::Center),
            )?;
        }
        err_frames.push(style::frame_of(&chart, TIME, &yd));
    }
    stacked(frames.into_iter().chain(err_frames))
        .ok_or_else(|| Error::field("report.uniform", "has no state components"))
}

/// An I-beam from a to b at time x (at least a few pixels tall so a point-like face shows).
fn face_bar<DB: DrawingBackend>(
    root: &Area<DB>,
    chart: &style::Chart<DB>,
    x: f64,
    a: f64,
    b: f64,
) -> Result<()> {
    let w = Win::of_chart(chart);
    if !(x >= w.x0 && x <= w.x1) {
        return Ok(());
    }
    let (lo, hi) = (
        style::px(chart, (x, a.clamp(w.y0, w.y1))),
        style::px(chart, (x, b.clamp(w.y0, w.y1))),
    );
    // Pixel y grows downwards: hi is above lo.
    let (top, bottom) = (hi.1.min(lo.1 - 3), lo.1.max(hi.1 + 3));
    let c = 4;
    style::polyline(root, &[(lo.0, top), (lo.0, bottom)], &FACE, 3, None)?;
    style::polyline(root, &[(lo.0 - c, top), (lo.0 + c, top)], &FACE, 2, None)?;
    style::polyline(
        root,
        &[(lo.0 - c, bottom), (lo.0 + c, bottom)],
        &FACE,
        2,
        None,
    )
}

// ------------------------------------------------------------------ Fig. 2: output

/// The "uoutput" panel — Fig. 2: the output y_t and its one-step prediction ŷ_{t|t−1}, and below
/// the prediction error.
pub fn draw_output<DB: DrawingBackend>(root: &Area<DB>, request: &Request) -> Result<Frame> {
    let (report, view, fonts) = (request.report, request.view, request.fonts);
    let u = check(report, view, Panel::of(&OUTPUT))?;
    let (m, steps) = (u.m, u.steps);
    let short = short_labels(root, &fonts);
    let yr_true = u.u.yr_true.as_deref();
    let mut entries = vec![
        Entry::new(
            if short {
                "output yₜ"
            } else {
                "measured output yₜ"
            },
            Swatch::Line {
                color: TRUTH,
                dashed: false,
                width: 2,
            },
        ),
        Entry::new(
            if short {
                "prediction ŷₜ|ₜ₋₁"
            } else {
                "one-step prediction ŷₜ|ₜ₋₁ = Ĉ(Âx̂ₜ₋₁ + B̂uₜ) + D̂uₜ"
            },
            Swatch::Line {
                color: UNIFORM_LP,
                dashed: false,
                width: 2,
            },
        ),
    ];
    if let Some(yr) = yr_true {
        entries.push(
            Entry::new(
                format!(
                    "output noise bound ±yᵣ{}",
                    if m == 1 {
                        format!(" = ±{}", sig(yr[0]))
                    } else {
                        String::new()
                    }
                ),
                Swatch::Line {
                    color: TRUTH,
                    dashed: true,
                    width: 1,
                },
            )
            .minor(),
        );
    }
    let mut notes = vec![format!("{}, window ∂ = {}", u.estimator(), u.u.window)];
    notes.push(format!(
        "RMS prediction error over t = {} … {steps}: {}",
        u.u.window.min(steps),
        sig(u.u.rms_prediction)
    ));
    if u.u.extended > 0 {
        notes.push(format!(
            "the half-width bounds were doubled {} where the LP was infeasible",
            crate::error::counted(u.u.extended, "time", "times")
        ));
    }
    let (rows, side, layout) = values_over_errors(
        root,
        &report.figure,
        &fonts,
        [
            "Fig. 2: predicted output and prediction error",
            "Predicted output and prediction error (Pavelková, Fig. 2)",
        ],
        notes,
        &entries,
        m,
        "outputs",
    )?;
    let mut frames = Vec::new();
    let mut err_frames = Vec::new();
    for j in 0..rows[0].len() {
        let (Some(top), bottom) = (&rows[0][j], &rows[1][j]) else {
            continue;
        };
        let sym = ysym(m, j);
        let y: Vec<(f64, f64)> = (1..=steps).map(|s| (s as f64, u.u.y[s][j])).collect();
        let p: Vec<(f64, f64)> = (1..=steps)
            .map(|s| (s as f64, u.u.steps[s - 1].y_pred[j]))
            .collect();
        let win = time_win(steps, y.iter().chain(&p).map(|q| q.1));
        let yd = if short {
            format!("{sym}, ŷ")
        } else {
            format!("output {sym}ₜ, prediction")
        };
        let sbs = layout == Layout::SideBySide;
        let heading = (m > 1 || sbs).then(|| format!("output {sym}"));
        let chart = cell(
            root,
            top,
            &fonts,
            heading.as_deref(),
            &u.time_axes(win, &yd, layout.x_labels(0, 2)),
            &u.record,
        )?;
        window_band(root, &chart, &u)?;
        style::path(root, &chart, &y, &TRUTH, 2, None)?;
        style::path(root, &chart, &p, &UNIFORM_LP, 2, None)?;
        cursor(root, &chart, &fonts, &u, true)?;
        let mut marks = style::marks_of(&chart, &y);
        marks.extend(style::marks_of(&chart, &p));
        if j == 0 {
            style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
        }
        frames.push(style::frame_of(&chart, TIME, &yd));

        let Some(bottom) = bottom else { continue };
        let e: Vec<(f64, f64)> = y.iter().zip(&p).map(|(a, b)| (a.0, b.1 - a.1)).collect();
        let yr = yr_true.map(|v| v[j]);
        let win = time_win(
            steps,
            e.iter()
                .map(|q| q.1)
                .chain(std::iter::once(0.0))
                .chain(yr.into_iter().flat_map(|v| [v, -v])),
        );
        let yd = if short {
            "error".to_string()
        } else {
            format!("error ŷ{}ₜ|ₜ₋₁ − {sym}ₜ", &sym[1..])
        };
        let side_heading = if short {
            "prediction error".to_string()
        } else {
            format!("prediction error of {sym}")
        };
        let chart = cell(
            root,
            bottom,
            &fonts,
            (sbs || m > 1).then_some(side_heading.as_str()),
            &u.time_axes(win, &yd, true),
            &u.record,
        )?;
        window_band(root, &chart, &u)?;
        level(root, &chart, win, 0.0, &TRUTH, 1, None)?;
        for v in yr.into_iter().flat_map(|v| [v, -v]) {
            level(root, &chart, win, v, &TRUTH, 1, Some((4, 4)))?;
        }
        style::path(root, &chart, &e, &UNIFORM_LP, 2, None)?;
        cursor(root, &chart, &fonts, &u, false)?;
        err_frames.push(style::frame_of(&chart, TIME, &yd));
    }
    stacked(frames.into_iter().chain(err_frames))
        .ok_or_else(|| Error::field("report.uniform", "has no outputs"))
}
