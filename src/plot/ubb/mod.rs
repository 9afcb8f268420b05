//! The figures of set-membership reports (Tempo, method `"ubb"`): `ubbset` (`set.rs`: the
//! exact feasible set of x(k+1) at the report's step k with its interval hull, the central
//! estimate, the truth and the Kalman ellipse, with the checks both panels share; with one
//! state, `band.rs`: the intervals over the steps) and `ubbwidth` (`width.rs`: the hull's
//! widths over k with the Theorem 4 bound). Both draw the set `ubb.set` chooses: the predicted
//! X(k+1 | y(0 … k)) or the filtered X(k | y(0 … k)). In compare,
//! Tempo's set is bluish green with a light fill.

mod band;
mod set;
mod width;

use crate::error::Result;
use crate::plot::figures::{Canvas, CompareLook, Figures, Request, SetFill};
use crate::plot::style::TEMPO_SET;
use crate::plot::view::{Frame, Panel};
use set::{check, draw_set, SET_PANEL, WIDTH_PANEL};

static PANELS: [Panel; 2] = [Panel::of(&SET_PANEL), Panel::of(&WIDTH_PANEL)];

/// The figures of a set-membership report.
pub(crate) struct UbbFigures;

impl Figures for UbbFigures {
    fn panels(&self) -> &'static [Panel] {
        &PANELS
    }
    fn reports(&self) -> &'static str {
        "a set-membership"
    }
    fn draw(&self, panel: Panel, canvas: Canvas<'_>, request: &Request) -> Result<Frame> {
        check(request.report, panel)?;
        canvas.paint(|root| {
            if panel == Panel::of(&SET_PANEL) {
                draw_set(root, request)
            } else {
                width::draw(root, request)
            }
        })
    }
    fn compare_look(&self) -> Option<CompareLook> {
        Some(CompareLook {
            color: TEMPO_SET,
            label: "Tempo set",
            dashed: false,
            fill: SetFill::Light,
            layer: 1,
        })
    }
}
