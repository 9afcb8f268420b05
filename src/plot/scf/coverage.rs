//! The "coverage" panel — Fig. 1 of the SCF paper: the conditional coverage
//! P{x_t ∈ X_t | x_t = x̄} of the KF and SCF regions against the state value x̄, with the level
//! α. The SCF curve stays at α for every x̄ (Property 1); the KF curve reaches α only on
//! average over x_t and collapses for unusual states. When the report knows the stationary
//! covariance Γ, the range where the prior puts probability α on x_t is shaded.

use super::context::Ctx;
use crate::error::{Error, Result};
use crate::plot::figures::Area;
use crate::plot::geom::Win;
use crate::plot::style::{self, pct, sci, sub, Axes, Entry, Swatch, KF, REFERENCE, SCF};
use crate::plot::view::Frame;
use crate::plot::view::PanelSpec;
use crate::stats::chi2_quantile;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

/// Fig. 1: conditional coverage of KF and SCF against the state value.
pub(crate) static COVERAGE: PanelSpec = PanelSpec {
    name: "coverage",
    alt_text:
        "conditional coverage of the Kalman and SCF regions against the state value (SCF Fig. 1)",
};

const PRIOR: RGBColor = RGBColor(150, 150, 150);

pub fn draw<DB: DrawingBackend>(root: &Area<DB>, cx: &Ctx) -> Result<Frame> {
    let r = cx.report;
    let fonts = cx.fonts;
    let cc = r
        .coverage_curve
        .as_ref()
        .ok_or_else(|| Error::field("coverage_curve", "is not in this report"))?;
    let m = cc.xbar.len();
    if m < 2 || cc.kf.len() != m || cc.scf.len() != m {
        return Err(Error::field(
            "coverage_curve",
            "needs at least two points with a KF and an SCF value each",
        ));
    }
    let kf: Vec<(f64, f64)> = cc.xbar.iter().copied().zip(cc.kf.iter().copied()).collect();
    let scf: Vec<(f64, f64)> = cc
        .xbar
        .iter()
        .copied()
        .zip(cc.scf.iter().copied())
        .collect();
    let mut xw = Win::empty();
    for &x in &cc.xbar {
        xw.add_x(x);
    }
    xw.add_y(0.0);
    if xw.is_empty() || xw.width() <= 0.0 {
        return Err(Error::field(
            "coverage_curve.xbar",
            "must span a range of values",
        ));
    }
    let win = Win::new((xw.x0, xw.x1), (0.0, 1.06));

    // The prior's α-range of the component, when the stationary Γ is known.
    let c = cc.component;
    let prior = r.asymptotic.as_ref().and_then(|a| {
        let g = *a.gamma.get(c)?.get(c)?;
        let mean = r
            .prior_mean
            .get(cc.time.checked_sub(1)?)
            .and_then(|m| m.get(c).copied())
            .unwrap_or(0.0);
        let half = (chi2_quantile(r.alpha, 1).ok()? * g).sqrt();
        (half.is_finite() && half > 0.0).then_some((mean - half, mean + half))
    });

    let mut entries = vec![
        Entry::new(
            "KF region",
            Swatch::Line {
                color: KF,
                dashed: true,
                width: 3,
            },
        ),
        Entry::new(
            "SCF region",
            Swatch::Line {
                color: SCF,
                dashed: false,
                width: 3,
            },
        ),
        Entry::new(
            format!("level α = {}", pct(r.alpha)),
            Swatch::Line {
                color: REFERENCE,
                dashed: false,
                width: 1,
            },
        ),
    ];
    if prior.is_some() {
        entries.push(
            Entry::new(
                format!("prior {} range of x{}", pct(r.alpha), sub(cc.time)),
                Swatch::Region {
                    color: PRIOR,
                    dashed: false,
                    fill: true,
                },
            )
            .minor(),
        );
    }
    let name = cx.name(c);
    let min_kf = cc.kf.iter().copied().fold(f64::INFINITY, f64::min);
    let notes = [
        format!("t = {}", cc.time),
        cc.how.clone(),
        format!(
            "SCF keeps P = α for every state value; KF has P = α only on average over xₜ (min {} here)",
            sci(min_kf)
        ),
    ];
    let title = cx.title("Conditional coverage (SCF paper, Fig. 1)");
    let title = if cx.figure().title.is_some() {
        format!("{title}: conditional coverage")
    } else {
        title
    };
    let (area, side) = style::titled_legend(root, &fonts, &title, &notes, &entries)?;
    let xd = if r.n == 1 {
        format!("x̄: the value at which x{} is fixed", sub(cc.time))
    } else {
        format!("x̄: the value at which {name} is fixed (t = {})", cc.time)
    };
    let yd = "P{ xₜ ∈ Xₜ | xₜ = x̄ }";
    let chart = style::chart(
        &area,
        &fonts,
        &Axes {
            win,
            x_desc: &xd,
            y_desc: yd,
            x_integer: false,
            equal: false,
            x_labels: true,
        },
    )?;
    if let Some((lo, hi)) = prior {
        let (lo, hi) = (lo.max(win.x0), hi.min(win.x1));
        if lo < hi {
            style::band(
                root,
                &chart,
                &[lo, hi],
                &[win.y0, win.y0],
                &[win.y1, win.y1],
                &PRIOR,
            )?;
        }
    }
    let a = style::px(&chart, (win.x0, r.alpha));
    let b = style::px(&chart, (win.x1, r.alpha));
    style::polyline(root, &[a, b], &REFERENCE, 1, None)?;
    style::text(
        root,
        &format!("α = {}", pct(r.alpha)),
        (b.0 - 4, b.1 + 3),
        &fonts.note().color(&REFERENCE),
        (HPos::Right, VPos::Top),
    )?;
    style::path(root, &chart, &scf, &SCF, 3, None)?;
    style::path(root, &chart, &kf, &KF, 3, Some(style::DASH))?;
    let mut marks = style::marks_of(&chart, &kf);
    marks.extend(style::marks_of(&chart, &scf));
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, &xd, yd))
}
