//! LSCR (seed 000) against the paper and against independent derivations, natively and in
//! the browser (`wasm-pack test`):
//!
//! * Section V-A's printed backward representation F^b, Q′; F^b, Q′ again from a Kronecker
//!   Lyapunov solve written here.
//! * The regressions (11), (20), (21) against the paper's stacking y = Φx_τ + B·v^b built here
//!   block by block (Q″ = B·diag(Q′)·Bᵀ), which the crate avoids (it runs a covariance recursion).
//! * Karhunen–Loève and SVD facts; the pairs of smoothing eigenvalues.
//! * Exactness: the affine coefficients against the definition g_{i,l}(x) = Σ_k h_{i,k}(s_k −
//!   a_k x)u_{a,l,k} evaluated here, the fast raster against brute force on random models and
//!   windows, the boundary's area against the raster's.
//! * Invariance: the region from an SVD computed here (arbitrary signs) and from flipped
//!   eigenvectors and singular vectors is the same region.
//! * Guarantees, statistically: for a fixed true state (typical and far out), the coverage of
//!   each X̂_l over 2,000 conditioned runs lies in the 99.9 % binomial interval around 1 − 2q/M,
//!   the joint coverage reaches that interval around 1 − 2qn/M, the BLUE ellipse holds its
//!   level, and the Kalman ellipse collapses far out.
//! * Bad input names its field; MA(1) is unbounded along [1, 1]ᵀ.

use crate::common::patch::run_json;
use crate::common::*;
use confset::lscr::{
    self, choose_m_q, Construction, Estimator, KarhunenLoeve, LscrModel, Options, Problem,
    Regression, Strings, Target,
};
use confset::model::{MatrixSpec, ModelSpec};
use confset::presets;
use confset::scenario::lscr::LscrStudy;
use confset::scenario::Scenario;
use confset::sets::{BoxSet, SignRegion};
use confset::study::{Chunked, Study};
use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{json, Value};

const RUNS: usize = 2000;
const CONF: f64 = 0.999;

fn cascade() -> LscrModel {
    LscrModel::from_spec(&presets::get("lscr-predict").unwrap().model).unwrap()
}

fn ma1() -> LscrModel {
    LscrModel::from_spec(&presets::get("lscr-ma1").unwrap().model).unwrap()
}

fn spec(f: &DMatrix<f64>, h: &[f64], g: &[f64], sv: f64, sw: f64) -> ModelSpec {
    ModelSpec {
        f: Some(MatrixSpec::Constant(rows(f))),
        h: Some(MatrixSpec::Constant(vec![h.to_vec()])),
        g: Some(g.iter().map(|&v| vec![v]).collect()),
        sigma_v2: Some(sv),
        sigma_w2: Some(sw),
        ..Default::default()
    }
}

/// A random stable n-state model with spectral radius ≤ 0.85, random H and G.
fn random_model(n: usize, rng: &mut ChaCha8Rng) -> LscrModel {
    loop {
        let f = DMatrix::from_fn(n, n, |_, _| rng.random::<f64>() * 2.0 - 1.0);
        let rho = f
            .complex_eigenvalues()
            .iter()
            .map(|z| z.norm())
            .fold(0.0, f64::max);
        let f = f * (rng.random::<f64>() * 0.8 + 0.05) / rho.max(1e-3);
        let h: Vec<f64> = (0..n).map(|_| rng.random::<f64>() * 2.0 - 1.0).collect();
        let g: Vec<f64> = (0..n).map(|_| rng.random::<f64>() * 2.0 - 1.0).collect();
        if let Ok(m) = LscrModel::from_spec(&spec(&f, &h, &g, 0.01, 0.02)) {
            return m;
        }
    }
}

fn opts(target: Target, m: usize, q: usize, construction: Construction, seed: u64) -> Options {
    Options {
        target,
        m,
        q,
        construction,
        seed,
        strings: None,
    }
}

/// Data y_1..y_t drawn given x_τ = truth.
fn draw_y(est: &Estimator, truth: &[f64], rng: &mut ChaCha8Rng) -> Vec<f64> {
    let sampler = est.sampler().unwrap();
    let tr = sampler.draw(&est.model.linear, &DVector::from_column_slice(truth), rng);
    tr.y[..est.problem.regression.t]
        .iter()
        .map(|v| v[0])
        .collect()
}

fn run(s: &Value) -> confset::scenario::Report {
    run_json(&s).unwrap()
}

fn preset_json(name: &str) -> Value {
    serde_json::to_value(presets::get(name).unwrap()).unwrap()
}

// ---------------------------------------------------------------------------------------------
// The paper's numbers and the regression forms.

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn cascade_backward_representation_is_the_printed_one() {
    let m = cascade();
    let b = m.backward().unwrap();
    // Section V-A, to the printed digits.
    assert_mat_close(
        &b.f_b,
        &mat(&[&[0.2450, 0.3315], &[-0.3500, 0.9550]]),
        5e-5,
        "F^b",
    );
    assert_mat_close(&b.v_b, &mat(&[&[0.49, -0.70], &[-0.70, 1.00]]), 5e-3, "Q′");
    // And from Π′ = FΠ′Fᵀ + GGᵀ solved here: F^b = Π′FᵀΠ′⁻¹, Q′ = Π′ − F^bΠ′F^bᵀ (crate docs).
    let f = mat(&[&[0.5, 0.0], &[1.0, 0.7]]);
    let pi = lyapunov_kron(&f, &mat(&[&[1.0, 0.0], &[0.0, 0.0]]));
    let fb = &pi * f.transpose() * pi.clone().try_inverse().unwrap();
    let qb = &pi - &fb * &pi * fb.transpose();
    assert_mat_close(&b.f_b, &fb, 1e-10, "F^b vs Kronecker Lyapunov");
    assert_mat_close(&b.v_b, &qb, 1e-10, "Q′ vs Kronecker Lyapunov");
    // The report carries them.
    let l = presets::get("lscr-predict")
        .unwrap()
        .run()
        .unwrap()
        .lscr
        .unwrap();
    assert_mat_close(&from_rows(&l.f_b), &fb, 1e-10, "report f_b");
    assert_mat_close(&from_rows(&l.q_prime), &qb, 1e-10, "report q_prime");
    assert_eq!((l.m, l.q, l.time, l.t), (80, 2, 31, 30));
    assert!(close(l.level, 0.9, 1e-12) && close(l.level_each, 0.95, 1e-12));
}
in_browser!(cascade_backward_representation_is_the_printed_one);

/// Powers M^0..M^k.
fn powers(m: &DMatrix<f64>, k: usize) -> Vec<DMatrix<f64>> {
    let mut v = vec![DMatrix::identity(m.nrows(), m.nrows())];
    for _ in 0..k {
        let next = v.last().unwrap() * m;
        v.push(next);
    }
    v
}

/// The stacking of the paper written out: Φ and Q″ = B·blockdiag(noise covariances)·Bᵀ for
/// rows [y_t, …, y_1].
fn stacked_reference(model: &LscrModel, t: usize, target: Target) -> (DMatrix<f64>, DMatrix<f64>) {
    let n = model.f.nrows();
    let b = model.backward().unwrap();
    let (fb, qb) = (&b.f_b, &b.v_b);
    let pb = powers(fb, t + 1);
    let pf = powers(&model.f, t + 1);
    let h = &model.h;
    let tau = target.time(t);
    // Noise sources: backward v^b_s (s = 1..τ−1, cov Q′; x_s = F^b x_{s+1} + v^b_s) and forward
    // G v_s (s = τ..t−1, cov GGᵀ) — independent of each other and of x_τ (Lemma 2.1).
    let sources: Vec<(usize, bool)> = (1..tau)
        .map(|s| (s, true))
        .chain((tau..t).map(|s| (s, false)))
        .collect();
    let mut phi = DMatrix::zeros(t, n);
    let mut big_b = DMatrix::zeros(t, sources.len() * n);
    for row in 0..t {
        let time = t - row; // paper order y_t, …, y_1
        if time <= tau {
            // x_time = F^b^{τ−time} x_τ + Σ_{s=time}^{τ−1} F^b^{s−time} v^b_s
            phi.row_mut(row).copy_from(&(h * &pb[tau - time]));
            for (j, &(s, back)) in sources.iter().enumerate() {
                if back && s >= time {
                    big_b
                        .view_mut((row, j * n), (1, n))
                        .copy_from(&(h * &pb[s - time]));
                }
            }
        } else {
            // x_time = F^{time−τ} x_τ + Σ_{s=τ}^{time−1} F^{time−1−s} G v_s
            phi.row_mut(row).copy_from(&(h * &pf[time - tau]));
            for (j, &(s, back)) in sources.iter().enumerate() {
                if !back && s < time {
                    big_b
                        .view_mut((row, j * n), (1, n))
                        .copy_from(&(h * &pf[time - 1 - s]));
                }
            }
        }
    }
    let mut cov = DMatrix::zeros(sources.len() * n, sources.len() * n);
    for (j, &(_, back)) in sources.iter().enumerate() {
        cov.view_mut((j * n, j * n), (n, n))
            .copy_from(if back { qb } else { &model.shape });
    }
    let q2 = &big_b * cov * big_b.transpose();
    (phi, q2)
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn regressions_are_the_papers_stacking() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let models = [
        cascade(),
        random_model(3, &mut rng),
        random_model(2, &mut rng),
    ];
    for (k, model) in models.iter().enumerate() {
        let t = 9;
        for target in [
            Target::Predict,
            Target::Filter,
            Target::Smooth(1),
            Target::Smooth(4),
            Target::Smooth(8),
        ] {
            let reg = Regression::new(model, t, target).unwrap();
            let (phi, q2) = stacked_reference(model, t, target);
            let what = format!("model {k}, {target:?}");
            assert_mat_close(&reg.phi, &phi, 1e-10, &format!("Φ of {what}"));
            assert_mat_close(&reg.q2, &q2, 1e-10, &format!("Q″ of {what}"));
        }
    }
}
in_browser!(regressions_are_the_papers_stacking);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn karhunen_loeve_whitens_and_the_svd_spans_a() {
    let m = cascade();
    for target in [Target::Predict, Target::Filter, Target::Smooth(15)] {
        let p = Problem::new(&m, 30, target).unwrap();
        let (u, d) = (&p.kl.u, &p.kl.d);
        let ua = &p.kl.u_a;
        // The whitening, the basis and the span, each as (computed, expected, tolerance).
        for (got, want, tol, what) in [
            (u.transpose() * u, DMatrix::identity(30, 30), 1e-12, "UᵀU"),
            (
                u.transpose() * &p.regression.q2 * u,
                DMatrix::from_diagonal(d),
                1e-9,
                "UᵀQ″U",
            ),
            (
                p.kl.a.clone(),
                u.transpose() * &p.regression.phi,
                1e-12,
                "A = UᵀΦ",
            ),
            (
                ua.transpose() * ua,
                DMatrix::identity(2, 2),
                1e-12,
                "U_AᵀU_A",
            ),
            (
                ua * ua.transpose() * &p.kl.a,
                p.kl.a.clone(),
                1e-12,
                "U_A spans A",
            ),
        ] {
            assert_mat_close(&got, &want, tol, what);
        }
        assert!(
            d.iter().zip(d.iter().skip(1)).all(|(a, b)| a >= b),
            "{target:?}: D decreasing"
        );
        let sv = p.kl.a.clone().svd(false, false).singular_values;
        let mut sv: Vec<f64> = sv.iter().copied().collect();
        sv.sort_by(|a, b| b.total_cmp(a));
        assert_slice_rel(&p.kl.singular, &sv, 1e-10, "singular values of A");
        assert_eq!(p.kl.rank, 2);
    }
}
in_browser!(karhunen_loeve_whitens_and_the_svd_spans_a);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn smoothing_eigenvalues_come_in_pairs() {
    // x_15 from y_1..y_30: the 15 data after τ (forward model) and the 14 before it (backward
    // model) have the same law, time reversed, so their covariance blocks share 14 eigenvalues;
    // y_15 itself carries no process noise (D = 0).
    let p = Problem::new(&cascade(), 30, Target::Smooth(15)).unwrap();
    let d: Vec<f64> = p.kl.d.iter().copied().collect();
    let pairs = d
        .windows(2)
        .filter(|w| (w[0] - w[1]).abs() <= 1e-9 * w[0].abs().max(1e-12))
        .count();
    assert!(pairs >= 14, "{pairs} equal neighbours in {d:?}");
    assert!(
        d[29].abs() < 1e-12,
        "the datum at τ has no process noise: {}",
        d[29]
    );
    // Prediction: no ties.
    let p = Problem::new(&cascade(), 30, Target::Predict).unwrap();
    let d: Vec<f64> = p.kl.d.iter().copied().collect();
    assert!(d.windows(2).all(|w| w[0] - w[1] > 1e-9 * w[0]), "{d:?}");
}
in_browser!(smoothing_eigenvalues_come_in_pairs);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn ma1_region_is_an_unbounded_band_along_one_one() {
    let b = ma1().backward().unwrap();
    // x_t = [v_{t−1}, v_{t−1} + v_{t−2}]: backward, x_{1,t} = x_{2,t+1} − x_{1,t+1} (singular F^b).
    assert_mat_close(
        &b.f_b,
        &mat(&[&[-1.0, 1.0], &[-1.0, 1.0]]),
        1e-9,
        "MA(1) F^b",
    );
    assert_mat_close(&b.v_b, &mat(&[&[0.0, 0.0], &[0.0, 1.0]]), 1e-9, "MA(1) Q′");
    let l = presets::get("lscr-ma1")
        .unwrap()
        .run()
        .unwrap()
        .lscr
        .unwrap();
    assert!(!l.bounded);
    assert_eq!(l.rank, 1);
    let s = std::f64::consts::FRAC_1_SQRT_2;
    assert_eq!(l.invariant_directions.len(), 1);
    let v = &l.invariant_directions[0];
    assert!(
        (v[0].abs() - s).abs() < 1e-9 && (v[0] - v[1]).abs() < 1e-9,
        "{v:?}"
    );
    assert!(
        l.recession
            .iter()
            .any(|r| close(r[0], s, 1e-9) && close(r[1], s, 1e-9)),
        "{:?}",
        l.recession
    );
    assert!(
        l.recession
            .iter()
            .any(|r| close(r[0], -s, 1e-9) && close(r[1], -s, 1e-9)),
        "{:?}",
        l.recession
    );
    assert!(
        l.recession.iter().all(|r| (r[0] - r[1]).abs() < 1e-9),
        "only ±[1,1]: {:?}",
        l.recession
    );
    // x ∈ X̂ ⇔ x + c[1, 1] ∈ X̂, at points near the band.
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (lo, hi) = (&l.window.lo, &l.window.hi);
    let mut inside = 0;
    for _ in 0..500 {
        let x = [
            lo[0] + rng.random::<f64>() * (hi[0] - lo[0]),
            lo[1] + rng.random::<f64>() * (hi[1] - lo[1]),
        ];
        let c = (rng.random::<f64>() - 0.5) * 200.0;
        // Membership changes only on lines parallel to [1,1]; skip points within rounding of one.
        let a = l.region.contains(&x);
        if a {
            inside += 1;
        }
        let shifted = [x[0] + c, x[1] + c];
        let gmin = l
            .region
            .groups
            .iter()
            .flat_map(|g| {
                g.c.iter()
                    .zip(&g.d)
                    .map(|(c0, d)| (c0 - d[0] * x[0] - d[1] * x[1]).abs())
            })
            .fold(f64::MAX, f64::min);
        if gmin > 1e-9 {
            assert_eq!(a, l.region.contains(&shifted), "x = {x:?}, c = {c}");
        }
    }
    assert!(
        inside > 20 && inside < 480,
        "{inside} of 500 window points inside: the band should be visible"
    );
    // No BLUE (A is rank deficient and σ_w² = 0), a Kalman ellipse centred at x_{1} = 0.
    assert!(l.blue.is_none() && l.blue_note.is_some());
    let kf = l.kf.as_ref().expect("KF ellipse");
    assert!(
        kf.center[0].abs() < 1e-12,
        "the KF predicts x_1 = v_t by 0: {:?}",
        kf.center
    );
}
in_browser!(ma1_region_is_an_unbounded_band_along_one_one);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn choice_of_m_and_q() {
    // 90 %, n = 2: the paper's M = 80, q = 2 (random); 2^7 = 128 strings, q = 3 (group).
    assert_eq!(choose_m_q(0.9, 2, Construction::Random).unwrap(), (80, 2));
    assert_eq!(choose_m_q(0.9, 2, Construction::Group).unwrap(), (128, 3));
    for (level, n) in [(0.5, 2), (0.9, 3), (0.95, 2), (0.99, 2), (0.8, 5)] {
        for c in [Construction::Random, Construction::Group] {
            let (m, q) = choose_m_q(level, n, c).unwrap();
            let achieved = 1.0 - 2.0 * (q * n) as f64 / m as f64;
            assert!(
                achieved >= level - 1e-12 && q >= 1 && q <= m / (2 * n),
                "{level} {n} {c:?}: M {m} q {q}"
            );
            assert!(m >= 40 * n, "{m} strings");
            if c == Construction::Group {
                assert!(m.is_power_of_two());
            }
        }
    }
    assert_eq!(
        choose_m_q(1.0, 2, Construction::Random).unwrap_err().field,
        "lscr.level"
    );
    assert_eq!(
        choose_m_q(0.0, 2, Construction::Random).unwrap_err().field,
        "lscr.level"
    );
}
in_browser!(choice_of_m_and_q);

// ---------------------------------------------------------------------------------------------
// Exactness of the region.

/// g_{i,l}(x) = Σ_k h_{i,k} (s_k − a_k·x) u_{a,k,l} (the correlations of point 4).
fn g_by_definition(
    p: &Problem,
    s: &DVector<f64>,
    strings: &Strings,
    x: &[f64],
    l: usize,
) -> Vec<f64> {
    let t = p.regression.t;
    let f: Vec<f64> = (0..t)
        .map(|k| {
            let ax: f64 = (0..x.len()).map(|j| p.kl.a[(k, j)] * x[j]).sum();
            (s[k] - ax) * p.kl.u_a[(k, l)]
        })
        .collect();
    (0..strings.h.nrows())
        .map(|i| (0..t).map(|k| strings.h[(i, k)] * f[k]).sum())
        .collect()
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn region_membership_is_the_definition() {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    for case in 0..6 {
        let n = 2 + case % 2;
        let model = random_model(n, &mut rng);
        let target = [Target::Predict, Target::Filter, Target::Smooth(6)][case % 3];
        let est = Estimator::new(
            &model,
            12,
            &opts(
                target,
                8 * n,
                1 + case % 3,
                Construction::Random,
                case as u64,
            ),
        )
        .unwrap();
        let truth: Vec<f64> = (0..n).map(|_| rng.random::<f64>() - 0.5).collect();
        let y = draw_y(&est, &truth, &mut rng);
        let s = est.problem.s(&y);
        let region = est.region(&y);
        let mut checked = 0;
        for _ in 0..400 {
            let x: Vec<f64> = (0..n)
                .map(|j| truth[j] + (rng.random::<f64>() - 0.5) * 6.0)
                .collect();
            let mut mask = 0u32;
            let mut near_zero = false;
            for l in 0..n {
                let g = g_by_definition(&est.problem, &s, &est.strings, &x, l);
                near_zero |= g.iter().any(|v| v.abs() < 1e-9);
                let (pos, neg) = (
                    g.iter().filter(|&&v| v > 0.0).count(),
                    g.iter().filter(|&&v| v < 0.0).count(),
                );
                if pos < est.q || neg < est.q {
                    mask |= 1 << l;
                }
            }
            if !near_zero {
                assert_eq!(region.excluded(&x), mask, "case {case} at {x:?}");
                checked += 1;
            }
        }
        assert!(checked > 350, "{checked}");
    }
}
in_browser!(region_membership_is_the_definition);

fn random_window(center: [f64; 2], scale: f64, rng: &mut ChaCha8Rng) -> BoxSet {
    let w = scale * (0.05 + 3.0 * rng.random::<f64>());
    let h = w * (0.3 + 1.5 * rng.random::<f64>());
    let cx = center[0] + (rng.random::<f64>() - 0.5) * scale;
    let cy = center[1] + (rng.random::<f64>() - 0.5) * scale;
    BoxSet {
        lo: vec![cx - w / 2.0, cy - h / 2.0],
        hi: vec![cx + w / 2.0, cy + h / 2.0],
    }
}

/// Regions of random models and data (n = 2, and 2-D slices of n = 3, 4).
fn random_plane_regions(count: usize, seed: u64) -> Vec<(SignRegion, [f64; 2], f64)> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count)
        .map(|k| {
            let n = [2, 2, 3, 4][k % 4];
            let model = random_model(n, &mut rng);
            let t = 10 + k % 25;
            let m = 2 * n * (3 + k % 20);
            let target = [Target::Predict, Target::Filter, Target::Smooth(t / 2)][k % 3];
            let est = Estimator::new(
                &model,
                t,
                &opts(target, m, 1 + k % 3, Construction::Random, k as u64),
            )
            .unwrap();
            let truth: Vec<f64> = (0..n).map(|_| rng.random::<f64>() - 0.5).collect();
            let y = draw_y(&est, &truth, &mut rng);
            let full = est.region(&y);
            let plane = if n == 2 {
                full
            } else {
                full.slice(&truth, [0, n - 1]).unwrap()
            };
            (plane, [truth[0], truth[n - 1]], 1.0 + k as f64 % 3.0)
        })
        .collect()
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn fast_raster_equals_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut nonempty = 0;
    for (k, (plane, centre, scale)) in random_plane_regions(24, 77).into_iter().enumerate() {
        for _ in 0..4 {
            let w = random_window(centre, scale, &mut rng);
            let (a, b) = (
                20 + rng.random_range(0..140usize),
                20 + rng.random_range(0..140usize),
            );
            let fast = plane.raster(&w, a, b).unwrap();
            let brute = plane.raster_brute(&w, a, b).unwrap();
            assert_eq!(fast, brute, "model {k}, window {w:?}, {a}×{b}");
            if fast.inside_count() > 0 && fast.inside_count() < a * b {
                nonempty += 1;
            }
        }
    }
    // Also the paper's presets at the page's size.
    for name in ["lscr-predict", "lscr-smooth", "lscr-ma1"] {
        let l = presets::get(name).unwrap().run().unwrap().lscr.unwrap();
        assert_eq!(
            l.region.raster(&l.window, 300, 200).unwrap(),
            l.region.raster_brute(&l.window, 300, 200).unwrap(),
            "{name}"
        );
    }
    assert!(
        nonempty >= 20,
        "only {nonempty} windows showed a region boundary"
    );
}
in_browser!(fast_raster_equals_brute_force);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn boundary_area_agrees_with_the_raster() {
    let mut regions: Vec<(SignRegion, BoxSet)> = ["lscr-predict", "lscr-smooth", "lscr-ma1"]
        .iter()
        .map(|name| {
            let l = presets::get(name).unwrap().run().unwrap().lscr.unwrap();
            (l.region, l.window)
        })
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    for (plane, centre, scale) in random_plane_regions(8, 99) {
        let w = random_window(centre, scale, &mut rng);
        regions.push((plane, w));
    }
    for (k, (plane, w)) in regions.iter().enumerate() {
        let exact = plane.area(w).unwrap();
        let (nx, ny) = (800, 800);
        let grid = plane.raster(w, nx, ny).unwrap();
        let (px, py) = grid.pixel();
        // The raster's error is at most the pixels the boundary crosses.
        let perimeter: f64 = plane
            .boundary(w)
            .unwrap()
            .iter()
            .map(|lp| {
                lp.points
                    .windows(2)
                    .map(|p| ((p[1][0] - p[0][0]) / px).abs() + ((p[1][1] - p[0][1]) / py).abs())
                    .sum::<f64>()
            })
            .sum();
        let tol = (perimeter + 4.0) * px * py;
        assert!(
            (exact - grid.area()).abs() <= tol,
            "region {k}: boundary area {exact}, raster {} (tolerance {tol})",
            grid.area()
        );
        assert!(exact >= 0.0 && exact <= (w.hi[0] - w.lo[0]) * (w.hi[1] - w.lo[1]) * (1.0 + 1e-12));
    }
}
in_browser!(boundary_area_agrees_with_the_raster);

// ---------------------------------------------------------------------------------------------
// Invariances.

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn sign_flips_of_eigenvectors_and_singular_vectors_leave_the_region() {
    let model = cascade();
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    for target in [Target::Predict, Target::Smooth(15)] {
        let est =
            Estimator::new(&model, 30, &opts(target, 80, 2, Construction::Random, 1)).unwrap();
        let y = draw_y(&est, &[0.05, -0.1], &mut rng);
        let base = est.region(&y);
        let window = BoxSet {
            lo: vec![-4.0, -3.0],
            hi: vec![4.0, 3.0],
        };
        let reference = base.raster(&window, 400, 300).unwrap();
        assert!(
            reference.inside_count() > 100,
            "{target:?}: region visible in the window"
        );

        // Singular vectors: U_A's columns negated one at a time flip every g_{i,l} of that
        // group — exactly, so the raster is bit-identical.
        for col in 0..2 {
            let mut kl: KarhunenLoeve = est.problem.kl.clone();
            kl.u_a.column_mut(col).neg_mut();
            let p = Problem {
                regression: est.problem.regression.clone(),
                kl,
            };
            let r = p.region(&p.s(&y), &est.strings, est.q);
            assert_eq!(
                r.raster(&window, 400, 300).unwrap(),
                reference,
                "{target:?}: u_a column {col} flipped"
            );
        }

        // Eigenvectors: negate every other column of U, then rebuild A and U_A with nalgebra's
        // own SVD (signs of its choosing). Same region up to rounding at cell edges.
        let mut kl: KarhunenLoeve = est.problem.kl.clone();
        for k in (0..30).step_by(2) {
            kl.u.column_mut(k).neg_mut();
        }
        kl.a = kl.u.transpose() * &est.problem.regression.phi;
        let svd = kl.a.clone().svd(true, false);
        let mut idx = vec![0, 1];
        idx.sort_by(|&i, &j| svd.singular_values[j].total_cmp(&svd.singular_values[i]));
        let u = svd.u.unwrap();
        kl.u_a =
            DMatrix::from_columns(&[u.column(idx[0]).into_owned(), u.column(idx[1]).into_owned()]);
        let p = Problem {
            regression: est.problem.regression.clone(),
            kl,
        };
        let r = p.region(&p.s(&y), &est.strings, est.q);
        let flipped = r.raster(&window, 400, 300).unwrap();
        let differ = flipped
            .excluded
            .iter()
            .zip(&reference.excluded)
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            differ <= 4,
            "{target:?}: {differ} of 120000 pixels differ after flipping eigenvectors"
        );
        assert!(
            (r.area(&window).unwrap() - base.area(&window).unwrap()).abs()
                < 1e-9 * base.area(&window).unwrap().max(1.0)
        );
    }
}
in_browser!(sign_flips_of_eigenvectors_and_singular_vectors_leave_the_region);

// ---------------------------------------------------------------------------------------------
// Guarantees (Theorem 3.2), statistically.

/// Coverage counts of a chunked experiment at `truth`.
fn experiment(est: Estimator, truth: &[f64], runs: usize, seed: u64) -> lscr::Coverage {
    let mut e = Chunked::new(LscrStudy(
        lscr::Experiment::new(est, truth, runs, seed).unwrap(),
    ));
    while !e.finished() {
        e.step(500).unwrap();
    }
    e.counts().clone()
}

fn assert_in(count: usize, band: (usize, usize), what: &str) {
    assert!(
        band.0 <= count && count <= band.1,
        "{what}: {count} outside the 99.9 % interval {band:?}"
    );
}

/// The counts of X̂_1 and X̂_2 (`label(1)`, `label(2)`) over RUNS runs are within the band of
/// their level.
fn assert_each_in(inside_each: &[usize], each_level: f64, label: impl Fn(usize) -> String) {
    let band_each = binomial_interval(RUNS, each_level, CONF);
    for l in 0..2 {
        assert_in(inside_each[l], band_each, &label(l + 1));
    }
}

/// Stationary standard deviations of the state (σ_v² = the model's).
fn stationary_sd(m: &LscrModel) -> Vec<f64> {
    let pi = lyapunov_kron(&m.f, &(&m.shape * m.sigma_v2));
    (0..m.f.nrows()).map(|i| pi[(i, i)].sqrt()).collect()
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn coverage_holds_at_a_typical_and_a_far_state() {
    let model = cascade();
    let sd = stationary_sd(&model);
    let typical = [0.5 * sd[0], -0.5 * sd[1]];
    let far = [6.0 * sd[0], -6.0 * sd[1]];
    for (target, construction, m, q) in [
        (Target::Predict, Construction::Random, 80, 2),
        (Target::Predict, Construction::Group, 128, 3),
        (Target::Smooth(15), Construction::Random, 80, 2),
        (Target::Filter, Construction::Group, 64, 2),
    ] {
        for (where_, truth) in [("typical", typical), ("far", far)] {
            let est = Estimator::new(&model, 30, &opts(target, m, q, construction, 3)).unwrap();
            let (each_level, level) = est.levels();
            let has_kf = est.kalman.is_some();
            let c = experiment(est, &truth, RUNS, 42);
            let what =
                format!("{target:?} {construction:?} M={m} q={q} at the {where_} state {truth:?}");
            assert_eq!(c.runs, RUNS);
            assert_each_in(&c.inside_each, each_level, |l| format!("X̂_{l} of {what}"));
            let band = binomial_interval(RUNS, level, CONF);
            assert!(
                c.inside >= band.0,
                "X̂ of {what}: {} below {band:?}",
                c.inside
            );
            // The BLUE ellipse at the joint level: x̂ − x_τ ~ N(0, Cov) whatever x_τ is.
            assert_in(c.blue.expect("BLUE"), band, &format!("BLUE of {what}"));
            match (has_kf, where_) {
                (true, "far") => {
                    let kf = c.kf.unwrap();
                    assert!(
                        kf < RUNS / 10,
                        "KF of {what}: {kf} of {RUNS} — it should collapse 6σ out"
                    );
                }
                (true, _) => assert!(
                    c.kf.unwrap() >= band.0,
                    "KF of {what} at a typical state: {:?}",
                    c.kf
                ),
                _ => assert!(c.kf.is_none()),
            }
        }
    }
}
in_browser!(coverage_holds_at_a_typical_and_a_far_state);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn coverage_through_the_full_region_construction() {
    // Independent of the experiment's shortcut (membership from g at x̄ only): the region of
    // each run built in full, group strings (fixed, so the theorem holds given them), far out.
    let model = cascade();
    let sd = stationary_sd(&model);
    let truth = [-5.0 * sd[0], 5.0 * sd[1]];
    let est = Estimator::new(
        &model,
        30,
        &opts(Target::Predict, 64, 2, Construction::Group, 9),
    )
    .unwrap();
    let (each_level, level) = est.levels();
    let sampler = est.sampler().unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let x = DVector::from_column_slice(&truth);
    let (mut each, mut joint, mut blue) = ([0usize; 2], 0usize, 0usize);
    for _ in 0..RUNS {
        let tr = sampler.draw(&est.model.linear, &x, &mut rng);
        assert_eq!(tr.x[30], x, "the conditioned state sits at τ = 31");
        let y: Vec<f64> = tr.y[..30].iter().map(|v| v[0]).collect();
        let mask = est.region(&y).excluded(&truth);
        for (l, c) in each.iter_mut().enumerate() {
            if mask & (1 << l) == 0 {
                *c += 1;
            }
        }
        joint += (mask == 0) as usize;
        blue += est.blue(&y).unwrap().contains(&truth) as usize;
    }
    let band_each = binomial_interval(RUNS, each_level, CONF);
    assert_in(each[0], band_each, "X̂_1");
    assert_in(each[1], band_each, "X̂_2");
    assert!(
        joint >= binomial_interval(RUNS, level, CONF).0,
        "X̂: {joint}"
    );
    assert_in(blue, binomial_interval(RUNS, level, CONF), "BLUE");
}
in_browser!(coverage_through_the_full_region_construction);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn ma1_coverage_holds_where_the_kalman_ellipse_fails() {
    let model = ma1();
    // x_{1,21} = v_20: σ_v = 0.316, so 3.0 is 9.5σ out.
    for (truth, kf_fails) in [([0.1, 0.3], false), ([3.0, 3.2], true)] {
        let est = Estimator::new(
            &model,
            20,
            &opts(Target::Predict, 80, 2, Construction::Random, 4),
        )
        .unwrap();
        let (each_level, level) = est.levels();
        let c = experiment(est, &truth, RUNS, 5);
        assert_each_in(&c.inside_each, each_level, |l| {
            format!("MA(1) X̂_{l} at {truth:?}")
        });
        assert!(c.inside >= binomial_interval(RUNS, level, CONF).0);
        assert!(c.blue.is_none(), "no BLUE for MA(1)");
        let kf = c.kf.unwrap();
        if kf_fails {
            assert_eq!(kf, 0, "KF at x_1 = 9.5σ");
        } else {
            assert!(
                kf >= binomial_interval(RUNS, level, CONF).0,
                "KF at a typical state: {kf}"
            );
        }
    }
}
in_browser!(ma1_coverage_holds_where_the_kalman_ellipse_fails);

#[cfg(not(target_arch = "wasm32"))]
#[test]
fn scenario_pipeline_coverage_at_a_placed_state() {
    // What the page does on a click: simulate.condition at τ and a full report per data set.
    let mut s = preset_json("lscr-predict");
    s["simulate"]["condition"] = json!({"t": 31, "x": [0.3, -0.4]});
    s["lscr"]["construction"] = json!("group");
    s["lscr"]["M"] = json!(64);
    s["lscr"]["q"] = json!(2);
    s["lscr"]["resolution"] = Value::Null;
    let runs = 400;
    let mut inside = [0usize; 2];
    for seed in 0..runs {
        s["simulate"]["seed"] = json!(seed);
        let l = run(&s).lscr.unwrap();
        assert_eq!(l.x_true.as_deref(), Some(&[0.3, -0.4][..]));
        let each = l.truth_inside_each.unwrap();
        assert_eq!(l.truth_inside, Some(each[0] && each[1]));
        assert_eq!(each[0] && each[1], l.region.contains(&[0.3, -0.4]));
        for k in 0..2 {
            inside[k] += each[k] as usize;
        }
    }
    let band = binomial_interval(runs as usize, 1.0 - 4.0 / 64.0, CONF);
    assert_in(inside[0], band, "X̂_1 via scenarios");
    assert_in(inside[1], band, "X̂_2 via scenarios");
}

// ---------------------------------------------------------------------------------------------
// Strings, scenarios, bad input.

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn string_constructions() {
    let r = Strings::random(80, 30, 1).unwrap();
    assert_eq!(r.m(), 80);
    let texts = r.texts();
    let set: std::collections::HashSet<&String> = texts.iter().collect();
    assert_eq!(set.len(), 79, "distinct");
    assert!(
        texts.iter().all(|s| s.len() == 30 && s.contains('1')),
        "non-zero strings of length t"
    );
    assert_ne!(
        Strings::random(80, 30, 2).unwrap().texts(),
        texts,
        "the seed matters"
    );
    assert_eq!(
        Strings::random(80, 30, 1).unwrap().texts(),
        texts,
        "and fixes them"
    );
    // Group: closed under symmetric difference.
    let g = Strings::group(64, 30, 3).unwrap();
    assert!(g.is_group && g.m() == 64);
    let bits: std::collections::HashSet<String> = g.texts().into_iter().collect();
    for a in g.texts() {
        for b in g.texts() {
            let x: String = a
                .chars()
                .zip(b.chars())
                .map(|(p, q)| if p == q { '0' } else { '1' })
                .collect();
            assert!(
                x.chars().all(|c| c == '0') || bits.contains(&x),
                "{a} ⊕ {b}"
            );
        }
    }
    // Random strings are almost never a group; M ≤ 2^t is enforced.
    assert!(!r.is_group);
    assert_eq!(Strings::random(9, 3, 1).unwrap_err().field, "lscr.M");
    assert_eq!(Strings::random(8, 3, 1).unwrap().m(), 8);
    // Explicit: a group (the span of two strings) is guaranteed, an arbitrary set is not.
    let model = cascade();
    let mut o = opts(Target::Predict, 4, 1, Construction::Explicit, 0);
    o.strings = Some(vec!["1100".into(), "0110".into(), "1010".into()]);
    let est = Estimator::new(&model, 4, &o).unwrap();
    assert!(est.guaranteed() && est.strings.is_group);
    o.strings = Some(vec!["1100".into(), "0110".into(), "1011".into()]);
    let est = Estimator::new(&model, 4, &o).unwrap();
    assert!(!est.guaranteed());
    let l = {
        let mut s = preset_json("lscr-predict");
        s["simulate"]["steps"] = json!(4);
        s["lscr"] = json!({"estimate": "predict", "strings": ["1100", "0110", "1011"], "q": 1});
        run(&s).lscr.unwrap()
    };
    assert!(!l.guaranteed && l.m == 4);
}
in_browser!(string_constructions);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn reports_are_deterministic_and_probes_agree_with_the_region() {
    let mut s = preset_json("lscr-predict");
    s["lscr"]["probes"] = json!([[0.0, 0.0], [0.5, 0.5], [10.0, -10.0]]);
    s["lscr"]["resolution"] = json!([64, 48]);
    let a = run(&s);
    let b = run(&s);
    assert_eq!(
        serde_json::to_string(&a).unwrap(),
        serde_json::to_string(&b).unwrap()
    );
    let l = a.lscr.unwrap();
    for p in &l.probes {
        assert_eq!(p.inside, l.region.contains(&p.x));
        let m = l.region.excluded(&p.x);
        assert_eq!(p.inside_each, vec![m & 1 == 0, m & 2 == 0]);
    }
    assert!(!l.probes[2].inside, "a point 100σ out is excluded");
    let grid = l.raster.as_ref().expect("raster");
    assert_eq!(grid.excluded.len(), 64 * 48);
    assert_eq!(grid, &l.region.raster(&l.window, 64, 48).unwrap());
    s["lscr"]["seed"] = json!(2);
    assert_ne!(
        run(&s).lscr.unwrap().strings,
        l.strings,
        "another seed, other strings"
    );
}
in_browser!(reports_are_deterministic_and_probes_agree_with_the_region);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn bad_input_names_the_field() {
    let base = preset_json("lscr-predict");
    let cases: Vec<(&str, Value)> = vec![
        ("lscr.q", json!({"lscr": {"q": 21}})),
        ("lscr.q", json!({"lscr": {"q": 0}})),
        ("lscr.M", json!({"lscr": {"M": 3}})),
        ("lscr.M", json!({"lscr": {"M": 200000}})),
        ("lscr.M", json!({"lscr": {"construction": "group"}})),
        ("lscr.M", json!({"simulate": {"steps": 6}})),
        (
            "lscr.index",
            json!({"lscr": {"estimate": "smooth", "index": 30}}),
        ),
        (
            "lscr.index",
            json!({"lscr": {"estimate": "smooth", "index": 0}}),
        ),
        ("lscr.index", json!({"lscr": {"estimate": "smooth"}})),
        ("lscr.index", json!({"lscr": {"index": 3}})),
        ("lscr.estimate", json!({"lscr": {"estimate": "guess"}})),
        (
            "lscr.level",
            json!({"lscr": {"M": null, "q": null, "level": 1.5}}),
        ),
        (
            "lscr.level",
            json!({"lscr": {"M": null, "q": null, "level": 0.0}}),
        ),
        ("lscr.level", json!({"lscr": {"level": 0.9}})),
        (
            "lscr.strings[1]",
            json!({"lscr": {"M": null, "strings": ["000000000000000000000000000001", "10"]}}),
        ),
        (
            "lscr.strings[1]",
            json!({"lscr": {"M": null, "strings": ["000000000000000000000000000001", "000000000000000000000000000001"]}}),
        ),
        (
            "lscr.strings[0]",
            json!({"lscr": {"M": null, "strings": ["00000000000000000000000000000x"]}}),
        ),
        (
            "lscr.window",
            json!({"lscr": {"window": {"lo": [1, 1], "hi": [0, 2]}}}),
        ),
        ("lscr.resolution", json!({"lscr": {"resolution": [0, 10]}})),
        ("simulate.steps", json!({"simulate": {"steps": 1}})),
        (
            "simulate.condition.t",
            json!({"simulate": {"condition": {"t": 0, "x": [0, 0]}}}),
        ),
        ("model.F", json!({"model": {"F": [[1.2, 0.0], [1.0, 0.7]]}})),
        // A scalar state runs (its region is intervals of the line); the plane's two
        // components are refused for it.
        (
            "plot",
            json!({"model": {"F": [[0.5]], "H": [[1]], "G": [[1]]}}),
        ),
        // A NaN becomes null in JSON: the parse error names the entry.
        (
            "model.F[0][1]",
            json!({"model": {"F": [[0.5, f64::NAN], [1.0, 0.7]]}}),
        ),
        ("model.H", json!({"model": {"H": [[0, 1], [1, 0]]}})),
        ("model.H", json!({"model": {"H": [[0, 1, 2]]}})),
        ("model.G", json!({"model": {"G": [[1], [0], [0]]}})),
        ("model.sigma_v2", json!({"model": {"sigma_v2": -1.0}})),
    ];
    crate::common::patch::assert_refused(&base, &cases);
    // The experiment needs a fixed state and a coverage block, at the estimated time.
    let refused_field = |sc: &Value| {
        Scenario::from_json(&sc.to_string())
            .unwrap()
            .lscr_experiment()
            .err()
            .unwrap()
            .field
    };
    let mut sc = base.clone();
    sc["lscr"]["coverage"] = json!({"runs": 10, "seed": 1});
    assert_eq!(refused_field(&sc), "simulate.condition");
    sc["simulate"]["condition"] = json!({"t": 30, "x": [0, 0]});
    assert_eq!(refused_field(&sc), "simulate.condition.t");
    sc["simulate"]["condition"] = json!({"t": 31, "x": [0, 0]});
    sc["lscr"]["coverage"] = json!({"runs": 0});
    assert_eq!(refused_field(&sc), "lscr.coverage.runs");
}
in_browser!(bad_input_names_the_field);

/// The LSCR presets have no coverage block: with one (at the estimated time), each coverage
/// study shards and merges to its unsharded result exactly (`shards::check_shards`).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_lscr_preset_coverage_study_shards() {
    let mut seen = 0;
    for p in presets::all()
        .into_iter()
        .filter(|p| p.scenario.method == confset::Method::Lscr)
    {
        let r = p
            .scenario
            .run()
            .unwrap_or_else(|e| panic!("{}: {e}", p.name));
        let mut v = serde_json::to_value(&p.scenario).expect("JSON");
        v["simulate"]["condition"] = json!({"t": r.time, "x": vec![0.1; r.n]});
        v["lscr"]["coverage"] = json!({"runs": 10, "seed": 4});
        let s: Scenario = serde_json::from_value(v).expect("a scenario");
        crate::shards::check_shards(&p.name, &s);
        seen += 1;
    }
    assert!(seen > 0, "no LSCR preset");
}
in_browser!(every_lscr_preset_coverage_study_shards);
