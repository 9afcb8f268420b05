//! `simulate.true_noise`: the simulation draws its noise with covariances V ×, W × the model's,
//! while every filter assumes the model's V and W.
//!
//! * Scale 1 changes nothing: every SCF, KF and LSCR preset's report with `{"V": 1, "W": 1}`
//!   is the report without it (the golden digests pin the latter), and so are the SCF study's
//!   counts.
//! * The record moves and the filter does not: the truth and the data change, the KF's
//!   covariance P_t (a function of the assumed V, W only, (35c)) stays bit for bit.
//! * SCF's conditional coverage (Property 1) holds at true = assumed (the robots' count in its
//!   exact 99.9 % binomial band, as `coverage::robot_experiment_counts`) and fails when the
//!   data have 4 V and 4 W: the count falls below the band's lower bound.
//! * LSCR's region assumes no variance: Theorem 3.2 holds for any σ_v², σ_w² with the noise's
//!   shape (G Gᵀ, or V up to scale) known (Lemma 3.1: s = A x_τ + n̄ with Cov n̄ = σ_v²D + σ_w²I,
//!   diagonal at any scale; F^b = Π′FᵀΠ′⁻¹ does not depend on σ_v²). A common scale of V and W
//!   keeps Cov n̄ ∝ its old self, and scaling V alone changes D's weight but keeps n̄'s
//!   components independent and symmetric, which is all the sign-perturbed sums need. So the
//!   region keeps its coverage under ×4, while the BLUE and Kalman ellipses, which assume the
//!   model's variances, lose theirs.
//! * Refusals name the field: data scenarios, methods that cannot honour it, scales out of
//!   range, and SCF's Fig. 1 curve (the model's own law in closed form).

use crate::common::*;
use confset::presets::{self, NoiseReading};
use confset::scenario::{Scenario, TrueNoise};
use confset::study::{Chunked, Study};
use confset::Method;
use serde_json::{json, Value};

const RUNS: usize = 2000;
const CONF: f64 = 0.999;

fn scaled(mut s: Scenario, v: f64, w: f64) -> Scenario {
    s.simulate.as_mut().expect("a simulated preset").true_noise = Some(TrueNoise { v, w });
    s
}

/// Every SCF, KF and LSCR preset that simulates: its report with scale 1 is its report.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn unit_scales_change_no_report() {
    let mut seen = 0;
    for p in presets::all() {
        let s = p.scenario.clone();
        if !matches!(s.method, Method::Scf | Method::Kf | Method::Lscr) || s.simulate.is_none() {
            continue;
        }
        let plain = s.run().unwrap_or_else(|e| panic!("{}: {e}", p.name));
        let unit = scaled(s, 1.0, 1.0).run().unwrap();
        assert_eq!(plain, unit, "{}: scale 1 changed the report", p.name);
        seen += 1;
    }
    assert!(seen >= 4, "only {seen} presets checked");
}

/// ×4 on V moves the truth and the data; the KF's P_t, which depends on the assumed V, W only,
/// does not move by a bit. ×4 on the model's V (the assumed one) does move it.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_truth_moves_and_the_filter_does_not() {
    let mut s = presets::scalar();
    // Fig. 1's curve is the model's own law: refused beside a true noise (below).
    s.scf.as_mut().unwrap().coverage_curve = None;
    let plain = s.run().unwrap();
    let truer = scaled(s.clone(), 4.0, 1.0).run().unwrap();
    assert_ne!(plain.x_true, truer.x_true, "the truth did not move");
    assert_ne!(plain.y, truer.y, "the data did not move");
    assert_eq!(plain.steps.len(), truer.steps.len());
    for (a, b) in plain.steps.iter().zip(&truer.steps) {
        assert_eq!(a.kf.cov, b.kf.cov, "P_{} moved with the true noise", a.t);
        assert_eq!(a.kf.radius2, b.kf.radius2);
    }
    // The assumed V × 4: the model's V itself, so P moves.
    let mut v = serde_json::to_value(&s).unwrap();
    let vv = v["model"]["V"][0][0].as_f64().unwrap();
    v["model"]["V"][0][0] = json!(4.0 * vv);
    let assumed: Scenario = serde_json::from_value(v).unwrap();
    let assumed = assumed.run().unwrap();
    let last = |r: &confset::scenario::Report| r.steps.last().unwrap().kf.cov[0][0];
    assert!(
        last(&assumed) > last(&plain) * 1.1,
        "P did not grow with the assumed V: {} vs {}",
        last(&assumed),
        last(&plain)
    );
}
in_browser!(the_truth_moves_and_the_filter_does_not);

fn robots_counts(s: &Scenario) -> confset::scf::experiment::ExperimentResult {
    let mut e = Chunked::new(s.prepare_scf().unwrap().conditional_experiment().unwrap());
    while !e.finished() {
        e.step(500).unwrap();
    }
    e.report()
}

/// Property 1 at true = assumed (the count in its band, and scale 1 the same counts as no
/// field), and its failure when the data have 4 V and 4 W (below the band: a statistical test
/// that fails for a filter which ignored the field).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn scf_coverage_falls_when_the_noise_is_four_times_the_assumed() {
    let mut s = presets::robots(NoiseReading::Unscaled);
    s.experiment.as_mut().unwrap().runs = RUNS;
    let (lo, hi) = binomial_interval(RUNS, 0.95, CONF);
    let plain = robots_counts(&s);
    let unit = robots_counts(&scaled(s.clone(), 1.0, 1.0));
    assert_eq!(plain, unit, "scale 1 changed the study's counts");
    assert!(
        (lo..=hi).contains(&unit.scf_inside),
        "true = assumed: SCF {}/{RUNS} outside [{lo}, {hi}]",
        unit.scf_inside
    );
    let four = robots_counts(&scaled(s, 4.0, 4.0));
    eprintln!(
        "robots, true noise ×4: SCF {}/{RUNS} (band [{lo}, {hi}]), KF {}",
        four.scf_inside, four.kf_inside
    );
    assert!(
        four.scf_inside < lo,
        "true noise ×4: SCF {}/{RUNS} not below the band's lower bound {lo}",
        four.scf_inside
    );
}
in_browser!(scf_coverage_falls_when_the_noise_is_four_times_the_assumed);

/// LSCR's coverage experiment at a fixed x̄ (Fig. 1's cascade, prediction of x₃₁) under true
/// noise ×4 on both V and W: each X̂_l in its band, X̂ at least its level's lower bound; the
/// BLUE and Kalman ellipses (the model's variances) below their band.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn lscr_region_keeps_its_coverage_and_the_ellipses_lose_theirs() {
    for (v, w) in [(4.0, 4.0), (4.0, 1.0)] {
        let mut j = serde_json::to_value(presets::get("lscr-predict").unwrap()).unwrap();
        j["simulate"]["condition"] = json!({"t": 31, "x": [0.05, -0.1]});
        j["simulate"]["true_noise"] = json!({"V": v, "W": w});
        j["lscr"]["coverage"] = json!({"runs": RUNS, "seed": 11});
        let s: Scenario = serde_json::from_value(j).unwrap();
        let p = s.prepare_lscr().unwrap();
        let c = p.coverage(&[0.05, -0.1]).unwrap();
        let what = format!("true noise V ×{v}, W ×{w}");
        eprintln!("LSCR {what}: {c:?}");
        let band_each = binomial_interval(RUNS, c.level_each, CONF);
        for (l, &k) in c.counts.inside_each.iter().enumerate() {
            assert!(
                band_each.0 <= k && k <= band_each.1,
                "{what}: X̂_{} {k}/{RUNS} outside {band_each:?}",
                l + 1
            );
        }
        let band = binomial_interval(RUNS, c.level, CONF);
        assert!(
            c.counts.inside >= band.0,
            "{what}: X̂ {} below {band:?}",
            c.counts.inside
        );
        if v == w {
            let blue = c.counts.blue.expect("BLUE counted");
            let kf = c.counts.kf.expect("Kalman counted");
            assert!(
                blue < band.0,
                "{what}: BLUE {blue}/{RUNS} not below {band:?}"
            );
            assert!(kf < band.0, "{what}: Kalman {kf}/{RUNS} not below {band:?}");
        }
    }
}
in_browser!(lscr_region_keeps_its_coverage_and_the_ellipses_lose_theirs);

fn refused(mut v: Value, noise: Value) -> (String, String) {
    v["simulate"]["true_noise"] = noise;
    let e = Scenario::from_json(&v.to_string())
        .and_then(|s| s.run())
        .expect_err("refused");
    (e.field, e.message)
}

/// Every refusal names `simulate.true_noise` (or its scale) and says why in words.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn refusals_name_the_field() {
    let one = json!({"V": 4.0});
    for p in presets::all() {
        let s = &p.scenario;
        if s.simulate.is_none() {
            continue;
        }
        let v = serde_json::to_value(s).unwrap();
        match s.method {
            Method::Scf | Method::Kf | Method::Lscr | Method::Conformal => {
                for (bad, field) in [
                    (json!({"V": 0.0}), "simulate.true_noise.V"),
                    (json!({"W": -1.0}), "simulate.true_noise.W"),
                    (json!({"V": 1e5}), "simulate.true_noise.V"),
                ] {
                    let (f, m) = refused(v.clone(), bad);
                    assert_eq!(f, field, "{}: {m}", p.name);
                    assert!(m.contains("positive number"), "{}: {m}", p.name);
                }
                let (f, m) = refused(v.clone(), json!({"X": 1.0}));
                assert!(f.starts_with("simulate.true_noise"), "{}: {f}: {m}", p.name);
            }
            Method::Glls | Method::UniformLp | Method::Ubb | Method::Compare => {
                let (f, m) = refused(v.clone(), one.clone());
                assert_eq!(f, "simulate.true_noise", "{}: {m}", p.name);
                assert!(m.contains("is not used by method"), "{}: {m}", p.name);
            }
        }
    }
    // Data: the record is measured.
    let mut v = serde_json::to_value(presets::scalar()).unwrap();
    v["data"] = json!({"y": [[0.1], [0.2], [0.3]]});
    let (f, m) = refused(v, one.clone());
    assert_eq!(f, "simulate.true_noise");
    assert!(m.contains("needs a simulated record"), "{m}");
    // SCF's Fig. 1 curve is the model's own law.
    let fig1 = presets::all()
        .into_iter()
        .find(|p| {
            p.scenario
                .scf
                .as_ref()
                .is_some_and(|b| b.coverage_curve.is_some())
        })
        .expect("a preset with Fig. 1's curve");
    let (f, m) = refused(serde_json::to_value(&fig1.scenario).unwrap(), one);
    assert_eq!(f, "simulate.true_noise");
    assert!(m.contains("scf.coverage_curve"), "{m}");
}
in_browser!(refusals_name_the_field);
