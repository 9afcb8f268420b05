//! The "series" panel — each plotted component over time: the true value, the KF and SCF centers
//! and intervals (projections of the n-dimensional regions on the component), and the time
//! cursor; one chart per component, stacked, sharing the time axis.
//!
//! When the intervals are tiny next to the component's range (the robots travel 20 m with
//! centimetre regions), the charts show the estimates minus the true value instead (Zoom::Auto;
//! Zoom::Regions forces it, Zoom::Full forbids it), so the reader sees whether 0 — the truth —
//! lies inside each interval.

use super::context::Ctx;
use crate::error::Result;
use crate::plot::figures::Area;
use crate::plot::geom::Win;
use crate::plot::style::{self, pct, Axes, Entry, Marker, Swatch, KF, MEASURE, SCF, TRUTH};
use crate::plot::view::PanelSpec;
use crate::plot::view::{Frame, Zoom};
use crate::sets::Ellipsoid;
use plotters::prelude::*;

/// Components over time with KF and SCF intervals.
pub(crate) static SERIES: PanelSpec = PanelSpec::new(
    "series",
    "state components over time with the Kalman and SCF intervals",
);

/// Center, low and high end of an interval.
type Iv = (f64, f64, f64);

struct Comp {
    k: usize,
    kf: Vec<Option<Iv>>,
    scf: Vec<Option<Iv>>,
    truth: Vec<Option<f64>>,
    meas: Vec<Option<f64>>,
}

fn interval(e: &Ellipsoid, k: usize) -> Result<Iv> {
    let p = e.project(&[k])?;
    let b = p.bounding_box();
    Ok((p.center[0], b.lo[0], b.hi[0]))
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    crate::linalg::sort_increasing(&mut v);
    v[v.len() / 2]
}

pub fn draw<DB: DrawingBackend>(root: &Area<DB>, cx: &Ctx) -> Result<Frame> {
    let r = cx.report;
    let fonts = cx.fonts;
    let steps = r.steps.len();
    let t = cx.t;
    // A stacked chart needs about 120 px: small figures show the first components only.
    let (_, h) = root.dim_in_pixel();
    let room = h as i32 - if fonts.compact { 50 } else { 110 };
    let shown = ((room / 120).max(1) as usize).min(r.plot.len());
    let mut comps = Vec::new();
    for &k in &r.plot[..shown] {
        let mut c = Comp {
            k,
            kf: Vec::with_capacity(steps),
            scf: Vec::with_capacity(steps),
            truth: (1..=steps).map(|s| cx.truth(s, k)).collect(),
            meas: (1..=steps).map(|s| cx.measurement(s, k)).collect(),
        };
        for st in &r.steps {
            c.kf.push(Some(interval(&st.kf, k)?));
            c.scf.push(match &st.scf {
                Some(e) => Some(interval(e, k)?),
                None => None,
            });
        }
        comps.push(c);
    }
    let has_truth = comps.iter().any(|c| c.truth.iter().any(|v| v.is_some()));
    let deviation = has_truth
        && match cx.view.zoom {
            Zoom::Regions => true,
            Zoom::Full => false,
            Zoom::Auto => comps.iter().any(|c| {
                let mut w = Win::empty();
                for v in c.truth.iter().flatten() {
                    w.add_y(*v);
                }
                let half = median(
                    c.kf.iter()
                        .flatten()
                        .map(|iv| 0.5 * (iv.2 - iv.1))
                        .collect(),
                );
                w.height() > 40.0 * half
            }),
        };
    if deviation {
        for c in &mut comps {
            let shift = |v: Option<Iv>, x: Option<f64>| match (v, x) {
                (Some(v), Some(x)) => Some((v.0 - x, v.1 - x, v.2 - x)),
                _ => None,
            };
            for s in 0..steps {
                let x = c.truth[s];
                c.kf[s] = shift(c.kf[s], x);
                c.scf[s] = shift(c.scf[s], x);
                c.meas[s] = match (c.meas[s], x) {
                    (Some(m), Some(x)) => Some(m - x),
                    _ => None,
                };
                c.truth[s] = x.map(|_| 0.0);
            }
        }
    }
    let has_scf = comps.iter().any(|c| c.scf.iter().any(|v| v.is_some()));
    let has_meas = comps.iter().any(|c| c.meas.iter().any(|v| v.is_some()));

    let mut entries = Vec::new();
    if has_truth {
        entries.push(Entry::new(
            if deviation {
                "true value (zero line)"
            } else {
                "true value"
            },
            Swatch::Line {
                color: TRUTH,
                dashed: false,
                width: 2,
            },
        ));
    }
    if has_meas {
        entries.push(
            Entry::new(
                if deviation {
                    "measurement − true value"
                } else {
                    "measurements"
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
    // Each filter's center line, then its interval: KF dashed lines, SCF a solid line and band.
    let kf_interval = Swatch::Line {
        color: KF,
        dashed: true,
        width: 1,
    };
    let scf_interval = Swatch::Region {
        color: SCF,
        dashed: false,
        fill: true,
    };
    let filters = [
        ("KF", KF, true, kf_interval),
        ("SCF", SCF, false, scf_interval),
    ];
    for (name, color, dashed, interval) in filters.into_iter().take(1 + has_scf as usize) {
        entries.push(Entry::new(
            format!("{name} center"),
            Swatch::Line {
                color,
                dashed,
                width: 2,
            },
        ));
        entries.push(Entry::new(
            format!("{name} interval ({})", pct(r.alpha)),
            interval,
        ));
    }

    let record = cx.record();
    let mut notes = vec![format!("shown time {}", record.at("t", t))];
    if shown < r.plot.len() {
        notes.insert(
            0,
            format!(
                "{} of {} components (enlarge the figure for all)",
                shown,
                r.plot.len()
            ),
        );
    }
    if r.n > 1 {
        notes.push(format!(
            "intervals: the {}-dimensional regions Xₜ projected on each component",
            r.n
        ));
    }
    if deviation {
        notes.push(
            "estimates minus the true value (the intervals are tiny next to the trajectory)"
                .to_string(),
        );
    }
    if !has_scf {
        notes.push(cx.scf_missing_note());
    } else if let Some(first) = r.steps.iter().find(|s| s.scf.is_some()).map(|s| s.t) {
        if first > 1 {
            notes.push(format!("SCF from t = {first} (t ≥ n = {})", r.n));
        }
    }
    let title = cx.title("KF and SCF estimates over time");
    let (area, side) = style::titled_legend(root, &fonts, &title, &notes, &entries)?;
    let parts = area.split_evenly((comps.len().max(1), 1));
    // The frame names x in its units, steps (the page's read-out adds the record's time); the
    // drawn axis says what its ticks read.
    let steps_name = "time t (steps)";
    let xd = record.axis_name(steps_name);
    let mut frames: Vec<Frame> = Vec::new();
    for (idx, (c, part)) in comps.iter().zip(&parts).enumerate() {
        let mut win = Win::empty();
        win.add_x(0.0);
        win.add_x(steps as f64 + 1.0);
        for iv in c.kf.iter().chain(&c.scf).flatten() {
            win.add_y(iv.1);
            win.add_y(iv.2);
        }
        for v in c.truth.iter().chain(&c.meas).flatten() {
            win.add_y(*v);
        }
        let p = win.padded(0.0, 0.06);
        let win = Win::new((0.0, steps as f64 + 1.0), (p.y0, p.y1));
        // Frame label: the full name; drawn: the name on the axis for one chart, or a heading
        // above each of a stack with a short axis label.
        let yd = if deviation {
            format!("{} − true value", cx.name(c.k))
        } else {
            cx.name(c.k)
        };
        let stacked = comps.len() > 1;
        let heading_style = fonts.bold(if fonts.compact { 11.5 } else { 13.0 });
        let (part, axis_desc) = if stacked {
            let hh = style::text_size(part, "Xg", &heading_style)?.1 as i32 + 6;
            let short = if deviation {
                "estimate − true"
            } else {
                "value"
            };
            (part.split_vertically(hh).1, short.to_string())
        } else {
            (part.clone(), yd.clone())
        };
        let last = idx + 1 == comps.len();
        let chart = style::time_chart(
            &part,
            &fonts,
            &Axes {
                win,
                x_desc: xd,
                y_desc: &axis_desc,
                x_integer: true,
                equal: false,
                x_labels: last,
            },
            &record,
        )?;
        if stacked {
            let (xr, yr) = chart.plotting_area().get_pixel_range();
            let top = yr.start - 12;
            // The heading names the chart: without its qualifiers, else in the notes' smaller
            // type, before it is ever cut.
            let room = (xr.end - xr.start).max(40) as u32;
            let small = fonts.subtitle();
            let (head, heading_style) =
                match style::without_qualifiers(root, &yd, &heading_style, room)? {
                    Some(h) => (h, heading_style),
                    None => (style::fit_label(root, &yd, &small, room)?, small),
                };
            style::text(
                root,
                &head,
                (xr.start, top),
                &heading_style,
                (
                    plotters::style::text_anchor::HPos::Left,
                    plotters::style::text_anchor::VPos::Bottom,
                ),
            )?;
        }
        let xs = |s: usize| (s + 1) as f64;
        // SCF band in contiguous runs.
        let mut s = 0;
        while s < steps {
            if c.scf[s].is_none() {
                s += 1;
                continue;
            }
            let start = s;
            while s < steps && c.scf[s].is_some() {
                s += 1;
            }
            let run: Vec<(f64, Iv)> = (start..s)
                .filter_map(|q| Some((xs(q), c.scf[q]?)))
                .collect();
            let x: Vec<f64> = run.iter().map(|p| p.0).collect();
            let lo: Vec<f64> = run.iter().map(|p| p.1 .1).collect();
            let hi: Vec<f64> = run.iter().map(|p| p.1 .2).collect();
            style::band(root, &chart, &x, &lo, &hi, &SCF)?;
        }
        let line = |v: &[Option<Iv>], which: usize| -> Vec<(f64, f64)> {
            v.iter()
                .enumerate()
                .filter_map(|(q, iv)| {
                    let iv = (*iv)?;
                    Some((xs(q), [iv.0, iv.1, iv.2][which]))
                })
                .collect()
        };
        for which in [1, 2] {
            style::path(root, &chart, &line(&c.kf, which), &KF, 1, Some((5, 4)))?;
        }
        // The points of a series where it has a value.
        let known = |v: &[Option<f64>]| -> Vec<(f64, f64)> {
            v.iter()
                .enumerate()
                .filter_map(|(q, v)| Some((xs(q), (*v)?)))
                .collect()
        };
        let truth = known(&c.truth);
        style::path(root, &chart, &truth, &TRUTH, 2, None)?;
        style::dots(root, &chart, &known(&c.meas), &MEASURE, 2)?;
        style::path(root, &chart, &line(&c.kf, 0), &KF, 2, Some(style::DASH))?;
        style::path(root, &chart, &line(&c.scf, 0), &SCF, 2, None)?;
        style::cursor(root, &chart, &fonts, t as f64, &record.at("t", t))?;
        if idx == 0 {
            let mut marks = Vec::new();
            for which in [1, 2] {
                marks.extend(style::marks_of(&chart, &line(&c.kf, which)));
                marks.extend(style::marks_of(&chart, &line(&c.scf, which)));
            }
            marks.extend(style::marks_of(&chart, &truth));
            style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
        }
        frames.push(style::frame_of(&chart, steps_name, &yd));
    }
    let mut it = frames.into_iter();
    let mut first = it.next().ok_or_else(|| {
        crate::error::Error::field("plot", "must name one or two state components")
    })?;
    first.more = it.collect();
    Ok(first)
}
