//! The SCF paper's numbers and identities (Carè, Campi, Weyer, *State Conditional Filtering*):
//! Example 1 (scalar, Section I and footnote 1), the backward representation (29)–(30) of a
//! 3-state system, and the ratio matrix — recursion (38) against the closed form (41) and against
//! U_tA_t built by brute force from the batch form (31)–(32).
//!
//! Every expected value is either printed in the paper, derived by hand below, or computed here
//! by an independent route (Kronecker-solved Lyapunov equation, textbook Kalman filter, batch
//! matrices, Monte Carlo of the definitions).

use crate::common::*;
use confset::kalman::{self, KalmanGains, Offline};
use confset::model::{ConditionedSampler, Inputs, LinearModel};
use confset::presets::{self, NoiseReading};
use confset::scenario::{DataSpec, Scenario, SimulateSpec};
use confset::scf;
use nalgebra::{DMatrix, DVector};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// χ²(0.99, 1) = z²_{0.995}, z_{0.995} = 2.5758293035489004 (normal tables).
const CHI2_99_1: f64 = 6.634_896_601_021_214;

fn scalar_model() -> LinearModel {
    let one = DMatrix::from_element(1, 1, 1.0);
    LinearModel::time_invariant(
        DMatrix::from_element(1, 1, (5.0f64 / 6.0).sqrt()),
        one.clone(),
        one.clone(),
        one,
    )
    .unwrap()
}

/// Example 1 by hand. Γ = F²Γ + V ⇒ Γ = 1/(1 − 5/6) = 6. Backward: F^b = ΓFΓ⁻¹ = F = √(5/6),
/// V^b = Γ − F^bΓF^b = 6 − (5/6)·6 = 1. Riccati fixed point: P⁻ = (5/6)P + 1, P = P⁻/(P⁻ + 1)
/// ⇒ P̄ = 3/5, P̄⁻ = 3/2, K̄ = 3/5. Ratio 1 − P̄/Γ = 0.9; Π̄ = P̄/0.9 = 2/3.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn scalar_example_gamma_backward_steady_state() {
    let m = scalar_model();
    let g = m.stationary_covariance().unwrap();
    assert!(close(g[(0, 0)], 6.0, 1e-12), "Γ = {g}");
    assert!(m.stationary_prior && close(m.x1_cov[(0, 0)], 6.0, 1e-12));

    let b = m.backward_representation().unwrap();
    assert!(
        close(b.f_b[(0, 0)], (5.0f64 / 6.0).sqrt(), 1e-12),
        "F^b = {}",
        b.f_b
    );
    assert!(close(b.v_b[(0, 0)], 1.0, 1e-12), "V^b = {}", b.v_b);

    let ss = kalman::steady_state(&m).unwrap();
    assert!(close(ss.p[(0, 0)], 0.6, 1e-12), "P̄ = {}", ss.p);
    assert!(close(ss.p_pred[(0, 0)], 1.5, 1e-12), "P̄⁻ = {}", ss.p_pred);
    assert!(close(ss.k[(0, 0)], 0.6, 1e-12), "K̄ = {}", ss.k);

    let a = scf::asymptotic(&m).unwrap();
    assert!(close(a.gamma[0][0], 6.0, 1e-12));
    assert!(close(a.p[0][0], 0.6, 1e-12));
    assert!(close(a.ratio[0][0], 0.9, 1e-12), "R̄ = {:?}", a.ratio);
    assert!(close(a.pi[0][0], 2.0 / 3.0, 1e-12), "Π̄ = {:?}", a.pi);
    assert!(close(a.f_b[0][0], (5.0f64 / 6.0).sqrt(), 1e-12));
    assert!(close(a.v_b[0][0], 1.0, 1e-12));
}
in_browser!(scalar_example_gamma_backward_steady_state);

/// ρ of Example 1 (with the integrand exp(−x²/(2p̄)), crate docs: errata): ρ = √(χ²(0.99,1)·3/5)
/// ≈ 1.995, "≈ 2" in the paper. The KF interval at the end of a long run is x̂ ± ρ, the SCF
/// interval x̂/0.9 ± ρ·√(1/0.9) — both for the recursive filter (last step of 200) and for the
/// asymptotic filter (every step).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn scalar_example_intervals_long_run_and_asymptotic() {
    let rho = (CHI2_99_1 * 0.6).sqrt();
    assert!((rho - 2.0).abs() < 0.01, "ρ = {rho}");
    for asymptotic in [false, true] {
        let mut s = presets::scalar();
        s.simulate = Some(SimulateSpec {
            steps: 200,
            seed: 5,
            u: vec![],
            condition: None,
            x0: None,
            true_noise: None,
        });
        s.scf = Some(confset::scenario::ScfSpec {
            asymptotic,
            ..Default::default()
        });
        assert_eq!(s.alpha, 0.99);
        let r = s.run().unwrap();
        assert_eq!(r.steps.len(), 200);
        let checked: Vec<usize> = if asymptotic {
            vec![0, 1, 99, 199]
        } else {
            vec![199]
        };
        for i in checked {
            let st = &r.steps[i];
            let what = format!("asymptotic={asymptotic}, t={}", st.t);
            assert!(close(st.kf.radius2, CHI2_99_1, 1e-10), "{what}: radius2");
            assert!(close(st.kf.cov[0][0], 0.6, 1e-10), "{what}: P_t");
            assert!(close(st.ratio[0][0], 0.9, 1e-10), "{what}: ratio");
            let kf_half = (st.kf.radius2 * st.kf.cov[0][0]).sqrt();
            assert!(
                close(kf_half, rho, 1e-10),
                "{what}: KF half-width {kf_half}"
            );
            let scf = st.scf.as_ref().expect("SCF region");
            assert!(
                close(scf.center[0], st.kf.center[0] / 0.9, 1e-10),
                "{what}: SCF center {} vs KF center/0.9 = {}",
                scf.center[0],
                st.kf.center[0] / 0.9
            );
            let scf_half = (scf.radius2 * scf.cov[0][0]).sqrt();
            assert!(
                close(scf_half, rho * (1.0f64 / 0.9).sqrt(), 1e-10),
                "{what}: SCF half-width {scf_half}"
            );
            // The KF center is the data's: check it against a hand-written scalar filter.
        }
        if !asymptotic {
            // Hand-written scalar KF over the report's measurements.
            let (f2, mut xp, mut pp) = (5.0f64 / 6.0, 0.0, 6.0);
            for (i, y) in r.y.iter().enumerate() {
                let k = pp / (pp + 1.0);
                let x = xp + k * (y[0] - xp);
                let p = pp * (1.0 - k);
                let st = &r.steps[i];
                assert!(close(st.kf.center[0], x, 1e-10), "t={}: KF center", i + 1);
                assert!(close(st.kf.cov[0][0], p, 1e-10), "t={}: P_t", i + 1);
                assert!(
                    close(st.ratio[0][0], 1.0 - p / 6.0, 1e-10),
                    "t={}: ratio",
                    i + 1
                );
                xp = f2.sqrt() * x;
                pp = f2 * p + 1.0;
            }
        }
    }
}
in_browser!(scalar_example_intervals_long_run_and_asymptotic);

/// Footnote 1: given x_t = x̄, the KF estimate has mean c·x̄ with c = 1 − p_t/E[x_t²] → 0.9 and
/// variance p_t(1 − p_t/E[x_t²]) → 0.54. Checked two independent ways:
/// (a) by brute force: the KF is linear, x̂_t = Σ_k u_k y_k (weights from unit impulses through a
///     hand-written scalar filter), and with E[y_k y_j] = F^{|k−j|}Γ + δ_kj, E[y_k x_t] = F^{t−k}Γ
///     the regression coefficient c = Cov(x̂, x)/Γ and the residual variance Var(x̂) − Cov²/Γ;
/// (b) by simulating realizations conditioned on x_t = x̄ (backward representation,
///     footnote 2) and filtering them with the crate's Kalman filter.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn scalar_footnote1_conditional_mean_and_variance() {
    let t = 40usize;
    let f = (5.0f64 / 6.0).sqrt();
    let gamma = 6.0;
    // (a) weights u_k by impulses.
    let filter = |y: &[f64]| {
        let (mut xp, mut pp, mut x) = (0.0, gamma, 0.0);
        for &yk in y {
            let k = pp / (pp + 1.0);
            x = xp + k * (yk - xp);
            pp = f * f * pp * (1.0 - k) + 1.0;
            xp = f * x;
        }
        x
    };
    let u: Vec<f64> = (0..t)
        .map(|k| {
            let mut y = vec![0.0; t];
            y[k] = 1.0;
            filter(&y)
        })
        .collect();
    let mut var = 0.0;
    let mut cov = 0.0;
    for k in 0..t {
        cov += u[k] * f.powi((t - 1 - k) as i32) * gamma;
        for j in 0..t {
            let e = f.powi((k as i32 - j as i32).abs()) * gamma + if k == j { 1.0 } else { 0.0 };
            var += u[k] * u[j] * e;
        }
    }
    let c = cov / gamma;
    let cond_var = var - cov * cov / gamma;
    assert!(close(c, 0.9, 1e-10), "coefficient c = {c}");
    assert!(
        close(cond_var, 0.54, 1e-10),
        "conditional variance {cond_var}"
    );

    // The crate's ratio matrix and P_t give the same two numbers.
    let m = scalar_model();
    let off = Offline::new(&m, t, &Inputs::none()).unwrap();
    let ratios = scf::ratio_recursion(&m, &off).unwrap();
    let p_t = off.gains.steps[t - 1].p[(0, 0)];
    assert!(close(ratios[t - 1][(0, 0)], c, 1e-10));
    assert!(close(p_t * ratios[t - 1][(0, 0)], cond_var, 1e-10));

    // (b) conditioned simulation + crate KF: sample mean and variance of x̂^KF_t given x_t = x̄.
    let runs = if cfg!(target_arch = "wasm32") {
        2000
    } else {
        6000
    };
    let xbar = 10.0;
    let sampler = ConditionedSampler::new(&m, t, &Inputs::none(), t).unwrap();
    let gains = KalmanGains::new(&m, t).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let xc = DVector::from_element(1, xbar);
    let (mut s1, mut s2) = (0.0, 0.0);
    for _ in 0..runs {
        let tr = sampler.draw(&m, &xc, &mut rng);
        assert_eq!(tr.x[t - 1][0], xbar);
        let xh = gains.filter(&m, &tr.y, &Inputs::none())[t - 1][0];
        s1 += xh;
        s2 += xh * xh;
    }
    let n = runs as f64;
    let mean = s1 / n;
    let svar = (s2 - n * mean * mean) / (n - 1.0);
    // 4.5 standard errors: mean SE = √(0.54/N); variance SE = 0.54·√(2/(N−1)).
    let se_mean = (0.54 / n).sqrt();
    let se_var = 0.54 * (2.0 / (n - 1.0)).sqrt();
    assert!(
        (mean - 0.9 * xbar).abs() < 4.5 * se_mean,
        "E[x̂ | x = {xbar}] ≈ {mean}, expected {} ± {}",
        0.9 * xbar,
        4.5 * se_mean
    );
    assert!(
        (svar - 0.54).abs() < 4.5 * se_var,
        "Var[x̂ | x] ≈ {svar}, expected 0.54 ± {}",
        4.5 * se_var
    );
}
in_browser!(scalar_footnote1_conditional_mean_and_variance);

/// A stable, non-symmetric 3-state F with a full V (= LLᵀ) and one output.
pub fn three_state() -> (
    DMatrix<f64>,
    DMatrix<f64>,
    DMatrix<f64>,
    DMatrix<f64>,
    LinearModel,
) {
    let f = mat(&[&[0.5, 0.4, 0.0], &[-0.3, 0.6, 0.2], &[0.1, 0.0, 0.7]]);
    let l = mat(&[&[1.0, 0.0, 0.0], &[0.5, 0.8, 0.0], &[-0.3, 0.2, 0.6]]);
    let v = &l * l.transpose();
    let h = mat(&[&[1.0, 0.0, 0.5]]);
    let w = mat(&[&[0.3]]);
    let model = LinearModel::time_invariant(f.clone(), h.clone(), v.clone(), w.clone()).unwrap();
    (f, h, v, w, model)
}

/// Γ of the 3-state example: residual of Γ = FΓFᵀ + V, and agreement with the Kronecker
/// solution; F^b = ΓFᵀΓ⁻¹ and V^b = Γ − ΓFᵀΓ⁻¹FΓ computed here from the independent Γ; and the
/// backward representation reproduces the second moments: x_{t−1} = F^b x_t + v^b with
/// v^b ⟂ x_t gives E[x_{t−1}x_tᵀ] = F^bΓ, which must equal (E[x_t x_{t−1}ᵀ])ᵀ = (FΓ)ᵀ = ΓFᵀ,
/// and Cov(x_{t−1}) = F^bΓF^bᵀ + V^b = Γ.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn three_state_gamma_and_backward_representation() {
    let (f, _h, v, _w, m) = three_state();
    // Stability of the chosen F, checked without the crate: F^200 → 0.
    assert!(f.pow(200).amax() < 1e-12);
    // The example is the 3-state one asked for: non-symmetric F, full V.
    assert!((&f - f.transpose()).amax() > 0.1);
    assert!(v.iter().all(|x| *x != 0.0));

    let g = m.stationary_covariance().unwrap();
    let residual = (&g - &f * &g * f.transpose() - &v).amax();
    assert!(
        residual <= 1e-12 * g.amax(),
        "Lyapunov residual {residual:.3e}"
    );
    let g_ref = lyapunov_kron(&f, &v);
    assert_mat_close(&g, &g_ref, 1e-11, "Γ vs (I − F⊗F)⁻¹ vec V");
    assert_mat_close(&m.x1_cov, &g_ref, 1e-11, "stationary prior Γ_1");

    let g_inv = g_ref.clone().try_inverse().unwrap();
    let fb_ref = &g_ref * f.transpose() * &g_inv;
    let vb_ref = &g_ref - &g_ref * f.transpose() * &g_inv * &f * &g_ref;
    let b = m.backward_representation().unwrap();
    assert_mat_close(&b.f_b, &fb_ref, 1e-10, "F^b = ΓFᵀΓ⁻¹");
    assert_mat_close(&b.v_b, &vb_ref, 1e-10, "V^b = Γ − ΓFᵀΓ⁻¹FΓ");
    assert_mat_close(
        &(&b.f_b * &g_ref),
        &(&g_ref * f.transpose()),
        1e-10,
        "F^bΓ = ΓFᵀ",
    );
    assert_mat_close(
        &(&b.f_b * &g_ref * b.f_b.transpose() + &b.v_b),
        &g_ref,
        1e-10,
        "F^bΓF^bᵀ + V^b = Γ",
    );
    // V^b is a covariance: symmetric, PSD.
    assert!((&b.v_b - b.v_b.transpose()).amax() <= 1e-14 * b.v_b.amax());
    assert!(b.v_b.clone().symmetric_eigen().eigenvalues.min() > 0.0);

    // The non-stationary form (45) along the propagated moments gives the same matrices.
    let mo = m.moments(5, &Inputs::none());
    for t in 2..=5 {
        let st = m.backward_step(t, &mo).unwrap();
        assert_mat_close(&st.f_b, &fb_ref, 1e-10, &format!("F^b_{t} (45)"));
        assert_mat_close(&st.v_b, &vb_ref, 1e-10, &format!("V^b_{t} (45)"));
    }
}
in_browser!(three_state_gamma_and_backward_representation);

/// U_tA_t by brute force from the batch form (31)–(32): the KF is linear in the data,
/// x̂^KF_t = U_t [y]_1^t, so U_t's column for y_k is the filter's response to a unit impulse at
/// time k (a textbook filter written in `common`); A_t stacks H(F^b)^{t−k}. Their product
/// must equal the crate's recursion (38) — and the closed form (41) — at every t.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn ratio_matrix_equals_batch_u_times_a() {
    let (f, h, v, w, m) = three_state();
    let n = 3;
    let g = lyapunov_kron(&f, &v);
    let fb = &g * f.transpose() * g.clone().try_inverse().unwrap();
    let steps = 8;
    let off = Offline::new(&m, steps, &Inputs::none()).unwrap();
    let rec = scf::ratio_recursion(&m, &off).unwrap();
    let zero = DVector::zeros(n);
    for t in 1..=steps {
        let mut ua = DMatrix::zeros(n, n);
        for k in 1..=t {
            let mut y = vec![DVector::zeros(1); t];
            y[k - 1][0] = 1.0;
            let u_k = reference_kf(&f, &h, &v, &w, &zero, &g, &zero, &y)[t - 1]
                .xhat
                .clone();
            let a_k = &h * fb.pow((t - k) as u32);
            ua += u_k * a_k;
        }
        assert_mat_close(
            &rec[t - 1],
            &ua,
            1e-10,
            &format!("(38) vs batch U_tA_t, t={t}"),
        );
        if t < n {
            // Fewer scalar measurements than states: U_tA_t has rank t < n.
            let rank = ua.clone().svd(false, false).rank(1e-9);
            assert_eq!(rank, t, "rank of U_tA_t at t = {t}");
        }
    }
}
in_browser!(ratio_matrix_equals_batch_u_times_a);

/// (38) ≡ (41) along the recursion for the stationary 3-state example: the crate's recursion
/// against I − P_tΓ⁻¹ with P_t from the textbook filter and Γ from the Kronecker solve.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn recursion_38_equals_closed_form_41_stationary() {
    let (f, h, v, w, m) = three_state();
    let steps = 60;
    let g = lyapunov_kron(&f, &v);
    let g_inv = g.clone().try_inverse().unwrap();
    let zero = DVector::zeros(3);
    let y = vec![DVector::zeros(1); steps];
    let reference = reference_kf(&f, &h, &v, &w, &zero, &g, &zero, &y);
    let off = Offline::new(&m, steps, &Inputs::none()).unwrap();
    let rec = scf::ratio_recursion(&m, &off).unwrap();
    for t in 1..=steps {
        let closed = DMatrix::identity(3, 3) - &reference[t - 1].p * &g_inv;
        assert_mat_close(
            &rec[t - 1],
            &closed,
            1e-9,
            &format!("(38) vs (41) at t={t}"),
        );
        assert_mat_close(
            &off.gains.steps[t - 1].p,
            &reference[t - 1].p,
            1e-10,
            &format!("P_t at t={t}"),
        );
    }
    // The limit is the asymptotic ratio I − P̄Γ⁻¹ (IV-B).
    let a = scf::asymptotic(&m).unwrap();
    assert_mat_close(&rec[steps - 1], &from_rows(&a.ratio), 1e-9, "R_60 vs R̄");
}
in_browser!(recursion_38_equals_closed_form_41_stationary);

/// (38) ≡ (41) for the non-stationary robot model (known x_1, Γ_1 = 0, inputs; V-D/V-E): the
/// recursion with F^b_t of (45) against I − P_tΓ_t⁻¹, Γ_t propagated here by
/// Γ_{t+1} = FΓ_tFᵀ + V from Γ_1 = 0 and P_t from the textbook filter; from t = 2 (Γ_1 = 0).
/// Both noise readings of the preset.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn recursion_38_equals_closed_form_41_robots() {
    for reading in [NoiseReading::Unscaled, NoiseReading::Literal] {
        let (spec, u) = presets::robot_model(reading);
        let m = LinearModel::from_spec(&spec).unwrap();
        let steps = 60;
        let inputs = Inputs(vec![DVector::from_vec(u.clone())]);
        let (f, h, v, w) = (
            m.f(1).clone(),
            m.h(1).clone(),
            m.v(1).clone(),
            m.w(1).clone(),
        );
        let m1 = DVector::from_vec(spec.x1_mean.clone().unwrap());
        let g1 = DMatrix::zeros(8, 8);
        let y = vec![DVector::zeros(4); steps];
        let reference = reference_kf(&f, &h, &v, &w, &m1, &g1, &DVector::from_vec(u), &y);
        let off = Offline::new(&m, steps, &inputs).unwrap();
        let rec = scf::ratio_recursion(&m, &off).unwrap();
        assert!(rec[0].amax() == 0.0, "R_1 = K_1H = 0 when x_1 is known");
        for t in 2..=steps {
            let r = &reference[t - 1];
            assert_mat_close(&off.moments.cov[t - 1], &r.gamma, 1e-10, &format!("Γ_{t}"));
            assert_slice_rel(
                off.moments.mean[t - 1].as_slice(),
                r.m.as_slice(),
                1e-12,
                &format!("m_{t}"),
            );
            let closed =
                DMatrix::identity(8, 8) - &r.p * r.gamma.clone().try_inverse().expect("Γ_t ≻ 0");
            assert_mat_close(
                &rec[t - 1],
                &closed,
                1e-9,
                &format!("{reading:?}: (38) vs (41) at t={t}"),
            );
        }
    }
}
in_browser!(recursion_38_equals_closed_form_41_robots);

/// The CLI's scalar numbers through the JSON path: a scenario parsed from text, with the data
/// given explicitly, reports ratio → 0.9 and the SCF center = KF center / ratio.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn scalar_example_from_json() {
    let y: Vec<Vec<f64>> = (0..30).map(|k| vec![((k * 7) % 11) as f64 - 5.0]).collect();
    let text = serde_json::json!({
        "method": "scf",
        "model": {"F": [[(5.0f64/6.0).sqrt()]], "H": [[1.0]], "V": [[1.0]], "W": [[1.0]]},
        "data": {"y": y},
        "alpha": 0.99
    })
    .to_string();
    let s = Scenario::from_json(&text).unwrap();
    assert_eq!(
        s.data,
        Some(DataSpec {
            y: y.clone(),
            u: vec![],
            t: vec![]
        })
    );
    let r = s.run().unwrap();
    let last = r.steps.last().unwrap();
    assert!(close(last.ratio[0][0], 0.9, 1e-12));
    let a = r.asymptotic.as_ref().expect("asymptotic block");
    assert!(close(a.gamma[0][0], 6.0, 1e-12) && close(a.ratio[0][0], 0.9, 1e-12));
    for st in &r.steps {
        let scf = st.scf.as_ref().unwrap();
        assert!(close(
            scf.center[0] * st.ratio[0][0],
            st.kf.center[0],
            1e-12
        ));
        assert!(close(
            scf.cov[0][0] * st.ratio[0][0],
            st.kf.cov[0][0],
            1e-12
        ));
    }
}
in_browser!(scalar_example_from_json);
