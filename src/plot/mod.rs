//! Figures, drawn with plotters on any backend (SVG natively, canvas in the browser).
//!
//! One entry point, [`draw`], generic over plotters' `DrawingBackend`: the CLI hands it an
//! `SVGBackend` ([`report_svg`], [`scenario_svg`]), the wasm bindings a `CanvasBackend`. It
//! takes the report and a [`View`] (panel, time, zoom: what the viewer chooses) and nothing
//! else: the scenario's part of the figure (title, axis names, measured components, collision
//! check) is the report's [`FigureContext`] (`Report::figure`, made with the report), so the
//! page and the CLI draw the same figure from the same scenario. The pictures ([`Panel`]):
//!
//! * [`Panel::State`] (`state.rs`) — for two plotted components the state plane at the shown
//!   time t: true trajectory, measurements (when they measure the plotted components
//!   directly), the true state (+), the KF region (dashed) and the SCF region (solid, light
//!   fill). When the report has a target (components ζ, τ-step prediction) those regions are
//!   drawn (e.g. "SCF Z₄₀|₃₆"); with a collision check both bodies' predicted regions, their
//!   true positions and the KF/SCF warnings. The window zooms on the regions when the
//!   trajectory is much larger than they are, with an inset of the whole run. For one plotted
//!   component: the state over time with KF/SCF interval bands and the shown time's intervals.
//! * [`Panel::Series`] (`series.rs`) — each plotted component over time: truth, KF and SCF
//!   centers and intervals (projections of the n-dimensional regions), time cursor; when the
//!   intervals are tiny next to the trajectory, the estimates minus the true value.
//! * [`Panel::Coverage`] (`coverage.rs`) — Fig. 1 of the SCF paper: P{x_t ∈ X_t | x_t = x̄}
//!   against x̄ for KF and SCF, with the level α.
//! * [`Panel::Region`] (`region.rs`) — Figs. 1–3 of the LSCR paper: the confidence region X̂
//!   (tinted, outlined), the areas excluded by each X̂_l hatched exactly (one style per group),
//!   the true state ◇, the BLUE ⋆ with its ellipse, the Kalman ellipse dashed, and the
//!   directions along which X̂ is unbounded. The only panel of an LSCR report (which has no
//!   time steps); the other panels are for KF/SCF reports.
//! * GLLS reports (Gubarev & Mishchenko; no time steps either) have their own four panels,
//!   all with a marker at the horizon s in use: [`Panel::Singular`] (`glls.rs`, Fig. 1: every
//!   σ_i(Γ_{s+1}) solid, σ_i(Γ_{s+1}A^{−s}) dashed in the same colour, the floating-point floor
//!   as a grey band), [`Panel::Index`] (`glls.rs`, Fig. 2: σ_n/√s and σ_p/√s with the best
//!   horizons), [`Panel::Plane`] (`glls_plane.rs`: the two `plane` components of x(k) — truth ◇,
//!   estimate ⋆, the guaranteed ball (35) as a disk, the exact interval box, the regularized
//!   estimate with the projected truth, the state-noise estimate) and [`Panel::Precision`]
//!   (`glls_precision.rs`, Figs. 3–4: box-and-whisker of the Monte Carlo errors per horizon
//!   with the bound κ·√E‖δ‖², or paired half-boxes state-noise vs LLS with the mean ‖x(k)‖
//!   dash-dotted). Log axes plot log10 values on a linear axis labelled 10ᵏ
//!   ([`style::log_chart`]); their [`Frame`]'s y range is in log10 units.
//! * Uniform-innovation reports (Pavelková, method `uniform_lp`; no KF/SCF steps) have four
//!   panels with a time cursor at the window the report solved (`at.time`):
//!   [`Panel::UStates`] (`uniform.rs`, Fig. 1: per state component the truth, the LP and KF
//!   estimates with the optimal-face ranges of the window as bars, and the estimation errors
//!   below), [`Panel::UOutput`] (`uniform.rs`, Fig. 2: y_t, the one-step prediction and its
//!   error), [`Panel::UParams`] (`uniform_params.rs`, Fig. 3: the entries of Â and the
//!   half-widths x̂ᵣ, ŷᵣ with the true values dashed) and [`Panel::UPolygon`]
//!   (`uniform_polygon.rs`: the exact consistent-state polygon with truth ◇, LP ⋆, KF × and
//!   the optimal-face box; not for a scalar state). On the user's data there is no truth and
//!   no KF: those marks and curves are left out and the error charts say why.
//! * Set-membership reports (Tempo, method `ubb`) have two panels: [`Panel::UbbSet`]
//!   (`ubb.rs`: the exact feasible polygon of x(k+1) at the report's step k, its interval hull
//!   dashed, the central estimate ⋆, the truth ◇, the Kalman ellipse dashed) and
//!   [`Panel::UbbWidth`] (`ubb_width.rs`: the hull's widths over k with the Theorem 4 bound and
//!   a cursor at k; below, the truth inside its hull bands).
//!
//! Colors, fonts and the legend are shared (`style.rs`): KF vermillion dashed, SCF blue solid,
//! truth black, measurements grey (Okabe–Ito, colorblind-safe).
//!
//! Fonts: on wasm32 plotters measures text with the browser. Natively it measures with a
//! ~41 KB subset of DejaVu Sans embedded in the binary (`fonts/`, registered through plotters'
//! `ab_glyph` feature, native only); SVG text names the generic family `sans-serif`.
//!
//! Nothing here panics on bad input: every drawing failure and every inconsistent view
//! becomes a crate [`Error`].

mod compare;
mod coverage;
mod erase;
pub mod geom;
mod glls;
mod glls_plane;
mod glls_precision;
mod region;
mod series;
mod state;
pub mod style;
mod ubb;
mod ubb_width;
mod uniform;
mod uniform_params;
mod uniform_polygon;

use crate::error::{Error, Result};
use crate::method::Method;
use crate::scenario::{FigureContext, Report, Scenario};
use crate::scf::ScfStep;
use plotters::coord::Shift;
use plotters::drawing::DrawingAreaErrorKind;
use plotters::prelude::*;
use serde::{Deserialize, Serialize};
use style::{sub, Fonts};

/// Which picture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Panel {
    /// State plane (two plotted components; for n = 1 the state over time): trajectory,
    /// measurements, true state, KF ellipse (dashed), SCF ellipse (solid) at the chosen time.
    #[default]
    State,
    /// Components over time with KF and SCF intervals.
    Series,
    /// Fig. 1: conditional coverage of KF and SCF against the state value.
    Coverage,
    /// LSCR paper, Figs. 1–3: the LSCR region with the excluded areas hatched per group, the
    /// truth, the BLUE and Kalman ellipses (LSCR reports only).
    Region,
    /// GLLS paper, Fig. 1: the singular values of Γ_{s+1} (and of Γ_{s+1}A^{−s}) against the
    /// horizon s on a log scale, with the floating-point floor (GLLS reports only).
    Singular,
    /// GLLS paper, Fig. 2: the horizon index σ_n/√s (and σ_p/√s) with its best horizon.
    Index,
    /// GLLS: the state plane at time k: truth, estimate, guaranteed ball and interval box.
    Plane,
    /// GLLS paper, Figs. 3–4: the Monte Carlo error ‖x_est(k) − x(k)‖ per horizon (boxes) with
    /// the bound κ·√E‖δ‖², or state-noise estimator vs LLS in paired half-boxes.
    Precision,
    /// Uniform-innovation paper, Fig. 1: states, LP and KF estimates, estimation errors and
    /// the optimal-face ranges of the window at the cursor (uniform reports only).
    #[serde(rename = "ustates")]
    UStates,
    /// Uniform-innovation paper, Fig. 2: the output, its one-step prediction and the error.
    #[serde(rename = "uoutput")]
    UOutput,
    /// Uniform-innovation paper, Fig. 3: the entries of Â and the half-widths over time.
    #[serde(rename = "uparams")]
    UParams,
    /// The states consistent with the window at the cursor (a polygon in the plane
    /// components) with the truth, the LP and KF estimates and the optimal-face box.
    #[serde(rename = "upolygon")]
    UPolygon,
    /// Set-membership (Tempo): the exact feasible set of x(k+1) at the report's step k (a
    /// polygon in the plane components) with its interval hull, the central estimate, the
    /// truth and the Kalman ellipse (ubb reports only).
    #[serde(rename = "ubbset")]
    UbbSet,
    /// Set-membership: the widths of the interval hull over k with the Theorem 4 bound, and
    /// the truth inside its hull bands.
    #[serde(rename = "ubbwidth")]
    UbbWidth,
    /// Every method's set for the same state on one record, in the state plane, with the truth
    /// (compare reports only).
    Compare,
}

impl Panel {
    /// Lower-case name as in JSON ("state", "series", "coverage", "region", "singular", …).
    pub fn name(&self) -> &'static str {
        match self {
            Panel::State => "state",
            Panel::Series => "series",
            Panel::Coverage => "coverage",
            Panel::Region => "region",
            Panel::Singular => "singular",
            Panel::Index => "index",
            Panel::Plane => "plane",
            Panel::Precision => "precision",
            Panel::UStates => "ustates",
            Panel::UOutput => "uoutput",
            Panel::UParams => "uparams",
            Panel::UPolygon => "upolygon",
            Panel::UbbSet => "ubbset",
            Panel::UbbWidth => "ubbwidth",
            Panel::Compare => "compare",
        }
    }
    /// The figure in words: the text alternative of its canvas on the page (the numbers
    /// table beside it carries the values).
    pub fn alt_text(&self) -> &'static str {
        match self {
            Panel::State => "state plane at the shown time: trajectory, true state, Kalman and SCF regions",
            Panel::Series => "state components over time with the Kalman and SCF intervals",
            Panel::Coverage => "conditional coverage of the Kalman and SCF regions against the state value (SCF Fig. 1)",
            Panel::Region => "LSCR confidence region with the excluded areas hatched, the truth, the BLUE and Kalman ellipses",
            Panel::Singular => "singular values of the observability matrix against the horizon (GLLS Fig. 1)",
            Panel::Index => "horizon index σₙ/√s with the best horizon (GLLS Fig. 2)",
            Panel::Plane => "state plane at time k: truth, estimate, guaranteed ball and interval box",
            Panel::Precision => "Monte Carlo errors per horizon as box plots with the bound κ·√E‖δ‖² (GLLS Figs. 3–4)",
            Panel::UStates => "states, LP and Kalman estimates and their errors over time (uniform Fig. 1)",
            Panel::UOutput => "output, its one-step prediction and the prediction error (uniform Fig. 2)",
            Panel::UParams => "entries of Â and the estimated half-widths over time (uniform Fig. 3)",
            Panel::UPolygon => "consistent-state polygon at the time cursor with the truth, LP and Kalman estimates and the optimal-face box",
            Panel::UbbSet => "feasible set of the state at step k, its interval hull, the central estimate, the truth and the Kalman ellipse",
            Panel::UbbWidth => "widths of the interval hull over k with the Theorem 4 bound, and the truth inside its hull bands",
            Panel::Compare => "every method's set for the same state in the state plane: Kalman, SCF and GLLS ellipses, the LSCR region, Tempo's and the uniform-LP polygons, and the truth",
        }
    }
    /// The method whose reports this panel draws.
    pub fn method(&self) -> Method {
        Method::ALL
            .into_iter()
            .find(|m| method_panels(*m).contains(self))
            .unwrap_or(Method::Scf)
    }
    /// Parse a lower-case name.
    pub fn from_name(s: &str) -> Result<Panel> {
        match s {
            "state" => Ok(Panel::State),
            "series" => Ok(Panel::Series),
            "coverage" => Ok(Panel::Coverage),
            "region" => Ok(Panel::Region),
            "singular" => Ok(Panel::Singular),
            "index" => Ok(Panel::Index),
            "plane" => Ok(Panel::Plane),
            "precision" => Ok(Panel::Precision),
            "ustates" => Ok(Panel::UStates),
            "uoutput" => Ok(Panel::UOutput),
            "uparams" => Ok(Panel::UParams),
            "upolygon" => Ok(Panel::UPolygon),
            "ubbset" => Ok(Panel::UbbSet),
            "ubbwidth" => Ok(Panel::UbbWidth),
            "compare" => Ok(Panel::Compare),
            _ => Err(Error::field(
                "panel",
                format!("{} is unknown: choose state, series, coverage, region, singular, index, plane, precision, ustates, uoutput, uparams, upolygon, ubbset, ubbwidth or compare", crate::error::quoted(s)),
            )),
        }
    }
}

/// Window of the state plane / series.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Zoom {
    /// Zoom on the regions when the trajectory is much larger than they are (robots);
    /// otherwise show everything.
    #[default]
    Auto,
    /// Always the regions (state plane) / the estimates minus the true value (series).
    Regions,
    /// Always the whole run / the raw values.
    Full,
}

/// What to draw: only what the viewer chooses.
///
/// Everything the figure takes from the scenario (title, axis names, measured components,
/// the collision check) comes with the report ([`Report::figure`]), so a view of the same
/// report draws the same figure from the CLI and from the page. Unknown fields are refused.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct View {
    #[serde(default)]
    pub panel: Panel,
    /// Time shown (default: the report's `time`).
    #[serde(default)]
    pub time: Option<usize>,
    /// Window of the state plane and of the series.
    #[serde(default)]
    pub zoom: Zoom,
    /// Methods whose sets the compare panel leaves out (its toggles).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hide: Vec<Method>,
}

impl View {
    /// A view of `panel` at the report's time.
    pub fn new(panel: Panel) -> View {
        View {
            panel,
            ..View::default()
        }
    }
}

fn default_name(i: usize) -> String {
    // 1-based, as everywhere the page and the figures number components.
    format!("state x{}", sub(i + 1))
}

/// Where the plotting area landed, so a page can map the cursor to chart units.
///
/// `plot_area` is in backend pixels (for the wasm bindings: CSS pixels of the canvas, like
/// `MouseEvent.offsetX/Y`); chart x = x_range.0 + (px − left) / (right − left) · (x_range.1 −
/// x_range.0), and y likewise but from the bottom (y_range.0 at `bottom`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Frame {
    pub x_range: (f64, f64),
    pub y_range: (f64, f64),
    /// Pixel box (left, top, right, bottom) of the plotting area in backend pixels.
    pub plot_area: (i32, i32, i32, i32),
    pub x_label: String,
    pub y_label: String,
    /// Further plotting areas of the same figure (the Series panel stacks one chart per
    /// component: this frame is the top one, `more` the ones below, top to bottom).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub more: Vec<Frame>,
    /// Pixel boxes (left, top, right, bottom) of the figure's legends, in backend pixels (on
    /// the top frame only). A legend is laid out beside or below the charts, so no box meets a
    /// `plot_area`, except on figures too small for that (see `style::legend`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub legends: Vec<(i32, i32, i32, i32)>,
}

/// Smallest figure drawn (backend pixels).
pub const MIN_SIZE: (u32, u32) = (240, 180);

/// Draw `view` of `report` on any plotters backend.
pub fn draw<DB: DrawingBackend>(backend: DB, report: &Report, view: &View) -> Result<Frame> {
    // The legends are laid out deep in `style`'s helpers while each panel assembles its own
    // frame: they note their boxes on the side, collected here.
    style::legend_boxes_clear();
    let mut frame = draw_panel(backend, report, view)?;
    frame.legends = style::legend_boxes_take();
    Ok(frame)
}

fn draw_panel<DB: DrawingBackend>(backend: DB, report: &Report, view: &View) -> Result<Frame> {
    ensure_fonts()?;
    let (w, h) = backend.get_size();
    if w < MIN_SIZE.0 || h < MIN_SIZE.1 {
        return Err(Error::field(
            "size",
            format!(
                "{w} × {h} pixels is too small for a figure (at least {} × {})",
                MIN_SIZE.0, MIN_SIZE.1
            ),
        ));
    }
    let fonts = Fonts::for_backend::<DB>((w, h));
    // The one dispatch from a report's method to its figures: a panel draws its own method's
    // reports only.
    let panels = method_panels(report.method);
    if !panels.contains(&view.panel) {
        let owner = view.panel.method();
        return Err(Error::field(
            "panel",
            format!(
                "\"{}\" draws {} reports, but this is {} report (method \"{}\"), with no {} part: choose {}",
                view.panel.name(),
                describe(owner),
                describe(report.method),
                report.method,
                owner.block().unwrap_or("SCF"),
                choose(panels),
            ),
        ));
    }
    match view.panel {
        Panel::UbbSet | Panel::UbbWidth => {
            ubb::check(report, view.panel)?;
            return draw_erased(backend, |root| match view.panel {
                Panel::UbbSet => ubb::draw_set(root, report, view, fonts),
                _ => ubb_width::draw(root, report, view, fonts),
            });
        }
        Panel::UStates | Panel::UOutput | Panel::UParams | Panel::UPolygon => {
            uniform::check(report, view, view.panel)?;
            return draw_erased(backend, |root| match view.panel {
                Panel::UStates => uniform::draw_states(root, report, view, fonts),
                Panel::UOutput => uniform::draw_output(root, report, view, fonts),
                Panel::UParams => uniform_params::draw(root, report, view, fonts),
                _ => uniform_polygon::draw(root, report, view, fonts),
            });
        }
        Panel::Singular | Panel::Index | Panel::Plane | Panel::Precision => {
            glls::check(report, view.panel)?;
            return draw_erased(backend, |root| match view.panel {
                Panel::Singular => glls::draw_singular(root, report, fonts),
                Panel::Index => glls::draw_index(root, report, fonts),
                Panel::Plane => glls_plane::draw(root, report, fonts),
                _ => glls_precision::draw(root, report, fonts),
            });
        }
        Panel::Compare => {
            compare::check(report)?;
            return draw_erased(backend, |root| compare::draw(root, report, view, fonts));
        }
        Panel::Region => {
            region::lscr_of(report)?;
            return draw_erased(backend, |root| region::draw(root, report, view, fonts));
        }
        Panel::State | Panel::Series | Panel::Coverage => {}
    }
    let cx = Ctx::new(report, view, fonts)?;
    if view.panel == Panel::Coverage && report.coverage_curve.is_none() {
        return Err(Error::field(
            "coverage_curve",
            "is not in this report: ask for it in the scenario (\"scf\": {\"coverage_curve\": {\"component\", \"from\", \"to\"}}) to draw the coverage panel",
        ));
    }
    // All figure code runs on one backend type (see erase.rs).
    let mut adapter = erase::Adapter(backend);
    let root = erase::Erased(&mut adapter).into_drawing_area();
    root.fill(&WHITE).map_err(de)?;
    let frame = match view.panel {
        Panel::Coverage => coverage::draw(&root, &cx)?,
        Panel::Series => series::draw(&root, &cx)?,
        // The other panels returned above.
        _ => state::draw(&root, &cx)?,
    };
    root.present().map_err(de)?;
    Ok(frame)
}

/// One view of a report as SVG text.
pub fn report_svg(report: &Report, view: &View, w: u32, h: u32) -> Result<String> {
    let mut s = String::new();
    draw(SVGBackend::with_string(&mut s, (w, h)), report, view)?;
    Ok(s)
}

/// A figure as PNG (native only): the SVG of [`report_svg`] at `w`×`h` rasterized by resvg at
/// `scale` pixels per SVG pixel (2 for slides and hi-DPI screens), its text in the embedded font
/// the SVG's layout was measured with.
#[cfg(not(target_arch = "wasm32"))]
pub fn report_png(report: &Report, view: &View, w: u32, h: u32, scale: f32) -> Result<Vec<u8>> {
    svg_to_png(&report_svg(report, view, w, h)?, scale)
}

/// Most pixels of a PNG: 8192 × 8192 (256 MiB of RGBA while it is drawn). Each of size and
/// scale is bounded on its own (16 … 8192 pixels a side, scale 0.25 … 8), but together they
/// asked the allocator for 17 GB and aborted; this bounds their product, before any pixel is
/// allocated.
pub const MAX_PNG_PIXELS: u64 = 8192 * 8192;

/// Whether a `w`×`h` figure at `scale` fits [`MAX_PNG_PIXELS`]: `Err` names `scale` and says
/// the pixels asked and the limit in words.
pub fn check_png_pixels(w: u32, h: u32, scale: f32) -> Result<()> {
    if !(scale.is_finite() && (0.25..=8.0).contains(&scale)) {
        return Err(Error::field("scale", "must be a number from 0.25 to 8"));
    }
    let side = |p: u32| (f64::from(p) * f64::from(scale)).ceil();
    let (pw, ph) = (side(w), side(h));
    if pw * ph > MAX_PNG_PIXELS as f64 {
        return Err(Error::field(
            "scale",
            format!(
                "is {scale} with a figure of {w} × {h} pixels: the PNG would have {pw} × {ph} = {:.3e} pixels, and a PNG has at most {MAX_PNG_PIXELS} (8192 × 8192, 256 MB while drawn)",
                pw * ph
            ),
        ));
    }
    Ok(())
}

/// Rasterize an SVG made by this module (see [`report_png`]); its size times `scale` is held
/// to [`MAX_PNG_PIXELS`] before the pixels are allocated.
#[cfg(not(target_arch = "wasm32"))]
pub fn svg_to_png(svg: &str, scale: f32) -> Result<Vec<u8>> {
    use resvg::{tiny_skia, usvg};
    let fail = |what: &str| Error::field("figure", format!("could not be rasterized: {what}"));
    check_png_pixels(1, 1, scale)?;
    let mut options = usvg::Options::default();
    options.fontdb_mut().load_font_data(FONT.to_vec());
    options.fontdb_mut().set_sans_serif_family("DejaVu Sans");
    let tree = usvg::Tree::from_str(svg, &options).map_err(|e| fail(&e.to_string()))?;
    let drawn = tree.size().to_int_size();
    check_png_pixels(drawn.width(), drawn.height(), scale)?;
    let size = tree
        .size()
        .to_int_size()
        .scale_by(scale)
        .ok_or_else(|| fail("empty size"))?;
    let mut pixmap =
        tiny_skia::Pixmap::new(size.width(), size.height()).ok_or_else(|| fail("no pixmap"))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    pixmap.encode_png().map_err(|e| fail(&e.to_string()))
}

/// The scenario's default figure (the first of its [`useful_panels`]) as SVG text.
pub fn scenario_svg(s: &Scenario, w: u32, h: u32) -> Result<String> {
    let report = s.run()?;
    let panel = useful_panels(&report)
        .first()
        .copied()
        .unwrap_or(Panel::State);
    report_svg(&report, &View::new(panel), w, h)
}

/// The panels worth drawing for a report: Region alone for an LSCR report; Singular, Index,
/// Plane and (with a Monte Carlo study) Precision for a GLLS report; UStates, UOutput, UParams
/// and UPolygon (when the report has a polygon: not for n = 1) for a uniform-innovation report; UbbSet and UbbWidth for a set-membership report; otherwise State and Series always, Coverage
/// when the report has a coverage curve.
pub fn useful_panels(report: &Report) -> Vec<Panel> {
    method_panels(report.method)
        .iter()
        .copied()
        .filter(|p| match p {
            Panel::Precision => report.glls.as_ref().is_some_and(|g| g.precision.is_some()),
            Panel::Coverage => report.coverage_curve.is_some(),
            // A scalar state (n = 1) has no consistent-state polygon.
            Panel::UPolygon => report
                .uniform
                .as_ref()
                .is_some_and(|u| u.at.polygon.is_some()),
            _ => true,
        })
        .collect()
}

/// Every panel a method's reports are drawn with, in the order worth showing: the one map
/// from a [`Method`] to its figures (with [`Panel::method`], its inverse).
pub fn method_panels(m: Method) -> &'static [Panel] {
    match m {
        Method::Scf | Method::Kf => &[Panel::State, Panel::Series, Panel::Coverage],
        Method::Lscr => &[Panel::Region],
        Method::Glls => &[
            Panel::Singular,
            Panel::Index,
            Panel::Plane,
            Panel::Precision,
        ],
        Method::UniformLp => &[
            Panel::UStates,
            Panel::UOutput,
            Panel::UParams,
            Panel::UPolygon,
        ],
        Method::Ubb => &[Panel::UbbSet, Panel::UbbWidth],
        Method::Compare => &[Panel::Compare],
    }
}

/// "an LSCR", "a set-membership", … (for messages).
fn describe(m: Method) -> &'static str {
    match m {
        Method::Scf | Method::Kf => "a KF/SCF",
        Method::Lscr => "an LSCR",
        Method::Glls => "a GLLS",
        Method::UniformLp => "a uniform-innovation",
        Method::Ubb => "a set-membership",
        Method::Compare => "a compare",
    }
}

/// "a, b or c".
fn choose(panels: &[Panel]) -> String {
    let names: Vec<&str> = panels.iter().map(|p| p.name()).collect();
    match names.split_last() {
        Some((last, [])) => last.to_string(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

/// The panels of reports without KF/SCF steps draw on the type-erased backend, so each is
/// compiled once rather than once per backend type: white page, `draw`, present.
fn draw_erased<DB: DrawingBackend>(
    backend: DB,
    draw: impl for<'a> FnOnce(&Area<erase::Erased<'a>>) -> Result<Frame>,
) -> Result<Frame> {
    let mut adapter = erase::Adapter(backend);
    let root = erase::Erased(&mut adapter).into_drawing_area();
    root.fill(&WHITE).map_err(de)?;
    let frame = draw(&root)?;
    root.present().map_err(de)?;
    Ok(frame)
}

/// A drawing error as a crate error.
pub(crate) fn de<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> Error {
    Error::field("figure", format!("could not be drawn: {e}"))
}

/// The embedded font subset (native only): what plotters measures text with, and what the PNG
/// export draws it with.
#[cfg(not(target_arch = "wasm32"))]
static FONT: &[u8] = include_bytes!("fonts/DejaVuSans-subset.ttf");

/// The embedded font (native only): registered once for the family "sans-serif".
#[cfg(not(target_arch = "wasm32"))]
fn ensure_fonts() -> Result<()> {
    use std::sync::OnceLock;
    static DONE: OnceLock<bool> = OnceLock::new();
    let ok = *DONE.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(Error::field(
            "figure",
            "the embedded font could not be loaded",
        ))
    }
}

#[cfg(target_arch = "wasm32")]
fn ensure_fonts() -> Result<()> {
    Ok(())
}

/// A checked report and view: everything a panel needs.
pub(crate) struct Ctx<'a> {
    pub report: &'a Report,
    pub view: &'a View,
    /// Shown time, 1 ≤ t ≤ number of steps.
    pub t: usize,
    pub fonts: Fonts,
}

impl<'a> Ctx<'a> {
    fn new(report: &'a Report, view: &'a View, fonts: Fonts) -> Result<Self> {
        let steps = report.steps.len();
        if steps == 0 {
            return Err(Error::field("report", "has no time steps to draw"));
        }
        let t = view.time.unwrap_or(report.time);
        if t == 0 || t > steps {
            return Err(Error::field(
                if view.time.is_some() {
                    "time"
                } else {
                    "report.time"
                },
                format!(
                    "must be a whole number from 1 to {steps} (the report's time steps), found {t}"
                ),
            ));
        }
        if report.plot.is_empty() || report.plot.len() > 2 {
            return Err(Error::field(
                "plot",
                "must name one or two state components",
            ));
        }
        if let Some(&i) = report.plot.iter().find(|&&i| i >= report.n) {
            return Err(Error::field(
                "plot",
                format!(
                    "names component {i}, but the state has {} components (0-based)",
                    report.n
                ),
            ));
        }
        if report.steps.iter().any(|s| s.kf.dim() != report.n) {
            return Err(Error::field(
                "report.steps",
                "hold regions of the wrong dimension",
            ));
        }
        Ok(Ctx {
            report,
            view,
            t,
            fonts,
        })
    }

    /// The shown step.
    pub fn step(&self) -> &'a ScfStep {
        // Checked in `new`.
        &self.report.steps[self.t - 1]
    }
    /// True state at time s, if simulated.
    pub fn x_true(&self, s: usize) -> Option<&'a [f64]> {
        let xs = self.report.x_true.as_ref()?;
        let x = xs.get(s.checked_sub(1)?)?;
        (x.len() == self.report.n).then_some(x.as_slice())
    }
    /// True value of component i at time s.
    pub fn truth(&self, s: usize, i: usize) -> Option<f64> {
        self.x_true(s).and_then(|x| x.get(i).copied())
    }
    /// Measurement of component i at time s, when a row of y measures it directly.
    pub fn measurement(&self, s: usize, i: usize) -> Option<f64> {
        let [_, row] = *self.figure().measured.iter().find(|[c, _]| *c == i)?;
        self.report.y.get(s.checked_sub(1)?)?.get(row).copied()
    }
    /// Axis name of component i.
    pub fn name(&self, i: usize) -> String {
        match self.figure().names.get(i) {
            Some(s) if !s.is_empty() => s.clone(),
            _ if self.report.n == 1 => "state xₜ".to_string(),
            _ => default_name(i),
        }
    }
    /// Short symbol of component i ("x₁").
    pub fn symbol(&self, i: usize) -> String {
        if self.report.n == 1 {
            "x".to_string()
        } else {
            format!("x{}", sub(i + 1))
        }
    }
    /// The figure title or a default.
    pub fn title(&self, default: &str) -> String {
        self.figure()
            .title
            .clone()
            .unwrap_or_else(|| default.to_string())
    }
    /// The scenario's part of the figure (made with the report).
    pub fn figure(&self) -> &'a FigureContext {
        &self.report.figure
    }
    /// Why there is no SCF region at the shown time.
    pub fn scf_missing_note(&self) -> String {
        if self.report.method == crate::method::Method::Kf {
            "method \"kf\": KF regions only".to_string()
        } else {
            let first = self
                .report
                .steps
                .iter()
                .find(|s| s.scf.is_some())
                .map(|s| s.t);
            match first {
                Some(f) => format!(
                    "no SCF region at t = {} yet (UₜAₜ is invertible from t = {f}; n = {})",
                    self.t, self.report.n
                ),
                None => "no SCF region in this report (UₜAₜ never invertible)".to_string(),
            }
        }
    }
}

/// Convenience for panels: split off the legend, then build axes.
pub(crate) type Area<DB> = DrawingArea<DB, Shift>;

// Native only: they measure text with the embedded font (the wasm build has none).
#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests;
