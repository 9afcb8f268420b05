//! A compare never counts "does not apply" as "missed", natively and in the browser:
//!
//! * on a lag-embedded AR(1) of the Nile record, (F, H) is unobservable: SCF, GLLS and
//!   Tempo's ubb have no set; each says why (its own error) and what would give one, in the
//!   report, its CSV table and the study, which counts those runs apart and gives them no band
//!   verdict ("does not apply"); following ubb's remedy (a bound on x(0)) gives it a set;
//! * the verdict over the runs with a set is the exact binomial band of those runs (a merged
//!   partial with runs without a set, against the binomial CDF here);
//! * each member's options go through its descriptor (`compare.members.<method>`): a GLLS
//!   horizon reaches the GLLS report, an option a member does not pass is refused by name;
//! * every model size: n = 1 (intervals, the Kalman one against a textbook filter here), n = 3
//!   in the plane `compare.plane` = [0, 2] (each set against its own panel's, projected here);
//! * the step cap is the work budget's: 203 rows run, 5,000 are refused by the budget naming
//!   `data.y` and the formula, before any work;
//! * a record with a gap: each member takes it as its method does, or has no set saying so.

use crate::common::*;
use confset::method::Method;
use confset::plot::{self, View};
use confset::presets;
use confset::scenario::compare::{MethodSet, PlaneSet, Standing};
use confset::scenario::{Job, Report, Scenario};
use confset::sets::Ellipsoid;
use nalgebra::{DMatrix, DVector};
use serde_json::{json, Value};
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// The annual flow of the Nile at Aswan, 1871–1970 (10⁸ m³; Durbin & Koopman's series).
const NILE: [f64; 100] = [
    1120.0, 1160.0, 963.0, 1210.0, 1160.0, 1160.0, 813.0, 1230.0, 1370.0, 1140.0, 995.0, 935.0,
    1110.0, 994.0, 1020.0, 960.0, 1180.0, 799.0, 958.0, 1140.0, 1100.0, 1210.0, 1150.0, 1250.0,
    1260.0, 1220.0, 1030.0, 1100.0, 774.0, 840.0, 874.0, 694.0, 940.0, 833.0, 701.0, 916.0, 692.0,
    1020.0, 1050.0, 969.0, 831.0, 726.0, 456.0, 824.0, 702.0, 1120.0, 1100.0, 832.0, 764.0, 821.0,
    768.0, 845.0, 864.0, 862.0, 698.0, 845.0, 744.0, 796.0, 1040.0, 759.0, 781.0, 865.0, 845.0,
    944.0, 984.0, 897.0, 822.0, 1010.0, 771.0, 676.0, 649.0, 846.0, 812.0, 742.0, 801.0, 1040.0,
    860.0, 874.0, 848.0, 890.0, 744.0, 749.0, 838.0, 1050.0, 918.0, 986.0, 797.0, 923.0, 975.0,
    815.0, 1020.0, 906.0, 901.0, 1170.0, 912.0, 746.0, 919.0, 718.0, 714.0, 740.0,
];

/// The methods a compare gives no set on the lag-embedded AR(1): (F, H) is unobservable.
/// The members without a set on the lag-embedded AR(1): SCF's ratio matrix and GLLS's Γ_{s+1}
/// need observability, which the lag breaks; Tempo's set needs only reconstructibility (the
/// lag z_{t−1} is read from the last measurement), so ubb has a bounded set there.
const NO_SET: [Method; 2] = [Method::Scf, Method::Glls];

/// The Nile's first 60 years about their mean as an AR(1) z_{t+1} = 0.5 z_t + v_t embedded
/// with its lag, x_t = (z_t, z_{t−1}): F = [[0.5, 0], [1, 0]], only z_t measured. The lag never
/// reaches an output, so no number of measurements determines it.
fn nile_ar1() -> Value {
    let mean = NILE.iter().sum::<f64>() / NILE.len() as f64;
    let y: Vec<Value> = NILE[..60].iter().map(|v| json!([v - mean])).collect();
    json!({
        "method": "compare",
        "title": "The Nile as a lag-embedded AR(1)",
        "model": {"F": [[0.5, 0.0], [1.0, 0.0]], "H": [[1.0, 0.0]], "G": [[1.0], [0.0]],
                  "sigma_v2": 15000.0, "sigma_w2": 5000.0},
        "data": {"y": y},
        "alpha": 0.9,
        "compare": {"noise": "gaussian", "target": "predict", "window": 10}
    })
}

fn scenario(v: &Value) -> Scenario {
    Scenario::from_json(&v.to_string()).unwrap_or_else(|e| panic!("{e}"))
}

fn set_of<'a>(r: &'a Report, m: Method) -> &'a MethodSet {
    r.compare
        .as_ref()
        .expect("compare part")
        .at
        .sets
        .iter()
        .find(|s| s.method == m)
        .unwrap_or_else(|| panic!("no set entry of {m}"))
}

fn count<'a>(result: &'a Value, m: Method) -> &'a Value {
    result["methods"]
        .as_array()
        .expect("methods")
        .iter()
        .find(|c| c["method"] == m.name())
        .unwrap_or_else(|| panic!("no count of {m}"))
}

fn run_study(s: &Scenario) -> Value {
    let mut study = s.study(None).expect("study");
    while !study.finished() {
        study.step(50).expect("step");
    }
    study.result().expect("result")
}

/// The member's own scenario as the compare ran it (`sets[i].scenario`), run as its panel.
fn panel(set: &MethodSet) -> Report {
    let own = set
        .scenario
        .as_ref()
        .unwrap_or_else(|| panic!("{}: its own scenario", set.method));
    scenario(own)
        .run()
        .unwrap_or_else(|e| panic!("{}'s own scenario: {e}", set.method))
}

#[track_caller]
fn assert_ellipse_rel(a: &Ellipsoid, b: &Ellipsoid, tol: f64, what: &str) {
    assert_slice_rel(&a.center, &b.center, tol, &format!("{what}: centre"));
    for (ra, rb) in a.cov.iter().zip(&b.cov) {
        assert_slice_rel(ra, rb, tol, &format!("{what}: shape"));
    }
    assert!(rel_close(a.radius2, b.radius2, tol), "{what}: radius²");
}

/// The projection of an ellipsoid on components `idx`, computed here.
fn project(e: &Ellipsoid, idx: &[usize]) -> Ellipsoid {
    Ellipsoid {
        center: idx.iter().map(|&i| e.center[i]).collect(),
        cov: idx
            .iter()
            .map(|&i| idx.iter().map(|&j| e.cov[i][j]).collect())
            .collect(),
        radius2: e.radius2,
    }
}

/// F·E computed here: centre F·c, shape F·C·Fᵀ.
fn mapped(f: &DMatrix<f64>, e: &Ellipsoid) -> Ellipsoid {
    let c = f * DVector::from_column_slice(&e.center);
    let cov = f * from_rows(&e.cov) * f.transpose();
    Ellipsoid {
        center: c.iter().copied().collect(),
        cov: rows(&cov),
        radius2: e.radius2,
    }
}

// --- 1. no set is no miss -------------------------------------------------------------------

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn an_unobservable_record_gives_no_set_with_reasons() {
    let s = scenario(&nile_ar1());
    let r = s.run().expect("the compare runs");
    for m in NO_SET {
        let set = set_of(&r, m);
        assert!(
            set.set.is_none() && set.holds.is_none() && set.area.is_none(),
            "{m}: {set:?}"
        );
        let reason = set.reason.as_deref().expect("a reason");
        let remedy = set.remedy.as_deref().expect("a remedy");
        // Each member's own words, naming its own field.
        let (field, says) = match m {
            Method::Scf => ("report.steps.target.scf", "not observable"),
            Method::Glls => ("glls.horizon", "no horizon"),
            Method::Ubb => ("ubb.delta", "compare.members.ubb.delta"),
            _ => unreachable!(),
        };
        assert!(reason.starts_with(field), "{m}: {reason}");
        assert!(remedy.contains(says), "{m}: {remedy}");
    }
    // The others have their sets.
    for m in [
        Method::Kf,
        Method::Conformal,
        Method::Lscr,
        Method::UniformLp,
    ] {
        assert!(
            set_of(&r, m).set.is_some(),
            "{m}: {:?}",
            set_of(&r, m).reason
        );
    }
    // The CSV table: has_set 0 on their rows and a line naming each with its reason.
    let csv = r.table().expect("table").to_csv();
    let c = r.compare.as_ref().expect("compare");
    for (i, set) in c.at.sets.iter().enumerate() {
        let line = csv
            .lines()
            .find(|l| l.starts_with(&format!("{i},")))
            .expect("the method's row");
        assert_eq!(
            line.ends_with(",0"),
            NO_SET.contains(&set.method),
            "{}: {line}",
            set.method
        );
        let said = csv.lines().any(|l| {
            l.starts_with(&format!(
                "# warning: method {i} (\"{}\") has no set",
                set.method
            )) && l.contains(set.reason.as_deref().unwrap_or("?"))
        });
        assert_eq!(said, NO_SET.contains(&set.method), "{}: {csv}", set.method);
    }

    // Following ubb's remedy: a bound on x(0) gives it a set (the unobservable lag is bounded).
    let mut v = nile_ar1();
    v["compare"]["members"] = json!({"ubb": {"delta": [2000.0, 2000.0]}});
    let r = scenario(&v).run().expect("with δ");
    let ubb = set_of(&r, Method::Ubb);
    assert!(
        matches!(ubb.set, Some(PlaneSet::Polygon { .. })),
        "{:?}",
        ubb.reason
    );
    let row = &r.compare.as_ref().expect("c").rows;
    let row = row.iter().find(|r| r.method == Method::Ubb).expect("row");
    assert_eq!(row.options, Some(json!({"delta": [2000.0, 2000.0]})));
}
in_browser!(an_unobservable_record_gives_no_set_with_reasons);

/// The study on records drawn from the same model: the three members without a set count no
/// miss, get no band and no verdict ("does not apply", with their reason); the others' verdicts
/// are over all runs, against the exact binomial band computed here.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_study_counts_no_set_apart() {
    const RUNS: usize = 24;
    let mut v = nile_ar1();
    v.as_object_mut().expect("object").remove("data");
    v["simulate"] = json!({"steps": 60, "seed": 4});
    v["compare"]["study"] = json!({"x": [0.0, 0.0], "runs": RUNS, "seed": 2});
    let result = run_study(&scenario(&v));
    assert_eq!(result["runs"], RUNS);
    for c in result["methods"].as_array().expect("methods") {
        let m = c["method"].as_str().expect("name");
        let (holds, misses, no_set, with_set) = (
            c["holds"].as_u64().expect("holds") as usize,
            c["misses"].as_u64().expect("misses") as usize,
            c["no_set"].as_u64().expect("no_set") as usize,
            c["with_set"].as_u64().expect("with_set") as usize,
        );
        assert_eq!(holds + misses, with_set, "{m}");
        assert_eq!(with_set + no_set, RUNS, "{m}");
        let verdict = c["verdict"].as_str().expect("verdict");
        assert!(!verdict.contains("below"), "{m}: {verdict}");
        if NO_SET.iter().any(|x| x.name() == m) {
            assert_eq!((no_set, misses), (RUNS, 0), "{m}: no set is no miss");
            assert!(c["band"].is_null(), "{m}: no band over no runs");
            assert_eq!(verdict, "does not apply: no run gave a set (see why)");
            assert_eq!(c["standing"], "does_not_apply");
            assert!(
                c["no_set_reason"].as_str().is_some_and(|r| !r.is_empty()),
                "{m}"
            );
            assert!(
                c["no_set_remedy"].as_str().is_some_and(|r| !r.is_empty()),
                "{m}"
            );
        } else if let Some(level) = c["level"].as_f64() {
            assert_eq!(no_set, 0, "{m}: {c}");
            let (lo, hi) = binomial_interval(with_set, level, 0.999);
            assert_eq!(c["band"], json!([lo, hi]), "{m}");
        }
    }
}
in_browser!(the_study_counts_no_set_apart);

/// The verdict is over the runs with a set: a part whose Kalman count has 10 of 40 runs
/// without a set is merged, and the band is the exact binomial band of the 30 runs with one,
/// computed here; the verdict follows it (inside, then below), and no run without a set is a
/// miss.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_band_is_over_the_runs_with_a_set() {
    const RUNS: usize = 40;
    let mut s = presets::get("compare-gaussian").expect("preset");
    let c = s.compare.as_mut().expect("compare");
    c.methods = Some(vec![Method::Kf, Method::Scf]);
    c.study.as_mut().expect("study").runs = RUNS;
    let mut st = s.study(None).expect("study");
    while !st.finished() {
        st.step(RUNS).expect("runs");
    }
    let part = st.partial().expect("partial");
    let (lo, hi) = binomial_interval(RUNS - 10, 0.9, 0.999);
    assert!(lo > 0, "a band with room below it");
    for (holds, inside) in [(lo, true), (lo - 1, false)] {
        let mut p = part.clone();
        p["counts"]["holds"][0] = json!(holds);
        p["counts"]["no_set"][0] = json!(10);
        p["counts"]["no_set_first"][0] =
            json!({"run": 3, "reason": "kf: no set in this run", "remedy": "another run"});
        let mut merged = s.study(None).expect("study");
        merged.merge(&[p]).expect("merge");
        let result = merged.result().expect("result");
        let kf = count(&result, Method::Kf);
        assert_eq!(kf["with_set"], RUNS - 10);
        assert_eq!(kf["misses"], RUNS - 10 - holds);
        assert_eq!(kf["band"], json!([lo, hi]));
        assert_eq!(kf["no_set_reason"], "kf: no set in this run");
        let verdict = kf["verdict"].as_str().expect("verdict");
        let want = if inside {
            "inside the 99.9 % band of its promise (10 runs without a set not counted)"
        } else {
            "below the 99.9 % band of its promise (10 runs without a set not counted)"
        };
        assert_eq!(verdict, want);
        let standing = if inside {
            Standing::Kept
        } else {
            Standing::Broken
        };
        assert_eq!(
            kf["standing"],
            serde_json::to_value(standing).expect("json")
        );
    }
    // A reason without a run without a set (or the reverse) is no count of this study.
    let mut p = part.clone();
    p["counts"]["no_set"][0] = json!(1);
    let mut merged = s.study(None).expect("study");
    assert!(merged.merge(&[p]).is_err(), "no_set without a reason");
}
in_browser!(the_band_is_over_the_runs_with_a_set);

/// An empty set is a set: bounds at half the uniform noise's make the data contradict Tempo's
/// bounds, its solver finds no consistent state, and the set is empty. It holds no state: in
/// the report (`empty`, holds no), in the CSV (has_set 1, holds 0) and in the study, which
/// counts those runs as misses (none as runs without a set) and says the promise failed.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn an_empty_set_is_a_miss_not_no_set() {
    let mut s = presets::get("compare-uniform").expect("preset");
    let c = s.compare.as_mut().expect("compare");
    c.methods = Some(vec![Method::Ubb]);
    c.bound_scale = 0.5;
    c.study.as_mut().expect("study").runs = 30;
    let r = s.run().expect("report");
    let ubb = set_of(&r, Method::Ubb);
    assert!(ubb.set.is_none() && ubb.empty, "{ubb:?}");
    assert_eq!(ubb.holds, Some(false));
    assert!(ubb
        .reason
        .as_deref()
        .expect("reason")
        .contains("leaves no state consistent with the data"));
    assert!(ubb
        .remedy
        .as_deref()
        .expect("remedy")
        .contains("compare.bound_scale"));
    let csv = r.table().expect("table").to_csv();
    assert!(csv.lines().any(|l| l == "0,,0,1,0,1"), "{csv}");
    assert!(
        csv.contains("has an empty set (it holds no state)"),
        "{csv}"
    );
    let result = run_study(&s);
    let k = count(&result, Method::Ubb);
    assert_eq!(k["no_set"], 0, "{k}");
    assert_eq!(k["with_set"], 30);
    let misses = k["misses"].as_u64().expect("misses");
    assert!(misses > 0, "{k}");
    assert_eq!(
        k["verdict"],
        format!("failed {misses} times (its assumption is violated)")
    );
    assert_eq!(k["standing"], "broken");
}
in_browser!(an_empty_set_is_a_miss_not_no_set);

// --- 2. each member's options through its descriptor ----------------------------------------

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn member_options_reach_the_member() {
    let base =
        serde_json::to_value(presets::get("compare-gaussian").expect("preset")).expect("json");
    let mut v = base.clone();
    v["compare"]["members"] = json!({"glls": {"horizon": 6}, "lscr": {"M": 100, "q": 2}});
    let r = scenario(&v).run().expect("report");
    let glls = set_of(&r, Method::Glls);
    assert!(glls.set.is_some(), "{:?}", glls.reason);
    assert_eq!(
        glls.scenario.as_ref().expect("scenario")["glls"]["horizon"],
        6
    );
    assert!(glls
        .note
        .as_deref()
        .expect("note")
        .starts_with("horizon s = 6;"));
    assert_eq!(
        panel(glls).glls.as_ref().expect("glls").s,
        6,
        "the GLLS report's horizon"
    );
    // Without it the horizon is the method's own choice, not 6 here.
    let auto = scenario(&base).run().expect("report");
    assert_ne!(panel(set_of(&auto, Method::Glls)).glls.expect("glls").s, 6);
    // LSCR's M and q: the level 1 − 2qn/M (19) = 1 − 8/100 in its row and its report.
    let lscr = panel(set_of(&r, Method::Lscr)).lscr.expect("lscr");
    assert_eq!((lscr.m, lscr.q), (100, 2));
    let rows = &r.compare.as_ref().expect("c").rows;
    let row = rows.iter().find(|x| x.method == Method::Lscr).expect("row");
    assert!(close(row.level.expect("level"), 0.92, 1e-12));
    assert!(close(lscr.level, 0.92, 1e-12));
    // A horizon too short for the state: no set, and the remedy is a longer one.
    let mut v = base.clone();
    v["compare"]["members"] = json!({"glls": {"horizon": 0}});
    let r = scenario(&v).run().expect("report");
    let glls = set_of(&r, Method::Glls);
    assert!(glls.set.is_none());
    assert!(glls
        .remedy
        .as_deref()
        .expect("remedy")
        .starts_with("a longer horizon"));
    // Refused by name: an option the member does not pass, a value its block does not read,
    // a method the compare does not run.
    for (members, methods, field) in [
        (
            json!({"glls": {"mu": 1.0}}),
            None,
            "compare.members.glls.mu",
        ),
        (
            json!({"glls": {"horizon": "long"}}),
            None,
            "compare.members.glls.horizon",
        ),
        (
            json!({"kf": {"asymptotic": true}}),
            None,
            "compare.members.kf.asymptotic",
        ),
        (
            json!({"ubb": {"delta": [1.0, 1.0]}}),
            Some(json!(["kf", "scf"])),
            "compare.members.ubb",
        ),
        (
            json!({"ubb": {"delta": "wide"}}),
            None,
            "compare.members.ubb.delta",
        ),
    ] {
        let mut v = base.clone();
        v["compare"]["members"] = members.clone();
        if let Some(m) = methods {
            v["compare"]["methods"] = m;
        }
        let e = Scenario::from_json(&v.to_string())
            .and_then(|s| s.run())
            .expect_err(&format!("{members} is refused"));
        assert_eq!(e.field, field, "{members}: {e}");
    }
}
in_browser!(member_options_reach_the_member);

// --- 3. every model size --------------------------------------------------------------------

/// n = 1: an AR(1) local level, its x₄₁ predicted. Each member that applies gives an interval
/// holding its own centre (its panel's set, the Kalman one against the textbook filter here);
/// LSCR, Tempo and Pavelková say why they have none; the figure draws the rows.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_scalar_state_gives_intervals() {
    let v = json!({
        "method": "compare",
        "title": "A scalar local level",
        "model": {"F": [[0.95]], "H": [[1.0]], "G": [[1.0]], "sigma_v2": 0.1, "sigma_w2": 1.0},
        "simulate": {"steps": 40, "seed": 1},
        "alpha": 0.9,
        "compare": {"noise": "gaussian", "target": "predict", "study": {"x": [0.5], "runs": 20}}
    });
    let s = scenario(&v);
    let r = s.run().expect("n = 1 runs");
    assert_eq!(r.plot, vec![0]);
    let c = r.compare.as_ref().expect("compare");
    let truth = c.at.truth.as_ref().expect("truth");
    assert_eq!(truth.len(), 1);
    assert_eq!(truth[0], c.x_true.as_ref().expect("x")[40][0]);
    // The textbook filter's prediction of x₄₁ and its χ²₁(0.9) interval.
    let y: Vec<DVector<f64>> = r.y.iter().map(|v| DVector::from_column_slice(v)).collect();
    let (f, v1, w1) = (mat(&[&[0.95]]), mat(&[&[0.1]]), mat(&[&[1.0]]));
    let g1 = mat(&[&[0.1 / (1.0 - 0.95 * 0.95)]]);
    let kf = reference_kf(
        &f,
        &mat(&[&[1.0]]),
        &v1,
        &w1,
        &DVector::zeros(1),
        &g1,
        &DVector::zeros(1),
        &y,
    );
    let last = kf.last().expect("steps");
    let (m, p) = (0.95 * last.xhat[0], 0.95 * 0.95 * last.p[(0, 0)] + 0.1);
    let half = (ChiSquared::new(1.0).expect("χ²").inverse_cdf(0.9) * p).sqrt();
    let mut with_set = 0;
    for set in &c.at.sets {
        let Some(PlaneSet::Interval { lo, hi }) = set.set else {
            assert!(set.set.is_none(), "{}: {:?}", set.method, set.set);
            assert!(
                set.reason.is_some() && set.remedy.is_some(),
                "{}",
                set.method
            );
            assert!(
                [Method::Lscr, Method::Ubb, Method::UniformLp].contains(&set.method),
                "{}: {:?}",
                set.method,
                set.reason
            );
            continue;
        };
        with_set += 1;
        // LSCR (n = 1: X̂ as one interval of the line) and Tempo (n = 1: the interval hull of
        // its line recursion) are their own panels' intervals: a bounded interval whose
        // verdict is its own membership.
        if matches!(set.method, Method::Lscr | Method::Ubb) {
            assert!(lo < hi, "{}: [{lo}, {hi}]", set.method);
            assert!(
                close(set.area.expect("length"), hi - lo, 1e-9),
                "{}",
                set.method
            );
            assert_eq!(
                set.holds,
                Some(lo <= truth[0] && truth[0] <= hi),
                "{}",
                set.method
            );
            continue;
        }
        // The panel's own set of x₄₁, as an ellipsoid of one dimension.
        let own = panel(set);
        let e = match set.method {
            Method::Kf | Method::Scf => {
                let target = own
                    .steps
                    .last()
                    .and_then(|s| s.target.clone())
                    .expect("target");
                if set.method == Method::Kf {
                    target.kf
                } else {
                    target.scf.expect("SCF region")
                }
            }
            Method::Conformal => own.conformal.expect("conformal").region,
            Method::Glls => mapped(&f, &own.glls.expect("glls").ball_current),
            m => panic!("{m} gave an interval"),
        };
        let centre = e.center[0];
        let w = (e.radius2 * e.cov[0][0]).sqrt();
        assert!(
            lo <= centre && centre <= hi,
            "{}: {centre} in [{lo}, {hi}]",
            set.method
        );
        assert!(
            close(lo, centre - w, 1e-9) && close(hi, centre + w, 1e-9),
            "{}",
            set.method
        );
        assert!(
            close(set.area.expect("length"), hi - lo, 1e-9),
            "{}",
            set.method
        );
        assert_eq!(
            set.holds,
            Some(lo <= truth[0] && truth[0] <= hi),
            "{}",
            set.method
        );
        if set.method == Method::Kf {
            assert!(
                close(lo, m - half, 1e-9) && close(hi, m + half, 1e-9),
                "KF: [{lo}, {hi}] vs {m} ± {half}"
            );
        }
    }
    assert!(
        with_set >= 5,
        "KF, conformal, SCF, GLLS and Tempo's interval at least: {with_set}"
    );
    let svg = plot::report_svg(
        &r,
        &View::new(plot::Panel::from_name("compare").expect("panel")),
        800,
        500,
    )
    .expect("the intervals' figure");
    assert!(svg.contains("Every method") && svg.contains("no set"));
    // The study of a scalar state: the full state is one number.
    let result = run_study(&s);
    assert_eq!(result["x"], json!([0.5]));
    assert_eq!(
        count(&result, Method::UniformLp)["standing"],
        "does_not_apply"
    );
    assert_eq!(count(&result, Method::Kf)["with_set"], 20);
}
in_browser!(a_scalar_state_gives_intervals);

/// n = 3, drawn in the plane of x₁ and x₃: every set is of those two components, each against
/// its own panel's (projected here); LSCR and the uniform LP's prediction say why they have
/// none; with the filtered target the uniform LP's polygon is its panel's.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn three_states_in_a_chosen_plane() {
    let mut v = json!({
        "method": "compare",
        "title": "Three states, the plane of x₁ and x₃",
        "model": {"F": [[0.8, 0.1, 0.0], [0.0, 0.7, 0.2], [0.1, 0.0, 0.6]],
                  "H": [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]], "G": [[1.0], [0.5], [0.2]],
                  "sigma_v2": 0.05, "sigma_w2": 0.02},
        "simulate": {"steps": 30, "seed": 2},
        "alpha": 0.9,
        "compare": {"noise": "uniform", "target": "predict", "window": 8, "plane": [0, 2]}
    });
    let f = mat(&[&[0.8, 0.1, 0.0], &[0.0, 0.7, 0.2], &[0.1, 0.0, 0.6]]);
    let r = scenario(&v).run().expect("n = 3 runs");
    assert_eq!((r.n, r.plot.clone()), (3, vec![0, 2]));
    let c = r.compare.as_ref().expect("compare");
    let x = &c.x_true.as_ref().expect("x")[30];
    assert_eq!(c.at.truth, Some(vec![x[0], x[2]]));
    for set in &c.at.sets {
        let m = set.method;
        match m {
            Method::Lscr | Method::UniformLp => {
                let field = if m == Method::Lscr {
                    "compare.plane"
                } else {
                    "compare.target"
                };
                assert!(
                    set.reason.as_deref().expect("reason").starts_with(field),
                    "{m}"
                );
                assert!(set.remedy.is_some(), "{m}");
                continue;
            }
            _ => {}
        }
        let own = panel(set);
        let what = format!("{m} in the plane [0, 2]");
        match (&set.set, m) {
            (Some(PlaneSet::Ellipse(e)), Method::Kf | Method::Scf) => {
                let target = own
                    .steps
                    .last()
                    .and_then(|s| s.target.clone())
                    .expect("target");
                assert_eq!(target.components, vec![0, 2]);
                let want = if m == Method::Kf {
                    target.kf
                } else {
                    target.scf.expect("SCF")
                };
                assert_ellipse_rel(e, &want, 1e-9, &what);
            }
            (Some(PlaneSet::Ellipse(e)), Method::Conformal) => {
                let region = own.conformal.expect("conformal").region;
                assert_ellipse_rel(e, &project(&region, &[0, 2]), 1e-9, &what);
            }
            (Some(PlaneSet::Ellipse(e)), Method::Glls) => {
                // The ball of x_t carried by F (no state noise in GLLS), projected.
                let ball = own.glls.expect("glls").ball_current;
                assert_ellipse_rel(e, &project(&mapped(&f, &ball), &[0, 2]), 1e-9, &what);
            }
            (Some(PlaneSet::Polygon { vertices }), Method::Ubb) => {
                let u = own.ubb.expect("ubb");
                assert_eq!(u.plane, [0, 2]);
                assert_eq!(vertices, &u.at.polygon.vertices, "{what}");
            }
            (other, _) => panic!("{what}: {other:?} ({:?})", set.reason),
        }
        assert!(set.holds.is_some(), "{what}: a simulated truth is checked");
    }
    plot::report_svg(
        &r,
        &View::new(plot::Panel::from_name("compare").expect("panel")),
        800,
        500,
    )
    .expect("the plane's figure");
    // The filtered x₃₀: Pavelková's consistent set projected on the plane is its panel's.
    v["compare"]["target"] = json!("filter");
    let r = scenario(&v).run().expect("filter");
    let set = set_of(&r, Method::UniformLp);
    let own = panel(set).uniform.expect("uniform");
    match &set.set {
        Some(PlaneSet::Polygon { vertices }) => assert_eq!(
            vertices,
            &own.at.polygon.as_ref().expect("polygon").vertices
        ),
        other => panic!("uniform_lp: {other:?} ({:?})", set.reason),
    }
    // The plane is two different components below n, and only for n ≥ 3.
    for (plane, model) in [
        (json!([0, 3]), None),
        (json!([1, 1]), None),
        (json!([1, 0]), Some("cascade")),
    ] {
        let mut bad = v.clone();
        bad["compare"]["plane"] = plane.clone();
        if model.is_some() {
            bad = serde_json::to_value(presets::get("compare-gaussian").expect("preset"))
                .expect("json");
            bad["compare"]["plane"] = plane.clone();
        }
        let e = Scenario::from_json(&bad.to_string())
            .and_then(|s| s.run())
            .expect_err("refused");
        assert_eq!(e.field, "compare.plane", "{plane}: {e}");
    }
}
in_browser!(three_states_in_a_chosen_plane);

// --- 4. the step cap is the work budget's ---------------------------------------------------

/// The cascade on a record of `rows` rows as data (a deterministic signal: only its length
/// matters here).
fn cascade_on_rows(rows: usize) -> Scenario {
    let mut v =
        serde_json::to_value(presets::get("compare-gaussian").expect("preset")).expect("json");
    let o = v.as_object_mut().expect("object");
    o.remove("simulate");
    let y: Vec<Value> = (0..rows)
        .map(|k| json!([0.3 * (0.37 * k as f64).sin() + 0.05 * (1.3 * k as f64).cos()]))
        .collect();
    o.insert("data".into(), json!({ "y": y }));
    v["compare"]
        .as_object_mut()
        .expect("compare")
        .remove("study");
    scenario(&v)
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_step_cap_is_the_budgets() {
    // 203 rows (past the old cap of 150): cheap, so they run; Tempo's own scenario takes at
    // most 150 measurements, so it has no set and says which times would give one.
    let r = cascade_on_rows(203).run().expect("203 rows run");
    let c = r.compare.as_ref().expect("compare");
    assert_eq!((c.steps, c.at.t), (203, 203));
    // Every member, Tempo's included (its steps are held by the work budget too), has a set.
    for set in &c.at.sets {
        assert!(set.set.is_some(), "{}: {:?}", set.method, set.reason);
    }
    // 5,000 rows: refused by the budget, naming the record's field and the formula of its
    // largest term, before any work (the estimate alone refuses it, the same words).
    let huge = cascade_on_rows(5000);
    let e = huge.run().expect_err("5,000 rows are refused");
    assert_eq!(e.field, "data.y", "{e}");
    assert!(e.message.contains("is limited to about"), "{e}");
    // The largest term names its member and its formula (Tempo's steps², now that its steps are
    // held by the budget, not a cap).
    assert!(e.message.contains("(method \""), "{e}");
    assert!(e.message.contains(" · "), "{e}");
    let estimate = huge
        .work(Job::Report)
        .check(Job::Report)
        .expect_err("the estimate refuses");
    assert_eq!(estimate.to_string(), e.to_string());
    // Compare's step range is the widest of its members' (Tempo's steps, held by the budget
    // alone now, reach the scenario's count limit): past it only the budget refuses, as above.
    let limits = confset::scenario::limits();
    let most = limits["simulate.steps"]["compare"][1]
        .as_u64()
        .expect("compare's steps") as usize;
    let widest = confset::Method::ALL
        .iter()
        .filter(|m| **m != Method::Compare)
        .filter_map(|m| limits["simulate.steps"][m.name()][1].as_u64())
        .max()
        .expect("members") as usize;
    assert_eq!(most, widest);
}
in_browser!(the_step_cap_is_the_budgets);

// --- 5. gaps --------------------------------------------------------------------------------

/// A gap at data.y[19]: the compare takes the record; each member takes the gap as its own
/// method does (its descriptor's `gaps`), or has no set saying why and that t ≤ 19 gives one;
/// at t = 19 every member has its set. The report, its CSV and the cursor's detail hold the gap
/// as null and pass the finiteness check.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_gap_is_each_members_own() {
    let mut v = serde_json::to_value(cascade_on_rows(40)).expect("json");
    v["data"]["y"][19] = json!([null]);
    let s = scenario(&v);
    let r = s.run().expect("a compare takes a record with a gap");
    assert!(r.y[19][0].is_nan());
    assert!(
        r.warnings
            .iter()
            .any(|w| w.starts_with("data.y has 1 row with a gap (the first is data.y[19])")),
        "{:?}",
        r.warnings
    );
    let c = r.compare.as_ref().expect("compare");
    let mut refusing = 0;
    for set in &c.at.sets {
        if set.set.is_some() {
            continue;
        }
        refusing += 1;
        let reason = set.reason.as_deref().expect("reason");
        assert!(
            reason.contains("cannot take a gap"),
            "{}: {reason}",
            set.method
        );
        assert!(reason.starts_with("data.y[19]"), "{}: {reason}", set.method);
        assert!(
            set.remedy
                .as_deref()
                .expect("remedy")
                .starts_with("compare.time at most 19"),
            "{}: {:?}",
            set.method,
            set.remedy
        );
    }
    assert!(
        refusing > 0,
        "on this branch every member still refuses a gap"
    );
    let csv = r.table().expect("table").to_csv();
    assert!(
        csv.starts_with("# warning: data.y has 1 row with a gap"),
        "{csv}"
    );
    // Before the gap every member has its set, from the cursor as from a report at that time.
    let mut cursor = s.cursor().expect("cursor").expect("a compare has one");
    let detail = cursor.at(19).expect("t = 19");
    for set in detail["sets"].as_array().expect("sets") {
        assert!(set["set"].is_object(), "{}", set["method"]);
    }
    cursor
        .at(30)
        .expect("after the gap, the detail holds the gap as null");
    let mut early = v.clone();
    early["compare"]["time"] = json!(19);
    let r = scenario(&early).run().expect("t = 19");
    assert!(r
        .compare
        .expect("c")
        .at
        .sets
        .iter()
        .all(|s| s.set.is_some()));
}
in_browser!(a_gap_is_each_members_own);
