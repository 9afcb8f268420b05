// The SCF vs KF panel: controls → Scenario JSON → wasm Session.run → figures and numbers.
// No estimation happens here: the page only edits the preset's scenario and shows the report.
import { runScenario, fieldErrors, frameScheduler, busyFlag } from './chunked.js';
import { Session } from './pkg/confset.js';
import { presetMenu, panelApi, dataMode } from './panel.js';
import { Figure, download, redrawOnResize } from './figure.js';
import { mountMonteCarlo } from './montecarlo.js';
import { parseMatrix, parseVector, matrixText, wholeNumber } from './parse.js';

const $ = (id) => document.getElementById(id);
const clone = (v) => JSON.parse(JSON.stringify(v));
const fmt = (v) => (typeof v !== 'number' || !Number.isFinite(v) ? '–'
  : Math.abs(v) >= 1e4 || (v !== 0 && Math.abs(v) < 1e-3) ? v.toExponential(2) : v.toFixed(3));
const scale = (m, k) => (Array.isArray(m) ? m.map((r) => scale(r, k)) : m * k);
const CUSTOM = 'custom';

// The custom mode is one more "preset" whose model comes from the four text boxes.
const CUSTOM_PRESET = {
  name: CUSTOM,
  description: 'Your own F, H, V, W: every change is validated and run at once.',
  scenario: {
    method: 'scf', title: 'Custom model',
    model: { F: [[0.98, 0.1], [0, 0.9]], H: [[1, 0]], V: [[0.01, 0], [0, 0.04]], W: [[0.25]] },
    simulate: { steps: 50, seed: 1 }, alpha: 0.95, tau: 0,
    coverage_curve: { component: 0, from: -6, to: 6, points: 101 },
    notes: 'A time-invariant model xₜ₊₁ = F xₜ + vₜ, yₜ = H xₜ + wₜ with the stationary prior x₁ ~ N(0, Γ), '
      + 'Γ = FΓFᵀ + V (so F must be stable), simulated for 50 steps. The SCF region exists from t = n on, once the '
      + 'ratio matrix U_tA_t is invertible (the state must be observable). The example: position and velocity, only '
      + 'the position measured — the velocity is poorly observed, so its SCF extent is much larger than the KF one. '
      + 'The Fig. 1 curve (for n ≤ 2) fixes the whole state at x̄ on component 1 and the prior mean elsewhere.',
  },
};

export async function mountScf(root, presets) {
  const session = new Session();
  const ui = Object.fromEntries(['preset', 'alpha', 'sv', 'sw', 'time', 'tau', 'seed', 'components', 'rare',
    'asym', 'xbar', 'cov-range', 'custom', 'm-F', 'm-H', 'm-V', 'm-W', 'stale', 'notes', 'numbers', 'num-t',
    'preset-desc', 'rare-opts', 'rare-hint', 'xbar-row', 'asym-row', 'components-row', 't-run', 't-draw']
    .map((id) => [id, $(id)]));
  const menu = presetMenu(ui.preset, presets, CUSTOM_PRESET);
  const all = menu.all;
  const st = { preset: all[0], report: null, reportJson: '', scenario: null, runMs: 0 };
  const stem = () => `${st.preset.name}-t${ui.time.value}`;
  const figures = [...root.querySelectorAll('figure.card')].map((c) => new Figure(c, session, stem));
  const coverageCard = $('fig-coverage');
  for (const k of ['F', 'H', 'V', 'W']) ui[`m-${k}`].value = matrixText(CUSTOM_PRESET.scenario.model[k]);

  // ----- controls ⇄ scenario -----
  const isCustom = () => st.preset === CUSTOM_PRESET;
  const isRobots = () => !!st.preset.scenario.collision;
  const customModel = () => Object.fromEntries(['F', 'H', 'V', 'W']
    .map((k) => [k, parseMatrix(`model.${k}`, ui[`m-${k}`].value)]));
  const dim = () => { try { return customModel().F.length; } catch { return 0; } };

  function componentOptions() {
    const opts = [['full state', 'all']];
    if (isRobots()) opts.unshift(['robot A position (pₓ, p_y)', '0,1'], ['robot A, all 4 states', '0,1,2,3']);
    else if (isCustom() && dim() >= 2) opts.push(['component 1', '0'], ['components 1, 2', '0,1']);
    const keep = ui.components.value;
    ui.components.replaceChildren(...opts.map(([t, v]) => new Option(t, v)));
    if (opts.some(([, v]) => v === keep)) ui.components.value = keep;
    ui['components-row'].hidden = opts.length < 2;
  }

  function loadPreset(name) {
    st.preset = all.find((p) => p.name === name) || all[0];
    const s = st.preset.scenario;
    ui.custom.hidden = !isCustom();
    ui['preset-desc'].textContent = st.preset.description;
    ui.alpha.value = s.alpha;
    ui.sv.value = ui.sw.value = 0;
    ui.tau.value = s.tau;
    ui.seed.value = s.simulate?.seed ?? 0;
    ui.rare.checked = !!s.simulate?.condition;
    ui.asym.checked = !!s.asymptotic;
    ui.xbar.value = isCustom() ? '5 0' : '12.25';
    ui['cov-range'].value = s.coverage_curve ? s.coverage_curve.to : '';
    componentOptions();
    ui.components.value = s.components ? s.components.join(',') : 'all';
    ui.time.dataset.preset = s.time ?? '';
    ui.notes.textContent = s.notes || '';
    dataMode(root, s);
    updateVisibility();
  }

  function updateVisibility() {
    ui['asym-row'].hidden = isRobots();
    ui['xbar-row'].hidden = isRobots();
    ui['rare-opts'].hidden = !ui.rare.checked;
    $('mc').hidden = !isRobots();
  }

  // The scenario the controls describe: the preset's, with fields changed.
  function buildScenario() {
    const s = clone(st.preset.scenario);
    if (isCustom()) {
      s.model = customModel();
      // Fig. 1 is a closed form for n = 1 and a Monte Carlo (2000 draws per point) otherwise:
      // keep it quick enough for a slider.
      if (s.model.F.length > 2) delete s.coverage_curve;
      else if (s.model.F.length === 2) s.coverage_curve.points = 17;
    }
    s.alpha = Number(ui.alpha.value);
    s.model.V = scale(s.model.V, 10 ** Number(ui.sv.value));
    s.model.W = scale(s.model.W, 10 ** Number(ui.sw.value));
    s.tau = wholeNumber('tau', ui.tau.value);
    if (s.simulate) s.simulate.seed = wholeNumber('simulate.seed', ui.seed.value);
    if (ui.components.value === 'all') delete s.components;
    else s.components = ui.components.value.split(',').map(Number);
    if (!s.simulate) { /* the user's data: nothing to simulate or condition */ }
    else if (!ui.rare.checked) delete s.simulate.condition;
    else if (!isRobots()) s.simulate.condition = { t: s.simulate.steps, x: parseVector('simulate.condition.x', ui.xbar.value) };
    s.asymptotic = ui.asym.checked && !isRobots();
    if (s.coverage_curve) {
      const r = Number(ui['cov-range'].value);
      Object.assign(s.coverage_curve, { from: -r, to: r });
    }
    delete s.time; // the time shown is a view setting: moving it does not recompute
    delete s.notes;
    return s;
  }

  // ----- errors next to the field they name -----
  const errors = fieldErrors(root, ui.stale);

  // ----- compute and draw -----
  const setBusy = busyFlag('busy');

  function compute() {
    if (!runScenario(st, errors, buildScenario, (s) => session.run(JSON.stringify(s)))) return;
    ui['t-run'].textContent = `computed in ${st.runMs.toFixed(1)} ms`;
    const steps = st.report.steps.length;
    ui.time.max = steps;
    if (ui.time.dataset.preset !== undefined) {
      ui.time.value = ui.time.dataset.preset || st.report.time;
      delete ui.time.dataset.preset;
    }
    coverageCard.hidden = !st.report.coverage_curve;
    redraw();
  }

  function redraw() {
    if (!st.report) return;
    const t = Math.min(Number(ui.time.value), st.report.steps.length);
    ui.time.value = t;
    const t0 = performance.now();
    for (const f of figures) f.draw(t);
    ui['t-draw'].textContent = `· drawn in ${(performance.now() - t0).toFixed(1)} ms`;
    showNumbers(t);
    showOutputs();
  }

  // Bursts of input events coalesce into one run (or redraw) per frame.
  const schedule = frameScheduler(setBusy, () => compute(), () => redraw());

  // ----- numbers from the report -----
  function showNumbers(t) {
    const r = st.report;
    const s = r.steps[t - 1];
    const idx = r.plot;
    const pick = (v) => (v ? idx.map((i) => fmt(v[i])).join(', ') : '–');
    const diag = (m) => (m ? idx.map((i) => fmt(m[i][i])).join(', ') : '–');
    const names = idx.map((i) => `x${i + 1}`).join(', ');
    const rows = [
      ['KF  (dashed)', pick(s.kf.center), diag(s.kf.cov)],
      ['SCF (solid)', s.scf ? pick(s.scf.center) : 'not yet (ratio singular)', s.scf ? diag(s.scf.cov) : '–'],
    ];
    if (r.x_true) rows.push(['true state', pick(r.x_true[t - 1]), '']);
    rows.push(['prior mean', pick(r.prior_mean[t - 1]), '']);
    let html = `<table><thead><tr><th></th><th>center (${names})</th><th>variances P, Π</th></tr></thead><tbody>${
      rows.map(([a, b, c]) => `<tr><th>${a}</th><td>${b}</td><td>${c}</td></tr>`).join('')}</tbody></table>`;
    html += `<p>ratio U<sub>t</sub>A<sub>t</sub> (diagonal): ${diag(s.ratio)} · χ² radius² ${fmt(s.kf.radius2)} (α = ${r.alpha})</p>`;
    const c = r.collision && r.collision.find((x) => x.time === t);
    if (c) {
      const w = (b) => (b ? '<b class="warn">collision warning</b>' : 'no warning');
      html += `<p>Prediction for t + τ = ${t + (st.scenario?.tau ?? 0)} from y<sub>1..${t}</sub>: gap between the
        robots' regions — KF ${fmt(c.kf_distance)} → ${w(c.kf_warning)}; SCF ${fmt(c.scf_distance)} → ${w(c.scf_warning)}
        (d<sub>min</sub> ${fmt(st.scenario?.collision?.d_min)})${c.true_distance != null ? `; true distance ${fmt(c.true_distance)}` : ''}.</p>`;
    }
    if (r.asymptotic && r.n === 1) {
      const a = r.asymptotic;
      html += `<p>Steady state: Γ = ${fmt(a.gamma[0][0])}, P̄ = ${fmt(a.p[0][0])}, ratio R̄ = ${fmt(a.ratio[0][0])}, Π̄ = ${fmt(a.pi[0][0])}</p>`;
    }
    ui.numbers.innerHTML = html;
    ui['num-t'].textContent = t;
  }

  function showOutputs() {
    $('alpha-out').textContent = Number(ui.alpha.value).toFixed(3);
    $('sv-out').textContent = (10 ** Number(ui.sv.value)).toFixed(2);
    $('sw-out').textContent = (10 ** Number(ui.sw.value)).toFixed(2);
    $('time-out').textContent = ui.time.value;
    const a = st.report && st.report.asymptotic;
    const x = Number(ui.xbar.value);
    ui['rare-hint'].textContent = isRobots()
      ? `Measurements drawn backwards from a colliding state at t = ${st.preset.scenario.simulate?.condition?.t} (robot centres 0.1 apart). `
        + 'The whole state is fixed: the SCF guarantee is for the components ζ when only ζ is fixed.'
      : a && a.gamma.length === 1 && Number.isFinite(x)
        ? `x̄ = ${fmt(x)} is ${(x / Math.sqrt(a.gamma[0][0])).toFixed(1)} σ of the prior (Γ = ${fmt(a.gamma[0][0])}); fixed at t = ${st.report.steps.length}.`
        : 'The whole state is fixed at the last step (one value per component).';
  }

  // ----- wiring -----
  ui.preset.addEventListener('change', () => { resetMonteCarlo(); loadPreset(ui.preset.value); schedule('compute'); });
  for (const id of ['alpha', 'sv', 'sw', 'tau', 'seed', 'components', 'asym', 'xbar', 'cov-range', 'm-F', 'm-H', 'm-V', 'm-W']) {
    ui[id].addEventListener('input', () => { showOutputs(); schedule('compute'); });
  }
  for (const id of ['m-F', 'm-H']) ui[id].addEventListener('input', componentOptions);
  ui.rare.addEventListener('input', () => { updateVisibility(); schedule('compute'); });
  ui.time.addEventListener('input', () => { showOutputs(); schedule('redraw'); });

  // Hi-DPI: refit the backing stores when the layout or the pixel ratio changes (no recompute).
  redrawOnResize(figures, () => schedule('redraw'));

  $('dl-report').addEventListener('click', () => st.reportJson
    && download(`${stem()}-report.json`, new Blob([st.reportJson], { type: 'application/json' })));
  $('dl-scenario').addEventListener('click', () => st.scenario
    && download(`${stem()}-scenario.json`, new Blob([JSON.stringify(st.scenario, null, 2)], { type: 'application/json' })));

  const resetMonteCarlo = mountMonteCarlo($('mc'), () => {
    const s = buildScenario();
    if (!s.simulate) throw { field: 'data', message: 'the Monte Carlo over rare realizations simulates: it needs a simulated scenario, not data' };
    s.simulate.condition = clone(st.preset.scenario.simulate.condition);
    return { scenario: s, preset: st.preset.scenario };
  }, setBusy);

  ui.preset.value = all[0].name;
  loadPreset(all[0].name);
  compute();
  return panelApi(ui.preset, menu, () => st.scenario);
}
