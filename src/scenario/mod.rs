//! Scenario (input) and Report (output) JSON, and the dispatch from one to the other.
//!
//! A scenario names a `method`, a `model`, and either observed `data` or a `simulate` block
//! (seeded; optionally conditioned on a state x_c at time t_c, drawn backwards with the
//! backward representation). Everything numeric in a report is a JSON number; ellipsoids are
//! `{"center", "cov", "radius2"}` meaning (x − c)ᵀ cov⁻¹ (x − c) ≤ radius2.

use crate::error::{Error, Result};
use crate::linalg;
use crate::model::{Inputs, LinearModel, ModelSpec, Trajectory};
use crate::scf::{self, Asymptotic, ScfOptions, ScfStep};
use crate::sets::{Ellipsoid, PlanarEllipse};
use nalgebra::DVector;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

pub mod glls;
pub mod lscr;
pub mod ubb;
pub mod uniform;
pub use glls::{GllsReport, GllsSpec};
pub use lscr::{LscrReport, LscrSpec};
pub use ubb::{UbbReport, UbbSpec};
pub use uniform::{UniformReport, UniformSpec};

/// Observed data.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DataSpec {
    /// y_1, y_2, …: one measurement vector per time step.
    pub y: Vec<Vec<f64>>,
    /// Measured inputs u_1, u_2, … (one vector is held constant).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub u: Vec<Vec<f64>>,
}

/// A state x_c imposed at time t_c: the simulation draws the past backwards from it.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Condition {
    pub t: usize,
    pub x: Vec<f64>,
}

/// Seeded simulation.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SimulateSpec {
    pub steps: usize,
    #[serde(default)]
    pub seed: u64,
    /// Measured inputs u_1, u_2, … (one vector is held constant).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub u: Vec<Vec<f64>>,
    /// Fix x_c at t_c ("rare realization").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub condition: Option<Condition>,
    /// The true x(0) (method "ubb"; default: drawn in the box of x(0)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x0: Option<Vec<f64>>,
}

/// Two 2-D position blocks and a collision distance (SCF Section II).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CollisionSpec {
    /// Components of the first body's position (two indices).
    pub a: Vec<usize>,
    /// Components of the second body's position.
    pub b: Vec<usize>,
    pub d_min: f64,
}

/// Fig. 1: conditional coverage P{x_t ∈ X_t | x_t = x̄} as x̄ moves along one component.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CurveSpec {
    pub component: usize,
    pub from: f64,
    pub to: f64,
    #[serde(default = "default_points")]
    pub points: usize,
}
fn default_points() -> usize {
    201
}

/// Monte Carlo over conditioned realizations (SCF Section II-B).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ExperimentSpec {
    pub runs: usize,
    #[serde(default)]
    pub seed: u64,
    /// Components whose coverage is counted at the conditioning time.
    pub components: Vec<usize>,
    /// Time from which the τ-step collision warning is issued (needs `collision`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub warning_t: Option<usize>,
}

/// A scenario: see the module docs and README.md for the fields.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    pub method: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub title: Option<String>,
    pub model: ModelSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub data: Option<DataSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub simulate: Option<SimulateSpec>,
    /// Probability level α of every region.
    #[serde(default = "default_alpha")]
    pub alpha: f64,
    /// Components ζ for the extra ("target") region.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub components: Option<Vec<usize>>,
    /// Prediction steps τ of the target region.
    #[serde(default)]
    pub tau: usize,
    /// Use the asymptotic SCF (IV-B).
    #[serde(default)]
    pub asymptotic: bool,
    /// Time the figure shows (default: the last step).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<usize>,
    /// The two state components drawn in the state-plane figure (default `[0, 1]`, or `[0]` if n = 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plot: Option<Vec<usize>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collision: Option<CollisionSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coverage_curve: Option<CurveSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub experiment: Option<ExperimentSpec>,
    /// LSCR options (method "lscr"): see [`lscr::LscrSpec`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lscr: Option<LscrSpec>,
    /// GLLS options (method "glls"): see [`glls::GllsSpec`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub glls: Option<GllsSpec>,
    /// Uniform-innovation LP options (method "uniform_lp"): see [`uniform::UniformSpec`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uniform: Option<UniformSpec>,
    /// Set-membership options (method "ubb"): see [`ubb::UbbSpec`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ubb: Option<UbbSpec>,
    /// Free text shown with the preset (where the numbers come from, which reading of the paper).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub notes: Option<String>,
}
fn default_alpha() -> f64 {
    0.95
}

/// Collision warning from the τ-step prediction regions at one time.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct CollisionReport {
    /// Time of the prediction (the regions are for `time + tau`).
    pub time: usize,
    pub kf_distance: f64,
    pub scf_distance: Option<f64>,
    pub kf_warning: bool,
    pub scf_warning: Option<bool>,
    /// Regions of the two bodies' positions: [kf_a, kf_b], [scf_a, scf_b].
    pub kf_regions: Vec<Ellipsoid>,
    pub scf_regions: Vec<Ellipsoid>,
    /// True distance at time + tau, when simulated.
    pub true_distance: Option<f64>,
}

fn st_kf_mean(st: &ScfStep) -> DVector<f64> {
    st.kf.center_vec()
}

/// Fig. 1 curve.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct CoverageCurve {
    pub component: usize,
    pub time: usize,
    pub xbar: Vec<f64>,
    pub kf: Vec<f64>,
    pub scf: Vec<f64>,
    /// "closed form" (n = 1) or "monte carlo (N draws per point)".
    pub how: String,
}

/// The result of a scenario.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Report {
    pub method: String,
    pub alpha: f64,
    pub n: usize,
    pub q: usize,
    /// Time shown by the figure.
    pub time: usize,
    pub plot: Vec<usize>,
    pub steps: Vec<ScfStep>,
    /// Measurements used.
    pub y: Vec<Vec<f64>>,
    /// True states (simulation only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_true: Option<Vec<Vec<f64>>>,
    /// Prior means m_t = E(x_t).
    pub prior_mean: Vec<Vec<f64>>,
    /// Steady-state quantities (stable, time-invariant, stationary prior).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub asymptotic: Option<Asymptotic>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collision: Option<Vec<CollisionReport>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coverage_curve: Option<CoverageCurve>,
    /// The LSCR result (method "lscr"; `steps` is then empty).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lscr: Option<LscrReport>,
    /// The GLLS result (method "glls"; `steps` is then empty).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub glls: Option<GllsReport>,
    /// The uniform-innovation result (method "uniform_lp").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uniform: Option<UniformReport>,
    /// The set-membership result (method "ubb").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ubb: Option<UbbReport>,
}

/// The first list entry that is not a number (every list of a scenario holds numbers or lists
/// of numbers), as (field, message): e.g. `model.F`, "is not valid: entry [0][1] is null …".
fn non_numeric_entry(v: &serde_json::Value, path: &str) -> Option<(String, String)> {
    use serde_json::Value;
    fn in_list(v: &Value, idx: &str) -> Option<String> {
        match v {
            Value::Number(_) => None,
            Value::Array(a) => a
                .iter()
                .enumerate()
                .find_map(|(i, x)| in_list(x, &format!("{idx}[{i}]"))),
            other => Some(format!(
                "is not valid: entry {idx} is {other}, but entries must be numbers (JSON has no NaN or Infinity)"
            )),
        }
    }
    match v {
        Value::Object(o) => o.iter().find_map(|(k, x)| {
            let p = if path.is_empty() {
                k.clone()
            } else {
                format!("{path}.{k}")
            };
            non_numeric_entry(x, &p)
        }),
        Value::Array(_) => in_list(v, "").map(|m| (path.to_string(), m)),
        _ => None,
    }
}

/// A validated scenario: the model, data (given or simulated) and options.
pub struct Prepared {
    pub scenario: Scenario,
    pub model: LinearModel,
    pub inputs: Inputs,
    pub y: Vec<DVector<f64>>,
    pub x_true: Option<Vec<DVector<f64>>>,
    pub options: ScfOptions,
}

impl Scenario {
    /// Parse JSON; errors say where the JSON is wrong.
    pub fn from_json(text: &str) -> Result<Self> {
        serde_json::from_str(text).map_err(|e| {
            // serde cannot name the field of an untagged matrix ("data did not match any
            // variant of untagged enum MatrixSpec"): find a non-number inside a list ourselves.
            let found = serde_json::from_str::<serde_json::Value>(text)
                .ok()
                .and_then(|v| non_numeric_entry(&v, ""));
            match found {
                Some((field, message)) => Error::field(
                    field,
                    format!("{message} (line {}, column {})", e.line(), e.column()),
                ),
                None => Error::field("scenario", format!("is not valid: {e}")),
            }
        })
    }

    /// Validate everything and produce the data (simulating if asked).
    pub fn prepare(&self) -> Result<Prepared> {
        self.check_method_blocks()?;
        if !matches!(self.method.as_str(), "scf" | "kf") {
            return Err(Error::field(
                "method",
                format!(
                    "\"{}\" is not available yet (this build has \"scf\", \"kf\", \"lscr\", \"glls\", \"uniform_lp\" and \"ubb\")",
                    self.method
                ),
            ));
        }
        if !(self.alpha > 0.0 && self.alpha < 1.0) {
            return Err(Error::field(
                "alpha",
                format!("must lie strictly between 0 and 1, found {}", self.alpha),
            ));
        }
        let model = LinearModel::from_spec(&self.model)?;
        let n = model.n();
        let (inputs, y, x_true) = match (&self.data, &self.simulate) {
            (Some(_), Some(_)) => {
                return Err(Error::field(
                    "data",
                    "and simulate are both given: choose one",
                ))
            }
            (None, None) => {
                return Err(Error::field(
                    "data",
                    "is missing (give data.y or a simulate block)",
                ))
            }
            (Some(d), None) => {
                let u = Inputs::from_rows("data.u", &d.u)?;
                model
                    .check_inputs(&u)
                    .map_err(|e| Error::field(format!("data.{}", e.field), e.message))?;
                if d.y.is_empty() {
                    return Err(Error::field(
                        "data.y",
                        "is empty: at least one measurement is needed",
                    ));
                }
                let y =
                    d.y.iter()
                        .enumerate()
                        .map(|(k, r)| linalg::vector(&format!("data.y[{k}]"), r, model.q()))
                        .collect::<Result<Vec<_>>>()?;
                (u, y, None)
            }
            (None, Some(s)) => {
                if s.steps == 0 || s.steps > 100_000 {
                    return Err(Error::field(
                        "simulate.steps",
                        format!("must lie in 1..=100000, found {}", s.steps),
                    ));
                }
                let u = Inputs::from_rows("simulate.u", &s.u)?;
                model
                    .check_inputs(&u)
                    .map_err(|e| Error::field(format!("simulate.{}", e.field), e.message))?;
                let mut rng = ChaCha8Rng::seed_from_u64(s.seed);
                let traj: Trajectory = match &s.condition {
                    None => model.simulate(s.steps, &u, None, &mut rng),
                    Some(c) => {
                        let xc = linalg::vector("simulate.condition.x", &c.x, n)?;
                        model
                            .simulate_conditioned(s.steps, &u, c.t, &xc, &mut rng)
                            .map_err(|e| {
                                if e.field == "condition.t" {
                                    Error::field("simulate.condition.t", e.message)
                                } else {
                                    e
                                }
                            })?
                    }
                };
                let finite = |v: &[DVector<f64>]| v.iter().all(|x| x.iter().all(|e| e.is_finite()));
                if !(finite(&traj.x) && finite(&traj.y)) {
                    return Err(Error::field(
                        "simulate.steps",
                        "the simulated trajectory overflows double precision: the model is too large or unstable over this many steps",
                    ));
                }
                (u, traj.y, Some(traj.x))
            }
        };
        if y.len() < n {
            return Err(Error::field(
                if self.data.is_some() { "data.y" } else { "simulate.steps" },
                format!("gives {} measurements: at least n = {n} are needed before an SCF region exists", y.len()),
            ));
        }
        if let Some(t) = self.time {
            crate::kalman::check_time("time", t, y.len())?;
        }
        if self.tau > 10_000 {
            return Err(Error::field("tau", "must be at most 10000"));
        }
        // Index lists are checked here, before any method indexes a matrix with them (the
        // experiment reads `collision` and `experiment.components` without a report).
        let check_idx = |field: &str, idx: &[usize]| {
            Ellipsoid::new(&DVector::zeros(n), &nalgebra::DMatrix::identity(n, n), 1.0)
                .project(idx)
                .map(|_| ())
                .map_err(|e| Error::field(field, e.message))
        };
        if let Some(c) = &self.collision {
            for (name, blk) in [("collision.a", &c.a), ("collision.b", &c.b)] {
                if blk.len() != 2 {
                    return Err(Error::field(name, "must name two state components"));
                }
                check_idx(name, blk)?;
            }
        }
        if let Some(e) = &self.experiment {
            check_idx("experiment.components", &e.components)?;
        }
        let options = ScfOptions {
            alpha: self.alpha,
            components: self.components.clone(),
            tau: self.tau,
            asymptotic: self.asymptotic,
            kf_only: self.method == "kf",
        };
        if self.asymptotic
            && !(model.is_time_invariant() && model.stationary_prior && model.m() == 0)
        {
            return Err(Error::field(
                "asymptotic",
                "needs a stable time-invariant model with the stationary prior and no inputs",
            ));
        }
        Ok(Prepared {
            scenario: self.clone(),
            model,
            inputs,
            y,
            x_true,
            options,
        })
    }

    /// Validate and run: the report of this scenario.
    pub fn run(&self) -> Result<Report> {
        self.check_method_blocks()?;
        match self.method.as_str() {
            "lscr" => self.run_lscr(),
            "glls" => {
                let g = self.prepare_glls()?.report()?;
                let mut r =
                    self.method_report(self.alpha, g.n, g.m, g.k, g.plane.to_vec(), g.y.clone());
                r.glls = Some(g);
                Ok(r)
            }
            "uniform_lp" => {
                let u = self.uniform_report()?;
                let q = u.y.first().map_or(0, |y| y.len());
                let mut r = self.method_report(
                    self.alpha,
                    u.n,
                    q,
                    u.at.time,
                    u.plane.to_vec(),
                    u.y.clone(),
                );
                r.uniform = Some(u);
                Ok(r)
            }
            "ubb" => {
                let u = self.prepare_ubb()?.report()?;
                let mut r =
                    self.method_report(self.alpha, u.r, u.q, u.at.k, u.plane.to_vec(), u.y.clone());
                r.ubb = Some(u);
                Ok(r)
            }
            _ => self.prepare()?.report(),
        }
    }

    /// A method block (`lscr`, `glls`, `uniform`) belongs to its own method only.
    fn check_method_blocks(&self) -> Result<()> {
        for (block, present, method) in [
            ("lscr", self.lscr.is_some(), "lscr"),
            ("glls", self.glls.is_some(), "glls"),
            ("uniform", self.uniform.is_some(), "uniform_lp"),
            ("ubb", self.ubb.is_some(), "ubb"),
        ] {
            if present && self.method != method {
                return Err(Error::field(
                    block,
                    format!(
                        "is only used with \"method\": \"{method}\" (found \"{}\")",
                        self.method
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The report of a method with its own result block (LSCR, GLLS, uniform): the SCF fields
    /// stay empty; the caller sets its block.
    fn method_report(
        &self,
        alpha: f64,
        n: usize,
        q: usize,
        time: usize,
        plot: Vec<usize>,
        y: Vec<Vec<f64>>,
    ) -> Report {
        Report {
            method: self.method.clone(),
            alpha,
            n,
            q,
            time,
            plot,
            steps: Vec::new(),
            y,
            x_true: None,
            prior_mean: Vec::new(),
            asymptotic: None,
            collision: None,
            coverage_curve: None,
            lscr: None,
            glls: None,
            uniform: None,
            ubb: None,
        }
    }

    /// An LSCR scenario's report: `lscr` holds the result.
    fn run_lscr(&self) -> Result<Report> {
        let p = self.prepare_lscr()?;
        let mut l = p.report()?;
        if p.spec.coverage.is_some() {
            let x = self
                .simulate
                .as_ref()
                .and_then(|s| s.condition.as_ref())
                .ok_or_else(|| {
                    Error::field(
                        "simulate.condition",
                        "is needed by lscr.coverage (the fixed true state)",
                    )
                })?
                .x
                .clone();
            l.coverage = Some(p.coverage(&x)?);
        }
        let y = p.y.iter().map(|v| vec![*v]).collect();
        let mut r = self.method_report(
            l.level,
            p.estimator.problem.n(),
            1,
            l.time,
            l.plot.to_vec(),
            y,
        );
        r.lscr = Some(l);
        Ok(r)
    }
}

impl Prepared {
    /// Compute the report.
    pub fn report(&self) -> Result<Report> {
        let s = &self.scenario;
        let n = self.model.n();
        let steps = self.y.len();
        let time = s.time.unwrap_or(steps);
        let plot = s
            .plot
            .clone()
            .unwrap_or_else(|| if n >= 2 { vec![0, 1] } else { vec![0] });
        Ellipsoid::new(&DVector::zeros(n), &nalgebra::DMatrix::identity(n, n), 1.0)
            .project(&plot)
            .map_err(|e| Error::field("plot", e.message))?;
        if plot.len() > 2 {
            return Err(Error::field("plot", "must name one or two components"));
        }
        let mut run = scf::run(&self.model, &self.y, &self.inputs, &self.options)?;
        if s.method == "kf" {
            for st in &mut run.steps {
                st.scf = None;
                if let Some(t) = &mut st.target {
                    t.scf = None;
                }
            }
        }
        let asymptotic =
            if self.model.is_time_invariant() && self.model.stationary_prior && self.model.m() == 0
            {
                // Optional extra: omitted when the steady state has no invertible ratio (unobservable).
                scf::asymptotic(&self.model).ok()
            } else {
                None
            };
        let collision = match &s.collision {
            Some(c) => Some(self.collisions(c, &run.steps)?),
            None => None,
        };
        let coverage_curve = match &s.coverage_curve {
            Some(c) => Some(self.coverage_curve(c, time)?),
            None => None,
        };
        let moments = self.model.moments(steps, &self.inputs);
        Ok(Report {
            method: s.method.clone(),
            alpha: s.alpha,
            n,
            q: self.model.q(),
            time,
            plot,
            steps: run.steps,
            y: self.y.iter().map(|v| v.iter().copied().collect()).collect(),
            x_true: self
                .x_true
                .as_ref()
                .map(|xs| xs.iter().map(|v| v.iter().copied().collect()).collect()),
            prior_mean: moments
                .mean
                .iter()
                .map(|v| v.iter().copied().collect())
                .collect(),
            asymptotic,
            collision,
            coverage_curve,
            lscr: None,
            glls: None,
            uniform: None,
            ubb: None,
        })
    }

    fn collisions(&self, c: &CollisionSpec, steps: &[ScfStep]) -> Result<Vec<CollisionReport>> {
        let n = self.model.n();
        for (name, blk) in [("collision.a", &c.a), ("collision.b", &c.b)] {
            if blk.len() != 2 || blk.iter().any(|&i| i >= n) {
                return Err(Error::field(
                    name,
                    format!("must name two state components below n = {n}"),
                ));
            }
        }
        if !(c.d_min.is_finite() && c.d_min > 0.0) {
            return Err(Error::field(
                "collision.d_min",
                "must be a positive distance",
            ));
        }
        let tau = self.options.tau;
        let o = crate::kalman::Offline::new(&self.model, steps.len() + tau, &self.inputs)?;
        let mut out = Vec::new();
        for st in steps {
            let g = &o.gains.steps[st.t - 1];
            let (xp, pp) =
                crate::kalman::predict(&self.model, st.t, tau, &st_kf_mean(st), &g.p, &self.inputs);
            let (mp, gp) = (
                &o.moments.mean[st.t + tau - 1],
                &o.moments.cov[st.t + tau - 1],
            );
            let pair = |idx: &[usize]| {
                scf::region_pair(st.t + tau, idx, &xp, &pp, mp, gp, self.options.alpha)
            };
            let (ra, rb) = (pair(&c.a)?, pair(&c.b)?);
            let kf_distance = PlanarEllipse::from(&ra.kf).distance(&PlanarEllipse::from(&rb.kf));
            let scf_distance = match (&ra.scf, &rb.scf) {
                (Some(a), Some(b)) => {
                    Some(PlanarEllipse::from(a).distance(&PlanarEllipse::from(b)))
                }
                _ => None,
            };
            let true_distance = self
                .x_true
                .as_ref()
                .and_then(|xs| xs.get(st.t + tau - 1))
                .map(|x| {
                    ((x[c.a[0]] - x[c.b[0]]).powi(2) + (x[c.a[1]] - x[c.b[1]]).powi(2)).sqrt()
                });
            out.push(CollisionReport {
                time: st.t,
                kf_distance,
                scf_distance,
                kf_warning: kf_distance < c.d_min,
                scf_warning: scf_distance.map(|d| d < c.d_min),
                kf_regions: vec![ra.kf.clone(), rb.kf.clone()],
                scf_regions: [ra.scf, rb.scf].into_iter().flatten().collect(),
                true_distance,
            });
        }
        Ok(out)
    }

    fn coverage_curve(&self, c: &CurveSpec, time: usize) -> Result<CoverageCurve> {
        crate::experiment::coverage_curve(&self.model, &self.inputs, &self.options, c, time)
    }
}
