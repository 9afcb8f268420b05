//! The figures of SCF and KF reports (Carè, Campi and Weyer; KF shares them with its SCF
//! regions left out): [`STATE`] (`state.rs`), [`SERIES`] (`series.rs`) and [`COVERAGE`]
//! (`coverage.rs`, the SCF paper's Fig. 1). In compare, KF is the dashed vermillion ellipse and
//! SCF the solid blue one, as on these panels.

mod context;
mod coverage;
mod series;
mod state;

use crate::error::{Error, Result};
use crate::plot::figures::{Canvas, CompareLook, Figures, Request, SetFill};
use crate::plot::style::{KF, SCF};
use crate::plot::view::{Frame, Panel};
use crate::scenario::Report;
use context::Ctx;
use coverage::COVERAGE;
use series::SERIES;
use state::STATE;

static PANELS: [Panel; 3] = [Panel::of(&STATE), Panel::of(&SERIES), Panel::of(&COVERAGE)];

/// The figures of a KF/SCF report; `kalman_only` for method `kf` (its look in compare).
pub(crate) struct ScfFigures {
    pub kalman_only: bool,
}

impl Figures for ScfFigures {
    fn panels(&self) -> &'static [Panel] {
        &PANELS
    }
    fn reports(&self) -> &'static str {
        "a KF/SCF"
    }
    fn useful(&self, panel: Panel, report: &Report) -> bool {
        panel != Panel::of(&COVERAGE) || report.coverage_curve.is_some()
    }
    fn draw(&self, panel: Panel, canvas: Canvas<'_>, request: &Request) -> Result<Frame> {
        let cx = Ctx::new(request.report, request.view, request.fonts)?;
        if panel == Panel::of(&COVERAGE) {
            if request.report.coverage_curve.is_none() {
                return Err(Error::field(
                    "coverage_curve",
                    "is not in this report: ask for it in the scenario (\"scf\": {\"coverage_curve\": {\"component\", \"from\", \"to\"}}) to draw the coverage panel",
                ));
            }
            canvas.paint(|root| coverage::draw(root, &cx))
        } else if panel == Panel::of(&SERIES) {
            canvas.paint(|root| series::draw(root, &cx))
        } else {
            canvas.paint(|root| state::draw(root, &cx))
        }
    }
    fn compare_look(&self) -> Option<CompareLook> {
        Some(if self.kalman_only {
            CompareLook {
                color: KF,
                label: "Kalman",
                dashed: true,
                fill: SetFill::None,
                layer: 2,
            }
        } else {
            CompareLook {
                color: SCF,
                label: "SCF",
                dashed: false,
                fill: SetFill::None,
                layer: 2,
            }
        })
    }
}
