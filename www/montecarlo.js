// Monte Carlo over rare realizations (SCF paper, Section II-B: the robots' collision, or any
// state fixed at x̄), run on every core by the study workers (studypool.js), with progress and Cancel.
import { Study } from './pkg/confset.js';
import { wholeNumber } from './parse.js';
import { studyRunner } from './chunked.js';
import { int as n } from './format.js';

export function mountMonteCarlo(root, getScenario, setBusy) {
  const q = (id) => root.querySelector(`#${id}`);

  function show(c, done) {
    const frac = (k) => `${n(k)} / ${n(c.runs_done)}`;
    q('mc-kf-in').textContent = frac(c.kf_inside);
    q('mc-scf-in').textContent = frac(c.scf_inside);
    q('mc-kf-w').textContent = c.warning_t ? frac(c.kf_warnings) : '–';
    q('mc-scf-w').textContent = c.warning_t ? frac(c.scf_warnings) : '–';
    if (done) {
      const [lo, hi] = c.scf_expected_range;
      const ok = c.scf_inside >= lo && c.scf_inside <= hi;
      q('mc-range').innerHTML = `At α = ${c.alpha}, the SCF count should lie in [${n(lo)}, ${n(hi)}] `
        + `(99.9 % binomial range for ${n(c.runs_total)} runs): ${ok ? '<b class="good">it does</b>' : '<b class="warn">it does not</b>'}.`;
    }
  }

  function start() {
    q('mc-range').textContent = '';
    const runs = wholeNumber('experiment.runs', q('mc-n').value);
    const scenario = getScenario();
    scenario.experiment.runs = runs;
    show.labels(scenario);
    const json = JSON.stringify(scenario);
    return { scenario: json, runs: 0, study: new Study(json, 0), total: runs };
  }

  // The card's words for the scenario: the robots' collision study (with the paper's counts) or
  // a state fixed at x̄.
  show.labels = (scenario) => {
    const robots = !!scenario.experiment.warning_t;
    for (const el of root.querySelectorAll('.robots')) el.hidden = !robots;
    for (const el of root.querySelectorAll('.fixed')) el.hidden = robots;
    for (const el of root.querySelectorAll('.mc-tc')) el.textContent = scenario.simulate.condition.t;
    for (const el of root.querySelectorAll('.mc-x')) el.textContent = scenario.simulate.condition.x.join(', ');
    if (robots) for (const el of root.querySelectorAll('.mc-tw')) el.textContent = `${scenario.experiment.warning_t} (τ = ${scenario.scf?.tau ?? 0})`;
  };

  const runner = studyRunner({
    go: q('mc-go'), cancel: q('mc-cancel'), bar: q('mc-progress'), status: q('mc-status'), err: q('mc-err'),
    busy: setBusy, start, show, runs: (c) => c.runs_done,
    perRun: (ms, k) => `${(1000 * ms / k).toFixed(1)} µs`, cancelWall: false,
  });

  // A new scenario: stop a run and clear counts that belong to the old one.
  return function reset(scenario) {
    runner.reset();
    if (scenario) show.labels(scenario);
    for (const id of ['mc-kf-in', 'mc-scf-in', 'mc-kf-w', 'mc-scf-w']) q(id).textContent = '–';
    q('mc-range').textContent = '';
  };
}
