// The uniform-innovation panel: controls → Scenario JSON (method "uniform_lp") → a run in the compute worker →
// four figures drawn by the core (views {"panel": "ustates" | "uoutput" | "uparams" | "upolygon"})
// and the numbers of the report (report.uniform). The time cursor (cursor.js) marks t in every
// figure: the report keeps the window, the optimal face and the consistent-state polygon of one
// time (its `at`); moving t draws the kept report with the detail of t, which the compute worker
// computes once per time (the scenario's uniform.time follows t, so a run, a download or a link
// gives the same picture). The window ∂ changes the estimates: it runs the scenario again. No
// estimation happens here: the page edits the preset's scenario and shows what the core reports.
import { mountPanel } from './panel.js';
import { Figure } from './figure.js';
import { parseMatrix, parseVector, parseNumber, matrixText, wholeNumber } from './parse.js';
import { withScripts, verdict, sub, escapeHtml } from './richtext.js';
import { fmt, vec } from './format.js';
import { timeOf, recordTime } from './cursor.js';

const mat = (m) => (Array.isArray(m) && m.length && m[0].length
  ? `[${m.map((r) => r.map(fmt).join(' ')).join('; ')}]` : '–');
const METHOD = { states: 'Θ known', parameters: 'states known (3.4)', swapping: 'swapping (4.1)', expansion: 'expansion (4.2)' };

// The custom mode is one more "preset" whose model comes from the text boxes: an observable
// model (C·A is not parallel to C), so the optimal face collapses where the paper's is long.
const CUSTOM_PRESET = {
  name: 'custom',
  description: 'Your own LU model: x_t = A x_{t−1} + B u_t + e^x_t, y_t = C x_t + D u_t + e^y_t with uniform innovations; every change is validated and run at once.',
  scenario: {
    method: 'uniform_lp', title: 'Uniform innovations: custom LU model',
    model: { F: [[0.8, 0.3], [-0.3, 0.7]], H: [[1, 0]], B: [[1], [0.5]] },
    simulate: { steps: 120, seed: 1 },
    uniform: {
      D: [[0]], xr: [0.2, 0.2], yr: [0.2], u_half: 0.5, estimator: 'swapping', window: 5, prior_rel: 0.3,
      xr_max: [1, 1], yr_max: [1], x_bound: 5, plane: [0, 1], directions: 64,
    },
    notes: 'An observable model (C = [1 0], C·A = [0.8 0.3] is not parallel to C): two outputs fix the state, so the '
      + 'optimal face shrinks to (nearly) a point and the polygon closes without the prior box. Try C = [1 1] with '
      + 'A = [[1 0.5] [−0.5 0]] to get the paper’s non-observable strip back.',
  },
};

const richText = (t) => withScripts(t, (w) => w
  .replace(/\^([a-z])_([a-z])/g, '<sup>$1</sup><sub>$2</sub>')
  .replace(/(\p{L}[\u0300-\u036f]?)_([\p{L}\d]+)/gu, '$1<sub>$2</sub>'));

// The core draws every picture; the cursor read-out finds the chart (a figure may stack several)
// under the pointer. Time axes read whole samples.
class UniformFigure extends Figure {
  stacked = true;

  cursorText({ chart, x, y }) {
    const xs = this.panel === 'upolygon' ? fmt(x) : `${Math.round(x)}${recordTime(this.report, Math.round(x))}`;
    return `${chart.x_label || 'x'} = ${xs}, ${chart.y_label || 'y'} = ${fmt(y)}`;
  }
}

// ----- controls ⇄ scenario -----
// State dimension n and output dimension m the controls describe (0 while they do not parse).
function dims({ ui, st, isCustom }) {
  if (!isCustom()) return [st.preset.scenario.model.F.length, st.preset.scenario.model.H.length];
  const rows = (k) => { try { return parseMatrix(`model.${k}`, ui[`m-${k}`].value).length; } catch { return 0; } };
  return [rows('F'), rows('H')];
}
const half = (v) => (Array.isArray(v) ? (v.every((x) => x === v[0]) ? String(v[0]) : v.join(' ')) : '');

function load(p, s) {
  const { ui } = p;
  const u = s.uniform;
  ui.estimator.value = u.estimator || 'swapping';
  setWindow(p, u.window ?? 5);
  ui.xr.value = half(u.xr);
  ui.yr.value = half(u.yr);
  ui.uhalf.value = u.u_half ?? 0.5;
  ui.prior.value = +(100 * (u.prior_rel ?? 0.3)).toPrecision(6);
  ui.xrmax.value = half(u.xr_max || [1]);
  ui.yrmax.value = half(u.yr_max || [1]);
  // Empty: the core derives the bound from the record (its report says which).
  ui.xbound.value = u.x_bound ?? '';
  ui.seed.value = s.simulate?.seed ?? 0;
  ui.steps.value = s.simulate ? s.simulate.steps : s.data.y.length;
  timeRange(p, true);
}

function setWindow({ ui }, v) {
  ui.window.value = String(v);
  ui['window-range'].value = String(v);
  ui['window-out'].textContent = `= ${v}`;
}

// The cursor spans 1..T (what the steps field says; the core checks). `toEnd`: put it at T.
// A cursor at the end stays at the end when T changes.
function timeRange(p, toEnd = false) {
  const { ui } = p;
  const steps = Number(ui.steps.value);
  const atEnd = toEnd || Number(ui.time.value) === Number(ui.time.max);
  if (Number.isSafeInteger(steps) && steps >= 2) {
    ui.time.max = String(steps);
    ui['time-max'].textContent = String(steps);
    if (atEnd) ui.time.value = String(steps);
  }
  showTime(p);
}

function showTime({ ui, st }) {
  const u = st.report?.uniform;
  const t = Number(ui.time.value);
  ui['time-out'].textContent = `= ${t}${recordTime(st.report, t)}`;
  ui['time-window'].textContent = u && u.at.time === t ? `window ${u.at.first} … ${t}: polygon, face ranges` : '';
}

// Half-widths: one number stands for every component.
function halfWidths(field, text, len) {
  const v = parseVector(field, text);
  return v.length === 1 && len > 1 ? Array(len).fill(v[0]) : v;
}

// The scenario the controls describe: the preset's, with fields changed.
function build(p, s) {
  const { ui } = p;
  const u = s.uniform;
  if (p.isCustom()) {
    Object.assign(s.model, p.model());
    u.D = parseMatrix('uniform.D', ui['m-D'].value);
  }
  const [n, m] = dims(p);
  u.estimator = ui.estimator.value;
  u.window = wholeNumber('uniform.window', ui.window.value);
  // The true half-widths only simulate: on measured data (a file, the compare view's "open in
  // its panel") the boxes may be empty and the core needs none.
  if (s.simulate) {
    u.xr = halfWidths('uniform.xr', ui.xr.value, n);
    u.yr = halfWidths('uniform.yr', ui.yr.value, m);
  } else {
    delete u.xr;
    delete u.yr;
  }
  u.u_half = parseNumber('uniform.u_half', ui.uhalf.value);
  u.prior_rel = parseNumber('uniform.prior_rel', ui.prior.value) / 100;
  u.xr_max = halfWidths('uniform.xr_max', ui.xrmax.value, n);
  u.yr_max = halfWidths('uniform.yr_max', ui.yrmax.value, m);
  if (ui.xbound.value.trim() === '') delete u.x_bound;
  else u.x_bound = parseNumber('uniform.x_bound', ui.xbound.value);
  // A scalar state has no polygon, hence no plane (the polygon card then says why).
  if (n === 1) delete u.plane;
  if (s.simulate) {
    s.simulate.seed = wholeNumber('simulate.seed', ui.seed.value);
    s.simulate.steps = wholeNumber('simulate.steps', ui.steps.value);
  }
  u.time = wholeNumber('uniform.time', ui.time.value);
}

// ----- numbers from the report -----
// The numbers at time t: the report's detail of t once it is here (until then, the estimates
// the report holds for every time, and the window's numbers marked as being computed).
function showNumbers({ ui, st }, t) {
  const u = st.report.uniform;
  const at = u.at.time === t ? u.at : null;
  const n = u.n;
  const step = u.steps[t - 1];
  const truth = u.x_true ? u.x_true[t] : null;
  const pending = '… <span class="hint">(being computed)</span>';
  ui['num-title'].textContent = `At the time cursor t = ${t}${recordTime(st.report, t)}: window ${at ? `${at.first} … ${t} ` : ''}(∂ = ${u.window}), ${METHOD[u.estimator] || u.estimator}`;
  const rows = [];
  const row = (a, b) => rows.push(`<tr><th>${a}</th><td>${b}</td></tr>`);
  row(`true x<sub>${t}</sub>`, truth ? vec(truth) : '– (data given)');
  row('LP estimate', vec(step?.x));
  row('Kalman filter', u.kf ? `${vec(u.kf[t - 1])} <span class="hint">(true Θ, variances r²/3)</span>` : '– (data given: no true Θ)');
  const faces = at?.face_lo[0].map((lo, i) => `<span class="nw">x${sub(i + 1)} ∈ [${fmt(lo)}, ${fmt(at.face_hi[0][i])}]</span>`);
  row(`optimal face of x<sub>${t}</sub>`, at ? faces.join(' ') : pending);
  const guaranteed = at?.polygon_theta_true;
  if (!at) {
    row('objective Σx̂<sub>r</sub> + Σŷ<sub>r</sub>', pending);
  } else if (at.true_objective != null) {
    const below = at.objective <= at.true_objective * (1 + 1e-9) + 1e-12;
    row('objective Σx̂<sub>r</sub> + Σŷ<sub>r</sub>', `${fmt(at.objective)} vs the truth’s ${fmt(at.true_objective)} ${below
      ? '<b class="good">✓ the optimum is never above the truth’s</b>'
      : `<b class="warn">✗ above the truth’s</b>${guaranteed ? '' : ' <span class="hint">(Θ̂ ≠ Θ: the truth need not be feasible)</span>'}`}`);
  } else {
    row('objective Σx̂<sub>r</sub> + Σŷ<sub>r</sub>', fmt(at.objective));
  }
  if (!at) {
    row('polygon', pending);
  } else if (at.polygon) {
    const exact = at.polygon.exact ? `exact, ${at.polygon.calls} LPs` : `budget spent: within ${fmt(at.polygon.gap)}`;
    row('truth in polygon', `${verdict(at.truth_in_polygon, 'inside', 'outside')} <span class="hint">${guaranteed
      ? '(polygon with the true Θ: it must hold the truth)' : `(polygon with the estimated Θ̂<sub>${t}</sub>, not the true Θ: no guarantee)`}; ${exact}</span>`);
  } else {
    row('polygon', `– <span class="hint">(${escapeHtml(at.polygon_absent || 'none')})</span>`);
  }
  ui.numbers.innerHTML = `<table class="est"><tbody>${rows.join('')}</tbody></table>`;

  // Over the run.
  const last = u.steps[u.steps.length - 1];
  const r = [];
  const rrow = (a, b) => r.push(`<tr><th>${a}</th><td>${b}</td></tr>`);
  const from = Math.min(u.window, u.steps.length);
  if (u.rms_lp != null && u.rms_kf != null) {
    const lpWins = u.rms_lp < u.rms_kf;
    rrow(`RMS state error <span class="hint">t = ${from} … ${u.steps.length}</span>`, `LP ${fmt(u.rms_lp)} vs KF ${fmt(u.rms_kf)} — ${lpWins
      ? '<span class="good">the hard bounds help here</span>'
      : '<span class="warn">the hard bounds hurt here</span> <span class="hint">(the LP picks a point of a face the data leave open; the KF averages)</span>'}`);
  }
  rrow('RMS prediction error', `${fmt(u.rms_prediction)} <span class="hint">(y<sub>t</sub> − ŷ<sub>t|t−1</sub>)</span>`);
  const [A, B, C] = u.theta_true || [];
  const theta = (name, est, tru) => rrow(`final ${name}̂`, `${mat(est)}${tru ? ` <span class="hint">true</span> ${mat(tru)}` : ''}`);
  theta('A', last.a, A);
  theta('B', last.b, B);
  theta('C', last.c, C);
  rrow('final x̂<sub>r</sub>, ŷ<sub>r</sub>', `${vec(last.xr)}, ${vec(last.yr)}${u.xr_true ? ` <span class="hint">true</span> ${vec(u.xr_true)}, ${vec(u.yr_true)}` : ''}`);
  rrow('half-width bounds extended', `${u.extended} ${u.extended === 1 ? 'time' : 'times'}${u.extended ? ' <span class="hint">(doubled where the LP was infeasible)</span>' : ''}`);
  ui['run-numbers'].innerHTML = `<table class="est"><tbody>${r.join('')}</tbody></table>`
    + (u.estimator === 'states' ? '<p class="hint">Θ known: the final Θ̂ is the true Θ.</p>' : '')
    + (n === 2 || !u.plane ? '' : `<p class="hint">The polygon shows x${sub(u.plane[0] + 1)}, x${sub(u.plane[1] + 1)} of the ${n} state components.</p>`);
}

export const mountUniform = async (root, presets) => mountPanel(root, {
  presets,
  custom: CUSTOM_PRESET,
  prefix: 'u-',
  busy: 'uniformBusy',
  Figure: UniformFigure,
  model: ['F', 'H', 'B'],
  prose: richText,
  ids: ['time-out', 'time-max', 'time-window', 'window-out', 'run-numbers', 'num-title'],
  compute: ['m-F', 'm-H', 'm-B', 'm-D', 'estimator', 'xr', 'yr', 'uhalf', 'prior', 'xrmax', 'yrmax', 'xbound', 'seed',
    'steps', 'window-range', 'window'],
  redraw: ['time'],
  cursor: timeOf('uniform'),
  input(p, id) {
    const { ui } = p;
    if (id === 'steps') timeRange(p);
    if (id === 'time') showTime(p);
    if (id === 'window-range') setWindow(p, ui['window-range'].value);
    if (id === 'window') {
      const v = Number(ui.window.value);
      // The slider spans the core's range too (the shell's limits); the box may hold what the
      // core will refuse, with its message.
      if (Number.isSafeInteger(v) && v >= Number(ui['window-range'].min) && v <= Number(ui['window-range'].max)) ui['window-range'].value = String(v);
      ui['window-out'].textContent = `= ${ui.window.value}`;
    }
  },
  stem({ st, cursorTime }) {
    const u = st.report?.uniform;
    return `${st.preset.name}-${u ? `${u.estimator}-w${u.window}-t${cursorTime()}` : 'uniform'}`;
  },
  init: ({ ui }) => { ui['m-D'].value = matrixText(CUSTOM_PRESET.scenario.uniform.D); },
  load,
  build,
  draw(p, t) {
    showTime(p);
    showNumbers(p, t);
  },
});
