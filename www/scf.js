// The SCF vs KF panel: controls → Scenario JSON → a run in the compute worker → figures and numbers.
// No estimation happens here: the page only edits the preset's scenario and shows the report.
import { mountPanel, clone } from './panel.js';
import { mountMonteCarlo } from './montecarlo.js';
import { parseMatrix, parseVector, wholeNumber } from './parse.js';
import { fmtFixed as fmt, noiseReadout } from './format.js';
import { recordTime } from './cursor.js';

const scale = (m, k) => (Array.isArray(m) ? m.map((r) => scale(r, k)) : m * k);

// The custom mode is one more "preset" whose model comes from the four text boxes.
const CUSTOM_PRESET = {
  name: 'custom',
  description: 'Your own F, H, V, W: every change is validated and run at once.',
  scenario: {
    method: 'scf', title: 'Custom model',
    model: { F: [[0.98, 0.1], [0, 0.9]], H: [[1, 0]], V: [[0.01, 0], [0, 0.04]], W: [[0.25]] },
    simulate: { steps: 50, seed: 1 }, alpha: 0.95,
    scf: { tau: 0, coverage_curve: { component: 0, from: -6, to: 6, points: 101 } },
    notes: 'A time-invariant model xₜ₊₁ = F xₜ + vₜ, yₜ = H xₜ + wₜ with the stationary prior x₁ ~ N(0, Γ), '
      + 'Γ = FΓFᵀ + V (so F must be stable), simulated for 50 steps. The SCF region exists from t = n on, once the '
      + 'ratio matrix U_tA_t is invertible (the state must be observable). The example: position and velocity, only '
      + 'the position measured — the velocity is poorly observed, so its SCF extent is much larger than the KF one. '
      + 'The Fig. 1 curve (for n ≤ 2) fixes the whole state at x̄ on component 1 and the prior mean elsewhere.',
  },
};

// ----- controls ⇄ scenario -----
// SCF's options live in the scenario's "scf" block. A file of an older version has them at the top
// level (the core reads them there too): they are moved into the block before the page edits them.
const OLD_TOP_LEVEL = ['components', 'tau', 'asymptotic', 'collision', 'coverage_curve'];
function scfBlock(s) {
  s.scf = s.scf ?? {};
  for (const k of OLD_TOP_LEVEL) if (k in s) { if (!(k in s.scf)) s.scf[k] = s[k]; delete s[k]; }
  return s.scf;
}
const isRobots = ({ st }) => !!(st.preset.scenario.scf?.collision ?? st.preset.scenario.collision);
const dim = (p) => { try { return p.model().F.length; } catch { return 0; } };

function componentOptions(p) {
  const { ui } = p;
  const opts = [['full state', 'all']];
  if (isRobots(p)) opts.unshift(['robot A position (pₓ, p_y)', '0,1'], ['robot A, all 4 states', '0,1,2,3']);
  else if (p.isCustom() && dim(p) >= 2) opts.push(['component 1', '0'], ['components 1, 2', '0,1']);
  const keep = ui.components.value;
  ui.components.replaceChildren(...opts.map(([t, v]) => new Option(t, v)));
  if (opts.some(([, v]) => v === keep)) ui.components.value = keep;
  ui['components-row'].hidden = opts.length < 2;
}

function load(p, scenario) {
  const { ui } = p;
  const s = clone(scenario);
  const o = scfBlock(s);
  ui.alpha.value = s.alpha;
  ui.sv.value = ui.sw.value = 0;
  // The true noise of the simulated record, apart from the assumed one (log₁₀ of the scale).
  const tn = s.simulate?.true_noise;
  ui.tv.value = tn?.V ? Math.log10(tn.V) : 0;
  ui.tw.value = tn?.W ? Math.log10(tn.W) : 0;
  ui.tau.value = o.tau ?? 0;
  ui.seed.value = s.simulate?.seed ?? 0;
  ui.rare.checked = !!s.simulate?.condition;
  ui.asym.checked = !!o.asymptotic;
  // Far enough out (about 10 σ of the stationary prior) that the Kalman region, pulled towards the
  // prior mean by 1 − ratio = 0.1 of x̄, misses it on the default seed while the SCF region holds it.
  ui.xbar.value = p.isCustom() ? '5 0' : '25';
  ui['cov-range'].value = o.coverage_curve ? o.coverage_curve.to : '';
  componentOptions(p);
  ui.components.value = o.components ? o.components.join(',') : 'all';
  ui.time.dataset.preset = s.time ?? '';
  updateVisibility(p);
  try { p.resetMonteCarlo(studyScenario(p)); } catch { /* no study on data: the card is hidden */ }
}

function updateVisibility(p) {
  const { ui } = p;
  ui['asym-row'].hidden = isRobots(p);
  ui['xbar-row'].hidden = isRobots(p);
  ui['rare-opts'].hidden = !ui.rare.checked;
  // The study is one click away wherever the run simulates.
  ui.mc.hidden = !p.st.preset.scenario.simulate;
  // Measured data carry their own noise: only a simulated record has a true noise to set.
  ui['true-group'].hidden = !p.st.preset.scenario.simulate;
  // τ moves the collision check's prediction (t + τ); without a collision check no figure or
  // number shows the predicted region, so the control is not offered.
  ui.tau.closest('label').hidden = !isRobots(p);
}

// The scenario of the Monte Carlo: the robots' collision as the preset conditions it, or the
// state fixed at x̄ (the rare realization's value) at the last step, every component counted.
function studyScenario(p) {
  const s = p.build();
  if (!s.simulate) throw { field: 'data', message: 'the Monte Carlo over rare realizations simulates: it needs a simulated scenario, not data' };
  const preset = p.st.preset.scenario;
  if (isRobots(p)) {
    s.simulate.condition = clone(preset.simulate.condition);
    s.experiment = clone(preset.experiment);
  } else {
    s.simulate.condition = { t: s.simulate.steps, x: parseVector('simulate.condition.x', p.ui.xbar.value) };
    s.experiment = { seed: s.simulate.seed, components: s.simulate.condition.x.map((_, i) => i) };
  }
  return s;
}

// The scenario the controls describe: the preset's, with fields changed.
function build(p, s) {
  const { ui } = p;
  const o = scfBlock(s);
  if (p.isCustom()) {
    s.model = p.model();
    // The prior of x₁: the stationary one unless given (an unstable F has none).
    if (ui['m-P1'].value.trim() !== '') s.model.x1_cov = parseMatrix('model.x1_cov', ui['m-P1'].value);
    // Fig. 1 is a closed form for n = 1 and a Monte Carlo (2000 draws per point) otherwise:
    // keep it quick enough for a slider.
    if (s.model.F.length > 2) delete o.coverage_curve;
    else if (s.model.F.length === 2) o.coverage_curve.points = 17;
  }
  s.alpha = Number(ui.alpha.value);
  s.model.V = scale(s.model.V, 10 ** Number(ui.sv.value));
  s.model.W = scale(s.model.W, 10 ** Number(ui.sw.value));
  // The simulated record's noise, apart from what the filters assume (the core's
  // simulate.true_noise: scales of the assumed V and W, so the two groups multiply).
  const [tv, tw] = trueScales(p);
  if (s.simulate) {
    if (tv === 1 && tw === 1) delete s.simulate.true_noise;
    else {
      s.simulate.true_noise = { V: tv, W: tw };
      // Fig. 1's curve is the model's own law (the core refuses it beside a true noise).
      delete o.coverage_curve;
    }
  }
  o.tau = wholeNumber('scf.tau', ui.tau.value);
  if (s.simulate) s.simulate.seed = wholeNumber('simulate.seed', ui.seed.value);
  if (ui.components.value === 'all') delete o.components;
  else o.components = ui.components.value.split(',').map(Number);
  if (!s.simulate) { /* the user's data: nothing to simulate or condition */ }
  else if (!ui.rare.checked) delete s.simulate.condition;
  else if (!isRobots(p)) s.simulate.condition = { t: s.simulate.steps, x: parseVector('simulate.condition.x', ui.xbar.value) };
  o.asymptotic = ui.asym.checked && !isRobots(p);
  if (o.coverage_curve) {
    const r = Number(ui['cov-range'].value);
    Object.assign(o.coverage_curve, { from: -r, to: r });
  }
  delete s.time; // the time shown is a view setting: moving it does not recompute
}

// The true noise's scales relative to the assumed noise, as the sliders give them (1 at 0).
function trueScales({ ui }) {
  return [ui.tv, ui.tw].map((el) => (Number(el.value) === 0 ? 1 : Number((10 ** Number(el.value)).toPrecision(12))));
}

// ----- after a run -----
function after({ ui, st }) {
  ui.time.max = st.report.steps.length;
  if (ui.time.dataset.preset !== undefined) {
    ui.time.value = ui.time.dataset.preset || st.report.time;
    delete ui.time.dataset.preset;
  }
}

function time({ ui, st }) {
  const t = Math.min(Number(ui.time.value), st.report.steps.length);
  ui.time.value = t;
  return t;
}

// ----- numbers from the report -----
function showNumbers({ ui, st }, t) {
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
    html += `<p>Prediction for t + τ = ${t + (st.scenario?.scf?.tau ?? 0)} from y<sub>1..${t}</sub>: gap between the
      robots' regions — KF ${fmt(c.kf_distance)} → ${w(c.kf_warning)}; SCF ${fmt(c.scf_distance)} → ${w(c.scf_warning)}
      (d<sub>min</sub> ${fmt(st.scenario?.scf?.collision?.d_min)})${c.true_distance != null ? `; true distance ${fmt(c.true_distance)}` : ''}.</p>`;
  }
  if (r.asymptotic && r.n === 1) {
    const a = r.asymptotic;
    html += `<p>Steady state: Γ = ${fmt(a.gamma[0][0])}, P̄ = ${fmt(a.p[0][0])}, ratio R̄ = ${fmt(a.ratio[0][0])}, Π̄ = ${fmt(a.pi[0][0])}</p>`;
  }
  ui.numbers.innerHTML = html;
  ui['num-t'].textContent = `${t}${recordTime(st.report, t)}`;
}

function showOutputs(p) {
  const { ui, st } = p;
  ui['alpha-out'].textContent = Number(ui.alpha.value).toFixed(3);
  ui['sv-out'].textContent = (10 ** Number(ui.sv.value)).toFixed(2);
  ui['sw-out'].textContent = (10 ** Number(ui.sw.value)).toFixed(2);
  ui['tv-out'].textContent = (10 ** Number(ui.tv.value)).toFixed(2);
  ui['tw-out'].textContent = (10 ** Number(ui.tw.value)).toFixed(2);
  ui['noise-readout'].textContent = noiseReadout(trueScales(p), ['V', 'W']);
  ui['time-out'].textContent = `${ui.time.value}${recordTime(st.report, Number(ui.time.value))}`;
  const a = st.report && st.report.asymptotic;
  const x = Number(ui.xbar.value);
  ui['rare-hint'].textContent = isRobots(p)
    ? `Measurements drawn backwards from a colliding state at t = ${st.preset.scenario.simulate?.condition?.t} (robot centres 0.1 apart). `
      + 'The whole state is fixed: the SCF guarantee is for the components ζ when only ζ is fixed.'
    : a && a.gamma.length === 1 && Number.isFinite(x)
      ? `x̄ = ${fmt(x)} is ${(x / Math.sqrt(a.gamma[0][0])).toFixed(1)} σ of the prior (Γ = ${fmt(a.gamma[0][0])}); fixed at t = ${st.report.steps.length}.`
      : 'The whole state is fixed at the last step (one value per component).';
}

export const mountScf = async (root, presets) => mountPanel(root, {
  presets,
  custom: CUSTOM_PRESET,
  busy: 'busy',
  model: ['F', 'H', 'V', 'W'],
  errorsWithin: '', // the coverage card holds the error of scf.coverage_curve
  ids: ['num-t', 'rare-opts', 'rare-hint', 'xbar-row', 'asym-row', 'components-row', 't-run', 't-draw', 'mc',
    'alpha-out', 'sv-out', 'sw-out', 'tv-out', 'tw-out', 'noise-readout', 'true-group', 'time-out', 'm-P1'],
  compute: ['alpha', 'sv', 'sw', 'tv', 'tw', 'tau', 'seed', 'components', 'asym', 'xbar', 'cov-range', 'm-F', 'm-H', 'm-V', 'm-W', 'm-P1', 'rare'],
  redraw: ['time'],
  animate: { control: 'time', button: 'animate' },
  input(p, id) {
    if (id === 'rare') updateVisibility(p); else showOutputs(p);
    if (id === 'm-F' || id === 'm-H') componentOptions(p);
  },
  stem: ({ st, ui }) => `${st.preset.name}-t${ui.time.value}`,
  init(p) {
    p.resetMonteCarlo = mountMonteCarlo(p.ui.mc, () => studyScenario(p), p.setBusy);
  },
  leave: (p) => p.resetMonteCarlo(),
  load,
  build,
  after,
  time,
  stepCard: {}, // the filters' update at the time shown
  draw(p, t) {
    showNumbers(p, t);
    showOutputs(p);
  },
  timing({ ui, st }) {
    ui['t-run'].textContent = `computed in ${st.runMs.toFixed(1)} ms`;
    ui['t-draw'].textContent = `· drawn in ${st.drawMs.toFixed(1)} ms`;
  },
});
