//! The set-membership panel [`"ubbset"`](SET_PANEL) (Tempo, method `"ubb"`), with what both
//! ubb panels share (their names, the check of the report's ubb part, the colours): the exact
//! feasible set of x(k+1) at the report's step k in the `plane` components — a
//! polygon from support LPs — with its interval hull dashed, the central estimate ⋆ (the
//! hull's midpoint), Theorem 2's linear optimal estimate ○ with its error box φ ± E(φ₀) (22)
//! dashed (l∞ bounds, the detail's step only), the true state ◇ and the Kalman ellipse dashed) and [`"ubbwidth"`](WIDTH_PANEL)
//! (`width.rs`: the hull's widths over k with the Theorem 4 bound, and the truth inside
//! its hull bands).
//!
//! Step k's set is the set of x(k+1) consistent with y(0 … k) (the paper's prediction set);
//! equal scales on both axes of the set panel.

use crate::error::{Error, Result};
use crate::plot::figures::{Area, Request};
use crate::plot::geom::Win;
use crate::plot::style::{self, num, percent, sig, sub, Entry, Marker, Swatch, KF, TRUTH};
use crate::plot::view::PanelSpec;
use crate::plot::view::{Frame, Panel};
use crate::scenario::{Report, UbbReport};
use crate::ubb::Norm;
use plotters::prelude::*;

/// Set-membership (Tempo): the exact feasible set of x(k+1) at the report's step k (a
/// polygon in the plane components) with its interval hull, the central estimate, the
/// truth and the Kalman ellipse.
pub(crate) static SET_PANEL: PanelSpec = PanelSpec::new("ubbset", "feasible set of the state at step k, its interval hull, the central estimate, the linear optimal estimate of Theorem 2 with its error box, the truth and the Kalman ellipse");
/// Set-membership: the widths of the interval hull over k with the Theorem 4 bound, and
/// the truth inside its hull bands.
pub(crate) static WIDTH_PANEL: PanelSpec = PanelSpec::new("ubbwidth", "widths of the interval hull over k with the Theorem 4 bound, and the truth inside its hull bands");

/// The feasible set (blue, light fill) and its central estimate.
pub const SET: RGBColor = RGBColor(0, 114, 178);
/// The interval hull (bluish green, dashed).
pub const HULL: RGBColor = RGBColor(0, 158, 115);
/// Second plotted component in the time charts (reddish purple).
pub const SECOND: RGBColor = RGBColor(204, 121, 167);

/// Points on the drawn Kalman ellipse.
const ELLIPSE_POINTS: usize = 120;

/// The report's set-membership part, or an error naming the panel.
pub fn ubb_of(report: &Report, panel: Panel) -> Result<&UbbReport> {
    report.ubb.as_ref().ok_or_else(|| {
        Error::field(
            "panel",
            format!(
                "\"{}\" draws a set-membership figure, but this report (method \"{}\") has no ubb part: run a scenario with \"method\": \"ubb\"",
                panel.name(),
                report.method
            ),
        )
    })
}

fn finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// "l∞", "l1", "l2".
pub fn norm_name(n: Norm) -> &'static str {
    match n {
        Norm::Linf => "l∞",
        Norm::L1 => "l₁",
        Norm::L2 => "l₂",
    }
}

/// Check every array the panels index, so drawing never panics on a broken report.
pub(crate) fn check(report: &Report, panel: Panel) -> Result<&UbbReport> {
    let u = ubb_of(report, panel)?;
    let r = u.r;
    let bad = |what: &str| Err(Error::field("report.ubb", what.to_string()));
    if r < 2 || u.plane[0] >= r || u.plane[1] >= r || u.plane[0] == u.plane[1] {
        return bad("must name two distinct plane components below r");
    }
    if u.track.is_empty() {
        return bad("has no step with a bounded set to draw");
    }
    let ok = |lo: &[f64], hi: &[f64]| lo.len() == r && hi.len() == r && finite(lo) && finite(hi);
    let point = |v: &[f64]| v.len() == r && finite(v);
    if !u
        .track
        .iter()
        .all(|t| ok(&t.lo, &t.hi) && point(&t.center) && point(&t.kf_mean) && t.radius.is_finite())
    {
        return bad("holds track steps of the wrong dimension or with non-finite numbers");
    }
    if let Some(x) = &u.x_true {
        if x.iter().any(|row| row.len() != r || !finite(row)) {
            return bad("must hold true states of the state's dimension");
        }
    }
    let at = &u.at;
    if !ok(&at.lo, &at.hi) || at.center.len() != r || !finite(&at.center) {
        return Err(Error::field(
            "report.ubb.at",
            "must hold the hull and centre of x(k+1) (r numbers each)",
        ));
    }
    if at.polygon.vertices.iter().any(|p| !finite(p)) || !finite(&at.polygon.hull) {
        return Err(Error::field(
            "report.ubb.at.polygon",
            "holds non-finite vertices",
        ));
    }
    if at
        .truth
        .as_ref()
        .is_some_and(|t| t.len() != 2 || !finite(t))
    {
        return Err(Error::field(
            "report.ubb.at.truth",
            "must hold the two plane coordinates of x(k+1)",
        ));
    }
    if at.kf.dim() != 2 {
        return Err(Error::field(
            "report.ubb.at.kf",
            "must be the Kalman ellipse in the plane (2-D)",
        ));
    }
    Ok(u)
}

/// The level of a 2-D ellipse of radius² `r2` (χ²₂: 1 − e^{−r²/2}).
pub fn level_2d(r2: f64) -> f64 {
    1.0 - (-0.5 * r2).exp()
}

/// The "ubbset" panel.
pub fn draw_set<DB: DrawingBackend>(root: &Area<DB>, request: &Request) -> Result<Frame> {
    let (report, view, fonts) = (request.report, request.view, request.fonts);
    let u = check(report, Panel::of(&SET_PANEL))?;
    let at = &u.at;
    // The step shown: the view's, else the report's. Its exact polygon, Kalman ellipse and LP
    // come with the report's `at` only; another step of the track is drawn from what the
    // report holds for every step (hull, centre, truth, Kalman mean) until its detail is set
    // (`Report::set_at`). A detail of one step is never drawn at another.
    let k = view.time.unwrap_or(at.k);
    let detail = k == at.k;
    let step = u.track.iter().find(|t| t.k == k);
    if step.is_none() && !detail {
        return Err(Error::field(
            "time",
            format!(
                "k = {k} has no bounded set in this report (its track holds k = {} … {})",
                u.track[0].k,
                u.track[u.track.len() - 1].k
            ),
        ));
    }
    let [i, j] = u.plane;
    let short = fonts.compact;
    let poly: Vec<(f64, f64)> = if detail {
        at.polygon.vertices.iter().map(|p| (p[0], p[1])).collect()
    } else {
        Vec::new()
    };
    // The hull, centre and radius: the detail's (from its own LPs) or the track's.
    let (s_lo, s_hi, s_center, radius) = match step {
        Some(t) if !detail => (&t.lo, &t.hi, &t.center, t.radius),
        _ => (&at.lo, &at.hi, &at.center, at.radius),
    };
    let (lo, hi) = ((s_lo[i], s_lo[j]), (s_hi[i], s_hi[j]));
    let hull = [(lo.0, lo.1), (hi.0, lo.1), (hi.0, hi.1), (lo.0, hi.1)];
    let center = (s_center[i], s_center[j]);
    let truth = if detail {
        at.truth.as_ref().map(|t| (t[0], t[1]))
    } else {
        u.x_true
            .as_ref()
            .and_then(|x| x.get(k + 1))
            .map(|x| (x[i], x[j]))
    };
    let ellipse = if detail {
        at.kf.boundary_2d(ELLIPSE_POINTS)?
    } else {
        Vec::new()
    };
    // Theorem 2's linear optimal estimate φ of the plane components with its error box φ ± E
    // (22): the detail's only (one LP per component; not in the track).
    let linear = if detail {
        at.linear.as_ref().and_then(|l| {
            let c = |comp: usize| l.iter().find(|e| e.component == comp);
            let (a, b) = (c(i)?, c(j)?);
            let ok = [a.estimate, a.error, b.estimate, b.error]
                .iter()
                .all(|v| v.is_finite());
            ok.then_some(((a.estimate, b.estimate), (a.error, b.error)))
        })
    } else {
        None
    };
    let linear_box = linear.map(|((x, y), (ex, ey))| {
        [
            (x - ex, y - ey),
            (x + ex, y - ey),
            (x + ex, y + ey),
            (x - ex, y + ey),
        ]
    });
    let kf_center = match step {
        Some(t) if !detail => (t.kf_mean[i], t.kf_mean[j]),
        _ => (at.kf.center[0], at.kf.center[1]),
    };
    // The level is the same at every step (`ubb.kf_level`).
    let kf_level = percent(level_2d(at.kf.radius2));

    let mut w = Win::empty();
    w.add_points(&poly);
    w.add_points(&hull);
    w.add(center.0, center.1);
    if let Some(b) = &linear_box {
        w.add_points(b);
    }
    if let Some(p) = truth {
        w.add(p.0, p.1);
    }
    // The Kalman ellipse widens the window up to three times the set's (a much larger ellipse
    // would shrink the set to a dot): beyond that it is clipped, and the chart says so.
    let reach = w.padded(1.0, 1.0);
    let mut kf_clipped = false;
    for &(x, y) in &ellipse {
        let (cx, cy) = (x.clamp(reach.x0, reach.x1), y.clamp(reach.y0, reach.y1));
        kf_clipped |= cx != x || cy != y;
        w.add(cx, cy);
    }
    let pad = if short { 0.25 } else { 0.1 };
    let win = w.padded(pad, pad);

    // Example 1's state is the coefficient vector a (constant in k): its names come as "a₁ (1)".
    let coefficients = u.state_names.first().is_some_and(|n| !n.starts_with('x'));
    let comp = |c: usize| match u.state_names.get(c) {
        Some(name) if coefficients => name.clone(),
        _ => format!("x{}(k+1)", sub(c + 1)),
    };
    let target = if coefficients {
        "the coefficients a".to_string()
    } else {
        format!("x({})", k + 1)
    };
    let axis = |c: usize| match report.figure.names.get(c) {
        Some(name) if !name.is_empty() && !short => format!("{}: {name}", comp(c)),
        _ => comp(c),
    };
    let (x_desc, y_desc) = (axis(i), axis(j));
    let norm = norm_name(u.norm);
    let mut notes = vec![if u.q == 0 {
        format!("{target}: the image of the a-priori set (no measurements)")
    } else if detail {
        format!(
            "{target} consistent with y({}) … y({k}) and the {norm} noise bounds",
            at.first
        )
    } else {
        format!("{target} consistent with the data up to y({k}) and the {norm} noise bounds")
    }];
    if detail {
        notes.push(format!(
            "polygon: {} vertices from {} LPs{}",
            poly.len(),
            at.polygon.calls,
            if at.polygon.exact {
                " (exact)".to_string()
            } else {
                format!(", within {} of the set", sig(at.polygon.gap))
            }
        ));
        notes.push(format!(
            "LP: {} variables, {} rows{}",
            at.size.variables,
            at.size.rows,
            if at.size.cones > 0 {
                format!(", {} cones", at.size.cones)
            } else {
                String::new()
            }
        ));
    } else {
        notes.push(format!(
            "k = {k}: polygon and Kalman ellipse not in this report (it holds k = {})",
            at.k
        ));
    }
    if u.r > 2 {
        notes.push(format!(
            "r = {}: the projection on x{}, x{}",
            u.r,
            sub(i + 1),
            sub(j + 1)
        ));
    }

    let marker = |shape, color| Swatch::Marker {
        shape,
        color,
        size: 5,
    };
    let mut entries = Vec::new();
    if truth.is_some() {
        entries.push(Entry::new(
            if coefficients {
                "true coefficients a".to_string()
            } else {
                format!("true state x({})", k + 1)
            },
            marker(Marker::Diamond, TRUTH),
        ));
    }
    entries.push(Entry::new(
        if short {
            "central estimate".to_string()
        } else {
            "central estimate (hull midpoint)".to_string()
        },
        marker(Marker::Star, SET),
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
        entries.push(Entry::new(
            if short {
                "its error box".to_string()
            } else {
                "its error box φ ± E(φ₀) (22)".to_string()
            },
            Swatch::Region {
                color: SECOND,
                dashed: true,
                fill: false,
            },
        ));
    }
    entries.push(Entry::new(
        if short {
            "feasible set".to_string()
        } else {
            format!("feasible set ({norm} bounds)")
        },
        Swatch::Region {
            color: SET,
            dashed: false,
            fill: true,
        },
    ));
    entries.push(Entry::new(
        "interval hull",
        Swatch::Region {
            color: HULL,
            dashed: true,
            fill: false,
        },
    ));
    entries.push(Entry::new(
        if short {
            format!("Kalman {kf_level} (× mean)")
        } else {
            format!("Kalman {kf_level} ellipse (× its mean)")
        },
        Swatch::Region {
            color: KF,
            dashed: true,
            fill: false,
        },
    ));
    let what = format!(
        "Feasible set at {}: {target}, {norm} bounds",
        style::RecordTimes::of(&report.figure, crate::scenario::TimeIndex::ZeroBased).at("k", k)
    );
    let title = style::title(&report.figure, &fonts, &what, &what);
    let (area, side) = style::titled_legend_beside(root, &fonts, &title, &notes, &entries)?;
    let chart = style::equal_chart(&area, &fonts, win, &x_desc, &y_desc)?;
    let mut marks = Vec::new();
    if poly.len() >= 2 {
        style::region(root, &chart, &poly, &SET, false, true)?;
        marks.extend(style::marks_of(&chart, &poly));
    }
    style::region(root, &chart, &hull, &HULL, true, false)?;
    marks.extend(style::marks_of(&chart, &hull));
    if let Some(b) = &linear_box {
        style::region(root, &chart, b, &SECOND, true, false)?;
        marks.extend(style::marks_of(&chart, b));
    }
    if !ellipse.is_empty() {
        style::region(root, &chart, &ellipse, &KF, true, false)?;
        marks.extend(style::marks_of(&chart, &ellipse));
    }
    let mut points = vec![
        (kf_center, Marker::Cross, KF, "KF prediction"),
        (center, Marker::Star, SET, "central estimate"),
    ];
    points.extend(linear.map(|(p, _)| (p, Marker::Ring, SECOND, "linear optimal estimate")));
    points.extend(truth.map(|p| (p, Marker::Diamond, TRUTH, "true state")));
    let outside = style::markers_inside(root, &chart, &points, &mut marks)?;

    let mut chart_notes = Vec::new();
    let inside = step.and_then(|t| t.inside);
    match inside {
        Some(true) => chart_notes.push("truth inside the set (guaranteed)".to_string()),
        Some(false) => chart_notes.push("truth OUTSIDE the set (solver tolerance?)".to_string()),
        None => {}
    }
    if detail && !at.polygon.exact {
        chart_notes.push(format!(
            "polygon within gap {} of the set",
            sig(at.polygon.gap)
        ));
    }
    if kf_clipped {
        chart_notes.push(if short {
            "Kalman ellipse clipped".to_string()
        } else {
            "the Kalman ellipse reaches beyond the window".to_string()
        });
    }
    if detail && poly.is_empty() {
        chart_notes.push("the feasible set is empty".to_string());
    }
    if !outside.is_empty() {
        chart_notes.push(format!("outside the window: {}", outside.join(", ")));
    }
    if !short {
        chart_notes.push(format!(
            "radius {} (largest half-width of the hull)",
            num(radius, 3)
        ));
        if let Some((_, (ex, ey))) = linear {
            chart_notes.push(format!(
                "Theorem 2: E = {}, {} (the hull's half-widths {}, {})",
                num(ex, 3),
                num(ey, 3),
                num(0.5 * (s_hi[i] - s_lo[i]), 3),
                num(0.5 * (s_hi[j] - s_lo[j]), 3)
            ));
        }
    }
    style::chart_notes(root, &chart, &fonts, &chart_notes, &mut marks)?;
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, &x_desc, &y_desc))
}
