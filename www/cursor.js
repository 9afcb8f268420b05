// The time cursor of a panel (the set-membership step k, the uniform-innovation time t): moving it
// redraws from the kept report, with the detail the report keeps for one step only (its `at`: the
// exact polygon, hull, optimal face … there) taken from a small cache of details by step. The
// panel's compute worker computes each step's detail once (worker.js: it prefetches every step
// after each report, nearest to the cursor first, and answers a step asked for at once) and sends
// it here; nothing is run again. A step whose detail has not come yet is drawn from what the
// report holds for every step, and completed when it comes (the panel stays busy until then).
// ▶ animate steps the cursor once per display frame over the cached steps, waiting only for a
// step whose detail has not come yet.
//
// `spec` is the panel's: block(report) → the report's block holding `at` (report.ubb, …),
// setTime(scenario, t) → writes the cursor into a scenario (the one the panel shows, downloads
// and shares), first(report) and last(report) → the cursor's range for the animation.

// The spec of a panel whose cursor is the slider `time` (with its ▶ `animate`) over the steps of
// the report's block `key`, written into the scenario as its `key.time`.
export const timeOf = (key) => ({
  control: 'time',
  animate: 'animate',
  block: (report) => report[key],
  setTime: (s, v) => { s[key].time = v; },
});

export function timeCursor({ worker, session, st, setBusy, redraw, showError }, spec) {
  const details = new Map(); // step → JSON text of the report's `at` there (this report's cursor)
  let key = null; // the worker's cursor of the kept report
  let scenarioText = ''; // the scenario it was run on (the worker's cursor is made from it)
  let asked = null; // the step asked for, not here yet (the panel is busy meanwhile)
  const arrivals = new Map(); // step → resolvers waiting for its detail

  worker.onDetail = (k, t, at) => {
    if (k !== key) return; // another report's
    details.set(t, at);
    for (const resolve of arrivals.get(t) || []) resolve();
    arrivals.delete(t);
    if (t === asked) {
      asked = null;
      redraw();
      setBusy(-1);
    }
  };

  function release() {
    if (asked === null) return;
    asked = null;
    setBusy(-1);
  }

  // Ask the worker for step t (the newest wins); busy until it comes.
  function ask(t) {
    if (asked === t) return;
    if (asked === null) setBusy(+1);
    asked = t;
    request(t);
  }

  function request(t) {
    worker.at(scenarioText, t).then((d) => {
      // Superseded by a request for another step (a download's, the animation's): again, while
      // it is still the step shown.
      if (d === null && asked === t && !details.has(t)) request(t);
    }, (e) => {
      if (asked !== t) return;
      release();
      showError(e);
    });
  }

  // Whoever waits for a detail of the last report's cursor looks again.
  function wakeAll() {
    const waiters = [...arrivals.values()].flat();
    arrivals.clear();
    for (const resolve of waiters) resolve();
  }

  const cursor = {
    // A new report, run on `text` in the worker, whose cursor is `cursorKey`: the cache starts
    // again with the report's own detail.
    reset(text, cursorKey) {
      release();
      wakeAll();
      key = cursorKey;
      scenarioText = text;
      details.clear();
      details.set(st.report.time, JSON.stringify(spec.block(st.report).at));
    },
    // Whether step t's detail is here.
    has: (t) => details.has(t),
    // Make the kept report show step t: true when it does, false while its detail is asked for
    // (the figures then draw the step from what the report holds for every step).
    show(t) {
      if (!st.report) return false;
      if (st.report.time === t) { if (asked !== null && asked !== t) release(); return true; }
      const at = details.get(t);
      if (at === undefined) { ask(t); return false; }
      if (asked !== null) release();
      session.setAt(at);
      spec.block(st.report).at = JSON.parse(at);
      st.report.time = t;
      return true;
    },
    // A Promise that resolves when step t's detail is here, asking for it (or, when a newer
    // request or report came first, for the caller to look again); it rejects with the error
    // of the step.
    ready(t) {
      if (details.has(t)) return Promise.resolve();
      return new Promise((resolve, reject) => {
        arrivals.set(t, [...(arrivals.get(t) || []), resolve]);
        worker.at(scenarioText, t).then((d) => { if (d === null) resolve(); }, (e) => {
          arrivals.delete(t);
          reject(e);
        });
      });
    },
    // The scenario the panel shows, downloads and shares follows the cursor.
    moved(t) {
      if (st.scenario) spec.setTime(st.scenario, t);
    },
  };
  return cursor;
}

// ▶ animate: the cursor control steps once per display frame from where it is (from the first
// step when it is at the end) to the last, drawing each step from the cache and waiting only for
// a detail that has not come yet. `at(value)` is the step a control value shows, `moved()` what
// the panel does when the control moves (its outputs; the scenario's time), `draw()` its redraw.
export function animation({ button, control, cursor, setBusy, first, last, at, moved, draw, showError }) {
  let playing = null;
  const label = button.textContent;
  function stop() {
    if (!playing) return;
    playing = null;
    button.textContent = label;
    setBusy(-1);
    // The share link follows the cursor (it listens to change events).
    control.dispatchEvent(new Event('change', { bubbles: true }));
  }
  function start() {
    if (playing) return;
    const me = {};
    playing = me;
    setBusy(+1);
    button.textContent = '■ stop';
    let v = Number(control.value);
    if (v >= last()) v = first() - 1;
    const frame = () => {
      if (playing !== me) return;
      const next = v + 1;
      if (next > last()) { stop(); return; }
      if (!cursor.has(at(next))) {
        // Wait for this step's detail, then go on at the next frame.
        cursor.ready(at(next)).then(() => requestAnimationFrame(frame), (e) => {
          if (playing !== me) return;
          stop();
          showError(e);
        });
        return;
      }
      v = next;
      control.value = String(v);
      moved();
      draw();
      requestAnimationFrame(frame);
    };
    requestAnimationFrame(frame);
  }
  button.addEventListener('click', () => (playing ? stop() : start()));
  return { stop, get playing() { return !!playing; } };
}
