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
    for s in &c.at.sets {
        look(figures_of, s.method)?;
        let ok = match &s.set {
            Some(PlaneSet::Ellipse(e)) => {
                e.dim() == 2 && finite(&e.center) && e.cov.iter().all(|r| r.len() == 2 && finite(r))
            }
            Some(PlaneSet::Polygon { vertices }) => vertices.iter().all(|v| finite(v)),
            Some(PlaneSet::Region { loops, .. }) => {
                loops.iter().all(|l| l.points.iter().all(|p| finite(p)))
            }
            None => true,
        };
        if !ok {
            return Err(Error::field(
                "report.compare.at.sets",
                format!(
                    "holds a set of \"{}\" that is not a finite 2-D set",
                    s.method
                ),
            ));
        }
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
        None => Vec::new(),
    })
}

/// The "compare" panel.
pub fn draw<DB: DrawingBackend>(root: &Area<DB>, request: &Request) -> Result<Frame> {
    let (report, view, fonts) = (request.report, request.view, request.fonts);
    let figures_of = request.figures_of;
    let c = check(report, figures_of)?;
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
    let truth = at.truth.map(|p| (p[0], p[1]));
    if let Some(p) = truth {
        w.add(p.0, p.1);
    }
    if w.is_empty() {
        // Nothing to draw: the truth or the origin, so the chart still has axes.
        w.add(-1.0, -1.0);
        w.add(1.0, 1.0);
    }
    let win = w.padded(0.08, 0.08);
    let which = match c.target {
        Target::Predict => format!(
            "x{} predicted from y₁ … y{}",
            style::sub(at.target_time),
            style::sub(at.t)
        ),
        Target::Filter => format!(
            "x{} from y₁ … y{}",
            style::sub(at.target_time),
            style::sub(at.t)
        ),
    };
    let law = match c.noise {
        crate::scenario::compare::NoiseLaw::Gaussian => "Gaussian",
        crate::scenario::compare::NoiseLaw::Uniform => "uniform",
        crate::scenario::compare::NoiseLaw::Truncated => "truncated Gaussian",
    };
    let mut notes = vec![format!(
        "{law} noise; bounds b_v = {}, b_w = {}",
        style::sig(c.bound_v),
        style::sig(c.bound_w)
    )];
    let missing: Vec<String> = shown
        .iter()
        .filter(|s| s.set.is_none())
        .map(|s| Ok(format!("{}: no set", look(s.method)?.label)))
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
    let (xd, yd) = (axis(report, 0), axis(report, 1));
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

fn axis(report: &Report, c: usize) -> String {
    match report.figure.names.get(c) {
        Some(name) if !name.is_empty() => name.clone(),
        _ => format!("x{}", style::sub(c + 1)),
    }
}
