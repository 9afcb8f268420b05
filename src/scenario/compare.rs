//! The compare scenario (`"method": "compare"`): one linear system, one record of data, every
//! method's set for the same state in one plane, what each method assumes checked against the
//! noise law that made the record, and a study counting how often each set holds a fixed
//! true state.
//!
//! Nothing here estimates, and nothing here knows a method: every set is the one the
//! method's own scenario gives, and what a method does for a compare is written in its own
//! scenario file, in a section above its presets that implements `CompareMember` (reached
//! through `MethodScenario::compare_member`; `None` keeps a method out). For each member,
//! in its `compare_order`, the compare asks for its assumption and promise (the table's row),
//! its derived scenario (typed: `Scenario::new` with the method's block, its parameters
//! derived from the one noise law, the record's first t rows as `data`), runs that scenario
//! through [`Scenario::run`] exactly as the method's panel would, and asks the member to read
//! the set for the target state out of its report (a [`PlaneSet`]). So a compare set equals
//! its panel's set on the same data (`tests/suite/compare.rs` checks it to 1e-9, natively and
//! in wasm). The plane geometry the members need (hulls, areas, 2×2 maps, Minkowski sums) is
//! [`crate::sets::plane`]'s.
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
//! * Conformal's region is the Kalman ellipse of x_{t+τ} (τ = 1 for the prediction) with the
//!   radius² calibrated on N runs simulated from the model's Gaussian law: under another law
//!   the calibration runs are not exchangeable with the record, and its row says so. Its
//!   promise is on average over runs, like Kalman's over states: at the study's fixed state it
//!   counts what the Kalman region counts, not what SCF's does.
//!
//! The study (`compare.study`: `x`, `runs`, `seed`) fixes the true target state and draws
//! records from their law given it: exactly, by the backward representation, for Gaussian
//! noise ([`crate::model::ConditionedSampler`]); for the other laws no exact conditional
//! sampler exists, so the study counts unconditional coverage (x_1 from the model's prior) and
//! says so in its result. A study's run asks each member only for its verdict
//! (`CompareMember::holds_at`): the report's set by default, or the member's own cheaper path
//! to the same verdict (ubb: the target step's window; uniform_lp: the on-line run to t and the
//! polygon at t), tested run for run against the report's (`tests` below).

use super::budget::{Job, Work};
use super::csv::{flag, Table};
use super::preset::Preset;
use super::{detail_of, detail_value, Cursor, DataSpec, MethodScenario, Report, Scenario};
use crate::error::{Error, Result};
use crate::linalg;
use crate::method::Method;
use crate::model::{normal_vector, LinearModel, MatrixSpec, ModelSpec};
use crate::sets::{BoxSet, Ellipsoid, Loop};
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
    pub(crate) fn name(self) -> &'static str {
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
    /// The methods compared (default: every method that joins a compare (seven with conformal)).
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

/// Most simulated steps or data rows of a compare (each step of the time cursor reruns every
/// method on the rows up to it).
pub const MAX_STEPS: usize = 150;
/// Largest window of the set-membership methods.
pub const MAX_WINDOW: usize = 40;
/// Support LPs of each exact polygon (Tempo's feasible set, Pavelková's consistent states).
pub(crate) const POLYGON_BUDGET: usize = 64;

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

/// Everything a compare needs once: the model, its noise, the bounds, the record and the
/// members compared. A member reads it through the methods below `CompareMember`.
pub(crate) struct ComparePrepared {
    scenario: Scenario,
    spec: CompareSpec,
    model: LinearModel,
    noise: Noise,
    bound_v: f64,
    bound_w: f64,
    members: Vec<Member>,
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
        for (field, v, lo, hi) in [
            ("compare.bound_sigmas", spec.bound_sigmas, 0.5, 10.0),
            ("compare.bound_scale", spec.bound_scale, 0.01, 100.0),
        ] {
            if !(lo..=hi).contains(&v) {
                return Err(Error::field(
                    field,
                    format!(
                        "must be a number from {lo} to {hi}, found {}",
                        crate::error::shown(v)
                    ),
                ));
            }
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
        let members = chosen_members(spec.methods.as_deref())?;
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
            members,
            y: y.iter().map(|v| v.iter().copied().collect()).collect(),
            x,
            time,
        })
    }
}

/// The members of `compare.methods` in its order (default: every member), each named once.
fn chosen_members(methods: Option<&[Method]>) -> Result<Vec<Member>> {
    let all = members();
    let Some(methods) = methods else {
        return Ok(all);
    };
    if methods.is_empty() {
        return Err(Error::field(
            "compare.methods",
            "is empty: name at least one method",
        ));
    }
    let mut chosen = Vec::with_capacity(methods.len());
    for (i, &m) in methods.iter().enumerate() {
        let Some(member) = all.iter().find(|a| a.method == m) else {
            let names: Vec<&str> = all.iter().map(|a| a.method.name()).collect();
            let runs = match names.split_last() {
                Some((last, [])) => last.to_string(),
                Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
                None => String::new(),
            };
            return Err(Error::field(
                format!("compare.methods[{i}]"),
                format!("is \"{m}\": a compare runs {runs}"),
            ));
        };
        if methods[..i].contains(&m) {
            return Err(Error::field(
                format!("compare.methods[{i}]"),
                format!("names \"{m}\" twice"),
            ));
        }
        chosen.push(*member);
    }
    Ok(chosen)
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

/// What a compare asks of a method that joins it. The method's scenario file implements it in
/// a section above its presets and hands it out through
/// [`MethodScenario::compare_member`]; the compare loops over the members it finds there and
/// never asks which method it holds (a method without a member, compare itself, is not
/// compared).
pub(crate) trait CompareMember: Sync {
    /// Where the method stands in a compare's default list, table, sets and study counts
    /// (ascending; ties keep [`Method::ALL`]'s order).
    fn compare_order(&self) -> usize;
    /// What the method assumes of the noise, whether the record's law meets it, and what it
    /// promises (the module docs' table gives the parameters behind it).
    fn assumption(&self, p: &ComparePrepared) -> Assumption;
    /// The method's own scenario on the record's first t rows, its parameters derived from the
    /// noise law: [`ComparePrepared::own_scenario`] with the method's block.
    fn derived_scenario(&self, p: &ComparePrepared, t: usize) -> Result<Scenario>;
    /// The set of the target state read from the method's own report of its derived scenario,
    /// carried to the target by the model the method assumes where its paper's set is of
    /// another time (or an error saying why it has none). `truth`: the true target state, to
    /// say whether the set holds it.
    fn plane_set(
        &self,
        p: &ComparePrepared,
        report: &Report,
        truth: Option<[f64; 2]>,
    ) -> Result<PlaneReading>;
    /// Whether the method's set of the target state holds `truth`: what a study's run counts
    /// (an error: the method gives no set, counted as such). `scenario` is
    /// [`Self::derived_scenario`]'s. The default builds the method's whole report and reads the
    /// set from it, as the report and the cursor do ([`Self::plane_set`]); a member overrides it
    /// with only the work the set at the target time needs, and must give the same verdict
    /// (`compare::tests::the_study_counts_what_the_reports_count`).
    fn holds_at(&self, p: &ComparePrepared, scenario: &Scenario, truth: [f64; 2]) -> Result<bool> {
        let report = scenario.run()?;
        self.plane_set(p, &report, Some(truth))?
            .holds
            .ok_or_else(|| {
                Error::field("compare", "the set could not be checked against the state")
            })
    }
}

/// What [`Scenario::run`] checks of a derived scenario before its method runs (its blocks,
/// its work budget): a member's [`CompareMember::holds_at`] that skips the report checks
/// them first, so it refuses exactly what the report refuses.
pub(crate) fn checked_as_run(s: &Scenario) -> Result<()> {
    s.check_method_blocks()?;
    s.work(Job::Report).check(Job::Report)
}

/// A method's assumption and promise: its row of the compare table without the method.
pub(crate) struct Assumption {
    pub assumes: &'static str,
    /// Why the record's law breaks the assumption, in words (`None`: met).
    pub violated: Option<String>,
    pub promise: &'static str,
    pub level: Option<f64>,
    /// Whether `level` is a lower bound rather than exact.
    pub at_least: bool,
}

/// A method's set for the target state, as its member reads it from the method's report.
pub(crate) struct PlaneReading {
    pub set: PlaneSet,
    /// A second, outer set drawn dashed (an interval box or hull).
    pub outline: Option<Vec<[f64; 2]>>,
    /// Area of the set (`None` when unbounded).
    pub area: Option<f64>,
    /// Whether the set holds the true state (`None` without one).
    pub holds: Option<bool>,
    pub note: Option<String>,
}

/// A method of the compare with what it implements for it.
#[derive(Clone, Copy)]
struct Member {
    method: Method,
    of: &'static dyn CompareMember,
}

/// Every method that joins a compare, in the members' order: what a compare runs when
/// `compare.methods` is not given.
fn members() -> Vec<Member> {
    let mut all: Vec<Member> = Method::ALL
        .into_iter()
        .filter_map(|method| {
            super::make_method(method)
                .compare_member()
                .map(|of| Member { method, of })
        })
        .collect();
    all.sort_by_key(|m| m.of.compare_order());
    all
}

/// The methods a compare runs when `compare.methods` is not given, in its order.
pub fn compared() -> Vec<Method> {
    members().into_iter().map(|m| m.method).collect()
}

/// The table row of one method for the prepared record.
fn row(p: &ComparePrepared, m: Member) -> CompareRow {
    let a = m.of.assumption(p);
    CompareRow {
        method: m.method,
        assumes: a.assumes.to_string(),
        met: a.violated.is_none(),
        violated: a.violated,
        promise: a.promise.to_string(),
        level: a.level,
        at_least: a.at_least,
    }
}

impl MethodSet {
    /// The method's entry before anything is known of its set.
    fn of(method: Method) -> MethodSet {
        MethodSet {
            method,
            set: None,
            outline: None,
            area: None,
            holds: None,
            reason: None,
            note: None,
            seconds: None,
            scenario: None,
        }
    }
}

/// What the members read: the record's law and bounds, the model, the target, and the
/// method's own scenario on the record.
impl ComparePrepared {
    /// Whether the target is the prediction x_{t+1} (else the filtered x_t).
    pub(crate) fn predicts(&self) -> bool {
        self.spec.target == Target::Predict
    }

    /// The compare's probability level α (every method's own level).
    pub(crate) fn alpha(&self) -> f64 {
        self.scenario.alpha
    }

    /// The noise law of the record.
    pub(crate) fn law(&self) -> NoiseLaw {
        self.spec.noise
    }

    /// Whether the bounds were scaled below the noise's own (`compare.bound_scale` < 1).
    pub(crate) fn bounds_below_truth(&self) -> bool {
        self.spec.bound_scale < 1.0
    }

    /// The constant model of the compare.
    pub(crate) fn model(&self) -> &LinearModel {
        &self.model
    }

    /// G of the state noise G·v.
    pub(crate) fn noise_g(&self) -> &DMatrix<f64> {
        &self.noise.g
    }

    /// σ_w, the standard deviation of each output's noise.
    pub(crate) fn sigma_w(&self) -> f64 {
        self.noise.sigma_w
    }

    /// The bounds b_v, b_w the set-membership methods are given (after `bound_scale`).
    pub(crate) fn bounds(&self) -> (f64, f64) {
        (self.bound_v, self.bound_w)
    }

    /// Whether the system has state noise (G·v not identically 0).
    pub(crate) fn has_state_noise(&self) -> bool {
        self.noise.sigma_v > 0.0 && self.noise.g.iter().any(|&g| g != 0.0)
    }

    /// The steps of the record (y_1 … y_T: T).
    pub(crate) fn steps(&self) -> usize {
        self.y.len()
    }

    /// The window of the set-membership methods at time t (`compare.window`, at most t).
    pub(crate) fn window(&self, t: usize) -> usize {
        self.spec.window.min(t)
    }

    /// Why the law breaks an assumption of Gaussian noise, in words (`None`: it is Gaussian).
    pub(crate) fn not_gaussian(&self) -> Option<String> {
        (self.spec.noise != NoiseLaw::Gaussian)
            .then(|| format!("violated: noise not Gaussian ({})", self.spec.noise.name()))
    }

    /// Whether the bounded methods' bounds hold the record's noise, in words when they do not.
    pub(crate) fn bounds_violation(&self) -> Option<String> {
        let s = &self.spec;
        if s.bound_scale < 1.0 {
            return Some(format!(
                "violated: the bounds are {}× the noise's own (b_v = {:.4}, b_w = {:.4})",
                s.bound_scale, self.bound_v, self.bound_w
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

    /// The record's scale: its largest datum, prior mean or noise bound (the unit every set of
    /// the compare has).
    pub(crate) fn record_scale(&self) -> f64 {
        let prior = self.model.x1_mean.amax();
        self.y
            .iter()
            .flatten()
            .fold(self.bound_v.max(self.bound_w).max(prior), |m, v| {
                m.max(v.abs())
            })
    }

    /// The compare's own model block (for the methods that take its noise as it is written).
    pub(crate) fn written_model(&self) -> ModelSpec {
        self.scenario.model.clone()
    }

    /// The model F and H alone (for the methods that take the noise as bounds or variances of
    /// their own).
    pub(crate) fn bare_model(&self) -> ModelSpec {
        ModelSpec {
            f: Some(MatrixSpec::of(self.model.f(1))),
            h: Some(MatrixSpec::of(self.model.h(1))),
            ..ModelSpec::default()
        }
    }

    /// The scenario of `method` on `model` with the record's first t rows as `data`, the
    /// compare's α and its title: a member adds its block.
    pub(crate) fn own_scenario(&self, method: Method, model: ModelSpec, t: usize) -> Scenario {
        let s = &self.scenario;
        let own = Scenario::new(method, model)
            .with_data(DataSpec {
                y: self.y[..t].to_vec(),
                u: Vec::new(),
                t: Vec::new(),
            })
            .with_alpha(s.alpha);
        // The title as its figures would show it (cut at `error::DISPLAY_CHARS`): each derived
        // scenario keeps a copy, and a long title must not be copied six times into the report.
        match &s.title {
            Some(title) => own.with_title(format!("{} — {method}", crate::error::displayed(title))),
            None => own,
        }
    }

    fn target_time(&self, t: usize) -> usize {
        t + usize::from(self.predicts())
    }

    fn truth(&self, t: usize) -> Option<[f64; 2]> {
        let x = self.x.as_ref()?.get(self.target_time(t) - 1)?;
        Some([x[0], x[1]])
    }

    /// One method's set at t, or the reason it has none.
    fn method_set(&self, m: Member, t: usize, truth: Option<[f64; 2]>) -> MethodSet {
        let clock = CLOCK.get();
        let start = clock.map(|c| c());
        let scenario = m.of.derived_scenario(self, t);
        let result = scenario
            .as_ref()
            .map_err(Clone::clone)
            .and_then(|s| s.run())
            .and_then(|r| m.of.plane_set(self, &r, truth));
        let seconds = clock.zip(start).map(|(c, s)| (c() - s).max(0.0));
        let mut set = MethodSet::of(m.method);
        match result {
            Ok(r) => {
                set.set = Some(r.set);
                set.outline = r.outline;
                set.area = r.area;
                set.holds = r.holds;
                set.note = r.note;
            }
            Err(e) => set.reason = Some(e.to_string()),
        }
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
                .members
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
            rows: self.members.iter().map(|&m| row(self, m)).collect(),
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

/// How a study's run reaches each method's verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Path {
    /// The member's [`CompareMember::holds_at`]: only the set at the target time.
    Fast,
    /// The method's whole report, as the compare's report and cursor read it (the tests' oracle
    /// for [`Path::Fast`]).
    #[cfg_attr(not(test), allow(dead_code))]
    Report,
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
        // Without a compare.study block, runs given (the CLI's --runs) stand for the block
        // with seed 0 and the true state at its prior mean m (E x at the target time).
        let spec = match (prepared.spec.study.clone(), runs) {
            (Some(spec), _) => spec,
            (None, Some(runs)) => {
                let target = prepared.target_time(prepared.time);
                let m = prepared
                    .model
                    .moments(target, &crate::model::Inputs::none());
                CompareStudySpec {
                    x: m.mean[target - 1].iter().copied().collect(),
                    runs,
                    seed: 0,
                }
            }
            (None, None) => {
                return Err(Error::field(
                    "compare.study",
                    "is missing: give the true state x (and runs, seed) to count, or a number of runs (the command line's --runs), which counts at the prior mean of the target state with seed 0",
                ))
            }
        };
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
            .members
            .iter()
            .map(|&m| row(&prepared, m))
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

    /// The counts of `range`: each run's record drawn, each member's verdict on it, by the
    /// members' own [`CompareMember::holds_at`] (`Path::Fast`, what the study runs) or read
    /// from the sets the report shows (`Path::Report`, what the fast path is tested against).
    fn counts(&mut self, range: std::ops::Range<usize>, path: Path) -> CompareCounts {
        let mut c = self.zero();
        let t = self.prepared.time;
        for i in range {
            let (y, truth) = self.draw(i);
            let saved = std::mem::replace(&mut self.prepared.y, y);
            for (j, &m) in self.prepared.members.iter().enumerate() {
                let p = &self.prepared;
                let holds = match path {
                    Path::Fast => {
                        m.of.derived_scenario(p, t)
                            .and_then(|s| m.of.holds_at(p, &s, truth))
                            .ok()
                    }
                    Path::Report => p.method_set(m, t, Some(truth)).holds,
                };
                match holds {
                    Some(true) => c.holds[j] += 1,
                    Some(false) => {}
                    None => c.no_set[j] += 1,
                }
            }
            self.prepared.y = saved;
            c.runs += 1;
        }
        c
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
        let k = self.prepared.members.len();
        CompareCounts {
            runs: 0,
            holds: vec![0; k],
            no_set: vec![0; k],
        }
    }
    fn run(&mut self, range: std::ops::Range<usize>) -> Result<CompareCounts> {
        Ok(self.counts(range, Path::Fast))
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
                                "failed {misses_times}{}",
                                if row.met {
                                    ""
                                } else {
                                    " (its assumption is violated)"
                                },
                                misses_times = crate::error::counted(misses, "time", "times")
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
    for &Member { method: m, of } in &p.members {
        let Ok(d) = of.derived_scenario(&p, p.steps()) else {
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
    fn true_noise(&self) -> Option<&'static str> {
        Some(
            "the compare draws its record from compare.noise (its law) and derives what each member assumes from it; make the assumptions wrong with compare.bound_scale",
        )
    }
    fn gaps(&self) -> super::Gaps {
        super::Gaps::Refused("its members (LSCR, GLLS, the uniform LP) need every measurement of the one record they share")
    }
    fn time_index(&self) -> super::TimeIndex {
        super::TimeIndex::NotTime
    }
    fn max_states(&self) -> usize {
        // Every set is drawn in the state plane.
        2
    }
    fn truth_keys(&self) -> &'static [(&'static str, &'static str)] {
        &[(
            "holds",
            "compare: whether each method's set holds the true state",
        )]
    }
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
    fn compare_member(&self) -> Option<&dyn CompareMember> {
        None
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
            menu: "Compare — Gaussian, far-out x".into(),
            description: "The LSCR cascade with Gaussian noise and x₃₁ fixed far out: the Kalman ellipse misses, SCF and LSCR hold".into(),
            scenario: compare_cascade(NoiseLaw::Gaussian),
        },
        Preset {
            name: "compare-uniform".into(),
            label: "Compare — every method, uniform noise".into(),
            menu: "Compare — uniform noise".into(),
            description: "The LSCR cascade with uniform noise within known bounds: the set-membership sets always hold".into(),
            scenario: compare_cascade(NoiseLaw::Uniform),
        },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The study's fast path (each member's `holds_at`: only the set at the target time) gives
    /// run for run the verdict the full path reads from the sets the report shows (each
    /// method's whole report, `plane_set`): over the two presets' 200 runs, bounds below the
    /// truth (where windows turn infeasible: no set), a filtered target (Tempo has no set) and
    /// the truncated law. The native run prints each path's time per run.
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn the_study_counts_what_the_reports_count() {
        let cases = [
            ("gaussian", NoiseLaw::Gaussian, 1.0, Target::Predict, 200),
            ("uniform", NoiseLaw::Uniform, 1.0, Target::Predict, 200),
            (
                "uniform, bounds × 0.7",
                NoiseLaw::Uniform,
                0.7,
                Target::Predict,
                60,
            ),
            (
                "gaussian, bounds × 0.5",
                NoiseLaw::Gaussian,
                0.5,
                Target::Predict,
                60,
            ),
            (
                "uniform, filter",
                NoiseLaw::Uniform,
                1.0,
                Target::Filter,
                30,
            ),
            ("truncated", NoiseLaw::Truncated, 1.0, Target::Predict, 30),
        ];
        for (name, noise, scale, target, runs) in cases {
            let mut s = compare_cascade(noise);
            let c = s.compare.as_mut().expect("compare block");
            c.bound_scale = scale;
            c.target = target;
            let mut study = CompareStudy::new(s.prepare_compare().expect("prepared"), Some(runs))
                .expect("study");
            let (mut fast, mut full) = (study.zero(), study.zero());
            let (mut fast_s, mut full_s) = (0.0, 0.0);
            for i in 0..runs {
                let (a, da) = timed(|| study.counts(i..i + 1, Path::Fast));
                let (b, db) = timed(|| study.counts(i..i + 1, Path::Report));
                assert_eq!(a, b, "{name}: run {i}");
                fast.add(&a).expect("adds");
                full.add(&b).expect("adds");
                fast_s += da;
                full_s += db;
            }
            assert_eq!(fast, full, "{name}");
            assert_eq!(fast.runs, runs);
            eprintln!(
                "compare study, {name}: {runs} runs; per run {:.1} ms full reports, {:.1} ms fast; holds {:?}, no set {:?}",
                1e3 * full_s / runs as f64,
                1e3 * fast_s / runs as f64,
                fast.holds,
                fast.no_set
            );
        }
    }

    /// `f`'s value and its time in seconds (0 on wasm, where the core has no clock).
    fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
        #[cfg(not(target_arch = "wasm32"))]
        {
            let start = std::time::Instant::now();
            let v = f();
            (v, start.elapsed().as_secs_f64())
        }
        #[cfg(target_arch = "wasm32")]
        {
            (f(), 0.0)
        }
    }
}
