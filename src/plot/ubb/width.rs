//! The "ubbwidth" panel — over the steps k, the widths hi − lo of the interval hull of x(k+1) in
//! the two `plane` components (and 2·radius over all components when r > 2; the one component
//! when r = 1) with the Theorem 4 bound 2·τ‖B‖/(1 − ‖A‖e^{1/α}) on the width of the a-priori
//! set dashed (when it applies) and the step of the report's set as a cursor; below (figures
//! at least 460 px high), the true components inside their hull bands. With `ubb.set`
//! "filtered" the same for the filtered sets of x(k) ([`super::set::Chosen`]).

use super::set::{check, Chosen, HULL, SECOND, SET};
use crate::plot::geom::Win;
use crate::plot::style::{self, num, sub, Axes, Entry, RecordTimes, Swatch, MUTED};
use crate::scenario::TimeIndex;

use crate::error::Result;
use crate::plot::figures::{Area, Request};
use crate::plot::view::{Frame, Panel};
use plotters::prelude::*;

const STEP: &str = "step k (set of x(k+1) from y(0 … k))";
const STEP_FILTERED: &str = "step k (set of x(k) from y(0 … k))";
const STEP_SHORT: &str = "step k";

fn time_win(k0: f64, k1: f64, ys: impl Iterator<Item = f64>) -> Win {
    let x = if k1 > k0 {
        (k0, k1)
    } else {
        (k0 - 0.5, k0 + 0.5)
    };
    Win::time(x, ys)
}

/// The "ubbwidth" panel.
pub fn draw<DB: DrawingBackend>(root: &Area<DB>, request: &Request) -> Result<Frame> {
    let (report, view, fonts) = (request.report, request.view, request.fonts);
    let u = check(report, Panel::of(&super::set::WIDTH_PANEL))?;
    let chosen = Chosen::of(u);
    let steps = chosen.steps();
    // The plotted components: the plane's two, or the one state.
    let comps: Vec<usize> = if u.r == 1 { vec![0] } else { u.plane.to_vec() };
    let colors = [SET, SECOND];
    let short = fonts.compact;
    let cursor_k = view.time.unwrap_or(u.at.k);
    // Step k is row k of the record (Tempo's y(k)).
    let record = RecordTimes::of(&report.figure, TimeIndex::ZeroBased);
    let ks: Vec<f64> = steps.iter().map(|(k, _)| *k as f64).collect();
    let width = |c: usize| -> Vec<f64> { steps.iter().map(|(_, h)| h.hi[c] - h.lo[c]).collect() };
    let widths: Vec<Vec<f64>> = comps.iter().map(|&c| width(c)).collect();
    let wmax: Vec<f64> = steps.iter().map(|(_, h)| 2.0 * h.radius).collect();
    let bound = u.smoothing.limit.filter(|l| l.is_finite()).map(|l| 2.0 * l);
    let Some(&k0) = ks.first() else {
        return Err(crate::error::Error::field(
            "report.ubb",
            format!("has no step with a bounded {} to draw", chosen.name()),
        ));
    };
    let k1 = (u.steps.max(1) - 1) as f64;
    let names: Vec<String> = comps.iter().map(|&c| format!("x{}", sub(c + 1))).collect();
    let at_lag = if chosen.filtered { "(k)" } else { "(k+1)" };

    let mut notes = vec![format!(
        "interval hull of the {} of {}, {} bounds, window {} steps",
        if chosen.filtered {
            "filtered set"
        } else {
            "feasible set"
        },
        chosen.state_symbol(),
        super::set::norm_name(u.norm),
        u.window
    )];
    match (bound, &u.smoothing.note) {
        (Some(b), _) => notes.push(format!(
            "Theorem 4 (as k → ∞, not at every k): lim sup width ≤ 2·τ‖B‖/(1−‖A‖·exp(1/α)) = {} (‖A‖·exp(1/α) = {})",
            num(b, 3),
            num(u.smoothing.ratio, 3)
        )),
        (None, _) if u.smoothing.b_norm == 0.0 || u.p == 0 => notes
            .push("no Theorem 4 bound: no process noise, the unknowns are x(0) alone".to_string()),
        (None, _) => notes.push(format!(
            "no Theorem 4 bound (‖A‖·exp(1/α) = {} ≥ 1)",
            num(u.smoothing.ratio, 3)
        )),
    }
    let truth = u.x_true.as_ref();
    let stacked = root.dim_in_pixel().1 >= 460;

    let line = |color, dashed, width| Swatch::Line {
        color,
        dashed,
        width,
    };
    let mut entries: Vec<Entry> = names
        .iter()
        .zip(colors)
        .map(|(name, color)| Entry::new(format!("width of {name}{at_lag}"), line(color, false, 2)))
        .collect();
    if u.r > 2 {
        entries.push(Entry::new(
            format!("2·radius (all {} components)", u.r),
            line(MUTED, false, 1),
        ));
    }
    if bound.is_some() {
        entries.push(Entry::new(
            if short {
                "Theorem 4 bound on lim sup".to_string()
            } else {
                "Theorem 4 bound on lim sup (2·τ‖B‖/(1−‖A‖·exp(1/α)))".to_string()
            },
            line(HULL, true, 2),
        ));
    }
    if stacked {
        entries.push(Entry::new(
            if truth.is_some() {
                "below: truth in its hull band"
            } else {
                "below: hull bands, centres"
            },
            Swatch::Region {
                color: SET,
                dashed: false,
                fill: true,
            },
        ));
    }
    let what = "Width of the interval hull over k";
    let title = style::title(&report.figure, &fonts, what, what);
    let (area, side) = style::titled_legend(root, &fonts, &title, &notes, &entries)?;

    let (top, bottom) = if stacked {
        let h = area.dim_in_pixel().1 as f64;
        let (a, b) = area.split_vertically((0.58 * h).round() as i32);
        (a, Some(b))
    } else {
        (area, None)
    };

    // Widths.
    let win = time_win(
        k0,
        k1,
        widths
            .iter()
            .flatten()
            .chain(if u.r > 2 { wmax.as_slice() } else { &[] })
            .copied()
            .chain(bound)
            .chain(std::iter::once(0.0)),
    );
    let y_desc = if short {
        "width".to_string()
    } else {
        "hull width hi − lo".to_string()
    };
    let steps_name = match (short, chosen.filtered) {
        (true, _) => STEP_SHORT,
        (false, false) => STEP,
        (false, true) => STEP_FILTERED,
    };
    let step_label = record.axis_name(steps_name);
    let axes = Axes {
        win,
        x_desc: step_label,
        y_desc: &y_desc,
        x_integer: true,
        equal: false,
        x_labels: bottom.is_none(),
    };
    let chart = style::time_chart(&top, &fonts, &axes, &record)?;
    let mut marks = Vec::new();
    if let Some(b) = bound {
        style::path(
            root,
            &chart,
            &[(win.x0, b), (win.x1, b)],
            &HULL,
            2,
            Some(style::DASH),
        )?;
        marks.extend(style::marks_of(&chart, &[(win.x0, b), (win.x1, b)]));
    }
    let pts =
        |ys: &[f64]| -> Vec<(f64, f64)> { ks.iter().copied().zip(ys.iter().copied()).collect() };
    if u.r > 2 {
        style::path(root, &chart, &pts(&wmax), &MUTED, 1, None)?;
    }
    for (ys, color) in widths.iter().zip(colors) {
        let p = pts(ys);
        style::path(root, &chart, &p, &color, 2, None)?;
        if p.len() == 1 {
            style::dots(root, &chart, &p, &color, 3)?;
        }
        marks.extend(style::marks_of(&chart, &p));
    }
    style::cursor(
        root,
        &chart,
        &fonts,
        cursor_k as f64,
        &record.at("k", cursor_k),
    )?;
    let mut frame = style::frame_of(&chart, steps_name, &y_desc);

    if let Some(bottom) = bottom {
        let mut ys: Vec<f64> = Vec::new();
        for (k, h) in &steps {
            for &c in &comps {
                ys.extend([h.lo[c], h.hi[c]]);
                if let Some(x) = chosen.truth(*k) {
                    ys.push(x[c]);
                }
            }
        }
        let win2 = time_win(k0, k1, ys.into_iter());
        let y2 = names
            .iter()
            .map(|n| format!("{n}{at_lag}"))
            .collect::<Vec<_>>()
            .join(", ");
        let axes2 = Axes {
            win: win2,
            x_desc: step_label,
            y_desc: &y2,
            x_integer: true,
            equal: false,
            x_labels: true,
        };
        let chart2 = style::time_chart(&bottom, &fonts, &axes2, &record)?;
        for (&c, color) in comps.iter().zip(colors) {
            let lo: Vec<f64> = steps.iter().map(|(_, h)| h.lo[c]).collect();
            let hi: Vec<f64> = steps.iter().map(|(_, h)| h.hi[c]).collect();
            style::band(root, &chart2, &ks, &lo, &hi, &color)?;
            style::path(root, &chart2, &pts(&lo), &color, 1, None)?;
            style::path(root, &chart2, &pts(&hi), &color, 1, None)?;
        }
        for (&c, color) in comps.iter().zip(colors) {
            let line: Vec<(f64, f64)> = match truth {
                Some(_) => steps
                    .iter()
                    .filter_map(|(k, _)| chosen.truth(*k).map(|v| (*k as f64, v[c])))
                    .collect(),
                None => steps
                    .iter()
                    .map(|(k, h)| (*k as f64, h.center[c]))
                    .collect(),
            };
            style::path(
                root,
                &chart2,
                &line,
                &color,
                2,
                if truth.is_some() {
                    None
                } else {
                    Some(style::DASH)
                },
            )?;
        }
        style::cursor(root, &chart2, &fonts, cursor_k as f64, "")?;
        frame.more.push(style::frame_of(&chart2, steps_name, &y2));
    }
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(frame)
}
