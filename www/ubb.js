// The set-membership panel (Tempo, method "ubb"): controls → Scenario JSON → a run in the compute worker →
// two figures drawn by the core (views {"panel": "ubbset" | "ubbwidth"}) and the numbers of the
// report (report.ubb). The step k is a time cursor (cursor.js): the report keeps the exact polygon,
// hull and prediction of one step (its `at`); moving k draws the kept report with the detail of k,
// which the compute worker computes once per step (the scenario's ubb.time follows k, so a run,
// a download or a link gives the same picture). The read-out puts Theorem 2's linear optimal
// estimate (the report's at.linear) beside the central one. The true noise (ubb.sim_eps,
// ubb.sim_tau: what the simulation draws) is set apart from the assumed bounds ε, τ. The guarantee
// runs fresh simulations with the true noise on every core (studypool.js) and counts how often
// the truth left the set of the assumed bounds (never, while the true noise is within them) and
// the KF ellipse. The report holds two sets per step, the predicted X(k+1 | y(0 … k)) and the
// filtered X(k | y(0 … k)); the "set drawn" control (ubb.set) chooses which the figures and the
// read-out show. The report's warnings (gaps of a record, the Kalman comparison's assumption)
// are shown above the figures by the panel skeleton (panel.js), as for every panel.
// No estimation happens here: the page edits the preset's scenario and shows what the core says.
import { Study, ellipsoidLevel } from './pkg/confset.js';
import { mountPanel } from './panel.js';
import { Figure } from './figure.js';
import { studyRunner, busyFlag } from './chunked.js';
import { parseNumber, parseVector, wholeNumber } from './parse.js';
import { withScripts, verdict, sub, escapeHtml } from './richtext.js';
import { fmt, vec, int } from './format.js';
import { timeOf, recordTime } from './cursor.js';

const NORM = { linf: 'l∞', l1: 'l₁', l2: 'l₂' };

// The custom mode is one more "preset" whose model comes from the text boxes.
const CUSTOM_PRESET = {
  name: 'custom',
  description: 'Your own A, B, C: x(k+1) = A x(k) + B u(k), y(k) = C x(k) + η(k) with |u| ≤ τ, |η| ≤ ε; every change is validated and run at once.',
  scenario: {
    method: 'ubb', title: 'Custom model',
    model: { F: [[0.9, 0.2], [-0.1, 0.8]], G: [[1], [0.5]], H: [[1, 0]] },
    simulate: { steps: 50, seed: 1 },
    // A window of its own: ‖A‖·exp(1/α) > 1 here, so Theorem 5 gives no j (issue 29: the
    // custom model was refused by default).
    ubb: { eps: 0.2, tau: 0.1, delta: [2], alpha: 50, beta: 50, gamma: 0.1, window: 20, time: 40 },
    notes: 'A stable 2-state system with one bounded noise input and one measured output. The set of states consistent '
      + 'with the data and the bounds is a polygon drawn by support LPs; it holds the true state at every step '
      + 'as long as the simulated noise stays within ε and τ.',
  },
};

const richText = (t) => withScripts(t, (w) => w.replace(/(\p{L}[\u0300-\u036f]?)_([\p{L}\d]+)/gu, '$1<sub>$2</sub>'));

// The set panel reads plane coordinates, the width panel steps (whole numbers) and values.
class UbbFigure extends Figure {
  stacked = true;

  cursorText({ chart, x, y }) {
    const set = this.panel === 'ubbset';
    const k = Math.round(x);
    return `${set ? `${chart.x_label} = ${fmt(x)}` : `k = ${k}${recordTime(this.report, k, true)}`}, ${chart.y_label || 'y'} = ${fmt(y)}`;
  }
}

// ----- controls ⇄ scenario -----
const text = (v) => (v == null ? '' : Array.isArray(v) ? (v.every((x) => x === v[0]) ? String(v[0]) : v.join(' ')) : String(v));

function load(p, s) {
  const { ui } = p;
  const u = s.ubb;
  ui.eps.value = u.eps;
  ui.tau.value = u.tau ?? 0;
  ui.delta.value = text(u.delta);
  ui.alpha.value = text(u.alpha);
  ui.beta.value = text(u.beta);
  ui.gamma.value = u.gamma ?? 0.1;
  ui.window.value = u.window ?? '';
  ui.norm.value = u.norm || 'linf';
  ui.set.value = u.set || 'predicted';
  ui.noise.checked = u.noise === 'bound';
  ui.seed.value = s.simulate?.seed ?? 0;
  // The true noise (simulated) apart from the assumed bounds ε, τ: the preset's unless it says.
  ui['sim-eps'].value = u.sim_eps ?? u.eps;
  ui['sim-tau'].value = u.sim_tau ?? u.tau ?? 0;
  ui['true-noise'].hidden = !s.simulate;
  const steps = s.simulate?.steps ?? s.data?.y?.length ?? 1;
  ui.time.min = '0';
  ui.time.max = String(steps - 1);
  ui['time-max'].textContent = String(steps - 1);
  ui.time.value = String(u.time ?? steps - 1);
  ui['g-result'].textContent = '';
  ui['g-status'].textContent = '';
  showSim(p);
  showTime(p);
}

// Whether the true (simulated) noise exceeds the bounds the estimator assumes, from a scenario.
const exceeds = (s) => {
  const u = s?.ubb;
  if (!u || !s.simulate) return false;
  return (u.sim_eps ?? u.eps) > u.eps || (u.sim_tau ?? u.tau ?? 0) > (u.tau ?? 0);
};
const NO_GUARANTEE = 'the noise exceeds the bounds the estimator assumes: no guarantee';

// The line under the true noise: within the assumed bounds or not (from the controls' numbers).
function showSim({ ui }) {
  const [e, t, se, stau] = ['eps', 'tau', 'sim-eps', 'sim-tau'].map((id) => Number(ui[id].value));
  const over = [se > e ? `|η| ≤ ${fmt(se)} > ε = ${fmt(e)}` : '', stau > t ? `|u| ≤ ${fmt(stau)} > τ = ${fmt(t)}` : ''].filter(Boolean);
  ui['sim-out'].innerHTML = over.length
    ? `<b class="warn">${NO_GUARANTEE}</b> (${over.join(', ')}): the set may lose the truth, or the data contradict the bounds`
    : 'within the assumed bounds: the set holds the truth at every step';
}

function showTime({ ui, st }) {
  const k = Number(ui.time.value);
  ui['time-out'].textContent = `= ${k}${recordTime(st.report, k, true)}`;
  const u = st.report?.ubb;
  ui['time-window'].textContent = u && u.at.k === k ? `window y(${u.at.first}) … y(${k})` : '';
  // The cursor's first step (the core's: the first with a bounded set; an earlier k shows it).
  if (u) ui['time-min'].textContent = String(st.cursorSteps[0]);
}

// An optional positive number: empty (or ∞, inf) = ∞ (null).
const infinite = (t) => ['', '∞', 'inf', 'infinity'].includes(String(t).trim().toLowerCase());
const optional = (field, t) => (infinite(t) ? null : parseNumber(field, t));

function build(p, s) {
  const { ui, st } = p;
  if (p.isCustom()) Object.assign(s.model, p.model());
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
  if (ui.window.value.trim() === '') delete u.window;
  else u.window = wholeNumber('ubb.window', ui.window.value);
  u.norm = ui.norm.value;
  if (ui.set.value === 'filtered') u.set = 'filtered';
  else delete u.set;
  u.noise = ui.noise.checked ? 'bound' : 'random';
  u.time = wholeNumber('ubb.time', ui.time.value);
  // The true noise the simulation draws, apart from ε and τ (the bounds the estimator assumes):
  // above them the data may contradict the bounds, or the set lose the truth.
  if (s.simulate) {
    u.sim_eps = parseNumber('ubb.sim_eps', ui['sim-eps'].value);
    u.sim_tau = parseNumber('ubb.sim_tau', ui['sim-tau'].value);
  } else {
    delete u.sim_eps;
    delete u.sim_tau;
  }
  if (s.simulate) s.simulate.seed = wholeNumber('simulate.seed', ui.seed.value);
}

// ----- numbers from the report -----
// The numbers at step k: the report's detail of k once it is here (until then, what the track
// holds for every step, and the rest marked as being computed).
function showNumbers({ ui, st }, k) {
  const u = st.report.ubb;
  // The set drawn (ubb.set): the predicted one (the step's own fields) or the filtered one
  // (their `filtered` parts); `lag` is the state's time after k.
  const filtered = u.set === 'filtered';
  const lag = filtered ? 0 : 1;
  const pick = (x) => (x && filtered ? x.filtered || null : x);
  const detail = u.at.k === k ? u.at : null;
  const at = pick(detail);
  const step = pick(u.track.find((t) => t.k === k));
  const hull = at || step;
  if (!hull) {
    ui['num-title'].textContent = `At step k = ${k}${recordTime(st.report, k, true)}`;
    ui.numbers.textContent = `No bounded ${filtered ? 'filtered ' : ''}set at step k = ${k}.`;
    return;
  }
  const [i, j] = u.plane;
  const sm = u.smoothing;
  const pending = '… <span class="hint">(being computed)</span>';
  // Example 1's state is the coefficient vector a: the report names it ("a₁ (1)", …).
  const names = (u.state_names || hull.lo.map((_, c) => `x${sub(c + 1)}`)).map(escapeHtml);
  const coef = !names[0].startsWith('x');
  const target = coef ? 'the coefficients a' : `x(${k + lag})`;
  ui['num-title'].textContent = `At step k = ${k}${recordTime(st.report, k, true)}: the ${filtered ? 'filtered ' : ''}set of ${target}${detail ? ` from y(${detail.first}) … y(${k})` : ''}, ${NORM[u.norm] || u.norm} bounds`;
  const rows = [];
  const row = (a, b) => rows.push(`<tr><th>${a}</th><td>${b}</td></tr>`);
  row('window', `${u.window} ${u.window === 1 ? 'step' : 'steps'}${detail ? ` <span class="hint">(data y(${detail.first}) … y(${k}))</span>` : ''}`);
  const cones = detail?.size.cones ? `, ${detail.size.cones} cones (${detail.size.cone_rows} rows)` : '';
  row('LP size', detail ? `${detail.size.variables} variables, ${detail.size.rows} rows${cones}` : pending);
  if (u.r === 1) row('set', `an interval <span class="hint">(one state: drawn over the steps as a band)</span>`);
  else row('polygon', at ? `${at.polygon.vertices.length} vertices from ${at.polygon.calls} LPs — ${at.polygon.exact
    ? '<b class="good">exact</b>' : `within ${fmt(at.polygon.gap)} of the set`}${u.r > 2 ? ` <span class="hint">(projection on x${sub(i + 1)}, x${sub(j + 1)})</span>` : ''}` : pending);
  row('estimates', estimates(u, at, hull, names));
  if (at?.linear) row('Theorem 2 active rows', activeRows(at.linear, names, u));
  row('interval hull', hull.lo.map((lo, c) => `<span class="nw">${names[c]} ∈ [${fmt(lo)}, ${fmt(hull.hi[c])}]</span>`).join(' '));
  // The other set of the same step, for comparison.
  const other = filtered ? (detail || u.track.find((t) => t.k === k)) : (detail?.filtered || u.track.find((t) => t.k === k)?.filtered);
  if (other) {
    row(filtered ? `predicted set of x(${k + 1})` : `filtered set of x(${k})`,
      other.lo.map((lo, c) => `<span class="nw">${names[c]} ∈ [${fmt(lo)}, ${fmt(other.hi[c])}]</span>`).join(' '));
  }
  row('radius', `${fmt(hull.radius)} <span class="hint">(largest half-width: the guaranteed error of the central estimate)</span>`);
  row('Theorem 4 bound', sm.limit != null ? `${fmt(sm.limit)} <span class="hint">(on the radius; ‖A‖e<sup>1/α</sup> = ${fmt(sm.ratio)})</span>`
    : `– <span class="hint">(‖A‖e<sup>1/α</sup> = ${fmt(sm.ratio)}${sm.b_norm === 0 ? ', no process noise' : ' ≥ 1'})</span>`);
  row('Theorem 5 j', sm.j != null ? `${sm.j} <span class="hint">(γ = ${fmt(u.gamma)}: window j + 1 = ${sm.j + 1}${sm.tail != null ? `, tail ${fmt(sm.tail)}` : ''})</span>`
    : `– <span class="hint">${sm.note ? richText(sm.note) : ''}</span>`);
  const truth = u.x_true ? u.x_true[k + lag] : null;
  row(coef ? 'true a' : `true x(${k + lag})`, truth ? vec(truth) : '– (data given)');
  row('truth inside the set', `${verdict(step?.inside, 'yes', 'no')}${step?.inside === false
    ? ' <span class="hint">(ε or τ below the simulated noise: the bounds are wrong, so no guarantee)</span>' : ''}`);
  const kfLevel = Math.round(100 * ellipsoidLevel(JSON.stringify(u.at.kf))); // ubb.kf_level: the same at every step (its own dimension)
  row(`truth inside the KF ${kfLevel} % ellipsoid`, verdict(step?.kf_inside, 'yes', 'no'));
  if (!detail) {
    row(`prediction of y(${k + 1})`, pending);
  } else if (detail.prediction.length) {
    row(`prediction of y(${k + 1})`, detail.prediction.map(([lo, hi], o) => `<span class="nw">${detail.prediction.length > 1 ? `y${sub(o + 1)} ` : ''}∈ [${fmt(lo)}, ${fmt(hi)}]</span>`).join(' '));
  } else {
    row(`prediction of y(${k + 1})`, '– <span class="hint">(no measurements)</span>');
  }
  const counted = filtered ? u.track.filter((t) => t.filtered).length : u.track.length;
  const [out, kfOut] = filtered ? [u.filtered_outside, u.filtered_kf_outside] : [u.outside, u.kf_outside];
  row('over the run', `truth outside the set ${out} / ${counted} steps, outside the KF ellipsoid ${kfOut} / ${counted}`
    + (exceeds(st.scenario) ? ` <span class="hint">(<b class="warn">${NO_GUARANTEE}</b>)</span>` : ''));
  ui.numbers.innerHTML = `<table class="est"><tbody>${rows.join('')}</tbody></table>`;
  ui['window-out'].innerHTML = sm.j != null
    ? `Theorem 5: j = ${sm.j}, window ${u.window} steps`
    : `window ${u.window} steps${sm.note ? ` — ${richText(sm.note)}` : ''}`;
}

// The central estimate (31) with its half-widths, and Theorem 2's linear optimal estimate (25)
// with its error E(φ₀) (22), in the plane components (the report's numbers).
function estimates(u, at, hull, names) {
  const comps = u.r === 1 ? [0] : u.plane; // one state: its plane is [0, 0]
  const half = (c) => 0.5 * (hull.hi[c] - hull.lo[c]);
  const pm = (v, e) => `${fmt(v)} ± ${fmt(e)}`;
  const value = (c, v, e) => `<span class="nw">${names[c]} = ${pm(v, e)}</span>`;
  const central = `central (strongly optimal, (31)): ${comps.map((c) => value(c, hull.center[c], half(c))).join(', ')}`;
  let linear;
  if (u.norm !== 'linf') linear = 'linear optimal (Theorem 2): – <span class="hint">(needs l∞ bounds)</span>';
  else if (at?.linear_refused) linear = `linear optimal (Theorem 2): – <span class="hint">(${escapeHtml(at.linear_refused)})</span>`;
  else if (!at?.linear) linear = 'linear optimal (Theorem 2): … <span class="hint">(being computed)</span>';
  else {
    linear = `linear optimal (Theorem 2): ${at.linear.map((l) => value(l.component, l.estimate, l.error)).join(', ')}`;
  }
  return `${central};<br>${linear}`;
}

// "3–7, 9": whole numbers in runs.
const runs = (ts) => {
  const out = [];
  for (let a = 0; a < ts.length;) {
    let b = a;
    while (b + 1 < ts.length && ts[b + 1] === ts[b] + 1) b += 1;
    out.push(b > a ? `${ts[a]}–${ts[b]}` : `${ts[a]}`);
    a = b + 1;
  }
  return out.join(', ');
};

// The active constraints t₁ … t_n of (22) per component, by the bound they come from:
// measurements η(t) (46), process noise u(t) (45), the box of the window's first state, Σx(0).
function activeRows(linear, names, u) {
  const what = (a) => ({
    measurement: `η${u.q > 1 ? sub(a.index + 1) : ''}(t)`,
    process: `u${u.p > 1 ? sub(a.index + 1) : ''}(t)`,
    prior: `the box of x${sub(a.index + 1)}(t)`,
    sum: 'Σx(0) = its sum',
  })[a.kind] || a.kind;
  return linear.map((l) => {
    const groups = new Map();
    for (const a of l.active) {
      const key = what(a);
      if (!groups.has(key)) groups.set(key, []);
      groups.get(key).push(a.t);
    }
    const parts = [...groups].map(([key, ts]) => (key.includes('(t)') ? key.replace('(t)', ` at t = ${runs(ts)}`) : key));
    return `${names[l.component]}: ${parts.join('; ')} <span class="hint">(${l.active.length} rows)</span>`;
  }).join('<br>');
}

// ----- the guarantee: fresh simulations at the step k of the last good scenario -----
function startGuarantee({ ui, st }) {
  if (!st.scenario) return null;
  const total = wholeNumber('runs', ui.runs.value);
  const json = JSON.stringify(st.scenario);
  const study = new Study(json, total);
  st.guaranteeScenario = st.scenario;
  const k = JSON.parse(study.result()).k;
  return { scenario: json, runs: total, study, total, at: ` at k = ${k}`, note: '…' };
}

function showGuarantee({ ui, st }, c) {
  const lvl = Math.round(100 * c.kf_level);
  ui['g-result'].innerHTML = `truth outside the set: <b class="${c.outside ? 'warn' : 'good'}">${int(c.outside)} / ${int(c.runs)}</b>`
    + (c.empty ? ` <span class="hint">(${int(c.empty)} of them: the data contradict the bounds, no set)</span>` : '')
    + `; outside the KF ${lvl} % ellipse: <b>${int(c.kf_outside)} / ${int(c.runs)}</b>`
    + (c.runs && !c.empty && Number.isFinite(c.worst_excess) ? ` <span class="hint">(closest approach to the hull’s edge ${fmt(-c.worst_excess)})</span>` : '')
    + (exceeds(st.guaranteeScenario) ? ` — <b class="warn">${NO_GUARANTEE}</b>` : '');
}

export const mountUbb = async (root, presets) => mountPanel(root, {
  presets,
  custom: CUSTOM_PRESET,
  prefix: 'b-',
  busy: 'ubbBusy',
  Figure: UbbFigure,
  model: ['F', 'G', 'H'],
  prose: richText,
  ids: ['time-out', 'time-min', 'time-max', 'time-window', 'sim-out', 'true-noise', 'window-out', 'num-title',
    'runs', 'go', 'cancel', 'g-status', 'g-result', 'g-err'],
  compute: ['eps', 'tau', 'sim-eps', 'sim-tau', 'delta', 'alpha', 'beta', 'gamma', 'window', 'norm', 'set', 'seed', 'noise', 'm-F', 'm-G', 'm-H'],
  redraw: ['time'],
  cursor: timeOf('ubb'),
  input: (p, id) => {
    if (id === 'time') showTime(p);
    if (['eps', 'tau', 'sim-eps', 'sim-tau'].includes(id)) showSim(p);
  },
  stem({ st, cursorTime }) {
    const u = st.report?.ubb;
    return `${st.preset.name}-${u ? `${u.norm}-k${cursorTime()}` : 'ubb'}`;
  },
  init(p) {
    const { ui } = p;
    studyRunner({
      go: ui.go, cancel: ui.cancel, status: ui['g-status'], err: ui['g-err'],
      busy: busyFlag('ubbGuaranteeBusy'), start: () => startGuarantee(p), show: (c) => showGuarantee(p, c),
      perRun: (ms, runs) => `${(ms / Math.max(1, runs)).toFixed(2)} ms`,
    });
  },
  load,
  build,
  stepCard: {}, // the window, hull, central estimate and Theorem 2's active constraints at k
  draw(p, k) {
    showTime(p);
    showNumbers(p, k);
  },
});
