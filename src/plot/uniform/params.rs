//! The "uparams" panel — Fig. 3 of the uniform-innovation paper: the entries of Â over time (one
//! line per entry âᵢⱼ, the true aᵢⱼ as a thin dashed line of the same colour), and below the
//! half-width estimates x̂ᵣ,ᵢ and ŷᵣ,ⱼ with the true half-widths dashed. On the user's data
//! there are no true values: the curves stand alone.

use super::time_series::{
    cell, check, columns, cursor, grid, level, short_labels, stacked, time_win, window_band, TIME,
};
use crate::plot::style::{self, sig, sub, Entry, Swatch, TEXT};

use crate::error::Result;
use crate::plot::figures::{Area, Request};
use crate::plot::view::{Frame, Panel};
use crate::uniform::OnlineStep;
use plotters::prelude::*;

/// A curve of Fig. 3: label, colour, estimates over t = 1 … T, true value (simulation).
type Curve = (String, RGBColor, Vec<(f64, f64)>, Option<f64>);

/// The "uparams" panel — Fig. 3.
pub fn draw<DB: DrawingBackend>(root: &Area<DB>, request: &Request) -> Result<Frame> {
    let (report, view, fonts) = (request.report, request.view, request.fonts);
    let u = check(report, view, Panel::of(&super::time_series::PARAMS))?;
    let (n, steps) = (u.n, u.steps);
    let short = short_labels(root, &fonts);
    let a_true = u.u.theta_true.as_ref().map(|th| &th[0]);
    let m = u.m;
    let mut a_curves: Vec<Curve> = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let k = i * n + j;
            let pts = (1..=steps)
                .map(|s| (s as f64, u.u.steps[s - 1].a[i][j]))
                .collect();
            let label = if n == 1 {
                "â".to_string()
            } else {
                format!("â{}{}", sub(i + 1), sub(j + 1))
            };
            a_curves.push((label, style::series_color(k), pts, a_true.map(|a| a[i][j])));
        }
    }
    let mut r_curves: Vec<Curve> = Vec::new();
    // x̂ᵣ per state, then ŷᵣ per output; colours continue after the n² entries of Â.
    let half_widths: [(&str, usize, Option<&[f64]>, fn(&OnlineStep) -> &[f64]); 2] = [
        ("x̂ᵣ", n, u.u.xr_true.as_deref(), |s| &s.xr),
        ("ŷᵣ", m, u.u.yr_true.as_deref(), |s| &s.yr),
    ];
    for (name, count, truths, estimates) in half_widths {
        for i in 0..count {
            let truth = truths.map(|v| v[i]);
            let pts = (1..=steps)
                .map(|s| (s as f64, estimates(&u.u.steps[s - 1])[i]))
                .collect();
            let label = if count == 1 {
                name.to_string()
            } else {
                format!("{name},{}", sub(i + 1))
            };
            let color = style::series_color(n * n + r_curves.len());
            r_curves.push((label, color, pts, truth));
        }
    }
    let line = |color: RGBColor| Swatch::Line {
        color,
        dashed: false,
        width: 2,
    };
    let mut entries: Vec<Entry> = Vec::new();
    for (label, color, _, truth) in a_curves.iter().chain(&r_curves) {
        entries.push(Entry::new(
            match truth {
                Some(v) if !short => format!("{label} (true {})", sig(*v)),
                _ => label.clone(),
            },
            line(*color),
        ));
    }
    if !u.is_data() {
        entries.push(Entry::new(
            if short {
                "true value"
            } else {
                "true value (same colour)"
            },
            Swatch::Line {
                color: TEXT,
                dashed: true,
                width: 1,
            },
        ));
    }
    let at = &u.u.at;
    let mut notes = vec![format!(
        "Θ̂ and the half-widths after each step of the {}, window ∂ = {}",
        u.estimator(),
        u.u.window
    )];
    notes.push(match at.true_objective {
        // The objective belongs to the window at `at.time`: at another cursor it is not shown.
        _ if !u.at_window() => format!(
            "t = {}: the MAP objective is not in this report (it holds t = {})",
            u.t, at.time
        ),
        Some(truth) => format!(
            "the MAP estimate minimises Σx̂ᵣ + Σŷᵣ: {} at t = {} against {} at the true half-widths",
            sig(at.objective),
            at.time,
            sig(truth)
        ),
        None => format!(
            "the MAP estimate minimises Σx̂ᵣ + Σŷᵣ: {} at t = {}",
            sig(at.objective),
            at.time
        ),
    });
    if u.is_data() {
        notes.insert(
            0,
            "your data: no true values (Θ's prior box is around the model's Θ)".to_string(),
        );
    }
    notes.push("a finite window forgets: no convergence is to be expected".to_string());
    let (_, layout) = columns(root, 1);
    let (rows, side) = grid(
        root,
        &report.figure,
        &fonts,
        [
            "Fig. 3: estimates of A and of the noise half-widths",
            "Parameter A estimation and noise boundary estimation (Pavelková, Fig. 3)",
        ],
        &notes,
        &entries,
        &[1, 1],
        1,
        layout,
    )?;
    let mut frames = Vec::new();
    let mut marks = Vec::new();
    let parts: [(&[Curve], String, bool); 2] = [
        (
            &a_curves,
            if short {
                "âᵢⱼ".into()
            } else {
                "entries âᵢⱼ of Â".into()
            },
            false,
        ),
        (
            &r_curves,
            if short {
                "x̂ᵣ, ŷᵣ".into()
            } else {
                "half-widths x̂ᵣ, ŷᵣ".into()
            },
            true,
        ),
    ];
    for (row, (curves, yd, half)) in parts.iter().enumerate() {
        let Some(part) = &rows[row][0] else { continue };
        let win = time_win(
            steps,
            curves
                .iter()
                .flat_map(|c| c.2.iter().map(|p| p.1).chain(c.3))
                .chain(if *half { Some(0.0) } else { None }),
        );
        let chart = cell(
            root,
            part,
            &fonts,
            None,
            &u.time_axes(win, yd, layout.x_labels(row, 2)),
            &u.record,
        )?;
        window_band(root, &chart, &u)?;
        for (_, color, _, truth) in curves.iter() {
            if let Some(v) = truth {
                level(root, &chart, win, *v, color, 1, Some((6, 4)))?;
            }
        }
        for (_, color, pts, _) in curves.iter() {
            style::path(root, &chart, pts, color, 2, None)?;
            marks.extend(style::marks_of(&chart, pts));
        }
        cursor(root, &chart, &fonts, &u, row == 0)?;
        if row == 0 {
            style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
        }
        frames.push(style::frame_of(&chart, TIME, yd));
    }
    Ok(stacked(frames.into_iter()).unwrap_or_else(|| Frame {
        x_range: (0.0, 1.0),
        y_range: (0.0, 1.0),
        plot_area: (0, 0, 1, 1),
        x_label: String::new(),
        y_label: String::new(),
        more: vec![],
        legends: vec![],
    }))
}
