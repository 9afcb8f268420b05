//! The output contract every test and the long campaign (`tests/fuzz/campaign.rs`, which
//! includes this file by `#[path]`) hold the core to: a report's numbers are JSON numbers (null
//! only under the core's nullable keys), and a message speaks JSON, never Rust.

use confset::scenario::Report;
use serde_json::Value;

/// Words of Rust, not of JSON: no message may contain them.
pub const RUST_WORDS: [&str; 9] = [
    "struct ",
    "enum ",
    "usize",
    "u64",
    "f64",
    "Vec<",
    "variant identifier",
    "MatrixSpec",
    "`",
];

/// The core's list of report keys that may be null.
use confset::scenario::NULLABLE_REPORT_KEYS as NULLABLE;

/// The first word of Rust in a message, if any.
pub fn rust_word(message: &str) -> Option<&'static str> {
    RUST_WORDS.into_iter().find(|w| message.contains(w))
}

/// Every null in `v` (a report, a study's result, a merged result), with its path and whether
/// it sits under a [`NULLABLE`] key.
pub fn null_paths(v: &Value) -> Vec<(String, bool)> {
    fn nulls(v: &Value, key: &str, path: &str, out: &mut Vec<(String, bool)>) {
        match v {
            Value::Null => out.push((path.into(), NULLABLE.iter().any(|(k, _)| *k == key))),
            Value::Array(a) => a
                .iter()
                .enumerate()
                .for_each(|(i, x)| nulls(x, key, &format!("{path}[{i}]"), out)),
            Value::Object(o) => o
                .iter()
                .for_each(|(k, x)| nulls(x, k, &format!("{path}.{k}"), out)),
            _ => {}
        }
    }
    let mut found = Vec::new();
    nulls(v, "", "", &mut found);
    found
}

/// The report's JSON contract (crate docs, Invariants: every number in a report is a JSON
/// number): null only under a [`NULLABLE`] key, and the text parses back to an equal report.
/// The round trip is what catches every non-finite number: serde_json writes NaN and ±∞ as
/// null, which does not parse as an f64 and comes back as `None` in an `Option` (and
/// NaN ≠ NaN). (serde_json's `Value` cannot hold a non-finite number, so there is no separate
/// finiteness check to make on the parsed JSON.)
pub fn check_report_json(r: &Report) -> Result<(), String> {
    let list = |paths: Vec<&String>| {
        let n = paths.len();
        let first: Vec<&str> = paths.into_iter().take(5).map(|p| p.as_str()).collect();
        format!("{n}: {}", first.join(", "))
    };
    let text = serde_json::to_string(r).map_err(|e| format!("the report is not JSON: {e}"))?;
    let v: Value = serde_json::from_str(&text).map_err(|e| format!("unreadable JSON: {e}"))?;
    let found = null_paths(&v);
    // A null in the report's measurements (`y`, ubb's `y`) is a gap of the user's record, a
    // missing measurement (crate docs, Invariants): no number stands there.
    let gap = |p: &str| p.starts_with(".y[") || p.starts_with(".ubb.y[");
    let unexpected: Vec<&String> = found
        .iter()
        .filter(|(p, ok)| !ok && !gap(p))
        .map(|(p, _)| p)
        .collect();
    if !unexpected.is_empty() {
        return Err(format!(
            "null where a number belongs (a non-finite f64?), {}",
            list(unexpected)
        ));
    }
    let back: Option<Report> = serde_json::from_str(&text).ok();
    if back.as_ref().map(without_gaps) != Some(without_gaps(r)) {
        return Err(format!(
            "the report does not survive its JSON: a NaN or ±∞ behind one of the nulls, {}",
            list(found.iter().map(|(p, _)| p).collect())
        ));
    }
    Ok(())
}

/// The report with every gap of its measurements (NaN, which is never equal to itself) read as
/// 0, so that a report with gaps can be compared with its JSON read back.
fn without_gaps(r: &Report) -> Report {
    let mut c = r.clone();
    let fill = |rows: &mut Vec<Vec<f64>>| {
        rows.iter_mut()
            .flatten()
            .filter(|x| x.is_nan())
            .for_each(|x| *x = 0.0)
    };
    fill(&mut c.y);
    if let Some(u) = c.ubb.as_mut() {
        fill(&mut u.y);
    }
    c
}
