//! The work budget: an estimate of what a scenario costs, from its sizes alone, checked once
//! before any heavy computation ([`super::Scenario::run`] and [`super::Scenario::study`]).
//!
//! Each method's scenario file states the dominant cost terms of its algorithm as a [`Work`]
//! (`MethodScenario::work`): operations, calibrated so that one unit is about a nanosecond
//! natively on the build machine, and bytes held at the peak (the method's matrices, the report
//! and its JSON). A report must fit [`MAX_OPERATIONS`] (about 2 s natively) and [`MAX_BYTES`];
//! a study's preparation and one of its runs must fit them too (a study runs in chunks, so its
//! run count is not limited by time). The per-field limits ([`super::limits`]) give the
//! controls their ranges; the combined estimate is what keeps every accepted report within
//! about 2 s when several fields sit at their limits at once.
//!
//! A size past its own per-field limit (the steps, the model's states, the windows, the LSCR
//! strings) is that limit's to refuse, with its own message: the estimate is then empty.
//!
//! A refusal names the field of the largest term, the sizes that drive it, its formula, the
//! limit and what to change; where a Monte Carlo inside the report is the cost, it says that
//! more runs go through the chunked study. `cargo test --profile bench --test suite
//! fuzz::work_at_the_limits -- --ignored --nocapture` measures the slowest accepted scenarios.

use super::Scenario;
use crate::error::{Error, Result};
use crate::model::MatrixSpec;

/// Operations a report (or a study's preparation and one run) may cost: about 2 s natively on
/// the 2-core build machine, where one operation of the estimates is about a nanosecond.
pub const MAX_OPERATIONS: f64 = 2e9;

/// Bytes a report may hold at its peak (the method's matrices, the report and its JSON tree):
/// the process stays within about 256 MB.
pub const MAX_BYTES: f64 = 200e6;

/// The refusal's pointer to the chunked study, for a Monte Carlo inside a report.
const STUDY_HINT: &str = "; more runs go through the chunked study (`confset experiment`, or the page's Monte Carlo, which runs in steps)";

/// One term of an estimate: the field to blame, the sizes that drive it and what it costs.
#[derive(Debug, Clone, PartialEq)]
pub struct Term {
    /// The JSON path the refusal names.
    pub field: String,
    /// The sizes after the field's name, e.g. "(100 states) with simulate.steps = 10000".
    pub sizes: String,
    /// The cost model in symbols, e.g. "steps · (n + q)³".
    pub formula: &'static str,
    /// Operations (about a nanosecond each natively) or bytes.
    pub amount: f64,
    /// What to change, e.g. "fewer steps or states".
    pub advice: String,
    /// Whether the term is a Monte Carlo inside the report, which the chunked study can run
    /// instead.
    pub study: bool,
}

impl Term {
    /// A term about `field`: its sizes, formula and amount; advice and the study hint follow.
    pub fn new(
        field: impl Into<String>,
        sizes: impl Into<String>,
        formula: &'static str,
        amount: f64,
    ) -> Term {
        Term {
            field: field.into(),
            sizes: sizes.into(),
            formula,
            amount,
            advice: String::new(),
            study: false,
        }
    }

    /// What to change.
    pub fn advice(mut self, advice: impl Into<String>) -> Term {
        self.advice = advice.into();
        self
    }

    /// The term is a Monte Carlo that the chunked study runs instead.
    pub fn study(mut self) -> Term {
        self.study = true;
        self
    }
}

/// What a scenario's report (or a study's preparation and one run) costs: its terms of
/// operations and of bytes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Work {
    pub operations: Vec<Term>,
    pub bytes: Vec<Term>,
}

/// What the estimate is for, in the refusal's words.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Job {
    /// The report of `run`.
    Report,
    /// A study: its preparation and one run (the runs come in chunks), with the run count
    /// that overrides the scenario's (for what a study keeps per run).
    Study { runs: Option<usize> },
}

impl Job {
    fn words(self) -> &'static str {
        match self {
            Job::Report => "a report",
            Job::Study { .. } => "a study's preparation and one run",
        }
    }
}

impl Work {
    /// Add a term of operations.
    pub fn ops(&mut self, term: Term) -> &mut Work {
        self.operations.push(term);
        self
    }

    /// Add a term of bytes.
    pub fn mem(&mut self, term: Term) -> &mut Work {
        self.bytes.push(term);
        self
    }

    /// Total operations.
    pub fn total_operations(&self) -> f64 {
        self.operations.iter().map(|t| t.amount).sum()
    }

    /// Total bytes.
    pub fn total_bytes(&self) -> f64 {
        self.bytes.iter().map(|t| t.amount).sum()
    }

    /// Within [`MAX_OPERATIONS`] and [`MAX_BYTES`], or an error naming the largest term's field.
    pub fn check(&self, job: Job) -> Result<()> {
        let refuse =
            |terms: &[Term], total: f64, limit: f64, unit: &dyn Fn(f64) -> String, what: &str| {
                if !(total > limit) {
                    return Ok(());
                }
                let Some(t) = terms.iter().max_by(|a, b| a.amount.total_cmp(&b.amount)) else {
                    return Ok(());
                };
                let share = if t.amount < 0.95 * total {
                    format!(" of the {} in all", unit(total))
                } else {
                    String::new()
                };
                Err(Error::field(
                    t.field.clone(),
                    format!(
                    "{} asks for about {}{share} ({}); {} is limited to about {} ({what}): {}{}",
                    t.sizes,
                    unit(t.amount),
                    t.formula,
                    job.words(),
                    unit(limit),
                    t.advice,
                    if t.study { STUDY_HINT } else { "" }
                ),
                ))
            };
        refuse(
            &self.operations,
            self.total_operations(),
            MAX_OPERATIONS,
            &|x| format!("{x:.1e} operations"),
            "about 2 s natively",
        )?;
        refuse(
            &self.bytes,
            self.total_bytes(),
            MAX_BYTES,
            &|x| format!("{:.0} MB", x / 1e6),
            "the page's worker stays within 256 MB",
        )
    }
}

/// Rows and columns of a model matrix as written (the first of a sequence), 0 × 0 when absent:
/// the estimate reads sizes only; the method's validation judges the entries.
pub(crate) fn shape(spec: &Option<MatrixSpec>) -> (usize, usize) {
    match spec {
        Some(MatrixSpec::Constant(rows)) => rows_shape(rows),
        Some(MatrixSpec::Sequence(seq)) => seq.first().map_or((0, 0), |m| rows_shape(m)),
        None => (0, 0),
    }
}

/// Rows and columns of a list of rows (the longest row).
pub(crate) fn rows_shape(rows: &[Vec<f64>]) -> (usize, usize) {
    (rows.len(), rows.iter().map(Vec::len).max().unwrap_or(0))
}

/// A count as a float for the estimates.
pub(crate) fn f(x: usize) -> f64 {
    x as f64
}

impl Scenario {
    /// The time steps of the scenario as written (data rows or simulated steps; 0 when neither).
    pub(crate) fn written_steps(&self) -> usize {
        match (&self.data, &self.simulate) {
            (Some(d), _) => d.y.len(),
            (None, Some(s)) => s.steps,
            (None, None) => 0,
        }
    }

    /// The field that holds the step count: `data.y` or `simulate.steps`.
    pub(crate) fn steps_field(&self) -> &'static str {
        if self.data.is_some() {
            "data.y"
        } else {
            "simulate.steps"
        }
    }
}
