//! GLLS (seed 003) against independent computations, natively and in the browser:
//!
//! * Γ_{s+1}, Φ_{s+1} (6) against a noise-free trajectory simulated step by step.
//! * The GLLS estimate (11) in the crate's SVD form (21) against least squares on the whitened
//!   system solved here by QR; κ_GLLS ≥ κ_LLS = 1/σ_n (27) on random Ω; κ of the current state
//!   = 1/σ_n(Γ_{s+1}A^{−s}) (45).
//! * The regularized estimators equal the paper's projection plus noise term (30), (48).
//! * The singular-value curves (QR updates) against a full SVD of each Γ_{s+1}, also for an
//!   unstable system at s = 500, and σ(Γ A^{−s}) against its own SVD; the paper's remark that
//!   both coincide holds for an orthogonal A and fails otherwise.
//! * The state-noise estimator: closed form = clarabel's QP = the full KKT system solved here.
//! * The guarantee: under ‖δ(j)‖₂ ≤ μ the true state lies in the ball (35, with √(s+1)) and the
//!   interval box in every one of ≥ 10,000 runs — random noise in the ball, noise on the
//!   sphere, and the worst-case patterns that reach the box's faces.

use crate::common::patch::run_json;
use crate::common::*;
use confset::glls::{
    fast_forward, history_controllability, noise_map, observability, Curves, GllsModel, Horizon,
    StateNoise, Weighting,
};
use confset::model::{normal_vector, MatrixSpec, ModelSpec};
use confset::presets;
use confset::scenario::glls::GllsReport;
use confset::scenario::Scenario;
use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{json, Value};

fn spec(
    a: &DMatrix<f64>,
    b: Option<&DMatrix<f64>>,
    c: &DMatrix<f64>,
    w: &DMatrix<f64>,
    v: Option<&DMatrix<f64>>,
) -> ModelSpec {
    ModelSpec {
        f: Some(MatrixSpec::Constant(rows(a))),
        h: Some(MatrixSpec::Constant(rows(c))),
        b: b.map(|b| MatrixSpec::Constant(rows(b))),
        w: Some(MatrixSpec::Constant(rows(w))),
        v: v.map(|v| MatrixSpec::Constant(rows(v))),
        ..Default::default()
    }
}

fn random_matrix(r: usize, c: usize, rng: &mut ChaCha8Rng) -> DMatrix<f64> {
    DMatrix::from_fn(r, c, |_, _| rng.random::<f64>() * 2.0 - 1.0)
}

fn random_pd(n: usize, rng: &mut ChaCha8Rng) -> DMatrix<f64> {
    let l = random_matrix(n, n, rng);
    &l * l.transpose() + DMatrix::identity(n, n) * 0.1
}

/// A random model with spectral radius `rho`, m outputs, r inputs.
fn random_model(n: usize, m: usize, r: usize, rho: f64, rng: &mut ChaCha8Rng) -> GllsModel {
    let a = random_matrix(n, n, rng);
    let sr = a
        .complex_eigenvalues()
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max);
    let a = a * (rho / sr);
    let b = random_matrix(n, r, rng);
    let c = random_matrix(m, n, rng);
    let w = random_pd(m, rng);
    GllsModel::from_spec(&spec(&a, if r > 0 { Some(&b) } else { None }, &c, &w, None)).unwrap()
}

fn stack(v: &[DVector<f64>]) -> DVector<f64> {
    DVector::from_iterator(
        v.iter().map(|x| x.len()).sum(),
        v.iter().flat_map(|x| x.iter().copied()),
    )
}

fn preset_json(name: &str) -> Value {
    serde_json::to_value(presets::get(name).unwrap()).unwrap()
}

/// The GLLS part of a preset's report.
fn glls_report(name: &str) -> GllsReport {
    presets::get(name).unwrap().run().unwrap().glls.unwrap()
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn trajectory_form_matches_a_step_by_step_simulation() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for (n, m, r) in [(3, 1, 1), (4, 2, 2), (2, 1, 0)] {
        let model = random_model(n, m, r, 0.9, &mut rng);
        let s = 6;
        let x0 = normal_vector(n, &mut rng);
        let us: Vec<DVector<f64>> = (0..=s).map(|_| normal_vector(r, &mut rng)).collect();
        let (mut xs, mut ys) = (vec![x0.clone()], vec![]);
        for p in 0..=s {
            ys.push(&model.c * &xs[p]);
            let next = &model.a * &xs[p] + &model.b * &us[p];
            xs.push(next);
        }
        let gamma = observability(&model.a, &model.c, s);
        let phi = history_controllability(&model.a, &model.b, &model.c, s);
        assert_eq!((gamma.nrows(), gamma.ncols()), (m * (s + 1), n));
        assert_eq!((phi.nrows(), phi.ncols()), (m * (s + 1), r * (s + 1)));
        let y = stack(&ys);
        let u = stack(&us);
        assert_mat_close(
            &DMatrix::from_column_slice(y.len(), 1, y.as_slice()),
            &DMatrix::from_column_slice(y.len(), 1, (&gamma * &x0 + &phi * &u).as_slice()),
            1e-12,
            "(6)",
        );
        // (41)/(5): x(k) = A^s x(k−s) + Σ A^{s−1−i} B u(k−s+i).
        let (a_pow, fu) = fast_forward(&model.a, &model.b, s);
        let xk = &a_pow * &x0 + &fu * &u;
        assert!((xk - &xs[s]).norm() < 1e-12 * xs[s].norm().max(1.0));
        // The estimator recovers x(k−s) and x(k) exactly from noise-free data.
        let h = Horizon::new(&model, s, Weighting::Glls).unwrap();
        let (past, cur) = h.estimate(&y, &u);
        assert!((past - &x0).norm() < 1e-9 * x0.norm().max(1.0));
        assert!((cur - &xs[s]).norm() < 1e-9 * xs[s].norm().max(1.0));
    }
}
in_browser!(trajectory_form_matches_a_step_by_step_simulation);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn glls_is_weighted_least_squares_and_its_kappa_bounds_lls() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for case in 0..12 {
        let (n, m) = (2 + case % 3, 1 + case % 2);
        let model = random_model(n, m, 1, 0.5 + 0.1 * (case % 6) as f64, &mut rng);
        let s = 2 * n;
        let h = Horizon::new(&model, s, Weighting::Glls).unwrap();
        let y = DVector::from_fn(m * (s + 1), |_, _| rng.random::<f64>());
        let u = DVector::from_fn(s + 1, |_, _| rng.random::<f64>());
        // Least squares on L⁻¹Γ x = L⁻¹(y − Φu) with Ω = LLᵀ, by QR: independent of the SVD form.
        let l = model.omega.clone().cholesky().unwrap().l();
        let linv = l.clone().try_inverse().unwrap();
        let mut wblk = DMatrix::zeros(m * (s + 1), m * (s + 1));
        for p in 0..=s {
            wblk.view_mut((p * m, p * m), (m, m)).copy_from(&linv);
        }
        let gw = &wblk * &h.gamma;
        let rhs = &wblk * (&y - &h.phi * &u);
        let qr = gw.clone().qr();
        let x_ls = qr
            .r()
            .solve_upper_triangular(&(qr.q().transpose() * rhs))
            .unwrap();
        let (past, _) = h.estimate(&y, &u);
        assert!(
            (&past - &x_ls).norm() <= 1e-9 * x_ls.norm().max(1.0),
            "case {case}: {past} vs {x_ls}"
        );
        // κ_LLS = 1/σ_n(Γ) (19) ≤ κ_GLLS (27).
        let sv = h.gamma.clone().svd(false, false).singular_values;
        assert!(rel_close(h.kappa_lls_past, 1.0 / sv.min(), 1e-10));
        assert!(
            h.kappa_past >= h.kappa_lls_past * (1.0 - 1e-10),
            "case {case}: κ_GLLS {} < κ_LLS {}",
            h.kappa_past,
            h.kappa_lls_past
        );
        // Ω = c·I: GLLS is LLS.
        let lls = Horizon::new(&model, s, Weighting::Lls).unwrap();
        assert!(rel_close(lls.kappa_past, lls.kappa_lls_past, 1e-10));
        // (45): κ_LLS(s,k) = ‖A^s Γ⁺‖ = 1/σ_n(Γ A^{−s}).
        let ainv_s = h.a_pow.clone().try_inverse().unwrap();
        let svp = (&h.gamma * ainv_s).svd(false, false).singular_values;
        assert!(
            rel_close(lls.kappa_current, 1.0 / svp.min(), 1e-8),
            "case {case}: {} vs {}",
            lls.kappa_current,
            1.0 / svp.min()
        );
        assert!(rel_close(
            lls.kappa_lls_current.unwrap(),
            1.0 / svp.min(),
            1e-8
        ));
    }
}
in_browser!(glls_is_weighted_least_squares_and_its_kappa_bounds_lls);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn regularized_estimators_are_projection_plus_noise() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for case in 0..8 {
        let n = 3 + case % 2;
        let model = random_model(n, 1, 1, 0.95, &mut rng);
        let s = 2 * n + case;
        let h = Horizon::new(&model, s, Weighting::Glls).unwrap();
        for p in 1..=n {
            let reg = h.regularized(p).unwrap();
            let x0 = normal_vector(n, &mut rng);
            let u = DVector::from_fn(s + 1, |_, _| rng.random::<f64>());
            let delta = DVector::from_fn(s + 1, |_, _| rng.random::<f64>() * 0.1);
            let y = &h.gamma * &x0 + &h.phi * &u + &delta;
            // (30): x_reg(k−s) = Π_p x(k−s) + ∂f_reg δ with Π_p = R diag(1_p, 0) Rᵀ (31).
            let x_reg = &reg.gain_past * h.residual_data(&y, &u);
            let expect = &reg.projection_past * &x0 + &reg.gain_past * &delta;
            assert!(
                (&x_reg - &expect).norm() < 1e-9 * expect.norm().max(1.0),
                "case {case}, p {p}"
            );
            // Π_p is an orthogonal projection of rank p.
            assert_mat_close(
                &(&reg.projection_past * &reg.projection_past),
                &reg.projection_past,
                1e-10,
                "Π² = Π",
            );
            assert!((reg.projection_past.trace() - p as f64).abs() < 1e-9);
            // (32): κ_reg ≥ 1/σ_p, and p = n is the plain estimator.
            assert!(reg.kappa_past >= (1.0 - 1e-10) / h.sigma[p - 1]);
            if p == n {
                assert_mat_close(&reg.gain_past, &h.gain_past, 1e-9, "p = n");
            }
            // (47)–(48): x_reg(k) = Π'_p x(k) + noise term, with the inputs fast-forwarded.
            let (gain, proj, kappa) = reg.current.clone().unwrap();
            let xk = &h.a_pow * &x0 + &h.fu * &u;
            let cur = reg.estimate_current(&h, &y, &u).unwrap();
            let expect = &proj * &xk + &gain * &delta;
            // Through Γ A^{−s}: the accuracy is limited by cond(A^s).
            let sv = h.a_pow.clone().svd(false, false).singular_values;
            let cond = sv.max() / sv.min();
            let tol = (1e-9 + 1e-13 * cond) * expect.norm().max(1.0);
            assert!(
                (&cur - &expect).norm() < tol,
                "case {case}, p {p}: current {cur} vs {expect}, cond(A^s) {cond:.1e}"
            );
            assert!(kappa >= (1.0 - 1e-10) / h.sigma_prime.as_ref().unwrap()[p - 1]);
        }
    }
}
in_browser!(regularized_estimators_are_projection_plus_noise);

/// log10 σ_i of a full SVD of m, decreasing.
fn log10_svd(m: &DMatrix<f64>) -> Vec<f64> {
    let mut sv: Vec<f64> = m
        .clone()
        .svd(false, false)
        .singular_values
        .iter()
        .copied()
        .collect();
    sv.sort_by(|a, b| b.total_cmp(a));
    sv.iter().map(|v| v.log10()).collect()
}

/// Compare a curve row with a full SVD where both are resolved (above the floor by 10³). Both
/// carry an absolute error of about ε·σ₁ (the floor), so the tolerance on log10 σ_i grows as
/// σ_i approaches it.
fn assert_curve_row(curve: &[f64], full: &[f64], floor: f64, tol: f64, what: &str) -> usize {
    let mut compared = 0;
    for (i, (c, f)) in curve.iter().zip(full).enumerate() {
        if *f > floor + 3.0 && *c > floor + 3.0 {
            let allowed = tol + 10.0 * 10f64.powf(floor - f);
            assert!(
                (c - f).abs() < allowed,
                "{what}: σ_{} log10 {c} vs full SVD {f} (allowed {allowed:.1e})",
                i + 1
            );
            compared += 1;
        }
    }
    compared
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn singular_value_curves_match_full_svds() {
    let mut models: Vec<(String, GllsModel, usize)> =
        ["glls-saturate", "glls-grow", "glls-mixed", "glls-unstable5"]
            .iter()
            .map(|p| {
                (
                    p.to_string(),
                    GllsModel::from_spec(&presets::get(p).unwrap().model).unwrap(),
                    500,
                )
            })
            .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    models.push((
        "random n=10".into(),
        random_model(10, 2, 0, 1.02, &mut rng),
        200,
    ));
    for (name, model, s_max) in &models {
        let curves = Curves::new(model, *s_max).unwrap();
        assert_eq!(curves.log10_sigma.len(), s_max + 1);
        let mut compared = 0;
        for s in [0, 1, 2, 5, 17, 60, 200, 500]
            .into_iter()
            .filter(|s| s <= s_max)
        {
            let gamma = observability(&model.a, &model.c, s);
            assert!(
                gamma.iter().all(|v| v.is_finite()),
                "{name}: Γ_{} overflows",
                s + 1
            );
            let full = log10_svd(&gamma);
            compared += assert_curve_row(
                &curves.log10_sigma[s],
                &full,
                curves.log10_floor[s],
                1e-7,
                &format!("{name} s = {s}"),
            );
            // σ(Γ A^{−s}) where A^{−s} stays finite.
            if let (Some(sp), Some(ainv)) =
                (&curves.log10_sigma_prime, model.a.clone().try_inverse())
            {
                // Rows C A^{p−s} = C (A^{−1})^{s−p}, built from powers of A^{−1} (the product
                // Γ·A^{−s} would cancel catastrophically between growing and decaying modes).
                let mut gp = DMatrix::zeros(gamma.nrows(), model.n());
                let mut row = model.c.clone();
                let m = model.m();
                for q in 0..=s {
                    gp.view_mut(((s - q) * m, 0), (m, model.n()))
                        .copy_from(&row);
                    row = &row * &ainv;
                }
                if gp.iter().all(|v| v.is_finite()) && gp.amax() < 1e100 {
                    let fullp = log10_svd(&gp);
                    let floor = fullp[0] + (f64::EPSILON * 1e3).log10();
                    compared += assert_curve_row(
                        &sp[s],
                        &fullp,
                        floor,
                        1e-6,
                        &format!("{name} s = {s} (Γ A^-s)"),
                    );
                }
            }
        }
        assert!(
            compared >= 8,
            "{name}: only {compared} singular values compared"
        );
    }
    // The unstable 5-state system at s = 500: σ₁ ≈ 3.057^500 ≈ 10^242.
    let c = Curves::new(&models[3].1, 500).unwrap();
    assert!(
        c.log10_sigma[500][0] > 200.0 && c.log10_sigma[500][0] < 300.0,
        "{}",
        c.log10_sigma[500][0]
    );
}
in_browser!(singular_value_curves_match_full_svds);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn kappa_curves_match_the_horizon_estimators() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for case in 0..4 {
        let model = random_model(3, 2, 0, [0.8, 1.0, 1.1, 0.95][case], &mut rng);
        let curves = Curves::new(&model, 40).unwrap();
        for s in [2, 7, 20, 40] {
            let g = Horizon::new(&model, s, Weighting::Glls).unwrap();
            let l = Horizon::new(&model, s, Weighting::Lls).unwrap();
            let close10 = |a: f64, b: f64, what: &str| {
                assert!(
                    (a - b.log10()).abs() < 1e-7,
                    "case {case} s {s} {what}: {a} vs {}",
                    b.log10()
                )
            };
            close10(curves.log10_kappa_glls_past[s], g.kappa_past, "κ_GLLS past");
            close10(
                curves.log10_kappa_glls_current[s],
                g.kappa_current,
                "κ_GLLS current",
            );
            close10(
                curves.log10_kappa_lls_current[s],
                l.kappa_current,
                "κ_LLS current",
            );
        }
    }
}
in_browser!(kappa_curves_match_the_horizon_estimators);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_papers_remark_on_gamma_a_minus_s_holds_only_for_orthogonal_a() {
    // Orthogonal A (a rotation): Γ A^{−s} has rows C A^{p−s}, a reordering up to the orthogonal
    // factor, so the singular values coincide.
    let (c, s) = (0.3f64.cos(), 0.3f64.sin());
    let a = DMatrix::from_row_slice(2, 2, &[c, -s, s, c]);
    let rot = GllsModel::from_spec(&spec(
        &a,
        None,
        &DMatrix::from_row_slice(1, 2, &[1.0, 0.5]),
        &DMatrix::identity(1, 1),
        None,
    ))
    .unwrap();
    let curves = Curves::new(&rot, 100).unwrap();
    let sp = curves.log10_sigma_prime.as_ref().unwrap();
    for s in 1..=100 {
        for i in 0..2 {
            assert!(
                (curves.log10_sigma[s][i] - sp[s][i]).abs() < 1e-9,
                "rotation, s = {s}"
            );
        }
    }
    // The presets: far apart.
    for name in ["glls-saturate", "glls-grow", "glls-unstable5"] {
        let g = glls_report(name);
        assert!(
            g.prime_gap_log10.unwrap() > 1.0,
            "{name}: gap {:?}",
            g.prime_gap_log10
        );
    }
}
in_browser!(the_papers_remark_on_gamma_a_minus_s_holds_only_for_orthogonal_a);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn state_noise_estimator_closed_form_qp_and_kkt_agree() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    for case in 0..6 {
        let (n, m) = (3, 1 + case % 2);
        let mut model = random_model(n, m, 1, 1.1, &mut rng);
        model.xi = random_pd(n, &mut rng) * 0.1;
        for s in [2, 4, 7] {
            let sn = StateNoise::new(&model, s).unwrap();
            let y = DVector::from_fn(m * (s + 1), |_, _| rng.random::<f64>());
            let u = DVector::from_fn(s + 1, |_, _| rng.random::<f64>());
            let (xp, xi, _) = sn.estimate(&y, &u);
            let yt = &y - &sn.phi * &u;
            // The constraints (64) hold exactly.
            assert!(
                (&sn.gamma * &xp + &noise_map(&model.a, &model.c, s) * &xi - &yt).norm()
                    < 1e-8 * yt.norm().max(1.0)
            );
            // The full KKT system of min ½ ξᵀ(I⊗Ω⁻¹)ξ s.t. Γx + Ψξ = ỹ, solved here by LU.
            let rows = m * (s + 1);
            let dim = n + n * s;
            let oinv = model.xi.clone().try_inverse().unwrap();
            let mut kkt = DMatrix::zeros(dim + rows, dim + rows);
            for i in 0..s {
                kkt.view_mut((n + i * n, n + i * n), (n, n))
                    .copy_from(&oinv);
            }
            let mut a = DMatrix::zeros(rows, dim);
            a.view_mut((0, 0), (rows, n)).copy_from(&sn.gamma);
            a.view_mut((0, n), (rows, n * s)).copy_from(&sn.psi);
            kkt.view_mut((dim, 0), (rows, dim)).copy_from(&a);
            kkt.view_mut((0, dim), (dim, rows))
                .copy_from(&a.transpose());
            let mut rhs = DVector::zeros(dim + rows);
            rhs.rows_mut(dim, rows).copy_from(&yt);
            if let Some(sol) = kkt.lu().solve(&rhs) {
                if m * (s + 1) > n {
                    assert!(
                        (sol.rows(0, n) - &xp).norm() < 1e-6 * xp.norm().max(1.0),
                        "case {case} s {s}: KKT x"
                    );
                    assert!(
                        (sol.rows(n, n * s) - &xi).norm() < 1e-6 * xi.norm().max(1.0),
                        "case {case} s {s}: KKT ξ"
                    );
                }
            }
            // clarabel.
            let (qx, qxi) = sn.estimate_qp(&model, &y, &u).unwrap();
            assert!(
                (&qx - &xp).norm() < 1e-5 * xp.norm().max(1.0),
                "case {case} s {s}: QP x {qx} vs {xp}"
            );
            assert!(
                (&qxi - &xi).norm() < 1e-5 * xi.norm().max(1.0),
                "case {case} s {s}: QP ξ"
            );
        }
    }
    // The preset's report carries the same check.
    let g = glls_report("glls-unstable5");
    assert!(
        g.state_noise.as_ref().unwrap().qp_difference < 1e-4,
        "{:?}",
        g.state_noise.as_ref().map(|s| s.qp_difference)
    );
}
in_browser!(state_noise_estimator_closed_form_qp_and_kkt_agree);

/// The guaranteed sets, ≥ 10,000 runs: noise uniform in the ball, on the sphere, and the
/// worst-case patterns of every component (which reach the box faces).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn guaranteed_ball_and_box_never_miss() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut runs = 0;
    let mut reached_face = 0;
    for (name, s_list) in [
        ("glls-saturate", vec![2, 8, 20]),
        ("glls-grow", vec![1, 8, 25]),
        ("glls-mixed", vec![2, 12]),
    ] {
        let model = GllsModel::from_spec(&presets::get(name).unwrap().model).unwrap();
        let (n, m) = (model.n(), model.m());
        for s in s_list {
            for weighting in [Weighting::Lls, Weighting::Glls] {
                let h = Horizon::new(&model, s, weighting).unwrap();
                let mu = 0.1;
                let b = h.bounds(mu);
                // A true trajectory of the preset (noise-free), estimated from noisy windows.
                let (xs, ys) = GllsModel {
                    omega: DMatrix::zeros(m, m),
                    ..model.clone()
                }
                .simulate(s + 1, &[], &mut rng);
                let (x_past, x_cur) = (&xs[0], &xs[s]);
                let clean = stack(&ys);
                let u = DVector::zeros(0);
                let check = |delta: &DVector<f64>, what: &str| -> bool {
                    let (_, est) = h.estimate(&(&clean + delta), &u);
                    let e = &est - x_cur;
                    let tol =
                        1e-9 * x_cur.norm().max(1.0) + h.rounding_estimate(x_past, &clean) * 10.0;
                    assert!(
                        e.norm() <= b.radius_current + tol,
                        "{name} s {s} {what}: error {} > ball {}",
                        e.norm(),
                        b.radius_current
                    );
                    let mut face = false;
                    for i in 0..n {
                        assert!(
                            e[i].abs() <= b.half_widths_current[i] + tol,
                            "{name} s {s} {what}: |e_{i}| = {} > {}",
                            e[i].abs(),
                            b.half_widths_current[i]
                        );
                        face |= e[i].abs() >= b.half_widths_current[i] * (1.0 - 1e-9) - tol;
                    }
                    face
                };
                for _ in 0..800 {
                    // Uniform in the ball of radius μ per block, or on its sphere.
                    let on_sphere = rng.random::<f64>() < 0.5;
                    let delta = DVector::from_iterator(
                        m * (s + 1),
                        (0..=s).flat_map(|_| {
                            let d = normal_vector(m, &mut rng).normalize();
                            let r = if on_sphere {
                                mu
                            } else {
                                mu * rng.random::<f64>().powf(1.0 / m as f64)
                            };
                            (d * r).iter().copied().collect::<Vec<_>>()
                        }),
                    );
                    check(&delta, "random");
                    runs += 1;
                }
                // Worst cases: δ(j) = ±μ g_{i,j}/‖g_{i,j}‖ for each component i.
                for i in 0..n {
                    for sign in [1.0, -1.0] {
                        let delta = DVector::from_iterator(
                            m * (s + 1),
                            (0..=s).flat_map(|j| {
                                let g: DVector<f64> = h
                                    .gain_current
                                    .view((i, j * m), (1, m))
                                    .transpose()
                                    .column(0)
                                    .into_owned();
                                let d = if g.norm() > 0.0 {
                                    g.normalize() * (sign * mu)
                                } else {
                                    DVector::zeros(m)
                                };
                                d.iter().copied().collect::<Vec<_>>()
                            }),
                        );
                        if check(&delta, "worst case") {
                            reached_face += 1;
                        }
                        runs += 1;
                    }
                }
            }
        }
    }
    assert!(runs >= 10_000, "{runs} runs");
    assert!(
        reached_face >= 30,
        "the worst cases reach the box faces ({reached_face}): the box is the exact hull"
    );
}
in_browser!(guaranteed_ball_and_box_never_miss);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn monte_carlo_mean_error_is_below_the_expected_bound() {
    // (14)/(39): E‖x_est(k) − x(k)‖ ≤ κ·√E‖δ(k,s)‖², per horizon, for Gaussian noise.
    let p = Scenario::from_json(&{
        let mut s = preset_json("glls-saturate");
        s["glls"]["monte_carlo"] = json!({"runs": 1500, "seed": 2, "max_horizon": 20});
        s["glls"]["noise"] = json!("gaussian");
        s.to_string()
    })
    .unwrap()
    .run()
    .unwrap()
    .glls
    .unwrap()
    .precision
    .unwrap();
    assert_eq!(p.runs, 1500);
    assert!(p.horizons.len() >= 15);
    for (h, (sp, b)) in p.first.iter().zip(&p.bound).enumerate() {
        let sp = sp.as_ref().unwrap();
        assert!(sp.min <= sp.q1 && sp.q1 <= sp.median && sp.median <= sp.q3 && sp.q3 <= sp.max);
        assert!(
            sp.mean <= *b,
            "s = {}: mean error {} above the bound {b}",
            p.horizons[h],
            sp.mean
        );
    }
    // The error shrinks as the horizon grows past n (more data), then saturates.
    assert!(
        p.first[p.first.len() - 1].as_ref().unwrap().median
            < 0.5 * p.first[0].as_ref().unwrap().median
    );
}
in_browser!(monte_carlo_mean_error_is_below_the_expected_bound);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn state_noise_estimator_beats_lls_on_noisy_transitions() {
    // Section 5.2 / Fig. 4 on the preset (2,000 runs at horizons 4..15).
    let g = glls_report("glls-unstable5");
    let p = g.precision.unwrap();
    let second = p.second.as_ref().unwrap();
    let better = p
        .first
        .iter()
        .zip(second)
        .filter(|(a, b)| a.as_ref().unwrap().median < b.as_ref().unwrap().median)
        .count();
    assert!(
        better >= p.horizons.len() - 2,
        "state-noise better at {better} of {} horizons",
        p.horizons.len()
    );
    let (a, b) = (
        p.first.last().unwrap().as_ref().unwrap(),
        second.last().unwrap().as_ref().unwrap(),
    );
    assert!(
        a.median < 0.9 * b.median,
        "longest horizon: {} vs LLS {}",
        a.median,
        b.median
    );
    assert!(
        p.mean_state_norm > 1e5,
        "the states grow (unstable A): {}",
        p.mean_state_norm
    );
}
in_browser!(state_noise_estimator_beats_lls_on_noisy_transitions);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn presets_report_guarantees_and_best_horizons() {
    for name in ["glls-saturate", "glls-grow", "glls-mixed", "glls-unstable5"] {
        let g = glls_report(name);
        assert_eq!(
            g.curves.log10_sigma.len(),
            presets::get(name).unwrap().glls.unwrap().max_horizon + 1
        );
        assert!(g.error_current.unwrap().is_finite());
        if name != "glls-unstable5" {
            assert_eq!(g.truth_in_ball, Some(true), "{name}");
        }
    }
    // Fig. 2a: σ_n/√s peaks inside the range when σ_n saturates; Fig. 2b: it keeps growing.
    let sat = glls_report("glls-saturate");
    let best = sat.best_horizon.unwrap();
    assert!(best > 2 && best < 60, "saturating: best horizon {best}");
    let grow = glls_report("glls-grow");
    assert_eq!(
        grow.best_horizon,
        Some(60),
        "growing: the index is largest at the end"
    );
    // (36): the regularized current estimate is within √(s+1)·μ·κ_reg of the projected truth.
    let reg = sat.regularized.as_ref().unwrap();
    let (est, proj) = (
        reg.estimate_current.as_ref().unwrap(),
        reg.truth_projected_current.as_ref().unwrap(),
    );
    let dist = est
        .iter()
        .zip(proj)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(
        dist <= reg.radius_current.unwrap(),
        "regularized error {dist} > (36) radius {:?}",
        reg.radius_current
    );
    // The bounded-noise preset: the noise stayed within μ and the box holds the truth.
    assert!(sat.noise_max.unwrap() <= sat.mu && sat.truth_in_box == Some(true));
}
in_browser!(presets_report_guarantees_and_best_horizons);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn bad_input_names_the_field() {
    let base = preset_json("glls-saturate");
    let cases: Vec<(&str, Value)> = vec![
        ("model.F", json!({"model": {"F": [[1, 2, 3], [4, 5, 6]]}})),
        ("model.H", json!({"model": {"H": [[1, 0]]}})),
        ("model.W", json!({"model": {"W": [[-1]]}})),
        (
            "model.W",
            json!({"model": {"W": [[0]]}, "glls": {"estimator": "glls"}}),
        ),
        ("model.G", json!({"model": {"G": [[1], [0], [0]]}})),
        ("glls.estimator", json!({"glls": {"estimator": "kalman"}})),
        ("glls.p", json!({"glls": {"p": 0}})),
        ("glls.p", json!({"glls": {"p": 4}})),
        ("glls.horizon", json!({"glls": {"horizon": 0}})),
        ("glls.horizon", json!({"glls": {"horizon": 40}})),
        ("glls.mu", json!({"glls": {"mu": -1.0}})),
        ("glls.noise", json!({"glls": {"noise": "pink"}})),
        ("glls.plane", json!({"glls": {"plane": [0, 3]}})),
        ("glls.max_horizon", json!({"glls": {"max_horizon": 0}})),
        (
            "glls.monte_carlo.study",
            json!({"glls": {"monte_carlo": {"runs": 10, "study": "x"}}}),
        ),
        (
            "glls.monte_carlo.runs",
            json!({"glls": {"monte_carlo": {"runs": 0}}}),
        ),
        ("model.V", json!({"glls": {"estimator": "state_noise"}})),
        ("simulate.u", json!({"simulate": {"u": [[1.0]]}})),
        (
            "simulate.steps",
            json!({"model": {"F": [[1e3, 0, 0], [0, 1, 0], [0, 0, 1]]}, "simulate": {"steps": 200}}),
        ),
    ];
    crate::common::patch::assert_refused(&base, &cases);
}
in_browser!(bad_input_names_the_field);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn worst_case_noise_puts_the_truth_on_the_box_face_and_singular_a_is_explained() {
    // noise "worst" aligns δ with the plotted component's gain at the horizon in use (here the
    // best one, chosen by the report): that component's error equals the box half-width.
    let mut s = preset_json("glls-saturate");
    s["glls"]["noise"] = json!("worst");
    s["glls"]["monte_carlo"] = Value::Null;
    let g = run_json(&s).unwrap().glls.unwrap();
    let i = g.plane[0];
    let err = (g.x_true_current.as_ref().unwrap()[i]
        - (g.box_current.lo[i] + g.box_current.hi[i]) / 2.0)
        .abs();
    let half = (g.box_current.hi[i] - g.box_current.lo[i]) / 2.0;
    assert!(
        (err - half).abs() <= 1e-9 * half.max(1e-12) + 1e-12,
        "component {i}: error {err} vs half-width {half}"
    );
    assert_eq!(g.truth_in_box, Some(true));
    assert_eq!(g.truth_in_ball, Some(true));
    // A nilpotent A: no Γ A^{−s}; the report says why, κ(s,k) still comes from ‖A^s ∂f‖.
    let mut s = preset_json("glls-grow");
    s["model"]["F"] = json!([[0.0, 1.0], [0.0, 0.0]]);
    s["glls"]["monte_carlo"] = Value::Null;
    s["glls"]["horizon"] = json!(3);
    let g = run_json(&s).unwrap().glls.unwrap();
    assert!(g.sigma_prime.is_none() && g.curves.log10_sigma_prime.is_none());
    assert!(
        g.prime_note.as_deref().unwrap_or("").contains("singular"),
        "{:?}",
        g.prime_note
    );
    assert!(g.kappa_current.is_finite());
}
in_browser!(worst_case_noise_puts_the_truth_on_the_box_face_and_singular_a_is_explained);
