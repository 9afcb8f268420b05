//! What a researcher running confset on a public record must be told (issue: the Nile flow,
//! the US macro quarters): defaults made for a paper's scale derived from the record instead,
//! an estimate decided by an artificial bound or a promise whose assumption fails said in the
//! report's warnings, a method that a figure's limits no longer block, and messages that state
//! their rule with its numbers.

use crate::common::patch::run_json;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{json, Value};

/// A Nile-scale local level record: x_t a slow walk near 900, y_t = x_t + noise of about 150
/// (100 rows, seeded), as `data.y` rows.
fn nile_like(seed: u64) -> Vec<Value> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut level = 900.0;
    (0..100)
        .map(|_| {
            level += (rng.random::<f64>() - 0.5) * 40.0;
            let noise = (rng.random::<f64>() - 0.5) * 2.0 * 150.0;
            json!([level + noise])
        })
        .collect()
}

fn nile_uniform(x_bound: Option<f64>) -> Value {
    let mut s = json!({
        "method": "uniform_lp",
        "model": {"F": [[1.0]], "H": [[1.0]]},
        "data": {"y": nile_like(7)},
        "uniform": {}
    });
    if let Some(b) = x_bound {
        s["uniform"]["x_bound"] = json!(b);
    }
    s
}

/// The mean |ŷ_t|t−1 − y_t| of a uniform report and the mean of its y.
fn prediction_error(r: &confset::scenario::Report) -> (f64, f64) {
    let u = r.uniform.as_ref().expect("a uniform report");
    let pairs: Vec<(f64, f64)> = u.steps.iter().map(|s| (s.y_pred[0], u.y[s.t][0])).collect();
    let n = pairs.len() as f64;
    (
        pairs.iter().map(|(p, y)| (p - y).abs()).sum::<f64>() / n,
        pairs.iter().map(|(_, y)| y).sum::<f64>() / n,
    )
}

/// Pavelková's ±5 on the states is made for her example's scale. On a Nile-scale record the
/// default bound comes from the record (10·‖C⁺‖∞·max|y| here, 10 × the largest flow), so the
/// one-step predictions follow the flows (about the noise's 150 away, not the 1115 of every
/// state clamped at 5) and no estimate sits on the bound; with the paper's 5 given explicitly,
/// every estimate sits on it and the report says so, with the count.
#[test]
fn uniform_default_bound_follows_the_record() {
    let r = run_json(&nile_uniform(None)).expect("the Nile-scale record runs");
    let u = r.uniform.as_ref().expect("a uniform report");
    let largest = u.y[1..].iter().map(|y| y[0].abs()).fold(0.0, f64::max);
    assert!(u.x_bound_derived, "the bound is derived from the record");
    assert!(
        (u.x_bound - 10.0 * largest).abs() <= 1e-9 * u.x_bound,
        "x_bound {} is not 10 × max|y| = {}",
        u.x_bound,
        10.0 * largest
    );
    let (err, mean_y) = prediction_error(&r);
    assert!(
        mean_y > 700.0 && mean_y < 1100.0,
        "the record's mean {mean_y}"
    );
    // Uniform noise of half-width 150 has mean |e| = 75; the level walks by ±20 per step.
    assert!(
        err < 200.0,
        "ŷ does not track the data: mean |ŷ − y| = {err}"
    );
    assert!(
        r.warnings.is_empty(),
        "no estimate is on the derived bound, yet: {:?}",
        r.warnings
    );

    let small = run_json(&nile_uniform(Some(5.0))).expect("an explicit small bound runs");
    let (err_small, _) = prediction_error(&small);
    assert!(
        err_small > 500.0,
        "the clamped states still predict within {err_small}"
    );
    let w = small
        .warnings
        .iter()
        .find(|w| w.starts_with("x₁ sits on uniform.x_bound = 5 at "))
        .unwrap_or_else(|| panic!("no warning of the bound: {:?}", small.warnings));
    assert!(w.contains(" of 100 steps"), "{w}");
    assert!(w.contains("the bound, not the data, decides it"), "{w}");
    assert!(w.contains("raise uniform.x_bound"), "{w}");
    // Its CSV table carries the warning above the header.
    let table = small.table().expect("a table").to_csv();
    assert!(
        table.contains("# warning: x₁ sits on uniform.x_bound = 5"),
        "{table}"
    );
}
in_browser!(uniform_default_bound_follows_the_record);

/// A preset's scenario as JSON.
fn preset_json(name: &str) -> Value {
    serde_json::to_value(confset::presets::get(name).expect("a preset")).expect("JSON")
}

/// GLLS's guaranteed ball and box (35) are for the model (7) without state noise: with
/// model.V ≠ 0 the report says they guarantee nothing; without V nothing is said.
#[test]
fn glls_box_under_state_noise_is_warned() {
    let base = preset_json("glls-saturate");
    let quiet = run_json(&base).expect("the preset runs");
    assert!(
        quiet.warnings.is_empty(),
        "no state noise, no warning: {:?}",
        quiet.warnings
    );
    let mut noisy = base.clone();
    noisy["model"]["V"] = json!([[0.01, 0, 0], [0, 0.01, 0], [0, 0, 0.01]]);
    let r = run_json(&noisy).expect("the noisy model runs");
    let w = r
        .warnings
        .iter()
        .find(|w| w.starts_with("model.V is not zero"))
        .unwrap_or_else(|| panic!("no warning of the state noise: {:?}", r.warnings));
    assert!(w.contains("(35)") && w.contains("guarantee nothing"), "{w}");
    assert!(w.contains("1.000e-2"), "the largest variance is named: {w}");
}
in_browser!(glls_box_under_state_noise_is_warned);

/// The state-noise estimator (60)–(64) fits the measurements exactly: a non-zero model.W is
/// ignored, and the report says so; with W = 0 (the preset) it does not.
#[test]
fn glls_state_noise_estimator_ignoring_w_is_warned() {
    let base = preset_json("glls-unstable5");
    let exact = run_json(&base).expect("the preset runs");
    assert!(
        !exact.warnings.iter().any(|w| w.contains("ignores model.W")),
        "W = 0: {:?}",
        exact.warnings
    );
    let mut noisy = base.clone();
    noisy["model"]["W"] = json!([[0.04]]);
    let r = run_json(&noisy).expect("a measurement noise runs");
    let w = r
        .warnings
        .iter()
        .find(|w| w.contains("ignores model.W"))
        .unwrap_or_else(|| panic!("no warning of the ignored W: {:?}", r.warnings));
    assert!(w.starts_with("the state-noise estimator (60)–(64)"), "{w}");
    assert!(w.contains("4.000e-2"), "{w}");
    // Absent, W is the identity: still ignored, and said so.
    let mut absent = base.clone();
    absent["model"].as_object_mut().unwrap().remove("W");
    let r = run_json(&absent).expect("the default W runs");
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("ignores model.W (the identity when absent)")),
        "{:?}",
        r.warnings
    );
}
in_browser!(glls_state_noise_estimator_ignoring_w_is_warned);

/// The exact intervals of a 1-D sign region agree with the region's own membership test: at
/// the middle of every interval and of every gap, and just outside every finite end.
#[test]
fn sign_region_intervals_match_membership() {
    use confset::sets::{AffineGroup, SignRegion};
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for case in 0..200 {
        let count = 4 + case % 30;
        let q = 1 + case % 4;
        // Some repeated roots and some constant functions, as the KL transform gives.
        let (c, d): (Vec<f64>, Vec<Vec<f64>>) = (0..count)
            .map(|k| {
                let d: f64 = if k % 9 == 4 {
                    0.0
                } else {
                    rng.random::<f64>() * 4.0 - 2.0
                };
                let root = (rng.random::<f64>() * 10.0 - 5.0).round() / 2.0;
                let c = if d == 0.0 {
                    rng.random::<f64>() - 0.5
                } else {
                    root * d
                };
                (c, vec![d])
            })
            .unzip();
        let region = SignRegion {
            dim: 1,
            q,
            groups: vec![AffineGroup { c, d }],
        };
        let pieces = region.intervals_1d().expect("1-D");
        let inside = |x: f64| {
            pieces.iter().any(|i| {
                let (lo, hi) = i.ends();
                lo < x && x < hi
            })
        };
        let mut probes: Vec<f64> = vec![-1e6, 1e6];
        for w in pieces.windows(2) {
            let (_, a) = w[0].ends();
            let (b, _) = w[1].ends();
            assert!(a <= b, "case {case}: intervals out of order {pieces:?}");
            probes.push(0.5 * (a + b));
        }
        for i in &pieces {
            let (lo, hi) = i.ends();
            if lo.is_finite() && hi.is_finite() {
                probes.push(0.5 * (lo + hi));
            }
            for end in [lo, hi].into_iter().filter(|v| v.is_finite()) {
                probes.extend([end - 1e-6, end + 1e-6]);
            }
        }
        for x in probes {
            assert_eq!(
                region.contains(&[x]),
                inside(x),
                "case {case}: x = {x}, intervals {pieces:?}"
            );
        }
    }
}
in_browser!(sign_region_intervals_match_membership);

/// An AR(1) record (n = 1): LSCR runs (it was refused for the figure's sake), its region is a
/// union of intervals that holds the BLUE here, the intervals are the region's (membership at
/// their middles and just outside), and the region panel draws them on one axis.
#[test]
fn lscr_scalar_state_gives_intervals_and_draws_them() {
    use confset::plot::{report_svg, useful_panels, View};
    let s = json!({
        "method": "lscr",
        "model": {"F": [[0.8]], "H": [[1.0]], "G": [[1.0]], "sigma_v2": 1.0, "sigma_w2": 0.5},
        "simulate": {"steps": 60, "seed": 4},
        "lscr": {"estimate": "filter", "M": 100, "q": 5}
    });
    let r = run_json(&s).expect("n = 1 runs");
    let l = r.lscr.as_ref().expect("an LSCR report");
    assert_eq!(l.region.dim, 1);
    assert!(!l.intervals.is_empty(), "an empty region");
    let blue = l.blue.as_ref().expect("a BLUE").center[0];
    assert!(
        l.intervals.iter().any(|i| {
            let (lo, hi) = i.ends();
            lo < blue && blue < hi
        }),
        "the BLUE {blue} is outside {:?}",
        l.intervals
    );
    assert!(l.region.contains(&[blue]));
    for i in &l.intervals {
        let (lo, hi) = i.ends();
        assert!(
            lo.is_finite() && hi.is_finite(),
            "a stationary AR(1): bounded {i:?}"
        );
        assert!(l.region.contains(&[0.5 * (lo + hi)]));
        let eps = 1e-9 * (hi - lo).max(1.0);
        assert!(
            !l.region.contains(&[lo - eps]) || l.intervals.len() > 1,
            "{lo}"
        );
    }
    assert!(l.bounded);
    let length: f64 = l.intervals.iter().map(|i| i.ends().1 - i.ends().0).sum();
    assert!(
        (l.area - length).abs() <= 1e-9 * length,
        "area {} vs length {length}",
        l.area
    );
    let panels = useful_panels(&r);
    assert!(!panels.is_empty());
    let svg = report_svg(&r, &View::new(panels[0]), 960, 640).expect("the region panel draws");
    // X̂'s tint (LSCR_TINT, 240 228 66) as a band, its row and the BLUE's.
    assert!(svg.contains("#F0E442"), "no tinted band of X̂ in the SVG");
    for label in ["X̂ 90", "BLUE", "n = 1: X̂ is"] {
        assert!(svg.contains(label), "the SVG lacks \"{label}\"");
    }
    let small = report_svg(&r, &View::new(panels[0]), 350, 438).expect("a phone-sized figure");
    assert!(small.contains("#F0E442"));
}
in_browser!(lscr_scalar_state_gives_intervals_and_draws_them);

/// `scenario` without the block at `path` ("experiment", "lscr.coverage", …).
fn without(mut scenario: Value, path: &str) -> Value {
    let mut keys: Vec<&str> = path.split('.').collect();
    let last = keys.pop().expect("a path");
    let mut at = &mut scenario;
    for k in keys {
        at = &mut at[k];
    }
    if let Some(o) = at.as_object_mut() {
        o.remove(last);
    }
    scenario
}

/// `confset experiment --runs N` on a scenario without its study block: every method with a
/// study runs N runs with the defaults the help states. The KF case is the researcher's:
/// a kf scenario (no `experiment` block, no `simulate.condition`) conditions on the prior mean
/// at the last step, with every component and seed 0.
#[test]
fn a_study_given_only_its_runs_runs_on_every_method() {
    use confset::method::Method;
    use confset::scenario::Scenario;
    // The KF case, against the scalar model's own numbers: m_t = 0 (zero prior mean).
    let mut kf = without(preset_json("scf-scalar"), "experiment");
    kf["method"] = json!("kf");
    let kf = without(kf, "simulate.condition");
    let steps = kf["simulate"]["steps"].as_u64().expect("steps") as usize;
    let s = Scenario::from_json(&kf.to_string()).expect("a kf scenario");
    let no_runs = s.study(None).err().expect("no block and no runs: refused");
    assert_eq!(no_runs.field, "experiment");
    assert!(no_runs.message.contains("--runs"), "{}", no_runs.message);
    let mut st = s.study(Some(100)).expect("kf with --runs 100");
    let v = confset::study::run_to_end(st.as_mut(), 1000, |_, _| {}).expect("runs");
    assert_eq!(v["runs_done"], json!(100), "{v}");
    assert_eq!(v["condition_t"], json!(steps), "{v}");
    assert_eq!(v["condition_x"], json!([0.0]), "{v}");
    assert_eq!(v["components"], json!([0]), "{v}");
    let kf_inside = v["kf_inside"].as_u64().expect("a count");
    assert!(kf_inside <= 100, "{v}");

    // Every method with a study, from its first preset without the study block.
    for method in Method::ALL {
        let Some(block) = method.study_block() else {
            continue;
        };
        let Some(p) = confset::presets::all()
            .into_iter()
            .find(|p| p.scenario.method == method)
        else {
            continue;
        };
        let v = without(serde_json::to_value(&p.scenario).expect("JSON"), block);
        let s = Scenario::from_json(&v.to_string()).expect("readable");
        let mut st = s
            .study(Some(16))
            .unwrap_or_else(|e| panic!("{} ({}) without {block}: {e}", p.name, method.name()));
        assert_eq!(st.total(), 16, "{}", p.name);
        confset::study::run_to_end(st.as_mut(), 1000, |_, _| {})
            .unwrap_or_else(|e| panic!("{}: {e}", p.name));
    }
}
in_browser!(a_study_given_only_its_runs_runs_on_every_method);

/// A covariance refused as numerically singular says the rule with its numbers: the
/// smallest eigenvalue is positive, but not above 10⁻⁹ × the largest entry.
#[test]
fn a_singular_covariance_states_its_rule() {
    let mut s = preset_json("scf-scalar");
    s["model"]["W"] = json!([[1.2e4, 0.0], [0.0, 3.5e-12]]);
    s["model"]["H"] = json!([[1.0], [1.0]]);
    let e = run_json(&s).err().expect("a numerically singular W");
    assert_eq!(e.field, "model.W", "{e}");
    for words in [
        "smallest eigenvalue 3.50e-12",
        "1e-9 × its largest entry (1.20e4)",
        "numerically singular",
        "above 1.20e-5",
    ] {
        assert!(e.message.contains(words), "{words:?} not in: {}", e.message);
    }
    s["model"]["W"] = json!([[1.0, 0.0], [0.0, -2.0]]);
    let e = run_json(&s).err().expect("a negative eigenvalue");
    assert!(
        e.message
            .contains("its smallest eigenvalue is -2.000e0, negative"),
        "{}",
        e.message
    );
}
in_browser!(a_singular_covariance_states_its_rule);

/// Counts in messages agree with their nouns: one output is "1 output".
#[test]
fn a_count_of_one_is_singular() {
    assert_eq!(confset::error::counted(1, "output", "outputs"), "1 output");
    assert_eq!(confset::error::counted(0, "output", "outputs"), "0 outputs");
    assert_eq!(confset::error::counted(3, "entry", "entries"), "3 entries");
    // A budget refusal of a one-output model names "m = 1 output".
    let mut s = preset_json("glls-saturate");
    s["glls"]["max_horizon"] = json!(2000);
    s["simulate"]["steps"] = json!(5000);
    if let Err(e) = run_json(&s) {
        assert!(!e.message.contains("1 outputs"), "{e}");
    }
}
in_browser!(a_count_of_one_is_singular);

/// The SCF's "no region" says the rule with the numbers: an unobservable component at
/// t ≥ n is not "too few measurements".
#[test]
fn scf_singular_ratio_states_the_rule() {
    let words = confset::scf::singular_ratio(100, 2, None);
    assert!(
        words.contains("t ≥ n = 2") && words.contains("not observable"),
        "{words}"
    );
    assert!(!words.contains("too few"), "{words}");
    let early = confset::scf::singular_ratio(1, 2, None);
    assert!(early.contains("t = 1 is before t = n = 2"), "{early}");
}
in_browser!(scf_singular_ratio_states_the_rule);

/// An LSCR model with ρ(F) ≥ 1 (a random walk) is refused in one sentence about F.
#[test]
fn lscr_unstable_model_message_reads_as_a_sentence() {
    let s = json!({
        "method": "lscr",
        "model": {"F": [[1.0]], "H": [[1.0]], "G": [[1.0]], "sigma_v2": 1.0, "sigma_w2": 1.0},
        "simulate": {"steps": 30, "seed": 1},
        "lscr": {"estimate": "filter"}
    });
    let e = confset::scenario::Scenario::from_json(&s.to_string())
        .and_then(|s| s.run())
        .err()
        .expect("a random walk is refused");
    assert_eq!(e.field, "model.F");
    assert!(
        e.message
            .starts_with("must be stable (every eigenvalue inside the unit circle)"),
        "{}",
        e.message
    );
    assert!(
        e.message.contains("spectral radius is 1.000000"),
        "{}",
        e.message
    );
    assert!(!e.message.contains(" — is needed"), "{}", e.message);
}
in_browser!(lscr_unstable_model_message_reads_as_a_sentence);

/// A level of 1e-100 is refused in four digits with the accepted range, never a hundred
/// zeros and "could not be computed".
#[test]
fn a_tiny_alpha_is_refused_with_the_range() {
    for method in ["scf-scalar", "glls-saturate", "lscr-ma1"] {
        let mut s = preset_json(method);
        s["alpha"] = json!(1e-100);
        let Err(e) = run_json(&s) else {
            // A method that does not draw at `alpha` (GLLS, LSCR's own level) may take it.
            continue;
        };
        assert_eq!(e.field, "alpha", "{method}: {e}");
        assert!(e.message.contains("1.000e-100"), "{method}: {e}");
        assert!(e.message.contains("from 1e-6 to 1 − 1e-9"), "{method}: {e}");
        assert!(!e.message.contains("0.00000000"), "{method}: {e}");
        assert!(
            !e.message.contains("could not be computed"),
            "{method}: {e}"
        );
    }
    let e = confset::stats::chi2_quantile(1e-100, 2).unwrap_err();
    assert!(e.message.contains("1.000e-100"), "{e}");
    assert_eq!(confset::error::shown(0.95), "0.95");
    assert_eq!(confset::error::shown(1e-100), "1.000e-100");
}
in_browser!(a_tiny_alpha_is_refused_with_the_range);
