//! The `uniform` block of a scenario and its report (method `"uniform_lp"`).
//!
//! ```json
//! {"method": "uniform_lp",
//!  "model": {"F": [[1, 0.5], [-0.5, 0]], "H": [[1, 1]], "B": [[1], [3]]},
//!  "simulate": {"steps": 120, "seed": 1},
//!  "uniform": {"D": [[0]], "xr": [0.3, 0.3], "yr": [0.3], "u_half": 0.5,
//!              "estimator": "swapping", "window": 5, "prior_rel": 0.3,
//!              "prior_overrides": [{"matrix": "A", "row": 1, "col": 1, "lo": -0.3, "hi": 0.3}],
//!              "xr_max": [1, 1], "yr_max": [1], "x_bound": 5, "time": 120}}
//! ```
//!
//! Times are the paper's: x_0 = `model.x1_mean`, data u_t, y_t for t = 1 … steps.
//!
//! With `"data": {"y": [...], "u": [...]}` instead of `simulate`, the method runs on the user's
//! measurements (and measured inputs when the model has B): the model's F, H, B and
//! `uniform.D` are then the nominal Θ around which Θ's prior box is built, `xr`, `yr` and
//! `u_half` (the simulation's truth) are not used, and the report holds nothing that needs the
//! truth (true states and Θ, the Kalman filter with the true variances, errors, the true
//! objective, whether the truth lies in the polygon). A scalar state (n = 1) runs too; its
//! report has no polygon (the reason is in `at.polygon_absent`).
//!
//! The file ends with the method's presets (`// Presets`: the menu entries and their
//! builders), re-exported by [`crate::presets`].

use super::budget::{f, shape, Job, Term, Work};
use super::compare::{
    Assumption, CompareMember, ComparePrepared, NoiseLaw, PlaneReading, PlaneSet, POLYGON_BUDGET,
};
use super::csv::{cells, Table};
use super::preset::Preset;
use super::{
    detail_of, detail_value, Cursor, MethodScenario, Report, Scenario, SimulateSpec, Source,
};
use crate::error::{quoted, Error, Result};
use crate::kalman::KalmanGains;
use crate::linalg::{self, to_rows};
use crate::method::Method;
use crate::model::{Inputs, LinearModel, MatrixSpec, ModelSpec};
use crate::sets::{
    box_image_corners, map_point, minkowski_sum, point_in_convex, polygon_area, SupportPolygon,
};
use crate::study::Study;
use crate::uniform::{self, Joint, Online, OnlineStep, StatePrior, Theta, ThetaPrior, Window};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use std::ops::RangeInclusive;

/// One entry of Θ's prior box set by hand (the paper's A₂₂ ∈ [−0.3, 0.3]).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PriorOverride {
    /// "A", "B", "C" or "D".
    pub matrix: String,
    pub row: usize,
    pub col: usize,
    pub lo: f64,
    pub hi: f64,
}

/// The `uniform` block.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct UniformSpec {
    /// D of (1) (default 0).
    #[serde(rename = "D", default, skip_serializing_if = "Option::is_none")]
    pub d: Option<Vec<Vec<f64>>>,
    /// True half-widths x_r, y_r (2) of the simulated innovations: needed with `simulate`, not
    /// used with `data` (the user's data have no known truth).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub xr: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yr: Option<Vec<f64>>,
    /// Inputs uniform on [−u_half, u_half] (simulation).
    #[serde(default = "default_u_half")]
    pub u_half: f64,
    /// `"states"` (Θ known), `"parameters"` (states known: Θ only, 3.4; simulation only),
    /// `"swapping"` (4.1, the default) or `"expansion"` (4.2).
    #[serde(default)]
    pub estimator: Joint,
    /// Window length ∂ (Section 4).
    #[serde(default = "default_window")]
    pub window: usize,
    /// Prior box of Θ: ±prior_rel·|θ| around the model's Θ (the truth of a simulation, the
    /// user's nominal Θ with data), then the overrides.
    #[serde(default = "default_rel")]
    pub prior_rel: f64,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub prior_overrides: Vec<PriorOverride>,
    /// Upper bounds x̄_r, ȳ_r of the half-widths (5) (default 1; extended automatically when
    /// infeasible).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub xr_max: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yr_max: Option<Vec<f64>>,
    /// Bound on every entry of the window's states (±5 in the paper's example, made for its
    /// scale). Absent: derived from the record ([`derived_x_bound`]), so that a record of
    /// another scale (the Nile's flows near 900) is not clamped by a box made for the paper's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_bound: Option<f64>,
    /// The time cursor (default: the last step).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<usize>,
    /// State components of the polygon (default [0, 1]; absent for n = 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane: Option<[usize; 2]>,
    /// Budget of support LPs of the exact consistent-state polygon (8..=720). The JSON name is
    /// that of the former fixed fan of directions, kept for old scenarios; `budget` (the name
    /// of `ubb`) is accepted too.
    #[serde(default = "default_directions", alias = "budget")]
    pub directions: usize,
}
fn default_u_half() -> f64 {
    0.5
}
fn default_window() -> usize {
    5
}
fn default_rel() -> f64 {
    0.3
}
fn default_directions() -> usize {
    64
}

/// The window at the time cursor.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct WindowReport {
    pub time: usize,
    pub first: usize,
    /// MAP objective Σx_r + Σy_r of the state LP with the Θ in use at that time, and
    /// (simulation) the same sum at the true half-widths (the truth is feasible, so the optimum
    /// is never above it).
    pub objective: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub true_objective: Option<f64>,
    /// Doublings of the half-width bounds this window's LP needed (the polygon uses the bounds
    /// after them).
    #[serde(default)]
    pub extended: usize,
    /// Per state x_time … x_{first−1}: the range of each entry over the optimal face.
    pub face_lo: Vec<Vec<f64>>,
    pub face_hi: Vec<Vec<f64>>,
    /// Ranges of x̂_r and ŷ_r over the same face (the objective is unique, the split between
    /// the half-widths need not be).
    pub face_xr: Vec<[f64; 2]>,
    pub face_yr: Vec<[f64; 2]>,
    /// The states consistent with the window's constraints at the half-width bounds x̄_r, ȳ_r
    /// and the Θ in use, in the `plane` components of x_time: the exact polygon (vertices
    /// counter-clockwise, `exact`, `gap`, `calls`, `hull`). Absent for n = 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polygon: Option<SupportPolygon>,
    /// Why there is no polygon.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polygon_absent: Option<String>,
    /// Whether the polygon's Θ is the true one (a simulation with Θ known: then it must hold the
    /// true state).
    pub polygon_theta_true: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth_in_polygon: Option<bool>,
}

/// The report. Fields that need the truth are present for a simulation only.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct UniformReport {
    pub n: usize,
    pub estimator: Joint,
    pub window: usize,
    /// The polygon's components (absent for n = 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane: Option<[usize; 2]>,
    pub steps: Vec<OnlineStep>,
    /// x_0 … x_T (simulation), u_0 … u_T (without inputs: empty), y_0 … y_T (index 0 unused).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_true: Option<Vec<Vec<f64>>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub u: Vec<Vec<f64>>,
    pub y: Vec<Vec<f64>>,
    /// The true Θ and half-widths (simulation), beside the final estimates.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub theta_true: Option<[Vec<Vec<f64>>; 4]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub xr_true: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yr_true: Option<Vec<f64>>,
    /// Kalman filter with the true Θ and the uniform variances r²/3 (simulation): estimates
    /// x_1 … x_T.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kf: Option<Vec<Vec<f64>>>,
    /// RMS state errors over t = window … T (simulation): LP estimator and KF.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rms_lp: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rms_kf: Option<f64>,
    /// RMS one-step output prediction error of the LP estimator over t = window … T.
    pub rms_prediction: f64,
    /// Total doublings of the half-width bounds over the run.
    pub extended: usize,
    /// The bound |x| ≤ x_bound of every state entry in the LP's prior box (10): the
    /// scenario's `uniform.x_bound`, or derived from the record when absent
    /// (`x_bound_derived`, by 10·‖C⁺‖∞·max_t ‖y_t − D·u_t‖∞).
    pub x_bound: f64,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub x_bound_derived: bool,
    pub at: WindowReport,
}

fn matrix(field: &str, rows: &[Vec<f64>]) -> Result<DMatrix<f64>> {
    linalg::from_rows(field, rows)
}

fn positive(field: &str, v: &[f64], len: usize) -> Result<DVector<f64>> {
    let d = linalg::vector(field, v, len)?;
    if d.iter().any(|x| !(*x > 0.0)) {
        return Err(Error::field(field, "must hold half-widths > 0"));
    }
    Ok(d)
}

/// What a simulation knows beside its data.
struct Truth {
    xr: DVector<f64>,
    yr: DVector<f64>,
    x0: DVector<f64>,
}

/// The reason a scalar state has no polygon.
const NO_PLANE: &str = "the state is scalar (n = 1): there is no plane for the consistent-state polygon; the optimal-face range of x_t is the window's answer";

/// The derived bound's factor over the states the data point at (see [`derived_x_bound`]).
const X_BOUND_FACTOR: f64 = 10.0;

/// The derived bound's formula, as messages and warnings state it.
const DERIVED_RULE: &str = "10·‖C⁺‖∞·max_t ‖y_t − D·u_t‖∞";

/// A state estimate within this fraction of the bound is on it (the simplex's vertices sit
/// on the bound exactly; an interior-point answer within its tolerance).
const ON_BOUND: f64 = 1e-6;

/// The bound of the state LP's prior box |x| ≤ x_bound (10): the scenario's `uniform.x_bound`
/// or, when absent, derived from the record.
#[derive(Debug, Clone, Copy)]
struct StateBound {
    value: f64,
    derived: bool,
}

impl StateBound {
    fn of(spec: &UniformSpec, theta: &Theta, traj: &uniform::Trajectory) -> Result<StateBound> {
        match spec.x_bound {
            Some(value) => Ok(StateBound {
                value,
                derived: false,
            }),
            None => derived_x_bound(theta, traj).map(|value| StateBound {
                value,
                derived: true,
            }),
        }
    }

    /// How the warnings name the bound.
    fn words(&self) -> String {
        if self.derived {
            format!(
                "the bound {:.3e} derived from the record (uniform.x_bound absent: {DERIVED_RULE})",
                self.value
            )
        } else {
            format!("uniform.x_bound = {}", self.value)
        }
    }
}

/// The default bound of every state entry when `uniform.x_bound` is absent. The paper's ±5 is
/// made for its example's scale; a record of another scale must not be clamped by it (the
/// Nile's flows near 900 would all sit at 5). The states the data point at are C⁺(y_t − D u_t)
/// (C⁺ the pseudo-inverse of the nominal C: the least-squares state of one sample), so
/// |x_i| ≲ ‖C⁺‖∞ · max_t ‖y_t − D u_t‖∞; the bound is 10 times that, generous enough for the
/// ±prior_rel freedom of the joint estimators' C (a C 30 % smaller scales the states by 1.43)
/// and for states between samples, while staying at the data's scale. A state C does not see
/// (an unobservable direction) is decided by the bound whatever it is: the report's warning
/// says so. Refused when the formula gives no positive bound (the data all zero, or C = 0).
fn derived_x_bound(theta: &Theta, traj: &uniform::Trajectory) -> Result<f64> {
    let c = &theta.c;
    let svd = linalg::try_svd(c.clone(), true, true)
        .ok_or_else(|| Error::field("model.H", "its singular values do not converge"))?;
    let top = svd.singular_values.iter().copied().fold(0.0, f64::max);
    let pinv = svd
        .pseudo_inverse(1e-9 * top.max(f64::MIN_POSITIVE))
        .map_err(|e| Error::field("model.H", e.to_string()))?;
    let largest = (1..traj.y.len())
        .map(|t| (&traj.y[t] - &theta.d * &traj.u[t]).amax())
        .fold(0.0, f64::max);
    let bound = X_BOUND_FACTOR * linalg::norm_inf(&pinv) * largest;
    if bound.is_finite() && bound > 0.0 {
        Ok(bound)
    } else {
        Err(Error::field(
            "uniform.x_bound",
            format!(
                "is needed: the bound derived from the record, {DERIVED_RULE}, is {bound:e} (the measurements are all zero, or C = 0): give the bound on every state entry"
            ),
        ))
    }
}

/// The warnings of an on-line run: every state component whose estimate sits on the prior
/// box's bound (within [`ON_BOUND`] of it) at some step, with the count. There the bound, not
/// the data, decides the estimate. With `"parameters"` the states are the measured ones, not
/// estimates: nothing to say.
fn bound_warnings(steps: &[OnlineStep], n: usize, bound: StateBound, joint: Joint) -> Vec<String> {
    if joint == Joint::Parameters || steps.is_empty() {
        return Vec::new();
    }
    (0..n)
        .filter_map(|i| {
            let on = steps
                .iter()
                .filter(|s| s.x.get(i).is_some_and(|x| x.abs() >= bound.value * (1.0 - ON_BOUND)))
                .count();
            (on > 0).then(|| {
                format!(
                    "x{} sits on {} at {on} of {} steps: the bound, not the data, decides it there; {}",
                    super::subscript(i + 1),
                    bound.words(),
                    steps.len(),
                    if bound.derived {
                        "the data do not tie this state to the measurements (an unobservable direction), or give uniform.x_bound larger"
                    } else {
                        "raise uniform.x_bound"
                    }
                )
            })
        })
        .collect()
}

/// Most states of a uniform-innovation model: a report within about 2 s.
pub const MAX_STATES: usize = 8;

impl Scenario {
    /// Validate a uniform-innovation scenario: the model, Θ's prior box, the data or the
    /// simulated trajectory, and the on-line estimator ready to run.
    pub fn prepare_uniform(&self) -> Result<UniformPrepared> {
        let spec = self
            .block(
                &self.uniform,
                "estimator, window, …; xr and yr for a simulation",
            )?
            .clone();
        let ms: &ModelSpec = &self.model;
        let constant = |field: &str, m| ModelSpec::constant(field, m, Method::UniformLp);
        let a = constant("model.F", &ms.f)?.ok_or_else(|| Error::field("model.F", "is missing"))?;
        let n = a.nrows();
        linalg::expect_shape("model.F", &a, n, n)?;
        if n > MAX_STATES {
            return Err(Error::field(
                "model.F",
                format!("is {n} × {n}: the uniform-innovation LP is dense in the window's states, so at most {MAX_STATES} states (n = 20 took over 10 s)"),
            ));
        }
        let c = constant("model.H", &ms.h)?.ok_or_else(|| Error::field("model.H", "is missing"))?;
        linalg::expect_shape("model.H", &c, c.nrows(), n)?;
        let m = c.nrows();
        let b = constant("model.B", &ms.b)?.unwrap_or_else(|| DMatrix::zeros(n, 0));
        linalg::expect_shape("model.B", &b, n, b.ncols())?;
        let r = b.ncols();
        let d = match &spec.d {
            Some(rows) => matrix("uniform.D", rows)?,
            None => DMatrix::zeros(m, r),
        };
        linalg::expect_shape("uniform.D", &d, m, r)?;
        // The model's Θ: the truth of a simulation, the nominal Θ with data.
        let theta = Theta { a, b, c, d };
        let xr_max = positive(
            "uniform.xr_max",
            spec.xr_max.as_deref().unwrap_or(&vec![1.0; n]),
            n,
        )?;
        let yr_max = positive(
            "uniform.yr_max",
            spec.yr_max.as_deref().unwrap_or(&vec![1.0; m]),
            m,
        )?;
        if !(spec.u_half.is_finite() && spec.u_half >= 0.0) {
            return Err(Error::field(
                "uniform.u_half",
                "must be a finite half-width ≥ 0",
            ));
        }
        if let Some(b) = spec.x_bound {
            if !(b.is_finite() && b > 0.0) {
                return Err(Error::field(
                    "uniform.x_bound",
                    format!("must be a finite bound > 0, found {b:e}"),
                ));
            }
        }
        if !(spec.prior_rel.is_finite() && spec.prior_rel >= 0.0) {
            return Err(Error::field(
                "uniform.prior_rel",
                "must be a finite fraction ≥ 0",
            ));
        }
        if !(8..=720).contains(&spec.directions) {
            return Err(Error::field(
                "uniform.directions",
                "must be a whole number from 8 to 720 (the budget of support LPs of the polygon)",
            ));
        }
        let joint = spec.estimator;
        let plane = match spec.plane {
            Some(_) if n == 1 => {
                return Err(Error::field(
                    "uniform.plane",
                    "must be absent for a scalar state (n = 1): there is no polygon",
                ))
            }
            Some(p) if p[0] < n && p[1] < n && p[0] != p[1] => Some(p),
            Some(_) => {
                return Err(Error::field(
                    "uniform.plane",
                    format!("must name two distinct state components below n = {n}"),
                ))
            }
            None => (n >= 2).then_some([0, 1]),
        };
        let source = self.source(&Uniform)?;
        let steps = source.steps();
        let (traj, truth) = match source {
            Source::Simulate(sim) => {
                let need = |field: &str, v: &Option<Vec<f64>>| {
                    v.clone().ok_or_else(|| {
                        Error::field(
                            field,
                            "is missing: a simulation needs the true half-widths of the innovations",
                        )
                    })
                };
                let xr = positive("uniform.xr", &need("uniform.xr", &spec.xr)?, n)?;
                let yr = positive("uniform.yr", &need("uniform.yr", &spec.yr)?, m)?;
                let x0 = match &ms.x1_mean {
                    Some(v) => linalg::vector("model.x1_mean", v, n)?,
                    None => DVector::zeros(n),
                };
                let traj =
                    uniform::simulate(&theta, &xr, &yr, &x0, spec.u_half, sim.steps, sim.seed);
                (traj, Some(Truth { xr, yr, x0 }))
            }
            Source::Data(_) => {
                if joint == Joint::Parameters {
                    return Err(Error::field(
                        "uniform.estimator",
                        "\"parameters\" needs the measured states (Section 3.4), which data.y and data.u do not hold: use \"states\", \"swapping\" or \"expansion\" with data",
                    ));
                }
                (data_trajectory(&source, m, r)?, None)
            }
        };
        let x_bound = StateBound::of(&spec, &theta, &traj)?;
        if truth.is_some() {
            // The prior box (5) must hold the simulated truth, or the LP is asked for a state
            // it excludes by construction.
            let reach = traj.x.iter().map(|x| x.amax()).fold(0.0, f64::max);
            if !traj.x.iter().all(|x| x.iter().all(|v| v.is_finite())) || reach > x_bound.value {
                return Err(Error::field(
                    "uniform.x_bound",
                    match x_bound.derived {
                        false => format!("= {} is violated by the simulated states (|x| reaches {reach:.3}): the prior box must hold the truth", x_bound.value),
                        true => format!("is absent, and the bound derived from the data ({DERIVED_RULE} = {:.3e}) does not hold the simulated states (|x| reaches {reach:.3e}): give a bound that holds the truth", x_bound.value),
                    },
                ));
            }
        }
        uniform_resolution(
            self,
            &traj,
            truth
                .as_ref()
                .map_or((&xr_max, &yr_max), |t| (&t.xr, &t.yr)),
            spec.window,
        )?;
        // Θ's prior box: ±rel·|θ| around the model's Θ, then the overrides.
        let tv = theta.to_vec();
        let mut lo = tv.map(|v| v - spec.prior_rel * v.abs());
        let mut hi = tv.map(|v| v + spec.prior_rel * v.abs());
        let offsets = [0, n * n, n * n + n * r, n * n + n * r + m * n];
        let cols = [n, r, n, r];
        let shapes = [(n, n), (n, r), (m, n), (m, r)];
        for (k, o) in spec.prior_overrides.iter().enumerate() {
            let field = format!("uniform.prior_overrides[{k}]");
            let idx = ["A", "B", "C", "D"]
                .iter()
                .position(|s| *s == o.matrix)
                .ok_or_else(|| {
                    Error::field(
                        format!("{field}.matrix"),
                        format!(
                            "must be \"A\", \"B\", \"C\" or \"D\", found {}",
                            quoted(&o.matrix)
                        ),
                    )
                })?;
            if o.row >= shapes[idx].0 || o.col >= shapes[idx].1 {
                return Err(Error::field(
                    &field,
                    format!(
                        "entry ({}, {}) is outside {} ({}×{})",
                        o.row, o.col, o.matrix, shapes[idx].0, shapes[idx].1
                    ),
                ));
            }
            if !(o.lo.is_finite() && o.hi.is_finite() && o.lo <= o.hi) {
                return Err(Error::field(&field, "needs finite lo ≤ hi"));
            }
            let j = offsets[idx] + o.row * cols[idx] + o.col;
            lo[j] = o.lo;
            hi[j] = o.hi;
        }
        let theta_prior = ThetaPrior {
            lo: Theta::from_vec(lo.as_slice(), &theta),
            hi: Theta::from_vec(hi.as_slice(), &theta),
            xr_max: xr_max.clone(),
            yr_max: yr_max.clone(),
        };
        let state_prior = StatePrior {
            x_lo: -x_bound.value,
            x_hi: x_bound.value,
            x0: None,
            xr_max: xr_max.clone(),
            yr_max: yr_max.clone(),
        };
        // The joint methods start from the middle of Θ's prior box.
        let theta0 = match joint {
            Joint::States => theta.clone(),
            _ => Theta::from_vec(((&lo + &hi) * 0.5).as_slice(), &theta),
        };
        let online = Online::new(joint, spec.window, theta0, theta_prior, state_prior.clone())
            .map_err(|e| Error::field("uniform.window", e.message))?;
        Ok(UniformPrepared {
            spec,
            n,
            m,
            plane,
            steps,
            theta,
            traj,
            truth,
            x_bound,
            state_prior,
            online,
            thetas: Vec::new(),
        })
    }

    /// Validate a uniform-innovation scenario and run it.
    pub fn uniform_report(&self) -> Result<UniformReport> {
        let mut p = self.prepare_uniform()?;
        // The cursor is checked before the on-line run (the costly part).
        let time = p.spec.time.unwrap_or(p.steps);
        p.check_time(time)?;
        p.run_online()?;
        let at = p.window_at(time)?;
        p.report(at)
    }
}

/// The uniform model's precision boundary ([`crate::precision`]): every constraint of the LP
/// (6)–(10) is one datum against the half-width of a uniform innovation, |y − Cx − Du| ≤ yr and
/// |x⁺ − Ax − Bu| ≤ xr, and a window combines (n + m) such data per step. The noise scale is the
/// smallest half-width: the simulation's true xr, yr, or with data the bound yr_max of the
/// measurements.
/// (The uniform density puts at most δ/ε of its mass within δ of a bound ε, below the Gaussian
/// factor 0.8/σ the check uses.)
fn uniform_resolution(
    scenario: &Scenario,
    traj: &uniform::Trajectory,
    (xr, yr): (&DVector<f64>, &DVector<f64>),
    window: usize,
) -> Result<()> {
    let largest = |v: &[DVector<f64>]| crate::precision::largest(v.iter().map(|x| x.as_slice()));
    let magnitude = largest(&traj.x).max(largest(&traj.y)).max(largest(&traj.u));
    // With data the half-widths are only bounds, and the state ones may be floors for states
    // without noise (compare's 10⁻⁶): the measured data are judged against the measurement
    // half-widths. A simulation's true half-widths are all real noise.
    let noise = if scenario.data.is_some() {
        yr.iter().copied().fold(f64::INFINITY, f64::min)
    } else {
        xr.iter()
            .chain(yr.iter())
            .copied()
            .fold(f64::INFINITY, f64::min)
    };
    let n_m = traj.x.first().map_or(0, |x| x.len()) + traj.y.first().map_or(0, |y| y.len());
    crate::precision::Resolution {
        field: if scenario.data.is_some() {
            "data.y"
        } else {
            "model.x1_mean"
        },
        what: "the states and data",
        magnitude,
        noise,
        noise_name: "the smallest innovation half-width",
        combined: window.max(1) * n_m,
        tests: 1,
        method: "the uniform-innovation LP",
    }
    .check()
}

/// A validated uniform-innovation scenario ([`Scenario::prepare_uniform`]); after
/// `UniformPrepared::run_online`, the on-line estimates and the Θ in use after every step,
/// from which the report and the cursor take the window at any time.
pub struct UniformPrepared {
    spec: UniformSpec,
    n: usize,
    m: usize,
    plane: Option<[usize; 2]>,
    steps: usize,
    /// The model's Θ: the truth of a simulation, the nominal Θ with data.
    theta: Theta,
    traj: uniform::Trajectory,
    truth: Option<Truth>,
    /// The bound |x| ≤ x_bound of the state LP's prior box (10): the scenario's or derived.
    x_bound: StateBound,
    state_prior: StatePrior,
    online: Online,
    /// Θ̂ after step t (index t − 1): the Θ the window at t is solved with.
    thetas: Vec<Theta>,
}

impl UniformPrepared {
    /// `uniform.time` = t must be a step of the run.
    fn check_time(&self, time: usize) -> Result<()> {
        if (1..=self.steps).contains(&time) {
            Ok(())
        } else {
            Err(Error::field(
                "uniform.time",
                format!(
                    "must be a whole number from 1 to {}, found {time}",
                    self.steps
                ),
            ))
        }
    }

    /// The on-line run over every step (Section 4), keeping the Θ in use after each.
    fn run_online(&mut self) -> Result<()> {
        let traj = &self.traj;
        for t in 1..=self.steps {
            if self.online.joint == Joint::Parameters {
                self.online.step_parameters(t, &traj.x, &traj.u, &traj.y)?;
            } else {
                self.online.step(t, &traj.u, &traj.y)?;
            }
            self.thetas.push(self.online.theta.clone());
        }
        Ok(())
    }

    /// The window at the time cursor t, with the Θ the estimator used there (after its step):
    /// its optimal face, half-width ranges and the consistent-state polygon.
    fn window_at(&self, time: usize) -> Result<WindowReport> {
        self.check_time(time)?;
        let (n, m) = (self.n, self.m);
        let (traj, state_prior) = (&self.traj, &self.state_prior);
        let theta_at = &self.thetas[time - 1];
        let w = Window {
            first: time.saturating_sub(self.spec.window - 1).max(1),
            last: time,
        };
        let (est, lp) = uniform::estimate_states(theta_at, &traj.u, &traj.y, w, state_prior)?;
        let face = uniform::optimal_face(&lp, est.objective, n, w.states())?;
        let nx = w.states() * n;
        let hw = uniform::face_ranges(&lp, est.objective, &(nx..nx + n + m).collect::<Vec<_>>())?;
        let (face_xr, face_yr): (Vec<[f64; 2]>, Vec<[f64; 2]>) = (
            hw[..n].iter().map(|r| [r.0, r.1]).collect(),
            hw[n..].iter().map(|r| [r.0, r.1]).collect(),
        );
        let truth = &self.truth;
        let polygon_theta_true = self.online.joint == Joint::States && truth.is_some();
        // The polygon at the bounds the window's LP ended with (x̄_r, ȳ_r unless it had to
        // extend them): the state LP was feasible there, so the set is not empty.
        let polygon = match self.plane {
            Some(plane) => Some(uniform::consistent_polygon(
                theta_at,
                &traj.u,
                &traj.y,
                w,
                state_prior,
                &lp.hi.rows(nx, n).into_owned(),
                &lp.hi.rows(nx + n, m).into_owned(),
                plane,
                self.spec.directions,
            )?),
            None => None,
        };
        let truth_in_polygon = match (&polygon, self.plane, truth) {
            (Some(poly), Some(p), Some(_)) => {
                Some(poly.contains([traj.x[time][p[0]], traj.x[time][p[1]]], 1e-7))
            }
            _ => None,
        };
        Ok(WindowReport {
            time,
            first: w.first,
            objective: est.objective,
            true_objective: truth.as_ref().map(|t| t.xr.sum() + t.yr.sum()),
            extended: est.extended,
            face_lo: face.iter().map(|f| f.0.iter().copied().collect()).collect(),
            face_hi: face.iter().map(|f| f.1.iter().copied().collect()).collect(),
            face_xr,
            face_yr,
            polygon_absent: polygon.is_none().then(|| NO_PLANE.to_string()),
            polygon,
            polygon_theta_true,
            truth_in_polygon,
        })
    }

    /// The report of the run, with `at`, the window at the cursor.
    fn report(self, at: WindowReport) -> Result<UniformReport> {
        let UniformPrepared {
            spec,
            n,
            plane,
            steps,
            theta,
            traj,
            truth,
            online,
            x_bound,
            ..
        } = self;
        let r = theta.r();
        let from = spec.window.min(steps);
        let rms = |e: &dyn Fn(usize) -> f64| -> f64 {
            let total: f64 = (from..=steps).map(e).sum();
            (total / (steps + 1 - from) as f64).sqrt()
        };
        let rms_prediction = rms(&|t| {
            (DVector::from_vec(online.steps[t - 1].y_pred.clone()) - &traj.y[t]).norm_squared()
        });
        let rows = |v: &[DVector<f64>]| {
            v.iter()
                .map(|x| x.iter().copied().collect())
                .collect::<Vec<Vec<f64>>>()
        };
        // What only a simulation knows: the truth, the KF with the uniform variances r²/3 and
        // the true Θ (x_{t+1} = A x_t + B u_{t+1}), and the errors against the truth.
        let (mut kf, mut rms_lp, mut rms_kf) = (None, None, None);
        if let Some(tr) = &truth {
            let k = kalman_uniform(&theta, &tr.xr, &tr.yr, &tr.x0, &traj)?;
            let err = |est: &dyn Fn(usize) -> DVector<f64>| {
                rms(&|t| (est(t) - &traj.x[t]).norm_squared())
            };
            rms_lp = Some(err(&|t| DVector::from_vec(online.steps[t - 1].x.clone())));
            rms_kf = Some(err(&|t| k[t - 1].clone()));
            kf = Some(rows(&k));
        }
        Ok(UniformReport {
            n,
            estimator: online.joint,
            window: spec.window,
            plane,
            extended: online.steps.iter().map(|s| s.extended).sum(),
            x_true: truth.as_ref().map(|_| rows(&traj.x)),
            u: if r > 0 { rows(&traj.u) } else { Vec::new() },
            y: rows(&traj.y),
            theta_true: truth.as_ref().map(|_| {
                [
                    linalg::to_rows(&theta.a),
                    linalg::to_rows(&theta.b),
                    linalg::to_rows(&theta.c),
                    linalg::to_rows(&theta.d),
                ]
            }),
            xr_true: truth.as_ref().map(|t| t.xr.iter().copied().collect()),
            yr_true: truth.as_ref().map(|t| t.yr.iter().copied().collect()),
            kf,
            rms_lp,
            rms_kf,
            rms_prediction,
            steps: online.steps,
            x_bound: x_bound.value,
            x_bound_derived: x_bound.derived,
            at,
        })
    }
}

/// The uniform-innovation cursor: the on-line run made once; the window, optimal face and
/// consistent-state polygon at any time on demand (the report's `at`).
struct UniformCursor(UniformPrepared);

impl Cursor for UniformCursor {
    fn steps(&self) -> RangeInclusive<usize> {
        1..=self.0.steps
    }
    fn at(&mut self, t: usize) -> Result<serde_json::Value> {
        detail_value(&self.0.window_at(t)?)
    }
}

/// The user's data in the layout of [`uniform::Trajectory`]: u_0 … u_T and y_0 … y_T (index 0
/// unused), no states. `data.u` holds one row per measurement, or one row held constant.
fn data_trajectory(source: &Source, m: usize, r: usize) -> Result<uniform::Trajectory> {
    let y = source.measurements(m)?;
    let steps = y.len();
    let u = match source.inputs(r)? {
        Some(u) if u.len() == 1 || u.len() == steps => u,
        Some(u) => {
            return Err(Error::field(
                "data.u",
                format!(
                    "has {} rows for {steps_measurements}: give one input row per measurement (or one row, held constant)",
                    u.len(), steps_measurements = crate::error::counted(steps, "measurement", "measurements")
                ),
            ))
        }
        None if r > 0 => {
            return Err(Error::field(
                "data.u",
                "is missing: the model has inputs (model.B), so the measured u_1 … u_T are needed",
            ))
        }
        None => Vec::new(),
    };
    let input = |t: usize| match u.len() {
        0 => DVector::zeros(r),
        len => u[(t - 1).min(len - 1)].clone(),
    };
    Ok(uniform::Trajectory {
        x: Vec::new(),
        u: std::iter::once(DVector::zeros(r))
            .chain((1..=steps).map(input))
            .collect(),
        y: std::iter::once(DVector::zeros(m)).chain(y).collect(),
    })
}

/// The Kalman filter of the LU model with Cov e^x = diag(x_r²/3), Cov e^y = diag(y_r²/3).
fn kalman_uniform(
    theta: &Theta,
    xr: &DVector<f64>,
    yr: &DVector<f64>,
    x0: &DVector<f64>,
    traj: &uniform::Trajectory,
) -> Result<Vec<DVector<f64>>> {
    let q = DMatrix::from_diagonal(&xr.map(|v| v * v / 3.0));
    let rr = DMatrix::from_diagonal(&yr.map(|v| v * v / 3.0));
    let steps = traj.y.len() - 1;
    let spec = ModelSpec {
        f: Some(MatrixSpec::of(&theta.a)),
        h: Some(MatrixSpec::of(&theta.c)),
        v: Some(MatrixSpec::of(&q)),
        w: Some(MatrixSpec::of(&rr)),
        b: (theta.r() > 0).then(|| MatrixSpec::of(&theta.b)),
        // x_1 = A x_0 + B u_1 + e^x_1: known mean, covariance Q.
        x1_mean: Some(
            (&theta.a * x0 + &theta.b * &traj.u[1])
                .iter()
                .copied()
                .collect(),
        ),
        x1_cov: Some(linalg::to_rows(&q)),
        ..Default::default()
    };
    let model = LinearModel::from_spec(&spec)?;
    // The crate's model adds B u_t to x_{t+1}: feed u_{t+1}.
    let u_rows: Vec<Vec<f64>> = (1..=steps)
        .map(|t| traj.u[(t + 1).min(steps)].iter().copied().collect())
        .collect();
    let inputs = if theta.r() > 0 {
        Inputs::from_rows("uniform.u", &u_rows)?
    } else {
        Inputs::none()
    };
    let y: Vec<DVector<f64>> = (1..=steps)
        .map(|t| &traj.y[t] - &theta.d * &traj.u[t])
        .collect();
    let gains = KalmanGains::new(&model, steps)?;
    Ok(gains.filter(&model, &y, &inputs))
}

/// Linear models with uniform innovations (Pavelková): the `uniform` block, the on-line LP
/// estimates and the window at the cursor.
pub(crate) struct Uniform;

impl MethodScenario for Uniform {
    fn true_noise(&self) -> Option<&'static str> {
        Some(
            "the uniform-noise LP draws its simulated noise uniformly within the model's half-widths; its noise is not Gaussian, so a covariance scale does not apply",
        )
    }
    fn gaps(&self) -> super::Gaps {
        super::Gaps::Refused("its state LP (6)–(10) ties each sample's output innovation to the state at that time: a missing sample leaves the MAP estimate of Pavelková's window undefined there")
    }
    fn time_index(&self) -> super::TimeIndex {
        super::TimeIndex::OneBased
    }
    fn max_states(&self) -> usize {
        MAX_STATES
    }
    fn truth_keys(&self) -> &'static [(&'static str, &'static str)] {
        &[
            ("theta_true", "uniform: the true Θ"),
            ("xr_true", "uniform: the true state-noise half-widths"),
            ("yr_true", "uniform: the true output-noise half-widths"),
            (
                "true_objective",
                "uniform: the LP objective at the true half-widths",
            ),
            (
                "truth_in_polygon",
                "uniform: whether the consistent polygon holds the truth",
            ),
            (
                ".uniform.kf",
                "uniform: the Kalman filter tuned with the true half-widths",
            ),
            (
                "rms_kf",
                "uniform: the Kalman filter's error against the truth",
            ),
            (
                "rms_lp",
                "uniform: the LP estimate's error against the truth",
            ),
        ]
    }
    fn steps(&self) -> RangeInclusive<usize> {
        2..=2000
    }
    fn data_shape(&self, s: &Scenario) -> Result<(usize, usize)> {
        // m = rows of C (model.H), r = columns of B, as `uniform_report` reads the data.
        let constant = |field: &str, m| ModelSpec::constant(field, m, Method::UniformLp);
        let c = constant("model.H", &s.model.h)?
            .ok_or_else(|| Error::field("model.H", "is missing"))?;
        let r = constant("model.B", &s.model.b)?.map_or(0, |b| b.ncols());
        Ok((c.nrows(), r))
    }
    fn work(&self, s: &Scenario, _: Job) -> Work {
        work(s)
    }
    fn run(&self, s: &Scenario) -> Result<Report> {
        let u = s.uniform_report()?;
        let q = u.y.first().map_or(0, |y| y.len());
        let mut r = Report::of(
            s,
            s.alpha,
            (u.n, q),
            u.at.time,
            u.plane.map_or(vec![0], |p| p.to_vec()),
            // The measurements y_1 … y_T, as `data.y` takes them (the block keeps the paper's
            // index 0).
            u.y.get(1..).unwrap_or_default().to_vec(),
        );
        let bound = StateBound {
            value: u.x_bound,
            derived: u.x_bound_derived,
        };
        r.warnings
            .extend(bound_warnings(&u.steps, u.n, bound, u.estimator));
        r.uniform = Some(u);
        Ok(r)
    }
    fn cursor(&self, s: &Scenario) -> Result<Option<Box<dyn Cursor>>> {
        let mut p = s.prepare_uniform()?;
        p.run_online()?;
        Ok(Some(Box::new(UniformCursor(p))))
    }
    fn table(&self, r: &Report) -> Table {
        // One row per time t: the data, the MAP state estimate and the estimated innovation
        // half-widths (the set sizes of the uniform model), and the truth when simulated.
        let Some(u) = &r.uniform else {
            return Table::new(vec!["t".into()]);
        };
        let (n, q) = (u.n, u.y.get(1).map_or(0, |y| y.len()));
        let truth = u.x_true.is_some();
        let mut columns = vec!["t".to_string()];
        columns.extend(Table::numbered("y", q));
        if truth {
            columns.extend(Table::numbered("x", n));
        }
        columns.extend(Table::numbered("x_map", n));
        columns.extend(Table::numbered("xr", n));
        columns.extend(Table::numbered("yr", q));
        columns.extend(Table::numbered("y_pred", q));
        if u.kf.is_some() {
            columns.extend(Table::numbered("kf", n));
        }
        let mut table = Table::new(columns);
        for (k, st) in u.steps.iter().enumerate() {
            let mut row = vec![Some(st.t as f64)];
            row.extend(cells(u.y.get(st.t).map(|y| y.as_slice()), q));
            if truth {
                let x = u.x_true.as_ref().and_then(|x| x.get(st.t));
                row.extend(cells(x.map(|x| x.as_slice()), n));
            }
            row.extend(cells(Some(&st.x), n));
            row.extend(cells(Some(&st.xr), n));
            row.extend(cells(Some(&st.yr), q));
            row.extend(cells(Some(&st.y_pred), q));
            if let Some(kf) = &u.kf {
                row.extend(cells(kf.get(k).map(|x| x.as_slice()), n));
            }
            table.push(row);
        }
        table
    }
    fn cursor_steps(&self, report: &Report) -> Option<RangeInclusive<usize>> {
        // The times 1 … T of the on-line run, as `UniformCursor`'s.
        report.uniform.as_ref().map(|u| 1..=u.steps.len())
    }
    fn set_at(&self, report: &mut Report, at: serde_json::Value) -> Result<()> {
        let at: WindowReport = detail_of(at)?;
        let u = report.uniform.as_mut().ok_or_else(|| {
            Error::field(
                "report.uniform",
                "is missing: the report is not a uniform-innovation report",
            )
        })?;
        report.time = at.time;
        u.at = at;
        Ok(())
    }
    fn study(&self, _: &Scenario, _: Option<usize>) -> Result<Box<dyn Study>> {
        Err(Error::field(
            "method",
            "\"uniform_lp\" has no Monte Carlo study: its LP gives MAP estimates and a consistent set, with no probability to count",
        ))
    }
    fn compare_member(&self) -> Option<&dyn CompareMember> {
        Some(self)
    }
    fn presets(&self) -> Vec<Preset> {
        presets()
    }
}

/// Operations of one interior-point solve per unit of (variables + rows) · variables (the
/// LPs are dense in the window's states: n = 2, ∂ = 80 about 33 ms natively, 200 measured,
/// 260 for a margin).
const OPS_LP: f64 = 260.0;
/// Operations of one solve besides (building it, clarabel's setup: about 0.35 ms natively).
const OPS_SOLVE: f64 = 350_000.0;
/// A re-solve of the loaded state LP at the cursor (optimal face, polygon) against a fresh one.
const RESOLVE: f64 = 0.15;

/// The uniform-innovation costs: at every step t one state LP over the window's min(t, ∂) + 1
/// states (and, estimating Θ, one parameter LP), each of (variables + rows) · variables; at
/// the cursor re-solves of the state LP for the optimal face (two per state entry of the window
/// and per half-width) and the polygon's support LPs (`uniform.directions`).
fn work(s: &Scenario) -> Work {
    let n = shape(&s.model.f).0.max(1);
    let m = shape(&s.model.h).0.max(1);
    let r = shape(&s.model.b).1;
    let steps = s.written_steps();
    let mut w = Work::default();
    let Some(spec) = s
        .uniform
        .as_ref()
        .filter(|u| n <= MAX_STATES && u.window <= uniform::MAX_WINDOW)
    else {
        return w;
    };
    let lp = |vars: usize, rows: usize| OPS_LP * f(vars + rows) * f(vars) + OPS_SOLVE;
    let state = |len: usize| lp((len + 2) * n + m, 2 * len * (2 * n + m));
    let parameters = |len: usize| match spec.estimator {
        Joint::States => 0.0,
        _ => lp(n * n + n * r + m * n + m * r + n + m, 2 * len * (n + m)),
    };
    let window = spec.window;
    let online: f64 = (1..=steps)
        .map(|t| {
            let len = t.min(window);
            state(len) + parameters(len)
        })
        .sum();
    w.ops(
        Term::new(
            "uniform.window",
            format!(
                "= {window} with {} = {steps} and n = {n_states}, m = {m_outputs}",
                s.steps_field(),
                n_states = crate::error::counted(n, "state", "states"),
                m_outputs = crate::error::counted(m, "output", "outputs")
            ),
            "steps · one LP over the window's ∂·n states, of (variables + rows) · variables",
            online,
        )
        .advice("a shorter window, fewer steps or states"),
    );
    let len = window.min(spec.time.unwrap_or(steps)).max(1);
    let resolves = f(2 * (len + 1) * n + 2 * (n + m) + spec.directions);
    w.ops(
        Term::new(
            "uniform.directions",
            format!(
                "= {} with window = {window} and n = {n_states}",
                spec.directions,
                n_states = crate::error::counted(n, "state", "states")
            ),
            "(2(∂ + 1)·n + directions) LPs at the cursor: the optimal face and the polygon",
            resolves * RESOLVE * state(len),
        )
        .advice("fewer directions or a shorter window"),
    );
    w
}

// ---------------------------------------------------------------------------------------------
// Compare: what a compare asks of Pavelková's estimator (`scenario::compare`)

/// Bound on every state entry of Pavelková's window LP in units of the record's scale (her ±5,
/// widened: the compare states are the model's, not hers). In the record's own unit, so that a
/// record scaled by 10⁶ is not cut by the box, nor one scaled by 10⁻⁸ lost in it (issue 25).
const X_BOUND_PER_SCALE: f64 = 1e4;

impl CompareMember for Uniform {
    fn options(&self) -> &'static [&'static str] {
        // The box on the window's states and the polygon's support directions. The half-width
        // bounds are the compare's (b_v, b_w of its noise law), Θ its model, the window its
        // `compare.window`.
        &["x_bound", "directions"]
    }
    fn compare_order(&self) -> usize {
        5
    }
    fn assumption(&self, p: &ComparePrepared) -> Assumption {
        let violated = match (p.law(), p.bounds_violation()) {
            (_, Some(b)) if p.bounds_below_truth() => Some(b),
            (NoiseLaw::Uniform, _) => None,
            (law, _) => Some(format!("violated: noise not uniform ({})", law.name())),
        };
        Assumption {
            assumes: "innovations uniform within the half-width bounds",
            violated,
            promise: "nothing (the consistent set holds the state whenever the bounds hold)",
            level: None,
            at_least: false,
        }
    }
    fn derived_scenario(&self, p: &ComparePrepared, t: usize) -> Result<Scenario> {
        // |(G v)_i| ≤ Σ_j |G_ij|·b_v: the half-width bound of each state's innovation. The
        // LP needs positive half-widths: a state without noise gets 10⁻⁶ of the largest.
        let &[i, j] = p.plane() else {
            return Err(Error::field(
                "model.F",
                "is 1×1: Pavelková's consistent set is computed and drawn as a polygon of two state components (uniform.plane), which a scalar state does not have",
            ));
        };
        if p.n() > 2 && p.predicts() {
            // F·P ⊕ G·[−b_v, b_v] needs the consistent set of the whole x_t mapped by F's two
            // rows: its projection on two coordinates (the polygon) does not determine that.
            return Err(Error::field(
                "compare.target",
                format!(
                    "is \"predict\", but with n = {} states Pavelková's prediction of the plane's components needs the consistent set of all of x_t mapped by F, and only its projection on the plane is computed",
                    p.n()
                ),
            ));
        }
        let (bound_v, bound_w) = p.bounds();
        let xr: Vec<f64> = p
            .noise_g()
            .row_iter()
            .map(|r| r.iter().map(|g| g.abs()).sum::<f64>() * bound_v)
            .collect();
        let floor = 1e-6 * xr.iter().copied().fold(bound_w, f64::max);
        let xr: Vec<f64> = xr.into_iter().map(|x| x.max(floor)).collect();
        let mut s = p.own_scenario(Method::UniformLp, p.bare_model(), t);
        s.uniform = Some(UniformSpec {
            d: None,
            xr: None,
            yr: None,
            u_half: default_u_half(),
            // Θ (the model) known: the consistent states of the window (Section 3.3).
            estimator: Joint::States,
            window: p.window(t),
            prior_rel: default_rel(),
            prior_overrides: Vec::new(),
            xr_max: Some(xr),
            yr_max: Some(vec![bound_w; p.model().q()]),
            x_bound: Some(X_BOUND_PER_SCALE * p.record_scale()),
            time: Some(t),
            plane: Some([i, j]),
            directions: POLYGON_BUDGET,
        });
        Ok(s)
    }
    fn plane_set(
        &self,
        p: &ComparePrepared,
        r: &Report,
        truth: Option<&[f64]>,
    ) -> Result<PlaneReading> {
        let w = r
            .uniform
            .as_ref()
            .ok_or_else(|| Error::field("report.uniform", "has no uniform part"))?;
        let poly = w.at.polygon.as_ref().ok_or_else(|| {
            Error::field(
                "report.uniform.at.polygon",
                w.at.polygon_absent
                    .clone()
                    .unwrap_or_else(|| "is absent".into()),
            )
        })?;
        let mut note = vec![format!("window ∂ = {}", w.window)];
        if w.at.extended > 0 {
            note.push(format!(
                "half-width bounds doubled {}× (the data contradicted them)",
                w.at.extended
            ));
        }
        if p.predicts() {
            note.push("F·P ⊕ G·[−b_v, b_v]".to_string());
        }
        let (vertices, holds) = target_set(p, poly, truth);
        Ok(PlaneReading {
            area: Some(polygon_area(&vertices)),
            holds,
            note: Some(note.join("; ")),
            set: PlaneSet::Polygon { vertices },
            outline: None,
        })
    }
    /// The on-line run up to t (each window's Θ and bounds depend on the steps before) and
    /// the consistent polygon at t, without the optimal face and half-width ranges the
    /// report adds there.
    fn holds_at(&self, p: &ComparePrepared, s: &Scenario, truth: &[f64]) -> Result<bool> {
        super::compare::checked_as_run(s)?;
        let mut prepared = s.prepare_uniform()?;
        let time = prepared.spec.time.unwrap_or(prepared.steps);
        prepared.check_time(time)?;
        let poly = match prepared.polygon_without_lp(time)? {
            Some(poly) => poly,
            None => {
                prepared.run_online()?;
                prepared.polygon_at(time)?
            }
        };
        Ok(target_set(p, &poly, Some(truth)).1 == Some(true))
    }
    fn remedy(&self, p: &ComparePrepared, e: &Error) -> Option<String> {
        match e.field.as_str() {
            "model.F" => Some("a model of n ≥ 2 states".to_string()),
            "compare.target" => Some(format!(
                "compare.target \"filter\" (the consistent set of x_t itself, projected on the plane), or a model of n = 2 states (n = {} here)",
                p.n()
            )),
            _ => None,
        }
    }
}

/// The target's set from the consistent polygon P of x_t, and whether it holds `truth`. P is
/// of x_t; x_{t+1} = F·x_t + G·v with |v_i| ≤ b_v, so the prediction set is the Minkowski sum
/// F·P ⊕ G·[−b_v, b_v]^p (exact, a polygon).
fn target_set(
    p: &ComparePrepared,
    poly: &SupportPolygon,
    truth: Option<&[f64]>,
) -> (Vec<[f64; 2]>, Option<bool>) {
    let truth = truth.map(|x| [x[0], x[1]]);
    // A prediction reaches here for n = 2 only (`derived_scenario` refuses it for n > 2).
    if p.predicts() {
        let f = p.model().f(1);
        let image: Vec<[f64; 2]> = poly.vertices.iter().map(|&v| map_point(f, v)).collect();
        let noise = box_image_corners(p.noise_g(), p.bounds().0);
        let vertices = minkowski_sum(&image, &noise);
        let holds = truth.map(|x| point_in_convex(&vertices, x, 1e-9));
        (vertices, holds)
    } else {
        (poly.vertices.clone(), truth.map(|x| poly.contains(x, 1e-9)))
    }
}

impl UniformPrepared {
    /// With Θ known ([`Joint::States`]) and a planar state, each window's estimate depends on
    /// nothing before it, and its polygon only on the bounds its LP is extended to
    /// ([`uniform::consistent_polygon_extending`]): the polygon at `time` with no LP. Every
    /// window up to `time` is checked for feasibility, as the on-line run's LPs are (the report
    /// refuses a record whose earlier window admits no state). `None`: the LP path is needed.
    fn polygon_without_lp(&self, time: usize) -> Result<Option<SupportPolygon>> {
        let Some(plane) = self.plane else {
            return Ok(None);
        };
        if self.online.joint != Joint::States {
            return Ok(None);
        }
        let mut last = None;
        for t in 1..=time {
            let w = Window {
                first: t.saturating_sub(self.spec.window - 1).max(1),
                last: t,
            };
            let theta = &self.online.theta;
            match uniform::consistent_polygon_extending(
                theta,
                &self.traj.u,
                &self.traj.y,
                w,
                &self.state_prior,
                plane,
            )? {
                Some((polygon, _)) => last = Some(polygon),
                None => return Ok(None),
            }
        }
        Ok(last)
    }

    /// The consistent-state polygon of the window at `time` alone: [`Self::window_at`]'s, at
    /// the bounds the window's LP ends with, after [`Self::run_online`].
    fn polygon_at(&self, time: usize) -> Result<SupportPolygon> {
        let plane = self
            .plane
            .ok_or_else(|| Error::field("report.uniform.at.polygon", NO_PLANE))?;
        let (n, m) = (self.n, self.m);
        let theta_at = &self.thetas[time - 1];
        let w = Window {
            first: time.saturating_sub(self.spec.window - 1).max(1),
            last: time,
        };
        let (_, lp) =
            uniform::estimate_states(theta_at, &self.traj.u, &self.traj.y, w, &self.state_prior)?;
        let nx = w.states() * n;
        uniform::consistent_polygon(
            theta_at,
            &self.traj.u,
            &self.traj.y,
            w,
            &self.state_prior,
            &lp.hi.rows(nx, n).into_owned(),
            &lp.hi.rows(nx + n, m).into_owned(),
            plane,
            self.spec.directions,
        )
    }
}

// ---------------------------------------------------------------------------------------------
// Presets

/// Pavelková's example as the method's one preset (the trait's `presets`, gathered by
/// [`crate::presets::all`]).
fn presets() -> Vec<Preset> {
    vec![
        Preset {
            name: "uniform-paper".into(),
            label: "Pavelková Section 5 — the LU model, swapping".into(),
            menu: "Pavelková Sec. 5 — the LU model".into(),
            description: "Pavelková, Section 5: LU model (14)–(15), 120 samples, window ∂ = 5, swapping-based joint estimation of states, Θ and half-widths".into(),
            scenario: uniform_paper(),
        },
    ]
}

/// Pavelková's example (14)–(15): A = [[1, 0.5], [−0.5, 0]], B = [1, 3]ᵀ, C = [1 1], D = 0,
/// x_r = 0.3·1, y_r = 0.3, inputs uniform with half-width 0.5, 120 samples, ∂ = 5, Θ's prior ±30 %
/// (A₂₂ ∈ [−0.3, 0.3]), x̄_r = ȳ_r = 1, ±5 on the window's states.
/// Θ, x_r and y_r of Pavelková's example (14)–(15), for code that works on the core directly
/// (tests, benchmarks); [`uniform_paper`] is the same model as a scenario.
pub fn uniform_paper_model() -> (crate::uniform::Theta, DVector<f64>, DVector<f64>) {
    let theta = crate::uniform::Theta {
        a: DMatrix::from_row_slice(2, 2, &[1.0, 0.5, -0.5, 0.0]),
        b: DMatrix::from_row_slice(2, 1, &[1.0, 3.0]),
        c: DMatrix::from_row_slice(1, 2, &[1.0, 1.0]),
        d: DMatrix::zeros(1, 1),
    };
    (
        theta,
        DVector::from_element(2, 0.3),
        DVector::from_element(1, 0.3),
    )
}

pub fn uniform_paper() -> Scenario {
    let (theta, xr, yr) = uniform_paper_model();
    let model = ModelSpec {
        f: Some(MatrixSpec::of(&theta.a)),
        h: Some(MatrixSpec::of(&theta.c)),
        b: Some(MatrixSpec::of(&theta.b)),
        ..Default::default()
    };
    let mut s = Scenario::new(Method::UniformLp, model)
        .with_title("Uniform innovations: swapping-based joint estimation (Pavelková, Figs. 1–3)")
        .with_simulate(SimulateSpec { steps: 120, seed: 1, u: vec![], condition: None, x0: None, true_noise: None })
        .with_alpha(0.9)
        .with_notes(
            "The paper's example is not observable: C·A = 0.5·C, so rank [C; CA] = 1 and only x₁ + x₂ is fixed by the data; \
             along x₁ − x₂ the LP optimum is a whole face bounded by the prior box (±5). The report gives each state's range over the optimal face; \
             the estimate drawn is the optimal vertex the simplex finds (in general one end of the face along x₁ − x₂; an interior-point method would return a point near the face's centre). \
             The polygon is the set of x_t consistent with the window at the half-width bounds x̄_r = ȳ_r = 1 and the Θ in use.",
        );
    s.uniform = Some(UniformSpec {
        d: Some(to_rows(&theta.d)),
        xr: Some(xr.iter().copied().collect()),
        yr: Some(yr.iter().copied().collect()),
        u_half: 0.5,
        estimator: crate::uniform::Joint::Swapping,
        window: 5,
        prior_rel: 0.3,
        prior_overrides: vec![PriorOverride {
            matrix: "A".into(),
            row: 1,
            col: 1,
            lo: -0.3,
            hi: 0.3,
        }],
        xr_max: Some(vec![1.0, 1.0]),
        yr_max: Some(vec![1.0]),
        x_bound: Some(5.0),
        time: None,
        plane: Some([0, 1]),
        directions: 64,
    });
    s
}
