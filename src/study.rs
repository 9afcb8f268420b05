//! One interface for every chunked Monte Carlo study.
//!
//! Each method's promise is checked by counting over fresh runs: the SCF conditional
//! experiment ([`crate::scf::ConditionalExperiment`]), the LSCR coverage experiment
//! ([`crate::lscr::Experiment`]), the GLLS precision study ([`crate::glls::Precision`]) and the
//! set-membership guarantee (`scenario::ubb::Guarantee`). They all implement [`Study`], so the
//! CLI (`confset experiment`), the one wasm `Study` binding and the tests drive them alike: run
//! a chunk, look at the merged result, stop when finished. A chunk boundary never changes the
//! numbers (every study draws run i from a stream fixed by its seed and i, or by whole batches).

use crate::error::Result;

/// A Monte Carlo study run in chunks.
pub trait Study {
    /// Run up to `runs` more runs (never past the total). A study may round a chunk up to
    /// whole batches of its own; [`Study::runs`] says how many are done.
    fn step(&mut self, runs: usize) -> Result<()>;
    /// Runs done so far.
    fn runs(&self) -> usize;
    /// Runs asked for.
    fn total(&self) -> usize;
    /// Whether every run is done.
    fn finished(&self) -> bool {
        self.runs() >= self.total()
    }
    /// The merged result so far, as the JSON the CLI prints and the page reads (its counts,
    /// the promised levels and their exact binomial bands where the method promises one).
    fn result(&self) -> Result<serde_json::Value>;
}

/// Run a study to the end in chunks of `chunk` runs, calling `progress(done, total)` after each.
pub fn run_to_end(
    study: &mut dyn Study,
    chunk: usize,
    mut progress: impl FnMut(usize, usize),
) -> Result<serde_json::Value> {
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

/// Serialize a study result; serde_json only fails on non-string map keys, which no result has.
pub(crate) fn to_value<T: serde::Serialize>(v: &T) -> Result<serde_json::Value> {
    serde_json::to_value(v)
        .map_err(|e| crate::Error::field("", format!("the study result could not be written: {e}")))
}
