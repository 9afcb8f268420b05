//! GLLS moving-horizon estimation: V. Gubarev and M. Mishchenko, "Interval state estimator for
//! linear systems with known structure" (seed 003).
//!
//! Model (7)–(8): x(k+1) = A x(k) + B u(k), y(k) = C x(k) + δ(k), Cov δ(k) = Ω (m×m), u known.
//! Over the horizon y(k−s), …, y(k) (s + 1 measurements) the trajectory form (10) reads
//! y(k,s) = Γ_{s+1} x(k−s) + Φ_{s+1} u(k,s) + δ(k,s).
//!
//! * [`Horizon`]: Γ_{s+1}, Φ_{s+1}, the GLLS gain of the past state (11) in the SVD form (21),
//!   the fast-forward to the current state (41), the absolute condition numbers (17), (19), (45),
//!   the truncated-SVD regularized estimators (29), (47) with their projections (31), (48) and
//!   condition numbers (32), (49), and the guaranteed error bounds (35)–(38) with the corrected
//!   √(s+1) (δ(k,s) stacks s + 1 errors: the printed (34) has √s) and the expected-error bound
//!   (39)–(40).
//! * [`Curves`]: σ_i(Γ_{s+1}) and σ_i(Γ_{s+1}A^{−s}) for s = 0..S without forming Γᵀ Γ or a
//!   tall SVD per s: an n×n triangular factor R with σ(R) = σ(Γ_{s+1}) is updated by a QR of
//!   [R; C A^s] as each block arrives, in a scaled representation (R = e^ρ R̂) so that the powers
//!   of an unstable A never overflow; the index σ_n/√s (σ_p/√s regularized, Fig. 2) and its best
//!   horizon; κ curves of LLS and GLLS for the past and the current state. The σ of each small
//!   factor come from an allocation-free Golub–Kahan bidiagonalization + Demmel–Kahan
//!   bidiagonal QR (`SvWork`), relatively accurate down to ε·σ₁ and beyond on graded factors.
//! * [`StateNoise`]: the estimator (60)–(64) for x(k+1) = A x + B u + ξ, y = C x (54)–(55), as the
//!   closed-form least-norm solution of its KKT system; the same QP through [`crate::solve`].
//! * [`Precision`]: the Monte Carlo of Section 5.1 (error of the current-state estimate against
//!   the horizon, with κ·√E‖δ(k,s)‖²) and of Section 5.2 (state-noise estimator vs LLS), chunked.
//!
//! Erratum handled here (crate docs): the authors' remark that σ(Γ_{s+1}) and σ(Γ_{s+1}A^{−s})
//! coincide is empirical; both are computed and shown, and they differ unless A is orthogonal.

use crate::error::{Error, Result};
use crate::linalg;
use crate::method::Method;
use crate::model::{normal_vector, ModelSpec};
use nalgebra::{DMatrix, DVector};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Most states of a GLLS model (the panel's limit; the work of a report is bounded by the
/// combined budget of `scenario::budget`).
pub const MAX_STATES: usize = 20;

/// The model of (7)–(8), with the optional transition noise of (54).
#[derive(Debug, Clone, PartialEq)]
pub struct GllsModel {
    pub a: DMatrix<f64>,
    /// n×r (r = 0 without inputs).
    pub b: DMatrix<f64>,
    pub c: DMatrix<f64>,
    /// Ω: covariance of δ(k) (m×m, positive semidefinite; GLLS needs it definite).
    pub omega: DMatrix<f64>,
    /// Covariance of ξ(k) in (54) (n×n, zero for the model (7)).
    pub xi: DMatrix<f64>,
    /// x(0) of simulations.
    pub x0: DVector<f64>,
}

impl GllsModel {
    /// From a scenario model: `F` = A, `H` = C, `B`, `W` = Ω (default: identity), `V` = the
    /// covariance of ξ (default 0), `x1_mean` = x(0) (default 0). Errors name the field.
    pub fn from_spec(spec: &ModelSpec) -> Result<Self> {
        if spec.g.is_some() || spec.sigma_v2.is_some() || spec.sigma_w2.is_some() {
            return Err(Error::field("model.G", "is the LSCR noise form: GLLS takes W (Ω, measurement noise) and optionally V (transition noise ξ)"));
        }
        let a = ModelSpec::constant("model.F", &spec.f, Method::Glls)?
            .ok_or_else(|| Error::field("model.F", "is missing"))?;
        let n = a.nrows();
        if a.ncols() != n || n == 0 {
            return Err(Error::field(
                "model.F",
                format!("must be square, found {}×{}", a.nrows(), a.ncols()),
            ));
        }
        if n > MAX_STATES {
            return Err(Error::field(
                "model.F",
                format!("is {n}×{n}: the GLLS panel supports n ≤ {MAX_STATES}"),
            ));
        }
        let c = ModelSpec::constant("model.H", &spec.h, Method::Glls)?
            .ok_or_else(|| Error::field("model.H", "is missing"))?;
        linalg::expect_shape("model.H", &c, c.nrows(), n)?;
        let m = c.nrows();
        let b = ModelSpec::constant("model.B", &spec.b, Method::Glls)?
            .unwrap_or_else(|| DMatrix::zeros(n, 0));
        linalg::expect_shape("model.B", &b, n, b.ncols())?;
        let omega = ModelSpec::constant("model.W", &spec.w, Method::Glls)?
            .unwrap_or_else(|| DMatrix::identity(m, m));
        linalg::expect_shape("model.W", &omega, m, m)?;
        linalg::check_covariance("model.W", &omega, false)?;
        let xi = ModelSpec::constant("model.V", &spec.v, Method::Glls)?
            .unwrap_or_else(|| DMatrix::zeros(n, n));
        linalg::expect_shape("model.V", &xi, n, n)?;
        linalg::check_covariance("model.V", &xi, false)?;
        let x0 = match &spec.x1_mean {
            Some(v) => linalg::vector("model.x1_mean", v, n)?,
            None => DVector::zeros(n),
        };
        Ok(GllsModel {
            a,
            b,
            c,
            omega,
            xi,
            x0,
        })
    }

    pub fn n(&self) -> usize {
        self.a.nrows()
    }
    pub fn m(&self) -> usize {
        self.c.nrows()
    }
    pub fn r(&self) -> usize {
        self.b.ncols()
    }

    /// Seeded simulation of x(0..steps−1), y(0..steps−1) from x(0): δ ~ N(0, Ω), ξ ~ N(0, V).
    pub fn simulate(
        &self,
        steps: usize,
        u: &[DVector<f64>],
        rng: &mut ChaCha8Rng,
    ) -> (Vec<DVector<f64>>, Vec<DVector<f64>>) {
        let (n, m) = (self.n(), self.m());
        let so = linalg::psd_sqrt(&self.omega);
        let sx = linalg::psd_sqrt(&self.xi);
        let noisy_x = self.xi.iter().any(|&v| v != 0.0);
        let mut x = self.x0.clone();
        let (mut xs, mut ys) = (Vec::with_capacity(steps), Vec::with_capacity(steps));
        for k in 0..steps {
            ys.push(&self.c * &x + &so * normal_vector(m, rng));
            xs.push(x.clone());
            let mut next = &self.a * &x;
            if self.r() > 0 {
                next += &self.b * input(u, k, self.r());
            }
            if noisy_x {
                next += &sx * normal_vector(n, rng);
            }
            x = next;
        }
        (xs, ys)
    }
}

/// u(k) (a shorter list holds its last entry; none means zero).
pub fn input(u: &[DVector<f64>], k: usize, r: usize) -> DVector<f64> {
    match u.len() {
        0 => DVector::zeros(r),
        len => u[k.min(len - 1)].clone(),
    }
}

/// Γ_{s+1} = [C; CA; …; CA^s] (6).
pub fn observability(a: &DMatrix<f64>, c: &DMatrix<f64>, s: usize) -> DMatrix<f64> {
    let (m, n) = (c.nrows(), a.nrows());
    let mut g = DMatrix::zeros(m * (s + 1), n);
    let mut block = c.clone();
    for p in 0..=s {
        g.view_mut((p * m, 0), (m, n)).copy_from(&block);
        block = &block * a;
    }
    g
}

/// Φ_{s+1} of (6)/(10): block (p, i) = C A^{p−1−i} B for i < p, zero otherwise; r(s+1) columns
/// (the last block column, u(k), does not reach the horizon).
pub fn history_controllability(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    c: &DMatrix<f64>,
    s: usize,
) -> DMatrix<f64> {
    let (m, r) = (c.nrows(), b.ncols());
    let mut phi = DMatrix::zeros(m * (s + 1), r * (s + 1));
    if r == 0 {
        return phi;
    }
    // C A^j B for j = 0..s−1.
    let mut cab = Vec::with_capacity(s);
    let mut ca = c.clone();
    for _ in 0..s {
        cab.push(&ca * b);
        ca = &ca * a;
    }
    for p in 1..=s {
        for i in 0..p {
            phi.view_mut((p * m, i * r), (m, r))
                .copy_from(&cab[p - 1 - i]);
        }
    }
    phi
}

/// Ψ of (59): block (p, i) = C A^{p−1−i} for i < p (the transition noises ξ(k−s+i), i < s).
pub fn noise_map(a: &DMatrix<f64>, c: &DMatrix<f64>, s: usize) -> DMatrix<f64> {
    let (m, n) = (c.nrows(), a.nrows());
    let mut psi = DMatrix::zeros(m * (s + 1), n * s);
    let mut pw = Vec::with_capacity(s);
    let mut ca = c.clone();
    for _ in 0..s {
        pw.push(ca.clone());
        ca = &ca * a;
    }
    for p in 1..=s {
        for i in 0..p {
            psi.view_mut((p * m, i * n), (m, n))
                .copy_from(&pw[p - 1 - i]);
        }
    }
    psi
}

/// A^s and the fast-forward of the inputs in (41): x(k) = A^s x(k−s) + F_u u(k,s) with block i
/// of F_u = A^{s−1−i} B (i < s; the block of u(k) is zero).
pub fn fast_forward(a: &DMatrix<f64>, b: &DMatrix<f64>, s: usize) -> (DMatrix<f64>, DMatrix<f64>) {
    let (n, r) = (a.nrows(), b.ncols());
    let mut fu = DMatrix::zeros(n, r * (s + 1));
    let mut p = DMatrix::identity(n, n);
    for i in (0..s).rev() {
        if r > 0 {
            fu.view_mut((0, i * r), (n, r)).copy_from(&(&p * b));
        }
        p = &p * a;
    }
    (p, fu)
}

/// The full orthogonal factor Q (rows × rows) of a QR of a tall matrix.
fn full_q(m: &DMatrix<f64>) -> DMatrix<f64> {
    let rows = m.nrows();
    // Householder reflections of the QR applied to the identity: Q = H₁…H_n.
    let mut aug = DMatrix::zeros(rows, rows);
    aug.columns_mut(0, m.ncols()).copy_from(m);
    // Complete the basis with the identity's columns, then orthonormalize by a square QR.
    let mut k = m.ncols();
    for j in 0..rows {
        if k >= rows {
            break;
        }
        let mut e = DVector::zeros(rows);
        e[j] = 1.0;
        aug.set_column(k, &e);
        k += 1;
    }
    aug.qr().q()
}

/// Thin SVD sorted by decreasing singular value: (P₁, σ, R) with M = P₁ diag(σ) Rᵀ (20).
fn thin_svd(m: &DMatrix<f64>) -> (DMatrix<f64>, Vec<f64>, DMatrix<f64>) {
    debug_assert!(m.iter().all(|v| v.is_finite()), "callers check finiteness");
    let svd = m.clone().svd(true, true);
    let (u, vt) = (svd.u.expect("requested"), svd.v_t.expect("requested"));
    let idx = linalg::decreasing_order(svd.singular_values.as_slice());
    let p1 = DMatrix::from_columns(
        &idx.iter()
            .map(|&i| u.column(i).into_owned())
            .collect::<Vec<_>>(),
    );
    let r = DMatrix::from_columns(
        &idx.iter()
            .map(|&i| vt.row(i).transpose())
            .collect::<Vec<_>>(),
    );
    (p1, idx.iter().map(|&i| svd.singular_values[i]).collect(), r)
}

/// Ω(s)⁻¹ M for a block-diagonal Ω(s) = I_{s+1} ⊗ Ω, applied block by block.
fn apply_blocks(omega_inv: &DMatrix<f64>, m: &DMatrix<f64>) -> DMatrix<f64> {
    let q = omega_inv.nrows();
    let mut out = m.clone();
    for p in 0..m.nrows() / q {
        let blk = omega_inv * m.rows(p * q, q);
        out.rows_mut(p * q, q).copy_from(&blk);
    }
    out
}

/// The SVD form (21)/(29) of the (regularized) GLLS gain for a matrix G = P₁ diag(σ) Rᵀ:
/// R diag(1/σ₁ … 1/σ_p, 0 …) (P₁ᵀΩ⁻¹P₁)⁻¹ P₁ᵀΩ⁻¹, and its κ (32): the norm without R.
fn svd_gain(
    p1: &DMatrix<f64>,
    sigma: &[f64],
    r: &DMatrix<f64>,
    omega_inv: &DMatrix<f64>,
    keep: usize,
) -> Result<(DMatrix<f64>, f64)> {
    let n = sigma.len();
    let wp1 = apply_blocks(omega_inv, p1); // Ω⁻¹P₁
    let mmat = p1.transpose() * &wp1; // P₁ᵀΩ⁻¹P₁
    let mut right = linalg::inverse("P₁ᵀΩ⁻¹P₁", &linalg::symmetrize(&mmat))? * wp1.transpose(); // (P₁ᵀΩ⁻¹P₁)⁻¹P₁ᵀΩ⁻¹
    for i in 0..n {
        let f = if i < keep { 1.0 / sigma[i] } else { 0.0 };
        right.row_mut(i).scale_mut(f);
    }
    let kappa = linalg::norm_2(&right);
    Ok((r * right, kappa))
}

/// The truncated-SVD projection R diag(1_p, 0) Rᵀ of (31)/(48).
fn projection(r: &DMatrix<f64>, keep: usize) -> DMatrix<f64> {
    let rp = r.columns(0, keep);
    &rp * rp.transpose()
}

/// Everything of one horizon s: the estimators and their condition numbers.
#[derive(Debug, Clone)]
pub struct Horizon {
    pub s: usize,
    pub gamma: DMatrix<f64>,
    pub phi: DMatrix<f64>,
    /// A^s and the inputs' fast-forward F_u of (41).
    pub a_pow: DMatrix<f64>,
    pub fu: DMatrix<f64>,
    /// σ(Γ_{s+1}), decreasing, and R of (20).
    pub sigma: Vec<f64>,
    pub r: DMatrix<f64>,
    /// GLLS gain of x(k−s) (16)/(21) and of x(k) (43): x_est = gain · (y(k,s) − Φu(k,s)) (+ F_u u).
    pub gain_past: DMatrix<f64>,
    pub gain_current: DMatrix<f64>,
    /// κ_GLLS(s, k−s) (17), κ_LLS(s, k−s) = 1/σ_n (19), κ_GLLS(s, k) (45) = ‖A^s ∂f‖.
    pub kappa_past: f64,
    pub kappa_lls_past: f64,
    pub kappa_current: f64,
    /// σ(Γ_{s+1}A^{−s}) (44) and κ_LLS(s, k) = 1/σ'_n — None when A is singular.
    pub sigma_prime: Option<Vec<f64>>,
    pub kappa_lls_current: Option<f64>,
    /// (R', P'₁) of (44), for the regularized current-state estimator (47).
    prime: Option<(DMatrix<f64>, DMatrix<f64>)>,
    omega_inv: DMatrix<f64>,
}

/// How the measurement errors are weighted: ordinary LLS (Ω = I) or GLLS (the model's Ω).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Weighting {
    Lls,
    Glls,
}

impl Horizon {
    pub fn new(model: &GllsModel, s: usize, weighting: Weighting) -> Result<Self> {
        let (n, m) = (model.n(), model.m());
        let omega = match weighting {
            Weighting::Lls => DMatrix::identity(m, m),
            Weighting::Glls => model.omega.clone(),
        };
        let omega_inv = linalg::inverse("model.W", &omega).map_err(|_| {
            Error::field("model.W", "must be positive definite for GLLS (Ω⁻¹ weights the measurements); choose LLS for a singular Ω")
        })?;
        let gamma = observability(&model.a, &model.c, s);
        let phi = history_controllability(&model.a, &model.b, &model.c, s);
        let (a_pow, fu) = fast_forward(&model.a, &model.b, s);
        if !gamma.iter().all(|v| v.is_finite()) || !a_pow.iter().all(|v| v.is_finite()) {
            return Err(Error::field(
                "glls.horizon",
                format!("s = {s}: the powers of A overflow double precision"),
            ));
        }
        let (p1, sigma, r) = thin_svd(&gamma);
        if sigma.len() < n || !(sigma[n - 1] > sigma[0] * f64::EPSILON * (gamma.nrows() as f64)) {
            let rank = sigma
                .iter()
                .filter(|&&v| v > sigma[0] * f64::EPSILON * (gamma.nrows() as f64))
                .count();
            return Err(Error::field(
                "glls.horizon",
                format!("s = {s}: Γ_{{s+1}} has rank {rank} < n = {n}: x(k−s) is not observable from {} (lengthen the horizon, or check that (A, C) is observable)", crate::error::counted(s + 1, "measurement", "measurements")),
            ));
        }
        let (gain_past, kappa_past) = svd_gain(&p1, &sigma, &r, &omega_inv, n)?;
        let gain_current = &a_pow * &gain_past;
        let kappa_current = linalg::norm_2(&gain_current);
        let kappa_lls_past = 1.0 / sigma[n - 1];
        let (sigma_prime, kappa_lls_current, prime) = match model.a.clone().try_inverse() {
            Some(ainv) if linalg::rcond(&model.a) > 1e-14 => {
                let mut ainv_s = DMatrix::identity(n, n);
                for _ in 0..s {
                    ainv_s = &ainv_s * &ainv;
                }
                let gp = &gamma * ainv_s;
                if gp.iter().all(|v| v.is_finite()) {
                    let (p1p, sp, rp) = thin_svd(&gp);
                    let k = 1.0 / sp[n - 1];
                    (Some(sp), Some(k), Some((rp, p1p)))
                } else {
                    (None, None, None)
                }
            }
            _ => (None, None, None),
        };
        Ok(Horizon {
            s,
            gamma,
            phi,
            a_pow,
            fu,
            sigma,
            r,
            gain_past,
            gain_current,
            kappa_past,
            kappa_lls_past,
            kappa_current,
            sigma_prime,
            kappa_lls_current,
            prime,
            omega_inv,
        })
    }

    /// y(k,s) − Φ_{s+1}u(k,s) for stacked y, u.
    pub fn residual_data(&self, y: &DVector<f64>, u: &DVector<f64>) -> DVector<f64> {
        if self.phi.ncols() == 0 {
            y.clone()
        } else {
            y - &self.phi * u
        }
    }

    /// (11) and (41): estimates of x(k−s) and x(k).
    pub fn estimate(&self, y: &DVector<f64>, u: &DVector<f64>) -> (DVector<f64>, DVector<f64>) {
        let past = &self.gain_past * self.residual_data(y, u);
        let mut cur = &self.a_pow * &past;
        if self.fu.ncols() > 0 {
            cur += &self.fu * u;
        }
        (past, cur)
    }

    /// The regularized estimator keeping p singular values: of the past state (29) with its
    /// projection (31) and κ (32), and — when A is invertible — of the current state (47) with
    /// its projection (48) and κ (49).
    pub fn regularized(&self, p: usize) -> Result<Regularized> {
        let n = self.sigma.len();
        if p < 1 || p > n {
            return Err(Error::field(
                "glls.p",
                format!("must be a whole number from 1 to {n} (singular values kept), found {p}"),
            ));
        }
        let p1 = self.gamma.clone() * &self.r; // Γ R = P₁ diag(σ): recover P₁ column by column
        let p1 = DMatrix::from_columns(
            &(0..n)
                .map(|i| p1.column(i) / self.sigma[i])
                .collect::<Vec<_>>(),
        );
        let (gain_past, kappa_past) = svd_gain(&p1, &self.sigma, &self.r, &self.omega_inv, p)?;
        let projection_past = projection(&self.r, p);
        let current = match (&self.prime, &self.sigma_prime) {
            (Some((rp, p1p)), Some(sp)) => {
                let (g, k) = svd_gain(p1p, sp, rp, &self.omega_inv, p)?;
                Some((g, projection(rp, p), k))
            }
            _ => None,
        };
        Ok(Regularized {
            p,
            gain_past,
            projection_past,
            kappa_past,
            current,
        })
    }

    /// Guaranteed bounds under ‖δ(j)‖₂ ≤ μ for every j (33): ‖δ(k,s)‖₂ ≤ √(s+1)·μ (corrected
    /// (34)), so ‖x_est(k) − x(k)‖₂ ≤ √(s+1)·μ·κ_GLLS(s,k) (35) — a ball; and the exact interval
    /// hull of the error set {∂f·δ : ‖δ(j)‖₂ ≤ μ}: |e_i| ≤ μ Σ_j ‖(∂f)_{i, block j}‖₂.
    pub fn bounds(&self, mu: f64) -> Bounds {
        let m = self.omega_inv.nrows();
        let scale = ((self.s + 1) as f64).sqrt() * mu;
        let half = |g: &DMatrix<f64>| -> Vec<f64> {
            (0..g.nrows())
                .map(|i| {
                    (0..=self.s)
                        .map(|j| g.view((i, j * m), (1, m)).norm())
                        .sum::<f64>()
                        * mu
                })
                .collect()
        };
        Bounds {
            mu,
            radius_past: scale * self.kappa_past,
            radius_current: scale * self.kappa_current,
            half_widths_past: half(&self.gain_past),
            half_widths_current: half(&self.gain_current),
        }
    }

    /// (39): κ_GLLS(s,k)·√E‖δ(k,s)‖² with E‖δ(k,s)‖² = (s+1)·tr Ω_true.
    pub fn expected_bound(&self, omega_true: &DMatrix<f64>) -> f64 {
        self.kappa_current * (((self.s + 1) as f64) * omega_true.trace()).max(0.0).sqrt()
    }

    /// A first-order estimate of the floating-point error of the current-state estimate:
    /// ε·(cond(Γ_{s+1})·‖A^s‖·‖x(k−s)‖ + κ·‖y‖) — to set against the statistical bounds (the
    /// paper's Fig. 3b, where ‖x‖ ≈ 1.5·10⁷ swamps the gain of a longer horizon).
    pub fn rounding_estimate(&self, past: &DVector<f64>, y: &DVector<f64>) -> f64 {
        let n = self.sigma.len();
        let cond = self.sigma[0] / self.sigma[n - 1];
        f64::EPSILON
            * (cond * linalg::norm_2(&self.a_pow) * past.norm() + self.kappa_current * y.norm())
    }
}

/// Truncated-SVD estimators keeping p singular values.
#[derive(Debug, Clone)]
pub struct Regularized {
    pub p: usize,
    /// (29): x_reg(k−s) = gain_past · (y − Φu); it estimates projection_past · x(k−s) (31).
    pub gain_past: DMatrix<f64>,
    pub projection_past: DMatrix<f64>,
    /// κ_reg.GLLS(s, k−s) (32).
    pub kappa_past: f64,
    /// (47)–(49): gain, projection R'diag(1_p,0)R'ᵀ and κ of the current state (A invertible).
    pub current: Option<(DMatrix<f64>, DMatrix<f64>, f64)>,
}

impl Regularized {
    /// (47): x_reg(k) = gain·(y − Φu) + projection·F_u u — or None when A is singular.
    pub fn estimate_current(
        &self,
        h: &Horizon,
        y: &DVector<f64>,
        u: &DVector<f64>,
    ) -> Option<DVector<f64>> {
        let (g, proj, _) = self.current.as_ref()?;
        let mut x = g * h.residual_data(y, u);
        if h.fu.ncols() > 0 {
            x += proj * (&h.fu * u);
        }
        Some(x)
    }
}

/// Worst-case error bounds of one horizon at noise level μ.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Bounds {
    pub mu: f64,
    /// (35) for x(k−s) and x(k), with √(s+1).
    pub radius_past: f64,
    pub radius_current: f64,
    /// Exact interval hull of the error set, per component.
    pub half_widths_past: Vec<f64>,
    pub half_widths_current: Vec<f64>,
}

// ---------------------------------------------------------------------------------------------
// Singular-value curves by QR updates.

/// An n×n upper-triangular factor with a scale: the factor is e^{log_scale}·r.
#[derive(Debug, Clone)]
struct ScaledFactor {
    r: DMatrix<f64>,
    log_scale: f64,
}

impl ScaledFactor {
    fn new(n: usize) -> Self {
        ScaledFactor {
            r: DMatrix::zeros(n, n),
            log_scale: f64::NEG_INFINITY,
        }
    }

    /// Append rows e^{log_b}·block: the new factor of [e^ρ r; e^{log_b} block] by one QR.
    fn append(&mut self, block: &DMatrix<f64>, log_b: f64) {
        let n = self.r.ncols();
        let c = self.log_scale.max(log_b);
        if self.log_scale.is_finite() {
            self.r *= (self.log_scale - c).exp();
        }
        // Givens rotations fold each new row into the triangle in place (O(n²) per row).
        let scale = (log_b - c).exp();
        let mut row = vec![0.0; n];
        for i in 0..block.nrows() {
            for (k, v) in row.iter_mut().enumerate() {
                *v = block[(i, k)] * scale;
            }
            for j in 0..n {
                if row[j] == 0.0 {
                    continue;
                }
                let (cs, sn, h) = rotation(self.r[(j, j)], row[j]);
                self.r[(j, j)] = h;
                row[j] = 0.0;
                for k in j + 1..n {
                    let (x, y) = (self.r[(j, k)], row[k]);
                    self.r[(j, k)] = cs * x + sn * y;
                    row[k] = cs * y - sn * x;
                }
            }
        }
        let big = self.r.amax();
        if big > 0.0 && big.is_finite() {
            self.r /= big;
            self.log_scale = c + big.ln();
        } else {
            self.log_scale = c;
        }
    }

    /// Bring a full square factor back to upper-triangular form (same RᵀR) by Givens rotations.
    fn triangularize(&mut self) {
        let n = self.r.ncols();
        for j in 0..n {
            for i in j + 1..n {
                let b = self.r[(i, j)];
                if b == 0.0 {
                    continue;
                }
                let (cs, sn, _) = rotation(self.r[(j, j)], b);
                for k in j..n {
                    let (x, y) = (self.r[(j, k)], self.r[(i, k)]);
                    self.r[(j, k)] = cs * x + sn * y;
                    self.r[(i, k)] = cs * y - sn * x;
                }
            }
        }
    }

    /// Singular values (decreasing) as natural logarithms (−∞ for exact zeros), by the
    /// allocation-free bidiagonal route of [`SvWork`] (a full SVD only if that fails to
    /// converge).
    fn ln_singular(&self, work: &mut SvWork) -> Vec<f64> {
        if !self.r.iter().all(|v| v.is_finite()) {
            return vec![f64::NAN; self.r.ncols()];
        }
        let mut sv = std::mem::take(&mut work.sv);
        if !work.singular_values(&self.r, &mut sv) {
            sv.clear();
            sv.extend(self.r.clone().svd(false, false).singular_values.iter());
            linalg::sort_decreasing(&mut sv);
        }
        let out = sv.iter().map(|v| v.ln() + self.log_scale).collect();
        work.sv = sv;
        out
    }
}

// ---------------------------------------------------------------------------------------------
// Singular values of a small square factor, without allocation per call.
//
// Each step of [`Curves::new`] needs σ(R) of two n×n triangular factors (n ≤ 20); a general
// SVD allocates and carries overhead that dominated the curves. Here: Householder
// Golub–Kahan bidiagonalization (normwise backward stable: each σ_i moves by O(ε)·σ₁, the
// same as a full SVD of Γ, whose floor ε·σ₁·√(m(s+1)) the curves report), then the
// implicit-QR iteration of Demmel and Kahan ("Accurate singular values of bidiagonal matrices",
// SIAM J. Sci. Stat. Comput. 11 (1990); LAPACK dbdsqr without vectors), which computes the
// bidiagonal's singular values to high relative accuracy: relative convergence tests, a
// zero-shift sweep when the shift would swamp the smallest value, and the chase direction
// chosen by the grading. RᵀR is never formed (it would square the condition number).

/// Relative tolerance of the bidiagonal iteration (the singular values of the bidiagonal are
/// found to about n·TOL relative error).
const SV_TOL: f64 = 10.0 * f64::EPSILON;
/// Iteration budget: at most SV_MAXITR·n² inner steps (dbdsqr's MAXITR).
const SV_MAXITR: usize = 6;

/// Reusable buffers for [`SvWork::singular_values`]: a column-major copy of the matrix, the
/// bidiagonal and one Householder vector.
#[derive(Debug, Clone, Default)]
struct SvWork {
    a: Vec<f64>,
    d: Vec<f64>,
    e: Vec<f64>,
    v: Vec<f64>,
    w: Vec<f64>,
    /// The singular values of the last call (kept to reuse the allocation).
    sv: Vec<f64>,
}

/// A Householder reflector H = I − τ·u·uᵀ (u₀ = 1) with H·[α; x] = [β; 0] (LAPACK dlarfg):
/// scales `x` into u₁.. in place and returns (τ, β); τ = 0 when x is already zero.
#[inline]
fn householder(alpha: f64, x: &mut [f64]) -> (f64, f64) {
    let sigma: f64 = x.iter().map(|v| v * v).sum();
    if sigma == 0.0 {
        return (0.0, alpha);
    }
    let norm = (alpha * alpha + sigma).sqrt();
    let beta = if alpha >= 0.0 { -norm } else { norm };
    let scale = 1.0 / (alpha - beta);
    for v in x.iter_mut() {
        *v *= scale;
    }
    ((beta - alpha) / beta, beta)
}

/// A plane rotation (c, s, r) with c·f + s·g = r, −s·f + c·g = 0 (LAPACK dlartg up to signs).
/// √(f² + g²) directly unless the squares leave the safe range (then `hypot`, which is slower).
#[inline]
fn rotation(f: f64, g: f64) -> (f64, f64, f64) {
    if g == 0.0 {
        return (1.0, 0.0, f);
    }
    if f == 0.0 {
        return (0.0, 1.0, g);
    }
    let r2 = f * f + g * g;
    let r = if r2 > 1e-290 && r2 < 1e290 {
        r2.sqrt()
    } else {
        f.hypot(g)
    };
    let inv = 1.0 / r;
    (f * inv, g * inv, r)
}

/// The singular values (smaller, larger) of the 2×2 upper triangle [f g; 0 h] (LAPACK dlas2),
/// to high relative accuracy without overflow.
fn singular_2x2(f: f64, g: f64, h: f64) -> (f64, f64) {
    let (fa, ga, ha) = (f.abs(), g.abs(), h.abs());
    let (fhmn, fhmx) = (fa.min(ha), fa.max(ha));
    if fhmn == 0.0 {
        let big = if fhmx == 0.0 {
            ga
        } else {
            let (lo, hi) = (fhmx.min(ga), fhmx.max(ga));
            hi * (1.0 + (lo / hi) * (lo / hi)).sqrt()
        };
        (0.0, big)
    } else if ga < fhmx {
        let as_ = 1.0 + fhmn / fhmx;
        let at = (fhmx - fhmn) / fhmx;
        let au = (ga / fhmx) * (ga / fhmx);
        let c = 2.0 / ((as_ * as_ + au).sqrt() + (at * at + au).sqrt());
        (fhmn * c, fhmx / c)
    } else {
        let au = fhmx / ga;
        if au == 0.0 {
            // fhmx/ga underflows: the 2×2 is numerically diag(ga, fhmn·fhmx/ga).
            ((fhmn * fhmx) / ga, ga)
        } else {
            let as_ = 1.0 + fhmn / fhmx;
            let at = (fhmx - fhmn) / fhmx;
            let c = 1.0
                / ((1.0 + (as_ * au) * (as_ * au)).sqrt() + (1.0 + (at * au) * (at * au)).sqrt());
            (2.0 * (fhmn * c) * au, ga / (c + c))
        }
    }
}

impl SvWork {
    /// The spectral norm of a square matrix (+∞ if an entry is not finite).
    fn norm2(&mut self, m: &DMatrix<f64>) -> f64 {
        if !m.iter().all(|v| v.is_finite()) {
            return f64::INFINITY;
        }
        let mut sv = std::mem::take(&mut self.sv);
        let big = if self.singular_values(m, &mut sv) {
            sv.first().copied().unwrap_or(0.0)
        } else {
            linalg::norm_2(m)
        };
        self.sv = sv;
        big
    }

    /// The singular values of the square matrix `r` (column-major, any n), decreasing, into
    /// `out`. Returns false if the bidiagonal iteration did not converge within its budget
    /// (not observed; the caller then falls back to a full SVD).
    fn singular_values(&mut self, r: &DMatrix<f64>, out: &mut Vec<f64>) -> bool {
        let n = r.ncols();
        self.a.clear();
        self.a.extend_from_slice(r.as_slice());
        self.d.clear();
        self.d.resize(n, 0.0);
        self.e.clear();
        self.e.resize(n.saturating_sub(1), 0.0);
        self.v.clear();
        self.v.resize(n, 0.0);
        self.w.clear();
        self.w.resize(n, 0.0);
        self.bidiagonalize(n);
        let ok = bidiagonal_singular(&mut self.d, &mut self.e);
        out.clear();
        out.extend(self.d.iter().map(|v| v.abs()));
        linalg::sort_decreasing(out);
        ok
    }

    /// Golub–Kahan: Householder reflections from the left (columns, contiguous in column-major
    /// storage) and from the right (rows, applied as column axpys) reduce `a` to the upper
    /// bidiagonal (d, e). The reflectors are not kept.
    fn bidiagonalize(&mut self, n: usize) {
        let a = &mut self.a;
        for k in 0..n {
            // Left: annihilate a[k+1.., k].
            let (left, right) = a.split_at_mut((k + 1) * n);
            let col = &mut left[k * n + k..];
            let (alpha, x) = col.split_first_mut().expect("k < n");
            let (tau, beta) = householder(*alpha, x);
            self.d[k] = beta;
            if tau != 0.0 {
                for y in right.chunks_exact_mut(n) {
                    let y = &mut y[k..];
                    let (y0, ys) = y.split_first_mut().expect("k < n");
                    let w = *y0 + x.iter().zip(ys.iter()).map(|(u, v)| u * v).sum::<f64>();
                    let tw = tau * w;
                    *y0 -= tw;
                    for (yv, u) in ys.iter_mut().zip(x.iter()) {
                        *yv -= tw * u;
                    }
                }
            }
            if k + 1 >= n {
                break;
            }
            // Right: annihilate a[k, k+2..] (row k, strided), applied to rows k+1.. .
            let v = &mut self.v[..n - k - 1];
            for (j, vj) in v.iter_mut().enumerate() {
                *vj = right[j * n + k];
            }
            let (alpha, x) = v.split_first_mut().expect("k + 1 < n");
            let (tau, beta) = householder(*alpha, x);
            *alpha = 1.0;
            self.e[k] = beta;
            if tau == 0.0 {
                continue;
            }
            // w = A[k+1.., k+1..]·u, then A[k+1.., k+1..] −= τ·w·uᵀ, column by column.
            let w = &mut self.w[..n - k - 1];
            w.fill(0.0);
            for (col, &u) in right.chunks_exact(n).zip(v.iter()) {
                for (wi, c) in w.iter_mut().zip(col[k + 1..].iter()) {
                    *wi += u * c;
                }
            }
            for (col, &u) in right.chunks_exact_mut(n).zip(v.iter()) {
                let tu = tau * u;
                for (c, wi) in col[k + 1..].iter_mut().zip(w.iter()) {
                    *c -= tu * wi;
                }
            }
        }
    }
}

/// Singular values of the upper bidiagonal (d, e) in place into |d| (unsorted), by the implicit
/// QR iteration of Demmel and Kahan (1990) as in LAPACK dbdsqr (values only, relative
/// tolerance). Returns false if the iteration budget ran out.
fn bidiagonal_singular(d: &mut [f64], e: &mut [f64]) -> bool {
    let n = d.len();
    if n <= 1 {
        return true;
    }
    let tol = SV_TOL;
    let eps = f64::EPSILON;
    // Threshold for negligible off-diagonals: tol times a lower bound on σ_min (Demmel–Kahan's
    // μ recurrence, Section 2), or the underflow limit.
    let mut smin_est = d[0].abs();
    let mut mu = smin_est;
    for i in 1..n {
        if smin_est == 0.0 {
            break;
        }
        mu = d[i].abs() * (mu / (mu + e[i - 1].abs()));
        smin_est = smin_est.min(mu);
    }
    let smin_est = smin_est / (n as f64).sqrt();
    let thresh = (tol * smin_est).max((SV_MAXITR * n * n) as f64 * f64::MIN_POSITIVE);
    let maxit = SV_MAXITR * n * n;
    let mut iter = 0;
    let mut m = n - 1; // the bottom of the active block (0-based)
    let (mut old_ll, mut old_m) = (usize::MAX, usize::MAX);
    'outer: while m > 0 {
        if iter > maxit {
            return false;
        }
        // Find the active block [ll, m]: e[ll..m] nonzero, e[ll−1] negligible.
        let mut smax = d[m].abs();
        let mut ll = 0;
        for l in (0..m).rev() {
            let (abss, abse) = (d[l].abs(), e[l].abs());
            if abse <= thresh {
                e[l] = 0.0;
                if l == m - 1 {
                    // The bottom value converged.
                    m -= 1;
                    continue 'outer;
                }
                ll = l + 1;
                break;
            }
            smax = smax.max(abss).max(abse);
        }
        if ll == m - 1 {
            // A 2×2 block: closed form.
            let (lo, hi) = singular_2x2(d[m - 1], e[m - 1], d[m]);
            d[m - 1] = hi;
            d[m] = lo;
            e[m - 1] = 0.0;
            if m < 2 {
                break;
            }
            m -= 2;
            continue;
        }
        // A new block: chase from the larger end (graded matrices keep relative accuracy). The
        // reversed bidiagonal (d and e read backwards) is the transpose of a permuted copy, so
        // chasing top to bottom on it is chasing bottom to top on the block.
        if ll > old_m || m < old_ll {
            if d[ll].abs() < d[m].abs() {
                d[ll..=m].reverse();
                e[ll..m].reverse();
            }
            old_ll = ll;
            old_m = m;
        }
        // Relative convergence tests (Demmel–Kahan, criteria 1a/2a): e[m−1] against d[m], and
        // the μ recurrence down the block, which also bounds σ_min of the block.
        if e[m - 1].abs() <= tol * d[m].abs() {
            e[m - 1] = 0.0;
            continue;
        }
        let mut mu = d[ll].abs();
        let mut smin = mu;
        for l in ll..m {
            if e[l].abs() <= tol * mu {
                e[l] = 0.0;
                continue 'outer;
            }
            mu = d[l + 1].abs() * (mu / (mu + e[l].abs()));
            smin = smin.min(mu);
        }
        // Shift: the smaller singular value of the trailing 2×2, unless it is negligible next to
        // the block's top value or σ_min is tiny relative to σ_max (then the zero-shift sweep,
        // which keeps every value to high relative accuracy).
        let mut shift = 0.0;
        if (n as f64) * tol * (smin / smax) > eps.max(0.01 * tol) {
            shift = singular_2x2(d[m - 1], e[m - 1], d[m]).0;
            let sll = d[ll].abs();
            if sll > 0.0 && (shift / sll) * (shift / sll) < eps {
                shift = 0.0;
            }
        }
        iter += m - ll;
        if shift == 0.0 {
            // Demmel–Kahan zero-shift QR sweep.
            let (mut cs, mut oldcs, mut oldsn) = (1.0, 1.0, 0.0);
            for i in ll..m {
                let (c, s, r) = rotation(d[i] * cs, e[i]);
                cs = c;
                if i > ll {
                    e[i - 1] = oldsn * r;
                }
                let (oc, os, dr) = rotation(oldcs * r, d[i + 1] * s);
                oldcs = oc;
                oldsn = os;
                d[i] = dr;
            }
            let h = d[m] * cs;
            d[m] = h * oldcs;
            e[m - 1] = h * oldsn;
        } else {
            // Shifted implicit QR sweep (bulge chase), first rotation from (d_ll² − shift²)/d_ll.
            let mut f = (d[ll].abs() - shift) * (d[ll].signum() + shift / d[ll]);
            let mut g = e[ll];
            for i in ll..m {
                let (cr, sr, r) = rotation(f, g);
                if i > ll {
                    e[i - 1] = r;
                }
                f = cr * d[i] + sr * e[i];
                e[i] = cr * e[i] - sr * d[i];
                g = sr * d[i + 1];
                d[i + 1] *= cr;
                let (cl, sl, r) = rotation(f, g);
                d[i] = r;
                f = cl * e[i] + sl * d[i + 1];
                d[i + 1] = cl * d[i + 1] - sl * e[i];
                if i + 1 < m {
                    g = sl * e[i + 1];
                    e[i + 1] *= cl;
                }
            }
            e[m - 1] = f;
        }
        if e[m - 1].abs() <= thresh {
            e[m - 1] = 0.0;
        }
    }
    true
}

/// A matrix power kept as e^{log_scale}·p with max |p| = 1.
#[derive(Debug, Clone)]
struct ScaledPower {
    p: DMatrix<f64>,
    log_scale: f64,
}

impl ScaledPower {
    fn identity(n: usize) -> Self {
        ScaledPower {
            p: DMatrix::identity(n, n),
            log_scale: 0.0,
        }
    }
    fn times(&mut self, a: &DMatrix<f64>) {
        let p = &self.p * a;
        let big = p.amax();
        if big > 0.0 && big.is_finite() {
            self.p = p / big;
            self.log_scale += big.ln();
        } else {
            self.p = p;
        }
    }
}

/// The singular-value and condition-number curves for s = 0..S (Figs. 1–2), all as log10.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Curves {
    /// log10 σ_i(Γ_{s+1}), i = 1..n decreasing, per s.
    pub log10_sigma: Vec<Vec<f64>>,
    /// log10 σ_i(Γ_{s+1}A^{−s}) per s (None when A is singular).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub log10_sigma_prime: Option<Vec<Vec<f64>>>,
    /// log10 of ε·σ₁·√(m(s+1)): singular values below it are not resolved in floating point.
    pub log10_floor: Vec<f64>,
    /// log10 κ_LLS(s,k) = log10 ‖A^s Γ⁺‖ (the current state; = −log10 σ'_n when A is invertible).
    pub log10_kappa_lls_current: Vec<f64>,
    /// log10 κ_GLLS(s,k−s) and κ_GLLS(s,k) with the model's Ω.
    pub log10_kappa_glls_past: Vec<f64>,
    pub log10_kappa_glls_current: Vec<f64>,
}

/// Natural log → log10 (−∞ and NaN become a finite floor for JSON).
fn log10_of_ln(v: f64) -> f64 {
    let l = v / std::f64::consts::LN_10;
    if l.is_finite() {
        l
    } else {
        -400.0
    }
}

impl Curves {
    /// O(S·n³): the factors of Γ_{s+1} (rows C A^p), of Ω^{-1/2}-whitened and Ω⁻¹-weighted rows
    /// (for the GLLS κ: ∂f∂fᵀ = G⁻¹ΓᵀΩ⁻²ΓG⁻¹ with G = ΓᵀΩ⁻¹Γ) and of Γ_{s+1}A^{−s} (rows
    /// C A^{p−s}: [R'A^{−1}; C] per step) are updated block by block.
    pub fn new(model: &GllsModel, s_max: usize) -> Result<Self> {
        let n = model.n();
        let m = model.m();
        let omega_inv = linalg::inverse("model.W", &model.omega).ok();
        // W with WᵀW = Ω⁻¹ (psd_sqrt gives L with LLᵀ = Ω⁻¹, so W = Lᵀ).
        let w_half = omega_inv
            .as_ref()
            .map(|oi| linalg::psd_sqrt(oi).transpose());
        let ainv = match model.a.clone().try_inverse() {
            Some(ai) if linalg::rcond(&model.a) > 1e-14 => Some(ai),
            _ => None,
        };
        let mut gam = ScaledFactor::new(n);
        let mut white = ScaledFactor::new(n);
        let mut weighted = ScaledFactor::new(n);
        let mut prime = ScaledFactor::new(n);
        let mut pw = ScaledPower::identity(n); // A^s
        let mut sv_work = SvWork::default();
        let isotropic = {
            let c = model.omega[(0, 0)];
            c > 0.0 && (&model.omega - DMatrix::identity(m, m) * c).amax() <= 1e-15 * c
        };
        let mut out = Curves {
            log10_sigma: Vec::with_capacity(s_max + 1),
            log10_sigma_prime: ainv.as_ref().map(|_| Vec::with_capacity(s_max + 1)),
            log10_floor: Vec::with_capacity(s_max + 1),
            log10_kappa_lls_current: Vec::with_capacity(s_max + 1),
            log10_kappa_glls_past: Vec::with_capacity(s_max + 1),
            log10_kappa_glls_current: Vec::with_capacity(s_max + 1),
        };
        for s in 0..=s_max {
            // The new block C A^s = e^{ρ_s} C P_s.
            let block = &model.c * &pw.p;
            gam.append(&block, pw.log_scale);
            let ln_sv = gam.ln_singular(&mut sv_work);
            if ln_sv.iter().any(|v| v.is_nan()) || !pw.log_scale.is_finite() {
                return Err(Error::field(
                    "model.F",
                    format!(
                        "the powers of A leave double precision at s = {s} (non-finite entries)"
                    ),
                ));
            }
            out.log10_floor.push(log10_of_ln(
                ln_sv[0] + (f64::EPSILON * ((m * (s + 1)) as f64).sqrt()).ln(),
            ));
            out.log10_sigma
                .push(ln_sv.iter().map(|&v| log10_of_ln(v)).collect());
            // κ_LLS(s,k) = σ_max(A^s R⁻¹) = 1/σ_n(Γ_{s+1}A^{−s}) (45): taken from the σ' curve
            // below when A is invertible, else by one small SVD.
            let direct_kappa = |pw: &ScaledPower, gam: &ScaledFactor, work: &mut SvWork| {
                log10_of_ln(ln_norm_power_rinv(pw, gam, None, work))
            };
            if ainv.is_none() {
                out.log10_kappa_lls_current
                    .push(direct_kappa(&pw, &gam, &mut sv_work));
            }
            match (&omega_inv, &w_half) {
                // Ω = c·I: GLLS is LLS (κ_GLLS = 1/σ_n, κ_GLLS(s,k) = κ_LLS(s,k)); filled below.
                _ if isotropic => {}
                (Some(oi), Some(wh)) => {
                    white.append(&(wh * &block), pw.log_scale);
                    weighted.append(&(oi * &block), pw.log_scale);
                    let ident = ScaledPower::identity(n);
                    out.log10_kappa_glls_past
                        .push(log10_of_ln(ln_norm_power_rinv(
                            &ident,
                            &white,
                            Some(&weighted),
                            &mut sv_work,
                        )));
                    out.log10_kappa_glls_current
                        .push(log10_of_ln(ln_norm_power_rinv(
                            &pw,
                            &white,
                            Some(&weighted),
                            &mut sv_work,
                        )));
                }
                _ => {
                    out.log10_kappa_glls_past.push(f64::NAN.max(-400.0));
                    out.log10_kappa_glls_current.push(f64::NAN.max(-400.0));
                }
            }
            if let (Some(ai), Some(list)) = (&ainv, out.log10_sigma_prime.as_mut()) {
                // Γ_{s+1}A^{−s} = [Γ_s A^{−(s−1)} · A^{−1}; C]: rows C A^{p−s}.
                if prime.log_scale.is_finite() {
                    prime.r = &prime.r * ai;
                    prime.triangularize();
                    let big = prime.r.amax();
                    if big > 0.0 && big.is_finite() {
                        prime.r /= big;
                        prime.log_scale += big.ln();
                    }
                }
                prime.append(&model.c, 0.0);
                let row: Vec<f64> = prime
                    .ln_singular(&mut sv_work)
                    .iter()
                    .map(|&v| log10_of_ln(v))
                    .collect();
                // 1/σ'_n is accurate only while σ'_n is resolved against σ'_1 (an ill-conditioned
                // A^{−1} can bury it): otherwise the direct route.
                out.log10_kappa_lls_current
                    .push(if row[n - 1] > row[0] - 12.0 {
                        -row[n - 1]
                    } else {
                        direct_kappa(&pw, &gam, &mut sv_work)
                    });
                list.push(row);
            }
            if isotropic {
                let last = out.log10_sigma[s][n - 1];
                out.log10_kappa_glls_past.push(-last);
                let cur = out.log10_kappa_lls_current[s];
                out.log10_kappa_glls_current.push(cur);
            }
            pw.times(&model.a);
        }
        Ok(out)
    }
}

/// ln σ_max(A^s R⁻¹ R⁻ᵀ Sᵀ) (GLLS, with S the factor of Ω⁻¹-weighted rows) or ln σ_max(A^s R⁻¹)
/// (LLS) from scaled factors; +∞ when R is singular.
fn ln_norm_power_rinv(
    pw: &ScaledPower,
    r: &ScaledFactor,
    weighted: Option<&ScaledFactor>,
    work: &mut SvWork,
) -> f64 {
    let rt = r.r.transpose();
    // X = P R̂⁻¹ ⇔ R̂ᵀ Xᵀ = Pᵀ.
    let Some(xt) = rt.solve_lower_triangular(&pw.p.transpose()) else {
        return f64::INFINITY;
    };
    match weighted {
        None => {
            let x = xt.transpose();
            work.norm2(&x).ln() + pw.log_scale - r.log_scale
        }
        Some(sf) => {
            // Y = X R̂⁻ᵀ ⇔ R̂ Yᵀ = Xᵀ; then Z = Y Ŝᵀ.
            let Some(yt) = r.r.solve_upper_triangular(&xt) else {
                return f64::INFINITY;
            };
            let z = yt.transpose() * sf.r.transpose();
            work.norm2(&z).ln() + pw.log_scale - 2.0 * r.log_scale + sf.log_scale
        }
    }
}

/// The index σ_i/√s of Fig. 2 (s ≥ 1) for the i-th singular value (i = n: σ_n; i = p
/// regularized) and the best horizon (its maximum), from log10 curves.
pub fn horizon_index(log10_sigma: &[Vec<f64>], i: usize) -> (Vec<f64>, Option<usize>) {
    let idx: Vec<f64> = log10_sigma
        .iter()
        .enumerate()
        .map(|(s, row)| {
            if s == 0 {
                f64::NAN
            } else {
                row[i - 1] - 0.5 * (s as f64).log10()
            }
        })
        .collect();
    let best = idx
        .iter()
        .enumerate()
        .skip(1)
        .filter(|(_, v)| v.is_finite())
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map(|(s, _)| s);
    (
        idx.iter()
            .map(|v| if v.is_finite() { *v } else { -400.0 })
            .collect(),
        best,
    )
}

// ---------------------------------------------------------------------------------------------
// The state-noise estimator (60)–(64).

/// The estimator of Section 4.2 for one horizon s ≥ 1: the minimizer of Σ ξᵀΩ_ξ⁻¹ξ (63) subject
/// to the exact measurement equations (64), as linear maps of ỹ = y(k,s) − Φ_{s+1}u(k,s).
#[derive(Debug, Clone)]
pub struct StateNoise {
    pub s: usize,
    /// x_est(k−s) = gain_x · ỹ; ξ_est = gain_xi · ỹ (n·s entries, ξ(k−s) … ξ(k−1)).
    pub gain_x: DMatrix<f64>,
    pub gain_xi: DMatrix<f64>,
    /// x_est(k) = A^s x_est(k−s) + F_u u + Σ A^{s−1−i} ξ_est(k−s+i) (58) = current_x · ỹ + F_u u.
    pub gain_current: DMatrix<f64>,
    pub a_pow: DMatrix<f64>,
    pub fu: DMatrix<f64>,
    pub phi: DMatrix<f64>,
    /// Ψ of (59) and Γ_{s+1}, for the QP form.
    pub psi: DMatrix<f64>,
    pub gamma: DMatrix<f64>,
}

impl StateNoise {
    /// min ½‖η‖² s.t. Γx + ΨLη = ỹ (ξ = Lη, Ω_ξ = LLᵀ): the quadratic program (63)–(64) in
    /// whitened noise, solved in closed form through an orthogonal basis of range(Γ).
    pub fn new(model: &GllsModel, s: usize) -> Result<Self> {
        let (n, m) = (model.n(), model.m());
        if s == 0 {
            return Err(Error::field("glls.horizon", "must be at least 1 for the state-noise estimator (no transition inside a single measurement)"));
        }
        linalg::check_covariance("model.V", &model.xi, true).map_err(|_| {
            Error::field("model.V", "must be positive definite for the state-noise estimator (Ω of ξ in (54) weights the transition noises)")
        })?;
        let gamma = observability(&model.a, &model.c, s);
        let psi = noise_map(&model.a, &model.c, s);
        let phi = history_controllability(&model.a, &model.b, &model.c, s);
        let (a_pow, fu) = fast_forward(&model.a, &model.b, s);
        let rows = m * (s + 1);
        if rows < n {
            return Err(Error::field(
                "glls.horizon",
                format!(
                    "s = {s}: {rows_measurements} cannot determine n = {n_states}",
                    rows_measurements = crate::error::counted(rows, "measurement", "measurements"),
                    n_states = crate::error::counted(n, "state", "states")
                ),
            ));
        }
        let l = model
            .xi
            .clone()
            .cholesky()
            .map(|c| c.l())
            .ok_or_else(|| Error::field("model.V", "is not positive definite"))?;
        let mut lblock = DMatrix::zeros(n * s, n * s);
        for i in 0..s {
            lblock.view_mut((i * n, i * n), (n, n)).copy_from(&l);
        }
        let psil = &psi * &lblock;
        // Null-space solution (orthogonal transformations only; the KKT matrix squares the
        // conditioning): Γ = [Q₁ Q₂][R; 0]. The constraint splits into Q₂ᵀΨLη = Q₂ᵀỹ, whose
        // least-norm solution is η = (Q₂ᵀΨL)⁺Q₂ᵀỹ, and x = R⁻¹Q₁ᵀ(ỹ − ΨLη).
        let qr = gamma.clone().qr();
        let (q_full, r_fac) = (full_q(&gamma), qr.r());
        let q1 = q_full.columns(0, n).into_owned();
        let q2 = q_full.columns(n, rows - n).into_owned();
        let diag_min = (0..n)
            .map(|i| r_fac[(i, i)].abs())
            .fold(f64::INFINITY, f64::min);
        let diag_max = (0..n).map(|i| r_fac[(i, i)].abs()).fold(0.0, f64::max);
        if !(diag_min > diag_max * f64::EPSILON * rows as f64) {
            return Err(Error::field("glls.horizon", format!("s = {s}: Γ_{{s+1}} is rank deficient: x(k−s) is not determined by the state-noise estimator")));
        }
        let reduced = q2.transpose() * &psil;
        let gain_eta = if reduced.is_empty() {
            // m(s+1) = n: the data fix x(k−s) alone and the least-norm noise is zero.
            DMatrix::zeros(n * s, rows)
        } else {
            let tol = f64::EPSILON * reduced.amax().max(1e-300) * (rows as f64);
            let pinv = reduced
                .clone()
                .pseudo_inverse(tol)
                .map_err(|e| Error::field("glls.horizon", format!("s = {s}: {e}")))?;
            &pinv * q2.transpose()
        };
        let rinv = r_fac
            .solve_upper_triangular(&DMatrix::identity(n, n))
            .ok_or_else(|| Error::field("glls.horizon", "Γ_{s+1} is singular"))?;
        let gain_x = &rinv * q1.transpose() * (DMatrix::identity(rows, rows) - &psil * &gain_eta);
        let gain_xi = &lblock * &gain_eta;
        // (58): x(k) = A^s x(k−s) + Σ_{i<s} A^{s−1−i}(B u + ξ)(k−s+i).
        let mut xi_map = DMatrix::zeros(n, n * s);
        let mut p = DMatrix::identity(n, n);
        for i in (0..s).rev() {
            xi_map.view_mut((0, i * n), (n, n)).copy_from(&p);
            p = &p * &model.a;
        }
        let gain_current = &a_pow * &gain_x + &xi_map * &gain_xi;
        Ok(StateNoise {
            s,
            gain_x,
            gain_xi,
            gain_current,
            a_pow,
            fu,
            phi,
            psi,
            gamma,
        })
    }

    /// x_est(k−s), ξ_est and x_est(k) from stacked y, u.
    pub fn estimate(
        &self,
        y: &DVector<f64>,
        u: &DVector<f64>,
    ) -> (DVector<f64>, DVector<f64>, DVector<f64>) {
        let yt = if self.phi.ncols() == 0 {
            y.clone()
        } else {
            y - &self.phi * u
        };
        let mut cur = &self.gain_current * &yt;
        if self.fu.ncols() > 0 {
            cur += &self.fu * u;
        }
        (&self.gain_x * &yt, &self.gain_xi * &yt, cur)
    }

    /// The same estimate as the quadratic program (63)–(64) solved by clarabel: variables
    /// [x(k−s); ξ(k−s) … ξ(k−1)], objective ξᵀ(I ⊗ Ω_ξ⁻¹)ξ, equalities [Γ Ψ][x; ξ] = ỹ.
    pub fn estimate_qp(
        &self,
        model: &GllsModel,
        y: &DVector<f64>,
        u: &DVector<f64>,
    ) -> Result<(DVector<f64>, DVector<f64>)> {
        let n = model.n();
        let s = self.s;
        let yt = if self.phi.ncols() == 0 {
            y.clone()
        } else {
            y - &self.phi * u
        };
        let xinv = linalg::inverse("model.V", &model.xi)?;
        let dim = n + n * s;
        let mut p = DMatrix::zeros(dim, dim);
        for i in 0..s {
            p.view_mut((n + i * n, n + i * n), (n, n)).copy_from(&xinv);
        }
        let mut aeq = DMatrix::zeros(yt.len(), dim);
        aeq.view_mut((0, 0), (yt.len(), n)).copy_from(&self.gamma);
        aeq.view_mut((0, n), (yt.len(), n * s)).copy_from(&self.psi);
        let sol = crate::solve::quadratic(&crate::solve::Problem {
            p: Some(p),
            q: DVector::zeros(dim),
            eq: Some((aeq, yt)),
            le: None,
            soc: Vec::new(),
            // Equalities only: infeasible when the rows of [Γ Ψ] are dependent and the
            // measurements contradict them; the estimator is the user's choice.
            blame: crate::solve::Blame::new(
                "glls.estimator",
                "state and state noise",
                "no state and state noise reproduce the measurements exactly (the rows of [Γ Ψ] are dependent); try glls.estimator \"lls\"",
            ),
            unit: None,
        })?;
        let x = sol.x.rows(0, n).into_owned();
        let xi = sol.x.rows(n, n * s).into_owned();
        Ok((x, xi))
    }
}

// ---------------------------------------------------------------------------------------------
// Monte Carlo (Section 5).

/// Distribution of an error norm over runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Spread {
    pub min: f64,
    pub q1: f64,
    pub median: f64,
    pub q3: f64,
    pub max: f64,
    pub mean: f64,
}

impl Spread {
    pub fn of(mut v: Vec<f64>) -> Option<Spread> {
        v.retain(|x| x.is_finite());
        if v.is_empty() {
            return None;
        }
        linalg::sort_increasing(&mut v);
        let q = |f: f64| {
            let pos = f * (v.len() - 1) as f64;
            let (lo, hi) = (pos.floor() as usize, pos.ceil() as usize);
            v[lo] + (v[hi] - v[lo]) * (pos - lo as f64)
        };
        Some(Spread {
            min: v[0],
            q1: q(0.25),
            median: q(0.5),
            q3: q(0.75),
            max: v[v.len() - 1],
            mean: v.iter().sum::<f64>() / v.len() as f64,
        })
    }
}

/// Which estimators a study compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Study {
    /// Section 5.1: the (G)LLS current-state estimate on data of (7)–(8).
    Precision,
    /// Section 5.2: the state-noise estimator vs LLS on data of (54)–(55).
    StateNoiseVsLls,
}

/// A Monte Carlo over horizons s = s_min..=s_max: each run simulates `steps` steps from x(0)
/// and estimates the last state with every horizon. Run i simulates from its own stream
/// ([`crate::study::run_stream`] of the seed and i); the study runs it in ranges of runs
/// ([`crate::study::Runs`]).
pub struct Precision {
    model: GllsModel,
    study: Study,
    steps: usize,
    u: Vec<DVector<f64>>,
    /// Per horizon: (s, first estimator, second estimator).
    horizons: Vec<(usize, Horizon, Option<StateNoise>)>,
    pub seed: u64,
    pub total: usize,
}

/// What a range of runs gives: every run's error norms, in run order (the quartiles need them
/// all, so these, not counts, are what adds: ranges concatenate).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrecisionRuns {
    /// Per horizon, the first estimator's ‖x_est(k) − x(k)‖ of each run.
    pub first: Vec<crate::study::Floats>,
    /// Per horizon, the second's (LLS in Section 5.2; empty in 5.1).
    pub second: Vec<crate::study::Floats>,
    /// ‖x(k)‖ of each run.
    pub state_norms: crate::study::Floats,
}

impl crate::study::Tally for PrecisionRuns {
    fn runs(&self) -> usize {
        self.state_norms.0.len()
    }
    /// No counts: one number per run and horizon, whose lengths `add` checks.
    fn counts(&self) -> Vec<(String, usize)> {
        Vec::new()
    }
    fn add(&mut self, later: &Self) -> std::result::Result<(), String> {
        let runs = later.runs();
        if later.first.len() != self.first.len() || later.second.len() != self.second.len() {
            return Err(format!(
                "its errors are for {} horizons, this study's for {}",
                later.first.len(),
                self.first.len()
            ));
        }
        if later.first.iter().any(|v| v.0.len() != runs)
            || later
                .second
                .iter()
                .any(|v| !v.0.is_empty() && v.0.len() != runs)
        {
            return Err(format!(
                "its errors per horizon are not one per run of its {runs}"
            ));
        }
        for (a, b) in self.first.iter_mut().zip(&later.first) {
            a.0.extend_from_slice(&b.0);
        }
        for (a, b) in self.second.iter_mut().zip(&later.second) {
            a.0.extend_from_slice(&b.0);
        }
        self.state_norms.0.extend_from_slice(&later.state_norms.0);
        Ok(())
    }
}

/// The result of a study so far.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PrecisionReport {
    pub runs: usize,
    pub total: usize,
    pub horizons: Vec<usize>,
    /// The (G)LLS estimator (Study::Precision) or the state-noise estimator (5.2).
    pub first: Vec<Option<Spread>>,
    /// LLS in the comparison of Section 5.2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub second: Option<Vec<Option<Spread>>>,
    /// κ(s,k)·√E‖δ(k,s)‖² (39) per horizon (Section 5.1).
    pub bound: Vec<f64>,
    /// Mean ‖x(k)‖ over the runs.
    pub mean_state_norm: f64,
}

impl Precision {
    pub fn new(
        model: &GllsModel,
        study: Study,
        weighting: Weighting,
        steps: usize,
        s_range: (usize, usize),
        u: Vec<DVector<f64>>,
        runs: usize,
        seed: u64,
    ) -> Result<Self> {
        let (s_min, s_max) = s_range;
        if runs == 0 || runs > 1_000_000 {
            return Err(Error::field(
                "glls.monte_carlo.runs",
                format!("must be a whole number from 1 to 1000000, found {runs}"),
            ));
        }
        if s_max + 1 > steps {
            return Err(Error::field(
                "glls.monte_carlo.steps",
                format!("= {steps} leaves no room for horizon s = {s_max} (needs s + 1 ≤ steps)"),
            ));
        }
        let mut horizons = Vec::new();
        for s in s_min..=s_max {
            let h = match Horizon::new(model, s, weighting) {
                Ok(h) => h,
                Err(_) if study == Study::StateNoiseVsLls || s < model.n() => continue, // not yet observable
                Err(e) => return Err(e),
            };
            let sn = match study {
                Study::Precision => None,
                Study::StateNoiseVsLls => match StateNoise::new(model, s) {
                    Ok(sn) => Some(sn),
                    Err(_) => continue,
                },
            };
            horizons.push((s, h, sn));
        }
        if horizons.is_empty() {
            return Err(Error::field(
                "glls.monte_carlo",
                "no horizon in the range determines the state",
            ));
        }
        Ok(Precision {
            model: model.clone(),
            study,
            steps,
            u,
            horizons,
            seed,
            total: runs,
        })
    }

    /// The numbers of no run.
    pub fn zero(&self) -> PrecisionRuns {
        let h = self.horizons.len();
        PrecisionRuns {
            first: vec![Default::default(); h],
            second: vec![Default::default(); h],
            state_norms: Default::default(),
        }
    }

    /// Run the realizations of `runs`.
    pub fn run(&self, runs: std::ops::Range<usize>) -> PrecisionRuns {
        let (m, r) = (self.model.m(), self.model.r());
        let mut out = self.zero();
        for i in runs {
            let mut rng = crate::study::run_stream(self.seed, i);
            let (xs, ys) = self.model.simulate(self.steps, &self.u, &mut rng);
            let last = self.steps - 1;
            let x = &xs[last];
            out.state_norms.0.push(x.norm());
            let slots = out.first.iter_mut().zip(out.second.iter_mut());
            for ((first, second), (s, h, sn)) in slots.zip(&self.horizons) {
                let s = *s;
                let y = DVector::from_iterator(
                    m * (s + 1),
                    (last - s..=last).flat_map(|k| ys[k].iter().copied().collect::<Vec<_>>()),
                );
                let u = DVector::from_iterator(
                    r * (s + 1),
                    (last - s..=last)
                        .flat_map(|k| input(&self.u, k, r).iter().copied().collect::<Vec<_>>()),
                );
                let (_, lls) = h.estimate(&y, &u);
                match sn {
                    Some(sn) => {
                        let (_, _, cur) = sn.estimate(&y, &u);
                        first.0.push((cur - x).norm());
                        second.0.push((lls - x).norm());
                    }
                    None => first.0.push((lls - x).norm()),
                }
            }
        }
        out
    }

    /// The result for the numbers of some runs.
    pub fn report(&self, runs: &PrecisionRuns) -> PrecisionReport {
        let first = runs.first.iter().map(|e| Spread::of(e.0.clone())).collect();
        let second = match self.study {
            Study::StateNoiseVsLls => Some(
                runs.second
                    .iter()
                    .map(|e| Spread::of(e.0.clone()))
                    .collect(),
            ),
            Study::Precision => None,
        };
        let bound = self
            .horizons
            .iter()
            .map(|(_, h, _)| h.expected_bound(&self.model.omega))
            .collect();
        let norms = &runs.state_norms.0;
        PrecisionReport {
            runs: norms.len(),
            total: self.total,
            horizons: self.horizons.iter().map(|h| h.0).collect(),
            first,
            second,
            bound,
            mean_state_norm: if norms.is_empty() {
                0.0
            } else {
                norms.iter().sum::<f64>() / norms.len() as f64
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// D_row·R·D_col with R the triangular factor of a random n×n matrix (entries uniform in
    /// (−1, 1): R is moderately conditioned, unlike a triangle of random entries), column j
    /// scaled by 10^{−col_k·j/(n−1)} and row i by 10^{−row_k·i/(n−1)} (graded either way).
    fn triangle(rng: &mut ChaCha8Rng, n: usize, col_k: f64, row_k: f64) -> DMatrix<f64> {
        let den = (n.max(2) - 1) as f64;
        let g = DMatrix::from_fn(n, n, |_, _| 2.0 * rng.random::<f64>() - 1.0);
        let r = g.qr().r();
        DMatrix::from_fn(n, n, |i, j| {
            r[(i, j)] * 10f64.powf(-col_k * j as f64 / den - row_k * i as f64 / den)
        })
    }

    /// |σ_i − σ̂_i| ≤ rel·σ̂_i + 8n·ε·σ̂₁ for all i: relative accuracy down to the floor of a
    /// normwise backward-stable SVD.
    fn close(sv: &[f64], refv: &[f64], rel: f64) -> bool {
        let floor = 8.0 * sv.len() as f64 * f64::EPSILON * refv[0];
        sv.len() == refv.len()
            && sv
                .iter()
                .zip(refv)
                .all(|(a, b)| (a - b).abs() <= rel * b + floor)
    }

    fn reference(r: &DMatrix<f64>) -> Vec<f64> {
        let mut sv: Vec<f64> = r
            .clone()
            .svd(false, false)
            .singular_values
            .iter()
            .copied()
            .collect();
        sv.sort_by(|a, b| b.total_cmp(a));
        sv
    }

    /// One-sided (Hestenes) Jacobi on the columns, test-only: for R = B·D with B well
    /// conditioned and D diagonal (column grading) it is relatively accurate (Demmel and
    /// Veselić, 1992), so it checks small values beyond a normwise SVD's ε·σ₁.
    fn jacobi(r: &DMatrix<f64>) -> Vec<f64> {
        let mut a = r.clone();
        let n = a.ncols();
        for _ in 0..60 {
            let mut rotated = false;
            for p in 0..n {
                for q in p + 1..n {
                    let alpha = a.column(p).norm_squared();
                    let beta = a.column(q).norm_squared();
                    let gamma = a.column(p).dot(&a.column(q));
                    if gamma.abs() <= f64::EPSILON * (alpha * beta).sqrt() || gamma == 0.0 {
                        continue;
                    }
                    rotated = true;
                    let zeta = (beta - alpha) / (2.0 * gamma);
                    let t = zeta.signum() / (zeta.abs() + (1.0 + zeta * zeta).sqrt());
                    let c = 1.0 / (1.0 + t * t).sqrt();
                    let s = c * t;
                    for i in 0..n {
                        let (x, y) = (a[(i, p)], a[(i, q)]);
                        a[(i, p)] = c * x - s * y;
                        a[(i, q)] = s * x + c * y;
                    }
                }
            }
            if !rotated {
                break;
            }
        }
        let mut sv: Vec<f64> = (0..n).map(|j| a.column(j).norm()).collect();
        sv.sort_by(|a, b| b.total_cmp(a));
        sv
    }

    /// Largest relative error |σ_i − σ̂_i| / σ̂_i.
    fn worst_relative(sv: &[f64], refv: &[f64]) -> f64 {
        sv.iter()
            .zip(refv)
            .map(|(a, b)| (a - b).abs() / b)
            .fold(0.0, f64::max)
    }

    #[test]
    fn triangular_singular_values_match_svd() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut work = SvWork::default();
        let mut sv = Vec::new();
        for &n in &[1usize, 2, 3, 4, 5, 7, 10, 15, 20] {
            for k in 0..=14 {
                for (col_k, row_k) in [(k as f64, 0.0), (0.0, k as f64), (k as f64, k as f64 / 2.0)]
                {
                    for _ in 0..5 {
                        let r = triangle(&mut rng, n, col_k, row_k);
                        assert!(work.singular_values(&r, &mut sv), "converged n = {n}");
                        let refv = reference(&r);
                        assert!(
                            close(&sv, &refv, 1e-12),
                            "n = {n}, grading ({col_k}, {row_k}): {sv:?} vs {refv:?}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn graded_triangles_keep_relative_accuracy() {
        // Column grading 10^{−k·j/(n−1)}, k ≤ 14: the small values are far below ε·σ₁ of the
        // unscaled part yet determined to high relative accuracy; a bidiagonal reduction with
        // the columns in decreasing order keeps them.
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut work = SvWork::default();
        let mut sv = Vec::new();
        let mut worst_rel: f64 = 0.0;
        for &n in &[3usize, 5, 10, 20] {
            for k in 0..=14 {
                for _ in 0..5 {
                    let r = triangle(&mut rng, n, k as f64, 0.0);
                    assert!(work.singular_values(&r, &mut sv));
                    let refv = jacobi(&r);
                    worst_rel = worst_rel.max(worst_relative(&sv, &refv));
                }
            }
        }
        // Observed ≲ 6e-15 (nalgebra's SVD returns 0 for the smallest value at k ≥ 13).
        assert!(worst_rel < 1e-13, "relative error {worst_rel:e}");
    }

    #[test]
    fn rank_deficient_and_zero_triangles() {
        let mut work = SvWork::default();
        let mut sv = Vec::new();
        // Rows 2.. zero (Γ of a short horizon): exact zeros stay zero.
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut r = triangle(&mut rng, 10, 0.0, 0.0);
        for i in 2..10 {
            for j in 0..10 {
                r[(i, j)] = 0.0;
            }
        }
        assert!(work.singular_values(&r, &mut sv));
        let refv = reference(&r);
        assert!(worst_relative(&sv[..2], &refv[..2]) < 1e-13);
        assert!(sv[2..].iter().all(|&v| v <= 1e-15 * sv[0]));
        // A zero in the middle of the diagonal, the zero matrix, the identity.
        let mut r = triangle(&mut rng, 6, 0.0, 0.0);
        r[(3, 3)] = 0.0;
        assert!(work.singular_values(&r, &mut sv));
        assert!(close(&sv, &reference(&r), 1e-12));
        assert!(work.singular_values(&DMatrix::zeros(4, 4), &mut sv));
        assert_eq!(sv, vec![0.0; 4]);
        assert!(work.singular_values(&DMatrix::identity(5, 5), &mut sv));
        assert!(sv.iter().all(|&v| (v - 1.0).abs() < 1e-15));
    }
}

impl crate::study::Runs for Precision {
    type Tally = PrecisionRuns;
    type Report = PrecisionReport;
    fn total(&self) -> usize {
        self.total
    }
    fn seed(&self) -> u64 {
        self.seed
    }
    fn zero(&self) -> PrecisionRuns {
        Precision::zero(self)
    }
    fn run(&mut self, range: std::ops::Range<usize>) -> Result<PrecisionRuns> {
        Ok(Precision::run(self, range))
    }
    fn report(&self, runs: &PrecisionRuns) -> PrecisionReport {
        Precision::report(self, runs)
    }
}
