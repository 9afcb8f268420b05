// Preset descriptions and notes write sub-/superscripts as x_{…} and x^{…}: they are shown as
// HTML, so the text is escaped first and only the markup the panels add is live.

// A check mark for the numbers tables: ✓ `yes`, ✗ `no`, or – when unknown (null).
export const verdict = (b, yes, no) => (b == null ? '–' : b ? `<b class="good">✓ ${yes}</b>` : `<b class="warn">✗ ${no}</b>`);

// Text as HTML that shows it as it is: every string of a report that goes into a numbers table
// (it may carry a name from a loaded scenario) passes through it.
export const escapeHtml = (t) => String(t).replace(/[&<>"']/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' }[c]));

// Escaped text with runs of whitespace folded and the braced _{…} / ^{…} as <sub>/<sup>; each
// panel adds its own unbraced subscripts (their symbols differ).
export const bracedScripts = (t) => escapeHtml(t.replace(/\s{2,}/g, ' '))
  .replace(/_\{([^{}]*)\}/g, '<sub>$1</sub>').replace(/\^\{([^{}]*)\}/g, '<sup>$1</sup>');

// Escaped text with the braced scripts, and each panel's unbraced subscripts (`unbraced`, a
// replacement on escaped text) applied to every word but a file's name: "compare-uniform_lp-t30.json"
// keeps its underscore.
const FILE_NAME = /^["'(\[]*[\w.-]+\.(json|csv|svg|png|zip|txt|html?)["')\].,;:!?]*$/i;
export const withScripts = (t, unbraced) => bracedScripts(t).split(/(\s+)/)
  .map((word) => (FILE_NAME.test(word.replace(/&(quot|#39);/g, '"')) ? word : unbraced(word))).join('');

// 12 → ₁₂ (state components and times in plain text).
const SUB = '₀₁₂₃₄₅₆₇₈₉';
export const sub = (k) => String(k).replace(/\d/g, (d) => SUB[d]);
