//! The compare scenario (`"method": "compare"`): one linear system, one record of data, every
//! method's set for the same state in one plane, what each method assumes checked against the
//! noise law that made the record, and a study counting how often each set holds a fixed
//! true state.
//!
//! Nothing here estimates: every set is the one the method's own scenario gives. For each
//! method, [`derived_scenario`] writes that scenario (the method's block with its parameters
//! derived from the one noise law, the record's first t rows as `data`), [`Scenario::run`]
//! runs it exactly as the method's panel would, and [`extract`] reads the set for the target
//! state out of its report. So a compare set equals its panel's set on the same data
//! (`tests/suite/compare.rs` checks it to 1e-9, natively and in wasm).
//!
//! The noise law (`compare.noise`) makes the record and decides the parameters:
//!
//! | law | variances (KF, SCF, LSCR's BLUE) | bounds b_v, b_w (ubb τ, ε; GLLS μ = √q·b_w; uniform_lp x̄_r, ȳ_r) |
//! |---|---|---|
//! | `gaussian` | σ_v², σ_w² | k·σ (`bound_sigmas`, default 3): exceeded with probability 2(1 − Φ(k)) per sample |
//! | `uniform` | σ_v², σ_w² (uniform on ±√3·σ) | √3·σ: the support, never exceeded |
//! | `truncated` | σ_v², σ_w² of the untruncated law (conservative) | k·σ: the truncation, never exceeded |
//!
//! `bound_scale` multiplies every bound (below 1: bounds tighter than the truth, to see a
//! guarantee fail when its assumption does). The noise enters as G·v with v's components
//! independent and of variance σ_v² (`model.G` with `sigma_v2`, `sigma_w2`; a `V`/`W` model is
//! read as G = V^{1/2}, σ_v = 1, and W must be σ_w²·I).
//!
//! The target (`compare.target`) is the prediction x_{t+1} or the filtered x_t from y_1 … y_t.
//! Where a method's paper gives the other one only, the set is carried over exactly by the
//! model it assumes, or the method says why it has none:
//! * GLLS's ball is of x_t (its current state); without state noise (its assumption)
//!   x_{t+1} = F·x_t, so its prediction set is the ellipse F·ball (and its box the
//!   parallelogram F·box).
//! * Pavelková's consistent polygon is of x_t; x_{t+1} = F·x_t + G·v with |v_i| ≤ b_v, so the
//!   prediction set is the Minkowski sum F·P ⊕ G·[−b_v, b_v]^p (exact, a polygon).
//! * Tempo's set is of x(k+1) from y(0 … k): a prediction only; for the filter target it says
//!   so.
//!
//! The study (`compare.study`: `x`, `runs`, `seed`) fixes the true target state and draws
//! records from their law given it: exactly, by the backward representation, for Gaussian
//! noise ([`crate::model::ConditionedSampler`]); for the other laws no exact conditional
//! sampler exists, so the study counts unconditional coverage (x_1 from the model's prior) and
//! says so in its result.

use super::budget::{Job, Work};
use super::csv::{flag, Table};
use super::{detail_of, detail_value, Cursor, DataSpec, MethodScenario, Report, Scenario};
use crate::error::{Error, Result};
use crate::linalg;
use crate::method::Method;
use crate::model::{normal_vector, LinearModel, MatrixSpec, ModelSpec};
use crate::presets::Preset;
use crate::sets::{point_in_convex, BoxSet, Ellipsoid, Loop};
use crate::stats;
use crate::study::{self, Runs, Study, Tally};
use nalgebra::{DMatrix, DVector};
use rand::{Rng, RngExt};
use serde::{Deserialize, Serialize};
use std::ops::RangeInclusive;
use std::sync::OnceLock;

/// The law of every noise sample of the record (and of the study's records).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NoiseLaw {
    #[default]
    Gaussian,
    Uniform,
    Truncated,
}

impl NoiseLaw {
    fn name(self) -> &'static str {
        match self {
            NoiseLaw::Gaussian => "Gaussian",
            NoiseLaw::Uniform => "uniform",
            NoiseLaw::Truncated => "truncated Gaussian",
        }
    }
}

/// Which state the sets are about.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Target {
    /// x_{t+1} from y_1 … y_t.
    #[default]
    Predict,
    /// x_t from y_1 … y_t.
    Filter,
}

/// The compare study: a fixed true target state and the runs that count each set's hits.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CompareStudySpec {
    /// The true target state (x_{t+1} or x_t), both components.
    pub x: Vec<f64>,
    #[serde(default = "default_study_runs")]
    pub runs: usize,
    #[serde(default)]
    pub seed: u64,
}
fn default_study_runs() -> usize {
    200
}

/// The `compare` block.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CompareSpec {
    #[serde(default)]
    pub noise: NoiseLaw,
    /// k of the truncated law, and the bound k·σ the bounded methods are given under Gaussian
    /// noise.
    #[serde(default = "default_bound_sigmas")]
    pub bound_sigmas: f64,
    /// Multiplies every bound the set-membership methods are given (below 1: tighter than the
    /// truth).
    #[serde(default = "default_bound_scale")]
    pub bound_scale: f64,
    #[serde(default)]
    pub target: Target,
    /// The time t of the data y_1 … y_t (default: the last).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<usize>,
    /// The methods compared (default: all six).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub methods: Option<Vec<Method>>,
    /// Window length of the set-membership methods (Tempo's j + 1, Pavelková's ∂).
    #[serde(default = "default_window")]
    pub window: usize,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub study: Option<CompareStudySpec>,
}
fn default_bound_sigmas() -> f64 {
    3.0
}
fn default_bound_scale() -> f64 {
    1.0
}
fn default_window() -> usize {
    10
}

/// The methods a compare runs when `compare.methods` is not given.
pub const COMPARED: [Method; 6] = [
    Method::Kf,
    Method::Scf,
    Method::Lscr,
    Method::Glls,
    Method::Ubb,
    Method::UniformLp,
];

/// Most simulated steps or data rows of a compare (each step of the time cursor reruns every
/// method on the rows up to it).
pub const MAX_STEPS: usize = 150;
/// Largest window of the set-membership methods.
pub const MAX_WINDOW: usize = 40;
/// Bound on every state entry of Pavelková's window LP in units of the record's scale (her ±5,
/// widened: the compare states are the model's, not hers). In the record's own unit, so that a
/// record scaled by 10⁶ is not cut by the box, nor one scaled by 10⁻⁸ lost in it (issue 25).
const X_BOUND_PER_SCALE: f64 = 1e4;
/// Support LPs of each exact polygon.
const POLYGON_BUDGET: usize = 64;

/// A set in the compare plane (the two state components).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum PlaneSet {
    /// (x − c)ᵀ cov⁻¹ (x − c) ≤ radius2.
    Ellipse(Ellipsoid),
    /// A convex polygon, vertices counter-clockwise.
    Polygon { vertices: Vec<[f64; 2]> },
    /// The LSCR region: its boundary loops inside `window` (unbounded when `bounded` is false).
    Region {
        loops: Vec<Loop>,
        bounded: bool,
        window: BoxSet,
    },
}

/// One method's set at the cursor's time, or why it has none.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct MethodSet {
    pub method: Method,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub set: Option<PlaneSet>,
    /// A second, outer set drawn dashed: GLLS's interval box, Tempo's interval hull.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outline: Option<Vec<[f64; 2]>>,
    /// Area of the set (absent when unbounded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub area: Option<f64>,
    /// Whether the set holds the true state (simulation only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub holds: Option<bool>,
    /// Why the method has no set here (its own error, naming its field).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// What the set is besides (the horizon, the prediction carried over, bounds extended).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// Seconds the method's run took, by the caller's clock ([`set_clock`]); absent without one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seconds: Option<f64>,
    /// The method's own scenario on the record up to t (its JSON: a report is read without
    /// reading scenarios): open it in the method's panel to see the same set there.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scenario: Option<serde_json::Value>,
}

/// One method's row of the table: what it assumes, whether the record's law meets it, what
/// it promises.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct CompareRow {
    pub method: Method,
    pub assumes: String,
    pub met: bool,
    /// Why the assumption is violated, in plain words.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub violated: Option<String>,
    /// "on average over states", "for every state", "always", "nothing".
    pub promise: String,
    /// The promised probability that the set holds the state (absent: no probability).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub level: Option<f64>,
    /// Whether `level` is a lower bound (LSCR) rather than exact.
    #[serde(default)]
    pub at_least: bool,
}

/// The detail at one time t: every method's set.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct CompareAt {
    pub t: usize,
    /// t + 1 (prediction) or t.
    pub target_time: usize,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth: Option<[f64; 2]>,
    pub sets: Vec<MethodSet>,
}

/// The compare report.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct CompareReport {
    pub noise: NoiseLaw,
    pub target: Target,
    pub sigma_v: f64,
    pub sigma_w: f64,
    /// The bounds the set-membership methods are given (after `bound_scale`).
    pub bound_v: f64,
    pub bound_w: f64,
    pub bound_scale: f64,
    pub steps: usize,
    /// The first time of the cursor.
    pub first: usize,
    /// x_1 … x_{T+1} (simulation only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_true: Option<Vec<Vec<f64>>>,
    pub rows: Vec<CompareRow>,
    pub at: CompareAt,
}

static CLOCK: OnceLock<fn() -> f64> = OnceLock::new();

/// Give the compare a clock (seconds, any origin) to time each method's run: the core never
/// reads one itself (the CLI passes the process clock, the page `performance.now`).
pub fn set_clock(now: fn() -> f64) {
    let _ = CLOCK.set(now);
}

/// The noise of the model as G·v, v of independent components of variance σ_v², and w of
/// variance σ_w² per output.
#[derive(Debug, Clone)]
struct Noise {
    g: DMatrix<f64>,
    sigma_v: f64,
    sigma_w: f64,
}

fn noise_of(model: &ModelSpec, lm: &LinearModel) -> Result<Noise> {
    if let Some(g) = &model.g {
        let g = linalg::from_rows("model.G", g)?;
        let sv2 = model.sigma_v2.unwrap_or(0.0);
        let sw2 = model.sigma_w2.ok_or_else(|| {
            Error::field(
                "model.sigma_w2",
                "is missing (the measurement noise variance σ_w²)",
            )
        })?;
        return Ok(Noise {
            g,
            sigma_v: sv2.max(0.0).sqrt(),
            sigma_w: sw2.max(0.0).sqrt(),
        });
    }
    let w = lm.w(1);
    let w0 = w[(0, 0)];
    let q = w.nrows();
    if (0..q).any(|i| (0..q).any(|j| w[(i, j)] != if i == j { w0 } else { 0.0 })) {
        return Err(Error::field(
            "model.W",
            "must be σ_w²·I for a compare (one bound ε for every output): give equal variances and no correlations",
        ));
    }
    Ok(Noise {
        g: linalg::psd_sqrt(lm.v(1)),
        sigma_v: 1.0,
        sigma_w: w0.max(0.0).sqrt(),
    })
}

/// One standardized sample (mean 0, variance 1 except the truncated law's, which is σ's
/// untruncated variance's fraction) of the law.
fn standard<R: Rng>(law: NoiseLaw, k: f64, rng: &mut R) -> f64 {
    match law {
        NoiseLaw::Gaussian => normal_vector(1, rng)[0],
        NoiseLaw::Uniform => 3f64.sqrt() * (2.0 * rng.random::<f64>() - 1.0),
        NoiseLaw::Truncated => loop {
            // k ≥ 0.5 (checked): at most ~2.6 draws on average.
            let z = normal_vector(1, rng)[0];
            if z.abs() <= k {
                break z;
            }
        },
    }
}

/// Everything a compare needs once: the model, its noise, the bounds, the record.
pub(crate) struct ComparePrepared {
    scenario: Scenario,
    spec: CompareSpec,
    model: LinearModel,
    noise: Noise,
    bound_v: f64,
    bound_w: f64,
    methods: Vec<Method>,
    /// The record: y_1 … y_T, and x_1 … x_{T+1} when simulated.
    y: Vec<Vec<f64>>,
    x: Option<Vec<DVector<f64>>>,
    time: usize,
}

impl Scenario {
    pub(crate) fn prepare_compare(&self) -> Result<ComparePrepared> {
        let spec = self
            .block(&self.compare, "the noise law and the target")?
            .clone();
        let lm = LinearModel::from_spec(&self.model)?;
        if lm.n() != 2 {
            return Err(Error::field(
                "model.F",
                format!(
                    "is {n}×{n}: a compare draws every set in the state plane, so it takes n = 2 states",
                    n = lm.n()
                ),
            ));
        }
        if !lm.is_time_invariant() {
            return Err(Error::field(
                "model",
                "must be time-invariant for a compare (LSCR, GLLS, Tempo and Pavelková take one F and one H)",
            ));
        }
        if self.model.b.is_some() {
            return Err(Error::field(
                "model.B",
                "is not taken by a compare yet: the papers time their inputs differently (u_t or u_{t−1}); compare a system without measured inputs",
            ));
        }
        let noise = noise_of(&self.model, &lm)?;
        if !(0.5..=10.0).contains(&spec.bound_sigmas) {
            return Err(Error::field(
                "compare.bound_sigmas",
                format!(
                    "must be a number from 0.5 to 10, found {}",
                    spec.bound_sigmas
                ),
            ));
        }
        if !(0.01..=100.0).contains(&spec.bound_scale) {
            return Err(Error::field(
                "compare.bound_scale",
                format!(
                    "must be a number from 0.01 to 100, found {}",
                    spec.bound_scale
                ),
            ));
        }
        if !(1..=MAX_WINDOW).contains(&spec.window) {
            return Err(Error::field(
                "compare.window",
                format!(
                    "must be a whole number from 1 to {MAX_WINDOW}, found {}",
                    spec.window
                ),
            ));
        }
        let methods = spec.methods.clone().unwrap_or_else(|| COMPARED.to_vec());
        if methods.is_empty() {
            return Err(Error::field(
                "compare.methods",
                "is empty: name at least one method",
            ));
        }
        for (i, m) in methods.iter().enumerate() {
            if !COMPARED.contains(m) {
                return Err(Error::field(
                    format!("compare.methods[{i}]"),
                    format!("is \"{m}\": a compare runs kf, scf, lscr, glls, ubb and uniform_lp"),
                ));
            }
            if methods[..i].contains(m) {
                return Err(Error::field(
                    format!("compare.methods[{i}]"),
                    format!("names \"{m}\" twice"),
                ));
            }
        }
        let factor = match spec.noise {
            NoiseLaw::Uniform => 3f64.sqrt(),
            NoiseLaw::Gaussian | NoiseLaw::Truncated => spec.bound_sigmas,
        } * spec.bound_scale;
        let source = self.source(&Compare)?;
        let steps = source.steps();
        let (y, x) = match source {
            super::Source::Data(d) => {
                let y = source.measurements(lm.q())?;
                if !d.u.is_empty() {
                    return Err(Error::field(
                        "data.u",
                        "is given, but a compare takes no inputs",
                    ));
                }
                (y, None)
            }
            super::Source::Simulate(sim) => {
                if !sim.u.is_empty() {
                    return Err(Error::field(
                        "simulate.u",
                        "is given, but a compare takes no inputs",
                    ));
                }
                let mut rng = study::run_stream(sim.seed, 0);
                let (x, y) = match &sim.condition {
                    Some(c) => {
                        let x_c = linalg::vector("simulate.condition.x", &c.x, 2)?;
                        record_conditioned(&lm, spec.noise, steps, c.t, &x_c, &mut rng)?
                    }
                    None => record(&lm, &noise, spec.noise, spec.bound_sigmas, steps, &mut rng),
                };
                (y, Some(x))
            }
        };
        let time = spec.time.unwrap_or(steps);
        if !(2..=steps).contains(&time) {
            return Err(Error::field(
                "compare.time",
                format!(
                    "must be a whole number from 2 to {steps} (the record's steps), found {time}"
                ),
            ));
        }
        Ok(ComparePrepared {
            scenario: self.clone(),
            bound_v: factor * noise.sigma_v,
            bound_w: factor * noise.sigma_w,
            spec,
            model: lm,
            noise,
            methods,
            y: y.iter().map(|v| v.iter().copied().collect()).collect(),
            x,
            time,
        })
    }
}

/// x_1 … x_{T+1}, y_1 … y_T: x_1 from the model's prior, the noise from the law.
fn record<R: Rng>(
    lm: &LinearModel,
    noise: &Noise,
    law: NoiseLaw,
    k: f64,
    steps: usize,
    rng: &mut R,
) -> (Vec<DVector<f64>>, Vec<DVector<f64>>) {
    let (f, h) = (lm.f(1), lm.h(1));
    let p = noise.g.ncols();
    let mut x = &lm.x1_mean + linalg::psd_sqrt(&lm.x1_cov) * normal_vector(2, rng);
    let mut xs = Vec::with_capacity(steps + 1);
    let mut ys = Vec::with_capacity(steps);
    for _ in 0..steps {
        let w = DVector::from_fn(h.nrows(), |_, _| noise.sigma_w * standard(law, k, rng));
        ys.push(h * &x + w);
        xs.push(x.clone());
        let v = DVector::from_fn(p, |_, _| noise.sigma_v * standard(law, k, rng));
        x = f * &x + &noise.g * v;
    }
    xs.push(x);
    (xs, ys)
}

/// The record drawn given x_{t_c} = x_c: exact for Gaussian noise (backward representation).
fn record_conditioned<R: Rng>(
    lm: &LinearModel,
    law: NoiseLaw,
    steps: usize,
    t_c: usize,
    x_c: &DVector<f64>,
    rng: &mut R,
) -> Result<(Vec<DVector<f64>>, Vec<DVector<f64>>)> {
    if law != NoiseLaw::Gaussian {
        return Err(Error::field(
            "simulate.condition",
            format!(
                "needs Gaussian noise: with {} noise there is no exact draw of the past given a state (remove the condition, or choose \"noise\": \"gaussian\")",
                law.name()
            ),
        ));
    }
    let traj = lm.simulate_conditioned(steps + 1, &crate::model::Inputs::none(), t_c, x_c, rng)?;
    let mut y = traj.y;
    y.truncate(steps);
    Ok((traj.x, y))
}

/// Whether the bounded methods' bounds hold the record's noise, in words when they do not.
fn bounds_violation(p: &ComparePrepared) -> Option<String> {
    let s = &p.spec;
    if s.bound_scale < 1.0 {
        return Some(format!(
            "violated: the bounds are {}× the noise's own (b_v = {:.4}, b_w = {:.4})",
            s.bound_scale, p.bound_v, p.bound_w
        ));
    }
    match s.noise {
        NoiseLaw::Gaussian => Some(format!(
            "violated: Gaussian noise is unbounded (the bound {}σ is exceeded with probability {:.2} % per sample)",
            s.bound_sigmas,
            200.0 * (1.0 - stats::normal_cdf(s.bound_sigmas))
        )),
        NoiseLaw::Uniform | NoiseLaw::Truncated => None,
    }
}

/// The table row of one method for the prepared record (its scenario at time t).
fn row(p: &ComparePrepared, m: Method, alpha: f64) -> CompareRow {
    let gaussian = p.spec.noise == NoiseLaw::Gaussian;
    let not_gaussian =
        (!gaussian).then(|| format!("violated: noise not Gaussian ({})", p.spec.noise.name()));
    let bounds = bounds_violation(p);
    let state_noise = p.noise.sigma_v > 0.0 && p.noise.g.iter().any(|&g| g != 0.0);
    let (assumes, violated, promise, level, at_least) = match m {
        Method::Kf => (
            "Gaussian noise and prior, known variances",
            not_gaussian,
            "on average over states",
            Some(alpha),
            false,
        ),
        Method::Scf => (
            "Gaussian noise, known variances",
            not_gaussian,
            "for every state",
            Some(alpha),
            false,
        ),
        Method::Lscr => (
            "noise symmetric about 0 and independent; variances need not be known",
            None,
            "for every state, at least",
            None,
            true,
        ),
        Method::Glls => (
            "no state noise; ‖w(t)‖₂ ≤ μ",
            if state_noise {
                Some(
                    "violated: the system has state noise (GLLS takes x(t+1) = F·x(t))".to_string(),
                )
            } else {
                bounds
            },
            "always",
            Some(1.0),
            false,
        ),
        Method::Ubb => (
            "|v(t)| ≤ τ and |w(t)| ≤ ε at every t",
            bounds,
            "always",
            Some(1.0),
            false,
        ),
        _ => (
            "innovations uniform within the half-width bounds",
            match (p.spec.noise, &bounds) {
                (_, Some(b)) if p.spec.bound_scale < 1.0 => Some(b.clone()),
                (NoiseLaw::Uniform, _) => None,
                (law, _) => Some(format!("violated: noise not uniform ({})", law.name())),
            },
            "nothing (the consistent set holds the state whenever the bounds hold)",
            None,
            false,
        ),
    };
    // LSCR's level comes from its M and q (not from the time): its run on the whole record
    // says it.
    let level = match m {
        Method::Lscr => derived_scenario(p, m, p.y.len())
            .and_then(|s| s.run())
            .ok()
            .and_then(|r| r.lscr.map(|l| l.level)),
        _ => level,
    };
    CompareRow {
        method: m,
        assumes: assumes.to_string(),
        met: violated.is_none(),
        violated,
        promise: promise.to_string(),
        level,
        at_least,
    }
}

/// The method's own scenario on the record's first t rows, with its parameters derived from
/// the noise law (the table in the module docs).
/// The record's scale: its largest datum, prior mean or noise bound (the unit every set of
/// the compare has).
fn record_scale(p: &ComparePrepared) -> f64 {
    let prior = p.model.x1_mean.amax();
    p.y.iter()
        .flatten()
        .fold(p.bound_v.max(p.bound_w).max(prior), |m, v| m.max(v.abs()))
}

fn derived_scenario(p: &ComparePrepared, m: Method, t: usize) -> Result<Scenario> {
    let s = &p.scenario;
    let c = &p.spec;
    let lm = &p.model;
    let f = linalg::to_rows(lm.f(1));
    let h = linalg::to_rows(lm.h(1));
    let q = lm.q();
    let predict = c.target == Target::Predict;
    let bare = |extra: fn(&mut ModelSpec, &ComparePrepared)| {
        let mut spec = ModelSpec {
            f: Some(MatrixSpec::Constant(f.clone())),
            h: Some(MatrixSpec::Constant(h.clone())),
            v: None,
            w: None,
            g: None,
            sigma_v2: None,
            sigma_w2: None,
            b: None,
            x1_mean: None,
            x1_cov: None,
        };
        extra(&mut spec, p);
        spec
    };
    let window = c.window.min(t);
    let block = |v: serde_json::Value, name: &str| serde_json::json!({ name: v });
    let (model, extra) = match m {
        Method::Kf | Method::Scf => (
            s.model.clone(),
            serde_json::json!({"tau": usize::from(predict), "components": [0, 1]}),
        ),
        Method::Lscr => (
            s.model.clone(),
            block(
                serde_json::json!({
                    "estimate": if predict { "predict" } else { "filter" },
                    "level": s.alpha,
                    "construction": "random",
                    "seed": 1,
                }),
                "lscr",
            ),
        ),
        Method::Glls => (
            bare(|spec, p| {
                let w = p.noise.sigma_w * p.noise.sigma_w;
                let q = p.model.q();
                spec.w = Some(MatrixSpec::Constant(linalg::to_rows(
                    &(DMatrix::identity(q, q) * w),
                )));
            }),
            block(
                serde_json::json!({
                    "mu": (q as f64).sqrt() * p.bound_w,
                    "max_horizon": (t - 1).clamp(1, 60),
                }),
                "glls",
            ),
        ),
        Method::Ubb => (
            bare(|spec, p| spec.g = Some(linalg::to_rows(&p.noise.g))),
            block(
                serde_json::json!({
                    "norm": "linf",
                    "eps": p.bound_w,
                    "tau": p.bound_v,
                    "delta": null,
                    "alpha": null,
                    "beta": null,
                    "window": window,
                    "time": t - 1,
                    "plane": [0, 1],
                    "budget": POLYGON_BUDGET,
                    "kf_level": s.alpha,
                }),
                "ubb",
            ),
        ),
        _ => {
            // |(G v)_i| ≤ Σ_j |G_ij|·b_v: the half-width bound of each state's innovation. The
            // LP needs positive half-widths: a state without noise gets 10⁻⁶ of the largest.
            let xr: Vec<f64> = p
                .noise
                .g
                .row_iter()
                .map(|r| r.iter().map(|g| g.abs()).sum::<f64>() * p.bound_v)
                .collect();
            let floor = 1e-6 * xr.iter().copied().fold(p.bound_w, f64::max);
            let xr: Vec<f64> = xr.into_iter().map(|x| x.max(floor)).collect();
            (
                bare(|_, _| {}),
                block(
                    serde_json::json!({
                        "estimator": "states",
                        "window": window,
                        "xr_max": xr,
                        "yr_max": vec![p.bound_w; q],
                        "x_bound": X_BOUND_PER_SCALE * record_scale(p),
                        "time": t,
                        "plane": [0, 1],
                        "directions": POLYGON_BUDGET,
                    }),
                    "uniform",
                ),
            )
        }
    };
    let mut v = serde_json::json!({
        "method": m,
        "model": model,
        "data": DataSpec { y: p.y[..t].to_vec(), u: Vec::new() },
        "alpha": s.alpha,
    });
    if let (Some(o), Some(e)) = (v.as_object_mut(), extra.as_object()) {
        for (k, x) in e {
            o.insert(k.clone(), x.clone());
        }
    }
    // The title as its figures would show it (cut at `error::DISPLAY_CHARS`): each derived
    // scenario keeps a copy, and a long title must not be copied six times into the report.
    if let Some(title) = &s.title {
        v["title"] = serde_json::Value::String(format!("{} — {m}", crate::error::displayed(title)));
    }
    super::parse::from_value(&v, "")
}

/// Area of a polygon (the LSCR boundary's shoelace).
fn polygon_area(v: &[[f64; 2]]) -> f64 {
    crate::sets::sign_region::signed_area(v).abs()
}

/// Convex hull (counter-clockwise, Andrew's monotone chain).
fn convex_hull(mut pts: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * pts.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &[f64; 2]>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

fn map2(f: &DMatrix<f64>, p: [f64; 2]) -> [f64; 2] {
    [
        f[(0, 0)] * p[0] + f[(0, 1)] * p[1],
        f[(1, 0)] * p[0] + f[(1, 1)] * p[1],
    ]
}

/// The image F·E of a 2-D ellipse.
fn map_ellipse(f: &DMatrix<f64>, e: &Ellipsoid) -> Ellipsoid {
    let c = DMatrix::from_fn(2, 2, |i, j| e.cov[i][j]);
    let fc = f * c * f.transpose();
    let center = map2(f, [e.center[0], e.center[1]]);
    Ellipsoid::new(&DVector::from_column_slice(&center), &fc, e.radius2)
}

fn box_corners(b: &BoxSet) -> Vec<[f64; 2]> {
    vec![
        [b.lo[0], b.lo[1]],
        [b.hi[0], b.lo[1]],
        [b.hi[0], b.hi[1]],
        [b.lo[0], b.hi[1]],
    ]
}

/// The set of the target state from one method's own report (the module docs say how each
/// paper's set becomes the target's). `truth`: the true target state, to say whether it is
/// inside.
fn extract(
    p: &ComparePrepared,
    m: Method,
    r: &Report,
    truth: Option<[f64; 2]>,
) -> Result<MethodSet> {
    let predict = p.spec.target == Target::Predict;
    let f = p.model.f(1);
    let missing = |what: &str| {
        Error::field(
            format!("report.{}", m.block().unwrap_or("steps")),
            format!("has no {what}"),
        )
    };
    let mut out = MethodSet {
        method: m,
        set: None,
        outline: None,
        area: None,
        holds: None,
        reason: None,
        note: None,
        seconds: None,
        scenario: None,
    };
    match m {
        Method::Kf | Method::Scf => {
            let step = r.steps.last().ok_or_else(|| missing("steps"))?;
            let target = step
                .target
                .as_ref()
                .ok_or_else(|| missing("target region"))?;
            let e = if m == Method::Kf {
                target.kf.clone()
            } else {
                target.scf.clone().ok_or_else(|| {
                    Error::field(
                        "report.steps.target.scf",
                        format!("is absent at t = {}: the ratio matrix is still singular (too few measurements)", step.t),
                    )
                })?
            };
            out.area = Some(e.volume());
            out.holds = truth.map(|x| e.contains(&x));
            out.set = Some(PlaneSet::Ellipse(e));
        }
        Method::Lscr => {
            let l = r.lscr.as_ref().ok_or_else(|| missing("lscr part"))?;
            out.holds = truth.map(|x| l.region.contains(&x));
            out.area = l.bounded.then_some(l.area);
            out.note = Some(format!("M = {}, q = {}", l.m, l.q));
            out.set = Some(PlaneSet::Region {
                loops: l.boundary.clone(),
                bounded: l.bounded,
                window: l.window.clone(),
            });
        }
        Method::Glls => {
            let g = r.glls.as_ref().ok_or_else(|| missing("glls part"))?;
            let (ball, corners) = if predict {
                let corners = box_corners(&g.box_current)
                    .into_iter()
                    .map(|c| map2(f, c))
                    .collect();
                (map_ellipse(f, &g.ball_current), convex_hull(corners))
            } else {
                (g.ball_current.clone(), box_corners(&g.box_current))
            };
            out.area = Some(ball.volume());
            out.holds = truth.map(|x| ball.contains(&x));
            out.note = Some(if predict {
                format!("horizon s = {}; F·ball (no state noise)", g.s)
            } else {
                format!("horizon s = {}", g.s)
            });
            out.set = Some(PlaneSet::Ellipse(ball));
            out.outline = Some(corners);
        }
        Method::Ubb => {
            if !predict {
                return Err(Error::field(
                    "compare.target",
                    "is \"filter\", but Tempo's set is of x(k+1) from y(0 … k): a prediction only (choose \"predict\")",
                ));
            }
            let u = r.ubb.as_ref().ok_or_else(|| missing("ubb part"))?;
            let poly = &u.at.polygon;
            out.area = Some(polygon_area(&poly.vertices));
            out.holds = truth.map(|x| poly.contains(x, 1e-9));
            out.set = Some(PlaneSet::Polygon {
                vertices: poly.vertices.clone(),
            });
            let (lo, hi) = (&u.at.lo, &u.at.hi);
            out.outline = Some(vec![
                [lo[0], lo[1]],
                [hi[0], lo[1]],
                [hi[0], hi[1]],
                [lo[0], hi[1]],
            ]);
            out.note = Some(format!("window {} steps", u.window));
        }
        _ => {
            let w = r.uniform.as_ref().ok_or_else(|| missing("uniform part"))?;
            let poly = w.at.polygon.as_ref().ok_or_else(|| {
                Error::field(
                    "report.uniform.at.polygon",
                    w.at.polygon_absent
                        .clone()
                        .unwrap_or_else(|| "is absent".into()),
                )
            })?;
            let vertices = if predict {
                // F·P ⊕ G·[−b_v, b_v]^p: the corners of the noise box through G.
                let g = &p.noise.g;
                let pcount = g.ncols().min(12);
                let mut pts = Vec::new();
                for mask in 0..(1usize << pcount) {
                    let mut shift = [0.0; 2];
                    for j in 0..pcount {
                        let s = if mask >> j & 1 == 1 {
                            p.bound_v
                        } else {
                            -p.bound_v
                        };
                        shift[0] += g[(0, j)] * s;
                        shift[1] += g[(1, j)] * s;
                    }
                    for &v in &poly.vertices {
                        let fv = map2(f, v);
                        pts.push([fv[0] + shift[0], fv[1] + shift[1]]);
                    }
                }
                convex_hull(pts)
            } else {
                poly.vertices.clone()
            };
            out.area = Some(polygon_area(&vertices));
            out.holds = truth.map(|x| {
                if predict {
                    point_in_convex(&vertices, x, 1e-9)
                } else {
                    poly.contains(x, 1e-9)
                }
            });
            let mut note = vec![format!("window ∂ = {}", w.window)];
            if w.at.extended > 0 {
                note.push(format!(
                    "half-width bounds doubled {}× (the data contradicted them)",
                    w.at.extended
                ));
            }
            if predict {
                note.push("F·P ⊕ G·[−b_v, b_v]".to_string());
            }
            out.note = Some(note.join("; "));
            out.set = Some(PlaneSet::Polygon { vertices });
        }
    }
    Ok(out)
}

impl ComparePrepared {
    fn target_time(&self, t: usize) -> usize {
        t + usize::from(self.spec.target == Target::Predict)
    }

    fn truth(&self, t: usize) -> Option<[f64; 2]> {
        let x = self.x.as_ref()?.get(self.target_time(t) - 1)?;
        Some([x[0], x[1]])
    }

    /// One method's set at t, or the reason it has none.
    fn method_set(&self, m: Method, t: usize, truth: Option<[f64; 2]>) -> MethodSet {
        let clock = CLOCK.get();
        let start = clock.map(|c| c());
        let scenario = derived_scenario(self, m, t);
        let result = scenario
            .as_ref()
            .map_err(Clone::clone)
            .and_then(|s| s.run())
            .and_then(|r| extract(self, m, &r, truth));
        let seconds = clock.zip(start).map(|(c, s)| (c() - s).max(0.0));
        let mut set = result.unwrap_or_else(|e| MethodSet {
            method: m,
            set: None,
            outline: None,
            area: None,
            holds: None,
            reason: Some(e.to_string()),
            note: None,
            seconds: None,
            scenario: None,
        });
        set.seconds = seconds;
        set.scenario = scenario.ok().and_then(|s| serde_json::to_value(s).ok());
        set
    }

    fn at(&self, t: usize) -> Result<CompareAt> {
        if !(2..=self.y.len()).contains(&t) {
            return Err(Error::field(
                "compare.time",
                format!(
                    "must be a whole number from 2 to {} (the record's steps), found {t}",
                    self.y.len()
                ),
            ));
        }
        let truth = self.truth(t);
        Ok(CompareAt {
            t,
            target_time: self.target_time(t),
            truth,
            sets: self
                .methods
                .iter()
                .map(|&m| self.method_set(m, t, truth))
                .collect(),
        })
    }

    fn report(&self) -> Result<Report> {
        let s = &self.scenario;
        let at = self.at(self.time)?;
        let c = CompareReport {
            noise: self.spec.noise,
            target: self.spec.target,
            sigma_v: self.noise.sigma_v,
            sigma_w: self.noise.sigma_w,
            bound_v: self.bound_v,
            bound_w: self.bound_w,
            bound_scale: self.spec.bound_scale,
            steps: self.y.len(),
            first: 2,
            x_true: self
                .x
                .as_ref()
                .map(|x| x.iter().map(|v| v.iter().copied().collect()).collect()),
            rows: self
                .methods
                .iter()
                .map(|&m| row(self, m, s.alpha))
                .collect(),
            at,
        };
        let mut r = Report::of(
            s,
            s.alpha,
            (2, self.model.q()),
            self.time,
            vec![0, 1],
            self.y.clone(),
        );
        r.x_true = c.x_true.clone();
        r.compare = Some(c);
        Ok(r)
    }
}

/// The time cursor: every method's set at any t.
struct CompareCursor(ComparePrepared);

impl Cursor for CompareCursor {
    fn steps(&self) -> RangeInclusive<usize> {
        2..=self.0.y.len()
    }
    fn at(&mut self, t: usize) -> Result<serde_json::Value> {
        detail_value(&self.0.at(t)?)
    }
}

/// Hits per method over a range of runs.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct CompareCounts {
    pub runs: usize,
    /// Per method (in the study's order): runs whose set held the state.
    pub holds: Vec<usize>,
    /// Per method: runs where the method gave no set (its run refused: e.g. bounds the data
    /// contradict). A set that does not exist holds nothing: these count as misses.
    pub no_set: Vec<usize>,
}

impl Tally for CompareCounts {
    fn runs(&self) -> usize {
        self.runs
    }
    /// Each method's hits and runs without a set, and their sum: a run either held the
    /// state, missed it or gave no set, so the sum is a count of runs too.
    fn counts(&self) -> Vec<(String, usize)> {
        let mut c = crate::study::listed_counts("holds", &self.holds);
        c.extend(crate::study::listed_counts("no_set", &self.no_set));
        c.extend(
            self.holds
                .iter()
                .zip(&self.no_set)
                .enumerate()
                .map(|(j, (h, n))| (format!("holds[{j}] + no_set[{j}]"), h.saturating_add(*n))),
        );
        c
    }
    fn add(&mut self, later: &Self) -> std::result::Result<(), String> {
        // The shape is checked even against no runs: the zero counts have the study's.
        if later.holds.len() != self.holds.len() || later.no_set.len() != self.no_set.len() {
            return Err(format!(
                "counts of {} methods, not {}",
                later.holds.len(),
                self.holds.len()
            ));
        }
        crate::study::add_count(&mut self.runs, later.runs, "runs")?;
        crate::study::add_counts(&mut self.holds, &later.holds, "holds", "methods' holds")?;
        crate::study::add_counts(&mut self.no_set, &later.no_set, "no_set", "methods' no_set")?;
        Ok(())
    }
}

/// One method's count beside its promise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MethodCount {
    pub method: Method,
    pub holds: usize,
    pub misses: usize,
    pub no_set: usize,
    pub promise: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub level: Option<f64>,
    /// The 99.9 % binomial band of the count under the promised level.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub band: Option<[usize; 2]>,
    /// The count against the promise, in words.
    pub verdict: String,
}

/// The study's result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CompareStudyReport {
    pub runs: usize,
    pub total: usize,
    pub t: usize,
    pub target_time: usize,
    pub x: [f64; 2],
    /// How the records were drawn given the state.
    pub conditioning: String,
    pub methods: Vec<MethodCount>,
}

/// The compare study: records given the target state, every method's set counted.
struct CompareStudy {
    prepared: ComparePrepared,
    x: [f64; 2],
    rows: Vec<CompareRow>,
    total: usize,
    seed: u64,
    sampler: Option<crate::model::ConditionedSampler>,
}

impl CompareStudy {
    fn new(prepared: ComparePrepared, runs: Option<usize>) -> Result<CompareStudy> {
        let spec = prepared.spec.study.clone().ok_or_else(|| {
            Error::field(
                "compare.study",
                "is missing: give the true state x (and runs, seed) to count",
            )
        })?;
        let x = linalg::vector("compare.study.x", &spec.x, 2)?;
        let total = runs.unwrap_or(spec.runs);
        if !(1..=super::MAX_STUDY_RUNS).contains(&total) {
            return Err(Error::field(
                "compare.study.runs",
                format!(
                    "must be a whole number from 1 to {}, found {total}",
                    super::MAX_STUDY_RUNS
                ),
            ));
        }
        let t = prepared.time;
        let sampler = if prepared.spec.noise == NoiseLaw::Gaussian {
            Some(crate::model::ConditionedSampler::new(
                &prepared.model,
                t + 1,
                &crate::model::Inputs::none(),
                prepared.target_time(t),
            )?)
        } else {
            None
        };
        let rows = prepared
            .methods
            .iter()
            .map(|&m| row(&prepared, m, prepared.scenario.alpha))
            .collect();
        Ok(CompareStudy {
            x: [x[0], x[1]],
            rows,
            total,
            seed: spec.seed,
            sampler,
            prepared,
        })
    }

    /// Run i's record up to y_t and its true target state.
    fn draw(&self, i: usize) -> (Vec<Vec<f64>>, [f64; 2]) {
        let p = &self.prepared;
        let t = p.time;
        let mut rng = study::run_stream(self.seed, i);
        let (xs, ys) = match &self.sampler {
            Some(sampler) => {
                let x_c = DVector::from_column_slice(&self.x);
                let traj = sampler.draw(&p.model, &x_c, &mut rng);
                (traj.x, traj.y)
            }
            None => record(
                &p.model,
                &p.noise,
                p.spec.noise,
                p.spec.bound_sigmas,
                t,
                &mut rng,
            ),
        };
        let x = &xs[p.target_time(t) - 1];
        (
            ys[..t]
                .iter()
                .map(|v| v.iter().copied().collect())
                .collect(),
            [x[0], x[1]],
        )
    }
}

impl Runs for CompareStudy {
    type Tally = CompareCounts;
    type Report = CompareStudyReport;
    fn total(&self) -> usize {
        self.total
    }
    fn seed(&self) -> u64 {
        self.seed
    }
    fn zero(&self) -> CompareCounts {
        let k = self.prepared.methods.len();
        CompareCounts {
            runs: 0,
            holds: vec![0; k],
            no_set: vec![0; k],
        }
    }
    fn run(&mut self, range: std::ops::Range<usize>) -> Result<CompareCounts> {
        let mut c = self.zero();
        let t = self.prepared.time;
        for i in range {
            let (y, truth) = self.draw(i);
            let saved = std::mem::replace(&mut self.prepared.y, y);
            for (j, &m) in self.prepared.methods.iter().enumerate() {
                let s = self.prepared.method_set(m, t, Some(truth));
                match s.holds {
                    Some(true) => c.holds[j] += 1,
                    Some(false) => {}
                    None => c.no_set[j] += 1,
                }
            }
            self.prepared.y = saved;
            c.runs += 1;
        }
        Ok(c)
    }
    fn report(&self, c: &CompareCounts) -> CompareStudyReport {
        let p = &self.prepared;
        let conditioning = if self.sampler.is_some() {
            format!(
                "exact: every record drawn given x_{} at the chosen state (backward representation)",
                p.target_time(p.time)
            )
        } else {
            format!(
                "unconditional: {} noise has no exact draw of the past given a state, so x_1 is drawn from the prior and the truth varies from run to run (the chosen state is not used)",
                p.spec.noise.name()
            )
        };
        let methods = self
            .rows
            .iter()
            .enumerate()
            .map(|(j, row)| {
                let holds = c.holds.get(j).copied().unwrap_or(0);
                let no_set = c.no_set.get(j).copied().unwrap_or(0);
                let misses = c.runs - holds;
                let band = row.level.filter(|_| c.runs > 0).map(|l| {
                    let (lo, hi) = stats::band(c.runs, l);
                    [lo, hi]
                });
                let verdict = match (row.level, band) {
                    (Some(l), _) if l >= 1.0 => {
                        if misses == 0 {
                            "never failed".to_string()
                        } else {
                            format!(
                                "failed {misses} times{}",
                                if row.met {
                                    ""
                                } else {
                                    " (its assumption is violated)"
                                }
                            )
                        }
                    }
                    (Some(_), Some([lo, hi])) => {
                        if holds < lo {
                            "below the 99.9 % band of its promise".to_string()
                        } else if holds > hi && !row.at_least {
                            "above the 99.9 % band of its promise".to_string()
                        } else if holds > hi {
                            "above its level (a lower bound): kept".to_string()
                        } else {
                            "inside the 99.9 % band of its promise".to_string()
                        }
                    }
                    _ => "no probability promised".to_string(),
                };
                MethodCount {
                    method: row.method,
                    holds,
                    misses,
                    no_set,
                    promise: row.promise.clone(),
                    level: row.level,
                    band,
                    verdict,
                }
            })
            .collect();
        CompareStudyReport {
            runs: c.runs,
            total: self.total,
            t: p.time,
            target_time: p.target_time(p.time),
            x: self.x,
            conditioning,
            methods,
        }
    }
}

/// The compare's cost is its methods' own: each derived scenario's estimate on the whole record
/// (what the report and one cursor step cost at most), their terms renamed to the compare's
/// fields (a method's window is `compare.window`, anything else the record's length). A study's
/// run reruns them all on a fresh record. A scenario that cannot be prepared costs nothing
/// here: its validation names the field.
fn work(s: &Scenario, job: Job) -> Work {
    let mut w = Work::default();
    let Ok(p) = s.prepare_compare() else {
        return w;
    };
    let steps_field = s.steps_field();
    for &m in &p.methods {
        let Ok(d) = derived_scenario(&p, m, p.y.len()) else {
            continue;
        };
        let own = d.work(Job::Report);
        for (terms, into) in [
            (own.operations, &mut w.operations),
            (own.bytes, &mut w.bytes),
        ] {
            for mut t in terms {
                let field = if t.field.ends_with(".window") {
                    "compare.window"
                } else {
                    steps_field
                };
                t.sizes = format!("(method \"{m}\": {} {})", t.field, t.sizes);
                t.field = field.to_string();
                if let Job::Study { .. } = job {
                    t.field = "compare.study.runs".to_string();
                    t.advice =
                        "one run of the study reruns every method: fewer steps or methods".into();
                }
                into.push(t);
            }
        }
    }
    w
}

/// Every method on one record (`"method": "compare"`).
pub(crate) struct Compare;

impl MethodScenario for Compare {
    fn steps(&self) -> RangeInclusive<usize> {
        2..=MAX_STEPS
    }
    fn data_shape(&self, s: &Scenario) -> Result<(usize, usize)> {
        let lm = LinearModel::from_spec(&s.model)?;
        Ok((lm.q(), 0))
    }
    fn work(&self, s: &Scenario, job: Job) -> Work {
        work(s, job)
    }
    fn run(&self, s: &Scenario) -> Result<Report> {
        s.prepare_compare()?.report()
    }
    fn cursor(&self, s: &Scenario) -> Result<Option<Box<dyn Cursor>>> {
        Ok(Some(Box::new(CompareCursor(s.prepare_compare()?))))
    }
    fn cursor_steps(&self, report: &Report) -> Option<RangeInclusive<usize>> {
        report.compare.as_ref().map(|c| c.first..=c.steps)
    }
    fn set_at(&self, report: &mut Report, at: serde_json::Value) -> Result<()> {
        let at: CompareAt = detail_of(at)?;
        let c = report.compare.as_mut().ok_or_else(|| {
            Error::field(
                "report.compare",
                "is missing: the report is not a compare report",
            )
        })?;
        report.time = at.t;
        c.at = at;
        Ok(())
    }
    fn table(&self, r: &Report) -> Table {
        // One row per method at the report's time: its set's area and whether it holds the truth.
        let mut table = Table::new(
            ["method", "area", "holds", "level", "assumption_met"]
                .map(String::from)
                .to_vec(),
        );
        let Some(c) = &r.compare else {
            return table;
        };
        for (i, set) in c.at.sets.iter().enumerate() {
            let row = c.rows.get(i);
            table.push(vec![
                Some(i as f64),
                set.area,
                flag(set.holds),
                row.and_then(|r| r.level),
                flag(row.map(|r| r.met)),
            ]);
        }
        table
    }
    fn study(&self, s: &Scenario, runs: Option<usize>) -> Result<Box<dyn Study>> {
        Ok(Box::new(study::Chunked::new(CompareStudy::new(
            s.prepare_compare()?,
            runs,
        )?)))
    }
    fn presets(&self) -> Vec<Preset> {
        presets()
    }
}

// Presets

/// The LSCR paper's cascade (Fig. 1's system) as a compare: under `noise`, a record of 30 steps,
/// the prediction of x₃₁.
pub fn compare_cascade(noise: NoiseLaw) -> Scenario {
    let law = match noise {
        NoiseLaw::Gaussian => "gaussian",
        NoiseLaw::Uniform => "uniform",
        NoiseLaw::Truncated => "truncated",
    };
    let name = match noise {
        NoiseLaw::Gaussian => "Gaussian",
        NoiseLaw::Uniform => "uniform",
        NoiseLaw::Truncated => "truncated Gaussian",
    };
    let (condition, study) = match noise {
        // A far-out x₃₁ (about 3.5 prior standard deviations): Kalman's "on average" promise
        // fails here, SCF's and LSCR's "for every state" hold.
        NoiseLaw::Gaussian => (
            r#", "condition": {"t": 31, "x": [0.35, 1.1]}"#,
            r#", "study": {"x": [0.35, 1.1], "runs": 200, "seed": 1}"#,
        ),
        _ => (
            "",
            r#", "study": {"x": [0.0, 0.0], "runs": 200, "seed": 1}"#,
        ),
    };
    let text = format!(
        r#"{{"method": "compare",
  "title": "Every method on the LSCR cascade ({name} noise)",
  "model": {{"F": [[0.5, 0.0], [1.0, 0.7]], "H": [[0.0, 1.0]], "G": [[1.0], [0.0]],
            "sigma_v2": 0.005, "sigma_w2": 0.005}},
  "simulate": {{"steps": 30, "seed": 5{condition}}},
  "alpha": 0.9,
  "compare": {{"noise": "{law}", "target": "predict", "window": 10{study}}},
  "notes": "The cascade of the LSCR paper's Fig. 1 (σ_v² = σ_w² = 0.005), x₃₁ predicted from y₁ … y₃₀ by every method, each with the parameters its paper needs from the one noise law."}}"#
    );
    Scenario::from_json(&text).expect("the compare preset parses")
}

fn presets() -> Vec<Preset> {
    vec![
        Preset {
            name: "compare-gaussian".into(),
            label: "Compare — every method, Gaussian noise, a far-out state".into(),
            description: "The LSCR cascade with Gaussian noise and x₃₁ fixed far out: the Kalman ellipse misses, SCF and LSCR hold".into(),
            scenario: compare_cascade(NoiseLaw::Gaussian),
        },
        Preset {
            name: "compare-uniform".into(),
            label: "Compare — every method, uniform noise".into(),
            description: "The LSCR cascade with uniform noise within known bounds: the set-membership sets always hold".into(),
            scenario: compare_cascade(NoiseLaw::Uniform),
        },
    ]
}
