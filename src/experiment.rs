//! Conditional-coverage studies: what the SCF promises (Property 1) made visible in numbers.
//!
//! * [`coverage_curve`] — Fig. 1: P{x_t ∈ X_t | x_t = x̄} for KF and SCF as x̄ moves along one
//!   component; closed form for n = 1, exact-law Monte Carlo otherwise.
//! * [`ConditionalExperiment`] — the robot Monte Carlo of Section II-B: realizations drawn
//!   backwards from a fixed state x_c at t_c (footnote 2), both filters run on each, inclusion at
//!   t_c and τ-step collision warnings counted. Runs in chunks so a page can show progress and
//!   cancel. Gains, ratio matrices, backward matrices and noise square roots are computed once;
//!   the loop is sparse matrix-vector products and normal draws.

use crate::error::{Error, Result};
use crate::kalman::{self, Offline};
use crate::linalg::{self, sub_matrix, sub_vector};
use crate::model::{ConditionedSampler, Inputs, LinearModel};
use crate::scenario::{CoverageCurve, CurveSpec, Prepared};
use crate::scf::{self, ScfOptions};
use crate::sets::{chi2_quantile, Ellipsoid, PlanarEllipse};
use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

/// Draws per point of a Monte Carlo coverage curve.
pub const CURVE_DRAWS: usize = 2000;

/// Fig. 1 for component `c.component` at time `time` (filtering, full state conditioned).
pub fn coverage_curve(
    model: &LinearModel,
    u: &Inputs,
    opts: &ScfOptions,
    c: &CurveSpec,
    time: usize,
) -> Result<CoverageCurve> {
    let n = model.n();
    if c.component >= n {
        return Err(Error::field(
            "coverage_curve.component",
            format!("must be below n = {n}"),
        ));
    }
    if !(c.from.is_finite() && c.to.is_finite() && c.from < c.to) {
        return Err(Error::field(
            "coverage_curve.from",
            "must be finite and below coverage_curve.to",
        ));
    }
    if c.points < 2 || c.points > 2001 {
        return Err(Error::field(
            "coverage_curve.points",
            "must lie in 2..=2001",
        ));
    }
    let off = Offline::new(model, time, u)?;
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

/// Compressed-row sparse matrix: the robot model is block diagonal and mostly zeros, and the
/// Monte Carlo loop is all matrix-vector products.
#[derive(Debug, Clone)]
struct Csr {
    ptr: Vec<u32>,
    col: Vec<u32>,
    val: Vec<f64>,
}

impl Csr {
    fn new(m: &DMatrix<f64>) -> Self {
        let (mut ptr, mut col, mut val) = (vec![0u32], Vec::new(), Vec::new());
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                if m[(i, j)] != 0.0 {
                    col.push(j as u32);
                    val.push(m[(i, j)]);
                }
            }
            ptr.push(col.len() as u32);
        }
        Csr { ptr, col, val }
    }
    /// out += M x
    #[inline]
    fn mul_add(&self, x: &[f64], out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            let (a, b) = (self.ptr[i] as usize, self.ptr[i + 1] as usize);
            let mut s = 0.0;
            for k in a..b {
                s += self.val[k] * x[self.col[k] as usize];
            }
            *o += s;
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
            let ev = linalg::symmetrize(shape).symmetric_eigen().eigenvalues;
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
    /// Center for a KF estimate x̂ (full state).
    fn center(&self, xhat: &[f64], out: &mut [f64]) {
        let dev: Vec<f64> = self
            .idx
            .iter()
            .zip(&self.m)
            .map(|(&i, m)| xhat[i] - m)
            .collect();
        out.copy_from_slice(&self.m);
        self.a.mul_add(&dev, out);
    }
    fn contains(&self, xhat: &[f64], x: &[f64]) -> bool {
        let mut c = vec![0.0; self.idx.len()];
        self.center(xhat, &mut c);
        let e = DVector::from_fn(self.idx.len(), |k, _| x[self.idx[k]] - c[k]);
        e.dot(&(&self.s_inv * &e)) <= 1.0
    }
}

/// Distance-below-d test of two moving 2-D regions, with cheap exits before the exact distance.
fn warns(ra: &MovingRegion, rb: &MovingRegion, xhat: &[f64], d_min: f64) -> bool {
    let (mut ca, mut cb) = ([0.0; 2], [0.0; 2]);
    ra.center(xhat, &mut ca);
    rb.center(xhat, &mut cb);
    let dc = ((ca[0] - cb[0]).powi(2) + (ca[1] - cb[1]).powi(2)).sqrt();
    if dc - ra.axes.0 - rb.axes.0 >= d_min {
        return false; // even the circumscribed discs are d_min apart
    }
    if dc - ra.axes.1 - rb.axes.1 < d_min {
        return true; // the inscribed discs are closer than d_min
    }
    let (mut pa, mut pb) = (ra.planar.expect("2-D"), rb.planar.expect("2-D"));
    pa.c = ca;
    pb.c = cb;
    pa.distance(&pb) < d_min
}

/// Counts of a conditional Monte Carlo so far.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct ExperimentResult {
    pub runs_done: usize,
    pub runs_total: usize,
    pub alpha: f64,
    pub condition_t: usize,
    pub components: Vec<usize>,
    /// Runs with the true ζ_{t_c} inside X^KF / X^SCF.
    pub kf_inside: usize,
    pub scf_inside: usize,
    /// Collision warnings from the τ-step prediction at `warning_t` (if configured).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub warning_t: Option<usize>,
    pub kf_warnings: usize,
    pub scf_warnings: usize,
    /// 99.9 % Clopper–Pearson-like interval (normal approximation) for the SCF count at α.
    pub scf_expected_range: (usize, usize),
}

/// Chunked Monte Carlo over realizations conditioned on x_{t_c} = x_c.
pub struct ConditionalExperiment {
    rng: ChaCha8Rng,
    n: usize,
    q: usize,
    t_c: usize,
    x_c: Vec<f64>,
    mean: Vec<Vec<f64>>,
    back: Vec<(Csr, Csr)>,
    out: Vec<(Csr, Csr)>,
    kf: Vec<(Csr, Csr, Csr, Vec<f64>)>, // K_t, H_t, F_t, B_t u_t
    x1_mean: Vec<f64>,
    cover: (MovingRegion, MovingRegion),
    warning: Option<(usize, Csr, Vec<f64>, [MovingRegion; 4], f64)>, // t, Φ, c, [kf_a, kf_b, scf_a, scf_b], d_min
    result: ExperimentResult,
}

impl ConditionalExperiment {
    /// Prepare from a validated scenario with `simulate.condition` and `experiment`.
    pub fn new(p: &Prepared) -> Result<Self> {
        let s = &p.scenario;
        let e = s
            .experiment
            .as_ref()
            .ok_or_else(|| Error::field("experiment", "is missing"))?;
        let cond = s
            .simulate
            .as_ref()
            .and_then(|s| s.condition.as_ref())
            .ok_or_else(|| {
                Error::field(
                    "simulate.condition",
                    "is needed: the experiment draws realizations conditioned on a state",
                )
            })?;
        if e.runs == 0 || e.runs > 10_000_000 {
            return Err(Error::field("experiment.runs", "must lie in 1..=10000000"));
        }
        let model = &p.model;
        let (n, q, t_c) = (model.n(), model.q(), cond.t);
        let steps = t_c;
        let sampler = ConditionedSampler::new(model, steps, &p.inputs, t_c).map_err(|e| {
            if e.field == "condition.t" {
                Error::field("simulate.condition.t", e.message)
            } else {
                e
            }
        })?;
        let off = Offline::new(model, steps + s.tau, &p.inputs)?;
        let r2c = chi2_quantile(s.alpha, e.components.len())?;
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
        let warning = match (e.warning_t, &s.collision) {
            (None, _) => None,
            (Some(_), None) => {
                return Err(Error::field(
                    "experiment.warning_t",
                    "needs a collision block",
                ))
            }
            (Some(tw), Some(c)) => {
                kalman::check_time("experiment.warning_t", tw, t_c)?;
                let tau = s.tau;
                // x̂_{tw+τ|tw} = Φ x̂_tw + c: an affine map, composed once.
                let (mut phi, mut cst) = (DMatrix::identity(n, n), DVector::zeros(n));
                for k in tw..tw + tau {
                    phi = model.f(k) * phi;
                    cst = model.f(k) * cst + model.input_term(k, &p.inputs);
                }
                let (_, pp) = kalman::predict(
                    model,
                    tw,
                    tau,
                    &DVector::zeros(n),
                    &off.gains.steps[tw - 1].p,
                    &p.inputs,
                );
                let tt = tw + tau;
                let r2 = chi2_quantile(s.alpha, 2)?;
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
        let vec = |v: &DVector<f64>| v.iter().copied().collect::<Vec<f64>>();
        let lo_hi = {
            let (nn, a) = (e.runs as f64, s.alpha);
            let sd = (nn * a * (1.0 - a)).sqrt();
            (
                ((nn * a - 3.29 * sd).floor().max(0.0)) as usize,
                ((nn * a + 3.29 * sd).ceil().min(nn)) as usize,
            )
        };
        Ok(ConditionalExperiment {
            rng: ChaCha8Rng::seed_from_u64(e.seed),
            n,
            q,
            t_c,
            x_c: linalg::vector("simulate.condition.x", &cond.x, n)?
                .iter()
                .copied()
                .collect(),
            mean: sampler.moments.mean.iter().map(vec).collect(),
            back: sampler
                .backward
                .iter()
                .map(|(f, l)| (Csr::new(f), Csr::new(l)))
                .collect(),
            out: sampler
                .output
                .iter()
                .map(|(h, l)| (Csr::new(h), Csr::new(l)))
                .collect(),
            kf: (1..=steps)
                .map(|t| {
                    (
                        Csr::new(&off.gains.steps[t - 1].k),
                        Csr::new(model.h(t)),
                        Csr::new(model.f(t)),
                        vec(&model.input_term(t, &p.inputs)),
                    )
                })
                .collect(),
            x1_mean: vec(&model.x1_mean),
            cover,
            warning,
            result: ExperimentResult {
                runs_total: e.runs,
                alpha: s.alpha,
                condition_t: t_c,
                components: e.components.clone(),
                warning_t: e.warning_t,
                scf_expected_range: lo_hi,
                ..Default::default()
            },
        })
    }

    /// Run up to `chunk` more realizations; returns the counts so far.
    pub fn step(&mut self, chunk: usize) -> &ExperimentResult {
        let (n, q, tc) = (self.n, self.q, self.t_c);
        let todo = chunk.min(self.result.runs_total - self.result.runs_done);
        let mut x = vec![0.0; n * tc];
        let mut z = vec![0.0; n.max(q)];
        let mut dev = vec![0.0; n];
        let mut y = vec![0.0; q];
        let mut xhat = vec![0.0; n];
        let mut xpred = vec![0.0; n];
        let mut innov = vec![0.0; q];
        for _ in 0..todo {
            // Backward draw from x_{t_c} = x_c (SCF (45), footnote 2).
            x[(tc - 1) * n..tc * n].copy_from_slice(&self.x_c);
            for t in (2..=tc).rev() {
                let (f_b, l) = &self.back[t - 2];
                for i in 0..n {
                    dev[i] = x[(t - 1) * n + i] - self.mean[t - 1][i];
                    z[i] = self.rng.sample(StandardNormal);
                }
                let cur = &mut x[(t - 2) * n..(t - 1) * n];
                cur.copy_from_slice(&self.mean[t - 2]);
                f_b.mul_add(&dev, cur);
                l.mul_add(&z[..n], cur);
            }
            // Measurements and the forward KF pass.
            xpred.copy_from_slice(&self.x1_mean);
            let mut warned = (false, false);
            for t in 1..=tc {
                let (h, lw) = &self.out[t - 1];
                let (k, hk, f, bu) = &self.kf[t - 1];
                y.iter_mut().for_each(|v| *v = 0.0);
                for zi in z.iter_mut().take(q) {
                    *zi = self.rng.sample(StandardNormal);
                }
                h.mul_add(&x[(t - 1) * n..t * n], &mut y);
                lw.mul_add(&z[..q], &mut y);
                innov.copy_from_slice(&y);
                for v in innov.iter_mut() {
                    *v = -*v;
                }
                hk.mul_add(&xpred, &mut innov); // −(y − H x̂⁻)
                for v in innov.iter_mut() {
                    *v = -*v;
                }
                xhat.copy_from_slice(&xpred);
                k.mul_add(&innov, &mut xhat);
                if let Some((tw, phi, c, regs, d)) = &self.warning {
                    if *tw == t {
                        let mut xp = c.clone();
                        phi.mul_add(&xhat, &mut xp);
                        warned = (
                            warns(&regs[0], &regs[1], &xp, *d),
                            warns(&regs[2], &regs[3], &xp, *d),
                        );
                    }
                }
                xpred.copy_from_slice(bu);
                f.mul_add(&xhat, &mut xpred);
            }
            let xt = &x[(tc - 1) * n..tc * n];
            self.result.kf_inside += self.cover.0.contains(&xhat, xt) as usize;
            self.result.scf_inside += self.cover.1.contains(&xhat, xt) as usize;
            self.result.kf_warnings += warned.0 as usize;
            self.result.scf_warnings += warned.1 as usize;
            self.result.runs_done += 1;
        }
        &self.result
    }

    /// Counts so far.
    pub fn result(&self) -> &ExperimentResult {
        &self.result
    }

    /// True when every run is done.
    pub fn finished(&self) -> bool {
        self.result.runs_done >= self.result.runs_total
    }
}
