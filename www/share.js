// Share links. A panel's state is its preset and the values of its controls (and, for a scenario
// loaded from a file, that scenario): everything the panel's own code turns into the Scenario it
// runs, so restoring the controls reproduces the same scenario, numbers and picture (same seed).
//
//   #<panel>                      the panel with its first preset
//   #<panel>/preset/<name>        the panel with that preset
//   #<panel>/v1/<token>           token = base64url(deflate-raw(JSON {preset, fields, scenario?}))
//   any of them + &present[&panel=<figure>[,<figure>]]   present/embed mode (fragmentOptions)
//
// The fragment, never the query string: static hosts answer long queries with 414. Every version
// ever emitted keeps a decoder in DECODERS; a renamed preset keeps an alias in PRESET_ALIASES.
import { int } from './format.js';

export const MAX_LINK_CHARS = 32_000;
export const LINK_VERSION = 'v1';
export const PRESET_ALIASES = {};

const toBase64Url = (bytes) => {
  let s = '';
  for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(s).replace(/\+/g, '-').replace(/\//g, '_').replace(/=+$/, '');
};
const fromBase64Url = (text) => {
  if (!/^[A-Za-z0-9_-]*$/.test(text)) throw new Error('it holds characters a link token never has');
  const b = atob(text.replace(/-/g, '+').replace(/_/g, '/') + '==='.slice((text.length + 3) % 4));
  return Uint8Array.from(b, (c) => c.charCodeAt(0));
};

async function pipe(bytes, stream) {
  const out = new Blob([bytes]).stream().pipeThrough(stream);
  return new Uint8Array(await new Response(out).arrayBuffer());
}

export async function encodeState(state) {
  const json = new TextEncoder().encode(JSON.stringify(state));
  return toBase64Url(await pipe(json, new CompressionStream('deflate-raw')));
}

const DECODERS = {
  async v1(token) {
    // Damaged tokens are said in words: the browser's own texts ("Failed to fetch", "Failed to
    // execute 'atob'…", "Unexpected token…") mean nothing to the reader of a link.
    const damaged = (what) => new Error(`its data are damaged: ${what} (part of the link was cut or changed when it was copied)`);
    let raw;
    try {
      raw = fromBase64Url(token);
    } catch {
      throw damaged('the token is not the text a link token is made of');
    }
    let bytes;
    try {
      bytes = await pipe(raw, new DecompressionStream('deflate-raw'));
    } catch {
      throw damaged(`its ${int(token.length)}-character token does not unpack`);
    }
    let state;
    try {
      state = JSON.parse(new TextDecoder().decode(bytes));
    } catch {
      throw damaged('what it unpacks to is not a panel\'s settings');
    }
    if (!state || typeof state !== 'object' || typeof state.preset !== 'string' || typeof state.fields !== 'object') {
      throw new Error('it does not describe a panel');
    }
    return state;
  },
};

// A fragment's display options after the link proper, each after a "&" (a token, a preset
// name encoded with encodeURIComponent and a view id never hold one):
//   &present              present mode: the figure, the animation's controls and a title only
//   &panel=<a>[,<b>]      the figure(s) present mode shows (the core's panel names)
// → { present, panels, suffix } where suffix is the options' text as given ("" for none), kept
// on the fragment when the page rewrites the link part.
export function fragmentOptions(hash) {
  const [, ...opts] = hash.replace(/^#/, '').split('&');
  const present = opts.includes('present');
  const panel = opts.find((o) => o.startsWith('panel='));
  let names = '';
  try { names = panel ? decodeURIComponent(panel.slice(6)) : ''; } catch { names = ''; }
  const panels = names.split(',').map((x) => x.trim()).filter(Boolean).slice(0, 2);
  return { present, panels, suffix: opts.length ? `&${opts.join('&')}` : '' };
}

// The route of a fragment: { id, state?, preset?, error?, present, panels, suffix } (the display
// options: fragmentOptions). `id` is '' for the landing view.
export async function parseFragment(hash) {
  const options = fragmentOptions(hash);
  const link = hash.replace(/^#/, '').split('&')[0];
  const route = await parseLink(link);
  return { ...route, ...options };
}

async function parseLink(link) {
  const parts = link.split('/');
  const id = parts[0].replace(/-(head|section)$/, ''); // old in-page anchors
  if (parts.length === 1) return { id };
  if (parts[1] === 'preset' && parts.length === 3) {
    const name = decodeURIComponent(parts[2]);
    return { id, preset: PRESET_ALIASES[name] || name };
  }
  const decode = DECODERS[parts[1]];
  if (!decode || parts.length !== 3) {
    return { id, error: `this link has a format this page does not know (“${parts.slice(1).join('/').slice(0, 24)}”)` };
  }
  if (link.length + 1 > MAX_LINK_CHARS) return { id, error: `this link is longer than ${int(MAX_LINK_CHARS)} characters` };
  try {
    const state = await decode(parts[2]);
    state.preset = PRESET_ALIASES[state.preset] || state.preset;
    return { id, state };
  } catch (e) {
    return { id, error: `this link could not be read: ${e.message}` };
  }
}

// ----- the controls of a panel -----

// The panel's controls with an id, in document order (file pickers and buttons excluded).
const controls = (root) => [...root.querySelectorAll('form input[id], form select[id], form textarea[id]')]
  .filter((el) => el.type !== 'file' && el.type !== 'button' && el.type !== 'submit');
const valueOf = (el) => (el.type === 'checkbox' ? String(el.checked) : el.value);

export function captureFields(root, presetId) {
  const fields = {};
  for (const el of controls(root)) if (el.id !== presetId) fields[el.id] = valueOf(el);
  return fields;
}

function setControl(el, value) {
  if (valueOf(el) === value) return false;
  if (el.type === 'checkbox') el.checked = value === 'true'; else el.value = value;
  el.dispatchEvent(new Event('input', { bubbles: true }));
  el.dispatchEvent(new Event('change', { bubbles: true }));
  return true;
}

// Resolves once the panel holds no compute (its busy flag clear; a scheduled compute sets it at once).
export function idle(busyKey) {
  return new Promise((resolve) => {
    const check = () => (document.body.dataset[busyKey] ? requestAnimationFrame(check) : resolve());
    check();
  });
}

// Put `fields` into the panel's controls, all at once (one compute); then, once the panel has
// computed, the sliders again where their range only now admits the value (the report sets it).
// A control is only touched when its value differs, so one that follows another (an
// "automatic" horizon) is kept.
export async function restoreFields(root, fields, busyKey) {
  const els = controls(root).filter((el) => el.id in fields);
  for (const el of els) setControl(el, String(fields[el.id]));
  await idle(busyKey);
  let moved = false;
  for (const el of els.filter((e) => e.type === 'range')) moved = setControl(el, String(fields[el.id])) || moved;
  if (moved) await idle(busyKey);
  // Fields that no control of this panel has (a link from a later page version) are reported.
  return Object.keys(fields).filter((k) => !els.some((el) => el.id === k));
}
