//! The shared view types: what the viewer chooses ([`View`]: a [`Panel`], a time, a [`Zoom`],
//! the methods hidden) and where a drawing landed ([`Frame`]). A panel is a name and its
//! alternative text, declared by its method's figures (`plot/<method>/`); the registry in
//! `plot/mod.rs` resolves names to panels (`Panel::from_name`, serde) by asking each method's
//! figures in turn.

use crate::method::Method;
use serde::{Deserialize, Serialize};

/// One picture of a method's reports, declared as a `static` by the method's figures.
#[derive(Debug)]
pub struct PanelSpec {
    /// Lower-case name, as in JSON, the CLI's `--panel` and the page's `data-panel`.
    pub name: &'static str,
    /// The figure in words: the text alternative of its canvas on the page (the numbers table
    /// beside it carries the values).
    pub alt_text: &'static str,
}

impl PanelSpec {
    /// A panel's name and alternative text.
    pub const fn new(name: &'static str, alt_text: &'static str) -> PanelSpec {
        PanelSpec { name, alt_text }
    }
}

/// Which picture: a handle on a [`PanelSpec`] of some method's figures. Two panels are the
/// same when their names are (names are unique across methods; a test checks it). Written in
/// JSON as its name.
#[derive(Clone, Copy)]
pub struct Panel(&'static PanelSpec);

impl Panel {
    /// The panel of `spec` (for the figures that declare it).
    pub const fn of(spec: &'static PanelSpec) -> Panel {
        Panel(spec)
    }
    /// Lower-case name as in JSON ("state", "series", "coverage", "region", "singular", …).
    pub fn name(&self) -> &'static str {
        self.0.name
    }
    /// The figure in words: the text alternative of its canvas on the page (the numbers
    /// table beside it carries the values).
    pub fn alt_text(&self) -> &'static str {
        self.0.alt_text
    }
}

impl PartialEq for Panel {
    fn eq(&self, other: &Panel) -> bool {
        self.0.name == other.0.name
    }
}
impl Eq for Panel {}

impl std::fmt::Debug for Panel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Panel({:?})", self.0.name)
    }
}

impl Serialize for Panel {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.0.name)
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
