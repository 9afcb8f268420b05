//! The "precision" panel — Figs. 3 and 4 of the GLLS paper: the Monte Carlo errors
//! ‖x_est(k) − x(k)‖₂ per horizon on a log axis.
//!
//! The paper draws violins with min, max and mean marked; here each horizon gets a
//! box-and-whisker (whiskers min–max, box q1–q3, median line, mean dot), which carries the same
//! marks and needs no density estimate. Section 5.1 (Fig. 3): one box per horizon with the
//! bound κ(s,k)·√E‖δ(k,s)‖² (39) overlaid. Section 5.2 (Fig. 4, `second` present): paired
//! half-boxes, the state-noise estimator left and LLS right, and the mean ‖x(k)‖ of the
//! ensemble as a dash-dotted horizontal line (or a note when it is off the axis).

use super::horizon::{glls_of, horizon_chart, horizon_desc, horizon_marker};
use crate::plot::geom::Win;

use crate::error::{Error, Result};
use crate::glls::Spread;
use crate::plot::erase::de;
use crate::plot::figures::Area;
use crate::plot::style::{self, sci, Entry, Fonts, Marker, Swatch, GLLS_EST, STATE_NOISE, TEXT};
use crate::plot::view::{Frame, Panel};
use crate::scenario::Report;
use plotters::prelude::*;

/// One box: horizontal pixel span [x0, x1] and the spread in log10.
fn draw_box<DB: DrawingBackend>(
    root: &Area<DB>,
    chart: &style::Chart<DB>,
    x: f64,
    (dx0, dx1): (i32, i32),
    sp: &Spread,
    color: &RGBColor,
    marks: &mut Vec<(i32, i32)>,
) -> Result<()> {
    let win = Win::of_chart(chart);
    let lg = |v: f64| {
        if v > 0.0 {
            v.log10().clamp(win.y0, win.y1)
        } else {
            win.y0
        }
    };
    let px = |v: f64| style::px(chart, (x, lg(v)));
    let (x0, x1) = (px(sp.median).0 + dx0, px(sp.median).0 + dx1);
    let xc = (x0 + x1) / 2;
    let (ymin, yq1, ymed, yq3, ymax) = (
        px(sp.min).1,
        px(sp.q1).1,
        px(sp.median).1,
        px(sp.q3).1,
        px(sp.max).1,
    );
    // Whiskers and caps.
    style::polyline(root, &[(xc, ymin), (xc, yq1)], color, 1, None)?;
    style::polyline(root, &[(xc, yq3), (xc, ymax)], color, 1, None)?;
    let cap = ((x1 - x0) / 3).max(1);
    style::polyline(root, &[(xc - cap, ymin), (xc + cap, ymin)], color, 1, None)?;
    style::polyline(root, &[(xc - cap, ymax), (xc + cap, ymax)], color, 1, None)?;
    // The box, filled, outlined.
    let (bx, by) = root.get_base_pixel();
    root.draw(&Rectangle::new(
        [(x0 - bx, yq3 - by), (x1 - bx, yq1 - by)],
        color.mix(0.22).filled(),
    ))
    .map_err(de)?;
    style::polyline(
        root,
        &[(x0, yq1), (x1, yq1), (x1, yq3), (x0, yq3), (x0, yq1)],
        color,
        1,
        None,
    )?;
    style::polyline(root, &[(x0, ymed), (x1, ymed)], color, 2, None)?;
    // Mean.
    let ym = px(sp.mean).1;
    let r = if x1 - x0 >= 8 { 3 } else { 2 };
    style::marker(root, (xc, ym), Marker::Dot, &TEXT, r)?;
    marks.extend([(xc, ymin), (xc, yq1), (xc, ymed), (xc, yq3), (xc, ymax)]);
    Ok(())
}

/// A dash-dotted horizontal line between pixel columns x0 and x1 at row y.
fn dash_dot<DB: DrawingBackend>(
    root: &Area<DB>,
    (x0, x1): (i32, i32),
    y: i32,
    color: &RGBColor,
) -> Result<()> {
    let mut x = x0;
    while x < x1 {
        let e = (x + 10).min(x1);
        style::polyline(root, &[(x, y), (e, y)], color, 2, None)?;
        let d = x + 14;
        if d + 2 <= x1 {
            style::polyline(root, &[(d, y), (d + 2, y)], color, 2, None)?;
        }
        x += 20;
    }
    Ok(())
}

/// Draw the precision panel.
pub fn draw<DB: DrawingBackend>(root: &Area<DB>, report: &Report, fonts: Fonts) -> Result<Frame> {
    let g = glls_of(report, Panel::of(&super::horizon::PRECISION))?;
    let p = g.precision.as_ref().ok_or_else(|| {
        Error::field(
            "glls.monte_carlo",
            "is not in this report: ask for a Monte Carlo study to draw the precision panel",
        )
    })?;
    let nh = p.horizons.len();
    if nh == 0
        || p.first.len() != nh
        || p.bound.len() != nh
        || p.second.as_ref().is_some_and(|s| s.len() != nh)
    {
        return Err(Error::field(
            "report.glls.precision",
            "must hold one spread and one bound per horizon",
        ));
    }
    let paired = p.second.is_some();
    let none = vec![None; nh];
    let second = p.second.as_ref().unwrap_or(&none);
    // Window: every spread and every positive bound.
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut take = |v: f64| {
        if v > 0.0 && v.is_finite() {
            lo = lo.min(v.log10());
            hi = hi.max(v.log10());
        }
    };
    for sp in p.first.iter().chain(second.iter()).flatten() {
        take(sp.min);
        take(sp.max);
        take(sp.mean);
    }
    let bound_shown = !paired && p.bound.iter().any(|b| *b > 0.0 && b.is_finite());
    if bound_shown {
        for b in &p.bound {
            take(*b);
        }
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(Error::field(
            "report.glls.precision",
            "holds no positive error yet: run the Monte Carlo study",
        ));
    }
    let span = (hi - lo).max(0.5);
    let (mid, half) = (0.5 * (lo + hi), 0.5 * span);
    let (y0, y1) = (mid - half * 1.08, mid + half * 1.08);
    let (h0, h1) = (
        p.horizons.iter().copied().min().unwrap_or(0) as f64,
        p.horizons.iter().copied().max().unwrap_or(0) as f64,
    );
    let win = Win::new((h0 - 0.8, h1 + 0.8), (y0, y1));
    let norm = p.mean_state_norm;
    let norm_fits =
        paired && norm > 0.0 && norm.is_finite() && norm.log10() <= y1 && norm.log10() >= y0;

    // Texts.
    let short = fonts.compact;
    let runs = if p.runs < p.total {
        format!(
            "{} of {} so far",
            p.runs,
            crate::error::counted(p.total, "run", "runs")
        )
    } else {
        crate::error::counted(p.runs, "run", "runs")
    };
    let (c1, c2) = if paired {
        (STATE_NOISE, GLLS_EST)
    } else {
        (GLLS_EST, GLLS_EST)
    };
    let mut notes = vec![format!(
        "‖x̂(k) − x(k)‖₂ of the last state over {runs} per horizon · box: quartiles and median, whiskers: min–max, dot: mean"
    )];
    if paired {
        notes.push(
            "Section 5.2: state-noise estimator (63)–(64) left, LLS right, same runs".to_string(),
        );
    } else {
        notes.push(format!(
            "Section 5.1: {} with the bound κ(s,k)·√E‖δ(k,s)‖² (39)",
            super::horizon::estimator_name(g)
        ));
    }
    let mut chart_notes = Vec::new();
    if paired && !norm_fits && norm.is_finite() {
        chart_notes.push(format!(
            "mean ‖x(k)‖ = {} ({} the axis)",
            sci(norm),
            if norm.log10() > y1 {
                "far above"
            } else {
                "below"
            }
        ));
    } else if !paired {
        notes.push(format!("mean ‖x(k)‖ = {}", sci(norm)));
    }
    if !paired && !bound_shown {
        chart_notes.push("bound (39) is 0 (no measurement noise): not drawn".to_string());
    }
    let mut entries = Vec::new();
    if paired {
        entries.push(Entry::new(
            if short {
                "state-noise est."
            } else {
                "state-noise estimator (left)"
            },
            Swatch::Region {
                color: c1,
                dashed: false,
                fill: true,
            },
        ));
        entries.push(Entry::new(
            if short { "LLS" } else { "LLS (right)" },
            Swatch::Region {
                color: c2,
                dashed: false,
                fill: true,
            },
        ));
    } else {
        entries.push(Entry::new(
            format!("{} error", super::horizon::estimator_name(g)),
            Swatch::Region {
                color: c1,
                dashed: false,
                fill: true,
            },
        ));
    }
    entries.push(
        Entry::new(
            "mean",
            Swatch::Marker {
                shape: Marker::Dot,
                color: TEXT,
                size: 3,
            },
        )
        .minor(),
    );
    if bound_shown {
        entries.push(Entry::new(
            if short {
                "bound (39)"
            } else {
                "bound κ·√E‖δ‖² (39)"
            },
            Swatch::Line {
                color: TEXT,
                dashed: false,
                width: 2,
            },
        ));
    }
    if norm_fits {
        entries.push(Entry::new(
            "mean ‖x(k)‖",
            Swatch::Line {
                color: TEXT,
                dashed: true,
                width: 2,
            },
        ));
    }
    let t = if paired {
        style::title(
            &report.figure,
            &fonts,
            "State-noise estimator vs LLS",
            "State-noise estimator vs LLS (GLLS paper, Fig. 4)",
        )
    } else {
        style::title(
            &report.figure,
            &fonts,
            "Precision against the horizon",
            "Precision of the estimate against the horizon (GLLS paper, Fig. 3)",
        )
    };
    let (xd, yd) = (horizon_desc(short), "‖x̂(k) − x(k)‖₂ (log scale)");
    let (chart, side) = horizon_chart(root, &fonts, &t, &notes, &entries, win, short, yd)?;
    let mut marks = Vec::new();
    let (xr, _) = chart.plotting_area().get_pixel_range();
    // Box width from the spacing of the horizons.
    let spacing = (style::px(&chart, (h0 + 1.0, y0)).0 - style::px(&chart, (h0, y0)).0).max(2);
    let half = ((spacing as f64 * 0.36).round() as i32).clamp(1, 16);
    if bound_shown {
        let pts: Vec<(f64, f64)> = p
            .horizons
            .iter()
            .zip(&p.bound)
            .filter(|(_, b)| **b > 0.0 && b.is_finite())
            .map(|(h, b)| (*h as f64, b.log10()))
            .collect();
        style::path(root, &chart, &pts, &TEXT, 2, None)?;
        marks.extend(style::marks_of(&chart, &pts));
    }
    if norm_fits {
        let y = style::px(&chart, (h0, norm.log10())).1;
        dash_dot(root, (xr.start, xr.end), y, &TEXT)?;
        for x in (xr.start..xr.end).step_by(20) {
            marks.push((x, y));
        }
    }
    for (k, &h) in p.horizons.iter().enumerate() {
        let x = h as f64;
        if paired {
            if let Some(sp) = &p.first[k] {
                draw_box(root, &chart, x, (-half, 0), sp, &c1, &mut marks)?;
            }
            if let Some(sp) = &second[k] {
                draw_box(root, &chart, x, (0, half), sp, &c2, &mut marks)?;
            }
        } else if let Some(sp) = &p.first[k] {
            draw_box(root, &chart, x, (-half, half), sp, &c1, &mut marks)?;
        }
    }
    horizon_marker(root, &chart, &fonts, g.s, &mut chart_notes)?;
    style::chart_notes(root, &chart, &fonts, &chart_notes, &mut marks)?;
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, xd, yd))
}
