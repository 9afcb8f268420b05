//! The figures of LSCR reports (Weyer & Campi): one panel, [`REGION`] (`region.rs`, Figs. 1–3;
//! for a scalar state `line.rs`: X̂'s intervals on one axis),
//! since an LSCR report has no time steps. In compare, LSCR's region is black over its yellow
//! tint, as on its panel, and drawn first (under the others).

mod line;
pub(crate) mod region;

use crate::error::Result;
use crate::plot::figures::{Canvas, CompareLook, Figures, Request, SetFill};
use crate::plot::style::{LSCR, LSCR_TINT};
use crate::plot::view::{Frame, Panel};
use region::REGION;

static PANELS: [Panel; 1] = [Panel::of(&REGION)];

/// The figures of an LSCR report.
pub(crate) struct LscrFigures;

impl Figures for LscrFigures {
    fn panels(&self) -> &'static [Panel] {
        &PANELS
    }
    fn reports(&self) -> &'static str {
        "an LSCR"
    }
    fn draw(&self, _panel: Panel, canvas: Canvas<'_>, request: &Request) -> Result<Frame> {
        region::lscr_of(request.report)?;
        canvas.paint(|root| region::draw(root, request))
    }
    fn compare_look(&self) -> Option<CompareLook> {
        Some(CompareLook {
            color: LSCR,
            label: "LSCR",
            dashed: false,
            // Denser than the tint of its own panel (0.22): here it lies under five outlines.
            fill: SetFill::Tint {
                color: LSCR_TINT,
                opacity: 0.45,
            },
            layer: 0,
        })
    }
}
