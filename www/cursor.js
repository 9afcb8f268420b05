// The time cursor of a panel (the set-membership step k, the uniform-innovation time t): moving it
// redraws from the kept report, with the detail the report keeps for one step only (its `at`: the
// exact polygon, hull, optimal face … there) taken from a small cache of details by step. The
// panel's compute worker computes each step's detail once (worker.js: it prefetches every step
// after each report, nearest to the cursor first, and answers a step asked for at once) and sends
// it here; nothing is run again. A step whose detail has not come yet is drawn from what the
// report holds for every step, and completed when it comes (the panel stays busy until then).
// The animation (animation() below) steps the cursor at a chosen speed over the cached steps,
// waiting only for a step whose detail has not come yet.
//
// `spec` is the panel's: block(report) → the report's block holding `at` (report.ubb, …),
// setTime(scenario, t) → writes the cursor into a scenario (the one the panel shows, downloads
// and shares), first(report) and last(report) → the cursor's range for the animation.

// The spec of a panel whose cursor is the slider `time` (with its play button `animate`) over the steps of
// the report's block `key`, written into the scenario as its `key.time`.
export const timeOf = (key) => ({
  control: 'time',
  animate: 'animate',
  block: (report) => report[key],
  setTime: (s, v) => { s[key].time = v; },
});

// The record's own time at a cursor step, as the report carries it (report.figure.times, the
// user's data.t as the core writes it: row t − 1 for t = 1, 2, …; row k for the set-membership
// step k = 0, 1, … with zeroBased): " · 1890" to follow "k = 19", or '' when the record has no
// times (a simulation) or none at that step. Text only: the page computes no time.
export function recordTime(report, step, zeroBased = false) {
  const times = report?.figure?.times;
  const row = zeroBased ? step : step - 1;
  const label = Array.isArray(times) && Number.isInteger(row) ? times[row] : undefined;
  return typeof label === 'string' && label ? ` · ${label}` : '';
}

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

// The narratable animation of a cursor control (a time slider): ◀ and ▶ step it once, the
// play/pause toggle steps it at the chosen speed (0.5–20 steps/s, by elapsed time, not by display
// frames) from where it is (from the first step when it is at the last) to the last, or round and
// round with "loop"; a step whose detail has not come yet is waited for (cursor.ready), never
// skipped. The controls are made here, around the view's play button (its id is the view's), in
// a bar after the slider's row. Keys, while the view is shown and the focus is not in a text
// field or menu: ← and → step, Space or k plays and pauses. The step's read-out (the slider's
// <output>) is a polite live region while paused and silent while playing.
//   button     the view's play button; control: the slider; root: the panel (is it shown?)
//   cursor     the panel's time cursor (timeCursor), or null when every step is drawn at once
//   first(), last()  the steps played over; at(value): the step a slider value shows
//   moved()    what the panel does when the slider moves (its outputs; the scenario's time)
//   draw()     its redraw, or for a control that recomputes (LSCR's data length, GLLS's horizon)
//              its compute: a Promise of whether it succeeded. The next step waits until it has
//              (never a compute queued behind another; the speed is then an upper bound); a
//              compute that fails (false: the panel has shown why; a rejection: showError) pauses
//   ready()    optional: a Promise of the range being known (first() and last() ask the core)
//   rangeText()  optional: the range it plays over, said in the bar ("t = 7 … 30", refresh())
// A disabled control (a simulation's field on the user's data) disables the bar with it.
// frames(capture): the animation's steps one by one for an export (a figure's ZIP of frames):
// pauses, shows each step from first() to last() as playing does (its detail waited for), awaits
// `capture(i, n)` after drawing the i-th of n, then puts the slider back where it was and redraws;
// a Promise of the captures in step order. Play, pause, ◀ ▶, the slider moved by hand or another
// preset meanwhile cancel it (it rejects with FramesCancelled, the slider left where it is now).
export const SPEEDS = [0.5, 1, 2, 5, 10, 20]; // steps per second
export const DEFAULT_SPEED = 2;
const PLAY = '▶ play';
const PAUSE = '❚❚ pause';

const el = (tag, props = {}, attrs = {}) => {
  const e = Object.assign(document.createElement(tag), props);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  return e;
};

export class FramesCancelled extends Error {
  constructor() { super('the frame export was cancelled'); }
}

export function animation({ button, control, root, cursor = null, setBusy, first, last, at = (v) => v, moved, draw, showError, ready = null, rangeText = null }) {
  // The bar: ◀ play ▶, speed, loop.
  const bar = el('div', { className: 'anim-bar' });
  const prev = el('button', { type: 'button', textContent: '◀', title: 'previous step (←)' }, { 'aria-label': 'previous step', 'data-anim': 'prev' });
  const next = el('button', { type: 'button', textContent: '▶', title: 'next step (→)' }, { 'aria-label': 'next step', 'data-anim': 'next' });
  const speed = el('select', { title: 'steps per second' }, { 'aria-label': 'animation speed', 'data-anim': 'speed' });
  speed.append(...SPEEDS.map((v) => new Option(`${v} steps/s`, String(v), v === DEFAULT_SPEED, v === DEFAULT_SPEED)));
  const loop = el('input', { type: 'checkbox' }, { 'data-anim': 'loop' });
  const loopLabel = el('label', { className: 'anim-loop' });
  loopLabel.append(loop, ' loop');
  const row = button.closest('.slider-num') || button.parentElement;
  row.after(bar);
  button.classList.add('anim-play');
  button.dataset.anim = 'play';
  button.title = 'play or pause (Space or k)';
  bar.append(prev, button, next, speed, loopLabel);
  const range = rangeText ? el('span', { className: 'anim-range', title: 'the steps the animation plays over' }, { 'data-anim': 'range' }) : null;
  if (range) bar.append(range);
  const out = root.querySelector(`label[for="${control.id}"] output`) || control.closest('label')?.querySelector('output')
    || root.querySelector(`#${control.id}-out`);
  out?.setAttribute('aria-live', 'polite');
  const label = (on) => {
    button.textContent = on ? PAUSE : PLAY;
    button.setAttribute('aria-label', on ? 'pause' : 'play');
    button.setAttribute('aria-pressed', String(on));
    out?.setAttribute('aria-live', on ? 'off' : 'polite');
  };
  label(false);

  let playing = null;
  let exporting = null; // the frame export going on (frames())
  let stepping = false; // while the bar sends the control's events (the panel tells them from the user's)
  let timer = 0;
  let resched = null; // a new speed: the next step one new interval after the last shown
  const interval = () => 1000 / Number(speed.value || DEFAULT_SPEED);
  function stop() {
    exporting = null; // so do pause, ◀ ▶, the slider moved by hand, another preset
    if (!playing) return;
    playing = null;
    clearTimeout(timer);
    timer = 0;
    label(false);
    setBusy(-1);
    // The share link follows the cursor (it listens to change events).
    stepping = true;
    try {
      control.dispatchEvent(new Event('change', { bubbles: true }));
    } finally {
      stepping = false;
    }
  }
  // Show slider value v: drawn from the cache (the caller has waited for its detail), or
  // computed (a Promise of whether the compute succeeded).
  const showValue = (v) => {
    control.value = String(v);
    moved();
    return draw();
  };
  function start() {
    if (playing || control.disabled) return;
    exporting = null; // play cancels a frame export
    const me = {};
    playing = me;
    setBusy(+1);
    label(true);
    let v = null; // the step shown: from where the control is once the range is known
    let due = performance.now();
    let shownAt = due;
    resched = () => {
      if (playing !== me || !timer) return;
      clearTimeout(timer);
      due = shownAt + interval();
      timer = setTimeout(tick, Math.max(0, due - performance.now()));
    };
    const tick = async () => {
      timer = 0;
      if (playing !== me) return;
      if (v === null) {
        v = Number(control.value);
        if (v >= last()) v = first() - 1;
      }
      let n = v + 1;
      if (n > last()) {
        if (!loop.checked) { stop(); return; }
        n = first();
      }
      if (n < first()) n = first();
      if (cursor && !cursor.has(at(n))) {
        // Wait for this step's detail, then show it at once.
        cursor.ready(at(n)).then(() => { if (playing === me) tick(); }, (e) => {
          if (playing !== me) return;
          stop();
          showError(e);
        });
        return;
      }
      v = n;
      const drawn = showValue(v);
      if (drawn && typeof drawn.then === 'function') {
        // A compute: the next step is scheduled once it has ended, never queued behind it.
        let ok;
        try {
          ok = await drawn;
        } catch (e) {
          if (playing !== me) return;
          stop();
          showError(e);
          return;
        }
        if (playing !== me) return;
        if (ok === false) { stop(); return; }
      }
      // The next step one interval after this one was due (later, if drawing or waiting fell behind).
      const now = performance.now();
      shownAt = now;
      due = Math.max(due + interval(), now);
      if (due - now > interval()) due = now + interval();
      timer = setTimeout(tick, due - now);
    };
    if (ready) {
      // The range is asked of the core: the first step waits for it.
      ready().then(() => { if (playing === me && !timer) timer = setTimeout(tick, 0); }, (e) => {
        if (playing !== me) return;
        stop();
        showError(e);
      });
    } else {
      timer = setTimeout(tick, 0);
    }
  }
  const toggle = () => (playing ? stop() : start());

  async function frames(capture) {
    stop();
    const me = {};
    exporting = me;
    const was = control.value;
    if (ready) await ready(); // a range asked of the core
    if (exporting !== me) throw new FramesCancelled();
    const lo = first(), hi = last();
    const n = hi - lo + 1;
    const out = [];
    setBusy(+1);
    try {
      for (let v = lo; v <= hi; v++) {
        // The step's detail, waited for as tick() does (ready() may resolve for a newer request:
        // look again).
        while (cursor && exporting === me && !cursor.has(at(v))) await cursor.ready(at(v));
        if (exporting !== me) throw new FramesCancelled();
        if (first() !== lo || last() !== hi) throw new Error('the steps changed while the frames were made (a new run)');
        // A control that recomputes: the step's run first (false: refused, said by the panel).
        if ((await showValue(v)) === false) throw new Error(`step ${v} could not be computed`);
        if (exporting !== me) throw new FramesCancelled();
        out.push(await capture(v - lo, n));
      }
      return out;
    } finally {
      if (exporting === me) {
        exporting = null;
        await showValue(was);
      }
      setBusy(-1);
    }
  }

  // One step back or forward, as the user moving the slider (its input and change events): the
  // animation pauses, the panel redraws through its usual path, the share link follows.
  async function step(d) {
    stop();
    if (control.disabled) return;
    if (ready) {
      try {
        await ready();
      } catch (e) {
        showError(e);
        return;
      }
      if (playing) return; // played meanwhile
    }
    const v = Number(control.value);
    let n = Math.min(Math.max(v + d, Math.max(first(), Number(control.min))), Math.min(last(), Number(control.max)));
    if (d < 0 && v > last()) n = last();
    if (n === v) return;
    control.value = String(n);
    stepping = true;
    try {
      control.dispatchEvent(new Event('input', { bubbles: true }));
      control.dispatchEvent(new Event('change', { bubbles: true }));
    } finally {
      stepping = false;
    }
  }

  // The bar follows the control (disabled with it) and says its range (data-first, data-last).
  function refresh() {
    for (const b of [prev, button, next, speed, loop]) b.disabled = control.disabled;
    if (!range) return;
    const [lo, hi] = [first(), last()];
    bar.dataset.first = String(lo);
    bar.dataset.last = String(hi);
    range.textContent = rangeText();
  }
  refresh();

  button.addEventListener('click', toggle);
  prev.addEventListener('click', () => step(-1));
  next.addEventListener('click', () => step(+1));
  speed.addEventListener('change', () => resched?.());
  // The range asked for as the pointer or the focus reaches the bar (the first step is then ready).
  if (ready) for (const ev of ['pointerenter', 'focusin']) bar.addEventListener(ev, () => { ready().catch(() => {}); });

  // Keys, for the view that is shown, unless the focus is where they mean something else.
  document.addEventListener('keydown', (e) => {
    if (e.defaultPrevented || e.ctrlKey || e.altKey || e.metaKey) return;
    if (root.closest('[hidden]') || !root.isConnected) return;
    const t = e.target;
    if (t instanceof Element && t.closest('input:not([type=checkbox]), select, textarea, [contenteditable=""], [contenteditable=true]')) return;
    const onButton = t instanceof Element && t.closest('button, a[href], summary, input[type=checkbox]');
    if (e.key === 'ArrowLeft' || e.key === 'ArrowRight') {
      e.preventDefault();
      step(e.key === 'ArrowLeft' ? -1 : +1);
    } else if ((e.key === ' ' && !onButton) || e.key === 'k' || e.key === 'K') {
      e.preventDefault();
      toggle();
    }
  });

  return { stop, step, toggle, refresh, frames, get playing() { return !!playing; }, get stepping() { return stepping; } };
}
