//! The `lscr` block of a scenario and the LSCR part of a report (method `"lscr"`).
//!
//! ```json
//! {"method": "lscr",
//!  "model": {"F": [[0.5,0],[1,0.7]], "H": [[0,1]], "G": [[1],[0]], "sigma_v2": 0.005, "sigma_w2": 0.005},
//!  "simulate": {"steps": 30, "seed": 7, "condition": {"t": 31, "x": [0.1, -0.2]}},
//!  "lscr": {"estimate": "predict", "M": 80, "q": 2, "construction": "random", "seed": 1,
//!           "window": {"lo": [-1,-1], "hi": [1,1]}, "resolution": [256, 256],
//!           "probes": [[0,0]], "coverage": {"runs": 2000, "seed": 3}}}
//! ```
//!
//! `simulate.steps` (or the length of `data.y`) is t, the number of measurements; the true
//! state of a simulation is reported at the estimated time (t + 1 for prediction).
//! `simulate.condition` fixes the state at a time (usually the estimated one) and draws the data
//! from their law given it. `M`, `q` default to the choice of [`lscr::choose_m_q`] for `level`
//! (default 0.9, the paper's).
//!
//! The file ends with the method's presets (`// Presets`: the menu entries and their
//! builders), re-exported by [`crate::presets`].

use super::budget::{f, shape, Job, Term, Work};
use super::compare::{Assumption, CompareMember, ComparePrepared, PlaneReading, PlaneSet};
use super::csv::{cells, flag, Table};
use super::preset::Preset;
use super::{
    first_accepted_in, Condition, FirstAccepted, MethodScenario, Report, Scenario, SimulateSpec,
    Source,
};
use crate::error::{Error, Result};
use crate::linalg;
use crate::lscr::{self, Construction, Coverage, Estimator, LscrModel, Options, Target};
use crate::method::Method;
use crate::model::{ConditionedSampler, Inputs, LinearModel, MatrixSpec, ModelSpec};
use crate::sets::{BoxSet, Ellipsoid, GridRegion, LineInterval, Loop, SignRegion};
use crate::study::{self, Chunked, Runs, Study};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::ops::RangeInclusive;

/// Coverage experiment at the fixed true state `simulate.condition.x`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LscrCoverageSpec {
    pub runs: usize,
    #[serde(default)]
    pub seed: u64,
}

/// Which state the region is for (`lscr.estimate`): the regressions (21), (11) and (20).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Estimate {
    /// x_{t+1} from y_1 … y_t.
    #[default]
    Predict,
    /// x_t.
    Filter,
    /// x_i, 1 ≤ i < t (`lscr.index`).
    Smooth,
}

/// The `lscr` block.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LscrSpec {
    /// "predict" (x_{t+1}), "filter" (x_t) or "smooth" (x_index).
    #[serde(default)]
    pub estimate: Estimate,
    /// Smoothing time i, 1 ≤ i < t.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub index: Option<usize>,
    #[serde(rename = "M", default, skip_serializing_if = "Option::is_none")]
    pub m: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub q: Option<usize>,
    /// Target joint level when M and q are not given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub level: Option<f64>,
    #[serde(default = "default_construction")]
    pub construction: Construction,
    /// Seed of the random strings (point 4) or generators (point 4a).
    #[serde(default)]
    pub seed: u64,
    /// Explicit strings "0110…" over the Karhunen–Loève components (overrides M).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strings: Option<Vec<String>>,
    /// Window of the figure and of the raster (2-D, in the plotted components).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub window: Option<BoxSet>,
    /// [width, height] of a membership raster over the window.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resolution: Option<[usize; 2]>,
    /// Points whose membership in every X̂_l and in X̂ is reported.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub probes: Vec<Vec<f64>>,
    /// For n > 2: the point the 2-D slice goes through (default: the BLUE, else least squares).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slice_at: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coverage: Option<LscrCoverageSpec>,
}

fn default_construction() -> Construction {
    Construction::Random
}

/// Membership of one probe point.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Probe {
    pub x: Vec<f64>,
    pub inside_each: Vec<bool>,
    pub inside: bool,
}

/// Coverage counts with the promised levels and 99.9 % binomial bands.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct CoverageReport {
    pub truth: Vec<f64>,
    #[serde(flatten)]
    pub counts: Coverage,
    pub level_each: f64,
    pub level: f64,
    /// 99.9 % band of a Binomial(runs, level_each) count.
    pub band_each: [usize; 2],
    /// 99.9 % band of a Binomial(runs, level) count (the joint count must reach `band[0]`).
    pub band: [usize; 2],
}

/// The LSCR part of a report.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct LscrReport {
    pub estimate: Estimate,
    /// Time of the estimated state.
    pub time: usize,
    /// Number of measurements.
    pub t: usize,
    #[serde(rename = "M")]
    pub m: usize,
    pub q: usize,
    /// 1 − 2q/M (18).
    pub level_each: f64,
    /// 1 − 2qn/M (19).
    pub level: f64,
    pub construction: Construction,
    /// Whether Theorem 3.2 applies (random or group strings).
    pub guaranteed: bool,
    /// F^b and Q′ (σ_v² = 1) of the backward representation (6)–(7).
    pub f_b: Vec<Vec<f64>>,
    pub q_prime: Vec<Vec<f64>>,
    /// Karhunen–Loève eigenvalues D (decreasing).
    pub kl_variances: Vec<f64>,
    pub singular_values: Vec<f64>,
    pub rank: usize,
    /// X̂ in the full state space: g_{i,l}(x) = c − d·x per group l.
    pub region: SignRegion,
    /// A scalar state (n = 1): X̂ exactly, as the open intervals of the line it is made of
    /// ([`SignRegion::intervals_1d`]; an absent end is unbounded). Absent for n ≥ 2.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub intervals: Vec<LineInterval>,
    /// Components drawn ([0, 0] for a scalar state: one axis).
    pub plot: [usize; 2],
    /// Point the 2-D slice goes through (n > 2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slice_at: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_true: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth_inside_each: Option<Vec<bool>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth_inside: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blue: Option<Ellipsoid>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blue_note: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kf: Option<Ellipsoid>,
    /// Directions along which X̂ is invariant (null space of A): unbounded along them.
    pub invariant_directions: Vec<Vec<f64>>,
    /// Unit directions in the plotted plane along which the (sliced) region contains rays.
    pub recession: Vec<[f64; 2]>,
    pub bounded: bool,
    /// The figure's window (given, or fitted to the region, truth and ellipses): a 2-D box, or
    /// for a scalar state one interval of the line.
    pub window: BoxSet,
    /// Exact area of the (sliced) region inside the window (for a scalar state its length).
    pub area: f64,
    /// Boundary of the (sliced) region inside the window.
    pub boundary: Vec<Loop>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub raster: Option<GridRegion>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub probes: Vec<Probe>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coverage: Option<CoverageReport>,
    /// The strings h_1..h_{M−1} as "0110…" over the KL components.
    pub strings: Vec<String>,
}

/// A validated LSCR scenario.
pub struct LscrPrepared {
    pub estimator: Estimator,
    pub spec: LscrSpec,
    pub y: Vec<f64>,
    /// The simulated state at the estimated time.
    pub x_true: Option<Vec<f64>>,
    pub plot: [usize; 2],
    /// The model the simulation and the coverage experiment draw from (`simulate.true_noise`:
    /// the model with σ_v², σ_w² scaled); the BLUE and Kalman ellipses assume the model's.
    pub truth: LinearModel,
}

impl LscrSpec {
    fn options(&self, n: usize, t: usize) -> Result<Options> {
        let target = match (self.estimate, self.index) {
            (Estimate::Predict, None) => Target::Predict,
            (Estimate::Filter, None) => Target::Filter,
            (Estimate::Smooth, Some(i)) if (1..t).contains(&i) => Target::Smooth(i),
            (Estimate::Smooth, Some(i)) => {
                return Err(Error::field(
                    "lscr.index",
                    format!(
                        "must be a whole number from 1 to {} (smoothing estimates x_i with i < t = {t}), found {i}",
                        t - 1
                    ),
                ))
            }
            (Estimate::Smooth, None) => {
                return Err(Error::field(
                    "lscr.index",
                    "is needed for smoothing: the time i < t of the state",
                ))
            }
            (Estimate::Predict | Estimate::Filter, Some(_)) => {
                return Err(Error::field(
                    "lscr.index",
                    "is only used with \"estimate\": \"smooth\"",
                ))
            }
        };
        let (m, q) = match (self.m, self.q, self.level) {
            (Some(m), Some(q), None) => (m, q),
            (None, None, level) => lscr::choose_m_q(level.unwrap_or(0.9), n, self.construction)?,
            (Some(m), None, None) => (m, 1),
            // Explicit strings fix M themselves.
            (None, Some(q), None) if self.strings.is_some() => (0, q),
            (None, Some(_), None) => return Err(Error::field("lscr.M", "is needed with q")),
            (_, _, Some(_)) => {
                return Err(Error::field(
                    "lscr.level",
                    "chooses M and q: give either level or M and q",
                ))
            }
        };
        if let Some(s) = &self.strings {
            if s.is_empty() {
                return Err(Error::field("lscr.strings", "is empty"));
            }
        }
        Ok(Options {
            target,
            m,
            q,
            construction: self.construction,
            seed: self.seed,
            strings: self.strings.clone(),
        })
    }
}

/// The record y_1 … y_t (and the state at τ) drawn from `truth`: the model's linear form with
/// its noise scaled by `simulate.true_noise` (the region assumes no variance; the BLUE and
/// Kalman ellipses keep the model's).
fn simulate(
    model: &LscrModel,
    truth: &LinearModel,
    s: &SimulateSpec,
    t: usize,
    tau: usize,
) -> Result<(Vec<f64>, Vec<f64>)> {
    if !s.u.is_empty() {
        return Err(Error::field(
            "simulate.u",
            "is not used by LSCR (no inputs)",
        ));
    }
    let n = model.f.nrows();
    let mut rng = ChaCha8Rng::seed_from_u64(s.seed);
    let traj = match &s.condition {
        None => truth.simulate(t.max(tau), &Inputs::none(), None, &mut rng),
        Some(c) => {
            // The condition fixes a state of the simulated run: one of x_1 … x_max(t, τ). A
            // later time would only lengthen the simulation (t = 10⁹ asked for 32 GB).
            let steps = t.max(tau);
            if !(1..=steps).contains(&c.t) {
                return Err(Error::field(
                    "simulate.condition.t",
                    format!(
                        "must be a whole number from 1 to {steps} (a time of the simulated run: the data length t or the estimated time), found {}",
                        c.t
                    ),
                ));
            }
            let xc = linalg::vector("simulate.condition.x", &c.x, n)?;
            ConditionedSampler::new(truth, steps, &Inputs::none(), c.t)
                .map_err(|e| Error::field("simulate.condition.t", e.message))?
                .draw(truth, &xc, &mut rng)
        }
    };
    let y: Vec<f64> = traj.y[..t].iter().map(|v| v[0]).collect();
    if !y.iter().all(|v| v.is_finite()) {
        return Err(Error::field(
            "simulate.steps",
            "the simulated data overflow double precision",
        ));
    }
    Ok((y, traj.x[tau - 1].iter().copied().collect()))
}

/// LSCR's precision boundary ([`crate::precision`]): each of the M·n sign tests of (17) is a
/// combination of the t Karhunen–Loève components s_k = u_kᵀ(y − Φx), whose noise standard
/// deviations are √λ_k, λ_k = σ_v² D_k + σ_w² (Lemma 3.1). The data y (and the true state x̄ a
/// study conditions on) set the magnitude; the smallest √λ_k of a noisy component sets the scale.
fn lscr_resolution(
    scenario: &Scenario,
    estimator: &Estimator,
    y: &[f64],
    x_true: Option<&[f64]>,
) -> Result<()> {
    let lam = estimator
        .problem
        .noise_variances(estimator.model.sigma_v2, estimator.model.sigma_w2);
    let top = lam.max();
    let smallest = lam
        .iter()
        .copied()
        .filter(|&v| v > 1e-12 * top)
        .fold(f64::INFINITY, f64::min);
    let data = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let truth = x_true.map_or(0.0, |x| x.iter().fold(0.0_f64, |m, v| m.max(v.abs())));
    let field = if scenario.data.is_some() {
        "data.y"
    } else if scenario
        .simulate
        .as_ref()
        .is_some_and(|s| s.condition.is_some())
    {
        "simulate.condition.x"
    } else {
        "simulate.steps"
    };
    crate::precision::Resolution {
        field,
        what: "the data y",
        magnitude: data.max(truth),
        noise: smallest.sqrt(),
        noise_name: "σ, the smallest noise standard deviation of a Karhunen–Loève component",
        combined: y.len(),
        tests: estimator.strings.m() * estimator.problem.n(),
        method: "LSCR",
    }
    .check()
}

impl Scenario {
    /// Validate an LSCR scenario and produce its data.
    pub fn prepare_lscr(&self) -> Result<LscrPrepared> {
        let spec = self.block(&self.lscr, "estimate, M, q, …")?.clone();
        let model = LscrModel::from_spec(&self.model)?;
        let n = model.f.nrows();
        let source = self.source(&Lscr)?;
        let t = source.steps();
        if t < n {
            return Err(Error::field(
                source.steps_field(),
                format!(
                    "gives t = {t_measurements}: LSCR needs t ≥ n = {n}",
                    t_measurements = crate::error::counted(t, "measurement", "measurements")
                ),
            ));
        }
        let options = spec.options(n, t)?;
        let tau = options.target.time(t);
        let truth = self.true_model(&model.linear)?;
        let (y, x_true) = match source {
            Source::Data(d) => {
                if !d.u.is_empty() {
                    return Err(Error::field("data.u", "is not used by LSCR (no inputs)"));
                }
                let y = source.measurements(1)?.iter().map(|v| v[0]).collect();
                (y, None)
            }
            Source::Simulate(s) => {
                let (y, x) = simulate(&model, &truth, s, t, tau)?;
                (y, Some(x))
            }
        };
        let plot = match &self.plot {
            // A scalar state: one axis, the region a union of intervals on it.
            None if n == 1 => [0, 0],
            Some(_) if n == 1 => return Err(Error::field(
                "plot",
                "must be absent for a scalar state (n = 1): its region is drawn on the one axis x",
            )),
            None => [0, 1],
            Some(p) if p.len() == 2 && p[0] < n && p[1] < n && p[0] != p[1] => [p[0], p[1]],
            Some(_) => {
                return Err(Error::field(
                    "plot",
                    format!("must name two distinct state components below n = {n}"),
                ))
            }
        };
        let estimator = Estimator::new(&model, t, &options)?;
        lscr_resolution(self, &estimator, &y, x_true.as_deref())?;
        for (k, p) in spec.probes.iter().enumerate() {
            linalg::vector(&format!("lscr.probes[{k}]"), p, n)?;
        }
        if let Some(p) = &spec.slice_at {
            linalg::vector("lscr.slice_at", p, n)?;
        }
        if let Some(w) = &spec.window {
            if n == 1 {
                let ok = w.lo.len() == 1
                    && w.hi.len() == 1
                    && w.lo[0].is_finite()
                    && w.hi[0].is_finite()
                    && w.lo[0] < w.hi[0];
                if !ok {
                    return Err(Error::field(
                        "lscr.window",
                        "must be one finite interval {\"lo\": [a], \"hi\": [b]} with a < b: the state is scalar (n = 1)",
                    ));
                }
            } else {
                SignRegion {
                    dim: 2,
                    q: 1,
                    groups: vec![],
                }
                .raster(w, 1, 1)
                .map_err(|e| Error::field("lscr.window", e.message))?;
            }
        }
        if let (Some(_), 1) = (spec.resolution, n) {
            return Err(Error::field(
                "lscr.resolution",
                "is the size of the plane's membership raster: a scalar state's region (n = 1) is given exactly as intervals of the line (report.lscr.intervals); remove it",
            ));
        }
        if let Some([w, h]) = spec.resolution {
            if w == 0 || h == 0 || w > 4096 || h > 4096 {
                return Err(Error::field(
                    "lscr.resolution",
                    "must be [width, height] with 1 to 4096 pixels each",
                ));
            }
        }
        if spec.coverage.is_some()
            && self
                .simulate
                .as_ref()
                .and_then(|s| s.condition.as_ref())
                .is_none()
        {
            return Err(Error::field(
                "simulate.condition",
                "is needed by lscr.coverage: the experiment fixes the true state x̄ and draws the data given it",
            ));
        }
        Ok(LscrPrepared {
            estimator,
            spec,
            y,
            x_true,
            plot,
            truth,
        })
    }

    /// A chunked coverage experiment for the scenario's conditioned true state.
    pub fn lscr_experiment(&self) -> Result<lscr::Experiment> {
        self.lscr_experiment_with(None)
    }

    /// The coverage experiment with `runs` runs. Without an `lscr.coverage` block, `runs`
    /// given (the CLI's `--runs`, [`Scenario::study`]) stands for the block with seed 0, and
    /// the true state is `simulate.condition`'s when there is one, else x_τ = 0, the mean of
    /// the stationary state LSCR assumes (Assumption 2).
    fn lscr_experiment_with(&self, runs: Option<usize>) -> Result<lscr::Experiment> {
        let p = self.prepare_lscr()?;
        let (c, defaulted) = match (p.spec.coverage.clone(), runs) {
            (Some(c), runs) => (
                LscrCoverageSpec {
                    runs: runs.unwrap_or(c.runs),
                    ..c
                },
                false,
            ),
            (None, Some(runs)) => (LscrCoverageSpec { runs, seed: 0 }, true),
            (None, None) => return Err(Error::field("lscr.coverage", "is missing (runs, seed)")),
        };
        let tau = p.estimator.problem.regression.target.time(p.y.len());
        let given = self.simulate.as_ref().and_then(|s| s.condition.as_ref());
        let x = match given {
            Some(cond) if cond.t != tau => {
                return Err(Error::field(
                    "simulate.condition.t",
                    format!(
                        "must be the estimated time {tau} for the coverage experiment, found {}",
                        cond.t
                    ),
                ))
            }
            Some(cond) => cond.x.clone(),
            None if defaulted => vec![0.0; p.estimator.problem.n()],
            None => self
                .condition("lscr.coverage needs the fixed true state")?
                .x
                .clone(),
        };
        lscr::Experiment::new(p.estimator, &x, c.runs, c.seed)?.with_truth(&p.truth)
    }
}

/// The 2-D region drawn: X̂ itself (n = 2, axes in order) or its slice through `at`.
pub fn plane_region(
    region: &SignRegion,
    plot: [usize; 2],
    at: Option<&[f64]>,
) -> Result<SignRegion> {
    match at {
        Some(p) => region.slice(p, plot),
        None if plot == [0, 1] => Ok(region.clone()),
        None => region.slice(&vec![0.0; region.dim], plot),
    }
}

/// A window showing the whole region when it is bounded (the box of every vertex of the line
/// arrangement contains all cells, so the boundary found there is the full one), plus the
/// truth and the ellipses.
fn fit_window(region: &SignRegion, extra: &[BoxSet], bounded: bool) -> Result<(BoxSet, Vec<Loop>)> {
    let lines: Vec<(f64, [f64; 2])> = region
        .groups
        .iter()
        .flat_map(|g| g.c.iter().zip(&g.d).map(|(&c, d)| (c, [d[0], d[1]])))
        .filter(|(_, d)| d[0] != 0.0 || d[1] != 0.0)
        .collect();
    let mut big = BoxSet {
        lo: vec![f64::INFINITY; 2],
        hi: vec![f64::NEG_INFINITY; 2],
    };
    for a in 0..lines.len() {
        for b in a + 1..lines.len() {
            let ((c1, d1), (c2, d2)) = (lines[a], lines[b]);
            let det = d1[0] * d2[1] - d1[1] * d2[0];
            if det.abs() > 1e-12 * (d1[0].hypot(d1[1]) * d2[0].hypot(d2[1])) {
                let x = (c1 * d2[1] - c2 * d1[1]) / det;
                let y = (d1[0] * c2 - d2[0] * c1) / det;
                // The box of the vertices, kept as they come: (nM)²/2 of them would fill
                // gigabytes as a list.
                if x.is_finite() && y.is_finite() {
                    for (k, v) in [x, y].into_iter().enumerate() {
                        big.lo[k] = big.lo[k].min(v);
                        big.hi[k] = big.hi[k].max(v);
                    }
                }
            }
        }
    }
    let mut win: Option<BoxSet> = None;
    let mut loops = Vec::new();
    if bounded && big.lo[0].is_finite() {
        let big = big.padded(0.01);
        loops = region.boundary(&big)?;
        let mut b = BoxSet {
            lo: vec![f64::INFINITY; 2],
            hi: vec![f64::NEG_INFINITY; 2],
        };
        for lp in &loops {
            for p in &lp.points {
                for k in 0..2 {
                    b.lo[k] = b.lo[k].min(p[k]);
                    b.hi[k] = b.hi[k].max(p[k]);
                }
            }
        }
        if b.lo[0].is_finite() {
            win = Some(b);
        }
    }
    for e in extra {
        win = Some(match win {
            Some(w) => w.union(e),
            None => e.clone(),
        });
    }
    let mut w = win
        .unwrap_or(BoxSet {
            lo: vec![-1.0, -1.0],
            hi: vec![1.0, 1.0],
        })
        .padded(0.08);
    // Never degenerate: at least 1e-6 of the larger side, or 1 when everything is a point.
    let side = (w.hi[0] - w.lo[0]).max(w.hi[1] - w.lo[1]).max(1e-300);
    for k in 0..2 {
        let need = (side * 0.05).max(if side < 1e-12 { 1.0 } else { 0.0 });
        if w.hi[k] - w.lo[k] < need {
            let mid = 0.5 * (w.hi[k] + w.lo[k]);
            w.lo[k] = mid - need / 2.0;
            w.hi[k] = mid + need / 2.0;
        }
    }
    Ok((w, loops))
}

/// The part of an ellipse the figure shows: its projection for n = 2, for n > 2 its slice
/// through the region's slice point (the figure draws slices, so projections would only
/// inflate the window).
fn ellipse_box(e: &Ellipsoid, plot: [usize; 2], slice_at: Option<&[f64]>) -> Option<BoxSet> {
    match slice_at {
        None => e.project(&plot).ok().map(|p| p.bounding_box()),
        Some(point) => e
            .slice(&plot, point)
            .ok()
            .flatten()
            .map(|p| p.bounding_box()),
    }
}

/// What the figure takes from the region besides the region itself ([`LscrReport`]'s fields
/// of the same names).
struct Drawn {
    recession: Vec<[f64; 2]>,
    bounded: bool,
    window: BoxSet,
    area: f64,
    loops: Vec<Loop>,
    raster: Option<GridRegion>,
    intervals: Vec<LineInterval>,
}

impl LscrPrepared {
    /// The report.
    pub fn report(&self) -> Result<LscrReport> {
        let est = &self.estimator;
        let n = est.problem.n();
        let t = self.y.len();
        let target = est.problem.regression.target;
        let s = est.problem.s(&self.y);
        let region = est.problem.region(&s, &est.strings, est.q);
        let (level_each, level) = est.levels();
        let blue = est.blue(&self.y);
        let kf = est.kalman(&self.y);
        // Least-squares point (minimum norm): the slice's default when there is no BLUE.
        let ls: Vec<f64> = est
            .problem
            .kl
            .a
            .clone()
            .pseudo_inverse(1e-12)
            .map(|p| (p * &s).iter().copied().collect())
            .unwrap_or_else(|_| vec![0.0; n]);
        let slice_at = if n > 2 {
            Some(
                self.spec
                    .slice_at
                    .clone()
                    .or_else(|| blue.as_ref().map(|b| b.center.clone()))
                    .unwrap_or_else(|| ls.clone()),
            )
        } else {
            None
        };
        let Drawn {
            recession,
            bounded,
            window,
            area,
            loops,
            raster,
            intervals,
        } = if n == 1 {
            self.line_parts(&region, [&blue, &kf], &ls)?
        } else {
            self.plane_parts(&region, [&blue, &kf], &ls, slice_at.as_deref())?
        };
        let probes = self
            .spec
            .probes
            .iter()
            .map(|p| {
                let mask = region.excluded(p);
                Probe {
                    x: p.clone(),
                    inside_each: (0..n).map(|l| mask & (1 << l.min(31)) == 0).collect(),
                    inside: mask == 0,
                }
            })
            .collect();
        let (truth_inside_each, truth_inside) = match &self.x_true {
            Some(x) => {
                let mask = region.excluded(x);
                (
                    Some((0..n).map(|l| mask & (1 << l.min(31)) == 0).collect()),
                    Some(mask == 0),
                )
            }
            None => (None, None),
        };
        let b = &est.problem.regression.backward;
        Ok(LscrReport {
            estimate: self.spec.estimate,
            time: target.time(t),
            t,
            m: est.strings.m(),
            q: est.q,
            level_each,
            level,
            construction: est.strings.construction,
            guaranteed: est.guaranteed(),
            f_b: linalg::to_rows(&b.f_b),
            q_prime: linalg::to_rows(&b.v_b),
            kl_variances: est.problem.kl.d.iter().copied().collect(),
            singular_values: est.problem.kl.singular.clone(),
            rank: est.problem.kl.rank,
            invariant_directions: region.invariant_directions(),
            region,
            intervals,
            plot: self.plot,
            slice_at,
            x_true: self.x_true.clone(),
            truth_inside_each,
            truth_inside,
            blue_note: est.blue.as_ref().err().cloned(),
            blue,
            kf,
            recession,
            bounded,
            window,
            area,
            boundary: loops,
            raster,
            probes,
            coverage: None,
            strings: est.strings.texts(),
        })
    }

    /// What a figure of the plane takes from the region (n ≥ 2): its recession directions, the
    /// window, the boundary loops in it, their area and the raster.
    fn plane_parts(
        &self,
        region: &SignRegion,
        ellipses: [&Option<Ellipsoid>; 2],
        ls: &[f64],
        slice_at: Option<&[f64]>,
    ) -> Result<Drawn> {
        let plane = plane_region(region, self.plot, slice_at)?;
        let recession = plane.recession_2d()?;
        let bounded = recession.is_empty();
        let mut extra: Vec<BoxSet> = Vec::new();
        if let Some(x) = &self.x_true {
            extra.push(BoxSet::point(&[x[self.plot[0]], x[self.plot[1]]]));
        }
        for e in ellipses.into_iter().flatten() {
            extra.extend(ellipse_box(e, self.plot, slice_at));
        }
        if extra.is_empty() || !bounded {
            extra.push(BoxSet::point(&[ls[self.plot[0]], ls[self.plot[1]]]));
        }
        let (window, loops) = match &self.spec.window {
            Some(w) => (w.clone(), plane.boundary(w)?),
            None => {
                let (w, loops) = fit_window(&plane, &extra, bounded)?;
                if bounded && !loops.is_empty() {
                    (w, loops)
                } else {
                    let l = plane.boundary(&w)?;
                    (w, l)
                }
            }
        };
        let area: f64 = loops
            .iter()
            .map(|l| crate::sets::sign_region::signed_area(&l.points))
            .sum();
        // Outer loops run counter-clockwise and holes clockwise, so the sum is X̂'s area: a
        // negative sum means rounding broke the loops, and is never shown as an area.
        if area < 0.0 || !area.is_finite() {
            return Err(Error::field(
                "lscr.window",
                format!(
                    "holds a region whose boundary double precision cannot resolve (its loops sum to an area of {area:.3e}): \
                     choose a window nearer the region or data nearer the origin"
                ),
            ));
        }
        let raster = match self.spec.resolution {
            Some([w, h]) => Some(plane.raster(&window, w, h)?),
            None => None,
        };
        Ok(Drawn {
            recession,
            bounded,
            window,
            area,
            loops,
            raster,
            intervals: Vec::new(),
        })
    }

    /// The same for a scalar state (n = 1): X̂ as exact intervals of the line
    /// ([`SignRegion::intervals_1d`]), the window one interval around the finite ends, the
    /// truth and the BLUE and Kalman intervals (the ellipses of one dimension), and the length
    /// of X̂ inside it. Unbounded towards −∞ or +∞: the recession direction [−1, 0] or [1, 0].
    fn line_parts(
        &self,
        region: &SignRegion,
        ellipses: [&Option<Ellipsoid>; 2],
        ls: &[f64],
    ) -> Result<Drawn> {
        let intervals = region.intervals_1d()?;
        let mut recession = Vec::new();
        if intervals.first().is_some_and(|i| i.lo.is_none()) {
            recession.push([-1.0, 0.0]);
        }
        if intervals.last().is_some_and(|i| i.hi.is_none()) {
            recession.push([1.0, 0.0]);
        }
        let bounded = recession.is_empty();
        let window = match &self.spec.window {
            Some(w) => w.clone(),
            None => {
                let mut points: Vec<f64> = intervals
                    .iter()
                    .flat_map(|i| [i.lo, i.hi])
                    .flatten()
                    .collect();
                points.extend(self.x_true.iter().flatten());
                for e in ellipses.into_iter().flatten() {
                    let b = e.bounding_box();
                    points.extend([b.lo[0], b.hi[0]]);
                }
                if points.is_empty() || !bounded {
                    points.push(ls[0]);
                }
                let lo = points.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = points.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                // An unbounded side gets a third of the window to show that it goes on.
                let span = (hi - lo).max(1e-6 * lo.abs().max(hi.abs())).max(1e-300);
                let pad = |open: bool| if open { 0.35 * span } else { 0.08 * span };
                let lo = lo - pad(recession.contains(&[-1.0, 0.0]));
                let hi = hi + pad(recession.contains(&[1.0, 0.0]));
                let (lo, hi) = if hi - lo > 0.0 {
                    (lo, hi)
                } else {
                    (lo - 1.0, hi + 1.0)
                };
                BoxSet {
                    lo: vec![lo],
                    hi: vec![hi],
                }
            }
        };
        let (a, b) = (window.lo[0], window.hi[0]);
        let area = intervals
            .iter()
            .map(|i| {
                let (lo, hi) = i.ends();
                (hi.min(b) - lo.max(a)).max(0.0)
            })
            .sum();
        Ok(Drawn {
            recession,
            bounded,
            window,
            area,
            loops: Vec::new(),
            raster: None,
            intervals,
        })
    }

    /// Run the scenario's coverage experiment to the end (CLI, tests).
    pub fn coverage(&self, truth: &[f64]) -> Result<CoverageReport> {
        let c = self
            .spec
            .coverage
            .clone()
            .ok_or_else(|| Error::field("lscr.coverage", "is missing"))?;
        let e = lscr::Experiment::new(self.estimator.clone(), truth, c.runs, c.seed)?
            .with_truth(&self.truth)?;
        let mut runs = Chunked::new(LscrStudy(e));
        study::run_to_end(&mut runs, 1000, |_, _| {})?;
        Ok(runs.report())
    }
}

/// Counts with their promised levels and 99.9 % bands.
pub fn coverage_report(est: &Estimator, truth: &[f64], counts: Coverage) -> CoverageReport {
    let (level_each, level) = est.levels();
    let (a, b) = crate::stats::band(counts.runs, level_each);
    let (c, d) = crate::stats::band(counts.runs, level.max(0.0));
    CoverageReport {
        truth: truth.to_vec(),
        counts,
        level_each,
        level,
        band_each: [a, b],
        band: [c, d],
    }
}

/// LSCR (Weyer & Campi): the `lscr` block, the region report and the coverage experiment.
pub(crate) struct Lscr;

/// LSCR's step (points 2–6 of the construction, LSCR paper Section III): the sign-perturbed
/// sums g_{i,l}(x) at one point x, from the report's region (the functions the region, its
/// boundary and `truth_inside` are read from, evaluated as [`SignRegion::contains`] does), the
/// reference g_{0,l} ≡ 0's rank among them, the rule with q and the verdict.
fn explain_lscr(
    report: &Report,
    t: Option<usize>,
    point: Option<&[f64]>,
) -> Result<super::StepExplanation> {
    use super::explain::{check_point, check_step, StepValue as V};
    let l = report
        .lscr
        .as_ref()
        .ok_or_else(|| Error::field("report.lscr", "has no lscr part"))?;
    if let Some(t) = t {
        // LSCR's report is about one data length: its step is that one.
        check_step(t, l.t..=l.t)?;
    }
    let r = &l.region;
    let n = r.dim;
    let x: Vec<f64> = match point {
        Some(p) if p.len() == n => p.to_vec(),
        Some(p) if p.len() == 2 && n >= 2 => {
            // A point of the figure's plane: the other components at the section's point.
            let mut x = l.slice_at.clone().unwrap_or_else(|| vec![0.0; n]);
            x[l.plot[0]] = p[0];
            x[l.plot[1]] = p[1];
            x
        }
        Some(p) => {
            return Err(Error::field(
                "explain.x",
                if n == 1 {
                    format!("has {} components: the state is scalar, give one", p.len())
                } else {
                    format!(
                        "has {}: give n = {n} or the plane's 2",
                        crate::error::counted(p.len(), "component", "components")
                    )
                },
            ))
        }
        None => l
            .blue
            .as_ref()
            .map(|b| b.center.clone())
            .or_else(|| l.slice_at.clone())
            .ok_or_else(|| {
                Error::field(
                    "explain.x",
                    "is needed: the report has no BLUE centre to evaluate the sums at",
                )
            })?,
    };
    check_point(&x)?;
    let mut out = super::StepExplanation {
        method: "lscr".into(),
        paper: "Weyer, Campi, Prediction, filtering and smoothing using LSCR (LSCR paper)".into(),
        t: l.t,
        point: Some(x.clone()),
        title: format!(
            "The sign-perturbed sums at one point, for x{} from y₁ … y{}",
            super::subscript(l.time),
            super::subscript(l.t)
        ),
        rows: Vec::new(),
    };
    out.row(
        "point",
        "",
        r"x",
        V::Vector(x.clone()),
        "the clicked point (or the BLUE centre) where the sums are evaluated",
    );
    out.row(
        "prediction errors",
        "point 2",
        r"\epsilon_k(x) = s_k - a_k x",
        V::Text(format!("k = 1, …, {}", l.t)),
        "s and A from the backward representation and the Karhunen–Loève transform (14)–(16)",
    );
    let mut inside_all = true;
    for (i, _) in r.groups.iter().enumerate() {
        let vals = r.values(i, &x);
        let pos = vals.iter().filter(|v| **v > 0.0).count();
        let neg = vals.iter().filter(|v| **v < 0.0).count();
        let inside = pos >= r.q && neg >= r.q;
        inside_all &= inside;
        let li = i + 1;
        out.row(
            &format!("sums of group l = {li}"),
            "point 4",
            &format!(r"g_{{i,{li}}}(x) = \sum_{{k=1}}^{{t}} h_{{i,k}}\,\epsilon_k(x)\,u_{{a,{li},k}},\; i = 1,\dots,M-1"),
            V::Vector(vals),
            format!("{} perturbed sums; the reference g₀ ≡ 0", r.groups[i].c.len()),
        );
        out.row(
            &format!("rank of the reference, l = {li}"),
            "point 5",
            &format!(r"\#\{{i : g_{{i,{li}}}(x) < 0\}} + 1"),
            V::Scalar((neg + 1) as f64),
            format!("{pos} sums above 0, {neg} below, of M = {}", l.m),
        );
        out.row(
            &format!("verdict for X̂{}", super::subscript(li)),
            "point 5, (18)",
            &format!(r"\#\{{g_{{i,{li}}} > 0\}} \ge q \;\wedge\; \#\{{g_{{i,{li}}} < 0\}} \ge q"),
            V::Text(if inside { "in".into() } else { "out".into() }),
            format!(
                "q = {}: 0 is neither among the q largest nor the q smallest",
                r.q
            ),
        );
    }
    out.row(
        "q",
        "point 5",
        r"q \in [1, M/2n]",
        V::Scalar(r.q as f64),
        format!(
            "M = {}, n = {n}: each X̂ₗ has probability 1 − 2q/M = {} (18)",
            l.m, l.level_each
        ),
    );
    out.row(
        "verdict",
        "(17), (19)",
        r"x \in \hat X = \bigcap_{l=1}^n \hat X_l",
        V::Text(if inside_all {
            "in the region".into()
        } else {
            "out of the region".into()
        }),
        format!(
            "the region has probability at least 1 − 2qn/M = {} (19)",
            l.level
        ),
    );
    Ok(out)
}

impl MethodScenario for Lscr {
    /// Honoured: the record and `lscr.coverage` draw from the true noise; the region assumes no
    /// variances (Theorem 3.2 holds at any scale), the BLUE and Kalman ellipses keep the model's.
    fn true_noise(&self) -> Option<&'static str> {
        None
    }
    fn gaps(&self) -> super::Gaps {
        super::Gaps::Refused("its sign-perturbed sums (17) run over every measurement of the record: the regression (11), (20)–(21) has no term for a missing y, and the exact level of Theorem 3.2 counts all t of them")
    }
    fn time_index(&self) -> super::TimeIndex {
        super::TimeIndex::OneBased
    }
    fn max_states(&self) -> usize {
        crate::lscr::MAX_STATES
    }
    fn truth_keys(&self) -> &'static [(&'static str, &'static str)] {
        &[
            ("truth_inside", "lscr: whether X̂ holds the true state"),
            ("truth_inside_each", "lscr: the same per X̂_l"),
        ]
    }
    fn explain(
        &self,
        _s: &Scenario,
        report: &Report,
        t: Option<usize>,
        point: Option<&[f64]>,
    ) -> Result<super::StepExplanation> {
        explain_lscr(report, t, point)
    }
    fn steps(&self) -> RangeInclusive<usize> {
        // lscr-predict takes about 14 s natively at t = 2000, growing like t^2.4: 800 keeps a
        // report near 2 s.
        1..=800
    }
    fn first_accepted(&self, s: &Scenario) -> Result<Option<FirstAccepted>> {
        // The data length t the view animates (the region as the data arrive): a simulated
        // record only (measured data have the length they have). From the first t the
        // method's own validation accepts (t ≥ n, M ≤ 2^t for random strings, 2^k = M with
        // k ≤ t for groups, the smoothed index below t: `prepare_lscr`) up to the scenario's.
        // A truth fixed at the estimated time (the view's rare realization: x̄ is the state
        // the region is for) stays at the estimated time as t moves; one fixed elsewhere stays.
        let Some(current) = s.simulate.as_ref().map(|sim| sim.steps) else {
            return Ok(None);
        };
        let estimated = |t: usize| match s.lscr.as_ref().map(|l| (l.estimate, l.index)) {
            Some((Estimate::Predict, _)) => Some(t + 1),
            Some((Estimate::Filter, _)) => Some(t),
            Some((Estimate::Smooth, i)) => i,
            None => None,
        };
        let follows = s
            .simulate
            .as_ref()
            .and_then(|sim| sim.condition.as_ref())
            .is_some_and(|c| Some(c.t) == estimated(current));
        let value = first_accepted_in(1..=current, |t| {
            let mut at = s.clone();
            if let Some(sim) = at.simulate.as_mut() {
                sim.steps = t;
                if let (true, Some(c), Some(time)) = (follows, sim.condition.as_mut(), estimated(t))
                {
                    c.t = time;
                }
            }
            at.prepare_lscr().map(|_| ())
        })?;
        Ok(Some(FirstAccepted {
            field: "simulate.steps".into(),
            value,
        }))
    }
    fn data_shape(&self, s: &Scenario) -> Result<(usize, usize)> {
        // A scalar output y_t and no inputs (`prepare_lscr` refuses `data.u`).
        LscrModel::from_spec(&s.model).map(|_| (1, 0))
    }
    fn work(&self, s: &Scenario, job: Job) -> Work {
        work(s, job)
    }
    fn table(&self, r: &Report) -> Table {
        // One region for one target time: a single row of its size and, when simulated,
        // whether it holds the true state.
        let mut columns: Vec<String> = ["time", "M", "q", "level", "area", "bounded"]
            .map(String::from)
            .into();
        let Some(l) = &r.lscr else {
            return Table::new(columns);
        };
        let truth = l.x_true.as_deref();
        if let Some(x) = truth {
            columns.extend(Table::numbered("x", x.len()));
            columns.push("holds".into());
        }
        let mut table = Table::new(columns);
        let mut row = vec![
            Some(l.time as f64),
            Some(l.m as f64),
            Some(l.q as f64),
            Some(l.level),
            Some(l.area),
            flag(Some(l.bounded)),
        ];
        if let Some(x) = truth {
            row.extend(cells(Some(x), x.len()));
            row.push(flag(l.truth_inside));
        }
        table.push(row);
        table
    }
    fn run(&self, s: &Scenario) -> Result<Report> {
        let p = s.prepare_lscr()?;
        let mut l = p.report()?;
        if p.spec.coverage.is_some() {
            let x = s
                .condition("lscr.coverage needs the fixed true state")?
                .x
                .clone();
            l.coverage = Some(p.coverage(&x)?);
        }
        let y = p.y.iter().map(|v| vec![*v]).collect();
        let mut r = Report::of(
            s,
            l.level,
            (p.estimator.problem.n(), 1),
            l.time,
            // A scalar state is drawn on its one axis.
            if l.region.dim == 1 {
                vec![0]
            } else {
                l.plot.to_vec()
            },
            y,
        );
        r.lscr = Some(l);
        Ok(r)
    }
    fn study(&self, s: &Scenario, runs: Option<usize>) -> Result<Box<dyn Study>> {
        Ok(Box::new(Chunked::new(LscrStudy(
            s.lscr_experiment_with(runs)?,
        ))))
    }
    fn compare_member(&self) -> Option<&dyn CompareMember> {
        Some(self)
    }
    fn presets(&self) -> Vec<Preset> {
        presets()
    }
}

/// The LSCR coverage experiment's runs; as a [`Study`] (`Chunked::new(LscrStudy(e))`) its
/// result is the [`CoverageReport`] (counts, promised levels, exact bands).
pub struct LscrStudy(pub lscr::Experiment);

impl Runs for LscrStudy {
    type Tally = Coverage;
    type Report = CoverageReport;
    fn total(&self) -> usize {
        self.0.total
    }
    fn seed(&self) -> u64 {
        self.0.seed
    }
    fn zero(&self) -> Coverage {
        self.0.zero()
    }
    fn run(&mut self, range: std::ops::Range<usize>) -> Result<Coverage> {
        Ok(self.0.run(range))
    }
    fn report(&self, counts: &Coverage) -> CoverageReport {
        let e = &self.0;
        coverage_report(e.estimator(), e.truth(), counts.clone())
    }
}

/// Operations per unit of t³: the covariance Q″ and its Karhunen–Loève eigenvectors (12)–(15)
/// (t = 800: about 0.8 s natively).
const OPS_T3: f64 = 2.0;
/// Operations per string bit and unit of n²: the correlations d_{i,l} of every group (point 4).
const OPS_REGION: f64 = 1.5;
/// Operations per pair of lines and unit of log₂ lines: the boundary sweeps every line against
/// all others, the fitted window intersects every pair (M = 3000, n = 2: about 6 s natively;
/// 18 measured, 24 for a margin).
const OPS_PAIR: f64 = 24.0;
/// Operations per pixel of the raster (its JSON dominates), and per pixel row and line.
const OPS_PIXEL: f64 = 260.0;
const OPS_ROW_LINE: f64 = 10.0;
/// Operations per pair of strings and 64 bits of the group check (for at most 4096 strings).
const OPS_GROUP_PAIR: f64 = 100.0;
/// Operations per run of the coverage experiment, per unit of t² (the data's draw and
/// transform) and per string bit and group (redrawing the strings, g = H z).
const OPS_RUN_T2: f64 = 2.0;
const OPS_RUN_BIT: f64 = 4.0;
/// Bytes per reported number (the value, its JSON tree), per raster pixel (its u32, its JSON
/// tree and text: about 51 measured) and per unit of t² (the covariance, its eigenvectors, the
/// regressors: about 40 measured).
const BYTES_NUMBER: f64 = 60.0;
const BYTES_PIXEL: f64 = 55.0;
const BYTES_T2: f64 = 48.0;

/// The LSCR costs: t³ for the Karhunen–Loève basis, M·t·n² for the region's functions, (nM)²
/// line pairs (times log₂ nM) for the boundary and the fitted window, pixels and pixel rows ×
/// lines for the raster, and per coverage run t² + M·t·(n + 1). Bytes: t² of the basis, M·t
/// string bits (the 0/1 matrix and the strings' text), the region's M·n·(n + 1) numbers, the
/// raster's pixels and the probes' points and memberships.
fn work(s: &Scenario, job: Job) -> Work {
    let n = shape(&s.model.f).0.max(1);
    let t = s.written_steps();
    let steps_field = s.steps_field();
    let mut w = Work::default();
    let Some(spec) = s.lscr.as_ref().filter(|_| n <= lscr::MAX_STATES) else {
        return w;
    };
    let m = match (&spec.strings, spec.m, spec.level) {
        (Some(strings), _, _) => strings.len() + 1,
        (None, Some(m), _) if m > lscr::MAX_STRINGS => return w,
        (None, Some(m), _) => m,
        (None, None, level) => {
            lscr::choose_m_q(level.unwrap_or(0.9), n, spec.construction).map_or(0, |(m, _)| m)
        }
    };
    let m_field = if spec.strings.is_some() {
        "lscr.strings"
    } else {
        "lscr.M"
    };
    let bits = f(m) * f(t);
    w.ops(
        Term::new(
            steps_field,
            format!(
                "= {t_measurements}",
                t_measurements = crate::error::counted(t, "measurement", "measurements")
            ),
            "t³: the Karhunen–Loève basis of the data's covariance",
            OPS_T3 * f(t).powi(3),
        )
        .advice("fewer measurements"),
    );
    w.mem(
        Term::new(
            steps_field,
            format!(
                "= {t_measurements}",
                t_measurements = crate::error::counted(t, "measurement", "measurements")
            ),
            "t²: the covariance, its eigenvectors and the regressors",
            BYTES_T2 * f(t).powi(2),
        )
        .advice("fewer measurements"),
    );
    let strings = || {
        format!(
            "= {m} with t = {t_measurements} and n = {n_states}",
            t_measurements = crate::error::counted(t, "measurement", "measurements"),
            n_states = crate::error::counted(n, "state", "states")
        )
    };
    w.mem(
        Term::new(
            m_field,
            strings(),
            "M · t: the strings as a 0/1 matrix and as text",
            bits * (8.0 + 3.0),
        )
        .advice("fewer strings or measurements"),
    );
    // The group check of point 4a (and of explicit strings that might form one).
    if spec.construction != Construction::Random && m <= 4096 {
        w.ops(
            Term::new(
                m_field,
                strings(),
                "M² · t/64: whether the strings form a group",
                OPS_GROUP_PAIR * f(m) * f(m) / 2.0 * f(t.div_ceil(64)),
            )
            .advice("fewer strings"),
        );
    }
    let per_run = OPS_RUN_T2 * f(t).powi(2) + OPS_RUN_BIT * bits * f(n + 1);
    if let Job::Study { .. } = job {
        w.ops(
            Term::new(
                m_field,
                strings(),
                "t² + M · t · (n + 1) per run: the data's transform and every string's sign",
                per_run,
            )
            .advice("fewer strings or measurements"),
        );
        return w;
    }
    w.ops(
        Term::new(
            m_field,
            strings(),
            "M · t · n²: every string's correlation with every group",
            OPS_REGION * bits * f(n * n),
        )
        .advice("fewer strings, measurements or states"),
    );
    let lines = f(n) * f(m);
    w.ops(
        Term::new(
            m_field,
            format!(
                "= {m} with n = {n_states} ({lines} lines)",
                n_states = crate::error::counted(n, "state", "states")
            ),
            "(n · M)² · log₂(n · M): the boundary sweeps every line against all others",
            OPS_PAIR * lines * lines * lines.max(2.0).log2(),
        )
        .advice("fewer strings"),
    );
    let numbers = lines * f(n + 1) + f(m) + f(t);
    w.mem(
        Term::new(
            m_field,
            format!(
                "= {m} with n = {n_states}",
                n_states = crate::error::counted(n, "state", "states")
            ),
            "M · n · (n + 1): the region's functions in the report",
            numbers * BYTES_NUMBER,
        )
        .advice("fewer strings"),
    );
    if let Some([wd, ht]) = spec.resolution {
        let pixels = f(wd) * f(ht);
        w.ops(
            Term::new(
                "lscr.resolution",
                format!("= [{wd}, {ht}] with {lines} lines"),
                "pixels + rows · lines: the raster",
                OPS_PIXEL * pixels + OPS_ROW_LINE * f(ht) * lines,
            )
            .advice("a coarser raster or fewer strings"),
        );
        w.mem(
            Term::new(
                "lscr.resolution",
                format!("= [{wd}, {ht}]"),
                "pixels: the raster in the report",
                pixels * BYTES_PIXEL,
            )
            .advice("a coarser raster"),
        );
    }
    w.ops(
        Term::new(
            "lscr.probes",
            format!(
                "({}) with {lines} lines",
                crate::error::counted(spec.probes.len(), "point", "points")
            ),
            "probes · lines · n: the membership of every probe",
            f(spec.probes.len()) * lines * f(n),
        )
        .advice("fewer probes"),
    );
    // Each probe is written back with its point and one membership flag per group (n + 1
    // groups at most): its bytes count toward the report's like the region's numbers.
    w.mem(
        Term::new(
            "lscr.probes",
            format!(
                "({}) with n = {n_states}",
                crate::error::counted(spec.probes.len(), "point", "points"),
                n_states = crate::error::counted(n, "state", "states")
            ),
            "probes · (2n + 2): each probe's point and memberships in the report",
            f(spec.probes.len()) * f(2 * n + 2) * BYTES_NUMBER,
        )
        .advice("fewer probes"),
    );
    if let Some(c) = &spec.coverage {
        w.ops(
            Term::new(
                "lscr.coverage.runs",
                format!("= {} with M = {m}, t = {t}, n = {n}", c.runs),
                "runs · (t² + M · t · (n + 1)): per run the data's transform and every string's sign",
                f(c.runs) * per_run,
            )
            .advice("fewer runs")
            .study(),
        );
    }
    w
}

// ---------------------------------------------------------------------------------------------
// Compare: what a compare asks of LSCR (`scenario::compare`)

impl CompareMember for Lscr {
    fn compare_order(&self) -> usize {
        2
    }
    fn assumption(&self, p: &ComparePrepared) -> Assumption {
        Assumption {
            assumes: "noise symmetric about 0 and independent; variances need not be known",
            violated: None,
            promise: "for every state, at least",
            // The level 1 − 2qn/M (19) comes from the M and q the run chooses (not from the
            // time): read from the member's scenario on the whole record.
            level: p
                .member_scenario(Method::Lscr, p.steps())
                .and_then(|s| promised_level(&s))
                .ok(),
            at_least: true,
        }
    }
    fn options(&self) -> &'static [&'static str] {
        // The strings (M, q, their construction and seed) and the figure's window and raster;
        // with M or q given the compare's α no longer chooses them.
        &["M", "q", "construction", "seed", "window", "resolution"]
    }
    fn remedy(&self, p: &ComparePrepared, e: &Error) -> Option<String> {
        match (e.field.as_str(), p.n()) {
            ("model.F", 1) => {
                Some("a model of n ≥ 2 states (LSCR's scenario takes no scalar state)".to_string())
            }
            ("compare.plane", _) => Some("a model of n = 2 states".to_string()),
            _ => None,
        }
    }
    fn derived_scenario(&self, p: &ComparePrepared, t: usize) -> Result<Scenario> {
        // The compare's model as written (only its F, H and the BLUE's variances are read);
        // the joint level the compare's α, with random strings (point 4), unless the member's
        // options give M or q.
        if p.n() > 2 {
            return Err(Error::field(
                "compare.plane",
                format!(
                    "is a plane of n = {} states, but LSCR's region X̂ (18) is a union of polyhedra in all n dimensions whose projection on a plane is not computed (LSCR's own panel draws 2-D slices of it)",
                    p.n()
                ),
            ));
        }
        let chosen = p.member_option(Method::Lscr, "M").is_some()
            || p.member_option(Method::Lscr, "q").is_some();
        let mut s = p.own_scenario(Method::Lscr, p.written_model(), t);
        s.lscr = Some(LscrSpec {
            estimate: if p.predicts() {
                Estimate::Predict
            } else {
                Estimate::Filter
            },
            index: None,
            m: None,
            q: None,
            level: (!chosen).then_some(p.alpha()),
            construction: Construction::Random,
            seed: 1,
            strings: None,
            window: None,
            resolution: None,
            probes: Vec::new(),
            slice_at: None,
            coverage: None,
        });
        Ok(s)
    }
    fn plane_set(
        &self,
        _p: &ComparePrepared,
        r: &Report,
        truth: Option<&[f64]>,
    ) -> Result<PlaneReading> {
        let l = r
            .lscr
            .as_ref()
            .ok_or_else(|| Error::field("report.lscr", "has no lscr part"))?;
        if l.plot == [0, 0] {
            // A scalar state: X̂ is a union of open intervals of the line (`intervals`). The
            // compare draws one interval per method, so X̂ is drawn when it is one bounded
            // interval; a union or an unbounded piece is said in words, never replaced by a
            // hull that would hold states X̂ does not.
            return match l.intervals.as_slice() {
                [one] => match (one.lo, one.hi) {
                    (Some(lo), Some(hi)) => Ok(PlaneReading {
                        holds: truth.map(|x| l.region.contains(x)),
                        area: Some(hi - lo),
                        note: Some(format!("M = {}, q = {}", l.m, l.q)),
                        set: PlaneSet::Interval { lo, hi },
                        outline: None,
                    }),
                    _ => Err(Error::field(
                        "lscr",
                        "gives an unbounded interval X̂ for this record: too few measurements or a level too high for a bounded region",
                    )),
                },
                [] => Err(Error::field("lscr", "gives an empty X̂ for this record")),
                many => Err(Error::field(
                    "lscr",
                    format!(
                        "gives X̂ as a union of {} intervals, which the compare's one interval per method cannot draw: the LSCR view draws them",
                        many.len()
                    ),
                )),
            };
        }
        Ok(PlaneReading {
            holds: truth.map(|x| l.region.contains(x)),
            area: l.bounded.then_some(l.area),
            note: Some(format!("M = {}, q = {}", l.m, l.q)),
            set: PlaneSet::Region {
                loops: l.boundary.clone(),
                bounded: l.bounded,
                window: l.window.clone(),
            },
            outline: None,
        })
    }
    /// Whether X̂ (18) holds the true state: its sign-perturbed sums evaluated at that one
    /// point, as [`plane_set`](Self::plane_set) reads `region.contains` from the report; the
    /// report's boundary, window, area, BLUE and Kalman ellipses are not needed for it (they
    /// were most of a compare study's run). The state is the plane (a compare gives LSCR a set
    /// for n = 2 only; another n takes the report's path, which says why it has none).
    fn holds_at(&self, p: &ComparePrepared, s: &Scenario, truth: &[f64]) -> Result<bool> {
        super::compare::checked_as_run(s)?;
        let prepared = s.prepare_lscr()?;
        let est = &prepared.estimator;
        if est.problem.n() != 2 {
            let report = s.run()?;
            return self
                .plane_set(p, &report, Some(truth))?
                .holds
                .ok_or_else(|| {
                    Error::field("compare", "the set could not be checked against the state")
                });
        }
        let sums = est.problem.s(&prepared.y);
        Ok(est
            .problem
            .region(&sums, &est.strings, est.q)
            .contains(truth))
    }
}

/// The joint level 1 − 2qn/M (19) an LSCR scenario promises, from its options alone for
/// random strings (point 4: M is the strings' count as chosen, [`lscr::choose_m_q`] for a
/// level); group or explicit strings fix M themselves, so their estimator is built.
pub(crate) fn promised_level(s: &Scenario) -> Result<f64> {
    let spec = s.block(&s.lscr, "estimate, M, q, …")?;
    let n = LscrModel::from_spec(&s.model)?.f.nrows();
    let options = spec.options(n, s.written_steps())?;
    if options.strings.is_none() && options.construction == Construction::Random {
        let (m, q) = (options.m as f64, options.q as f64);
        return Ok(1.0 - 2.0 * q * n as f64 / m);
    }
    Ok(s.prepare_lscr()?.estimator.levels().1)
}

// ---------------------------------------------------------------------------------------------
// Presets

/// The LSCR paper's presets, in menu order (the trait's `presets`, gathered by
/// [`crate::presets::all`]).
fn presets() -> Vec<Preset> {
    vec![
        Preset {
            name: "lscr-predict".into(),
            label: "LSCR Fig. 1 — prediction of x₃₁".into(),
            menu: "LSCR Fig. 1 — prediction of x₃₁".into(),
            description: "LSCR paper, Fig. 1: 90 % confidence set for x₃₁ of the cascade of V-A (t = 30, M = 80, q = 2) with the BLUE ellipse".into(),
            scenario: lscr_cascade(LscrTarget::Predict),
        },
        Preset {
            name: "lscr-smooth".into(),
            label: "LSCR Fig. 2 — smoothing of x₁₅".into(),
            menu: "LSCR Fig. 2 — smoothing of x₁₅".into(),
            description: "LSCR paper, Fig. 2: 90 % confidence set for x₁₅ from y₁..y₃₀ (smoothing, forward + backward representation)".into(),
            scenario: lscr_cascade(LscrTarget::Smooth),
        },
        Preset {
            name: "lscr-ma1".into(),
            label: "LSCR Fig. 3 — MA(1): an unbounded band".into(),
            menu: "LSCR Fig. 3 — MA(1), unbounded".into(),
            description: "LSCR paper, Fig. 3: MA(1) y_t = v_t + v_{t−1}, prediction of x₂₁ — an unbounded LSCR band vs the Kalman ellipse".into(),
            scenario: lscr_ma1(),
        },
    ]
}

/// Which cascade figure of the LSCR paper.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LscrTarget {
    /// Fig. 1: x_31 from y_1..y_30.
    Predict,
    /// Fig. 2: x_15 from y_1..y_30.
    Smooth,
}

fn lscr_scenario(
    title: &str,
    model: ModelSpec,
    simulate: SimulateSpec,
    lscr: LscrSpec,
    notes: &str,
) -> Scenario {
    let mut s = Scenario::new(Method::Lscr, model)
        .with_title(title)
        .with_simulate(simulate)
        .with_alpha(0.9)
        .with_plot(vec![0, 1])
        .with_notes(notes);
    s.lscr = Some(lscr);
    s
}

fn lscr_spec(estimate: Estimate, index: Option<usize>) -> LscrSpec {
    LscrSpec {
        estimate,
        index,
        m: Some(80),
        q: Some(2),
        level: None,
        construction: Construction::Random,
        seed: 1,
        strings: None,
        window: None,
        resolution: None,
        probes: vec![],
        slice_at: None,
        coverage: None,
    }
}

/// Section V-A of the LSCR paper: x_{t+1} = [[0.5, 0], [1, 0.7]] x_t + [1, 0]ᵀ v_t, y_t = [0 1] x_t + w_t.
pub fn lscr_cascade(target: LscrTarget) -> Scenario {
    let model = ModelSpec {
        f: Some(MatrixSpec::Constant(vec![vec![0.5, 0.0], vec![1.0, 0.7]])),
        h: Some(MatrixSpec::Constant(vec![vec![0.0, 1.0]])),
        g: Some(vec![vec![1.0], vec![0.0]]),
        sigma_v2: Some(0.005),
        sigma_w2: Some(0.005),
        ..Default::default()
    };
    let (title, spec) = match target {
        LscrTarget::Predict => (
            "Confidence set for x₃₁ (LSCR paper, Fig. 1)",
            lscr_spec(Estimate::Predict, None),
        ),
        LscrTarget::Smooth => (
            "Confidence set for x₁₅ (LSCR paper, Fig. 2)",
            lscr_spec(Estimate::Smooth, Some(15)),
        ),
    };
    lscr_scenario(
        title,
        model,
        SimulateSpec { steps: 30, seed: 5, u: vec![], condition: None, x0: None, true_noise: None },
        spec,
        "Cascade of two first-order systems, σ_v² = σ_w² = 0.005 (used only to simulate and for the BLUE).          F^b = [[0.2450, 0.3315], [−0.3500, 0.9550]], Q′ = [[0.49, −0.70], [−0.70, 1.00]] (Q′ = Π′ − F^bΠ′F^bᵀ; the printed (7) is a typo).          M = 80 strings, q = 2: each X̂_l holds the true state with probability 1 − 2q/M = 0.95, X̂ with ≥ 1 − 2qn/M = 0.90 — the paper's 90 %.          (The text says q = 4 but computes 1 − 2·2·2/80; Theorem 3.2 needs q = 2 for 90 %.)          For smoothing the Karhunen–Loève eigenvalues come in exact pairs; the basis is fixed block by block          (data after, at and before the estimated time), before seeing the data.",
    )
}

/// Section V-B of the LSCR paper: the MA(1) process y_t = v_t + v_{t−1}, σ_v² = 0.1, σ_w² = 0.
pub fn lscr_ma1() -> Scenario {
    let model = ModelSpec {
        f: Some(MatrixSpec::Constant(vec![vec![0.0, 0.0], vec![1.0, 0.0]])),
        h: Some(MatrixSpec::Constant(vec![vec![0.0, 1.0]])),
        g: Some(vec![vec![1.0], vec![1.0]]),
        sigma_v2: Some(0.1),
        sigma_w2: Some(0.0),
        ..Default::default()
    };
    lscr_scenario(
        "MA(1): LSCR vs Kalman prediction of x₂₁ (LSCR paper, Fig. 3)",
        model,
        SimulateSpec { steps: 20, seed: 3, u: vec![], condition: Some(Condition { t: 21, x: vec![1.0, 1.2] }), x0: None, true_noise: None },
        lscr_spec(Estimate::Predict, None),
        "x_t = [[0, 0], [1, 0]] x_{t−1} + [1, 1]ᵀ v_t, y_t = [0 1] x_t, no measurement noise. F^b = [[−1, 1], [−1, 1]] is singular,          so X̂ is invariant along [1, 1]ᵀ: an unbounded band. The first state is white noise (σ_v² = 0.1); the true x₂₁ is placed at          x₁ = 1.0 (3.2 σ): the Kalman ellipse, always centred at x₁ = 0, misses it, while the LSCR band holds it with probability ≥ 0.9          whatever its value. (The paper's caption says x₂₀; the text and the data say x₂₁.)",
    )
}
