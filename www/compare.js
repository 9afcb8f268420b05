// The compare panel (method "compare"): controls → Scenario JSON → a run in the compute worker →
// one figure drawn by the core (view {"panel": "compare", "hide": [methods]}) and the table of the
// report (report.compare: each method's row and its set at t). The time t is a time cursor
// (cursor.js): the worker computes every method's set at each t once, so moving t only redraws.
// The toggles only redraw (the view's `hide`). A click on the figure places the true state; the
// study counts, on every core (studypool.js), how often each method's set holds it; the core
// gives each count's band and verdict. No estimation happens here.
import { Study } from './pkg/confset.js';
import { mountPanel } from './panel.js';
import { Figure } from './figure.js';
import { studyRunner } from './chunked.js';
import { parseNumber, parseVector, wholeNumber } from './parse.js';
import { withScripts, verdict, sub, escapeHtml } from './richtext.js';
import { fmt3 as fmt, int } from './format.js';
import { PANELS } from './registry.js';
import { timeOf } from './cursor.js';

const pct = (p) => `${Number((100 * p).toFixed(1))} %`;
const LAWS = { gaussian: 'Gaussian', uniform: 'Uniform', truncated: 'Truncated Gaussian' };
// Each method's name in the table, from its panel's descriptor.
const NAMES = Object.fromEntries(PANELS.flatMap((d) => Object.entries(d.names || {})));
const richText = (t) => withScripts(t, (w) => w.replace(/(\p{L}[\u0300-\u036f]?)_([\p{L}\d]+)/gu, '$1<sub>$2</sub>'));

// The custom mode is one more "preset" whose model comes from the text boxes.
const CUSTOM_PRESET = {
  name: 'custom',
  description: 'Your own F, G, H (any number of states: one draws intervals side by side, three or more the plane of compare.plane, [0, 1] by default): every method runs on the same simulated record, with its parameters derived from σ_v², σ_w² and the noise law.',
  scenario: {
    method: 'compare', title: 'Custom model',
    model: { F: [[0.9, 0.2], [-0.1, 0.8]], G: [[1], [0.5]], H: [[1, 0]], sigma_v2: 0.01, sigma_w2: 0.01 },
    simulate: { steps: 30, seed: 1 },
    alpha: 0.9,
    compare: { noise: 'gaussian', target: 'predict', window: 10, study: { x: [0, 0], runs: 200, seed: 1 } },
    notes: 'A stable two-state system with one noise input and one measured output.',
  },
};

// The figure hides the methods whose toggles are off; its read-out names the plane's axes.
class CompareFigure extends Figure {
  hide = [];

  zoom = 'auto';

  view() { return JSON.stringify({ panel: this.panel, time: this.time, hide: this.hide, zoom: this.zoom }); }
}

// ----- controls ⇄ scenario -----
function load(p, s) {
  const { ui } = p;
  const c = s.compare;
  ui.noise.value = c.noise || 'gaussian';
  ui.target.value = c.target || 'predict';
  ui.k.value = c.bound_sigmas ?? 3;
  ui.window.value = c.window ?? 10;
  ui.scale.value = c.bound_scale ?? 1;
  ui.sv.value = s.model.sigma_v2 ?? '';
  ui.sw.value = s.model.sigma_w2 ?? '';
  ui.alpha.value = s.alpha ?? 0.95;
  ui.seed.value = s.simulate?.seed ?? 0;
  const steps = s.simulate?.steps ?? s.data?.y?.length ?? 2;
  ui.time.min = '2';
  ui.time.max = String(steps);
  ui['time-max'].textContent = String(steps);
  ui.time.value = String(c.time ?? steps);
  const cond = s.simulate?.condition;
  ui.fix.checked = !!cond;
  ui.xbar.value = (cond?.x || c.study?.x || []).join(' ');
  // The time of the fixed state stays where it was placed: the time slider only redraws the
  // record drawn given it, so a link or a download gives the same record.
  ui.ct.value = cond?.t ?? (Number(ui.time.value) + (c.target === 'filter' ? 0 : 1));
  if (c.study?.runs) ui.runs.value = c.study.runs;
  // Counts and their wording belong to the scenario they were counted on.
  p.counts = null;
  p.studyHow ??= ui['study-how'].textContent;
  ui['study-how'].textContent = p.studyHow;
  ui['study-truth'].textContent = '';
  showInputs(p);
}

function showInputs({ ui }) {
  ui['time-out'].textContent = `= ${ui.time.value}`;
  ui['scale-out'].textContent = `× ${Number(ui.scale.value).toFixed(2)}`;
}

function build(p, s) {
  const { ui } = p;
  if (p.isCustom()) Object.assign(s.model, p.model());
  const c = s.compare;
  c.noise = ui.noise.value;
  c.target = ui.target.value;
  c.bound_sigmas = parseNumber('compare.bound_sigmas', ui.k.value);
  c.window = wholeNumber('compare.window', ui.window.value);
  c.bound_scale = parseNumber('compare.bound_scale', ui.scale.value);
  c.time = wholeNumber('compare.time', ui.time.value);
  if (s.model.G) {
    s.model.sigma_v2 = parseNumber('model.sigma_v2', ui.sv.value);
    s.model.sigma_w2 = parseNumber('model.sigma_w2', ui.sw.value);
  }
  s.alpha = parseNumber('alpha', ui.alpha.value);
  const x = ui.xbar.value.trim() ? parseVector('simulate.condition.x', ui.xbar.value) : null;
  if (s.simulate) {
    s.simulate.seed = wholeNumber('simulate.seed', ui.seed.value);
    // The record drawn given the true target state: Gaussian noise only (the core says so
    // otherwise, next to the checkbox).
    if (ui.fix.checked && x) s.simulate.condition = { t: wholeNumber('simulate.condition.t', ui.ct.value), x };
    else delete s.simulate.condition;
  }
  if (x) c.study = { ...(c.study || {}), x };
  c.study = { seed: 1, ...(c.study || {}), runs: wholeNumber('compare.study.runs', ui.runs.value) };
  if (!c.study.x) delete c.study;
}

// ----- the table: each method's row, its set at t, and the study's counts -----
function showNumbers(p) {
  const { ui, st } = p;
  const c = st.report.compare;
  const at = c.at;
  const when = c.target === 'predict' ? `x${sub(at.target_time)} predicted from y₁ … y${sub(at.t)}` : `x${sub(at.target_time)} from y₁ … y${sub(at.t)}`;
  ui['num-title'].textContent = `Every method, for ${when}`;
  const counts = p.counts && p.counts.t === at.t ? p.counts : null;
  // n = 1: each set is an interval, its measure a length.
  const measure = st.report.plot.length === 1 ? 'length' : 'area';
  const head = ['method', 'promises', 'assumes', measure, `holds x${sub(at.target_time)}`, 'time',
    ...(counts ? ['holds x̄ (runs with a set)', 'no set', '99.9 % band', 'verdict'] : [])];
  const rows = c.rows.map((row, i) => {
    const set = at.sets[i];
    const assume = `${richText(row.assumes)}${row.met ? ' <b class="good">✓ met</b>' : `<br><b class="warn">✗ ${richText(row.violated || 'violated')}</b>`}`;
    const level = row.level == null ? '' : ` <span class="nw">(${row.at_least ? '≥ ' : ''}${pct(row.level)})</span>`;
    // An empty set (the data contradict the method's bounds) holds nothing; no set is no set.
    const area = set.set ? (set.area == null ? 'unbounded' : fmt(set.area)) : `<span class="warn">${set.empty ? 'empty set' : 'no set'}</span>`;
    // No set is neither a hit nor a miss: the core's reason, and what would give one.
    const why = `${escapeHtml(set.reason || '')}${set.remedy ? `<br><b>a set needs:</b> ${escapeHtml(set.remedy)}` : ''}`;
    const holds = set.set ? verdict(set.holds, 'yes', 'no')
      : `${set.empty && set.holds != null ? `${verdict(set.holds, 'yes', 'no')}<br>` : ''}<span class="hint">${why}</span>`;
    const time = set.seconds == null ? '–' : `${(1000 * set.seconds).toFixed(1)} ms`;
    const open = set.scenario ? `<br><button type="button" class="open-panel" data-i="${i}" title="the same scenario and data in the method's own panel">open in its panel</button>` : '';
    const cells = [`<b>${NAMES[row.method] || escapeHtml(row.method)}</b>${set.note ? `<br><span class="hint">${richText(set.note)}</span>` : ''}${open}`,
      `${escapeHtml(row.promise)}${level}`, assume, area, holds, time];
    if (counts) {
      // The counts, band and verdict are the core's (over the runs with a set); the page only
      // colours by the core's standing.
      const k = counts.methods.find((m) => m.method === row.method);
      const tone = { kept: 'good', broken: 'warn', does_not_apply: 'hint', no_promise: 'hint' };
      const noSet = k && k.no_set > 0
        ? `${int(k.no_set)}${k.no_set_reason ? `<br><span class="hint">${escapeHtml(k.no_set_reason)}${k.no_set_remedy ? `<br><b>a set needs:</b> ${escapeHtml(k.no_set_remedy)}` : ''}</span>` : ''}`
        : (k ? '0' : '–');
      cells.push(k ? `${int(k.holds)} / ${int(k.with_set)}` : '–',
        noSet,
        k?.band ? `[${int(k.band[0])}, ${int(k.band[1])}]` : '–',
        k ? `<span class="${tone[k.standing] || 'hint'}">${escapeHtml(k.verdict)}</span>` : '–');
    }
    // data-label: on a phone the rows stack, and each value says its column (style.css).
    return `<tr>${cells.map((v, j) => (j === 0 ? `<th>${v}</th>` : `<td data-label="${escapeHtml(head[j])}">${v}</td>`)).join('')}</tr>`;
  });
  ui.numbers.innerHTML = `<div class="table-scroll"><table class="est compare-table"><thead><tr>${head.map((h) => `<th>${h}</th>`).join('')}</tr></thead>`
    + `<tbody>${rows.join('')}</tbody></table></div>`
    + `<p class="hint">${LAWS[c.noise] || escapeHtml(c.noise)} noise, σ<sub>v</sub> = ${fmt(c.sigma_v)}, σ<sub>w</sub> = ${fmt(c.sigma_w)}; bounds given to the bounded methods: b<sub>v</sub> = ${fmt(c.bound_v)}, b<sub>w</sub> = ${fmt(c.bound_w)}`
    + `${at.truth ? `; true x${sub(at.target_time)} = (${at.truth.map(fmt).join(', ')})` : '; your data: no truth'}.</p>`
    + (st.report.warnings || []).map((w) => `<p class="hint warn">${escapeHtml(w)}</p>`).join('');
  // Whether the bounds are below the noise's is the core's verdict (the rows' `violated`).
  const tight = c.rows.map((r) => r.violated).find((v) => /bounds are/.test(v || ''));
  ui['bounds-out'].innerHTML = `b<sub>v</sub> = ${fmt(c.bound_v)}, b<sub>w</sub> = ${fmt(c.bound_w)}${tight ? ` <b class="warn">${richText(tight)}</b>` : ''}`;
  ui['time-min'].textContent = String(c.first);
}

// ----- placing the true state with a click -----
function placeTruth(p, e) {
  const { ui, st } = p;
  const figure = p.figures[0];
  const at = figure.frame && st.report ? figure.locate(e.offsetX, e.offsetY) : null;
  if (!at) return;
  const span = Math.max(Math.abs(at.chart.x_range[1] - at.chart.x_range[0]), Math.abs(at.chart.y_range[1] - at.chart.y_range[0]));
  const digits = Math.max(0, 3 - Math.floor(Math.log10(span)));
  // The click gives the plane's components (one for n = 1, whose rows are methods); the
  // state's other components stay as they were (the simulated truth's at first).
  const { plot, n } = st.report;
  const c = st.report.compare;
  const before = ui.xbar.value.trim().split(/[\s,]+/).map(Number);
  const x = before.length === n && before.every(Number.isFinite)
    ? before : (c.x_true?.[c.at.target_time - 1] || new Array(n).fill(0)).slice();
  plot.forEach((k, i) => { x[k] = i === 0 ? at.x : at.y; });
  ui.xbar.value = x.map((v) => +v.toFixed(digits)).join(' ');
  // The state drawn is the target of the time shown.
  ui.ct.value = String(st.report.compare.at.target_time);
  // Gaussian noise: the record itself is drawn given the state (the picture shows it there).
  ui.fix.checked = ui.noise.value === 'gaussian' && !!st.scenario?.simulate;
  p.schedule('compute');
}

// ----- the study -----
function startStudy({ ui, st }) {
  if (!st.report) throw new Error('no valid scenario to count');
  const s = JSON.parse(JSON.stringify(st.scenario));
  // The whole true state (the simulated one at the target time when none was placed).
  const c = st.report.compare;
  const x = s.compare.study?.x || c.x_true?.[c.at.target_time - 1];
  if (!x) throw { field: 'compare.study.x', message: 'the study needs a true state: click the figure to place one' };
  if (!s.simulate) throw { field: 'data', message: 'the study draws new records: it needs a simulated scenario, not your data' };
  const total = wholeNumber('compare.study.runs', ui.runs.value);
  s.compare.study = { x, runs: total, seed: s.compare.study?.seed ?? 1 };
  const json = JSON.stringify(s);
  ui['study-truth'].textContent = `at x̄ = (${x.map(fmt).join(', ')}), t = ${s.compare.time}`;
  return { scenario: json, runs: 0, study: new Study(json, 0), total };
}

function showStudy(p, c) {
  p.counts = c;
  p.ui['study-how'].textContent = c.conditioning;
  if (p.st.report) showNumbers(p);
}

export const mountCompare = async (root, presets) => mountPanel(root, {
  presets,
  custom: CUSTOM_PRESET,
  prefix: 'c-',
  busy: 'compareBusy',
  Figure: CompareFigure,
  model: ['F', 'G', 'H'],
  prose: richText,
  ids: ['time-out', 'time-min', 'time-max', 'scale-out', 'bounds-out', 'num-title', 'toggles',
    'runs', 'go', 'cancel', 'progress', 'status', 'err', 'study-truth', 'study-how'],
  compute: ['noise', 'target', 'k', 'window', 'scale', 'sv', 'sw', 'alpha', 'seed', 'fix', 'xbar', 'ct', 'm-F', 'm-G', 'm-H'],
  redraw: ['time'],
  cursor: timeOf('compare'),
  input: (p) => showInputs(p),
  stem: ({ st, ui }) => `${st.preset.name}-t${ui.time.value}`,
  init(p) {
    const { ui } = p;
    p.study = studyRunner({
      go: ui.go, cancel: ui.cancel, bar: ui.progress, status: ui.status, err: ui.err,
      busy: p.setBusy, start: () => startStudy(p), show: (c) => showStudy(p, c),
      perRun: (ms, runs) => `${(ms / Math.max(1, runs)).toFixed(1)} ms`,
    });
    p.figures[0].canvas.addEventListener('click', (e) => placeTruth(p, e));
    // A method's own scenario on this record, opened in its panel (the shell loads it there as a
    // scenario file): the same set, with everything that panel shows.
    ui.numbers.addEventListener('click', (e) => {
      const b = e.target.closest('button.open-panel');
      const set = b && p.st.report?.compare.at.sets[Number(b.dataset.i)];
      if (!set?.scenario) return;
      document.dispatchEvent(new CustomEvent('confset:open-scenario', {
        detail: { scenario: set.scenario, name: `compare-${set.method}-t${p.st.report.compare.at.t}.json` },
      }));
    });
    // One toggle per method a compare draws, from the registry's names (a new method needs no
    // markup here); they only redraw: the figure leaves the hidden methods out.
    const zoom = ui.toggles.querySelector('label.zoom');
    for (const [m, name] of Object.entries(NAMES)) {
      const label = document.createElement('label');
      label.innerHTML = `<input type="checkbox" id="c-show-${m}" data-method="${m}" checked> ${escapeHtml(name)}`;
      zoom.before(label);
    }
    ui.toggles.addEventListener('change', () => {
      p.figures[0].hide = [...ui.toggles.querySelectorAll('input[data-method]')].filter((b) => !b.checked).map((b) => b.dataset.method);
      p.figures[0].zoom = ui.toggles.querySelector('#c-zoom').value;
      p.schedule('redraw');
    });
  },
  leave(p) { p.study.reset(); p.counts = null; },
  after(p) {
    // A new scenario: counts of the old one are stale.
    if (p.counts && JSON.stringify(p.counts.x) !== JSON.stringify(p.st.scenario.compare.study?.x)) p.counts = null;
  },
  load,
  build,
  draw(p) {
    showInputs(p);
    showNumbers(p);
  },
});
