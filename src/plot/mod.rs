//! Figures, drawn with plotters on any backend (SVG natively, canvas in the browser).
//!
//! STUB — the drawing code is being written; the API below is the contract the CLI and the wasm
//! bindings use.
use crate::error::{Error, Result};
use crate::scenario::{Report, Scenario};
use plotters::prelude::*;
use serde::{Deserialize, Serialize};

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
}

/// What to draw.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct View {
    #[serde(default)]
    pub panel: Panel,
    /// Time shown (default: the report's `time`).
    #[serde(default)]
    pub time: Option<usize>,
}

/// Where the plotting area landed, so a page can map the cursor to chart units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Frame {
    pub x_range: (f64, f64),
    pub y_range: (f64, f64),
    /// Pixel box (left, top, right, bottom) of the plotting area in backend pixels.
    pub plot_area: (i32, i32, i32, i32),
    pub x_label: String,
    pub y_label: String,
}

/// Draw `view` of `report` on any plotters backend.
pub fn draw<DB: DrawingBackend>(_backend: DB, _report: &Report, _view: &View) -> Result<Frame> {
    Err(Error::field("", "figures are not drawn yet"))
}

/// One view of a report as SVG text.
pub fn report_svg(report: &Report, view: &View, w: u32, h: u32) -> Result<String> {
    let mut s = String::new();
    draw(SVGBackend::with_string(&mut s, (w, h)), report, view)?;
    Ok(s)
}

/// The scenario's default figure as SVG text.
pub fn scenario_svg(s: &Scenario, w: u32, h: u32) -> Result<String> {
    report_svg(
        &s.run()?,
        &View {
            panel: Panel::State,
            time: None,
        },
        w,
        h,
    )
}
