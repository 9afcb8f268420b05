// The compute worker: its own instance of the wasm module runs the panels' scenarios, so a long
// run never blocks the page's input and a fault (a panic or an allocation failure aborts the
// instance; every later call into it would fail) dies with the worker, not with the page. It
// never draws: plotters' text layout panics inside a worker, so the page draws on the main
// thread from the report this worker sends back (Session.setReport).
//
// Messages in:  {id, scenario: JSON text} — run it; {id, scenario, testOnlyAbort: true} — the
//               page tests' crash: abort the instance instead (no scenario can ask for it).
// Messages out: {ready: true, initMs} once the module is loaded; then per job one of
//               {id, report: JSON text, ms}        the core's report and its compute time here
//               {id, error: {field, message}}      the core refused the scenario (a user error)
//               {id, fault: message}               anything else: the instance is not to be trusted
import init, { Session, testOnlyAbort } from './pkg/confset.js';

const t0 = performance.now();
const loaded = init().then(() => postMessage({ ready: true, initMs: performance.now() - t0 }));

self.onmessage = async ({ data: { id, scenario, testOnlyAbort: abort } }) => {
  try {
    await loaded;
  } catch (e) {
    postMessage({ id, fault: `the WebAssembly module could not be loaded in the worker: ${e?.message || e}` });
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
    // The core's errors carry the field they are about; a trap (RuntimeError) or anything else
    // does not.
    if (e && typeof e.field === 'string') postMessage({ id, error: { field: e.field, message: e.message } });
    else postMessage({ id, fault: `${e?.name || 'Error'}: ${e?.message || e}` });
    return;
  }
  session.free();
};
