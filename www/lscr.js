// The LSCR panel: controls → Scenario JSON (method "lscr") → wasm Session.run → the region figure
// (Session.draw, view {"panel":"region"}), the numbers of the report, and the chunked coverage
// experiment (wasm Study) at a true state placed with a click. No estimation happens
// here: the page only edits the preset's scenario and shows what the core reports.
import { Session, Study } from './pkg/confset.js';
import { presetMenu, panelApi, dataMode } from './panel.js';
import { Figure, download, redrawOnResize } from './figure.js';
import { runChunked, runScenario, fieldErrors, frameScheduler, busyFlag } from './chunked.js';
import { parseMatrix, parseVector, parseNumber, matrixText, wholeNumber } from './parse.js';

const clone = (v) => JSON.parse(JSON.stringify(v));
const fmt = (v) => (typeof v !== 'number' || !Number.isFinite(v) ? '–'
  : Math.abs(v) >= 1e4 || (v !== 0 && Math.abs(v) < 1e-3) ? v.toExponential(2) : v.toFixed(3));
const vec = (v) => (Array.isArray(v) ? `(${v.map(fmt).join(', ')})` : '–');
const pct = (v) => `${+(100 * v).toFixed(2)} %`;
const int = (v) => v.toLocaleString('en-US');
const SUB = '₀₁₂₃₄₅₆₇₈₉';
const sub = (k) => String(k).replace(/\d/g, (d) => SUB[d]);
const CUSTOM = 'custom';
const CHUNK = 100; // runs per Study.step

// The custom mode is one more "preset" whose model comes from the text boxes.
const CUSTOM_PRESET = {
  name: CUSTOM,
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

export async function mountLscr(root, presets) {
  const session = new Session();
  const $ = (id) => root.querySelector(`#${id}`);
  const ui = Object.fromEntries(['preset', 'preset-desc', 'custom', 'm-F', 'm-H', 'm-G', 'sv', 'sw', 't', 'dseed',
    'estimate', 'index', 'index-row', 'mode', 'M', 'q', 'mq-row', 'level', 'level-row', 'level-out', 'construction',
    'seed', 'fix', 'fix-opts', 'xbar', 'stale', 'numbers', 'num-title', 'timing', 'notes',
    'cov-n', 'cov-go', 'cov-cancel', 'cov-progress', 'cov-status', 'cov-err', 'cov-body', 'cov-truth', 'cov-verdict']
    .map((id) => [id, $(`l-${id}`)]));
  const menu = presetMenu(ui.preset, presets, CUSTOM_PRESET);
  const all = menu.all;
  const st = { preset: all[0], report: null, reportJson: '', scenario: null, scenarioJson: '', runMs: 0, drawMs: 0 };
  const stem = () => `${st.preset.name}-t${ui.t.value}`;
  const figure = new RegionFigure($('fig-region'), session, stem);
  for (const k of ['F', 'H', 'G']) ui[`m-${k}`].value = matrixText(CUSTOM_PRESET.scenario.model[k]);

  // ----- controls ⇄ scenario -----
  const isCustom = () => st.preset === CUSTOM_PRESET;

  function loadPreset(name) {
    st.preset = all.find((p) => p.name === name) || all[0];
    const s = st.preset.scenario;
    const l = s.lscr;
    ui.custom.hidden = !isCustom();
    ui['preset-desc'].textContent = st.preset.description;
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
    ui.notes.textContent = (s.notes || '').replace(/\s{2,}/g, ' ');
    dataMode(root, s);
    updateVisibility();
  }

  function updateVisibility() {
    const smooth = ui.estimate.value === 'smooth';
    ui['index-row'].hidden = !smooth;
    if (smooth && ui.index.value === '') ui.index.value = Math.max(1, Math.floor(Number(ui.t.value) / 2) || 1);
    ui['mq-row'].hidden = ui.mode.value !== 'mq';
    ui['level-row'].hidden = ui.mode.value !== 'level';
    ui['fix-opts'].hidden = !ui.fix.checked;
    ui['level-out'].textContent = pct(Number(ui.level.value));
  }

  // The estimated time by the scenario contract (prediction t + 1, filtering t, smoothing i);
  // checked against the report's lscr.time after the run.
  function estimatedTime(s) {
    const t = s.simulate ? s.simulate.steps : s.data.y.length;
    return s.lscr.estimate === 'predict' ? t + 1 : s.lscr.estimate === 'filter' ? t : s.lscr.index;
  }

  // The scenario the controls describe: the preset's, with fields changed.
  function buildScenario() {
    const s = clone(st.preset.scenario);
    if (isCustom()) {
      for (const k of ['F', 'H', 'G']) s.model[k] = parseMatrix(`model.${k}`, ui[`m-${k}`].value);
      const n = s.model.F.length;
      s.plot = n >= 2 ? [0, 1] : undefined;
    }
    s.model.sigma_v2 = parseNumber('model.sigma_v2', ui.sv.value);
    s.model.sigma_w2 = parseNumber('model.sigma_w2', ui.sw.value);
    if (s.simulate) {
      s.simulate.steps = wholeNumber('simulate.steps', ui.t.value);
      s.simulate.seed = wholeNumber('simulate.seed', ui.dseed.value);
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
    delete s.notes;
    return s;
  }

  // ----- errors next to the field they name -----
  const errors = fieldErrors(root, ui.stale, 'form ');

  // ----- compute and draw -----
  const setBusy = busyFlag('lscrBusy');

  function runReport(scenario) {
    let json = session.run(JSON.stringify(scenario));
    const c = scenario.simulate?.condition;
    if (c) {
      const time = JSON.parse(json).lscr.time;
      if (time !== c.t) { // the truth belongs at the estimated time
        c.t = time;
        json = session.run(JSON.stringify(scenario));
      }
    }
    return json;
  }

  function compute() {
    if (!runScenario(st, errors, buildScenario, runReport)) return;
    const sj = JSON.stringify(st.scenario);
    if (sj !== st.scenarioJson) resetCoverage();
    st.scenarioJson = sj;
    redraw();
  }

  function redraw() {
    if (!st.report) return;
    const t0 = performance.now();
    figure.draw();
    st.drawMs = performance.now() - t0;
    showNumbers();
  }

  // Bursts of input events coalesce into one run (or redraw) per frame.
  const schedule = frameScheduler(setBusy, () => compute(), () => redraw());

  // ----- numbers from the report -----
  const regionName = (l) => `X̂${sub(l + 1)}`;
  const mark = (b) => (b == null ? '–' : b ? '<b class="good">✓ inside</b>' : '<b class="warn">✗ outside</b>');
  const dirText = (d) => `(${d.map((v) => fmt(v)).join(', ')})`;

  function showNumbers() {
    const r = st.report;
    const l = r.lscr;
    const n = l.region ? l.region.dim : r.n;
    const what = { predict: 'prediction', filter: 'filtering', smooth: 'smoothing' }[l.estimate] || l.estimate;
    ui['num-title'].textContent = `Confidence set for x${sub(l.time)} from y${sub(1)}..y${sub(l.t)} (${what})`;
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
    if (l.bounded) {
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
      ['BLUE ⋆', l.blue ? vec(l.blue.center) : `none${l.blue_note ? ` — ${l.blue_note}` : ''}`],
      ['Kalman (dashed)', l.kf ? vec(l.kf.center) : 'none for smoothing'],
    ];
    html += `<table class="est"><tbody>${est.map(([a, b]) => `<tr><th>${a}</th><td>${b}</td></tr>`).join('')}</tbody></table>`;
    if (l.blue || l.kf) html += `<p class="hint">Ellipses at the joint level ${pct(l.level)} (χ² radius² ${fmt((l.blue || l.kf).radius2)}).</p>`;
    ui.numbers.innerHTML = html;
    ui.timing.textContent = `rendered in ${(st.runMs + st.drawMs).toFixed(1)} ms (run ${st.runMs.toFixed(1)} ms + draw ${st.drawMs.toFixed(1)} ms)`;
    ui['level-out'].textContent = ui.mode.value === 'level'
      ? `${pct(Number(ui.level.value))} → M = ${l.M}, q = ${l.q}` : pct(Number(ui.level.value));
    ui['cov-truth'].textContent = truthLabel();
  }

  // ----- placing the true state with a click -----
  function toState(px, py) {
    const f = figure.frame;
    if (!f || !st.report) return null;
    const [left, top, right, bottom] = f.plot_area;
    if (px < left || px > right || py < top || py > bottom || right <= left || bottom <= top) return null;
    const w = st.report.lscr.window;
    const xr = f.x_range || [w.lo[0], w.hi[0]];
    const yr = f.y_range || [w.lo[1], w.hi[1]];
    return [xr[0] + ((px - left) / (right - left)) * (xr[1] - xr[0]), yr[1] - ((py - top) / (bottom - top)) * (yr[1] - yr[0])];
  }

  figure.canvas.addEventListener('click', (e) => {
    const p = toState(e.offsetX, e.offsetY);
    if (!p) return;
    const l = st.report.lscr;
    // A few significant digits of the window's size; other components (n > 2) keep their values.
    const span = Math.max(l.window.hi[0] - l.window.lo[0], l.window.hi[1] - l.window.lo[1]);
    const digits = Math.max(0, 3 - Math.floor(Math.log10(span)));
    const x = (l.x_true || l.slice_at || Array(l.region.dim).fill(0)).slice();
    x[l.plot[0]] = p[0];
    x[l.plot[1]] = p[1];
    ui.xbar.value = x.map((v) => +v.toFixed(digits)).join(' ');
    ui.fix.checked = true;
    updateVisibility();
    schedule('compute');
  });

  // ----- coverage experiment -----
  let running = null; // { cancelled, stale }

  function truthLabel() {
    const r = st.report;
    if (!r) return '';
    const x = r.lscr.x_true;
    return x ? `x̄ = ${vec(x)}, time ${r.lscr.time}` : '';
  }

  function showCoverage(c, done) {
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
    ui['cov-progress'].max = Math.max(1, running?.total ?? c.runs);
    ui['cov-progress'].value = c.runs;
  }

  function emptyCoverage() {
    const names = st.report ? Array.from({ length: st.report.lscr.region.dim }, (_, l) => regionName(l)) : [];
    ui['cov-body'].innerHTML = [...names, '<b>X̂</b> (LSCR)', 'BLUE ellipse', 'Kalman ellipse']
      .map((nm) => `<tr><th>${nm}</th><td>–</td><td>–</td><td>–</td><td>–</td><td></td></tr>`).join('');
  }

  async function runCoverage() {
    ui['cov-err'].textContent = '';
    let exp, total;
    try {
      if (!st.report) throw new Error('no valid scenario to run');
      total = wholeNumber('lscr.coverage.runs', ui['cov-n'].value);
      const s = clone(st.scenario);
      if (!s.simulate) throw { field: 'data', message: 'the coverage experiment simulates new data many times: it needs a simulated scenario, not your data' };
      const x = s.simulate.condition ? s.simulate.condition.x : st.report.lscr.x_true;
      if (!x) throw { field: 'simulate.condition.x', message: 'the coverage experiment needs a true state: click the figure to place one' };
      s.simulate.condition = { t: st.report.lscr.time, x };
      s.lscr.coverage = { runs: total, seed: 1 };
      exp = new Study(JSON.stringify(s), 0);
    } catch (e) {
      ui['cov-err'].textContent = e.message;
      return;
    }
    const me = { cancelled: false, total };
    running = me;
    ui['cov-go'].disabled = true;
    ui['cov-cancel'].disabled = false;
    setBusy(+1);
    try {
      const { counts: c, wall, compute } = await runChunked(exp, CHUNK, me, (c) => {
        showCoverage(c, false);
        ui['cov-status'].textContent = `${int(c.runs)} / ${int(total)} runs`;
      });
      if (me.stale) return; // the scenario changed: these counts belong to the old one
      showCoverage(c, !me.cancelled);
      ui['cov-status'].textContent = me.cancelled
        ? `cancelled after ${int(c.runs)} runs (${wall.toFixed(0)} ms)`
        : `${int(c.runs)} runs in ${wall.toFixed(0)} ms (computing ${compute.toFixed(0)} ms, ${(1000 * compute / c.runs).toFixed(0)} µs per run)`;
    } catch (e) {
      ui['cov-err'].textContent = e.message;
    } finally {
      exp.free();
      if (running === me) running = null;
      ui['cov-go'].disabled = false;
      ui['cov-cancel'].disabled = true;
      setBusy(-1);
    }
  }

  function resetCoverage() {
    if (running) Object.assign(running, { cancelled: true, stale: true });
    emptyCoverage();
    ui['cov-verdict'].textContent = '';
    ui['cov-status'].textContent = '';
    ui['cov-err'].textContent = '';
    ui['cov-progress'].value = 0;
  }

  // ----- wiring -----
  ui.preset.addEventListener('change', () => { loadPreset(ui.preset.value); schedule('compute'); });
  for (const id of ['m-F', 'm-H', 'm-G', 'sv', 'sw', 't', 'dseed', 'estimate', 'index', 'mode', 'M', 'q', 'level',
    'construction', 'seed', 'fix', 'xbar']) {
    ui[id].addEventListener('input', () => { updateVisibility(); schedule('compute'); });
  }
  ui['cov-go'].addEventListener('click', runCoverage);
  ui['cov-cancel'].addEventListener('click', () => { if (running) running.cancelled = true; });

  // Hi-DPI: refit the backing store when the layout or the pixel ratio changes (no recompute).
  redrawOnResize([figure], () => schedule('redraw'));

  $('l-dl-report').addEventListener('click', () => st.reportJson
    && download(`${stem()}-report.json`, new Blob([st.reportJson], { type: 'application/json' })));
  $('l-dl-scenario').addEventListener('click', () => st.scenario
    && download(`${stem()}-scenario.json`, new Blob([JSON.stringify(st.scenario, null, 2)], { type: 'application/json' })));

  ui.preset.value = all[0].name;
  loadPreset(all[0].name);
  compute();
  return panelApi(ui.preset, menu, () => st.scenario);
}
