//! One step of a report, step by step ([`Scenario::explain`]): the quantities of one update
//! with the paper's equation numbers and their formulas as KaTeX source, for the page's
//! "One step, step by step" card. Each method says what its step is through
//! [`MethodScenario::explain`](super::MethodScenario::explain) (SCF/KF: the filter's update at t;
//! LSCR: the sign-perturbed sums at a point); a method without one refuses in words. The
//! numbers are computed by the same code the report's are, so they equal the report's.

use super::{make_method, Report, Scenario};
use crate::error::{Error, Result};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// The number(s) of one row: a scalar, a vector, a matrix (rows) or a word (a verdict).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum StepValue {
    Scalar(f64),
    Vector(Vec<f64>),
    Matrix(Vec<Vec<f64>>),
    Text(String),
}

impl StepValue {
    pub fn vector(v: &DVector<f64>) -> StepValue {
        StepValue::Vector(v.iter().copied().collect())
    }
    pub fn matrix(m: &DMatrix<f64>) -> StepValue {
        StepValue::Matrix(crate::linalg::to_rows(m))
    }
}

/// One quantity of the step.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct StepRow {
    /// What it is, in words ("prediction", "gain").
    pub name: String,
    /// The paper's equation number, e.g. "(35b)"; empty when the paper numbers none.
    pub equation: String,
    /// The formula as KaTeX source.
    pub tex: String,
    pub value: StepValue,
    /// Why or how, in words; may be empty.
    pub note: String,
}

/// The quantities of one step of a report.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct StepExplanation {
    /// The method's name ("scf", "lscr").
    pub method: String,
    /// The paper the equation numbers are from.
    pub paper: String,
    /// The step explained (the time t of the update, or LSCR's data length).
    pub t: usize,
    /// The point the quantities are evaluated at, when the step depends on one (LSCR).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<Vec<f64>>,
    /// One line saying what the step is.
    pub title: String,
    pub rows: Vec<StepRow>,
}

impl StepExplanation {
    pub(crate) fn row(
        &mut self,
        name: &str,
        equation: &str,
        tex: &str,
        value: StepValue,
        note: impl Into<String>,
    ) {
        self.rows.push(StepRow {
            name: name.into(),
            equation: equation.into(),
            tex: tex.into(),
            value,
            note: note.into(),
        });
    }
}

/// `t` within `range`, or a message naming the field and the range.
pub(crate) fn check_step(t: usize, range: std::ops::RangeInclusive<usize>) -> Result<()> {
    if range.contains(&t) {
        Ok(())
    } else {
        Err(Error::field(
            "explain.t",
            format!(
                "is {t}: the step explained must lie in {}..={} (the report's steps)",
                range.start(),
                range.end()
            ),
        ))
    }
}

/// A point given to the explanation must be finite numbers.
pub(crate) fn check_point(point: &[f64]) -> Result<()> {
    if let Some(i) = point.iter().position(|v| !v.is_finite()) {
        return Err(Error::field(
            "explain.x",
            format!("component {} of the point is not a finite number", i + 1),
        ));
    }
    Ok(())
}

impl Scenario {
    /// One step of `report` (this scenario's report), step by step: at step `t` (the report's
    /// time when `None`) and, for a method whose step depends on a state, at `point` (the
    /// report's estimate when `None`). Refuses an out-of-range t, a point that is not finite,
    /// and a method without a step-through, in words naming the field.
    pub fn explain(
        &self,
        report: &Report,
        t: Option<usize>,
        point: Option<&[f64]>,
    ) -> Result<StepExplanation> {
        if report.method != self.method {
            return Err(Error::field(
                "explain",
                format!(
                    "the report is of method \"{}\" but the scenario of \"{}\"",
                    report.method, self.method
                ),
            ));
        }
        if let Some(p) = point {
            check_point(p)?;
        }
        make_method(self.method).explain(self, report, t, point)
    }
}
