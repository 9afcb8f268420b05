//! The Monte Carlo's versioned generator, `experiment.rng` (issue 27): `"chacha8"` when absent,
//! so every scenario written before the field keeps its streams bit for bit (its counts are
//! pinned here as they were before the field existed); `"xoshiro256++"` gives other streams of
//! the same law (counts judged inside the exact 99.9 % binomial band of `confset::stats`, an
//! independent check of the law); anything else is refused in words naming the field and the
//! accepted names.

use confset::presets::{self, NoiseReading};
use confset::scenario::{Condition, Scenario, SimulateSpec};
use confset::scf::{ExperimentResult, ExperimentSpec, Generator};
use confset::study::{Chunked, Study};
use serde_json::{json, Value};

/// The experiment run to the end in chunks of `chunk` runs.
fn run(s: &Scenario, chunk: usize) -> ExperimentResult {
    let mut e = Chunked::new(s.prepare_scf().unwrap().conditional_experiment().unwrap());
    while !e.finished() {
        e.step(chunk).unwrap();
    }
    e.report()
}

/// The robots at their preset's seed (2021) and 10,000 runs, under `rng`.
fn robots(reading: NoiseReading, rng: Generator) -> Scenario {
    let mut s = presets::robots(reading);
    s.experiment.as_mut().unwrap().rng = rng;
    s
}

/// The scalar example with a conditional experiment (x̄ = 9 at t = 30, seed 11, 4,000 runs).
fn scalar(rng: Generator) -> Scenario {
    let mut s = presets::scalar();
    s.simulate = Some(SimulateSpec {
        steps: 30,
        seed: 3,
        u: vec![],
        condition: Some(Condition {
            t: 30,
            x: vec![9.0],
        }),
        x0: None,
        true_noise: None,
    });
    s.experiment = Some(ExperimentSpec {
        runs: 4000,
        seed: 11,
        components: vec![0],
        warning_t: None,
        rng,
    });
    s
}

/// (KF inside, SCF inside, KF warnings, SCF warnings).
fn counts(r: &ExperimentResult) -> (usize, usize, usize, usize) {
    (r.kf_inside, r.scf_inside, r.kf_warnings, r.scf_warnings)
}

/// ChaCha8 gives today exactly the counts it gave before `experiment.rng` existed (measured at
/// 438df52, where the robot presets ran ChaCha8: the README's and the gallery's 9514).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn chacha8_keeps_the_old_counts() {
    let r = run(&robots(NoiseReading::Unscaled, Generator::ChaCha8), 1000);
    assert_eq!(counts(&r), PINNED_ROBOTS, "scf-robots under chacha8");
    let r = run(&robots(NoiseReading::Literal, Generator::ChaCha8), 10_000);
    assert_eq!(
        counts(&r),
        PINNED_LITERAL,
        "scf-robots-literal under chacha8"
    );
    let r = run(&scalar(Generator::ChaCha8), 333);
    assert_eq!(counts(&r), PINNED_SCALAR, "scalar study under chacha8");
}
in_browser!(chacha8_keeps_the_old_counts);

const PINNED_ROBOTS: (usize, usize, usize, usize) = (2, 9514, 0, 10_000);
const PINNED_LITERAL: (usize, usize, usize, usize) = (0, 9502, 0, 10_000);
const PINNED_SCALAR: (usize, usize, usize, usize) = (3695, 3960, 0, 0);

/// xoshiro256++ draws other realizations of the same law: the SCF count inside the exact band
/// around α (Property 1), for the robots (both readings) and the scalar example; and the
/// streams are not ChaCha8's. The presets themselves run xoshiro256++.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn xoshiro_counts_are_inside_the_band() {
    for reading in [NoiseReading::Unscaled, NoiseReading::Literal] {
        let s = robots(reading, Generator::Xoshiro256PlusPlus);
        let r = run(&s, 1000);
        let (lo, hi) = confset::stats::band(r.runs_total, r.alpha);
        assert_eq!(r.scf_expected_range, (lo, hi));
        assert!(
            (lo..=hi).contains(&r.scf_inside),
            "{reading:?}: SCF {} outside {lo}–{hi}",
            r.scf_inside
        );
        assert_ne!(
            counts(&r),
            counts(&run(&robots(reading, Generator::ChaCha8), 10_000)),
            "{reading:?}: the same counts as ChaCha8"
        );
    }
    assert_eq!(
        presets::get("scf-robots").unwrap().experiment.unwrap().rng,
        Generator::Xoshiro256PlusPlus
    );
    assert_eq!(
        presets::get("scf-robots-literal")
            .unwrap()
            .experiment
            .unwrap()
            .rng,
        Generator::Xoshiro256PlusPlus
    );
    assert_eq!(
        counts(&run(&presets::get("scf-robots").unwrap(), 10_000)),
        PINNED_ROBOTS_XOSHIRO
    );
    // The scalar example: x̄ = 9 at t = 30 against the closed-form conditional coverage.
    let s = scalar(Generator::Xoshiro256PlusPlus);
    let r = run(&s, 333);
    let p = s.prepare_scf().unwrap();
    let off = confset::kalman::Offline::new(&p.model, 30, &p.inputs).unwrap();
    let (kf, scf) = confset::scf::conditional_coverage_1d(
        off.gains.steps[29].p[(0, 0)],
        off.moments.cov[29][(0, 0)],
        0.0,
        9.0,
        s.alpha,
    )
    .unwrap();
    for (count, prob, name) in [(r.kf_inside, kf, "KF"), (r.scf_inside, scf, "SCF")] {
        let (lo, hi) = confset::stats::band(r.runs_total, prob);
        assert!(
            (lo..=hi).contains(&count),
            "scalar {name}: {count} outside {lo}–{hi} (p = {prob})"
        );
    }
}
in_browser!(xoshiro_counts_are_inside_the_band);

/// scf-robots as shipped (xoshiro256++, seed 2021): the gallery's `ours_now` and the bench
/// kernel's summary.
const PINNED_ROBOTS_XOSHIRO: (usize, usize, usize, usize) = (2, 9481, 0, 10_000);

/// Under xoshiro256++ too, the counts do not depend on the chunking, and two shards merged give
/// the whole run's counts (each block's stream depends only on the seed and the block).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn xoshiro_chunks_and_shards_agree() {
    let mut s = robots(NoiseReading::Unscaled, Generator::Xoshiro256PlusPlus);
    s.experiment.as_mut().unwrap().runs = 203;
    let whole = run(&s, 1000);
    assert_eq!(whole, run(&s, 1));
    assert_eq!(whole, run(&s, 24));
    let p = s.prepare_scf().unwrap();
    let parts: Vec<Value> = (0..3)
        .map(|shard| {
            let mut e = Chunked::new(p.conditional_experiment().unwrap());
            e.restrict(shard, 3).unwrap();
            while !e.finished() {
                e.step(16).unwrap();
            }
            e.partial().unwrap()
        })
        .collect();
    let mut merged = Chunked::new(p.conditional_experiment().unwrap());
    merged.merge(&parts).unwrap();
    merged.complete().unwrap();
    assert_eq!(merged.report(), whole);
}
in_browser!(xoshiro_chunks_and_shards_agree);

/// The field in JSON: absent reads as chacha8 and is not written back (an old file round-trips
/// unchanged); the two names read; a number, another spelling and null are refused, naming
/// `experiment.rng` and the accepted names.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_field_reads_writes_and_refuses() {
    let mut v: Value =
        serde_json::to_value(robots(NoiseReading::Unscaled, Generator::ChaCha8)).unwrap();
    assert!(
        v["experiment"].get("rng").is_none(),
        "chacha8 is written as no field: {}",
        v["experiment"]
    );
    let s = Scenario::from_json(&v.to_string()).unwrap();
    assert_eq!(s.experiment.as_ref().unwrap().rng, Generator::ChaCha8);
    v["experiment"]["rng"] = json!("chacha8");
    let s = Scenario::from_json(&v.to_string()).unwrap();
    assert_eq!(s.experiment.as_ref().unwrap().rng, Generator::ChaCha8);
    v["experiment"]["rng"] = json!("xoshiro256++");
    let s = Scenario::from_json(&v.to_string()).unwrap();
    assert_eq!(
        s.experiment.as_ref().unwrap().rng,
        Generator::Xoshiro256PlusPlus
    );
    assert_eq!(
        serde_json::to_value(&s).unwrap()["experiment"]["rng"],
        json!("xoshiro256++")
    );
    assert_eq!(Generator::NAMES, ["chacha8", "xoshiro256++"]);
    for (bad, found) in [
        (json!(3), "the number 3"),
        (json!("XOSHIRO"), "\"XOSHIRO\""),
        (json!("xoshiro256"), "\"xoshiro256\""),
        (Value::Null, "null"),
    ] {
        v["experiment"]["rng"] = bad.clone();
        let e = Scenario::from_json(&v.to_string()).expect_err(&bad.to_string());
        assert_eq!(e.field, "experiment.rng", "{bad}: {e}");
        assert_eq!(
            e.message,
            format!("must be one of \"chacha8\" or \"xoshiro256++\", found {found}"),
            "{bad}"
        );
    }
    // A name with options: the name alone is asked for.
    v["experiment"]["rng"] = json!({"xoshiro256++": 1});
    let e = Scenario::from_json(&v.to_string()).expect_err("an object");
    assert_eq!(e.field, "experiment.rng", "{e}");
    assert!(e.message.contains("\"xoshiro256++\" alone"), "{e}");
}
in_browser!(the_field_reads_writes_and_refuses);
