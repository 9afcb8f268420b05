//! Correct or refused (issue 25): a merge takes no count above its runs, no wrapped sum and no
//! part file whose shard, range, run count or scenario disagree with its counts; no output
//! (report, study result, merged result, CSV table) holds a number that is not finite; an
//! absent comparison is an absent key, never `null`; a basis function's period too short for
//! double precision is blamed on `ubb.basis[i]`.

use crate::shards::{one_per_method, shard_part};
use confset::scenario::Scenario;
use confset::study::{add_count, run_to_end, Tally};
use confset::{presets, Error};
use serde_json::{json, Value};

/// The JSON of a preset.
fn preset(name: &str) -> Value {
    serde_json::to_value(presets::get(name).expect("preset")).expect("json")
}

fn scenario(v: &Value) -> Scenario {
    Scenario::from_json(&v.to_string()).unwrap_or_else(|e| panic!("{e}"))
}

/// Merge `parts` into a fresh study of `s` with `runs` runs, complete, and its result.
fn merged(s: &Scenario, runs: usize, parts: &[Value]) -> Result<Value, Error> {
    let mut st = s.study(Some(runs))?;
    st.merge(parts)?;
    st.complete()?;
    st.result()
}

/// The paths of every whole-number count under a partial's `counts` but `runs`
/// (`kf_inside`, `inside_each[1]`); the GLLS errors (floats, no `runs` key) have none.
fn count_paths(counts: &Value) -> Vec<(String, Vec<Value>)> {
    let Some(o) = counts.as_object().filter(|o| o.contains_key("runs")) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (k, v) in o {
        match v {
            _ if k == "runs" => {}
            Value::Number(n) if n.is_u64() => out.push((k.clone(), vec![json!(k)])),
            Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    if x.is_u64() {
                        out.push((format!("{k}[{i}]"), vec![json!(k), json!(i)]));
                    }
                }
            }
            _ => {}
        }
    }
    out
}

/// The entry of `v` at a path of keys and indices.
fn at<'a>(v: &'a mut Value, path: &[Value]) -> &'a mut Value {
    path.iter().fold(v, |v, p| match p {
        Value::String(k) => &mut v[k.as_str()],
        Value::Number(i) => &mut v[i.as_u64().unwrap() as usize],
        _ => unreachable!(),
    })
}

/// Every count of every method's partial set one above its runs, and to 2^64 − 1, is refused
/// naming the part and the field; with the old merge, 1,000,000 hits in 8 runs were accepted.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn merge_refuses_counts_above_their_runs() {
    let mut studies = one_per_method();
    assert!(!studies.is_empty(), "no preset has a study");
    // The LSCR presets have no coverage block: one with it.
    studies.push(("lscr-smooth with coverage".into(), lscr_smooth_coverage(9)));
    let mut checked = 0;
    for (name, s) in &studies {
        let runs = 9;
        let part = shard_part(name, s, runs, (0, 1), 50);
        merged(s, runs, std::slice::from_ref(&part))
            .unwrap_or_else(|e| panic!("{name}: the untouched part: {e}"));
        for (field, path) in count_paths(&part["counts"]) {
            for bad in [runs as u64 + 1, u64::MAX] {
                let mut p = part.clone();
                *at(&mut p["counts"], &path) = json!(bad);
                let e = merged(s, runs, &[p])
                    .expect_err(&format!("{name}: counts.{field} = {bad} in {runs} runs"));
                if bad <= usize::MAX as u64 {
                    let want =
                        format!("part 1's counts.{field} is {bad}, more than the {runs} runs");
                    assert!(e.message.contains(&want), "{name}: {e}\n(wanted: {want})");
                } else {
                    // 2⁶⁴ − 1 is past a 32-bit usize (wasm32): refused as it is read, at its path.
                    assert_eq!(e.field, format!("partial.counts.{field}"), "{name}: {e}");
                }
                checked += 1;
            }
        }
        // Compare: a run holds, misses or gives no set, so holds + no_set is a count too.
        if part["counts"].get("no_set").is_some() {
            let mut p = part.clone();
            p["counts"]["holds"][0] = json!(runs);
            p["counts"]["no_set"][0] = json!(1);
            let e = merged(s, runs, &[p]).expect_err("holds + no_set above runs");
            assert!(
                e.message.contains("counts.holds[0] + no_set[0] is 10"),
                "{name}: {e}"
            );
        }
    }
    assert!(checked >= 8, "only {checked} counts were tampered with");
}
in_browser!(merge_refuses_counts_above_their_runs);

/// A sum of counts is checked: 2^64 − 1 + 2 is an error, not 1 (the release build wrapped).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn count_sums_are_checked_not_wrapped() {
    let mut a = usize::MAX;
    let e = add_count(&mut a, 2, "kf_inside").expect_err("overflow");
    assert!(e.contains("kf_inside overflows"), "{e}");
    assert_eq!(a, usize::MAX, "a refused sum leaves the count");

    use confset::scf::experiment::ConditionalCounts;
    let mut c = ConditionalCounts {
        runs: 8,
        kf_inside: usize::MAX,
        ..Default::default()
    };
    let later = ConditionalCounts {
        runs: 8,
        kf_inside: 2,
        ..Default::default()
    };
    let e = c.add(&later).expect_err("SCF counts overflow");
    assert!(e.contains("kf_inside overflows"), "{e}");

    let mut l = confset::lscr::Coverage {
        runs: 1,
        inside_each: vec![0, usize::MAX],
        inside: 0,
        blue: Some(0),
        kf: None,
    };
    let mut later = l.clone();
    later.inside_each[1] = 2;
    let e = l.add(&later).expect_err("LSCR counts overflow");
    assert!(e.contains("inside_each[1] overflows"), "{e}");

    use confset::scenario::ubb::GuaranteeCount;
    let mut g = GuaranteeCount {
        runs: 3,
        outside: 0,
        kf_outside: usize::MAX,
        empty: 0,
        worst_excess: -1.0,
    };
    let later = GuaranteeCount { kf_outside: 2, ..g };
    let e = g.add(&later).expect_err("ubb counts overflow");
    assert!(e.contains("kf_outside overflows"), "{e}");

    use confset::scenario::compare::CompareCounts;
    let mut c = CompareCounts {
        runs: 1,
        holds: vec![usize::MAX, 0],
        no_set: vec![0, 0],
        no_set_first: vec![None, None],
    };
    let later = CompareCounts {
        runs: 1,
        holds: vec![2, 0],
        no_set: vec![0, 0],
        no_set_first: vec![None, None],
    };
    let e = c.add(&later).expect_err("compare counts overflow");
    assert!(e.contains("holds[0] overflows"), "{e}");
    // Another shape is refused even against no runs (the old add took it as it was).
    let mut zero = CompareCounts {
        runs: 0,
        holds: vec![0, 0],
        no_set: vec![0, 0],
        no_set_first: vec![None, None],
    };
    let e = zero.add(&CompareCounts {
        runs: 1,
        holds: vec![1],
        no_set: vec![0],
        no_set_first: vec![None],
    });
    assert!(e.is_err(), "counts of 1 method merged into a study of 2");
}
in_browser!(count_sums_are_checked_not_wrapped);

/// `experiment` on glls-grow with 1000 steps (the limit is 5000): the states overflow, and the
/// study is refused naming its field, as `run` refuses the same scenario; the old result held
/// `"mean_state_norm": null` and exited 0.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn an_overflowing_study_is_refused_naming_its_field() {
    let mut v = preset("glls-grow");
    v["glls"]["monte_carlo"]["steps"] = json!(1000);
    let s = scenario(&v);
    let mut st = s.study(Some(20)).expect("the study is accepted");
    let e = run_to_end(st.as_mut(), 7, |_, _| {}).expect_err("overflowing study");
    assert!(e.field.starts_with("study."), "{e}");
    assert!(
        e.message.contains("is not a finite number") && e.message.contains("lower the steps"),
        "{e}"
    );
    let e = s.run().expect_err("run refuses it too");
    assert!(e.field.starts_with("report.glls.precision."), "{e}");
}
in_browser!(an_overflowing_study_is_refused_naming_its_field);

/// Parts whose numbers are finite but add past the largest double (state norms of 1e308):
/// the merged result is refused naming `study.mean_state_norm`, and says the parts may be
/// the cause; the old merge printed `null`.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_merge_whose_numbers_overflow_is_refused() {
    let s = presets::get("glls-saturate").expect("preset");
    let runs = 6;
    let parts: Vec<Value> = (0..2)
        .map(|i| {
            let mut p = shard_part("glls-saturate", &s, runs, (i, 2), 5);
            p["counts"]["state_norms"] = json!([1e308, 1e308, 1e308]);
            p
        })
        .collect();
    let e = merged(&s, runs, &parts).expect_err("1e308 × 6 / 6");
    assert_eq!(e.field, "study.mean_state_norm", "{e}");
    assert!(e.message.contains("the parts' own numbers"), "{e}");
}
in_browser!(a_merge_whose_numbers_overflow_is_refused);

/// scf-robots with V × 1e90 (every number within 1e100): the JSON report is finite, but the
/// CSV table's region volumes overflow; the table is refused naming the column and the time
/// (the old table wrote 112 `inf` cells).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_csv_table_with_an_infinite_cell_is_refused() {
    let mut v = preset("scf-robots");
    for row in v["model"]["V"].as_array_mut().expect("V is a matrix") {
        for x in row.as_array_mut().expect("a row") {
            *x = json!(x.as_f64().unwrap() * 1e90);
        }
    }
    let report = scenario(&v).run().expect("the JSON report is finite");
    let e = report.table().expect_err("infinite volumes");
    assert!(
        e.field.starts_with("csv.") && e.field.contains(" at t="),
        "{e}"
    );
    assert!(e.message.contains("is not a finite number"), "{e}");
    // The presets' tables are finite.
    let table = presets::get("scf-robots").unwrap().run().unwrap().table();
    assert!(table.is_ok(), "{:?}", table.err());
}
in_browser!(a_csv_table_with_an_infinite_cell_is_refused);

/// lscr-smooth (a smoothing target: no Kalman comparison) with a coverage study of `runs`.
fn lscr_smooth_coverage(runs: usize) -> Scenario {
    let mut v = preset("lscr-smooth");
    v["lscr"]["coverage"] = json!({"runs": runs, "seed": 3});
    v["simulate"]["condition"] = json!({"t": 15, "x": [0.3, -0.4]});
    scenario(&v)
}

/// lscr-smooth's coverage has no Kalman comparison (smoothing): the key is absent from the
/// result and the partials, never `null`; shards still merge to the same result.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn an_absent_comparison_is_an_absent_key() {
    let s = lscr_smooth_coverage(12);
    let mut st = s.study(None).expect("study");
    let whole = run_to_end(st.as_mut(), 5, |_, _| {}).expect("result");
    let part = st.partial().expect("partial");
    for (what, x) in [("result", &whole), ("partial", &part)] {
        assert!(!x.to_string().contains("null"), "{what}: {x}");
    }
    assert!(
        whole.get("kf").is_none() && whole.get("blue").is_some(),
        "{whole}"
    );
    let parts: Vec<Value> = (0..2)
        .map(|i| shard_part("lscr-smooth", &s, 12, (i, 2), 5))
        .collect();
    assert_eq!(merged(&s, 12, &parts).expect("merge"), whole);
}
in_browser!(an_absent_comparison_is_an_absent_key);

/// A `sin:P` or `cos:P` basis whose phase 2πk/P is past what a double resolves is blamed on
/// its entry `ubb.basis[i]` (the old message blamed model.F's powers).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_basis_period_too_short_is_blamed_on_its_entry() {
    for bad in ["sin:1e-308", "cos:1e-300", "sin:1e-10"] {
        let mut v = preset("ubb-series");
        v["ubb"]["basis"][1] = json!(bad);
        let e = scenario(&v).run().expect_err(bad);
        assert_eq!(e.field, "ubb.basis[1]", "{bad}: {e}");
        assert!(
            e.message.contains("the period") && e.message.contains("must be at least"),
            "{bad}: {e}"
        );
    }
    let mut v = preset("ubb-series");
    v["ubb"]["basis"][1] = json!("sin:12");
    scenario(&v).run().expect("a period of 12 steps");
}
in_browser!(a_basis_period_too_short_is_blamed_on_its_entry);

/// `confset merge` names each part by its file, and refuses a file whose `shard`, `range`,
/// `runs`, `partial.total` or scenario disagree with its counts or with part 1, or whose counts
/// exceed its runs.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn cli_merge_checks_each_part_file() {
    let run = crate::cli::confset;
    let dir = std::env::temp_dir().join(format!("confset-merge-checks-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let part = |args: &[&str]| -> Value {
        let out = run(args, None);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).expect("a part is JSON")
    };
    let shard = |i: usize| {
        part(&[
            "experiment",
            "--preset",
            "scf-robots",
            "--runs",
            "16",
            "--shard",
            &format!("{i}/2"),
        ])
    };
    let (a, b) = (shard(0), shard(1));
    let write = |name: &str, v: &Value| {
        let f = dir.join(name);
        std::fs::write(&f, v.to_string()).expect("write a part");
        f.to_string_lossy().into_owned()
    };
    let (fa, fb) = (write("a.json", &a), write("b.json", &b));
    let good = run(&["merge", &fa, &fb], None);
    assert!(
        good.status.success(),
        "{}",
        String::from_utf8_lossy(&good.stderr)
    );

    // Part 2 (runs 8..16) edited.
    let refused = |edited: &Value, words: &[&str]| {
        let f = write("edited.json", edited);
        let out = run(&["merge", &fa, &f], None);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && out.stdout.is_empty(),
            "accepted: {edited}"
        );
        assert!(err.contains(&format!("part 2 ({f})")), "{err}");
        for w in words {
            assert!(err.contains(w), "{err}\n(wanted: {w})");
        }
    };
    let mut e = b.clone();
    e["partial"]["counts"]["kf_inside"] = json!(1_000_000);
    refused(&e, &["counts.kf_inside is 1000000, more than the 8 runs"]);
    let mut e = b.clone();
    e["partial"]["counts"]["scf_inside"] = json!(u64::MAX);
    refused(&e, &["counts.scf_inside is 18446744073709551615"]);
    let mut e = b.clone();
    e["shard"] = json!([0, 2]);
    refused(&e, &["'s shard 0/2 holds runs 0..8", "range is 8..16"]);
    let mut e = b.clone();
    e["range"] = json!([0, 16]);
    refused(&e, &["'s range 0..16 is not the partial's range"]);
    let mut e = b.clone();
    e["runs"] = json!(24);
    refused(&e, &["'s runs is 24, part 1's is 16"]);
    let mut e = b.clone();
    e["partial"]["total"] = json!(24);
    refused(&e, &["'s partial.total is not the file's runs 16"]);
    // A part of another scenario, written by confset itself (its digest is its own).
    let other = {
        let mut v = preset("scf-robots");
        v["alpha"] = json!(0.5);
        let f = write("other-scenario.json", &v);
        part(&["experiment", &f, "--runs", "16", "--shard", "1/2"])
    };
    let fo = write("other.json", &other);
    let out = run(&["merge", &fa, &fo], None);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "another scenario's part merged");
    assert!(
        err.contains(&format!("part 2 ({fo})'s scenario is not part 1's")),
        "{err}"
    );
    // Overlap and gaps name the files too.
    let out = run(&["merge", &fa, &fb, &fb], None);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!(
            "part 3 ({fb}) covers runs 8..16 which part 2 ({fb}) also covers"
        )),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `run --format csv` refuses a table with an infinite cell (exit 1, nothing written).
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn cli_csv_refuses_an_infinite_cell() {
    let mut v = preset("scf-robots");
    for row in v["model"]["V"].as_array_mut().expect("V is a matrix") {
        for x in row.as_array_mut().expect("a row") {
            *x = json!(x.as_f64().unwrap() * 1e90);
        }
    }
    let text = v.to_string();
    let out = crate::cli::confset(&["run", "-", "--format", "csv"], Some(text.as_bytes()));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(out.stdout.is_empty(), "wrote {} bytes", out.stdout.len());
    assert!(
        err.contains("error: csv.") && err.contains(" at t="),
        "{err}"
    );
    let mut v = preset("glls-grow");
    v["glls"]["monte_carlo"]["steps"] = json!(1000);
    let text = v.to_string();
    let out = crate::cli::confset(&["experiment", "-", "--runs", "20"], Some(text.as_bytes()));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        out.stdout.is_empty() && err.contains("error: study."),
        "{err}"
    );
}
