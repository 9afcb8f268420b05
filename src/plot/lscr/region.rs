//! The region panel ([`REGION`]) — an LSCR confidence region like Figs. 1–3 of Weyer & Campi, "Prediction,
//! filtering and smoothing using LSCR".
//!
//! The paper marks the points excluded by X̂_1 with × and those excluded by X̂_2 with +, and
//! leaves X̂ = ∩_l X̂_l blank (17); here the excluded areas are hatched, one style per group
//! ("\\" for X̂_1, "/" for X̂_2, then "—", "|", … for n > 2), so where both exclude a point the
//! hatching crosses. The hatching is exact, not sampled: every hatch line is a straight line
//! of the plane, and [`SignRegion::spans`] returns exactly the pieces of it that lie outside
//! each X̂_l (every g_{i,l} is affine, so a line crosses each zero set at most once). X̂ gets a
//! light tint and its outline from [`SignRegion::boundary`] (holes respected). On top: the
//! true state ◇, the BLUE ⋆ with its ellipse at the joint level (Figs. 1, 2), the Kalman
//! estimate and its ellipse dashed (Fig. 3), and, when X̂ is unbounded (Section V-B: F^b
//! singular), the directions along which it extends.
//!
//! For n > 2 the picture is the 2-D slice of X̂ through the report's `slice_at` point (the
//! BLUE by default), and the ellipses are sliced through the same point so that everything
//! drawn lives in the same plane.

use crate::error::{Error, Result};
use crate::plot::erase::de;
use crate::plot::figures::{Area, Request};
use crate::plot::geom::Win;
use crate::plot::style::{
    self, pct, sig, sub, Entry, Marker, Swatch, BLUE_EST, KF, LSCR, LSCR_TINT, TRUTH,
};
use crate::plot::view::{Frame, PanelSpec, Zoom};
use crate::scenario::lscr::Estimate;
use crate::scenario::lscr::{plane_region, LscrReport};
use crate::scenario::Report;
use crate::sets::{BoxSet, Ellipsoid, Loop, SignRegion};
use plotters::prelude::*;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// LSCR paper, Figs. 1–3: the LSCR region with the excluded areas hatched per group, the
/// truth, the BLUE and Kalman ellipses.
pub(crate) static REGION: PanelSpec = PanelSpec::new("region", "LSCR confidence region with the excluded areas hatched, the truth, the BLUE and Kalman ellipses");

/// Points on a drawn ellipse boundary.
const ELLIPSE_POINTS: usize = 160;

/// Hatch spacing in pixels (normal / small figures): dense enough to read as an area, sparse
/// enough that two crossing styles stay distinguishable; it also bounds the work (a few
/// hundred lines, each one sweep over the M·n functions).
const SPACING: (f64, f64) = (7.0, 6.0);

/// Opacity of the tint of X̂ (light: the paper leaves X̂ blank).
const TINT_ALPHA: f64 = 0.22;

/// The report's LSCR part, or an error naming the panel.
pub fn lscr_of(report: &Report) -> Result<&LscrReport> {
    report.lscr.as_ref().ok_or_else(|| {
        Error::field(
            "panel",
            format!(
                "\"region\" draws an LSCR confidence region, but this report (method \"{}\") has none: choose state, series or coverage",
                report.method
            ),
        )
    })
}

/// What the estimate is, for the title and subtitle ("prediction of x₃₁ from y₁ … y₃₀").
pub(super) fn what(l: &LscrReport) -> (String, String) {
    let x = format!("x{}", sub(l.time));
    let ys = format!("y₁ … y{}", sub(l.t));
    let kind = match l.estimate {
        Estimate::Predict => "prediction",
        Estimate::Filter => "filtering",
        Estimate::Smooth => "smoothing",
    };
    (kind.to_string(), format!("{kind} of {x} from {ys}"))
}

/// Level of an ellipsoid {(x − c)ᵀ Σ⁻¹ (x − c) ≤ r²} of a Gaussian in `dim` dimensions.
pub(super) fn ellipse_level(radius2: f64, dim: usize) -> Option<f64> {
    let chi = ChiSquared::new(dim as f64).ok()?;
    let p = chi.cdf(radius2);
    p.is_finite().then_some(p)
}

/// The 2-D ellipse drawn for an n-dimensional one: itself (n = 2, plotted in order), its slice
/// through `at` (n > 2, like the region), or its projection when there is no slice point.
fn planar(e: &Ellipsoid, plot: [usize; 2], at: Option<&[f64]>) -> Result<Option<Ellipsoid>> {
    let finite = e.radius2.is_finite()
        && e.center.iter().all(|v| v.is_finite())
        && e.cov.iter().flatten().all(|v| v.is_finite());
    if !finite || plot.iter().any(|&i| i >= e.dim()) {
        return Err(Error::field(
            "report.lscr",
            "holds an ellipse with non-finite numbers or the wrong dimension: it cannot be drawn",
        ));
    }
    match at {
        Some(p) if e.dim() > 2 => e.slice(&plot, p),
        _ => e.project(&plot).map(Some),
    }
}

/// "[0.71, 0.71]" for each recession direction, one of each ± pair.
fn directions(rec: &[[f64; 2]]) -> Vec<String> {
    let mut kept: Vec<[f64; 2]> = Vec::new();
    for v in rec {
        let opposite = kept
            .iter()
            .any(|k| (k[0] + v[0]).abs() < 1e-6 && (k[1] + v[1]).abs() < 1e-6);
        let same = kept
            .iter()
            .any(|k| (k[0] - v[0]).abs() < 1e-6 && (k[1] - v[1]).abs() < 1e-6);
        if !opposite && !same {
            kept.push(*v);
        }
    }
    kept.iter()
        .map(|v| {
            let both = rec
                .iter()
                .any(|k| (k[0] + v[0]).abs() < 1e-6 && (k[1] + v[1]).abs() < 1e-6);
            format!(
                "{}[{}, {}]",
                if both { "±" } else { "" },
                style::num(v[0], 2),
                style::num(v[1], 2)
            )
        })
        .collect()
}

fn win_of(b: &BoxSet) -> Result<Win> {
    let ok = b.lo.len() == 2
        && b.hi.len() == 2
        && (0..2).all(|k| b.lo[k].is_finite() && b.hi[k].is_finite() && b.lo[k] < b.hi[k]);
    if !ok {
        return Err(Error::field(
            "report.lscr.window",
            "must be a 2-D box with finite lo < hi",
        ));
    }
    Ok(Win::new((b.lo[0], b.hi[0]), (b.lo[1], b.hi[1])))
}

/// The window: the report's (fitted to X̂, the truth and the ellipses, or the scenario's own)
/// for `Zoom::Auto`; tight on X̂ for `Zoom::Regions` (when bounded); the report's grown to every
/// ellipse for `Zoom::Full`.
fn window(l: &LscrReport, zoom: Zoom, ellipses: &[&Ellipsoid]) -> Result<Win> {
    let base = win_of(&l.window)?;
    Ok(match zoom {
        Zoom::Auto => base,
        Zoom::Regions => {
            let mut w = Win::empty();
            for lp in &l.boundary {
                for p in &lp.points {
                    w.add(p[0], p[1]);
                }
            }
            if l.bounded && !w.is_empty() && w.width() > 0.0 && w.height() > 0.0 {
                w.padded(0.06, 0.06)
            } else {
                base
            }
        }
        Zoom::Full => {
            let mut w = base;
            for e in ellipses {
                let b = e.bounding_box();
                w = w.union(&Win::new((b.lo[0], b.hi[0]), (b.lo[1], b.hi[1])));
            }
            w
        }
    })
}

/// Pixel ↔ chart mapping of the plotting area, from the chart's own mapping of two corners
/// (so hatch segments land where plotters puts chart coordinates).
#[derive(Clone, Copy)]
struct Map {
    win: Win,
    /// Pixel positions of (x0, y0) and (x1, y1).
    p0: (f64, f64),
    p1: (f64, f64),
}

impl Map {
    fn new<DB: DrawingBackend>(chart: &style::Chart<DB>) -> Map {
        let win = Win::of_chart(chart);
        let a = style::px(chart, (win.x0, win.y0));
        let b = style::px(chart, (win.x1, win.y1));
        Map {
            win,
            p0: (a.0 as f64, a.1 as f64),
            p1: (b.0 as f64, b.1 as f64),
        }
    }
    /// Chart units per pixel along x and y (y grows upwards in the chart, downwards on screen).
    fn scale(&self) -> (f64, f64) {
        (
            self.win.width() / (self.p1.0 - self.p0.0),
            self.win.height() / (self.p1.1 - self.p0.1),
        )
    }
    fn to_chart(&self, p: (f64, f64)) -> [f64; 2] {
        let (sx, sy) = self.scale();
        [
            self.win.x0 + (p.0 - self.p0.0) * sx,
            self.win.y0 + (p.1 - self.p0.1) * sy,
        ]
    }
    fn to_px(&self, q: [f64; 2]) -> (i32, i32) {
        let (sx, sy) = self.scale();
        (
            (self.p0.0 + (q[0] - self.win.x0) / sx).round() as i32,
            (self.p0.1 + (q[1] - self.win.y0) / sy).round() as i32,
        )
    }
    /// The plotting area as a pixel box (x0 < x1, y0 < y1 on screen).
    fn pixel_box(&self) -> Win {
        Win::new(
            (self.p0.0.min(self.p1.0), self.p0.0.max(self.p1.0)),
            (self.p0.1.min(self.p1.1), self.p0.1.max(self.p1.1)),
        )
    }
}

/// The exact hatching of the areas outside X̂_l for every group l, as pixel segments per group.
///
/// Each hatch line of [`style::hatch_lines`] is mapped to the chart (an affine map, so it stays
/// a line) and split by [`SignRegion::spans`] into the pieces outside each X̂_l; neighbouring
/// pieces outside the same group are merged so every drawn segment is maximal.
pub(crate) fn hatch_segments(
    plane: &SignRegion,
    map_win: Win,
    p0: (f64, f64),
    p1: (f64, f64),
    spacing: f64,
) -> Result<Vec<Vec<((i32, i32), (i32, i32))>>> {
    let map = Map {
        win: map_win,
        p0,
        p1,
    };
    let (sx, sy) = map.scale();
    let bx = map.pixel_box();
    let ng = plane.groups.len();
    let mut out = vec![Vec::new(); ng];
    for (l, segs) in out.iter_mut().enumerate() {
        let bit = 1u32 << l.min(31);
        for (a, b) in style::hatch_lines(&bx, l, spacing) {
            let len = (b.0 - a.0).hypot(b.1 - a.1);
            if !(len > 0.0) {
                continue;
            }
            let d = ((b.0 - a.0) / len, (b.1 - a.1) / len);
            // Chart direction per pixel of the line.
            let dir = [d.0 * sx, d.1 * sy];
            let start = map.to_chart(a);
            let mut open: Option<(f64, f64)> = None;
            let flush = |piece: (f64, f64), segs: &mut Vec<_>| {
                let pa = (a.0 + piece.0 * d.0, a.1 + piece.0 * d.1);
                let pb = (a.0 + piece.1 * d.0, a.1 + piece.1 * d.1);
                let (ia, ib) = (
                    (pa.0.round() as i32, pa.1.round() as i32),
                    (pb.0.round() as i32, pb.1.round() as i32),
                );
                if ia != ib {
                    segs.push((ia, ib));
                }
            };
            for sp in plane.spans(start, dir, 0.0, len)? {
                let outside = sp.excluded & bit != 0;
                open = match (open, outside) {
                    (Some((s0, _)), true) => Some((s0, sp.s1)),
                    (None, true) => Some((sp.s0, sp.s1)),
                    (Some(piece), false) => {
                        flush(piece, segs);
                        None
                    }
                    (None, false) => None,
                };
            }
            if let Some(piece) = open {
                flush(piece, segs);
            }
        }
    }
    Ok(out)
}

/// The pieces of the boundary loops that are not on the window's edges (where the window, not
/// the region, cuts the loop), as chart polylines.
fn outline(loops: &[Loop], w: &Win) -> Vec<Vec<(f64, f64)>> {
    let eps = 1e-7 * w.width().max(w.height());
    let on_edge = |a: &[f64; 2], b: &[f64; 2]| {
        ((a[0] - w.x0).abs() < eps && (b[0] - w.x0).abs() < eps)
            || ((a[0] - w.x1).abs() < eps && (b[0] - w.x1).abs() < eps)
            || ((a[1] - w.y0).abs() < eps && (b[1] - w.y0).abs() < eps)
            || ((a[1] - w.y1).abs() < eps && (b[1] - w.y1).abs() < eps)
    };
    let mut out = Vec::new();
    for lp in loops {
        let n = lp.points.len();
        if n < 2 {
            continue;
        }
        // Start right after an edge segment, if any, so pieces are not split at index 0.
        let first = (0..n)
            .find(|&k| on_edge(&lp.points[k], &lp.points[(k + 1) % n]))
            .map_or(0, |k| (k + 1) % n);
        let mut cur: Vec<(f64, f64)> = Vec::new();
        for step in 0..n {
            let k = (first + step) % n;
            let (a, b) = (lp.points[k], lp.points[(k + 1) % n]);
            if on_edge(&a, &b) {
                if cur.len() > 1 {
                    out.push(std::mem::take(&mut cur));
                }
                cur.clear();
            } else {
                if cur.is_empty() {
                    cur.push((a[0], a[1]));
                }
                cur.push((b[0], b[1]));
            }
        }
        if cur.len() > 1 {
            out.push(cur);
        }
    }
    out
}

/// Arrows at the window's edge showing that X̂ goes on along each recession direction
/// (Section V-B: x ∈ X̂ ⇒ x + c·[1, 1]ᵀ ∈ X̂), from the centre of the visible region; returns
/// their pixels (to keep the legend off them).
fn unbounded_arrows<DB: DrawingBackend>(
    root: &Area<DB>,
    map: &Map,
    loops: &[Loop],
    rec: &[[f64; 2]],
) -> Result<Vec<(i32, i32)>> {
    let mut marks = Vec::new();
    // Area-weighted centroid of the visible region (holes count negative).
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for lp in loops {
        let n = lp.points.len();
        for k in 0..n {
            let (p, q) = (lp.points[k], lp.points[(k + 1) % n]);
            let cr = p[0] * q[1] - q[0] * p[1];
            a += cr;
            cx += (p[0] + q[0]) * cr;
            cy += (p[1] + q[1]) * cr;
        }
    }
    if !(a.abs() > 0.0) {
        return Ok(marks);
    }
    let c = map.to_px([cx / (3.0 * a), cy / (3.0 * a)]);
    let c = (c.0 as f64, c.1 as f64);
    let (sx, sy) = map.scale();
    let bx = map.pixel_box();
    for v in rec {
        let d = (v[0] / sx, v[1] / sy);
        let len = d.0.hypot(d.1);
        if !(len > 0.0) {
            continue;
        }
        let d = (d.0 / len, d.1 / len);
        // Distance from the centre to the box edge along d, less a margin.
        let mut t = f64::INFINITY;
        for (dc, lo, hi, pc) in [(d.0, bx.x0, bx.x1, c.0), (d.1, bx.y0, bx.y1, c.1)] {
            if dc > 0.0 {
                t = t.min((hi - pc) / dc);
            } else if dc < 0.0 {
                t = t.min((lo - pc) / dc);
            }
        }
        let t = t - 10.0;
        if !(t > 50.0 && t.is_finite()) {
            continue;
        }
        let tip = (c.0 + t * d.0, c.1 + t * d.1);
        let tail = (tip.0 - 36.0 * d.0, tip.1 - 36.0 * d.1);
        let r = |p: (f64, f64)| (p.0.round() as i32, p.1.round() as i32);
        let wing = |ang: f64| {
            let (s, co) = ang.sin_cos();
            let w = (d.0 * co - d.1 * s, d.0 * s + d.1 * co);
            r((tip.0 - 11.0 * w.0, tip.1 - 11.0 * w.1))
        };
        style::polyline(root, &[r(tail), r(tip)], &LSCR, 2, None)?;
        style::polyline(root, &[wing(0.45), r(tip), wing(-0.45)], &LSCR, 2, None)?;
        marks.extend([r(tail), r(tip)]);
    }
    Ok(marks)
}

/// Draw the region panel.
pub fn draw<DB: DrawingBackend>(root: &Area<DB>, request: &Request) -> Result<Frame> {
    let (report, view, fonts) = (request.report, request.view, request.fonts);
    let l = lscr_of(report)?;
    l.region.validate("report.lscr.region")?;
    if l.region.dim == 1 {
        // A scalar state: intervals on one axis.
        return super::line::draw(root, request);
    }
    if l.plot[0] >= l.region.dim || l.plot[1] >= l.region.dim || l.plot[0] == l.plot[1] {
        return Err(Error::field(
            "report.lscr.plot",
            format!(
                "must name two distinct components below n = {}",
                l.region.dim
            ),
        ));
    }
    let n = l.region.dim;
    let plot = l.plot;
    let at = l.slice_at.as_deref();
    let plane = plane_region(&l.region, plot, at)?;
    let ng = plane.groups.len();

    // Ellipses in the plane (sliced like the region for n > 2).
    let blue = match &l.blue {
        Some(e) => planar(e, plot, at)?,
        None => None,
    };
    let kf = match &l.kf {
        Some(e) => planar(e, plot, at)?,
        None => None,
    };
    let shown: Vec<&Ellipsoid> = blue.iter().chain(kf.iter()).collect();
    let win = window(l, view.zoom, &shown)?;

    // Texts.
    let tau = l.time;
    let (kind, what) = what(l);
    let xt = format!("x{}", sub(tau));
    let axis = |k: usize| {
        let comp = plot[k] + 1;
        let sym = format!("{xt},{}", sub(comp));
        match report.figure.names.get(plot[k]) {
            Some(name) if !name.is_empty() => format!("{sym}: {name}"),
            _ => format!("{sym}  (component {comp} of {xt})"),
        }
    };
    let (x_desc, y_desc) = (axis(0), axis(1));
    let title = match &report.figure.title {
        Some(t) if t.to_lowercase().contains(&kind) => t.clone(),
        Some(t) => format!("{t}: {kind}"),
        None => format!("LSCR {}", what),
    };
    let mut notes: Vec<String> = vec![format!("LSCR {what}")];
    if l.guaranteed {
        notes.push(format!(
            "M = {}, q = {}: each X̂ₗ holds {xt} w.p. ≥ {}, X̂ = ∩ X̂ₗ w.p. ≥ {} (Theorem 3.2)",
            l.m,
            l.q,
            pct(l.level_each),
            pct(l.level)
        ));
    } else {
        notes.push(format!(
            "M = {}, q = {}: explicit strings, no probability guarantee (Theorem 3.2 needs random or group strings)",
            l.m, l.q
        ));
    }
    let unbounded = directions(&l.recession);
    let unbounded_note = (!l.bounded).then(|| {
        let d = if unbounded.is_empty() {
            "some direction".to_string()
        } else {
            unbounded.join(" and ")
        };
        format!("X̂ is unbounded along {d}")
    });
    if let Some(u) = &unbounded_note {
        notes.push(u.clone());
    }
    if let Some(p) = at {
        let fixed: Vec<String> = (0..n)
            .filter(|i| !plot.contains(i))
            .map(|i| format!("x{} = {}", sub(i + 1), sig(p[i])))
            .collect();
        notes.push(format!(
            "n = {n}: slice of X̂ and of the ellipses through {}",
            fixed.join(", ")
        ));
    }
    if let Some(inside) = l.truth_inside {
        let each: Vec<String> = l
            .truth_inside_each
            .iter()
            .flatten()
            .enumerate()
            .map(|(k, &b)| format!("X̂{} {}", sub(k + 1), if b { "yes" } else { "no" }))
            .collect();
        notes.push(format!(
            "true {xt} in X̂: {} ({})",
            if inside { "yes" } else { "no" },
            each.join(", ")
        ));
    }
    if l.blue.is_none() {
        if let Some(why) = &l.blue_note {
            notes.push(format!("no BLUE: {why}"));
        }
    }

    // Legend: short labels and no estimate markers on small figures, where the legend is
    // drawn over the chart and must leave room for it.
    let short = fonts.compact;
    let sliced = if at.is_some() { " (slice)" } else { "" };
    let mut entries = vec![Entry::new(
        if short {
            format!("X̂ {}", pct(l.level))
        } else {
            format!("X̂ (LSCR, {})", pct(l.level))
        },
        Swatch::Tinted {
            line: LSCR,
            tint: LSCR_TINT.mix(TINT_ALPHA),
        },
    )];
    for g in 0..ng {
        entries.push(Entry::new(
            if short {
                format!("not in X̂{}", sub(g + 1))
            } else {
                format!("excluded by X̂{} ({})", sub(g + 1), pct(l.level_each))
            },
            Swatch::Hatch {
                color: style::hatch_color(g),
                group: g,
            },
        ));
    }
    let truth = l
        .x_true
        .as_ref()
        .filter(|x| x.len() == n)
        .map(|x| (x[plot[0]], x[plot[1]]));
    if truth.is_some() {
        entries.push(Entry::new(
            match (short, at.is_some()) {
                (true, _) => format!("true {xt}"),
                // n > 2: the truth is projected; its other components need not be the slice's.
                (false, true) => format!("true state {xt} (projected)"),
                (false, false) => format!("true state {xt}"),
            },
            Swatch::Marker {
                shape: Marker::Diamond,
                color: TRUTH,
                size: 5,
            },
        ));
    }
    let level_of = |e: &Option<Ellipsoid>, orig: &Option<Ellipsoid>| {
        orig.as_ref()
            .zip(e.as_ref())
            .and_then(|(o, _)| ellipse_level(o.radius2, o.dim()))
    };
    // Each estimate the report holds: its point (a minor entry), then its ellipse. The Kalman
    // one is x̂_{t+1|t} (prediction) or x̂_{t|t} (filtering): τ given t.
    let estimates = [
        (
            &blue,
            &l.blue,
            "BLUE estimate".to_string(),
            Marker::Star,
            BLUE_EST,
            "BLUE",
            false,
        ),
        (
            &kf,
            &l.kf,
            format!("Kalman estimate x̂{}|{}", sub(tau), sub(l.t)),
            Marker::Cross,
            KF,
            "KF",
            true,
        ),
    ];
    for (e, orig, point, shape, color, name, dashed) in estimates {
        if e.is_none() {
            continue;
        }
        entries.push(
            Entry::new(
                point,
                Swatch::Marker {
                    shape,
                    color,
                    size: 5,
                },
            )
            .minor(),
        );
        let lv = level_of(e, orig).map(pct).unwrap_or_default();
        entries.push(Entry::new(
            if short {
                format!("{name} {lv}")
            } else {
                format!("{name} ellipse {lv}{sliced}")
            },
            Swatch::Region {
                color,
                dashed,
                fill: false,
            },
        ));
    }

    let (area, side) = style::titled_legend(root, &fonts, &title, &notes, &entries)?;
    let chart = style::equal_chart(&area, &fonts, win, &x_desc, &y_desc)?;
    let map = Map::new(&chart);
    let cw = map.win;
    // The boundary inside the chart's window (it may have grown for equal aspect): exact.
    let loops = plane.boundary(&BoxSet {
        lo: vec![cw.x0, cw.y0],
        hi: vec![cw.x1, cw.y1],
    })?;
    let (bx, by) = root.get_base_pixel();

    // 1. The light tint of X̂: all loops in one polygon joined through the first point (the
    //    joins are walked both ways, so they add no area); holes run clockwise and cancel
    //    under both the nonzero and the even-odd rule.
    let mut tint: Vec<(i32, i32)> = Vec::new();
    for lp in &loops {
        if lp.points.len() < 3 {
            continue;
        }
        let anchor = tint.first().copied();
        for p in lp.points.iter().chain(lp.points.first()) {
            let q = map.to_px(*p);
            tint.push((q.0 - bx, q.1 - by));
        }
        if let Some(a) = anchor {
            tint.push(a);
        }
    }
    if tint.len() >= 3 {
        root.draw(&Polygon::new(tint, LSCR_TINT.mix(TINT_ALPHA).filled()))
            .map_err(de)?;
    }

    // 2. Exact hatching of the areas outside each X̂_l.
    let spacing = if fonts.compact { SPACING.1 } else { SPACING.0 };
    let hatches = hatch_segments(&plane, cw, map.p0, map.p1, spacing)?;
    for (g, segs) in hatches.iter().enumerate() {
        let color = style::hatch_color(g);
        let st = color.stroke_width(1);
        for &(a, b) in segs {
            root.draw(&PathElement::new(
                vec![(a.0 - bx, a.1 - by), (b.0 - bx, b.1 - by)],
                st,
            ))
            .map_err(de)?;
        }
    }

    // 3. The outline of X̂ (not where the window cuts it).
    let mut marks: Vec<(i32, i32)> = Vec::new();
    for piece in outline(&loops, &cw) {
        style::path(root, &chart, &piece, &LSCR, 2, None)?;
        marks.extend(style::marks_of(&chart, &piece));
    }

    // 4. Ellipses and estimates.
    if let Some(e) = &kf {
        let pts = e.boundary_2d(ELLIPSE_POINTS)?;
        style::region(root, &chart, &pts, &KF, true, false)?;
        marks.extend(style::marks_of(&chart, &pts));
    }
    if let Some(e) = &blue {
        let pts = e.boundary_2d(ELLIPSE_POINTS)?;
        style::region(root, &chart, &pts, &BLUE_EST, false, false)?;
        marks.extend(style::marks_of(&chart, &pts));
    }
    let mut outside: Vec<String> = Vec::new();
    let mut point = |c: (f64, f64), shape: Marker, color: &RGBColor, what: &str| -> Result<()> {
        if cw.contains(c.0, c.1) {
            let p = style::px(&chart, c);
            marks.push(p);
            style::marker(root, p, shape, color, 5)
        } else {
            outside.push(what.to_string());
            Ok(())
        }
    };
    // The hollow ◇ first, so an estimate on the true state stays visible.
    if let Some(t) = truth {
        point(t, Marker::Diamond, &TRUTH, "true state")?;
    }
    if let Some(e) = &kf {
        point(
            (e.center[0], e.center[1]),
            Marker::Cross,
            &KF,
            "Kalman estimate",
        )?;
    }
    if let Some(e) = &blue {
        point((e.center[0], e.center[1]), Marker::Star, &BLUE_EST, "BLUE")?;
    }

    // 5. On-chart notes: unbounded directions, markers outside the window.
    let mut chart_notes: Vec<String> = Vec::new();
    if let Some(u) = &unbounded_note {
        chart_notes.push(if fonts.compact {
            u.replace(" is unbounded", " unbounded")
        } else {
            u.clone()
        });
        marks.extend(unbounded_arrows(root, &map, &loops, &l.recession)?);
    }
    // A group whose excluded area lies wholly outside the window (its legend swatch would
    // otherwise promise hatching that is not there).
    let empty: Vec<String> = hatches
        .iter()
        .enumerate()
        .filter(|(_, s)| s.is_empty())
        .map(|(g, _)| format!("X̂{}", sub(g + 1)))
        .collect();
    if !empty.is_empty() && ng > 0 && !fonts.compact {
        chart_notes.push(format!(
            "{} {} nothing in this window",
            empty.join(", "),
            if empty.len() == 1 {
                "excludes"
            } else {
                "exclude"
            }
        ));
    }
    if !outside.is_empty() {
        chart_notes.push(format!("outside the window: {}", outside.join(", ")));
    }
    style::note_box(root, &chart, &fonts, &chart_notes, &mut marks, &LSCR, &LSCR)?;
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, &x_desc, &y_desc))
}
