//! The compare scenario (every method on one record), natively and in the browser:
//!
//! * each method's set in the compare report is the set its own panel's report gives on the
//!   same scenario and data (the row's scenario), read here from that report's own fields
//!   (1e-9), and the cursor's detail at t is the report run at t;
//! * statistically, at a far-out true state under Gaussian noise (2,000 runs drawn given the
//!   state): SCF inside the 99.9 % binomial band of α, LSCR at or above the band of its level (a
//!   lower bound), Kalman far below α;
//! * under uniform noise within the bounds the set-membership sets never miss; with the bounds
//!   below the truth Tempo's misses and its row says the assumption is violated;
//! * a compare's own fields are refused by name.

use crate::common::*;
use confset::method::Method;
use confset::presets;
use confset::scenario::compare::{compared, PlaneSet, Target};
use confset::scenario::{Report, Scenario};
use confset::sets::{point_in_convex, Ellipsoid};
use nalgebra::DMatrix;

fn preset(name: &str) -> Scenario {
    presets::get(name).expect("compare preset")
}

fn ellipse(set: &Option<PlaneSet>, what: &str) -> Ellipsoid {
    match set {
        Some(PlaneSet::Ellipse(e)) => e.clone(),
        other => panic!("{what}: expected an ellipse, found {other:?}"),
    }
}

fn vertices(set: &Option<PlaneSet>, what: &str) -> Vec<[f64; 2]> {
    match set {
        Some(PlaneSet::Polygon { vertices }) => vertices.clone(),
        other => panic!("{what}: expected a polygon, found {other:?}"),
    }
}

#[track_caller]
fn assert_ellipse_eq(a: &Ellipsoid, b: &Ellipsoid, what: &str) {
    assert_slice_rel(&a.center, &b.center, 1e-9, &format!("{what}: centre"));
    for (ra, rb) in a.cov.iter().zip(&b.cov) {
        assert_slice_rel(ra, rb, 1e-9, &format!("{what}: covariance"));
    }
    assert!(
        rel_close(a.radius2, b.radius2, 1e-9),
        "{what}: radius² {} vs {}",
        a.radius2,
        b.radius2
    );
}

/// The compare report's sets against the method panels' reports on the rows' scenarios.
fn check_against_panels(s: &Scenario) {
    let report = s.run().expect("compare report");
    let c = report.compare.as_ref().expect("compare part");
    assert_eq!(c.target, Target::Predict);
    let f = DMatrix::from_row_slice(2, 2, &[0.5, 0.0, 1.0, 0.7]);
    assert_eq!(c.at.sets.len(), 7, "all seven methods");
    for (set, row) in c.at.sets.iter().zip(&c.rows) {
        let m = set.method;
        assert_eq!(row.method, m);
        assert!(set.reason.is_none(), "{m}: {:?}", set.reason);
        let own = Scenario::from_json(
            &set.scenario
                .as_ref()
                .unwrap_or_else(|| panic!("{m}: its own scenario"))
                .to_string(),
        )
        .unwrap_or_else(|e| panic!("{m}: its own scenario parses: {e}"));
        assert_eq!(own.method, m);
        assert_eq!(
            own.data.as_ref().expect("data").y,
            report.y[..c.at.t].to_vec(),
            "{m}: the record up to t"
        );
        let panel: Report = own
            .run()
            .unwrap_or_else(|e| panic!("{m}'s own scenario: {e}"));
        assert_eq!(panel.method, m);
        let what = format!("{m} at t = {}", c.at.t);
        match m {
            Method::Kf | Method::Scf => {
                let step = panel.steps.last().expect("steps");
                assert_eq!(step.t, c.at.t);
                let target = step.target.as_ref().expect("the x_(t+1) region");
                assert_eq!(target.time, c.at.target_time);
                let own = if m == Method::Kf {
                    target.kf.clone()
                } else {
                    target.scf.clone().expect("SCF region")
                };
                assert_ellipse_eq(&ellipse(&set.set, &what), &own, &what);
            }
            Method::Lscr => {
                let l = panel.lscr.as_ref().expect("lscr");
                assert_eq!(l.time, c.at.target_time);
                match &set.set {
                    Some(PlaneSet::Region { loops, bounded, .. }) => {
                        assert_eq!(loops, &l.boundary, "{what}: boundary");
                        assert_eq!(*bounded, l.bounded);
                    }
                    other => panic!("{what}: {other:?}"),
                }
                assert_eq!(set.area, l.bounded.then_some(l.area));
                if let Some(x) = &c.at.truth {
                    assert_eq!(set.holds, Some(l.region.contains(x)));
                }
            }
            Method::Glls => {
                // The ball is of x_t; F·ball is the prediction set (no state noise in GLLS).
                let g = panel.glls.as_ref().expect("glls");
                assert_eq!(g.k + 1, c.at.t, "GLLS's current time k is 0-based");
                let b = &g.ball_current;
                let cov = DMatrix::from_fn(2, 2, |i, j| b.cov[i][j]);
                let fc = &f * cov * f.transpose();
                let e = ellipse(&set.set, &what);
                let centre = [0.5 * b.center[0], b.center[0] + 0.7 * b.center[1]];
                assert_slice_rel(&e.center, &centre, 1e-9, &format!("{what}: F·centre"));
                for i in 0..2 {
                    assert_slice_rel(
                        &e.cov[i],
                        &[fc[(i, 0)], fc[(i, 1)]],
                        1e-9,
                        &format!("{what}: F·cov·Fᵀ"),
                    );
                }
                assert!(rel_close(e.radius2, b.radius2, 1e-12));
            }
            Method::Ubb => {
                let u = panel.ubb.as_ref().expect("ubb");
                assert_eq!(
                    u.at.k + 1,
                    c.at.t,
                    "Tempo's k is 0-based: x(k+1) is x_(t+1)"
                );
                assert_eq!(
                    vertices(&set.set, &what),
                    u.at.polygon.vertices,
                    "{what}: polygon"
                );
            }
            Method::UniformLp => {
                // F·P ⊕ G·[−b_v, b_v]: every image of a vertex of P shifted by ±G·b_v lies in
                // the compare polygon, and every compare vertex is one of those images.
                let w = panel.uniform.as_ref().expect("uniform");
                assert_eq!(w.at.time, c.at.t);
                let p =
                    w.at.polygon
                        .as_ref()
                        .expect("consistent polygon")
                        .vertices
                        .clone();
                let v = vertices(&set.set, &what);
                let images: Vec<[f64; 2]> = p
                    .iter()
                    .flat_map(|q| {
                        let fq = [0.5 * q[0], q[0] + 0.7 * q[1]];
                        [-1.0, 1.0].map(|s| [fq[0] + s * c.bound_v, fq[1]])
                    })
                    .collect();
                for im in &images {
                    assert!(
                        point_in_convex(&v, *im, 1e-9),
                        "{what}: image {im:?} outside the sum"
                    );
                }
                for x in &v {
                    assert!(
                        images
                            .iter()
                            .any(|im| (im[0] - x[0]).abs() + (im[1] - x[1]).abs() <= 1e-12),
                        "{what}: vertex {x:?} is no image"
                    );
                }
            }
            // Every arm is written out: a method that joins a compare gets its check here.
            Method::Compare => panic!("a compare does not compare itself"),
            Method::Conformal => {
                // The conformal region of x_{t+1}: the panel's own, projected on the plane.
                let own = panel.conformal.as_ref().expect("conformal");
                assert_eq!(own.time + own.tau, c.at.target_time, "{what}: target time");
                let plane = own.region.project(&[0, 1]).expect("projection");
                assert_ellipse_eq(&ellipse(&set.set, &what), &plane, &what);
            }
        }
    }
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn each_set_is_its_own_panels_set() {
    for name in ["compare-gaussian", "compare-uniform"] {
        check_against_panels(&preset(name));
        // Another time: the record's first 12 rows.
        let mut s = preset(name);
        s.compare.as_mut().expect("compare").time = Some(12);
        check_against_panels(&s);
    }
}
in_browser!(each_set_is_its_own_panels_set);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_cursor_detail_is_the_report_at_that_time() {
    let s = preset("compare-uniform");
    let mut cursor = s.cursor().expect("cursor").expect("a compare has a cursor");
    assert_eq!(cursor.steps(), 2..=30);
    for t in [2, 9, 30] {
        let mut at_t = s.clone();
        at_t.compare.as_mut().expect("compare").time = Some(t);
        let report = at_t.run().expect("report at t");
        let detail = cursor.at(t).expect("detail");
        assert_eq!(
            detail,
            serde_json::to_value(&report.compare.as_ref().expect("compare").at).expect("json"),
            "t = {t}"
        );
        // And set into the report of another time, it is that report's detail.
        let mut kept = s.run().expect("report");
        kept.set_at(detail).expect("set_at");
        assert_eq!(kept.time, t);
        assert_eq!(
            kept.compare.as_ref().expect("c").at,
            report.compare.as_ref().expect("c").at
        );
    }
}
in_browser!(the_cursor_detail_is_the_report_at_that_time);

/// The study's result for one method (the native studies below).
#[cfg(not(target_arch = "wasm32"))]
fn count<'a>(result: &'a serde_json::Value, m: &str) -> &'a serde_json::Value {
    result["methods"]
        .as_array()
        .expect("methods")
        .iter()
        .find(|c| c["method"] == m)
        .unwrap_or_else(|| panic!("no count of {m}"))
}

#[cfg(not(target_arch = "wasm32"))]
fn run_study(s: &Scenario) -> serde_json::Value {
    let mut study = s.study(None).expect("study");
    while !study.finished() {
        study.step(100).expect("step");
    }
    study.result().expect("result")
}

/// Far out under Gaussian noise, 2,000 records drawn given x₃₁: SCF "for every state" keeps
/// α, LSCR keeps its level, Kalman's "on average" does not hold at this state.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn far_out_gaussian_state_counts() {
    const RUNS: usize = 2000;
    let mut s = preset("compare-gaussian");
    let c = s.compare.as_mut().expect("compare");
    c.methods = Some(vec![Method::Kf, Method::Scf, Method::Lscr]);
    c.study.as_mut().expect("study").runs = RUNS;
    let result = run_study(&s);
    assert_eq!(result["runs"], RUNS);
    assert!(result["conditioning"]
        .as_str()
        .expect("text")
        .starts_with("exact"));
    let holds = |m: &str| count(&result, m)["holds"].as_u64().expect("holds") as usize;
    let (lo, hi) = binomial_interval(RUNS, 0.9, 0.999);
    let scf = holds("scf");
    assert!(
        (lo..=hi).contains(&scf),
        "SCF {scf}/{RUNS} outside [{lo}, {hi}] around α = 0.9"
    );
    assert_eq!(
        count(&result, "scf")["verdict"],
        "inside the 99.9 % band of its promise"
    );
    let level = count(&result, "lscr")["level"]
        .as_f64()
        .expect("LSCR level");
    let (llo, _) = binomial_interval(RUNS, level, 0.999);
    let lscr = holds("lscr");
    assert!(
        lscr >= llo,
        "LSCR {lscr}/{RUNS} below the band [{llo}, …] of its level {level}"
    );
    let kf = holds("kf");
    assert!(
        kf < RUNS / 2,
        "Kalman {kf}/{RUNS} at a far-out state: expected far below α = 0.9"
    );
    assert_eq!(
        count(&result, "kf")["verdict"],
        "below the 99.9 % band of its promise"
    );
}

/// Uniform noise within the bounds: Tempo's and Pavelková's sets never miss; bounds at half the
/// truth: Tempo's misses, and its row says why.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn uniform_noise_bounds_hold_and_fail() {
    let mut s = preset("compare-uniform");
    let c = s.compare.as_mut().expect("compare");
    c.methods = Some(vec![Method::Ubb, Method::UniformLp]);
    c.study.as_mut().expect("study").runs = 300;
    let result = run_study(&s);
    assert!(result["conditioning"]
        .as_str()
        .expect("text")
        .starts_with("unconditional"));
    for m in ["ubb", "uniform_lp"] {
        assert_eq!(count(&result, m)["misses"], 0, "{m}: {result}");
    }
    assert_eq!(count(&result, "ubb")["verdict"], "never failed");
    let report = s.run().expect("report");
    assert!(
        report
            .compare
            .as_ref()
            .expect("c")
            .rows
            .iter()
            .all(|r| r.met),
        "uniform noise within its bounds meets both"
    );

    s.compare.as_mut().expect("compare").bound_scale = 0.5;
    s.compare.as_mut().expect("compare").methods = Some(vec![Method::Ubb]);
    let result = run_study(&s);
    let misses = count(&result, "ubb")["misses"].as_u64().expect("misses");
    assert!(
        misses > 0,
        "bounds at half the noise's: Tempo must miss ({result})"
    );
    assert!(count(&result, "ubb")["verdict"]
        .as_str()
        .expect("v")
        .contains("violated"));
    let report = s.run().expect("report");
    let row = &report.compare.as_ref().expect("c").rows[0];
    assert!(!row.met);
    assert!(row
        .violated
        .as_deref()
        .expect("why")
        .starts_with("violated: the bounds are 0.5×"));
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_table_says_which_assumptions_hold() {
    let report = preset("compare-gaussian").run().expect("report");
    let rows = &report.compare.as_ref().expect("c").rows;
    let row = |m: Method| rows.iter().find(|r| r.method == m).expect("row");
    assert!(row(Method::Kf).met && row(Method::Scf).met && row(Method::Lscr).met);
    assert!(row(Method::Ubb)
        .violated
        .as_deref()
        .expect("why")
        .contains("Gaussian noise is unbounded"));
    assert!(row(Method::UniformLp)
        .violated
        .as_deref()
        .expect("why")
        .contains("noise not uniform"));
    assert!(row(Method::Glls)
        .violated
        .as_deref()
        .expect("why")
        .contains("state noise"));
    let uniform = preset("compare-uniform").run().expect("report");
    let rows = &uniform.compare.as_ref().expect("c").rows;
    let kf = rows.iter().find(|r| r.method == Method::Kf).expect("kf");
    assert_eq!(
        kf.violated.as_deref(),
        Some("violated: noise not Gaussian (uniform)")
    );
    // The far-out preset: Kalman misses, SCF and LSCR hold.
    let c = report.compare.as_ref().expect("c");
    let holds = |m: Method| {
        c.at.sets
            .iter()
            .find(|s| s.method == m)
            .and_then(|s| s.holds)
    };
    assert_eq!(holds(Method::Kf), Some(false));
    assert_eq!(holds(Method::Scf), Some(true));
    assert_eq!(holds(Method::Lscr), Some(true));
}
in_browser!(the_table_says_which_assumptions_hold);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_compare_refuses_by_field() {
    let base = serde_json::to_value(preset("compare-uniform")).expect("json");
    let cases: Vec<(serde_json::Value, &str)> = vec![
        (
            serde_json::json!({"compare": {"bound_scale": 0.0}}),
            "compare.bound_scale",
        ),
        (
            serde_json::json!({"compare": {"bound_sigmas": 1e9}}),
            "compare.bound_sigmas",
        ),
        (
            serde_json::json!({"compare": {"window": 0}}),
            "compare.window",
        ),
        (
            serde_json::json!({"compare": {"methods": ["kf", "compare"]}}),
            "compare.methods[1]",
        ),
        (
            serde_json::json!({"compare": {"methods": []}}),
            "compare.methods",
        ),
        (serde_json::json!({"compare": {"time": 31}}), "compare.time"),
        (
            serde_json::json!({"simulate": {"condition": {"t": 31, "x": [0.0, 0.0]}}}),
            "simulate.condition",
        ),
        (
            serde_json::json!({"model": {"F": [[0.5, 0, 0], [1, 0.7, 0], [0, 0, 0.1]], "H": [[0, 1, 0]], "G": [[1], [0], [0]]}, "compare": {"plane": [0, 3]}}),
            "compare.plane",
        ),
        (
            serde_json::json!({"compare": {"plane": [1, 0]}}),
            "compare.plane",
        ),
        (
            serde_json::json!({"compare": {"members": {"glls": {"mu": 1}}}}),
            "compare.members.glls.mu",
        ),
        (
            serde_json::json!({"model": {"B": [[1.0], [0.0]]}}),
            "model.B",
        ),
    ];
    for (patch, field) in cases {
        let mut v = base.clone();
        merge(&mut v, &patch);
        let err = Scenario::from_json(&v.to_string())
            .and_then(|s| s.run())
            .expect_err(&format!("{patch} is refused"));
        assert!(
            err.to_string().starts_with(field),
            "{patch}: expected {field}, got {err}"
        );
    }
}
in_browser!(a_compare_refuses_by_field);

fn merge(a: &mut serde_json::Value, b: &serde_json::Value) {
    match (a, b) {
        (serde_json::Value::Object(a), serde_json::Value::Object(b)) => {
            for (k, v) in b {
                merge(a.entry(k.clone()).or_insert(serde_json::Value::Null), v);
            }
        }
        (a, b) => *a = b.clone(),
    }
}

/// The user's own record (CSV, one column per output): every method runs on it, with no truth.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn own_csv_data_runs_every_method_without_truth() {
    let simulated = preset("compare-uniform").run().expect("report");
    let csv: String = simulated.y.iter().map(|r| format!("{}\n", r[0])).collect();
    let s = preset("compare-uniform")
        .with_csv_data(&csv)
        .expect("CSV data");
    assert!(s.simulate.is_none() && s.data.is_some());
    let report = s.run().expect("report on data");
    let c = report.compare.as_ref().expect("compare");
    assert!(c.x_true.is_none() && c.at.truth.is_none());
    for (own, sim) in
        c.at.sets
            .iter()
            .zip(&simulated.compare.as_ref().expect("c").at.sets)
    {
        assert!(own.set.is_some(), "{}: {:?}", own.method, own.reason);
        assert_eq!(own.holds, None, "{}: no truth, no verdict", own.method);
        assert_eq!(
            own.area, sim.area,
            "{}: the same record, the same set",
            own.method
        );
    }
}
in_browser!(own_csv_data_runs_every_method_without_truth);

/// The methods of a compare are found, not listed: those whose scenario file answers what a
/// compare asks (`compare::compared()`, in their order). The report's rows and sets follow
/// them, the refusal of any other method names exactly them, and each method's derived
/// scenario is a scenario file that reads back as itself.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_members_are_found_not_listed() {
    let members = compared();
    assert!(!members.contains(&Method::Compare));
    for (i, m) in members.iter().enumerate() {
        assert!(!members[..i].contains(m), "{m} twice");
    }
    let report = preset("compare-uniform").run().expect("report");
    let c = report.compare.as_ref().expect("compare");
    let rows: Vec<Method> = c.rows.iter().map(|r| r.method).collect();
    let sets: Vec<Method> = c.at.sets.iter().map(|s| s.method).collect();
    assert_eq!(rows, members);
    assert_eq!(sets, members);
    for set in &c.at.sets {
        let written = set.scenario.clone().expect("its own scenario");
        let read = Scenario::from_json(&written.to_string())
            .unwrap_or_else(|e| panic!("{}: {e}", set.method));
        assert_eq!(
            serde_json::to_value(&read).expect("json"),
            written,
            "{}: the derived scenario reads back as itself",
            set.method
        );
    }
    let mut v = serde_json::to_value(preset("compare-uniform")).expect("json");
    v["compare"]["methods"] = serde_json::json!(["compare"]);
    let err = Scenario::from_json(&v.to_string())
        .and_then(|s| s.run())
        .expect_err("compare in a compare");
    let names: Vec<&str> = members.iter().map(|m| m.name()).collect();
    let (last, rest) = names.split_last().expect("members");
    assert_eq!(
        err.to_string(),
        format!(
            "compare.methods[0] is \"compare\": a compare runs {} and {last}",
            rest.join(", ")
        )
    );
}
in_browser!(the_members_are_found_not_listed);
