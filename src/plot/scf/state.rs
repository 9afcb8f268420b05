//! The "state" panel — the regions at the shown time.
//!
//! Two plotted components: the state plane (trajectory, measurements, true state, KF region
//! dashed, SCF region solid), or the τ-step / subset regions of the report's target, or both
//! bodies' predicted regions of a collision check. One plotted component: the state over time
//! with interval bands and the shown time's intervals as error bars.

use super::context::Ctx;
use crate::error::{Error, Result};
use crate::plot::figures::Area;
use crate::plot::geom::{clip_polyline, Win};
use crate::plot::style::{
    self, pct, sig, sub, Axes, Entry, Marker, Swatch, FRAME, KF, MEASURE, SCF, TRUTH,
};
use crate::plot::view::PanelSpec;
use crate::plot::view::{Frame, Zoom};
use crate::sets::Ellipsoid;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

/// State plane (two plotted components; for n = 1 the state over time): trajectory,
/// measurements, true state, KF ellipse (dashed), SCF ellipse (solid) at the chosen time.
pub(crate) static STATE: PanelSpec = PanelSpec::new(
    "state",
    "state plane at the shown time: trajectory, true state, Kalman and SCF regions",
);

/// Points on a drawn ellipse boundary.
const BOUNDARY: usize = 160;

pub fn draw<DB: DrawingBackend>(root: &Area<DB>, cx: &Ctx) -> Result<Frame> {
    match cx.report.plot.as_slice() {
        [i, j] => plane(root, cx, *i, *j),
        [k] => over_time(root, cx, *k),
        _ => Err(Error::field(
            "plot",
            "must name one or two state components",
        )),
    }
}

/// A body (or the plotted pair) drawn in the plane.
struct Body {
    tag: Option<&'static str>,
    idx: [usize; 2],
    kf: Option<Vec<(f64, f64)>>,
    scf: Option<Vec<(f64, f64)>>,
}

fn boundary(e: &Ellipsoid) -> Result<Vec<(f64, f64)>> {
    let finite = e.radius2.is_finite()
        && e.center.iter().all(|v| v.is_finite())
        && e.cov.iter().flatten().all(|v| v.is_finite());
    if !finite {
        return Err(Error::field(
            "report",
            "holds a region with non-finite numbers: it cannot be drawn",
        ));
    }
    e.boundary_2d(BOUNDARY)
}

/// What the plane shows at the shown time: the bodies' regions, their name ("X₁₀", "Z₄₀|₃₆"),
/// the notes, the collision verdict and the time the regions are for.
struct Shown {
    bodies: Vec<Body>,
    region_name: String,
    notes: Vec<String>,
    verdict: Option<String>,
    /// t, or t + τ for a prediction.
    pred: usize,
}

/// The name of a region `z` for time `pred` from data up to `t` ("Z₄₀|₃₆", or "Z₃₆" when they
/// are the same); a prediction (`pred` > t) says so in `notes`, naming `of` what.
fn predicted(z: &str, of: &str, pred: usize, t: usize, notes: &mut Vec<String>) -> String {
    if pred == t {
        return format!("{z}{}", sub(t));
    }
    notes.push(format!(
        "{}-step prediction{of} for t = {pred} from y₁ … y{}",
        pred - t,
        sub(t)
    ));
    format!("{z}{}|{}", sub(pred), sub(t))
}

/// The body drawn at `idx` from the KF and SCF regions projected on their components `pp`.
fn projected(
    kf: &Ellipsoid,
    scf: Option<&Ellipsoid>,
    pp: [usize; 2],
    idx: [usize; 2],
) -> Result<Body> {
    let kf = boundary(&kf.project(&pp)?)?;
    let scf = match scf {
        Some(e) => Some(boundary(&e.project(&pp)?)?),
        None => None,
    };
    Ok(Body {
        tag: None,
        idx,
        kf: Some(kf),
        scf,
    })
}

/// Regions of `dim` > 2 dimensions are drawn projected on the plane: say so in `notes`.
fn projection_note(dim: usize, notes: &mut Vec<String>) {
    if dim > 2 {
        notes.push(format!("{dim}-dimensional regions projected on the plane"));
    }
}

/// Which regions the plane of components i, j shows: both collision bodies (the check's
/// predicted regions), the target (ζ at t + τ, projected), or X_t projected.
fn shown(cx: &Ctx, i: usize, j: usize) -> Result<Shown> {
    let r = cx.report;
    let t = cx.t;
    let step = cx.step();
    let collision = r
        .collision
        .as_ref()
        .and_then(|cs| cs.iter().find(|c| c.time == t));
    let spec = cx.figure().collision.as_ref();
    let target = step.target.as_ref();
    let pred = target.map_or(t, |g| g.time);
    let mut bodies: Vec<Body> = Vec::new();
    let mut notes: Vec<String> = vec![cx.record().at("t", t)];
    let region_name;
    let mut verdict: Option<String> = None;
    let plane_is_a = match spec {
        Some(s) => s.a.as_slice() == [i, j],
        None => target.is_some_and(|g| g.components.as_slice() == [i, j]),
    };
    if let (Some(c), true) = (collision, plane_is_a) {
        let b_idx = spec.and_then(|s| (s.b.len() == 2).then(|| [s.b[0], s.b[1]]));
        for (k, tag) in ["A", "B"].iter().enumerate() {
            let idx = if k == 0 {
                [i, j]
            } else {
                b_idx.unwrap_or([usize::MAX, usize::MAX])
            };
            let kf = match c.kf_regions.get(k) {
                Some(e) if e.dim() == 2 => Some(boundary(e)?),
                _ => None,
            };
            let scf = match c.scf_regions.get(k) {
                Some(e) if e.dim() == 2 && c.scf_regions.len() == 2 => Some(boundary(e)?),
                _ => None,
            };
            bodies.push(Body {
                tag: Some(tag),
                idx,
                kf,
                scf,
            });
        }
        region_name = predicted("Z", " of both positions", pred, t, &mut notes);
        let d_min = spec
            .map(|s| format!(" (d_min = {})", sig(s.d_min)))
            .unwrap_or_default();
        let kf_v = if c.kf_warning { "YES" } else { "no" };
        let scf_v = match c.scf_warning {
            Some(true) => "YES".to_string(),
            Some(false) => "no".to_string(),
            None => "no region yet".to_string(),
        };
        let dist = |d: f64| {
            if d > 0.0 {
                sig(d)
            } else {
                "0 (overlap)".to_string()
            }
        };
        let mut v = format!("Collision warning{d_min}: KF {kf_v}, SCF {scf_v}");
        v.push_str(&format!(
            " · distance between the regions: KF {}",
            dist(c.kf_distance)
        ));
        if let Some(d) = c.scf_distance {
            v.push_str(&format!(", SCF {}", dist(d)));
        }
        if let Some(d) = c.true_distance {
            v.push_str(&format!(" · true distance at t = {pred}: {}", sig(d)));
        }
        verdict = Some(v);
    } else if let Some(pos) = target.and_then(|g| {
        let pi = g.components.iter().position(|&c| c == i)?;
        let pj = g.components.iter().position(|&c| c == j)?;
        Some((g, [pi, pj]))
    }) {
        let (g, pp) = pos;
        bodies.push(projected(&g.kf, g.scf.as_ref(), pp, [i, j])?);
        let z = if g.components.len() == r.n { "X" } else { "Z" };
        region_name = predicted(z, "", pred, t, &mut notes);
        projection_note(g.components.len(), &mut notes);
    } else {
        bodies.push(projected(&step.kf, step.scf.as_ref(), [i, j], [i, j])?);
        region_name = format!("X{}", sub(t));
        projection_note(r.n, &mut notes);
    }
    Ok(Shown {
        bodies,
        region_name,
        notes,
        verdict,
        pred,
    })
}

fn plane<DB: DrawingBackend>(root: &Area<DB>, cx: &Ctx, i: usize, j: usize) -> Result<Frame> {
    let r = cx.report;
    let t = cx.t;
    let fonts = cx.fonts;
    let steps = r.steps.len();
    let spec = cx.figure().collision.as_ref();
    let Shown {
        bodies,
        region_name,
        mut notes,
        verdict,
        pred,
    } = shown(cx, i, j)?;
    let has_scf = bodies.iter().any(|b| b.scf.is_some());
    if !has_scf {
        notes.push(cx.scf_missing_note());
    }

    // Data of each body: trajectory, measurements up to t, truth at t and at t + τ.
    let coord = |x: &[f64], idx: [usize; 2]| -> Option<(f64, f64)> {
        Some((*x.get(idx[0])?, *x.get(idx[1])?))
    };
    let mut trajectories: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut meas: Vec<(f64, f64)> = Vec::new();
    let mut truth_now: Vec<(f64, f64)> = Vec::new();
    let mut truth_pred: Vec<((f64, f64), Option<&'static str>)> = Vec::new();
    for b in &bodies {
        if b.idx[0] >= r.n || b.idx[1] >= r.n {
            continue;
        }
        let traj: Vec<(f64, f64)> = (1..=steps)
            .filter_map(|s| coord(cx.x_true(s)?, b.idx))
            .collect();
        if traj.len() > 1 {
            trajectories.push(traj);
        }
        for s in 1..=t {
            if let (Some(a), Some(c)) = (cx.measurement(s, b.idx[0]), cx.measurement(s, b.idx[1])) {
                meas.push((a, c));
            }
        }
        if let Some(p) = cx.x_true(t).and_then(|x| coord(x, b.idx)) {
            if pred != t {
                truth_now.push(p);
            } else {
                truth_pred.push((p, b.tag));
            }
        }
        if pred != t {
            if let Some(p) = cx.x_true(pred).and_then(|x| coord(x, b.idx)) {
                truth_pred.push((p, b.tag));
            }
        }
    }

    // Windows: the regions with the true states, or everything.
    let mut near = Win::empty();
    for b in &bodies {
        for pts in [&b.kf, &b.scf].into_iter().flatten() {
            near.add_points(pts);
        }
    }
    for (p, _) in &truth_pred {
        near.add(p.0, p.1);
    }
    // The true positions at t too, unless they are far from the regions (fast motion).
    let mut with_now = near;
    with_now.add_points(&truth_now);
    let span = near.width().max(near.height());
    if with_now.width() <= 1.2 * span && with_now.height() <= 1.2 * span {
        near = with_now;
    }
    let mut all = near;
    for tr in &trajectories {
        all.add_points(tr);
    }
    all.add_points(&meas);
    let zoomed = match cx.view.zoom {
        Zoom::Regions => true,
        Zoom::Full => false,
        Zoom::Auto => {
            // Zoom when the largest region would be a speck in the whole run's window.
            let mut largest: f64 = 0.0;
            for b in &bodies {
                for pts in [&b.kf, &b.scf].into_iter().flatten() {
                    let mut w = Win::empty();
                    w.add_points(pts);
                    largest = largest.max(w.width()).max(w.height());
                }
            }
            largest < 0.08 * all.width().max(all.height())
        }
    };
    let win = if zoomed { near } else { all }.padded(0.12, 0.12);
    if !zoomed || trajectories.is_empty() {
        notes.push(format!("level α = {}", pct(r.alpha)));
    }
    let ratio = win.width() / win.height();
    let equal = spec.is_some() || (0.2..=5.0).contains(&ratio);

    // Legend.
    let mut entries = Vec::new();
    if !trajectories.is_empty() {
        entries.push(
            Entry::new(
                format!("true path to t = {pred}"),
                Swatch::Line {
                    color: TRUTH,
                    dashed: false,
                    width: 1,
                },
            )
            .minor(),
        );
    }
    if !meas.is_empty() {
        entries.push(
            Entry::new(
                if t == 1 {
                    "measurement y₁".to_string()
                } else {
                    format!("measurements y₁ … y{}", sub(t))
                },
                Swatch::Marker {
                    shape: Marker::Dot,
                    color: MEASURE,
                    size: 2,
                },
            )
            .minor(),
        );
    }
    let plural = if bodies.len() > 1 { "s" } else { "" };
    if !truth_now.is_empty() {
        let what = if bodies.len() > 1 {
            format!("true position{plural}")
        } else {
            "true state".to_string()
        };
        entries.push(
            Entry::new(
                format!("{what} at t = {t}"),
                Swatch::Marker {
                    shape: Marker::Ring,
                    color: TRUTH,
                    size: 4,
                },
            )
            .minor(),
        );
    }
    if !truth_pred.is_empty() {
        let what = if bodies.len() > 1 {
            format!("true position{plural}")
        } else {
            "true state".to_string()
        };
        entries.push(Entry::new(
            format!("{what} at t = {pred}"),
            Swatch::Marker {
                shape: Marker::Plus,
                color: TRUTH,
                size: 6,
            },
        ));
    }
    entries.push(Entry::new(
        format!("KF {region_name} ({})", pct(r.alpha)),
        Swatch::Region {
            color: KF,
            dashed: true,
            fill: false,
        },
    ));
    if has_scf {
        entries.push(Entry::new(
            format!("SCF {region_name} ({})", pct(r.alpha)),
            Swatch::Region {
                color: SCF,
                dashed: false,
                fill: true,
            },
        ));
    }

    let mut subtitle = notes.join(" · ");
    if let Some(v) = &verdict {
        subtitle = format!("{v}\n{subtitle}");
    }
    let title = cx.title(if cx.report.method == crate::method::Method::Kf {
        "KF regions in the state plane"
    } else {
        "KF and SCF regions in the state plane"
    });
    let area = style::title_block(root, &fonts, &title, &subtitle)?;
    let (area, side) = style::legend(&area, &fonts, &entries)?;
    let (mut xd, mut yd) = (cx.name(i), cx.name(j));
    if bodies.len() > 1 {
        // Both bodies share the plane: "position p_x of robot A [m]" → "position p_x [m]".
        for d in [&mut xd, &mut yd] {
            for who in [" of robot A", " of body A"] {
                *d = d.replace(who, "");
            }
        }
    }
    let chart = style::chart(
        &area,
        &fonts,
        &Axes {
            win,
            x_desc: &xd,
            y_desc: &yd,
            x_integer: false,
            equal,
            x_labels: true,
        },
    )?;
    let cwin = Win::of_chart(&chart);

    // The true path up to the latest time shown, solid; afterwards, faint.
    let faint = RGBColor(185, 185, 185);
    for tr in &trajectories {
        let cut = pred.min(tr.len());
        if cut < tr.len() {
            style::path(root, &chart, &tr[cut.saturating_sub(1)..], &faint, 1, None)?;
        }
        style::path(root, &chart, &tr[..cut], &TRUTH, 1, None)?;
    }
    style::dots(root, &chart, &meas, &MEASURE, 2)?;
    for b in &bodies {
        if let Some(s) = &b.scf {
            style::region(root, &chart, s, &SCF, false, true)?;
        }
    }
    for b in &bodies {
        if let Some(k) = &b.kf {
            style::region(root, &chart, k, &KF, true, false)?;
        }
    }
    for &p in &truth_now {
        if cwin.contains(p.0, p.1) {
            style::marker(root, style::px(&chart, p), Marker::Ring, &TRUTH, 4)?;
        }
    }
    let label_style = fonts.tag();
    for &(p, tag) in &truth_pred {
        if cwin.contains(p.0, p.1) {
            let q = style::px(&chart, p);
            style::marker(root, q, Marker::Plus, &TRUTH, 6)?;
            if let Some(tag) = tag {
                style::text(
                    root,
                    tag,
                    (q.0 + 7, q.1 - 5),
                    &label_style,
                    (HPos::Left, VPos::Bottom),
                )?;
            }
        }
    }
    // Each body's letter above its KF region (in the KF color), so the reader can tell which
    // dashed region belongs to whom.
    for b in &bodies {
        if let (Some(tag), Some(k)) = (b.tag, &b.kf) {
            if let Some(top) = k.iter().copied().max_by(|a, c| a.1.total_cmp(&c.1)) {
                let q = style::px(&chart, top);
                style::text(
                    root,
                    tag,
                    (q.0, q.1 - 3),
                    &label_style.color(&KF),
                    (HPos::Center, VPos::Bottom),
                )?;
            }
        }
    }
    let mut marks: Vec<(i32, i32)> = Vec::new();
    for b in &bodies {
        for pts in [&b.kf, &b.scf].into_iter().flatten() {
            marks.extend(style::marks_of(&chart, pts));
        }
    }
    for tr in &trajectories {
        for piece in clip_polyline(tr, &cwin) {
            marks.extend(style::marks_of(&chart, &piece));
        }
    }
    marks.extend(
        meas.iter()
            .filter(|p| cwin.contains(p.0, p.1))
            .map(|&p| style::px(&chart, p)),
    );
    for &p in truth_now.iter().chain(truth_pred.iter().map(|(p, _)| p)) {
        marks.push(style::px(&chart, p));
    }
    if zoomed && !trajectories.is_empty() && side != style::LegendSide::Overlay {
        inset(root, &chart, cx, &trajectories, &cwin, &marks)?;
    }
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, &xd, &yd))
}

/// The whole run, small, in the emptiest corner of the plotting area, with the zoom window
/// marked.
fn inset<DB: DrawingBackend>(
    root: &Area<DB>,
    chart: &style::Chart<DB>,
    cx: &Ctx,
    trajectories: &[Vec<(f64, f64)>],
    zoom: &Win,
    marks: &[(i32, i32)],
) -> Result<()> {
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let (pw, ph) = (xr.end - xr.start, yr.end - yr.start);
    let mut full = Win::empty();
    for tr in trajectories {
        full.add_points(tr);
    }
    let full = full.union(zoom).padded(0.06, 0.04);
    // Shape: follow the data's aspect, within bounds.
    let aspect = (full.width() / full.height()).clamp(0.45, 2.2);
    let iw = ((0.26 * pw as f64).clamp(90.0, 220.0) * aspect.min(1.0)).max(70.0) as i32;
    let ih = ((iw as f64 / aspect).min(0.45 * ph as f64)).max(60.0) as i32;
    if iw + 16 > pw || ih + 16 > ph {
        return Ok(());
    }
    let (x0, y0) = style::emptiest_corner(chart, (iw, ih), marks);
    let (bx, by) = root.get_base_pixel();
    root.draw(&Rectangle::new(
        [(x0 - bx, y0 - by), (x0 + iw - bx, y0 + ih - by)],
        WHITE.filled(),
    ))
    .map_err(crate::plot::erase::de)?;
    style::polyline(
        root,
        &[
            (x0, y0),
            (x0 + iw, y0),
            (x0 + iw, y0 + ih),
            (x0, y0 + ih),
            (x0, y0),
        ],
        &FRAME,
        1,
        None,
    )?;
    let label = cx.fonts.note();
    let lh = style::text_size(root, "whole run", &label)?.1 as i32;
    style::text(
        root,
        "whole run",
        (x0 + 5, y0 + 3),
        &label,
        (HPos::Left, VPos::Top),
    )?;
    let (ix0, iy0, iw2, ih2) = (x0 + 6, y0 + lh + 6, iw - 12, ih - lh - 12);
    if iw2 < 10 || ih2 < 10 {
        return Ok(());
    }
    let map = |p: (f64, f64)| {
        (
            ix0 + ((p.0 - full.x0) / full.width() * iw2 as f64).round() as i32,
            iy0 + ih2 - ((p.1 - full.y0) / full.height() * ih2 as f64).round() as i32,
        )
    };
    for tr in trajectories {
        let p: Vec<(i32, i32)> = tr.iter().map(|&q| map(q)).collect();
        style::polyline(root, &p, &TRUTH, 1, None)?;
        if let Some(&s) = tr.first() {
            style::marker(root, map(s), Marker::Dot, &TRUTH, 2)?;
        }
    }
    // The zoom window, at least 8 px so it can be seen.
    let (a, b) = (map((zoom.x0, zoom.y1)), map((zoom.x1, zoom.y0)));
    let (cxp, cyp) = ((a.0 + b.0) / 2, (a.1 + b.1) / 2);
    let (hw, hh) = (((b.0 - a.0) / 2).max(4), ((b.1 - a.1) / 2).max(4));
    style::polyline(
        root,
        &[
            (cxp - hw, cyp - hh),
            (cxp + hw, cyp - hh),
            (cxp + hw, cyp + hh),
            (cxp - hw, cyp + hh),
            (cxp - hw, cyp - hh),
        ],
        &SCF,
        2,
        None,
    )
}

/// One component over time: bands for all times, error bars at the shown time.
fn over_time<DB: DrawingBackend>(root: &Area<DB>, cx: &Ctx, k: usize) -> Result<Frame> {
    let r = cx.report;
    let fonts = cx.fonts;
    let steps = r.steps.len();
    let t = cx.t;
    let iv = |e: &Ellipsoid| -> Result<(f64, f64)> {
        let b = e.project(&[k])?.bounding_box();
        Ok((b.lo[0], b.hi[0]))
    };
    let xs: Vec<f64> = (1..=steps).map(|s| s as f64).collect();
    let mut kf = Vec::with_capacity(steps);
    let mut scf: Vec<Option<(f64, f64)>> = Vec::with_capacity(steps);
    for st in &r.steps {
        kf.push(iv(&st.kf)?);
        scf.push(match &st.scf {
            Some(e) => Some(iv(e)?),
            None => None,
        });
    }
    let truth: Vec<Option<f64>> = (1..=steps).map(|s| cx.truth(s, k)).collect();
    let meas: Vec<(f64, f64)> = (1..=steps)
        .filter_map(|s| Some((s as f64, cx.measurement(s, k)?)))
        .collect();

    let x1 = steps as f64 + 1.0 + (steps as f64 / 40.0).max(0.5);
    let mut win = Win::empty();
    win.add_x(0.0);
    win.add_x(x1);
    for &(lo, hi) in &kf {
        win.add_y(lo);
        win.add_y(hi);
    }
    for (lo, hi) in scf.iter().flatten() {
        win.add_y(*lo);
        win.add_y(*hi);
    }
    for v in truth.iter().flatten() {
        win.add_y(*v);
    }
    for (_, v) in &meas {
        win.add_y(*v);
    }
    let pad = win.padded(0.0, 0.06);
    let win = Win::new((0.0, x1), (pad.y0, pad.y1));

    let has_scf = scf.iter().any(|s| s.is_some());
    let mut entries = Vec::new();
    if truth.iter().any(|v| v.is_some()) {
        entries.push(Entry::new(
            if r.n == 1 {
                "true state xₜ".to_string()
            } else {
                format!("true value of {}", cx.symbol(k))
            },
            Swatch::Line {
                color: TRUTH,
                dashed: false,
                width: 2,
            },
        ));
    }
    if !meas.is_empty() {
        entries.push(
            Entry::new(
                "measurements y_t",
                Swatch::Marker {
                    shape: Marker::Dot,
                    color: MEASURE,
                    size: 3,
                },
            )
            .minor(),
        );
    }
    entries.push(Entry::new(
        format!("KF interval Xₜ ({})", pct(r.alpha)),
        Swatch::Line {
            color: KF,
            dashed: true,
            width: 2,
        },
    ));
    if has_scf {
        entries.push(Entry::new(
            format!("SCF interval Xₜ ({})", pct(r.alpha)),
            Swatch::Region {
                color: SCF,
                dashed: false,
                fill: true,
            },
        ));
    }
    let record = cx.record();
    let mut notes = vec![format!("shown time {}", record.at("t", t))];
    let (klo, khi) = kf[t - 1];
    notes.push(format!("KF [{}, {}]", sig(klo), sig(khi)));
    match scf[t - 1] {
        Some((lo, hi)) => notes.push(format!("SCF [{}, {}]", sig(lo), sig(hi))),
        None => notes.push(cx.scf_missing_note()),
    }
    if let Some(x) = cx.truth(t, k) {
        let inside = |(lo, hi): (f64, f64)| {
            if x >= lo && x <= hi {
                "inside"
            } else {
                "outside"
            }
        };
        let what = if r.n == 1 {
            format!("x{}", sub(t))
        } else {
            format!("{} at t = {t}", cx.symbol(k))
        };
        let mut s = format!("true {what} = {}: {} KF", sig(x), inside(kf[t - 1]));
        if let Some(si) = scf[t - 1] {
            s.push_str(&format!(", {} SCF", inside(si)));
        }
        notes.push(s);
    }
    if r.n > 1 {
        notes.push(format!("projection of the {}-dimensional regions", r.n));
    }
    let title = cx.title("KF and SCF intervals over time");
    let (area, side) = style::titled_legend(root, &fonts, &title, &notes, &entries)?;
    let yd = cx.name(k);
    let steps_name = "time t (steps)";
    let xd = record.axis_name(steps_name);
    let chart = style::time_chart(
        &area,
        &fonts,
        &Axes {
            win,
            x_desc: xd,
            y_desc: &yd,
            x_integer: true,
            equal: false,
            x_labels: true,
        },
        &record,
    )?;

    // SCF band (filled, solid bounds) in contiguous runs.
    let mut run: Vec<(f64, f64, f64)> = Vec::new();
    let flush = |run: &mut Vec<(f64, f64, f64)>| -> Result<()> {
        if run.len() > 1 {
            let xs: Vec<f64> = run.iter().map(|p| p.0).collect();
            let lo: Vec<f64> = run.iter().map(|p| p.1).collect();
            let hi: Vec<f64> = run.iter().map(|p| p.2).collect();
            style::band(root, &chart, &xs, &lo, &hi, &SCF)?;
            let l: Vec<(f64, f64)> = run.iter().map(|p| (p.0, p.1)).collect();
            let h: Vec<(f64, f64)> = run.iter().map(|p| (p.0, p.2)).collect();
            style::path(root, &chart, &l, &SCF, 1, None)?;
            style::path(root, &chart, &h, &SCF, 1, None)?;
        }
        run.clear();
        Ok(())
    };
    for (s, v) in scf.iter().enumerate() {
        match v {
            Some((lo, hi)) => run.push(((s + 1) as f64, *lo, *hi)),
            None => flush(&mut run)?,
        }
    }
    flush(&mut run)?;
    let klo: Vec<(f64, f64)> = xs.iter().zip(&kf).map(|(x, v)| (*x, v.0)).collect();
    let khi: Vec<(f64, f64)> = xs.iter().zip(&kf).map(|(x, v)| (*x, v.1)).collect();
    style::path(root, &chart, &klo, &KF, 2, Some(style::DASH))?;
    style::path(root, &chart, &khi, &KF, 2, Some(style::DASH))?;
    style::dots(root, &chart, &meas, &MEASURE, 3)?;
    let tr: Vec<(f64, f64)> = xs
        .iter()
        .zip(&truth)
        .filter_map(|(x, v)| Some((*x, (*v)?)))
        .collect();
    style::path(root, &chart, &tr, &TRUTH, 2, None)?;
    // The shown time: cursor and the two intervals as bars with caps.
    style::cursor(root, &chart, &fonts, t as f64, &record.at("t", t))?;
    let bar =
        |x: f64, (lo, hi): (f64, f64), color: &RGBColor, dash: Option<(i32, i32)>| -> Result<()> {
            let (a, b) = (style::px(&chart, (x, lo)), style::px(&chart, (x, hi)));
            style::polyline(root, &[a, b], color, 3, dash)?;
            for p in [a, b] {
                style::polyline(root, &[(p.0 - 6, p.1), (p.0 + 6, p.1)], color, 3, None)?;
            }
            Ok(())
        };
    let off = (steps as f64 / 120.0).max(0.25);
    bar(t as f64 - off, kf[t - 1], &KF, Some((6, 4)))?;
    if let Some(si) = scf[t - 1] {
        bar(t as f64 + off, si, &SCF, None)?;
    }
    if let Some(x) = cx.truth(t, k) {
        style::marker(
            root,
            style::px(&chart, (t as f64, x)),
            Marker::Plus,
            &TRUTH,
            7,
        )?;
    }
    let mut marks = style::marks_of(&chart, &klo);
    marks.extend(style::marks_of(&chart, &khi));
    marks.extend(style::marks_of(&chart, &tr));
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, steps_name, &yd))
}
