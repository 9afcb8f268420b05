//! The "upolygon" panel — the states x_t consistent with the window y_first … y_t at the cursor:
//! every x_t for which some window x_{first−1} … x_t satisfies the constraints (4) of the LU
//! model at the half-width bounds x̄ᵣ, ȳᵣ with the Θ in use there (a convex polygon in the
//! `plane` components, exact from support LPs). With the true Θ it must hold the true state;
//! with Θ̂ₜ (joint estimation) it need not, and the note says so; on the user's data with Θ
//! known it holds every state the model and the bounds allow. Drawn with the true state ◇
//! (simulation), the LP estimate ⋆, the KF estimate × (simulation) and the box of ranges over
//! the LP's optimal face (dashed). Equal scales on both axes. A scalar state has no polygon:
//! the panel says why.

use super::time_series::check;
use crate::plot::geom::Win;
use crate::plot::style::{
    self, num, sig, sub, Entry, Marker, Swatch, FACE, KF, POLYGON, TRUTH, UNIFORM_LP,
};

use crate::error::{Error, Result};
use crate::plot::figures::{Area, Request};
use crate::plot::view::{Frame, Panel};
use crate::uniform::Joint;
use plotters::prelude::*;

/// The "upolygon" panel.
pub fn draw<DB: DrawingBackend>(root: &Area<DB>, request: &Request) -> Result<Frame> {
    let (report, view, fonts) = (request.report, request.view, request.fonts);
    let u = check(report, view, Panel::of(&super::time_series::POLYGON))?;
    let at = &u.u.at;
    // The time shown: the view's, else the report's. The polygon and the optimal face come
    // with the report's `at` only; at another time the estimates are drawn alone until its
    // detail is set (`Report::set_at`): a window's polygon is never drawn at another time.
    let t = u.t;
    let detail = u.at_window();
    // The report's reason, else `otherwise`.
    let absent = |otherwise: &str| {
        Error::field(
            "report.uniform.at.polygon",
            format!(
                "is absent: {}",
                at.polygon_absent.as_deref().unwrap_or(otherwise)
            ),
        )
    };
    let Some([i, j]) = u.u.plane else {
        return Err(absent("the report has no polygon or no plane"));
    };
    let polygon = match (&at.polygon, detail) {
        (_, false) => None,
        (Some(p), true) => Some(p),
        (None, true) => return Err(absent("the report has no polygon")),
    };
    if i >= u.n || j >= u.n || i == j {
        return Err(Error::field(
            "report.uniform.plane",
            format!("must name two distinct components below n = {}", u.n),
        ));
    }
    let pick = |v: &[f64]| (v[i], v[j]);
    let poly: Vec<(f64, f64)> = polygon
        .map(|p| p.vertices.iter().map(|v| (v[0], v[1])).collect())
        .unwrap_or_default();
    let truth = u.truth.map(|x| pick(&x[t]));
    let lp = pick(&u.u.steps[t - 1].x);
    let kf = u.kf.map(|k| pick(&k[t - 1]));
    let face = detail.then(|| {
        let (flo, fhi) = (pick(&at.face_lo[0]), pick(&at.face_hi[0]));
        (
            flo,
            fhi,
            [
                (flo.0, flo.1),
                (fhi.0, flo.1),
                (fhi.0, fhi.1),
                (flo.0, fhi.1),
            ],
        )
    });

    let mut w = Win::empty();
    w.add_points(&poly);
    if let Some((_, _, corners)) = &face {
        w.add_points(corners);
    }
    for p in [Some(lp), kf, truth].into_iter().flatten() {
        w.add(p.0, p.1);
    }
    let pad = if fonts.compact { 0.3 } else { 0.1 };
    let win = w.padded(pad, pad);

    let short = fonts.compact;
    let (xs, ys) = (format!("x{}", sub(i + 1)), format!("x{}", sub(j + 1)));
    let axis = |s: &str, c: usize| match report.figure.names.get(c) {
        Some(name) if !name.is_empty() => format!("{s}: {name}"),
        _ if short => s.to_string(),
        _ => format!("{s} of the state x{} at t = {t}", sub(t)),
    };
    let (x_desc, y_desc) = (axis(&xs, i), axis(&ys, j));
    // The Θ of the polygon: the truth (simulation, Θ known), the model's (data, Θ known) or
    // the estimate Θ̂ₜ (joint estimation).
    let model_theta = u.is_data() && u.u.estimator == Joint::States;
    let theta = if at.polygon_theta_true {
        "the true Θ"
    } else if model_theta {
        "the model's Θ"
    } else {
        "Θ̂ₜ"
    };
    let mut notes = Vec::new();
    if let (Some((flo, fhi, _)), Some(polygon)) = (face, polygon) {
        notes.push(format!(
            "states x{} consistent with y{} … y{} at the half-width bounds x̄ᵣ, ȳᵣ and {theta}",
            sub(t),
            sub(at.first),
            sub(t)
        ));
        notes.push(format!(
            "optimal face of the LP: {xs} ∈ [{}, {}], {ys} ∈ [{}, {}]",
            sig(flo.0),
            sig(fhi.0),
            sig(flo.1),
            sig(fhi.1)
        ));
        if !polygon.exact {
            notes.push(format!(
                "the support-LP budget ({} LPs) ran out: the set lies within {} of the polygon",
                polygon.calls,
                sig(polygon.gap)
            ));
        }
        if at.extended > 0 {
            notes.push(format!(
                "the window's LP doubled the half-width bounds {}: the polygon uses the extended bounds",
                crate::error::counted(at.extended, "time", "times")
            ));
        }
    } else {
        notes.push(format!(
            "t = {t}: polygon and optimal face not in this report (it holds t = {})",
            at.time
        ));
    }
    if u.n > 2 {
        notes.push(format!(
            "n = {}: the polygon is the projection on {xs}, {ys}",
            u.n
        ));
    }
    notes.push(u.estimator().to_string());

    // The legend's point markers, one size for the three estimates.
    let marker = |shape, color| Swatch::Marker {
        shape,
        color,
        size: 5,
    };
    let mut entries = Vec::new();
    if truth.is_some() {
        entries.push(Entry::new(
            format!("true state x{}", sub(t)),
            marker(Marker::Diamond, TRUTH),
        ));
    }
    entries.push(Entry::new(
        if short {
            "LP estimate x̂ₜ".to_string()
        } else {
            format!("LP (MAP) estimate x̂{}", sub(t))
        },
        marker(Marker::Star, UNIFORM_LP),
    ));
    if kf.is_some() {
        entries.push(Entry::new(
            if short {
                "KF (true Θ)"
            } else {
                "KF estimate (true Θ, variances r²/3)"
            },
            marker(Marker::Cross, KF),
        ));
    }
    entries.push(Entry::new(
        if short {
            "consistent states".to_string()
        } else {
            format!("consistent states (x̄ᵣ, ȳᵣ, {theta})")
        },
        Swatch::Region {
            color: POLYGON,
            dashed: false,
            fill: true,
        },
    ));
    entries.push(Entry::new(
        if short {
            "optimal face"
        } else {
            "box of the LP's optimal face"
        },
        Swatch::Region {
            color: FACE,
            dashed: true,
            fill: false,
        },
    ));
    let title = style::title(
        &report.figure,
        &fonts,
        &format!(
            "States consistent with the window at {}",
            u.record.at("t", t)
        ),
        &format!(
            "States x{} consistent with the window (Pavelková, (4) at the bounds)",
            sub(t)
        ),
    );
    let (area, side) = style::titled_legend_beside(root, &fonts, &title, &notes, &entries)?;
    let chart = style::equal_chart(&area, &fonts, win, &x_desc, &y_desc)?;
    let mut marks = Vec::new();
    if poly.len() >= 2 {
        style::region(root, &chart, &poly, &POLYGON, false, true)?;
        marks.extend(style::marks_of(&chart, &poly));
    }
    // The face box, at least a few pixels wide so a point-like face shows.
    if let Some((flo, fhi, _)) = face {
        let (a, b) = (style::px(&chart, flo), style::px(&chart, fhi));
        let (x0, x1) = (a.0.min(b.0).min(a.0 - 4), a.0.max(b.0).max(a.0 + 4));
        let (y0, y1) = (a.1.min(b.1).min(a.1 - 4), a.1.max(b.1).max(a.1 + 4));
        style::polyline(
            root,
            &[(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)],
            &FACE,
            2,
            Some((4, 3)),
        )?;
    }
    let mut points: Vec<_> = kf
        .map(|p| (p, Marker::Cross, KF, "KF estimate"))
        .into_iter()
        .collect();
    points.push((lp, Marker::Star, UNIFORM_LP, "LP estimate"));
    points.extend(truth.map(|p| (p, Marker::Diamond, TRUTH, "true state")));
    let outside = style::markers_inside(root, &chart, &points, &mut marks)?;

    let mut chart_notes = Vec::new();
    chart_notes.extend(detail.then(|| {
        if at.polygon_theta_true {
            "true Θ: guaranteed to hold the true state".to_string()
        } else if model_theta {
            "the model's Θ: holds the state if the model and the bounds hold".to_string()
        } else if short {
            "Θ̂ₜ: not guaranteed to hold the truth".to_string()
        } else {
            "uses the estimate Θ̂ₜ: not guaranteed to hold the true state".to_string()
        }
    }));
    if detail && at.truth_in_polygon == Some(false) {
        chart_notes.push(if at.polygon_theta_true {
            "truth outside (numerical tolerance?)".to_string()
        } else {
            "truth outside: Θ̂ₜ differs from Θ".to_string()
        });
    }
    if detail && poly.is_empty() {
        chart_notes.push("no consistent state: the polygon is empty".to_string());
    }
    if !outside.is_empty() {
        chart_notes.push(format!("outside the window: {}", outside.join(", ")));
    }
    if let Some(p) = truth {
        if !short {
            chart_notes.push(format!(
                "true x{}: ({}, {})",
                sub(t),
                num(p.0, 3),
                num(p.1, 3)
            ));
        }
    }
    style::chart_notes(root, &chart, &fonts, &chart_notes, &mut marks)?;
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, &x_desc, &y_desc))
}
