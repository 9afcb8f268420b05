// The compute worker: its own instance of the wasm module runs the panels' scenarios, so a long
// run never blocks the page's input and a fault (a panic or an allocation failure aborts the
// instance; every later call into it would fail) dies with the worker, not with the page. It
// never draws: plotters' text layout panics inside a worker, so the page draws on the main
// thread from the report this worker sends back (Session.setReport).
//
// Messages in:  first {module: WebAssembly.Module} (compiled once by the page: wasm.js);
//               then {id, scenario: JSON text} — run it; {id, scenario, testOnlyAbort: true} — the
//               page tests' crash: abort the instance instead (no scenario can ask for it);
//               {id, scenario, testOnlySlowMs: ms} — the page tests' long run: hold the worker
//               that long first, as a long wasm call would (the work budget keeps every
//               accepted scenario to about 2 s, too close to the 1 s Cancel to test with);
//               {id, cursor: {scenario: JSON text, t}} — the detail of step t of that
//               scenario's time cursor (the report's `at` there; see "time cursor" below);
//               {id, study: {scenario, runs, shard: [i, n]}} — run shard i of n of the
//               scenario's study (studypool.js), to its end, in slices;
//               {id, firstAccepted: JSON text} — the smallest value of the quantity the
//               scenario's view animates by rerunning that the core accepts (an animation's start);
//               {id, csv: {scenario, text, name}} — the scenario with the CSV file's data (the
//               core's reader: a 20 MB file takes a fifth of a second, off the page's thread).
// Messages out: {ready: true, initMs} once the module is loaded; then per job one of
//               {id, report: JSON text, ms}        the core's report and its compute time here
//               {id, first: JSON text}             a firstAccepted job's {field, value}
//               {id, withData: JSON text}          a csv job's scenario
//               {id, detail: {t, at: JSON text, cursor}}  a cursor job's detail (`cursor`: the
//                                                  number of the cursor it comes from)
//               {id, superseded: true}             a cursor job a newer one replaced unanswered
//               {id, error: {field, message}}      the core refused the scenario (a user error)
//               {id, fault: message}               anything else: the instance is not to be trusted
//               {id, partial: JSON text, ms, done}  a study's shard after each slice: its
//                                                  partial counts (the core's `Study.partial`),
//                                                  the time computed so far, whether it is done
//               and, unasked, {prefetched: {t, at, cursor}} for every detail prefetched.
import init, { Session, Cursor, Study, firstAccepted, withCsvData, testOnlyAbort, timeCompare } from './pkg/confset.js';

// A study sends its partial counts about this often: often enough for a live progress bar, and
// the main thread merges at most once per frame.
const STUDY_SLICE_MS = 150;
// Run one shard of a study to its end; steps grow until one takes about a tenth of a slice (a
// chunk boundary never changes the counts).
function studyJob({ id, study: { scenario, runs, shard: [i, n] } }) {
  let study;
  try {
    study = new Study(scenario, runs);
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
  } catch (e) {
    answerError(id, e);
  } finally {
    study?.free();
  }
}

const t0 = performance.now();
// The module comes compiled from the main thread (wasm.js), in the first message: {module}
// (or {moduleError: message} when the page could not compile it); the worker never fetches it.
let arrived;
const compiled = new Promise((resolve, reject) => { arrived = { resolve, reject }; });
// Each method of a compare is timed by this worker's clock (the core reads none).
const loaded = compiled
  .then((module) => init({ module_or_path: module }))
  .then(() => { timeCompare(); postMessage({ ready: true, initMs: performance.now() - t0 }); });

self.onmessage = async ({ data }) => {
  if (data.module) { arrived.resolve(data.module); return; }
  if (data.moduleError) { arrived.reject(new Error(data.moduleError)); return; }
  try {
    await loaded;
  } catch (e) {
    postMessage({ id: data.id, fault: `the WebAssembly module could not be loaded in the worker: ${e?.message || e}` });
    return;
  }
  if (data.study) studyJob(data);
  else if (data.cursor) cursorJob(data);
  else if (data.firstAccepted) firstJob(data);
  else if (data.csv) csvJob(data);
  else runJob(data);
};

// The core's errors carry the field they are about; a trap (RuntimeError) or anything else
// does not.
function answerError(id, e) {
  if (e && typeof e.field === 'string') postMessage({ id, error: { field: e.field, message: e.message } });
  else postMessage({ id, fault: `${e?.name || 'Error'}: ${e?.message || e}` });
}

function firstJob({ id, firstAccepted: scenario }) {
  try {
    postMessage({ id, first: firstAccepted(scenario) });
  } catch (e) {
    answerError(id, e);
  }
}

function csvJob({ id, csv: { scenario, text, name, columns } }) {
  try {
    postMessage({ id, withData: withCsvData(scenario, text, name, columns) });
  } catch (e) {
    answerError(id, e);
  }
}

function runJob({ id, scenario, testOnlyAbort: abort, testOnlySlowMs: slow }) {
  // A fresh Session per job: the worker keeps no report (the page's Session keeps the one it draws).
  const session = new Session();
  try {
    if (abort) testOnlyAbort();
    for (const end = performance.now() + (slow || 0); performance.now() < end;); // blocks, as a long call
    const s0 = performance.now();
    const report = session.run(scenario);
    const ms = performance.now() - s0;
    const c = cursorOf(scenario);
    c.focus ??= session.shownTime();
    postMessage({ id, report, ms, cursor: c.number });
  } catch (e) {
    answerError(id, e);
    return;
  }
  session.free();
  // From the next task on: the jobs already waiting come first.
  setTimeout(() => prefetch(current), 0);
}

// ----- the time cursor -----
// After every report the worker makes that scenario's Cursor (the run prepared once: its
// time field is not used) and computes the detail of every step, nearest to the cursor first,
// one step per task: a job that arrives meanwhile is served before the next step. Every detail
// is kept here and posted unasked ({prefetched}) for the page's own cache. A cursor job is
// answered from what is kept, or computed at once; of the cursor jobs waiting, only the newest
// is computed (the others are answered `superseded`: the page wants the newest cursor only).

let current = null; // {scenario, cursor: Cursor | null, error, number, details: Map t → JSON, focus}
let cursors = 0;
let waiting = null; // the newest cursor job not yet answered: {id, scenario, t}

// The state of a scenario's cursor: the kept one, or a new one (replacing it), numbered. Its
// Cursor is made when first needed (`made`); a method without a cursor (or a scenario the core
// refuses) keeps the error, thrown at each cursor job.
function cursorOf(scenario) {
  if (current?.scenario === scenario) return current;
  current?.cursor?.free();
  current = { scenario, cursor: undefined, error: null, number: ++cursors, details: new Map(), focus: null, running: false };
  return current;
}

function made(c) {
  if (c.cursor === undefined) {
    try {
      c.cursor = new Cursor(c.scenario);
    } catch (e) {
      c.cursor = null;
      c.error = e;
    }
  }
  return c.cursor;
}

// The detail of step t from state `c` (kept, or computed and kept).
function detailOf(c, t) {
  let at = c.details.get(t);
  if (at === undefined) {
    if (!made(c)) throw c.error;
    at = c.cursor.at(t);
    c.details.set(t, at);
  }
  return at;
}

function cursorJob({ id, cursor: { scenario, t } }) {
  if (waiting) postMessage({ id: waiting.id, superseded: true });
  waiting = { id, scenario, t };
  // Served in a task of its own, after the jobs already queued: a burst of cursor moves costs
  // one detail, the newest.
  setTimeout(serveCursorJob, 0);
}

function serveCursorJob() {
  const job = waiting;
  if (!job) return;
  waiting = null;
  const c = cursorOf(job.scenario);
  try {
    c.focus = job.t;
    const at = detailOf(c, job.t);
    postMessage({ id: job.id, detail: { t: job.t, at, cursor: c.number } });
  } catch (e) {
    answerError(job.id, e);
  }
  prefetch(c);
}

// One step per task while `c` is the current cursor and a step is missing.
function prefetch(c) {
  if (!c || c.running || !made(c)) return;
  c.running = true;
  const next = () => {
    if (c !== current) { c.running = false; return; }
    const [first, last] = [c.cursor.first(), c.cursor.last()];
    const focus = Math.min(Math.max(c.focus ?? last, first), last);
    let t = null;
    for (let d = 0; d <= last - first && t === null; d++) {
      for (const u of [focus + d, focus - d]) {
        if (u >= first && u <= last && !c.details.has(u)) { t = u; break; }
      }
    }
    if (t === null) { c.running = false; return; }
    let at;
    try {
      at = detailOf(c, t);
    } catch (e) {
      // A step the core refuses: the cursor job for it says why; the prefetch stops here.
      c.running = false;
      return;
    }
    postMessage({ prefetched: { t, at, cursor: c.number } });
    setTimeout(next, 0);
  };
  setTimeout(next, 0);
}
