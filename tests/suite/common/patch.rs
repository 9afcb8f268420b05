//! Bad-input tables: a preset's scenario JSON with a two-level patch applied must be refused
//! with an error naming the expected field. (Test plumbing, not a reference computation.)

use confset::scenario::Scenario;
use serde_json::Value;

/// `base` with `patch` = {"block": {"key": value}} applied; a null value removes the key.
pub fn patched(base: &Value, patch: &Value) -> Value {
    let mut sc = base.clone();
    for (k, v) in patch.as_object().expect("patch is an object") {
        for (k2, v2) in v.as_object().expect("patch blocks are objects") {
            if v2.is_null() {
                if let Some(block) = sc[k].as_object_mut() {
                    block.remove(k2);
                }
            } else {
                sc[k][k2] = v2.clone();
            }
        }
    }
    sc
}

/// Every (field, patch) case runs to an error whose field is `field`.
pub fn assert_refused(base: &Value, cases: &[(&str, Value)]) {
    for (want, patch) in cases {
        let sc = patched(base, patch);
        let err = Scenario::from_json(&sc.to_string())
            .and_then(|s| s.run())
            .err()
            .unwrap_or_else(|| panic!("{patch} is accepted"));
        assert_eq!(err.field, *want, "{patch}: {}", err.message);
        assert!(!err.message.is_empty(), "{patch}: empty message");
    }
}

/// A scenario given as JSON, read (it must be readable) and run.
pub fn run_json(sc: &Value) -> confset::Result<confset::scenario::Report> {
    Scenario::from_json(&sc.to_string())
        .expect("a readable scenario")
        .run()
}
