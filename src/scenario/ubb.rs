//! The `ubb` block of a scenario and its report (method `"ubb"`): Tempo's set-membership state
//! estimation ([`crate::ubb`]).
//!
//! ```json
//! {"method": "ubb",
//!  "model": {"F": [[0.7, 0.2], [-0.2, 0.7]], "G": [[0.5], [1]], "H": [[1, 0]]},
//!  "simulate": {"steps": 60, "seed": 1},
//!  "ubb": {"eps": 0.2, "tau": 0.1, "delta": [2, 2], "alpha": 50, "beta": 50, "gamma": 0.1,
//!          "norm": "linf", "noise": "random", "time": 40}}
//! ```
//!
//! The system is (35): x(k+1) = F x(k) + G u(k) + B v(k), y(k) = H x(k) + η(k), with the
//! process noise u bounded by τ (37)/(45), the measurement noise η by ε (46), the known input
//! v = `simulate.u` or `data.u` through `model.B` (Leontief demand) and x(0) in the box
//! `x0_center ± delta` (δ = null: unbounded). Without `H` there are no measurements (Markov
//! chain); `basis` makes H time-varying, H(t) = [g₁(t+1) … g_l(t+1)] (Example 1). Times are
//! the paper's: y(0 … steps−1), and step k (row k of the report's track, 0-based; the record's
//! row k + 1) holds the predicted set X(k+1 | y(0 … k)) (38) and the filtered set
//! X(k | y(0 … k)) (`track[k].filtered`); `ubb.set` chooses which the figures draw. A state of
//! one component (r = 1) has intervals for sets. A missing measurement (`null` in `data.y`) is
//! a step without a measurement strip ([`crate::ubb`]'s note), and the report says where.
//!
//! The file ends with the method's presets (`// Presets`: the menu entries and their
//! builders), re-exported by [`crate::presets`].

use super::budget::{f, rows_shape, shape, Job, Term, Work};
use super::compare::{
    Assumption, CompareMember, ComparePrepared, PlaneReading, PlaneSet, POLYGON_BUDGET,
};
use super::csv::{cells, flag, Table};
use super::preset::Preset;
use super::{detail_of, detail_value, Cursor, MethodScenario, Report, Scenario, Source};
use crate::error::{quoted, Error, Result};
use crate::linalg;
use crate::method::Method;
use crate::model::ModelSpec;
use crate::sets::{box_corners, polygon_area, Ellipsoid, SupportPolygon};
use crate::stats::chi2_quantile;
use crate::study::{self, Runs, Study};
use crate::ubb::{
    Bounds, IntervalHull, KalmanStep, L1Form, LinearEstimate, LpSize, NoiseMode, Norm, Run,
    Smoothing, StateProblem, StateStep, System,
};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use std::ops::RangeInclusive;

/// The guarantee study: `runs` fresh simulations checked at the step k of `ubb.time`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GuaranteeSpec {
    #[serde(default = "default_guarantee_runs")]
    pub runs: usize,
}
fn default_guarantee_runs() -> usize {
    2000
}

/// The `ubb` block.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct UbbSpec {
    /// Norm of the stacked noise sequences: "linf" (per sample, (45)–(46)), "l1" or "l2".
    #[serde(default = "default_norm")]
    pub norm: Norm,
    /// Theorem 3's form of l1 bounds: "lifted" or "enumerated" (2^{m−1} rows, small m only).
    #[serde(default = "default_l1_form")]
    pub l1_form: L1Form,
    /// Bound ε of the measurement noise (46).
    pub eps: f64,
    /// Bound τ of the process noise (45).
    #[serde(default)]
    pub tau: f64,
    /// Half-widths of the box of x(0) (one number: the same for all); null: δ = ∞.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub delta: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x0_center: Option<Vec<f64>>,
    /// Σ x(0) (a probability vector: 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x0_sum: Option<f64>,
    /// Smoothing constants α (45) and β (46); null: ∞ (no smoothing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beta: Option<f64>,
    /// Truncation accuracy γ of Theorem 5: the window is j + 1 steps, j from (58).
    #[serde(default = "default_gamma")]
    pub gamma: f64,
    /// Window length set by hand (overrides γ).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub window: Option<usize>,
    /// Simulated noise: "random" (uniform within the bound) or "bound" (± the bound).
    #[serde(default = "default_noise")]
    pub noise: NoiseMode,
    /// The step k shown (the set of x(k+1)); default: the last.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<usize>,
    /// The set the figures draw: "predicted", X(k+1 | y(0 … k)) (the paper's (38), the
    /// default), or "filtered", X(k | y(0 … k)). The report holds both.
    #[serde(default, skip_serializing_if = "SetChoice::is_predicted")]
    pub set: SetChoice,
    /// State components of the polygon.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane: Option<[usize; 2]>,
    /// Most LPs spent on the polygon.
    #[serde(default = "default_budget")]
    pub budget: usize,
    /// Basis functions of Example 1: "1", "k", "k2", "sin:P", "cos:P" (period P).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub basis: Option<Vec<String>>,
    /// True noise levels of the simulation when they differ from the assumed bounds (default:
    /// the bounds). Bounds below the truth can contradict the data (an infeasible LP) or
    /// lose the truth: the page uses this to show what a wrong bound does.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sim_eps: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sim_tau: Option<f64>,
    /// Level of the Kalman ellipsoid compared with the set.
    #[serde(default = "default_kf_level")]
    pub kf_level: f64,
    /// The guarantee study (`confset experiment`, the page's counter).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub guarantee: Option<GuaranteeSpec>,
}
/// Which of a step's two sets the figures draw ([`UbbSpec::set`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SetChoice {
    /// X(k+1 | y(0 … k)): the state one step ahead of the data (38).
    #[default]
    Predicted,
    /// X(k | y(0 … k)): the state at the last measurement's time.
    Filtered,
}

impl SetChoice {
    pub fn is_predicted(&self) -> bool {
        *self == SetChoice::Predicted
    }
}

fn default_norm() -> Norm {
    Norm::Linf
}
fn default_l1_form() -> L1Form {
    L1Form::Lifted
}
fn default_gamma() -> f64 {
    0.1
}
fn default_noise() -> NoiseMode {
    NoiseMode::Random
}
fn default_budget() -> usize {
    128
}
fn default_kf_level() -> f64 {
    0.99
}

/// Longest window accepted.
pub const MAX_WINDOW: usize = 400;

/// Most states of a set-membership model: a report within about 2 s.
pub const MAX_STATES: usize = 10;

/// Theorems 4 and 5 for the scenario (l∞-induced norms).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct SmoothingReport {
    pub a_norm: f64,
    pub b_norm: f64,
    /// ‖A‖·e^{1/α}.
    pub ratio: f64,
    /// Theorem 4 (47), when ratio < 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limit: Option<f64>,
    /// Theorem 5 (58), when it applies.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub j: Option<usize>,
    /// (55) at the last step with that j.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tail: Option<f64>,
    /// Why Theorem 4/5 do not apply, or why the window is not j + 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// The filtered set X(k | y(0 … k)) of a step of the track: its interval hull, central
/// estimate and local error, and the Kalman filter's x(k|k), each with whether it holds the
/// true x(k).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct FilteredHull {
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    pub center: Vec<f64>,
    pub radius: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inside: Option<bool>,
    pub kf_mean: Vec<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kf_inside: Option<bool>,
}

/// One step of the track: the interval hull of x(k+1).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct TrackStep {
    pub k: usize,
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    /// Central estimate (31) and its local error (5) (largest half-width).
    pub center: Vec<f64>,
    pub radius: f64,
    /// The true x(k+1) is in the hull (solver tolerance `TOL`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inside: Option<bool>,
    /// KF prediction x(k+1|k) and whether its ellipsoid holds the truth.
    pub kf_mean: Vec<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kf_inside: Option<bool>,
    /// The filtered set X(k | y(0 … k)) of the same step; absent when it is unbounded though
    /// the predicted set is not (δ = ∞ with a singular A: [`crate::ubb::StateStep::filtered`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filtered: Option<FilteredHull>,
}

/// The filtered set X(k | y(0 … k)) at the time cursor's step: its exact polygon in the
/// plane, hull, centre, local error, the true x(k), the Kalman ellipse of x(k|k) and Theorem 2
/// for x_i(k).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct UbbFiltered {
    pub polygon: SupportPolygon,
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    pub center: Vec<f64>,
    pub radius: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth: Option<Vec<f64>>,
    pub kf: Ellipsoid,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub linear: Option<Vec<LinearEstimate>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub linear_refused: Option<String>,
}

/// The step at the time cursor.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct UbbStep {
    pub k: usize,
    /// First time of the window.
    pub first: usize,
    pub polygon: SupportPolygon,
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    pub center: Vec<f64>,
    pub radius: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth: Option<Vec<f64>>,
    /// The KF ellipse in the plane at `kf_level`.
    pub kf: Ellipsoid,
    pub size: LpSize,
    /// Central prediction interval of the next output y(k+1) = H(k+1)x(k+1) + η (Example 1's
    /// f(m+1)), per output.
    pub prediction: Vec<[f64; 2]>,
    /// Theorem 2 for the two `plane` components of x(k+1): the linear optimal estimate (25)
    /// beside the central one, its error E(φ_o) (22) and its active constraints (l∞ bounds
    /// only: absent for l1 and l2). At this step only, not in the track: one LP per component
    /// and step where the planar path needs none (ubb-track's report took 211 ms with it at
    /// every step, 17 ms without).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub linear: Option<Vec<LinearEstimate>>,
    /// Why Theorem 2's estimate is missing at this step though the bounds are l∞ (its LP (22)
    /// refused: the set itself does not depend on it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub linear_refused: Option<String>,
    /// The filtered set X(k | y(0 … k)) at this step (absent when unbounded, as in the track).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filtered: Option<UbbFiltered>,
}

/// The report.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct UbbReport {
    pub r: usize,
    pub p: usize,
    pub q: usize,
    pub steps: usize,
    pub norm: Norm,
    pub l1_form: L1Form,
    pub noise: NoiseMode,
    pub window: usize,
    pub gamma: f64,
    /// The plotted components (with one state, [0, 0]: the polygon of the plane (x₁, x₁) is
    /// the diagonal segment of the interval).
    pub plane: [usize; 2],
    /// The set the figures draw (`ubb.set`).
    #[serde(default, skip_serializing_if = "SetChoice::is_predicted")]
    pub set: SetChoice,
    /// Names of the state components for axes and tables: "x₁", … or, with a basis
    /// (Example 1), the coefficients "a₁ (1)", "a₂ (k)", ….
    pub state_names: Vec<String>,
    pub smoothing: SmoothingReport,
    /// Per-component noise levels of the simulation.
    pub u_level: f64,
    pub eta_level: f64,
    /// x(0 … steps) (simulation) and y(0 … steps−1) (a gap of the record is `null`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_true: Option<Vec<Vec<f64>>>,
    #[serde(with = "super::gap_rows")]
    pub y: Vec<Vec<f64>>,
    /// Steps whose set is bounded (with δ = ∞ the first steps are not).
    pub track: Vec<TrackStep>,
    /// Steps where the truth left the hull (must be 0) and where it left the KF ellipsoid.
    pub outside: usize,
    pub kf_outside: usize,
    /// The same counts for the filtered sets and the Kalman filter's x(k|k), against x(k).
    pub filtered_outside: usize,
    pub filtered_kf_outside: usize,
    pub at: UbbStep,
}

impl UbbReport {
    /// The steps of the time cursor, as [`UbbCursor`]'s: from the first step with a bounded
    /// set (`first_bounded`, where the report's track starts; with δ = ∞ the first steps have
    /// none) to the last step. An earlier time shows the first (`shown_step`).
    pub fn cursor_steps(&self) -> RangeInclusive<usize> {
        let last = self.steps.saturating_sub(1);
        self.track.first().map_or(last, |t| t.k)..=last
    }
}

/// Tolerance of the membership checks: the interior-point solver's accuracy on the data scale.
pub const TOL: f64 = 1e-6;

/// A validated `ubb` scenario.
pub struct UbbPrepared {
    pub problem: StateProblem,
    pub spec: UbbSpec,
    pub steps: usize,
    pub seed: u64,
    pub x0: Option<DVector<f64>>,
    pub smoothing: SmoothingReport,
    pub plane: [usize; 2],
    /// Given data (instead of a simulation); a gap is NaN.
    pub data: Option<Vec<DVector<f64>>>,
    /// The record's own times (`data.t`; empty for a simulation or a record without them).
    pub times: Vec<super::RecordTime>,
}

/// Largest phase 2πk/P of a `sin:P` or `cos:P` basis function, in radians: a double's spacing
/// there is 1.2e-4, so the phase, and the function's value, keep about four digits.
const MAX_PHASE: f64 = 1e12;

/// The value at time k of basis function `g`, the entry `field` (`ubb.basis[1]`) of the list.
fn basis_value(field: &str, g: &str, k: f64) -> Result<f64> {
    let period = |s: &str| -> Result<f64> {
        s.parse::<f64>()
            .ok()
            .filter(|p| p.is_finite() && *p > 0.0)
            .ok_or_else(|| {
                Error::field(
                    field,
                    format!("{}: the period must be a positive number", quoted(g)),
                )
            })
    };
    // The phase 2πk/P of a sine or cosine. Past MAX_PHASE radians the spacing of doubles
    // (1.2e-4 at 1e12) leaves the phase, and so the function's value, with few digits; at a
    // period like 1e-308 it is ∞ and the value NaN. The period is the cause, so it is named
    // here, not the model whose matrices the NaN would reach.
    let phase = |p: &str| -> Result<f64> {
        let period = period(p)?;
        let phase = 2.0 * std::f64::consts::PI * k / period;
        if phase.is_finite() && phase.abs() <= MAX_PHASE {
            return Ok(phase);
        }
        let reached = if phase.is_finite() {
            format!("{phase:.3e} radians")
        } else {
            "∞ (past the largest double)".into()
        };
        Err(Error::field(
            field,
            format!(
                "{}: the period {period:e} is too short for double precision: the phase 2πk/P \
                 reaches {reached} by k = {k}, and past {MAX_PHASE:e} radians a double keeps too \
                 few digits of it (its spacing there is 1.2e-4); the period must be at least \
                 {:.3e} for times up to k = {k}",
                quoted(g),
                2.0 * std::f64::consts::PI * k / MAX_PHASE
            ),
        ))
    };
    Ok(match g {
        "1" => 1.0,
        "k" => k,
        "k2" => k * k,
        _ => match g.split_once(':') {
            Some(("sin", p)) => phase(p)?.sin(),
            Some(("cos", p)) => phase(p)?.cos(),
            _ => {
                let known = "\"1\", \"k\", \"k2\", \"sin:P\", \"cos:P\"";
                return Err(Error::field(
                    field,
                    format!("{} is not a basis function ({known})", quoted(g)),
                ));
            }
        },
    })
}

fn finite_positive(field: &str, v: f64, allow_zero: bool) -> Result<f64> {
    if v.is_finite() && (v > 0.0 || (allow_zero && v == 0.0)) {
        Ok(v)
    } else {
        Err(Error::field(
            field,
            format!(
                "must be a finite number {} 0, found {v}",
                if allow_zero { "≥" } else { ">" }
            ),
        ))
    }
}

impl Scenario {
    /// Validate a `ubb` scenario.
    pub fn prepare_ubb(&self) -> Result<UbbPrepared> {
        let spec = self.block(&self.ubb, "eps, tau, delta, …")?.clone();
        let ms = &self.model;
        finite_positive("ubb.eps", spec.eps, false)?;
        finite_positive("ubb.tau", spec.tau, true)?;
        finite_positive("ubb.gamma", spec.gamma, false)?;
        for (f, v) in [("ubb.alpha", spec.alpha), ("ubb.beta", spec.beta)] {
            if let Some(v) = v {
                finite_positive(f, v, false)?;
            }
        }
        for (f, v) in [("ubb.sim_eps", spec.sim_eps), ("ubb.sim_tau", spec.sim_tau)] {
            if let Some(v) = v {
                finite_positive(f, v, true)?;
            }
        }
        if !(spec.kf_level > 0.0 && spec.kf_level < 1.0) {
            return Err(Error::field(
                "ubb.kf_level",
                format!("must lie strictly between 0 and 1, found {}", spec.kf_level),
            ));
        }
        if !(8..=512).contains(&spec.budget) {
            return Err(Error::field(
                "ubb.budget",
                "must be a whole number from 8 to 512 LPs",
            ));
        }
        let source = self.source(&Ubb)?;
        let (steps, seed) = (source.steps(), source.seed());
        // A, and the time-varying H of Example 1.
        let basis = spec.basis.clone().unwrap_or_default();
        let a = match ModelSpec::constant("model.F", &ms.f, Method::Ubb)? {
            Some(a) => a,
            None if !basis.is_empty() => DMatrix::identity(basis.len(), basis.len()),
            None => return Err(Error::field("model.F", "is missing")),
        };
        let r = a.nrows();
        linalg::expect_shape("model.F", &a, r, r)?;
        if r > MAX_STATES {
            return Err(Error::field(
                "model.F",
                format!("is {r} × {r}: one LP window per step and support LPs per direction, so at most {MAX_STATES} states (n = 20 took 4.7 s)"),
            ));
        }
        let c: Vec<DMatrix<f64>> = if basis.is_empty() {
            let h = ModelSpec::constant("model.H", &ms.h, Method::Ubb)?
                .unwrap_or_else(|| DMatrix::zeros(0, r));
            linalg::expect_shape("model.H", &h, h.nrows(), r)?;
            vec![h]
        } else {
            if basis.len() != r {
                return Err(Error::field(
                    "ubb.basis",
                    format!(
                        "has {} functions for a state of {r} coefficients",
                        basis.len()
                    ),
                ));
            }
            if ms.h.is_some() {
                return Err(Error::field(
                    "model.H",
                    "must be absent when ubb.basis gives the outputs",
                ));
            }
            // Each function's phase grows with k: checked once at the last time, so an error
            // names the period that every step needs.
            for (i, g) in basis.iter().enumerate() {
                basis_value(&format!("ubb.basis[{i}]"), g, (steps + 1) as f64)?;
            }
            (0..=steps)
                .map(|t| {
                    let row = basis
                        .iter()
                        .enumerate()
                        .map(|(i, g)| basis_value(&format!("ubb.basis[{i}]"), g, (t + 1) as f64))
                        .collect::<Result<Vec<f64>>>()?;
                    Ok(DMatrix::from_row_slice(1, r, &row))
                })
                .collect::<Result<_>>()?
        };
        let b = match &ms.g {
            Some(rows) => linalg::from_rows("model.G", rows)?,
            None => DMatrix::zeros(r, 0),
        };
        linalg::expect_shape("model.G", &b, r, b.ncols())?;
        // Known input v(t) = B·u(t), u from `simulate.u` or `data.u`.
        let (u_field, u) = source.input_rows();
        let v = match ModelSpec::constant("model.B", &ms.b, Method::Ubb)? {
            Some(bm) if !u.is_empty() => {
                linalg::expect_shape("model.B", &bm, r, bm.ncols())?;
                u.iter()
                    .enumerate()
                    .map(|(t, row)| {
                        Ok(&bm * linalg::vector(&format!("{u_field}[{t}]"), row, bm.ncols())?)
                    })
                    .collect::<Result<Vec<_>>>()?
            }
            Some(_) => {
                return Err(Error::field(
                    u_field,
                    "is needed with model.B (the known input)",
                ))
            }
            None if !u.is_empty() => {
                return Err(Error::field("model.B", format!("is needed with {u_field}")))
            }
            None => Vec::new(),
        };
        let delta = match &spec.delta {
            None => None,
            Some(d) => {
                let d = if d.len() == 1 {
                    vec![d[0]; r]
                } else {
                    d.clone()
                };
                let d = linalg::vector("ubb.delta", &d, r)?;
                if d.iter().any(|v| !(*v >= 0.0)) {
                    return Err(Error::field(
                        "ubb.delta",
                        "must hold half-widths ≥ 0 (or be null for δ = ∞)",
                    ));
                }
                Some(d)
            }
        };
        let x0_center = match &spec.x0_center {
            Some(c) => linalg::vector("ubb.x0_center", c, r)?,
            None => DVector::zeros(r),
        };
        let plane = spec.plane.unwrap_or([0, 1.min(r - 1)]);
        if r == 1 {
            // One state: its set is an interval, drawn over time; there is no plane to name.
            if plane != [0, 0] {
                return Err(Error::field(
                    "ubb.plane",
                    format!(
                        "is {plane:?}, but the state has one component (r = 1): its set is an interval [lo, hi], drawn as a band over the steps; leave ubb.plane out (or give [0, 0])"
                    ),
                ));
            }
        } else if plane[0] >= r || plane[1] >= r || plane[0] == plane[1] {
            return Err(Error::field(
                "ubb.plane",
                format!("must name two different state components below r = {r}"),
            ));
        }
        // Theorems 4 and 5 in the l∞-induced norm.
        let sm = Smoothing::new(
            linalg::norm_inf(&a),
            linalg::norm_inf(&b),
            spec.tau,
            spec.alpha,
        );
        let (window, j, note) = window_length(&spec, &sm, b.ncols(), steps)?;
        if spec.norm == Norm::L1 && spec.l1_form == L1Form::Enumerated {
            // The longest window's bounds, before any LP (the steps before it would run first);
            // without process noise every step's LP holds all the data.
            let longest = if b.ncols() == 0 {
                steps
            } else {
                window.min(steps)
            };
            crate::ubb::check_enumerated("ubb.eps", c[0].nrows() * longest)?;
            crate::ubb::check_enumerated("ubb.tau", b.ncols() * longest)?;
        }
        let smoothing = SmoothingReport {
            a_norm: sm.a_norm,
            b_norm: sm.b_norm,
            ratio: sm.ratio,
            limit: sm.limit(),
            j,
            tail: j.map(|j| sm.tail(j, Some(steps))),
            note,
        };
        let x0 = match self.simulate.as_ref().and_then(|s| s.x0.as_ref()) {
            Some(x) => Some(linalg::vector("simulate.x0", x, r)?),
            None => None,
        };
        if spec.x0_sum.is_some() && x0.is_none() && self.simulate.is_some() {
            return Err(Error::field(
                "simulate.x0",
                "is needed with ubb.x0_sum (a true x(0) on the simplex)",
            ));
        }
        // A gap (NaN) stays in the data: each step leaves its strip out (the method's `gaps`).
        let data = match source {
            Source::Data(_) => Some(source.measurements_with_gaps(c[0].nrows())?),
            Source::Simulate(_) => None,
        };
        let times = source.record_times().to_vec();
        ubb_resolution(
            self,
            &spec,
            window,
            x0.as_ref(),
            &x0_center,
            data.as_deref(),
        )?;
        Ok(UbbPrepared {
            problem: StateProblem {
                system: System { a, b, c, v },
                bounds: Bounds {
                    norm: spec.norm,
                    l1_form: spec.l1_form,
                    tau: spec.tau,
                    eps: spec.eps,
                    delta,
                    x0_center,
                    x0_sum: spec.x0_sum,
                    alpha: spec.alpha,
                    beta: spec.beta,
                },
                window,
                sim_levels: (spec.sim_tau, spec.sim_eps),
            },
            spec,
            steps,
            seed,
            x0,
            smoothing,
            plane,
            data,
            times,
        })
    }
}

/// Set-membership's precision boundary ([`crate::precision`]): each constraint of T(h) (3) is
/// one datum y(t) against its bound ε, and the hull of a window combines its j + 1 steps' data.
/// A bound below the spacing of the data leaves a strip a double cannot represent. The
/// magnitude is the data's, or before a simulation the true x(0) and the centre of its box.
fn ubb_resolution(
    scenario: &Scenario,
    spec: &UbbSpec,
    window: usize,
    x0: Option<&DVector<f64>>,
    x0_center: &DVector<f64>,
    data: Option<&[DVector<f64>]>,
) -> Result<()> {
    let data_magnitude = data.map_or(0.0, |d| {
        d.iter()
            .flat_map(|y| y.iter())
            .fold(0.0_f64, |m, e| m.max(e.abs()))
    });
    let states = x0.map_or(0.0, |x| x.amax()).max(x0_center.amax());
    let field = if data_magnitude >= states {
        if scenario.data.is_some() {
            "data.y"
        } else {
            "ubb.x0_center"
        }
    } else if x0.is_some_and(|x| x.amax() >= x0_center.amax()) {
        "simulate.x0"
    } else {
        "ubb.x0_center"
    };
    crate::precision::Resolution {
        field,
        what: "the states and data",
        magnitude: data_magnitude.max(states),
        noise: spec.eps,
        noise_name: "the noise bound ε (ubb.eps)",
        combined: window.max(1),
        tests: 1,
        method: "the set-membership estimator",
    }
    .check()
}

/// The window j + 1 of Theorem 5 (58) for the truncation accuracy `ubb.gamma`, capped at
/// [`MAX_WINDOW`], or `ubb.window` when given; without process noise (p = 0) every step's LP
/// holds all data. Returns the window, j and a note on how it was chosen.
fn window_length(
    spec: &UbbSpec,
    sm: &Smoothing,
    p: usize,
    steps: usize,
) -> Result<(usize, Option<usize>, Option<String>)> {
    let (j, mut note) = match sm.truncation(spec.gamma, "ubb.gamma") {
        Ok(j) => (Some(j), None),
        Err(_) if p == 0 => (
            None,
            Some("no process noise: the unknowns are x(0) alone, so the LP does not grow with k and needs no truncation".into()),
        ),
        Err(e) => (None, Some(format!("Theorem 5 {}", e.message))),
    };
    let window = match (spec.window, j) {
        (Some(w), _) => {
            if !(1..=MAX_WINDOW).contains(&w) {
                return Err(Error::field(
                    "ubb.window",
                    format!("must be a whole number from 1 to {MAX_WINDOW}"),
                ));
            }
            w
        }
        (None, Some(j)) if j < MAX_WINDOW => j + 1,
        (None, Some(j)) => {
            note = Some(format!(
                "Theorem 5 asks for j = {j}; the window is capped at {MAX_WINDOW} steps"
            ));
            MAX_WINDOW
        }
        (None, None) if p == 0 => steps,
        (None, None) => {
            return Err(Error::field(
                "ubb.window",
                format!("must be given: {} ", note.unwrap_or_default()),
            ))
        }
    };
    Ok((window, j, note))
}

impl UbbPrepared {
    /// See [`UbbReport::state_names`].
    pub fn state_names(&self) -> Vec<String> {
        match &self.spec.basis {
            Some(b) => b
                .iter()
                .enumerate()
                .map(|(i, g)| format!("a{} ({g})", super::subscript(i + 1)))
                .collect(),
            None => (0..self.problem.system.r())
                .map(|i| format!("x{}", super::subscript(i + 1)))
                .collect(),
        }
    }

    /// The simulated (or given) run.
    pub fn run_data(&self) -> Run {
        let mut run =
            self.problem
                .simulate(self.steps, self.spec.noise, self.x0.as_ref(), self.seed);
        if let Some(y) = &self.data {
            run.y = y.clone();
        }
        run
    }

    /// An empty set's error (`ubb.eps` leaves no state …) with the reason when the simulated
    /// noise exceeds the assumed bounds: the data then may contradict them.
    fn explained(&self, e: Error) -> Error {
        let (sim_tau, sim_eps) = self.problem.sim_levels;
        let (eps, tau) = (self.spec.eps, self.spec.tau);
        let (true_eps, true_tau) = (sim_eps.unwrap_or(eps), sim_tau.unwrap_or(tau));
        if self.data.is_some() || e.field != "ubb.eps" || (true_eps <= eps && true_tau <= tau) {
            return e;
        }
        Error::field(
            e.field,
            format!(
                "{}; the true noise (|η| ≤ {true_eps}, |u| ≤ {true_tau}: ubb.sim_eps, ubb.sim_tau) exceeds the bounds the estimator assumes (ε = {eps}, τ = {tau}), so the data may contradict them",
                e.message
            ),
        )
    }

    /// What the reader must know beside the report ([`Report::warnings`]): the gaps of the
    /// record and what the estimator did there, and the assumption behind the Kalman
    /// comparison (it is not part of Tempo's method).
    pub fn warnings(&self, s: &Scenario, u: &UbbReport) -> Vec<String> {
        let mut out = Vec::new();
        if let Some(d) = &s.data {
            let rows = d.gap_rows();
            if !rows.is_empty() {
                let q = u.q;
                let partial = rows
                    .iter()
                    .filter(|&&k| d.y[k].iter().any(|v| !v.is_nan()))
                    .count();
                let partial = if partial > 0 && q > 1 {
                    format!(" ({partial} of them miss only some of the {q} outputs: only those strips are left out)")
                } else {
                    String::new()
                };
                out.push(format!(
                    "data.y has gaps (missing measurements) in {} of its {} rows: {}{partial}. At a gap step k the feasible set has no measurement strip: the set of x(k) is the previous prediction unclipped, and the set of x(k+1) is it mapped by A plus the noise set (Tempo's T(h) (3) with that row of the information (40) left out), so the sets can only grow there; the Kalman comparison skips the same rows of its update",
                    rows.len(),
                    d.y.len(),
                    gap_ranges(d, &rows)
                ));
            }
        }
        let (eta, tau) = (u.eta_level, u.u_level);
        let (law, var, v) = match u.noise {
            NoiseMode::Random => (
                "the variance of the uniform law on [−bound, bound], bound²/3",
                "²/3",
                1.0 / 3.0,
            ),
            NoiseMode::Bound => ("the variance of noise at ± the bound, bound²", "²", 1.0),
        };
        let mut noise = Vec::new();
        if u.p > 0 {
            noise.push(format!(
                "Var u = {}{var} = {}",
                three_digits(tau),
                three_digits(v * tau * tau)
            ));
        }
        if u.q > 0 {
            noise.push(format!(
                "Var η = {}{var} = {}",
                three_digits(eta),
                three_digits(v * eta * eta)
            ));
        }
        let noise = if noise.is_empty() {
            "no noise (no process noise and no measurements)".to_string()
        } else {
            format!(
                "Gaussian noise with {law} ({} per component)",
                noise.join(", ")
            )
        };
        let prior = match &self.problem.bounds.delta {
            Some(_) => format!("x(0) with the variances δᵢ{var} of its box"),
            None => {
                let y: Vec<DVector<f64>> =
                    u.y.iter().map(|r| DVector::from_column_slice(r)).collect();
                format!(
                    "x(0) diffuse (δ = ∞): variance {} on every component, (10⁴ times the data's magnitude)²",
                    three_digits(self.problem.diffuse_prior(&y))
                )
            }
        };
        out.push(format!(
            "the Kalman filter beside the sets (its ellipse at ubb.kf_level, kf_mean, kf_inside) is a comparison under a stated assumption, not part of Tempo's method: {noise}, and {prior}"
        ));
        out
    }

    /// The report.
    pub fn report(&self) -> Result<UbbReport> {
        self.report_plain().map_err(|e| self.explained(e))
    }

    fn report_plain(&self) -> Result<UbbReport> {
        let run = self.run_data();
        let simulated = self.data.is_none();
        let kf = self.problem.kalman(&run, self.spec.noise);
        let r = self.problem.system.r();
        let chi_full = chi2_quantile(self.spec.kf_level, r)?;
        let mut track = Vec::new();
        let (mut outside, mut kf_outside) = (0, 0);
        let (mut filtered_outside, mut filtered_kf_outside) = (0, 0);
        let first = self.first_bounded(&run.y)?;
        for k in first..self.steps {
            let Some(step) = self.bounded_step(&run.y, k)? else {
                continue;
            };
            let (hull, filtered_hull) = step.hulls().map_err(|e| self.empty_at(k, e))?;
            let held = simulated.then(|| holds(&hull, &kf[k].predicted, chi_full, &run.x[k + 1]));
            let (inside, kf_inside) = (held.map(|h| h.0), held.map(|h| h.1));
            let m = &kf[k].predicted.0;
            outside += usize::from(inside == Some(false));
            kf_outside += usize::from(kf_inside == Some(false));
            // The filtered set of the same T(h), against the true x(k) and the Kalman x(k|k).
            let filtered = match filtered_hull {
                Some(fh) => {
                    let held = simulated.then(|| holds(&fh, &kf[k].filtered, chi_full, &run.x[k]));
                    let (inside, kf_inside) = (held.map(|h| h.0), held.map(|h| h.1));
                    filtered_outside += usize::from(inside == Some(false));
                    filtered_kf_outside += usize::from(kf_inside == Some(false));
                    Some(FilteredHull {
                        center: fh.center(),
                        radius: fh.radius(),
                        lo: fh.lo,
                        hi: fh.hi,
                        inside,
                        kf_mean: kf[k].filtered.0.iter().copied().collect(),
                        kf_inside,
                    })
                }
                None => None,
            };
            track.push(TrackStep {
                k,
                center: hull.center(),
                radius: hull.radius(),
                lo: hull.lo,
                hi: hull.hi,
                inside,
                kf_mean: m.iter().copied().collect(),
                kf_inside,
                filtered,
            });
        }
        let Some(last) = track.last() else {
            return Err(Error::field("simulate.steps", "no step has a bounded set"));
        };
        let k = match self.spec.time {
            Some(t) => self.shown_step(t, first)?,
            None => last.k,
        };
        let at = self.at(&run, &kf, k)?;
        Ok(UbbReport {
            r,
            p: self.problem.system.p(),
            q: self.problem.system.c[0].nrows(),
            steps: self.steps,
            norm: self.spec.norm,
            l1_form: self.spec.l1_form,
            noise: self.spec.noise,
            window: self.problem.window,
            gamma: self.spec.gamma,
            plane: self.plane,
            set: self.spec.set,
            state_names: self.state_names(),
            smoothing: self.smoothing.clone(),
            u_level: run.u_level,
            eta_level: run.eta_level,
            x_true: simulated.then(|| run.x.iter().map(|v| v.iter().copied().collect()).collect()),
            y: run.y.iter().map(|v| v.iter().copied().collect()).collect(),
            track,
            outside,
            kf_outside,
            filtered_outside,
            filtered_kf_outside,
            at,
        })
    }

    /// Where the data first contradict the bounds: an empty set's error (the LP's
    /// infeasibility, `ubb.eps leaves no state consistent …`) with the step k at which the set
    /// became empty and the record's row of y(k) (its time when `data.t` gives one). Other
    /// errors pass unchanged.
    fn empty_at(&self, k: usize, e: Error) -> Error {
        if e.field != "ubb.eps" || !e.message.starts_with("leaves no state consistent") {
            return e;
        }
        let row = if self.data.is_some() {
            let record = super::DataSpec {
                t: self.times.clone(),
                ..Default::default()
            };
            format!(" ({} of the record)", record.row_words(k))
        } else {
            String::new()
        };
        // The window of step k (all the data without process noise), as StateProblem::step.
        let len = if self.problem.system.p() == 0 {
            k + 1
        } else {
            self.problem.window.clamp(1, k + 1)
        };
        Error::field(
            e.field,
            format!(
                "{}; the set became empty at step k = {k}, when y({k}){row} joined the window y({} … {k})",
                e.message,
                k + 1 - len
            ),
        )
    }

    /// Step k's feasible set, or `None` when it is unbounded (δ = ∞ and y(0 … k) do not fix
    /// x(k+1) yet): no set at that step. Data that contradict the bounds are the error, with
    /// the step ([`UbbPrepared::empty_at`]).
    fn bounded_step(&self, y: &[DVector<f64>], k: usize) -> Result<Option<StateStep>> {
        match self.problem.step(y, k) {
            Ok(s) => Ok(Some(s)),
            Err(e) if e.field == "ubb.delta" => Ok(None),
            Err(e) => Err(self.empty_at(k, e)),
        }
    }

    /// The first step with a bounded set (the first of the report's track); when none is, the
    /// first step's reason.
    fn first_bounded(&self, y: &[DVector<f64>]) -> Result<usize> {
        for k in 0..self.steps {
            if self.bounded_step(y, k)?.is_some() {
                return Ok(k);
            }
        }
        // Every step is unbounded: the first says why.
        Err(self
            .problem
            .step(y, 0)
            .err()
            .unwrap_or_else(|| Error::field("simulate.steps", "no step has a bounded set")))
    }

    /// The step shown for `ubb.time` = t: t itself, or the first bounded step `first` when t
    /// comes before it.
    fn shown_step(&self, t: usize, first: usize) -> Result<usize> {
        if t < self.steps {
            Ok(t.max(first))
        } else {
            Err(Error::field(
                "ubb.time",
                format!("must be below the {} steps, found {t}", self.steps),
            ))
        }
    }

    /// The components Theorem 2 estimates at the detail's step: the plane's two (one with a
    /// single state).
    fn plane_components(&self) -> Vec<usize> {
        if self.plane[0] == self.plane[1] {
            vec![self.plane[0]]
        } else {
            self.plane.to_vec()
        }
    }

    /// The Kalman ellipse of (mean, covariance) in the plane at `ubb.kf_level`: the 2-D
    /// projection at the χ²₂ level, or with one state the interval at the χ²₁ level.
    fn kf_in_plane(&self, kf: &(DVector<f64>, DMatrix<f64>)) -> Result<Ellipsoid> {
        let (m, p) = kf;
        if self.problem.system.r() == 1 {
            return Ok(Ellipsoid::new(m, p, chi2_quantile(self.spec.kf_level, 1)?));
        }
        Ellipsoid::new(m, p, chi2_quantile(self.spec.kf_level, 2)?).project(&self.plane)
    }

    /// The polygon, hull and prediction at step k, and the filtered set's.
    pub fn at(&self, run: &Run, kf: &[KalmanStep], k: usize) -> Result<UbbStep> {
        let step = self
            .problem
            .step(&run.y, k)
            .map_err(|e| self.empty_at(k, e))?;
        let (hull, polygon, size): (IntervalHull, SupportPolygon, LpSize) = step
            .hull_and_polygon(self.plane, self.spec.budget)
            .map_err(|e| self.empty_at(k, e))?;
        // y(k+1) = H(k+1) x(k+1) + η: the hull of H(k+1)x over the set, widened by the
        // newest sample's bound ε (weight 1 at age 0 in every norm).
        let sys = &self.problem.system;
        let h_next = &sys.c[(k + 1).min(sys.c.len() - 1)];
        let prediction = if h_next.nrows() == 0 {
            Vec::new()
        } else {
            let ph = step.image_hull(h_next)?;
            (0..h_next.nrows())
                .map(|i| [ph.lo[i] - self.spec.eps, ph.hi[i] + self.spec.eps])
                .collect()
        };
        let pl = self.plane_components();
        // Theorem 2 beside the exact set, not in its place: where its LP (22) cannot be
        // solved (extreme scales: the metamorphic test's ×1e12 data) the step keeps its exact
        // polygon and hull and says why the linear estimate is missing.
        let split = |r: Result<Option<Vec<LinearEstimate>>>| match r {
            Ok(l) => (l, None),
            Err(e) => (None, Some(e.to_string())),
        };
        let (linear, linear_refused) = split(self.problem.theorem_2(&run.y, k, &pl));
        let simulated = self.data.is_none();
        let truth_at = |t: usize| -> Vec<f64> { self.plane.iter().map(|&i| run.x[t][i]).collect() };
        let filtered = match &step.filtered {
            Some(f) => {
                let (fh, fpoly, _) = f
                    .hull_and_polygon(self.plane, self.spec.budget)
                    .map_err(|e| self.empty_at(k, e))?;
                let (linear, linear_refused) =
                    split(self.problem.theorem_2_filtered(&run.y, k, &pl));
                Some(UbbFiltered {
                    center: fh.center(),
                    radius: fh.radius(),
                    lo: fh.lo,
                    hi: fh.hi,
                    polygon: fpoly,
                    truth: simulated.then(|| truth_at(k)),
                    kf: self.kf_in_plane(&kf[k].filtered)?,
                    linear,
                    linear_refused,
                })
            }
            None => None,
        };
        Ok(UbbStep {
            k,
            first: step.first,
            center: hull.center(),
            radius: hull.radius(),
            lo: hull.lo,
            hi: hull.hi,
            polygon,
            truth: simulated.then(|| truth_at(k + 1)),
            kf: self.kf_in_plane(&kf[k].predicted)?,
            size,
            prediction,
            linear,
            linear_refused,
            filtered,
        })
    }
}

/// A number in a sentence: about three significant digits, or 2.17e-5 for tiny and huge
/// magnitudes.
fn three_digits(v: f64) -> String {
    let a = v.abs();
    if v != 0.0 && v.is_finite() && !(1e-3..1e5).contains(&a) {
        return format!("{v:.2e}");
    }
    let d = if v == 0.0 || !v.is_finite() {
        0
    } else {
        (2.0 - a.log10().floor()).clamp(0.0, 8.0) as usize
    };
    let s = format!("{v:.d$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The gap rows of a record (0-based, increasing) in words, runs of rows joined: "row 1
/// (time 1959-03), rows 50–69 (times 1971-06 … 1976-03)", at most 12 runs and then how many
/// rows more.
fn gap_ranges(d: &super::DataSpec, rows: &[usize]) -> String {
    const SHOWN: usize = 12;
    let time = |k: usize| d.t.get(k).map(|t| t.label());
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for &k in rows {
        match runs.last_mut() {
            Some((_, b)) if *b + 1 == k => *b = k,
            _ => runs.push((k, k)),
        }
    }
    let mut parts: Vec<String> = runs
        .iter()
        .take(SHOWN)
        .map(|&(a, b)| {
            if a == b {
                match time(a) {
                    Some(t) => format!("row {} (step k = {a}, time {t})", a + 1),
                    None => format!("row {} (step k = {a})", a + 1),
                }
            } else {
                match (time(a), time(b)) {
                    (Some(ta), Some(tb)) => {
                        format!(
                            "rows {}–{} (steps k = {a}–{b}, times {ta} … {tb})",
                            a + 1,
                            b + 1
                        )
                    }
                    _ => format!("rows {}–{} (steps k = {a}–{b})", a + 1, b + 1),
                }
            }
        })
        .collect();
    if runs.len() > SHOWN {
        let more: usize = runs[SHOWN..].iter().map(|(a, b)| b - a + 1).sum();
        parts.push(format!("and {more} rows more"));
    }
    parts.join(", ")
}

/// The set-membership cursor: the run, its Kalman predictions and the first bounded step made
/// once; the polygon, hull and prediction of any step on demand (one window LP loaded per step,
/// as the report's `at`).
struct UbbCursor {
    prepared: UbbPrepared,
    run: Run,
    kf: Vec<KalmanStep>,
    first: usize,
}

impl UbbCursor {
    /// The cursor of a scenario, within the report's work budget (its preparation finds the
    /// first bounded step, a search as long as the report's).
    fn of(s: &Scenario) -> Result<UbbCursor> {
        s.work(Job::Report).check(Job::Report)?;
        UbbCursor::new(s.prepare_ubb()?)
    }

    fn new(prepared: UbbPrepared) -> Result<UbbCursor> {
        let run = prepared.run_data();
        let kf = prepared.problem.kalman(&run, prepared.spec.noise);
        let first = prepared.first_bounded(&run.y)?;
        Ok(UbbCursor {
            prepared,
            run,
            kf,
            first,
        })
    }
}

impl Cursor for UbbCursor {
    fn steps(&self) -> RangeInclusive<usize> {
        self.first..=self.prepared.steps - 1
    }
    fn at(&mut self, t: usize) -> Result<serde_json::Value> {
        let k = self.prepared.shown_step(t, self.first)?;
        let at = self
            .prepared
            .at(&self.run, &self.kf, k)
            .map_err(|e| self.prepared.explained(e))?;
        detail_value(&at)
    }
}

/// The guarantee counter: over runs, how often the true x(k+1) left the set (interval hull;
/// must be 0) and how often it left the Kalman ellipsoid at `kf_level`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct GuaranteeCount {
    pub runs: usize,
    pub outside: usize,
    pub kf_outside: usize,
    /// Runs whose data contradict the assumed bounds (no set at all: counted in `outside`),
    /// possible only when the simulated noise exceeds them (`ubb.sim_eps`, `ubb.sim_tau`).
    #[serde(default)]
    pub empty: usize,
    /// Largest distance by which a true state left the hull (≤ 0 when inside: the margin; 0
    /// when no run had a set).
    pub worst_excess: f64,
}

impl study::Tally for GuaranteeCount {
    fn runs(&self) -> usize {
        self.runs
    }
    fn counts(&self) -> Vec<(String, usize)> {
        vec![
            ("outside".into(), self.outside),
            ("kf_outside".into(), self.kf_outside),
            ("empty".into(), self.empty),
        ]
    }
    /// The sum; the worst excess of no run (0 here, −∞ in truth, which JSON cannot hold) is
    /// replaced by the first counted run's.
    fn add(&mut self, later: &GuaranteeCount) -> std::result::Result<(), String> {
        match (self.runs, later.runs) {
            (_, 0) => {}
            (0, _) => *self = *later,
            _ => {
                study::add_count(&mut self.runs, later.runs, "runs")?;
                study::add_count(&mut self.outside, later.outside, "outside")?;
                study::add_count(&mut self.kf_outside, later.kf_outside, "kf_outside")?;
                study::add_count(&mut self.empty, later.empty, "empty")?;
                self.worst_excess = self.worst_excess.max(later.worst_excess);
            }
        }
        Ok(())
    }
}

/// Whether the truth lies in the hull (tolerance `TOL`) and in the Kalman ellipsoid (prediction,
/// covariance; radius² `chi`), and by how much it exceeds the hull (≤ 0: its margin).
fn holds(
    hull: &IntervalHull,
    kf: &(DVector<f64>, DMatrix<f64>),
    chi: f64,
    truth: &DVector<f64>,
) -> (bool, bool, f64) {
    let excess = truth
        .iter()
        .zip(hull.lo.iter().zip(&hull.hi))
        .map(|(x, (l, h))| (l - x).max(x - h))
        .fold(f64::NEG_INFINITY, f64::max);
    (
        hull.contains(truth.as_slice(), TOL * (1.0 + truth.amax())),
        Ellipsoid::new(&kf.0, &kf.1, chi).contains(truth.as_slice()),
        excess,
    )
}

impl UbbPrepared {
    /// `runs` fresh simulations (seeds first_seed, first_seed + 1, …; the truth x(0) is redrawn
    /// unless `simulate.x0` fixes it), each checked at step k. The noise is the true one
    /// (`ubb.sim_eps`, `ubb.sim_tau`, default the bounds), the set the assumed bounds' (ε, τ):
    /// a run whose data contradict them has no set, and its truth counts as outside.
    pub fn guarantee(&self, k: usize, first_seed: u64, runs: usize) -> Result<GuaranteeCount> {
        if k >= self.steps {
            return Err(Error::field(
                "ubb.time",
                format!("must be below the {} steps, found {k}", self.steps),
            ));
        }
        let r = self.problem.system.r();
        let chi = chi2_quantile(self.spec.kf_level, r)?;
        let mut count = GuaranteeCount {
            worst_excess: f64::NEG_INFINITY,
            ..Default::default()
        };
        for i in 0..runs {
            let run = self.problem.simulate(
                k + 1,
                self.spec.noise,
                self.x0.as_ref(),
                first_seed.wrapping_add(i as u64),
            );
            let hull = match self.problem.step_if_consistent(&run.y, k)? {
                Some(step) => step.hull_if_consistent()?,
                None => None,
            };
            let kf = self.problem.kalman(&run, self.spec.noise);
            match hull {
                Some(hull) => {
                    let (inside, kf_inside, excess) =
                        holds(&hull, &kf[k].predicted, chi, &run.x[k + 1]);
                    count.worst_excess = count.worst_excess.max(excess);
                    count.outside += usize::from(!inside);
                    count.kf_outside += usize::from(!kf_inside);
                }
                None => {
                    let (m, p) = &kf[k].predicted;
                    let kf_inside = Ellipsoid::new(m, p, chi).contains(run.x[k + 1].as_slice());
                    count.empty += 1;
                    count.outside += 1;
                    count.kf_outside += usize::from(!kf_inside);
                }
            }
            count.runs += 1;
        }
        if count.runs > 0 && count.worst_excess == f64::NEG_INFINITY {
            // Every run's data contradicted the bounds: no hull to measure a distance to.
            count.worst_excess = 0.0;
        }
        Ok(count)
    }
}

/// The guarantee of a set-membership scenario made visible, as a [`Study`]: `total` fresh
/// simulations, run i with seed `base + i` where base = seed·1000003 + 1 (so the count of any
/// run range depends only on the scenario's seed and the range: chunks and shards merge
/// exactly), each checked at step k: how often the true x(k+1) left the set (must be 0) and how
/// often it left the Kalman ellipsoid at `ubb.kf_level`.
pub struct Guarantee {
    prepared: UbbPrepared,
    k: usize,
    base_seed: u64,
    total: usize,
}

/// The guarantee counts so far, as the study's result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GuaranteeReport {
    #[serde(flatten)]
    pub count: GuaranteeCount,
    pub total: usize,
    pub k: usize,
    pub kf_level: f64,
}

impl Guarantee {
    /// `total` runs of the prepared scenario checked at its step k (`ubb.time`, default the last).
    pub fn new(prepared: UbbPrepared, total: usize) -> Result<Guarantee> {
        if !(1..=super::MAX_STUDY_RUNS).contains(&total) {
            return Err(Error::field(
                "ubb.guarantee.runs",
                format!(
                    "must be a whole number from 1 to {}, found {total}",
                    super::MAX_STUDY_RUNS
                ),
            ));
        }
        let k = prepared
            .spec
            .time
            .unwrap_or(prepared.steps.saturating_sub(1));
        if k >= prepared.steps {
            return Err(Error::field(
                "ubb.time",
                format!("must be below the {} steps, found {k}", prepared.steps),
            ));
        }
        let base_seed = prepared.seed.wrapping_mul(1_000_003).wrapping_add(1);
        Ok(Guarantee {
            prepared,
            k,
            base_seed,
            total,
        })
    }

    /// The step k checked.
    pub fn k(&self) -> usize {
        self.k
    }
}

impl Runs for Guarantee {
    type Tally = GuaranteeCount;
    type Report = GuaranteeReport;
    fn total(&self) -> usize {
        self.total
    }
    fn seed(&self) -> u64 {
        self.prepared.seed
    }
    fn zero(&self) -> GuaranteeCount {
        // worst_excess starts at 0 (not −∞, which JSON cannot hold); the first counted run's
        // replaces it (`Tally::add`).
        GuaranteeCount::default()
    }
    fn run(&mut self, range: std::ops::Range<usize>) -> Result<GuaranteeCount> {
        let first = self.base_seed.wrapping_add(range.start as u64);
        self.prepared.guarantee(self.k, first, range.len())
    }
    fn report(&self, count: &GuaranteeCount) -> GuaranteeReport {
        GuaranteeReport {
            count: *count,
            total: self.total,
            k: self.k,
            kf_level: self.prepared.spec.kf_level,
        }
    }
}

/// One step of a set-membership report, step by step: the window, the interval hull and
/// central estimate (31) with its local error (5), Theorem 2's linear optimal estimate (25) of
/// each plotted component with its error (22) and the active constraints it comes from, the
/// Kalman prediction and the verdict. Step k is the report's detail (`at`) or, for another
/// step, the time cursor's: the same numbers the figure draws there.
fn explain_ubb(s: &Scenario, report: &Report, t: Option<usize>) -> Result<super::StepExplanation> {
    use super::explain::{check_step, StepValue as V};
    use super::subscript;
    let u = report
        .ubb
        .as_ref()
        .ok_or_else(|| Error::field("report.ubb", "has no set-membership part"))?;
    let k = t.unwrap_or(u.at.k);
    let at: UbbStep = if k == u.at.k {
        u.at.clone()
    } else {
        let mut cursor = UbbCursor::of(s)?;
        check_step(k, cursor.steps())?;
        detail_of(cursor.at(k)?)?
    };
    // Three significant digits for the bounds and gains listed in words.
    let short = |v: f64| {
        format!("{:.3}", v)
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    };
    let mut out = super::StepExplanation {
        method: "ubb".into(),
        paper: "Tempo, Robust estimation and filtering in the presence of unknown but bounded noise".into(),
        t: k,
        point: None,
        title: format!(
            "The set of x({}) at step k = {k}: its interval hull, central estimate and Theorem 2 from y({}) … y({k})",
            k + 1,
            at.first
        ),
        rows: Vec::new(),
    };
    out.row(
        "window",
        "Theorem 5, (58)",
        r"y(k-j), \dots, y(k)",
        V::Text(format!(
            "y({}) … y({k}): {} steps",
            at.first,
            k + 1 - at.first
        )),
        format!(
            "the LP (36)–(41) on {} variables and {} rows, its bounds smoothed (45)–(46)",
            at.size.variables, at.size.rows
        ),
    );
    out.row(
        "interval hull",
        "(31)",
        r"[\underline{x}_i, \overline{x}_i] = [\min_{T(h)} x_i, \max_{T(h)} x_i]",
        V::Matrix(vec![at.lo.clone(), at.hi.clone()]),
        "first row the least, second the largest value of each component over the feasible set",
    );
    out.row(
        "central estimate",
        "(31)",
        r"\hat x = \tfrac{1}{2}(\underline{x} + \overline{x})",
        V::Vector(at.center.clone()),
        "strongly optimal: the hull's midpoint",
    );
    out.row(
        "local error",
        "(5)",
        r"\max_i \tfrac{1}{2}(\overline{x}_i - \underline{x}_i)",
        V::Scalar(at.radius),
        "guaranteed: no consistent state is farther from the central estimate",
    );
    match (&at.linear, &at.linear_refused) {
        (Some(linear), _) => {
            for l in linear {
                let c = format!("x{}({})", subscript(l.component + 1), k + 1);
                out.row(
                    &format!("Theorem 2 estimate of {c}"),
                    "(25)",
                    r"\varphi = S\,\tilde P^{-1}\,\tilde d",
                    V::Scalar(l.estimate),
                    "linear in the data of the n active constraints below",
                );
                out.row(
                    &format!("its error E for {c}"),
                    "(22)",
                    r"E(\varphi_o) = \sum_j |g_j|\, b_{t_j}",
                    V::Scalar(l.error),
                    "never below the hull's half-width: the central estimate is optimal",
                );
                // The rows that carry weight, largest gain first (an active row of gain 0 adds
                // nothing to φ or E: the vertex's degenerate rows).
                let top = l.active.iter().map(|a| a.gain.abs()).fold(0.0, f64::max);
                let mut weighty: Vec<_> = l
                    .active
                    .iter()
                    .filter(|a| a.gain.abs() > 1e-9 * top)
                    .collect();
                weighty.sort_by(|a, b| b.gain.abs().total_cmp(&a.gain.abs()));
                let shown = weighty.len().min(8);
                let mut rows: Vec<String> = weighty[..shown]
                    .iter()
                    .map(|a| {
                        let (what, bound) = match a.kind {
                            crate::ubb::RowKind::Measurement => ("η", "ε"),
                            crate::ubb::RowKind::Process => ("u", "τ"),
                            crate::ubb::RowKind::Prior => ("x", "δ"),
                            crate::ubb::RowKind::Sum => ("Σx", "the sum"),
                        };
                        format!(
                            "{what}{}({}) at ±{} ({bound}), gain {}",
                            subscript(a.index + 1),
                            a.t,
                            short(a.bound),
                            short(a.gain)
                        )
                    })
                    .collect();
                if weighty.len() > shown {
                    rows.push(format!("{} more with smaller gains", weighty.len() - shown));
                }
                let idle = l.active.len() - weighty.len();
                if idle > 0 {
                    rows.push(format!("{idle} active with gain 0"));
                }
                out.row(
                    &format!("active constraints for {c}"),
                    "(22)",
                    r"|P_{t_j} f - d_{t_j}| = b_{t_j},\ j = 1, \dots, n",
                    V::Text(rows.join("; ")),
                    "the rows of (22) at their bounds at the LP's optimal vertex",
                );
            }
        }
        (None, Some(why)) => out.row(
            "Theorem 2",
            "(22)",
            r"\varphi = S\,\tilde P^{-1}\,\tilde d",
            V::Text(why.clone()),
            "the set and its hull stand without it",
        ),
        (None, None) => {}
    }
    out.row(
        "Kalman prediction",
        "",
        r"\hat x_{k+1|k}",
        V::Vector(at.kf.center.clone()),
        "for comparison: the centre of the Kalman ellipse drawn beside the set",
    );
    if let Some(inside) = u.track.iter().find(|st| st.k == k).and_then(|st| st.inside) {
        out.row(
            "verdict",
            "(31)",
            r"x(k+1) \in [\underline{x}, \overline{x}]",
            V::Text(if inside {
                "in the hull".into()
            } else {
                "out of the hull".into()
            }),
            "guaranteed while the noise respects its bounds",
        );
    }
    Ok(out)
}

/// Set-membership estimation (Tempo): the `ubb` block, the hull of x(k+1) at every step, the
/// exact polygon and the guarantee study.
pub(crate) struct Ubb;

impl MethodScenario for Ubb {
    fn true_noise(&self) -> Option<&'static str> {
        Some(
            "the set-membership method draws its simulated noise within ubb.sim_tau and ubb.sim_eps, apart from the bounds it assumes",
        )
    }
    fn gaps(&self) -> super::Gaps {
        super::Gaps::Handled("a missing measurement drops its strip from the feasible set T(h) (3) (its row of the information (40) leaves the window's constraints): at that step the set is the previous one mapped by A plus the noise set, and it can only grow; the Kalman comparison skips the same rows of its update")
    }
    fn time_index(&self) -> super::TimeIndex {
        super::TimeIndex::ZeroBased
    }
    fn max_states(&self) -> usize {
        MAX_STATES
    }
    fn truth_keys(&self) -> &'static [(&'static str, &'static str)] {
        &[
            ("truth", "ubb: the true x(k+1) at the step shown"),
            ("inside", "ubb: whether the truth lies in the hull"),
            (
                "kf_inside",
                "ubb: whether the truth lies in the Kalman ellipsoid",
            ),
        ]
    }
    fn explain(
        &self,
        s: &Scenario,
        report: &Report,
        t: Option<usize>,
        _point: Option<&[f64]>,
    ) -> Result<super::StepExplanation> {
        explain_ubb(s, report, t)
    }
    fn steps(&self) -> RangeInclusive<usize> {
        // Up to the general count limit: what a record of N steps costs depends on the path
        // (the exact planar or line recursion, or LPs), the window and the states, and the work
        // budget (`work`) refuses a costly one before any work, naming its formula.
        1..=super::MAX_COUNT as usize
    }
    fn data_shape(&self, s: &Scenario) -> Result<(usize, usize)> {
        // One output when `ubb.basis` gives the outputs (Example 1), else the rows of H; the
        // known input v = B·u has the columns of B (model.G is the unknown noise's matrix).
        let basis = s
            .ubb
            .as_ref()
            .and_then(|u| u.basis.as_ref())
            .is_some_and(|b| !b.is_empty());
        let q = if basis {
            1
        } else {
            ModelSpec::constant("model.H", &s.model.h, Method::Ubb)?.map_or(0, |h| h.nrows())
        };
        let r = ModelSpec::constant("model.B", &s.model.b, Method::Ubb)?.map_or(0, |b| b.ncols());
        Ok((q, r))
    }
    fn work(&self, s: &Scenario, job: Job) -> Work {
        work(s, job)
    }
    fn run(&self, s: &Scenario) -> Result<Report> {
        let prepared = s.prepare_ubb()?;
        let u = prepared.report()?;
        let plot = if u.r == 1 { vec![0] } else { u.plane.to_vec() };
        let mut r = Report::of(s, s.alpha, (u.r, u.q), u.at.k, plot, u.y.clone());
        r.warnings.extend(prepared.warnings(s, &u));
        r.ubb = Some(u);
        Ok(r)
    }
    fn cursor(&self, s: &Scenario) -> Result<Option<Box<dyn Cursor>>> {
        Ok(Some(Box::new(UbbCursor::of(s)?)))
    }
    fn table(&self, r: &Report) -> Table {
        // One row per step k: the outer box of x(k+1) (31), its centre and local error (5),
        // the Kalman prediction, and, when simulated, the truth and whether each holds it.
        let Some(u) = &r.ubb else {
            return Table::new(vec!["k".into()]);
        };
        // Then the same for the filtered set X(k | y(0 … k)) of the step, its columns named
        // filtered_… (filtered_x_i: the true x(k); empty where that set is unbounded).
        let n = u.r;
        let truth = u.x_true.is_some();
        let mut columns = vec!["k".to_string()];
        columns.extend(Table::numbered("center", n));
        columns.extend(Table::numbered("lo", n));
        columns.extend(Table::numbered("hi", n));
        columns.push("radius".into());
        columns.extend(Table::numbered("kf", n));
        if truth {
            columns.extend(Table::numbered("x", n));
            columns.extend(["holds", "kf_holds"].map(String::from));
        }
        columns.extend(Table::numbered("filtered_center", n));
        columns.extend(Table::numbered("filtered_lo", n));
        columns.extend(Table::numbered("filtered_hi", n));
        columns.push("filtered_radius".into());
        columns.extend(Table::numbered("filtered_kf", n));
        if truth {
            columns.extend(Table::numbered("filtered_x", n));
            columns.extend(["filtered_holds", "filtered_kf_holds"].map(String::from));
        }
        let mut table = Table::new(columns);
        for st in &u.track {
            let mut row = vec![Some(st.k as f64)];
            row.extend(cells(Some(&st.center), n));
            row.extend(cells(Some(&st.lo), n));
            row.extend(cells(Some(&st.hi), n));
            row.push(Some(st.radius));
            row.extend(cells(Some(&st.kf_mean), n));
            if truth {
                let x = u.x_true.as_ref().and_then(|x| x.get(st.k + 1));
                row.extend(cells(x.map(|x| x.as_slice()), n));
                row.extend([flag(st.inside), flag(st.kf_inside)]);
            }
            let f = st.filtered.as_ref();
            row.extend(cells(f.map(|f| f.center.as_slice()), n));
            row.extend(cells(f.map(|f| f.lo.as_slice()), n));
            row.extend(cells(f.map(|f| f.hi.as_slice()), n));
            row.push(f.map(|f| f.radius));
            row.extend(cells(f.map(|f| f.kf_mean.as_slice()), n));
            if truth {
                let x = u.x_true.as_ref().and_then(|x| x.get(st.k));
                row.extend(cells(x.map(|x| x.as_slice()), n));
                row.extend([
                    flag(f.and_then(|f| f.inside)),
                    flag(f.and_then(|f| f.kf_inside)),
                ]);
            }
            table.push(row);
        }
        table
    }
    fn set_at(&self, report: &mut Report, at: serde_json::Value) -> Result<()> {
        let at: UbbStep = detail_of(at)?;
        let u = report.ubb.as_mut().ok_or_else(|| {
            Error::field(
                "report.ubb",
                "is missing: the report is not a set-membership report",
            )
        })?;
        report.time = at.k;
        u.at = at;
        Ok(())
    }
    fn cursor_steps(&self, report: &Report) -> Option<RangeInclusive<usize>> {
        report.ubb.as_ref().map(UbbReport::cursor_steps)
    }
    fn study(&self, s: &Scenario, runs: Option<usize>) -> Result<Box<dyn Study>> {
        let p = s.prepare_ubb()?;
        let total = runs
            .or(p.spec.guarantee.as_ref().map(|g| g.runs))
            .unwrap_or_else(default_guarantee_runs);
        Ok(Box::new(study::Chunked::new(Guarantee::new(p, total)?)))
    }
    fn compare_member(&self) -> Option<&dyn CompareMember> {
        Some(self)
    }
    fn presets(&self) -> Vec<Preset> {
        presets()
    }
}

/// Operations of one interior-point solve per window step and unit of r + p + q (the
/// stage-wise KKT system is banded: r = 10, a window of 30 about 5 ms natively).
const OPS_LP_STAGE: f64 = 14_000.0;
/// Operations per row and unit of r + q of a solve without process noise (x(0) alone: a tall
/// LP whose rows grow with k).
const OPS_LP_ROW: f64 = 400.0;
/// Operations per entry of the enumerated l1 form's sign rows in one solve (2^{m−1} dense rows:
/// about 1.3 µs each natively).
const OPS_LP_ENUMERATED: f64 = 1300.0;
/// Operations of one solve besides (setting it up, clarabel's start).
const OPS_SOLVE: f64 = 30_000.0;
/// Operations per entry of the dense constraint matrices a step builds (and reads into the
/// solver's sparse form; a window of 400 times, 4 M entries, took 14 ms natively).
const OPS_ENTRY: f64 = 3.0;
/// Second-order cones (l2 bounds) against linear rows.
const L2_FACTOR: f64 = 1.5;
/// The exact planar recursion ([`crate::ubb::planar`]), per time of a window: a clip by one
/// strip and the map by A of a polygon of about ten vertices, and per noise segment and time
/// of the window OPS_VERTEX: a rotating A turns every segment of the window into its own
/// pair of edges, so the polygon has up to 2·len vertices (measured: ubb-track, a window of
/// 30 times, about 0.2 ms a step natively, a window of 400 about 36 ms; ubb-series without
/// process noise about 2 µs per time).
const OPS_CLIP: f64 = 1200.0;
const OPS_MAP: f64 = 800.0;
const OPS_VERTEX: f64 = 250.0;
/// The line recursion ([`crate::ubb::interval`]) per time and unit of q + p + 1.
const OPS_LINE: f64 = 100.0;
/// Per earlier time k of every step: the nominal trajectory and the powers A⁰ … A^{k+1}
/// rebuilt for the step (and with process noise the prior box of the window's first state,
/// a sum over the times before it), OPS_HISTORY per matrix, OPS_HISTORY_SQUARE per entry and
/// noise column (measured: 2.7e-7 s per step² with r = 2, p = 1; 1.7e-7 with r = 1).
const OPS_HISTORY: f64 = 200.0;
const OPS_HISTORY_SQUARE: f64 = 50.0;
/// With δ = ∞, per row of a window's observability matrix and unit of r²: its SVD and the
/// reconstructibility test.
const OPS_OBSERVABILITY: f64 = 250.0;
/// Per number of the report: computing it, its JSON tree in the finiteness check and its text
/// (as SCF's), and the bytes it holds with its JSON.
const OPS_NUMBER: f64 = 300.0;
const BYTES_NUMBER: f64 = 80.0;

/// Over the steps k = 0 … steps − 1 with a window len_k = min(k + 1, w): (Σ len, Σ len²) (the
/// window grows until it reaches w, then slides; w = steps without process noise), and Σ k.
fn window_sums(steps: usize, w: usize) -> (f64, f64, f64) {
    let (n, w) = (f(steps), f(w.clamp(1, steps.max(1))));
    let grow = w.min(n);
    let rest = (n - grow).max(0.0);
    let sum = grow * (grow + 1.0) / 2.0 + rest * w;
    let sum2 = grow * (grow + 1.0) * (2.0 * grow + 1.0) / 6.0 + rest * w * w;
    (sum, sum2, n * (n - 1.0) / 2.0)
}

/// The set-membership costs, step by step: the window (Theorem 5's j + 1, `ubb.window`, or all
/// the data without process noise) sets the size of each step's problem, dim = r(len + 1) +
/// p·len unknowns. Every step rebuilds the nominal trajectory and the powers of A up to k
/// (steps² terms), builds its dense constraint matrices ((q + p + r)·len × dim entries, the
/// enumerated l1 form 2^{m−1} rows) and then either runs the exact recursion over its window
/// (r ≤ 2 with l∞ bounds: no LP) or solves 4r LPs for the hulls of the predicted and the
/// filtered set; with δ = ∞ it tests the window's observability matrix. The step shown adds,
/// on the LP path, `ubb.budget` support LPs for each set's polygon, and Theorem 2's LP (22) per
/// plotted component and set (a dense simplex, within [`crate::ubb::THEOREM_2_MAX_WORK`]). A
/// study's run: one simulation and the hull at its step.
fn work(s: &Scenario, job: Job) -> Work {
    let mut w = Work::default();
    let Some(spec) = &s.ubb else {
        return w;
    };
    let basis = spec.basis.as_ref().map_or(0, Vec::len);
    let r = shape(&s.model.f).0.max(basis).max(1);
    if r > MAX_STATES {
        return w;
    }
    let q = if basis > 0 { 1 } else { shape(&s.model.h).0 };
    let g = s.model.g.as_deref().map_or((0, 0), rows_shape);
    let p = g.1;
    let steps = s.written_steps();
    let steps_field = s.steps_field();
    let norm = |rows: Option<&Vec<Vec<f64>>>| {
        rows.map_or(0.0, |rows| {
            rows.iter()
                .map(|row| row.iter().map(|v| v.abs()).sum::<f64>())
                .fold(0.0, f64::max)
        })
    };
    let a_norm = match &s.model.f {
        Some(crate::model::MatrixSpec::Constant(rows)) => norm(Some(rows)),
        _ => 1.0,
    };
    let sm = Smoothing::new(a_norm, norm(s.model.g.as_ref()), spec.tau, spec.alpha);
    let window = window_length(spec, &sm, p, steps).map_or(1, |(w, _, _)| w);
    // Without process noise every step holds all the data: its window is k + 1.
    let w_eff = if p == 0 { steps.max(1) } else { window };
    let exact = (r == 1 || r == 2) && spec.norm == Norm::Linf;
    // Theorem 3's enumerated rows, when the longest window allows them (else refused first).
    let longest = w_eff.min(steps);
    let enumerated_form = spec.norm == Norm::L1
        && spec.l1_form == L1Form::Enumerated
        && (q * longest).max(p * longest) <= crate::ubb::MAX_ENUMERATED_M;
    let window_field = if spec.window.is_some() {
        "ubb.window"
    } else if p == 0 {
        steps_field
    } else {
        "ubb.gamma"
    };
    let width = f(r + p + q);
    let dim = |len: usize| if p == 0 { r } else { r * (len + 1) + p * len };
    // One LP solve of a step whose window holds len times, and its dense matrices' entries.
    let solve = |len: usize| {
        let mut rows = 2 * (q + p) * len + r * len + 2 * r;
        let mut enumerated = 0;
        if enumerated_form {
            for m in [q * len, p * len] {
                if m > 0 {
                    enumerated += 1 << (m - 1);
                }
            }
        }
        rows += enumerated;
        let lp = if p == 0 {
            OPS_LP_ROW * f(2 * q * len) * f(r + q)
        } else {
            OPS_LP_STAGE * f(len) * width
        } * if spec.norm == Norm::L2 {
            L2_FACTOR
        } else {
            1.0
        } + OPS_LP_ENUMERATED * f(enumerated) * f(dim(len));
        (lp + OPS_SOLVE, OPS_ENTRY * f(rows) * f(dim(len)))
    };
    let sizes = format!(
        "= {steps} with a window of {} (ubb.window, or Theorem 5's j + 1 from ubb.gamma; all the data without process noise), r = {r} states, p = {p} noise inputs, q = {q} outputs",
        if p == 0 { "k + 1".to_string() } else { window.to_string() }
    );
    let (sum_len, sum_len2, sum_k) = window_sums(steps, w_eff);
    // Per step k: the nominal trajectory and the powers of A up to k (and the prior box).
    let history = sum_k
        * (OPS_HISTORY * if p > 0 { 2.0 } else { 1.0 } + OPS_HISTORY_SQUARE * f(r * r) * f(1 + p));
    if let Job::Study { .. } = job {
        let k = spec.time.unwrap_or(steps.saturating_sub(1));
        let len = w_eff.min(k + 1);
        let (lp, fill) = solve(len);
        let hull = if exact { 0.0 } else { 2.0 * f(r) * lp };
        w.ops(
            Term::new(
                window_field,
                format!("({window}) with ubb.time = {k}, r = {r} states"),
                "one run: the window's set (2r LPs for the hull off the exact path) at the step checked",
                hull + fill
                    + f(k) * (OPS_HISTORY + OPS_HISTORY_SQUARE * f(r * r) * f(1 + p))
                    + f(len) * (OPS_CLIP * f(q) + OPS_MAP + OPS_VERTEX * f(p * len)),
            )
            .advice("a shorter window or an earlier ubb.time"),
        );
        return w;
    }
    w.ops(
        Term::new(
            steps_field,
            sizes.clone(),
            "steps² · (r²(p + 1) + c) / 2: the nominal trajectory, the powers of A and the prior box rebuilt at every step",
            history,
        )
        .advice("fewer steps"),
    );
    // The dense constraints of every step: (q + p + r)·len rows of dim = r(len + 1) + p·len.
    let fills = OPS_ENTRY
        * f(q + p + r)
        * if p == 0 {
            sum_len * f(r)
        } else {
            f(r + p) * sum_len2 + f(r) * sum_len
        };
    w.ops(
        Term::new(
            steps_field,
            sizes.clone(),
            "steps · (q + p + r)·len · dim: the dense constraints of every step's window",
            fills,
        )
        .advice("fewer steps or a shorter window (ubb.window, or a larger ubb.gamma)"),
    );
    if exact {
        let recursion = if r == 2 {
            sum_len * (OPS_CLIP * f(q) + OPS_MAP) + sum_len2 * OPS_VERTEX * f(p)
        } else {
            sum_len * OPS_LINE * f(q + p + 1)
        };
        w.ops(
            Term::new(
                steps_field,
                sizes.clone(),
                "steps · len · (q clips + the map + p·len polygon vertices): the exact recursion over every step's window (no LP)",
                recursion,
            )
            .advice("fewer steps or a shorter window (ubb.window, or a larger ubb.gamma)"),
        );
    } else {
        // 4r LPs per step: the hulls of the predicted and the filtered set on one loaded T(h).
        let mut solves = 0.0;
        if enumerated_form || p > 0 {
            // The LP grows with the window until it slides: each distinct length once.
            for len in 1..=w_eff.min(steps) {
                let count = if len < w_eff.min(steps) {
                    1
                } else {
                    steps + 1 - len
                };
                solves += f(count) * solve(len).0;
            }
        } else {
            // Without process noise len = k + 1, and the solve is linear in it.
            solves = OPS_LP_ROW
                * f(2 * q)
                * f(r + q)
                * sum_len
                * if spec.norm == Norm::L2 {
                    L2_FACTOR
                } else {
                    1.0
                }
                + OPS_SOLVE * f(steps);
        }
        w.ops(
            Term::new(
                steps_field,
                sizes.clone(),
                "steps · 4r LPs over the window's r(len + 1) + p·len unknowns (the hulls of the predicted and the filtered set)",
                4.0 * f(r) * solves,
            )
            .advice(
                "fewer steps, a shorter window (ubb.window, or a larger ubb.gamma) or fewer states",
            ),
        );
    }
    if spec.delta.is_none() {
        w.ops(
            Term::new(
                steps_field,
                sizes.clone(),
                "steps · len · q · r²: the observability matrix of every window (δ = ∞)",
                sum_len * f(q) * f(r * r) * OPS_OBSERVABILITY,
            )
            .advice("fewer steps, a bound δ on x(0) or a shorter window"),
        );
    }
    let k = spec.time.unwrap_or(steps.saturating_sub(1));
    let len_k = w_eff.min(k + 1);
    if !exact {
        w.ops(
            Term::new(
                "ubb.budget",
                format!("= {} with window {window} and r = {r} states", spec.budget),
                "2·budget LPs for the predicted and the filtered polygon at the step shown",
                f(2 * spec.budget + 2 * q + 2) * solve(len_k).0,
            )
            .advice("a smaller budget or a shorter window"),
        );
    }
    // Theorem 2 at the step shown: per plotted component and set, a dense simplex on (22).
    if spec.norm == Norm::Linf {
        let n = f(r + p * len_k);
        let rows = f((q + p) * len_k + r + 1);
        let units = rows * n * (rows + n);
        if units <= crate::ubb::THEOREM_2_MAX_WORK {
            w.ops(
                Term::new(
                    window_field,
                    format!("({window}) at the step shown with r = {r} states, p = {p}, q = {q}"),
                    "2 sets · 2 components · rows·n·(rows + n): Theorem 2's LP (22) at the step shown",
                    4.0 * (crate::ubb::THEOREM_2_OPS * units + OPS_SOLVE),
                )
                .advice("a shorter window"),
            );
        }
    }
    // The report: per step the two hulls, centres and Kalman means, the truth and the data.
    let numbers = f(steps) * f(9 * r + q + 6);
    w.ops(
        Term::new(
            steps_field,
            format!("= {steps} with r = {r} states, q = {q} outputs"),
            "steps · (9r + q): the numbers of the report and their JSON",
            numbers * OPS_NUMBER,
        )
        .advice("fewer steps"),
    );
    w.mem(
        Term::new(
            steps_field,
            format!("= {steps} with r = {r} states, q = {q} outputs"),
            "steps · (9r + q): the report's hulls, centres, truth and data, and their JSON",
            numbers * BYTES_NUMBER,
        )
        .advice("fewer steps"),
    );
    // The largest step's dense matrices (the solver's copy beside them).
    let (_, fill) = solve(longest.max(1));
    w.mem(
        Term::new(
            window_field,
            format!("({window}) with {steps_field} = {steps}, r = {r} states, p = {p} noise inputs, q = {q} outputs"),
            "(q + p + r)·len · dim: the dense constraints of one step",
            fill / OPS_ENTRY * 8.0 * 2.0,
        )
        .advice("a shorter window or fewer states"),
    );
    w
}

// ---------------------------------------------------------------------------------------------
// Compare: what a compare asks of the set-membership estimator (`scenario::compare`)

impl CompareMember for Ubb {
    fn options(&self) -> &'static [&'static str] {
        // A bound on x(0) (its half-widths δ, centre and sum) and the polygon's LP budget. The
        // bounds ε, τ are the compare's (b_w, b_v of its noise law), the window its
        // `compare.window`, the norm l∞ (the per-sample bounds they are).
        &["delta", "x0_center", "x0_sum", "budget"]
    }
    fn compare_order(&self) -> usize {
        4
    }
    fn assumption(&self, p: &ComparePrepared) -> Assumption {
        Assumption {
            assumes: "|v(t)| ≤ τ and |w(t)| ≤ ε at every t",
            violated: p.bounds_violation(),
            promise: "always",
            // The feasible set T(h) (3) holds the state whenever the bounds hold.
            level: Some(1.0),
            at_least: false,
        }
    }
    fn derived_scenario(&self, p: &ComparePrepared, t: usize) -> Result<Scenario> {
        // Per-sample l∞ bounds (45)–(46): τ = b_v on v, ε = b_w on w, no smoothing, no box of
        // x(0); the window of j + 1 = `compare.window` steps ending at k = t − 1.
        let &[i, j] = p.plane() else {
            return Err(Error::field(
                "model.F",
                "is 1×1: Tempo's set is computed and drawn in a plane of two state components (ubb.plane), which a scalar state does not have",
            ));
        };
        let (bound_v, bound_w) = p.bounds();
        let mut model = p.bare_model();
        model.g = Some(linalg::to_rows(p.noise_g()));
        let mut s = p.own_scenario(Method::Ubb, model, t);
        s.ubb = Some(UbbSpec {
            norm: Norm::Linf,
            l1_form: default_l1_form(),
            eps: bound_w,
            tau: bound_v,
            delta: None,
            x0_center: None,
            x0_sum: None,
            alpha: None,
            beta: None,
            gamma: default_gamma(),
            window: Some(p.window(t)),
            noise: default_noise(),
            time: Some(t - 1),
            set: SetChoice::Predicted,
            plane: Some([i, j]),
            budget: POLYGON_BUDGET,
            basis: None,
            sim_eps: None,
            sim_tau: None,
            kf_level: p.alpha(),
            guarantee: None,
        });
        Ok(s)
    }
    fn plane_set(
        &self,
        p: &ComparePrepared,
        r: &Report,
        truth: Option<&[f64]>,
    ) -> Result<PlaneReading> {
        predicts_only(p)?;
        let u = r
            .ubb
            .as_ref()
            .ok_or_else(|| Error::field("report.ubb", "has no ubb part"))?;
        let poly = &u.at.polygon;
        Ok(PlaneReading {
            area: Some(polygon_area(&poly.vertices)),
            holds: truth.map(|x| poly.contains([x[0], x[1]], 1e-9)),
            set: PlaneSet::Polygon {
                vertices: poly.vertices.clone(),
            },
            // The interval hull of x(k+1) (31).
            outline: Some(box_corners(&u.at.lo, &u.at.hi)),
            note: Some(format!("window {} steps", u.window)),
        })
    }
    /// The window at the target step k = t − 1 (its hull and exact polygon, as the report's
    /// `at`); of the steps before it only whether each bounded window is feasible (one LP,
    /// where the report's track solves its interval hull, 2n LPs): the report refuses the
    /// whole record when an earlier window contradicts the bounds, and so must this.
    fn holds_at(&self, p: &ComparePrepared, s: &Scenario, truth: &[f64]) -> Result<bool> {
        predicts_only(p)?;
        super::compare::checked_as_run(s)?;
        let prepared = s.prepare_ubb()?;
        let run = prepared.run_data();
        let k = s
            .ubb
            .as_ref()
            .and_then(|u| u.time)
            .ok_or_else(|| Error::field("ubb.time", "is missing"))?;
        // A record the report refuses (an earlier window's data contradict the bounds) is no
        // set: every earlier window is checked. The planar path has already clipped its polygon
        // (an empty one is the error); the LP path needs one support LP to find out.
        for earlier in 0..k {
            if let Some(step) = prepared.bounded_step(&run.y, earlier)? {
                if step.planar.is_none() {
                    let first_row = step.s_map.row(0).transpose();
                    step.set.support_solver()?.support(&first_row)?;
                }
            }
        }
        let step = prepared.problem.step(&run.y, k)?;
        let (_, poly, _) = step.hull_and_polygon(prepared.plane, prepared.spec.budget)?;
        Ok(poly.contains([truth[0], truth[1]], 1e-9))
    }
    fn remedy(&self, p: &ComparePrepared, e: &Error) -> Option<String> {
        match e.field.as_str() {
            "ubb.delta" => Some(match p.unobservable() {
                Some(why) => format!(
                    "a finite bound on x(0): compare.members.ubb.delta (and x0_center, its centre; x(0) is x₁), since {why}"
                ),
                None => "a finite bound on x(0): compare.members.ubb.delta (and x0_center, its centre; x(0) is x₁), or a later compare.time (more measurements in the window)".to_string(),
            }),
            "model.F" => Some("a model of n ≥ 2 states".to_string()),
            "compare.target" => Some("compare.target \"predict\"".to_string()),
            "ubb.eps" | "ubb.tau" | "ubb.window" => Some(
                "bounds the record does not contradict: a larger compare.bound_scale (or compare.bound_sigmas)".to_string(),
            ),
            _ => None,
        }
    }
}

/// Tempo's set is of x(k+1) from y(0 … k): a compare of the filtered state has none.
fn predicts_only(p: &ComparePrepared) -> Result<()> {
    if p.predicts() {
        Ok(())
    } else {
        Err(Error::field(
            "compare.target",
            "is \"filter\", but Tempo's set is of x(k+1) from y(0 … k): a prediction only (choose \"predict\")",
        ))
    }
}

// ---------------------------------------------------------------------------------------------
// Presets

/// Tempo's presets, in menu order (the trait's `presets`, gathered by
/// [`crate::presets::all`]).
fn presets() -> Vec<Preset> {
    vec![
        Preset {
            name: "ubb-track".into(),
            label: "Tempo Section IV — tracking with bounded noise".into(),
            menu: "Tempo Sec. IV — tracking".into(),
            description: "Tempo, Section IV: a stable 2-state system tracked with unknown-but-bounded noise (|u| ≤ 0.1, |η| ≤ 0.2), exponentially smoothed bounds α = β = 50, window j + 1 = 30 from Theorem 5 (γ = 0.1)".into(),
            scenario: ubb_preset(UbbKind::Track),
        },
        Preset {
            name: "ubb-series".into(),
            label: "Tempo Example 1 — time-series prediction".into(),
            menu: "Tempo Ex. 1 — time series".into(),
            description: "Tempo, Example 1: time-series prediction with basis functions 1 and k — the set of coefficients consistent with |u(k)| ≤ 0.5 and the prediction interval of f(m+1)".into(),
            scenario: ubb_preset(UbbKind::Series),
        },
        Preset {
            name: "ubb-leontief".into(),
            label: "Tempo Example 3 — a Leontief economy".into(),
            menu: "Tempo Ex. 3 — a Leontief economy".into(),
            description: "Tempo, Example 3: dynamic Leontief model of 3 industries (nonnegative A, column sums 0.6), known demand, uncertain demand |u| ≤ 0.1, production measured within ±0.3".into(),
            scenario: ubb_preset(UbbKind::Leontief),
        },
        Preset {
            name: "ubb-markov".into(),
            label: "Tempo Example 4 — an absorbing Markov chain".into(),
            menu: "Tempo Ex. 4 — a Markov chain".into(),
            description: "Tempo, Example 4: absorbing Markov chain with an uncertain initial distribution 0 ≤ x_i(0) ≤ δ_i — the set of distributions after k + 1 steps".into(),
            scenario: ubb_preset(UbbKind::Markov),
        },
    ]
}

/// The set-membership presets (Tempo's paper prints no numbers: these are chosen to show each
/// example).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UbbKind {
    Track,
    Series,
    Leontief,
    Markov,
}

/// A set-membership preset. Written as scenario JSON (read like a user's, so the defaults
/// are the scenario's own), not with `serde_json::json!`, whose expansion of these four
/// documents took ~75 KB of the wasm module; the notes are Rust strings for the line breaks.
pub fn ubb_preset(kind: UbbKind) -> Scenario {
    let (json, notes) = match kind {
        UbbKind::Track => (
            r#"{"method": "ubb",
                "title": "Set-membership state estimation with smoothed bounds (Tempo, Section IV)",
                "model": {"F": [[0.7, 0.2], [-0.2, 0.7]], "G": [[0.5], [1.0]], "H": [[1.0, 0.0]]},
                "simulate": {"steps": 60, "seed": 1},
                "ubb": {"eps": 0.2, "tau": 0.1, "delta": [2.0], "alpha": 50.0, "beta": 50.0, "gamma": 0.1, "time": 40}}"#,
            "x(k+1) = A x(k) + B u(k), y(k) = C x(k) + η(k) with |u(k)| ≤ τ = 0.1, |η(k)| ≤ ε = 0.2 and |x_i(0)| ≤ δ = 2. \
             ‖A‖∞ = 0.9 and α = 50 give ‖A‖e^{1/α} = 0.918 < 1, so Theorem 4 bounds the state and Theorem 5 with γ = 0.1 gives j = 29: \
             each step's feasible set lives in x(k−29 … k+1) and u(k−29 … k) with the dynamics as equalities, a constant 92 unknowns; with a 2-D state and l∞ bounds it is computed exactly as a polygon (clip by each measurement strip, map by A, add the noise segment), with no LP. The window's initial state is bounded by the Theorem 4 series, \
             so the set is guaranteed exactly (not only up to γ).",
        ),
        UbbKind::Series => (
            r#"{"method": "ubb",
                "title": "Time-series prediction with basis functions (Tempo, Example 1)",
                "model": {"F": [[1.0, 0.0], [0.0, 1.0]]},
                "simulate": {"steps": 30, "seed": 2, "x0": [1.0, 0.15]},
                "ubb": {"eps": 0.5, "basis": ["1", "k"], "time": 9}}"#,
            "f(k) = a₁ + a₂k + u(k), |u(k)| ≤ 0.5, k = 1 … m: the problem element is (a, u), the information f(1 … m) is exact and partial. \
             The polygon is the set of coefficients a consistent with the data (the strips |f(k) − a₁ − a₂k| ≤ 0.5 intersected); \
             the optimal error predictor of f(m+1) is the midpoint of its prediction interval. True a = (1, 0.15).",
        ),
        UbbKind::Leontief => (
            r#"{"method": "ubb",
                "title": "Dynamic Leontief model, 3 industries (Tempo, Example 3)",
                "model": {"F": [[0.2, 0.3, 0.1], [0.1, 0.1, 0.3], [0.3, 0.2, 0.2]],
                          "G": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                          "H": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                          "B": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]},
                "simulate": {"steps": 40, "seed": 3, "u": [[1.0, 0.8, 1.2]]},
                "ubb": {"eps": 0.3, "tau": 0.1, "delta": [1.0], "x0_center": [2.42, 2.14, 2.94], "alpha": 50.0, "beta": 50.0, "gamma": 0.05, "time": 25}}"#,
            "x(k+1) = A x(k) + v(k) + u(k): production x, known demand v = (1, 0.8, 1.2), uncertain demand |u_i| ≤ 0.1, production measured as y = x + η, |η_i| ≤ 0.3. \
             A is nonnegative with column sums 0.6 < 1 (a feasible Leontief model, σ(A) = 0.6); x(0) within ±1 of the steady state (I − A)⁻¹v. \
             The polygon shows industries 1 and 2 (a projection of the 3-D set).",
        ),
        UbbKind::Markov => (
            r#"{"method": "ubb",
                "title": "Absorbing Markov chain with uncertain initial distribution (Tempo, Example 4)",
                "model": {"F": [[1.0, 0.2, 0.1], [0.0, 0.5, 0.3], [0.0, 0.3, 0.6]]},
                "simulate": {"steps": 15, "seed": 4, "x0": [0.1, 0.5, 0.4]},
                "ubb": {"eps": 1.0, "delta": [0.15, 0.4, 0.4], "x0_center": [0.15, 0.4, 0.4], "x0_sum": 1.0, "plane": [1, 2], "time": 2}}"#,
            "Transition probabilities (row-stochastic, the paper's form [[I, O], [D, G]]) P = [[1, 0, 0], [0.2, 0.5, 0.3], [0.1, 0.3, 0.6]]; \
             the distribution evolves as x(k+1) = Pᵀx(k), so model.F = Pᵀ (the paper's x(k+1) = Ax(k) with rows summing to 1 mixes the two conventions). \
             0 ≤ x_i(0) ≤ δ = (0.3, 0.8, 0.8) and Σx_i(0) = 1; no measurements. The transient probabilities x₂, x₃ shrink to 0 as G^k → 0; \
             Theorem 4 does not apply (ρ(A) = 1, so ‖A‖ ≥ 1 in every norm) but A^k stays bounded.",
        ),
    };
    let mut s = Scenario::from_json(json).expect("ubb presets are valid scenarios");
    s.notes = Some(notes.to_string());
    s
}
