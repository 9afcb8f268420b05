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

use super::{MethodScenario, Report, Scenario, Source};
use crate::error::{Error, Result};
use crate::kalman::KalmanGains;
use crate::linalg;
use crate::model::{Inputs, LinearModel, MatrixSpec, ModelSpec};
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
    /// True half-widths of the innovations (simulation) x_r, y_r (2).
    pub xr: Vec<f64>,
    pub yr: Vec<f64>,
    /// Inputs uniform on [−u_half, u_half] (simulation).
    #[serde(default = "default_u_half")]
    pub u_half: f64,
    /// "states" (Θ known), "parameters" (states known: Θ only, 3.4), "swapping" (4.1) or
    /// "expansion" (4.2).
    #[serde(default = "default_estimator")]
    pub estimator: String,
    /// Window length ∂ (Section 4).
    #[serde(default = "default_window")]
    pub window: usize,
    /// Prior box of Θ: ±prior_rel·|θ| around the true values, then the overrides.
    #[serde(default = "default_rel")]
    pub prior_rel: f64,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub prior_overrides: Vec<PriorOverride>,
    /// Upper bounds x̄_r, ȳ_r of the half-widths (5) (extended automatically when infeasible).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub xr_max: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yr_max: Option<Vec<f64>>,
    /// Bound on every entry of the window's states (±5 in the paper).
    #[serde(default = "default_x_bound")]
    pub x_bound: f64,
    /// The time cursor (default: the last step).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<usize>,
    /// State components of the polygon.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane: Option<[usize; 2]>,
    /// Directions of the consistent-state polygon's support function.
    #[serde(default = "default_directions")]
    pub directions: usize,
}
fn default_u_half() -> f64 {
    0.5
}
fn default_estimator() -> String {
    "swapping".into()
}
fn default_window() -> usize {
    5
}
fn default_rel() -> f64 {
    0.3
}
fn default_x_bound() -> f64 {
    5.0
}
fn default_directions() -> usize {
    64
}

/// The window at the time cursor.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct WindowReport {
    pub time: usize,
    pub first: usize,
    /// MAP objective Σx_r + Σy_r of the state LP with the Θ in use at that time, and the same
    /// sum at the true half-widths (the truth is feasible, so the optimum is never above it).
    pub objective: f64,
    pub true_objective: f64,
    /// Per state x_time … x_{first−1}: the range of each entry over the optimal face.
    pub face_lo: Vec<Vec<f64>>,
    pub face_hi: Vec<Vec<f64>>,
    /// Ranges of x̂_r and ŷ_r over the same face (the objective is unique, the split between
    /// the half-widths need not be).
    pub face_xr: Vec<[f64; 2]>,
    pub face_yr: Vec<[f64; 2]>,
    /// The states consistent with the window's constraints at the half-width bounds x̄_r, ȳ_r
    /// and the Θ in use, in the `plane` components of x_time (counter-clockwise polygon).
    pub polygon: Vec<[f64; 2]>,
    /// Whether the polygon's Θ is the true one (then it must hold the true state).
    pub polygon_theta_true: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth_in_polygon: Option<bool>,
}

/// The report.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct UniformReport {
    pub n: usize,
    pub estimator: String,
    pub window: usize,
    pub plane: [usize; 2],
    pub steps: Vec<OnlineStep>,
    /// x_0 … x_T (simulation), u_1 … u_T, y_1 … y_T (index 0 unused).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_true: Option<Vec<Vec<f64>>>,
    pub y: Vec<Vec<f64>>,
    /// The true Θ and half-widths (simulation), beside the final estimates.
    pub theta_true: [Vec<Vec<f64>>; 4],
    pub xr_true: Vec<f64>,
    pub yr_true: Vec<f64>,
    /// Kalman filter with the uniform variances r²/3 (true Θ): estimates x_1 … x_T.
    pub kf: Vec<Vec<f64>>,
    /// RMS state errors over t = window … T: LP estimator and KF; RMS one-step output
    /// prediction error of the LP estimator.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rms_lp: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rms_kf: Option<f64>,
    pub rms_prediction: f64,
    /// Total doublings of the half-width bounds over the run.
    pub extended: usize,
    pub at: WindowReport,
}

fn matrix(field: &str, rows: &[Vec<f64>]) -> Result<DMatrix<f64>> {
    linalg::from_rows(field, rows)
}

pub(super) fn constant(field: &str, spec: &Option<MatrixSpec>) -> Result<Option<DMatrix<f64>>> {
    match spec {
        None => Ok(None),
        Some(MatrixSpec::Constant(r)) => matrix(field, r).map(Some),
        Some(_) => Err(Error::field(
            field,
            "must be one matrix (time-invariant LU model)",
        )),
    }
}

fn positive(field: &str, v: &[f64], len: usize) -> Result<DVector<f64>> {
    let d = linalg::vector(field, v, len)?;
    if d.iter().any(|x| !(*x > 0.0)) {
        return Err(Error::field(field, "must hold half-widths > 0"));
    }
    Ok(d)
}

impl Scenario {
    /// Validate a uniform-innovation scenario and run it.
    pub fn uniform_report(&self) -> Result<UniformReport> {
        let spec = self
            .block(&self.uniform, "xr, yr, estimator, window, …")?
            .clone();
        let ms: &ModelSpec = &self.model;
        let a = constant("model.F", &ms.f)?.ok_or_else(|| Error::field("model.F", "is missing"))?;
        let n = a.nrows();
        linalg::expect_shape("model.F", &a, n, n)?;
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
        let theta = Theta { a, b, c, d };
        let xr = positive("uniform.xr", &spec.xr, n)?;
        let yr = positive("uniform.yr", &spec.yr, m)?;
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
        if !(spec.x_bound.is_finite() && spec.x_bound > 0.0) {
            return Err(Error::field(
                "uniform.x_bound",
                "must be a finite bound > 0",
            ));
        }
        if !(spec.prior_rel.is_finite() && spec.prior_rel >= 0.0) {
            return Err(Error::field(
                "uniform.prior_rel",
                "must be a finite fraction ≥ 0",
            ));
        }
        if !(8..=720).contains(&spec.directions) {
            return Err(Error::field("uniform.directions", "must lie in 8..=720"));
        }
        let joint = match spec.estimator.as_str() {
            "states" => Joint::States,
            "parameters" => Joint::Parameters,
            "swapping" => Joint::Swapping,
            "expansion" => Joint::Expansion,
            other => {
                return Err(Error::field(
                    "uniform.estimator",
                    format!("must be \"states\", \"parameters\", \"swapping\" or \"expansion\", found \"{other}\""),
                ))
            }
        };
        let plane = match spec.plane {
            Some(p) if p[0] < n && p[1] < n && p[0] != p[1] => p,
            Some(_) => {
                return Err(Error::field(
                    "uniform.plane",
                    format!("must name two distinct state components below n = {n}"),
                ))
            }
            None if n >= 2 => [0, 1],
            None => {
                return Err(Error::field(
                    "model.F",
                    "is 1×1: the consistent-state polygon needs n ≥ 2",
                ))
            }
        };
        let source = self.source(&Uniform)?;
        let Source::Simulate(sim) = source else {
            return Err(Error::field(
                "data",
                "is not supported for uniform_lp yet: use simulate",
            ));
        };
        let x0 = match &ms.x1_mean {
            Some(v) => linalg::vector("model.x1_mean", v, n)?,
            None => DVector::zeros(n),
        };
        let traj = uniform::simulate(&theta, &xr, &yr, &x0, spec.u_half, sim.steps, sim.seed);
        if !traj
            .x
            .iter()
            .all(|x| x.iter().all(|v| v.is_finite() && v.abs() <= spec.x_bound))
        {
            return Err(Error::field("uniform.x_bound", format!("= {} is violated by the simulated states (|x| reaches {:.3}): the prior box must hold the truth", spec.x_bound, traj.x.iter().map(|x| x.amax()).fold(0.0, f64::max))));
        }
        // Θ's prior box: ±rel·|θ|, then the overrides.
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
                        &field,
                        format!(
                            "matrix must be \"A\", \"B\", \"C\" or \"D\", found \"{}\"",
                            o.matrix
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
            x_lo: -spec.x_bound,
            x_hi: spec.x_bound,
            x0: None,
            xr_max: xr_max.clone(),
            yr_max: yr_max.clone(),
        };
        // The joint methods start from the middle of Θ's prior box.
        let theta0 = match joint {
            Joint::States => theta.clone(),
            _ => Theta::from_vec(((&lo + &hi) * 0.5).as_slice(), &theta),
        };
        let mut online = Online::new(joint, spec.window, theta0, theta_prior, state_prior.clone())
            .map_err(|e| Error::field("uniform.window", e.message))?;
        let time = spec.time.unwrap_or(sim.steps);
        if !(1..=sim.steps).contains(&time) {
            return Err(Error::field(
                "uniform.time",
                format!("must lie in 1..={}, found {time}", sim.steps),
            ));
        }
        let mut theta_at = theta.clone();
        for t in 1..=sim.steps {
            if joint == Joint::Parameters {
                online.step_parameters(t, &traj.x, &traj.u, &traj.y)?;
            } else {
                online.step(t, &traj.u, &traj.y)?;
            }
            if t == time {
                theta_at = online.theta.clone();
            }
        }
        // The window at the cursor, with the Θ the estimator used there (after its step).
        let w = Window {
            first: time.saturating_sub(spec.window - 1).max(1),
            last: time,
        };
        let (est, lp) = uniform::estimate_states(&theta_at, &traj.u, &traj.y, w, &state_prior)?;
        let face = uniform::optimal_face(&lp, est.objective, n, w.states())?;
        let nx = w.states() * n;
        let hw_range =
            |k: usize| uniform::face_range(&lp, est.objective, nx + k).map(|(a, b)| [a, b]);
        let face_xr = (0..n).map(&hw_range).collect::<Result<Vec<_>>>()?;
        let face_yr = (n..n + m).map(&hw_range).collect::<Result<Vec<_>>>()?;
        let polygon_theta_true = joint == Joint::States;
        let polygon = uniform::consistent_polygon(
            &theta_at,
            &traj.u,
            &traj.y,
            w,
            &state_prior,
            &xr_max,
            &yr_max,
            plane,
            spec.directions,
        )?;
        let truth_in_polygon = Some(point_in_convex(
            &polygon,
            [traj.x[time][plane[0]], traj.x[time][plane[1]]],
            1e-7,
        ));
        let at = WindowReport {
            time,
            first: w.first,
            objective: est.objective,
            true_objective: xr.sum() + yr.sum(),
            face_lo: face.iter().map(|f| f.0.iter().copied().collect()).collect(),
            face_hi: face.iter().map(|f| f.1.iter().copied().collect()).collect(),
            face_xr,
            face_yr,
            polygon,
            polygon_theta_true,
            truth_in_polygon,
        };
        // KF with the uniform variances r²/3 and the true Θ (x_{t+1} = A x_t + B u_{t+1}).
        let kf = kalman_uniform(&theta, &xr, &yr, &x0, &traj)?;
        let from = spec.window.min(sim.steps);
        let rms = |est: &dyn Fn(usize) -> DVector<f64>| -> f64 {
            let e: f64 = (from..=sim.steps)
                .map(|t| (est(t) - &traj.x[t]).norm_squared())
                .sum();
            (e / (sim.steps + 1 - from) as f64).sqrt()
        };
        let rms_lp = rms(&|t| DVector::from_vec(online.steps[t - 1].x.clone()));
        let rms_kf = rms(&|t| kf[t - 1].clone());
        let pe: f64 = (from..=sim.steps)
            .map(|t| {
                (DVector::from_vec(online.steps[t - 1].y_pred.clone()) - &traj.y[t]).norm_squared()
            })
            .sum();
        let rows = |v: &[DVector<f64>]| {
            v.iter()
                .map(|x| x.iter().copied().collect())
                .collect::<Vec<Vec<f64>>>()
        };
        Ok(UniformReport {
            n,
            estimator: spec.estimator.clone(),
            window: spec.window,
            plane,
            extended: online.steps.iter().map(|s| s.extended).sum(),
            x_true: Some(rows(&traj.x)),
            y: rows(&traj.y),
            theta_true: [
                linalg::to_rows(&theta.a),
                linalg::to_rows(&theta.b),
                linalg::to_rows(&theta.c),
                linalg::to_rows(&theta.d),
            ],
            xr_true: xr.iter().copied().collect(),
            yr_true: yr.iter().copied().collect(),
            kf: rows(&kf),
            rms_lp: Some(rms_lp),
            rms_kf: Some(rms_kf),
            rms_prediction: (pe / (sim.steps + 1 - from) as f64).sqrt(),
            steps: online.steps,
            at,
        })
    }
}

/// Whether p lies in a convex counter-clockwise polygon (within `tol`, relative to its size).
pub fn point_in_convex(poly: &[[f64; 2]], p: [f64; 2], tol: f64) -> bool {
    let scale = poly
        .iter()
        .map(|q| q[0].abs().max(q[1].abs()))
        .fold(1.0, f64::max);
    (0..poly.len()).all(|i| {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let cross = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        cross >= -tol * scale * scale
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
        f: Some(MatrixSpec::Constant(linalg::to_rows(&theta.a))),
        h: Some(MatrixSpec::Constant(linalg::to_rows(&theta.c))),
        v: Some(MatrixSpec::Constant(linalg::to_rows(&q))),
        w: Some(MatrixSpec::Constant(linalg::to_rows(&rr))),
        b: (theta.r() > 0).then(|| MatrixSpec::Constant(linalg::to_rows(&theta.b))),
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
    fn steps(&self) -> RangeInclusive<usize> {
        2..=2000
    }
    fn run(&self, s: &Scenario) -> Result<Report> {
        let u = s.uniform_report()?;
        let q = u.y.first().map_or(0, |y| y.len());
        let mut r = Report::of(
            s,
            s.alpha,
            (u.n, q),
            u.at.time,
            u.plane.to_vec(),
            u.y.clone(),
        );
        r.uniform = Some(u);
        Ok(r)
    }
    fn study(&self, _: &Scenario, _: Option<usize>) -> Result<Box<dyn Study>> {
        Err(Error::field(
            "method",
            "\"uniform_lp\" has no Monte Carlo study: its LP gives MAP estimates and a consistent set, with no probability to count",
        ))
    }
}
