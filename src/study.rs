//! One interface for every chunked Monte Carlo study, and the one way a study is split into
//! shards whose counts merge exactly.
//!
//! Each method's promise is checked by counting over fresh runs: the SCF conditional
//! experiment ([`crate::scf::ConditionalExperiment`]), the LSCR coverage experiment
//! ([`crate::lscr::Experiment`]), the GLLS precision study ([`crate::glls::Precision`]) and the
//! set-membership guarantee (`scenario::ubb::Guarantee`). Each says only what one range of runs
//! gives ([`Runs`]) and how two ranges' counts add ([`Tally`]); [`Chunked`] turns that into a
//! [`Study`], so the CLI (`confset experiment`, `--shard i/N`, `confset merge`), the one wasm
//! `Study` binding (one per Web Worker) and the tests drive them alike: run a chunk, look at the
//! result, restrict to a shard, hand out the partial counts, merge a list of them.
//!
//! The invariant that makes this exact: run i draws its randomness from a stream fixed by the
//! study's seed and i (or by the seed and i's batch, for a study that draws [`Runs::batch`] runs
//! side by side), never from what earlier runs drew. So the counts of a run range do not depend
//! on how the runs were chunked, sharded or spread over workers, and the sum of the parts'
//! counts is the unsharded count, bit for bit.

use crate::error::{Error, Result};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::ops::Range;

/// A Monte Carlo study run in chunks, possibly as one shard of many.
pub trait Study {
    /// Run up to `runs` more runs of this study's range (never past its end). A study may round
    /// a chunk up to whole batches of its own; [`Study::runs`] says how many are done.
    fn step(&mut self, runs: usize) -> Result<()>;
    /// Runs counted so far (in this shard, or in the merged parts).
    fn runs(&self) -> usize;
    /// Runs of the whole study (every shard together).
    fn total(&self) -> usize;
    /// Whether this study's range is done (after [`Study::merge`]: whether the parts hold
    /// every run).
    fn finished(&self) -> bool;
    /// The result so far, as the JSON the CLI prints and the page reads (its counts, the
    /// promised levels and their exact binomial bands where the method promises one).
    fn result(&self) -> Result<Value>;
    /// The runs this study does: all of them, or its shard's.
    fn range(&self) -> Range<usize>;
    /// Do only shard `shard` of `shards` (0-based): the run range [`shard_range`] gives. Only
    /// before the first step.
    fn restrict(&mut self, shard: usize, shards: usize) -> Result<()>;
    /// The counts so far with the runs they cover, as JSON that [`Study::merge`] takes:
    /// `{"scenario_digest", "seed", "total", "batch", "range": [a, b], "counts"}`.
    fn partial(&self) -> Result<Value>;
    /// Replace this study's counts by the sum of `parts` (each a [`Study::partial`] of the same
    /// scenario, seed and total, their ranges disjoint; gaps are allowed, see
    /// [`Study::complete`]). Afterwards [`Study::result`] is what one study over those runs
    /// gives, and the study only reports (it no longer steps). Messages call the parts
    /// "part 1", "part 2", … ([`Study::merge_named`] names them otherwise).
    fn merge(&mut self, parts: &[Value]) -> Result<()> {
        let names: Vec<String> = (1..=parts.len()).map(|k| format!("part {k}")).collect();
        let named: Vec<(&str, &Value)> = names.iter().map(String::as_str).zip(parts).collect();
        self.merge_named(&named)
    }
    /// [`Study::merge`] with each part's name for the messages (the CLI's "part 2 (b.json)").
    /// Every part is checked before any is added: its shape, seed, total and scenario digest;
    /// its range (a range of this study's runs, on batch edges, as many runs as its counts
    /// say); no count above its runs ([`Tally::counts`]); no two parts overlapping; and every
    /// sum is checked for overflow.
    fn merge_named(&mut self, parts: &[(&str, &Value)]) -> Result<()>;
    /// Ok when the counts cover every run of the study; else an error naming the missing runs.
    fn complete(&self) -> Result<()>;
    /// The digest of the scenario the study was made from ([`crate::scenario::Scenario::digest`]),
    /// carried in its partials so that a merge refuses another scenario's parts.
    fn set_scenario_digest(&mut self, digest: &str);
}

/// Counts over a range of runs that add exactly over disjoint ranges.
pub trait Tally: Clone + Serialize + DeserializeOwned {
    /// Runs counted.
    fn runs(&self) -> usize;
    /// Every count of runs with its field path in the counts' JSON (`kf_inside`,
    /// `inside_each[1]`, `holds[2] + no_set[2]` for a count of runs that is a sum): none may
    /// exceed [`Tally::runs`], which a merge checks on every part. Per-run numbers that are
    /// not counts (the GLLS errors) are not listed; their shape is [`Tally::add`]'s to check.
    fn counts(&self) -> Vec<(String, usize)>;
    /// Add the counts of the runs that come right after these (the sum is the count of both
    /// ranges, exactly, whatever the order the ranges were run in). `Err` says, in words, why
    /// `later` cannot be counts of the same study (another shape), or which sum overflows
    /// (every sum is checked: [`add_count`]).
    fn add(&mut self, later: &Self) -> std::result::Result<(), String>;
}

/// A Monte Carlo whose run i depends only on the seed and i (or i's batch): what each study
/// says, once; [`Chunked`] does the chunking, sharding and merging for all of them.
pub trait Runs {
    /// The additive counts of a range of runs.
    type Tally: Tally;
    /// The result, made from the counts.
    type Report: Serialize;
    /// Runs drawn side by side from one stream position: ranges (chunks, shards) start at a
    /// multiple of it.
    fn batch(&self) -> usize {
        1
    }
    /// Runs of the whole study.
    fn total(&self) -> usize;
    /// The seed of the study's random streams.
    fn seed(&self) -> u64;
    /// The counts of no run.
    fn zero(&self) -> Self::Tally;
    /// Do the runs of `range` and count them. The range starts at a multiple of
    /// [`Runs::batch`] and ends at one or at the total.
    fn run(&mut self, range: Range<usize>) -> Result<Self::Tally>;
    /// The result for these counts.
    fn report(&self, counts: &Self::Tally) -> Self::Report;
}

/// The runs of shard `shard` of `shards` (0-based) of a study of `total` runs drawn in batches
/// of `batch`: contiguous, starting on a batch, as even as whole batches allow; together the
/// shards cover 0..total once. More shards than batches leaves some shards empty.
pub fn shard_range(
    total: usize,
    batch: usize,
    shard: usize,
    shards: usize,
) -> Result<Range<usize>> {
    if shards == 0 || shard >= shards {
        return Err(Error::field(
            "shard",
            format!(
                "must read i/N with 0 ≤ i < N (shards are counted from 0), found {shard}/{shards}"
            ),
        ));
    }
    let batches = total.div_ceil(batch.max(1)) as u128;
    // u128: shard · batches cannot overflow for any usize shard count.
    let edge = |i: usize| ((i as u128 * batches / shards as u128) as usize * batch).min(total);
    Ok(edge(shard)..edge(shard + 1))
}

/// What a [`Study::partial`] holds.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Partial<T> {
    scenario_digest: String,
    seed: u64,
    total: usize,
    batch: usize,
    range: [usize; 2],
    counts: T,
}

/// A [`Runs`] as a [`Study`]: chunks, a shard's range, partial counts and merging, written once.
pub struct Chunked<R: Runs> {
    runs: R,
    /// The runs this study does (after a merge: all).
    range: Range<usize>,
    /// The next run to do.
    next: usize,
    /// Counts of runs range.start..next, or after a merge of the parts' ranges.
    counts: R::Tally,
    /// After a merge: the parts' non-empty ranges, in order.
    merged: Option<Vec<Range<usize>>>,
    scenario_digest: String,
}

impl<R: Runs> Chunked<R> {
    /// A study over all the runs of `runs`.
    pub fn new(runs: R) -> Self {
        let counts = runs.zero();
        let total = runs.total();
        Chunked {
            runs,
            range: 0..total,
            next: 0,
            counts,
            merged: None,
            scenario_digest: String::new(),
        }
    }

    /// The counts so far.
    pub fn counts(&self) -> &R::Tally {
        &self.counts
    }

    /// The result so far (typed; [`Study::result`] is its JSON).
    pub fn report(&self) -> R::Report {
        self.runs.report(&self.counts)
    }

    /// The runs the counts cover, in order.
    fn covered(&self) -> Vec<Range<usize>> {
        match &self.merged {
            Some(r) => r.clone(),
            None => vec![self.range.start..self.next],
        }
    }

    /// Parse part `k` (named `k` in messages: "part 2") and check it belongs to this study.
    fn read_part(&self, k: &str, part: &Value) -> Result<(Range<usize>, R::Tally)> {
        // Read as a scenario is (crate::parse): the field is the path of the value at fault,
        // the message in JSON words, never a Rust type.
        let p: Partial<R::Tally> = crate::parse::from_value(part, "partial").map_err(|e| {
            Error::field(
                e.field,
                format!("{k} is not a study's partial counts: {}", e.message),
            )
        })?;
        let (total, batch) = (self.runs.total(), self.runs.batch());
        if p.total != total {
            return Err(Error::field(
                "partial.total",
                format!(
                    "{k} is a shard of a study of {}, this study has {total}",
                    crate::error::counted(p.total, "run", "runs")
                ),
            ));
        }
        if p.seed != self.runs.seed() {
            return Err(Error::field(
                "partial.seed",
                format!(
                    "{k} was drawn with seed {}, this study with seed {}",
                    p.seed,
                    self.runs.seed()
                ),
            ));
        }
        if p.scenario_digest != self.scenario_digest {
            return Err(Error::field(
                "partial.scenario_digest",
                format!(
                    "{k} is of another scenario (digest {}, this study's {})",
                    p.scenario_digest, self.scenario_digest
                ),
            ));
        }
        let [a, b] = p.range;
        if a > b
            || b > total
            || a % batch != 0
            || (b % batch != 0 && b != total)
            || p.batch != batch
        {
            return Err(Error::field(
                "partial.range",
                format!(
                    "{k} covers runs {a}..{b}, which is not a range of this study's runs 0..{total} in batches of {batch}"
                ),
            ));
        }
        if p.counts.runs() != b - a {
            return Err(Error::field(
                "partial.counts",
                format!(
                    "{k} covers runs {a}..{b} but counts {}",
                    crate::error::counted(p.counts.runs(), "run", "runs")
                ),
            ));
        }
        // A count above its runs is no count of these runs: it would make a rate above 100 %
        // and a miss count below zero (runs − hits) in the result.
        let runs = p.counts.runs();
        if let Some((field, n)) = p.counts.counts().into_iter().find(|(_, n)| *n > runs) {
            return Err(Error::field(
                format!("partial.counts.{field}"),
                format!(
                    "{k}'s counts.{field} is {n}, more than the {runs_runs} it counts (runs {a}..{b}): a count of runs is a whole number from 0 to its runs", runs_runs = crate::error::counted(runs, "run", "runs")
                ),
            ));
        }
        Ok((a..b, p.counts))
    }
}

impl<R: Runs> Study for Chunked<R> {
    fn step(&mut self, runs: usize) -> Result<()> {
        if self.merged.is_some() {
            return Err(Error::field(
                "partial",
                "a merged study only reports its parts' counts: step the shards' studies",
            ));
        }
        let batch = self.runs.batch().max(1);
        let todo = runs
            .max(1)
            .div_ceil(batch)
            .saturating_mul(batch)
            .min(self.range.end - self.next);
        if todo == 0 {
            return Ok(());
        }
        let counts = self.runs.run(self.next..self.next + todo)?;
        self.counts
            .add(&counts)
            .map_err(|e| Error::field("", format!("a chunk's counts do not add up: {e}")))?;
        self.next += todo;
        Ok(())
    }
    fn runs(&self) -> usize {
        self.counts.runs()
    }
    fn total(&self) -> usize {
        self.runs.total()
    }
    fn finished(&self) -> bool {
        match &self.merged {
            Some(_) => self.counts.runs() >= self.runs.total(),
            None => self.next >= self.range.end,
        }
    }
    fn result(&self) -> Result<Value> {
        to_value(&self.report())
    }
    fn range(&self) -> Range<usize> {
        self.range.clone()
    }
    fn restrict(&mut self, shard: usize, shards: usize) -> Result<()> {
        if self.next != self.range.start || self.merged.is_some() {
            return Err(Error::field(
                "shard",
                "must be chosen before the study's first step",
            ));
        }
        self.range = shard_range(self.runs.total(), self.runs.batch(), shard, shards)?;
        self.next = self.range.start;
        Ok(())
    }
    fn partial(&self) -> Result<Value> {
        let covered = self.covered();
        let range = match covered.as_slice() {
            [] => [self.range.start; 2],
            [r] => [r.start, r.end],
            [first, .., last] if covered.windows(2).all(|w| w[0].end == w[1].start) => {
                [first.start, last.end]
            }
            _ => {
                return Err(Error::field(
                    "",
                    format!(
                        "the merged counts cover {}: a partial holds one range of runs",
                        ranges_text(&covered)
                    ),
                ))
            }
        };
        to_value(&Partial {
            scenario_digest: self.scenario_digest.clone(),
            seed: self.runs.seed(),
            total: self.runs.total(),
            batch: self.runs.batch(),
            range,
            counts: &self.counts,
        })
    }
    fn merge_named(&mut self, parts: &[(&str, &Value)]) -> Result<()> {
        let mut read = parts
            .iter()
            .enumerate()
            .map(|(i, (name, p))| self.read_part(name, p).map(|(r, c)| (i, r, c)))
            .collect::<Result<Vec<_>>>()?;
        read.retain(|(_, r, _)| !r.is_empty());
        read.sort_by_key(|(k, r, _)| (r.start, *k));
        // The part reaching furthest so far: any later start before its end overlaps it.
        let mut reach: Option<(usize, Range<usize>)> = None;
        let mut counts = self.runs.zero();
        for (k, r, c) in &read {
            let name = parts[*k].0;
            if let Some((j, prev)) = &reach {
                if r.start < prev.end {
                    return Err(Error::field(
                        "partial.range",
                        format!(
                            "{name} covers runs {}..{} which {} also covers",
                            r.start, r.end, parts[*j].0
                        ),
                    ));
                }
            }
            counts.add(c).map_err(|e| {
                Error::field(
                    "partial.counts",
                    format!("{name} does not fit this study: {e}"),
                )
            })?;
            reach = Some((*k, r.clone()));
        }
        self.counts = counts;
        self.merged = Some(read.into_iter().map(|(_, r, _)| r).collect());
        self.range = 0..self.runs.total();
        self.next = self.range.end;
        Ok(())
    }
    fn complete(&self) -> Result<()> {
        let missing = gaps(&self.covered(), self.runs.total());
        if missing.is_empty() {
            Ok(())
        } else {
            Err(Error::field(
                "partial.range",
                format!("runs {} are missing", ranges_text(&missing)),
            ))
        }
    }
    fn set_scenario_digest(&mut self, digest: &str) {
        self.scenario_digest = digest.to_string();
    }
}

/// The runs of 0..total that no range of `covered` (disjoint, in order) holds.
fn gaps(covered: &[Range<usize>], total: usize) -> Vec<Range<usize>> {
    let mut out = Vec::new();
    let mut at = 0;
    for r in covered.iter().filter(|r| !r.is_empty()) {
        if r.start > at {
            out.push(at..r.start);
        }
        at = at.max(r.end);
    }
    if at < total {
        out.push(at..total);
    }
    out
}

/// "0..250", "0..250 and 750..1000", "0..8, 16..24 and 40..48".
fn ranges_text(ranges: &[Range<usize>]) -> String {
    let t: Vec<String> = ranges
        .iter()
        .map(|r| format!("{}..{}", r.start, r.end))
        .collect();
    match t.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => t.concat(),
    }
}

/// Run a study to the end in chunks of `chunk` runs, calling `progress(done, total)` after each.
pub fn run_to_end(
    study: &mut dyn Study,
    chunk: usize,
    mut progress: impl FnMut(usize, usize),
) -> Result<Value> {
    while !study.finished() {
        let before = study.runs();
        study.step(chunk.max(1))?;
        progress(study.runs(), study.total());
        if study.runs() == before {
            break; // a study that cannot advance must not spin
        }
    }
    study.result()
}

/// Most runs per chunk when a study reports progress: a chunk's overhead (one call, its
/// counts added) is then negligible beside its runs.
pub const MAX_CHUNK: usize = 1000;

/// How many progress steps a study of any size is split into: a bar that moves every 0.5 %
/// of the runs, however few runs there are (compare's 2,000 runs in chunks of 1,000 on two
/// threads moved once, after 8 s).
pub const PROGRESS_STEPS: usize = 200;

/// The chunk of runs for a study of `runs` runs reporting progress: about
/// [`PROGRESS_STEPS`] chunks in all, at most [`MAX_CHUNK`] runs each. The counts never depend
/// on it (each run draws from its own stream).
pub fn progress_chunk(runs: usize) -> usize {
    runs.div_ceil(PROGRESS_STEPS).clamp(1, MAX_CHUNK)
}

/// Run a study as one shard per rayon thread and merge them: the result is the one serial
/// run's, bit for bit (`RAYON_NUM_THREADS=1`: one shard). `make` builds a fresh study (each
/// thread makes its own). Without threads (wasm32) it is one shard. `progress(runs)` is called
/// from the shards' threads with the runs each chunk just finished (the CLI's progress bar).
pub fn run_sharded(
    make: &(dyn Fn() -> Result<Box<dyn Study>> + Sync),
    chunk: usize,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Value> {
    let shard = |i: usize, n: usize| -> Result<Value> {
        let mut s = make()?;
        s.restrict(i, n)?;
        let mut done = 0;
        run_to_end(s.as_mut(), chunk, |runs, _| {
            progress(runs - done);
            done = runs;
        })?;
        s.partial()
    };
    #[cfg(not(target_arch = "wasm32"))]
    let parts = {
        use rayon::prelude::*;
        let n = rayon::current_num_threads().max(1);
        (0..n)
            .into_par_iter()
            .map(|i| shard(i, n))
            .collect::<Result<Vec<Value>>>()?
    };
    #[cfg(target_arch = "wasm32")]
    let parts = vec![shard(0, 1)?];
    let mut all = make()?;
    all.merge(&parts)?;
    all.complete()?;
    all.result()
}

/// The random stream of run `run` of a study seeded `seed`: ChaCha8 stream `run` of the seed,
/// so run i draws the same numbers whatever ran before it.
pub fn run_stream(seed: u64, run: usize) -> rand_chacha::ChaCha8Rng {
    use rand::SeedableRng;
    let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    r.set_stream(run as u64);
    r
}

/// Serialize a study result; serde_json only fails on non-string map keys, which no result has.
pub(crate) fn to_value<T: serde::Serialize>(v: &T) -> Result<Value> {
    serde_json::to_value(v)
        .map_err(|e| Error::field("", format!("the study result could not be written: {e}")))
}

/// `*a += b` for a count named `what`, or the words of the overflow: sums of counts are
/// checked, never wrapped (a wrapped sum is a small, plausible, false count).
pub fn add_count(a: &mut usize, b: usize, what: &str) -> std::result::Result<(), String> {
    *a = a.checked_add(b).ok_or_else(|| {
        format!(
            "{what} overflows: {a} + {b} is past the largest count, {}",
            usize::MAX
        )
    })?;
    Ok(())
}

/// Add counts element-wise ([`add_count`], named `field[i]`); `what` names one entry in the
/// message when the lengths differ.
pub(crate) fn add_counts(
    a: &mut [usize],
    b: &[usize],
    field: &str,
    what: &str,
) -> std::result::Result<(), String> {
    if a.len() != b.len() {
        return Err(format!("{} {what}, this study {}", b.len(), a.len()));
    }
    for (i, (x, y)) in a.iter_mut().zip(b).enumerate() {
        add_count(x, *y, &format!("{field}[{i}]"))?;
    }
    Ok(())
}

/// The counts of a list field, named `field[i]`, for [`Tally::counts`].
pub(crate) fn listed_counts(field: &str, v: &[usize]) -> Vec<(String, usize)> {
    v.iter()
        .enumerate()
        .map(|(i, n)| (format!("{field}[{i}]"), *n))
        .collect()
}

/// Per-run numbers in run order, for counts that keep each run's value (the GLLS errors, whose
/// quartiles need them all). JSON has no NaN or ±∞: such values are written as `null` and read
/// back as NaN; every consumer drops non-finite values or prints them as `null`, so the result
/// is the same JSON.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Floats(pub Vec<f64>);

impl Serialize for Floats {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.collect_seq(self.0.iter().map(|x| x.is_finite().then_some(*x)))
    }
}

impl<'de> Deserialize<'de> for Floats {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let v: Vec<Option<f64>> = Vec::deserialize(d)?;
        Ok(Floats(
            v.into_iter().map(|x| x.unwrap_or(f64::NAN)).collect(),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn shards_cover_every_run_once_on_batch_edges() {
        for total in [1, 7, 8, 37, 1000] {
            for batch in [1, 8] {
                for shards in [1, 2, 3, 7, 200] {
                    let mut at = 0;
                    for i in 0..shards {
                        let r = shard_range(total, batch, i, shards).unwrap();
                        assert_eq!(r.start, at, "{total} {batch} {i}/{shards}");
                        assert!(r.start % batch == 0 && (r.end % batch == 0 || r.end == total));
                        at = r.end;
                    }
                    assert_eq!(at, total);
                }
            }
        }
        assert!(shard_range(10, 1, 3, 3).is_err());
        assert!(shard_range(10, 1, 0, 0).is_err());
        assert_eq!(
            shard_range(10, 1, usize::MAX - 1, usize::MAX).unwrap(),
            9..10
        );
    }

    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn gaps_are_named() {
        assert_eq!(gaps(&[0..5, 7..9], 12), vec![5..7, 9..12]);
        assert_eq!(ranges_text(&[5..7, 9..12]), "5..7 and 9..12");
        assert_eq!(ranges_text(&[0..1, 5..7, 9..12]), "0..1, 5..7 and 9..12");
        assert!(gaps(&[0..12], 12).is_empty());
    }
}
