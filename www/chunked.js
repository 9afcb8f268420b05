// Shared by the panels: wasm experiments run in chunks (about 12 ms of work per task, then the
// browser paints and Cancel can land), input bursts coalesced into one run per frame, and core
// errors shown next to the field they name.

const SLICE_MS = 12;
// Yield to the browser (it paints when a frame is due) without setTimeout's 4 ms clamp.
const channel = new MessageChannel();
const waiting = [];
channel.port1.onmessage = () => waiting.shift()?.();
const yieldToBrowser = () => new Promise((r) => { waiting.push(r); channel.port2.postMessage(0); });

// Step `exp` (a wasm Study: step(k) → JSON result, finished()) `chunk`
// runs at a time until it finishes or `me.cancelled` is set; `onChunk(counts)` after every
// slice. Returns the last counts, the wall time and the time spent computing (ms).
export async function runChunked(exp, chunk, me, onChunk) {
  const t0 = performance.now();
  let compute = 0;
  let counts = null;
  while (!me.cancelled) {
    const s0 = performance.now();
    do counts = JSON.parse(exp.step(chunk)); while (!exp.finished() && performance.now() - s0 < SLICE_MS);
    compute += performance.now() - s0;
    onChunk(counts);
    if (exp.finished()) break;
    await yieldToBrowser();
  }
  return { counts, wall: performance.now() - t0, compute };
}

// A run-per-frame scheduler: schedule('compute') or schedule('redraw') during a burst of input
// events runs once on the next animation frame (a compute covers a redraw); the panel's busy
// count is held meanwhile so tests can wait for it.
export function frameScheduler(setBusy, compute, redraw) {
  let queued = null;
  return function schedule(what) {
    if (queued === 'compute' || queued === what) return;
    if (!queued) setBusy(+1);
    queued = what;
    requestAnimationFrame(() => {
      const w = queued;
      queued = null;
      try { if (w === 'compute') compute(); else redraw(); } finally { setBusy(-1); }
    });
  };
}

// Inline errors of a panel: `<p class="err" data-for="model.F">` holds the message of an error
// whose field is model.F or below it (model.F[1][0]); the longest matching prefix wins, and the
// control with the same data-field is marked invalid. `within` narrows what clear() empties.
export function fieldErrors(root, staleNote, within = '') {
  const all = (sel) => root.querySelectorAll(`${within}${sel}`);
  function clear() {
    for (const p of all('.err[data-for]')) p.textContent = '';
    for (const c of all('[aria-invalid]')) c.removeAttribute('aria-invalid');
    staleNote.hidden = true;
  }
  // `e` is a core error ({field, message}) or any Error; `hasGood` says a last good picture stays.
  function show(e, hasGood) {
    const field = e && typeof e.field === 'string' ? e.field : '';
    const message = (e && e.message) || String(e);
    let best = null;
    for (const p of root.querySelectorAll('.err[data-for]')) {
      const f = p.dataset.for;
      const hit = f === '' || field === f || field.startsWith(`${f}.`) || field.startsWith(`${f}[`);
      if (hit && (!best || f.length > best.dataset.for.length)) best = p;
    }
    clear();
    if (best) best.textContent = message;
    const control = root.querySelector(`[data-field="${best ? best.dataset.for : ''}"]`);
    if (control) control.setAttribute('aria-invalid', 'true');
    staleNote.hidden = !hasGood;
  }
  return { show, clear };
}

// One run of a panel's scenario: `build()` makes it, `run(scenario)` returns the report's JSON
// (one wasm call, or two when the first report fixes something the scenario must be run with).
// On success the report, its JSON, the scenario and the run time (ms, `build` excluded) land in
// `st` and the inline errors clear; on failure the error shows next to its field (the last good
// picture, if any, stays). Returns whether it succeeded.
export function runScenario(st, errors, build, run) {
  let scenario, json;
  try {
    scenario = build();
    const t0 = performance.now();
    json = run(scenario);
    st.runMs = performance.now() - t0;
    st.report = JSON.parse(json);
    errors.clear();
  } catch (e) {
    errors.show(e, !!st.report);
    return false;
  }
  st.reportJson = json;
  st.scenario = scenario;
  return true;
}

// A counter of running computations shown as document.body.dataset[key] (set while > 0), which
// the end-to-end tests wait on.
export function busyFlag(key) {
  let busy = 0;
  return (d) => {
    busy += d;
    if (busy > 0) document.body.dataset[key] = '1'; else delete document.body.dataset[key];
  };
}
