// "One step, step by step": a card under a view's figures that shows one update's quantities
// at the time cursor (SCF/KF: prediction, innovation, gain, update, U_tA_t, the SCF centre;
// LSCR: the sign-perturbed sums at a point), each with the paper's equation number and its
// formula rendered by KaTeX (www/vendor/katex, vendored from npm by .ci/build; loaded the first
// time the card is opened). Every number and verdict comes from the core (Session.explain on the
// kept report); the card only lays them out. Closed, it costs nothing.
import { fmt } from './format.js';
import { escapeHtml } from './richtext.js';

let katexLoaded = null;
function katex() {
  if (!katexLoaded) {
    const css = Object.assign(document.createElement('link'), { rel: 'stylesheet', href: 'vendor/katex/katex.min.css' });
    document.head.append(css);
    katexLoaded = import('./vendor/katex/katex.mjs').then((m) => m.default);
  }
  return katexLoaded;
}

// A row's value as text: a number, a vector (x₁, x₂), a matrix [[…]; […]] or a word.
function valueHtml(v) {
  if (typeof v === 'number') return fmt(v);
  if (typeof v === 'string') return escapeHtml(v);
  if (Array.isArray(v) && v.every((x) => typeof x === 'number')) return `(${v.map(fmt).join(', ')})`;
  if (Array.isArray(v) && v.length === 1 && v[0].length === 1) return fmt(v[0][0]); // a 1 × 1 matrix is a number
  if (Array.isArray(v)) return `<span class="matrix">${v.map((r) => `<span>${r.map(fmt).join('  ')}</span>`).join('')}</span>`;
  return '–';
}

// mountStepCard(p, {after, point}): the card, placed after the element `after`; `point(p)`
// gives LSCR's point ([x, y] in the figure's plane) or undefined for the method's default.
export function mountStepCard(p, { after, point }) {
  const card = document.createElement('details');
  card.className = 'card step-card';
  card.innerHTML = '<summary><b>One step, step by step</b> <span class="hint">the quantities of the update shown, with the paper’s equation numbers</span></summary>'
    + '<p class="step-title"></p><table class="step-rows"><thead><tr><th scope="col">quantity</th><th scope="col">eq.</th>'
    + '<th scope="col">formula</th><th scope="col">value</th></tr></thead><tbody></tbody></table><p class="err" role="alert"></p>';
  after.after(card);
  const [title, body, err] = [card.querySelector('.step-title'), card.querySelector('tbody'), card.querySelector('.err')];
  let time = null;
  let pending = 0;
  async function show() {
    if (!card.open || !p.st.report || !p.st.scenario) return;
    const mine = ++pending;
    const k = await katex();
    if (mine !== pending) return;
    let e;
    try {
      const at = point?.(p);
      e = JSON.parse(p.session.explain(JSON.stringify(p.st.scenario), time ?? undefined, at?.[0], at?.[1]));
    } catch (x) {
      body.replaceChildren();
      title.textContent = '';
      err.textContent = x?.message || String(x);
      card.dataset.t = '';
      return;
    }
    err.textContent = '';
    title.textContent = `${e.title} (${e.paper})`;
    body.innerHTML = e.rows.map((r) => `<tr><th scope="row">${escapeHtml(r.name)}</th><td>${escapeHtml(r.equation)}</td>`
      + `<td class="tex">${k.renderToString(r.tex, { throwOnError: false, output: 'htmlAndMathml' })}</td>`
      + `<td class="num">${valueHtml(r.value)}${r.note ? `<br><span class="hint">${escapeHtml(r.note)}</span>` : ''}</td></tr>`).join('');
    card.dataset.t = String(e.t);
    card.dataset.point = e.point ? e.point.join(' ') : '';
  }
  card.addEventListener('toggle', show);
  return {
    // After each drawing of the view: the step shown (null: the report's own time).
    update(t) { time = t ?? null; show(); },
  };
}
