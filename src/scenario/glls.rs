//! The `glls` block of a scenario and the GLLS part of a report (method `"glls"`).
//!
//! ```json
//! {"method": "glls",
//!  "model": {"F": [[0.6,0,0],[0,0.94,-0.34],[0,0.34,0.94]], "H": [[1,1,0]], "W": [[0.01]]},
//!  "simulate": {"steps": 40, "seed": 1},
//!  "glls": {"horizon": 6, "max_horizon": 60, "estimator": "lls", "p": 2, "mu": 0.1,
//!           "noise": "bounded", "plane": [0, 1],
//!           "monte_carlo": {"runs": 2000, "seed": 3, "study": "precision"}}}
//! ```
//!
//! Times are the paper's: x(0) = `model.x1_mean`, data y(0) … y(k) with k = steps − 1; the
//! horizon s uses y(k−s) … y(k). `model.W` is Ω (default I), `model.V` the covariance of the
//! transition noise ξ of (54) (default 0), `model.B` with `simulate.u` / `data.u` the inputs.
//!
//! The file ends with the method's presets (`// Presets`: the menu entries and their
//! builders), re-exported by [`crate::presets`].

use super::budget::{f, shape, Job, Term, Work};
use super::compare::{Assumption, CompareMember, ComparePrepared, PlaneReading, PlaneSet};
use super::csv::{cells, Table};
use super::preset::Preset;
use super::{
    first_accepted_in, FirstAccepted, MethodScenario, Report, Scenario, SimulateSpec, Source,
};
use crate::error::{Error, Result};
use crate::glls::{
    self, Curves, GllsModel, Horizon, Precision, PrecisionReport, StateNoise, Study, Weighting,
};
use crate::linalg;
use crate::method::Method;
use crate::model::{normal_vector, MatrixSpec, ModelSpec};
use crate::sets::{box_corners, convex_hull, map_ellipse, map_point, BoxSet, Ellipsoid};
use crate::study::Chunked;
use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::ops::RangeInclusive;

/// Monte Carlo of Section 5.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GllsMonteCarloSpec {
    pub runs: usize,
    #[serde(default)]
    pub seed: u64,
    /// "precision" (5.1: error vs horizon with the bound) or "state_noise" (5.2: vs LLS).
    #[serde(default)]
    pub study: GllsStudyKind,
    /// Steps per run (default: the simulation's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps: Option<usize>,
    /// Largest horizon (default: min(max_horizon, steps − 1, 30)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_horizon: Option<usize>,
}

/// Which Monte Carlo of Section 5 (`glls.monte_carlo.study`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GllsStudyKind {
    /// 5.1: the error of the current-state estimate against the horizon, with the bound.
    #[default]
    Precision,
    /// 5.2: the state-noise estimator against LLS.
    StateNoise,
}

/// The estimator (`glls.estimator`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GllsEstimator {
    /// Least squares with Ω = I.
    #[default]
    Lls,
    /// Generalized least squares with the model's Ω.
    Glls,
    /// The state-noise estimator (60)–(64) beside LLS.
    StateNoise,
}

/// The simulated measurement noise (`glls.noise`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GllsNoise {
    /// N(0, Ω).
    #[default]
    Gaussian,
    /// Uniform in the ball ‖δ(k)‖₂ ≤ μ.
    Bounded,
    /// ‖δ(k)‖₂ = μ, aligned to push the first plotted component as far as the bound allows.
    Worst,
}

/// The `glls` block.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GllsSpec {
    /// The horizon s (default: the best horizon of σ_n/√s, Fig. 2, within the data).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub horizon: Option<usize>,
    /// S of the curves s = 0..S (default 60).
    #[serde(default = "default_max_horizon")]
    pub max_horizon: usize,
    /// "lls" (Ω = I), "glls" (the model's Ω) or "state_noise" ((60)–(64)).
    #[serde(default)]
    pub estimator: GllsEstimator,
    /// Singular values kept by the regularized estimators (default n: none dropped).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p: Option<usize>,
    /// Bound μ on ‖δ(k)‖₂ for the guaranteed ball and box (default 3·√tr Ω).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mu: Option<f64>,
    /// Simulated measurement noise: "gaussian" (N(0, Ω)), "bounded" (uniform in the ball
    /// ‖δ(k)‖₂ ≤ μ) or "worst" (‖δ(k)‖₂ = μ aligned to push the first plotted component of the
    /// current estimate as far as the bound allows).
    #[serde(default)]
    pub noise: GllsNoise,
    /// Two state components for the state plane (default [0, 1], or [0, 0] when n = 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane: Option<[usize; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub monte_carlo: Option<GllsMonteCarloSpec>,
}
fn default_max_horizon() -> usize {
    60
}

/// The regularized estimators at the chosen horizon.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct RegularizedReport {
    pub p: usize,
    pub estimate_past: Vec<f64>,
    /// (31): R diag(1_p, 0) Rᵀ — what x_reg(k−s) estimates.
    pub projection_past: Vec<Vec<f64>>,
    /// κ_reg.GLLS(s, k−s) (32) and 1/σ_p (38).
    pub kappa_past: f64,
    pub kappa_lls_past: f64,
    /// (47), (49): with A invertible.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub estimate_current: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub projection_current: Option<Vec<Vec<f64>>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kappa_current: Option<f64>,
    /// (36) and (40): the guaranteed radius √(s+1)·μ·κ_reg and the expected bound
    /// κ_reg·√((s+1) tr Ω) of x_reg − x_pr, for the past state and (A invertible) the current one.
    pub radius_past: f64,
    pub expected_bound_past: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius_current: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub expected_bound_current: Option<f64>,
    /// Projection of the true states (simulation).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth_projected_past: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth_projected_current: Option<Vec<f64>>,
}

/// The state-noise estimator at the chosen horizon.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct StateNoiseReport {
    pub estimate_past: Vec<f64>,
    pub estimate_current: Vec<f64>,
    /// ξ(k−s) … ξ(k−1).
    pub xi: Vec<Vec<f64>>,
    /// max |closed form − clarabel QP| over x(k−s) and ξ.
    pub qp_difference: f64,
}

/// The GLLS part of a report.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct GllsReport {
    pub n: usize,
    pub m: usize,
    /// Time of the current state (k = steps − 1) and the horizon s.
    pub k: usize,
    pub s: usize,
    pub estimator: GllsEstimator,
    pub plane: [usize; 2],
    /// Figs. 1–2 for s = 0..S.
    pub curves: Curves,
    /// log10 σ_n/√s and its best horizon; log10 σ_p/√s and its best (p < n).
    pub index: Vec<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub best_horizon: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub index_p: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub best_horizon_p: Option<usize>,
    /// max over s of |log10 σ_i(Γ_{s+1}) − log10 σ_i(Γ_{s+1}A^{−s})| (the paper's empirical
    /// remark says 0; it is 0 only for orthogonal A).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prime_gap_log10: Option<f64>,
    /// At the chosen s.
    pub sigma: Vec<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma_prime: Option<Vec<f64>>,
    /// Why σ(Γ_{s+1}A^{−s}), 1/σ'_n (45) and the regularized current-state estimator (47) are
    /// missing: A is singular.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prime_note: Option<String>,
    /// The spectrum of A: its singular values (decreasing) and eigenvalues as (re, im), largest
    /// modulus first (GLLS Section 5.2 prints both for its 5-state system).
    pub a_singular_values: Vec<f64>,
    pub a_eigenvalues: Vec<[f64; 2]>,
    pub kappa_past: f64,
    pub kappa_lls_past: f64,
    pub kappa_current: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kappa_lls_current: Option<f64>,
    /// The (G)LLS estimates (11), (41) — or the state-noise estimator's when chosen.
    pub estimate_past: Vec<f64>,
    pub estimate_current: Vec<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_true_past: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_true_current: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error_current: Option<f64>,
    /// Guaranteed sets for x(k) under ‖δ(j)‖₂ ≤ μ: the ball (35) with √(s+1) as an ellipsoid
    /// (cov = r²I, radius2 = 1) and the exact interval hull of the error set.
    pub mu: f64,
    pub ball_current: Ellipsoid,
    pub box_current: BoxSet,
    pub ball_past: Ellipsoid,
    pub box_past: BoxSet,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth_in_ball: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth_in_box: Option<bool>,
    /// max_j ‖δ(j)‖₂ of the simulated noise in the window (the guarantee needs ≤ μ).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise_max: Option<f64>,
    /// (39): κ·√((s+1) tr Ω).
    pub expected_bound: f64,
    /// Estimated floating-point error of the current estimate, and whether it rivals the bound.
    pub rounding_estimate: f64,
    pub rounding_dominates: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub regularized: Option<RegularizedReport>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub state_noise: Option<StateNoiseReport>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub precision: Option<PrecisionReport>,
    /// The true trajectory (simulation) and the data.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_true: Option<Vec<Vec<f64>>>,
    pub y: Vec<Vec<f64>>,
}

/// A validated GLLS scenario.
pub struct GllsPrepared {
    pub spec: GllsSpec,
    pub model: GllsModel,
    pub y: Vec<DVector<f64>>,
    pub u: Vec<DVector<f64>>,
    pub x_true: Option<Vec<DVector<f64>>>,
    pub weighting: Weighting,
    pub mu: f64,
    pub plane: [usize; 2],
    pub noise_max: Option<f64>,
}

fn rows_of(v: &[DVector<f64>]) -> Vec<Vec<f64>> {
    v.iter().map(|x| x.iter().copied().collect()).collect()
}

fn vec_of(v: &DVector<f64>) -> Vec<f64> {
    v.iter().copied().collect()
}

/// Stack y(k−s) … y(k) (and the inputs).
fn window(v: &[DVector<f64>], k: usize, s: usize) -> DVector<f64> {
    DVector::from_iterator(
        v.iter().skip(k - s).take(s + 1).map(|x| x.len()).sum(),
        v[k - s..=k].iter().flat_map(|x| x.iter().copied()),
    )
}

/// What the report must say when the scenario's model is not the one a result assumes:
/// * the guaranteed ball and box (35) bound the error of the LLS/GLLS estimate through
///   ‖δ(k, s)‖₂ ≤ √(s+1)·μ for the model (7)–(8), x(k+1) = A·x(k) + B·u(k) with no state
///   noise; with model.V ≠ 0 (ξ of (54)) the measurements also carry Ψ·ξ (59), which μ does not
///   bound, so the sets are drawn but guarantee nothing;
/// * the state-noise estimator (60)–(64) fits the measurements exactly ((61), (64): y = C·x,
///   (55)), so it has no place for measurement noise: a non-zero model.W = Ω (the identity when
///   absent) is ignored, and that noise is read as state noise.
fn assumption_warnings(model: &GllsModel, estimator: GllsEstimator, w_given: bool) -> Vec<String> {
    let mut out = Vec::new();
    let nonzero = |m: &DMatrix<f64>| m.iter().any(|&v| v != 0.0);
    if nonzero(&model.xi) {
        out.push(format!(
            "model.V is not zero (state noise ξ of (54), largest variance {:.3e}): the guaranteed ball and box of x(k) (35) assume x(k+1) = A·x(k) + B·u(k) with no state noise, so here they guarantee nothing; the state noise reaches the measurements through Ψ (59), which the bound μ does not cover",
            model.xi.diagonal().max()
        ));
    }
    if estimator == GllsEstimator::StateNoise && nonzero(&model.omega) {
        out.push(format!(
            "the state-noise estimator (60)–(64) takes the measurements as exact (y = C·x, (55)) and ignores model.W{} (measurement noise of largest variance {:.3e}): that noise is read as state noise; give model.W = 0 if the measurements are exact, or use \"lls\" or \"glls\"",
            if w_given { "" } else { " (the identity when absent)" },
            model.omega.diagonal().max()
        ));
    }
    out
}

impl Scenario {
    /// Validate a GLLS scenario and produce its data.
    pub fn prepare_glls(&self) -> Result<GllsPrepared> {
        let spec = self.block(&self.glls, "horizon, estimator, …")?.clone();
        let model = GllsModel::from_spec(&self.model)?;
        let (n, m, r) = (model.n(), model.m(), model.r());
        let weighting = match spec.estimator {
            GllsEstimator::Lls | GllsEstimator::StateNoise => Weighting::Lls,
            GllsEstimator::Glls => Weighting::Glls,
        };
        if !(1..=2000).contains(&spec.max_horizon) {
            return Err(Error::field(
                "glls.max_horizon",
                format!(
                    "must be a whole number from 1 to 2000, found {}",
                    spec.max_horizon
                ),
            ));
        }
        let default_mu = 3.0 * model.omega.trace().max(0.0).sqrt();
        let mu = spec.mu.unwrap_or(default_mu);
        if !(mu.is_finite() && mu >= 0.0) {
            return Err(Error::field(
                "glls.mu",
                format!(
                    "must be a finite bound ≥ 0, found {}",
                    crate::error::shown(mu)
                ),
            ));
        }
        let plane = match spec.plane {
            Some(p) if p[0] < n && p[1] < n && (p[0] != p[1] || n == 1) => p,
            Some(_) => {
                return Err(Error::field(
                    "glls.plane",
                    format!("must name two distinct state components below n = {n}"),
                ))
            }
            None => [0, 1.min(n - 1)],
        };
        let source = self.source(&Glls)?;
        let u = source.inputs(r)?.unwrap_or_default();
        let (y, x_true, noise_max) = match source {
            Source::Data(_) => (source.measurements(m)?, None, None),
            Source::Simulate(sim) => {
                let (x, y, dmax) = simulate(&model, sim, &u, &spec, mu, weighting)?;
                (y, Some(x), dmax)
            }
        };
        Ok(GllsPrepared {
            spec,
            model,
            y,
            u,
            x_true,
            weighting,
            mu,
            plane,
            noise_max,
        })
    }
}

/// The data of a simulation: x(0..k), y(0..k) and the largest ‖δ(j)‖₂ drawn.
fn simulate(
    model: &GllsModel,
    sim: &SimulateSpec,
    u: &[DVector<f64>],
    spec: &GllsSpec,
    mu: f64,
    weighting: Weighting,
) -> Result<(Vec<DVector<f64>>, Vec<DVector<f64>>, Option<f64>)> {
    let steps = sim.steps;
    if !(1..=5000).contains(&steps) {
        return Err(Error::field(
            "simulate.steps",
            format!("must be a whole number from 1 to 5000, found {steps}"),
        ));
    }
    if sim.condition.is_some() {
        return Err(Error::field(
            "simulate.condition",
            "is not used by GLLS (x(0) is model.x1_mean)",
        ));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(sim.seed);
    let (xs, mut ys) = match spec.noise {
        GllsNoise::Gaussian => model.simulate(steps, u, &mut rng),
        GllsNoise::Bounded | GllsNoise::Worst => {
            let quiet = GllsModel {
                omega: DMatrix::zeros(model.m(), model.m()),
                ..model.clone()
            };
            quiet.simulate(steps, u, &mut rng)
        }
    };
    if !xs
        .iter()
        .chain(&ys)
        .all(|v| v.iter().all(|x| x.is_finite()))
    {
        return Err(Error::field("simulate.steps", "the simulated states overflow double precision (A is unstable): shorten the simulation"));
    }
    let m = model.m();
    let dmax = match spec.noise {
        GllsNoise::Bounded => {
            // Uniform in the ball of radius μ: direction uniform, radius μ·U^{1/m}.
            let mut big: f64 = 0.0;
            for y in ys.iter_mut() {
                let d = normal_vector(m, &mut rng);
                let rad = mu * rng.random::<f64>().powf(1.0 / m as f64);
                let delta = if d.norm() > 0.0 {
                    d.normalize() * rad
                } else {
                    DVector::zeros(m)
                };
                big = big.max(delta.norm());
                *y += delta;
            }
            Some(big)
        }
        GllsNoise::Worst => {
            // δ(j) = μ·g_j/‖g_j‖ with g_j the block of row `plane[0]` of the current-state gain:
            // the error of that component reaches its interval bound exactly.
            let k = steps - 1;
            // The horizon the report will use (the best one of Fig. 2 when none is given).
            let s = match spec.horizon {
                Some(s) => s,
                None => {
                    let curves = Curves::new(model, spec.max_horizon)?;
                    let n = model.n();
                    glls::horizon_index(&curves.log10_sigma, n)
                        .1
                        .unwrap_or(n.saturating_sub(1))
                        .max(n.saturating_sub(1))
                }
            }
            .min(k);
            let h = Horizon::new(model, s, weighting)?;
            let row = spec.plane.map(|p| p[0]).unwrap_or(0).min(model.n() - 1);
            for j in 0..=s {
                let g = h.gain_current.view((row, j * m), (1, m)).transpose();
                if g.norm() > 0.0 {
                    ys[k - s + j] += g.normalize() * mu;
                }
            }
            Some(mu)
        }
        GllsNoise::Gaussian => None,
    };
    Ok((xs, ys, dmax))
}

impl GllsPrepared {
    pub fn report(&self) -> Result<GllsReport> {
        let model = &self.model;
        let n = model.n();
        let k = self.y.len() - 1;
        let spec = &self.spec;
        let curves = Curves::new(model, spec.max_horizon)?;
        let (index, best_horizon) = glls::horizon_index(&curves.log10_sigma, n);
        let p = spec.p.unwrap_or(n);
        if p < 1 || p > n {
            return Err(Error::field(
                "glls.p",
                format!("must be a whole number from 1 to {n} (singular values kept), found {p}"),
            ));
        }
        let (index_p, best_horizon_p) = if p < n {
            let (i, b) = glls::horizon_index(&curves.log10_sigma, p);
            (Some(i), b)
        } else {
            (None, None)
        };
        let prime_gap_log10 = curves.log10_sigma_prime.as_ref().map(|sp| {
            curves
                .log10_sigma
                .iter()
                .zip(sp)
                .skip(n.saturating_sub(1))
                // Only singular values resolved in both (log10 −400 marks an exact zero).
                .flat_map(|(a, b)| {
                    a.iter()
                        .zip(b)
                        .filter(|(x, y)| **x > -300.0 && **y > -300.0)
                        .map(|(x, y)| (x - y).abs())
                })
                .filter(|v| v.is_finite())
                .fold(0.0, f64::max)
        });
        let s = match spec.horizon {
            Some(s) => s,
            None => best_horizon
                .unwrap_or(n.saturating_sub(1))
                .max(n.saturating_sub(1)),
        }
        .min(k);
        if let Some(h) = spec.horizon {
            if h > k {
                return Err(Error::field(
                    "glls.horizon",
                    format!(
                        "= {h} needs {} measurements; the data hold {}",
                        h + 1,
                        k + 1
                    ),
                ));
            }
        }
        let h = Horizon::new(model, s, self.weighting)?;
        let y = window(&self.y, k, s);
        let u = if model.r() > 0 {
            DVector::from_iterator(
                model.r() * (s + 1),
                (k - s..=k).flat_map(|j| {
                    glls::input(&self.u, j, model.r())
                        .iter()
                        .copied()
                        .collect::<Vec<_>>()
                }),
            )
        } else {
            DVector::zeros(0)
        };
        let (lls_past, lls_cur) = h.estimate(&y, &u);
        let state_noise = if spec.estimator == GllsEstimator::StateNoise {
            let sn = StateNoise::new(model, s)?;
            let (xp, xi, xc) = sn.estimate(&y, &u);
            let (qx, qxi) = sn.estimate_qp(model, &y, &u)?;
            let diff = (&qx - &xp).amax().max(if xi.is_empty() {
                0.0
            } else {
                (&qxi - &xi).amax()
            });
            Some(StateNoiseReport {
                estimate_past: vec_of(&xp),
                estimate_current: vec_of(&xc),
                xi: (0..s)
                    .map(|i| xi.rows(i * n, n).iter().copied().collect())
                    .collect(),
                qp_difference: diff,
            })
        } else {
            None
        };
        let (est_past, est_cur) = match &state_noise {
            Some(sn) => (
                DVector::from_vec(sn.estimate_past.clone()),
                DVector::from_vec(sn.estimate_current.clone()),
            ),
            None => (lls_past.clone(), lls_cur.clone()),
        };
        let truth = self
            .x_true
            .as_ref()
            .map(|x| (x[k - s].clone(), x[k].clone()));
        let bounds = h.bounds(self.mu);
        let ball = |c: &DVector<f64>, r: f64| {
            Ellipsoid::new(c, &(DMatrix::identity(n, n) * (r * r).max(1e-300)), 1.0)
        };
        let boxed = |c: &DVector<f64>, hw: &[f64]| BoxSet {
            lo: c.iter().zip(hw).map(|(c, w)| c - w).collect(),
            hi: c.iter().zip(hw).map(|(c, w)| c + w).collect(),
        };
        let ball_current = ball(&lls_cur, bounds.radius_current);
        let box_current = boxed(&lls_cur, &bounds.half_widths_current);
        // Guaranteed sets hold up to rounding: the worst-case noise reaches the box exactly.
        let slack = |r: f64| r * 1e-9 + h.rounding_estimate(&lls_past, &y) * 10.0;
        let truth_in_ball = truth.as_ref().map(|(_, xc)| {
            (xc - &lls_cur).norm() <= bounds.radius_current + slack(bounds.radius_current)
        });
        let truth_in_box = truth.as_ref().map(|(_, xc)| {
            (0..n).all(|i| {
                (xc[i] - lls_cur[i]).abs()
                    <= bounds.half_widths_current[i] + slack(bounds.half_widths_current[i])
            })
        });
        let regularized = if p < n {
            let reg = h.regularized(p)?;
            // √(s+1)·μ and √E‖δ(k,s)‖² = √((s+1) tr Ω).
            let worst = ((s + 1) as f64).sqrt() * self.mu;
            let spread = (((s + 1) as f64) * model.omega.trace()).max(0.0).sqrt();
            let rd = h.residual_data(&y, &u);
            let cur = reg.current.as_ref();
            Some(RegularizedReport {
                p,
                estimate_past: vec_of(&(&reg.gain_past * &rd)),
                projection_past: linalg::to_rows(&reg.projection_past),
                kappa_past: reg.kappa_past,
                kappa_lls_past: 1.0 / h.sigma[p - 1],
                estimate_current: reg.estimate_current(&h, &y, &u).map(|v| vec_of(&v)),
                projection_current: cur.map(|c| linalg::to_rows(&c.1)),
                kappa_current: cur.map(|c| c.2),
                radius_past: worst * reg.kappa_past,
                expected_bound_past: spread * reg.kappa_past,
                radius_current: cur.map(|c| worst * c.2),
                expected_bound_current: cur.map(|c| spread * c.2),
                truth_projected_past: truth
                    .as_ref()
                    .map(|(xp, _)| vec_of(&(&reg.projection_past * xp))),
                truth_projected_current: match (cur, &truth) {
                    (Some(c), Some((_, xc))) => Some(vec_of(&(&c.1 * xc))),
                    _ => None,
                },
            })
        } else {
            None
        };
        let rounding = h.rounding_estimate(&lls_past, &y);
        let precision = match &spec.monte_carlo {
            Some(mc) => {
                let mut runs = Chunked::new(self.precision(mc)?);
                crate::study::run_to_end(&mut runs, 1000, |_, _| {})?;
                Some(runs.report())
            }
            None => None,
        };
        Ok(GllsReport {
            n,
            m: model.m(),
            k,
            s,
            estimator: spec.estimator,
            plane: self.plane,
            index,
            best_horizon,
            index_p,
            best_horizon_p,
            prime_gap_log10,
            sigma: h.sigma.clone(),
            sigma_prime: h.sigma_prime.clone(),
            prime_note: h.sigma_prime.is_none().then(|| {
                format!(
                    "A is singular (reciprocal condition {:.1e}): Γ_{{s+1}}A^{{−s}} of (44) does not exist, so σ' and the regularized current-state estimator (47) are not available; κ(s,k) is computed as ‖A^s ∂f‖ (43) instead",
                    linalg::rcond(&model.a)
                )
            }),
            a_singular_values: {
                let mut sv: Vec<f64> = linalg::try_svd(model.a.clone(), false, false)
                    .map(|d| d.singular_values.iter().copied().collect())
                    .ok_or_else(|| Error::field("model.F", "its singular values do not converge"))?;
                sv.sort_by(|a, b| b.total_cmp(a));
                sv
            },
            a_eigenvalues: linalg::try_eigenvalues(&model.a)
                .ok_or_else(|| Error::field("model.F", "its eigenvalues do not converge"))?,
            kappa_past: h.kappa_past,
            kappa_lls_past: h.kappa_lls_past,
            kappa_current: h.kappa_current,
            kappa_lls_current: h.kappa_lls_current,
            estimate_past: vec_of(&est_past),
            estimate_current: vec_of(&est_cur),
            x_true_past: truth.as_ref().map(|t| vec_of(&t.0)),
            x_true_current: truth.as_ref().map(|t| vec_of(&t.1)),
            error_current: truth.as_ref().map(|t| (&est_cur - &t.1).norm()),
            mu: self.mu,
            ball_past: ball(&lls_past, bounds.radius_past),
            box_past: boxed(&lls_past, &bounds.half_widths_past),
            ball_current,
            box_current,
            truth_in_ball,
            truth_in_box,
            noise_max: self.noise_max,
            expected_bound: h.expected_bound(&model.omega),
            rounding_estimate: rounding,
            rounding_dominates: {
                let bound = bounds.radius_current.max(h.expected_bound(&model.omega));
                bound > 0.0 && rounding > 0.1 * bound
            },
            regularized,
            state_noise,
            precision,
            curves,
            x_true: self.x_true.as_ref().map(|x| rows_of(x)),
            y: rows_of(&self.y),
        })
    }

    /// The Monte Carlo of the `monte_carlo` block, not yet run (the page steps it in chunks).
    pub fn precision(&self, mc: &GllsMonteCarloSpec) -> Result<Precision> {
        let study = match mc.study {
            GllsStudyKind::Precision => Study::Precision,
            GllsStudyKind::StateNoise => Study::StateNoiseVsLls,
        };
        let steps = mc.steps.unwrap_or(self.y.len());
        if !(2..=5000).contains(&steps) {
            return Err(Error::field(
                "glls.monte_carlo.steps",
                format!("must be a whole number from 2 to 5000, found {steps}"),
            ));
        }
        let s_max = mc
            .max_horizon
            .unwrap_or(self.spec.max_horizon.min(steps - 1).min(30));
        let s_min = if study == Study::StateNoiseVsLls {
            1
        } else {
            0
        };
        Precision::new(
            &self.model,
            study,
            self.weighting,
            steps,
            (s_min, s_max),
            self.u.clone(),
            mc.runs,
            mc.seed,
        )
    }
}

/// The study of a scenario without a glls.monte_carlo block given only its runs (the CLI's
/// `--runs`): seed 0 and the study of the estimator, Section 5.2's (state noise against LLS)
/// for "state_noise", else Section 5.1's precision against the horizon.
fn default_monte_carlo(estimator: GllsEstimator, runs: usize) -> GllsMonteCarloSpec {
    GllsMonteCarloSpec {
        runs,
        seed: 0,
        study: match estimator {
            GllsEstimator::StateNoise => GllsStudyKind::StateNoise,
            _ => GllsStudyKind::Precision,
        },
        steps: None,
        max_horizon: None,
    }
}

/// GLLS (Gubarev & Mishchenko): the `glls` block, curves, estimates, guaranteed sets and the
/// Section 5 Monte Carlo.
pub(crate) struct Glls;

impl MethodScenario for Glls {
    fn true_noise(&self) -> Option<&'static str> {
        Some(
            "GLLS draws its simulated measurement noise by glls.noise (gaussian, bounded or worst) within its own bound",
        )
    }
    fn gaps(&self) -> super::Gaps {
        super::Gaps::Refused("its horizon stacks s + 1 consecutive measurements into the observability matrix Γ_{s+1} (6): the guaranteed ball (35) and κ (17) are computed for that operator, which a missing row changes")
    }
    fn time_index(&self) -> super::TimeIndex {
        super::TimeIndex::NotTime
    }
    fn max_states(&self) -> usize {
        crate::glls::MAX_STATES
    }
    fn truth_keys(&self) -> &'static [(&'static str, &'static str)] {
        &[
            (
                "truth_in_ball",
                "glls: whether the guaranteed ball holds the truth",
            ),
            ("truth_in_box", "glls: the same for the box"),
            ("x_true_current", "glls: the true current state"),
            ("x_true_past", "glls: the true past state"),
            (
                "truth_projected_current",
                "glls: the truth's regularized projection",
            ),
            ("truth_projected_past", "glls: the same, past state"),
            (
                "error_current",
                "glls: the estimate's distance to the truth",
            ),
            ("noise_max", "glls: the largest simulated noise"),
        ]
    }
    fn steps(&self) -> RangeInclusive<usize> {
        1..=5000
    }
    fn first_accepted(&self, s: &Scenario) -> Result<Option<FirstAccepted>> {
        // The horizon s the view animates (the x axis of Figs. 1–3), from the first at which
        // x(k − s) is observable, Γ_{s+1} of rank n (Horizon::new, as the run asks it), up to
        // the scenario's (all the data, k, when it names none).
        let p = s.prepare_glls()?;
        let k = p.y.len() - 1;
        let current = p.spec.horizon.unwrap_or(k);
        let value = first_accepted_in(0..=current, |h| {
            let mut at = s.clone();
            if let Some(g) = at.glls.as_mut() {
                g.horizon = Some(h);
            }
            let p = at.prepare_glls()?;
            if h > k {
                return Err(Error::field("glls.horizon", "exceeds the data"));
            }
            Horizon::new(&p.model, h, p.weighting).map(|_| ())
        })?;
        Ok(Some(FirstAccepted {
            field: "glls.horizon".into(),
            value,
        }))
    }
    fn data_shape(&self, s: &Scenario) -> Result<(usize, usize)> {
        // m = rows of C (model.H), r = columns of B, as `prepare_glls` reads the data.
        GllsModel::from_spec(&s.model).map(|m| (m.m(), m.r()))
    }
    fn work(&self, s: &Scenario, job: Job) -> Work {
        work(s, job)
    }
    fn table(&self, r: &Report) -> Table {
        // One row per horizon s = 0..S: the curves of Figs. 1–2 (log10) and the index.
        let Some(g) = &r.glls else {
            return Table::new(vec!["s".into()]);
        };
        let c = &g.curves;
        let mut columns = vec!["s".to_string()];
        columns.extend(Table::numbered("log10_sigma", g.n));
        columns.extend(
            [
                "log10_floor",
                "log10_kappa_lls_current",
                "log10_kappa_glls_past",
                "log10_kappa_glls_current",
                "index",
            ]
            .map(String::from),
        );
        let mut table = Table::new(columns);
        for (s, sigma) in c.log10_sigma.iter().enumerate() {
            let at = |v: &[f64]| v.get(s).copied();
            let mut row = vec![Some(s as f64)];
            row.extend(cells(Some(sigma), g.n));
            row.extend([
                at(&c.log10_floor),
                at(&c.log10_kappa_lls_current),
                at(&c.log10_kappa_glls_past),
                at(&c.log10_kappa_glls_current),
                at(&g.index),
            ]);
            table.push(row);
        }
        table
    }
    fn run(&self, s: &Scenario) -> Result<Report> {
        let p = s.prepare_glls()?;
        let g = p.report()?;
        let mut r = Report::of(s, s.alpha, (g.n, g.m), g.k, g.plane.to_vec(), g.y.clone());
        r.warnings.extend(assumption_warnings(
            &p.model,
            p.spec.estimator,
            s.model.w.is_some(),
        ));
        r.glls = Some(g);
        Ok(r)
    }
    fn study(&self, s: &Scenario, runs: Option<usize>) -> Result<Box<dyn crate::study::Study>> {
        let p = s.prepare_glls()?;
        // Without a glls.monte_carlo block, runs given stand for the block ([`default_monte_carlo`]).
        let mut mc = match (p.spec.monte_carlo.clone(), runs) {
            (Some(mc), _) => mc,
            (None, Some(runs)) => default_monte_carlo(p.spec.estimator, runs),
            (None, None) => {
                return Err(Error::field(
                    "glls.monte_carlo",
                    "is missing: the study needs glls.monte_carlo (runs, seed, study), or a number of runs (the command line's --runs), which takes seed 0 and the estimator's study",
                ))
            }
        };
        if let Some(r) = runs {
            mc.runs = r;
        }
        Ok(Box::new(Chunked::new(p.precision(&mc)?)))
    }
    fn compare_member(&self) -> Option<&dyn CompareMember> {
        Some(self)
    }
    fn presets(&self) -> Vec<Preset> {
        presets()
    }
    /// The Section 5 study's result is the report's `glls.precision` (the "precision" panel
    /// draws it), as a run with `glls.monte_carlo` holds it.
    fn set_study(&self, report: &mut Report, result: serde_json::Value) -> Result<()> {
        let precision: Option<PrecisionReport> =
            crate::scenario::parse::from_value(&result, "glls.precision")?;
        let g = report.glls.as_mut().ok_or_else(|| {
            Error::field("report.glls", "is missing: the report is not a GLLS report")
        })?;
        g.precision = precision;
        Ok(())
    }
}

/// Operations per horizon step and unit of n²(n + m): the curves' QR updates and small SVDs,
/// the powers of A, the SVD of Γ_{s+1} (S = 2000, n = 20: about 0.15 s natively).
const OPS_CUBE: f64 = 10.0;
/// Operations per entry of Φ_{s+1} (m(s + 1) × r(s + 1)), filled block by block (about 10 ns).
const OPS_ENTRY: f64 = 10.0;
/// Operations per unit of (m(s + 1) + n·s)³: the state-noise estimator's square QR, products
/// and pseudo-inverse, and its QP check (s = 400, n = 5: about 2 s natively).
const OPS_STATE_NOISE: f64 = 0.35;
/// Operations per simulated step of a Monte Carlo run, per unit of n(n + m + r) and besides
/// (a step of a 2-state model: about 0.25 µs natively).
const OPS_SIM: f64 = 3.0;
const OPS_SIM_STEP: f64 = 300.0;
/// Operations per step of a run's window at horizon s: stacking y and u (one small allocation
/// per step), and per unit of n·m the estimate (Σ_s (s + 1) steps per run: about 41 µs for
/// horizons 0..30 of a 2-state model natively).
const OPS_STACK: f64 = 60.0;
const OPS_ESTIMATE: f64 = 15.0;
/// Bytes per reported number (the value, its JSON tree).
const BYTES_NUMBER: f64 = 60.0;

/// The GLLS costs: the curves s = 0..S and the chosen horizon s, each O(s · n²(n + m)), with
/// Φ_{s+1} of m·r·s² entries; the state-noise estimator O((m(s + 1) + n·s)³); a Monte Carlo
/// (in the report, or a study's preparation and one run): its horizons 0..S_mc, and per run
/// the simulation (steps · n(n + m + r)) and one estimate per horizon (n·m·s), keeping one
/// error per run and horizon.
fn work(s: &Scenario, job: Job) -> Work {
    let n = shape(&s.model.f).0.max(1);
    let m = shape(&s.model.h).0.max(1);
    let r = shape(&s.model.b).1;
    let steps = s.written_steps();
    let steps_field = s.steps_field();
    let mut w = Work::default();
    let Some(spec) = s.glls.as_ref().filter(|_| n <= glls::MAX_STATES) else {
        return w;
    };
    let cube = f(n * n) * f(n + m);
    // The horizon: given, or the best of the curves (at most S), within the data.
    let horizon = spec
        .horizon
        .unwrap_or(spec.max_horizon.max(n.saturating_sub(1)))
        .min(steps.saturating_sub(1));
    let horizon_field = if spec.horizon.is_some() {
        "glls.horizon"
    } else {
        "glls.max_horizon"
    };
    // Φ_{s+1}, Γ_{s+1} and the SVD of one horizon s; the state-noise estimator's matrices.
    let one_horizon = |s: f64| OPS_CUBE * s * cube + OPS_ENTRY * f(m * r) * s * s;
    let state_noise = |s: f64| OPS_STATE_NOISE * (f(m) * (s + 1.0) + f(n) * s).powi(3);
    let state_noise_bytes = |s: f64| 8.0 * 3.0 * (f(m) * (s + 1.0) + f(n) * s).powi(2);
    let horizon_bytes = |s: f64| 8.0 * (f(m * r) * s * s + 6.0 * f(m * n) * s);
    let defaulted = match (&spec.monte_carlo, job) {
        (None, Job::Study { runs: Some(r) }) => Some(default_monte_carlo(spec.estimator, r)),
        _ => None,
    };
    let mc = spec.monte_carlo.as_ref().or(defaulted.as_ref());
    // A study prepares the scenario too: a worst-case simulation computes its horizon.
    let worst = spec.noise == GllsNoise::Worst;
    let passes = if job == Job::Report {
        1.0 + f64::from(u8::from(worst))
    } else {
        f64::from(u8::from(worst))
    };
    if passes > 0.0 {
        w.ops(
            Term::new(
                "glls.max_horizon",
                format!(
                    "= {} with n = {n_states} and m = {m_outputs}",
                    spec.max_horizon,
                    n_states = crate::error::counted(n, "state", "states"),
                    m_outputs = crate::error::counted(m, "output", "outputs")
                ),
                "S · n²(n + m): the singular-value curves s = 0..S",
                passes * one_horizon(f(spec.max_horizon)),
            )
            .advice("a smaller max_horizon"),
        );
        w.ops(
            Term::new(
                horizon_field,
                format!(
                    "(s = {horizon}) with n = {n_states}, m = {m_outputs}, r = {r_inputs}",
                    n_states = crate::error::counted(n, "state", "states"),
                    m_outputs = crate::error::counted(m, "output", "outputs"),
                    r_inputs = crate::error::counted(r, "input", "inputs")
                ),
                "s · n²(n + m) + m·r·s²: Γ_{s+1}, its SVD and Φ_{s+1}",
                passes * one_horizon(f(horizon)),
            )
            .advice("a shorter horizon"),
        );
        w.mem(
            Term::new(
                horizon_field,
                format!(
                    "(s = {horizon}) with m = {m_outputs}, r = {r_inputs}",
                    m_outputs = crate::error::counted(m, "output", "outputs"),
                    r_inputs = crate::error::counted(r, "input", "inputs")
                ),
                "m·r·s² + m·n·s: Φ_{s+1}, Γ_{s+1} and the gains",
                horizon_bytes(f(horizon)),
            )
            .advice("a shorter horizon"),
        );
    }
    if job == Job::Report {
        if spec.estimator == GllsEstimator::StateNoise {
            w.ops(
                Term::new(
                    horizon_field,
                    format!(
                        "(s = {horizon}) with n = {n_states} and m = {m_outputs}",
                        n_states = crate::error::counted(n, "state", "states"),
                        m_outputs = crate::error::counted(m, "output", "outputs")
                    ),
                    "(m(s + 1) + n·s)³: the state-noise estimator and its QP",
                    state_noise(f(horizon)),
                )
                .advice("a shorter horizon"),
            );
            w.mem(
                Term::new(
                    horizon_field,
                    format!(
                        "(s = {horizon}) with n = {n_states} and m = {m_outputs}",
                        n_states = crate::error::counted(n, "state", "states"),
                        m_outputs = crate::error::counted(m, "output", "outputs")
                    ),
                    "(m(s + 1) + n·s)²: the state-noise estimator's matrices",
                    state_noise_bytes(f(horizon)),
                )
                .advice("a shorter horizon"),
            );
        }
        let numbers = f(steps) * f(n + m) + f(spec.max_horizon) * f(n + 5);
        w.mem(
            Term::new(
                steps_field,
                format!(
                    "= {steps} with n = {n_states}, S = {}",
                    spec.max_horizon,
                    n_states = crate::error::counted(n, "state", "states")
                ),
                "steps · (n + m) + S · n: the trajectory and the curves in the report",
                numbers * BYTES_NUMBER,
            )
            .advice("fewer steps or a smaller max_horizon"),
        );
    }
    let runs = match job {
        Job::Report => mc.map(|c| c.runs),
        Job::Study { runs } => runs.or(mc.map(|c| c.runs)),
    };
    if let (Some(mc), Some(runs)) = (mc, runs) {
        let mc_steps = mc.steps.unwrap_or(steps).max(1);
        let s_max = mc
            .max_horizon
            .unwrap_or(spec.max_horizon.min(mc_steps - 1).min(30))
            .min(mc_steps - 1);
        let noise = mc.study == GllsStudyKind::StateNoise;
        let (field, sizes) = if mc.max_horizon.is_some() {
            (
                "glls.monte_carlo.max_horizon",
                format!("= {s_max} with n = {n}, m = {m}, r = {r}"),
            )
        } else {
            (
                "glls.max_horizon",
                format!("(the study's horizons 0..{s_max}) with n = {n}, m = {m}, r = {r}"),
            )
        };
        let (mut setup, mut setup_bytes) = (0.0, 0.0);
        for h in 0..=s_max {
            setup += one_horizon(f(h)) + if noise { state_noise(f(h)) } else { 0.0 };
            setup_bytes += horizon_bytes(f(h)) + if noise { state_noise_bytes(f(h)) } else { 0.0 };
        }
        w.ops(
            Term::new(
                field,
                sizes.clone(),
                "Σ_s s · n²(n + m) (+ (m(s + 1) + n·s)³ comparing the state-noise estimator): the study's horizons",
                setup,
            )
            .advice("fewer horizons"),
        );
        w.mem(
            Term::new(
                field,
                sizes,
                "Σ_s m·r·s² + (m(s + 1) + n·s)²: the horizons' matrices",
                setup_bytes,
            )
            .advice("fewer horizons"),
        );
        // Σ_s (s + 1): the steps of every horizon's window.
        let windows = f(s_max + 1) * f(s_max + 2) / 2.0;
        let per_run = f(mc_steps) * (OPS_SIM * f(n * (n + m + r)) + OPS_SIM_STEP)
            + windows * (OPS_STACK + OPS_ESTIMATE * f(n * m) * if noise { f(s_max) } else { 1.0 });
        let (run_field, run_count) = if job == Job::Report {
            ("glls.monte_carlo.runs", runs)
        } else {
            ("glls.monte_carlo.steps", 1)
        };
        w.ops(
            Term::new(
                run_field,
                format!(
                    "= {} with {mc_steps_steps}, horizons 0..{s_max}, n = {n}",
                    if job == Job::Report { runs } else { mc_steps }, mc_steps_steps = crate::error::counted(mc_steps, "step", "steps")
                ),
                "runs · (steps · n(n + m + r) + n·m·S²): a simulation and every horizon's estimate per run",
                f(run_count) * per_run,
            )
            .advice(if job == Job::Report { "fewer runs" } else { "fewer steps per run" })
            .study(),
        );
        w.mem(
            Term::new(
                "glls.monte_carlo.runs",
                format!("= {runs} with horizons 0..{s_max}"),
                "runs · horizons: one error per run and horizon, kept for the quartiles",
                f(runs) * f(s_max + 1) * if noise { 16.0 } else { 8.0 },
            )
            .advice("fewer runs or horizons"),
        );
    }
    w
}

// ---------------------------------------------------------------------------------------------
// Compare: what a compare asks of GLLS (`scenario::compare`)

impl CompareMember for Glls {
    fn options(&self) -> &'static [&'static str] {
        // The method's own choices: its horizon (or the longest it searches), the estimator and
        // the regularization rank. μ is the compare's (√q·b_w from its bounds).
        &["horizon", "max_horizon", "estimator", "p"]
    }
    fn compare_order(&self) -> usize {
        3
    }
    fn assumption(&self, p: &ComparePrepared) -> Assumption {
        Assumption {
            assumes: "no state noise; ‖w(t)‖₂ ≤ μ",
            violated: if p.has_state_noise() {
                Some(
                    "violated: the system has state noise (GLLS takes x(t+1) = F·x(t))".to_string(),
                )
            } else {
                p.bounds_violation()
            },
            promise: "always",
            // The guaranteed ball (35) holds the state whenever ‖δ(k)‖₂ ≤ μ.
            level: Some(1.0),
            at_least: false,
        }
    }
    fn derived_scenario(&self, p: &ComparePrepared, t: usize) -> Result<Scenario> {
        // Ω = σ_w²·I; μ = √q·b_w bounds ‖w(t)‖₂ when every |w_i| ≤ b_w.
        let q = p.model().q();
        let sigma_w2 = p.sigma_w() * p.sigma_w();
        let mut model = p.bare_model();
        model.w = Some(MatrixSpec::of(&(DMatrix::identity(q, q) * sigma_w2)));
        let mut s = p.own_scenario(Method::Glls, model, t);
        s.glls = Some(GllsSpec {
            horizon: None,
            max_horizon: (t - 1).clamp(1, 60),
            estimator: GllsEstimator::default(),
            p: None,
            mu: Some((q as f64).sqrt() * p.bounds().1),
            noise: GllsNoise::default(),
            // Its panel draws the compare's plane (n ≥ 3; n ≤ 2 draws its own).
            plane: match p.plane() {
                &[i, j] if p.n() >= 3 => Some([i, j]),
                _ => None,
            },
            monte_carlo: None,
        });
        Ok(s)
    }
    fn plane_set(
        &self,
        p: &ComparePrepared,
        r: &Report,
        truth: Option<&[f64]>,
    ) -> Result<PlaneReading> {
        let g = r
            .glls
            .as_ref()
            .ok_or_else(|| Error::field("report.glls", "has no glls part"))?;
        if p.n() != 2 {
            return plane_set_projected(p, g, truth);
        }
        let corners = box_corners(&g.box_current.lo, &g.box_current.hi);
        // The ball is of x_t; without state noise (GLLS's assumption) x_{t+1} = F·x_t, so the
        // prediction set is the ellipse F·ball and its box the parallelogram F·box.
        let (ball, outline, note) = if p.predicts() {
            let f = p.model().f(1);
            (
                map_ellipse(f, &g.ball_current),
                convex_hull(corners.into_iter().map(|c| map_point(f, c)).collect()),
                format!("horizon s = {}; F·ball (no state noise)", g.s),
            )
        } else {
            (
                g.ball_current.clone(),
                corners,
                format!("horizon s = {}", g.s),
            )
        };
        Ok(PlaneReading {
            area: Some(ball.volume()),
            holds: truth.map(|x| ball.contains(x)),
            note: Some(note),
            set: PlaneSet::Ellipse(ball),
            outline: Some(outline),
        })
    }
    fn remedy(&self, p: &ComparePrepared, e: &Error) -> Option<String> {
        if !e.field.starts_with("glls.horizon") {
            return None;
        }
        Some(match p.unobservable() {
            Some(why) => format!("no horizon: {why}, and GLLS needs x(k − s) determined by y(k − s … k)"),
            None => "a longer horizon, compare.members.glls.horizon (s + 1 measurements must determine x(k − s), Γ_{s+1} of rank n (6)), or a later compare.time".to_string(),
        })
    }
}

/// GLLS's set of a model of n ≠ 2 states: the ball of x_t (or F·ball, the prediction without
/// state noise) projected on the compare's plane (its shadow: it holds the plane's components
/// whenever the ball holds the state), an interval for n = 1; the box (or F·box) projected the
/// same way, the outline.
fn plane_set_projected(
    p: &ComparePrepared,
    g: &GllsReport,
    truth: Option<&[f64]>,
) -> Result<PlaneReading> {
    let f = p.model().f(1);
    let (ball, note) = if p.predicts() {
        (
            super::compare::map_ellipsoid(f, &g.ball_current),
            format!("horizon s = {}; F·ball (no state noise), projected", g.s),
        )
    } else {
        (g.ball_current.clone(), format!("horizon s = {}", g.s))
    };
    let e = ball.project(p.plane())?;
    let outline = match p.plane() {
        &[i, j] => Some(super::compare::projected_box_image(
            p.predicts().then_some(f),
            &g.box_current.lo,
            &g.box_current.hi,
            [i, j],
        )),
        _ => None,
    };
    Ok(PlaneReading {
        area: Some(e.volume()),
        holds: truth.map(|x| e.contains(x)),
        note: Some(note),
        set: PlaneSet::of_ellipsoid(e),
        outline,
    })
}

// ---------------------------------------------------------------------------------------------
// Presets

/// The GLLS paper's presets, in menu order (the trait's `presets`, gathered by
/// [`crate::presets::all`]).
fn presets() -> Vec<Preset> {
    vec![
        Preset {
            name: "glls-saturate".into(),
            label: "GLLS Figs. 1a, 2a — σ₃ saturates: a best horizon".into(),
            menu: "GLLS Figs. 1a, 2a — σ₃ saturates".into(),
            description: "GLLS paper, Fig. 1a/2a kind: a stable mode and a rotation — σ₃(Γ) saturates, so σ_n/√s has a best horizon".into(),
            scenario: glls_preset(GllsKind::Saturate),
        },
        Preset {
            name: "glls-grow".into(),
            label: "GLLS Figs. 1b, 2b — two unstable modes".into(),
            menu: "GLLS Figs. 1b, 2b — σ grows".into(),
            description: "GLLS paper, Fig. 1b/2b/3b kind: two unstable modes — every σ grows without bound, ‖x(39)‖ ≈ 10⁷ costs digits".into(),
            scenario: glls_preset(GllsKind::Grow),
        },
        Preset {
            name: "glls-mixed".into(),
            label: "GLLS Fig. 1c — stable, neutral and unstable modes".into(),
            menu: "GLLS Fig. 1c — mixed modes".into(),
            description: "GLLS paper, Fig. 1c kind: stable, neutral and unstable modes (eigenvalues 0.7, 1, 1.05)".into(),
            scenario: glls_preset(GllsKind::Mixed),
        },
        Preset {
            name: "glls-unstable5".into(),
            label: "GLLS Section 5.2 — five states with state noise".into(),
            menu: "GLLS Sec. 5.2 — five states".into(),
            description: "GLLS paper, Section 5.2: the 5-state unstable system (eigenvalues 3.057, −0.374 ± 1.130i, −0.600, 1.095) with noisy transitions: state-noise estimator vs LLS".into(),
            scenario: glls_preset(GllsKind::Unstable5),
        },
    ]
}

/// The GLLS presets (the paper prints no matrices: these are built to show each behaviour).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GllsKind {
    Saturate,
    Grow,
    Mixed,
    Unstable5,
}

fn rows(r: &[&[f64]]) -> Option<MatrixSpec> {
    Some(MatrixSpec::Constant(r.iter().map(|x| x.to_vec()).collect()))
}

pub fn glls_preset(kind: GllsKind) -> Scenario {
    let (t, s) = (0.5f64.cos(), 0.5f64.sin());
    let (title, model, steps, spec, notes) = match kind {
        GllsKind::Saturate => (
            "GLLS: a saturating singular value (Figs. 1a, 2a, 3a kind)",
            ModelSpec { f: rows(&[&[0.6, 0.0, 0.0], &[0.0, t, -s], &[0.0, s, t]]), h: rows(&[&[1.0, 1.0, 0.0]]), w: rows(&[&[0.01]]), x1_mean: Some(vec![1.0, 1.0, 0.0]), ..Default::default() },
            40,
            GllsSpec { horizon: None, max_horizon: 60, estimator: GllsEstimator::Lls, p: Some(2), mu: Some(0.1), noise: GllsNoise::Bounded, plane: Some([1, 2]), monte_carlo: Some(GllsMonteCarloSpec { runs: 2000, seed: 1, study: GllsStudyKind::Precision, steps: None, max_horizon: Some(30) }) },
            "A = diag(0.6, rotation by 0.5 rad), C = [1 1 0]: the stable mode's contribution to Γ_{s+1}ᵀΓ_{s+1} converges, so σ₃ saturates while σ₁, σ₂ grow like √s; σ₃/√s peaks at the best horizon. \
             Noise bounded by μ = 0.1 (uniform in the ball): the guaranteed ball and box of x(k) must hold the truth. \
             The paper prints no matrices for its three systems; these are built to show each behaviour.",
        ),
        GllsKind::Grow => (
            "GLLS: every singular value grows (Figs. 1b, 2b, 3b kind)",
            ModelSpec { f: rows(&[&[1.5, 0.2], &[0.0, 1.3]]), h: rows(&[&[1.0, 0.0]]), w: rows(&[&[0.01]]), x1_mean: Some(vec![1.0, 1.0]), ..Default::default() },
            40,
            GllsSpec { horizon: Some(8), max_horizon: 60, estimator: GllsEstimator::Lls, p: None, mu: Some(0.3), noise: GllsNoise::Gaussian, plane: Some([0, 1]), monte_carlo: Some(GllsMonteCarloSpec { runs: 2000, seed: 1, study: GllsStudyKind::Precision, steps: None, max_horizon: Some(30) }) },
            "A = [[1.5, 0.2], [0, 1.3]], C = [1 0]: both modes unstable, every σ_i(Γ_{s+1}) and σ_n/√s grow without bound (Fig. 2b). \
             ‖x(39)‖ ≈ 10⁷, as in the paper's Fig. 3b (1.47·10⁷): the estimates of longer horizons lose to rounding what the condition number promises — the page marks where the estimated rounding error exceeds the bound.",
        ),
        GllsKind::Mixed => (
            "GLLS: stable, neutral and unstable modes (Figs. 1c, 2c, 3c kind)",
            ModelSpec {
                f: rows(&[&[0.697, 0.1515, 0.01], &[-0.006, 1.003, 0.02], &[-0.105, 0.0525, 1.05]]),
                h: rows(&[&[1.0, 0.0, 0.0]]),
                w: rows(&[&[0.01]]),
                x1_mean: Some(vec![1.0, -1.0, 0.5]),
                ..Default::default()
            },
            40,
            GllsSpec { horizon: None, max_horizon: 60, estimator: GllsEstimator::Glls, p: Some(2), mu: Some(0.1), noise: GllsNoise::Gaussian, plane: Some([0, 1]), monte_carlo: Some(GllsMonteCarloSpec { runs: 2000, seed: 1, study: GllsStudyKind::Precision, steps: None, max_horizon: Some(30) }) },
            "A = T diag(0.7, 1, 1.05) T⁻¹ with T = [[1, 0.5, 0.2], [0, 1, 0.4], [0.3, 0, 1]] (rounded to 4 digits), C = [1 0 0]: one σ saturates, one grows like √s, one exponentially. \
             The bound κ·√E‖δ(k,s)‖² becomes conservative for long horizons, as in the paper's Fig. 3c.",
        ),
        GllsKind::Unstable5 => (
            "GLLS: state noise on 5 unstable states (Section 5.2, Fig. 4)",
            ModelSpec {
                f: rows(&[
                    &[0.5477, 1.9865, 0.7628, 0.993, 1.007],
                    &[-0.4814, 0.4988, -1.2108, 0.036, -0.4028],
                    &[-1.226, -0.5629, -0.8029, 0.6084, -1.6617],
                    &[0.4885, -0.3119, 0.6064, 3.0772, -0.4143],
                    &[0.4, -0.667, 0.5436, 1.3299, -0.5168],
                ]),
                h: rows(&[&[1.0, 0.0, 0.0, 0.0, 0.0]]),
                w: rows(&[&[0.0]]),
                v: rows(&[&[0.01, 0.0, 0.0, 0.0, 0.0], &[0.0, 0.01, 0.0, 0.0, 0.0], &[0.0, 0.0, 0.01, 0.0, 0.0], &[0.0, 0.0, 0.0, 0.01, 0.0], &[0.0, 0.0, 0.0, 0.0, 0.01]]),
                x1_mean: Some(vec![1.0, 1.0, 1.0, 1.0, 1.0]),
                ..Default::default()
            },
            16,
            GllsSpec { horizon: Some(8), max_horizon: 30, estimator: GllsEstimator::StateNoise, p: None, mu: Some(0.0), noise: GllsNoise::Gaussian, plane: Some([0, 3]), monte_carlo: Some(GllsMonteCarloSpec { runs: 2000, seed: 1, study: GllsStudyKind::StateNoise, steps: None, max_horizon: Some(15) }) },
            "x(k+1) = A x(k) + ξ(k), y = C x exactly (54)–(55), ξ ~ N(0, 0.01·I), 16 steps. A is built (real Schur form, fitted off-diagonal entries, a fixed rotation) to have the paper's eigenvalues 3.057, −0.374 ± 1.130i, −0.600, 1.095 and its singular values 3.735, 3.166, 1.828, 0.636, 0.206 (to 3 digits); the paper prints neither A nor C (C = [1 0 0 0 0] here). \
             The state-noise estimator (63)–(64) is solved in closed form and checked against clarabel's QP.",
        ),
    };
    let mut s = Scenario::new(Method::Glls, model)
        .with_title(title)
        .with_simulate(SimulateSpec {
            steps,
            seed: 3,
            u: vec![],
            condition: None,
            x0: None,
            true_noise: None,
        })
        .with_alpha(0.9)
        .with_notes(notes);
    s.glls = Some(spec);
    s
}
