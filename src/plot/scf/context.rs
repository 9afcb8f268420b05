//! What every KF/SCF panel draws from: the checked report and view ([`Ctx`]), with the
//! shown time, the truth and measurements at a time, and the axis names.

use crate::error::{Error, Result};
use crate::plot::style::{sub, Fonts, RecordTimes};
use crate::plot::view::View;
use crate::scenario::{FigureContext, Report, TimeIndex};
use crate::scf::ScfStep;

fn default_name(i: usize) -> String {
    // 1-based, as everywhere the page and the figures number components.
    format!("state x{}", sub(i + 1))
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
    pub fn new(report: &'a Report, view: &'a View, fonts: Fonts) -> Result<Self> {
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
                    "names component {i}, but the state has {} (0-based)",
                    crate::error::counted(report.n, "component", "components")
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
    /// Measurement of component i at time s, when a row of y measures it directly; none at a
    /// gap of the user's record (a NaN in the report's `y`: not measured, so no marker).
    pub fn measurement(&self, s: usize, i: usize) -> Option<f64> {
        let [_, row] = *self.figure().measured.iter().find(|[c, _]| *c == i)?;
        self.report
            .y
            .get(s.checked_sub(1)?)?
            .get(row)
            .copied()
            .filter(|v| !v.is_nan())
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
    /// The figure title, or `default` when the scenario has none (the KF/SCF panels title a
    /// figure by the scenario alone; the others use `style::title`).
    pub fn title(&self, default: &str) -> String {
        self.figure()
            .title
            .clone()
            .unwrap_or_else(|| default.to_string())
    }
    /// The record's own time at the steps t = 1, 2, … (row t − 1; none for a simulation).
    pub fn record(&self) -> RecordTimes<'a> {
        RecordTimes::of(&self.report.figure, TimeIndex::OneBased)
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
