//! What holds for every method, written once and driven by the registries: `presets::all()`
//! and `Method::ALL`, never a hand list of presets. A new preset or method is covered by every
//! test here without a line changed (the golden digest asks to be regenerated, see
//! [`golden`]).
//!
//! * every preset runs, its scenario JSON round-trips, and its report is plain JSON;
//! * every method is exercised by a preset ("kf" by the SCF presets switched to it);
//! * native = wasm to 1e-9 relative: a digest of every preset's report, pinned natively,
//!   checked on both targets (looser only where the numbers are rounding noise by
//!   construction, [`golden::LOOSE`]);
//! * (the seeded mutation fuzzer over every preset's JSON is `fuzz.rs`);
//! * every useful panel of every preset draws as SVG at the page's sizes (native);
//! * every study: chunking never changes its result, the wasm `Study` class returns the core's
//!   JSON, `confset experiment` prints it (native); sharding and merging in `shards.rs`;
//! * every method on explicit data: the simulated report's measurements given as `data` give
//!   the same estimates, and a report without truth.

use crate::common::rel_close;
use confset::presets;
use confset::scenario::{DataSpec, Report, Scenario, SimulateSpec};
use confset::study::run_to_end;
use confset::Method;
use serde_json::{json, Value};

fn report_value(r: &Report) -> Value {
    serde_json::to_value(r).expect("a report serializes")
}

fn run(name: &str, s: &Scenario) -> Report {
    s.run().unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The first place where two JSON values differ (path and both values), if any.
pub(crate) fn first_difference(a: &Value, b: &Value, path: &str) -> Option<String> {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => x
            .iter()
            .find_map(|(k, v)| match y.get(k) {
                Some(w) => first_difference(v, w, &format!("{path}.{k}")),
                None => Some(format!("{path}.{k} only in the first")),
            })
            .or_else(|| {
                y.keys()
                    .find(|k| !x.contains_key(*k))
                    .map(|k| format!("{path}.{k} only in the second"))
            }),
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => x
            .iter()
            .zip(y)
            .enumerate()
            .find_map(|(i, (v, w))| first_difference(v, w, &format!("{path}[{i}]"))),
        _ if a == b => None,
        _ => Some(format!("{path}: {} vs {}", cut(a), cut(b))),
    }
}

/// A JSON value in a message, cut to 120 characters.
fn cut(v: &Value) -> String {
    let s = v.to_string();
    match s.char_indices().nth(120) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s,
    }
}

// ---------------------------------------------------------------------------------------------
// 0. The registries are complete: a method missing from one fails here, not silently.
// ---------------------------------------------------------------------------------------------

/// Every variant of [`Method`], named once with no wildcard: a new variant does not compile
/// until it is added here, and [`method_all_names_every_variant`] then fails until it is in
/// `Method::ALL` too.
fn every_variant(m: Method) -> &'static str {
    match m {
        Method::Scf => "scf",
        Method::Kf => "kf",
        Method::Lscr => "lscr",
        Method::Glls => "glls",
        Method::UniformLp => "uniform_lp",
        Method::Ubb => "ubb",
        Method::Conformal => "conformal",
        Method::Compare => "compare",
    }
}

/// `Method::ALL` holds every variant once: the names serde's derive knows (its message for an
/// unknown name lists every variant, in declaration order), the names of the match above, and
/// `Method::ALL`'s agree. Everything below loops over `Method::ALL`, so a variant left out of it
/// would be skipped by every registry test without a word.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn method_all_names_every_variant() {
    let message = serde_json::from_value::<Method>(json!("no method"))
        .expect_err("not a method")
        .to_string();
    let listed = message
        .split_once("expected one of ")
        .map(|(_, list)| list)
        .unwrap_or_else(|| panic!("serde lists no variants: {message}"));
    let derived: Vec<&str> = listed.split(", ").map(|n| n.trim_matches('`')).collect();
    let all: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
    assert_eq!(all, derived, "Method::ALL against the enum's variants");
    for m in Method::ALL {
        assert_eq!(every_variant(m), m.name());
        assert_eq!(Method::from_name(m.name()).ok(), Some(m));
    }
}
in_browser!(method_all_names_every_variant);

/// Every method of `Method::ALL` is in every registry: its scenario file gives a step range, a
/// state limit and its truth keys; the core's limits name it; it has presets (KF: the SCF
/// presets switched to it) and figures. A registry that forgot one fails here by name.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_method_is_in_every_registry() {
    let limits = confset::scenario::limits();
    let all = presets::all();
    for m in Method::ALL {
        let steps = &limits["simulate.steps"][m.name()];
        assert!(
            steps[0]
                .as_u64()
                .is_some_and(|a| steps[1].as_u64().is_some_and(|b| a <= b)),
            "\"{m}\": no step range in scenario::limits(): {steps}"
        );
        assert!(
            confset::scenario::max_states(m) >= 1,
            "\"{m}\": no state limit"
        );
        let truth = confset::scenario::truth_keys(m);
        assert!(
            truth.iter().any(|(k, _)| *k == "x_true"),
            "\"{m}\": the truth keys miss x_true"
        );
        for (i, (k, what)) in truth.iter().enumerate() {
            assert!(!what.is_empty(), "\"{m}\": truth key {k} says nothing");
            assert!(
                truth[..i].iter().all(|(j, _)| j != k),
                "\"{m}\": truth key {k} twice"
            );
        }
        assert!(
            !scenarios_of(m).is_empty(),
            "\"{m}\": no preset runs this method"
        );
        assert!(
            m == Method::Kf || all.iter().any(|p| p.scenario.method == m),
            "\"{m}\": no preset in the menu"
        );
        assert!(
            !confset::plot::method_panels(m).is_empty(),
            "\"{m}\": no figures"
        );
    }
}
in_browser!(every_method_is_in_every_registry);

// ---------------------------------------------------------------------------------------------
// 1. Every preset runs, round-trips, and writes plain JSON.
// ---------------------------------------------------------------------------------------------

use crate::common::contract::check_report_json;

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_preset_runs_round_trips_and_writes_plain_json() {
    let all = presets::all();
    assert!(!all.is_empty());
    for (i, p) in all.iter().enumerate() {
        assert!(
            all[..i].iter().all(|q| q.name != p.name),
            "preset name {} is used twice",
            p.name
        );
        assert!(!p.description.is_empty(), "{}: no description", p.name);
        let r = run(&p.name, &p.scenario);
        assert_eq!(r.method, p.scenario.method, "{}", p.name);
        let text = serde_json::to_string(&p.scenario).expect("a scenario serializes");
        let back = Scenario::from_json(&text)
            .unwrap_or_else(|e| panic!("{}: its own JSON is refused: {e}", p.name));
        assert!(
            back == p.scenario,
            "{}: the scenario JSON does not round-trip: {}",
            p.name,
            first_difference(
                &serde_json::to_value(&p.scenario).unwrap(),
                &serde_json::to_value(&back).unwrap(),
                ""
            )
            .unwrap_or_default()
        );
        let again = run(&p.name, &back);
        assert!(
            again == r,
            "{}: the round-tripped scenario gives another report: {}",
            p.name,
            first_difference(&report_value(&r), &report_value(&again), "").unwrap_or_default()
        );
        check_report_json(&r).unwrap_or_else(|e| panic!("{}: {e}", p.name));
    }
}
in_browser!(every_preset_runs_round_trips_and_writes_plain_json);

// ---------------------------------------------------------------------------------------------
// 2. Every method is exercised by a preset.
/// The time cursor, for every preset: a preset whose report keeps one step's detail (an `at`
/// in its method's block) has a cursor, and no other does. Its detail at step t is, bit for
/// bit, the `at` of the report run with `<block>.time` = t; put into the report run at the
/// preset's own time (`Report::set_at`) it makes that whole report; and a time the run
/// refuses (before the first step, past the last) is the same error. Checked before the first
/// step, at the cursor's first, middle and last steps, and past them.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_cursor_gives_the_detail_of_a_run_at_that_time() {
    let mut with_cursor = 0;
    for p in presets::all() {
        let (name, s) = (&p.name, &p.scenario);
        let base = run(name, s);
        let block = s.method.block();
        let keeps_at = block.is_some_and(|b| report_value(&base)[b].get("at").is_some());
        let cursor = s.cursor().unwrap_or_else(|e| panic!("{name}: cursor: {e}"));
        assert_eq!(
            cursor.is_some(),
            keeps_at,
            "{name}: a cursor exactly when the report keeps an `at`"
        );
        let (Some(mut cursor), Some(b)) = (cursor, block) else {
            continue;
        };
        with_cursor += 1;
        let (lo, hi) = (*cursor.steps().start(), *cursor.steps().end());
        assert!(lo <= hi, "{name}: the cursor has steps ({lo}..={hi})");
        let mut times = vec![0, lo.saturating_sub(1), lo, (lo + hi) / 2, hi, hi + 1];
        times.dedup();
        for t in times {
            let mut v = serde_json::to_value(s).expect("a scenario serializes");
            v[b]["time"] = json!(t);
            let at_t: Scenario = serde_json::from_value(v).expect("the scenario at t");
            let what = format!("{name} at {b}.time = {t}");
            match (at_t.run(), cursor.at(t)) {
                (Ok(want), Ok(got)) => {
                    let want_at = &report_value(&want)[b]["at"];
                    if let Some(d) = first_difference(want_at, &got, &format!("{b}.at")) {
                        panic!("{what}: the cursor's detail differs from the run's: {d}");
                    }
                    let mut kept = base.clone();
                    kept.set_at(got)
                        .unwrap_or_else(|e| panic!("{what}: set_at: {e}"));
                    if let Some(d) =
                        first_difference(&report_value(&want), &report_value(&kept), "")
                    {
                        panic!(
                            "{what}: the kept report with the detail differs from the run's: {d}"
                        );
                    }
                }
                (Err(want), Err(got)) => assert_eq!(got.to_string(), want.to_string(), "{what}"),
                (want, got) => panic!(
                    "{what}: the run gives {:?}, the cursor {:?}",
                    want.map(|_| "a report"),
                    got.map(|_| "a detail")
                ),
            }
            assert!(
                !(lo..=hi).contains(&t) || cursor.at(t).is_ok(),
                "{what}: every step of the cursor has a detail"
            );
        }
    }
    assert!(with_cursor > 0, "some preset has a time cursor");
}
in_browser!(every_cursor_gives_the_detail_of_a_run_at_that_time);

// ---------------------------------------------------------------------------------------------

/// The scenarios that exercise `m`: its presets. "kf" has none of its own (it is SCF without the
/// SCF regions): while that holds, it gets the SCF presets switched to "kf".
fn scenarios_of(m: Method) -> Vec<(String, Scenario)> {
    let of = |m: Method| -> Vec<(String, Scenario)> {
        presets::all()
            .into_iter()
            .filter(|p| p.scenario.method == m)
            .map(|p| (p.name, p.scenario))
            .collect()
    };
    let own = of(m);
    if !own.is_empty() || m != Method::Kf {
        return own;
    }
    of(Method::Scf)
        .into_iter()
        .map(|(name, mut s)| {
            s.method = Method::Kf;
            (format!("{name} as kf"), s)
        })
        .collect()
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_method_is_exercised_by_a_preset() {
    let blocks: Vec<&str> = Method::ALL.iter().filter_map(|m| m.block()).collect();
    for m in Method::ALL {
        let cases = scenarios_of(m);
        assert!(!cases.is_empty(), "no preset exercises method \"{m}\"");
        for (name, s) in cases {
            let r = run(&name, &s);
            assert_eq!(r.method, m, "{name}");
            let v = report_value(&r);
            // No other method's result block; the method's own block, or else (SCF and KF,
            // whose `scf` block is options only) the KF/SCF steps.
            for b in blocks.iter().filter(|b| m.block() != Some(**b)) {
                assert!(
                    v.get(*b).is_none(),
                    "{name}: result block {b:?} in a \"{m}\" report"
                );
            }
            let own_block = m.block().is_some_and(|b| v.get(b).is_some());
            assert_eq!(
                r.steps.is_empty(),
                own_block,
                "{name}: {} KF/SCF steps in a \"{m}\" report",
                r.steps.len()
            );
            let scf_regions = r
                .steps
                .iter()
                .filter(|st| {
                    st.scf.is_some() || st.target.as_ref().is_some_and(|t| t.scf.is_some())
                })
                .count();
            match m {
                Method::Kf => assert_eq!(scf_regions, 0, "{name}: SCF regions in a KF report"),
                Method::Scf => assert!(scf_regions > 0, "{name}: an SCF report without SCF"),
                _ => {}
            }
            check_report_json(&r).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
    }
    // "kf" is SCF without the SCF: switching a scenario to it keeps every KF region.
    for (name, s) in scenarios_of(Method::Scf) {
        let mut kf = s.clone();
        kf.method = Method::Kf;
        let (a, b) = (run(&name, &s), run(&name, &kf));
        assert_eq!(a.steps.len(), b.steps.len(), "{name}");
        for (x, y) in a.steps.iter().zip(&b.steps) {
            assert!(
                x.kf == y.kf,
                "{name} t = {}: KF region changes with kf",
                x.t
            );
        }
    }
}
in_browser!(every_method_is_exercised_by_a_preset);

// ---------------------------------------------------------------------------------------------
// 3. Native = wasm: every preset's report against a digest pinned natively.
// ---------------------------------------------------------------------------------------------

/// A digest of a report, pinned natively in `tests/golden/presets.json` and checked on both
/// targets, so a wasm report that passes agrees with the native one to [`golden::TOL`]
/// (crate docs, Invariants).
///
/// The report's JSON is flattened into leaves in document order. Everything but the floats
/// (paths, strings, booleans, integers — sizes and counts) is hashed and must match exactly;
/// of the floats the digest keeps [`golden::SAMPLES`] evenly spaced values (each compared to
/// TOL relative to itself or, for a value in a list, to the list's largest entry), and
/// [`golden::BLOCKS`] weighted sums over consecutive runs of them (compared to TOL relative to
/// the run's weighted absolute sum), so a difference anywhere moves some sum. The parts listed
/// in [`golden::LOOSE`] are rounding noise by construction and get a looser tolerance.
///
/// After a deliberate change of the numbers (or a new preset), regenerate natively with
/// `CONFSET_BLESS_GOLDEN=1 cargo test --profile bench registry::every_preset_report_matches` and review the diff.
mod golden {
    use serde_json::{json, Map, Value};

    pub const TOL: f64 = 1e-9;

    /// Report parts that are rounding noise by construction, so native and wasm differ in them
    /// beyond TOL (measured: up to 1.5e-4 relative) — held to a looser tolerance, not left out.
    /// A difference in the last bit of any libm call (glibc natively, Rust's libm in wasm) is
    /// amplified there; the crate docs' 1e-9 contract does not hold for them.
    pub const LOOSE: [(&str, f64, &str); 2] = [
        (
            ".glls.precision",
            1e-3,
            "GLLS Section 5 Monte Carlo: the error statistics of growing or unstable systems at \
             long horizons are rounding errors (glls-grow's notes), quartiles jump between runs",
        ),
        (
            ".glls.curves",
            1e-6,
            "GLLS singular-value curves: an SVD is accurate to about ε·σ_max in absolute terms \
             (crate docs), so small σ_i of an ill-conditioned Γ_{s+1} carry relative noise",
        ),
    ];

    /// The tolerance of the float at `path`.
    fn tol(path: &str) -> f64 {
        LOOSE
            .iter()
            .find(|(p, _, _)| path.starts_with(p))
            .map_or(TOL, |(_, t, _)| *t)
    }
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    pub const SAMPLES: usize = 32;
    pub const BLOCKS: usize = 16;
    pub const TEXT: &str = include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/golden/presets.json"
    ));
    #[cfg(not(target_arch = "wasm32"))]
    pub const FILE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden/presets.json");

    /// The flattened report: the hash of everything but the floats, and the floats with the
    /// largest magnitude among their siblings.
    struct Flat {
        hash: u64,
        leaves: usize,
        floats: Vec<(f64, f64)>,
        /// The path of each float, for messages.
        paths: Vec<String>,
    }

    fn fnv(h: &mut u64, bytes: &[u8]) {
        for b in bytes {
            *h ^= *b as u64;
            *h = h.wrapping_mul(0x100_0000_01b3);
        }
    }

    fn flatten(v: &Value) -> Flat {
        fn walk(v: &Value, path: &str, scale: f64, f: &mut Flat) {
            let leaf = |f: &mut Flat, text: &str| {
                f.leaves += 1;
                fnv(&mut f.hash, path.as_bytes());
                fnv(&mut f.hash, b"=");
                fnv(&mut f.hash, text.as_bytes());
                fnv(&mut f.hash, b";");
            };
            match v {
                Value::Number(n) if n.is_f64() => {
                    let x = n.as_f64().expect("a float");
                    leaf(f, "float");
                    f.floats.push((x, scale.max(x.abs())));
                    f.paths.push(path.to_string());
                }
                Value::Array(a) if !a.is_empty() => {
                    let s = a
                        .iter()
                        .filter_map(|x| x.as_f64())
                        .fold(0.0f64, |m, x| m.max(x.abs()));
                    for (i, x) in a.iter().enumerate() {
                        walk(x, &format!("{path}[{i}]"), s, f);
                    }
                }
                Value::Object(o) if !o.is_empty() => {
                    for (k, x) in o {
                        walk(x, &format!("{path}.{k}"), 0.0, f);
                    }
                }
                other => leaf(f, &other.to_string()),
            }
        }
        let mut f = Flat {
            hash: 0xcbf2_9ce4_8422_2325,
            leaves: 0,
            floats: Vec::new(),
            paths: Vec::new(),
        };
        walk(v, "", 0.0, &mut f);
        f
    }

    /// A fixed weight in [1, 2) for float number i (the same on every platform).
    fn weight(i: usize) -> f64 {
        1.0 + ((i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 54) as f64 / 1024.0
    }

    fn block_range(n: usize, b: usize) -> std::ops::Range<usize> {
        b * n / BLOCKS..(b + 1) * n / BLOCKS
    }

    fn block(floats: &[(f64, f64)], b: usize) -> (f64, f64) {
        block_range(floats.len(), b).fold((0.0, 0.0), |(s, m), i| {
            let wx = weight(i) * floats[i].0;
            (s + wx, m + wx.abs())
        })
    }

    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    fn sample_index(j: usize, n: usize) -> usize {
        j * (n - 1) / (SAMPLES - 1).max(1)
    }

    /// The digest of a report's JSON.
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    pub fn digest(report: &Value) -> Value {
        let f = flatten(report);
        let n = f.floats.len();
        let mut samples: Vec<usize> = (0..SAMPLES.min(n)).map(|j| sample_index(j, n)).collect();
        samples.dedup();
        json!({
            "leaves": f.leaves,
            "shape": format!("{:016x}", f.hash),
            "floats": n,
            "samples": samples.iter().map(|&i| json!([i, f.floats[i].0])).collect::<Vec<_>>(),
            "blocks": (0..BLOCKS).map(|b| { let (s, m) = block(&f.floats, b); json!([s, m]) }).collect::<Vec<_>>(),
        })
    }

    /// How `report` differs from the pinned digest `gold` (empty: it agrees).
    pub fn compare(gold: &Value, report: &Value) -> Vec<String> {
        let f = flatten(report);
        let mut out = Vec::new();
        let shape = format!("{:016x}", f.hash);
        if gold["leaves"] != json!(f.leaves)
            || gold["floats"] != json!(f.floats.len())
            || gold["shape"] != json!(shape)
        {
            out.push(format!(
                "the structure, texts or integers differ: {} leaves, {} floats, shape {shape}; pinned {}, {}, {}",
                f.leaves,
                f.floats.len(),
                gold["leaves"],
                gold["floats"],
                gold["shape"]
            ));
            return out;
        }
        let num = |v: &Value| v.as_f64().unwrap_or(f64::NAN);
        for s in gold["samples"].as_array().into_iter().flatten() {
            let i = s[0].as_u64().unwrap_or(u64::MAX) as usize;
            let Some(&(x, scale)) = f.floats.get(i) else {
                out.push(format!("sample {i} is missing"));
                continue;
            };
            let want = num(&s[1]);
            if !((x - want).abs() <= tol(&f.paths[i]) * scale.max(want.abs())) {
                out.push(format!(
                    "float {i} ({}): {x:.17e}, pinned {want:.17e} (relative to scale {scale:.3e}: {:.1e})",
                    f.paths[i],
                    (x - want).abs() / scale.max(want.abs())
                ));
            }
        }
        for (b, g) in gold["blocks"].as_array().into_iter().flatten().enumerate() {
            let (s, m) = block(&f.floats, b);
            let (s0, m0) = (num(&g[0]), num(&g[1]));
            // What the block may move: each float's share of its weighted sum, at its tolerance.
            let r = block_range(f.floats.len(), b);
            let allowed: f64 = r
                .clone()
                .map(|i| tol(&f.paths[i]) * (weight(i) * f.floats[i].0).abs())
                .sum();
            if !((s - s0).abs() <= allowed && (m - m0).abs() <= allowed) {
                let ends = match (
                    f.paths.get(r.start),
                    r.end.checked_sub(1).and_then(|e| f.paths.get(e)),
                ) {
                    (Some(a), Some(z)) => format!("{a} … {z}"),
                    _ => String::new(),
                };
                out.push(format!(
                    "block {b} of {BLOCKS} ({ends}): weighted sum {s:.17e} / {m:.17e}, pinned {s0:.17e} / {m0:.17e} (relative {:.1e})",
                    (s - s0).abs().max((m - m0).abs()) / m0
                ));
            }
        }
        out
    }

    pub fn pinned() -> Map<String, Value> {
        serde_json::from_str(TEXT).expect("tests/golden/presets.json is JSON")
    }
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_preset_report_matches_its_native_golden() {
    let reports: Vec<(String, Value)> = presets::all()
        .into_iter()
        .map(|p| {
            let r = run(&p.name, &p.scenario);
            (p.name, report_value(&r))
        })
        .collect();
    #[cfg(not(target_arch = "wasm32"))]
    if std::env::var_os("CONFSET_BLESS_GOLDEN").is_some() {
        let map: std::collections::BTreeMap<String, Value> = reports
            .iter()
            .map(|(n, v)| (n.clone(), golden::digest(v)))
            .collect();
        // One line per preset: a reviewable diff when the numbers change.
        let lines: Vec<String> = map
            .iter()
            .map(|(n, d)| format!("  {}: {d}", json!(n)))
            .collect();
        let text = format!("{{\n{}\n}}\n", lines.join(",\n"));
        std::fs::write(golden::FILE, text).expect("write the golden file");
        eprintln!("wrote {} digests to tests/golden/presets.json", map.len());
        return;
    }
    let pinned = golden::pinned();
    let mut problems = Vec::new();
    for (name, v) in &reports {
        match pinned.get(name) {
            None => problems.push(format!("{name}: no pinned digest")),
            Some(g) => problems.extend(
                golden::compare(g, v)
                    .into_iter()
                    .map(|m| format!("{name}: {m}")),
            ),
        }
    }
    for name in pinned.keys() {
        if !reports.iter().any(|(n, _)| n == name) {
            problems.push(format!("{name}: pinned, but no such preset"));
        }
    }
    assert!(
        problems.is_empty(),
        "{} difference(s) from the native golden (after a deliberate change, regenerate natively \
         with CONFSET_BLESS_GOLDEN=1 cargo test --profile bench registry::every_preset_report_matches):\n{}",
        problems.len(),
        problems.join("\n")
    );
}
in_browser!(every_preset_report_matches_its_native_golden);

// ---------------------------------------------------------------------------------------------
// 5. Every useful panel of every preset draws at the page's sizes.
// ---------------------------------------------------------------------------------------------

/// Phone (a figure 4:5 at 390 px), narrow desktop column, full width (CSS pixels).
#[cfg(not(target_arch = "wasm32"))]
const PAGE_SIZES: [(u32, u32); 3] = [(350, 438), (640, 420), (960, 640)];

/// One panel of the page's 2 × 2 grid at 1366 px (methods with four panels: GLLS, uniform).
#[cfg(not(target_arch = "wasm32"))]
const GRID_PANEL: (u32, u32) = (428, 321);

#[cfg(not(target_arch = "wasm32"))]
#[test]
fn every_useful_panel_of_every_preset_draws_at_page_sizes() {
    use confset::plot::{draw, useful_panels, View};
    use plotters::prelude::SVGBackend;
    let mut drawn = 0;
    // Legend boxes over a plotting area (the frames give both rectangles): none may be.
    let mut overlaps = Vec::new();
    // Texts cut with "…" in the 2 × 2 grid's panel at 1366 px ("word…"; a range such as
    // "y(0) … y(k)" has spaces around its ellipsis): none may be.
    let mut cuts = Vec::new();
    for p in presets::all() {
        let r = run(&p.name, &p.scenario);
        let panels = useful_panels(&r);
        assert!(!panels.is_empty(), "{}: no useful panel", p.name);
        let grid = panels.len() >= 4;
        for panel in panels {
            let sizes = PAGE_SIZES.iter().copied().chain(grid.then_some(GRID_PANEL));
            for (w, h) in sizes {
                let what = format!("{} {} {w}×{h}", p.name, panel.name());
                let view = View::new(panel);
                let mut svg = String::new();
                let frame = draw(SVGBackend::with_string(&mut svg, (w, h)), &r, &view)
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                let areas: Vec<_> = std::iter::once(&frame)
                    .chain(&frame.more)
                    .map(|f| f.plot_area)
                    .collect();
                for &(l, t, rr, b) in &frame.legends {
                    for &(al, at, ar, ab) in &areas {
                        if l < ar && rr > al && t < ab && b > at {
                            overlaps.push(format!(
                                "{what}: legend ({l}, {t}, {rr}, {b}) over plot area ({al}, {at}, {ar}, {ab})"
                            ));
                        }
                    }
                }
                assert!(
                    svg.contains(&format!("<svg width=\"{w}\" height=\"{h}\"")),
                    "{what}: not an SVG of that size: {}",
                    &svg[..svg.len().min(120)]
                );
                let count = |tag: &str| svg.matches(tag).count();
                let curves = count("<path") + count("<polyline") + count("<polygon");
                let texts = count("<text");
                // A frame alone is rects; a figure has at least a curve and its axis labels.
                assert!(
                    curves >= 1 && texts >= 3,
                    "{what}: {curves} paths/polylines/polygons, {texts} texts"
                );
                // In the 2 × 2 grid's panel at 1366 px no text is cut ("word…"; a range such as
                // "y(0) … y(k)" has spaces around its ellipsis), except the notes under the
                // title (plain text above the charts): they end in "…" where the figure has no
                // room for them all (the report and the page's notes have them whole).
                let is_note = |i: usize| {
                    let tag = &svg[svg[..i].rfind("<text").unwrap_or(0)..i];
                    let y = tag
                        .split("y=\"")
                        .nth(1)
                        .and_then(|v| v.split('"').next())
                        .and_then(|v| v.parse::<f64>().ok());
                    !tag.contains("bold") && y.is_some_and(|y| y < frame.plot_area.1 as f64)
                };
                if (w, h) == GRID_PANEL {
                    cuts.extend(
                        svg.match_indices('…')
                            .filter(|(i, _)| {
                                svg[..*i]
                                    .chars()
                                    .next_back()
                                    .is_some_and(|c| !c.is_whitespace() && c != '>')
                                    && !is_note(*i)
                            })
                            .map(|(i, _)| {
                                let from = svg[..i].rfind('>').map_or(0, |j| j + 1);
                                format!("{what}: {}…", &svg[from..i])
                            }),
                    );
                }
                drawn += 1;
            }
        }
    }
    assert!(
        overlaps.is_empty(),
        "{} legend(s) over a chart:\n{}",
        overlaps.len(),
        overlaps.join("\n")
    );
    assert!(
        cuts.is_empty(),
        "{} cut text(s):\n{}",
        cuts.len(),
        cuts.join("\n")
    );
    eprintln!("drew {drawn} SVG figures");
}

// ---------------------------------------------------------------------------------------------
// 6. Studies: chunking never changes the numbers; the wasm binding returns the core's JSON.
// ---------------------------------------------------------------------------------------------

/// Runs of every study here: small, and not a multiple of the SCF batch of 8.
const STUDY_RUNS: usize = 20;

/// The presets whose method has a study for them (`Scenario::study` accepts them) of their
/// own: a study given only its runs would run on every preset of a method with a study, with
/// the defaults of `confset experiment --runs` (`honest::a_study_given_only_its_runs_…`);
/// here the presets whose scenario asks for one (its block, or a method whose study needs none).
pub(crate) fn study_presets() -> Vec<(String, Scenario)> {
    presets::all()
        .into_iter()
        .filter(|p| p.scenario.study(None).is_ok())
        .filter_map(|p| match p.scenario.study(Some(STUDY_RUNS)) {
            Ok(_) => Some((p.name, p.scenario)),
            Err(e) => {
                assert!(
                    !e.field.is_empty() && !e.message.is_empty(),
                    "{}: a study refused without a field: {e:?}",
                    p.name
                );
                None
            }
        })
        .collect()
}

/// Run a study to the end in chunks of `chunk`, checking the counters on the way.
pub(crate) fn run_study(name: &str, s: &Scenario, runs: usize, chunk: usize) -> Value {
    let mut st = s
        .study(Some(runs))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(st.total(), runs, "{name}: total");
    assert_eq!(st.runs(), 0, "{name}: runs before the first step");
    assert!(!st.finished(), "{name}: finished before the first step");
    let mut last = 0;
    let result = run_to_end(st.as_mut(), chunk, |done, total| {
        assert!(
            done > last && done <= total,
            "{name}: chunk of {chunk}: {last} → {done} of {total}"
        );
        last = done;
    })
    .unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(st.finished(), "{name}: not finished");
    assert_eq!(st.runs(), st.total(), "{name}: runs at the end");
    assert_eq!(
        st.result().unwrap_or_else(|e| panic!("{name}: {e}")),
        result,
        "{name}: result() after the end"
    );
    result
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn chunking_never_changes_a_study() {
    let studies = study_presets();
    assert!(!studies.is_empty(), "no preset has a study");
    for (name, s) in &studies {
        let a = run_study(name, s, STUDY_RUNS, 7);
        let b = run_study(name, s, STUDY_RUNS, 1000);
        if let Some(d) = first_difference(&a, &b, "") {
            panic!("{name}: chunks of 7 and of 1000 differ at {d}");
        }
    }
}
in_browser!(chunking_never_changes_a_study);

/// The one wasm `Study` class returns, chunk by chunk, the JSON of the core's study.
#[cfg(target_arch = "wasm32")]
fn the_wasm_study_class_returns_the_core_result() {
    let studies = study_presets();
    assert!(!studies.is_empty(), "no preset has a study");
    for (name, s) in &studies {
        let json = serde_json::to_string(s).expect("JSON");
        let mut b = confset::web::Study::new(&json, STUDY_RUNS as u32)
            .unwrap_or_else(|e| panic!("{name}: {e:?}"));
        assert_eq!(b.total(), STUDY_RUNS, "{name}");
        let mut last = String::new();
        while !b.finished() {
            let before = b.runs();
            last = b.step(7).unwrap_or_else(|e| panic!("{name}: {e:?}"));
            assert!(b.runs() > before, "{name}: the study does not advance");
        }
        assert_eq!(b.runs(), b.total(), "{name}");
        let got: Value = serde_json::from_str(&b.result().expect("result")).expect("JSON");
        let stepped: Value = serde_json::from_str(&last).expect("JSON");
        assert_eq!(got, stepped, "{name}: step's result and result() differ");
        let want = run_study(name, s, STUDY_RUNS, 7);
        if let Some(d) = first_difference(&got, &want, "") {
            panic!("{name}: the binding and the core differ at {d}");
        }
        // runs = 0: the scenario's own count.
        let own = confset::web::Study::new(&json, 0).unwrap_or_else(|e| panic!("{name}: {e:?}"));
        let core = s.study(None).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(own.total(), core.total(), "{name}: runs = 0");
    }
}
in_browser!(the_wasm_study_class_returns_the_core_result);

// ---------------------------------------------------------------------------------------------
// 7. The command line prints the core's results.
// ---------------------------------------------------------------------------------------------

#[cfg(not(target_arch = "wasm32"))]
pub(crate) fn cli(args: &[&str]) -> Value {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_confset"))
        .args(args)
        .output()
        .expect("the confset binary runs");
    assert!(
        out.status.success(),
        "confset {}: {}\n{}",
        args.join(" "),
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("confset {}: not JSON: {e}", args.join(" ")))
}

/// `confset experiment --preset NAME --runs 40` for the first preset of each method that has a
/// study prints what `Scenario::study(Some(40))` gives.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn cli_experiment_prints_the_core_study() {
    let mut methods = Vec::new();
    for (name, s) in study_presets() {
        if methods.contains(&s.method) {
            continue;
        }
        methods.push(s.method);
        let want = run_study(&name, &s, 40, 13);
        let got = cli(&["experiment", "--preset", &name, "--runs", "40"]);
        if let Some(d) = first_difference(&got, &want, "") {
            panic!("confset experiment --preset {name}: differs from the core at {d}");
        }
    }
    assert!(!methods.is_empty());
    eprintln!("confset experiment checked for {methods:?}");
}

/// `confset run --preset NAME` prints every preset's report.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn cli_run_prints_every_preset_report() {
    for p in presets::all() {
        let want = report_value(&run(&p.name, &p.scenario));
        let got = cli(&["run", "--preset", &p.name]);
        if let Some(d) = first_difference(&got, &want, "") {
            panic!(
                "confset run --preset {}: differs from the core at {d}",
                p.name
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 8. Every method on explicit data.
// ---------------------------------------------------------------------------------------------

/// A report key that holds a simulation's truth, or what is computed from it, of any method
/// (`scenario::truth_keys`, each method's scenario file's list), or its whole path there (an
/// entry starting with '.'): a report on `data` has none of them (or null where the field is a
/// [`NULLABLE`] one). Every method's keys, since a compare report holds the others' results.
fn is_truth(key: &str, path: &str) -> bool {
    Method::ALL
        .into_iter()
        .flat_map(confset::scenario::truth_keys)
        .any(|(k, _)| k == key || k == path)
}

/// Report fields framed around the truth too, not compared: LSCR fits the figure's window to
/// the region, the ellipses *and the true state*, and measures the region's area and boundary
/// inside that window. For a bounded region the truth lies inside the frame anyway and they
/// agree; for lscr-ma1's unbounded band with the truth placed at 3.2σ they do not.
const FRAMING: [&str; 3] = [".lscr.window", ".lscr.area", ".lscr.boundary"];

/// Compare a report on data with the simulated one: every key of the data report is in the
/// simulated one with the same value (numbers to 1e-9 relative), and the simulated report's
/// other keys are truth. Pushes each difference to `diffs`; returns how many numbers agreed.
fn compare_data_report(sim: &Value, data: &Value, path: &str, diffs: &mut Vec<String>) -> usize {
    match (sim, data) {
        (Value::Object(s), Value::Object(d)) => {
            let mut n = 0;
            for (k, v) in d {
                let p = format!("{path}.{k}");
                match s.get(k) {
                    _ if FRAMING.contains(&p.as_str()) => {}
                    _ if is_truth(k, &p) && !v.is_null() => {
                        diffs.push(format!("{p}: truth in a report on data"))
                    }
                    Some(_) if is_truth(k, &p) => {}
                    Some(w) => n += compare_data_report(w, v, &p, diffs),
                    None => diffs.push(format!("{p}: only in the report on data")),
                }
            }
            for k in s
                .keys()
                .filter(|k| !d.contains_key(*k) && !is_truth(k, &format!("{path}.{k}")))
            {
                diffs.push(format!("{path}.{k}: missing from the report on data"));
            }
            n
        }
        (Value::Array(s), Value::Array(d)) if s.len() == d.len() => s
            .iter()
            .zip(d)
            .enumerate()
            .map(|(i, (v, w))| compare_data_report(v, w, &format!("{path}[{i}]"), diffs))
            .sum(),
        (Value::Number(a), Value::Number(b)) => {
            let (a, b) = (
                a.as_f64().unwrap_or(f64::NAN),
                b.as_f64().unwrap_or(f64::NAN),
            );
            if rel_close(a, b, 1e-9) {
                1
            } else {
                diffs.push(format!("{path}: {b:.17e} on data, {a:.17e} simulated"));
                0
            }
        }
        _ if sim == data => 0,
        _ => {
            diffs.push(format!(
                "{path}: {} on data, {} simulated",
                cut(data),
                cut(sim)
            ));
            0
        }
    }
}

/// The inputs a simulated scenario used: `simulate.u`, or (a method that draws its own
/// inputs) the `u` its result block reports.
pub(crate) fn inputs_used(s: &Scenario, report: &Value) -> Vec<Vec<f64>> {
    let given = s
        .simulate
        .as_ref()
        .map(|sim| sim.u.clone())
        .unwrap_or_default();
    if !given.is_empty() {
        return given;
    }
    let mut used: Vec<Vec<f64>> = s
        .method
        .block()
        .and_then(|b| report[b].get("u"))
        .and_then(|u| serde_json::from_value(u.clone()).ok())
        .unwrap_or_default();
    // A block in the paper's time indexing (uniform_lp: u_0 … u_T beside y_1 … y_T) holds one
    // row more than the measurements; `data.u` starts at u_1.
    let measurements = report["y"].as_array().map_or(0, Vec::len);
    if used.len() == measurements + 1 {
        used.remove(0);
    }
    used
}

/// For each scenario of `m` ([`scenarios_of`]) that simulates: the same scenario with the report's measurements and
/// the inputs it used as `data` gives the same report, without truth. Conditioned simulations
/// (`simulate.condition`) are included: the condition shapes the data, not the estimator.
fn data_gives_the_simulated_estimates(m: Method) {
    let mut checked = 0;
    for (name, s) in scenarios_of(m) {
        if s.simulate.is_none() {
            continue;
        }
        let sim = run(&name, &s);
        let sim_v = report_value(&sim);
        let mut d = s.clone();
        d.simulate = None;
        d.data = Some(DataSpec {
            y: sim.y.clone(),
            u: inputs_used(&s, &sim_v),
            t: Vec::new(),
        });
        let name = format!("{name} on data");
        let on_data = run(&name, &d);
        assert!(on_data.x_true.is_none(), "{name}: x_true");
        let mut diffs = Vec::new();
        let numbers = compare_data_report(&sim_v, &report_value(&on_data), "", &mut diffs);
        assert!(
            diffs.is_empty(),
            "{name}: {} difference(s) from the simulated report:\n{}",
            diffs.len(),
            diffs.join("\n")
        );
        assert!(numbers > 0, "{name}: no number compared");
        checked += 1;
    }
    assert!(checked > 0, "no preset of \"{m}\" simulates");
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_method_on_data_gives_the_simulated_estimates() {
    for m in Method::ALL {
        data_gives_the_simulated_estimates(m);
    }
}
in_browser!(every_method_on_data_gives_the_simulated_estimates);

// ---------------------------------------------------------------------------------------------
// 9. The limits the page's controls take from the core are the ones its checks apply.
// ---------------------------------------------------------------------------------------------

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn exported_limits_are_the_checked_ones() {
    let limits = confset::scenario::limits();
    let mut checked = 0;
    for p in presets::all() {
        let Some(sim) = p.scenario.simulate.as_ref() else {
            continue;
        };
        let [lo, hi] = [0, 1].map(|i| {
            limits["simulate.steps"][p.scenario.method.name()][i]
                .as_u64()
                .unwrap_or_else(|| panic!("{}: no steps limit", p.name)) as usize
        });
        for outside in [hi + 1, lo - 1] {
            let mut s = p.scenario.clone();
            s.simulate = Some(SimulateSpec {
                steps: outside,
                ..sim.clone()
            });
            let e = s
                .run()
                .err()
                .unwrap_or_else(|| panic!("{}: steps = {outside} accepted", p.name));
            assert_eq!(e.field, "simulate.steps", "{}: {e}", p.name);
            assert!(
                e.message.contains(&hi.to_string()),
                "{}: the message names the limit {hi}: {e}",
                p.name
            );
        }
        checked += 1;
    }
    assert!(checked > 0);
    let runs = limits["runs"][1].as_u64().expect("runs") as usize;
    assert_eq!(runs, confset::scenario::MAX_STUDY_RUNS);
    let window = limits["uniform.window"][1].as_u64().expect("window");
    let mut s = presets::get("uniform-paper").expect("preset");
    s.uniform.as_mut().expect("uniform block").window = window as usize + 1;
    let e = s.run().expect_err("a window over the limit");
    assert_eq!(e.field, "uniform.window");
    assert!(e.message.contains(&window.to_string()), "{e}");
    // The noise bounds ubb assumes and the true noise it simulates: refused below the lower
    // limit (and past the scenario's largest magnitude), accepted at it (τ and the true noise).
    for field in ["ubb.eps", "ubb.tau", "ubb.sim_eps", "ubb.sim_tau"] {
        let [lo, hi] = [0, 1].map(|i| limits[field][i].as_f64().expect("noise limit"));
        assert_eq!((lo, hi), (0.0, confset::scenario::MAX_MAGNITUDE), "{field}");
        let set = |v: f64| {
            let mut s = presets::get("ubb-series").expect("preset");
            let u = s.ubb.as_mut().expect("ubb block");
            match field {
                "ubb.eps" => u.eps = v,
                "ubb.tau" => u.tau = v,
                "ubb.sim_eps" => u.sim_eps = Some(v),
                _ => u.sim_tau = Some(v),
            }
            s
        };
        let e = set(-0.1).run().expect_err("a negative noise bound");
        assert_eq!(e.field, field, "{e}");
        if field != "ubb.eps" {
            set(lo)
                .run()
                .unwrap_or_else(|e| panic!("{field} = {lo}: {e}"));
        }
    }
}
in_browser!(exported_limits_are_the_checked_ones);

/// The first value of the quantity a view animates by rerunning (LSCR's t, GLLS's s), asked of
/// the core, is one the full run accepts while the value below it is refused by the full run
/// (so the search, which asks the method's validation only, agrees with a run); with the
/// presets' values: LSCR t ≥ n = 2 and M = 80 ≤ 2^t (t = 7) for prediction, t above the
/// smoothed index 15 for smoothing (t = 16); GLLS the first observable horizon (Γ_{s+1} of
/// rank n).
#[test]
fn first_accepted_value_is_the_runs_first() {
    use confset::scenario::{FirstAccepted, Scenario};
    let set = |s: &Scenario, field: &str, v: usize| -> Scenario {
        let mut j = serde_json::to_value(s).unwrap();
        let (block, key) = field.split_once('.').unwrap();
        j[block][key] = serde_json::json!(v);
        // The view's truth stays at the predicted state x_{t+1} as t moves (lscr-ma1's).
        if field == "simulate.steps" && !j["simulate"]["condition"].is_null() {
            assert_eq!(j["lscr"]["estimate"], "predict");
            j["simulate"]["condition"]["t"] = serde_json::json!(v + 1);
        }
        serde_json::from_value(j).unwrap()
    };
    let expected = [
        ("lscr-predict", "simulate.steps", 7),
        ("lscr-smooth", "simulate.steps", 16),
        ("lscr-ma1", "simulate.steps", 7),
        ("glls-saturate", "glls.horizon", 2),
        ("glls-grow", "glls.horizon", 1),
        ("glls-mixed", "glls.horizon", 2),
        ("glls-unstable5", "glls.horizon", 4),
    ];
    for (name, field, value) in expected {
        let mut s = confset::presets::get(name).unwrap();
        if field == "glls.horizon" {
            // The view animates an explicit horizon: the preset's best one, from its report.
            let best = s.run().unwrap().glls.unwrap().s;
            s = set(&s, field, best);
        }
        let got = s.first_accepted().unwrap();
        assert_eq!(
            got,
            FirstAccepted {
                field: field.into(),
                value
            },
            "{name}"
        );
        assert!(
            set(&s, field, value).run().is_ok(),
            "{name}: the run at {value}"
        );
        let below = set(&s, field, value - 1).run();
        assert!(
            below.is_err(),
            "{name}: the run at {} is accepted",
            value - 1
        );
    }
    // A method animating nothing by rerunning says so in words; a refused scenario gives
    // its own message.
    let e = confset::presets::get("ubb-track")
        .unwrap()
        .first_accepted()
        .unwrap_err();
    assert!(e.to_string().contains("animates by rerunning"), "{e}");
    let mut s = confset::presets::get("lscr-predict").unwrap();
    s.lscr.as_mut().unwrap().m = Some(1 << 20);
    let e = s.first_accepted().unwrap_err();
    assert!(e.to_string().contains("lscr.M"), "{e}");
}
in_browser!(first_accepted_value_is_the_runs_first);
