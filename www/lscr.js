// The LSCR panel: controls → Scenario JSON (method "lscr") → a run in the panel's compute worker → the region figure
// (Session.draw, view {"panel":"region"}), the numbers of the report, and the coverage
// experiment (on every core: studypool.js) at a true state placed with a click. No estimation happens
// here: the page only edits the preset's scenario and shows what the core reports.
import { Study } from './pkg/confset.js';
import { mountPanel, clone } from './panel.js';
import { Figure } from './figure.js';
import { studyRunner } from './chunked.js';
import { parseVector, parseNumber, wholeNumber } from './parse.js';
import { sub, escapeHtml } from './richtext.js';
import { fmtFixed as fmt, vec as vecOf, int, noiseReadout } from './format.js';

const vec = (v) => vecOf(v, fmt);

const pct = (v) => `${+(100 * v).toFixed(2)} %`;

// The custom mode is one more "preset" whose model comes from the text boxes.
const CUSTOM_PRESET = {
  name: 'custom',
  description: 'Your own F, H, G: xₜ₊₁ = F xₜ + G vₜ, yₜ = H xₜ + wₜ with scalar noises; every change is validated and run at once.',
  scenario: {
    method: 'lscr', title: 'Custom model',
    model: { F: [[0.8, 0.3], [-0.3, 0.8]], H: [[1, 1]], G: [[1], [0.5]], sigma_v2: 0.01, sigma_w2: 0.01 },
    simulate: { steps: 40, seed: 2 }, plot: [0, 1],
    lscr: { estimate: 'predict', M: 80, q: 2, construction: 'random', seed: 1 },
    notes: 'A damped rotation driven by one scalar noise, measured through H = [1 1]. F must be stable (LSCR needs a '
      + 'stationary state); H has one row (a scalar measurement) and G one column. The variances only simulate the '
      + 'data and give the BLUE and Kalman ellipses: the LSCR region does not use them.',
  },
};

// The region figure: the core draws the LSCR picture (view {"panel":"region"}); the returned
// frame maps canvas pixels to state coordinates for the cursor and the click.
class RegionFigure extends Figure {
  view() { return JSON.stringify({ panel: 'region' }); }
}

// ----- controls ⇄ scenario -----
function load(p, s) {
  const { ui } = p;
  const l = s.lscr;
  ui.notes.textContent = (typeof s.notes === 'string' ? s.notes : '').replace(/\s{2,}/g, ' ');
  ui.sv.value = s.model.sigma_v2;
  ui.sw.value = s.model.sigma_w2;
  ui.t.value = s.simulate ? s.simulate.steps : s.data.y.length;
  ui.dseed.value = s.simulate?.seed ?? 0;
  ui.estimate.value = l.estimate || 'predict';
  ui.index.value = l.index ?? '';
  ui.mode.value = l.level != null && l.M == null ? 'level' : 'mq';
  ui.M.value = l.M ?? 80;
  ui.q.value = l.q ?? 2;
  ui.level.value = l.level ?? 0.9;
  ui.construction.value = l.construction || 'random';
  ui.seed.value = l.seed ?? 0;
  ui.fix.checked = !!s.simulate?.condition;
  ui.xbar.value = s.simulate?.condition ? s.simulate.condition.x.join(' ') : '';
  // The true noise of the simulated record (log₁₀ of its scales of the assumed σ_v², σ_w²).
  const tn = s.simulate?.true_noise;
  ui.tv.value = tn?.V ? Math.log10(tn.V) : 0;
  ui.tw.value = tn?.W ? Math.log10(tn.W) : 0;
  ui['true-group'].hidden = !s.simulate;
  updateVisibility(p);
}

function updateVisibility({ ui }) {
  const smooth = ui.estimate.value === 'smooth';
  ui['index-row'].hidden = !smooth;
  if (smooth && ui.index.value === '') ui.index.value = Math.max(1, Math.floor(Number(ui.t.value) / 2) || 1);
  ui['mq-row'].hidden = ui.mode.value !== 'mq';
  ui['level-row'].hidden = ui.mode.value !== 'level';
  ui['fix-opts'].hidden = !ui.fix.checked;
  ui['level-out'].textContent = pct(Number(ui.level.value));
  ui['tv-out'].textContent = (10 ** Number(ui.tv.value)).toFixed(2);
  ui['tw-out'].textContent = (10 ** Number(ui.tw.value)).toFixed(2);
  ui['noise-readout'].textContent = noiseReadout(trueScales(ui), ['σ_v²', 'σ_w²']);
}

// The true noise's scales of the assumed variances, as the sliders give them (1 at 0).
function trueScales(ui) {
  return [ui.tv, ui.tw].map((el) => (Number(el.value) === 0 ? 1 : Number((10 ** Number(el.value)).toPrecision(12))));
}

// The estimated time by the scenario contract (prediction t + 1, filtering t, smoothing i);
// checked against the report's lscr.time after the run.
function estimatedTime(s) {
  const t = s.simulate ? s.simulate.steps : s.data.y.length;
  return s.lscr.estimate === 'predict' ? t + 1 : s.lscr.estimate === 'filter' ? t : s.lscr.index;
}

// The scenario the controls describe: the preset's, with fields changed.
function build(p, s) {
  const { ui } = p;
  if (p.isCustom()) {
    Object.assign(s.model, p.model());
    const n = s.model.F.length;
    s.plot = n >= 2 ? [0, 1] : undefined;
  }
  s.model.sigma_v2 = parseNumber('model.sigma_v2', ui.sv.value);
  s.model.sigma_w2 = parseNumber('model.sigma_w2', ui.sw.value);
  if (s.simulate) {
    s.simulate.steps = wholeNumber('simulate.steps', ui.t.value);
    s.simulate.seed = wholeNumber('simulate.seed', ui.dseed.value);
    // The record's noise apart from the assumed σ_v², σ_w² (the core's simulate.true_noise).
    const [tv, tw] = trueScales(ui);
    if (tv === 1 && tw === 1) delete s.simulate.true_noise;
    else s.simulate.true_noise = { V: tv, W: tw };
  }
  const l = s.lscr;
  l.estimate = ui.estimate.value;
  if (l.estimate === 'smooth') l.index = wholeNumber('lscr.index', ui.index.value);
  else delete l.index;
  delete l.M; delete l.q; delete l.level;
  if (ui.mode.value === 'mq') {
    l.M = wholeNumber('lscr.M', ui.M.value);
    l.q = wholeNumber('lscr.q', ui.q.value);
  } else {
    l.level = Number(ui.level.value);
  }
  l.construction = ui.construction.value;
  l.seed = wholeNumber('lscr.seed', ui.seed.value);
  delete l.coverage;
  if (!s.simulate) {
    // the user's data: no truth to place
  } else if (ui.fix.checked) {
    s.simulate.condition = { t: estimatedTime(s), x: parseVector('simulate.condition.x', ui.xbar.value) };
  } else {
    delete s.simulate.condition;
  }
}

async function run(runInWorker, scenario) {
  let json = await runInWorker(scenario);
  const c = scenario.simulate?.condition;
  if (c) {
    const time = JSON.parse(json).lscr.time;
    if (time !== c.t) { // the truth belongs at the estimated time
      c.t = time;
      json = await runInWorker(scenario);
    }
  }
  return json;
}

// A new scenario: the coverage counts belong to the old one.
function after(p) {
  const sj = JSON.stringify(p.st.scenario);
  if (sj !== p.st.scenarioJson) resetCoverage(p);
  p.st.scenarioJson = sj;
}

// ----- numbers from the report -----
const regionName = (l) => `X̂${sub(l + 1)}`;
const mark = (b) => (b == null ? '–' : b ? '<b class="good">✓ inside</b>' : '<b class="warn">✗ outside</b>');
const dirText = (d) => `(${d.map((v) => fmt(v)).join(', ')})`;

function showNumbers({ ui, st }) {
  const r = st.report;
  const l = r.lscr;
  const n = l.region ? l.region.dim : r.n;
  const what = { predict: 'prediction', filter: 'filtering', smooth: 'smoothing' }[l.estimate] || l.estimate;
  ui['num-title'].textContent = `Confidence set for x${sub(l.time)} from y${sub(1)}..y${sub(l.t)} (${what})`;
  // The animation's read-out (a live region while paused): what this data length estimates.
  ui['t-out'].textContent = `(x${sub(l.time)} from y${sub(1)}..y${sub(l.t)})`;
  const rows = [];
  for (let k = 0; k < n; k++) {
    rows.push([`${regionName(k)} <span class="hint">(direction ${k + 1})</span>`, pct(l.level_each), mark(l.truth_inside_each?.[k])]);
  }
  rows.push(['<b>X̂</b> = ∩ X̂<sub>l</sub>', `≥ ${pct(l.level)}`, mark(l.truth_inside)]);
  let html = `<table class="levels"><thead><tr><th>region</th><th>level</th><th>true state</th></tr></thead><tbody>${
    rows.map(([a, b, c]) => `<tr><th>${a}</th><td>${b}</td><td>${c}</td></tr>`).join('')}</tbody></table>`;
  const constr = l.construction === 'group' ? 'group strings (4a)' : l.construction === 'random' ? 'random strings (4)' : `${l.construction} strings`;
  html += `<p><b>M = ${l.M}</b>, <b>q = ${l.q}</b> · ${constr} · ${l.guaranteed
    ? '<span class="good">guaranteed by Theorem 3.2</span>' : '<span class="warn">not guaranteed (explicit strings)</span>'}</p>`;
  const names = l.plot.map((i) => `x${sub(i + 1)}`).join(', ');
  if (l.bounded && l.region.dim === 1) {
    html += `<p>Region <b>bounded</b>: ${l.intervals.length === 1 ? 'one interval' : `${l.intervals.length} intervals`}, length ${fmt(l.area)}</p>`;
  } else if (l.bounded) {
    html += `<p>Region <b>bounded</b>, area ${fmt(l.area)} (in the ${names} plane)</p>`;
  } else {
    // Opposite recession directions (a band) read as one ± direction.
    const dirs = [];
    for (const d of l.recession) {
      const opp = dirs.find((e) => !e.both && Math.hypot(e.d[0] + d[0], e.d[1] + d[1]) < 1e-9);
      if (opp) opp.both = true; else dirs.push({ d, both: false });
    }
    const dirList = dirs.length ? dirs.map((e) => `${e.both ? '±' : ''}${dirText(e.d)}`).join(' and ') : '–';
    html += `<p>Region <b class="warn">unbounded</b> along ${dirList}${l.invariant_directions.length
      ? `: X̂ is invariant along ${l.invariant_directions.map(dirText).join(', ')} (the data do not determine the state there)` : ''}.
      Area inside the window ${fmt(l.area)}.</p>`;
  }
  const est = [
    ['true state', l.x_true ? vec(l.x_true) : '– (data given)'],
    ['BLUE ⋆', l.blue ? vec(l.blue.center) : `none${l.blue_note ? ` — ${escapeHtml(l.blue_note)}` : ''}`],
    ['Kalman (dashed)', l.kf ? vec(l.kf.center) : 'none for smoothing'],
  ];
  html += `<table class="est"><tbody>${est.map(([a, b]) => `<tr><th>${a}</th><td>${b}</td></tr>`).join('')}</tbody></table>`;
  if (l.blue || l.kf) html += `<p class="hint">Ellipses at the joint level ${pct(l.level)} (χ² radius² ${fmt((l.blue || l.kf).radius2)}).</p>`;
  ui.numbers.innerHTML = html;
  ui['level-out'].textContent = ui.mode.value === 'level'
    ? `${pct(Number(ui.level.value))} → M = ${l.M}, q = ${l.q}` : pct(Number(ui.level.value));
  const x = l.x_true;
  ui['cov-truth'].textContent = x ? `x̄ = ${vec(x)}, time ${l.time}` : '';
}

// ----- placing the true state with a click -----
function placeTruth(p, e) {
  const { ui, st } = p;
  const figure = p.figures[0];
  const at = figure.frame && st.report ? figure.locate(e.offsetX, e.offsetY) : null;
  if (!at) return;
  const l = st.report.lscr;
  // A few significant digits of the window's size; other components (n > 2) keep their values.
  // A scalar state (n = 1) is drawn on one axis: its window is one interval, the click's x.
  const scalar = l.region.dim === 1;
  const span = scalar ? l.window.hi[0] - l.window.lo[0]
    : Math.max(l.window.hi[0] - l.window.lo[0], l.window.hi[1] - l.window.lo[1]);
  const digits = Math.max(0, 3 - Math.floor(Math.log10(span)));
  const x = (l.x_true || l.slice_at || Array(l.region.dim).fill(0)).slice();
  x[l.plot[0]] = at.x;
  if (!scalar) x[l.plot[1]] = at.y;
  ui.xbar.value = x.map((v) => +v.toFixed(digits)).join(' ');
  ui.fix.checked = true;
  updateVisibility(p);
  p.schedule('compute');
}

// ----- coverage experiment -----
function showCoverage({ ui }, c, done) {
  const frac = (k) => `${int(k)} / ${int(c.runs)}`;
  const rate = (k) => (c.runs ? `${(100 * k / c.runs).toFixed(1)} %` : '–');
  const inBand = (k, [lo, hi]) => k >= lo && k <= hi;
  const ok = (b) => (!done ? '' : b ? '<b class="good">✓</b>' : '<b class="warn">✗</b>');
  const rows = c.inside_each.map((k, l) => [regionName(l), frac(k), rate(k), pct(c.level_each),
    `[${int(c.band_each[0])}, ${int(c.band_each[1])}]`, ok(inBand(k, c.band_each))]);
  rows.push(['<b>X̂</b> (LSCR)', frac(c.inside), rate(c.inside), `≥ ${pct(c.level)}`, `≥ ${int(c.band[0])}`, ok(c.inside >= c.band[0])]);
  for (const [name, k] of [['BLUE ellipse', c.blue], ['Kalman ellipse', c.kf]]) {
    rows.push(k == null ? [name, '–', '–', '–', '–', '<span class="hint">no such region</span>']
      : [name, frac(k), rate(k), pct(c.level), `[${int(c.band[0])}, ${int(c.band[1])}]`, ok(inBand(k, c.band))]);
  }
  ui['cov-body'].innerHTML = rows.map((r) => `<tr><th>${r[0]}</th>${r.slice(1).map((v) => `<td>${v}</td>`).join('')}</tr>`).join('');
  let verdict = '';
  if (done) {
    verdict = `LSCR: X̂ held x̄ in ${rate(c.inside)} of the runs (promised ≥ ${pct(c.level)}) — ${c.inside >= c.band[0]
      ? '<b class="good">its guarantee holds at this state</b>' : '<b class="warn">below its 99.9 % band</b>'}.`;
    if (c.kf != null) {
      verdict += ` Kalman: ${rate(c.kf)} (nominal ${pct(c.level)}) — ${inBand(c.kf, c.band)
        ? 'in its band at this state' : c.kf < c.band[0]
          ? '<b class="warn">it misses this state far more often than promised</b>' : 'above its band (conservative here)'}.`;
    }
  }
  ui['cov-verdict'].innerHTML = verdict;
}

// The runs ask for new data at the true state of the last good run (placed, or the simulated one).
function startCoverage({ ui, st }) {
  if (!st.report) throw new Error('no valid scenario to run');
  const total = wholeNumber('lscr.coverage.runs', ui['cov-n'].value);
  const s = clone(st.scenario);
  if (!s.simulate) throw { field: 'data', message: 'the coverage experiment simulates new data many times: it needs a simulated scenario, not your data' };
  const x = s.simulate.condition ? s.simulate.condition.x : st.report.lscr.x_true;
  if (!x) throw { field: 'simulate.condition.x', message: 'the coverage experiment needs a true state: click the figure to place one' };
  s.simulate.condition = { t: st.report.lscr.time, x };
  s.lscr.coverage = { runs: total, seed: 1 };
  const json = JSON.stringify(s);
  return { scenario: json, runs: 0, study: new Study(json, 0), total };
}

function resetCoverage({ ui, st, coverage }) {
  coverage.reset();
  const names = st.report ? Array.from({ length: st.report.lscr.region.dim }, (_, l) => regionName(l)) : [];
  ui['cov-body'].innerHTML = [...names, '<b>X̂</b> (LSCR)', 'BLUE ellipse', 'Kalman ellipse']
    .map((nm) => `<tr><th>${nm}</th><td>–</td><td>–</td><td>–</td><td>–</td><td></td></tr>`).join('');
  ui['cov-verdict'].textContent = '';
}

export const mountLscr = async (root, presets) => mountPanel(root, {
  presets,
  custom: CUSTOM_PRESET,
  prefix: 'l-',
  busy: 'lscrBusy',
  Figure: RegionFigure,
  model: ['F', 'H', 'G'],
  ids: ['t-out', 'tv-out', 'tw-out', 'noise-readout', 'true-group', 'index-row', 'mq-row', 'level-row', 'level-out', 'fix-opts', 'num-title',
    'cov-n', 'cov-go', 'cov-cancel', 'cov-progress', 'cov-status', 'cov-err', 'cov-body', 'cov-truth', 'cov-verdict'],
  compute: ['m-F', 'm-H', 'm-G', 'sv', 'sw', 'tv', 'tw', 't', 'dseed', 'estimate', 'index', 'mode', 'M', 'q', 'level',
    'construction', 'seed', 'fix', 'xbar'],
  // The data length t, animated: the region as the data arrive (each step a run).
  animate: { control: 't', button: 'animate', compute: true, end: 'chosen', name: 't' },
  input: updateVisibility,
  stem: ({ st, ui }) => `${st.preset.name}-t${ui.t.value}`,
  init(p) {
    const { ui } = p;
    p.st.scenarioJson = '';
    p.coverage = studyRunner({
      go: ui['cov-go'], cancel: ui['cov-cancel'], bar: ui['cov-progress'], status: ui['cov-status'], err: ui['cov-err'],
      busy: p.setBusy, start: () => startCoverage(p), show: (c, done) => showCoverage(p, c, done),
    });
    p.figures[0].canvas.addEventListener('click', (e) => placeTruth(p, e));
  },
  load,
  build,
  run,
  after,
  draw: showNumbers,
  // The sign-perturbed sums at the true state placed by a click (the fixed x̄, in the plane), or
  // at the BLUE centre, the core's default.
  stepCard: {
    point({ ui, st }) {
      const l = st.report?.lscr;
      return ui.fix.checked && l?.x_true ? [l.x_true[l.plot[0]], l.x_true[l.plot[1]]] : undefined;
    },
  },
});
