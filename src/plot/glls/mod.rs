//! The figures of GLLS reports (Gubarev & Mishchenko, "Interval state estimator for linear
//! systems with known structure"), each with a marker at the horizon s in use: Fig. 1
//! (`singular`) and Fig. 2 (`index`) in `horizon.rs`, with the checks and horizon axes all
//! GLLS panels share; the state plane at time k (`plane`) in `plane.rs`; Figs. 3–4
//! (`precision`) in `precision.rs`. In compare, GLLS's guaranteed ball is reddish purple.

mod horizon;
mod plane;
mod precision;

use crate::error::Result;
use crate::plot::figures::{Canvas, CompareLook, Figures, Request, SetFill};
use crate::plot::style::GLLS_BALL;
use crate::plot::view::{Frame, Panel};
use crate::scenario::Report;
use horizon::{check, draw_index, draw_singular, INDEX, PLANE, PRECISION, SINGULAR};

static PANELS: [Panel; 4] = [
    Panel::of(&SINGULAR),
    Panel::of(&INDEX),
    Panel::of(&PLANE),
    Panel::of(&PRECISION),
];

/// The figures of a GLLS report.
pub(crate) struct GllsFigures;

impl Figures for GllsFigures {
    fn panels(&self) -> &'static [Panel] {
        &PANELS
    }
    fn reports(&self) -> &'static str {
        "a GLLS"
    }
    fn useful(&self, panel: Panel, report: &Report) -> bool {
        // The error boxes need the Monte Carlo study.
        panel != Panel::of(&PRECISION)
            || report.glls.as_ref().is_some_and(|g| g.precision.is_some())
    }
    fn draw(&self, panel: Panel, canvas: Canvas<'_>, request: &Request) -> Result<Frame> {
        let (report, fonts) = (request.report, request.fonts);
        check(report, panel)?;
        canvas.paint(|root| {
            if panel == Panel::of(&SINGULAR) {
                draw_singular(root, report, fonts)
            } else if panel == Panel::of(&INDEX) {
                draw_index(root, report, fonts)
            } else if panel == Panel::of(&PLANE) {
                plane::draw(root, report, fonts)
            } else {
                precision::draw(root, report, fonts)
            }
        })
    }
    fn compare_look(&self) -> Option<CompareLook> {
        Some(CompareLook {
            color: GLLS_BALL,
            label: "GLLS ball",
            dashed: false,
            fill: SetFill::None,
            layer: 2,
        })
    }
}
