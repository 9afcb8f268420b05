//! The region panel of a scalar state (n = 1): X̂ is a union of intervals of the line
//! (`report.lscr.intervals`, exact: [`crate::sets::SignRegion::intervals_1d`]), so the figure
//! is one axis, the state x_τ, with a row per set: X̂ tinted and outlined, the part X̂₁ excludes
//! hatched as on the plane's panel; below it the BLUE and Kalman intervals (the ellipses of one
//! dimension, at the joint level), each with its estimate; the true state ◇ on X̂'s row with a
//! thin line across the rows. An end of X̂ that is unbounded is an arrow at the window's edge.

use super::region::{ellipse_level, lscr_of, what};
use crate::error::{Error, Result};
use crate::plot::erase::de;
use crate::plot::figures::{Area, Request};
use crate::plot::geom::Win;
use crate::plot::style::{
    self, pct, sub, Entry, Marker, Swatch, BLUE_EST, DASH, DOT, GRID, GRID_LIGHT, KF, LSCR,
    LSCR_TINT, MUTED, TRUTH,
};
use crate::plot::view::Frame;
use crate::sets::Ellipsoid;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

/// Opacity of X̂'s tint here: a band is thinner than the plane's regions, so denser.
const TINT_ALPHA: f64 = 0.45;
/// Half the height of a row's band, in rows.
const BAND: f64 = 0.22;

/// One row of the figure: its label and what it draws.
enum Row<'a> {
    Region,
    Interval {
        e: &'a Ellipsoid,
        color: RGBColor,
        dashed: bool,
        marker: Marker,
        name: &'static str,
    },
}

/// An ellipse of one dimension with a radius, or none.
fn one(e: &Option<Ellipsoid>) -> Option<&Ellipsoid> {
    e.as_ref().filter(|e| e.dim() == 1 && e.radius2 >= 0.0)
}

/// Draw the region panel of a scalar state.
pub fn draw<DB: DrawingBackend>(root: &Area<DB>, request: &Request) -> Result<Frame> {
    let (report, fonts) = (request.report, request.fonts);
    let l = lscr_of(report)?;
    let w = &l.window;
    let one_interval = w.lo.len() == 1
        && w.hi.len() == 1
        && w.lo[0].is_finite()
        && w.hi[0].is_finite()
        && w.lo[0] < w.hi[0];
    if !one_interval {
        return Err(Error::field(
            "report.lscr.window",
            "must be one finite interval lo < hi for a scalar state",
        ));
    }
    let (x0, x1) = (w.lo[0], w.hi[0]);
    let mut rows: Vec<Row> = vec![Row::Region];
    if let Some(e) = one(&l.blue) {
        rows.push(Row::Interval {
            e,
            color: BLUE_EST,
            dashed: false,
            marker: Marker::Star,
            name: "BLUE",
        });
    }
    if let Some(e) = one(&l.kf) {
        rows.push(Row::Interval {
            e,
            color: KF,
            dashed: true,
            marker: Marker::Cross,
            name: "Kalman",
        });
    }
    let label = |r: &Row| match r {
        Row::Region => format!("X̂ {}", pct(l.level)),
        Row::Interval { e, name, .. } => {
            let lv = ellipse_level(e.radius2, 1).map(pct).unwrap_or_default();
            format!("{name} {lv}")
        }
    };

    // Texts.
    let tau = l.time;
    let (kind, what) = what(l);
    let xt = format!("x{}", sub(tau));
    let x_desc = match report.figure.names.first() {
        Some(name) if !name.is_empty() => format!("{xt}: {name}"),
        _ => format!("{xt}  (the scalar state)"),
    };
    let title = match &report.figure.title {
        Some(t) if t.to_lowercase().contains(&kind) => t.clone(),
        Some(t) => format!("{t}: {kind}"),
        None => format!("LSCR {what}"),
    };
    let mut notes: Vec<String> = vec![format!("LSCR {what}")];
    if l.guaranteed {
        notes.push(format!(
            "M = {}, q = {}: X̂ holds {xt} w.p. ≥ {} (Theorem 3.2)",
            l.m,
            l.q,
            pct(l.level)
        ));
    } else {
        notes.push(format!(
            "M = {}, q = {}: explicit strings, no probability guarantee (Theorem 3.2 needs random or group strings)",
            l.m, l.q
        ));
    }
    let pieces = l.intervals.len();
    notes.push(match pieces {
        0 => "X̂ is empty".to_string(),
        1 => "n = 1: X̂ is an interval of the line".to_string(),
        k => format!(
            "n = 1: X̂ is a union of {k_intervals}",
            k_intervals = crate::error::counted(k, "interval", "intervals")
        ),
    });
    if let Some(inside) = l.truth_inside {
        notes.push(format!(
            "true {xt} in X̂: {}",
            if inside { "yes" } else { "no" }
        ));
    }
    if l.blue.is_none() {
        if let Some(why) = &l.blue_note {
            notes.push(format!("no BLUE: {why}"));
        }
    }
    let mut entries = vec![
        Entry::new(
            format!("X̂ (LSCR, {})", pct(l.level)),
            Swatch::Tinted {
                line: LSCR,
                tint: LSCR_TINT.mix(TINT_ALPHA),
            },
        ),
        Entry::new(
            format!("excluded by X̂{}", sub(1)),
            Swatch::Hatch {
                color: style::hatch_color(0),
                group: 0,
            },
        ),
    ];
    let truth = l.x_true.as_ref().and_then(|x| x.first().copied());
    if truth.is_some() {
        entries.push(Entry::new(
            format!("true state {xt}"),
            Swatch::Marker {
                shape: Marker::Diamond,
                color: TRUTH,
                size: 5,
            },
        ));
    }

    // The chart: the state on x, one row per set on y (named in the left margin, no numbers).
    let (area, side) = style::titled_legend(root, &fonts, &title, &notes, &entries)?;
    let tick = fonts.tick();
    let desc = fonts.axis();
    let desc_h = style::text_size(&area, "Xg", &desc)?.1 as i32;
    let tick_h = style::text_size(&area, "0", &tick)?.1 as i32;
    let mut label_w = 0;
    for r in &rows {
        label_w = label_w.max(style::text_size(&area, &label(r), &tick)?.0 as i32);
    }
    let (wpx, hpx) = area.dim_in_pixel();
    let x_area = tick_h + desc_h + 22;
    let y_area = label_w + 16;
    if (wpx as i32) < y_area + 80 || (hpx as i32) < x_area + 40 {
        return Err(Error::field(
            "size",
            format!("{wpx} × {hpx} pixels leave no room for the chart: make the figure larger"),
        ));
    }
    let n_rows = rows.len() as f64;
    let mut chart = ChartBuilder::on(&area)
        .margin_top(12)
        .margin_right(22)
        .margin_left(6)
        .margin_bottom(4)
        .x_label_area_size(x_area)
        .y_label_area_size(y_area)
        .build_cartesian_2d(x0..x1, 0.0..n_rows)
        .map_err(de)?;
    let xd = style::decimals(x1 - x0);
    let fx = move |v: &f64| style::num(*v, xd);
    let no_label = |_: &f64| String::new();
    let pw = wpx as i32 - y_area - 28;
    chart
        .configure_mesh()
        .x_desc(x_desc.clone())
        .label_style(tick.clone())
        .axis_desc_style(desc.clone())
        .x_labels(((pw / 55).clamp(3, 10)) as usize)
        .x_label_formatter(&fx)
        .y_label_formatter(&no_label)
        .set_tick_mark_size(LabelAreaPosition::Left, 0)
        .disable_y_mesh()
        .max_light_lines(4)
        .light_line_style(GRID_LIGHT)
        .bold_line_style(GRID)
        .axis_style(MUTED)
        .draw()
        .map_err(de)?;
    let centre = |k: usize| n_rows - k as f64 - 0.5;
    let px = |x: f64, y: f64| style::px(&chart, (x.clamp(x0, x1), y));
    let (bx, by) = root.get_base_pixel();
    let rel = |p: (i32, i32)| (p.0 - bx, p.1 - by);
    let mut marks: Vec<(i32, i32)> = Vec::new();
    let mut outside: Vec<String> = Vec::new();
    let mut chart_notes: Vec<String> = Vec::new();

    for (k, row) in rows.iter().enumerate() {
        let y = centre(k);
        let name_at = px(x0, y);
        style::text(
            root,
            &label(row),
            (name_at.0 - 8, name_at.1),
            &tick,
            (HPos::Right, VPos::Center),
        )?;
        match row {
            Row::Region => {
                // The part of the window outside X̂, hatched like the plane's X̂₁ exclusions.
                let mut inside: Vec<(f64, f64)> = Vec::new();
                for iv in &l.intervals {
                    let (lo, hi) = iv.ends();
                    let (a, b) = (lo.max(x0), hi.min(x1));
                    if a < b {
                        inside.push((a, b));
                    }
                }
                let mut excluded: Vec<(f64, f64)> = Vec::new();
                let mut from = x0;
                for &(a, b) in &inside {
                    if a > from {
                        excluded.push((from, a));
                    }
                    from = from.max(b);
                }
                if from < x1 {
                    excluded.push((from, x1));
                }
                let (top, bottom) = (px(x0, y + BAND), px(x1, y - BAND));
                let band = Win::new(
                    (top.0 as f64, bottom.0 as f64),
                    (top.1 as f64, bottom.1 as f64),
                );
                let spacing = if fonts.compact { 6.0 } else { 7.0 };
                let hatch = style::hatch_color(0).stroke_width(1);
                for (a, b) in style::hatch_lines(&band, 0, spacing) {
                    for &(e0, e1) in &excluded {
                        let (p0, p1) = (px(e0, y).0 as f64, px(e1, y).0 as f64);
                        if let Some((s0, s1)) = clip_to_columns(a, b, p0, p1) {
                            let at = |s: f64| {
                                (
                                    (a.0 + s * (b.0 - a.0)).round() as i32,
                                    (a.1 + s * (b.1 - a.1)).round() as i32,
                                )
                            };
                            root.draw(&PathElement::new(vec![rel(at(s0)), rel(at(s1))], hatch))
                                .map_err(de)?;
                        }
                    }
                }
                for &(a, b) in &inside {
                    let (p, q) = (px(a, y + BAND), px(b, y - BAND));
                    root.draw(&Rectangle::new(
                        [rel(p), rel(q)],
                        LSCR_TINT.mix(TINT_ALPHA).filled(),
                    ))
                    .map_err(de)?;
                    // The outline, open where the window (not X̂) ends the piece.
                    let (lo_cut, hi_cut) = (a <= x0, b >= x1);
                    let corners = [
                        px(a, y + BAND),
                        px(b, y + BAND),
                        px(b, y - BAND),
                        px(a, y - BAND),
                    ];
                    style::polyline(root, &[corners[0], corners[1]], &LSCR, 2, None)?;
                    style::polyline(root, &[corners[3], corners[2]], &LSCR, 2, None)?;
                    if !lo_cut {
                        style::polyline(root, &[corners[0], corners[3]], &LSCR, 2, None)?;
                    }
                    if !hi_cut {
                        style::polyline(root, &[corners[1], corners[2]], &LSCR, 2, None)?;
                    }
                    marks.extend(corners);
                }
                // Arrows where X̂ goes on beyond the window.
                for (dir, end) in [(-1.0, x0), (1.0, x1)] {
                    if l.recession.iter().any(|r| r[0] == dir) {
                        let tip = px(end, y);
                        let back = (tip.0 - (dir * 14.0) as i32, tip.1);
                        style::polyline(root, &[back, tip], &LSCR, 2, None)?;
                        style::polyline(
                            root,
                            &[(back.0, tip.1 - 6), tip, (back.0, tip.1 + 6)],
                            &LSCR,
                            2,
                            None,
                        )?;
                    }
                }
                if let Some(t) = truth {
                    if (x0..=x1).contains(&t) {
                        // A thin line across the rows, and the ◇ on X̂'s.
                        let (a, b) = (px(t, n_rows), px(t, 0.0));
                        style::polyline(root, &[a, b], &TRUTH, 1, Some(DOT))?;
                        let p = px(t, y);
                        marks.push(p);
                        style::marker(root, p, Marker::Diamond, &TRUTH, 5)?;
                    } else {
                        outside.push("true state".into());
                    }
                }
            }
            Row::Interval {
                e,
                color,
                dashed,
                marker,
                name,
            } => {
                let b = e.bounding_box();
                let (lo, hi) = (b.lo[0], b.hi[0]);
                let (p, q) = (px(lo, y), px(hi, y));
                let dash = dashed.then_some(DASH);
                style::polyline(root, &[p, q], color, 2, dash)?;
                for end in [lo, hi] {
                    if (x0..=x1).contains(&end) {
                        let e = px(end, y);
                        style::polyline(root, &[(e.0, e.1 - 7), (e.0, e.1 + 7)], color, 2, None)?;
                    }
                }
                marks.extend([p, q]);
                let c = e.center[0];
                if (x0..=x1).contains(&c) {
                    let p = px(c, y);
                    marks.push(p);
                    style::marker(root, p, *marker, color, 5)?;
                } else {
                    outside.push(format!("{name} estimate"));
                }
            }
        }
    }
    if !l.bounded {
        let towards: Vec<&str> = l
            .recession
            .iter()
            .map(|r| if r[0] < 0.0 { "−∞" } else { "+∞" })
            .collect();
        chart_notes.push(format!("X̂ is unbounded towards {}", towards.join(" and ")));
    }
    if !outside.is_empty() {
        chart_notes.push(format!("outside the window: {}", outside.join(", ")));
    }
    style::note_box(root, &chart, &fonts, &chart_notes, &mut marks, &LSCR, &LSCR)?;
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, &x_desc, ""))
}

/// The part s ∈ [s0, s1] ⊂ [0, 1] of the pixel segment a → b whose x lies between the columns
/// p0 and p1 (p0 < p1); None when it has none.
fn clip_to_columns(a: (f64, f64), b: (f64, f64), p0: f64, p1: f64) -> Option<(f64, f64)> {
    let dx = b.0 - a.0;
    let (mut s0, mut s1) = (0.0f64, 1.0f64);
    if dx == 0.0 {
        if a.0 < p0 || a.0 > p1 {
            return None;
        }
    } else {
        let (t0, t1) = ((p0 - a.0) / dx, (p1 - a.0) / dx);
        s0 = s0.max(t0.min(t1));
        s1 = s1.min(t0.max(t1));
    }
    (s0 < s1).then_some((s0, s1))
}
