//! One seeded mutation fuzzer over every preset's JSON (driven by `presets::all()`, so a new
//! preset or method is fuzzed without a line here): numbers replaced by the extremes of f64
//! (±1e308, 5e-324, 1e154, 1e-300), sizes of 10⁹ and 2⁶⁴ − 1, wrong types, deleted keys,
//! duplicated and ragged rows, oversized matrices (40 × 40, 400 × 400), another method on the
//! same scenario. Every case must give a report whose numbers are all JSON numbers, or an
//! error naming a field; never a panic, a hang or an abort (an allocation of many GB aborts
//! the test process, which fails the run).
//!
//! `cargo test` runs [`SAMPLE`] cases (in wasm a few per preset); the long run is
//! `CONFSET_FUZZ_CASES=1000000 cargo test --profile bench --test suite fuzz::long_run -- --ignored --nocapture`,
//! which prints its counts per outcome. Case k of preset p is drawn from its own seed, so any
//! case is replayed from its number alone (`CONFSET_FUZZ_ONLY=preset:k`), and the long run can
//! be cut into pieces whose counts add up: `CONFSET_FUZZ_FROM=200000 CONFSET_FUZZ_CASES=100000`
//! runs cases 200,000 … 299,999 (the numbering of one run of 1,000,000). Do not suspend a
//! piece (SIGSTOP, a laptop's sleep): the hang watchdog measures wall time, so the case in
//! flight on resuming is reported as a hang (seen: both cases so reported ran in 0.2–0.3 s when
//! replayed with `CONFSET_FUZZ_ONLY`).

use crate::common::contract::check_report_json;
use crate::common::mutate::mutate;
use confset::presets;
use confset::scenario::{Report, Scenario};
use confset::Method;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde_json::Value;

/// What a mutated scenario gave.
enum Outcome {
    /// Refused by the parser.
    Refused(confset::Error),
    /// Refused by the run.
    Failed(confset::Error),
    Report(Box<Report>),
}

/// Parse and run, catching a panic natively (in wasm a panic aborts the test, which fails it
/// just as well). A panic comes back as its message.
fn outcome(text: &str) -> Result<Outcome, String> {
    let go = || match Scenario::from_json(text) {
        Err(e) => Outcome::Refused(e),
        Ok(s) => match s.run() {
            Ok(r) => Outcome::Report(Box::new(r)),
            Err(e) => Outcome::Failed(e),
        },
    };
    #[cfg(not(target_arch = "wasm32"))]
    return std::panic::catch_unwind(std::panic::AssertUnwindSafe(go)).map_err(|p| {
        p.downcast_ref::<String>()
            .cloned()
            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default()
    });
    #[cfg(target_arch = "wasm32")]
    Ok(go())
}

/// Cases of the sample `cargo test` runs: natively about 20,000 (spread over the presets), in
/// wasm 8 per preset.
const SAMPLE: usize = if cfg!(target_arch = "wasm32") {
    8 * 16
} else {
    20_000
};

/// A case still running after this long (wall time) is named on stderr by the watchdog, once:
/// a hang is then stopped by the test phase's own limit (.ci/test), with its name in the log.
/// Nothing fails on the clock: a loaded machine may take any time (issue 24).
#[cfg(not(target_arch = "wasm32"))]
const HANG_SECONDS: u64 = 30;

/// The fuzzer's tally.
#[derive(Default)]
struct Tally {
    cases: usize,
    refused: usize,
    failed: usize,
    reports: usize,
    /// Panics and errors without a field or message: "preset with mutation: what".
    broken: Vec<String>,
    /// Reports that break the JSON contract of [`check_report_json`].
    non_finite: Vec<String>,
    /// The slowest cases (seconds, case), slowest first.
    slowest: Vec<(f64, String)>,
}

impl Tally {
    fn add(&mut self, other: Tally) {
        self.cases += other.cases;
        self.refused += other.refused;
        self.failed += other.failed;
        self.reports += other.reports;
        self.broken.extend(other.broken);
        self.non_finite.extend(other.non_finite);
        self.slowest.extend(other.slowest);
        self.slowest.sort_by(|a, b| b.0.total_cmp(&a.0));
        self.slowest.truncate(8);
    }

    fn summary(&self) -> String {
        let slow: Vec<String> = self
            .slowest
            .iter()
            .take(5)
            .map(|(t, c)| format!("{t:.2} s {c}"))
            .collect();
        format!(
            "fuzz: {} cases: {} refused by the parser, {} refused by the run, {} reports ({} with non-finite numbers), {} panics or errors without a field; slowest:\n  {}",
            self.cases,
            self.refused,
            self.failed,
            self.reports,
            self.non_finite.len(),
            self.broken.len(),
            slow.join("\n  ")
        )
    }
}

/// Case `k` of preset `p`: its mutation, from a seed of its own.
fn case(p: &presets::Preset, base: &Value, k: usize) -> (Value, String) {
    let seed = p
        .name
        .bytes()
        .fold(0x5eed_f00d_u64, |h, b| h.rotate_left(7) ^ u64::from(b))
        ^ (k as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (s, what) = mutate(base, &mut rng);
    (s, format!("{}:{k} with {what}", p.name))
}

/// Run one case into a tally of one.
fn run_case(s: &Value, name: String) -> Tally {
    let mut t = Tally {
        cases: 1,
        ..Tally::default()
    };
    let text = s.to_string();
    #[cfg(not(target_arch = "wasm32"))]
    let started = std::time::Instant::now();
    #[cfg(not(target_arch = "wasm32"))]
    let _watch = watchdog::watch(&name);
    match outcome(&text) {
        Err(panic) => t.broken.push(format!("{name}: PANIC {panic}")),
        Ok(Outcome::Refused(e)) | Ok(Outcome::Failed(e))
            if e.field.is_empty() || e.message.is_empty() =>
        {
            t.broken.push(format!(
                "{name}: an error without a field or message: {e:?}"
            ))
        }
        Ok(Outcome::Refused(_)) => t.refused += 1,
        Ok(Outcome::Failed(_)) => t.failed += 1,
        Ok(Outcome::Report(r)) => {
            t.reports += 1;
            if let Err(e) = check_report_json(&r) {
                t.non_finite.push(format!("{name}: {e}"));
            }
        }
    }
    #[cfg(not(target_arch = "wasm32"))]
    t.slowest.push((started.elapsed().as_secs_f64(), name));
    t
}

/// `cases` cases spread evenly over the presets (case numbers 0, 1, … per preset), natively
/// in parallel.
fn fuzz(cases: usize) -> Tally {
    fuzz_range(0..cases)
}

/// Cases `range` of the one numbering (case i is case i / #presets of preset i % #presets).
fn fuzz_range(range: std::ops::Range<usize>) -> Tally {
    let all = presets::all();
    let bases: Vec<Value> = all
        .iter()
        .map(|p| serde_json::to_value(&p.scenario).expect("JSON"))
        .collect();
    let only = option_env_var("CONFSET_FUZZ_ONLY");
    let jobs: Vec<(usize, usize)> = range
        .map(|i| (i % all.len(), i / all.len()))
        .filter(|&(p, k)| {
            only.as_deref()
                .is_none_or(|o| o == format!("{}:{k}", all[p].name))
        })
        .collect();
    let one = |&(p, k): &(usize, usize)| {
        let (s, name) = case(&all[p], &bases[p], k);
        run_case(&s, name)
    };
    #[cfg(not(target_arch = "wasm32"))]
    {
        use rayon::prelude::*;
        jobs.par_iter().map(one).reduce(Tally::default, |mut a, b| {
            a.add(b);
            a
        })
    }
    #[cfg(target_arch = "wasm32")]
    jobs.iter().map(one).fold(Tally::default(), |mut a, b| {
        a.add(b);
        a
    })
}

fn option_env_var(name: &str) -> Option<String> {
    #[cfg(not(target_arch = "wasm32"))]
    return std::env::var(name).ok();
    #[cfg(target_arch = "wasm32")]
    {
        let _ = name;
        None
    }
}

/// A thread that names on stderr a case still running past [`HANG_SECONDS`] (a hang cannot
/// name itself; the phase's time limit stops it).
#[cfg(not(target_arch = "wasm32"))]
mod watchdog {
    use std::collections::HashMap;
    use std::sync::{Mutex, OnceLock};
    use std::time::{Duration, Instant};

    type Running = Mutex<HashMap<u64, (String, Instant)>>;

    fn running() -> &'static Running {
        static RUNNING: OnceLock<Running> = OnceLock::new();
        RUNNING.get_or_init(|| {
            std::thread::spawn(|| loop {
                std::thread::sleep(Duration::from_secs(1));
                let slow = running().lock().ok().and_then(|mut m| {
                    let id = m
                        .iter()
                        .find(|(_, (_, t))| t.elapsed() > Duration::from_secs(super::HANG_SECONDS))
                        .map(|(id, _)| *id)?;
                    m.remove(&id).map(|(c, _)| c)
                });
                if let Some(c) = slow {
                    // Past the test harness's capture, which would hold it until the test ends.
                    use std::io::Write;
                    let _ = writeln!(
                        std::io::stderr().lock(),
                        "fuzz: still running after {} s: {c}",
                        super::HANG_SECONDS
                    );
                }
            });
            Mutex::new(HashMap::new())
        })
    }

    /// Watched while the guard lives.
    pub struct Guard(u64);

    pub fn watch(case: &str) -> Guard {
        static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        let id = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        if let Ok(mut m) = running().lock() {
            m.insert(id, (case.to_string(), Instant::now()));
        }
        Guard(id)
    }

    impl Drop for Guard {
        fn drop(&mut self) {
            if let Ok(mut m) = running().lock() {
                m.remove(&self.0);
            }
        }
    }
}

/// Every case: a report with JSON numbers only, or an error naming a field.
fn assert_clean(t: &Tally) {
    eprintln!("{}", t.summary());
    assert!(
        t.broken.is_empty() && t.non_finite.is_empty(),
        "{} of {} mutated presets panicked or gave an error without a field, {} of {} reports break the JSON contract:\n{}",
        t.broken.len(),
        t.cases,
        t.non_finite.len(),
        t.reports,
        t.broken.iter().chain(&t.non_finite).take(40).cloned().collect::<Vec<_>>().join("\n")
    );
    // The fuzzer reaches every side: the parser refuses, the run refuses, reports come out.
    assert!(
        t.refused > 0 && t.failed > 0 && t.reports > 0,
        "{} refused / {} failed / {} reports",
        t.refused,
        t.failed,
        t.reports
    );
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn mutated_presets_give_a_finite_report_or_a_field_error() {
    assert_clean(&fuzz(SAMPLE));
}
in_browser!(mutated_presets_give_a_finite_report_or_a_field_error);

/// The long run: `CONFSET_FUZZ_CASES` cases (default 1,000,000).
#[cfg(not(target_arch = "wasm32"))]
#[test]
#[ignore = "the long run (minutes to hours): run it by hand, see the module docs"]
fn long_run() {
    let number = |name: &str, default: usize| {
        option_env_var(name)
            .and_then(|c| c.parse().ok())
            .unwrap_or(default)
    };
    let from = number("CONFSET_FUZZ_FROM", 0);
    assert_clean(&fuzz_range(
        from..from + number("CONFSET_FUZZ_CASES", 1_000_000),
    ));
}

#[test]
fn every_method_is_reached() {
    // Sanity of the generator: mutations switch methods, so every method is fuzzed.
    let p = &presets::all()[0];
    let base = serde_json::to_value(&p.scenario).expect("JSON");
    let mut seen = std::collections::HashSet::new();
    for k in 0..400 {
        let (s, _) = case(p, &base, k);
        seen.insert(s["method"].as_str().unwrap_or("").to_string());
    }
    for m in Method::ALL {
        assert!(seen.contains(m.name()), "no case switches to {m}");
    }
}

/// The work at the limits: every preset with several size fields at their limits at once, right
/// under the budget (the common fraction of the way to the limits whose estimate fits it), in
/// pairs and all together, timed (CPU seconds of the thread, and wall) with the process's peak
/// memory (printed, not asserted:
/// timings belong to the machine), with the estimate beside each; then each field alone at its
/// limit, refused or run. The README's Limits section quotes this run:
/// `cargo test --profile bench --test suite fuzz::work_at_the_limits -- --ignored --nocapture --test-threads 1`.
#[cfg(not(target_arch = "wasm32"))]
#[test]
#[ignore = "a measurement (minutes): run it by hand"]
fn work_at_the_limits() {
    use crate::common::limits::{at, knobs, under_budget};
    use confset::scenario::{budget, Job};
    /// The process's peak resident memory since the last reset, in MB (Linux).
    fn peak_mb(reset: bool) -> f64 {
        if reset {
            let _ = std::fs::write("/proc/self/clear_refs", "5");
        }
        std::fs::read_to_string("/proc/self/status")
            .ok()
            .and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("VmHWM:"))
                    .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
            })
            .map_or(0.0, |kb| kb / 1024.0)
    }
    // CONFSET_WORK_ONLY=text: only presets whose name holds it; CONFSET_WORK_SCALE=x: aim the
    // estimates at x times the budget (calibrating with a raised budget); CONFSET_WORK_DUMP=dir:
    // write the slowest accepted scenario of each method there (METHOD.json), to time in wasm.
    /// The thread's CPU time in seconds (Linux): the machine is shared, so wall time overstates.
    fn cpu_seconds() -> f64 {
        std::fs::read_to_string("/proc/thread-self/schedstat")
            .ok()
            .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
            .map_or(0.0, |ns| ns / 1e9)
    }
    let only = option_env_var("CONFSET_WORK_ONLY");
    let scale: f64 = option_env_var("CONFSET_WORK_SCALE")
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    // (seconds, MB, line) of every run, and the slowest accepted per method.
    let mut rows: Vec<(f64, f64, String)> = Vec::new();
    let mut slowest: std::collections::BTreeMap<String, (f64, f64, String, String)> =
        Default::default();
    for p in presets::all() {
        if only.as_deref().is_some_and(|o| !p.name.contains(o)) {
            continue;
        }
        let base = serde_json::to_value(&p.scenario).expect("JSON");
        let method = base["method"].as_str().unwrap_or("").to_string();
        let ks = knobs(&base);
        let mut sets: Vec<Vec<&crate::common::limits::Knob>> = vec![ks.iter().collect()];
        for i in 0..ks.len() {
            for j in i + 1..ks.len() {
                sets.push(vec![&ks[i], &ks[j]]);
            }
        }
        let mut cases: Vec<(String, Value)> = Vec::new();
        for set in &sets {
            let names: Vec<String> = set.iter().map(|k| k.name()).collect();
            if let Some((t, s)) = under_budget(&base, set, scale) {
                cases.push((
                    format!("{} at {:.0} % of the way", names.join(" + "), 100.0 * t),
                    s,
                ));
            }
        }
        for k in ks.iter().filter(|_| scale == 1.0) {
            cases.push((
                format!("{} alone at its limit", k.name()),
                at(&base, &[k], 1.0),
            ));
        }
        for (what, s) in cases {
            let text = s.to_string();
            let est = Scenario::from_json(&text)
                .map(|sc| sc.work(Job::Report))
                .unwrap_or_default();
            peak_mb(true);
            let (t0, c0) = (std::time::Instant::now(), cpu_seconds());
            let r = Scenario::from_json(&text).and_then(|s| {
                s.run()
                    .map(|r| serde_json::to_string(&r).map(|j| j.len()).unwrap_or(0))
            });
            let wall = t0.elapsed().as_secs_f64();
            let secs = cpu_seconds() - c0;
            let mb = peak_mb(false);
            let mut terms: Vec<_> = est.operations.iter().collect();
            terms.sort_by(|a, b| b.amount.total_cmp(&a.amount));
            let top = terms
                .iter()
                .take(3)
                .map(|t| {
                    format!(
                        "{:.0}% {}",
                        100.0 * t.amount / est.total_operations(),
                        t.formula.chars().take(30).collect::<String>()
                    )
                })
                .collect::<Vec<_>>()
                .join(" | ");
            let line = format!(
                "{secs:7.3} s ({wall:5.2} s wall) {mb:6.0} MB  est {:8.2e} ops {:5.0} MB ({:4.2} ns/op)  {} with {what}: {}  [{}]",
                est.total_operations(),
                est.total_bytes() / 1e6,
                secs * 1e9 / est.total_operations().max(1.0),
                p.name,
                match &r {
                    Ok(len) => format!("report of {:.1} MB JSON", *len as f64 / 1e6),
                    Err(e) => format!("{} {}", e.field, e.message.chars().take(160).collect::<String>()),
                },
                top
            );
            eprintln!("{line}");
            if r.is_ok() {
                let e = slowest.entry(method.clone()).or_insert((
                    0.0,
                    0.0,
                    String::new(),
                    String::new(),
                ));
                if secs > e.0 {
                    *e = (secs, mb, line.clone(), text.clone());
                }
            }
            rows.push((secs, mb, line));
        }
    }
    rows.sort_by(|a, b| b.0.total_cmp(&a.0));
    eprintln!(
        "\nslowest runs (budget {:.0e} operations, {:.0} MB):",
        budget::MAX_OPERATIONS,
        budget::MAX_BYTES / 1e6
    );
    for (_, _, r) in rows.iter().take(12) {
        eprintln!("{r}");
    }
    eprintln!("\nslowest accepted per method:");
    let dump = option_env_var("CONFSET_WORK_DUMP");
    for (m, (_, _, line, text)) in &slowest {
        eprintln!("{m:10} {line}");
        if let Some(dir) = &dump {
            std::fs::write(format!("{dir}/{m}.json"), text).expect("the dump directory");
        }
    }
}
