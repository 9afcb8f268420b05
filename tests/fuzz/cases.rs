//! The cases, by kind: each a pure function of (kind, index) and the preset bases, written out
//! in full (scenario text, CSV text, part texts, command line and files) so that a reproducer
//! replays without the generator.

use crate::csv_mutate;
use crate::mutate::{mutate, nodes, path_text, pick};
use confset::presets;
use confset::scenario::{Job as Work, Scenario};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};
use std::collections::HashMap;
use std::path::Path;

/// The kinds of case that are not a method's: studies, CSV data files, merges of tampered
/// parts, shard edges, garbage text, and the real binary.
const OTHER_KINDS: [&str; 6] = ["study", "csv", "merge", "shard", "garbage", "cli"];

/// Every kind of case: one per method of `Method::ALL` (mutated presets run as `confset run`
/// would, with the report's CSV and now and then its figure: a new method is fuzzed without a
/// word here), then [`OTHER_KINDS`].
pub fn kinds() -> Vec<String> {
    confset::Method::ALL
        .iter()
        .map(|m| m.name())
        .chain(OTHER_KINDS)
        .map(String::from)
        .collect()
}

/// One case, complete.
#[derive(Serialize, Deserialize, Clone, Debug)]
pub struct Case {
    /// `kind:index`
    pub id: String,
    pub kind: String,
    /// One line: the base and what was done to it.
    pub what: String,
    pub job: Job,
}

/// What a case asks of the library or the binary.
#[derive(Serialize, Deserialize, Clone, Debug)]
#[serde(tag = "do", rename_all = "snake_case")]
pub enum Job {
    /// Parse, apply CSV data if any, run; the report's JSON and CSV checked, its first useful
    /// panel drawn as SVG when `figure`.
    Run {
        scenario: String,
        csv_data: Option<String>,
        figure: bool,
    },
    /// A study of `runs` (None: the scenario's own), restricted to `shard` (i, N) if given;
    /// at most [`STUDY_RUNS`] of its runs are run, then its result (finished) or its partial.
    Study {
        scenario: String,
        runs: Option<usize>,
        shard: Option<(usize, usize)>,
    },
    /// A fresh study of `runs` merges the part texts, completes and gives its result.
    Merge {
        scenario: String,
        runs: Option<usize>,
        parts: Vec<String>,
    },
    /// The `confset` binary with `args` (`{dir}` is the case's directory, where `files` are
    /// written first).
    Cli { args: Vec<String>, files: Vec<File> },
}

/// An input file of a command-line case.
#[derive(Serialize, Deserialize, Clone, Debug)]
pub struct File {
    pub name: String,
    pub text: String,
    /// Written as one byte per character (characters below 256), so a file can hold bytes
    /// that are not UTF-8.
    #[serde(default)]
    pub raw: bool,
}

/// Most runs a study case runs (a mutated run count may be 10⁹).
pub const STUDY_RUNS: usize = 64;

/// A preset's scenario JSON, as shipped and made light.
#[derive(Serialize, Deserialize, Clone)]
pub struct Base {
    pub name: String,
    pub method: String,
    pub full: Value,
    /// Size fields cut down (see [`lighten`]) so that a case runs in milliseconds.
    pub light: Value,
    /// Whether the preset has a study.
    pub study: bool,
}

/// The bases, and the genuine shard parts made from them (cached: a merge case tampers with
/// parts a study really wrote).
pub struct Bases {
    pub all: Vec<Base>,
    /// (base, runs, shards) → each shard's partial and run range.
    parts: HashMap<(usize, usize, usize), Vec<(Value, [usize; 2])>>,
}

impl Bases {
    /// The bases from `<out>/bases.json`, made (and written there) if absent or of another
    /// confset version: lightening runs every preset several times.
    pub fn load(out: &Path) -> Bases {
        let file = out.join("bases.json");
        let version = env!("CARGO_PKG_VERSION");
        let cached: Option<(String, Vec<Base>)> = std::fs::read_to_string(&file)
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok());
        let all = match cached {
            Some((v, all)) if v == version => all,
            _ => {
                eprintln!(
                    "campaign: lightening the presets (once; cached in {})",
                    file.display()
                );
                let all: Vec<Base> = presets::all()
                    .into_iter()
                    .map(|p| {
                        let full = serde_json::to_value(&p.scenario).expect("a preset is JSON");
                        Base {
                            name: p.name.clone(),
                            method: p.scenario.method.name().into(),
                            light: lighten(&full),
                            study: p.scenario.study(Some(1)).is_ok(),
                            full,
                        }
                    })
                    .collect();
                let _ = std::fs::create_dir_all(out);
                let _ = std::fs::write(&file, json!([version, all]).to_string());
                all
            }
        };
        Bases {
            all,
            parts: HashMap::new(),
        }
    }

    /// The genuine partials of shards 0 … n − 1 of base `b`'s light study of `runs` runs.
    fn parts(&mut self, b: usize, runs: usize, n: usize) -> Vec<Value> {
        self.shards(b, runs, n)
            .into_iter()
            .map(|(p, _)| p)
            .collect()
    }

    fn shards(&mut self, b: usize, runs: usize, n: usize) -> Vec<(Value, [usize; 2])> {
        let light = &self.all[b].light;
        self.parts
            .entry((b, runs, n))
            .or_insert_with(|| {
                let s = Scenario::from_json(&light.to_string()).expect("a light base parses");
                (0..n)
                    .map(|i| {
                        let mut st = s.study(Some(runs)).expect("a light study");
                        st.restrict(i, n).expect("a shard");
                        confset::study::run_to_end(st.as_mut(), 1000, |_, _| {})
                            .expect("a light study runs");
                        let r = st.range();
                        (st.partial().expect("a partial"), [r.start, r.end])
                    })
                    .collect()
            })
            .clone()
    }

    /// The part file `confset experiment --shard i/N` writes (the CLI's `Part`).
    fn part_file(&mut self, b: usize, runs: usize, n: usize, i: usize) -> Value {
        let (partial, range) = self.shards(b, runs, n)[i].clone();
        let s = Scenario::from_json(&self.all[b].light.to_string()).expect("parses");
        json!({
            "confset": env!("CARGO_PKG_VERSION"),
            "scenario": self.all[b].light,
            "scenario_digest": s.digest().expect("a digest"),
            "runs": runs,
            "shard": [i, n],
            "range": range,
            "partial": partial,
        })
    }
}

/// The base with every whole number of 4 or more that sizes the work (steps, runs, grid …)
/// cut to an eighth, a quarter or a half, one field at a time, kept where the core's work
/// estimate falls and the scenario still runs: the same code paths in a fraction of the time. Deterministic (the
/// estimate, not the clock, decides).
fn lighten(full: &Value) -> Value {
    let work = |v: &Value| -> Option<f64> {
        let s = Scenario::from_json(&v.to_string()).ok()?;
        Some(s.work(Work::Report).total_operations())
    };
    let runs = |v: &Value| {
        Scenario::from_json(&v.to_string())
            .and_then(|s| s.run())
            .is_ok()
    };
    let mut light = full.clone();
    let Some(mut best) = work(&light) else {
        return light;
    };
    // Two passes: a field bound by another (a time within the steps) is cut once the other is.
    for _ in 0..2 {
        for (path, v) in nodes(&light.clone()) {
            let Some(n) = v.as_u64().filter(|&n| n >= 4) else {
                continue;
            };
            for cut in [n / 8, n / 4, n / 2] {
                let mut trial = light.clone();
                *crate::mutate::at(&mut trial, &path) = json!(cut.max(2));
                match work(&trial) {
                    Some(w) if w < 0.9 * best && runs(&trial) => {
                        best = w;
                        light = trial;
                        break;
                    }
                    _ => {}
                }
            }
        }
    }
    light
}

/// The seed of case `index` of `kind`: the campaign's own (issue 25), the kind, the index.
fn rng_of(kind: &str, index: u64) -> ChaCha8Rng {
    let h = kind.bytes().fold(0xca3a_1e5e_ed00_0025_u64, |h, b| {
        h.rotate_left(9) ^ u64::from(b)
    });
    ChaCha8Rng::seed_from_u64(h ^ index.wrapping_mul(0x9e37_79b9_7f4a_7c15))
}

/// The kind of case `index` when `kinds` are run: in turn, four rounds at a time, with the
/// binary (a process per case, ~45 ms) in one round of the four.
pub fn kind_of(kinds: &[String], index: u64) -> &str {
    let cycle: Vec<&String> = (0..4)
        .flat_map(|round| kinds.iter().filter(move |k| round == 0 || *k != "cli"))
        .collect();
    cycle[(index % cycle.len() as u64) as usize]
}

/// Case `index` of `kind`.
pub fn make(bases: &mut Bases, kind: &str, index: u64) -> Case {
    let mut rng = rng_of(kind, index);
    let (what, job) = match kind {
        "study" => study(bases, &mut rng),
        "csv" => csv(bases, &mut rng),
        "merge" => merge(bases, &mut rng),
        "shard" => shard(bases, &mut rng),
        "garbage" => garbage(bases, &mut rng),
        "cli" => cli(bases, &mut rng),
        method => run(bases, method, &mut rng),
    };
    Case {
        id: format!("{kind}:{index}"),
        kind: kind.into(),
        what,
        job,
    }
}

/// Base indices matching `keep`.
fn indices(bases: &Bases, keep: impl Fn(&Base) -> bool) -> Vec<usize> {
    (0..bases.all.len())
        .filter(|&i| keep(&bases.all[i]))
        .collect()
}

/// A base (light fifteen times in sixteen), mutated one to three times: its text and what was
/// done.
fn mutated(
    bases: &Bases,
    b: usize,
    method: Option<&str>,
    rng: &mut ChaCha8Rng,
) -> (String, String) {
    let base = &bases.all[b];
    let full = rng.random_ratio(1, 16);
    let mut v = if full {
        base.full.clone()
    } else {
        base.light.clone()
    };
    let mut what = vec![format!(
        "{}{}",
        base.name,
        if full { "" } else { " (light)" }
    )];
    if let Some(m) = method {
        if base.method != m {
            v["method"] = json!(m);
            what.push(format!("method := \"{m}\""));
        }
    }
    for _ in 0..[1, 1, 1, 2, 3][rng.random_range(0..5)] {
        let (next, did) = mutate(&v, rng);
        v = next;
        what.push(did);
    }
    (v.to_string(), what.join(", "))
}

/// A method's case: a mutated preset of that method (kf: the SCF presets run as kf) run.
fn run(bases: &mut Bases, method: &str, rng: &mut ChaCha8Rng) -> (String, Job) {
    let own = if method == "kf" { "scf" } else { method };
    let ids = indices(bases, |b| b.method == own);
    let b = pick(rng, &ids).expect("every method has a preset");
    let (scenario, what) = mutated(bases, b, Some(method), rng);
    let figure = rng.random_ratio(1, 8);
    let job = Job::Run {
        scenario,
        csv_data: None,
        figure,
    };
    (
        format!("{what}{}", if figure { ", figure" } else { "" }),
        job,
    )
}

/// Run counts at the edges of the SCF batch of 8 and of the shards.
const RUN_COUNTS: [usize; 9] = [0, 1, 2, 3, 7, 8, 9, 17, 1_000_000_000];

/// A mutated preset's study, with an edge run count or its own.
fn study(bases: &mut Bases, rng: &mut ChaCha8Rng) -> (String, Job) {
    let ids = indices(bases, |b| b.study);
    let b = pick(rng, &ids).expect("studies");
    let (scenario, what) = mutated(bases, b, None, rng);
    let runs = (!rng.random_ratio(1, 4)).then(|| pick(rng, &RUN_COUNTS).expect("counts"));
    let job = Job::Study {
        scenario,
        runs,
        shard: None,
    };
    (format!("{what}, study of {runs:?} runs"), job)
}

/// Shard (i, N) at the edges for a study of `runs` runs.
fn edge_shard(runs: usize, rng: &mut ChaCha8Rng) -> (usize, usize) {
    let n = pick(rng, &[0, 1, 2, 3, 7, 8, runs, runs + 1, usize::MAX]).expect("counts");
    let i = pick(
        rng,
        &[
            0,
            1,
            n.saturating_sub(1),
            n,
            n.saturating_add(1),
            usize::MAX,
        ],
    )
    .expect("indices");
    (i, n)
}

/// A light study restricted to an edge shard, or all its shards merged in a shuffled order.
fn shard(bases: &mut Bases, rng: &mut ChaCha8Rng) -> (String, Job) {
    let ids = indices(bases, |b| b.study);
    let b = pick(rng, &ids).expect("studies");
    let runs = pick(rng, &RUN_COUNTS[1..8]).expect("counts");
    let scenario = bases.all[b].light.to_string();
    let name = bases.all[b].name.clone();
    if rng.random::<bool>() {
        let (i, n) = edge_shard(runs, rng);
        let job = Job::Study {
            scenario,
            runs: Some(runs),
            shard: Some((i, n)),
        };
        return (format!("{name} (light), {runs} runs, shard {i}/{n}"), job);
    }
    let n = rng.random_range(1..=9.min(runs.max(1)));
    let mut parts: Vec<String> = bases
        .parts(b, runs, n)
        .iter()
        .map(Value::to_string)
        .collect();
    parts.rotate_left(rng.random_range(0..n));
    let job = Job::Merge {
        scenario,
        runs: Some(runs),
        parts,
    };
    (
        format!("{name} (light), {runs} runs, its {n} shards merged, rotated"),
        job,
    )
}

/// The genuine parts of a light study, one tampered with (or dropped, repeated, inflated,
/// foreign).
fn tampered_parts(
    bases: &mut Bases,
    b: usize,
    runs: usize,
    rng: &mut ChaCha8Rng,
) -> (Vec<Value>, String) {
    let n = rng.random_range(1..=4.min(runs));
    let mut parts = bases.parts(b, runs, n);
    let k = rng.random_range(0..n);
    let what = match rng.random_range(0..6u32) {
        0 => {
            parts.remove(k);
            format!("part {k} of {n} dropped")
        }
        1 => {
            parts.push(parts[k].clone());
            format!("part {k} of {n} given twice")
        }
        2 => {
            // Every number of the part times a factor: counts beyond their runs.
            let f = pick(rng, &[2.0, 1e6, 1e300]).expect("factors");
            for (p, v) in nodes(&parts[k].clone()) {
                if let Some(x) = v.as_f64() {
                    *crate::mutate::at(&mut parts[k], &p) = json!(x * f);
                }
            }
            format!("part {k} of {n}: every number × {f}")
        }
        3 => {
            // A count at 2⁶⁴ − 1 in every part: the sum wraps unless checked.
            let mut at = String::new();
            for part in parts.iter_mut() {
                let ns: Vec<_> = nodes(part)
                    .into_iter()
                    .filter(|(_, v)| v.is_u64())
                    .collect();
                if let Some((p, _)) = ns.last() {
                    *crate::mutate::at(part, p) = json!(u64::MAX);
                    at = path_text(p);
                }
            }
            format!("{n} parts with {at} := 2⁶⁴ − 1")
        }
        4 => {
            let other = rng.random_range(0..bases.all.len());
            let foreign = indices(bases, |x| x.study && x.name != bases.all[other].name);
            let o = pick(rng, &foreign).expect("studies");
            parts[k] = bases.parts(o, runs, n)[k].clone();
            format!("part {k} of {n} from {}", bases.all[o].name)
        }
        _ => {
            let (v, did) = mutate(&parts[k], rng);
            parts[k] = v;
            format!("part {k} of {n} with {did}")
        }
    };
    (parts, what)
}

/// A light study's parts, tampered with, merged.
fn merge(bases: &mut Bases, rng: &mut ChaCha8Rng) -> (String, Job) {
    let ids = indices(bases, |b| b.study);
    let b = pick(rng, &ids).expect("studies");
    let runs = pick(rng, &RUN_COUNTS[1..8]).expect("counts");
    let (parts, what) = tampered_parts(bases, b, runs, rng);
    let job = Job::Merge {
        scenario: bases.all[b].light.to_string(),
        runs: Some(runs),
        parts: parts.iter().map(Value::to_string).collect(),
    };
    (
        format!("{} (light), {runs} runs, {what}", bases.all[b].name),
        job,
    )
}

/// CSV data for a preset (mutated now and then), itself mutated (`csv_mutate`).
fn csv(bases: &mut Bases, rng: &mut ChaCha8Rng) -> (String, Job) {
    let b = rng.random_range(0..bases.all.len());
    let (scenario, what) = if rng.random_ratio(1, 4) {
        mutated(bases, b, None, rng)
    } else {
        (
            bases.all[b].light.to_string(),
            format!("{} (light)", bases.all[b].name),
        )
    };
    let (text, did) = csv_text(&scenario, rng);
    let job = Job::Run {
        scenario,
        csv_data: Some(text),
        figure: false,
    };
    (format!("{what}, CSV data {did}"), job)
}

/// CSV text of the shape the scenario reads (2 × 1 if it has none), mutated.
fn csv_text(scenario: &str, rng: &mut ChaCha8Rng) -> (String, String) {
    let s = Scenario::from_json(scenario).ok();
    let (q, r) = s
        .as_ref()
        .and_then(|s| s.data_shape().ok())
        .unwrap_or((2, 1));
    let steps = s.map_or(20, |s| s.simulate.as_ref().map_or(20, |m| m.steps.min(400)));
    csv_mutate::mutated(q, r, steps, rng)
}

/// Text that is not a scenario, not CSV, not a part.
fn garbage(bases: &mut Bases, rng: &mut ChaCha8Rng) -> (String, Job) {
    let b = rng.random_range(0..bases.all.len());
    let base = bases.all[b].light.to_string();
    let (text, what) = csv_mutate::garbage(&base, rng);
    let job = match rng.random_range(0..3u32) {
        0 => Job::Run {
            scenario: text,
            csv_data: None,
            figure: false,
        },
        1 => Job::Run {
            scenario: base,
            csv_data: Some(text),
            figure: false,
        },
        _ => Job::Merge {
            scenario: base,
            runs: Some(8),
            parts: vec![text],
        },
    };
    let into = match &job {
        Job::Run { csv_data: None, .. } => "as the scenario",
        Job::Run { .. } => "as CSV data",
        _ => "as a merge part",
    };
    (format!("{} (light): {what} {into}", bases.all[b].name), job)
}

fn file(name: &str, text: String) -> File {
    File {
        name: name.into(),
        text,
        raw: false,
    }
}

/// `--shard` values at the edges, as text (clap reads them).
const SHARD_TEXTS: [&str; 12] = [
    "0/1",
    "0/0",
    "1/1",
    "3/2",
    "-1/2",
    "1/18446744073709551616",
    "18446744073709551615/18446744073709551615",
    "a/b",
    "1/2/3",
    "1",
    "6/7",
    " 0/2",
];

/// The real binary: run (JSON, CSV, with --data), figure (SVG or PNG, sizes and scales at
/// their edges), experiment --shard, merge of part files, compare, and garbage files.
fn cli(bases: &mut Bases, rng: &mut ChaCha8Rng) -> (String, Job) {
    let b = rng.random_range(0..bases.all.len());
    let (scenario, what) = mutated(bases, b, None, rng);
    let sc = "{dir}/scenario.json".to_string();
    let (args, files, did): (Vec<String>, Vec<File>, String) = match rng.random_range(0..8u32) {
        0 => {
            let format = pick(rng, &["json", "csv"]).expect("formats");
            (
                vec!["run".into(), sc, "--format".into(), format.into()],
                vec![file("scenario.json", scenario)],
                format!("run --format {format}"),
            )
        }
        1 => {
            let (text, did) = csv_text(&scenario, rng);
            (
                vec![
                    "run".into(),
                    sc,
                    "--data".into(),
                    "{dir}/data.csv".into(),
                    "--format".into(),
                    "csv".into(),
                ],
                vec![file("scenario.json", scenario), file("data.csv", text)],
                format!("run --data with CSV {did}"),
            )
        }
        2 | 3 => {
            let png = rng.random_ratio(1, 3);
            let size = pick(
                rng,
                &[
                    "960x640",
                    "1x1",
                    "64x48",
                    "4000x100",
                    "8192x8192",
                    "100x8192",
                ],
            )
            .expect("sizes");
            let scale = pick(rng, &["2", "0.25", "1", "8", "4"]).expect("scales");
            let mut args = vec![
                "figure".into(),
                sc,
                "-o".into(),
                format!("{{dir}}/f.{}", if png { "png" } else { "svg" }),
            ];
            args.extend(["--size".into(), size.to_string()]);
            if png {
                args.extend(["--scale".into(), scale.to_string()]);
            }
            if rng.random_ratio(1, 3) {
                let t = pick(rng, &["1", "2", "1000", "18446744073709551615"]).expect("times");
                args.extend(["--time".into(), t.into()]);
            }
            if rng.random_ratio(1, 3) {
                let z = pick(rng, &["auto", "regions", "full"]).expect("zooms");
                args.extend(["--zoom".into(), z.into()]);
            }
            let did = args[3..].join(" ").replace("{dir}/", "");
            (
                args,
                vec![file("scenario.json", scenario)],
                format!("figure {did}"),
            )
        }
        4 => {
            let shard = pick(rng, &SHARD_TEXTS).expect("shards");
            let runs = pick(rng, &["1", "8", "9", "37", "0"]).expect("runs");
            (
                vec![
                    "experiment".into(),
                    sc,
                    "--runs".into(),
                    runs.into(),
                    "--shard".into(),
                    shard.into(),
                ],
                vec![file("scenario.json", scenario)],
                format!("experiment --runs {runs} --shard {shard:?}"),
            )
        }
        5 => {
            let ids = indices(bases, |x| x.study);
            let s = pick(rng, &ids).expect("studies");
            let runs = pick(rng, &RUN_COUNTS[1..8]).expect("counts");
            let n = rng.random_range(1..=4.min(runs));
            let mut parts: Vec<Value> = (0..n).map(|i| bases.part_file(s, runs, n, i)).collect();
            let k = rng.random_range(0..n);
            let (v, did) = mutate(&parts[k], rng);
            parts[k] = v;
            let names: Vec<String> = (0..n).map(|i| format!("part-{i}.json")).collect();
            let mut args = vec!["merge".to_string()];
            args.extend(names.iter().map(|n| format!("{{dir}}/{n}")));
            let files = names
                .iter()
                .zip(&parts)
                .map(|(n, p)| file(n, p.to_string()))
                .collect();
            return (
                format!(
                    "{} (light), {runs} runs: merge of {n} part files, part {k} with {did}",
                    bases.all[s].name
                ),
                Job::Cli { args, files },
            );
        }
        6 => {
            let ids = indices(bases, |x| x.method == "compare");
            let c = pick(rng, &ids).expect("compare presets");
            let (scenario, what) = mutated(bases, c, None, rng);
            let mut args = vec!["compare".into(), sc];
            if rng.random::<bool>() {
                args.push("--no-study".into());
            } else {
                args.extend([
                    "--runs".into(),
                    pick(rng, &["1", "3", "9"]).expect("runs").into(),
                ]);
            }
            let did = args[2..].join(" ");
            return (
                format!("{what}: compare {did}"),
                Job::Cli {
                    args,
                    files: vec![file("scenario.json", scenario)],
                },
            );
        }
        _ => {
            let (text, g) = csv_mutate::garbage(&scenario, rng);
            let raw = rng.random_ratio(1, 4);
            let (args, name): (Vec<String>, &str) = match rng.random_range(0..3u32) {
                0 => (vec!["run".into(), "{dir}/g".into()], "g"),
                1 => (
                    vec!["run".into(), sc, "--data".into(), "{dir}/g".into()],
                    "g",
                ),
                _ => (vec!["merge".into(), "{dir}/g".into()], "g"),
            };
            let mut files = vec![file("scenario.json", scenario), file(name, text)];
            files[1].raw = raw;
            let did = format!(
                "{} with a garbage file ({g}{})",
                args[0],
                if raw { ", raw bytes" } else { "" }
            );
            (args, files, did)
        }
    };
    (format!("{what}: {did}"), Job::Cli { args, files })
}
