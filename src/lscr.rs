//! LSCR state estimation: E. Weyer and M. C. Campi, "Prediction, filtering and smoothing using
//! LSCR: state estimation algorithms with guaranteed confidence sets" (seed 000).
//!
//! Model (1)–(2): x_{t+1} = F x_t + G v_t, y_t = H x_t + w_t, scalar y, v, w Gaussian with
//! **unknown** variances σ_v², σ_w². Only the *shape* of the process noise is used (G Gᵀ, or a
//! user V up to scale); the variances serve to simulate data and for the BLUE/KF comparison.
//!
//! The construction, for an estimated state x_τ (prediction τ = t+1, filtering τ = t,
//! smoothing τ = i < t):
//! 1. [`Regression`]: the data in the paper's order [y_t, …, y_1] = Φ x_τ + noise, with
//!    Cov(noise) = σ_v² Q″ + σ_w² I and Q″ known — (11)–(12) for prediction through the backward
//!    representation (4)–(7) (Q′ = Π′ − F^bΠ′F^bᵀ: the printed (7) is a typo; crate docs), (20)
//!    for filtering, (21) for smoothing (forward model after τ, backward before, Lemma 2.1).
//!    Q″ is built by the covariance recursion of the noise chain, not as B·diag(Q′)·Bᵀ
//!    (O(t²n²) instead of O(t³n)).
//! 2. [`KarhunenLoeve`]: Q″ = U D Uᵀ, s = Uᵀy, A = UᵀΦ (13)–(15), so s = A x_τ + n̄ with
//!    independent components (Lemma 3.1; the paper swaps σ_v², σ_w² there: Cov n̄ = σ_v²D + σ_w²I).
//!    Basis rule (the eigenvalues of smoothing come in exact pairs, so the basis is not unique):
//!    eigenvectors are computed block by block of Q″'s independent blocks (data after τ, the
//!    datum at τ, data before τ), sorted by decreasing eigenvalue with ties in block order, and
//!    signed so that their largest entry is positive. It depends on the model only, never on
//!    the data, which is all the guarantee needs.
//! 3. A = U_A Σ V_Aᵀ (16) (thin, through a QR of A), correlations f_{k,l}(x) = (s_k − a_k x)u_{a,l,k}
//!    and g_{i,l}(x) = Σ_k h_{i,k} f_{k,l}(x) = c_{i,l} − d_{i,l}·x for the strings h_i
//!    ([`Strings`]: point 4, point 4a, or given).
//! 4. X̂_l, X̂ (17) as a [`SignRegion`]; Theorem 3.2: P{x_τ ∈ X̂_l} = 1 − 2q/M,
//!    P{x_τ ∈ X̂} ≥ 1 − 2qn/M, whatever x_τ is.
//!
//! Comparisons with known variances: the BLUE of x_τ from s (weights 1/(σ_v²D_k + σ_w²)) with
//! its ellipsoid at the LSCR level, and for prediction/filtering the Kalman filter's.

use crate::error::{Error, Result};
use crate::kalman::KalmanGains;
use crate::linalg;
use crate::method::Method;
use crate::model::{BackwardStep, ConditionedSampler, Inputs, LinearModel, MatrixSpec, ModelSpec};
use crate::sets::{AffineGroup, Ellipsoid, SignRegion};
use nalgebra::{DMatrix, DVector};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Which state is estimated from y_1..y_t.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// x_{t+1} (Section III).
    Predict,
    /// x_t (IV-A).
    Filter,
    /// x_i, 1 ≤ i < t (IV-B).
    Smooth(usize),
}

impl Target {
    /// Time of the estimated state.
    pub fn time(&self, t: usize) -> usize {
        match self {
            Target::Predict => t + 1,
            Target::Filter => t,
            Target::Smooth(i) => *i,
        }
    }
    pub fn name(&self) -> &'static str {
        match self {
            Target::Predict => "predict",
            Target::Filter => "filter",
            Target::Smooth(_) => "smooth",
        }
    }
}

/// The model as LSCR sees it: F, H (1×n), the process-noise shape S (G Gᵀ, or V) with
/// Cov(G v_t) = σ_v² S, and the true variances (simulation and comparisons only).
#[derive(Debug, Clone)]
pub struct LscrModel {
    pub f: DMatrix<f64>,
    pub h: DMatrix<f64>,
    pub shape: DMatrix<f64>,
    pub sigma_v2: f64,
    pub sigma_w2: f64,
    /// The same model for the model layer (simulation, Kalman filter).
    pub linear: LinearModel,
}

/// Most states of an LSCR model (the explorer's limit; the work of a report is bounded by the
/// combined budget of `scenario::budget`).
pub const MAX_STATES: usize = 16;

/// Most strings M (the work of a report with many strings is bounded by the combined budget of
/// `scenario::budget`: the region's boundary grows like (n·M)²).
pub const MAX_STRINGS: usize = 100_000;

fn rows_of(spec: &Option<MatrixSpec>) -> Option<&Vec<Vec<f64>>> {
    match spec {
        Some(MatrixSpec::Constant(r)) => Some(r),
        _ => None,
    }
}

impl LscrModel {
    /// Validate a scenario model for LSCR. Errors name the field.
    pub fn from_spec(spec: &ModelSpec) -> Result<Self> {
        for (field, given) in [
            ("model.B", spec.b.is_some()),
            ("model.x1_mean", spec.x1_mean.is_some()),
            ("model.x1_cov", spec.x1_cov.is_some()),
        ] {
            if given {
                return Err(Error::field(
                    field,
                    "is not used by LSCR: the construction assumes the stationary process of (1)–(2) without inputs (Assumption 2); remove it",
                ));
            }
        }
        for (field, m) in [
            ("model.F", &spec.f),
            ("model.H", &spec.h),
            ("model.V", &spec.v),
            ("model.W", &spec.w),
        ] {
            ModelSpec::constant(field, m, Method::Lscr)?;
        }
        let linear = LinearModel::from_spec(spec).map_err(|e| {
            // The model layer's complaint is about the prior of x_1 (its default is the
            // stationary law); LSCR has no prior to give: the stationarity itself is what it
            // assumes, so the message is about F.
            if e.field != "model.x1_cov" {
                return e;
            }
            let rho = ModelSpec::constant("model.F", &spec.f, Method::Lscr)
                .ok()
                .flatten()
                .map(|f| linalg::spectral_radius(&f));
            match rho {
                Some(rho) if !(rho < 1.0 - 1e-9) => Error::field(
                    "model.F",
                    format!(
                        "must be stable (every eigenvalue inside the unit circle): LSCR assumes a stationary x_t (Assumption 2), and F's spectral radius is {rho:.6}, so x_t has no stationary law; a random walk or trend (ρ(F) ≥ 1) needs a method with a prior of x_1, such as kf or scf with model.x1_cov"
                    ),
                ),
                _ => Error::field(
                    "model.F",
                    format!(
                        "must give a stationary x_t, which LSCR assumes (Assumption 2), but its stationary covariance cannot be computed: {}",
                        e.message
                    ),
                ),
            }
        })?;
        let n = linear.n();
        if linear.q() != 1 {
            return Err(Error::field(
                "model.H",
                format!(
                    "must have one row: LSCR works with a scalar output y_t (found {} rows)",
                    linear.q()
                ),
            ));
        }
        if n > MAX_STATES {
            return Err(Error::field(
                "model.F",
                format!("is {n}×{n}: the LSCR explorer supports n ≤ {MAX_STATES}"),
            ));
        }
        let (shape, sigma_v2, sigma_w2) = if let Some(g) = &spec.g {
            let g = linalg::from_rows("model.G", g)?;
            if g.ncols() != 1 {
                return Err(Error::field(
                    "model.G",
                    format!(
                        "must be one column (n×1): v_t is scalar in LSCR, found {} columns",
                        g.ncols()
                    ),
                ));
            }
            let sv = spec.sigma_v2.unwrap_or(0.0);
            (&g * g.transpose(), sv, spec.sigma_w2.unwrap_or(0.0))
        } else {
            let v = linalg::from_rows("model.V", rows_of(&spec.v).expect("validated above"))?;
            let w = linalg::from_rows("model.W", rows_of(&spec.w).expect("validated above"))?;
            (v, 1.0, w[(0, 0)])
        };
        if !(sigma_v2 > 0.0) {
            return Err(Error::field(
                "model.sigma_v2",
                "must be > 0: with no process noise the state is not a stationary random process and F^b does not exist",
            ));
        }
        Ok(LscrModel {
            f: linear.f(1).clone(),
            h: linear.h(1).clone(),
            shape,
            sigma_v2,
            sigma_w2,
            linear,
        })
    }

    /// Backward representation with σ_v² = 1: F^b = Π′FᵀΠ′⁻¹ (6), Q′ = Π′ − F^bΠ′F^bᵀ
    /// (erratum of (7)), where Π′ = FΠ′Fᵀ + S (3).
    pub fn backward(&self) -> Result<BackwardStep> {
        let unit = LinearModel::time_invariant(
            self.f.clone(),
            self.h.clone(),
            self.shape.clone(),
            DMatrix::identity(1, 1),
        )?;
        unit.backward_representation().map_err(|e| {
            if e.field == "model.V" {
                Error::field(
                    "model.G",
                    "does not excite every state: Π′ = FΠ′Fᵀ + GGᵀ is singular, so the backward representation (6) does not exist",
                )
            } else {
                e
            }
        })
    }
}

/// The data as a regression on the estimated state, in the paper's row order
/// [y_t, y_{t−1}, …, y_1]: y = Φ x_τ + noise, Cov(noise) = σ_v² Q″ + σ_w² I.
#[derive(Debug, Clone)]
pub struct Regression {
    pub target: Target,
    pub t: usize,
    /// Φ (t×n).
    pub phi: DMatrix<f64>,
    /// Q″ (t×t), known up to σ_v².
    pub q2: DMatrix<f64>,
    /// Row ranges of Q″'s independent blocks.
    pub blocks: Vec<std::ops::Range<usize>>,
    pub backward: BackwardStep,
}

/// Rows H·M^{k+offset} and the covariance of a noise chain ξ_k = M ξ_{k−1} + e_k (Cov e_k = S),
/// Cov ξ_0 = P_0, k = 0..len: Cov(Hξ_k, Hξ_j) = H M^{k−j} P_j Hᵀ for k ≥ j.
fn chain(
    h: &DMatrix<f64>,
    m: &DMatrix<f64>,
    offset: usize,
    len: usize,
    p0: &DMatrix<f64>,
    s: &DMatrix<f64>,
) -> (DMatrix<f64>, DMatrix<f64>) {
    let n = m.nrows();
    let mut phi = DMatrix::zeros(len, n);
    let mut row = h.clone();
    for _ in 0..offset {
        row = &row * m;
    }
    for k in 0..len {
        phi.row_mut(k).copy_from(&row);
        row = &row * m;
    }
    let mut cov = DMatrix::zeros(len, len);
    let mut p = p0.clone();
    let ht = h.transpose();
    for j in 0..len {
        // z = M^{k−j} P_j Hᵀ as k runs up from j.
        let mut z = &p * &ht;
        for k in j..len {
            let v = (h * &z)[(0, 0)];
            cov[(k, j)] = v;
            cov[(j, k)] = v;
            z = m * z;
        }
        p = linalg::symmetrize(&(m * &p * m.transpose() + s));
    }
    (phi, cov)
}

impl Regression {
    /// (11)–(12), (20) or (21) for `t` data.
    pub fn new(model: &LscrModel, t: usize, target: Target) -> Result<Self> {
        let n = model.f.nrows();
        if t < n {
            return Err(Error::field(
                "data.y",
                format!(
                    "gives t = {t_measurements}: LSCR needs t ≥ n = {n}",
                    t_measurements = crate::error::counted(t, "measurement", "measurements")
                ),
            ));
        }
        if let Target::Smooth(i) = target {
            if i < 1 || i >= t {
                return Err(Error::field(
                    "lscr.index",
                    format!(
                        "must be a whole number from 1 to {} (smoothing estimates x_i with i < t = {t}), found {i}",
                        t - 1
                    ),
                ));
            }
        }
        let backward = model.backward()?;
        let (fb, qb) = (&backward.f_b, &backward.v_b);
        let zero = DMatrix::zeros(n, n);
        let (phi, q2, blocks) = match target {
            Target::Predict => {
                let (phi, q2) = chain(&model.h, fb, 1, t, qb, qb);
                (phi, q2, vec![0..t])
            }
            Target::Filter => {
                let (phi, q2) = chain(&model.h, fb, 0, t, &zero, qb);
                (phi, q2, vec![0..1, 1..t])
            }
            Target::Smooth(i) => {
                // After i, forward from x_i: x_{i+1+k} = F^{k+1}x_i + η_k, η_0 = G v_i (21).
                let (fphi, fcov) = chain(&model.h, &model.f, 1, t - i, &model.shape, &model.shape);
                // At and before i, backward from x_i.
                let (bphi, bcov) = chain(&model.h, fb, 0, i, &zero, qb);
                let nf = t - i;
                let mut phi = DMatrix::zeros(t, n);
                let mut q2 = DMatrix::zeros(t, t);
                // Paper order: y_t … y_{i+1} (forward chain reversed), then y_i … y_1.
                for a in 0..nf {
                    phi.row_mut(a).copy_from(&fphi.row(nf - 1 - a));
                    for b in 0..nf {
                        q2[(a, b)] = fcov[(nf - 1 - a, nf - 1 - b)];
                    }
                }
                for a in 0..i {
                    phi.row_mut(nf + a).copy_from(&bphi.row(a));
                    for b in 0..i {
                        q2[(nf + a, nf + b)] = bcov[(a, b)];
                    }
                }
                (phi, q2, vec![0..nf, nf..nf + 1, nf + 1..t])
            }
        };
        let blocks = blocks.into_iter().filter(|r| !r.is_empty()).collect();
        Ok(Regression {
            target,
            t,
            phi,
            q2,
            blocks,
            backward,
        })
    }

    /// The data y_1..y_t (time order) in the paper's row order [y_t, …, y_1].
    pub fn stack(&self, y: &[f64]) -> DVector<f64> {
        DVector::from_fn(self.t, |r, _| y[self.t - 1 - r])
    }
}

/// Karhunen–Loève transform of the regression (12)–(15) and the SVD of A (16).
#[derive(Debug, Clone)]
pub struct KarhunenLoeve {
    /// U (t×t), orthonormal columns ordered by decreasing eigenvalue.
    pub u: DMatrix<f64>,
    /// D: eigenvalues of Q″ (σ_v² D is the v-part of Cov n̄).
    pub d: DVector<f64>,
    /// A = UᵀΦ (t×n).
    pub a: DMatrix<f64>,
    /// First n columns of U_A (t×n).
    pub u_a: DMatrix<f64>,
    /// Singular values of A, decreasing.
    pub singular: Vec<f64>,
    /// Numerical rank of A.
    pub rank: usize,
}

fn fix_sign(mut v: DVector<f64>) -> DVector<f64> {
    let k = v.iamax();
    if v[k] < 0.0 {
        v.neg_mut();
    }
    v
}

impl KarhunenLoeve {
    /// The basis rule of the module docs.
    pub fn new(reg: &Regression) -> Result<Self> {
        let t = reg.t;
        let mut pairs: Vec<(f64, usize, DVector<f64>)> = Vec::with_capacity(t);
        for (b, range) in reg.blocks.iter().enumerate() {
            let sub = reg
                .q2
                .view((range.start, range.start), (range.len(), range.len()))
                .into_owned();
            let eig = linalg::try_symmetric_eigen(linalg::symmetrize(&sub)).ok_or_else(|| {
                Error::field(
                    "model",
                    "the covariance of the data is not finite: the model's entries overflow double precision",
                )
            })?;
            for k in 0..range.len() {
                let mut full = DVector::zeros(t);
                full.rows_mut(range.start, range.len())
                    .copy_from(&eig.eigenvectors.column(k));
                pairs.push((eig.eigenvalues[k].max(0.0), b, fix_sign(full)));
            }
        }
        pairs.sort_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)));
        let u = DMatrix::from_columns(&pairs.iter().map(|p| p.2.clone()).collect::<Vec<_>>());
        let d = DVector::from_iterator(t, pairs.iter().map(|p| p.0));
        if !(u.iter().all(|v| v.is_finite())) {
            return Err(Error::field(
                "model",
                "the Karhunen–Loève decomposition failed (non-finite values)",
            ));
        }
        let a = u.transpose() * &reg.phi;
        let (u_a, singular, rank) = thin_svd_u(&a)?;
        Ok(KarhunenLoeve {
            u,
            d,
            a,
            u_a,
            singular,
            rank,
        })
    }

    /// s = Uᵀ y (14), with y in the paper's order.
    pub fn transform(&self, y_stacked: &DVector<f64>) -> DVector<f64> {
        self.u.tr_mul(y_stacked)
    }
}

/// Left singular vectors (t×n), singular values (decreasing) and rank of a tall A, through a QR
/// of A and the SVD of the n×n factor R: orthonormal columns even when A is rank-deficient.
fn thin_svd_u(a: &DMatrix<f64>) -> Result<(DMatrix<f64>, Vec<f64>, usize)> {
    let n = a.ncols();
    if !a.iter().all(|v| v.is_finite()) {
        return Err(Error::field(
            "model.H",
            "the regressors are not finite: the model's entries overflow double precision",
        ));
    }
    let qr = a.clone().qr();
    let q = qr.q();
    let r = qr.r();
    let svd = linalg::try_svd(r, true, false).ok_or_else(|| {
        Error::field(
            "model.H",
            "the regressors have no SVD (an entry is not finite)",
        )
    })?;
    let ur = svd.u.expect("requested");
    let idx = linalg::decreasing_order(svd.singular_values.as_slice());
    let singular: Vec<f64> = idx.iter().map(|&i| svd.singular_values[i]).collect();
    let cols: Vec<DVector<f64>> = idx.iter().map(|&i| &q * ur.column(i)).collect();
    let u_a = DMatrix::from_columns(&cols);
    let tol =
        singular.first().copied().unwrap_or(0.0) * (a.nrows().max(n) as f64) * f64::EPSILON * 16.0;
    let rank = singular.iter().filter(|&&s| s > tol).count();
    Ok((u_a, singular, rank))
}

/// How the subsample strings were made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Construction {
    /// Point 4: M − 1 distinct non-zero random strings and the zero string.
    Random,
    /// Point 4a: the span of k random independent generators under symmetric difference (M = 2^k).
    Group,
    /// Given in the scenario.
    Explicit,
}

/// The strings h_1..h_{M−1} (h_0 = 0 is implicit), as rows of a 0/1 matrix over the t
/// Karhunen–Loève components in decreasing-eigenvalue order.
#[derive(Debug, Clone)]
pub struct Strings {
    pub construction: Construction,
    pub h: DMatrix<f64>,
    /// Whether the strings with ∅ form a group under symmetric difference.
    pub is_group: bool,
}

type Bits = Vec<u64>;

fn random_bits<R: Rng>(t: usize, rng: &mut R) -> Bits {
    let words = t.div_ceil(64);
    let mut b: Bits = (0..words).map(|_| rng.next_u64()).collect();
    if t % 64 != 0 {
        b[words - 1] &= (1u64 << (t % 64)) - 1;
    }
    b
}

fn xor(a: &Bits, b: &Bits) -> Bits {
    a.iter().zip(b).map(|(x, y)| x ^ y).collect()
}

/// M − 1 distinct non-zero strings of t fair bits (duplicates and zero redrawn); needs M ≤ 2^t.
fn random_rows<R: Rng>(m: usize, t: usize, rng: &mut R) -> Vec<Bits> {
    let mut seen = std::collections::HashSet::new();
    seen.insert(vec![0u64; t.div_ceil(64)]);
    let mut rows = Vec::with_capacity(m - 1);
    while rows.len() < m - 1 {
        let b = random_bits(t, rng);
        if seen.insert(b.clone()) {
            rows.push(b);
        }
    }
    rows
}

/// Whether another M − 1 distinct non-zero strings of length t exist: M ≤ 2^t.
fn fits(m: usize, t: usize) -> bool {
    t >= 63 || (m as u64) <= (1u64 << t)
}

impl Strings {
    fn from_bits(construction: Construction, t: usize, rows: &[Bits]) -> Self {
        let h = DMatrix::from_fn(rows.len(), t, |i, k| {
            ((rows[i][k / 64] >> (k % 64)) & 1) as f64
        });
        let set: std::collections::HashSet<&Bits> = rows.iter().collect();
        let zero = vec![0u64; t.div_ceil(64)];
        // Closed under symmetric difference (with ∅): quadratic, so only for moderate M.
        let is_group = rows.len() <= 4096
            && rows.iter().enumerate().all(|(i, a)| {
                rows[i + 1..].iter().all(|b| {
                    let c = xor(a, b);
                    c == zero || set.contains(&c)
                })
            });
        Strings {
            construction,
            h,
            is_group,
        }
    }

    /// Point 4: M − 1 distinct non-zero strings, each bit a fair coin, duplicates redrawn.
    pub fn random(m: usize, t: usize, seed: u64) -> Result<Self> {
        if !fits(m, t) {
            return Err(Error::field(
                "lscr.M",
                format!(
                    "must be at most 2^t = {} (distinct strings of length t = {t})",
                    1u64 << t
                ),
            ));
        }
        let rows = random_rows(m, t, &mut ChaCha8Rng::seed_from_u64(seed));
        Ok(Self::from_bits(Construction::Random, t, &rows))
    }

    /// Redraw random strings in place (same M, t), skipping the group check: the coverage
    /// experiment draws fresh strings per run, since the probability of Theorem 3.2 for
    /// point 4 is over the strings as well as the noise.
    fn redraw_random<R: Rng>(&mut self, rng: &mut R) {
        let (m, t) = (self.h.nrows() + 1, self.h.ncols());
        for (i, row) in random_rows(m, t, rng).iter().enumerate() {
            for k in 0..t {
                self.h[(i, k)] = ((row[k / 64] >> (k % 64)) & 1) as f64;
            }
        }
    }

    /// Point 4a: M = 2^k elements spanned by k random generators independent over GF(2).
    pub fn group(m: usize, t: usize, seed: u64) -> Result<Self> {
        if !m.is_power_of_two() || m < 2 {
            return Err(Error::field(
                "lscr.M",
                format!("must be a power of two 2^k for the group construction, found {m}"),
            ));
        }
        let k = m.trailing_zeros() as usize;
        if k > t {
            return Err(Error::field(
                "lscr.M",
                format!("= 2^{k} needs k ≤ t = {t} independent generators"),
            ));
        }
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        // Echelon basis (pivot bit → vector) to test independence.
        let mut basis: Vec<(usize, Bits)> = Vec::new();
        let mut gens: Vec<Bits> = Vec::new();
        while gens.len() < k {
            let g = random_bits(t, &mut rng);
            let mut r = g.clone();
            for (p, b) in &basis {
                if (r[p / 64] >> (p % 64)) & 1 == 1 {
                    r = xor(&r, b);
                }
            }
            if let Some(p) = (0..t).find(|&p| (r[p / 64] >> (p % 64)) & 1 == 1) {
                basis.push((p, r));
                gens.push(g);
            }
        }
        let rows: Vec<Bits> = (1..m)
            .map(|i| {
                let mut e = vec![0u64; t.div_ceil(64)];
                for (j, g) in gens.iter().enumerate() {
                    if (i >> j) & 1 == 1 {
                        e = xor(&e, g);
                    }
                }
                e
            })
            .collect();
        Ok(Self::from_bits(Construction::Group, t, &rows))
    }

    /// Strings given as "0110…" (k-th character: k-th KL component); the zero string may be
    /// included or not.
    pub fn explicit(given: &[String], t: usize) -> Result<Self> {
        let mut rows: Vec<Bits> = Vec::new();
        let zero = vec![0u64; t.div_ceil(64)];
        let mut seen = std::collections::HashSet::new();
        for (i, s) in given.iter().enumerate() {
            let field = format!("lscr.strings[{i}]");
            if s.chars().count() != t {
                return Err(Error::field(
                    field,
                    format!(
                        "must have t = {t_characters} 0/1, found {}",
                        s.chars().count(),
                        t_characters = crate::error::counted(t, "character", "characters")
                    ),
                ));
            }
            let mut b = zero.clone();
            for (k, ch) in s.chars().enumerate() {
                match ch {
                    '0' => {}
                    '1' => b[k / 64] |= 1 << (k % 64),
                    other => {
                        return Err(Error::field(
                            field,
                            format!(
                                "must contain only 0 and 1, found {} at position {}",
                                crate::error::quoted(&other.to_string()),
                                k + 1
                            ),
                        ))
                    }
                }
            }
            if b == zero {
                continue;
            }
            if !seen.insert(b.clone()) {
                return Err(Error::field(
                    field,
                    "repeats an earlier string: the strings must be distinct",
                ));
            }
            rows.push(b);
        }
        if rows.is_empty() {
            return Err(Error::field(
                "lscr.strings",
                "must contain at least one non-zero string",
            ));
        }
        Ok(Self::from_bits(Construction::Explicit, t, &rows))
    }

    /// M: the number of strings including h_0 = 0.
    pub fn m(&self) -> usize {
        self.h.nrows() + 1
    }

    /// The strings as "0110…".
    pub fn texts(&self) -> Vec<String> {
        self.h
            .row_iter()
            .map(|r| {
                r.iter()
                    .map(|&v| if v != 0.0 { '1' } else { '0' })
                    .collect()
            })
            .collect()
    }
}

/// M and q for a target joint level β: for random strings the first q = 1, 2, … with
/// M = ⌈2qn/(1 − β)⌉ ≥ 40n (enough strings for a stable region; β = 0.9, n = 2 gives the paper's
/// M = 80, q = 2); for groups the first M = 2^k ≥ 40n with q = ⌊M(1 − β)/(2n)⌋ ≥ 1.
pub fn choose_m_q(level: f64, n: usize, construction: Construction) -> Result<(usize, usize)> {
    if !(level > 0.0 && level < 1.0) {
        return Err(Error::field(
            "lscr.level",
            format!(
                "must lie strictly between 0 and 1, found {}",
                crate::error::shown(level)
            ),
        ));
    }
    let miss = 1.0 - level;
    for q in 1..100_000usize {
        match construction {
            Construction::Group => {
                let mut m = 1usize;
                while m < 40 * n {
                    m *= 2;
                }
                while m <= 1 << 20 {
                    let q = ((m as f64) * miss / (2.0 * n as f64) + 1e-9).floor() as usize;
                    if q >= 1 {
                        return Ok((m, q));
                    }
                    m *= 2;
                }
                break;
            }
            _ => {
                let m = (2.0 * (q * n) as f64 / miss - 1e-9).ceil() as usize;
                if m >= 40 * n {
                    return Ok((m, q));
                }
            }
        }
    }
    Err(Error::field(
        "lscr.level",
        format!("{level} needs too many strings; choose a lower level"),
    ))
}

/// Everything data-independent of one LSCR problem: built once per (model, t, target) and
/// reused for every data set (sliders, Monte Carlo).
#[derive(Debug, Clone)]
pub struct Problem {
    pub regression: Regression,
    pub kl: KarhunenLoeve,
}

impl Problem {
    pub fn new(model: &LscrModel, t: usize, target: Target) -> Result<Self> {
        let regression = Regression::new(model, t, target)?;
        let kl = KarhunenLoeve::new(&regression)?;
        Ok(Problem { regression, kl })
    }

    pub fn n(&self) -> usize {
        self.kl.a.ncols()
    }

    /// s from y_1..y_t (time order).
    pub fn s(&self, y: &[f64]) -> DVector<f64> {
        self.kl.transform(&self.regression.stack(y))
    }

    /// g_{i,l}(x) = c_{i,l} − d_{i,l}·x with c_{i,l} = Σ_k h_{i,k}u_{a,l,k}s_k and
    /// d_{i,l} = Σ_k h_{i,k}u_{a,l,k}a_k (point 4), as the region X̂ with parameter q (point 5).
    pub fn region(&self, s: &DVector<f64>, strings: &Strings, q: usize) -> SignRegion {
        let n = self.n();
        let groups = (0..n)
            .map(|l| {
                let ul = self.kl.u_a.column(l);
                let us = ul.component_mul(s);
                let c = &strings.h * us;
                let ua = DMatrix::from_fn(self.regression.t, n, |k, j| ul[k] * self.kl.a[(k, j)]);
                let d = &strings.h * ua;
                AffineGroup {
                    c: c.iter().copied().collect(),
                    d: d.row_iter().map(|r| r.iter().copied().collect()).collect(),
                }
            })
            .collect();
        SignRegion { dim: n, q, groups }
    }

    /// Cov n̄ = σ_v² D + σ_w² I (Lemma 3.1 with the variances in their right places).
    pub fn noise_variances(&self, sigma_v2: f64, sigma_w2: f64) -> DVector<f64> {
        self.kl.d.map(|d| sigma_v2 * d + sigma_w2)
    }

    /// BLUE of x_τ from s = A x_τ + n̄ with known variances: x̂ = (AᵀΛ⁻¹A)⁻¹AᵀΛ⁻¹s, Cov = (AᵀΛ⁻¹A)⁻¹.
    /// Returns the gain K (x̂ = K s) and the covariance, or why there is none.
    pub fn blue_gain(
        &self,
        sigma_v2: f64,
        sigma_w2: f64,
    ) -> std::result::Result<(DMatrix<f64>, DMatrix<f64>), String> {
        let lam = self.noise_variances(sigma_v2, sigma_w2);
        let top = lam.max();
        if lam.iter().any(|&v| !(v > 1e-12 * top)) {
            return Err("some Karhunen–Loève components are noise-free (σ_w² = 0 and D_k = 0): no BLUE ellipse".into());
        }
        if self.kl.rank < self.n() {
            return Err(format!(
                "A has rank {} < n = {}: the state is not determined by the data, so there is no unique BLUE",
                self.kl.rank,
                self.n()
            ));
        }
        let aw = DMatrix::from_fn(self.kl.a.nrows(), self.n(), |k, j| {
            self.kl.a[(k, j)] / lam[k]
        });
        let info = linalg::symmetrize(&(self.kl.a.transpose() * &aw));
        let cov = linalg::inverse("AᵀΛ⁻¹A", &info).map_err(|e| e.message)?;
        let gain = &cov * aw.transpose();
        Ok((gain, linalg::symmetrize(&cov)))
    }
}

/// A prepared LSCR estimator: problem, strings, q and the comparison filters.
#[derive(Debug, Clone)]
pub struct Estimator {
    pub model: LscrModel,
    pub problem: Problem,
    pub strings: Strings,
    pub q: usize,
    /// BLUE gain and covariance (or why not).
    pub blue: std::result::Result<(DMatrix<f64>, DMatrix<f64>), String>,
    /// Kalman gains for the data length (prediction and filtering only).
    pub kalman: Option<KalmanGains>,
}

/// Options of the construction (the `lscr` block of a scenario, validated).
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    pub target: Target,
    pub m: usize,
    pub q: usize,
    pub construction: Construction,
    pub seed: u64,
    pub strings: Option<Vec<String>>,
}

impl Estimator {
    pub fn new(model: &LscrModel, t: usize, o: &Options) -> Result<Self> {
        let problem = Problem::new(model, t, o.target)?;
        let n = problem.n();
        let strings = match &o.strings {
            Some(s) => Strings::explicit(s, t)?,
            None => {
                if o.m < 2 * n {
                    return Err(Error::field("lscr.M", format!("must be at least 2n = {} (so that q ≥ 1 fits in [1, M/(2n)]), found {}", 2 * n, o.m)));
                }
                if o.m > MAX_STRINGS {
                    return Err(Error::field(
                        "lscr.M",
                        format!("must be at most {MAX_STRINGS}, found {}", o.m),
                    ));
                }
                match o.construction {
                    Construction::Group => Strings::group(o.m, t, o.seed)?,
                    _ => Strings::random(o.m, t, o.seed)?,
                }
            }
        };
        let m = strings.m();
        let qmax = m / (2 * n);
        if o.q < 1 || o.q > qmax {
            return Err(Error::field(
                "lscr.q",
                format!("must lie in [1, M/(2n)] = [1, {qmax}] for M = {m}, n = {n} (Theorem 3.2), found {}", o.q),
            ));
        }
        let blue = problem.blue_gain(model.sigma_v2, model.sigma_w2);
        let kalman = match o.target {
            Target::Smooth(_) => None,
            _ => KalmanGains::new(&model.linear, t).ok(),
        };
        Ok(Estimator {
            model: model.clone(),
            problem,
            strings,
            q: o.q,
            blue,
            kalman,
        })
    }

    /// 1 − 2q/M (18) and 1 − 2qn/M (19).
    pub fn levels(&self) -> (f64, f64) {
        let (m, q, n) = (
            self.strings.m() as f64,
            self.q as f64,
            self.problem.n() as f64,
        );
        (1.0 - 2.0 * q / m, 1.0 - 2.0 * q * n / m)
    }

    /// Whether Theorem 3.2 applies to these strings.
    pub fn guaranteed(&self) -> bool {
        self.strings.construction != Construction::Explicit || self.strings.is_group
    }

    /// The region X̂ for data y_1..y_t.
    pub fn region(&self, y: &[f64]) -> SignRegion {
        self.problem
            .region(&self.problem.s(y), &self.strings, self.q)
    }

    /// BLUE ellipsoid at the joint LSCR level.
    pub fn blue(&self, y: &[f64]) -> Option<Ellipsoid> {
        let (gain, cov) = self.blue.as_ref().ok()?;
        let x = gain * self.problem.s(y);
        Ellipsoid::at_level(&x, cov, self.levels().1.max(1e-9)).ok()
    }

    /// Kalman filter ellipsoid of x_{t+1} (prediction) or x_t (filtering) at the joint level.
    pub fn kalman(&self, y: &[f64]) -> Option<Ellipsoid> {
        let gains = self.kalman.as_ref()?;
        let lm = &self.model.linear;
        let yv: Vec<DVector<f64>> = y.iter().map(|&v| DVector::from_element(1, v)).collect();
        let xf = gains.filter(lm, &yv, &Inputs::none());
        let t = y.len();
        let (mean, cov) = match self.problem.regression.target {
            Target::Predict => {
                crate::kalman::predict(lm, t, 1, &xf[t - 1], &gains.steps[t - 1].p, &Inputs::none())
            }
            _ => (xf[t - 1].clone(), gains.steps[t - 1].p.clone()),
        };
        Ellipsoid::at_level(&mean, &cov, self.levels().1.max(1e-9)).ok()
    }

    /// Data y_1..y_t drawn from their exact law given x_τ = x (the backward representation
    /// before τ, the model forward after it: Lemma 2.1), with a sampler prepared once.
    pub fn sampler(&self) -> Result<ConditionedSampler> {
        let t = self.problem.regression.t;
        let tau = self.problem.regression.target.time(t);
        ConditionedSampler::new(&self.model.linear, t.max(tau), &Inputs::none(), tau)
    }
}

/// Counts of a coverage experiment for one fixed true state (over a range of runs: they add).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Coverage {
    pub runs: usize,
    /// Runs with x̄ ∈ X̂_l, per l.
    pub inside_each: Vec<usize>,
    /// Runs with x̄ ∈ X̂.
    pub inside: usize,
    /// Runs with x̄ in the BLUE ellipsoid (when there is one; absent, never null, when not).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blue: Option<usize>,
    /// Runs with x̄ in the Kalman ellipsoid (prediction and filtering; absent for smoothing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kf: Option<usize>,
}

impl crate::study::Tally for Coverage {
    fn runs(&self) -> usize {
        self.runs
    }
    fn counts(&self) -> Vec<(String, usize)> {
        let mut c = crate::study::listed_counts("inside_each", &self.inside_each);
        c.push(("inside".into(), self.inside));
        c.extend(self.blue.map(|n| ("blue".into(), n)));
        c.extend(self.kf.map(|n| ("kf".into(), n)));
        c
    }
    fn add(&mut self, later: &Self) -> std::result::Result<(), String> {
        use crate::study::add_count;
        crate::study::add_counts(
            &mut self.inside_each,
            &later.inside_each,
            "inside_each",
            "counts in inside_each",
        )?;
        for (a, b, what) in [
            (&mut self.blue, later.blue, "blue"),
            (&mut self.kf, later.kf, "kf"),
        ] {
            match (a.as_mut(), b) {
                (Some(a), Some(b)) => add_count(a, b, what)?,
                (None, None) => {}
                _ => return Err(format!("{what} is counted in one and not the other")),
            }
        }
        add_count(&mut self.runs, later.runs, "runs")?;
        add_count(&mut self.inside, later.inside, "inside")?;
        Ok(())
    }
}

/// A coverage experiment: N realizations of the data given x_τ = x̄, counting how often each
/// region holds x̄ (Theorem 3.2 made visible), run in ranges of runs (the study is
/// `scenario::lscr::LscrStudy`). Membership needs only g_{i,l}(x̄), so a run costs a draw of
/// the data, s = Uᵀy and (M − 1)·n·t additions. Random strings (point 4) are redrawn for every
/// run, because Theorem 3.2's probability is over the strings as well as the noise (one fixed
/// random draw can sit a little above or below the level); group and explicit strings stay
/// fixed, for which the theorem holds given the strings. Run i draws its strings and data from
/// its own stream ([`crate::study::run_stream`] of the seed and i).
pub struct Experiment {
    est: Estimator,
    /// The strings of the runs: the estimator's, redrawn per run for point 4 (random).
    strings: Strings,
    sampler: ConditionedSampler,
    truth: DVector<f64>,
    pub seed: u64,
    pub total: usize,
    blue_r2: f64,
    /// Inverse BLUE covariance (data-independent).
    blue_inv: Option<DMatrix<f64>>,
    kf: Option<(DMatrix<f64>, f64)>,
}

impl Experiment {
    pub fn new(est: Estimator, truth: &[f64], runs: usize, seed: u64) -> Result<Self> {
        let n = est.problem.n();
        let truth = linalg::vector("simulate.condition.x", truth, n)?;
        if runs == 0 || runs > 1_000_000 {
            return Err(Error::field(
                "lscr.coverage.runs",
                format!("must be a whole number from 1 to 1000000, found {runs}"),
            ));
        }
        let sampler = est.sampler()?;
        let level = est.levels().1;
        let blue_r2 = crate::stats::chi2_quantile(level, n)?;
        // The Kalman covariance does not depend on the data: invert it once.
        let kf = match (&est.kalman, est.problem.regression.target) {
            (Some(g), target) => {
                let t = est.problem.regression.t;
                let p = &g.steps[t - 1].p;
                let cov = match target {
                    Target::Predict => {
                        crate::kalman::predict(
                            &est.model.linear,
                            t,
                            1,
                            &DVector::zeros(n),
                            p,
                            &Inputs::none(),
                        )
                        .1
                    }
                    _ => p.clone(),
                };
                linalg::inverse("Kalman covariance", &cov)
                    .ok()
                    .map(|inv| (inv, blue_r2))
            }
            _ => None,
        };
        let blue_inv = est
            .blue
            .as_ref()
            .ok()
            .and_then(|(_, cov)| linalg::inverse("BLUE covariance", cov).ok());
        let strings = est.strings.clone();
        Ok(Experiment {
            est,
            strings,
            sampler,
            truth,
            seed,
            total: runs,
            blue_r2,
            blue_inv,
            kf,
        })
    }

    /// The counts of no run.
    pub fn zero(&self) -> Coverage {
        Coverage {
            runs: 0,
            inside_each: vec![0; self.est.problem.n()],
            inside: 0,
            blue: self.blue_inv.as_ref().map(|_| 0),
            kf: self.kf.as_ref().map(|_| 0),
        }
    }

    /// The estimator the runs use (levels, for [`crate::scenario::lscr::coverage_report`]).
    pub fn estimator(&self) -> &Estimator {
        &self.est
    }

    /// The fixed true state x̄.
    pub fn truth(&self) -> &[f64] {
        self.truth.as_slice()
    }

    /// The same experiment with its data drawn from `truth` (the model with its noise scaled
    /// by `simulate.true_noise`): the region, the BLUE and the Kalman ellipses are unchanged,
    /// only the law of the draws (backward representation before τ, the model forward after
    /// it) is the truth's. A scale keeps the noise's shape, so the region's Theorem 3.2 still
    /// holds (Lemma 3.1: Cov n̄ = σ_v²D + σ_w²I stays diagonal at any σ_v², σ_w²); the
    /// ellipses, which assume the model's variances, do not.
    pub fn with_truth(mut self, truth: &LinearModel) -> Result<Self> {
        let t = self.est.problem.regression.t;
        let tau = self.est.problem.regression.target.time(t);
        self.sampler = ConditionedSampler::new(truth, t.max(tau), &Inputs::none(), tau)?;
        Ok(self)
    }

    /// Run the realizations of `runs` and count them.
    pub fn run(&mut self, runs: std::ops::Range<usize>) -> Coverage {
        let mut counts = self.zero();
        let est = &self.est;
        let p = &est.problem;
        let n = p.n();
        let t = p.regression.t;
        let ax = &p.kl.a * &self.truth;
        let mut z = DVector::zeros(t);
        let redraw = est.strings.construction == Construction::Random;
        for i in runs {
            let mut rng = crate::study::run_stream(self.seed, i);
            if redraw {
                self.strings.redraw_random(&mut rng);
            }
            let traj = self.sampler.draw(&est.model.linear, &self.truth, &mut rng);
            let y: Vec<f64> = traj.y[..t].iter().map(|v| v[0]).collect();
            let s = p.s(&y);
            let resid = &s - &ax; // s_k − a_k x̄
            let mut all = true;
            for l in 0..n {
                for kk in 0..t {
                    z[kk] = p.kl.u_a[(kk, l)] * resid[kk];
                }
                let g = &self.strings.h * &z;
                let pos = g.iter().filter(|&&v| v > 0.0).count();
                let neg = g.iter().filter(|&&v| v < 0.0).count();
                if pos >= est.q && neg >= est.q {
                    counts.inside_each[l] += 1;
                } else {
                    all = false;
                }
            }
            if all {
                counts.inside += 1;
            }
            if let (Some(c), Ok((gain, _)), Some(inv)) =
                (counts.blue.as_mut(), &est.blue, &self.blue_inv)
            {
                let e = gain * &s - &self.truth;
                if (e.transpose() * inv * &e)[(0, 0)] <= self.blue_r2 {
                    *c += 1;
                }
            }
            if let (Some(c), Some((inv, r2))) = (counts.kf.as_mut(), &self.kf) {
                if let Some(ell) = est.kalman(&y) {
                    let e = ell.center_vec() - &self.truth;
                    if (e.transpose() * inv * &e)[(0, 0)] <= *r2 {
                        *c += 1;
                    }
                }
            }
            counts.runs += 1;
        }
        counts
    }
}
