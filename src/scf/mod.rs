//! State Conditional Filter — A. Carè, M. C. Campi, E. Weyer, *State Conditional Filtering*,
//! IEEE TAC (seed 001).
//!
//! X^SCF_t = {x : (x − x̂_t)ᵀ Π_t⁻¹ (x − x̂_t) ≤ χ²(α, n)} (40) contains x_t with probability α
//! *whatever the value of x_t* (Property 1), where, with the ratio matrix R_t = U_tA_t,
//!
//! * x̂_t = R_t⁻¹ x̂^KF_t (33), Π_t = R_t⁻¹ P_t (34);
//! * R_t = F R_{t−1} F^b + K_t (H − H F R_{t−1} F^b), R_0 = 0 (38)–(39), which equals the closed
//!   form R_t = I − P_t Γ_t⁻¹ (41) — tested along the recursion;
//! * asymptotically R̄ = I − P̄ Γ⁻¹ (IV-B);
//! * components ζ only: R^(s) = I − P^(s) (Γ^(s))⁻¹ with the upper-left blocks (V-A);
//! * τ-step prediction: the same with P_{t+τ|t} and Γ_{t+τ} (V-B, V-C);
//! * time-varying / non-stationary systems: Γ_t propagated, F^b_t from (45) (V-D);
//! * gaps in the record (a missing y_t, or some of its outputs): (38) with the Kalman gain of
//!   the measured outputs, zero at a full gap, so the ratio only propagates there (derived in
//!   [`ratio_recursion`]); the asymptotic filter refuses a gap;
//! * measured inputs: x̂_t = R_t⁻¹ x̂^KF_t + (I − R_t⁻¹) d_t with d_t the input response
//!   (V-E). We write it as x̂_t = m_t + R_t⁻¹(x̂^KF_t − m_t) with m_t = E(x_t), which is the same
//!   formula and also covers a non-zero prior mean of x_1.

pub mod experiment;
pub use experiment::{
    CollisionSpec, ConditionalExperiment, CoverageCurve, CurveSpec, ExperimentResult,
    ExperimentSpec, Generator,
};

use crate::error::{Error, Result};
use crate::kalman::{self, KalmanGains, Offline};
use crate::linalg::{self, sub_matrix, sub_vector, symmetrize};
use crate::model::{Inputs, LinearModel};
use crate::sets::Ellipsoid;
use crate::stats::chi2_quantile;
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// A ratio matrix is treated as singular below this reciprocal condition number: the SCF
/// region would be unbounded in some direction (the data carry no information on it yet).
pub const RATIO_RCOND_MIN: f64 = 1e-12;

/// The ratio matrices R_t = U_tA_t, t = 1..=T, by the recursion (38) from R_0 = 0 (39).
/// For t ≥ 2 the backward matrix is F^b_t = Γ_{t−1}F_{t−1}ᵀΓ_t⁻¹ ((30), or (45) when Γ_t moves).
///
/// **Gaps.** The SCF conditions on the observations: with y_t (or some of its outputs)
/// missing, the batch (31)–(32) at time t simply has no row block (or fewer rows) for it. Let
/// y°_t = S_t y_t be the measured outputs (S_t the selection of the observed rows, q° of q),
/// H° = S_t H, W° = S_t W S_tᵀ. Then
///
/// * (32) reads [y°]_1^t = A_t x_t + ν_t with A_t = [H°; A_{t−1}F^b] (the decomposition
///   under (37) with H° in place of H; A_t = A_{t−1}F^b when nothing is measured), and x_t
///   and ν_t are still independent (ν_t holds the backward noise (29) and the measured w's),
///   so Conditions 1 and 3 of Section III hold and (33)–(34) still give the SCF region, with
///   the U_t of the filter that saw [y°]_1^t;
/// * the Kalman filter on [y°]_1^t is (35a)–(35c) with H°, W° at t: gain K°_t (n × q°),
///   x̂ᴷᶠ_t = F x̂ᴷᶠ_{t−1} + K°_t (y°_t − H° F x̂ᴷᶠ_{t−1}); with nothing measured, K°_t is
///   empty and x̂ᴷᶠ_t = F x̂ᴷᶠ_{t−1}, P_t = P⁻_t ([`crate::kalman::KalmanGains::with_gaps`]);
/// * so (37) becomes U_t[h°; η] = FU_{t−1}η + K°_t(h° − H°FU_{t−1}η), and applying it to the
///   columns of A_t = [H°; A_{t−1}F^b] as the paper does gives
///   R_t = F R_{t−1} F^b + K°_t (H° − H° F R_{t−1} F^b): (38) with the missing rows of H left
///   out. With K_t = K°_t S_t (the n × q gain whose columns at the missing outputs are zero,
///   as the filter stores it), K°_t H° = K_t H, so this is (38) exactly as written; with
///   nothing measured, K_t = 0 and R_t = F R_{t−1} F^b: the ratio only propagates.
/// * (14) P_t = Γ_t − R_t Γ_t holds for the linear Bayesian estimate of any such batch, so the
///   closed form (41) R_t = I − P_t Γ_t⁻¹ still holds with the gap's P_t (tested along the
///   recursion). Over a gap P_t grows towards Γ_t and R_t shrinks towards 0: Π_t = R_t⁻¹P_t
///   (34) widens faster than P_t, and once fewer than n independent measurements remain in
///   [y°]_1^t (Condition 2, A_t of full column rank, footnote 13's "t ≥ n" counted in
///   measured steps) R_t is singular and there is no SCF region ([`scf_from_ratio`]).
///
/// This function needs nothing more than the gains: a gap is already in K_t.
pub fn ratio_recursion(model: &LinearModel, offline: &Offline) -> Result<Vec<DMatrix<f64>>> {
    let n = model.n();
    let mut out: Vec<DMatrix<f64>> = Vec::with_capacity(offline.gains.steps.len());
    for (i, g) in offline.gains.steps.iter().enumerate() {
        let t = i + 1;
        let h = model.h(t);
        let r = if t == 1 {
            &g.k * h // (38) with R_0 = 0
        } else {
            let f_b = model.backward_step(t, &offline.moments)?.f_b;
            let m = model.f(t - 1) * &out[i - 1] * f_b;
            &m + &g.k * (h - h * &m)
        };
        debug_assert_eq!(r.nrows(), n);
        out.push(r);
    }
    Ok(out)
}

/// Closed form (41): R = I − P Γ⁻¹ (for components ζ: with the ζ blocks of P and Γ).
pub fn ratio_closed_form(p: &DMatrix<f64>, gamma: &DMatrix<f64>) -> Result<DMatrix<f64>> {
    let g_inv = linalg::inverse("Γ_t (prior covariance of the estimated components)", gamma)?;
    Ok(DMatrix::identity(p.nrows(), p.ncols()) - p * g_inv)
}

/// Why there is no SCF region at time t for `n` estimated components, in words with the
/// numbers: before t = n there are fewer measurements than states; after, the ratio matrix
/// (`ratio`, when known) is singular to [`RATIO_RCOND_MIN`] because the measurements do not
/// determine every component (Assumption 3).
pub fn singular_ratio(t: usize, n: usize, ratio: Option<&DMatrix<f64>>) -> String {
    if t < n {
        return format!(
            "t = {t} is before t = n = {n}, from which on the SCF region (40) is formed (with one output per step the ratio matrix U_tA_t (38) has rank at most t before)"
        );
    }
    let rc = ratio.map(linalg::rcond).filter(|r| r.is_finite());
    format!(
        "the ratio matrix U_tA_t (38) is singular at t = {t}{} although t ≥ n = {n}: the measurements so far do not determine every component (the pair (F^b, H) is not observable, Assumption 3), so the SCF region (40) would be unbounded; estimate the observable components only (scf.components)",
        match rc {
            Some(r) => format!(" (reciprocal condition {r:.1e}, below {RATIO_RCOND_MIN:.0e})"),
            None => String::new(),
        }
    )
}

/// SCF center and shape from the KF ones and a ratio matrix: x̂ = m + R⁻¹(x̂^KF − m) (33, V-E),
/// Π = R⁻¹P (34). `None` while R is singular (fewer informative measurements than states).
pub fn scf_from_ratio(
    ratio: &DMatrix<f64>,
    kf_mean: &DVector<f64>,
    p: &DMatrix<f64>,
    prior_mean: &DVector<f64>,
) -> Option<(DVector<f64>, DMatrix<f64>)> {
    let (r_inv, rc) = linalg::inverse_rcond(ratio)?;
    if !(rc >= RATIO_RCOND_MIN) {
        return None;
    }
    let center = prior_mean + &r_inv * (kf_mean - prior_mean);
    let pi = symmetrize(&(&r_inv * p));
    Some((center, pi))
}

/// KF and SCF regions of one target (components ζ of x at some time), at level α.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct RegionPair {
    /// Time the region is about (t + τ).
    pub time: usize,
    /// State components (0-based) the regions are about.
    pub components: Vec<usize>,
    pub kf: Ellipsoid,
    /// `None` while the ratio matrix is singular.
    pub scf: Option<Ellipsoid>,
    /// R for these components (closed form I − P Γ⁻¹).
    pub ratio: Option<Vec<Vec<f64>>>,
}

/// KF/SCF regions for components `idx` from KF mean/cov and prior moments at the same time.
pub fn region_pair(
    time: usize,
    idx: &[usize],
    kf_mean: &DVector<f64>,
    p: &DMatrix<f64>,
    prior_mean: &DVector<f64>,
    gamma: &DMatrix<f64>,
    alpha: f64,
) -> Result<RegionPair> {
    let r2 = chi2_quantile(alpha, idx.len())?;
    let (xk, pk) = (sub_vector(kf_mean, idx), sub_matrix(p, idx));
    let (mk, gk) = (sub_vector(prior_mean, idx), sub_matrix(gamma, idx));
    let kf = Ellipsoid::new(&xk, &pk, r2);
    let (scf, ratio) = match linalg::inverse("Γ", &gk) {
        Ok(_) => {
            let ratio = ratio_closed_form(&pk, &gk)?;
            let scf =
                scf_from_ratio(&ratio, &xk, &pk, &mk).map(|(c, pi)| Ellipsoid::new(&c, &pi, r2));
            (scf, Some(linalg::to_rows(&ratio)))
        }
        Err(_) => (None, None),
    };
    Ok(RegionPair {
        time,
        components: idx.to_vec(),
        kf,
        scf,
        ratio,
    })
}

/// Options of the filter run.
#[derive(Debug, Clone, PartialEq)]
pub struct ScfOptions {
    /// Probability level α ∈ (0, 1).
    pub alpha: f64,
    /// Components ζ for the extra region (V-A, V-C); `None` = all.
    pub components: Option<Vec<usize>>,
    /// Prediction horizon τ for the extra region (V-B, V-C); 0 = filtering.
    pub tau: usize,
    /// Use the asymptotic (constant-gain, constant-ratio) filter of IV-B.
    pub asymptotic: bool,
    /// Kalman filter only (method "kf"): no SCF regions, so no observability requirement.
    pub kf_only: bool,
}

/// Everything reported at time t.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ScfStep {
    pub t: usize,
    /// X^KF_t.
    pub kf: Ellipsoid,
    /// X^SCF_t (40); `None` before the ratio matrix is invertible (t < n, or no information yet).
    pub scf: Option<Ellipsoid>,
    /// Ratio matrix U_tA_t from the recursion (38).
    pub ratio: Vec<Vec<f64>>,
    /// Regions of the components ζ at t + τ given y_1..y_t, when components or τ were asked for.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<RegionPair>,
}

/// Data-independent part of the asymptotic filter (IV-B).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Asymptotic {
    /// Stationary covariance Γ.
    pub gamma: Vec<Vec<f64>>,
    /// P̄ = lim P_t.
    pub p: Vec<Vec<f64>>,
    /// K̄ = lim K_t.
    pub k: Vec<Vec<f64>>,
    /// R̄ = I − P̄Γ⁻¹.
    pub ratio: Vec<Vec<f64>>,
    /// Π̄ = R̄⁻¹P̄.
    pub pi: Vec<Vec<f64>>,
    /// Backward matrix F^b = ΓFᵀΓ⁻¹ (30).
    pub f_b: Vec<Vec<f64>>,
    /// Backward noise covariance V^b = Γ − F^bΓF^bᵀ.
    pub v_b: Vec<Vec<f64>>,
}

/// Steady-state quantities of a stable time-invariant model.
pub fn asymptotic(model: &LinearModel) -> Result<Asymptotic> {
    let ss = kalman::steady_state(model)?;
    let gamma = model.stationary_covariance()?;
    let back = model.backward_representation()?;
    let ratio = ratio_closed_form(&ss.p, &gamma)?;
    let singular = || {
        Error::field(
            "model.H",
            "does not make the state observable: the asymptotic ratio matrix is singular",
        )
    };
    // The same threshold as the filter's regions: an unobservable direction leaves R̄ singular
    // only up to rounding (≈1e-16), and inverting it would report a Π̄ of ≈1e16.
    if !(linalg::rcond(&ratio) >= RATIO_RCOND_MIN) {
        return Err(singular());
    }
    let r_inv = linalg::inverse("asymptotic ratio matrix R̄", &ratio).map_err(|_| singular())?;
    let all_finite = [&gamma, &ss.p, &ss.k, &ratio, &r_inv, &back.f_b, &back.v_b]
        .iter()
        .all(|m| m.iter().all(|x| x.is_finite()));
    if !all_finite {
        return Err(Error::field(
            "model",
            "overflows double precision in the asymptotic filter: rescale the model",
        ));
    }
    Ok(Asymptotic {
        gamma: linalg::to_rows(&gamma),
        p: linalg::to_rows(&ss.p),
        k: linalg::to_rows(&ss.k),
        ratio: linalg::to_rows(&ratio),
        pi: linalg::to_rows(&symmetrize(&(r_inv * &ss.p))),
        f_b: linalg::to_rows(&back.f_b),
        v_b: linalg::to_rows(&back.v_b),
    })
}

/// The SCF and KF over data y_1..y_T: regions at every step.
pub struct ScfRun {
    pub steps: Vec<ScfStep>,
    /// KF means x̂^KF_t.
    pub kf_means: Vec<DVector<f64>>,
}

/// Run KF and SCF over `y` (and inputs `u`).
pub fn run(
    model: &LinearModel,
    y: &[DVector<f64>],
    u: &Inputs,
    opts: &ScfOptions,
) -> Result<ScfRun> {
    let steps = y.len();
    let n = model.n();
    if let Some(idx) = &opts.components {
        Ellipsoid::new(&DVector::zeros(n), &DMatrix::identity(n, n), 1.0).project(idx)?;
    }
    let r2 = chi2_quantile(opts.alpha, n)?;
    let gap = y.iter().any(|v| v.iter().any(|x| x.is_nan()));
    if opts.asymptotic && gap {
        return Err(asymptotic_gap_error());
    }
    // The gains with the record's gaps (skipped or partial updates); the steps past the
    // record (τ ahead) measure every output, and are cut off here anyway.
    let mut offline = Offline::with_gaps(model, steps + opts.tau, u, y)?;
    offline.gains.steps.truncate(steps);
    let (gains, ratios) = if opts.asymptotic {
        let ss = kalman::steady_state(model)?;
        let gamma = model.stationary_covariance()?;
        let ratio = ratio_closed_form(&ss.p, &gamma)?;
        let gains = KalmanGains {
            steps: (0..steps)
                .map(|_| kalman::GainStep {
                    p_pred: ss.p_pred.clone(),
                    k: ss.k.clone(),
                    p: ss.p.clone(),
                })
                .collect(),
        };
        (gains, vec![ratio; steps])
    } else {
        let ratios = ratio_recursion(model, &offline)?;
        (offline.gains.clone(), ratios)
    };
    let kf_means = gains.filter(model, y, u);
    let mut out = Vec::with_capacity(steps);
    let mut any_scf = false;
    // Footnote 13's "t ≥ n" counts measurements: the steps with at least one output measured.
    let mut measured_steps = 0;
    for i in 0..steps {
        let t = i + 1;
        measured_steps += usize::from(y[i].iter().any(|x| !x.is_nan()));
        let g = &gains.steps[i];
        let m_t = &offline.moments.mean[i];
        let kf = Ellipsoid::new(&kf_means[i], &g.p, r2);
        let scf = if measured_steps >= n {
            scf_from_ratio(&ratios[i], &kf_means[i], &g.p, m_t)
                .map(|(c, pi)| Ellipsoid::new(&c, &pi, r2))
        } else {
            None
        };
        any_scf |= scf.is_some();
        let target = if opts.components.is_some() || opts.tau > 0 {
            let idx: Vec<usize> = opts.components.clone().unwrap_or_else(|| (0..n).collect());
            let (xp, pp) = kalman::predict(model, t, opts.tau, &kf_means[i], &g.p, u);
            let (mp, gp) = if opts.asymptotic {
                (m_t.clone(), model.stationary_covariance()?)
            } else {
                (
                    offline.moments.mean[i + opts.tau].clone(),
                    offline.moments.cov[i + opts.tau].clone(),
                )
            };
            Some(region_pair(
                t + opts.tau,
                &idx,
                &xp,
                &pp,
                &mp,
                &gp,
                opts.alpha,
            )?)
        } else {
            None
        };
        out.push(ScfStep {
            t,
            kf,
            scf,
            ratio: linalg::to_rows(&ratios[i]),
            target,
        });
    }
    if !any_scf && !opts.kf_only && gap && measured_steps >= n {
        return Err(Error::field(
            "data.y",
            format!(
                "leaves the state unobservable: with the record's gaps the ratio matrix U_tA_t (38) stayed singular at every step \
                 ({measured_steps} of {steps} steps measured; Condition 2 needs n = {n} independent measurements in the batch (32)) — fill gaps, or estimate observable components only"
            ),
        ));
    }
    if steps >= n && !any_scf && !opts.kf_only && !gap {
        return Err(Error::field(
            "model.H",
            "does not make the state observable from the data: the ratio matrix U_tA_t stayed singular \
             (the pair (F^b, H) is not observable, Assumption 3) — estimate observable components only",
        ));
    }
    check_finite(&out)?;
    Ok(ScfRun {
        steps: out,
        kf_means,
    })
}

/// The asymptotic filter (IV-B) cannot take a gap: its constant K̄, P̄ and R̄ = I − P̄Γ⁻¹ are
/// the limits of (35b)–(35c) and (41) when every measurement arrives; at a gap P_t leaves P̄
/// (it grows by FP̄Fᵀ + V − P̄) and a region with P̄ would be too small for the level claimed.
pub(crate) fn asymptotic_gap_error() -> Error {
    Error::field(
        "scf.asymptotic",
        "cannot take a record with gaps: the asymptotic SCF (IV-B) uses the limits K̄, P̄, R̄ of a filter that reads every measurement, and at a gap P_t leaves P̄, so its regions would be too small; use the recursive SCF (\"asymptotic\": false), which skips the update at a gap",
    )
}

/// Every number of a run must be finite (a report is JSON numbers; NaN/∞ would become null).
/// Finite but extreme inputs (entries near f64::MAX) can still overflow: say where. Shapes and
/// ratios depend on the model only, centers also on the data.
fn check_finite(steps: &[ScfStep]) -> Result<()> {
    let fin = |v: &[f64]| v.iter().all(|x| x.is_finite());
    let shape = |e: &Ellipsoid| e.radius2.is_finite() && e.cov.iter().all(|r| fin(r));
    let opt_shape = |e: &Option<Ellipsoid>| e.as_ref().is_none_or(shape);
    let center = |e: &Ellipsoid| fin(&e.center);
    let opt_center = |e: &Option<Ellipsoid>| e.as_ref().is_none_or(center);
    for st in steps {
        let mut shapes_ok = shape(&st.kf) && opt_shape(&st.scf) && st.ratio.iter().all(|r| fin(r));
        let mut centers_ok = center(&st.kf) && opt_center(&st.scf);
        if let Some(tg) = &st.target {
            shapes_ok &= shape(&tg.kf)
                && opt_shape(&tg.scf)
                && tg.ratio.as_ref().is_none_or(|m| m.iter().all(|r| fin(r)));
            centers_ok &= center(&tg.kf) && opt_center(&tg.scf);
        }
        if !shapes_ok {
            return Err(Error::field(
                "model",
                format!(
                    "overflows double precision at t = {}: the filter's covariances are not finite — rescale the model",
                    st.t
                ),
            ));
        }
        if !centers_ok {
            return Err(Error::field(
                "data.y",
                format!(
                    "overflows double precision at t = {}: the estimates are not finite — rescale the measurements",
                    st.t
                ),
            ));
        }
    }
    Ok(())
}

/// P{x_t ∈ X_t | x_t = x̄} for KF and SCF — the conditional coverage of Fig. 1.
///
/// Given x_t = x̄, the KF estimate is Gaussian: x̂^KF_t − m_t ~ N(R_t(x̄ − m_t), P_t − P_tΓ_t⁻¹P_t)
/// (the paper's footnote 1 in n dimensions: the conditional covariance is U Cov(ν) Uᵀ = P Rᵀ).
/// For one dimension both probabilities are closed forms in the normal CDF.
pub fn conditional_coverage_1d(
    p: f64,
    gamma: f64,
    prior_mean: f64,
    xbar: f64,
    alpha: f64,
) -> Result<(f64, f64)> {
    use statrs::distribution::{ContinuousCDF, Normal};
    let r = 1.0 - p / gamma;
    let sd = (p * r).max(0.0).sqrt();
    let chi = chi2_quantile(alpha, 1)?;
    let phi = Normal::new(0.0, 1.0).map_err(|e| Error::field("", e.to_string()))?;
    // KF: x̂ − x̄ ~ N((r − 1)(x̄ − m), p r); inside iff |x̂ − x̄| ≤ ρ = √(χ² p).
    let rho = (chi * p).sqrt();
    let mu = (r - 1.0) * (xbar - prior_mean);
    let kf = phi.cdf((rho - mu) / sd) - phi.cdf((-rho - mu) / sd);
    // SCF: x̂_SCF − x̄ ~ N(0, p r / r²) = N(0, Π); inside iff |x̂_SCF − x̄| ≤ √(χ² Π).
    let pi = p / r;
    let rho_s = (chi * pi).sqrt();
    let sd_s = sd / r;
    let scf = phi.cdf(rho_s / sd_s) - phi.cdf(-rho_s / sd_s);
    Ok((kf, scf))
}
