//! Given explicit `data`, a report is deterministic, platform independent (crate docs:
//! native = wasm to 1e-9 relative). The same test bodies run natively and in Chromium and
//! compare the report with numbers computed here by a textbook Kalman filter (`common`) and
//! the SCF formulas x̂ = m + R⁻¹(x̂^KF − m), Π = R⁻¹P, R = I − PΓ⁻¹ — so both platforms are held
//! to the same independent reference. Golden values pin the seeded random stream (ChaCha8 +
//! StandardNormal) and one seeded simulation: the wasm run of the same test proves the stream is
//! identical there.

use crate::common::*;
use confset::scenario::{Report, Scenario};
use nalgebra::{DMatrix, DVector};
use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

const TOL: f64 = 1e-9;

/// Vector entries relative to the vector's largest entry.
#[track_caller]
fn assert_vec(a: &[f64], b: &DVector<f64>, what: &str) {
    let scale = b.amax().max(1e-300);
    for i in 0..b.len() {
        assert!(
            (a[i] - b[i]).abs() <= TOL * scale,
            "{what}[{i}]: report {:.17e}, reference {:.17e}",
            a[i],
            b[i]
        );
    }
}

/// Compare a report with the reference filter at the given times (1-based).
fn check_report(r: &Report, reference: &[KfStep], alpha_r2: f64, times: &[usize]) {
    let n = r.n;
    for &t in times {
        let st = &r.steps[t - 1];
        let rf = &reference[t - 1];
        assert_eq!(st.t, t);
        let what = |s: &str| format!("t={t}: {s}");
        assert!(
            rel_close(st.kf.radius2, alpha_r2, 1e-12),
            "{}",
            what("radius2")
        );
        assert_vec(&st.kf.center, &rf.xhat, &what("KF center"));
        assert_mat_close(&from_rows(&st.kf.cov), &rf.p, TOL, &what("KF cov"));
        let ratio = DMatrix::identity(n, n) - &rf.p * rf.gamma.clone().try_inverse().unwrap();
        assert_mat_close(&from_rows(&st.ratio), &ratio, TOL, &what("ratio"));
        let r_inv = ratio.try_inverse().unwrap();
        let center = &rf.m + &r_inv * (&rf.xhat - &rf.m);
        let pi = &r_inv * &rf.p;
        let pi = (&pi + pi.transpose()) * 0.5;
        assert_vec(&r.prior_mean[t - 1], &rf.m, &what("prior mean"));
        if t < n {
            assert!(st.scf.is_none(), "{}", what("no SCF region before t = n"));
            continue;
        }
        let scf = st.scf.as_ref().expect("SCF region");
        assert!(rel_close(scf.radius2, alpha_r2, 1e-12));
        assert_vec(&scf.center, &center, &what("SCF center"));
        assert_mat_close(&from_rows(&scf.cov), &pi, TOL, &what("SCF cov"));
    }
}

/// The JSON contract: every value is a number except the named text fields; the numbers survive
/// a round trip through text.
fn check_json(r: &Report) {
    fn walk(v: &serde_json::Value, key: &str) {
        match v {
            serde_json::Value::String(_) => {
                assert!(
                    matches!(key, "method" | "how"),
                    "string value under {key:?}"
                )
            }
            serde_json::Value::Array(a) => a.iter().for_each(|x| walk(x, key)),
            serde_json::Value::Object(o) => o.iter().for_each(|(k, x)| walk(x, k)),
            serde_json::Value::Number(x) => assert!(x.as_f64().unwrap().is_finite()),
            _ => {}
        }
    }
    let text = serde_json::to_string(r).unwrap();
    walk(&serde_json::from_str(&text).unwrap(), "");
    let back: Report = serde_json::from_str(&text).unwrap();
    for (a, b) in back.steps.iter().zip(&r.steps) {
        for (x, y) in a.kf.center.iter().zip(&b.kf.center) {
            assert!(rel_close(*x, *y, 1e-15));
        }
    }
}

const Y_SCALAR: [f64; 10] = [0.3, -1.25, 2.0, 0.75, -0.5, 1.6, 3.1, 2.2, -0.9, 0.05];

/// Scalar model (Example 1) with explicit data at α = 0.9: χ²(0.9, 1) = z²_{0.95}
/// = 1.6448536269514722² = 2.705543454095404.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn scalar_fixed_data_report() {
    let f = (5.0f64 / 6.0).sqrt();
    let s = Scenario::from_json(
        &serde_json::json!({
            "method": "scf",
            "model": {"F": [[f]], "H": [[1.0]], "V": [[1.0]], "W": [[1.0]]},
            "data": {"y": Y_SCALAR.iter().map(|y| vec![*y]).collect::<Vec<_>>()},
            "alpha": 0.9
        })
        .to_string(),
    )
    .unwrap();
    let r = s.run().unwrap();
    let one = mat(&[&[1.0]]);
    let y: Vec<DVector<f64>> = Y_SCALAR
        .iter()
        .map(|y| DVector::from_element(1, *y))
        .collect();
    let zero = DVector::zeros(1);
    let reference = reference_kf(
        &mat(&[&[f]]),
        &one,
        &one,
        &one,
        &zero,
        &mat(&[&[6.0]]),
        &zero,
        &y,
    );
    check_report(&r, &reference, 2.705_543_454_095_404, &[1, 2, 5, 10]);
    check_json(&r);
    // Spot values by hand: t = 1: K = 6/7, x̂ = 0.3·6/7, P = 6/7, ratio 1 − 1/7.
    let st = &r.steps[0];
    assert!(rel_close(st.kf.center[0], 0.3 * 6.0 / 7.0, 1e-14));
    assert!(rel_close(st.kf.cov[0][0], 6.0 / 7.0, 1e-14));
    assert!(rel_close(st.ratio[0][0], 6.0 / 7.0, 1e-14));
    assert!(rel_close(st.scf.as_ref().unwrap().center[0], 0.3, 1e-14));
}
in_browser!(scalar_fixed_data_report);

/// A 2-state model with one output, stationary prior (Γ from the Kronecker solve), α = 0.95:
/// χ²(0.95, 2) = −2 ln 0.05 (closed form for two degrees of freedom).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn two_state_fixed_data_report() {
    let f = mat(&[&[0.8, 0.3], &[-0.2, 0.6]]);
    let h = mat(&[&[1.0, -0.5]]);
    let v = mat(&[&[0.5, 0.1], &[0.1, 0.3]]);
    let w = mat(&[&[0.2]]);
    let ys = [
        0.4, 1.1, -0.3, -1.7, 0.2, 0.9, 2.4, 1.3, -0.6, 0.0, 0.35, -1.05,
    ];
    let s = Scenario::from_json(
        &serde_json::json!({
            "method": "scf",
            "model": {"F": rows(&f), "H": rows(&h), "V": rows(&v), "W": rows(&w)},
            "data": {"y": ys.iter().map(|y| vec![*y]).collect::<Vec<_>>()},
            "alpha": 0.95
        })
        .to_string(),
    )
    .unwrap();
    let r = s.run().unwrap();
    assert!(r.steps[0].scf.is_none(), "no SCF region before t = n");
    let y: Vec<DVector<f64>> = ys.iter().map(|y| DVector::from_element(1, *y)).collect();
    let zero = DVector::zeros(2);
    let g = lyapunov_kron(&f, &v);
    let reference = reference_kf(&f, &h, &v, &w, &zero, &g, &zero, &y);
    check_report(&r, &reference, -2.0 * 0.05f64.ln(), &[2, 3, 7, 12]);
    check_json(&r);
}
in_browser!(two_state_fixed_data_report);

/// Non-stationary prior, measured inputs and a non-zero prior mean (V-D, V-E): 2 states,
/// 2 outputs, F unstable (so the prior must be given), B u constant.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn inputs_and_given_prior_fixed_data_report() {
    let f = mat(&[&[1.0, 0.1], &[0.0, 1.02]]);
    let h = mat(&[&[1.0, 0.0], &[0.5, 1.0]]);
    let v = mat(&[&[0.01, 0.002], &[0.002, 0.04]]);
    let w = mat(&[&[0.25, 0.05], &[0.05, 0.16]]);
    let b = mat(&[&[0.0], &[1.0]]);
    let u = [0.3];
    let m1 = [2.0, -1.0];
    let g1 = mat(&[&[0.5, 0.0], &[0.0, 0.2]]);
    let ys: Vec<[f64; 2]> = (0..9)
        .map(|k| {
            let k = k as f64;
            [2.0 + 0.05 * k * k - 0.3 * (k * 1.3).sin(), -0.2 + 0.4 * k]
        })
        .collect();
    let s = Scenario::from_json(
        &serde_json::json!({
            "method": "scf",
            "model": {"F": rows(&f), "H": rows(&h), "V": rows(&v), "W": rows(&w), "B": rows(&b),
                      "x1_mean": m1, "x1_cov": rows(&g1)},
            "data": {"y": ys, "u": [u]},
            "alpha": 0.8
        })
        .to_string(),
    )
    .unwrap();
    let r = s.run().unwrap();
    assert!(
        r.asymptotic.is_none(),
        "no asymptotic block for an unstable F"
    );
    let y: Vec<DVector<f64>> = ys.iter().map(|y| DVector::from_column_slice(y)).collect();
    let bu = &b * DVector::from_column_slice(&u);
    let reference = reference_kf(
        &f,
        &h,
        &v,
        &w,
        &DVector::from_column_slice(&m1),
        &g1,
        &bu,
        &y,
    );
    check_report(&r, &reference, -2.0 * 0.2f64.ln(), &[1, 2, 4, 9]);
    check_json(&r);
}
in_browser!(inputs_and_given_prior_fixed_data_report);

/// Golden: the first draws of ChaCha8Rng::seed_from_u64 (raw u64 and StandardNormal), printed
/// natively once. The same assertions in wasm prove the stream is the same there.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn golden_chacha8_stream() {
    let cases: [(u64, [u64; 3], [f64; 6]); 2] = [
        (
            0,
            [
                13080132717333068652,
                8594738769458413623,
                12896916468484187878,
            ],
            [
                0.6999607946268154,
                -0.14406163542784764,
                0.30288628024558556,
                -1.374513899829971,
                1.200341661914451,
                0.1107813558351432,
            ],
        ),
        (
            42,
            [
                12578764544318200737,
                17529487244874322312,
                7886285670807131020,
            ],
            [
                0.47798123835102174,
                1.3340706102318078,
                -0.21086668327103028,
                0.4763469238088213,
                -0.5120906220561634,
                -0.9339784493906981,
            ],
        ),
    ];
    for (seed, raw, normals) in cases {
        let mut r = ChaCha8Rng::seed_from_u64(seed);
        let got: Vec<u64> = (0..3).map(|_| r.next_u64()).collect();
        assert_eq!(got, raw, "raw stream of seed {seed}");
        let mut r = ChaCha8Rng::seed_from_u64(seed);
        let got: Vec<f64> = (0..6).map(|_| r.sample(StandardNormal)).collect();
        assert_slice_rel(&got, &normals, 1e-15, &format!("normals of seed {seed}"));
    }
}
in_browser!(golden_chacha8_stream);

/// Golden: the scalar preset's seeded simulation (seed 1, 50 steps) and its estimates, and the
/// robot preset's conditioned simulation (drawn backwards from the collision state at t = 40).
/// Tolerance 1e-12: libm's exp/sin/cos may differ in the last bit between platforms.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn golden_seeded_simulations() {
    let mut s = confset::presets::scalar();
    s.scf = None;
    let r = s.run().unwrap();
    let y: Vec<f64> = r.y[..3].iter().map(|v| v[0]).collect();
    assert_slice_rel(
        &y,
        &[-1.9860731616665284, -1.3188716821418507, 0.2584639201984611],
        1e-12,
        "scalar y_1..3",
    );
    let x: Vec<f64> = r.x_true.as_ref().unwrap()[..3]
        .iter()
        .map(|v| v[0])
        .collect();
    assert_slice_rel(
        &x,
        &[
            -0.5752554610555289,
            -0.19210535776764137,
            -0.5091996208852513,
        ],
        1e-12,
        "scalar x_1..3",
    );
    let st = &r.steps[49];
    assert_slice_rel(&st.kf.center, &[4.550102434431439], 1e-12, "KF center t=50");
    assert_slice_rel(
        &st.scf.as_ref().unwrap().center,
        &[5.055669371590487],
        1e-12,
        "SCF center t=50",
    );

    let s = confset::presets::robots(confset::presets::NoiseReading::Unscaled);
    let r = s.run().unwrap();
    let xt = &r.x_true.as_ref().unwrap()[39];
    assert_slice_rel(
        xt,
        &[
            -0.506151259318493,
            1.977590395659038,
            -0.28649394024816804,
            -2.7214379393635344,
            -0.40615125931849305,
            1.977590395659038,
            0.4008510325137583,
            -2.7214379393635344,
        ],
        1e-12,
        "robot x_40 (the conditioning state)",
    );
    // The conditioning state is a collision: the robots' centers are d_min/2 = 0.1 apart.
    let d = ((xt[0] - xt[4]).powi(2) + (xt[1] - xt[5]).powi(2)).sqrt();
    assert!((d - 0.1).abs() < 1e-12, "distance {d}");
    assert_slice_rel(
        &r.y[0],
        &[
            -0.9981348280030216,
            20.035049496295837,
            1.067309301112424,
            20.10446162944819,
        ],
        1e-12,
        "robot y_1",
    );
    assert_slice_rel(
        &r.y[39],
        &[
            -0.484437671426522,
            1.9660645589090662,
            -0.4378016325750389,
            1.9689331472642662,
        ],
        1e-12,
        "robot y_40",
    );
    assert_slice_rel(
        &r.steps[35].kf.center,
        &[
            -0.7035132269763218,
            2.6647166349966716,
            -0.21023219861021586,
            -3.638370969689356,
            -0.05026246121591327,
            2.6317352664092493,
            0.5130149487104945,
            -3.6018110882932284,
        ],
        1e-12,
        "robot KF center t=36",
    );
}
in_browser!(golden_seeded_simulations);
