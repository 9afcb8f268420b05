//! Kalman filter (SCF paper (35a)–(35c), initialisation (36)) and its set estimate
//! X^KF_t = E^α_{P_t}(x̂^KF_t).
//!
//! The covariances and gains do not depend on the data, so they are computed once
//! ([`KalmanGains`]) and the data pass ([`KalmanGains::filter`]) is a few matrix-vector products
//! per step — which is what makes a 10,000-run Monte Carlo cheap.
//!
//! Gaps (a missing measurement, [`crate::scenario::DataSpec`]): at a step with no output
//! measured the update is skipped, x̂_t = x̂⁻_t and P_t = P⁻_t (K_t = 0); at a step with some
//! outputs missing the update is the textbook partial one, (35b)–(35c) with the observed rows
//! of H and the matching block of W ([`KalmanGains::with_gaps`]). The filter still keeps one
//! step per record row.
//!
//! Initialisation: (36) sets x̂_0 = 0, P_0 = Γ for a stationary process, which gives the prior
//! of x_1, x̂_{1|0} = 0 and P_{1|0} = FΓFᵀ + V = Γ. We start from the prior of x_1 directly,
//! x̂_{1|0} = m_1, P_{1|0} = Γ_1, which is the same in the stationary case and also covers a
//! known initial state (Γ_1 = 0) and inputs (SCF V-D, V-E).

use crate::error::{Error, Result};
use crate::linalg::symmetrize;
use crate::model::{Inputs, LinearModel, Moments};
use nalgebra::{DMatrix, DVector};

/// Data-independent quantities of one step t.
#[derive(Debug, Clone)]
pub struct GainStep {
    /// P_{t|t−1}: prediction error covariance.
    pub p_pred: DMatrix<f64>,
    /// K_t (35b).
    pub k: DMatrix<f64>,
    /// P_t (35c): filtering error covariance.
    pub p: DMatrix<f64>,
}

/// Gains and covariances for t = 1..=T (index t−1).
#[derive(Debug, Clone)]
pub struct KalmanGains {
    pub steps: Vec<GainStep>,
}

/// K = P⁻Hᵀ(W + HP⁻Hᵀ)⁻¹ and the Joseph form of (35c), P = (I − KH)P⁻(I − KH)ᵀ + KWKᵀ, which
/// equals (35c) exactly but stays positive semidefinite under rounding.
fn update(
    p_pred: &DMatrix<f64>,
    h: &DMatrix<f64>,
    w: &DMatrix<f64>,
) -> Result<(DMatrix<f64>, DMatrix<f64>)> {
    let s = symmetrize(&(w + h * p_pred * h.transpose()));
    let s_chol = s
        .cholesky()
        .ok_or_else(|| Error::field("model.W", "gives a singular innovation covariance"))?;
    // Kᵀ = S⁻¹ H P⁻ (S and P⁻ symmetric).
    let k = s_chol.solve(&(h * p_pred)).transpose();
    let i_kh = DMatrix::identity(p_pred.nrows(), p_pred.ncols()) - &k * h;
    let p = symmetrize(&(&i_kh * p_pred * i_kh.transpose() + &k * w * k.transpose()));
    Ok((k, p))
}

/// The update (35b)–(35c) with only the outputs `observed` measured at this step (a gap in
/// the record, [`crate::scenario::DataSpec`]): the textbook partial update. The measured part
/// of the output equation is y°_t = H° x_t + w°_t with H° the observed rows of H and
/// W° = Cov(w°_t) the matching block of W; (35b)–(35c) with H°, W° give K°_t (n × q°) and
/// P_t. The gain is returned as the n × q matrix K_t whose columns at the missing outputs are
/// zero (K_t = K°_t S with S the selection of the observed rows), so K_t e_t = K°_t e°_t
/// whatever stands in e_t at a missing output once it is read as 0 ([`innovation`]), and the
/// ratio recursion (38) reads K_t as it is (see [`crate::scf::ratio_recursion`]). With no
/// output measured, K_t = 0 and P_t = P⁻_t exactly: the update is skipped. With every output
/// measured this is [`update`] itself, bit for bit.
fn update_observed(
    p_pred: &DMatrix<f64>,
    h: &DMatrix<f64>,
    w: &DMatrix<f64>,
    observed: &[usize],
) -> Result<(DMatrix<f64>, DMatrix<f64>)> {
    let (n, q) = (p_pred.nrows(), h.nrows());
    if observed.len() == q {
        return update(p_pred, h, w);
    }
    let mut k = DMatrix::zeros(n, q);
    if observed.is_empty() {
        return Ok((k, p_pred.clone()));
    }
    let h_o = h.select_rows(observed);
    let w_o = w.select_rows(observed).select_columns(observed);
    let (k_o, p) = update(p_pred, &h_o, &w_o)?;
    for (c, &j) in observed.iter().enumerate() {
        k.set_column(j, &k_o.column(c));
    }
    Ok((k, p))
}

/// The outputs measured at a step: the indices of the finite entries of y_t (a NaN entry is a
/// gap, [`crate::scenario::DataSpec`]); every output for a step beyond the record (`None`).
pub fn observed_outputs(y: Option<&DVector<f64>>, q: usize) -> Vec<usize> {
    match y {
        Some(y) => (0..q)
            .filter(|&j| y.get(j).is_some_and(|x| !x.is_nan()))
            .collect(),
        None => (0..q).collect(),
    }
}

/// The innovation e_t = y_t − H_t x̂⁻_t (35a) with a missing output's entry read as 0: the
/// gain's column there is zero ([`update_observed`]), so the update takes the measured
/// outputs only, and a NaN never enters the estimate.
pub fn innovation(y: &DVector<f64>, h: &DMatrix<f64>, x_pred: &DVector<f64>) -> DVector<f64> {
    let mut e = y - h * x_pred;
    for (ej, yj) in e.iter_mut().zip(y.iter()) {
        if yj.is_nan() {
            *ej = 0.0;
        }
    }
    e
}

impl KalmanGains {
    /// Riccati recursion from P_{1|0} = Γ_1 for `steps` steps, every output measured.
    pub fn new(model: &LinearModel, steps: usize) -> Result<Self> {
        Self::with_gaps(model, steps, &[])
    }

    /// Riccati recursion from P_{1|0} = Γ_1 for `steps` steps with the record's gaps: at step
    /// t only the finite entries of `y[t − 1]` are measured ([`observed_outputs`]; a step
    /// beyond `y` has every output). At a step with no output the update is skipped
    /// (K_t = 0, P_t = P⁻_t), at a step with some the update takes those rows of H and that
    /// block of W ([`update_observed`]). The gains stay data-independent given which outputs
    /// were measured: the same pattern on any other record (a calibration run) gives the
    /// same K_t and P_t.
    pub fn with_gaps(model: &LinearModel, steps: usize, y: &[DVector<f64>]) -> Result<Self> {
        let mut out = Vec::with_capacity(steps);
        let mut p_pred = model.x1_cov.clone();
        let q = model.q();
        for t in 1..=steps {
            let observed = observed_outputs(y.get(t - 1), q);
            let (k, p) = update_observed(&p_pred, model.h(t), model.w(t), &observed)?;
            let f = model.f(t);
            let next = symmetrize(&(f * &p * f.transpose() + model.v(t)));
            out.push(GainStep { p_pred, k, p });
            p_pred = next;
        }
        Ok(KalmanGains { steps: out })
    }

    /// (35a): x̂_t = x̂_{t|t−1} + K_t (y_t − H_t x̂_{t|t−1}), x̂_{t+1|t} = F_t x̂_t + B_t u_t.
    /// A missing output (NaN) adds nothing ([`innovation`]): with gains from
    /// [`KalmanGains::with_gaps`] on the same record, x̂_t = x̂_{t|t−1} at a step with no
    /// measurement.
    pub fn filter(&self, model: &LinearModel, y: &[DVector<f64>], u: &Inputs) -> Vec<DVector<f64>> {
        let mut x_pred = model.x1_mean.clone();
        let mut out = Vec::with_capacity(y.len());
        for (i, yt) in y.iter().enumerate().take(self.steps.len()) {
            let t = i + 1;
            let x = &x_pred + &self.steps[i].k * innovation(yt, model.h(t), &x_pred);
            x_pred = model.f(t) * &x + model.input_term(t, u);
            out.push(x);
        }
        out
    }
}

/// τ-step Kalman prediction from time t: x̂_{t+τ|t} = F x̂_{t+τ−1|t} + Bu, and
/// P_{t+τ|t} = F P_{t+τ−1|t} Fᵀ + V (SCF footnote 16).
pub fn predict(
    model: &LinearModel,
    t: usize,
    tau: usize,
    mean: &DVector<f64>,
    cov: &DMatrix<f64>,
    u: &Inputs,
) -> (DVector<f64>, DMatrix<f64>) {
    let (mut m, mut p) = (mean.clone(), cov.clone());
    for s in t..t + tau {
        let f = model.f(s);
        m = f * &m + model.input_term(s, u);
        p = symmetrize(&(f * &p * f.transpose() + model.v(s)));
    }
    (m, p)
}

/// Steady state of a time-invariant filter: P̄⁻, K̄, P̄ by iterating the Riccati recursion from
/// Γ until it stops moving (it converges for a stable F, SCF IV-B).
#[derive(Debug, Clone)]
pub struct SteadyState {
    pub p_pred: DMatrix<f64>,
    pub k: DMatrix<f64>,
    pub p: DMatrix<f64>,
    /// Iterations used.
    pub iterations: usize,
}

/// See [`SteadyState`].
pub fn steady_state(model: &LinearModel) -> Result<SteadyState> {
    if !model.is_time_invariant() {
        return Err(Error::field(
            "model",
            "the asymptotic filter needs a time-invariant model",
        ));
    }
    let mut p_pred = model.stationary_covariance()?;
    for it in 1..=100_000 {
        let (_, p) = update(&p_pred, model.h(1), model.w(1))?;
        let f = model.f(1);
        let next = symmetrize(&(f * &p * f.transpose() + model.v(1)));
        let moved = (&next - &p_pred).amax();
        p_pred = next;
        if moved <= 1e-14 * p_pred.amax().max(f64::MIN_POSITIVE) {
            let (k, p) = update(&p_pred, model.h(1), model.w(1))?;
            return Ok(SteadyState {
                p_pred,
                k,
                p,
                iterations: it,
            });
        }
    }
    Err(Error::field(
        "model",
        "the Riccati recursion did not converge in 100000 steps",
    ))
}

/// Prior moments together with the filter's covariances, the data-independent half of KF and
/// SCF for one scenario.
#[derive(Debug, Clone)]
pub struct Offline {
    pub moments: Moments,
    pub gains: KalmanGains,
}

impl Offline {
    /// Compute both for `steps` steps.
    pub fn new(model: &LinearModel, steps: usize, u: &Inputs) -> Result<Self> {
        Self::with_gaps(model, steps, u, &[])
    }
    /// Both for `steps` steps with the gaps of the record `y` ([`KalmanGains::with_gaps`]);
    /// the prior moments do not depend on what was measured.
    pub fn with_gaps(
        model: &LinearModel,
        steps: usize,
        u: &Inputs,
        y: &[DVector<f64>],
    ) -> Result<Self> {
        Ok(Offline {
            moments: model.moments(steps, u),
            gains: KalmanGains::with_gaps(model, steps, y)?,
        })
    }
}

/// Check that a time index lies in 1..=steps.
pub fn check_time(field: &str, t: usize, steps: usize) -> Result<()> {
    if t < 1 || t > steps {
        return Err(Error::field(
            field,
            format!("must be a whole number from 1 to {steps}, found {t}"),
        ));
    }
    Ok(())
}
