// The conformal panel (method "conformal": split conformal prediction, Vovk et al.; adaptive
// conformal inference, Gibbs & Candès): controls → Scenario JSON → a run in the compute worker →
// two figures drawn by the core (views {"panel": "conformalset" | "aciband"}) and the numbers of
// the report (report.conformal). The study runs fresh runs on every core (studypool.js), each
// with its own N calibration runs, and counts how often the conformal and the Kalman regions
// held the state; the bands it is compared with are the core's (the study's result).
// No estimation and no verdict happen here: the page edits the preset's scenario and shows what
// the core says (the booleans inside/kf_inside, the counts and their bands).
import { Study } from './pkg/confset.js';
import { mountPanel } from './panel.js';
import { Figure } from './figure.js';
import { studyRunner, busyFlag } from './chunked.js';
import { parseNumber, wholeNumber } from './parse.js';
import { withScripts, verdict, sub } from './richtext.js';
import { fmt, vec, int } from './format.js';
import { recordTime } from './cursor.js';

// The custom mode is one more "preset" whose model comes from the text boxes.
const CUSTOM_PRESET = {
  name: 'custom',
  description: 'Your own F, H, V, W: the Kalman filter assumes them, the simulations draw from them with the noise law chosen below; every change is validated and run at once.',
  scenario: {
    method: 'conformal', title: 'Custom model',
    model: { F: [[0.9, 0.1], [0, 0.8]], H: [[1, 0]], V: [[0.2, 0], [0, 0.2]], W: [[1]] },
    simulate: { steps: 100, seed: 1 }, alpha: 0.9, time: 30,
    conformal: { calibration: 199, seed: 1000, noise: 'gaussian', nu: 3, gamma: 0.01, study: { runs: 1000, seed: 77 } },
    notes: 'A stable 2-state system with one measured output, its noise covariances V and W known to the filter. The conformal '
      + 'region is the Kalman ellipse with its radius calibrated on N simulated runs; ACI runs on the one-step predictions of y.',
  },
};

const richText = (t) => withScripts(t, (w) => w.replace(/(\p{L}[\u0300-\u036f]?)_([\p{L}\d]+)/gu, '$1<sub>$2</sub>'));

// A probability as a percentage with what the number carries (0.905 → "90.5 %", 0.9 → "90 %").
const pct = (v) => (Number.isFinite(v) ? `${Number((100 * v).toPrecision(4))} %` : '–');

class ConformalFigure extends Figure {
  stacked = true;

  cursorText({ chart, x, y }) {
    const time = this.panel === 'aciband';
    return `${time ? `t = ${Math.round(x)}` : `${chart.x_label || 'x'} = ${fmt(x)}`}, ${chart.y_label || 'y'} = ${fmt(y)}`;
  }
}

// ----- controls ⇄ scenario -----
function load(p, s) {
  const { ui } = p;
  const c = s.conformal || {};
  ui.alpha.value = s.alpha;
  ui.calibration.value = c.calibration ?? 199;
  ui.noise.value = c.noise || 'gaussian';
  ui.nu.value = c.nu ?? 3;
  ui.gamma.value = c.gamma ?? 0.01;
  const steps = s.simulate?.steps ?? s.data?.y?.length ?? 1;
  ui.steps.value = steps;
  ui.seed.value = s.simulate?.seed ?? 0;
  ui.time.max = String(steps);
  ui.time.value = String(s.time ?? steps);
  ui.runs.value = c.study?.runs ?? 1000;
  // The study simulates from the model: on measured data it would say nothing about them.
  ui.study.hidden = !s.simulate;
  p.resetStudy?.();
  showControls(p);
}

// What the controls show at once: the level, the time, the law's row (ν only for Student-t).
function showControls({ ui, st }) {
  ui['alpha-out'].textContent = Number(ui.alpha.value).toFixed(3);
  ui['time-out'].textContent = `= ${ui.time.value}${recordTime(st.report, Number(ui.time.value))}`;
  const t = ui.noise.value === 'student_t';
  ui['nu-row'].hidden = !t;
  ui['law-out'].textContent = t
    ? 'Student-t noise scaled to the model’s V and W: the covariances the filter assumes, with heavier tails.'
    : 'Gaussian noise with the model’s V and W: the law the filter assumes.';
}

function build(p, s) {
  const { ui } = p;
  if (p.isCustom()) s.model = p.model();
  s.alpha = Number(ui.alpha.value);
  const c = s.conformal = s.conformal || {};
  c.calibration = wholeNumber('conformal.calibration', ui.calibration.value);
  c.noise = ui.noise.value;
  // ν matters for the Student-t only; with the Gaussian the box is hidden and an unreadable
  // value in it keeps the scenario's.
  if (c.noise === 'student_t') c.nu = parseNumber('conformal.nu', ui.nu.value);
  else if (Number.isFinite(Number(ui.nu.value)) && ui.nu.value.trim() !== '') c.nu = Number(ui.nu.value);
  c.gamma = parseNumber('conformal.gamma', ui.gamma.value);
  s.time = wholeNumber('time', ui.time.value);
  if (s.simulate) {
    s.simulate.steps = wholeNumber('simulate.steps', ui.steps.value);
    s.simulate.seed = wholeNumber('simulate.seed', ui.seed.value);
  }
}

// ----- numbers from the report -----
function showNumbers({ ui, st }) {
  const r = st.report;
  const c = r.conformal;
  const a = c.aci;
  const x = (i) => `x${sub(i + 1)}`;
  ui['num-title'].textContent = `At t = ${c.time}${recordTime(r, c.time)}: level α = ${c.level}, ${c.calibration} calibration runs`;
  const rows = [];
  const row = (h, d) => rows.push(`<tr><th>${h}</th><td>${d}</td></tr>`);
  const hint = (t) => ` <span class="hint">(${t})</span>`;
  row('noise law', c.noise === 'student_t' ? `Student-t, ν = ${fmt(c.nu)}${hint('scaled to the model’s V, W')}` : 'Gaussian');
  row('radius²', `conformal <b>${fmt(c.radius2)}</b>${hint(`the k = ${c.rank}th smallest of N = ${c.calibration} scores`)}`
    + ` · χ²${sub(r.n)}(${c.level}) <b>${fmt(c.chi2_radius2)}</b>${hint('Kalman')}`);
  row('promise', `${pct(c.lower)} ≤ P ≤ ${pct(c.upper)}${hint(`k/(N + 1) = ${pct(c.exact)}: the chance a fresh run’s x${sub(c.time)} lies in the region, on average over runs`)}`);
  if (c.truth) {
    row(`true x${sub(c.time)}`, `${vec(c.truth)}${hint(`score ${fmt(c.truth_score)}`)}`);
  } else {
    row(`true x${sub(c.time)}`, `–${hint('measured data: no truth')}`);
  }
  row('truth in the regions', `conformal ${verdict(c.inside, 'inside', 'outside')} · Kalman ${verdict(c.kf_inside, 'inside', 'outside')}`);
  row(`ACI: coverage of y${r.q > 1 ? sub(1) : ''}`, `ACI <b>${pct(a.coverage)}</b> · Kalman <b>${pct(a.kf_coverage)}</b>`
    + `${hint(`over the ${int(a.covered_steps)} steps with an interval (${int(a.warmup)} warm-up steps apart), target ${pct(c.level)}, γ = ${fmt(a.gamma)}`)}`);
  const worst = (w) => (w ? `${pct(w[0])} from t = ${w[1]}` : '–');
  row(`worst ${a.window}-step window`, `ACI ${worst(a.worst)} · Kalman ${worst(a.kf_worst)}`);
  row('ACI’s bound', `|miss rate − ${fmt(a.miss)}| ≤ ${fmt(a.bound)}${hint('Gibbs & Candès, Prop. 4.1: on any record of this length')}`);
  if (r.plot?.length === 2 && r.n > 2) row('plane', `${x(r.plot[0])}, ${x(r.plot[1])}${hint('the regions projected')}`);
  ui.numbers.innerHTML = `<table class="est"><tbody>${rows.join('')}</tbody></table>`;
}

// ----- the study: fresh runs of the last good scenario -----
function startStudy(p) {
  const { ui, st } = p;
  if (!st.scenario) return null;
  const total = wholeNumber('runs', ui.runs.value);
  const json = JSON.stringify(st.scenario);
  const study = new Study(json, total);
  ui['s-result'].replaceChildren();
  return { scenario: json, runs: total, study, total, at: ` at t = ${st.scenario.time}` };
}

// The counts, their bands and the verdicts, all the core's (said once every run is counted).
function showStudy({ ui }, c, done) {
  const hint = (t) => ` <span class="hint">(${t})</span>`;
  const of = (k) => `${int(k)} / ${int(c.runs)}`;
  const band = ([lo, hi]) => `[${int(lo)}, ${int(hi)}]`;
  // The core's verdict (present once every run is counted).
  const said = (v) => (v ? ` — <b class="${v === 'in its band' ? 'good' : 'warn'}">${v}</b>` : '');
  const judged = done && c.verdict;
  const line = (name, k, b, v, what) => `<p>${name}: <b>${of(k)}</b> inside — band ${band(b)}${hint(what)}${judged ? said(v) : ''}</p>`;
  let html = line('conformal', c.inside, c.band, c.verdict, `99.9 % binomial band of ${int(c.total)} runs from level ${c.level} to the promise’s upper bound`)
    + line('Kalman', c.kf_inside, c.kf_band, c.kf_verdict, `99.9 % binomial band at level ${c.level}`);
  if (c.at) {
    html += `<p>at the fixed state ${vec(c.at)}: conformal <b>${of(c.fixed_inside)}</b>, Kalman <b>${of(c.fixed_kf_inside)}</b> inside`
      + `${hint('runs whose state at t is this one: neither promise is about a fixed state, so no band')}</p>`;
  }
  if (!judged && done === false) html += '<p class="hint">The bands are for the whole study: said once every run is counted.</p>';
  ui['s-result'].innerHTML = html;
}

export const mountConformal = async (root, presets) => mountPanel(root, {
  presets,
  custom: CUSTOM_PRESET,
  prefix: 'cf-',
  busy: 'conformalBusy',
  Figure: ConformalFigure,
  model: ['F', 'H', 'V', 'W'],
  prose: richText,
  ids: ['alpha-out', 'time-out', 'nu-row', 'law-out', 'num-title', 'runs', 'go', 'cancel', 'progress',
    's-status', 's-result', 's-err', 'study-at', 'study'],
  compute: ['alpha', 'time', 'calibration', 'gamma', 'noise', 'nu', 'steps', 'seed', 'm-F', 'm-H', 'm-V', 'm-W'],
  input: (p) => showControls(p),
  stem: ({ st }) => `${st.preset.name}-t${st.report?.conformal?.time ?? ''}`,
  init(p) {
    const { ui } = p;
    let runner = null;
    p.resetStudy = () => {
      runner?.reset();
      ui['s-result'].replaceChildren();
      ui.progress.value = 0;
    };
    runner = studyRunner({
      go: ui.go, cancel: ui.cancel, bar: ui.progress, status: ui['s-status'], err: ui['s-err'],
      busy: busyFlag('conformalStudyBusy'), start: () => startStudy(p), show: (c, done) => showStudy(p, c, done),
      perRun: (ms, runs) => `${(ms / Math.max(1, runs)).toFixed(2)} ms`,
    });
  },
  load,
  build,
  after(p) {
    const { ui, st } = p;
    // The target time spans the record the core accepted (a refused length leaves it alone, so
    // the time is not clamped by a value the core did not take).
    ui.time.max = String(st.report.y.length);
    // A study of another scenario is stale: its counts go.
    const text = JSON.stringify(st.scenario);
    if (p.studied !== text) { p.resetStudy(); p.studied = text; }
    const at = st.scenario.conformal?.study?.at;
    ui['study-at'].textContent = at ? `, and the same for runs whose state at t is fixed at (${at.join(', ')})` : '';
  },
  draw(p) {
    showControls(p);
    showNumbers(p);
  },
});
