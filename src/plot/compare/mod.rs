//! The compare panel ([`"compare"`](COMPARE)): every method's set for the same state (x_{t+1} or
//! x_t) in the state plane, on equal axes, with the truth ◇ when simulated. Each method has one
//! look, asked of its figures (`Figures::compare_look`: colour, legend label, dash, fill and
//! layer): its panel's colour where the panels' colours differ (Kalman orange dashed, SCF blue,
//! LSCR black over its yellow tint); the others take the next colours of the palette so that
//! six sets stay told apart. The panel loops over the sets and never asks a method's kind. A method the view hides ([`View::hide`]) is left out of the
//! picture, the window and the legend.

use crate::error::{Error, Result};
use crate::method::Method;
use crate::plot::figures::Area;
use crate::plot::figures::{Canvas, CompareLook, Figures, Request, SetFill};
use crate::plot::geom::Win;
use crate::plot::geom::{clip_polygon, clip_polyline};
use crate::plot::style::{self, Entry, Marker, Swatch, TRUTH};
use crate::plot::view::PanelSpec;
use crate::plot::view::{Frame, Panel, Zoom};
use crate::scenario::compare::{MethodSet, PlaneSet, Target};
use crate::scenario::{CompareReport, Report};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

/// A set more than this many times the median set's extent is cut at the window (zoom "auto").
const FOCUS: f64 = 6.0;
/// Points on each drawn ellipse.
const ELLIPSE_POINTS: usize = 120;

/// Every method's set for the same state on one record, in the state plane, with the truth.
pub(crate) static COMPARE: PanelSpec = PanelSpec::new("compare", "every method's set for the same state in the state plane: Kalman, SCF and GLLS ellipses, the LSCR region, Tempo's and the uniform-LP polygons, and the truth");

static PANELS: [Panel; 1] = [Panel::of(&COMPARE)];

/// The figures of a compare report.
pub(crate) struct CompareFigures;

impl Figures for CompareFigures {
    fn panels(&self) -> &'static [Panel] {
        &PANELS
    }
    fn reports(&self) -> &'static str {
        "a compare"
    }
    fn draw(&self, _panel: Panel, canvas: Canvas<'_>, request: &Request) -> Result<Frame> {
        check(request.report, request.figures_of)?;
        canvas.paint(|root| draw(root, request))
    }
}

/// The look of `m`'s set (`Figures::compare_look`), or an error for a method compare does
/// not draw.
fn look(figures_of: FiguresOf, m: Method) -> Result<CompareLook> {
    figures_of(m).compare_look().ok_or_else(|| {
        Error::field(
            "report.compare.at.sets",
            format!("holds a set of \"{m}\", which the compare panel does not draw"),
        )
    })
}

/// The registry, as handed down in a [`Request`].
type FiguresOf = fn(Method) -> &'static dyn Figures;

pub(crate) fn check(report: &Report, figures_of: FiguresOf) -> Result<&CompareReport> {
    let c = report.compare.as_ref().ok_or_else(|| {
        Error::field(
            "panel",
            format!(
                "\"compare\" draws a compare report, but this report is of method \"{}\": run a scenario with \"method\": \"compare\"",
                report.method
            ),
        )
    })?;
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    // The plane's components: two (a plane of sets), or one (intervals of a scalar state).
    let dims = report.plot.len();
    if !(1..=2).contains(&dims) {
        return Err(Error::field(
            "report.plot",
            format!("names {dims} components: a compare draws a plane (two) or a line (one)"),
        ));
    }
    for s in &c.at.sets {
        look(figures_of, s.method)?;
        let ok = match &s.set {
            Some(PlaneSet::Ellipse(e)) => {
                dims == 2
                    && e.dim() == 2
                    && finite(&e.center)
                    && e.cov.iter().all(|r| r.len() == 2 && finite(r))
            }
            Some(PlaneSet::Polygon { vertices }) => dims == 2 && vertices.iter().all(|v| finite(v)),
            Some(PlaneSet::Region { loops, .. }) => {
                dims == 2 && loops.iter().all(|l| l.points.iter().all(|p| finite(p)))
            }
            Some(PlaneSet::Interval { lo, hi }) => dims == 1 && finite(&[*lo, *hi]) && lo <= hi,
            None => true,
        };
        if !ok {
            return Err(Error::field(
                "report.compare.at.sets",
                format!(
                    "holds a set of \"{}\" that is not a finite {dims}-D set",
                    s.method
                ),
            ));
        }
    }
    if c.at
        .truth
        .as_ref()
        .is_some_and(|x| x.len() != dims || !finite(x))
    {
        return Err(Error::field(
            "report.compare.at.truth",
            format!("must be {dims} finite numbers (the true state in the plane)"),
        ));
    }
    Ok(c)
}

/// The drawable outline(s) of a set: closed loops of points.
fn loops(s: &MethodSet) -> Result<Vec<Vec<(f64, f64)>>> {
    Ok(match &s.set {
        Some(PlaneSet::Ellipse(e)) => vec![e.boundary_2d(ELLIPSE_POINTS)?],
        Some(PlaneSet::Polygon { vertices }) => {
            vec![vertices.iter().map(|p| (p[0], p[1])).collect()]
        }
        Some(PlaneSet::Region { loops, .. }) => loops
            .iter()
            .map(|l| l.points.iter().map(|p| (p[0], p[1])).collect())
            .collect(),
        // An interval is drawn on its row ([`draw_intervals`]), not as a loop.
        Some(PlaneSet::Interval { .. }) | None => Vec::new(),
    })
}

/// The "compare" panel.
pub fn draw<DB: DrawingBackend>(root: &Area<DB>, request: &Request) -> Result<Frame> {
    let (report, view, fonts) = (request.report, request.view, request.fonts);
    let figures_of = request.figures_of;
    let c = check(report, figures_of)?;
    if report.plot.len() == 1 {
        return draw_intervals(root, request, c);
    }
    let look = |m: Method| look(figures_of, m);
    let at = &c.at;
    let short = fonts.compact;
    let shown: Vec<&MethodSet> = at
        .sets
        .iter()
        .filter(|s| !view.hide.contains(&s.method))
        .collect();
    let mut drawn = Vec::new();
    for s in &shown {
        drawn.push((*s, loops(s)?));
    }
    // The window: every set (zoom "full"), or by default the sets of comparable size — a set
    // more than FOCUS times the median's extent (LSCR's region beside the ellipses) would shrink
    // the others to dots, so it is cut at the window and the chart says so.
    let extent = |l: &Vec<Vec<(f64, f64)>>| {
        let mut w = Win::empty();
        for lp in l {
            w.add_points(lp);
        }
        w
    };
    let mut sizes: Vec<f64> = drawn
        .iter()
        .map(|(_, l)| extent(l))
        .filter(|w| !w.is_empty())
        .map(|w| w.width().hypot(w.height()))
        .collect();
    sizes.sort_by(f64::total_cmp);
    let median = sizes.get(sizes.len() / 2).copied().unwrap_or(0.0);
    let mut w = Win::empty();
    let mut cut = Vec::new();
    for (s, l) in &drawn {
        let e = extent(l);
        if e.is_empty() {
            continue;
        }
        if view.zoom == Zoom::Full || median == 0.0 || e.width().hypot(e.height()) <= FOCUS * median
        {
            w = w.union(&e);
        } else {
            cut.push(look(s.method)?.label);
        }
    }
    let truth = at.truth.as_ref().map(|p| (p[0], p[1]));
    if let Some(p) = truth {
        w.add(p.0, p.1);
    }
    if w.is_empty() {
        // Nothing to draw: the truth or the origin, so the chart still has axes.
        w.add(-1.0, -1.0);
        w.add(1.0, 1.0);
    }
    let win = w.padded(0.08, 0.08);
    let which = which_state(report, c);
    let mut notes = noise_notes(c);
    let missing: Vec<String> = shown
        .iter()
        .filter(|s| s.set.is_none())
        .map(|s| Ok(format!("{}: {}", look(s.method)?.label, no_set_word(s))))
        .collect::<Result<_>>()?;
    if !missing.is_empty() && !short {
        notes.push(missing.join("; "));
    }
    let mut entries = Vec::new();
    if truth.is_some() {
        entries.push(Entry::new(
            format!("true state x{}", style::sub(at.target_time)),
            Swatch::Marker {
                shape: Marker::Diamond,
                color: TRUTH,
                size: 5,
            },
        ));
    }
    for (s, _) in &drawn {
        if s.set.is_none() {
            continue;
        }
        let l = look(s.method)?;
        let name = l.label;
        let text = match s.holds {
            Some(true) if !short => format!("{name} (holds it)"),
            Some(false) if !short => format!("{name} (misses it)"),
            _ => name.to_string(),
        };
        let swatch = match l.fill {
            SetFill::Tint { color, opacity } => Swatch::Tinted {
                line: l.color,
                tint: color.mix(opacity),
            },
            fill => Swatch::Region {
                color: l.color,
                dashed: l.dashed,
                fill: fill == SetFill::Light,
            },
        };
        entries.push(Entry::new(text, swatch));
    }
    let what = format!("Every method's set for {which}");
    let title = style::title(&report.figure, &fonts, &what, &what);
    let (area, side) = style::titled_legend_beside(root, &fonts, &title, &notes, &entries)?;
    let (xd, yd) = (axis(report, report.plot[0]), axis(report, report.plot[1]));
    let chart = style::equal_chart(&area, &fonts, win, &xd, &yd)?;
    let mut marks = Vec::new();
    // What the chart shows (the equal-aspect window may be wider than asked): every set is cut
    // to it, filled areas as polygons, outlines as pieces.
    let shown_win = Win::of_chart(&chart);
    // Filled sets first (lower layers), outlines over them.
    let mut sorted = Vec::new();
    for (s, l) in &drawn {
        sorted.push((look(s.method)?, s, l));
    }
    sorted.sort_by_key(|(look, _, _)| look.layer);
    for (look, s, l) in sorted {
        for lp in l {
            let mut closed = lp.clone();
            closed.extend(lp.first().copied());
            let inside = clip_polygon(lp, &shown_win);
            if look.fill != SetFill::None && inside.len() >= 3 {
                // The light fill (for LSCR its yellow tint, as on the LSCR panel).
                let (bx, by) = root.get_base_pixel();
                let px: Vec<(i32, i32)> = style::marks_of(&chart, &inside)
                    .into_iter()
                    .map(|(x, y)| (x - bx, y - by))
                    .collect();
                let tint = match look.fill {
                    SetFill::Tint { color, opacity } => color.mix(opacity).filled(),
                    _ => style::fill(&look.color),
                };
                root.draw(&Polygon::new(px, tint))
                    .map_err(crate::plot::erase::de)?;
            }
            let dash = look.dashed.then_some(style::DASH);
            style::path(root, &chart, &closed, &look.color, 2, dash)?;
            for piece in clip_polyline(&closed, &shown_win) {
                marks.extend(style::marks_of(&chart, &piece));
            }
        }
        if let Some(o) = &s.outline {
            let mut o: Vec<(f64, f64)> = o.iter().map(|p| (p[0], p[1])).collect();
            o.extend(o.first().copied());
            style::path(root, &chart, &o, &look.color, 1, Some(style::DASH))?;
        }
    }
    let points: Vec<((f64, f64), Marker, RGBColor, &'static str)> = truth
        .map(|p| (p, Marker::Diamond, TRUTH, "true state"))
        .into_iter()
        .collect();
    let outside = style::markers_inside(root, &chart, &points, &mut marks)?;
    let mut chart_notes = Vec::new();
    if !cut.is_empty() {
        chart_notes.push(if short {
            format!("{} cut at the window", cut.join(", "))
        } else {
            format!(
                "{} reaches beyond the window (zoom “full”: every set whole)",
                cut.join(", ")
            )
        });
    }
    // Tempo's set and Pavelková's carried-over polygon are the same consistent set when their
    // bounds and windows agree: say so, or one looks missing under the other.
    let area = |m: Method| {
        shown
            .iter()
            .find(|s| s.method == m && s.set.is_some())
            .and_then(|s| s.area)
    };
    if let (Some(a), Some(b)) = (area(Method::Ubb), area(Method::UniformLp)) {
        // 10⁻⁴: the LP's floor on a noiseless state's half-width widens its polygon by ~10⁻⁶.
        if (a - b).abs() <= 1e-4 * a.max(b) && !short {
            chart_notes.push("Tempo's set and the uniform-LP set coincide".to_string());
        }
    }
    if drawn
        .iter()
        .any(|(s, _)| matches!(s.set, Some(PlaneSet::Region { bounded: false, .. })))
    {
        chart_notes.push("the LSCR region is unbounded: drawn within its window".to_string());
    }
    if !outside.is_empty() {
        chart_notes.push(format!("outside the window: {}", outside.join(", ")));
    }
    style::chart_notes(root, &chart, &fonts, &chart_notes, &mut marks)?;
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, &xd, &yd))
}

/// Which state the sets are of, in words: "x₃₁ predicted from y₁ … y₃₀" (with the plane's
/// components named for a model of n ≥ 3 states).
fn which_state(report: &Report, c: &CompareReport) -> String {
    let at = &c.at;
    let part = if report.n > 2 {
        let names: Vec<String> = report
            .plot
            .iter()
            .map(|&i| format!("x{}", style::sub(i + 1)))
            .collect();
        format!(" ({} of n = {})", names.join(", "), report.n)
    } else {
        String::new()
    };
    match c.target {
        Target::Predict => format!(
            "x{} predicted from y₁ … y{}{part}",
            style::sub(at.target_time),
            style::sub(at.t)
        ),
        Target::Filter => format!(
            "x{} from y₁ … y{}{part}",
            style::sub(at.target_time),
            style::sub(at.t)
        ),
    }
}

/// The noise law and the bounds, the figure's first note.
fn noise_notes(c: &CompareReport) -> Vec<String> {
    let law = match c.noise {
        crate::scenario::compare::NoiseLaw::Gaussian => "Gaussian",
        crate::scenario::compare::NoiseLaw::Uniform => "uniform",
        crate::scenario::compare::NoiseLaw::Truncated => "truncated Gaussian",
    };
    vec![format!(
        "{law} noise; bounds b_v = {}, b_w = {}",
        style::sig(c.bound_v),
        style::sig(c.bound_w)
    )]
}

/// The compare of a scalar state (n = 1): each method's interval on its own row, top to bottom
/// in the report's order, the method named at the row's left, the truth a vertical line
/// through every row; a method without a set keeps its row with "no set".
fn draw_intervals<DB: DrawingBackend>(
    root: &Area<DB>,
    request: &Request,
    c: &CompareReport,
) -> Result<Frame> {
    let (report, view, fonts) = (request.report, request.view, request.fonts);
    let look = |m: Method| look(request.figures_of, m);
    let at = &c.at;
    let short = fonts.compact;
    let shown: Vec<&MethodSet> = at
        .sets
        .iter()
        .filter(|s| !view.hide.contains(&s.method))
        .collect();
    let pieces: Vec<Option<(f64, f64)>> = shown
        .iter()
        .map(|s| match s.set {
            Some(PlaneSet::Interval { lo, hi }) => Some((lo, hi)),
            _ => None,
        })
        .collect();
    // The window: every interval (zoom "full"), or by default those of comparable length, as
    // the plane's sets are (a far longer one is cut at the window and the chart says so).
    let mut lengths: Vec<f64> = pieces.iter().flatten().map(|(lo, hi)| hi - lo).collect();
    lengths.sort_by(f64::total_cmp);
    let median = lengths.get(lengths.len() / 2).copied().unwrap_or(0.0);
    let rows = shown.len().max(1) as f64;
    let mut w = Win::empty();
    let mut cut = Vec::new();
    for (s, piece) in shown.iter().zip(&pieces) {
        let Some((lo, hi)) = *piece else { continue };
        if view.zoom == Zoom::Full || median == 0.0 || hi - lo <= FOCUS * median {
            w.add_x(lo);
            w.add_x(hi);
        } else {
            cut.push(look(s.method)?.label);
        }
    }
    let truth = at.truth.as_ref().map(|x| x[0]);
    if let Some(x) = truth {
        w.add_x(x);
    }
    if w.is_empty() {
        w.add_x(-1.0);
        w.add_x(1.0);
    }
    w.add_y(-0.5);
    w.add_y(rows - 0.5);
    let win = w.padded(0.08, 0.0);
    let which = which_state(report, c);
    let mut notes = noise_notes(c);
    let missing: Vec<String> = shown
        .iter()
        .filter(|s| s.set.is_none())
        .map(|s| Ok(format!("{}: {}", look(s.method)?.label, no_set_word(s))))
        .collect::<Result<_>>()?;
    if !missing.is_empty() && !short {
        notes.push(missing.join("; "));
    }
    let mut entries = Vec::new();
    if truth.is_some() {
        entries.push(Entry::new(
            format!("true state x{}", style::sub(at.target_time)),
            Swatch::Marker {
                shape: Marker::Diamond,
                color: TRUTH,
                size: 5,
            },
        ));
    }
    let what = format!("Every method's interval for {which}");
    let title = style::title(&report.figure, &fonts, &what, &what);
    let (area, side) = style::titled_legend_beside(root, &fonts, &title, &notes, &entries)?;
    let xd = axis(report, report.plot[0]);
    let chart = style::rows_chart(&area, &fonts, win, &xd)?;
    let shown_win = Win::of_chart(&chart);
    let mut marks = Vec::new();
    let label_style = fonts.tick();
    for (i, (s, piece)) in shown.iter().zip(&pieces).enumerate() {
        let l = look(s.method)?;
        // The first method on the top row.
        let y = rows - 1.0 - i as f64;
        let name = match (piece, s.holds) {
            (None, _) => format!("{}: {}", l.label, no_set_word(s)),
            (Some(_), Some(true)) if !short => format!("{} (holds it)", l.label),
            (Some(_), Some(false)) if !short => format!("{} (misses it)", l.label),
            _ => l.label.to_string(),
        };
        if let Some((lo, hi)) = *piece {
            let (a, b) = (lo.max(shown_win.x0), hi.min(shown_win.x1));
            if a <= b {
                let dash = l.dashed.then_some(style::DASH);
                style::path(root, &chart, &[(a, y), (b, y)], &l.color, 4, dash)?;
                for end in [lo, hi] {
                    if shown_win.contains(end, y) {
                        style::path(
                            root,
                            &chart,
                            &[(end, y - 0.18), (end, y + 0.18)],
                            &l.color,
                            2,
                            None,
                        )?;
                    }
                }
                marks.extend(style::marks_of(&chart, &[(a, y), (b, y)]));
            }
        }
        // The method's name just above its row, at the window's left.
        let at_px = style::px(&chart, (shown_win.x0, y + 0.22));
        let color = if piece.is_some() {
            l.color
        } else {
            style::MUTED
        };
        style::text(
            root,
            &name,
            (at_px.0 + 4, at_px.1),
            &label_style.color(&color),
            (HPos::Left, VPos::Bottom),
        )?;
    }
    if let Some(x) = truth {
        style::path(
            root,
            &chart,
            &[(x, -0.5), (x, rows - 0.5)],
            &TRUTH,
            1,
            Some(style::DASH),
        )?;
        for i in 0..shown.len() {
            marks.push(style::px(&chart, (x, i as f64)));
        }
    }
    let mut chart_notes = Vec::new();
    if !cut.is_empty() {
        chart_notes.push(if short {
            format!("{} cut at the window", cut.join(", "))
        } else {
            format!(
                "{} reaches beyond the window (zoom “full”: every interval whole)",
                cut.join(", ")
            )
        });
    }
    style::chart_notes(root, &chart, &fonts, &chart_notes, &mut marks)?;
    style::overlay_legend(root, &chart, &fonts, &entries, side, &marks)?;
    Ok(style::frame_of(&chart, &xd, ""))
}

/// "empty set" (the data contradict the method's bounds: a set that holds nothing) or "no set"
/// (the method could not give one here).
fn no_set_word(s: &MethodSet) -> &'static str {
    if s.empty {
        "empty set"
    } else {
        "no set"
    }
}

fn axis(report: &Report, c: usize) -> String {
    match report.figure.names.get(c) {
        Some(name) if !name.is_empty() => name.clone(),
        _ => format!("x{}", style::sub(c + 1)),
    }
}
