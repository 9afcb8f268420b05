//! Kalman filter (SCF paper (35a)–(35c), initialisation (36)) and its set estimate
//! X^KF_t = E^α_{P_t}(x̂^KF_t).
//!
//! The covariances and gains do not depend on the data, so they are computed once
//! ([`KalmanGains`]) and the data pass ([`KalmanGains::filter`]) is a few matrix-vector products
//! per step — which is what makes a 10,000-run Monte Carlo cheap.
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

impl KalmanGains {
    /// Riccati recursion from P_{1|0} = Γ_1 for `steps` steps.
    pub fn new(model: &LinearModel, steps: usize) -> Result<Self> {
        let mut out = Vec::with_capacity(steps);
        let mut p_pred = model.x1_cov.clone();
        for t in 1..=steps {
            let (k, p) = update(&p_pred, model.h(t), model.w(t))?;
            let f = model.f(t);
            let next = symmetrize(&(f * &p * f.transpose() + model.v(t)));
            out.push(GainStep { p_pred, k, p });
            p_pred = next;
        }
        Ok(KalmanGains { steps: out })
    }

    /// (35a): x̂_t = x̂_{t|t−1} + K_t (y_t − H_t x̂_{t|t−1}), x̂_{t+1|t} = F_t x̂_t + B_t u_t.
    pub fn filter(&self, model: &LinearModel, y: &[DVector<f64>], u: &Inputs) -> Vec<DVector<f64>> {
        let mut x_pred = model.x1_mean.clone();
        let mut out = Vec::with_capacity(y.len());
        for (i, yt) in y.iter().enumerate().take(self.steps.len()) {
            let t = i + 1;
            let x = &x_pred + &self.steps[i].k * (yt - model.h(t) * &x_pred);
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
        Ok(Offline {
            moments: model.moments(steps, u),
            gains: KalmanGains::new(model, steps)?,
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
