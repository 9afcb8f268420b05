// The GLLS panel: controls → Scenario JSON (method "glls", without its Monte Carlo) → a run in
// the panel's compute worker → four figures drawn by the core (views {"panel": "singular" | "index" | "plane" |
// "precision"}) and the numbers of the report. The Monte Carlo of Section 5 runs apart, on every
// core (studypool.js), and its merged result is handed back to the Session (setStudy, the one
// path of every method's study result into a report) so the "precision" figure draws it. No
// estimation happens here: the page edits the preset's scenario and shows what the core reports.
import { Study } from './pkg/confset.js';
import { mountPanel, clone } from './panel.js';
import { Figure } from './figure.js';
import { studyRunner, busyFlag } from './chunked.js';
import { parseMatrix, parseVector, parseNumber, wholeNumber } from './parse.js';
import { withScripts, sub } from './richtext.js';
import { fmtPrecision as fmt, vec as vecOf } from './format.js';

// Vectors keep 5 digits for large entries: an unstable state of 10⁷ and its estimate differ in the 5th.
const fmtLong = (v) => (typeof v === 'number' && Number.isFinite(v) && Math.abs(v) >= 1e4 ? v.toExponential(4) : fmt(v));
const vec = (v) => vecOf(v, fmtLong);
const mark = (b) => (b == null ? '' : b ? '<b class="good">✓ inside</b>' : '<b class="warn">✗ outside</b>');
const STUDY_DRAW_MS = 120; // redraw the precision figure at most this often while the study runs

// The custom mode is one more "preset" whose model comes from the text boxes.
const CUSTOM_PRESET = {
  name: 'custom',
  description: 'Your own A, C, Ω (and B): x(k+1) = A x(k) + B u(k), y(k) = C x(k) + δ(k); every change is validated and run at once.',
  scenario: {
    method: 'glls', title: 'GLLS: custom model',
    model: { F: [[0.95, 0.3], [-0.3, 0.95]], H: [[1, 0]], W: [[0.01]], x1_mean: [1, 0] },
    simulate: { steps: 40, seed: 3 },
    glls: {
      max_horizon: 60, estimator: 'lls', mu: 0.3, noise: 'gaussian', plane: [0, 1],
      monte_carlo: { runs: 500, seed: 1, study: 'precision', max_horizon: 30 },
    },
    notes: 'A damped rotation (|λ| ≈ 0.996) seen through its first component. Both singular values of Γ_{s+1} grow '
      + 'while the rotation keeps feeding the measured component, then saturate as it decays. Try A = [[1.02 0.3] [-0.3 1.02]] '
      + '(both σ grow), a singular A (σ(Γ A^{−s}) disappears), or C = [1 1] with two outputs by adding a row.',
  },
};

// The presets' notes write Γ_{s+1} and σ_n: show them as sub-/superscripts (text escaped first).
const richText = (t) => withScripts(t, (w) => w.replace(/([σκΓxy])_([a-zA-Z0-9]+)/g, '$1<sub>$2</sub>'));

const hasStateNoise = (s) => Array.isArray(s?.model?.V) && s.model.V.flat(2).some((v) => v !== 0);

// The core draws every GLLS picture; the horizon marker and the sets come from the kept report.
class GllsFigure extends Figure {
  view() { return JSON.stringify({ panel: this.panel }); }

  // The precision figure draws the Monte Carlo (`hasStudy()`, set by the panel); until the first
  // chunk lands it says so.
  draw(time) {
    if (this.panel !== 'precision') return super.draw(time);
    const has = this.hasStudy();
    this.card.querySelector('.fig-note').hidden = has;
    if (has) return super.draw(time);
    this.fit();
    this.canvas.getContext('2d').clearRect(0, 0, this.canvas.width, this.canvas.height);
    this.frame = null;
    this.err.textContent = '';
  }

  // The precision card stays, with its note, until the Monte Carlo fills it.
  shownFor(useful) { return this.panel === 'precision' || super.shownFor(useful); }

  // Log axes are drawn in log10 units (the frame's y range): read the value itself out.
  cursorText({ chart: f, x, y }) {
    const log = /\(log scale\)/.test(f.y_label || '');
    const name = (s, d) => (s || d).replace(/\s*\(log scale\)/, '');
    const xs = this.panel === 'plane' ? fmt(x) : String(Math.round(x));
    return `${name(f.x_label, 'x')} = ${xs}, ${name(f.y_label, 'y')} = ${fmt(log ? 10 ** y : y)}`;
  }
}

// ----- controls ⇄ scenario -----
// State dimension n of the model the controls describe (0 while the custom F does not parse).
function dim({ ui, st, isCustom }) {
  if (!isCustom()) return st.preset.scenario.model.F.length;
  try { return parseMatrix('model.F', ui['m-F'].value).length; } catch { return 0; }
}

function planeOptions(p, plane) {
  const { ui } = p;
  const n = dim(p);
  if (!n) return;
  const keep = plane || [Number(ui.px.value), Number(ui.py.value)];
  for (const [sel, v] of [[ui.px, keep[0]], [ui.py, keep[1]]]) {
    sel.replaceChildren(...Array.from({ length: n }, (_, i) => new Option(`x${sub(i + 1)}`, String(i))));
    sel.value = String(Number.isInteger(v) && v < n ? v : Math.min(sel === ui.px ? 0 : 1, n - 1));
  }
  if (Number(ui.p.value) === Number(ui.p.max)) ui.p.value = String(n); // p = n stays "none dropped"
  ui.p.max = String(n);
}

function load(p, s) {
  const { ui } = p;
  const g = s.glls;
  ui.auto.checked = g.horizon == null;
  if (g.horizon != null) ui.s.value = g.horizon;
  ui.estimator.value = g.estimator || 'lls';
  ui.noise.value = g.noise || 'gaussian';
  planeOptions(p, g.plane || [0, 1]);
  ui.p.value = g.p ?? (dim(p) || s.model.F.length);
  ui.mu.value = g.mu ?? '';
  ui.steps.value = s.simulate ? s.simulate.steps : s.data.y.length;
  ui.seed.value = s.simulate?.seed ?? 0;
  ui.max.value = g.max_horizon ?? 60;
  // The preset's Monte Carlo size (a link or the gallery then shows the same precision figure).
  ui['mc-n'].value = g.monte_carlo?.runs ?? 500;
  horizonRange(p);
}

// The slider spans 0..min(S, k) with k = steps − 1 (what the inputs say; the core checks).
// Left alone while those inputs are not valid, so the horizon survives a typo.
function horizonRange(p) {
  const { ui } = p;
  const steps = Number(ui.steps.value);
  const max = Number(ui.max.value);
  if (Number.isSafeInteger(steps) && steps >= 2 && Number.isSafeInteger(max) && max >= 1) {
    const top = Math.min(max, steps - 1);
    ui.s.max = String(top);
    ui['s-max'].textContent = String(top);
  }
  showHorizon(p);
}

function showHorizon({ ui, st }) {
  const g = st.report?.glls;
  if (g && ui.auto.checked) ui.s.value = String(g.s); // the slider follows the best horizon
  const best = g?.best_horizon;
  let note = '(best)';
  if (g && best == null) note = '(no best in 1..S: s = n − 1)';
  else if (g && best > g.k) note = `(best ${best} > k = ${g.k})`;
  ui['s-out'].textContent = ui.auto.checked
    ? `= ${g ? g.s : '…'} ${note}` : `= ${ui.s.value}${best != null && Number(ui.s.value) === best ? ' (best)' : ''}`;
}

// The Monte Carlo block the page would send (the study type follows the estimator).
function monteCarlo(st, s) {
  const pre = st.preset.scenario.glls.monte_carlo || {};
  const cap = Math.min(pre.max_horizon ?? 30, s.glls.max_horizon, (s.simulate ? s.simulate.steps : s.data.y.length) - 1);
  return {
    runs: 500, seed: pre.seed ?? 1,
    study: s.glls.estimator === 'state_noise' ? 'state_noise' : 'precision',
    max_horizon: Math.max(0, cap),
  };
}

// The scenario the controls describe: the preset's, with fields changed, without monte_carlo.
function build(p, s) {
  const { ui } = p;
  if (p.isCustom()) {
    Object.assign(s.model, p.model());
    if (ui['m-B'].value.trim() !== '') {
      s.model.B = parseMatrix('model.B', ui['m-B'].value);
      s.simulate.u = [s.model.B[0].map(() => 1)]; // a unit step on every input
    } else {
      delete s.model.B;
      delete s.simulate.u;
    }
    s.model.x1_mean = parseVector('model.x1_mean', ui.x0.value);
  }
  if (s.simulate) {
    s.simulate.steps = wholeNumber('simulate.steps', ui.steps.value);
    s.simulate.seed = wholeNumber('simulate.seed', ui.seed.value);
  }
  const g = s.glls;
  g.max_horizon = wholeNumber('glls.max_horizon', ui.max.value);
  if (ui.auto.checked) delete g.horizon; else g.horizon = wholeNumber('glls.horizon', ui.s.value);
  g.estimator = ui.estimator.value;
  g.noise = ui.noise.value;
  g.p = wholeNumber('glls.p', ui.p.value);
  if (ui.mu.value.trim() === '') delete g.mu; else g.mu = parseNumber('glls.mu', ui.mu.value);
  g.plane = [Number(ui.px.value), Number(ui.py.value)];
  delete g.monte_carlo;
}

async function run(runInWorker, scenario) {
  let json = await runInWorker(scenario);
  const g = scenario.glls;
  if (g.noise === 'worst' && g.horizon == null) {
    // The worst-case noise is aligned with the gain of the horizon in use: the best one,
    // which only the report knows — run again with it fixed.
    g.horizon = JSON.parse(json).glls.s;
    json = await runInWorker(scenario);
  }
  return json;
}

// What the study depends on: the model, the data length and inputs, the weighting, its block.
const studyKey = (s, mc) => JSON.stringify([s.model, s.simulate?.steps, s.simulate?.u || [], s.data || null, s.glls.estimator, mc]);

// A new model starts its study; the same model keeps it for the new report.
function after(p) {
  const { st } = p;
  const key = studyKey(st.scenario, monteCarlo(st, st.scenario));
  if (key !== st.studyKey) {
    newStudy(p, key);
    queueMicrotask(() => p.mc.run(true));
  } else if (st.studyJson) {
    p.session.setStudy(st.studyJson);
  }
}

// ----- numbers from the report -----
const list = (v) => (Array.isArray(v) ? v.map(fmt).join(', ') : '–');
const pow10 = (l) => (typeof l === 'number' && l > -300 ? 10 ** l : null); // the report's log10 curves

function showNumbers({ ui, st }) {
  const r = st.report;
  const g = r.glls;
  const n = g.n;
  const s = g.s;
  const est = { lls: 'LLS', glls: 'GLLS', state_noise: 'state-noise estimator' }[g.estimator] || g.estimator;
  ui['num-title'].textContent = `x(${g.k}) from y(${g.k - s}) … y(${g.k}): s = ${s}, k = ${g.k}, ${est}`;
  const rows = [];
  const row = (a, b) => rows.push(`<tr><th>${a}</th><td>${b}</td></tr>`);
  const bestP = g.best_horizon_p != null ? `; of σ<sub>${g.regularized?.p ?? 'p'}</sub>/√s: s = ${g.best_horizon_p}` : '';
  const atEnd = g.best_horizon != null && g.best_horizon === g.curves.log10_sigma.length - 1
    ? ' <span class="hint">(the end of the curves: σ<sub>n</sub>/√s still rising)</span>' : '';
  row('best horizon', `${g.best_horizon != null ? `s = ${g.best_horizon}${g.best_horizon === s ? ' <span class="good">(in use)</span>' : ''}${atEnd}${
    g.best_horizon > g.k ? ` <span class="hint">(beyond the data: s ≤ k = ${g.k})</span>` : ''}`
    : 'none in 1..S (σ<sub>n</sub>/√s still rising)'}${bestP}`);
  row(`σ(Γ<sub>${s + 1}</sub>)`, list(g.sigma));
  row(`σ(Γ<sub>${s + 1}</sub>A<sup>−${s}</sup>)`, g.sigma_prime ? list(g.sigma_prime) : 'A is singular');
  let html = `<table class="est"><tbody>${rows.join('')}</tbody></table>`;
  if (g.prime_gap_log10 != null) {
    const tiny = g.prime_gap_log10 < 1e-6;
    html += `<p class="remark">Paper's remark (σ(Γ) = σ(Γ A<sup>−s</sup>)) checked over s ≤ S: max |log₁₀ σ − log₁₀ σ′| = ${fmt(g.prime_gap_log10)}: ${tiny
      ? '<b class="good">the singular values coincide</b> (A orthogonal)' : '<b class="warn">the singular values do NOT coincide</b>'}.</p>`;
  }
  // Condition numbers: κ_LLS = 1/σ_n (past), 1/σ'_n (current); κ_GLLS with the model's Ω.
  const c = g.curves;
  const at = (a) => (a && s < a.length ? a[s] : undefined);
  const kGllsPast = pow10(at(c.log10_kappa_glls_past));
  const kGllsCur = pow10(at(c.log10_kappa_glls_current));
  const kLlsCur = g.kappa_lls_current ?? pow10(at(c.log10_kappa_lls_current));
  const omegaNote = kGllsPast == null ? ' <span class="hint">(Ω singular)</span>' : '';
  html += `<table class="kappa"><thead><tr><th>κ</th><th>LLS</th><th>GLLS${omegaNote}</th><th>in use</th></tr></thead><tbody>
    <tr><th>past x(${g.k - s})</th><td>${fmt(g.kappa_lls_past)}</td><td>${fmt(kGllsPast)}</td><td>${fmt(g.kappa_past)}</td></tr>
    <tr><th>current x(${g.k})</th><td>${fmt(kLlsCur)}</td><td>${fmt(kGllsCur)}</td><td>${fmt(g.kappa_current)}</td></tr></tbody></table>`;
  // Estimate, truth, guaranteed sets.
  const e = [];
  const erow = (a, b) => e.push(`<tr><th>${a}</th><td>${b}</td></tr>`);
  erow(`estimate x̂(${g.k})`, vec(g.estimate_current));
  erow(`truth x(${g.k})`, g.x_true_current ? vec(g.x_true_current) : '– (data given)');
  if (g.error_current != null) erow('error ‖x̂ − x‖', fmt(g.error_current));
  // The report stores a zero radius as a tiny positive variance (a valid ellipsoid).
  const r2 = g.ball_current.cov[0][0] * g.ball_current.radius2;
  const radius = r2 < 1e-200 ? 0 : Math.sqrt(r2);
  erow('guaranteed ball', `radius ${fmt(radius)} <span class="hint">(‖δ(j)‖ ≤ μ = ${fmt(g.mu)})</span> ${mark(g.truth_in_ball)}`);
  const b = g.box_current;
  erow('guaranteed box', `${b.lo.map((lo, i) => `<span class="nw">x${sub(i + 1)} ∈ [${fmtLong(lo)}, ${fmtLong(b.hi[i])}]</span>`).join(' ')} ${mark(g.truth_in_box)}`);
  if (g.noise_max != null) {
    erow('largest ‖δ(j)‖ drawn', `${fmt(g.noise_max)} ${g.noise_max <= g.mu * (1 + 1e-12)
      ? '<span class="good">≤ μ: the sets are guaranteed</span>' : '<span class="warn">&gt; μ: no guarantee for this draw</span>'}`);
  }
  erow('expected error bound', `${fmt(g.expected_bound)} <span class="hint">= κ·√((s+1) tr Ω) (39)</span>`);
  erow('rounding estimate', `${fmt(g.rounding_estimate)}${g.rounding_dominates ? '' : ' <span class="hint">(negligible)</span>'}`);
  html += `<table class="est"><tbody>${e.join('')}</tbody></table>`;
  if (hasStateNoise(st.scenario)) {
    html += '<p class="hint">This model has transition noise ξ (model.V): the ball and box bound the effect of the '
      + 'measurement noise δ only, so they are not guaranteed here — the state-noise estimator is the one to use.</p>';
  }
  if (g.rounding_dominates) {
    html += `<p class="alarm">⚠ Rounding dominates: the estimated floating-point error ${fmt(g.rounding_estimate)} rivals the statistical bound — `
      + 'this horizon loses to double precision what κ promises (shorten s).</p>';
  }
  if (g.state_noise) {
    const sn = g.state_noise;
    const ok = sn.qp_difference <= 1e-6 * Math.max(1, ...sn.estimate_past.map(Math.abs));
    html += `<p><b>State-noise estimator</b> (60)–(64): x̂(${g.k}) = ${vec(sn.estimate_current)}<br>QP check (clarabel vs closed form): max difference ${fmt(sn.qp_difference)} ${
      ok ? '<b class="good">✓ agree</b>' : '<b class="warn">✗ differ</b>'}</p>`;
  }
  if (g.regularized) {
    const rg = g.regularized;
    html += `<p><b>Regularized</b>, p = ${rg.p} of ${n} σ's kept: κ = ${fmt(rg.kappa_past)} (vs 1/σ<sub>${rg.p}</sub> = ${fmt(rg.kappa_lls_past)}) for x(${g.k - s})<br>`
      + `x̂<sub>reg</sub>(${g.k - s}) = ${vec(rg.estimate_past)} vs projected truth ${vec(rg.truth_projected_past)}`;
    if (rg.estimate_current) {
      html += `<br>x̂<sub>reg</sub>(${g.k}) = ${vec(rg.estimate_current)} vs projected truth ${vec(rg.truth_projected_current)}`
        + `${rg.kappa_current != null ? `, κ = ${fmt(rg.kappa_current)}` : ''}`;
    } else {
      html += `<br>current state: <span class="hint">A is singular, no regularized x(${g.k})</span>`;
    }
    html += '</p>';
  } else if (n > 1) {
    html += `<p class="hint">p = n = ${n}: no regularization (set p &lt; n to drop the smallest singular values).</p>`;
  }
  ui.numbers.innerHTML = html;
}

// ----- the Monte Carlo of Section 5 -----
function newStudy({ ui, st, mc }, key) {
  mc.reset();
  Object.assign(st, { study: null, studyJson: '', studyKey: key, studyDone: false });
  ui['mc-verdict'].textContent = '';
  const sn = st.scenario?.glls.estimator === 'state_noise';
  ui['mc-kind'].textContent = sn ? '— Section 5.2: state-noise estimator vs LLS' : '— Section 5.1: precision vs horizon';
  ui['mc-hint'].textContent = sn
    ? 'Each run simulates x(k+1) = A x(k) + ξ(k), y = C x, and estimates x(k) with both estimators at every horizon (Fig. 4).'
    : 'Each run simulates new Gaussian data of the model and estimates x(k) at every horizon; the boxes are the error quartiles, the curve the expected bound κ√((s+1) tr Ω) (Fig. 3).';
}

function showStudy({ ui, st }, c, done) {
  st.study = c;
  st.studyJson = JSON.stringify(c);
  st.studyDone = done;
  if (!done) { ui['mc-verdict'].textContent = ''; return; }
  // Where the median error is smallest, and how the bound compares there.
  let best = -1;
  c.first.forEach((sp, i) => { if (sp && (best < 0 || sp.median < c.first[best].median)) best = i; });
  if (best < 0) { ui['mc-verdict'].textContent = ''; return; }
  const s = c.horizons[best];
  let v = `Smallest median error ${fmt(c.first[best].median)} at s = ${s}`;
  if (c.second) {
    const pairs = c.first.map((sp, i) => [sp, c.second[i]]).filter(([a, b2]) => a && b2);
    const wins = pairs.filter(([a, b2]) => a.median < b2.median).length;
    v += `; the state-noise estimator has the smaller median at ${wins} of ${pairs.length} horizons`;
  } else if (c.bound[best] != null) {
    v += ` (expected bound there ${fmt(c.bound[best])})`;
  }
  v += `. Mean ‖x(k)‖ = ${fmt(c.mean_state_norm)}.`;
  ui['mc-verdict'].textContent = v;
}

// A study of the last good scenario; `auto`: started with it.
function startStudy(p, auto) {
  const { ui, st } = p;
  if (!st.scenario) return null;
  const total = wholeNumber('glls.monte_carlo.runs', ui['mc-n'].value);
  const s = clone(st.scenario);
  s.glls.monte_carlo = { ...monteCarlo(st, s), runs: total };
  const json = JSON.stringify(s);
  p.lastDraw = 0;
  return { scenario: json, runs: 0, study: new Study(json, 0), total, note: auto ? ' (started with the scenario)' : '' };
}

// The precision figure follows the study: at most every STUDY_DRAW_MS while it runs, and at its end.
function studyCounts(p, c, done, final) {
  showStudy(p, c, done);
  const now = performance.now();
  if (final || (now - p.lastDraw > STUDY_DRAW_MS && p.st.report)) {
    if (!final) p.lastDraw = now;
    p.session.setStudy(p.st.studyJson);
    p.precision.draw();
  }
}

export const mountGlls = async (root, presets) => mountPanel(root, {
  presets,
  custom: CUSTOM_PRESET,
  prefix: 'g-',
  busy: 'gllsBusy',
  Figure: GllsFigure,
  model: ['F', 'H', 'W'],
  prose: richText,
  ids: ['s-out', 's-max', 'num-title', 'mc-n', 'mc-go', 'mc-cancel', 'mc-progress', 'mc-status', 'mc-err',
    'mc-verdict', 'mc-kind', 'mc-hint'],
  compute: ['m-F', 'm-H', 'm-B', 'm-W', 'x0', 'estimator', 'noise', 'p', 'mu', 'seed', 'px', 'py', 'auto', 'steps', 'max', 's'],
  // The horizon s, animated: the x axis of Figs. 1–3 (the marker walks along the curves, the
  // plane's estimate and guaranteed sets follow); each step a run, the Monte Carlo kept.
  animate: {
    control: 's', button: 'animate', compute: true, name: 's',
    scenario(p, v) {
      const s = p.build();
      s.glls.horizon = v;
      return s;
    },
  },
  input(p, id) {
    if (id === 'm-F') planeOptions(p);
    if (id === 'steps' || id === 'max') horizonRange(p);
    if (id === 's') {
      p.ui.auto.checked = false;
      showHorizon(p);
    }
  },
  stem: ({ st, ui }) => `${st.preset.name}-s${st.report ? st.report.glls.s : ui.s.value}`,
  init(p) {
    const { ui, st } = p;
    ui.x0.value = CUSTOM_PRESET.scenario.model.x1_mean.join(' ');
    // The last study (possibly partial) and the scenario key it belongs to.
    Object.assign(st, { study: null, studyJson: '', studyKey: '', studyDone: false });
    p.precision = p.figures.find((f) => f.panel === 'precision');
    p.precision.hasStudy = () => !!st.studyJson;
    ui.auto.addEventListener('change', () => {
      if (!ui.auto.checked && st.report) ui.s.value = st.report.glls.s; // start the slider where the best was
    });
    p.mc = studyRunner({
      go: ui['mc-go'], cancel: ui['mc-cancel'], bar: ui['mc-progress'], status: ui['mc-status'], err: ui['mc-err'],
      busy: busyFlag('gllsMcBusy'), start: (auto) => startStudy(p, auto),
      show: (c, done, final) => studyCounts(p, c, done, final), extra: (c) => `, ${c.horizons.length} horizons`,
    });
  },
  load,
  build,
  run,
  after,
  draw(p) {
    showHorizon(p);
    showNumbers(p);
  },
  reportFile({ st }) {
    const r = clone(st.report);
    if (st.study) r.glls.precision = st.study;
    return JSON.stringify(r);
  },
  scenarioFile({ st, ui }) {
    const s = clone(st.scenario);
    s.glls.monte_carlo = { ...monteCarlo(st, s), runs: Number(ui['mc-n'].value) || 500 };
    return s;
  },
});
