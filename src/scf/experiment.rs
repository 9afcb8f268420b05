//! Conditional-coverage studies: what the SCF promises (Property 1) made visible in numbers.
//!
//! * [`coverage_curve`] — Fig. 1: P{x_t ∈ X_t | x_t = x̄} for KF and SCF as x̄ moves along one
//!   component; closed form for n = 1, exact-law Monte Carlo otherwise.
//! * [`ConditionalExperiment`] — the robot Monte Carlo of Section II-B: realizations drawn
//!   backwards from a fixed state x_c at t_c (footnote 2), both filters run on each, inclusion at
//!   t_c and τ-step collision warnings counted. Runs in chunks so a page can show progress and
//!   cancel. Gains, ratio matrices, backward matrices and noise square roots are computed once;
//!   the loop is sparse matrix-vector products and normal draws, from the scenario's
//!   [`Generator`] (`experiment.rng`: ChaCha8 when absent, or xoshiro256++).

use crate::error::{Error, Result};
use crate::kalman::{self, Offline};
use crate::linalg::{self, sub_matrix, sub_vector};
use crate::model::{Inputs, LinearModel};
use crate::scf::{self, ScfOptions};
use crate::sets::{Ellipsoid, PlanarEllipse};
use crate::stats::chi2_quantile;
use nalgebra::{DMatrix, DVector};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

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
    /// The random generator of the runs (`"chacha8"` when absent, and then not written, so a
    /// scenario saved before the field existed reads, runs and writes exactly as it did).
    #[serde(default, skip_serializing_if = "Generator::is_default")]
    pub rng: Generator,
}

/// The Monte Carlo's random generator: a versioned choice, so that a scenario keeps its
/// streams (its counts, its golden digest, its share link) whatever a later version prefers.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
pub enum Generator {
    /// ChaCha8 (`rand_chacha`): stream b of the seed for block b. The generator of every
    /// scenario written before `experiment.rng` existed.
    #[default]
    #[serde(rename = "chacha8")]
    ChaCha8,
    /// xoshiro256++ (Blackman & Vigna; `rand::rngs::Xoshiro256PlusPlus`): block b starts from
    /// the words 4b + 1 … 4b + 4 of SplitMix64 started at the seed. Four 64-bit words of state
    /// and a few adds, shifts and rotations per word instead of ChaCha8's 64-byte block
    /// function: the robot Monte Carlo's generator in wasm, where ChaCha8 has no SIMD.
    #[serde(rename = "xoshiro256++")]
    Xoshiro256PlusPlus,
}

impl Generator {
    /// The scenario's names, in the order the error messages list them.
    pub const NAMES: [&'static str; 2] = ["chacha8", "xoshiro256++"];

    fn is_default(&self) -> bool {
        *self == Generator::default()
    }
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

/// Draws per point of a Monte Carlo coverage curve.
pub const CURVE_DRAWS: usize = 2000;

/// Fig. 1 for component `c.component` at time `time` (filtering, full state conditioned), with
/// the filter of the record `y` (its gaps: skipped or partial updates; the conditional law
/// below holds for any linear Bayesian estimate of x_t from the measured outputs, so it holds
/// with the gaps' P_t and R_t = I − P_tΓ_t⁻¹ (41)).
pub fn coverage_curve(
    model: &LinearModel,
    u: &Inputs,
    opts: &ScfOptions,
    c: &CurveSpec,
    time: usize,
    y: &[DVector<f64>],
) -> Result<CoverageCurve> {
    let n = model.n();
    if c.component >= n {
        return Err(Error::field(
            "scf.coverage_curve.component",
            format!("must be below n = {n}"),
        ));
    }
    if !(c.from.is_finite() && c.to.is_finite() && c.from < c.to) {
        return Err(Error::field(
            "scf.coverage_curve.from",
            "must be finite and below scf.coverage_curve.to",
        ));
    }
    if c.points < 2 || c.points > 2001 {
        return Err(Error::field(
            "scf.coverage_curve.points",
            "must be a whole number from 2 to 2001",
        ));
    }
    let off = Offline::with_gaps(model, time, u, y)?;
    let (p, gamma, m) = if opts.asymptotic {
        let ss = kalman::steady_state(model)?;
        (ss.p, model.stationary_covariance()?, DVector::zeros(n))
    } else {
        (
            off.gains.steps[time - 1].p.clone(),
            off.moments.cov[time - 1].clone(),
            off.moments.mean[time - 1].clone(),
        )
    };
    let xbar: Vec<f64> = (0..c.points)
        .map(|i| c.from + (c.to - c.from) * i as f64 / (c.points - 1) as f64)
        .collect();
    if n == 1 {
        let (mut kf, mut sc) = (Vec::new(), Vec::new());
        for &x in &xbar {
            let (a, b) =
                scf::conditional_coverage_1d(p[(0, 0)], gamma[(0, 0)], m[0], x, opts.alpha)?;
            kf.push(a);
            sc.push(b);
        }
        return Ok(CoverageCurve {
            component: 0,
            time,
            xbar,
            kf,
            scf: sc,
            how: "closed form".into(),
        });
    }
    // x̂^KF − m ~ N(R(x̄ − m), P − PΓ⁻¹P) given x_t = x̄ (see scf::conditional_coverage_1d).
    let ratio = scf::ratio_closed_form(&p, &gamma)?;
    let r_inv = linalg::inverse("ratio matrix", &ratio)
        .map_err(|_| Error::field("time", "is too early: the ratio matrix is still singular"))?;
    let cond_cov = linalg::symmetrize(&(&p - &p * linalg::inverse("Γ_t", &gamma)? * &p));
    let l = linalg::psd_sqrt(&cond_cov);
    let r2 = chi2_quantile(opts.alpha, n)?;
    let p_inv = linalg::inverse("P_t", &p)?;
    let pi_inv = linalg::inverse("Π_t", &linalg::symmetrize(&(&r_inv * &p)))?;
    let mut rng = ChaCha8Rng::seed_from_u64(0x5cf);
    let (mut kf, mut sc) = (Vec::new(), Vec::new());
    for &x in &xbar {
        let mut xb = m.clone();
        xb[c.component] = x;
        let mean = &ratio * (&xb - &m);
        let (mut ik, mut is) = (0usize, 0usize);
        for _ in 0..CURVE_DRAWS {
            let dev = &mean + &l * crate::model::normal_vector(n, &mut rng); // x̂^KF − m
            let e_kf = &m + &dev - &xb;
            let e_scf = &r_inv * &dev + &m - &xb;
            ik += (e_kf.dot(&(&p_inv * &e_kf)) <= r2) as usize;
            is += (e_scf.dot(&(&pi_inv * &e_scf)) <= r2) as usize;
        }
        kf.push(ik as f64 / CURVE_DRAWS as f64);
        sc.push(is as f64 / CURVE_DRAWS as f64);
    }
    Ok(CoverageCurve {
        component: c.component,
        time,
        xbar,
        kf,
        scf: sc,
        how: format!("monte carlo ({CURVE_DRAWS} draws per point, exact conditional law)"),
    })
}

/// A small matrix stored by its non-zero columns, for the Monte Carlo loop: every product is a
/// few axpy's over contiguous columns (which vectorize), and the all-zero columns of block
/// structured models (two independent robots) are skipped.
#[derive(Debug, Clone)]
struct Csr {
    rows: usize,
    /// (column index, the column's entries).
    cols: Vec<(usize, Vec<f64>)>,
}

impl Csr {
    fn new(m: &DMatrix<f64>) -> Self {
        let cols = (0..m.ncols())
            .filter(|&j| m.column(j).iter().any(|&v| v != 0.0))
            .map(|j| (j, m.column(j).iter().copied().collect()))
            .collect();
        Csr {
            rows: m.nrows(),
            cols,
        }
    }
    /// out += M x
    #[inline]
    fn mul_add(&self, x: &[f64], out: &mut [f64]) {
        let out = &mut out[..self.rows];
        for (j, col) in &self.cols {
            let xj = x[*j];
            for (o, a) in out.iter_mut().zip(col) {
                *o += a * xj;
            }
        }
    }
}

/// A region whose shape is fixed and whose center is an affine function of the KF estimate:
/// c = m + A(x̂ − m) on the selected components (A = I for KF, R⁻¹ for SCF).
#[derive(Debug, Clone)]
struct MovingRegion {
    idx: Vec<usize>,
    m: Vec<f64>,
    a: Csr,
    /// Inverse shape (radius2 folded in: inside iff eᵀ S e ≤ 1).
    s_inv: DMatrix<f64>,
    /// For 2-D regions, the planar shape (center filled per run).
    planar: Option<PlanarEllipse>,
    /// Largest and smallest semi-axes (2-D), for cheap collision bounds.
    axes: (f64, f64),
}

impl MovingRegion {
    fn new(
        idx: &[usize],
        m: &DVector<f64>,
        a: &DMatrix<f64>,
        shape: &DMatrix<f64>,
        r2: f64,
    ) -> Result<Self> {
        let s_inv = linalg::inverse("region shape", shape)? / r2;
        let e = Ellipsoid::new(&DVector::zeros(idx.len()), shape, r2);
        let (planar, axes) = if idx.len() == 2 {
            let ev = linalg::try_symmetric_eigen(linalg::symmetrize(shape))
                .ok_or_else(|| {
                    Error::field(
                        "model",
                        "the region's shape matrix is not finite: the model's covariances overflow",
                    )
                })?
                .eigenvalues;
            (
                Some(PlanarEllipse::from(&e)),
                ((r2 * ev.max()).sqrt(), (r2 * ev.min().max(0.0)).sqrt()),
            )
        } else {
            (None, (0.0, 0.0))
        };
        Ok(MovingRegion {
            idx: idx.to_vec(),
            m: sub_vector(m, idx).iter().copied().collect(),
            a: Csr::new(a),
            s_inv,
            planar,
            axes,
        })
    }
    /// Center for a KF estimate x̂ (full state), written to `out[..k]`; `dev` is scratch.
    #[inline]
    fn center(&self, xhat: &[f64], out: &mut [f64], dev: &mut [f64]) {
        for (k, (&i, m)) in self.idx.iter().zip(&self.m).enumerate() {
            dev[k] = xhat[i] - m;
        }
        out.copy_from_slice(&self.m);
        self.a.mul_add(&dev[..self.idx.len()], out);
    }
    /// Is the true state `x` inside the region centered by `xhat`? `scratch` holds ≥ 2k values.
    fn contains(&self, xhat: &[f64], x: &[f64], scratch: &mut [f64]) -> bool {
        let k = self.idx.len();
        let (c, rest) = scratch.split_at_mut(k);
        self.center(xhat, c, rest);
        for (j, &i) in self.idx.iter().enumerate() {
            c[j] = x[i] - c[j];
        }
        let mut q = 0.0;
        for a in 0..k {
            let mut row = 0.0;
            for b in 0..k {
                row += self.s_inv[(a, b)] * c[b];
            }
            q += c[a] * row;
        }
        q <= 1.0
    }
}

/// Distance-below-d test of two moving 2-D regions, with cheap exits before the exact distance.
fn warns(
    ra: &MovingRegion,
    rb: &MovingRegion,
    xhat: &[f64],
    d_min: f64,
    scratch: &mut [f64],
) -> bool {
    let (ca, rest) = scratch.split_at_mut(2);
    let (cb, dev) = rest.split_at_mut(2);
    ra.center(xhat, ca, dev);
    rb.center(xhat, cb, dev);
    let dc = ((ca[0] - cb[0]).powi(2) + (ca[1] - cb[1]).powi(2)).sqrt();
    if dc - ra.axes.0 - rb.axes.0 >= d_min {
        return false; // even the circumscribed discs are d_min apart
    }
    if dc - ra.axes.1 - rb.axes.1 < d_min {
        return true; // the inscribed discs are closer than d_min
    }
    match (ra.planar, rb.planar) {
        (Some(mut pa), Some(mut pb)) => {
            pa.c = [ca[0], ca[1]];
            pb.c = [cb[0], cb[1]];
            pa.distance(&pb) < d_min
        }
        _ => false,
    }
}

/// One step of the backward innovations model: given x_{t_c} and y_{t+1}, …, y_{t_c}, the state
/// x_t − m_t is N(ẑ_t, Σ_t) and y_t = H_t(ẑ_t + m_t) + e_t with e_t ~ N(0, S_t),
/// S_t = H_tΣ_tH_tᵀ + W_t; then ẑ⁺ = ẑ_t + G_t e_t, G_t = Σ_tH_tᵀS_t⁻¹, and
/// ẑ_{t−1} = F^b_t ẑ⁺ (45). It draws q normals per step instead of n + q, with exactly the law
/// of the measurements that a backward state simulation gives.
#[derive(Debug, Clone)]
struct InnovationStep {
    h: DMatrix<f64>,
    /// H_t m_t.
    hm: DVector<f64>,
    /// Lower Cholesky factor of S_t.
    l_s: DMatrix<f64>,
    g: DMatrix<f64>,
    /// F^b_t (zero at t = 1, where it is not used).
    f_b: DMatrix<f64>,
}

/// The steps t = 1..=t_c (index t−1) of the backward innovations model, from Σ_{t_c} = 0.
fn backward_innovations(
    model: &LinearModel,
    moments: &crate::model::Moments,
    t_c: usize,
) -> Result<Vec<InnovationStep>> {
    let n = model.n();
    let mut sigma = DMatrix::zeros(n, n);
    let mut out = Vec::with_capacity(t_c);
    for t in (1..=t_c).rev() {
        let h = model.h(t);
        let s = linalg::symmetrize(&(h * &sigma * h.transpose() + model.w(t)));
        let chol = s
            .clone()
            .cholesky()
            .ok_or_else(|| Error::field("model.W", "gives a singular innovation covariance"))?;
        let g = chol.solve(&(h * &sigma)).transpose();
        let plus = linalg::symmetrize(&(&sigma - &g * &s * g.transpose()));
        let f_b = if t >= 2 {
            let step = model.backward_step(t, moments)?;
            sigma = linalg::symmetrize(&(&step.f_b * plus * step.f_b.transpose() + step.v_b));
            step.f_b
        } else {
            DMatrix::zeros(n, n)
        };
        out.push(InnovationStep {
            h: h.clone(),
            hm: h * &moments.mean[t - 1],
            l_s: chol.l(),
            g,
            f_b,
        });
    }
    out.reverse();
    Ok(out)
}

/// An independent block of the model: states and outputs that no matrix of the Monte Carlo
/// loop couples to the rest.
#[derive(Debug, Clone)]
struct Block {
    states: Vec<usize>,
    outputs: Vec<usize>,
}

/// Connected components of the coupling graph (states 0..n, outputs n..n+q) of every matrix the
/// loop uses, so each block can run alone with exactly the same numbers.
fn independent_blocks(
    n: usize,
    q: usize,
    square: &[&DMatrix<f64>],
    state_by_output: &[&DMatrix<f64>],
) -> Vec<Block> {
    let mut parent: Vec<usize> = (0..n + q).collect();
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    let join = |p: &mut Vec<usize>, a: usize, b: usize| {
        let (ra, rb) = (find(p, a), find(p, b));
        p[ra.max(rb)] = ra.min(rb);
    };
    for m in square {
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                if m[(i, j)] != 0.0 {
                    let off = if m.nrows() == n { 0 } else { n };
                    join(&mut parent, off + i, off + j);
                }
            }
        }
    }
    for m in state_by_output {
        // n×q (gains) or q×n (output matrices)
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                if m[(i, j)] != 0.0 {
                    let (s, o) = if m.nrows() == n { (i, j) } else { (j, i) };
                    join(&mut parent, s, n + o);
                }
            }
        }
    }
    let mut blocks: Vec<(usize, Block)> = Vec::new();
    for v in 0..n + q {
        let root = find(&mut parent, v);
        let k = match blocks.iter().position(|(r, _)| *r == root) {
            Some(k) => k,
            None => {
                blocks.push((
                    root,
                    Block {
                        states: vec![],
                        outputs: vec![],
                    },
                ));
                blocks.len() - 1
            }
        };
        if v < n {
            blocks[k].1.states.push(v);
        } else {
            blocks[k].1.outputs.push(v - n);
        }
    }
    // An output block without states (pure noise) carries no information: merge into the first.
    let mut out: Vec<Block> = Vec::new();
    for (_, b) in blocks {
        if b.states.is_empty() {
            if let Some(first) = out.first_mut() {
                first.outputs.extend(b.outputs);
                first.outputs.sort_unstable();
            }
        } else {
            out.push(b);
        }
    }
    out
}

/// Backward innovations step on padded fixed-size arrays.
/// (Matrices stored by columns: `[[f64; rows]; cols]`.)
struct FixedInnovation<const N: usize, const Q: usize> {
    h: [[f64; Q]; N],
    hm: [f64; Q],
    l_s: [[f64; Q]; Q],
    g: [[f64; N]; Q],
    f_b: [[f64; N]; N],
}

/// Forward filter step on padded fixed-size arrays.
struct FixedForward<const N: usize, const Q: usize> {
    k: [[f64; N]; Q],
    h: [[f64; Q]; N],
    f: [[f64; N]; N],
    bu: [f64; N],
}

/// An R×C matrix zero-padded and stored by columns (`a[j][i]` = m_ij).
fn fixed<const R: usize, const C: usize>(m: &DMatrix<f64>) -> [[f64; R]; C] {
    let mut a = [[0.0; R]; C];
    for i in 0..m.nrows().min(R) {
        for j in 0..m.ncols().min(C) {
            a[j][i] = m[(i, j)];
        }
    }
    a
}

/// A vector zero-padded into an array.
fn fixed_vec<const R: usize>(v: &DVector<f64>) -> [f64; R] {
    let mut a = [0.0; R];
    for (ai, vi) in a.iter_mut().zip(v.iter()) {
        *ai = *vi;
    }
    a
}

/// Runs advanced together: independent runs side by side keep the pipeline full (one run's
/// recursion is a chain of dependent operations) and vectorize.
pub const LANES: usize = 8;

/// M X for M stored by columns (`m[j]` is column j) and X holding one column per lane.
#[inline(always)]
fn lanes_mat_vec<const R: usize, const C: usize>(
    m: &[[f64; R]; C],
    x: &[[f64; LANES]; C],
) -> [[f64; LANES]; R] {
    let mut out = [[0.0; LANES]; R];
    for j in 0..C {
        for i in 0..R {
            let a = m[j][i];
            for l in 0..LANES {
                out[i][l] += a * x[j][l];
            }
        }
    }
    out
}

/// The additive counts of a range of conditional runs (a shard's partial counts).
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ConditionalCounts {
    pub runs: usize,
    pub kf_inside: usize,
    pub scf_inside: usize,
    pub kf_warnings: usize,
    pub scf_warnings: usize,
}

impl crate::study::Tally for ConditionalCounts {
    fn runs(&self) -> usize {
        self.runs
    }
    fn counts(&self) -> Vec<(String, usize)> {
        [
            ("kf_inside", self.kf_inside),
            ("scf_inside", self.scf_inside),
            ("kf_warnings", self.kf_warnings),
            ("scf_warnings", self.scf_warnings),
        ]
        .map(|(k, n)| (k.to_string(), n))
        .to_vec()
    }
    fn add(&mut self, later: &Self) -> std::result::Result<(), String> {
        use crate::study::add_count;
        add_count(&mut self.runs, later.runs, "runs")?;
        add_count(&mut self.kf_inside, later.kf_inside, "kf_inside")?;
        add_count(&mut self.scf_inside, later.scf_inside, "scf_inside")?;
        add_count(&mut self.kf_warnings, later.kf_warnings, "kf_warnings")?;
        add_count(&mut self.scf_warnings, later.scf_warnings, "scf_warnings")?;
        Ok(())
    }
}

/// Counts of a conditional Monte Carlo so far.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct ExperimentResult {
    pub runs_done: usize,
    pub runs_total: usize,
    pub alpha: f64,
    pub condition_t: usize,
    /// The conditioning state x_{t_c} (the scenario's `simulate.condition.x`, or the prior
    /// mean m_{t_c} of a study given only its runs).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub condition_x: Vec<f64>,
    pub components: Vec<usize>,
    /// Runs with the true ζ_{t_c} inside X^KF / X^SCF.
    pub kf_inside: usize,
    pub scf_inside: usize,
    /// Collision warnings from the τ-step prediction at `warning_t` (if configured).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub warning_t: Option<usize>,
    pub kf_warnings: usize,
    pub scf_warnings: usize,
    /// Exact 99.9 % binomial band ([`crate::stats::band`]) of the SCF count at α.
    pub scf_expected_range: (usize, usize),
}

/// Monte Carlo over realizations conditioned on x_{t_c} = x_c, run in ranges of runs
/// ([`crate::study::Runs`]; as a study: `Chunked::new(experiment)`).
///
/// Randomness: one stream of the scenario's [`Generator`] per independent block of the model
/// (see [`block_streams`]), read in whole batches of [`LANES`] runs, each run taking t_c·q_b normals of block b. So
/// batch k always reads the k-th stretch of each stream's normals: run i depends only on the
/// seed and i's batch. A range that starts past the streams' position first draws and drops
/// the normals of the runs before it (a normal takes a varying number of words, so the
/// position cannot be computed); that costs a few percent of those runs' time.
pub struct ConditionalExperiment {
    seed: u64,
    generator: Generator,
    /// One random stream per independent block.
    rngs: Streams,
    /// The run the streams stand at.
    position: usize,
    blocks: Vec<Block>,
    n: usize,
    t_c: usize,
    x_c: Vec<f64>,
    /// x_c − m_{t_c}: the conditioning state, centered.
    x_c_dev: Vec<f64>,
    /// Backward innovations model of y_1..y_{t_c} given x_{t_c}, index t−1.
    innov: Vec<InnovationStep>,
    /// K_t, H_t, F_t, B_t u_t of the forward filter, index t−1.
    kf: Vec<(DMatrix<f64>, DMatrix<f64>, DMatrix<f64>, DVector<f64>)>,
    x1_mean: DVector<f64>,
    cover: (MovingRegion, MovingRegion),
    warning: Option<(usize, Csr, Vec<f64>, [MovingRegion; 4], f64)>, // t, Φ, c, [kf_a, kf_b, scf_a, scf_b], d_min
    /// The result's fixed fields (its counts come from [`ConditionalCounts`]).
    result: ExperimentResult,
}

/// One random stream per independent block, of the scenario's generator.
enum Streams {
    ChaCha8(Vec<ChaCha8Rng>),
    Xoshiro256PlusPlus(Vec<Xoshiro256PlusPlus>),
}

/// The golden-ratio increment of SplitMix64 (Steele, Lea & Flood 2014), the step between two of
/// its words.
const SPLITMIX64_GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

/// The streams of `seed` for each of `blocks` independent blocks. ChaCha8: stream b of the
/// seed. xoshiro256++: `seed_from_u64(s)` fills the four state words with SplitMix64's words
/// from state s, so starting block b at s = seed + 4b·γ gives it words 4b + 1 … 4b + 4 of one
/// SplitMix64 sequence: distinct, well-mixed states whatever the seed, and each block's stream
/// depends only on the seed and b (shards and chunks stay deterministic and mergeable).
fn block_streams(rng: Generator, seed: u64, blocks: usize) -> Streams {
    match rng {
        Generator::ChaCha8 => Streams::ChaCha8(
            (0..blocks)
                .map(|b| {
                    let mut r = ChaCha8Rng::seed_from_u64(seed);
                    r.set_stream(b as u64);
                    r
                })
                .collect(),
        ),
        Generator::Xoshiro256PlusPlus => Streams::Xoshiro256PlusPlus(
            (0..blocks)
                .map(|b| {
                    let start = seed.wrapping_add((4 * b as u64).wrapping_mul(SPLITMIX64_GAMMA));
                    Xoshiro256PlusPlus::seed_from_u64(start)
                })
                .collect(),
        ),
    }
}

/// The next `buf.len()` standard normals of `rng`, in order.
fn fill_normals<R: Rng>(rng: &mut R, buf: &mut [f64]) {
    for v in buf {
        *v = rng.sample(StandardNormal);
    }
}

/// A block's source of standard normals: fills a slice with the stream's next draws.
type Normals<'a> = dyn FnMut(&mut [f64]) + 'a;

/// Draw and drop `count` standard normals.
fn skip_normals<R: Rng>(rng: &mut R, count: usize) {
    for _ in 0..count {
        let _: f64 = rng.sample(StandardNormal);
    }
}

impl ConditionalExperiment {
    /// Prepare the study: `spec.runs` realizations of the model with inputs, each conditioned
    /// on x_{t_c} = x_c, scored with the SCF options' regions (and, with `spec.warning_t`, the
    /// τ-step collision warning of `collision`). `(model, truth)`: the filters assume `model`;
    /// the realizations are drawn from `truth` (the same model with its noise scaled by
    /// `simulate.true_noise`, or `model` itself).
    pub fn new(
        (model, truth): (&LinearModel, &LinearModel),
        inputs: &Inputs,
        opts: &ScfOptions,
        (t_c, x_c): (usize, &[f64]),
        e: &ExperimentSpec,
        collision: Option<&CollisionSpec>,
    ) -> Result<Self> {
        if e.runs == 0 || e.runs > 10_000_000 {
            return Err(Error::field(
                "experiment.runs",
                "must be a whole number from 1 to 10000000",
            ));
        }
        let (n, q) = (model.n(), model.q());
        let steps = t_c;
        if t_c < 1 || t_c > 100_000 {
            return Err(Error::field("simulate.condition.t", "must be at least 1"));
        }
        // The draws' law is the truth's: its moments (the means are the model's, which no noise
        // scale changes) and its backward innovations model (45).
        let moments = truth.moments(steps, inputs);
        let innov = backward_innovations(truth, &moments, t_c)?;
        let off = Offline::new(model, steps + opts.tau, inputs)?;
        let r2c = chi2_quantile(opts.alpha, e.components.len())?;
        let region = |idx: &[usize],
                      t: usize,
                      mean: &DVector<f64>,
                      pcov: &DMatrix<f64>,
                      r2: f64|
         -> Result<(MovingRegion, MovingRegion)> {
            let (pk, gk) = (
                sub_matrix(pcov, idx),
                sub_matrix(&off.moments.cov[t - 1], idx),
            );
            let ratio = scf::ratio_closed_form(&pk, &gk)?;
            let r_inv = linalg::inverse("ratio matrix", &ratio).map_err(|_| {
                Error::field(
                    "experiment.components",
                    format!("have a singular ratio matrix at t = {t}"),
                )
            })?;
            let pi = linalg::symmetrize(&(&r_inv * &pk));
            let eye = DMatrix::identity(idx.len(), idx.len());
            Ok((
                MovingRegion::new(idx, mean, &eye, &pk, r2)?,
                MovingRegion::new(idx, mean, &r_inv, &pi, r2)?,
            ))
        };
        Ellipsoid::new(&DVector::zeros(n), &DMatrix::identity(n, n), 1.0)
            .project(&e.components)
            .map_err(|er| Error::field("experiment.components", er.message))?;
        let cover = region(
            &e.components,
            t_c,
            &off.moments.mean[t_c - 1],
            &off.gains.steps[t_c - 1].p,
            r2c,
        )?;
        let warning = match (e.warning_t, collision) {
            (None, _) => None,
            (Some(_), None) => {
                return Err(Error::field(
                    "experiment.warning_t",
                    "needs a collision block",
                ))
            }
            (Some(tw), Some(c)) => {
                kalman::check_time("experiment.warning_t", tw, t_c)?;
                let tau = opts.tau;
                // x̂_{tw+τ|tw} = Φ x̂_tw + c: an affine map, composed once.
                let (mut phi, mut cst) = (DMatrix::identity(n, n), DVector::zeros(n));
                for k in tw..tw + tau {
                    phi = model.f(k) * phi;
                    cst = model.f(k) * cst + model.input_term(k, inputs);
                }
                let (_, pp) = kalman::predict(
                    model,
                    tw,
                    tau,
                    &DVector::zeros(n),
                    &off.gains.steps[tw - 1].p,
                    inputs,
                );
                let tt = tw + tau;
                let r2 = chi2_quantile(opts.alpha, 2)?;
                let mt = &off.moments.mean[tt - 1];
                let (ka, sa) = region(&c.a, tt, mt, &pp, r2)?;
                let (kb, sb) = region(&c.b, tt, mt, &pp, r2)?;
                Some((
                    tw,
                    Csr::new(&phi),
                    cst.iter().copied().collect(),
                    [ka, kb, sa, sb],
                    c.d_min,
                ))
            }
        };
        let lo_hi = crate::stats::band(e.runs, opts.alpha);
        let kf: Vec<_> = (1..=steps)
            .map(|t| {
                (
                    off.gains.steps[t - 1].k.clone(),
                    model.h(t).clone(),
                    model.f(t).clone(),
                    model.input_term(t, inputs),
                )
            })
            .collect();
        let blocks = {
            let square: Vec<&DMatrix<f64>> = innov
                .iter()
                .flat_map(|st| [&st.f_b, &st.l_s])
                .chain(kf.iter().map(|(_, _, f, _)| f))
                .collect();
            let rect: Vec<&DMatrix<f64>> = innov
                .iter()
                .flat_map(|st| [&st.h, &st.g])
                .chain(kf.iter().flat_map(|(k, h, _, _)| [k, h]))
                .collect();
            independent_blocks(n, q, &square, &rect)
        };
        if let Some(b) = blocks
            .iter()
            .find(|b| b.states.len() > 16 || b.outputs.len() > 8)
        {
            return Err(Error::field(
                "model",
                format!("couples {} and {} in one block: the Monte Carlo supports blocks of at most 16 states and 8 outputs", crate::error::counted(b.states.len(), "state", "states"), crate::error::counted(b.outputs.len(), "output", "outputs")),
            ));
        }
        Ok(ConditionalExperiment {
            seed: e.seed,
            generator: e.rng,
            rngs: block_streams(e.rng, e.seed, blocks.len()),
            position: 0,
            blocks,
            n,
            t_c,
            x_c: linalg::vector("simulate.condition.x", x_c, n)?
                .iter()
                .copied()
                .collect(),
            x_c_dev: x_c
                .iter()
                .zip(moments.mean[t_c - 1].iter())
                .map(|(x, m)| x - m)
                .collect(),
            innov,
            kf,
            x1_mean: model.x1_mean.clone(),
            cover,
            warning,
            result: ExperimentResult {
                runs_total: e.runs,
                alpha: opts.alpha,
                condition_t: t_c,
                condition_x: x_c.to_vec(),
                components: e.components.clone(),
                warning_t: e.warning_t,
                scf_expected_range: lo_hi,
                ..Default::default()
            },
        })
    }

    /// Runs `range` (starting on a batch of [`LANES`]); returns their counts.
    ///
    /// The model is split into its independent blocks (the two robots are two blocks), and each
    /// block runs on fixed-size arrays zero-padded to 2×1, 4×2, 8×4 or 16×8, so every product is
    /// unrolled and vectorized; zeros change no number.
    fn run_range(&mut self, range: std::ops::Range<usize>) -> ConditionalCounts {
        self.seek(range.start);
        let todo = range.len();
        let n = self.n;
        let mut at_tc = vec![0.0; todo * n];
        let mut at_tw = vec![0.0; todo * n];
        let tw = self.warning.as_ref().map(|w| w.0);
        for b in 0..self.blocks.len() {
            let (nb, qb) = (self.blocks[b].states.len(), self.blocks[b].outputs.len());
            let out = (&mut at_tc[..], &mut at_tw[..]);
            // The generator is chosen once per block, not per draw: each fills a batch's
            // normals in its own monomorphic loop, and the runs' arithmetic is compiled once
            // (generic over the generator it was two copies of ~110 KB in the page's module).
            let mut rngs = std::mem::replace(&mut self.rngs, Streams::ChaCha8(Vec::new()));
            match &mut rngs {
                Streams::ChaCha8(r) => {
                    let rng = &mut r[b];
                    let mut fill = |buf: &mut [f64]| fill_normals(rng, buf);
                    self.run_sized(b, &mut fill, (nb, qb), todo, tw, out)
                }
                Streams::Xoshiro256PlusPlus(r) => {
                    let rng = &mut r[b];
                    let mut fill = |buf: &mut [f64]| fill_normals(rng, buf);
                    self.run_sized(b, &mut fill, (nb, qb), todo, tw, out)
                }
            }
            self.rngs = rngs;
        }
        self.position = range.end;
        let mut counts = ConditionalCounts {
            runs: todo,
            ..Default::default()
        };
        let mut scratch = vec![0.0; 2 * n + 4];
        for r in 0..todo {
            let xhat = &at_tc[r * n..(r + 1) * n];
            counts.kf_inside += self.cover.0.contains(xhat, &self.x_c, &mut scratch) as usize;
            counts.scf_inside += self.cover.1.contains(xhat, &self.x_c, &mut scratch) as usize;
            if let Some((_, phi, c, regs, d)) = &self.warning {
                let mut xp = c.clone();
                phi.mul_add(&at_tw[r * n..(r + 1) * n], &mut xp);
                counts.kf_warnings += warns(&regs[0], &regs[1], &xp, *d, &mut scratch) as usize;
                counts.scf_warnings += warns(&regs[2], &regs[3], &xp, *d, &mut scratch) as usize;
            }
        }
        counts
    }

    /// Put the streams where run `start` begins: back to the start if they are past it, then
    /// draw and drop the t_c·q_b normals per run of block b that the runs before it take.
    fn seek(&mut self, start: usize) {
        if start < self.position {
            self.rngs = block_streams(self.generator, self.seed, self.blocks.len());
            self.position = 0;
        }
        let skip = start - self.position;
        for (b, block) in self.blocks.iter().enumerate() {
            let count = skip * self.t_c * block.outputs.len();
            match &mut self.rngs {
                Streams::ChaCha8(r) => skip_normals(&mut r[b], count),
                Streams::Xoshiro256PlusPlus(r) => skip_normals(&mut r[b], count),
            }
        }
        self.position = start;
    }

    /// [`Self::run_block`] on the smallest padded size that holds block `b`'s (states, outputs).
    fn run_sized(
        &self,
        b: usize,
        normals: &mut Normals,
        (nb, qb): (usize, usize),
        todo: usize,
        tw: Option<usize>,
        out: (&mut [f64], &mut [f64]),
    ) {
        match (nb, qb) {
            (n, q) if n <= 2 && q <= 1 => self.run_block::<2, 1>(b, normals, todo, tw, out),
            (n, q) if n <= 4 && q <= 2 => self.run_block::<4, 2>(b, normals, todo, tw, out),
            (n, q) if n <= 8 && q <= 4 => self.run_block::<8, 4>(b, normals, todo, tw, out),
            _ => self.run_block::<16, 8>(b, normals, todo, tw, out),
        }
    }

    /// `todo` runs of block `b`: KF estimates at t_c (and at the warning time) are written into
    /// the block's components of `out.0` (and `out.1`), one row of n per run.
    fn run_block<const N: usize, const Q: usize>(
        &self,
        b: usize,
        normals: &mut Normals,
        todo: usize,
        tw: Option<usize>,
        out: (&mut [f64], &mut [f64]),
    ) {
        let (tc, n) = (self.t_c, self.n);
        let block = &self.blocks[b];
        let (si, oi) = (&block.states, &block.outputs);
        let sub = |m: &DMatrix<f64>, rows: &[usize], cols: &[usize]| {
            DMatrix::from_fn(rows.len(), cols.len(), |i, j| m[(rows[i], cols[j])])
        };
        let subv =
            |v: &DVector<f64>, rows: &[usize]| DVector::from_fn(rows.len(), |i, _| v[rows[i]]);
        let innov: Vec<FixedInnovation<N, Q>> = self
            .innov
            .iter()
            .map(|st| FixedInnovation {
                h: fixed(&sub(&st.h, oi, si)),
                hm: fixed_vec(&subv(&st.hm, oi)),
                l_s: fixed(&sub(&st.l_s, oi, oi)),
                g: fixed(&sub(&st.g, si, oi)),
                f_b: fixed(&sub(&st.f_b, si, si)),
            })
            .collect();
        let forward: Vec<FixedForward<N, Q>> = self
            .kf
            .iter()
            .map(|(k, h, f, bu)| FixedForward {
                k: fixed(&sub(k, si, oi)),
                h: fixed(&sub(h, oi, si)),
                f: fixed(&sub(f, si, si)),
                bu: fixed_vec(&subv(bu, si)),
            })
            .collect();
        let x_c_dev: [f64; N] = fixed_vec(&subv(&DVector::from_column_slice(&self.x_c_dev), si));
        let x1_mean: [f64; N] = fixed_vec(&subv(&self.x1_mean, si));
        let qb = oi.len();
        let mut y = vec![[[0.0; LANES]; Q]; tc];
        // A batch's normals in the order they are used: t = t_c … 1, output, lane.
        let mut draws = vec![0.0; tc * qb * LANES];
        for first in (0..todo).step_by(LANES) {
            let lanes = LANES.min(todo - first);
            normals(&mut draws[..tc * qb * lanes]);
            let mut next = draws.iter();
            // y_{t_c}, …, y_1 from their exact law given x_{t_c} = x_c: a Kalman filter run
            // backwards in time on the backward representation (45), in innovations form.
            let mut zhat = [[0.0; LANES]; N];
            for (zi, xi) in zhat.iter_mut().zip(&x_c_dev) {
                *zi = [*xi; LANES];
            }
            for t in (1..=tc).rev() {
                let st = &innov[t - 1];
                let mut z = [[0.0; LANES]; Q];
                for zi in z.iter_mut().take(qb) {
                    for zl in zi.iter_mut().take(lanes) {
                        *zl = *next.next().expect("t_c · q_b · lanes normals drawn");
                    }
                }
                let e = lanes_mat_vec(&st.l_s, &z);
                let hz = lanes_mat_vec(&st.h, &zhat);
                let g_e = lanes_mat_vec(&st.g, &e);
                for i in 0..Q {
                    for l in 0..LANES {
                        y[t - 1][i][l] = st.hm[i] + hz[i][l] + e[i][l];
                    }
                }
                for i in 0..N {
                    for l in 0..LANES {
                        zhat[i][l] += g_e[i][l];
                    }
                }
                zhat = lanes_mat_vec(&st.f_b, &zhat);
            }
            // The forward KF pass over the drawn measurements (35a).
            let mut xpred = [[0.0; LANES]; N];
            for (xi, mi) in xpred.iter_mut().zip(&x1_mean) {
                *xi = [*mi; LANES];
            }
            let mut xhat = xpred;
            for t in 1..=tc {
                let st = &forward[t - 1];
                let hx = lanes_mat_vec(&st.h, &xpred);
                let mut innov = [[0.0; LANES]; Q];
                for i in 0..Q {
                    for l in 0..LANES {
                        innov[i][l] = y[t - 1][i][l] - hx[i][l];
                    }
                }
                let k_i = lanes_mat_vec(&st.k, &innov);
                for i in 0..N {
                    for l in 0..LANES {
                        xhat[i][l] = xpred[i][l] + k_i[i][l];
                    }
                }
                if Some(t) == tw {
                    for (k, &i) in si.iter().enumerate() {
                        for l in 0..lanes {
                            out.1[(first + l) * n + i] = xhat[k][l];
                        }
                    }
                }
                let fx = lanes_mat_vec(&st.f, &xhat);
                for i in 0..N {
                    for l in 0..LANES {
                        xpred[i][l] = fx[i][l] + st.bu[i];
                    }
                }
            }
            for (k, &i) in si.iter().enumerate() {
                for l in 0..lanes {
                    out.0[(first + l) * n + i] = xhat[k][l];
                }
            }
        }
    }
}

impl crate::study::Runs for ConditionalExperiment {
    type Tally = ConditionalCounts;
    type Report = ExperimentResult;
    fn batch(&self) -> usize {
        LANES
    }
    fn total(&self) -> usize {
        self.result.runs_total
    }
    fn seed(&self) -> u64 {
        self.seed
    }
    fn zero(&self) -> ConditionalCounts {
        ConditionalCounts::default()
    }
    fn run(&mut self, range: std::ops::Range<usize>) -> Result<ConditionalCounts> {
        Ok(self.run_range(range))
    }
    fn report(&self, c: &ConditionalCounts) -> ExperimentResult {
        ExperimentResult {
            runs_done: c.runs,
            kf_inside: c.kf_inside,
            scf_inside: c.scf_inside,
            kf_warnings: c.kf_warnings,
            scf_warnings: c.scf_warnings,
            ..self.result.clone()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::{Condition, ExperimentSpec, Scenario, SimulateSpec};
    use crate::study::{Chunked, Study};

    /// The experiment run to the end in chunks of `chunk`.
    fn run_all(e: ConditionalExperiment, chunk: usize) -> ExperimentResult {
        let mut e = Chunked::new(e);
        while !e.finished() {
            e.step(chunk).unwrap();
        }
        e.report()
    }

    /// The backward-innovations sampler must reproduce the exact conditional law: on the scalar
    /// example, with x_t fixed at x̄, the KF and SCF inside-counts must match the closed-form
    /// conditional coverage of scf::conditional_coverage_1d within a 99.9 % binomial band.
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn experiment_counts_match_closed_form_conditional_coverage() {
        let runs = 4000;
        for (xbar, t) in [(1.0, 20usize), (9.0, 30), (-12.0, 25)] {
            let mut s: Scenario = crate::presets::scalar();
            s.simulate = Some(SimulateSpec {
                steps: t,
                seed: 3,
                u: vec![],
                condition: Some(Condition { t, x: vec![xbar] }),
                x0: None,
                true_noise: None,
            });
            s.experiment = Some(ExperimentSpec {
                runs,
                seed: 11,
                components: vec![0],
                warning_t: None,
                rng: Generator::ChaCha8,
            });
            let p = s.prepare_scf().unwrap();
            let r = run_all(p.conditional_experiment().unwrap(), 333);
            let off = Offline::new(&p.model, t, &p.inputs).unwrap();
            let (pt, gt) = (
                off.gains.steps[t - 1].p[(0, 0)],
                off.moments.cov[t - 1][(0, 0)],
            );
            let (kf, scf) = scf::conditional_coverage_1d(pt, gt, 0.0, xbar, s.alpha).unwrap();
            for (count, prob, name) in [(r.kf_inside, kf, "KF"), (r.scf_inside, scf, "SCF")] {
                let sd = (runs as f64 * prob * (1.0 - prob)).sqrt().max(0.5);
                let z = (count as f64 - runs as f64 * prob) / sd;
                assert!(z.abs() < 3.29, "{name} at x̄ = {xbar}: {count}/{runs} inside, closed form {prob:.4} (z = {z:.2})");
            }
        }
    }

    /// Chunking does not change the counts (whole batches, one stream per block).
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn chunking_does_not_change_counts() {
        let mut s = crate::presets::robots(crate::presets::NoiseReading::Unscaled);
        s.experiment.as_mut().unwrap().runs = 203;
        let p = s.prepare_scf().unwrap();
        let run = |chunk: usize| run_all(p.conditional_experiment().unwrap(), chunk);
        let (a, b) = (run(1), run(1000));
        assert_eq!(a, b);
        assert_eq!(a.runs_done, 203);
    }
}
