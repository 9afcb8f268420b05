//! The "ubbset" panel of a one-state report (r = 1): the feasible set of x(k+1) (or, with
//! `ubb.set` "filtered", of x(k)) is an interval at every step, so the panel draws the
//! intervals over the steps as a band, with the central estimates (31), the truth and the
//! Kalman estimate as lines; at the step shown, its interval (the polygon of the plane
//! (x₁, x₁) is its diagonal), the central estimate ⋆, Theorem 2's φ ± E(φ₀) (22), the true
//! state ◇ and the Kalman interval at `ubb.kf_level` (the detail's step only).

use super::set::{check, Chosen, HULL, SECOND, SET, SET_PANEL};
use crate::error::Result;
use crate::plot::figures::{Area, Request};
use crate::plot::geom::Win;
use crate::plot::style::{self, num, percent, Axes, Entry, Marker, Swatch, KF, TRUTH};
use crate::plot::view::{Frame, Panel};
use plotters::prelude::*;

/// The band of intervals of a one-state report.
pub fn draw<DB: DrawingBackend>(root: &Area<DB>, request: &Request) -> Result<Frame> {
    let (report, view, fonts) = (request.report, request.view, request.fonts);
    let u = check(report, Panel::of(&SET_PANEL))?;
    let chosen = Chosen::of(u);
    let steps = chosen.steps();
    let short = fonts.compact;
    let at = &u.at;
    let k = view.time.unwrap_or(at.k);
    let detail = if k == at.k { chosen.detail() } else { None };
    let ks: Vec<f64> = steps.iter().map(|(k, _)| *k as f64).collect();
    let lo: Vec<f64> = steps.iter().map(|(_, h)| h.lo[0]).collect();
    let hi: Vec<f64> = steps.iter().map(|(_, h)| h.hi[0]).collect();
    let centers: Vec<(f64, f64)> = steps
        .iter()
        .map(|(k, h)| (*k as f64, h.center[0]))
        .collect();
    let kf_line: Vec<(f64, f64)> = steps
        .iter()
        .map(|(k, h)| (*k as f64, h.kf_mean[0]))
        .collect();
    let truth_line: Vec<(f64, f64)> = steps
        .iter()
        .filter_map(|(k, _)| chosen.truth(*k).map(|x| (*k as f64, x[0])))
        .collect();
    let shown = steps.iter().find(|(s, _)| *s == k).map(|(_, h)| h);
    // The interval at k: the detail's (its own computation) or the track's.
    let interval = match (&detail, shown) {
        (Some(d), _) => Some((d.lo[0], d.hi[0], d.center[0], d.radius)),
        (None, Some(h)) => Some((h.lo[0], h.hi[0], h.center[0], h.radius)),
        (None, None) => None,
    };
    let truth_at = match &detail {
        Some(d) => d.truth.map(|t| t[0]),
        None => chosen.truth(k).map(|x| x[0]),
    };
    // The Kalman interval mean ± √(r²·P) at the detail's step (its χ²₁ level).
    let kf_interval = detail.as_ref().and_then(|d| {
        let half = (d.kf.radius2 * d.kf.cov.first()?.first()?).sqrt();
        half.is_finite()
            .then(|| (d.kf.center[0] - half, d.kf.center[0] + half))
    });
    let linear = detail.as_ref().and_then(|d| {
        d.linear
            .and_then(|l| l.iter().find(|e| e.component == 0))
            .filter(|e| e.estimate.is_finite() && e.error.is_finite())
            .map(|e| (e.estimate, e.error))
    });

    let k0 = ks.first().copied().unwrap_or(k as f64);
    let k1 = (u.steps.max(1) - 1) as f64;
    let mut ys: Vec<f64> = lo.iter().chain(&hi).copied().collect();
    ys.extend(truth_line.iter().map(|p| p.1));
    ys.extend(interval.iter().flat_map(|i| [i.0, i.1]));
    ys.extend(truth_at);
    ys.extend(linear.iter().flat_map(|(e, r)| [e - r, e + r]));
    // The Kalman line and interval widen the window up to three times the band's (the
    // prior's first steps would flatten the band): beyond that they are clipped.
    let span = Win::time((k0, k1.max(k0 + 1.0)), ys.iter().copied());
    let (reach_lo, reach_hi) = (span.y0 - (span.y1 - span.y0), span.y1 + (span.y1 - span.y0));
    let mut kf_clipped = false;
    let mut clip = |v: f64| {
        let c = v.clamp(reach_lo, reach_hi);
        kf_clipped |= c != v;
        c
    };
    let kf_line: Vec<(f64, f64)> = kf_line.iter().map(|&(x, y)| (x, clip(y))).collect();
    let kf_interval = kf_interval.map(|(a, b)| (clip(a), clip(b)));
    ys.extend(kf_line.iter().map(|p| p.1));
    ys.extend(kf_interval.iter().flat_map(|i| [i.0, i.1]));
    let x_range = if k1 > k0 {
        (k0, k1)
    } else {
        (k0 - 0.5, k0 + 0.5)
    };
    let win = Win::time(x_range, ys.into_iter());

    let coefficients = u.state_names.first().is_some_and(|n| !n.starts_with('x'));
    let lag = if chosen.filtered { "k" } else { "k+1" };
    let name = match u.state_names.first() {
        Some(n) if coefficients => n.clone(),
        _ => format!("x₁({lag})"),
    };
    let y_desc = match report.figure.names.first() {
        Some(n) if !n.is_empty() && !short => format!("{name}: {n}"),
        _ => name.clone(),
    };
    let x_desc = if short {
        "step k".to_string()
    } else {
        format!("step k (the set of x({lag}) from y(0 … k))")
    };
    let norm = super::set::norm_name(u.norm);
    let mut notes = vec![format!(
        "one state: the {} of {} is an interval at every step, {norm} bounds, window {} steps",
        chosen.name(),
        chosen.state_symbol(),
        u.window
    )];
    match &detail {
        Some(_) => notes.push(format!(
            "at k = {k}: its interval from y({}) … y({k})",
            at.first
        )),
        None => notes.push(format!(
            "k = {k}: Theorem 2 and the Kalman interval not in this report (it holds k = {})",
            at.k
        )),
    }
    let kf_level = percent(level_1d(at.kf.radius2));
    let line = |color, dashed, width| Swatch::Line {
        color,
        dashed,
        width,
    };
    let marker = |shape, color| Swatch::Marker {
        shape,
        color,
        size: 5,
    };
    let mut entries = vec![Entry::new(
        if short {
            "set (interval)".to_string()
        } else {
            format!("{} (an interval at each step)", chosen.name())
        },
        Swatch::Region {
            color: SET,
            dashed: false,
            fill: true,
        },
    )];
    entries.push(Entry::new(
        if short {
            "central estimate"
        } else {
            "central estimate (midpoint)"
        },
        line(SET, true, 1),
    ));
    if !truth_line.is_empty() {
        entries.push(Entry::new("true state", line(TRUTH, false, 2)));
    }
    entries.push(Entry::new(
        if short {
            format!("Kalman, {kf_level} at k")
        } else {
            format!("Kalman estimate ({kf_level} interval at k)")
        },
        line(KF, true, 1),
    ));
    if linear.is_some() {
        entries.push(Entry::new(
            if short {
                "linear optimal ± E".to_string()
            } else {
                "linear optimal φ ± E (Theorem 2)".to_string()
            },
            marker(Marker::Ring, SECOND),
        ));
    }
    let what = format!(
        "{} over k: {} (one state), {norm} bounds",
        if chosen.filtered {
            "Filtered sets"
        } else {
            "Feasible sets"
        },
        chosen.state_symbol()
    );
    let title = style::title(&report.figure, &fonts, &what, &what);
    let (area, side) = style::titled_legend(root, &fonts, &title, &notes, &entries)?;
    let axes = Axes {
        win,
        x_desc: &x_desc,
        y_desc: &y_desc,
        x_integer: true,
        equal: false,
        x_labels: true,
    };
    let chart = style::chart(&area, &fonts, &axes)?;
    let mut marks = Vec::new();
    if !ks.is_empty() {
        style::band(root, &chart, &ks, &lo, &hi, &SET)?;
        let edge =
            |v: &[f64]| -> Vec<(f64, f64)> { ks.iter().copied().zip(v.iter().copied()).collect() };
        style::path(root, &chart, &edge(&lo), &SET, 1, None)?;
        style::path(root, &chart, &edge(&hi), &SET, 1, None)?;
        marks.extend(style::marks_of(&chart, &edge(&lo)));
        marks.extend(style::marks_of(&chart, &edge(&hi)));
        style::path(root, &chart, &centers, &SET, 1, Some(style::DASH))?;
        style::path(root, &chart, &kf_line, &KF, 1, Some(style::DASH))?;
        if truth_line.len() >= 2 {
            style::path(root, &chart, &truth_line, &TRUTH, 2, None)?;
        }
        marks.extend(style::marks_of(&chart, &truth_line));
    }
    style::cursor(root, &chart, &fonts, k as f64, &format!("k = {k}"))?;
    let x = k as f64;
    if let Some((l, h, _, _)) = interval {
        let seg = [(x, l), (x, h)];
        style::path(root, &chart, &seg, &HULL, 3, None)?;
        marks.extend(style::marks_of(&chart, &seg));
    }
    if let Some((a, b)) = kf_interval {
        let off = 0.15 * (win.x1 - win.x0) / 40.0;
        let seg = [(x + off, a), (x + off, b)];
        style::path(root, &chart, &seg, &KF, 2, Some(style::DASH))?;
        marks.extend(style::marks_of(&chart, &seg));
    }
    if let Some((e, r)) = linear {
        let off = 0.15 * (win.x1 - win.x0) / 40.0;
        let seg = [(x - off, e - r), (x - off, e + r)];
        style::path(root, &chart, &seg, &SECOND, 2, Some(style::DASH))?;
        marks.extend(style::marks_of(&chart, &seg));
    }
    let mut points = Vec::new();
    if let Some((_, _, c, _)) = interval {
        points.push(((x, c), Marker::Star, SET, "central estimate"));
    }
    points.extend(linear.map(|(e, _)| ((x, e), Marker::Ring, SECOND, "linear optimal estimate")));
    points.extend(truth_at.map(|t| ((x, t), Marker::Diamond, TRUTH, "true state")));
    let outside = style::markers_inside(root, &chart, &points, &mut marks)?;

    let mut chart_notes = Vec::new();
    match shown.and_then(|h| h.inside) {
        Some(true) => chart_notes.push("truth inside the set (guaranteed)".to_string()),
        Some(false) => chart_notes.push("truth OUTSIDE the set (solver tolerance?)".to_string()),
        None => {}
    }
    if kf_clipped {
        chart_notes.push(if short {
            "Kalman clipped".to_string()
        } else {
            "the Kalman estimate reaches beyond the window".to_string()
        });
    }
    if !outside.is_empty() {
        chart_notes.push(format!("outside the window: {}", outside.join(", ")));
    }
    if let (false, Some((l, h, _, radius))) = (short, interval) {
        chart_notes.push(format!(
            "at k = {k}: [{}, {}], radius {}",
            num(l, 3),
            num(h, 3),
            num(radius, 3)
        ));
    }
    style::chart_notes(root, &chart, &fonts, &chart_notes, &mut marks)?;
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, &x_desc, &y_desc))
}

/// The level of a 1-D interval of radius² `r2` (χ²₁: 2Φ(r) − 1), 0 when it cannot be read.
fn level_1d(r2: f64) -> f64 {
    crate::stats::ellipsoid_level(r2, 1).unwrap_or(0.0)
}
