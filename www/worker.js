// The compute worker: its own instance of the wasm module runs the panels' scenarios, so a long
// run never blocks the page's input and a fault (a panic or an allocation failure aborts the
// instance; every later call into it would fail) dies with the worker, not with the page. It
// never draws: plotters' text layout panics inside a worker, so the page draws on the main
// thread from the report this worker sends back (Session.setReport).
//
// Messages in:  {id, scenario: JSON text} — run it; {id, scenario, testOnlyAbort: true} — the
//               page tests' crash: abort the instance instead (no scenario can ask for it);
//               {id, study: {scenario, runs, shard: [i, n]}} — run shard i of n of the
//               scenario's study (studypool.js), to its end, in slices.
// Messages out: {ready: true, initMs} once the module is loaded; then per job one of
//               {id, report: JSON text, ms}        the core's report and its compute time here
//               {id, error: {field, message}}      the core refused the scenario (a user error)
//               {id, fault: message}               anything else: the instance is not to be trusted
//               {id, partial: JSON text, ms, done}  a study's shard after each slice: its
//                                                  partial counts (the core's `Study.partial`),
//                                                  the time computed so far, whether it is done
import init, { Session, Study, testOnlyAbort } from './pkg/confset.js';

// A study sends its partial counts about this often: often enough for a live progress bar, and
// the main thread merges at most once per frame.
const STUDY_SLICE_MS = 150;
// Run one shard of a study to its end; steps grow until one takes about a tenth of a slice (a
// chunk boundary never changes the counts).
function runShard(id, { scenario, runs, shard: [i, n] }) {
  const study = new Study(scenario, runs);
  try {
    study.restrict(i, n);
    let chunk = 1;
    let ms = 0;
    for (;;) {
      const s0 = performance.now();
      while (!study.finished() && performance.now() - s0 < STUDY_SLICE_MS) {
        const c0 = performance.now();
        study.step(chunk);
        if (performance.now() - c0 < STUDY_SLICE_MS / 10) chunk *= 2;
      }
      ms += performance.now() - s0;
      const done = study.finished();
      postMessage({ id, partial: study.partial(), ms, done });
      if (done) return;
    }
  } finally {
    study.free();
  }
}

// The core's errors carry the field they are about (a user error); a trap (RuntimeError) or
// anything else does not (a fault: the instance is not to be trusted).
function postFailure(id, e) {
  if (e && typeof e.field === 'string') postMessage({ id, error: { field: e.field, message: e.message } });
  else postMessage({ id, fault: `${e?.name || 'Error'}: ${e?.message || e}` });
}

const t0 = performance.now();
const loaded = init().then(() => postMessage({ ready: true, initMs: performance.now() - t0 }));

self.onmessage = async ({ data: { id, scenario, study, testOnlyAbort: abort } }) => {
  try {
    await loaded;
  } catch (e) {
    postMessage({ id, fault: `the WebAssembly module could not be loaded in the worker: ${e?.message || e}` });
    return;
  }
  if (study) {
    try {
      runShard(id, study);
    } catch (e) {
      postFailure(id, e);
    }
    return;
  }
  // A fresh Session per job: the worker keeps no report (the page's Session keeps the one it draws).
  const session = new Session();
  try {
    if (abort) testOnlyAbort();
    const s0 = performance.now();
    const report = session.run(scenario);
    postMessage({ id, report, ms: performance.now() - s0 });
  } catch (e) {
    postFailure(id, e);
    return;
  }
  session.free();
};
