//! GLLS Fig. 1 (`singular`) and Fig. 2 (`index`) against the horizon s, with what every GLLS
//! panel shares: the names of all four panels, the check of the report's GLLS part, the
//! horizon axis and the marker at the horizon in use (the plane is drawn in `plane.rs`,
//! Figs. 3–4 in `precision.rs`).
//!
//! Log axes: the report holds log10 values and the charts plot them on a linear axis labelled
//! 10ᵏ ([`style::log_chart`]). A log10 value ≤ −300 marks an exact zero (a rank-deficient
//! Γ_{s+1} for small s) and is never drawn; a singular value below the floating-point floor
//! ε·σ₁·√(m(s+1)) is not resolved in double precision and is not drawn either: the floor is
//! the grey band under which it would lie.

use crate::error::{Error, Result};
use crate::plot::erase::de;
use crate::plot::figures::Area;
use crate::plot::geom::Win;
use crate::plot::style::{self, sci, sub, Axes, Entry, Fonts, Marker, Swatch, FLOOR, TEXT};
use crate::plot::view::PanelSpec;
use crate::plot::view::{Frame, Panel};
use crate::scenario::glls::{GllsEstimator, GllsReport};
use crate::scenario::Report;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

/// GLLS paper, Fig. 1: the singular values of Γ_{s+1} (and of Γ_{s+1}A^{−s}) against the
/// horizon s on a log scale, with the floating-point floor.
pub(crate) static SINGULAR: PanelSpec = PanelSpec::new(
    "singular",
    "singular values of the observability matrix against the horizon (GLLS Fig. 1)",
);
/// GLLS paper, Fig. 2: the horizon index σ_n/√s (and σ_p/√s) with its best horizon.
pub(crate) static INDEX: PanelSpec = PanelSpec::new(
    "index",
    "horizon index σₙ/√s with the best horizon (GLLS Fig. 2)",
);
/// GLLS: the state plane at time k: truth, estimate, guaranteed ball and interval box.
pub(crate) static PLANE: PanelSpec = PanelSpec::new(
    "plane",
    "state plane at time k: truth, estimate, guaranteed ball and interval box",
);
/// GLLS paper, Figs. 3–4: the Monte Carlo error ‖x_est(k) − x(k)‖ per horizon (boxes) with
/// the bound κ·√E‖δ‖², or state-noise estimator vs LLS in paired half-boxes.
pub(crate) static PRECISION: PanelSpec = PanelSpec {
    name: "precision",
    alt_text:
        "Monte Carlo errors per horizon as box plots with the bound κ·√E‖δ‖² (GLLS Figs. 3–4)",
};

/// log10 values at or below this mark an exact zero.
pub(crate) const ZERO: f64 = -300.0;

/// The report's GLLS part, or an error naming the panel.
pub fn glls_of(report: &Report, panel: Panel) -> Result<&GllsReport> {
    report.glls.as_ref().ok_or_else(|| {
        let choose = if report.lscr.is_some() {
            "choose region"
        } else {
            "choose state, series or coverage"
        };
        Error::field(
            "panel",
            format!(
                "\"{}\" draws a GLLS figure, but this report (method \"{}\") has no GLLS part: {choose}",
                panel.name(),
                report.method
            ),
        )
    })
}

/// The panel fits the report (before anything is drawn).
pub fn check(report: &Report, panel: Panel) -> Result<()> {
    let g = glls_of(report, panel)?;
    if panel == Panel::of(&PRECISION) && g.precision.is_none() {
        return Err(Error::field(
            "glls.monte_carlo",
            "is not in this report: ask for a Monte Carlo study in the scenario (\"glls\": {\"monte_carlo\": {\"runs\", \"study\"}}) to draw the precision panel",
        ));
    }
    Ok(())
}

/// The x axis of the horizon panels.
pub(crate) fn horizon_desc(compact: bool) -> &'static str {
    if compact {
        "horizon s"
    } else {
        "horizon s (estimates from y(k−s) … y(k))"
    }
}

/// The frame of every figure against the horizon (Figs. 1–4): title block, legend, and a chart
/// over s with a log-scale y axis.
#[allow(clippy::too_many_arguments)]
pub(crate) fn horizon_chart<'a, DB: DrawingBackend>(
    root: &Area<DB>,
    fonts: &Fonts,
    title: &str,
    notes: &[String],
    entries: &[Entry],
    win: Win,
    short: bool,
    y_desc: &str,
) -> Result<(style::Chart<'a, DB>, style::LegendSide)> {
    let (area, side) = style::titled_legend(root, fonts, title, notes, entries)?;
    let axes = Axes {
        win,
        x_desc: horizon_desc(short),
        y_desc,
        x_integer: true,
        equal: false,
        x_labels: true,
    };
    Ok((style::log_chart(&area, fonts, &axes)?, side))
}

/// The estimator's name ("LLS", "GLLS", "state-noise").
pub(crate) fn estimator_name(g: &GllsReport) -> &'static str {
    match g.estimator {
        GllsEstimator::Glls => "GLLS",
        GllsEstimator::StateNoise => "state-noise",
        GllsEstimator::Lls => "LLS",
    }
}

/// Check the curves' shapes: S + 1 rows of n values, a floor per row.
fn check_curves(g: &GllsReport) -> Result<usize> {
    let c = &g.curves;
    let rows = c.log10_sigma.len();
    let n = g.n;
    let bad = rows == 0
        || n == 0
        || c.log10_floor.len() != rows
        || c.log10_sigma.iter().any(|r| r.len() != n)
        || c.log10_sigma_prime
            .as_ref()
            .is_some_and(|p| p.len() != rows || p.iter().any(|r| r.len() != n));
    if bad {
        return Err(Error::field(
            "report.glls.curves",
            "must hold, for s = 0 … S, n singular values and a floor each",
        ));
    }
    Ok(rows)
}

/// A curve as pieces of (s, log10 value) where `keep` holds (a gap splits it).
fn pieces(values: impl Iterator<Item = (usize, f64, bool)>) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    for (s, v, keep) in values {
        if keep && v.is_finite() {
            cur.push((s as f64, v));
        } else if !cur.is_empty() {
            out.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// The y window of log10 values: padded, at least `min_span` decades.
fn log_window(lo: f64, hi: f64, min_span: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (-1.0, 1.0);
    }
    let (mut lo, mut hi) = (lo.min(hi), lo.max(hi));
    if hi - lo < min_span {
        let mid = 0.5 * (lo + hi);
        lo = mid - 0.5 * min_span;
        hi = mid + 0.5 * min_span;
    }
    let pad = 0.06 * (hi - lo);
    (lo - pad, hi + pad)
}

/// A label above (or below) a point on a light background, kept inside the plotting area;
/// returns its pixels.
fn point_label<DB: DrawingBackend>(
    root: &Area<DB>,
    chart: &style::Chart<DB>,
    fonts: &Fonts,
    p: (i32, i32),
    label: &str,
    color: &RGBColor,
    avoid: &mut Vec<(i32, i32, i32, i32)>,
) -> Result<Vec<(i32, i32)>> {
    let st = fonts.legend().color(color);
    let (tw, th) = style::text_size(root, label, &st)?;
    let (tw, th) = (tw as i32, th as i32);
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let clamp_x = |x: i32| x.clamp(xr.start + 4, (xr.end - tw - 4).max(xr.start + 4));
    let inside = |y: i32| y > yr.start && y + th + 2 < yr.end;
    let hits = |x: i32, y: i32| {
        avoid
            .iter()
            .any(|b| x - 3 < b.2 && b.0 < x + tw + 3 && y - 2 < b.3 && b.1 < y + th + 2)
    };
    // Beside the point, in this order: above, below, right, left (issue 28: never over the
    // horizon marker's "s = 8 in use", the other best horizon's label or either point, which
    // the caller put in `avoid`).
    let centred = clamp_x(p.0 - tw / 2);
    let candidates = [
        (centred, p.1 - 10 - th),
        (centred, p.1 + 10),
        (p.0 + 10, p.1 - th / 2),
        (p.0 - 10 - tw, p.1 - th / 2),
    ];
    let free = candidates
        .into_iter()
        .find(|&(x, y)| x >= xr.start + 4 && x + tw + 4 <= xr.end && inside(y) && !hits(x, y));
    // All taken: stacked under the labels it meets.
    let (x, y) = free.unwrap_or_else(|| {
        let y = avoid
            .iter()
            .filter(|b| centred - 3 < b.2 && b.0 < centred + tw + 3)
            .map(|b| b.3 + 4)
            .max()
            .unwrap_or(p.1 + 10)
            .min(yr.end - th - 2);
        (centred, y)
    });
    avoid.push((x - 3, y - 2, x + tw + 3, y + th + 2));
    let (bx, by) = root.get_base_pixel();
    root.draw(&Rectangle::new(
        [(x - 3 - bx, y - 2 - by), (x + tw + 3 - bx, y + th + 2 - by)],
        WHITE.mix(0.85).filled(),
    ))
    .map_err(de)?;
    style::text(root, label, (x, y), &st, (HPos::Left, VPos::Top))?;
    Ok((0..5).map(|k| (x + k * tw / 4, y + th / 2)).collect())
}

/// The marker of the horizon in use; when it lies outside the chart, a note saying so.
pub(crate) fn horizon_marker<DB: DrawingBackend>(
    root: &Area<DB>,
    chart: &style::Chart<DB>,
    fonts: &Fonts,
    s: usize,
    notes: &mut Vec<String>,
) -> Result<()> {
    let w = Win::of_chart(chart);
    let x = s as f64;
    if x >= w.x0 && x <= w.x1 {
        style::cursor(root, chart, fonts, x, &format!("s = {s} in use"))
    } else {
        notes.push(format!(
            "the horizon in use, s = {s}, lies beyond the horizons drawn (≤ {})",
            w.x1.floor()
        ));
        Ok(())
    }
}

// ------------------------------------------------------------------ Fig. 1: singular values

/// The "singular" panel — Fig. 1.
pub fn draw_singular<DB: DrawingBackend>(
    root: &Area<DB>,
    report: &Report,
    fonts: Fonts,
) -> Result<Frame> {
    let g = glls_of(report, Panel::of(&SINGULAR))?;
    let rows = check_curves(g)?;
    let c = &g.curves;
    let n = g.n;
    let s_max = rows - 1;
    let floor = &c.log10_floor;
    // σ' has its own floor ε·σ'₁·√(m(s+1)).
    let prime_floor: Option<Vec<f64>> = c.log10_sigma_prime.as_ref().map(|p| {
        (0..rows)
            .map(|s| floor[s] - c.log10_sigma[s][0] + p[s][0])
            .collect()
    });
    let resolved = |v: f64, f: f64| v > ZERO && v.is_finite() && v > f;
    let solid: Vec<Vec<Vec<(f64, f64)>>> = (0..n)
        .map(|i| {
            pieces((0..rows).map(|s| {
                let v = c.log10_sigma[s][i];
                (s, v, resolved(v, floor[s]))
            }))
        })
        .collect();
    let dashed: Option<Vec<Vec<Vec<(f64, f64)>>>> = c
        .log10_sigma_prime
        .as_ref()
        .zip(prime_floor.as_ref())
        .map(|(p, pf)| {
            (0..n)
                .map(|i| {
                    pieces((0..rows).map(|s| {
                        let v = p[s][i];
                        (s, v, resolved(v, pf[s]))
                    }))
                })
                .collect()
        });
    // The window fits the solid curves (the figure's subject) and lets the dashed ones extend
    // it by at most 1.5 decades; beyond that they are clipped, with a note.
    let range = |cs: &[Vec<Vec<(f64, f64)>>]| {
        let mut r = (f64::INFINITY, f64::NEG_INFINITY);
        for &(_, v) in cs.iter().flatten().flatten() {
            r = (r.0.min(v), r.1.max(v));
        }
        r
    };
    let (mut lo, mut hi) = range(&solid);
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(Error::field(
            "report.glls.curves",
            "hold no singular value above the floating-point floor: nothing to draw",
        ));
    }
    let mut clipped: Option<(f64, usize)> = None;
    if let Some(d) = &dashed {
        let (dlo, dhi) = range(d);
        if dlo.is_finite() && dhi.is_finite() {
            let (nlo, nhi) = (dlo.max(lo - 1.5), dhi.min(hi + 1.5));
            if dhi > nhi || dlo < nlo {
                // Where the dashed curves go furthest.
                let far = d.iter().flatten().flatten().copied().max_by(|a, b| {
                    (a.1 - nhi)
                        .max(nlo - a.1)
                        .total_cmp(&(b.1 - nhi).max(nlo - b.1))
                });
                clipped = far.map(|(s, v)| (v, s as usize));
            }
            lo = lo.min(nlo);
            hi = hi.max(nhi);
        }
    }
    // The floor joins the window when it comes within three decades of the curves.
    let fmax = floor
        .iter()
        .copied()
        .filter(|f| f.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    let floor_shown = fmax > lo - 3.0;
    if floor_shown {
        lo = lo.min(fmax - 0.5);
    }
    let (y0, y1) = log_window(lo, hi, 1.0);
    let win = Win::new((0.0, s_max.max(1) as f64), (y0, y1));

    // Texts.
    let short = fonts.compact;
    let rows_of = if g.m == 1 {
        "s+1".to_string()
    } else {
        format!("{}(s+1)", g.m)
    };
    let mut notes = vec![format!(
        "σ₁ ≥ … ≥ σ{} of Γₛ₊₁ = [C; CA; …; CAˢ] of size {rows_of} × {n}, s = 0 … {s_max}; 1/σ{} is the LLS condition number of x(k−s) (Section 3.3)",
        sub(n),
        sub(n)
    )];
    match (g.prime_gap_log10, &c.log10_sigma_prime) {
        (Some(gap), Some(_)) if gap > 0.05 => notes.push(format!(
            "dashed σᵢ(Γₛ₊₁A⁻ˢ): the paper remarks they equal σᵢ(Γₛ₊₁); here they differ by a factor up to {} (equal only for orthogonal A)",
            sci(10f64.powf(gap.min(300.0)))
        )),
        (_, Some(_)) => notes.push(
            "dashed σᵢ(Γₛ₊₁A⁻ˢ) equal σᵢ(Γₛ₊₁) here, as the paper remarks".to_string(),
        ),
        (_, None) => notes.push("A is singular: no Γₛ₊₁A⁻ˢ".to_string()),
    }
    if let Some((v, s)) = clipped {
        notes.push(format!(
            "a dashed curve leaves the window (σ = {} at s = {s})",
            sci(10f64.powf(v.clamp(-300.0, 300.0)))
        ));
    }
    if !floor_shown {
        notes.push(format!(
            "floating-point floor ε·σ₁·√(m(s+1)) ≤ {}: every drawn σ is resolved",
            sci(10f64.powf(fmax))
        ));
    }
    let mut entries: Vec<Entry> = (0..n)
        .map(|i| {
            Entry::new(
                if short {
                    format!("σ{}", sub(i + 1))
                } else {
                    format!("σ{}(Γₛ₊₁)", sub(i + 1))
                },
                Swatch::Line {
                    color: style::series_color(i),
                    dashed: false,
                    width: 2,
                },
            )
        })
        .collect();
    if dashed.is_some() {
        entries.push(Entry::new(
            if short {
                "σᵢ(Γ A⁻ˢ)".to_string()
            } else {
                "σᵢ(Γ A⁻ˢ) — the paper's remark says equal".to_string()
            },
            Swatch::Line {
                color: TEXT,
                dashed: true,
                width: 2,
            },
        ));
    }
    if floor_shown {
        entries.push(Entry::new(
            if short {
                "not resolved"
            } else {
                "below: not resolved in double precision"
            },
            Swatch::Region {
                color: FLOOR,
                dashed: false,
                fill: true,
            },
        ));
    }
    let t = style::title(
        &report.figure,
        &fonts,
        "Singular values of Γₛ₊₁",
        "Singular values of the observability matrix Γₛ₊₁ (GLLS paper, Fig. 1)",
    );
    let (xd, yd) = (horizon_desc(short), "σᵢ (log scale)");
    let (chart, side) = horizon_chart(root, &fonts, &t, &notes, &entries, win, short, yd)?;
    let mut marks: Vec<(i32, i32)> = Vec::new();
    if floor_shown {
        let xs: Vec<f64> = (0..rows).map(|s| s as f64).collect();
        let top: Vec<f64> = floor.iter().map(|f| f.clamp(y0, y1)).collect();
        let bottom = vec![y0; rows];
        style::band(root, &chart, &xs, &bottom, &top, &FLOOR)?;
        let line: Vec<(f64, f64)> = xs.iter().copied().zip(top.iter().copied()).collect();
        style::path(root, &chart, &line, &FLOOR, 2, None)?;
        marks.extend(style::marks_of(&chart, &line));
    }
    for (i, ps) in solid.iter().enumerate() {
        for piece in ps {
            style::path(root, &chart, piece, &style::series_color(i), 2, None)?;
            marks.extend(style::marks_of(&chart, piece));
        }
    }
    if let Some(d) = &dashed {
        for (i, ps) in d.iter().enumerate() {
            for piece in ps {
                style::path(
                    root,
                    &chart,
                    piece,
                    &style::series_color(i),
                    2,
                    Some((6, 4)),
                )?;
                marks.extend(style::marks_of(&chart, piece));
            }
        }
    }
    let mut chart_notes = Vec::new();
    horizon_marker(root, &chart, &fonts, g.s, &mut chart_notes)?;
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, xd, yd))
}

// ------------------------------------------------------------------ Fig. 2: horizon index

/// The "index" panel — Fig. 2.
pub fn draw_index<DB: DrawingBackend>(
    root: &Area<DB>,
    report: &Report,
    fonts: Fonts,
) -> Result<Frame> {
    let g = glls_of(report, Panel::of(&INDEX))?;
    let rows = check_curves(g)?;
    let n = g.n;
    let s_max = rows - 1;
    let floor = &g.curves.log10_floor;
    let p = g.regularized.as_ref().map(|r| r.p);
    if g.index.len() != rows || g.index_p.as_ref().is_some_and(|v| v.len() != rows) {
        return Err(Error::field(
            "report.glls.index",
            "must hold one value per horizon s = 0 … S",
        ));
    }
    // σ/√s is resolved where σ is: above floor/√s.
    let curve = |v: &[f64]| {
        pieces((1..rows).map(|s| {
            let f = floor[s] - 0.5 * (s as f64).log10();
            (s, v[s], v[s] > ZERO && v[s] > f)
        }))
    };
    let main = curve(&g.index);
    let reg = g.index_p.as_deref().map(curve);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for piece in main.iter().chain(reg.iter().flatten()) {
        for &(_, v) in piece {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(Error::field(
            "report.glls.index",
            "holds no resolved value σₙ/√s: nothing to draw",
        ));
    }
    let (y0, y1) = log_window(lo, hi, 0.5);
    // Room above the curves for the best-horizon labels.
    let y1 = y1 + 0.12 * (y1 - y0);
    let win = Win::new((0.0, s_max.max(1) as f64), (y0, y1));
    let short = fonts.compact;
    let color_n = style::series_color(n - 1);
    let color_p = p.map(|p| style::series_color(p.saturating_sub(1)));
    let mut notes = vec![format!(
        "the LLS bounds (37), (39) are ∝ √s/σ{n}: the horizon maximising σ{n}/√s is the best one (Section 3.3)",
        n = sub(n)
    )];
    let grows = |b: Option<usize>| b == Some(s_max);
    if grows(g.best_horizon) {
        notes.push(format!(
            "σ{}/√s still grows at S = {s_max} (Fig. 2b kind): longer horizons keep helping, until rounding",
            sub(n)
        ));
    }
    if let Some(b) = g.best_horizon.filter(|&b| b > g.k) {
        notes.push(format!(
            "the best s = {b} needs {} measurements, the data hold {}: s = {} is used",
            b + 1,
            g.k + 1,
            g.s
        ));
    }
    if let Some(p) = p {
        notes.push(format!(
            "regularized: keeping p = {p} singular values, (38) is ∝ √s/σ{}; its best horizon differs",
            sub(p)
        ));
    }
    // The curve σ_k/√s, its long label saying which k.
    let curve = |k: usize, which: String, color: RGBColor, dashed: bool| {
        let label = format!("σ{}/√s", sub(k));
        Entry::new(
            if short {
                label
            } else {
                format!("{label} ({which})")
            },
            Swatch::Line {
                color,
                dashed,
                width: 2,
            },
        )
    };
    let mut entries = vec![curve(n, format!("n = {n}"), color_n, false)];
    if let (Some(p), Some(cp), Some(_)) = (p, color_p, &reg) {
        entries.push(curve(p, format!("p = {p}, regularized"), cp, true));
    }
    entries.push(
        Entry::new(
            "best horizon",
            Swatch::Marker {
                shape: Marker::Dot,
                color: TEXT,
                size: 4,
            },
        )
        .minor(),
    );
    let t = style::title(
        &report.figure,
        &fonts,
        "Horizon index σₙ/√s",
        "Choosing the horizon: σₙ/√s (GLLS paper, Fig. 2)",
    );
    let (xd, yd) = (horizon_desc(short), "σ/√s (log scale)");
    let (chart, side) = horizon_chart(root, &fonts, &t, &notes, &entries, win, short, yd)?;
    let mut marks = Vec::new();
    for piece in &main {
        style::path(root, &chart, piece, &color_n, 2, None)?;
        marks.extend(style::marks_of(&chart, piece));
    }
    if let (Some(r), Some(cp)) = (&reg, color_p) {
        for piece in r {
            style::path(root, &chart, piece, &cp, 2, Some(style::DASH))?;
            marks.extend(style::marks_of(&chart, piece));
        }
    }
    let mut chart_notes = Vec::new();
    horizon_marker(root, &chart, &fonts, g.s, &mut chart_notes)?;
    let mut taken: Vec<(i32, i32, i32, i32)> = style::cursor_label_box(
        root,
        &chart,
        &fonts,
        g.s as f64,
        &format!("s = {} in use", g.s),
    )?
    .into_iter()
    .collect();
    let mut best = vec![(g.best_horizon, &g.index, color_n, String::new())];
    if let (Some(b), Some(v), Some(cp), Some(p)) = (g.best_horizon_p, &g.index_p, color_p, p) {
        best.push((Some(b), v, cp, format!(" (p = {p})")));
    }
    // The points first, so that no label is drawn over either of them.
    let mut points = Vec::new();
    for (b, v, color, suffix) in best {
        let Some(b) = b else { continue };
        let Some(&y) = v.get(b) else { continue };
        if !(y > ZERO && win.contains(b as f64, y)) {
            continue;
        }
        let q = style::px(&chart, (b as f64, y));
        style::marker(root, q, Marker::Dot, &color, 5)?;
        taken.push((q.0 - 7, q.1 - 7, q.0 + 7, q.1 + 7));
        let label = if grows(Some(b)) {
            format!("largest at S = {b}{suffix}")
        } else {
            format!("best s = {b}{suffix}")
        };
        points.push((q, label, color));
    }
    for (q, label, color) in points {
        marks.extend(point_label(
            root, &chart, &fonts, q, &label, &color, &mut taken,
        )?);
        marks.push(q);
    }
    style::chart_notes(root, &chart, &fonts, &chart_notes, &mut marks)?;
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, xd, yd))
}
