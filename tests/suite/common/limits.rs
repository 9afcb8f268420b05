//! Scenarios at the core's limits: a preset's size fields ("knobs": steps, states, windows,
//! strings, horizons, runs, resolutions, …) moved from the preset's value toward their
//! per-field limits, alone or several at once, and the common fraction that puts the work
//! estimate right under the budget. The budget's regression tests (`bad_input.rs`) and its
//! measurement (`fuzz::work_at_the_limits`) use them. (Test plumbing, not a reference.)

use confset::scenario::{self, budget, Job, Scenario};
use confset::Method;
use serde_json::{json, Value};

/// One size field of a scenario and the largest value the core accepts for it alone.
#[derive(Debug, Clone)]
pub enum Knob {
    /// A count at `path`, from the preset's value to `limit`.
    Count {
        path: Vec<&'static str>,
        from: f64,
        limit: f64,
    },
    /// The model's states, from `n` to about `limit` (the preset's model repeated in blocks).
    States { n: usize, limit: usize },
}

impl Knob {
    /// The field's name (JSON path, or "states").
    pub fn name(&self) -> String {
        match self {
            Knob::Count { path, .. } => path.join("."),
            Knob::States { .. } => "states".into(),
        }
    }

    /// `s` with this knob moved a fraction `t` of the way (geometrically) to its limit.
    pub fn apply(&self, s: &Value, t: f64) -> Value {
        let toward =
            |from: f64, limit: f64| (from.max(1.0) * (limit / from.max(1.0)).powf(t)).round();
        match self {
            Knob::Count { path, from, limit } => {
                let mut s = s.clone();
                let v = toward(*from, *limit);
                let slot = path.iter().fold(&mut s, |v, k| &mut v[*k]);
                let v = v as u64;
                *slot = if path.last() == Some(&"resolution") {
                    json!([v, v])
                } else {
                    json!(v)
                };
                s
            }
            Knob::States { n, limit } => {
                let k = toward(1.0, (*limit / *n).max(1) as f64) as usize;
                grow(s, *n, k.max(1))
            }
        }
    }
}

/// The state dimension of a scenario's model (rows of F; the basis length for `ubb.basis`).
pub fn states(s: &Value) -> usize {
    s["model"]["F"]
        .as_array()
        .map(Vec::len)
        .or_else(|| s["ubb"]["basis"].as_array().map(Vec::len))
        .unwrap_or(0)
}

/// The most states the core accepts for a method (its scenario file says,
/// `scenario::max_states`); 0 for a name that is no method.
pub fn max_states(method: &str) -> usize {
    confset::Method::from_name(method).map_or(0, scenario::max_states)
}

/// The knobs of a preset's scenario: the fields it has, with the limits the core states.
pub fn knobs(s: &Value) -> Vec<Knob> {
    let limits = scenario::limits();
    let method = s["method"].as_str().unwrap_or("").to_string();
    let count = |path: Vec<&'static str>, limit: f64| {
        let v = path.iter().fold(s, |v, k| &v[*k]);
        let from = v
            .as_f64()
            .or_else(|| v.get(0).and_then(Value::as_f64))
            .or_else(|| v.is_null().then_some(1.0));
        from.map(|from| Knob::Count { path, from, limit })
    };
    let mut out: Vec<Option<Knob>> = Vec::new();
    if s["simulate"].is_object() {
        let max = limits["simulate.steps"][&method][1].as_f64().unwrap_or(1.0);
        out.push(count(vec!["simulate", "steps"], max));
    }
    let n = states(s);
    if n > 0 && s["ubb"]["basis"].is_null() && max_states(&method) >= 2 * n {
        out.push(Some(Knob::States {
            n,
            limit: max_states(&method),
        }));
    }
    let block = |b: &str| s[b].is_object();
    if block("scf") {
        if s["scf"]["components"].is_array() || s["scf"]["collision"].is_object() {
            out.push(count(vec!["scf", "tau"], 10_000.0));
        }
        if s["scf"]["coverage_curve"].is_object() {
            out.push(count(vec!["scf", "coverage_curve", "points"], 2001.0));
        }
    }
    if block("lscr") {
        out.push(count(vec!["lscr", "M"], 100_000.0));
        out.push(count(vec!["lscr", "resolution"], 4096.0));
        if s["lscr"]["coverage"].is_object() {
            out.push(count(vec!["lscr", "coverage", "runs"], 1_000_000.0));
        }
    }
    if block("compare") {
        out.push(count(
            vec!["compare", "window"],
            scenario::compare::MAX_WINDOW as f64,
        ));
    }
    if block("glls") {
        out.push(count(vec!["glls", "max_horizon"], 2000.0));
        if s["glls"]["monte_carlo"].is_object() {
            out.push(count(vec!["glls", "monte_carlo", "runs"], 1_000_000.0));
            out.push(count(vec!["glls", "monte_carlo", "max_horizon"], 4999.0));
        }
    }
    if block("uniform") {
        let max = limits["uniform.window"][1].as_f64().unwrap_or(1.0);
        out.push(count(vec!["uniform", "window"], max));
        out.push(count(vec!["uniform", "directions"], 720.0));
    }
    if block("conformal") {
        out.push(count(
            vec!["conformal", "calibration"],
            scenario::conformal::MAX_CALIBRATION as f64,
        ));
    }
    if block("ubb") {
        out.push(count(
            vec!["ubb", "window"],
            scenario::ubb::MAX_WINDOW as f64,
        ));
        out.push(count(vec!["ubb", "budget"], 512.0));
    }
    out.into_iter().flatten().collect()
}

/// `s` with every knob of `which` moved the fraction `t` toward its limit.
pub fn at(s: &Value, which: &[&Knob], t: f64) -> Value {
    which.iter().fold(s.clone(), |s, k| k.apply(&s, t))
}

/// Whether the scenario parses and its report's work estimate fits `scale` times the budget.
pub fn fits(s: &Value, scale: f64) -> bool {
    Scenario::from_json(&s.to_string()).is_ok_and(|sc| {
        let w = sc.work(Job::Report);
        w.total_operations() <= scale * budget::MAX_OPERATIONS
            && w.total_bytes() <= scale * budget::MAX_BYTES
    })
}

/// The largest common fraction (to 1/256) of the way to the knobs' limits whose scenario fits
/// `scale` times the budget, with that scenario; `None` when even the preset does not fit.
pub fn under_budget(s: &Value, which: &[&Knob], scale: f64) -> Option<(f64, Value)> {
    let fits = |s: &Value| fits(s, scale);
    if fits(&at(s, which, 1.0)) {
        return Some((1.0, at(s, which, 1.0)));
    }
    if !fits(s) {
        return None;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..8 {
        let mid = 0.5 * (lo + hi);
        if fits(&at(s, which, mid)) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some((lo, at(s, which, lo)))
}

/// The first preset of every method, as JSON.
pub fn first_presets() -> Vec<(Method, Value)> {
    Method::ALL
        .iter()
        .filter_map(|&m| {
            confset::presets::all()
                .into_iter()
                .find(|p| p.scenario.method == m)
                .map(|p| (m, serde_json::to_value(&p.scenario).expect("JSON")))
        })
        .collect()
}

/// The scenario with its model repeated in `k` diagonal blocks (block i scaled by 1 − 0.03 i,
/// so that the blocks differ), and every vector of the state's or the output's length repeated
/// with it. LSCR keeps its one output (H repeated side by side).
pub fn grow(s: &Value, n: usize, k: usize) -> Value {
    if k <= 1 {
        return s.clone();
    }
    let lscr = s["method"] == "lscr";
    // The lengths that grow: the state's, and (but for LSCR's one output) the outputs' and the
    // inputs'.
    let q = s["model"]["H"].as_array().map_or(0, Vec::len);
    let r = s["model"]["B"][0].as_array().map_or(0, Vec::len);
    let lengths: Vec<usize> = if lscr { vec![n] } else { vec![n, q, r] };
    let mut s = s.clone();
    let rows = |v: &Value| -> Option<Vec<Vec<f64>>> {
        v.as_array()?
            .iter()
            .map(|r| r.as_array()?.iter().map(Value::as_f64).collect())
            .collect()
    };
    let blocks = |m: &[Vec<f64>], scaled: bool| -> Value {
        let (r, c) = (m.len(), m.first().map_or(0, Vec::len));
        let mut out = vec![vec![0.0; c * k]; r * k];
        for b in 0..k {
            let scale = if scaled { 1.0 - 0.03 * b as f64 } else { 1.0 };
            for i in 0..r {
                for j in 0..c {
                    out[b * r + i][b * c + j] = m[i][j] * scale;
                }
            }
        }
        json!(out)
    };
    let model = s["model"].as_object().cloned().unwrap_or_default();
    for (key, v) in model {
        let Some(m) = rows(&v) else {
            // A vector: x1_mean.
            if let Some(x) = v.as_array().filter(|a| a.len() == n) {
                s["model"][&key] = json!(x.iter().cycle().take(x.len() * k).collect::<Vec<_>>());
            }
            continue;
        };
        s["model"][&key] = match key.as_str() {
            "H" if lscr => json!(m
                .iter()
                .map(|r| (0..k)
                    .flat_map(|b| r.iter().map(move |v| v * 0.5f64.powi(b as i32)))
                    .collect::<Vec<f64>>())
                .collect::<Vec<_>>()),
            "F" => blocks(&m, true),
            // LSCR's one noise input drives every block.
            "G" if lscr => json!(m
                .iter()
                .cycle()
                .take(m.len() * k)
                .cloned()
                .collect::<Vec<_>>()),
            _ => blocks(&m, false),
        };
    }
    if let Some(d) = rows(&s["uniform"]["D"]) {
        s["uniform"]["D"] = blocks(&d, false);
    }
    // Vectors of those lengths outside the model (data rows, bounds, probes) grow with it;
    // indices, planes and the LSCR window (in the plotted plane) do not.
    fn vectors(v: &mut Value, lengths: &[usize], k: usize) {
        match v {
            Value::Array(a) if a.iter().all(Value::is_number) && !a.is_empty() => {
                if lengths.contains(&a.len()) {
                    *a = a.iter().cycle().take(a.len() * k).cloned().collect();
                }
            }
            Value::Array(a) => a.iter_mut().for_each(|x| vectors(x, lengths, k)),
            Value::Object(o) => o
                .iter_mut()
                .filter(|(key, _)| {
                    !matches!(
                        key.as_str(),
                        "model"
                            | "D"
                            | "plot"
                            | "plane"
                            | "components"
                            | "a"
                            | "b"
                            | "window"
                            | "resolution"
                    )
                })
                .for_each(|(_, x)| vectors(x, lengths, k)),
            _ => {}
        }
    }
    vectors(&mut s, &lengths, k);
    s
}
