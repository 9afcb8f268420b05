//! Figures, drawn with plotters on any backend (SVG natively, canvas in the browser).
//!
//! One entry point, [`draw`], generic over plotters' `DrawingBackend`: the CLI hands it an
//! `SVGBackend` ([`report_svg`], [`scenario_svg`]), the wasm bindings a `CanvasBackend`. It
//! takes the report and a [`View`] (panel, time, zoom: what the viewer chooses) and nothing
//! else: the scenario's part of the figure (title, axis names, measured components, collision
//! check) is the report's [`FigureContext`](crate::scenario::FigureContext) (`Report::figure`,
//! made with the report), so the page and the CLI draw the same figure from the same scenario.
//!
//! Each method's figures live in their own folder behind one trait (`figures.rs`: its panels
//! with name and alternative text, which of them a report fills, the drawing, and its look in
//! the compare panel), reached through the one registry [`make_figures`]:
//!
//! * `scf/` (SCF and KF reports) — `state` (`state.rs`: for two plotted components the state
//!   plane at the shown time t: true trajectory, measurements, the true state (+), the KF region
//!   (dashed) and the SCF region (solid, light fill); with a target or a collision check the
//!   predicted regions; the window zooms on the regions with an inset of the whole run; for one
//!   component the state over time with KF/SCF bands), `series` (`series.rs`: each plotted
//!   component over time with KF and SCF intervals, or the estimates minus the true value when
//!   the intervals are tiny) and `coverage` (`coverage.rs`, Fig. 1 of the SCF paper:
//!   P{x_t ∈ X_t | x_t = x̄} against x̄ for KF and SCF, with the level α).
//! * `lscr/` — `region` (`region.rs`, Figs. 1–3 of the LSCR paper: the region X̂ tinted and
//!   outlined, the areas excluded by each X̂_l hatched exactly, the truth ◇, the BLUE ⋆ with its
//!   ellipse, the Kalman ellipse dashed, the directions along which X̂ is unbounded).
//! * `glls/` (Gubarev & Mishchenko; a marker at the horizon s in use) — `singular` and `index`
//!   (`mod.rs`, Figs. 1–2: every σ_i(Γ_{s+1}) solid, σ_i(Γ_{s+1}A^{−s}) dashed, the
//!   floating-point floor as a grey band; σ_n/√s and σ_p/√s with the best horizons), `plane`
//!   (`plane.rs`: truth ◇, estimate ⋆, the guaranteed ball (35), the exact interval box, the
//!   regularized and state-noise estimates) and `precision` (`precision.rs`, Figs. 3–4: box
//!   plots of the Monte Carlo errors per horizon with the bound κ·√E‖δ‖², or paired half-boxes
//!   state-noise vs LLS). Log axes plot log10 values on a linear axis labelled 10ᵏ
//!   ([`style::log_chart`]); their [`Frame`]'s y range is in log10 units.
//! * `uniform/` (Pavelková, method `uniform_lp`; a time cursor at the window solved) —
//!   `ustates` and `uoutput` (`mod.rs`, Figs. 1–2), `uparams` (`params.rs`, Fig. 3) and
//!   `upolygon` (`polygon.rs`: the exact consistent-state polygon; not for a scalar state). On
//!   the user's data there is no truth and no KF: those marks are left out and the charts say
//!   why.
//! * `ubb/` (Tempo) — `ubbset` (`mod.rs`: the exact feasible polygon of x(k+1), its interval
//!   hull dashed, the central estimate ⋆, the truth ◇, the Kalman ellipse) and `ubbwidth`
//!   (`width.rs`: the hull's widths over k with the Theorem 4 bound).
//! * `compare/` — `compare`: every method's set for one state on equal axes, each in the look
//!   its figures give (`Figures::compare_look`).
//!
//! Shared below them: the view types (`view.rs`: [`Panel`], [`View`], [`Zoom`], [`Frame`]), the
//! look in layers (`style/`: palette and number format, text, axes, marks, legend, notes), plane
//! windows and clipping (`geom.rs`) and the one backend type every panel is compiled for
//! (`erase.rs`). Colours: KF vermillion dashed, SCF blue solid, truth black, measurements grey
//! (Okabe–Ito, colorblind-safe).
//!
//! Fonts: on wasm32 plotters measures text with the browser. Natively it measures with a
//! ~41 KB subset of DejaVu Sans embedded in the binary (`fonts/`, registered through plotters'
//! `ab_glyph` feature, native only); SVG text names the generic family `sans-serif`.
//!
//! Nothing here panics on bad input: every drawing failure and every inconsistent view
//! becomes a crate [`Error`].

mod compare;
mod conformal;
mod erase;
mod figures;
pub mod geom;
mod glls;
mod lscr;
mod scf;
pub mod style;
mod ubb;
mod uniform;
mod view;

pub use view::{Frame, Panel, PanelSpec, View, Zoom};

use crate::error::{Error, Result};
use crate::method::Method;
use crate::scenario::{Report, Scenario};
use figures::{Canvas, Figures, Request};
use plotters::prelude::*;
use serde::Deserialize;
use std::sync::OnceLock;
use style::Fonts;

/// The one map from a [`Method`] to its figures (KF shares SCF's, with its regions alone).
pub(crate) fn make_figures(m: Method) -> &'static dyn Figures {
    match m {
        Method::Scf => &scf::ScfFigures { kalman_only: false },
        Method::Kf => &scf::ScfFigures { kalman_only: true },
        Method::Lscr => &lscr::LscrFigures,
        Method::Glls => &glls::GllsFigures,
        Method::UniformLp => &uniform::UniformFigures,
        Method::Ubb => &ubb::UbbFigures,
        Method::Conformal => &conformal::ConformalFigures,
        Method::Compare => &compare::CompareFigures,
    }
}

impl Panel {
    /// The method whose reports this panel draws (the first whose figures hold it).
    pub fn method(&self) -> Method {
        Method::ALL
            .into_iter()
            .find(|m| method_panels(*m).contains(self))
            .unwrap_or(Method::Scf)
    }
    /// Parse a lower-case name: the panel of that name among every method's figures.
    pub fn from_name(s: &str) -> Result<Panel> {
        Method::ALL
            .into_iter()
            .flat_map(method_panels)
            .find(|p| p.name() == s)
            .copied()
            .ok_or_else(|| {
                Error::field(
                    "panel",
                    format!(
                        "{} is unknown: choose {}",
                        crate::error::quoted(s),
                        choose(all_names())
                    ),
                )
            })
    }
}

/// Every panel name, each once, in the registry's order (for serde's "expected one of").
fn all_names() -> &'static [&'static str] {
    static NAMES: OnceLock<Vec<&'static str>> = OnceLock::new();
    NAMES.get_or_init(|| {
        let mut names: Vec<&'static str> = Vec::new();
        for p in Method::ALL.into_iter().flat_map(method_panels) {
            if !names.contains(&p.name()) {
                names.push(p.name());
            }
        }
        names
    })
}

/// The first figure of SCF, the default method's.
impl Default for Panel {
    fn default() -> Panel {
        method_panels(Method::Scf)[0]
    }
}

impl<'de> Deserialize<'de> for Panel {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Panel, D::Error> {
        let name = String::deserialize(d)?;
        Panel::from_name(&name).map_err(|_| serde::de::Error::unknown_variant(&name, all_names()))
    }
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
    // A panel draws its own method's reports only.
    let figures = make_figures(report.method);
    let panels = figures.panels();
    if !panels.contains(&view.panel) {
        let owner = view.panel.method();
        return Err(Error::field(
            "panel",
            format!(
                "\"{}\" draws {} reports, but this is {} report (method \"{}\"), with no {} part: choose {}",
                view.panel.name(),
                make_figures(owner).reports(),
                figures.reports(),
                report.method,
                owner.block().unwrap_or("SCF"),
                choose(&panels.iter().map(|p| p.name()).collect::<Vec<_>>()),
            ),
        ));
    }
    // All figure code runs on one backend type (see erase.rs).
    let mut adapter = erase::Adapter(backend);
    let request = Request {
        report,
        view,
        fonts,
        figures_of: make_figures,
    };
    figures.draw(view.panel, Canvas(erase::Erased(&mut adapter)), &request)
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
    let panel = useful_panels(&report).first().copied().unwrap_or_default();
    report_svg(&report, &View::new(panel), w, h)
}

/// The panels worth drawing for a report: those of its method's figures that the report fills
/// (`Figures::useful`: e.g. GLLS's precision only with a Monte Carlo study, SCF's coverage only
/// with a coverage curve, uniform's polygon not for a scalar state).
pub fn useful_panels(report: &Report) -> Vec<Panel> {
    let figures = make_figures(report.method);
    figures
        .panels()
        .iter()
        .copied()
        .filter(|&p| figures.useful(p, report))
        .collect()
}

/// Every panel a method's reports are drawn with, in the order worth showing (with
/// [`Panel::method`], its inverse).
pub fn method_panels(m: Method) -> &'static [Panel] {
    make_figures(m).panels()
}

/// "a, b or c".
fn choose(names: &[&str]) -> String {
    match names.split_last() {
        Some((last, [])) => last.to_string(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
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

// Native only: they measure text with the embedded font (the wasm build has none).
#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests;
