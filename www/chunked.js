// Shared by the panels: the studies' Start/Cancel/progress (their runs go to the study workers:
// studypool.js), input bursts coalesced into one run per frame, and core errors shown next to
// the field they name. (A panel's scenario runs in its compute worker: compute.js, panel.js.)
import { runStudy } from './studypool.js';
import { int } from './format.js';

// A run-per-frame scheduler: schedule('compute') or schedule('redraw') during a burst of input
// events runs once on the next animation frame (a compute covers a redraw); the panel's busy
// count is held until it has drawn — for a compute, until the Promise `compute()` returns
// settles — so tests can wait for it.
export function frameScheduler(setBusy, compute, redraw) {
  let queued = null;
  return function schedule(what) {
    if (queued === 'compute' || queued === what) return;
    if (!queued) setBusy(+1);
    queued = what;
    requestAnimationFrame(async () => {
      const w = queued;
      queued = null;
      try { if (w === 'compute') await compute(); else redraw(); } finally { setBusy(-1); }
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
    // Only a place the user can see: an error of a field whose box is hidden (a custom model's,
    // while a preset is shown) goes to the nearest visible place, at worst the panel's banner.
    for (const p of root.querySelectorAll('.err[data-for]')) {
      if (p.closest('[hidden]')) continue;
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

// A counter of running computations shown as document.body.dataset[key] (set while > 0), which
// the end-to-end tests wait on.
export function busyFlag(key) {
  let busy = 0;
  return (d) => {
    busy += d;
    if (busy > 0) document.body.dataset[key] = '1'; else delete document.body.dataset[key];
  };
}


// A panel's study (its Start and Cancel buttons, progress bar, status line and error), written
// once; its runs go to every core (studypool.js):
//   start(...args)        the run: { scenario (JSON text), runs (0: the scenario's count), study
//                         (the main thread's wasm Study of it, which merges the workers' counts),
//                         total (runs asked), at?, note? } — `at` follows "N runs" in every status
//                         line (" at k = 40"), `note` only while it runs; nothing to run: null; a
//                         throw shows in `err`
//   show(c, done, final)  the counts on the page after every slice; `final`: the last one, `done`:
//                         it finished without a cancel
//   runs(c)               the runs done in the counts (c.runs)
//   perRun(ms, runs), extra(c), cancelWall   the wording of the closing status line
// A new run or reset() makes the one running stale: it stops at its next slice and shows nothing
// more. The buttons come back only when the run that disabled them ends; `busy` is held meanwhile.
export function studyRunner({ go, cancel, bar, status, err, busy, start, show, runs = (c) => c.runs,
  perRun = (ms, k) => `${(1000 * ms / k).toFixed(0)} µs`, extra = () => '', cancelWall = true }) {
  let running = null; // { cancelled, stale, total, stop() }
  const makeStale = () => { if (running) { Object.assign(running, { cancelled: true, stale: true }); running.stop?.(); } };

  async function run(...args) {
    err.textContent = '';
    let job;
    try {
      job = start(...args);
    } catch (e) {
      err.textContent = e.message;
      return;
    }
    if (!job) return;
    makeStale();
    const me = { cancelled: false, stale: false, total: job.total };
    const at = job.at || '';
    const counted = (c, done, final) => {
      if (bar) {
        bar.max = Math.max(1, me.total);
        bar.value = runs(c);
      }
      show(c, done, final);
    };
    running = me;
    go.disabled = true;
    cancel.disabled = false;
    busy(+1);
    try {
      const { counts: c, wall, compute: ms, workers } = await runStudy({
        scenario: job.scenario, runs: job.runs, merger: job.study, me, onCounts: (c) => {
          if (me.stale) return;
          counted(c, false, false);
          status.textContent = `${int(runs(c))} / ${int(me.total)} runs${at}${job.note || ''}`;
        },
      });
      if (me.stale) return; // the scenario changed: these counts belong to the old one
      if (!c) { status.textContent = 'cancelled before the first runs were counted'; return; }
      counted(c, !me.cancelled, true);
      const k = runs(c);
      const on = `${workers} worker${workers === 1 ? '' : 's'}`;
      status.textContent = me.cancelled
        ? `cancelled after ${int(k)} runs${cancelWall ? ` (${wall.toFixed(0)} ms)` : ''}`
        : `${int(k)} runs${at} in ${wall.toFixed(0)} ms on ${on} (computing ${ms.toFixed(0)} ms in all, ${perRun(ms, k)} per run${extra(c)})`;
    } catch (e) {
      err.textContent = e.message;
    } finally {
      job.study.free();
      if (running === me) {
        running = null;
        go.disabled = false;
        cancel.disabled = true;
      }
      busy(-1);
    }
  }

  go.addEventListener('click', () => run());
  cancel.addEventListener('click', () => { if (running) { running.cancelled = true; running.stop?.(); } });
  return {
    run,
    // A new scenario: stop the run and clear what belongs to the old one.
    reset() {
      makeStale();
      status.textContent = '';
      err.textContent = '';
      if (bar) bar.value = 0;
    },
  };
}
