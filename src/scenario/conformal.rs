//! The `conformal` block (method `"conformal"`): split conformal state regions calibrated on
//! simulated runs, adaptive conformal output intervals on the record, and the study that counts
//! marginal coverage over fresh runs beside the coverage at one fixed state. The numerics are
//! [`crate::conformal`]'s; the promise and its references are stated there.

use super::budget::{f, shape, Job, Term, Work};
use super::compare::{Assumption, CompareMember, ComparePrepared, PlaneReading, PlaneSet};
use super::csv::{cells, flag, Table};
use super::preset::Preset;
use super::{DataSpec, MethodScenario, Report, Scenario, SimulateSpec, Source};
use crate::conformal::{
    aci, aci_bound, aci_informative_steps, aci_largest_gap, mahalanobis2, min_calibration,
    order_statistic, promise, split_rank, worst_window, NoiseLaw, Simulator,
};
use crate::error::{Error, Result};
use crate::kalman::{innovation, KalmanGains};
use crate::linalg;
use crate::method::Method;
use crate::model::{ConditionedSampler, Inputs, LinearModel, MatrixSpec, ModelSpec};
use crate::sets::Ellipsoid;
use crate::stats::{band, chi2_quantile};
use crate::study::{self, Runs, Study};
use nalgebra::{Cholesky, DVector, Dyn};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::ops::RangeInclusive;

/// Most calibration runs (a report of 10⁵ runs of 100 steps takes about a second natively).
pub const MAX_CALIBRATION: usize = 100_000;
/// The Student-t's degrees of freedom: above 2 (a finite variance to scale to the model's),
/// at most 10⁶ (beyond, it is the Gaussian to double precision).
pub const NU_RANGE: RangeInclusive<f64> = 2.0..=1e6;

/// The simulated noise's law (`conformal.noise`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NoiseKind {
    #[default]
    Gaussian,
    /// Student-t with `conformal.nu` degrees of freedom, scaled to the model's covariances.
    StudentT,
}

/// The `conformal` block.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ConformalSpec {
    /// N, the calibration runs simulated from the true noise law.
    #[serde(default = "default_calibration")]
    pub calibration: usize,
    /// Seed of the calibration runs (apart from the record's `simulate.seed`).
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// The law of the simulated noise (record, calibration and study).
    #[serde(default)]
    pub noise: NoiseKind,
    /// Degrees of freedom of the Student-t law.
    #[serde(default = "default_nu")]
    pub nu: f64,
    /// ACI's step size γ.
    #[serde(default = "default_gamma")]
    pub gamma: f64,
    /// The window of the worst-window coverage (steps; default the shorter of 50 and the
    /// record).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub window: Option<usize>,
    /// Steps ahead of the target: the region is of x_{t+τ} from y_1 … y_t (τ = 0: the filter's
    /// x_t; compare's prediction uses τ = 1).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub tau: usize,
    /// The study (`conformal.study`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub study: Option<ConformalStudySpec>,
}

fn default_calibration() -> usize {
    199
}
fn default_seed() -> u64 {
    1000
}
fn default_nu() -> f64 {
    3.0
}
fn default_gamma() -> f64 {
    0.01
}
fn is_zero(v: &usize) -> bool {
    *v == 0
}

/// Most prediction steps τ.
pub const MAX_TAU: usize = 1000;

/// The worst-window coverage's default window.
const DEFAULT_WINDOW: usize = 50;

impl Default for ConformalSpec {
    fn default() -> Self {
        ConformalSpec {
            calibration: default_calibration(),
            seed: default_seed(),
            noise: NoiseKind::Gaussian,
            nu: default_nu(),
            gamma: default_gamma(),
            window: None,
            tau: 0,
            study: None,
        }
    }
}

/// `conformal.study`: fresh runs, each with its own N calibration runs, counting marginal
/// coverage; with `at`, also runs whose state at the target time is fixed there.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ConformalStudySpec {
    #[serde(default = "default_study_runs")]
    pub runs: usize,
    #[serde(default = "default_study_seed")]
    pub seed: u64,
    /// A fixed true state at the target time (its length n).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<Vec<f64>>,
}

fn default_study_runs() -> usize {
    1000
}
fn default_study_seed() -> u64 {
    77
}

/// One ACI step of the report.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct AciReportStep {
    pub t: usize,
    /// ŷ_{t|t−1}.
    pub y_hat: Vec<f64>,
    /// √diag S_t: each output's one-step standard deviation (of the innovation e_t).
    pub sd: Vec<f64>,
    /// r_t = ‖S_t^{−1/2} e_t‖; absent at a gap (an output of y_t missing: nothing to score).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub score: Option<f64>,
    pub alpha_t: f64,
    /// q_t (absent: the whole space, too few past scores or α_t ≤ 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub q: Option<f64>,
    /// The set is empty (α_t ≥ 1).
    pub empty: bool,
    /// The ACI set missed y_t; absent at a gap (no miss or cover is counted there).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub err: Option<bool>,
    /// The Kalman set {r ≤ √χ²_q(level)} missed; absent at a gap.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kf_err: Option<bool>,
    /// A warm-up step: the past holds too few scores for a quantile, the set is the whole
    /// line, and the step is kept apart from the coverage.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub warmup: bool,
}

impl AciReportStep {
    /// The ACI set's shadow on each output: ŷ_j ± q_t·√S_jj (the projection of the ellipsoid
    /// {y : ‖S^{−1/2}(y − ŷ)‖ ≤ q_t} on output j; for one output, the interval itself).
    /// `None` where the set is the whole line or empty.
    pub fn bounds(&self) -> Option<(Vec<f64>, Vec<f64>)> {
        let q = self.q.filter(|_| !self.empty)?;
        let lo = self
            .y_hat
            .iter()
            .zip(&self.sd)
            .map(|(y, s)| y - q * s)
            .collect();
        let hi = self
            .y_hat
            .iter()
            .zip(&self.sd)
            .map(|(y, s)| y + q * s)
            .collect();
        Some((lo, hi))
    }
}

/// Adaptive conformal inference on the record's outputs.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct AciReport {
    pub gamma: f64,
    /// The target miss rate α = 1 − level.
    pub miss: f64,
    /// √χ²_q(level): the Kalman set's radius in the same normalized units.
    pub kf_radius: f64,
    pub steps: Vec<AciReportStep>,
    /// Fraction of the steps with an ACI interval (scored, past the warm-up, not the whole
    /// line) whose output lay in the ACI set, and in the Kalman one over the same steps.
    pub coverage: f64,
    pub kf_coverage: f64,
    /// How many steps `coverage` counts.
    pub covered_steps: usize,
    /// Warm-up steps: the first scored steps, whose set is the whole line because the past
    /// holds too few scores for a quantile (they cannot miss, and are not in `coverage`).
    pub warmup: usize,
    /// Later scored steps whose set is the whole line (α_t ≤ 0, or a rank past the scores
    /// held): not in `coverage` either.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub whole_line: usize,
    /// Steps with an output missing (gaps): not scored, not counted, α_t not updated.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub gaps: usize,
    /// T: the scored steps, warm-up included; Proposition 4.1 is about these.
    pub scored: usize,
    /// 1 − (1/T) Σ err_t over the T scored steps (warm-up and whole-line steps covering):
    /// the quantity Proposition 4.1 bounds.
    pub long_run_coverage: f64,
    /// |long-run miss rate − α| ≤ bound = (max(α₁, 1 − α₁) + γ)/(γT) (Gibbs & Candès,
    /// Proposition 4.1).
    pub bound: f64,
    /// The bound rules out no coverage: bound ≥ max(α, 1 − α), the largest distance a coverage
    /// in [0, 1] can have from 1 − α (the report's warnings say so).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub bound_vacuous: bool,
    pub window: usize,
    /// Lowest coverage over `window` consecutive steps with an interval and that window's
    /// first step t.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub worst: Option<(f64, usize)>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kf_worst: Option<(f64, usize)>,
}

/// The conformal result (`report.conformal`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ConformalReport {
    /// The time t of the last measurement the region uses, and τ: the region is of x_{t+τ}.
    pub time: usize,
    #[serde(default, skip_serializing_if = "is_zero")]
    pub tau: usize,
    pub level: f64,
    pub noise: NoiseKind,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nu: Option<f64>,
    /// N and k = ⌈(N + 1)·level⌉.
    pub calibration: usize,
    pub rank: usize,
    /// The conformal radius² (the k-th smallest calibration score) and the χ² one.
    pub radius2: f64,
    pub chi2_radius2: f64,
    /// k/(N + 1), and the promise's bounds level ≤ P ≤ level + 1/(N + 1).
    pub exact: f64,
    pub lower: f64,
    pub upper: f64,
    /// The calibration scores, ascending.
    pub scores: Vec<f64>,
    /// The conformal region and the Kalman one at the target time.
    pub region: Ellipsoid,
    pub kalman: Ellipsoid,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth_score: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inside: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kf_inside: Option<bool>,
    pub aci: AciReport,
}

/// Everything a report and a study need, validated.
pub struct ConformalPrepared {
    pub spec: ConformalSpec,
    pub level: f64,
    law: NoiseLaw,
    /// The model the filter assumes, and the one the simulations draw from.
    model: LinearModel,
    truth_model: LinearModel,
    inputs: Inputs,
    /// The time t of the last measurement used, and the steps ahead τ.
    pub time: usize,
    tau: usize,
    gains: KalmanGains,
    /// P_{t+τ|t} and its Cholesky factor.
    p_target: nalgebra::DMatrix<f64>,
    p_chol: Cholesky<f64, Dyn>,
    chi2_state: f64,
    chi2_output: f64,
    y: Vec<DVector<f64>>,
    x_true: Option<Vec<DVector<f64>>>,
    plot: Vec<usize>,
    study_at: Option<DVector<f64>>,
    window: usize,
}

impl Scenario {
    /// With the conformal block.
    pub fn with_conformal(mut self, spec: ConformalSpec) -> Scenario {
        self.conformal = Some(spec);
        self
    }

    /// Validate a conformal scenario (every field named before any simulation).
    pub fn prepare_conformal(&self) -> Result<ConformalPrepared> {
        let spec = self.conformal.clone().unwrap_or_default();
        let level = self.alpha;
        crate::stats::check_level("alpha", level)?;
        let n0 = min_calibration(level);
        if spec.calibration < n0 || spec.calibration > MAX_CALIBRATION {
            return Err(Error::field(
                "conformal.calibration",
                format!(
                    "is {}: at level {level} it must be from {n0} (the radius is the ⌈(N + 1)·{level}⌉-th smallest of N scores, which needs N ≥ {n0}) to {MAX_CALIBRATION}",
                    spec.calibration
                ),
            ));
        }
        if !(spec.gamma > 0.0 && spec.gamma <= 1.0) {
            return Err(Error::field(
                "conformal.gamma",
                format!("is {}: ACI's step size γ must lie in (0, 1]", spec.gamma),
            ));
        }
        let law = match spec.noise {
            NoiseKind::Gaussian => NoiseLaw::Gaussian,
            NoiseKind::StudentT => {
                if !(spec.nu > *NU_RANGE.start() && spec.nu <= *NU_RANGE.end()) {
                    return Err(Error::field(
                        "conformal.nu",
                        format!(
                            "is {}: the Student-t's degrees of freedom must be above 2 (a finite variance, scaled to the model's) and at most 10⁶",
                            spec.nu
                        ),
                    ));
                }
                NoiseLaw::StudentT { nu: spec.nu }
            }
        };
        let model = LinearModel::from_spec(&self.model)?;
        let n = model.n();
        let source = self.source(&Conformal)?;
        let steps = source.steps();
        let (input_field, input_rows) = source.input_rows();
        let inputs = Inputs::from_rows(input_field, input_rows)?;
        model
            .check_inputs(&inputs)
            .map_err(|e| Error::field(format!("{}.{}", source.prefix(), e.field), e.message))?;
        // The record's gaps (empty for a simulation): the filter skips or narrows its update
        // there, in the record and in every calibration run alike.
        let record = source.measurements_with_gaps(model.q())?;
        let unscored = record
            .iter()
            .filter(|y| y.iter().any(|x| x.is_nan()))
            .count();
        if unscored > 0 && steps - unscored < n0 + 1 {
            return Err(Error::field(
                "data.y",
                format!(
                    "has {} of {steps} rows with a gap: ACI scores only the complete rows, and its quantile of the past needs at least {} at level {level} (a finite quantile of the first {n0} normalized innovations)",
                    unscored,
                    n0 + 1
                ),
            ));
        }
        // ACI's first finite quantile needs n0 past scores.
        if steps < n0 + 1 {
            return Err(Error::field(
                source.steps_field(),
                format!(
                    "gives {}: ACI's quantile of the past needs at least {} at level {level} (a finite quantile of the first {n0} normalized innovations)",
                    super::scf::plural(steps, "step", "steps"),
                    n0 + 1
                ),
            ));
        }
        let window = spec.window.unwrap_or(DEFAULT_WINDOW.min(steps));
        if window == 0 || window > steps {
            return Err(Error::field(
                "conformal.window",
                format!(
                    "is {window}: the worst-window coverage's window must be from 1 to the record's {steps_steps}", steps_steps = crate::error::counted(steps, "step", "steps")
                ),
            ));
        }
        let time = self.time.unwrap_or(steps);
        crate::kalman::check_time("time", time, steps)?;
        let tau = spec.tau;
        if tau > MAX_TAU {
            return Err(Error::field(
                "conformal.tau",
                format!("is {tau}: at most {MAX_TAU} steps ahead"),
            ));
        }
        let study_at = match spec.study.as_ref().and_then(|s| s.at.as_ref()) {
            Some(at) => {
                if law != NoiseLaw::Gaussian {
                    return Err(Error::field(
                        "conformal.study.at",
                        "needs conformal.noise = \"gaussian\": runs through a fixed state are drawn from the Gaussian law's backward representation",
                    ));
                }
                Some(linalg::vector("conformal.study.at", at, n)?)
            }
            None => None,
        };
        if let Some(st) = &spec.study {
            if st.runs == 0 || st.runs > super::MAX_STUDY_RUNS {
                return Err(Error::field(
                    "conformal.study.runs",
                    format!(
                        "is {}: a study has from 1 to {} runs",
                        st.runs,
                        super::MAX_STUDY_RUNS
                    ),
                ));
            }
        }
        let truth_model = self.true_model(&model)?;
        let gains = KalmanGains::with_gaps(&model, steps, &record)?;
        // P_{t+τ|t} = F P F^T + V, τ times from P_t (SCF footnote 16); the mean is data's.
        let zero = DVector::zeros(n);
        let p_target =
            crate::kalman::predict(&model, time, tau, &zero, &gains.steps[time - 1].p, &inputs).1;
        let p_chol = Cholesky::new(p_target.clone()).ok_or_else(|| {
            Error::field(
                "model.V",
                format!(
                    "gives a singular error covariance at t = {}: no Mahalanobis score",
                    time + tau
                ),
            )
        })?;
        let chi2_state = chi2_quantile(level, n)?;
        let chi2_output = chi2_quantile(level, model.q())?;
        let (y, x_true) = match &source {
            Source::Data(_) => (record, None),
            Source::Simulate(sim) => {
                let mut rng = ChaCha8Rng::seed_from_u64(sim.seed);
                let traj = match &sim.condition {
                    None => Simulator::new(&truth_model, steps, &inputs, law)
                        .draw(&truth_model, &mut rng),
                    Some(c) => {
                        if law != NoiseLaw::Gaussian {
                            return Err(Error::field(
                                "simulate.condition",
                                "needs conformal.noise = \"gaussian\": a record through a fixed state is drawn from the Gaussian law's backward representation",
                            ));
                        }
                        let xc = linalg::vector("simulate.condition.x", &c.x, n)?;
                        truth_model
                            .simulate_conditioned(steps, &inputs, c.t, &xc, &mut rng)
                            .map_err(|e| Error::field(format!("simulate.{}", e.field), e.message))?
                    }
                };
                let finite = traj
                    .x
                    .iter()
                    .chain(&traj.y)
                    .all(|v| v.iter().all(|e| e.is_finite()));
                if !finite {
                    return Err(Error::field(
                        "simulate.steps",
                        "the simulated trajectory overflows double precision: the model is too large or unstable over this many steps",
                    ));
                }
                (traj.y, Some(traj.x))
            }
        };
        let plot = self
            .plot
            .clone()
            .unwrap_or_else(|| if n >= 2 { vec![0, 1] } else { vec![0] });
        if plot.iter().any(|&i| i >= n) || plot.is_empty() || plot.len() > 2 {
            return Err(Error::field(
                "plot",
                format!("must name one or two state components from 0 to {}", n - 1),
            ));
        }
        Ok(ConformalPrepared {
            spec,
            level,
            law,
            model,
            truth_model,
            inputs,
            time,
            tau,
            gains,
            p_target,
            p_chol,
            chi2_state,
            chi2_output,
            y,
            x_true,
            plot,
            study_at,
            window,
        })
    }
}

impl ConformalPrepared {
    /// x̂_{t+τ|t} from y_1..y_t (35a), then τ steps of the model's mean, without keeping
    /// the earlier estimates.
    fn estimate(&self, y: &[DVector<f64>]) -> DVector<f64> {
        let m = &self.model;
        let mut x_pred = m.x1_mean.clone();
        let mut x = x_pred.clone();
        for (i, yt) in y.iter().enumerate().take(self.time) {
            let s = i + 1;
            // The record's gaps are in the gains (a zero column of K_t): a calibration run's
            // output there adds nothing, as the record's missing one does.
            x = &x_pred + &self.gains.steps[i].k * innovation(yt, m.h(s), &x_pred);
            x_pred = m.f(s) * &x + m.input_term(s, &self.inputs);
        }
        for s in self.time..self.time + self.tau {
            x = m.f(s) * &x + m.input_term(s, &self.inputs);
        }
        x
    }

    /// The target time t + τ.
    fn target(&self) -> usize {
        self.time + self.tau
    }

    /// The score of one run: (x − x̂)ᵀ P⁻¹ (x − x̂) at the target time.
    fn score(&self, y: &[DVector<f64>], x_target: &DVector<f64>) -> f64 {
        mahalanobis2(x_target, &self.estimate(y), &self.p_chol)
    }

    fn simulator(&self) -> Simulator {
        Simulator::new(&self.truth_model, self.target(), &self.inputs, self.law)
    }

    /// N scores of runs drawn by `rng`, ascending.
    fn calibration_scores(&self, sim: &Simulator, rng: &mut ChaCha8Rng) -> Vec<f64> {
        (0..self.spec.calibration)
            .map(|_| {
                let run = sim.draw(&self.truth_model, rng);
                self.score(&run.y, &run.x[self.target() - 1])
            })
            .collect()
    }

    /// The conformal radius² of these scores (k-th smallest).
    fn radius2(&self, scores: &mut [f64]) -> f64 {
        let k = split_rank(self.spec.calibration, self.level).unwrap_or(self.spec.calibration);
        order_statistic(scores, k)
    }

    /// The report block.
    pub fn report(&self) -> Result<ConformalReport> {
        let sim = self.simulator();
        let mut rng = ChaCha8Rng::seed_from_u64(self.spec.seed);
        let mut scores = self.calibration_scores(&sim, &mut rng);
        let radius2 = self.radius2(&mut scores);
        scores.sort_by(f64::total_cmp);
        let (exact, lower, upper) =
            promise(self.spec.calibration, self.level).unwrap_or((1.0, self.level, 1.0));
        let rank = split_rank(self.spec.calibration, self.level).unwrap_or(0);
        let center = self.estimate(&self.y);
        let region = Ellipsoid::new(&center, &self.p_target, radius2);
        let kalman = Ellipsoid::new(&center, &self.p_target, self.chi2_state);
        let truth = self
            .x_true
            .as_ref()
            .and_then(|x| x.get(self.target() - 1).cloned());
        let truth_score = truth
            .as_ref()
            .map(|x| mahalanobis2(x, &center, &self.p_chol));
        Ok(ConformalReport {
            time: self.time,
            tau: self.tau,
            level: self.level,
            noise: self.spec.noise,
            nu: (self.spec.noise == NoiseKind::StudentT).then_some(self.spec.nu),
            calibration: self.spec.calibration,
            rank,
            radius2,
            chi2_radius2: self.chi2_state,
            exact,
            lower,
            upper,
            scores,
            region,
            kalman,
            inside: truth_score.map(|s| s <= radius2),
            kf_inside: truth_score.map(|s| s <= self.chi2_state),
            truth: truth.map(|x| x.as_slice().to_vec()),
            truth_score,
            aci: self.aci()?,
        })
    }

    /// ACI on the record's normalized innovations. A step with an output missing is not
    /// scored (its innovation has no full y_t): ACI counts nothing there and leaves α_t as it
    /// is ([`aci`]); the filter still updates with the outputs measured.
    fn aci(&self) -> Result<AciReport> {
        let m = &self.model;
        let mut x_pred = m.x1_mean.clone();
        let mut rows = Vec::with_capacity(self.y.len());
        let mut scores = Vec::with_capacity(self.y.len());
        for (i, yt) in self.y.iter().enumerate() {
            let t = i + 1;
            let g = &self.gains.steps[i];
            let h = m.h(t);
            let s = linalg::symmetrize(&(m.w(t) + h * &g.p_pred * h.transpose()));
            let chol = Cholesky::new(s.clone())
                .ok_or_else(|| Error::field("model.W", "gives a singular innovation covariance"))?;
            let y_hat = h * &x_pred;
            let complete = yt.iter().all(|x| !x.is_nan());
            let score = complete.then(|| mahalanobis2(yt, &y_hat, &chol).sqrt());
            rows.push((
                t,
                y_hat.as_slice().to_vec(),
                s.diagonal().map(f64::sqrt).as_slice().to_vec(),
                score,
            ));
            scores.push(score);
            let x = &x_pred + &g.k * innovation(yt, h, &x_pred);
            x_pred = m.f(t) * &x + m.input_term(t, &self.inputs);
        }
        let miss = 1.0 - self.level;
        let kf_radius = self.chi2_output.sqrt();
        let trace = aci(&scores, miss, self.spec.gamma);
        let steps: Vec<AciReportStep> = rows
            .into_iter()
            .zip(&trace)
            .map(|((t, y_hat, sd, score), a)| AciReportStep {
                t,
                y_hat,
                sd,
                score,
                alpha_t: a.alpha_t,
                q: a.q.is_finite().then_some(a.q),
                empty: a.empty,
                err: a.err,
                kf_err: score.map(|r| r > kf_radius),
                warmup: a.warmup && score.is_some(),
            })
            .collect();
        let summary = AciSummary::of(&steps, self.window);
        let scored = summary.scored;
        let bound = aci_bound(miss, self.spec.gamma, scored);
        Ok(AciReport {
            gamma: self.spec.gamma,
            miss,
            kf_radius,
            coverage: summary.coverage,
            kf_coverage: summary.kf_coverage,
            covered_steps: summary.covered,
            warmup: summary.warmup,
            whole_line: summary.whole_line,
            gaps: summary.gaps,
            scored,
            long_run_coverage: summary.long_run_coverage,
            bound,
            bound_vacuous: bound >= aci_largest_gap(miss),
            window: self.window,
            worst: summary.worst,
            kf_worst: summary.kf_worst,
            steps,
        })
    }
}

/// ACI's counts from its steps: which steps have an interval, the coverage over them, the
/// warm-up, whole-line and gap steps apart, and the long-run coverage Proposition 4.1 bounds.
struct AciSummary {
    coverage: f64,
    kf_coverage: f64,
    covered: usize,
    warmup: usize,
    whole_line: usize,
    gaps: usize,
    scored: usize,
    long_run_coverage: f64,
    worst: Option<(f64, usize)>,
    kf_worst: Option<(f64, usize)>,
}

impl AciSummary {
    fn of(steps: &[AciReportStep], window: usize) -> AciSummary {
        let scored: Vec<&AciReportStep> = steps.iter().filter(|s| s.err.is_some()).collect();
        // A step with an interval: scored, and a finite or empty set (an empty set is ACI's
        // own answer at α_t ≥ 1 and misses, Gibbs & Candès).
        let with_interval: Vec<&AciReportStep> = scored
            .iter()
            .copied()
            .filter(|s| s.q.is_some() || s.empty)
            .collect();
        let misses = |v: &[&AciReportStep], kf: bool| {
            v.iter()
                .filter(|s| if kf { s.kf_err } else { s.err } == Some(true))
                .count()
        };
        let rate =
            |v: &[&AciReportStep], kf: bool| 1.0 - misses(v, kf) as f64 / v.len().max(1) as f64;
        let warmup = scored.iter().filter(|s| s.warmup).count();
        let err: Vec<bool> = with_interval.iter().map(|s| s.err == Some(true)).collect();
        let kf_err: Vec<bool> = with_interval
            .iter()
            .map(|s| s.kf_err == Some(true))
            .collect();
        // A window's first step as the step t it starts at.
        let at = |w: Option<(f64, usize)>| w.map(|(c, k)| (c, with_interval[k - 1].t));
        AciSummary {
            coverage: rate(&with_interval, false),
            kf_coverage: rate(&with_interval, true),
            covered: with_interval.len(),
            warmup,
            whole_line: scored.len() - with_interval.len() - warmup,
            gaps: steps.len() - scored.len(),
            scored: scored.len(),
            long_run_coverage: rate(&scored, false),
            worst: at(worst_window(&err, window)),
            kf_worst: at(worst_window(&kf_err, window)),
        }
    }
}

/// The study's counts.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct ConformalCount {
    pub runs: usize,
    /// Fresh runs (each with its own calibration) whose truth lay in the conformal region,
    /// and in the Kalman χ² one.
    pub inside: usize,
    pub kf_inside: usize,
    /// Runs through the fixed state `conformal.study.at` (0 without it).
    pub fixed_inside: usize,
    pub fixed_kf_inside: usize,
}

impl study::Tally for ConformalCount {
    fn runs(&self) -> usize {
        self.runs
    }
    fn counts(&self) -> Vec<(String, usize)> {
        vec![
            ("inside".into(), self.inside),
            ("kf_inside".into(), self.kf_inside),
            ("fixed_inside".into(), self.fixed_inside),
            ("fixed_kf_inside".into(), self.fixed_kf_inside),
        ]
    }
    fn add(&mut self, later: &ConformalCount) -> std::result::Result<(), String> {
        study::add_count(&mut self.runs, later.runs, "runs")?;
        study::add_count(&mut self.inside, later.inside, "inside")?;
        study::add_count(&mut self.kf_inside, later.kf_inside, "kf_inside")?;
        study::add_count(&mut self.fixed_inside, later.fixed_inside, "fixed_inside")?;
        study::add_count(
            &mut self.fixed_kf_inside,
            later.fixed_kf_inside,
            "fixed_kf_inside",
        )?;
        Ok(())
    }
}

/// The study's result: the counts and the bands they should lie in.
#[derive(Debug, Clone, Serialize)]
pub struct ConformalStudyReport {
    #[serde(flatten)]
    pub count: ConformalCount,
    pub total: usize,
    pub level: f64,
    /// The 99.9 % binomial band of the conformal count: from the band's low end at the
    /// promise's lower bound (level) to its high end at the upper bound (level + 1/(N + 1)).
    pub band: (usize, usize),
    /// The Kalman count's band at its nominal level.
    pub kf_band: (usize, usize),
    /// Where each count lies against its band ("in its band", "below its band", "above its
    /// band"): said once every run is counted (a partial count is no verdict).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub verdict: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kf_verdict: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub at: Option<Vec<f64>>,
}

/// A finished count against its band, in words.
fn against_band(count: usize, (lo, hi): (usize, usize)) -> &'static str {
    if count < lo {
        "below its band"
    } else if count > hi {
        "above its band"
    } else {
        "in its band"
    }
}

/// The study's runs.
pub struct ConformalStudy {
    prepared: ConformalPrepared,
    total: usize,
    seed: u64,
    conditioned: Option<ConditionedSampler>,
}

impl ConformalStudy {
    fn new(prepared: ConformalPrepared, total: usize) -> Result<ConformalStudy> {
        let seed = prepared
            .spec
            .study
            .as_ref()
            .map_or(default_study_seed(), |s| s.seed);
        let conditioned = match &prepared.study_at {
            Some(_) => Some(
                ConditionedSampler::new(
                    &prepared.truth_model,
                    prepared.target(),
                    &prepared.inputs,
                    prepared.target(),
                )
                .map_err(|e| Error::field("conformal.study.at", e.message))?,
            ),
            None => None,
        };
        Ok(ConformalStudy {
            prepared,
            total,
            seed,
            conditioned,
        })
    }
}

impl Runs for ConformalStudy {
    type Tally = ConformalCount;
    type Report = ConformalStudyReport;
    fn total(&self) -> usize {
        self.total
    }
    fn seed(&self) -> u64 {
        self.seed
    }
    fn zero(&self) -> ConformalCount {
        ConformalCount::default()
    }
    fn run(&mut self, range: std::ops::Range<usize>) -> Result<ConformalCount> {
        let p = &self.prepared;
        let sim = p.simulator();
        let mut count = ConformalCount::default();
        for i in range {
            let mut rng = study::run_stream(self.seed, i);
            let mut scores = p.calibration_scores(&sim, &mut rng);
            let radius2 = p.radius2(&mut scores);
            let run = sim.draw(&p.truth_model, &mut rng);
            let s = p.score(&run.y, &run.x[p.target() - 1]);
            count.inside += usize::from(s <= radius2);
            count.kf_inside += usize::from(s <= p.chi2_state);
            if let (Some(sampler), Some(at)) = (&self.conditioned, &p.study_at) {
                let run = sampler.draw(&p.truth_model, at, &mut rng);
                let s = p.score(&run.y, at);
                count.fixed_inside += usize::from(s <= radius2);
                count.fixed_kf_inside += usize::from(s <= p.chi2_state);
            }
            count.runs += 1;
        }
        Ok(count)
    }
    fn report(&self, count: &ConformalCount) -> ConformalStudyReport {
        let p = &self.prepared;
        let (_, lower, upper) = promise(p.spec.calibration, p.level).unwrap_or((1.0, p.level, 1.0));
        let conformal_band = (band(self.total, lower).0, band(self.total, upper).1);
        let finished = count.runs == self.total;
        ConformalStudyReport {
            count: *count,
            total: self.total,
            level: p.level,
            band: conformal_band,
            kf_band: band(self.total, p.level),
            verdict: finished.then(|| against_band(count.inside, conformal_band)),
            kf_verdict: finished.then(|| against_band(count.kf_inside, band(self.total, p.level))),
            at: p.study_at.as_ref().map(|x| x.as_slice().to_vec()),
        }
    }
}

/// A number for a sentence: four decimals at most, trailing zeros cut ("0.9", "2.275").
fn short(x: f64) -> String {
    let s = format!("{x:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

/// Conformal prediction beside the Kalman filter: the `conformal` block.
pub(crate) struct Conformal;

impl MethodScenario for Conformal {
    /// Honoured: the record and the calibration runs draw from `simulate.true_noise`'s scales
    /// (and the `conformal.noise` law); the filter keeps the model's V, W.
    fn true_noise(&self) -> Option<&'static str> {
        None
    }
    fn gaps(&self) -> super::Gaps {
        super::Gaps::Handled("the Kalman update is skipped at a gap (partial where only some outputs are missing), in the record and in every calibration run alike, so the split conformal region stays calibrated; ACI scores no step with a gap: no miss or cover is counted there and αₜ is not updated")
    }
    fn time_index(&self) -> super::TimeIndex {
        super::TimeIndex::OneBased
    }
    fn max_states(&self) -> usize {
        super::MAX_MODEL_DIM
    }
    fn truth_keys(&self) -> &'static [(&'static str, &'static str)] {
        &[
            ("truth", "conformal: the true state at the target time"),
            ("truth_score", "conformal: the true state's score"),
            ("inside", "conformal: whether the region holds the truth"),
            (
                "kf_inside",
                "conformal: whether the Kalman region holds the truth",
            ),
        ]
    }
    fn steps(&self) -> RangeInclusive<usize> {
        1..=10_000
    }
    fn data_shape(&self, s: &Scenario) -> Result<(usize, usize)> {
        let model = LinearModel::from_spec(&s.model)?;
        Ok((model.q(), model.m()))
    }
    fn work(&self, s: &Scenario, job: Job) -> Work {
        work(s, job)
    }
    fn run(&self, s: &Scenario) -> Result<Report> {
        let p = s.prepare_conformal()?;
        let c = p.report()?;
        let mut r = Report::of(
            s,
            s.alpha,
            (p.model.n(), p.model.q()),
            p.time,
            p.plot.clone(),
            p.y.iter().map(|y| y.as_slice().to_vec()).collect(),
        );
        r.x_true = p
            .x_true
            .as_ref()
            .map(|xs| xs.iter().map(|x| x.as_slice().to_vec()).collect());
        let times = s.data.as_ref().map_or(&[][..], |d| d.t.as_slice());
        if let Some(gaps) = super::scf::GapRows::of(&p.y, times) {
            r.warnings.push(format!(
                "The record has gaps at {}: the Kalman update is skipped there (partial where only some outputs are missing), in the record and in every calibration run alike, so the region at t = {} comes from the filter with those updates skipped and stays calibrated; ACI scores none of these steps: no miss or cover is counted there and αₜ is not updated (its coverage and bound count the {} scored steps).",
                gaps.words(),
                c.time,
                c.aci.scored
            ));
        }
        if c.aci.bound_vacuous {
            let a = &c.aci;
            let largest = c.level.max(1.0 - c.level);
            r.warnings.push(format!(
                "ACI's long-run bound (Gibbs & Candès, Prop. 4.1) over these T = {} scored steps is {}: |coverage − {}| ≤ {} rules out no coverage at all, since any coverage from 0 to 1 lies within max(α, 1 − α) = {} of {}; at γ = {} it says something from T = {} scored steps on.",
                a.scored,
                short(a.bound),
                c.level,
                short(a.bound),
                short(largest),
                c.level,
                a.gamma,
                aci_informative_steps(a.miss, a.gamma)
            ));
        }
        r.conformal = Some(c);
        Ok(r)
    }
    fn table(&self, r: &Report) -> Table {
        // One row per step t: the data (empty at a gap), ŷ_{t|t−1}, √S (each output's
        // innovation standard deviation), the score, q_t (ACI's quantile, in normalized
        // units), the ACI set's bounds ŷ ± q_t·√S (empty where it is the whole line or empty)
        // and whether each set missed y_t (empty at a gap: nothing scored).
        let Some(c) = &r.conformal else {
            return Table::new(vec!["t".into()]);
        };
        let q = r.q;
        let mut columns = vec!["t".to_string()];
        columns.extend(Table::numbered("y", q));
        columns.extend(Table::numbered("y_hat", q));
        columns.extend(Table::numbered("sd", q));
        columns.extend(["score", "aci_q"].map(String::from));
        columns.extend(Table::numbered("aci_lower", q));
        columns.extend(Table::numbered("aci_upper", q));
        columns.extend(["aci_warmup", "aci_miss", "kf_miss"].map(String::from));
        let mut table = Table::new(columns);
        for st in &c.aci.steps {
            let mut row = vec![Some(st.t as f64)];
            row.extend(
                cells(r.y.get(st.t - 1).map(|y| y.as_slice()), q)
                    .map(|c| c.filter(|x| !x.is_nan())),
            );
            row.extend(cells(Some(&st.y_hat), q));
            row.extend(cells(Some(&st.sd), q));
            row.push(st.score);
            row.push(st.q);
            let bounds = st.bounds();
            row.extend(cells(bounds.as_ref().map(|b| b.0.as_slice()), q));
            row.extend(cells(bounds.as_ref().map(|b| b.1.as_slice()), q));
            row.push(flag(Some(st.warmup)));
            row.push(flag(st.err));
            row.push(flag(st.kf_err));
            table.push(row);
        }
        table
    }
    fn study(&self, s: &Scenario, runs: Option<usize>) -> Result<Box<dyn Study>> {
        let p = s.prepare_conformal()?;
        let total = runs
            .or(p.spec.study.as_ref().map(|st| st.runs))
            .unwrap_or_else(default_study_runs);
        Ok(Box::new(study::Chunked::new(ConformalStudy::new(
            p, total,
        )?)))
    }
    fn compare_member(&self) -> Option<&dyn CompareMember> {
        Some(self)
    }
    fn presets(&self) -> Vec<Preset> {
        presets()
    }
}

impl CompareMember for Conformal {
    fn options(&self) -> &'static [&'static str] {
        // The calibration runs N and their seed: its own choices; the level is the compare's α.
        &["calibration", "seed"]
    }
    fn compare_order(&self) -> usize {
        // Beside the Kalman region whose ellipse it rescales, before SCF.
        0
    }
    fn assumption(&self, p: &ComparePrepared) -> Assumption {
        // Split conformal's promise holds when the calibration runs (drawn from the model's
        // Gaussian law) and the record are exchangeable: a record of another law breaks it.
        Assumption {
            assumes: "exchangeable calibration runs (N simulated from the model)",
            violated: p.not_gaussian().map(|why| {
                format!("{why}: the calibration runs, drawn from the model's Gaussian law, are not exchangeable with the record")
            }),
            promise: "on average over runs, ≥ α, needs N labelled runs",
            level: Some(p.alpha()),
            at_least: true,
        }
    }
    fn derived_scenario(&self, p: &ComparePrepared, t: usize) -> Result<Scenario> {
        // The compare's model as written; the region of x_{t+1} (prediction) or x_t.
        Ok(p.own_scenario(Method::Conformal, p.written_model(), t)
            .with_conformal(ConformalSpec {
                tau: usize::from(p.predicts()),
                ..ConformalSpec::default()
            }))
    }
    fn plane_set(
        &self,
        p: &ComparePrepared,
        r: &Report,
        truth: Option<&[f64]>,
    ) -> Result<PlaneReading> {
        let c = r
            .conformal
            .as_ref()
            .ok_or_else(|| Error::field("report.conformal", "is missing"))?;
        // The region of the whole state, projected on the plane (its shadow: it holds the
        // plane's components whenever the region holds the state, so "≥ α" stays true).
        let e = c.region.project(p.plane())?;
        Ok(PlaneReading {
            area: Some(e.volume()),
            holds: truth.map(|x| e.contains(x)),
            note: Some(format!(
                "radius² {:.3} from N = {} calibration runs (χ²: {:.3})",
                c.radius2, c.calibration, c.chi2_radius2
            )),
            set: PlaneSet::of_ellipsoid(e),
            outline: None,
        })
    }
}

/// Operations per filter or simulation step and unit of n² + nq + q² (products of small
/// matrices allocated per step), and per step besides.
const OPS_STEP_SQUARE: f64 = 6.0;
const OPS_STEP: f64 = 2_000.0;
/// Bytes per reported number.
const BYTES_NUMBER: f64 = 80.0;

/// The conformal costs: N calibration runs of t steps, each simulated and filtered, and the
/// record's ACI; a study's run is N + 2 such runs.
fn work(s: &Scenario, job: Job) -> Work {
    let mut w = Work::default();
    let n = shape(&s.model.f).0.max(shape(&s.model.h).1).max(1);
    let q = shape(&s.model.h).0;
    let steps = s.written_steps();
    let spec = s.conformal.clone().unwrap_or_default();
    let calibration = spec.calibration.min(MAX_CALIBRATION);
    let per_step = OPS_STEP_SQUARE * f(n * n + n * q + q * q) + OPS_STEP;
    let runs = match job {
        Job::Report => f(calibration) + 1.0,
        Job::Study { .. } => f(calibration) + 2.0,
    };
    w.ops(
        Term::new(
            "conformal.calibration",
            format!(
                "= {calibration} with {} and {} = {steps}",
                super::scf::plural(n, "state", "states"),
                s.steps_field()
            ),
            "(N + 2) · steps · (n² + nq + q²): every calibration run simulated and filtered",
            runs * f(steps) * 2.0 * per_step,
        )
        .advice("fewer calibration runs, steps or states"),
    );
    if let Job::Report = job {
        w.mem(Term::new(
            "conformal.calibration",
            format!("= {calibration} with {} = {steps}", s.steps_field()),
            "(N + steps · (2q + 5)) numbers: the scores and the ACI steps",
            (f(calibration) + f(steps) * f(2 * q + 5)) * BYTES_NUMBER,
        ));
    }
    w
}

// Presets

/// The presets' model: a damped rotation observed through its first component (one output,
/// so ACI's sets are intervals), F = 0.9·R(0.3), V = 0.5·I, W = 1, stationary prior.
fn model() -> ModelSpec {
    let (c, s) = (0.3f64.cos(), 0.3f64.sin());
    let rows = |r: &[&[f64]]| Some(MatrixSpec::Constant(r.iter().map(|x| x.to_vec()).collect()));
    ModelSpec {
        f: rows(&[&[0.9 * c, -0.9 * s], &[0.9 * s, 0.9 * c]]),
        h: rows(&[&[1.0, 0.0]]),
        v: rows(&[&[0.5, 0.0], &[0.0, 0.5]]),
        w: rows(&[&[1.0]]),
        ..Default::default()
    }
}

fn simulate(steps: usize) -> SimulateSpec {
    SimulateSpec {
        steps,
        seed: 3,
        u: vec![],
        condition: None,
        x0: None,
        true_noise: None,
    }
}

/// A state far out in the stationary law (about 4.4 standard deviations along x₁).
pub const FAR_STATE: [f64; 2] = [6.0, -2.0];

fn scenario(kind: &str) -> Scenario {
    let base = Scenario::new(Method::Conformal, model()).with_time(30);
    match kind {
        "gaussian" => base
            .with_title("Conformal vs Kalman: Gaussian noise")
            .with_alpha(0.9)
            .with_simulate(SimulateSpec { seed: 7, ..simulate(120) })
            .with_conformal(ConformalSpec {
                study: Some(ConformalStudySpec { runs: 1000, seed: 77, at: None }),
                ..ConformalSpec::default()
            })
            .with_notes("Gaussian noise, as the filter assumes: the conformal radius² (the ⌈(N + 1)·0.9⌉ = 180th smallest of N = 199 scores) is close to χ²₂(0.9) = 4.61, and both regions hold the truth in about 90 % of fresh runs."),
        "heavy" => base
            .with_title("Conformal vs Kalman: Student-t noise (ν = 2.5)")
            .with_alpha(0.99)
            .with_simulate(simulate(120))
            .with_conformal(ConformalSpec {
                calibration: 999,
                noise: NoiseKind::StudentT,
                nu: 2.5,
                study: Some(ConformalStudySpec { runs: 1000, seed: 77, at: None }),
                ..ConformalSpec::default()
            })
            .with_notes("Heavy-tailed noise with the covariances the filter assumes: the scores are no longer χ², the χ² radius misses more often than 1 % of fresh runs, and the conformal radius, calibrated on this law, keeps its promise 0.99 ≤ P ≤ 0.99 + 1/1000."),
        "far" => {
            let mut s = base
                .with_title("Conformal vs Kalman: a state far out")
                .with_alpha(0.9)
                .with_conformal(ConformalSpec {
                    study: Some(ConformalStudySpec { runs: 1000, seed: 77, at: Some(FAR_STATE.to_vec()) }),
                    ..ConformalSpec::default()
                })
                .with_notes("The true state at t = 30 is fixed far out in the stationary law, (6, −2). Conformal's promise is an average over runs: at this state it misses far more often than 10 %, as the Kalman region does. The SCF region (the SCF view, the same model) is built to hold every state with its probability.");
            let mut sim = simulate(120);
            sim.condition = Some(super::Condition { t: 30, x: FAR_STATE.to_vec() });
            s = s.with_simulate(sim);
            s
        }
        _ => base
            .with_title("Adaptive conformal inference on a drifting record")
            .with_alpha(0.9)
            .with_data(drifting_record())
            .with_time(400)
            .with_conformal(ConformalSpec { gamma: 0.01, window: Some(50), ..ConformalSpec::default() })
            .with_notes("400 measurements whose output noise grows from the assumed standard deviation 1 to 3 (drawn once, seed 11, with the model's other noise): the Kalman interval from S_t keeps its width and its coverage falls; ACI widens its interval and keeps the long-run miss rate near 10 %."),
    }
}

/// 400 outputs of the presets' model whose output noise's standard deviation ramps from 1 to 3
/// (the state drawn with the model's process noise from x = 0 after 100 steps of burn-in).
fn drifting_record() -> DataSpec {
    use rand::RngExt;
    let (c, s) = (0.3f64.cos(), 0.3f64.sin());
    let f = [[0.9 * c, -0.9 * s], [0.9 * s, 0.9 * c]];
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut normal = || -> f64 { rng.sample(rand_distr::StandardNormal) };
    let steps = 400;
    let mut x = [0.0f64; 2];
    let mut y = Vec::with_capacity(steps);
    for i in 0..100 + steps {
        if i >= 100 {
            let sd = 1.0 + 2.0 * (i - 100) as f64 / (steps - 1) as f64;
            y.push(vec![x[0] + sd * normal()]);
        }
        let v = 0.5f64.sqrt();
        x = [
            f[0][0] * x[0] + f[0][1] * x[1] + v * normal(),
            f[1][0] * x[0] + f[1][1] * x[1] + v * normal(),
        ];
    }
    DataSpec {
        y,
        u: vec![],
        t: vec![],
    }
}

fn presets() -> Vec<Preset> {
    vec![
        Preset {
            name: "conformal-gaussian".into(),
            label: "Conformal vs Kalman — Gaussian noise: they agree".into(),
            menu: "Conformal — Gaussian noise".into(),
            description: "Split conformal (Vovk et al.) on the Kalman filter's Mahalanobis score, calibrated on 199 simulated runs: under the Gaussian law the filter assumes, its radius is close to the χ² one".into(),
            scenario: scenario("gaussian"),
        },
        Preset {
            name: "conformal-heavy".into(),
            label: "Conformal vs Kalman — heavy tails: conformal keeps 99 %".into(),
            menu: "Conformal — heavy tails".into(),
            description: "Student-t noise (ν = 2.5) with the covariances the filter assumes: the χ² radius loses marginal coverage at 99 %, the conformal radius keeps it".into(),
            scenario: scenario("heavy"),
        },
        Preset {
            name: "conformal-far".into(),
            label: "Conformal vs Kalman — a state far out: neither holds".into(),
            menu: "Conformal — a state far out".into(),
            description: "The true state fixed far out: conformal's promise is an average over runs, so at this state it misses far more often than 10 %, like the Kalman region (the SCF region holds)".into(),
            scenario: scenario("far"),
        },
        Preset {
            name: "conformal-aci-drift".into(),
            label: "Conformal ACI (Gibbs & Candès) — a drifting record".into(),
            menu: "Conformal — ACI, drifting noise".into(),
            description: "Adaptive conformal inference (Gibbs & Candès) on 400 measurements whose noise grows threefold: the Kalman interval's coverage falls, ACI's long-run miss rate stays near 10 %".into(),
            scenario: scenario("drift"),
        },
    ]
}
