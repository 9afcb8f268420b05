//! The set-membership panel [`"ubbset"`](SET_PANEL) (Tempo, method `"ubb"`), with what both
//! ubb panels share (their names, the check of the report's ubb part, the colours): the exact
//! feasible set of x(k+1) at the report's step k in the `plane` components — a
//! polygon from support LPs — with its interval hull dashed, the central estimate ⋆ (the
//! hull's midpoint), Theorem 2's linear optimal estimate ○ with its error box φ ± E(φ₀) (22)
//! dashed (l∞ bounds, the detail's step only), the true state ◇ and the Kalman ellipse dashed) and [`"ubbwidth"`](WIDTH_PANEL)
//! (`width.rs`: the hull's widths over k with the Theorem 4 bound, and the truth inside
//! its hull bands).
//!
//! Step k's set is the set of x(k+1) consistent with y(0 … k) (the paper's prediction set), or
//! with `ubb.set` "filtered" the set of x(k) ([`Chosen`]: what every panel reads from the
//! report); equal scales on both axes of the set panel. With one state (r = 1) the set is an
//! interval and the panel draws it over the steps as a band (`band.rs`).

use crate::error::{Error, Result};
use crate::plot::figures::{Area, Request};
use crate::plot::geom::Win;
use crate::plot::style::{self, num, percent, sig, sub, Entry, Marker, Swatch, KF, TRUTH};
use crate::plot::view::PanelSpec;
use crate::plot::view::{Frame, Panel};
use crate::scenario::ubb::{SetChoice, TrackStep};
use crate::scenario::{Report, UbbReport};
use crate::sets::{Ellipsoid, SupportPolygon};
use crate::ubb::{LinearEstimate, Norm};
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

/// One step's hull of the set the figures draw.
pub(crate) struct HullRef<'a> {
    pub lo: &'a [f64],
    pub hi: &'a [f64],
    pub center: &'a [f64],
    pub radius: f64,
    pub kf_mean: &'a [f64],
    pub inside: Option<bool>,
}

/// The detail step's exact set of the set the figures draw.
pub(crate) struct DetailRef<'a> {
    pub polygon: &'a SupportPolygon,
    pub lo: &'a [f64],
    pub hi: &'a [f64],
    pub center: &'a [f64],
    pub radius: f64,
    pub truth: Option<&'a [f64]>,
    pub kf: &'a Ellipsoid,
    pub linear: Option<&'a [LinearEstimate]>,
}

/// The set the figures draw (`ubb.set`, the report's `set`): the predicted X(k+1 | y(0 … k))
/// from the track's and the detail's own fields, or the filtered X(k | y(0 … k)) from their
/// `filtered` parts; `lag` is the state's time after k (1 or 0).
pub(crate) struct Chosen<'a> {
    pub u: &'a UbbReport,
    pub filtered: bool,
}

impl<'a> Chosen<'a> {
    pub fn of(u: &'a UbbReport) -> Chosen<'a> {
        Chosen {
            u,
            filtered: u.set == SetChoice::Filtered,
        }
    }
    /// The time of the state after step k: x(k+1) predicted, x(k) filtered.
    pub fn lag(&self) -> usize {
        usize::from(!self.filtered)
    }
    /// "x(41)" for step k = 40 (predicted) or "x(40)" (filtered).
    pub fn state_at(&self, k: usize) -> String {
        format!("x({})", k + self.lag())
    }
    /// "x(k+1)" or "x(k)".
    pub fn state_symbol(&self) -> &'static str {
        if self.filtered {
            "x(k)"
        } else {
            "x(k+1)"
        }
    }
    /// "the predicted set" or "the filtered set".
    pub fn name(&self) -> &'static str {
        if self.filtered {
            "filtered set"
        } else {
            "predicted set"
        }
    }
    pub fn hull(&self, t: &'a TrackStep) -> Option<HullRef<'a>> {
        if self.filtered {
            t.filtered.as_ref().map(|f| HullRef {
                lo: &f.lo,
                hi: &f.hi,
                center: &f.center,
                radius: f.radius,
                kf_mean: &f.kf_mean,
                inside: f.inside,
            })
        } else {
            Some(HullRef {
                lo: &t.lo,
                hi: &t.hi,
                center: &t.center,
                radius: t.radius,
                kf_mean: &t.kf_mean,
                inside: t.inside,
            })
        }
    }
    /// The steps of the track with a set to draw, with their hulls.
    pub fn steps(&self) -> Vec<(usize, HullRef<'a>)> {
        self.u
            .track
            .iter()
            .filter_map(|t| self.hull(t).map(|h| (t.k, h)))
            .collect()
    }
    pub fn detail(&self) -> Option<DetailRef<'a>> {
        let at = &self.u.at;
        if self.filtered {
            at.filtered.as_ref().map(|f| DetailRef {
                polygon: &f.polygon,
                lo: &f.lo,
                hi: &f.hi,
                center: &f.center,
                radius: f.radius,
                truth: f.truth.as_deref(),
                kf: &f.kf,
                linear: f.linear.as_deref(),
            })
        } else {
            Some(DetailRef {
                polygon: &at.polygon,
                lo: &at.lo,
                hi: &at.hi,
                center: &at.center,
                radius: at.radius,
                truth: at.truth.as_deref(),
                kf: &at.kf,
                linear: at.linear.as_deref(),
            })
        }
    }
    /// The true state of step k's set (x(k+1) or x(k)), when simulated.
    pub fn truth(&self, k: usize) -> Option<&'a [f64]> {
        self.u
            .x_true
            .as_ref()
            .and_then(|x| x.get(k + self.lag()))
            .map(|x| x.as_slice())
    }
}

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
    let plane_ok = if r == 1 {
        u.plane == [0, 0]
    } else {
        r >= 2 && u.plane[0] < r && u.plane[1] < r && u.plane[0] != u.plane[1]
    };
    if !plane_ok {
        return bad("must name two distinct plane components below r (with one state, [0, 0])");
    }
    if u.track.is_empty() {
        return bad("has no step with a bounded set to draw");
    }
    let ok = |lo: &[f64], hi: &[f64]| lo.len() == r && hi.len() == r && finite(lo) && finite(hi);
    let point = |v: &[f64]| v.len() == r && finite(v);
    if !u.track.iter().all(|t| {
        ok(&t.lo, &t.hi)
            && point(&t.center)
            && point(&t.kf_mean)
            && t.radius.is_finite()
            && t.filtered.as_ref().is_none_or(|f| {
                ok(&f.lo, &f.hi) && point(&f.center) && point(&f.kf_mean) && f.radius.is_finite()
            })
    }) {
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
    if at.kf.dim() != r.min(2) {
        return Err(Error::field(
            "report.ubb.at.kf",
            "must be the Kalman ellipse in the plane (2-D; with one state, its interval)",
        ));
    }
    if let Some(f) = &at.filtered {
        let polygon_ok = f.polygon.vertices.iter().all(|p| finite(p)) && finite(&f.polygon.hull);
        if !ok(&f.lo, &f.hi)
            || !point(&f.center)
            || !polygon_ok
            || f.kf.dim() != r.min(2)
            || f.truth.as_ref().is_some_and(|t| t.len() != 2 || !finite(t))
        {
            return Err(Error::field(
                "report.ubb.at.filtered",
                "must hold the filtered set's polygon, hull, centre, truth and Kalman ellipse of x(k) (finite, of the state's dimension)",
            ));
        }
    }
    if u.set == SetChoice::Filtered && !u.track.iter().any(|t| t.filtered.is_some()) {
        return bad("draws the filtered sets (set \"filtered\"), but no step of its track has a bounded one");
    }
    Ok(u)
}

/// The level of a 2-D ellipse of radius² `r2` (χ²₂: 1 − e^{−r²/2}).
pub fn level_2d(r2: f64) -> f64 {
    1.0 - (-0.5 * r2).exp()
}

/// The "ubbset" panel (with one state: the band of intervals over the steps, `band.rs`).
pub fn draw_set<DB: DrawingBackend>(root: &Area<DB>, request: &Request) -> Result<Frame> {
    let (report, view, fonts) = (request.report, request.view, request.fonts);
    let u = check(report, Panel::of(&SET_PANEL))?;
    if u.r == 1 {
        return super::band::draw(root, request);
    }
    let chosen = Chosen::of(u);
    let at = &u.at;
    // The step shown: the view's, else the report's. Its exact polygon, Kalman ellipse and LP
    // come with the report's `at` only; another step of the track is drawn from what the
    // report holds for every step (hull, centre, truth, Kalman mean) until its detail is set
    // (`Report::set_at`). A detail of one step is never drawn at another.
    let k = view.time.unwrap_or(at.k);
    let detail_ref = chosen.detail();
    let detail = k == at.k && detail_ref.is_some();
    let step = u.track.iter().find(|t| t.k == k);
    let step_hull = step.and_then(|t| chosen.hull(t));
    if step_hull.is_none() && !detail {
        let held: Vec<usize> = chosen.steps().iter().map(|(k, _)| *k).collect();
        return Err(Error::field(
            "time",
            match (held.first(), held.last()) {
                (Some(a), Some(b)) => format!(
                    "k = {k} has no bounded {} in this report (its track holds k = {a} … {b})",
                    chosen.name()
                ),
                _ => format!("k = {k} has no bounded {} in this report", chosen.name()),
            },
        ));
    }
    let [i, j] = u.plane;
    let short = fonts.compact;
    let poly: Vec<(f64, f64)> = match (&detail_ref, detail) {
        (Some(d), true) => d.polygon.vertices.iter().map(|p| (p[0], p[1])).collect(),
        _ => Vec::new(),
    };
    // The hull, centre and radius: the detail's (from its own LPs) or the track's.
    let (s_lo, s_hi, s_center, radius) = match (&step_hull, &detail_ref) {
        (Some(h), _) if !detail => (h.lo, h.hi, h.center, h.radius),
        (_, Some(d)) => (d.lo, d.hi, d.center, d.radius),
        (Some(h), None) => (h.lo, h.hi, h.center, h.radius),
        (None, None) => return Err(Error::field("time", format!("k = {k} has no set to draw"))),
    };
    let (lo, hi) = ((s_lo[i], s_lo[j]), (s_hi[i], s_hi[j]));
    let hull = [(lo.0, lo.1), (hi.0, lo.1), (hi.0, hi.1), (lo.0, hi.1)];
    let center = (s_center[i], s_center[j]);
    let truth = match (&detail_ref, detail) {
        (Some(d), true) => d.truth.map(|t| (t[0], t[1])),
        _ => chosen.truth(k).map(|x| (x[i], x[j])),
    };
    let ellipse = match (&detail_ref, detail) {
        (Some(d), true) => d.kf.boundary_2d(ELLIPSE_POINTS)?,
        _ => Vec::new(),
    };
    // Theorem 2's linear optimal estimate φ of the plane components with its error box φ ± E
    // (22): the detail's only (one LP per component; not in the track).
    let linear = match (&detail_ref, detail) {
        (Some(d), true) => d.linear.and_then(|l| {
            let c = |comp: usize| l.iter().find(|e| e.component == comp);
            let (a, b) = (c(i)?, c(j)?);
            let ok = [a.estimate, a.error, b.estimate, b.error]
                .iter()
                .all(|v| v.is_finite());
            ok.then_some(((a.estimate, b.estimate), (a.error, b.error)))
        }),
        _ => None,
    };
    let linear_box = linear.map(|((x, y), (ex, ey))| {
        [
            (x - ex, y - ey),
            (x + ex, y - ey),
            (x + ex, y + ey),
            (x - ex, y + ey),
        ]
    });
    let kf_center = match (&step_hull, &detail_ref) {
        (Some(h), _) if !detail => (h.kf_mean[i], h.kf_mean[j]),
        (_, Some(d)) => (d.kf.center[0], d.kf.center[1]),
        (Some(h), None) => (h.kf_mean[i], h.kf_mean[j]),
        (None, None) => return Err(Error::field("time", format!("k = {k} has no set to draw"))),
    };
    // The level is the same at every step (`ubb.kf_level`).
    let kf_level = percent(level_2d(at.kf.radius2));
    let (first, polygon, size) = (at.first, detail_ref.as_ref().map(|d| d.polygon), &at.size);

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
    let lag = if chosen.filtered { "k" } else { "k+1" };
    let comp = |c: usize| match u.state_names.get(c) {
        Some(name) if coefficients => name.clone(),
        _ => format!("x{}({lag})", sub(c + 1)),
    };
    let target = if coefficients {
        "the coefficients a".to_string()
    } else {
        chosen.state_at(k)
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
        format!("{target} consistent with y({first}) … y({k}) and the {norm} noise bounds")
    } else {
        format!("{target} consistent with the data up to y({k}) and the {norm} noise bounds")
    }];
    if chosen.filtered {
        notes.push(format!(
            "the filtered set X(k | y(0 … k)); the predicted X(k+1 | …) is it mapped by A plus the noise"
        ));
    }
    match (detail, polygon) {
        (true, Some(polygon)) => {
            notes.push(format!(
                "polygon: {} vertices from {} LPs{}",
                poly.len(),
                polygon.calls,
                if polygon.exact {
                    " (exact)".to_string()
                } else {
                    format!(", within {} of the set", sig(polygon.gap))
                }
            ));
            notes.push(format!(
                "LP: {} variables, {} rows{}",
                size.variables,
                size.rows,
                if size.cones > 0 {
                    format!(", {} cones", size.cones)
                } else {
                    String::new()
                }
            ));
        }
        _ => notes.push(format!(
            "k = {k}: polygon and Kalman ellipse not in this report (it holds k = {})",
            at.k
        )),
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
                format!("true state {}", chosen.state_at(k))
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
        match (short, chosen.filtered) {
            (true, false) => "feasible set".to_string(),
            (true, true) => "filtered set".to_string(),
            (false, false) => format!("feasible set ({norm} bounds)"),
            (false, true) => format!("filtered feasible set ({norm} bounds)"),
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
    let kf_what = if chosen.filtered { " of x(k|k)" } else { "" };
    entries.push(Entry::new(
        if short {
            format!("Kalman {kf_level} (× mean)")
        } else {
            format!("Kalman {kf_level} ellipse{kf_what} (× its mean)")
        },
        Swatch::Region {
            color: KF,
            dashed: true,
            fill: false,
        },
    ));
    let at_k =
        style::RecordTimes::of(&report.figure, crate::scenario::TimeIndex::ZeroBased).at("k", k);
    let what = if chosen.filtered {
        format!("Filtered set at {at_k}: {target}, {norm} bounds")
    } else {
        format!("Feasible set at {at_k}: {target}, {norm} bounds")
    };
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
        (
            kf_center,
            Marker::Cross,
            KF,
            if chosen.filtered {
                "KF estimate"
            } else {
                "KF prediction"
            },
        ),
        (center, Marker::Star, SET, "central estimate"),
    ];
    points.extend(linear.map(|(p, _)| (p, Marker::Ring, SECOND, "linear optimal estimate")));
    points.extend(truth.map(|p| (p, Marker::Diamond, TRUTH, "true state")));
    let outside = style::markers_inside(root, &chart, &points, &mut marks)?;

    let mut chart_notes = Vec::new();
    let inside = step_hull.as_ref().and_then(|t| t.inside);
    match inside {
        Some(true) => chart_notes.push("truth inside the set (guaranteed)".to_string()),
        Some(false) => chart_notes.push("truth OUTSIDE the set (solver tolerance?)".to_string()),
        None => {}
    }
    if let (true, Some(polygon)) = (detail, polygon) {
        if !polygon.exact {
            chart_notes.push(format!(
                "polygon within gap {} of the set",
                sig(polygon.gap)
            ));
        }
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
