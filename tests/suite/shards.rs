//! Every study split into shards: the parts merge to exactly the unsharded result, and a merge
//! refuses parts that overlap, leave runs out or come from another scenario or seed. Driven by
//! the registry (`registry::study_presets`: every preset whose method has a study for it); the
//! LSCR presets have no coverage block, so `lscr.rs` runs [`check_shards`] on them with one.

use crate::registry::{first_difference, run_study, study_presets};
use confset::scenario::{Job, Scenario};
use confset::study::{run_to_end, Study};
use serde_json::Value;

/// Runs of every sharded study here: small, and not a multiple of the SCF batch of 8.
const RUNS: usize = 37;

/// The work (the core's estimate, [`Job::Study`]) one preset's sharding check may spend on its
/// runs. Each check runs its study seven times over (unsharded, twice chunked, 1 + 2 + 3 + 7
/// shards); a compare run calls every method, 150 M estimated operations, about 70 ms
/// natively, so its 37 runs cost 18 s natively and 40 s in a browser: the budget gives it 9.
const CHECK_WORK: f64 = 1.5e9;

/// Runs of the sharding check of `s`: [`RUNS`], fewer where one run is costly by the core's
/// own estimate (no clock: the same count on every machine), never below 9 (7 shards each
/// hold a run, not a multiple of 8).
fn check_runs(s: &Scenario) -> usize {
    let per_run = s.work(Job::Study { runs: Some(RUNS) }).total_operations();
    ((CHECK_WORK / per_run.max(1.0)) as usize).clamp(9, RUNS)
}

/// A fresh study of `s` with `runs` runs.
fn study(name: &str, s: &Scenario, runs: usize) -> Box<dyn Study> {
    s.study(Some(runs))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Shard `i` of `n` of `s`, run to its end in chunks of `chunk`; its partial as JSON text read
/// back (as the CLI's files and the page's workers pass it).
pub(crate) fn shard_part(
    name: &str,
    s: &Scenario,
    runs: usize,
    (i, n): (usize, usize),
    chunk: usize,
) -> Value {
    let mut st = study(name, s, runs);
    st.restrict(i, n)
        .unwrap_or_else(|e| panic!("{name}: shard {i}/{n}: {e}"));
    let range = st.range();
    run_to_end(st.as_mut(), chunk, |_, _| {}).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(st.finished(), "{name}: shard {i}/{n} not finished");
    assert_eq!(st.runs(), range.len(), "{name}: shard {i}/{n} runs");
    let text = st
        .partial()
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .to_string();
    serde_json::from_str(&text).expect("a partial is JSON")
}

/// Merge `parts` into a fresh study of `s`, or the error's message.
fn merged(name: &str, s: &Scenario, runs: usize, parts: &[Value]) -> Result<Value, String> {
    let mut st = study(name, s, runs);
    st.merge(parts).map_err(|e| e.to_string())?;
    st.complete().map_err(|e| e.to_string())?;
    assert!(st.finished(), "{name}: merged but not finished");
    assert_eq!(st.runs(), runs, "{name}: merged runs");
    Ok(st.result().expect("result"))
}

fn same(name: &str, what: &str, got: &Value, want: &Value) {
    if let Some(d) = first_difference(got, want, "") {
        panic!("{name}: {what} differs from the unsharded result at {d}");
    }
    // Bit for bit: serde_json compares numbers exactly; the text too.
    assert_eq!(got.to_string(), want.to_string(), "{name}: {what}");
}

/// Unsharded, sharded in 1, 2, 3 and 7 shards merged in shuffled order, and chunked with odd
/// chunk sizes: all the same result, exactly.
pub(crate) fn check_shards(name: &str, s: &Scenario) {
    let runs = check_runs(s);
    let want = run_study(name, s, runs, 1000);
    for chunk in [3, 11] {
        same(
            name,
            &format!("chunks of {chunk}"),
            &run_study(name, s, runs, chunk),
            &want,
        );
    }
    for n in [1, 2, 3, 7] {
        let mut parts: Vec<Value> = (0..n)
            .map(|i| shard_part(name, s, runs, (i, n), 3))
            .collect();
        // Shuffled: reversed, then the last moved first.
        parts.reverse();
        parts.rotate_right(1);
        let got =
            merged(name, s, runs, &parts).unwrap_or_else(|e| panic!("{name}: {n} shards: {e}"));
        same(name, &format!("{n} shards merged"), &got, &want);
    }
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn shards_merge_to_the_unsharded_result() {
    let studies = study_presets();
    assert!(!studies.is_empty(), "no preset has a study");
    for (name, s) in &studies {
        check_shards(name, s);
    }
}
in_browser!(shards_merge_to_the_unsharded_result);

/// Every leaf `…seed` of the scenario JSON that holds `seed`, moved to seed + 1.
pub(crate) fn with_other_seed(s: &Scenario, seed: u64) -> Scenario {
    fn walk(v: &mut Value, key: &str, seed: u64, hits: &mut usize) {
        match v {
            Value::Object(m) => m.iter_mut().for_each(|(k, w)| walk(w, k, seed, hits)),
            Value::Array(a) => a.iter_mut().for_each(|w| walk(w, key, seed, hits)),
            Value::Number(n) if key == "seed" && n.as_u64() == Some(seed) => {
                *v = Value::from(seed + 1);
                *hits += 1;
            }
            _ => {}
        }
    }
    let mut v = serde_json::to_value(s).expect("JSON");
    let mut hits = 0;
    walk(&mut v, "", seed, &mut hits);
    assert!(hits > 0, "no seed field holds the study's seed {seed}");
    serde_json::from_value(v).expect("a scenario")
}

/// The first study preset of each method.
pub(crate) fn one_per_method() -> Vec<(String, Scenario)> {
    let mut seen = Vec::new();
    study_presets()
        .into_iter()
        .filter(|(_, s)| {
            let new = !seen.contains(&s.method);
            seen.push(s.method);
            new
        })
        .collect()
}

/// Overlapping, missing and foreign parts are refused, in words that name the problem; a merge
/// replaces the counts (the page merges its workers' latest partials after every slice).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn merge_refuses_overlapping_missing_and_foreign_parts() {
    let studies = one_per_method();
    assert!(!studies.is_empty(), "no preset has a study");
    for (name, s) in &studies {
        let runs = check_runs(s);
        let part = |i, n| shard_part(name, s, runs, (i, n), 7);
        let (a, b, c) = (part(0, 3), part(1, 3), part(2, 3));
        let range = |p: &Value| format!("{}..{}", p["range"][0], p["range"][1]);

        let e = merged(name, s, runs, &[a.clone(), b.clone(), c.clone(), b.clone()])
            .expect_err("overlap");
        let want = format!("part 4 covers runs {} which part 2 also covers", range(&b));
        assert!(e.contains(&want), "{name}: {e}\n(wanted: {want})");
        // A shard of another split that straddles two parts.
        let e = merged(
            name,
            s,
            runs,
            &[a.clone(), b.clone(), c.clone(), part(0, 2)],
        )
        .expect_err("overlap");
        assert!(
            e.contains("part 4 covers runs 0..") && e.contains("which part 1 also covers"),
            "{name}: {e}"
        );

        let e = merged(name, s, runs, &[c.clone(), a.clone()]).expect_err("missing");
        assert_eq!(
            e,
            format!("partial.range runs {} are missing", range(&b)),
            "{name}"
        );
        let e = merged(name, s, runs, &[b.clone()]).expect_err("missing");
        assert_eq!(
            e,
            format!(
                "partial.range runs {} and {} are missing",
                range(&a),
                range(&c)
            ),
            "{name}"
        );

        let seed = a["seed"].as_u64().expect("seed");
        let other = with_other_seed(s, seed);
        let foreign = shard_part(name, &other, runs, (1, 3), 7);
        let e = merged(name, s, runs, &[a.clone(), foreign, c.clone()]).expect_err("seed");
        let want = format!(
            "part 2 was drawn with seed {}, this study with seed {seed}",
            seed + 1
        );
        assert!(e.contains(&want), "{name}: {e}");

        let mut other = s.clone();
        other.alpha = if s.alpha == 0.9 { 0.95 } else { 0.9 };
        let foreign = shard_part(name, &other, runs, (1, 3), 7);
        let e = merged(name, s, runs, &[a.clone(), foreign, c.clone()]).expect_err("scenario");
        assert!(
            e.contains("part 2 is of another scenario (digest "),
            "{name}: {e}"
        );

        let e =
            merged(name, s, runs, &[shard_part(name, s, runs + 1, (0, 1), 50)]).expect_err("total");
        assert!(
            e.contains(&format!(
                "part 1 is a shard of a study of {} runs, this study has {runs}",
                runs + 1
            )),
            "{name}: {e}"
        );

        let mut bent = b.clone();
        bent["range"][0] = Value::from(b["range"][0].as_u64().unwrap() + 1);
        let e = merged(name, s, runs, &[a.clone(), bent, c.clone()]).expect_err("range");
        assert!(e.contains("part 2 covers runs"), "{name}: {e}");

        // merge replaces: first a part, then all three, then one again.
        let mut st = study(name, s, runs);
        st.merge(std::slice::from_ref(&a)).expect("one part");
        let one = st.result().expect("result");
        assert_eq!(
            st.runs(),
            a["range"][1].as_u64().unwrap() as usize,
            "{name}"
        );
        assert!(!st.finished() && st.complete().is_err(), "{name}");
        st.merge(&[a.clone(), b.clone(), c.clone()])
            .expect("all parts");
        assert!(st.finished(), "{name}");
        same(
            name,
            "merged after a partial merge",
            &st.result().unwrap(),
            &run_study(name, s, runs, 1000),
        );
        st.merge(std::slice::from_ref(&a)).expect("one part again");
        same(name, "merged again", &st.result().unwrap(), &one);
        assert!(st.step(5).is_err(), "{name}: a merged study steps");

        // A shard is chosen before the first step.
        let mut st = study(name, s, runs);
        st.step(1).expect("step");
        let e = st.restrict(0, 2).expect_err("restrict after a step");
        assert_eq!(e.field, "shard", "{name}: {e}");
        let e = study(name, s, runs).restrict(3, 3).expect_err("3/3");
        assert!(e.message.contains("0 ≤ i < N"), "{name}: {e}");
    }
}
in_browser!(merge_refuses_overlapping_missing_and_foreign_parts);

/// `confset experiment --shard i/3` three times, then `confset merge` of the parts (in
/// another order, and on stdin), prints what plain `confset experiment` prints; bad merges exit
/// non-zero with the problem in words.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn cli_shards_and_merge_print_the_unsharded_result() {
    use std::process::Command;
    let exe = env!("CARGO_BIN_EXE_confset");
    let dir = std::env::temp_dir().join(format!("confset-shards-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let run = crate::cli::confset;
    let studies = one_per_method();
    assert!(!studies.is_empty(), "no preset has a study");
    for (name, s) in studies {
        let runs = RUNS.to_string();
        let plain = run(&["experiment", "--preset", &name, "--runs", &runs], None);
        assert!(
            plain.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&plain.stderr)
        );
        let serial = Command::new(exe)
            .args(["experiment", "--preset", &name, "--runs", &runs])
            .env("RAYON_NUM_THREADS", "1")
            .output()
            .expect("confset runs");
        assert_eq!(
            serial.stdout, plain.stdout,
            "{name}: one thread and all cores differ"
        );
        let mut files = Vec::new();
        let mut all = Vec::new();
        for i in 0..3 {
            let out = run(
                &[
                    "experiment",
                    "--preset",
                    &name,
                    "--runs",
                    &runs,
                    "--shard",
                    &format!("{i}/3"),
                ],
                None,
            );
            assert!(
                out.status.success(),
                "{name}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            let part: Value = serde_json::from_slice(&out.stdout).expect("a part is JSON");
            assert_eq!(part["confset"], env!("CARGO_PKG_VERSION"));
            assert_eq!(part["shard"], serde_json::json!([i, 3]));
            assert_eq!(part["runs"], RUNS);
            assert_eq!(part["scenario_digest"], s.digest().unwrap().as_str());
            assert_eq!(part["range"], part["partial"]["range"]);
            let f = dir.join(format!("{name}-{i}.json"));
            std::fs::write(&f, &out.stdout).expect("write a part");
            files.push(f.to_string_lossy().into_owned());
            all.extend_from_slice(&out.stdout);
        }
        let m = run(&["merge", &files[2], &files[0], &files[1]], None);
        assert!(
            m.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&m.stderr)
        );
        assert_eq!(
            String::from_utf8_lossy(&m.stdout),
            String::from_utf8_lossy(&plain.stdout),
            "{name}: merge"
        );
        let m = run(&["merge", "-"], Some(&all));
        assert!(
            m.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&m.stderr)
        );
        assert_eq!(m.stdout, plain.stdout, "{name}: merge of stdin");

        let refused = |args: &[&str], words: &str| {
            let out = run(args, None);
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(
                !out.status.success() && out.stdout.is_empty(),
                "{name}: {args:?} succeeded"
            );
            assert!(
                err.contains(words),
                "{name}: {args:?}: {err}\n(wanted: {words})"
            );
        };
        refused(&["merge", &files[0], &files[2]], "are missing");
        refused(
            &["merge", &files[0], &files[1], &files[2], &files[1]],
            &format!("part 4 ({}) covers runs", files[1]),
        );
        refused(
            &["experiment", "--preset", &name, "--shard", "3/3"],
            "for '--shard <i/N>': must read i/N",
        );
        refused(
            &["experiment", "--preset", &name, "--shard", "x"],
            "for '--shard <i/N>': must read i/N",
        );
        refused(
            &["merge"],
            "the following required arguments were not provided",
        );
        let edited = dir.join(format!("{name}-edited.json"));
        let text = std::fs::read_to_string(&files[0]).unwrap();
        std::fs::write(
            &edited,
            text.replace(
                &format!("\"confset\":\"{}\"", env!("CARGO_PKG_VERSION")),
                "\"confset\":\"0.0.0\"",
            ),
        )
        .unwrap();
        refused(
            &["merge", edited.to_str().unwrap(), &files[1], &files[2]],
            &format!("part 1 ({}) was written by confset 0.0.0", edited.display()),
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
