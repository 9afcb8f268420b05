//! The linear Gaussian state-space model shared by every method.
//!
//! ```text
//! x_{t+1} = F_t x_t + B_t u_t + v_t,   v_t ~ N(0, V_t)
//! y_t     = H_t x_t + w_t,             w_t ~ N(0, W_t)        t = 1, 2, …
//! ```
//!
//! with a Gaussian prior x_1 ~ N(m_1, Γ_1). Time is 1-based as in the papers. The LSCR form
//! `x_{t+1} = F x_t + G v_t` with scalar variances σ_v², σ_w² is the special case V = σ_v² G Gᵀ,
//! W = σ_w² I.
//!
//! What lives here, because every method needs it:
//! * validation of user matrices, with errors naming the field;
//! * the stationary covariance Γ (discrete Lyapunov equation Γ = FΓFᵀ + V, SCF footnote 10)
//!   and the propagated moments m_t, Γ_t of a non-stationary process (SCF V-D);
//! * the backward representation x_{t−1} = F^b_t x_t + v^b_t (SCF (29)–(30), (45)):
//!   F^b_t = Γ_{t−1} F_{t−1}ᵀ Γ_t⁻¹, V^b_t = Γ_{t−1} − Γ_{t−1} F_{t−1}ᵀ Γ_t⁻¹ F_{t−1} Γ_{t−1};
//! * seeded forward simulation, and *state-conditioned* simulation: fix x_c at time t_c and draw
//!   the past backwards with (45) (SCF footnote 2), the future forwards. Every conditional
//!   coverage study of the project is built on it.

use crate::error::{Error, Result};
use crate::linalg::{self, check_covariance, expect_shape, psd_sqrt, symmetrize};
use crate::method::Method;
use nalgebra::{DMatrix, DVector};
use rand::{Rng, RngExt};
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

/// A matrix in JSON: a list of rows, or a list of such matrices (one per time step, for
/// time-varying systems; the last one is held beyond the list's end).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum MatrixSpec {
    /// The same matrix at every time.
    Constant(Vec<Vec<f64>>),
    /// `[M_1, M_2, …]`: the matrix at t = 1, 2, …
    Sequence(Vec<Vec<Vec<f64>>>),
}

impl MatrixSpec {
    /// A constant matrix as a spec (presets, and the models the methods build for a KF).
    pub fn of(m: &DMatrix<f64>) -> MatrixSpec {
        MatrixSpec::Constant(linalg::to_rows(m))
    }
}

/// The `model` object of a scenario.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ModelSpec {
    #[serde(rename = "F")]
    pub f: Option<MatrixSpec>,
    #[serde(rename = "H")]
    pub h: Option<MatrixSpec>,
    /// Process-noise covariance V (n×n).
    #[serde(rename = "V", default, skip_serializing_if = "Option::is_none")]
    pub v: Option<MatrixSpec>,
    /// Measurement-noise covariance W (q×q).
    #[serde(rename = "W", default, skip_serializing_if = "Option::is_none")]
    pub w: Option<MatrixSpec>,
    /// LSCR form: noise input matrix G (n×1), used with `sigma_v2`, `sigma_w2` instead of V, W.
    #[serde(rename = "G", default, skip_serializing_if = "Option::is_none")]
    pub g: Option<Vec<Vec<f64>>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma_v2: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma_w2: Option<f64>,
    /// Input matrix B (n×m) of measured inputs u_t.
    #[serde(rename = "B", default, skip_serializing_if = "Option::is_none")]
    pub b: Option<MatrixSpec>,
    /// Prior of x_1: mean m_1 (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x1_mean: Option<Vec<f64>>,
    /// Prior of x_1: covariance Γ_1 (default: the stationary Γ, which needs a stable F).
    /// All zeros means x_1 is known exactly.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x1_cov: Option<Vec<Vec<f64>>>,
}

impl ModelSpec {
    /// The one matrix of a model field for a method that needs a time-invariant model (GLLS,
    /// LSCR, uniform_lp, ubb): `None` when the field is absent, an error naming the field and
    /// the method when it is a sequence of matrices.
    pub fn constant(
        field: &str,
        spec: &Option<MatrixSpec>,
        method: Method,
    ) -> Result<Option<DMatrix<f64>>> {
        match spec {
            None => Ok(None),
            Some(MatrixSpec::Constant(rows)) => linalg::from_rows(field, rows).map(Some),
            Some(MatrixSpec::Sequence(_)) => Err(Error::field(
                field,
                format!("must be one matrix: method \"{method}\" needs a time-invariant model"),
            )),
        }
    }
}

/// A validated model: dimensions agree, covariances are symmetric PSD (W positive definite),
/// all entries finite.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearModel {
    f: Vec<DMatrix<f64>>,
    h: Vec<DMatrix<f64>>,
    v: Vec<DMatrix<f64>>,
    w: Vec<DMatrix<f64>>,
    b: Vec<DMatrix<f64>>,
    /// Prior mean of x_1.
    pub x1_mean: DVector<f64>,
    /// Prior covariance of x_1 (Γ_1).
    pub x1_cov: DMatrix<f64>,
    /// Whether Γ_1 is the stationary covariance (the process is stationary when also
    /// time-invariant with no inputs).
    pub stationary_prior: bool,
}

fn matrices(field: &str, spec: &MatrixSpec) -> Result<Vec<DMatrix<f64>>> {
    match spec {
        MatrixSpec::Constant(rows) => Ok(vec![linalg::from_rows(field, rows)?]),
        MatrixSpec::Sequence(seq) => {
            if seq.is_empty() {
                return Err(Error::field(field, "must not be an empty list of matrices"));
            }
            seq.iter()
                .enumerate()
                .map(|(k, rows)| linalg::from_rows(&format!("{field}[{k}]"), rows))
                .collect()
        }
    }
}

fn at(seq: &[DMatrix<f64>], t: usize) -> &DMatrix<f64> {
    &seq[(t.max(1) - 1).min(seq.len() - 1)]
}

impl LinearModel {
    /// Validate a JSON model. Errors name the field (`model.V`, `model.H`, …).
    pub fn from_spec(spec: &ModelSpec) -> Result<Self> {
        let f = matrices(
            "model.F",
            spec.f
                .as_ref()
                .ok_or_else(|| Error::field("model.F", "is missing"))?,
        )?;
        let n = f[0].nrows();
        for (k, fk) in f.iter().enumerate() {
            expect_shape(&format!("model.F[{k}]"), fk, n, n).map_err(|e| {
                if f.len() == 1 {
                    Error::field(
                        "model.F",
                        format!("must be square, found {}×{}", fk.nrows(), fk.ncols()),
                    )
                } else {
                    e
                }
            })?;
        }
        let h = matrices(
            "model.H",
            spec.h
                .as_ref()
                .ok_or_else(|| Error::field("model.H", "is missing"))?,
        )?;
        let q = h[0].nrows();
        for hk in &h {
            expect_shape("model.H", hk, q, n)?;
        }
        let lscr = spec.g.is_some() || spec.sigma_v2.is_some() || spec.sigma_w2.is_some();
        let (v, w) = if lscr {
            if spec.v.is_some() || spec.w.is_some() {
                return Err(Error::field(
                    "model",
                    "give either V and W, or G with sigma_v2 and sigma_w2, not both",
                ));
            }
            let g = linalg::from_rows(
                "model.G",
                spec.g
                    .as_ref()
                    .ok_or_else(|| Error::field("model.G", "is missing (needed with sigma_v2)"))?,
            )?;
            expect_shape("model.G", &g, n, g.ncols())?;
            let sv = spec
                .sigma_v2
                .ok_or_else(|| Error::field("model.sigma_v2", "is missing"))?;
            let sw = spec
                .sigma_w2
                .ok_or_else(|| Error::field("model.sigma_w2", "is missing"))?;
            if !(sv.is_finite() && sv >= 0.0) {
                return Err(Error::field(
                    "model.sigma_v2",
                    "must be a finite variance ≥ 0",
                ));
            }
            // σ_w² = 0 is allowed (LSCR's MA(1) example has no measurement noise); the Kalman
            // filter then fails with a clear error if H P Hᵀ is singular.
            if !(sw.is_finite() && sw >= 0.0) {
                return Err(Error::field(
                    "model.sigma_w2",
                    "must be a finite variance ≥ 0",
                ));
            }
            (
                vec![&g * g.transpose() * sv],
                vec![DMatrix::identity(q, q) * sw],
            )
        } else {
            let v = matrices(
                "model.V",
                spec.v
                    .as_ref()
                    .ok_or_else(|| Error::field("model.V", "is missing"))?,
            )?;
            let w = matrices(
                "model.W",
                spec.w
                    .as_ref()
                    .ok_or_else(|| Error::field("model.W", "is missing"))?,
            )?;
            for vk in &v {
                expect_shape("model.V", vk, n, n)?;
                check_covariance("model.V", vk, false)?;
            }
            for wk in &w {
                expect_shape("model.W", wk, q, q)?;
                check_covariance("model.W", wk, true)?;
            }
            (v, w)
        };
        let b = match &spec.b {
            Some(bs) => {
                let b = matrices("model.B", bs)?;
                let m = b[0].ncols();
                for bk in &b {
                    expect_shape("model.B", bk, n, m)?;
                }
                b
            }
            None => vec![DMatrix::zeros(n, 0)],
        };
        let x1_mean = match &spec.x1_mean {
            Some(m) => linalg::vector("model.x1_mean", m, n)?,
            None => DVector::zeros(n),
        };
        let mut model = LinearModel {
            f,
            h,
            v,
            w,
            b,
            x1_mean,
            x1_cov: DMatrix::zeros(n, n),
            stationary_prior: false,
        };
        match &spec.x1_cov {
            Some(rows) => {
                let c = linalg::from_rows("model.x1_cov", rows)?;
                expect_shape("model.x1_cov", &c, n, n)?;
                check_covariance("model.x1_cov", &c, false)?;
                model.x1_cov = c;
            }
            None => {
                model.x1_cov = model.stationary_covariance().map_err(|e| {
                    Error::field(
                        "model.x1_cov",
                        format!("is needed: no stationary prior exists ({e}), and without model.x1_cov x_1 would start from it; give the covariance of x_1"),
                    )
                })?;
                model.stationary_prior = true;
            }
        }
        Ok(model)
    }

    /// Build directly from matrices (time-invariant), with the stationary prior when F is
    /// stable. For tests and presets; user input goes through [`LinearModel::from_spec`].
    pub fn time_invariant(
        f: DMatrix<f64>,
        h: DMatrix<f64>,
        v: DMatrix<f64>,
        w: DMatrix<f64>,
    ) -> Result<Self> {
        Self::from_spec(&ModelSpec {
            f: Some(MatrixSpec::of(&f)),
            h: Some(MatrixSpec::of(&h)),
            v: Some(MatrixSpec::of(&v)),
            w: Some(MatrixSpec::of(&w)),
            ..Default::default()
        })
    }

    /// The same model with its noise covariances scaled: V_t → s_v·V_t, W_t → s_w·W_t (the
    /// true noise of a simulation that the filters do not know, `simulate.true_noise`). A
    /// stationary prior is the stationary law of the scaled process (s_v·Γ, so the process
    /// stays stationary: the backward representation's F^b is unchanged and V^b is scaled by
    /// s_v); a prior given in `model.x1_cov` is the initial state's law and is kept. Scales of
    /// exactly 1 give the model bit for bit.
    pub fn with_noise_scaled(&self, s_v: f64, s_w: f64) -> Result<LinearModel> {
        let mut m = self.clone();
        if s_v == 1.0 && s_w == 1.0 {
            return Ok(m);
        }
        m.v = self.v.iter().map(|v| v * s_v).collect();
        m.w = self.w.iter().map(|w| w * s_w).collect();
        if m.stationary_prior {
            m.x1_cov = m.stationary_covariance()?;
        }
        Ok(m)
    }

    /// State dimension n.
    pub fn n(&self) -> usize {
        self.f[0].nrows()
    }
    /// Output dimension q.
    pub fn q(&self) -> usize {
        self.h[0].nrows()
    }
    /// Input dimension m (0 without B).
    pub fn m(&self) -> usize {
        self.b[0].ncols()
    }
    /// F_t (maps x_t to x_{t+1}).
    pub fn f(&self, t: usize) -> &DMatrix<f64> {
        at(&self.f, t)
    }
    /// H_t.
    pub fn h(&self, t: usize) -> &DMatrix<f64> {
        at(&self.h, t)
    }
    /// V_t = Cov(v_t).
    pub fn v(&self, t: usize) -> &DMatrix<f64> {
        at(&self.v, t)
    }
    /// W_t = Cov(w_t).
    pub fn w(&self, t: usize) -> &DMatrix<f64> {
        at(&self.w, t)
    }
    /// B_t.
    pub fn b(&self, t: usize) -> &DMatrix<f64> {
        at(&self.b, t)
    }
    /// True when F, H, V, W, B are the same at every t.
    pub fn is_time_invariant(&self) -> bool {
        [&self.f, &self.h, &self.v, &self.w, &self.b]
            .iter()
            .all(|s| s.len() == 1)
    }

    /// Γ solving Γ = FΓFᵀ + V (SCF footnote 10) for a time-invariant model with spectral
    /// radius ρ(F) < 1, by the doubling iteration Γ = Σ_k F^k V F^kᵀ; the residual is checked.
    pub fn stationary_covariance(&self) -> Result<DMatrix<f64>> {
        if !self.is_time_invariant() {
            return Err(Error::field(
                "model.F",
                "is time-varying: a stationary covariance needs a time-invariant model",
            ));
        }
        let f = self.f(1);
        let rho = linalg::spectral_radius(f);
        if !(rho < 1.0 - 1e-9) {
            return Err(Error::field(
                "model.F",
                format!("is not asymptotically stable (spectral radius {rho:.6} ≥ 1): no stationary covariance"),
            ));
        }
        lyapunov(f, self.v(1))
    }

    /// Input term B_t u_t (zero when the model has no B).
    pub fn input_term(&self, t: usize, u: &Inputs) -> DVector<f64> {
        if self.m() == 0 {
            DVector::zeros(self.n())
        } else {
            self.b(t) * u.at(t)
        }
    }

    /// Check an input sequence against the model.
    pub fn check_inputs(&self, u: &Inputs) -> Result<()> {
        if self.m() == 0 && !u.is_empty() {
            return Err(Error::field("u", "is given but the model has no B"));
        }
        if self.m() > 0 && u.is_empty() {
            return Err(Error::field(
                "u",
                format!(
                    "is missing: model.B has {}",
                    crate::error::counted(self.m(), "column", "columns")
                ),
            ));
        }
        for (k, uk) in u.0.iter().enumerate() {
            if uk.len() != self.m() {
                return Err(Error::field(
                    format!("u[{k}]"),
                    format!(
                        "must have {} (columns of model.B), found {}",
                        crate::error::counted(self.m(), "entry", "entries"),
                        uk.len()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Prior moments m_t = E(x_t), Γ_t = Cov(x_t) for t = 1..=steps (index t−1).
    /// Γ_{t+1} = F_t Γ_t F_tᵀ + V_t, m_{t+1} = F_t m_t + B_t u_t (SCF V-D, V-E).
    pub fn moments(&self, steps: usize, u: &Inputs) -> Moments {
        let mut mean = Vec::with_capacity(steps);
        let mut cov = Vec::with_capacity(steps);
        let mut m = self.x1_mean.clone();
        let mut g = self.x1_cov.clone();
        for t in 1..=steps {
            mean.push(m.clone());
            cov.push(g.clone());
            let f = self.f(t);
            m = f * &m + self.input_term(t, u);
            g = symmetrize(&(f * &g * f.transpose() + self.v(t)));
        }
        Moments { mean, cov }
    }

    /// The backward step into time t (t ≥ 2): x_{t−1} − m_{t−1} = F^b_t (x_t − m_t) + v^b_t
    /// with F^b_t = Γ_{t−1} F_{t−1}ᵀ Γ_t⁻¹ and V^b_t = Γ_{t−1} − F^b_t Γ_t F^b_tᵀ (SCF (45);
    /// the same as Γ_{t−1} − Γ_{t−1}F_{t−1}ᵀΓ_t⁻¹F_{t−1}Γ_{t−1}, written in the form that stays
    /// symmetric). Needs Γ_t ≻ 0.
    pub fn backward_step(&self, t: usize, moments: &Moments) -> Result<BackwardStep> {
        assert!(t >= 2);
        let g_prev = &moments.cov[t - 2];
        let g = &moments.cov[t - 1];
        let g_inv = linalg::inverse(&format!("Γ_{t} (state covariance at t = {t})"), g)
            .map_err(|_| Error::field("model.V", format!("does not excite every state: Γ_{t} is singular, so no backward representation exists")))?;
        let f_b = g_prev * self.f(t - 1).transpose() * g_inv;
        let v_b = symmetrize(&(g_prev - &f_b * g * f_b.transpose()));
        Ok(BackwardStep { f_b, v_b })
    }

    /// Backward representation of the stationary process (SCF (29)–(30)): F^b = ΓFᵀΓ⁻¹,
    /// V^b = Γ − F^bΓF^bᵀ (= Γ − ΓFᵀΓ⁻¹FΓ; the LSCR paper's (7) prints Π − FΠFᵀ, a typo).
    pub fn backward_representation(&self) -> Result<BackwardStep> {
        let gamma = self.stationary_covariance()?;
        let g_inv = linalg::inverse("Γ (stationary covariance)", &gamma).map_err(|_| {
            Error::field(
                "model.V",
                "does not excite every state: the stationary covariance Γ is singular",
            )
        })?;
        let f_b = &gamma * self.f(1).transpose() * g_inv;
        let v_b = symmetrize(&(&gamma - &f_b * &gamma * f_b.transpose()));
        Ok(BackwardStep { f_b, v_b })
    }

    /// Seeded forward simulation of x_1..x_T and y_1..y_T.
    pub fn simulate<R: Rng>(
        &self,
        steps: usize,
        u: &Inputs,
        x1: Option<&DVector<f64>>,
        rng: &mut R,
    ) -> Trajectory {
        let n = self.n();
        let mut x = match x1 {
            Some(x) => x.clone(),
            None => &self.x1_mean + psd_sqrt(&self.x1_cov) * normal_vector(n, rng),
        };
        let mut traj = Trajectory {
            x: Vec::with_capacity(steps),
            y: Vec::with_capacity(steps),
        };
        for t in 1..=steps {
            traj.y.push(self.measure(t, &x, rng));
            traj.x.push(x.clone());
            x = self.f(t) * &x
                + self.input_term(t, u)
                + psd_sqrt(self.v(t)) * normal_vector(n, rng);
        }
        traj
    }

    /// y_t = H_t x_t + w_t.
    pub fn measure<R: Rng>(&self, t: usize, x: &DVector<f64>, rng: &mut R) -> DVector<f64> {
        self.h(t) * x + psd_sqrt(self.w(t)) * normal_vector(self.q(), rng)
    }

    /// State-conditioned simulation (SCF footnote 2): x_{t_c} = x_c is fixed, x_{t_c−1}, …, x_1
    /// are drawn backwards with (45) — exactly the conditional law of the past given x_{t_c} —
    /// and x_{t_c+1}, …, x_T forwards. Measurements are drawn given the states.
    pub fn simulate_conditioned<R: Rng>(
        &self,
        steps: usize,
        u: &Inputs,
        t_c: usize,
        x_c: &DVector<f64>,
        rng: &mut R,
    ) -> Result<Trajectory> {
        let plan = ConditionedSampler::new(self, steps, u, t_c)?;
        Ok(plan.draw(self, x_c, rng))
    }
}

/// Doubling iteration for Γ = FΓFᵀ + V with a residual check.
pub fn lyapunov(f: &DMatrix<f64>, v: &DMatrix<f64>) -> Result<DMatrix<f64>> {
    let mut a = f.clone();
    let mut g = v.clone();
    for _ in 0..80 {
        let next = &g + &a * &g * a.transpose();
        let done = (&next - &g).amax() <= 1e-16 * next.amax().max(f64::MIN_POSITIVE);
        g = symmetrize(&next);
        a = &a * &a;
        if done {
            break;
        }
    }
    let residual = (&g - f * &g * f.transpose() - v).amax();
    if !(residual <= 1e-9 * g.amax().max(1.0)) {
        return Err(Error::field(
            "model.F",
            format!("Lyapunov equation did not converge (residual {residual:.3e})"),
        ));
    }
    Ok(g)
}

/// One step of a backward representation.
#[derive(Debug, Clone, PartialEq)]
pub struct BackwardStep {
    /// F^b: backward transition matrix.
    pub f_b: DMatrix<f64>,
    /// V^b: covariance of the backward noise v^b.
    pub v_b: DMatrix<f64>,
}

/// Prior moments of the state, index t−1 for time t.
#[derive(Debug, Clone)]
pub struct Moments {
    pub mean: Vec<DVector<f64>>,
    pub cov: Vec<DMatrix<f64>>,
}

/// Measured inputs u_1, u_2, … (a single vector is held constant).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Inputs(pub Vec<DVector<f64>>);

impl Inputs {
    /// No inputs.
    pub fn none() -> Self {
        Inputs(Vec::new())
    }
    /// From JSON rows; `field` names them in errors.
    pub fn from_rows(field: &str, rows: &[Vec<f64>]) -> Result<Self> {
        rows.iter()
            .enumerate()
            .map(|(k, r)| linalg::vector(&format!("{field}[{k}]"), r, r.len()))
            .collect::<Result<Vec<_>>>()
            .map(Inputs)
    }
    /// u_t (the last one beyond the end).
    pub fn at(&self, t: usize) -> &DVector<f64> {
        &self.0[(t.max(1) - 1).min(self.0.len() - 1)]
    }
    /// True without inputs.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

/// A simulated (or observed) trajectory, index t−1 for time t.
#[derive(Debug, Clone, Default)]
pub struct Trajectory {
    pub x: Vec<DVector<f64>>,
    pub y: Vec<DVector<f64>>,
}

/// n independent standard normal draws.
pub fn normal_vector<R: Rng>(n: usize, rng: &mut R) -> DVector<f64> {
    DVector::from_fn(n, |_, _| rng.sample(StandardNormal))
}

/// Everything a state-conditioned draw needs, computed once so that Monte Carlo loops only
/// draw random numbers: prior moments, backward matrices and square roots of V^b_t, V_t, W_t.
#[derive(Debug, Clone)]
pub struct ConditionedSampler {
    pub t_c: usize,
    pub steps: usize,
    pub moments: Moments,
    /// F^b_t and a square root of V^b_t, for t = 2..=t_c (index t−2).
    pub backward: Vec<(DMatrix<f64>, DMatrix<f64>)>,
    /// Forward: F_t, B_t u_t, sqrt V_t for t = t_c..steps−1 (index t − t_c).
    pub forward: Vec<(DMatrix<f64>, DVector<f64>, DMatrix<f64>)>,
    /// H_t and sqrt W_t, t = 1..=steps (index t−1).
    pub output: Vec<(DMatrix<f64>, DMatrix<f64>)>,
}

impl ConditionedSampler {
    /// Prepare draws conditioned on x_{t_c}; `t_c` must lie in 1..=steps.
    pub fn new(model: &LinearModel, steps: usize, u: &Inputs, t_c: usize) -> Result<Self> {
        if t_c < 1 || t_c > steps {
            return Err(Error::field(
                "condition.t",
                format!(
                    "must be a whole number from 1 to {steps} (the simulated horizon), found {t_c}"
                ),
            ));
        }
        let moments = model.moments(steps, u);
        let mut backward = Vec::new();
        for t in 2..=t_c {
            let step = model.backward_step(t, &moments)?;
            backward.push((step.f_b, psd_sqrt(&step.v_b)));
        }
        let forward = (t_c..steps)
            .map(|t| {
                (
                    model.f(t).clone(),
                    model.input_term(t, u),
                    psd_sqrt(model.v(t)),
                )
            })
            .collect();
        let output = (1..=steps)
            .map(|t| (model.h(t).clone(), psd_sqrt(model.w(t))))
            .collect();
        Ok(ConditionedSampler {
            t_c,
            steps,
            moments,
            backward,
            forward,
            output,
        })
    }

    /// One realization with x_{t_c} = x_c.
    pub fn draw<R: Rng>(&self, model: &LinearModel, x_c: &DVector<f64>, rng: &mut R) -> Trajectory {
        let n = model.n();
        let mut x = vec![DVector::zeros(n); self.steps];
        x[self.t_c - 1] = x_c.clone();
        for t in (2..=self.t_c).rev() {
            let (f_b, l) = &self.backward[t - 2];
            let dev = &x[t - 1] - &self.moments.mean[t - 1];
            x[t - 2] = &self.moments.mean[t - 2] + f_b * dev + l * normal_vector(n, rng);
        }
        for t in self.t_c..self.steps {
            let (f, bu, l) = &self.forward[t - self.t_c];
            x[t] = f * &x[t - 1] + bu + l * normal_vector(n, rng);
        }
        let y = x
            .iter()
            .zip(&self.output)
            .map(|(xt, (h, l))| h * xt + l * normal_vector(h.nrows(), rng))
            .collect();
        Trajectory { x, y }
    }
}
