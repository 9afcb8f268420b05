//! The figures of uniform-innovation reports (Pavelková, method `uniform_lp`), each with a
//! time cursor at the window the report solved: `ustates` and `uoutput` (`time_series.rs`,
//! Figs. 1–2, with the checks and time axes all uniform panels share), `uparams`
//! (`params.rs`, Fig. 3) and `upolygon` (`polygon.rs`: the exact consistent-state polygon; not
//! for a scalar state). In compare, the uniform-LP set is sky blue with a light fill.

mod params;
mod polygon;
mod time_series;

use crate::error::Result;
use crate::plot::figures::{Canvas, CompareLook, Figures, Request, SetFill};
use crate::plot::style::UNIFORM_SET;
use crate::plot::view::{Frame, Panel};
use crate::scenario::Report;
use time_series::{check, draw_output, draw_states, OUTPUT, PARAMS, POLYGON, STATES};

static PANELS: [Panel; 4] = [
    Panel::of(&STATES),
    Panel::of(&OUTPUT),
    Panel::of(&PARAMS),
    Panel::of(&POLYGON),
];

/// The figures of a uniform-innovation report.
pub(crate) struct UniformFigures;

impl Figures for UniformFigures {
    fn panels(&self) -> &'static [Panel] {
        &PANELS
    }
    fn reports(&self) -> &'static str {
        "a uniform-innovation"
    }
    fn useful(&self, panel: Panel, report: &Report) -> bool {
        // A scalar state (n = 1) has no consistent-state polygon.
        panel != Panel::of(&POLYGON)
            || report
                .uniform
                .as_ref()
                .is_some_and(|u| u.at.polygon.is_some())
    }
    fn draw(&self, panel: Panel, canvas: Canvas<'_>, request: &Request) -> Result<Frame> {
        check(request.report, request.view, panel)?;
        canvas.paint(|root| {
            if panel == Panel::of(&STATES) {
                draw_states(root, request)
            } else if panel == Panel::of(&OUTPUT) {
                draw_output(root, request)
            } else if panel == Panel::of(&PARAMS) {
                params::draw(root, request)
            } else {
                polygon::draw(root, request)
            }
        })
    }
    fn compare_look(&self) -> Option<CompareLook> {
        Some(CompareLook {
            color: UNIFORM_SET,
            label: "uniform LP set",
            dashed: false,
            fill: SetFill::Light,
            layer: 1,
        })
    }
}
