//! The "plane" panel — the two `plane` components of the state x(k) of a GLLS report: the true
//! state ◇, the estimate ⋆, the guaranteed ball (35) (its projection is a disk of the same
//! radius around the LLS estimate), the exact interval box (dashed), the regularized estimate +
//! with the projection of the truth it estimates ◇, and the state-noise estimate ×. Equal
//! scales on both axes; the window holds every set and point; huge coordinates (‖x(k)‖ ≈ 10⁷
//! next to a ball of radius 3) are drawn with a round offset so the ticks stay short. Notes say
//! when the truth lies outside the sets and why, and when rounding rivals the bound.

use super::horizon::{estimator_name, glls_of};
use crate::plot::geom::Win;

use crate::error::{Error, Result};
use crate::plot::figures::Area;
use crate::plot::style::{
    self, sci, sig, sub, Entry, Fonts, Marker, Swatch, BALL, GLLS_EST, INTERVAL_BOX, REGULARIZED,
    STATE_NOISE, TRUTH,
};
use crate::plot::view::{Frame, Panel};
use crate::scenario::Report;
use plotters::prelude::*;

/// Points on a drawn circle.
const CIRCLE_POINTS: usize = 160;

/// An offset that keeps tick labels short when the values are huge next to their spread
/// (‖x(k)‖ ≈ 10⁷ with a ball of radius 3): a round number near `c`, or 0.
fn offset_for(lo: f64, span: f64) -> f64 {
    if !(lo.is_finite() && span.is_finite() && span > 0.0) || lo.abs() < 1e4 * span {
        return 0.0;
    }
    let step = 10f64.powf(span.log10().ceil());
    (lo / step).floor() * step
}

/// "x₂ − 21240190" for an axis with an offset.
fn with_offset(sym: &str, off: f64, span: f64) -> String {
    if off == 0.0 {
        return sym.to_string();
    }
    let d = (-(span.log10().ceil())).max(0.0) as usize;
    let v = style::num(off.abs(), d.min(8));
    format!("{sym} {} {v}", if off > 0.0 { "−" } else { "+" })
}

/// The "plane" panel — the two `plane` components of x(k).
pub fn draw<DB: DrawingBackend>(root: &Area<DB>, report: &Report, fonts: Fonts) -> Result<Frame> {
    let g = glls_of(report, Panel::of(&super::horizon::PLANE))?;
    let n = g.n;
    let [i, j] = g.plane;
    if i >= n || j >= n {
        return Err(Error::field(
            "report.glls.plane",
            format!("must name components below n = {n}"),
        ));
    }
    let one = i == j;
    let ok = |v: &[f64]| v.len() == n && v.iter().all(|x| x.is_finite());
    let ball = &g.ball_current;
    let bx = &g.box_current;
    if !ok(&g.estimate_current)
        || !ok(&ball.center)
        || ball.cov.len() != n
        || !ok(&bx.lo)
        || !ok(&bx.hi)
    {
        return Err(Error::field(
            "report.glls",
            "holds an estimate, ball or box of the wrong dimension or with non-finite numbers",
        ));
    }
    let r2 = ball.cov[i].get(i).copied().unwrap_or(f64::NAN) * ball.radius2;
    if !(r2.is_finite() && r2 >= 0.0) {
        return Err(Error::field(
            "report.glls.ball_current",
            "must have a finite radius",
        ));
    }
    // cov = r²I with r² ≥ 1e-300 stored for a zero radius (μ = 0).
    let r = if r2 <= 1e-290 { 0.0 } else { r2.sqrt() };
    let at = |v: &[f64]| (v[i], if one { 0.0 } else { v[j] });
    let center = at(&ball.center);
    let est = at(&g.estimate_current);
    let truth = g.x_true_current.as_deref().filter(|v| ok(v)).map(at);
    let (bx_x, bx_y) = (
        (bx.lo[i], bx.hi[i]),
        if one {
            let h = 0.5 * (bx.hi[i] - bx.lo[i]);
            (-h, h)
        } else {
            (bx.lo[j], bx.hi[j])
        },
    );
    let sn = g
        .state_noise
        .as_ref()
        .map(|s| s.estimate_current.as_slice())
        .filter(|v| ok(v))
        .map(at);
    let reg = g.regularized.as_ref();
    let reg_est = reg
        .and_then(|r| r.estimate_current.as_deref())
        .filter(|v| ok(v))
        .map(at);
    let reg_truth = reg
        .and_then(|r| r.truth_projected_current.as_deref())
        .filter(|v| ok(v))
        .map(at);

    // Window: every set and point, padded; then an offset for huge coordinates.
    let mut w = Win::empty();
    w.add(center.0 - r, center.1 - r);
    w.add(center.0 + r, center.1 + r);
    w.add(bx_x.0, bx_y.0);
    w.add(bx_x.1, bx_y.1);
    for p in [Some(est), truth, sn, reg_est, reg_truth]
        .into_iter()
        .flatten()
    {
        w.add(p.0, p.1);
    }
    if w.width() <= 0.0 && w.height() <= 0.0 {
        let e = 1e-6 * center.0.abs().max(center.1.abs()).max(1.0);
        w = Win::new((w.x0 - e, w.x1 + e), (w.y0 - e, w.y1 + e));
    }
    // Small figures draw the legend and notes over the chart: leave them room.
    let pad = if fonts.compact { 0.3 } else { 0.1 };
    let w = w.padded(pad, pad);
    let span = w.width().max(w.height());
    let (ox, oy) = (offset_for(w.x0, span), offset_for(w.y0, span));
    let sh = |p: (f64, f64)| (p.0 - ox, p.1 - oy);
    let win = Win::new((w.x0 - ox, w.x1 - ox), (w.y0 - oy, w.y1 - oy));

    // Texts.
    let short = fonts.compact;
    let k = g.k;
    let sym = |c: usize| format!("x{}({k})", sub(c + 1));
    let axis = |c: usize, off: f64| {
        let s = with_offset(&sym(c), off, span);
        match report.figure.names.get(c) {
            Some(name) if !name.is_empty() => format!("{s}: {name}"),
            _ => s,
        }
    };
    let x_desc = axis(i, ox);
    let y_desc = if one {
        "(n = 1: one component)".to_string()
    } else {
        axis(j, oy)
    };
    let est_name = estimator_name(g);
    let yes = |b: Option<bool>| match b {
        Some(true) => "yes",
        Some(false) => "NO",
        None => "—",
    };
    let mut notes = vec![format!(
        "x({k}) from y({}) … y({k}): horizon s = {}, {est_name} estimator",
        k.saturating_sub(g.s),
        g.s
    )];
    notes.push(format!(
        "‖δ(j)‖₂ ≤ μ = {} guarantees the ball (35) of radius √(s+1)·μ·κ = {} and the exact interval box",
        sig(g.mu),
        sig(r)
    ));
    if truth.is_some() {
        notes.push(format!(
            "true x({k}) in ball: {}, in box: {}",
            yes(g.truth_in_ball),
            yes(g.truth_in_box)
        ));
    }
    if n > 2 {
        notes.push(format!(
            "n = {n}: projection on x{}, x{} (a ball projects to a disk)",
            sub(i + 1),
            sub(j + 1)
        ));
    }
    let mut entries = Vec::new();
    if truth.is_some() {
        entries.push(Entry::new(
            format!("true state x({k})"),
            Swatch::Marker {
                shape: Marker::Diamond,
                color: TRUTH,
                size: 5,
            },
        ));
    }
    let lls_center = sn.is_some();
    entries.push(Entry::new(
        if lls_center {
            if short {
                "LLS (ball centre)".to_string()
            } else {
                "LLS estimate (centre of ball and box)".to_string()
            }
        } else {
            format!("{est_name} estimate x̂({k})")
        },
        Swatch::Marker {
            shape: Marker::Star,
            color: GLLS_EST,
            size: 5,
        },
    ));
    if sn.is_some() {
        entries.push(Entry::new(
            if short {
                "state-noise est."
            } else {
                "state-noise estimate (63)–(64)"
            },
            Swatch::Marker {
                shape: Marker::Cross,
                color: STATE_NOISE,
                size: 5,
            },
        ));
    }
    let degenerate = |e: Entry| if r == 0.0 { e.minor() } else { e };
    entries.push(degenerate(Entry::new(
        if short {
            "ball (35)".to_string()
        } else {
            format!("guaranteed ball (35), r = {}", sig(r))
        },
        Swatch::Region {
            color: BALL,
            dashed: false,
            fill: true,
        },
    )));
    entries.push(degenerate(Entry::new(
        if short {
            "interval box"
        } else {
            "interval box (exact hull)"
        },
        Swatch::Region {
            color: INTERVAL_BOX,
            dashed: true,
            fill: false,
        },
    )));
    if let (Some(rg), Some(_)) = (reg, reg_est) {
        entries.push(Entry::new(
            if short {
                format!("regularized p = {}", rg.p)
            } else {
                format!("regularized estimate (p = {})", rg.p)
            },
            Swatch::Marker {
                shape: Marker::Plus,
                color: REGULARIZED,
                size: 5,
            },
        ));
        if reg_truth.is_some() {
            entries.push(
                Entry::new(
                    "projected truth (what it estimates)",
                    Swatch::Marker {
                        shape: Marker::Diamond,
                        color: REGULARIZED,
                        size: 5,
                    },
                )
                .minor(),
            );
        }
    }
    let t = style::title(
        &report.figure,
        &fonts,
        &format!("State x({k}) with its guaranteed sets"),
        &format!("GLLS estimate of x({k}) with the guaranteed ball and interval box"),
    );
    let (area, side) = style::titled_legend(root, &fonts, &t, &notes, &entries)?;
    let chart = style::equal_chart(&area, &fonts, win, &x_desc, &y_desc)?;
    let mut marks = Vec::new();
    // The box (dashed), then the ball (filled disk), then the points.
    let b0 = sh((bx_x.0, bx_y.0));
    let b1 = sh((bx_x.1, bx_y.1));
    let rect = [(b0.0, b0.1), (b1.0, b0.1), (b1.0, b1.1), (b0.0, b1.1)];
    if b1.0 > b0.0 || b1.1 > b0.1 {
        style::region(root, &chart, &rect, &INTERVAL_BOX, true, false)?;
        marks.extend(style::marks_of(&chart, &rect));
    }
    let c = sh(center);
    if r > 0.0 {
        let circle: Vec<(f64, f64)> = (0..CIRCLE_POINTS)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / CIRCLE_POINTS as f64;
                (c.0 + r * a.cos(), c.1 + r * a.sin())
            })
            .collect();
        style::region(root, &chart, &circle, &BALL, false, true)?;
        marks.extend(style::marks_of(&chart, &circle));
    }
    let mut outside: Vec<&str> = Vec::new();
    let mut point =
        |p: (f64, f64), shape: Marker, color: &RGBColor, what: &'static str| -> Result<()> {
            if !style::marker_inside(root, &chart, sh(p), shape, color, &mut marks)? {
                outside.push(what);
            }
            Ok(())
        };
    if let Some(t) = reg_truth {
        point(t, Marker::Diamond, &REGULARIZED, "projected truth")?;
    }
    if let Some(t) = truth {
        point(t, Marker::Diamond, &TRUTH, "true state")?;
    }
    if let Some(e) = reg_est {
        point(e, Marker::Plus, &REGULARIZED, "regularized estimate")?;
    }
    point(
        if lls_center { center } else { est },
        Marker::Star,
        &GLLS_EST,
        "estimate",
    )?;
    if let Some(e) = sn {
        point(e, Marker::Cross, &STATE_NOISE, "state-noise estimate")?;
    }

    // On-chart notes.
    let mut chart_notes: Vec<String> = Vec::new();
    let out_of_sets = g.truth_in_ball == Some(false) || g.truth_in_box == Some(false);
    if out_of_sets {
        chart_notes.push(match (g.noise_max, short) {
            (Some(d), false) if d > g.mu => format!(
                "outside: the noise exceeded μ (max ‖δ(j)‖₂ = {} > μ = {})",
                sig(d),
                sig(g.mu)
            ),
            (Some(d), true) if d > g.mu => "outside: the noise exceeded μ".to_string(),
            (_, false) if g.state_noise.is_some() => format!(
                "outside: the sets cover only measurement noise ‖δ‖₂ ≤ μ = {}, not the state noise ξ",
                sig(g.mu)
            ),
            (_, true) if g.state_noise.is_some() => "outside: state noise ξ".to_string(),
            (_, false) => format!(
                "outside: the truth left the sets for ‖δ(j)‖₂ ≤ μ = {}",
                sig(g.mu)
            ),
            (_, true) => "outside the sets".to_string(),
        });
    }
    if r == 0.0 {
        chart_notes.push(if short {
            "μ = 0: the sets are a point".to_string()
        } else {
            "μ = 0: the ball and the box are the single point of the LLS estimate".to_string()
        });
    }
    if g.rounding_dominates {
        chart_notes.push(if short {
            format!(
                "floating point: rounding {} > 10 % of the bound",
                sci(g.rounding_estimate)
            )
        } else {
            format!(
                "floating point: estimated rounding error {} exceeds 10 % of the bound",
                sci(g.rounding_estimate)
            )
        });
    }
    if !outside.is_empty() {
        chart_notes.push(format!("outside the window: {}", outside.join(", ")));
    }
    style::chart_notes(root, &chart, &fonts, &chart_notes, &mut marks)?;
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, &x_desc, &y_desc))
}
