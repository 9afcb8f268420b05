//! The one seeded mutation of a scenario's JSON (numbers replaced by the extremes of f64,
//! sizes of 10⁹ and 2⁶⁴ − 1, wrong types, deleted keys, duplicated and ragged rows, oversized
//! matrices, another method), shared by the suite's fuzzer (`fuzz.rs`) and the long campaign
//! (`tests/fuzz/campaign.rs`, which includes this file by `#[path]`).

use confset::Method;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use serde_json::{json, Value};

/// One step into a JSON value.
#[derive(Debug, Clone, PartialEq)]
pub enum Seg {
    Key(String),
    Index(usize),
}

pub fn path_text(path: &[Seg]) -> String {
    let mut s = String::new();
    for seg in path {
        match seg {
            Seg::Key(k) if s.is_empty() => s.push_str(k),
            Seg::Key(k) => {
                s.push('.');
                s.push_str(k);
            }
            Seg::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

/// Every node below the root, with its path.
pub fn nodes(v: &Value) -> Vec<(Vec<Seg>, Value)> {
    fn walk(v: &Value, path: &mut Vec<Seg>, out: &mut Vec<(Vec<Seg>, Value)>) {
        let children: Vec<(Seg, &Value)> = match v {
            Value::Object(o) => o.iter().map(|(k, x)| (Seg::Key(k.clone()), x)).collect(),
            Value::Array(a) => a
                .iter()
                .enumerate()
                .map(|(i, x)| (Seg::Index(i), x))
                .collect(),
            _ => Vec::new(),
        };
        for (seg, x) in children {
            path.push(seg);
            out.push((path.clone(), x.clone()));
            walk(x, path, out);
            path.pop();
        }
    }
    let mut out = Vec::new();
    walk(v, &mut Vec::new(), &mut out);
    out
}

pub fn at<'a>(v: &'a mut Value, path: &[Seg]) -> &'a mut Value {
    path.iter().fold(v, |v, seg| match seg {
        Seg::Key(k) => &mut v[k.as_str()],
        Seg::Index(i) => &mut v[*i],
    })
}

/// Values put in place of a number: the extremes of f64, sizes of 10⁹ and 2⁶⁴ − 1, wrong types.
pub fn replacements() -> Vec<Value> {
    vec![
        Value::Null,
        json!(-1),
        json!(0),
        json!(1e308),
        json!(-1e308),
        json!(5e-324),
        json!(1_000_000_000u64),
        json!(u64::MAX),
        json!(1e-300),
        json!(1e154),
        json!("1"),
        json!([]),
        json!([[1.0, 2.0], [3.0]]),
    ]
}

/// A k × k matrix (0.5 on the diagonal, 0.01 elsewhere): an oversized model.
pub fn big_matrix(k: usize) -> Value {
    Value::Array(
        (0..k)
            .map(|i| {
                Value::Array(
                    (0..k)
                        .map(|j| json!(if i == j { 0.5 } else { 0.01 }))
                        .collect(),
                )
            })
            .collect(),
    )
}

/// A value of another JSON type than `v`.
pub fn other_type(v: &Value) -> Value {
    match v {
        Value::Null => json!(1),
        Value::Bool(_) => json!(1),
        Value::Number(_) => json!("0.5"),
        Value::String(_) => json!(2),
        Value::Array(_) => json!({}),
        Value::Object(_) => json!([1.0]),
    }
}

pub fn pick<T: Clone>(rng: &mut ChaCha8Rng, xs: &[T]) -> Option<T> {
    (!xs.is_empty()).then(|| xs[rng.random_range(0..xs.len())].clone())
}

/// One random mutation of a scenario's JSON, and what it did.
pub fn mutate(base: &Value, rng: &mut ChaCha8Rng) -> (Value, String) {
    let all = nodes(base);
    let numbers: Vec<_> = all.iter().filter(|(_, v)| v.is_number()).collect();
    let members: Vec<_> = all
        .iter()
        .filter(|(p, _)| matches!(p.last(), Some(Seg::Key(_))))
        .collect();
    let lists: Vec<_> = all
        .iter()
        .filter(|(_, v)| v.as_array().is_some_and(|a| !a.is_empty()))
        .collect();
    let rows: Vec<_> = all
        .iter()
        .filter(|(p, v)| v.is_array() && matches!(p.last(), Some(Seg::Index(_))))
        .collect();
    let any: Vec<_> = all.iter().collect();
    let matrices: Vec<_> = all
        .iter()
        .filter(|(_, v)| {
            v.as_array()
                .is_some_and(|a| a.first().is_some_and(|r| r.is_array()))
        })
        .collect();
    let mut s = base.clone();
    loop {
        match rng.random_range(0..10u32) {
            // A number replaced (four in nine mutations: most of a scenario is numbers).
            0..=3 => {
                let Some((p, _)) = pick(rng, &numbers) else {
                    continue;
                };
                let r = pick(rng, &replacements()).expect("values");
                *at(&mut s, p) = r.clone();
                return (s, format!("{} := {r}", path_text(p)));
            }
            4 => {
                let Some((p, _)) = pick(rng, &members) else {
                    continue;
                };
                let (parent, Some(Seg::Key(k))) = (&p[..p.len() - 1], p.last()) else {
                    continue;
                };
                at(&mut s, parent)
                    .as_object_mut()
                    .expect("an object")
                    .remove(k);
                return (s, format!("delete {}", path_text(p)));
            }
            5 => {
                let Some((p, v)) = pick(rng, &lists) else {
                    continue;
                };
                let a = v.as_array().expect("a list");
                let i = rng.random_range(0..a.len());
                at(&mut s, p)
                    .as_array_mut()
                    .expect("a list")
                    .insert(i, a[i].clone());
                return (s, format!("duplicate {}[{i}]", path_text(p)));
            }
            6 => {
                let Some((p, v)) = pick(rng, &any) else {
                    continue;
                };
                let r = other_type(v);
                *at(&mut s, p) = r.clone();
                return (s, format!("{} := {r} (type swapped)", path_text(p)));
            }
            7 => {
                // Another method on the same scenario.
                let m = pick(rng, &Method::ALL).expect("methods");
                s["method"] = json!(m.name());
                return (s, format!("method := \"{m}\""));
            }
            8 => {
                // An oversized matrix (a model of 40 or 400 states, a window of 400 rows …).
                let Some((p, _)) = pick(rng, &matrices) else {
                    continue;
                };
                let k = *pick(rng, &[40usize, 400]).as_ref().expect("sizes");
                *at(&mut s, p) = big_matrix(k);
                return (s, format!("{} := a {k} × {k} matrix", path_text(p)));
            }
            _ => {
                // A ragged row: one entry more or less than its siblings.
                let Some((p, v)) = pick(rng, &rows) else {
                    continue;
                };
                let row = at(&mut s, p).as_array_mut().expect("a list");
                let what = if v.as_array().is_some_and(|a| !a.is_empty()) && rng.random::<bool>() {
                    row.pop();
                    "one entry short"
                } else {
                    row.push(json!(0.5));
                    "one entry long"
                };
                return (s, format!("{} {what}", path_text(p)));
            }
        }
    }
}
