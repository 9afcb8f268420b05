//! The figures of conformal reports (method `"conformal"`): `conformalset` (the split
//! conformal region of the state at the target time beside the Kalman χ² region, both
//! ellipses of the filter's P_t around x̂_t, with the truth) and `aciband` (the first output
//! over time with ACI's interval ŷ ± q_t·√S beside the Kalman interval ŷ ± √χ²·√S, the misses
//! of each marked; below, on figures at least 460 px high, both running coverages against
//! the level).

use crate::error::{Error, Result};
use crate::plot::figures::{Area, Canvas, CompareLook, Figures, Request, SetFill};
use crate::plot::geom::Win;
use crate::plot::style::{
    self, num, percent, sub, Axes, Entry, Marker, RecordTimes, Swatch, KF, MUTED, TRUTH,
};
use crate::plot::view::{Frame, Panel, PanelSpec};
use crate::scenario::{ConformalReport, Report, TimeIndex};
use plotters::prelude::*;

/// Conformal's colour (reddish purple, Okabe–Ito).
const CONFORMAL: RGBColor = RGBColor(204, 121, 167);
const ELLIPSE_POINTS: usize = 120;

static SET_PANEL: PanelSpec = PanelSpec::new(
    "conformalset",
    "the split conformal region of the state at the target time beside the Kalman region of the same filter, with the estimate and the truth",
);
static ACI_PANEL: PanelSpec = PanelSpec::new(
    "aciband",
    "the first output over time with the adaptive conformal interval and the Kalman interval, each one's misses marked, and their running coverage",
);
static PANELS: [Panel; 2] = [Panel::of(&SET_PANEL), Panel::of(&ACI_PANEL)];

/// The figures of a conformal report.
pub(crate) struct ConformalFigures;

fn conformal_of(report: &Report) -> Result<&ConformalReport> {
    report.conformal.as_ref().ok_or_else(|| {
        Error::field(
            "report.conformal",
            "is missing: the report is not a conformal report",
        )
    })
}

impl Figures for ConformalFigures {
    fn panels(&self) -> &'static [Panel] {
        &PANELS
    }
    fn reports(&self) -> &'static str {
        "a conformal"
    }
    fn draw(&self, panel: Panel, canvas: Canvas<'_>, request: &Request) -> Result<Frame> {
        let c = conformal_of(request.report)?;
        if c.aci.steps.is_empty() || c.region.center.is_empty() {
            return Err(Error::field("report.conformal", "has no steps to draw"));
        }
        canvas.paint(|root| {
            if panel == Panel::of(&SET_PANEL) {
                draw_set(root, request, c)
            } else {
                draw_aci(root, request, c)
            }
        })
    }
    fn compare_look(&self) -> Option<CompareLook> {
        // An outline in its own colour: it shares the Kalman ellipse's centre and shape.
        Some(CompareLook {
            color: CONFORMAL,
            label: "conformal",
            dashed: false,
            fill: SetFill::None,
            layer: 2,
        })
    }
}

/// The "conformalset" panel.
fn draw_set<DB: DrawingBackend>(
    root: &Area<DB>,
    request: &Request,
    c: &ConformalReport,
) -> Result<Frame> {
    let (report, fonts) = (request.report, request.fonts);
    let short = fonts.compact;
    let plane: Vec<usize> = report.plot.clone();
    let two_d = plane.len() == 2;
    // The region is of x_{t+τ} from y_1 … y_t.
    let t = c.time + c.tau;
    let law = match c.nu {
        Some(nu) => format!("Student-t noise, ν = {}", num(nu, 3)),
        None => "Gaussian noise".to_string(),
    };
    let comp = |i: usize| format!("x{}", sub(i + 1));
    // The regions projected on the plane (the shadow of an n-dimensional ellipsoid).
    let outline = |e: &crate::sets::Ellipsoid| -> Result<Vec<(f64, f64)>> {
        if two_d {
            e.project(&plane)?.boundary_2d(ELLIPSE_POINTS)
        } else {
            let p = e.project(&plane)?;
            let h = (p.cov[0][0] * p.radius2).sqrt();
            Ok(vec![(p.center[0] - h, 0.0), (p.center[0] + h, 0.0)])
        }
    };
    let conf = outline(&c.region)?;
    let kal = outline(&c.kalman)?;
    let center = (
        c.region.center[plane[0]],
        if two_d {
            c.region.center[plane[1]]
        } else {
            0.0
        },
    );
    let truth = c
        .truth
        .as_ref()
        .map(|x| (x[plane[0]], if two_d { x[plane[1]] } else { 0.0 }));
    let mut w = Win::empty();
    w.add_points(&conf);
    w.add_points(&kal);
    w.add(center.0, center.1);
    if let Some(p) = truth {
        w.add(p.0, p.1);
    }
    if !two_d {
        w.add(center.0, -1.0);
        w.add(center.0, 1.0);
    }
    let win = w.padded(0.15, 0.15);
    let mut notes = vec![
        format!(
            "radius² {} (the {}th smallest of N = {} calibration scores, {law}) vs χ² {}",
            num(c.radius2, 4),
            c.rank,
            c.calibration,
            num(c.chi2_radius2, 4)
        ),
        format!(
            "promise on average over runs: {} ≤ P ≤ {}",
            percent(c.lower),
            percent(c.upper)
        ),
    ];
    // The verdicts go in the title block: inside the chart they covered the regions.
    notes.push(match (c.inside, c.kf_inside) {
        (Some(a), Some(b)) => format!(
            "truth {} the conformal region, {} the Kalman one (score {})",
            if a { "in" } else { "OUTSIDE" },
            if b { "in" } else { "OUTSIDE" },
            num(c.truth_score.unwrap_or(f64::NAN), 3)
        ),
        _ => "measured data: no true state".to_string(),
    });
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
            "estimate x̂"
        } else {
            "Kalman estimate x̂ₜ (35a)"
        },
        marker(Marker::Cross, KF),
    ));
    // The two regions' entries: the same ellipse shape, two radii.
    let region = |name: &str, color, dashed, fill| {
        Entry::new(
            if short {
                name.to_string()
            } else {
                format!("{name} {} region", percent(c.level))
            },
            Swatch::Region {
                color,
                dashed,
                fill,
            },
        )
    };
    entries.push(region(
        if short {
            "conformal"
        } else {
            "split conformal"
        },
        CONFORMAL,
        false,
        true,
    ));
    entries.push(region("Kalman χ²", KF, true, false));
    let what = if c.tau == 0 {
        format!(
            "State region at {}: conformal vs Kalman",
            RecordTimes::of(&report.figure, TimeIndex::OneBased).at("t", t)
        )
    } else {
        format!(
            "Region of x{} from y₁ … y{}: conformal vs Kalman",
            sub(t),
            sub(c.time)
        )
    };
    let title = style::title(&report.figure, &fonts, &what, &what);
    let (x_desc, y_desc) = (
        comp(plane[0]),
        if two_d { comp(plane[1]) } else { String::new() },
    );
    let (area, side) = style::titled_legend_beside(root, &fonts, &title, &notes, &entries)?;
    let chart = if two_d {
        style::equal_chart(&area, &fonts, win, &x_desc, &y_desc)?
    } else {
        style::chart(
            &area,
            &fonts,
            &Axes {
                win,
                x_desc: &x_desc,
                y_desc: "",
                x_integer: false,
                equal: false,
                x_labels: true,
            },
        )?
    };
    let mut marks = Vec::new();
    if two_d {
        style::region(root, &chart, &conf, &CONFORMAL, false, true)?;
        style::region(root, &chart, &kal, &KF, true, false)?;
    } else {
        let lift = |pts: &[(f64, f64)], y: f64| -> Vec<(f64, f64)> {
            pts.iter().map(|&(x, _)| (x, y)).collect()
        };
        style::path(root, &chart, &lift(&conf, 0.3), &CONFORMAL, 4, None)?;
        style::path(root, &chart, &lift(&kal, -0.3), &KF, 4, Some(style::DASH))?;
    }
    marks.extend(style::marks_of(&chart, &conf));
    marks.extend(style::marks_of(&chart, &kal));
    let mut points = vec![(center, Marker::Cross, KF, "estimate")];
    points.extend(truth.map(|p| (p, Marker::Diamond, TRUTH, "true state")));
    let outside = style::markers_inside(root, &chart, &points, &mut marks)?;
    let mut chart_notes = Vec::new();
    if report.n > 2 && two_d {
        chart_notes.push(format!(
            "n = {}: the shadows on {}, {}",
            report.n,
            comp(plane[0]),
            comp(plane[1])
        ));
    }
    if !outside.is_empty() {
        chart_notes.push(format!("outside the window: {}", outside.join(", ")));
    }
    style::chart_notes(root, &chart, &fonts, &chart_notes, &mut marks)?;
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, &x_desc, &y_desc))
}

/// The "aciband" panel.
fn draw_aci<DB: DrawingBackend>(
    root: &Area<DB>,
    request: &Request,
    c: &ConformalReport,
) -> Result<Frame> {
    let (report, fonts) = (request.report, request.fonts);
    let short = fonts.compact;
    let record = RecordTimes::of(&report.figure, TimeIndex::OneBased);
    let a = &c.aci;
    let ts: Vec<f64> = a.steps.iter().map(|s| s.t as f64).collect();
    let y: Vec<f64> = a
        .steps
        .iter()
        .map(|s| {
            report
                .y
                .get(s.t - 1)
                .and_then(|y| y.first())
                .copied()
                .unwrap_or(f64::NAN)
        })
        .collect();
    let kf_lo: Vec<f64> = a
        .steps
        .iter()
        .map(|s| s.y_hat[0] - a.kf_radius * s.sd[0])
        .collect();
    let kf_hi: Vec<f64> = a
        .steps
        .iter()
        .map(|s| s.y_hat[0] + a.kf_radius * s.sd[0])
        .collect();
    // The ACI interval where it is a finite, non-empty set.
    let finite: Vec<(f64, f64, f64)> = a
        .steps
        .iter()
        .filter_map(|s| {
            let q = s.q.filter(|_| !s.empty)?;
            Some((
                s.t as f64,
                s.y_hat[0] - q * s.sd[0],
                s.y_hat[0] + q * s.sd[0],
            ))
        })
        .collect();
    let stacked = root.dim_in_pixel().1 >= 460;
    let mut notes = vec![format!(
        "ACI (Gibbs & Candès): γ = {}, target miss rate α = {}; over the {} with an ACI interval ACI covers {}, Kalman {}",
        num(a.gamma, 3),
        num(a.miss, 3),
        if a.covered_steps == 1 { "1 step".to_string() } else { format!("{} steps", a.covered_steps) },
        percent(a.coverage),
        percent(a.kf_coverage)
    )];
    // The steps kept apart from that coverage, said once.
    let mut apart = Vec::new();
    if a.warmup > 0 {
        apart.push(format!(
            "{} warm-up {} (the whole line: too few past scores)",
            a.warmup,
            if a.warmup == 1 { "step" } else { "steps" }
        ));
    }
    if a.whole_line > 0 {
        apart.push(format!("{} later whole-line", a.whole_line));
    }
    if a.gaps > 0 {
        apart.push(format!(
            "{} {} with a gap (not scored, no dot)",
            a.gaps,
            if a.gaps == 1 { "step" } else { "steps" }
        ));
    }
    if !apart.is_empty() {
        notes.push(format!("apart: {}", apart.join(", ")));
    }
    if let (Some(w), Some(k)) = (a.worst, a.kf_worst) {
        notes.push(format!(
            "worst {}: ACI {} (from t = {}), Kalman {} (from t = {})",
            crate::error::counted(a.window, "step", "steps"),
            percent(w.0),
            w.1,
            percent(k.0),
            k.1
        ));
    }
    if report.q > 1 {
        notes.push(format!(
            "{} outputs: y₁ shown; the sets are ellipsoids in normalized units",
            report.q
        ));
    }
    let line = |color, dashed, width| Swatch::Line {
        color,
        dashed,
        width,
    };
    let entries = vec![
        Entry::new(
            "measured y₁",
            Swatch::Marker {
                shape: Marker::Dot,
                color: MUTED,
                size: 3,
            },
        ),
        Entry::new(
            if short {
                "ACI interval"
            } else {
                "ACI interval ŷ ± qₜ·√S"
            },
            Swatch::Region {
                color: CONFORMAL,
                dashed: false,
                fill: true,
            },
        ),
        Entry::new(
            if short {
                "Kalman interval"
            } else {
                "Kalman interval ŷ ± √χ²·√S"
            },
            line(KF, true, 2),
        ),
        Entry::new(
            "ACI miss",
            Swatch::Marker {
                shape: Marker::Ring,
                color: CONFORMAL,
                size: 5,
            },
        ),
        Entry::new(
            "Kalman miss",
            Swatch::Marker {
                shape: Marker::Cross,
                color: KF,
                size: 5,
            },
        ),
    ];
    let what = "One-step output intervals: ACI vs Kalman";
    let title = style::title(&report.figure, &fonts, what, what);
    let (area, side) = style::titled_legend(root, &fonts, &title, &notes, &entries)?;
    let (top, bottom) = if stacked {
        let h = area.dim_in_pixel().1 as f64;
        let (p, q) = area.split_vertically((0.62 * h).round() as i32);
        (p, Some(q))
    } else {
        (area, None)
    };
    let (t0, t1) = (ts[0], ts[ts.len() - 1].max(ts[0] + 1.0));
    // A gap's NaN takes no part in the window.
    let ys = y
        .iter()
        .chain(&kf_lo)
        .chain(&kf_hi)
        .copied()
        .chain(finite.iter().flat_map(|&(_, lo, hi)| [lo, hi]))
        .filter(|v| v.is_finite());
    let win = Win::time((t0, t1), ys);
    let steps_name = "time t";
    let x_desc = record.axis_name(steps_name);
    let y_desc = "output y₁";
    let chart = style::time_chart(
        &top,
        &fonts,
        &Axes {
            win,
            x_desc,
            y_desc,
            x_integer: true,
            equal: false,
            x_labels: bottom.is_none(),
        },
        &record,
    )?;
    // The band in runs of consecutive finite steps.
    let mut run: Vec<(f64, f64, f64)> = Vec::new();
    let flush = |run: &mut Vec<(f64, f64, f64)>| -> Result<()> {
        if run.len() >= 2 {
            let xs: Vec<f64> = run.iter().map(|r| r.0).collect();
            let lo: Vec<f64> = run.iter().map(|r| r.1).collect();
            let hi: Vec<f64> = run.iter().map(|r| r.2).collect();
            style::band(root, &chart, &xs, &lo, &hi, &CONFORMAL)?;
        }
        run.clear();
        Ok(())
    };
    let mut last = f64::NAN;
    for &f in &finite {
        if f.0 != last + 1.0 {
            flush(&mut run)?;
        }
        run.push(f);
        last = f.0;
    }
    flush(&mut run)?;
    let pts =
        |v: &[f64]| -> Vec<(f64, f64)> { ts.iter().copied().zip(v.iter().copied()).collect() };
    style::path(root, &chart, &pts(&kf_lo), &KF, 1, Some(style::DASH))?;
    style::path(root, &chart, &pts(&kf_hi), &KF, 1, Some(style::DASH))?;
    // A gap is a break in the dots: nothing is drawn at a step whose y₁ is missing.
    let measured: Vec<(f64, f64)> = pts(&y).into_iter().filter(|p| p.1.is_finite()).collect();
    style::dots(root, &chart, &measured, &MUTED, 2)?;
    let mut marks = style::marks_of(&chart, &measured);
    for (s, &yv) in a.steps.iter().zip(&y) {
        if !yv.is_finite() {
            continue;
        }
        let p = (s.t as f64, yv);
        if s.err == Some(true) {
            style::marker_inside(root, &chart, p, Marker::Ring, &CONFORMAL, &mut marks)?;
        }
        if s.kf_err == Some(true) {
            style::marker_inside(root, &chart, p, Marker::Cross, &KF, &mut marks)?;
        }
    }
    let mut frame = style::frame_of(&chart, steps_name, y_desc);
    if let Some(bottom) = bottom {
        // The running coverage over the steps with an ACI interval (as `coverage` counts:
        // warm-up, whole-line and gap steps apart).
        let counted: Vec<_> = a
            .steps
            .iter()
            .filter(|s| s.err.is_some() && (s.q.is_some() || s.empty))
            .collect();
        let running = |kf: bool| -> Vec<(f64, f64)> {
            let mut hits = 0usize;
            counted
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    let e = if kf { s.kf_err } else { s.err };
                    hits += usize::from(e == Some(false));
                    (s.t as f64, hits as f64 / (i + 1) as f64)
                })
                .collect()
        };
        let aci = running(false);
        let kf = running(true);
        let lo = aci
            .iter()
            .chain(&kf)
            .skip(0)
            .map(|p| p.1)
            .fold(1.0 - a.miss, f64::min)
            .max(0.0);
        let win2 = Win::time((t0, t1), [lo, 1.0].into_iter());
        let y2 = "running coverage";
        let chart2 = style::time_chart(
            &bottom,
            &fonts,
            &Axes {
                win: win2,
                x_desc,
                y_desc: y2,
                x_integer: true,
                equal: false,
                x_labels: true,
            },
            &record,
        )?;
        style::path(
            root,
            &chart2,
            &[(t0, 1.0 - a.miss), (t1, 1.0 - a.miss)],
            &MUTED,
            1,
            Some(style::DOT),
        )?;
        style::path(root, &chart2, &aci, &CONFORMAL, 2, None)?;
        style::path(root, &chart2, &kf, &KF, 2, Some(style::DASH))?;
        frame.more.push(style::frame_of(&chart2, steps_name, y2));
    }
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(frame)
}
