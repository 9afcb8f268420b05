//! What each method's figures implement ([`Figures`]), and what they draw on.
//!
//! A method's figures live in `plot/<method>/` and are reached through the one registry,
//! `plot::make_figures`. Shared code (the dispatch in `plot::draw`, the panel lists, the
//! compare panel's looks) loops over these descriptors and never asks a method's kind, as
//! Clarabel.rs's composite cone loops over its cones.

use super::erase::{de, Erased};
use super::style::Fonts;
use super::view::{Frame, Panel, View};
use crate::error::Result;
use crate::method::Method;
use crate::scenario::Report;
use plotters::coord::Shift;
use plotters::prelude::*;

/// A drawing area (the panels split off title, legend and charts from the root).
pub(crate) type Area<DB> = DrawingArea<DB, Shift>;

/// The figures of one method's reports.
pub(crate) trait Figures: Sync {
    /// Every panel of the method's reports, in the order worth showing.
    fn panels(&self) -> &'static [Panel];
    /// The reports these figures draw, in words for messages ("a KF/SCF", "an LSCR").
    fn reports(&self) -> &'static str;
    /// Whether `report` fills `panel` (one of [`Figures::panels`]): a panel the report has no
    /// part for is left out of the page's cards and of `confset figures`.
    fn useful(&self, _panel: Panel, _report: &Report) -> bool {
        true
    }
    /// Check the report for `panel`, then paint it on `canvas`. A report that cannot be drawn
    /// is refused before the canvas is touched, so the page keeps its last picture.
    fn draw(&self, panel: Panel, canvas: Canvas<'_>, request: &Request) -> Result<Frame>;
    /// How the method's set looks in the compare panel; `None` for a method compare does not
    /// run (a set of it in a compare report is refused).
    fn compare_look(&self) -> Option<CompareLook> {
        None
    }
}

/// What a panel is drawn from.
pub(crate) struct Request<'a> {
    pub report: &'a Report,
    pub view: &'a View,
    pub fonts: Fonts,
    /// The registry (`plot::make_figures`), handed down so that a figure of several methods
    /// (compare) asks each its look without importing the layer above.
    pub figures_of: fn(Method) -> &'static dyn Figures,
}

/// A method's set in the compare panel: one colour per method, from the palette.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CompareLook {
    pub color: RGBColor,
    /// The legend's name of the method's set.
    pub label: &'static str,
    /// Drawn dashed (the Kalman ellipse, as on its own panels).
    pub dashed: bool,
    pub fill: SetFill,
    /// Filled sets are drawn first (lower layers), outlines over them.
    pub layer: u8,
}

/// How a set's inside is painted in the compare panel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum SetFill {
    /// Outline only.
    None,
    /// The light fill of the set's own colour (`style::fill`).
    Light,
    /// A tint of another colour at `opacity`, under the outline (LSCR's yellow, as on its panel).
    Tint { color: RGBColor, opacity: f64 },
}

/// The page a panel paints on: one backend type for every panel ([`Erased`]), so each panel is
/// compiled once rather than once per backend type.
pub(crate) struct Canvas<'a>(pub(crate) Erased<'a>);

impl<'a> Canvas<'a> {
    /// White page, `draw`, present.
    pub fn paint(self, draw: impl FnOnce(&Area<Erased<'a>>) -> Result<Frame>) -> Result<Frame> {
        let root = self.0.into_drawing_area();
        root.fill(&WHITE).map_err(de)?;
        let frame = draw(&root)?;
        root.present().map_err(de)?;
        Ok(frame)
    }
}
