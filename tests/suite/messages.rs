//! What error messages promise (README "Errors"): a parse error names the JSON path of the
//! value at fault and says in JSON words what belongs there, never a Rust type; unknown keys
//! and names list the accepted ones; user strings are cut; a solver failure names the field
//! most likely responsible; a block of another method is refused with the right pointer.
//! One test per class, then every leaf of every preset replaced by a string.

use crate::common::patch::run_json;
use confset::plot::Panel;
use confset::scenario::Scenario;
use confset::{presets, Error, Method};
use serde_json::{json, Value};

use crate::common::contract::RUST_WORDS;

#[track_caller]
fn assert_plain(e: &Error) {
    let text = e.to_string();
    for w in RUST_WORDS {
        assert!(!text.contains(w), "{w:?} in \"{text}\"");
    }
}

/// The JSON of a preset.
fn preset(name: &str) -> Value {
    serde_json::to_value(presets::get(name).expect("preset")).expect("json")
}

/// The parse error of `v`.
#[track_caller]
fn parse_error(v: &Value) -> Error {
    let e = Scenario::from_json(&v.to_string()).expect_err("refused");
    assert_plain(&e);
    e
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_wrong_type_deep_inside_names_its_path() {
    let mut v = preset("glls-saturate");
    v["glls"]["monte_carlo"] = json!({"runs": "abc", "seed": 1});
    let e = parse_error(&v);
    assert_eq!(e.field, "glls.monte_carlo.runs");
    assert_eq!(
        e.message,
        "must be a whole number ≥ 0, found the text \"abc\""
    );
    // A block of the wrong kind, a number written as text, a whole number with a point.
    v["glls"] = json!("abc");
    let e = parse_error(&v);
    assert_eq!(
        (e.field.as_str(), e.message.as_str()),
        ("glls", "must be an object, found the text \"abc\"")
    );
    let mut v = preset("glls-saturate");
    v["alpha"] = json!("0.9");
    let e = parse_error(&v);
    assert_eq!(
        e.to_string(),
        "alpha must be a number, found the text \"0.9\" (write numbers without quotes)"
    );
    v["alpha"] = json!(0.9);
    v["simulate"]["steps"] = json!(40.0);
    let e = parse_error(&v);
    assert_eq!(e.field, "simulate.steps");
    assert!(e.message.contains("without a decimal point"), "{e}");
    // A missing field is named below its block.
    v["simulate"]["steps"] = json!(40);
    v["glls"]["monte_carlo"] = json!({"seed": 1});
    let e = parse_error(&v);
    assert_eq!(e.to_string(), "glls.monte_carlo.runs is missing");
    // A list of strings holds strings: its entry is named, not "entries must be numbers".
    let mut v = preset("ubb-series");
    v["ubb"]["basis"] = json!(["1", 5]);
    let e = parse_error(&v);
    assert_eq!(
        e.to_string(),
        "ubb.basis[1] must be text in double quotes, found the number 5"
    );
    // A fixed-length list says its length.
    let mut v = preset("glls-saturate");
    v["glls"]["plane"] = json!([0, 1, 2]);
    let e = parse_error(&v);
    assert_eq!(
        e.to_string(),
        "glls.plane must be a list of 2 entries, found a list of 3 entries"
    );
    // Not JSON at all: the path reached, the line and the column.
    let e = Scenario::from_json("{\"method\": \"scf\",\n \"alpha\": NaN}").unwrap_err();
    assert_plain(&e);
    assert_eq!(e.field, "alpha");
    assert!(
        e.message.contains("not valid JSON") && e.message.contains("line 2, column"),
        "{e}"
    );
}
in_browser!(a_wrong_type_deep_inside_names_its_path);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn an_unknown_key_lists_the_known_ones() {
    let mut block = preset("glls-saturate");
    block["glls"]["horizonn"] = json!(3);
    let mut top = preset("glls-saturate");
    top["methd"] = json!("glls");
    for (v, field, start) in [
        (
            block,
            "glls.horizonn",
            "is not a key of glls: the keys are \"horizon\", \"max_horizon\"",
        ),
        (
            top,
            "methd",
            "is not a key of a scenario: the keys are \"method\"",
        ),
    ] {
        let e = parse_error(&v);
        assert_eq!(e.field, field);
        assert!(e.message.starts_with(start), "{e}");
    }
}
in_browser!(an_unknown_key_lists_the_known_ones);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_wrong_name_lists_the_accepted_names() {
    let mut v = preset("glls-saturate");
    v["glls"]["estimator"] = json!("gls");
    let e = parse_error(&v);
    assert_eq!(e.field, "glls.estimator");
    assert_eq!(
        e.message,
        "must be one of \"lls\", \"glls\" or \"state_noise\", found \"gls\""
    );
    // A number where a name belongs: the names all the same.
    v["glls"]["estimator"] = json!("lls");
    v["method"] = json!(5);
    let e = parse_error(&v);
    // Every method of `Method::ALL`, in its order, the last one after "or".
    let names: Vec<String> = Method::ALL.iter().map(|m| format!("\"{m}\"")).collect();
    let (last, rest) = names.split_last().expect("methods");
    assert_eq!(
        e.to_string(),
        format!(
            "method must be one of {} or {last}, found the number 5",
            rest.join(", ")
        )
    );
    // A name that takes no options, written as an object.
    let mut v = preset("glls-saturate");
    v["glls"]["noise"] = json!({"bounded": 3});
    let e = parse_error(&v);
    assert_eq!(e.field, "glls.noise");
    assert!(e.message.contains("\"bounded\" alone"), "{e}");
}
in_browser!(a_wrong_name_lists_the_accepted_names);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn long_user_strings_are_cut() {
    let long = "x".repeat(500);
    let cut = format!("\"{}…\"", "x".repeat(40));
    let mut v = preset("glls-saturate");
    v["glls"]["estimator"] = json!(long);
    let e = parse_error(&v);
    assert!(e.message.contains(&cut), "{e}");
    assert!(!e.message.contains(&"x".repeat(41)), "{e}");
    let mut v = preset("ubb-series");
    v["ubb"]["basis"] = json!(["1", long]);
    let e = run_json(&v).unwrap_err();
    assert!(
        e.message.contains(&cut) && !e.message.contains(&"x".repeat(41)),
        "{e}"
    );
    let mut v = preset("uniform-paper");
    v["uniform"]["prior_overrides"] =
        json!([{"matrix": long, "row": 0, "col": 0, "lo": 0, "hi": 1}]);
    let e = run_json(&v).unwrap_err();
    assert_eq!(e.field, "uniform.prior_overrides[0].matrix");
    assert!(e.message.ends_with(&cut), "{e}");
    for e in [
        presets::get(&long).unwrap_err(),
        Panel::from_name(&long).unwrap_err(),
        confset::Method::from_name(&long).unwrap_err(),
    ] {
        assert!(
            e.message.contains(&cut) && !e.message.contains(&"x".repeat(41)),
            "{e}"
        );
    }
}
in_browser!(long_user_strings_are_cut);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn contradictory_bounds_name_the_bound() {
    // The measurement-noise bound far below the simulated noise: no state fits the data, and
    // the message says the true noise exceeds the assumed bound.
    let mut v = preset("ubb-track");
    v["ubb"]["eps"] = json!(1e-6);
    v["ubb"]["sim_eps"] = json!(0.2);
    let e = run_json(&v).unwrap_err();
    assert_plain(&e);
    assert_eq!(e.field, "ubb.eps");
    assert_eq!(
        e.message,
        "leaves no state consistent with the data under these bounds — ubb.eps may be too small (or ubb.tau, or ubb.delta); the set became empty at step k = 1, when y(1) joined the window y(0 … 1); the true noise (|η| ≤ 0.2, |u| ≤ 0.1: ubb.sim_eps, ubb.sim_tau) exceeds the bounds the estimator assumes (ε = 0.000001, τ = 0.1), so the data may contradict them"
    );
    // Given data (no simulation): the plain message.
    let mut d = preset("ubb-track");
    d["ubb"]["eps"] = json!(1e-6);
    let report = run_json(&preset("ubb-track")).unwrap();
    d["data"] = json!({"y": report.ubb.as_ref().unwrap().y});
    d.as_object_mut().unwrap().remove("simulate");
    let e = run_json(&d).unwrap_err();
    assert_eq!(e.field, "ubb.eps");
    assert_eq!(
        e.message,
        "leaves no state consistent with the data under these bounds — ubb.eps may be too small (or ubb.tau, or ubb.delta); the set became empty at step k = 1, when y(1) (row 2 (t = 2) of the record) joined the window y(0 … 1)"
    );
}
in_browser!(contradictory_bounds_name_the_bound);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_study_block_of_another_method_is_refused() {
    let experiment = json!({"runs": 10, "components": [0]});
    let mut v = preset("lscr-predict");
    v["experiment"] = experiment.clone();
    let s = Scenario::from_json(&v.to_string()).unwrap();
    for e in [s.run().unwrap_err(), s.study(None).err().expect("refused")] {
        assert_eq!(e.field, "experiment");
        assert!(
            e.message
                .contains("used only with \"method\": \"scf\" or \"kf\"")
                && e.message
                    .contains("found \"lscr\", whose Monte Carlo study is lscr.coverage"),
            "{e}"
        );
    }
    let mut v = preset("uniform-paper");
    let e = Scenario::from_json(&v.to_string())
        .unwrap()
        .study(None)
        .err()
        .expect("no study");
    assert!(e.message.contains("has no Monte Carlo study"), "{e}");
    v["experiment"] = experiment;
    let e = Scenario::from_json(&v.to_string())
        .unwrap()
        .study(None)
        .err()
        .expect("refused");
    assert_eq!(e.field, "experiment");
    assert!(
        e.message
            .contains("found \"uniform_lp\", which has no Monte Carlo study"),
        "{e}"
    );
}
in_browser!(a_study_block_of_another_method_is_refused);

/// Every leaf of `v` (numbers, strings, booleans) as (field path, JSON pointer), keeping of
/// each list its first two entries and its last (the others repeat their fields).
fn leaves(v: &Value, path: &str, pointer: &str, out: &mut Vec<(String, String)>) {
    match v {
        Value::Object(o) => {
            for (k, x) in o {
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                leaves(x, &p, &format!("{pointer}/{k}"), out);
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                if i < 2 || i + 1 == a.len() {
                    leaves(x, &format!("{path}[{i}]"), &format!("{pointer}/{i}"), out);
                }
            }
        }
        Value::Null => {}
        _ => out.push((path.to_string(), pointer.to_string())),
    }
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_leaf_of_every_preset_replaced_by_text_names_its_path() {
    let mut refused = 0;
    for p in presets::all() {
        let base = serde_json::to_value(&p.scenario).expect("json");
        let mut all = Vec::new();
        leaves(&base, "", "", &mut all);
        // A bounded sample, spread over the whole scenario.
        let step = all.len().div_ceil(150).max(1);
        for (path, pointer) in all.iter().step_by(step) {
            let mut v = base.clone();
            *v.pointer_mut(pointer).expect("leaf") = json!("abc");
            // Free text (title, notes, names) takes "abc".
            let Err(e) = Scenario::from_json(&v.to_string()) else {
                continue;
            };
            refused += 1;
            let at_or_above = e.field == *path
                || path.starts_with(&format!("{}.", e.field))
                || path.starts_with(&format!("{}[", e.field));
            assert!(
                at_or_above,
                "{}: {path} = \"abc\" gives an error about {}: {e}",
                p.name, e.field
            );
            assert_plain(&e);
            assert!(
                !e.message.starts_with("is not valid:"),
                "{}: {path}: serde's words left as they are: {e}",
                p.name
            );
        }
    }
    assert!(refused > 200, "only {refused} leaves refused");
}
in_browser!(every_leaf_of_every_preset_replaced_by_text_names_its_path);

/// SCF's options as older versions wrote them, at the top level: they still run, to the same
/// report, and the report says where each one moved; errors name them where the text has them.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn scf_options_at_the_top_level_still_run_and_the_report_says_they_moved() {
    let new = preset("scf-robots");
    let mut old = new.clone();
    let block = old
        .as_object_mut()
        .and_then(|o| o.remove("scf"))
        .expect("scf block");
    let keys: Vec<String> = block.as_object().expect("object").keys().cloned().collect();
    for (k, x) in block.as_object().expect("object") {
        old[k] = x.clone();
    }
    let run = |v: &Value| {
        Scenario::from_json(&v.to_string())
            .expect("parses")
            .run()
            .expect("runs")
    };
    let (a, mut b) = (run(&new), run(&old));
    assert!(a.notices.is_empty(), "{:?}", a.notices);
    assert_eq!(b.notices.len(), keys.len(), "{:?}", b.notices);
    for k in &keys {
        assert!(
            b.notices
                .iter()
                .any(|n| n.starts_with(&format!("{k} is read as scf.{k}:"))),
            "no notice for {k}: {:?}",
            b.notices
        );
    }
    b.notices.clear();
    assert_eq!(a, b, "the old file's report differs");
    // The scenario read from the old file writes the new shape, with the same digest.
    let s = Scenario::from_json(&old.to_string()).unwrap();
    assert_eq!(serde_json::to_value(&s).unwrap(), new);
    assert_eq!(
        s.digest().unwrap(),
        presets::get("scf-robots").unwrap().digest().unwrap()
    );

    // Errors name the key where the text has it ...
    let mut v = old.clone();
    v["tau"] = json!("abc");
    assert_eq!(parse_error(&v).field, "tau");
    v["tau"] = json!(4);
    v["scf"] = json!({"tau": 4});
    let e = parse_error(&v);
    assert_eq!(e.field, "tau");
    assert!(
        e.message.contains("given twice") && e.message.contains("scf.tau"),
        "{e}"
    );
    // ... and the checks of a run name the block's path.
    let mut v = preset("scf-scalar");
    v["scf"]["tau"] = json!(20_000);
    let e = run_json(&v).unwrap_err();
    assert_eq!(e.to_string(), "scf.tau must be at most 10000");
    let mut v = new.clone();
    v["scf"]["collision"]["d_min"] = json!(-1.0);
    let e = run_json(&v).unwrap_err();
    assert_eq!(e.field, "scf.collision.d_min");
    let mut v = old;
    v["collision"]["d_min"] = json!(-1.0);
    let e = run_json(&v).unwrap_err();
    assert_eq!(e.field, "scf.collision.d_min");
}
in_browser!(scf_options_at_the_top_level_still_run_and_the_report_says_they_moved);

/// On another method's scenario the `scf` block is refused like any other method's block, and
/// so is an old top-level SCF key that said something (it used to be ignored without a word);
/// the `"tau": 0` and `"asymptotic": false` every older scenario file carried still read.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_scf_block_belongs_to_scf_and_kf_only() {
    let mut v = preset("ubb-track");
    v["scf"] = json!({"tau": 3});
    let s = Scenario::from_json(&v.to_string()).unwrap();
    let e = s.run().unwrap_err();
    assert_eq!(e.field, "scf");
    assert_eq!(
        e.message,
        "is only used with \"method\": \"scf\" or \"kf\" (found \"ubb\")"
    );
    let mut v = preset("ubb-track");
    v["tau"] = json!(0);
    v["asymptotic"] = json!(false);
    let s = Scenario::from_json(&v.to_string()).expect("old defaults read");
    assert!(s.scf.is_none() && s.moved.is_empty());
    assert!(s.run().expect("runs").notices.is_empty());
    v["tau"] = json!(3);
    let e = parse_error(&v);
    assert_eq!(e.field, "tau");
    assert!(
        e.message.contains("scf.tau") && e.message.contains("\"ubb\""),
        "{e}"
    );
    // Every other method's block on an SCF scenario, through the same loop.
    for p in presets::all() {
        let m = p.scenario.method;
        let Some(block) = m.block().filter(|b| *b != "scf") else {
            continue;
        };
        let mut v = preset("scf-scalar");
        v[block] = serde_json::to_value(&p.scenario).unwrap()[block].clone();
        let e = run_json(&v).unwrap_err();
        assert_eq!(e.field, block, "{e}");
        assert!(e.message.contains(&format!("\"method\": \"{m}\"")), "{e}");
    }
}
in_browser!(the_scf_block_belongs_to_scf_and_kf_only);
