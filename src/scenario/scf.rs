//! SCF and KF scenarios (method `"scf"` / `"kf"`): the top-level options (`alpha`,
//! `components`, `tau`, `asymptotic`, `time`, `plot`, `collision`, `coverage_curve`,
//! `experiment`), their validation and the report's KF/SCF steps, collision warnings and the
//! Fig. 1 coverage curve.

use super::{FigureContext, MethodScenario, Report, Scenario, Source};
use crate::error::{Error, Result};
use crate::linalg;
use crate::method::Method;
use crate::model::{Inputs, LinearModel, Trajectory};
use crate::scf::{
    self, CollisionSpec, ConditionalExperiment, CoverageCurve, CurveSpec, ScfOptions, ScfStep,
};
use crate::sets::{Ellipsoid, PlanarEllipse};
use crate::study::Study;
use nalgebra::DVector;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::ops::RangeInclusive;

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

/// A validated SCF/KF scenario: the model, data (given or simulated) and options.
pub struct ScfPrepared {
    pub scenario: Scenario,
    pub model: LinearModel,
    pub inputs: Inputs,
    pub y: Vec<DVector<f64>>,
    pub x_true: Option<Vec<DVector<f64>>>,
    pub options: ScfOptions,
}

impl Scenario {
    /// Validate an SCF/KF scenario and produce its data (simulating if asked).
    pub fn prepare_scf(&self) -> Result<ScfPrepared> {
        if !matches!(self.method, Method::Scf | Method::Kf) {
            return Err(Error::field(
                "method",
                format!(
                    "is \"{}\": the SCF/KF preparation needs \"scf\" or \"kf\"",
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
        let source = self.source(&Scf)?;
        let (input_field, input_rows) = source.input_rows();
        let inputs = Inputs::from_rows(input_field, input_rows)?;
        model
            .check_inputs(&inputs)
            .map_err(|e| Error::field(format!("{}.{}", source.prefix(), e.field), e.message))?;
        let (y, x_true) = match source {
            Source::Data(_) => (source.measurements(model.q())?, None),
            Source::Simulate(s) => {
                let mut rng = ChaCha8Rng::seed_from_u64(s.seed);
                let traj: Trajectory = match &s.condition {
                    None => model.simulate(s.steps, &inputs, None, &mut rng),
                    Some(c) => {
                        let xc = linalg::vector("simulate.condition.x", &c.x, n)?;
                        model
                            .simulate_conditioned(s.steps, &inputs, c.t, &xc, &mut rng)
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
                (traj.y, Some(traj.x))
            }
        };
        if y.len() < n {
            return Err(Error::field(
                source.steps_field(),
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
            kf_only: self.method == Method::Kf,
        };
        if self.asymptotic
            && !(model.is_time_invariant() && model.stationary_prior && model.m() == 0)
        {
            return Err(Error::field(
                "asymptotic",
                "needs a stable time-invariant model with the stationary prior and no inputs",
            ));
        }
        Ok(ScfPrepared {
            scenario: self.clone(),
            model,
            inputs,
            y,
            x_true,
            options,
        })
    }
}

impl ScfPrepared {
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
        if s.method == Method::Kf {
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
            method: s.method,
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
            figure: FigureContext::of(s),
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
        scf::experiment::coverage_curve(&self.model, &self.inputs, &self.options, c, time)
    }

    /// The conditional Monte Carlo of a scenario with `simulate.condition` and `experiment`
    /// (SCF Section II-B), not yet run.
    pub fn conditional_experiment(&self) -> Result<ConditionalExperiment> {
        let s = &self.scenario;
        let e = s
            .experiment
            .as_ref()
            .ok_or_else(|| Error::field("experiment", "is missing (runs, seed, components)"))?;
        let cond = s.condition("the experiment draws realizations conditioned on a state")?;
        ConditionalExperiment::new(
            &self.model,
            &self.inputs,
            &self.options,
            (cond.t, &cond.x),
            e,
            s.collision.as_ref(),
        )
    }
}

/// SCF and KF (Ghirardi et al.): the scenario's top-level options, KF/SCF steps in the report.
pub(crate) struct Scf;

impl MethodScenario for Scf {
    fn steps(&self) -> RangeInclusive<usize> {
        1..=100_000
    }
    fn data_shape(&self, s: &Scenario) -> Result<(usize, usize)> {
        // The rows of H and the columns of B, as `prepare_scf` checks `data.y` and `data.u`.
        let model = LinearModel::from_spec(&s.model)?;
        Ok((model.q(), model.m()))
    }
    fn run(&self, s: &Scenario) -> Result<Report> {
        s.prepare_scf()?.report()
    }
    fn study(&self, s: &Scenario, runs: Option<usize>) -> Result<Box<dyn Study>> {
        let mut s = s.clone();
        if let (Some(r), Some(e)) = (runs, s.experiment.as_mut()) {
            e.runs = r;
        }
        Ok(Box::new(s.prepare_scf()?.conditional_experiment()?))
    }
}
