// Monte Carlo over rare realizations (SCF paper, Section II-B), run by the wasm Study in
// chunks: about 12 ms of work per task, so the page keeps painting and can cancel.
import { Study } from './pkg/confset.js';
import { wholeNumber } from './parse.js';

import { runChunked } from './chunked.js';

const CHUNK = 500;
const n = (v) => v.toLocaleString('en-US');

export function mountMonteCarlo(root, getScenario, setBusy) {
  const q = (id) => root.querySelector(`#${id}`);
  const [go, cancel, bar, status, err, nIn] = ['mc-go', 'mc-cancel', 'mc-progress', 'mc-status', 'mc-err', 'mc-n'].map(q);
  let running = null; // { cancelled, stale }

  function show(c, done) {
    const frac = (k) => `${n(k)} / ${n(c.runs_done)}`;
    q('mc-kf-in').textContent = frac(c.kf_inside);
    q('mc-scf-in').textContent = frac(c.scf_inside);
    q('mc-kf-w').textContent = c.warning_t ? frac(c.kf_warnings) : '–';
    q('mc-scf-w').textContent = c.warning_t ? frac(c.scf_warnings) : '–';
    bar.max = c.runs_total;
    bar.value = c.runs_done;
    if (done) {
      const [lo, hi] = c.scf_expected_range;
      const ok = c.scf_inside >= lo && c.scf_inside <= hi;
      q('mc-range').innerHTML = `At α = ${c.alpha}, the SCF count should lie in [${n(lo)}, ${n(hi)}] `
        + `(99.9 % binomial range for ${n(c.runs_total)} runs): ${ok ? '<b class="good">it does</b>' : '<b class="warn">it does not</b>'}.`;
    }
  }

  async function run() {
    err.textContent = '';
    q('mc-range').textContent = '';
    let exp;
    try {
      const runs = wholeNumber('experiment.runs', nIn.value);
      const { scenario, preset } = getScenario();
      scenario.experiment = { ...preset.experiment, runs };
      for (const el of root.querySelectorAll('.mc-tc')) el.textContent = scenario.simulate.condition.t;
      for (const el of root.querySelectorAll('.mc-tw')) el.textContent = `${scenario.experiment.warning_t} (τ = ${scenario.tau})`;
      exp = new Study(JSON.stringify(scenario), 0);
    } catch (e) {
      err.textContent = e.message;
      return;
    }
    const me = { cancelled: false };
    running = me;
    go.disabled = true;
    cancel.disabled = false;
    setBusy(+1);
    try {
      const { counts: c, wall, compute } = await runChunked(exp, CHUNK, me, (c) => {
        show(c, false);
        status.textContent = `${n(c.runs_done)} / ${n(c.runs_total)} runs`;
      });
      if (me.stale) return; // the scenario changed: these counts belong to the old one
      show(c, !me.cancelled);
      status.textContent = me.cancelled
        ? `cancelled after ${n(c.runs_done)} runs`
        : `${n(c.runs_done)} runs in ${wall.toFixed(0)} ms (computing ${compute.toFixed(0)} ms, ${(1000 * compute / c.runs_done).toFixed(1)} µs per run)`;
    } catch (e) {
      err.textContent = e.message;
    } finally {
      exp.free();
      running = null;
      go.disabled = false;
      cancel.disabled = true;
      setBusy(-1);
    }
  }

  go.addEventListener('click', run);
  cancel.addEventListener('click', () => { if (running) running.cancelled = true; });

  // A new scenario: stop a run and clear counts that belong to the old one.
  return function reset() {
    if (running) Object.assign(running, { cancelled: true, stale: true });
    for (const id of ['mc-kf-in', 'mc-scf-in', 'mc-kf-w', 'mc-scf-w']) q(id).textContent = '–';
    for (const el of [status, err, q('mc-range')]) el.textContent = '';
    bar.value = 0;
  };
}
