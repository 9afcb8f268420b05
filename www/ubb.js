// The set-membership panel (Tempo, method "ubb"): controls → Scenario JSON → wasm Session.run →
// two figures drawn by the core (views {"panel": "ubbset" | "ubbwidth"}) and the numbers of the
// report (report.ubb). The step k is the scenario's ubb.time: the core computes the exact polygon,
// the interval hull and the prediction there. The guarantee runs fresh simulations in chunks
// (wasm Study) and counts how often the truth left the set (never) and the KF ellipse.
// No estimation happens here: the page edits the preset's scenario and shows what the core says.
import { Session, Study } from './pkg/confset.js';
import { presetMenu, panelApi, dataMode } from './panel.js';
import { Figure, download, drawFigures, redrawOnResize } from './figure.js';
import { runChunked, runScenario, fieldErrors, frameScheduler, busyFlag } from './chunked.js';
import { parseMatrix, parseNumber, parseVector, matrixText, wholeNumber } from './parse.js';
import { bracedScripts, verdict } from './richtext.js';

const clone = (v) => JSON.parse(JSON.stringify(v));
const fmt = (v) => (typeof v !== 'number' || !Number.isFinite(v) ? '–'
  : v === 0 ? '0' : Math.abs(v) >= 1e4 || Math.abs(v) < 1e-3 ? v.toExponential(2) : String(Number(v.toPrecision(4))));
const vec = (v) => (Array.isArray(v) ? `(${v.map(fmt).join(', ')})` : '–');
const int = (n) => n.toLocaleString('en-US');
const SUB = '₀₁₂₃₄₅₆₇₈₉';
const sub = (k) => String(k).replace(/\d/g, (d) => SUB[d]);
const NORM = { linf: 'l∞', l1: 'l₁', l2: 'l₂' };
const CHUNK = 10; // runs per Study.step
const ANIMATE_MS = 350; // per step of the animation (at least one LP solve per frame)

// The custom mode is one more "preset" whose model comes from the text boxes.
const CUSTOM_PRESET = {
  name: 'custom',
  description: 'Your own A, B, C: x(k+1) = A x(k) + B u(k), y(k) = C x(k) + η(k) with |u| ≤ τ, |η| ≤ ε; every change is validated and run at once.',
  scenario: {
    method: 'ubb', title: 'Custom model',
    model: { F: [[0.9, 0.2], [-0.1, 0.8]], G: [[1], [0.5]], H: [[1, 0]] },
    simulate: { steps: 50, seed: 1 },
    ubb: { eps: 0.2, tau: 0.1, delta: [2], alpha: 50, beta: 50, gamma: 0.1, time: 40 },
    notes: 'A stable 2-state system with one bounded noise input and one measured output. The set of states consistent '
      + 'with the data and the bounds is a polygon drawn by support LPs; it holds the true state at every step '
      + 'as long as the simulated noise stays within ε and τ.',
  },
};

const richText = (t) => bracedScripts(t).replace(/(\p{L}[\u0300-\u036f]?)_([\p{L}\d]+)/gu, '$1<sub>$2</sub>');

// The set panel reads plane coordinates, the width panel steps (whole numbers) and values.
class UbbFigure extends Figure {
  view() { return JSON.stringify({ panel: this.panel }); }

  showCursor(px, py) {
    const f = this.frame;
    if (!f) return;
    const hit = [f, ...(f.more || [])].find(({ plot_area: [l, t, r, b] }) => px >= l && px <= r && py >= t && py <= b && r > l && b > t);
    if (!hit) { this.cursor.textContent = ''; return; }
    const [l, t, r, b] = hit.plot_area;
    const x = hit.x_range[0] + ((px - l) / (r - l)) * (hit.x_range[1] - hit.x_range[0]);
    const y = hit.y_range[1] - ((py - t) / (b - t)) * (hit.y_range[1] - hit.y_range[0]);
    const xs = this.panel === 'ubbset' ? fmt(x) : `k = ${Math.round(x)}`;
    const xl = this.panel === 'ubbset' ? `${hit.x_label} = ` : '';
    this.cursor.textContent = `${xl}${xs}, ${hit.y_label || 'y'} = ${fmt(y)}`;
  }
}

export async function mountUbb(root, presets) {
  const session = new Session();
  const $ = (id) => root.querySelector(`#${id}`);
  const ui = Object.fromEntries(['preset', 'preset-desc', 'time', 'time-out', 'time-min', 'time-max', 'time-window', 'animate',
    'eps', 'tau', 'delta', 'sim-out', 'alpha', 'beta', 'gamma', 'window-out', 'norm', 'seed', 'noise', 'stale', 'numbers', 'num-title',
    'timing', 'notes', 'runs', 'go', 'cancel', 'g-status', 'g-result', 'g-err', 'custom', 'm-F', 'm-G', 'm-H']
    .map((id) => [id, $(`b-${id}`)]));
  const st = { preset: presets[0], report: null, reportJson: '', scenario: null, runMs: 0, drawMs: 0 };
  const stem = () => {
    const u = st.report?.ubb;
    return `${st.preset.name}-${u ? `${u.norm}-k${u.at.k}` : 'ubb'}`;
  };
  const figures = [...root.querySelectorAll('figure.card')].map((c) => new UbbFigure(c, session, stem));
  const menu = presetMenu(ui.preset, presets, CUSTOM_PRESET);
  for (const k of ['F', 'G', 'H']) ui[`m-${k}`].value = matrixText(CUSTOM_PRESET.scenario.model[k]);
  const isCustom = () => st.preset === CUSTOM_PRESET;

  // ----- controls ⇄ scenario -----
  const text = (v) => (v == null ? '' : Array.isArray(v) ? (v.every((x) => x === v[0]) ? String(v[0]) : v.join(' ')) : String(v));

  function loadPreset(name) {
    st.preset = menu.all.find((p) => p.name === name) || menu.all[0];
    const s = st.preset.scenario;
    const u = s.ubb;
    ui['preset-desc'].innerHTML = richText(st.preset.description);
    ui.custom.hidden = !isCustom();
    ui.eps.value = u.eps;
    ui.tau.value = u.tau ?? 0;
    ui.delta.value = text(u.delta);
    ui.alpha.value = text(u.alpha);
    ui.beta.value = text(u.beta);
    ui.gamma.value = u.gamma ?? 0.1;
    ui.norm.value = u.norm || 'linf';
    ui.noise.checked = u.noise === 'bound';
    ui.seed.value = s.simulate?.seed ?? 0;
    ui.notes.innerHTML = richText(s.notes || '');
    ui['sim-out'].textContent = `simulated noise: |η| ≤ ${u.sim_eps ?? u.eps}, |u| ≤ ${u.sim_tau ?? u.tau ?? 0} (the preset’s; ε, τ are the bounds the estimator assumes)`;
    const steps = s.simulate?.steps ?? s.data?.y?.length ?? 1;
    dataMode(root, s);
    ui.time.min = '0';
    ui.time.max = String(steps - 1);
    ui['time-max'].textContent = String(steps - 1);
    ui.time.value = String(u.time ?? steps - 1);
    ui['g-result'].textContent = '';
    ui['g-status'].textContent = '';
    showTime();
  }

  function showTime() {
    const k = Number(ui.time.value);
    ui['time-out'].textContent = `= ${k}`;
    const u = st.report?.ubb;
    ui['time-window'].textContent = u && u.at.k === k ? `window y(${u.at.first}) … y(${k})` : '';
    if (u) ui['time-min'].textContent = String(u.track[0].k);
  }

  // An optional positive number: empty (or ∞, inf) = ∞ (null).
  const infinite = (t) => ['', '∞', 'inf', 'infinity'].includes(String(t).trim().toLowerCase());
  const optional = (field, t) => (infinite(t) ? null : parseNumber(field, t));

  function buildScenario() {
    const s = clone(st.preset.scenario);
    if (isCustom()) for (const k of ['F', 'G', 'H']) s.model[k] = parseMatrix(`model.${k}`, ui[`m-${k}`].value);
    const u = s.ubb;
    u.eps = parseNumber('ubb.eps', ui.eps.value);
    u.tau = parseNumber('ubb.tau', ui.tau.value);
    u.delta = infinite(ui.delta.value) ? null : parseVector('ubb.delta', ui.delta.value);
    if (u.delta === null) delete u.delta;
    u.alpha = optional('ubb.alpha', ui.alpha.value);
    if (u.alpha === null) delete u.alpha;
    u.beta = optional('ubb.beta', ui.beta.value);
    if (u.beta === null) delete u.beta;
    u.gamma = parseNumber('ubb.gamma', ui.gamma.value);
    u.norm = ui.norm.value;
    u.noise = ui.noise.checked ? 'bound' : 'random';
    u.time = wholeNumber('ubb.time', ui.time.value);
    // The simulated noise stays the preset's: ε and τ are the bounds the estimator assumes, so a
    // bound below the noise makes the data contradict it (or lose the truth).
    const p0 = st.preset.scenario.ubb;
    if (s.simulate) {
      u.sim_eps = p0.sim_eps ?? p0.eps;
      u.sim_tau = p0.sim_tau ?? (p0.tau ?? 0);
    }
    if (s.simulate) s.simulate.seed = wholeNumber('simulate.seed', ui.seed.value);
    delete s.notes;
    return s;
  }

  // ----- errors next to the field they name -----
  const errors = fieldErrors(root, ui.stale, 'form ');

  // ----- compute and draw -----
  const setBusy = busyFlag('ubbBusy');

  function compute() {
    if (!runScenario(st, errors, buildScenario, (s) => session.run(JSON.stringify(s)))) return false;
    redraw();
    return true;
  }

  function redraw() {
    if (!st.report) return;
    st.drawMs = drawFigures(figures);
    showTime();
    showNumbers();
  }

  const schedule = frameScheduler(setBusy, () => compute(), () => redraw());

  // ----- numbers from the report -----
  function showNumbers() {
    const u = st.report.ubb;
    const at = u.at;
    const k = at.k;
    const [i, j] = u.plane;
    const sm = u.smoothing;
    const step = u.track.find((t) => t.k === k);
    // Example 1's state is the coefficient vector a: the report names it ("a₁ (1)", …).
    const names = u.state_names || at.lo.map((_, c) => `x${sub(c + 1)}`);
    const coef = !names[0].startsWith('x');
    const target = coef ? 'the coefficients a' : `x(${k + 1})`;
    ui['num-title'].textContent = `At step k = ${k}: the set of ${target} from y(${at.first}) … y(${k}), ${NORM[u.norm] || u.norm} bounds`;
    const rows = [];
    const row = (a, b) => rows.push(`<tr><th>${a}</th><td>${b}</td></tr>`);
    row('window', `${u.window} ${u.window === 1 ? 'step' : 'steps'} <span class="hint">(data y(${at.first}) … y(${k}))</span>`);
    const cones = at.size.cones ? `, ${at.size.cones} cones (${at.size.cone_rows} rows)` : '';
    row('LP size', `${at.size.variables} variables, ${at.size.rows} rows${cones}`);
    row('polygon', `${at.polygon.vertices.length} vertices from ${at.polygon.calls} LPs — ${at.polygon.exact
      ? '<b class="good">exact</b>' : `within ${fmt(at.polygon.gap)} of the set`}${u.r > 2 ? ` <span class="hint">(projection on x${sub(i + 1)}, x${sub(j + 1)})</span>` : ''}`);
    row('central estimate', vec(at.center));
    row('interval hull', at.lo.map((lo, c) => `<span class="nw">${names[c]} ∈ [${fmt(lo)}, ${fmt(at.hi[c])}]</span>`).join(' '));
    row('radius', `${fmt(at.radius)} <span class="hint">(largest half-width: the guaranteed error of the central estimate)</span>`);
    row('Theorem 4 bound', sm.limit != null ? `${fmt(sm.limit)} <span class="hint">(on the radius; ‖A‖e<sup>1/α</sup> = ${fmt(sm.ratio)})</span>`
      : `– <span class="hint">(‖A‖e<sup>1/α</sup> = ${fmt(sm.ratio)}${sm.b_norm === 0 ? ', no process noise' : ' ≥ 1'})</span>`);
    row('Theorem 5 j', sm.j != null ? `${sm.j} <span class="hint">(γ = ${fmt(u.gamma)}: window j + 1 = ${sm.j + 1}${sm.tail != null ? `, tail ${fmt(sm.tail)}` : ''})</span>`
      : `– <span class="hint">${sm.note ? richText(sm.note) : ''}</span>`);
    const truth = u.x_true ? u.x_true[k + 1] : null;
    row(coef ? 'true a' : `true x(${k + 1})`, truth ? vec(truth) : '– (data given)');
    row('truth inside the set', `${verdict(step?.inside, 'yes', 'no')}${step?.inside === false
      ? ' <span class="hint">(ε or τ below the simulated noise: the bounds are wrong, so no guarantee)</span>' : ''}`);
    const kfLevel = Math.round(100 * (1 - Math.exp(-at.kf.radius2 / 2)));
    row(`truth inside the KF ${kfLevel} % ellipsoid`, verdict(step?.kf_inside, 'yes', 'no'));
    if (at.prediction.length) {
      row(`prediction of y(${k + 1})`, at.prediction.map(([lo, hi], o) => `<span class="nw">${at.prediction.length > 1 ? `y${sub(o + 1)} ` : ''}∈ [${fmt(lo)}, ${fmt(hi)}]</span>`).join(' '));
    } else {
      row(`prediction of y(${k + 1})`, '– <span class="hint">(no measurements)</span>');
    }
    row('over the run', `truth outside the set ${u.outside} / ${u.track.length} steps, outside the KF ellipsoid ${u.kf_outside} / ${u.track.length}`);
    ui.numbers.innerHTML = `<table class="est"><tbody>${rows.join('')}</tbody></table>`;
    ui['window-out'].innerHTML = sm.j != null
      ? `Theorem 5: j = ${sm.j}, window ${u.window} steps`
      : `window ${u.window} steps${sm.note ? ` — ${richText(sm.note)}` : ''}`;
    ui.timing.textContent = `rendered in ${(st.runMs + st.drawMs).toFixed(1)} ms (run ${st.runMs.toFixed(1)} ms + draw ${st.drawMs.toFixed(1)} ms)`;
  }

  // ----- animation of k -----
  let animating = null;
  function stopAnimation() {
    if (!animating) return;
    clearTimeout(animating.timer);
    animating = null;
    ui.animate.textContent = '▶ animate';
    setBusy(-1);
  }
  function startAnimation() {
    if (animating || !st.report) return;
    setBusy(+1);
    animating = { timer: 0 };
    ui.animate.textContent = '■ stop';
    let k = Number(ui.time.value);
    if (k >= Number(ui.time.max)) k = st.report.ubb.track[0].k - 1;
    const tick = () => {
      if (!animating) return;
      k += 1;
      if (k > Number(ui.time.max)) { stopAnimation(); return; }
      ui.time.value = String(k);
      showTime();
      if (!compute()) { stopAnimation(); return; }
      animating.timer = setTimeout(tick, ANIMATE_MS);
    };
    tick();
  }

  // ----- the guarantee -----
  let running = null;
  const setGBusy = busyFlag('ubbGuaranteeBusy');
  async function runGuarantee() {
    ui['g-err'].textContent = '';
    if (!st.scenario) return;
    let g, total;
    try {
      total = wholeNumber('runs', ui.runs.value);
      g = new Study(JSON.stringify(st.scenario), total);
    } catch (e) {
      ui['g-err'].textContent = e.message;
      return;
    }
    if (running) running.cancelled = true;
    const me = { cancelled: false };
    running = me;
    ui.go.disabled = true;
    ui.cancel.disabled = false;
    setGBusy(+1);
    const k = JSON.parse(g.result()).k;
    const show = (c) => {
      const lvl = Math.round(100 * c.kf_level);
      ui['g-result'].innerHTML = `truth outside the set: <b class="${c.outside ? 'warn' : 'good'}">${int(c.outside)} / ${int(c.runs)}</b>; `
        + `outside the KF ${lvl} % ellipse: <b>${int(c.kf_outside)} / ${int(c.runs)}</b>`
        + (c.runs && Number.isFinite(c.worst_excess) ? ` <span class="hint">(closest approach to the hull’s edge ${fmt(-c.worst_excess)})</span>` : '');
    };
    try {
      const { counts: c, wall, compute: ms } = await runChunked(g, CHUNK, me, (c) => {
        show(c);
        ui['g-status'].textContent = `${int(c.runs)} / ${int(total)} runs at k = ${k}…`;
      });
      show(c);
      ui['g-status'].textContent = me.cancelled
        ? `cancelled after ${int(c.runs)} runs (${wall.toFixed(0)} ms)`
        : `${int(c.runs)} runs at k = ${k} in ${wall.toFixed(0)} ms (computing ${ms.toFixed(0)} ms, ${(ms / Math.max(1, c.runs)).toFixed(2)} ms per run)`;
    } catch (e) {
      ui['g-err'].textContent = e.message;
    } finally {
      g.free();
      if (running === me) {
        running = null;
        ui.go.disabled = false;
        ui.cancel.disabled = true;
      }
      setGBusy(-1);
    }
  }

  // ----- wiring -----
  ui.preset.addEventListener('change', () => { stopAnimation(); loadPreset(ui.preset.value); schedule('compute'); });
  for (const id of ['eps', 'tau', 'delta', 'alpha', 'beta', 'gamma', 'norm', 'seed', 'noise', 'm-F', 'm-G', 'm-H']) {
    ui[id].addEventListener('input', () => schedule('compute'));
  }
  ui.time.addEventListener('input', () => { showTime(); schedule('compute'); });
  ui.animate.addEventListener('click', () => (animating ? stopAnimation() : startAnimation()));
  ui.go.addEventListener('click', () => runGuarantee());
  ui.cancel.addEventListener('click', () => { if (running) running.cancelled = true; });

  // Hi-DPI: refit the backing stores when the layout or the pixel ratio changes (no recompute).
  redrawOnResize(figures, () => schedule('redraw'));

  $('b-dl-report').addEventListener('click', () => {
    if (st.reportJson) download(`${stem()}-report.json`, new Blob([st.reportJson], { type: 'application/json' }));
  });
  $('b-dl-scenario').addEventListener('click', () => {
    if (st.scenario) download(`${stem()}-scenario.json`, new Blob([JSON.stringify(st.scenario, null, 2)], { type: 'application/json' }));
  });

  if (!presets.length) return panelApi(ui.preset, menu);
  ui.preset.value = presets[0].name;
  loadPreset(presets[0].name);
  compute();
  return panelApi(ui.preset, menu, () => st.scenario);
}
