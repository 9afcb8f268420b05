// The shell: load the wasm module, route the fragment to one view (the landing view or one panel
// of the registry), mount a panel on its first visit only, and keep its share link, scenario
// import and reset. The page computes nothing itself: every number and every picture comes from
// ./pkg/confset.js through the panels.
import * as confset from './pkg/confset.js';
import { load } from './wasm.js';
import { PANELS, panelById, panelOf } from './registry.js';
import { int } from './format.js';
import { parseFragment, fragmentOptions, encodeState, captureFields, restoreFields, idle, MAX_LINK_CHARS, LINK_VERSION } from './share.js';
import { mountTries } from './trylist.js';

// No form submits (Enter in a field must not reload the page); a listener, not an inline
// handler, so the page runs under a strict Content-Security-Policy.
for (const form of document.querySelectorAll('form')) form.addEventListener('submit', (e) => e.preventDefault());

// ----- the shell's menu and views, from the registry (index.html holds only the frame) -----

// The menu's links and one section per panel, after the landing view: heading, paragraph and
// the empty root its view's markup goes into on the first visit. Rendered before anything
// looks them up (this module runs once the document is parsed).
function renderShell() {
  const nav = document.querySelector('nav.routes');
  nav.replaceChildren(...PANELS.map((d) => {
    const a = document.createElement('a');
    a.href = `#${d.id}`;
    a.dataset.route = d.id;
    a.textContent = d.nav;
    return a;
  }));
  document.getElementById('app').append(...PANELS.map((d) => {
    const section = document.createElement('section');
    section.id = `${d.id}-section`;
    section.className = 'view';
    section.setAttribute('aria-label', d.label);
    section.hidden = true;
    section.innerHTML = `<header class="section-head" id="${d.id}-head"><h2>${d.heading}</h2>`
      + `<p class="sub">${d.sub}</p></header><div id="${d.id}" class="panel"></div>`;
    return section;
  }));
}
renderShell();

const status = document.getElementById('status');
const views = [document.getElementById('home'), ...PANELS.map((d) => d.section())];
const mounted = new Map(); // id → Promise of the panel's API
let presets = [];
let current = null; // the descriptor shown, or null for the landing view
let navigating = 0; // > 0 while the shell itself sets the fragment or restores a panel

// ----- the toolbar every panel view gets: link, scenario file, reset, undo -----

function toolbar(d) {
  const bar = document.createElement('div');
  bar.className = 'toolbar';
  bar.innerHTML = `
    <button type="button" data-act="link">Copy link</button>
    <button type="button" data-act="embed" title="an iframe of this view in present mode, for slides or a web page">Copy embed code</button>
    <label class="file-btn"><input type="file" accept=".json,application/json" data-act="file"><span>Load scenario file…</span></label>
    <label class="file-btn"><input type="file" accept=".csv,.tsv,.txt,text/csv,text/plain" data-act="csv"><span>Load data (CSV)…</span></label>
    <button type="button" data-act="paste" aria-expanded="false">Paste data…</button>
    <button type="button" data-act="reset">Reset to preset</button>
    <button type="button" data-act="undo" hidden>Undo load</button>
    <span class="share-status" role="status" aria-live="polite"></span>
    <p class="banner" role="alert" hidden></p>
    <label class="embed-box row" hidden>Embed code <span class="hint">copy it into a web page or slides</span>
      <textarea rows="3" readonly spellcheck="false" data-act="embed-text"></textarea></label>
    <div class="data-box card" hidden>
      <label class="row">Measured data <span class="hint">one row per time: columns y1 … yq, then u1 … ur;
        a header row is optional (a column named year, time or date is the record's time); comma,
        semicolon, tab or spaces; an empty, NA or #N/A cell is a gap</span>
        <textarea rows="6" spellcheck="false" data-act="csv-text"></textarea></label>
      <p class="hint data-shape"></p>
      <p class="err data-err" role="alert"></p>
      <div class="data-columns"></div>
      <div class="data-preview"></div>
      <p><button type="button" class="go" data-act="use-data">Run on these data</button></p>
    </div>`;
  const head = d.section().querySelector('.section-head');
  head.after(bar);
  const q = (a) => bar.querySelector(`[data-act=${a}]`);
  const say = (msg) => { bar.querySelector('.share-status').textContent = msg; };
  d.say = say;
  d.banner = (msg) => { const b = bar.querySelector('.banner'); b.textContent = msg || ''; b.hidden = !msg; };
  q('link').addEventListener('click', async () => {
    const link = await linkOf(d);
    if (!link) return;
    try {
      await navigator.clipboard.writeText(link);
      say(`link copied (${int(link.length)} characters)`);
    } catch {
      say(`copy this link: ${link}`);
    }
  });
  // The view in present mode, as an iframe for a web page or slides.
  q('embed').addEventListener('click', async () => {
    const link = await linkOf(d);
    if (!link) return;
    const code = `<iframe src="${link.replace(/"/g, '%22')}&present" width="960" height="540" style="border:0" allowfullscreen></iframe>`;
    const box = bar.querySelector('.embed-box');
    const area = q('embed-text');
    area.value = code;
    try {
      await navigator.clipboard.writeText(code);
      box.hidden = true;
      say('embed code copied: paste it into a web page or slides to show this view in present mode');
    } catch {
      box.hidden = false;
      area.focus();
      area.select();
      say('the clipboard is not available here: copy the embed code from the box below');
    }
  });
  q('file').addEventListener('change', async (e) => {
    const file = e.target.files[0];
    e.target.value = '';
    if (file) await loadScenarioFile(file);
  });
  q('csv').addEventListener('change', async (e) => {
    const file = e.target.files[0];
    e.target.value = '';
    if (file) await loadDataFile(d, file);
  });
  const box = bar.querySelector('.data-box');
  q('paste').addEventListener('click', async () => {
    box.hidden = !box.hidden;
    q('paste').setAttribute('aria-expanded', String(!box.hidden));
    if (!box.hidden) {
      await dataHint(d);
      q('csv-text').focus();
    }
  });
  q('use-data').addEventListener('click', () => useData(d, q('csv-text').value, 'pasted'));
  d.dataBox = {
    show(msg, preview) {
      box.hidden = false;
      box.querySelector('.data-err').textContent = msg || '';
      box.querySelector('.data-preview').replaceChildren(...(preview ? [preview] : []));
    },
    hint(text) { box.querySelector('.data-shape').textContent = text; },
    // The column picker (columnPicker), or none.
    picker(el) { box.querySelector('.data-columns').replaceChildren(...(el ? [el] : [])); },
    clear() {
      box.querySelector('.data-err').textContent = '';
      box.querySelector('.data-columns').replaceChildren();
      box.querySelector('.data-preview').replaceChildren();
      box.hidden = true;
      q('paste').setAttribute('aria-expanded', 'false');
    },
  };
  q('reset').addEventListener('click', async () => {
    const api = await mounted.get(d.id);
    d.banner('');
    // Measured data are not a preset: reset drops them and goes back to the preset they were
    // run with (or the view's first), its own data or simulation.
    const sel = api.presetSelect;
    const onData = sel.value.startsWith('data:');
    if (onData) {
      const real = [...sel.options].map((o) => o.value).filter((v) => !/^(data|file):/.test(v));
      const before = d.beforeLoad && d.beforeLoad.preset;
      sel.value = real.includes(before) ? before : real[0];
      d.dataBox.clear();
      q('undo').hidden = true;
    }
    sel.dispatchEvent(new Event('change', { bubbles: true }));
    say(onData ? `reset to the preset “${sel.selectedOptions[0]?.textContent ?? sel.value}”: the measured data are set aside` : 'reset to the preset');
  });
  q('undo').addEventListener('click', async () => {
    if (!d.beforeLoad) return;
    await restore(d, d.beforeLoad);
    d.beforeLoad = null;
    q('undo').hidden = true;
    say('the scenario before the load is back');
  });
  d.showUndo = () => { q('undo').hidden = false; };
  // Drop a scenario file anywhere on the view.
  const section = d.section();
  section.addEventListener('dragover', (e) => { e.preventDefault(); section.classList.add('drop'); });
  section.addEventListener('dragleave', () => section.classList.remove('drop'));
  section.addEventListener('drop', async (e) => {
    e.preventDefault();
    section.classList.remove('drop');
    const file = e.dataTransfer.files[0];
    if (file && /\.(csv|tsv|txt)$/i.test(file.name)) await loadDataFile(d, file);
    else if (file) await loadScenarioFile(file);
  });
}

// ----- the user's measured data (CSV), parsed by the core -----

const MAX_DATA_BYTES = 20e6;

async function dataHint(d) {
  const api = await mounted.get(d.id);
  try {
    const { outputs, inputs } = JSON.parse(confset.dataShape(JSON.stringify(api.scenario())));
    const names = (c, k) => (k === 1 ? `${c}1` : `${c}1 … ${c}${k}`);
    d.dataBox.hint(`This model: q = ${outputs} output${outputs === 1 ? '' : 's'} (${names('y', outputs)})`
      + `${inputs ? ` and r = ${inputs} input${inputs === 1 ? '' : 's'} (${names('u', inputs)})` : ', no inputs'}.`);
  } catch {
    d.dataBox.hint('');
  }
}

async function loadDataFile(d, file) {
  if (file.size > MAX_DATA_BYTES) {
    d.dataBox.show(`${file.name} is ${(file.size / 1e6).toFixed(1)} MB: data files have at most ${MAX_DATA_BYTES / 1e6} MB`);
    return;
  }
  const text = await file.text();
  d.section().querySelector('[data-act=csv-text]').value = text.length > 200_000 ? '' : text;
  await useData(d, text, file.name);
}

// The first rows of the data the core read, and their shape: a gap (null) shows as "—", the
// record's own time (data.t) in its own column.
function dataPreview(data) {
  const y = data.y, u = data.u || [], times = data.t || [];
  const q = y[0]?.length ?? 0, r = u[0]?.length ?? 0;
  const t = document.createElement('table');
  t.className = 'preview';
  const head = (times.length ? ['time'] : []).concat([...Array(q)].map((_, i) => `y${i + 1}`), [...Array(r)].map((_, i) => `u${i + 1}`));
  const cell = (v) => (v === null ? '<td title="gap: not measured">—</td>' : `<td>${+v.toPrecision(6)}</td>`);
  const time = (i) => (times.length ? `<td>${escapeHtml(String(times[i]))}</td>` : '');
  t.innerHTML = `<caption>${y.length} row${y.length === 1 ? '' : 's'} · ${q} output${q === 1 ? '' : 's'}${r ? ` · ${r} input${r === 1 ? '' : 's'}` : ''}</caption>`
    + `<thead><tr><th>row</th>${head.map((h) => `<th>${h}</th>`).join('')}</tr></thead><tbody>${
      y.slice(0, 5).map((row, i) => `<tr><th>${i + 1}</th>${time(i)}${row.concat(u[i] || []).map(cell).join('')}</tr>`).join('')
    }${y.length > 5 ? `<tr><td colspan="${head.length + 1}">…</td></tr>` : ''}</tbody>`;
  return t;
}

const escapeHtml = (s) => s.replace(/[&<>"']/g, (c) => `&#${c.charCodeAt(0)};`);

// When a file with a header is refused (its names are not the model's: year,flow,rain), a
// picker of its columns: one labelled select per output y1 … yq (each defaulting to the next
// column that is not the record's time, as the core's csvColumns names it) and per input
// u1 … ur (optional: none or all), and a button that reads the file again with that choice.
// The core decides everything else: a bad choice is its error, shown by the data box.
function columnPicker(d, text, name, header, shape, chosen) {
  const { columns, time } = header;
  const box = document.createElement('fieldset');
  box.className = 'column-picker';
  const legend = document.createElement('legend');
  legend.textContent = `Choose the columns of ${name}`;
  box.append(legend);
  const label = (c, k) => (c === '' ? `(unnamed column ${k + 1})` : c);
  const free = columns.map((_, k) => k).filter((k) => k !== time);
  const rows = [];
  const add = (role, pick, optional) => {
    const l = document.createElement('label');
    l.append(`${role} `);
    const s = document.createElement('select');
    if (optional) s.add(new Option('none', ''));
    columns.forEach((c, k) => s.add(new Option(label(c, k), String(k))));
    s.value = pick === undefined ? '' : String(pick);
    l.append(s);
    box.append(l, ' ');
    rows.push({ s, optional });
  };
  // A choice made before is kept; else the defaults.
  const at = (i) => (chosen && chosen[i] !== undefined ? columns.indexOf(chosen[i]) : -1);
  for (let i = 0; i < shape.outputs; i++) add(`y${i + 1}`, at(i) >= 0 ? at(i) : (free[i] ?? free[0] ?? 0), false);
  for (let i = 0; i < shape.inputs; i++) add(`u${i + 1}`, at(shape.outputs + i) >= 0 ? at(shape.outputs + i) : undefined, true);
  const go = document.createElement('button');
  go.type = 'button';
  go.textContent = 'Run with these columns';
  go.addEventListener('click', () => {
    const names = (optional) => rows.filter((x) => x.optional === optional && x.s.value !== '').map((x) => columns[+x.s.value]);
    useData(d, text, name, names(false).concat(names(true)));
  });
  box.append(go);
  return box;
}

// The picker for this file, or none (no header, or its names cannot be read).
function offerColumns(d, text, name, base, chosen) {
  try {
    const header = JSON.parse(confset.csvColumns(text));
    const shape = JSON.parse(confset.dataShape(JSON.stringify(base)));
    d.dataBox.picker(header.columns.length ? columnPicker(d, text, name, header, shape, chosen) : null);
  } catch {
    d.dataBox.picker(null);
  }
}

// `columns`: the header's names chosen in the picker (y1 … yq, then u1 … ur), or undefined.
async function useData(d, text, name, columns) {
  const api = await mounted.get(d.id);
  await dataHint(d);
  if (text.length > MAX_DATA_BYTES) return d.dataBox.show(`the data have ${(text.length / 1e6).toFixed(1)} MB of text: at most ${MAX_DATA_BYTES / 1e6} MB`);
  const base = api.scenario();
  if (!base) return d.dataBox.show('the panel has no valid scenario to run the data with: fix its controls first');
  let scenario;
  try {
    // Read by the core in the panel's worker (a 150,000-row file held the page 0.1–0.2 s), and
    // titled after the file: the figures' title is the scenario's, and the preset's ("… (LSCR
    // paper, Fig. 1)") claims the paper's data.
    scenario = await api.withCsvData(JSON.stringify(base), text, name, columns);
  } catch (e) {
    d.dataBox.show(e.message || String(e));
    // A file with a header that the model's names do not read: offer its columns.
    return offerColumns(d, text, name, base, columns);
  }
  // A choice made stays on offer (to change it); a file read by its own names needs none.
  if (columns) offerColumns(d, text, name, base, columns);
  else d.dataBox.picker(null);
  d.beforeLoad = await stateOf(d);
  navigating++;
  try {
    addLoaded(d, api, `data:${name}`.slice(0, 80), scenario);
    api.presetSelect.value = d.loaded.name;
    api.presetSelect.dispatchEvent(new Event('change', { bubbles: true }));
    await idle(d.busy);
  } finally {
    navigating--;
  }
  // The method may refuse what the core could read (too few rows for its window, …): said
  // here, next to the data, not only at the field far below.
  const refusals = [...d.root().querySelectorAll('.err[data-for]')].map((e) => e.textContent.trim()).filter(Boolean);
  const rows = scenario.data.y.length;
  d.dataBox.show(refusals.length ? `${name}: ${rows} rows read, but the method refused them: ${refusals[0]}` : '', dataPreview(scenario.data));
  d.showUndo();
  d.say(refusals.length ? `${name} was refused by the method: see the message by the data` : `running on ${name}: ${rows} rows`);
  const link = await linkOf(d);
  history.replaceState(null, '', (link ? link.slice(link.indexOf('#')) : `#${d.id}`) + keptOptions());
}

// ----- share links -----

async function stateOf(d) {
  const api = await mounted.get(d.id);
  const name = api.presetSelect.value;
  const state = { preset: name, fields: captureFields(d.root(), api.presetSelect.id) };
  if (d.loaded && d.loaded.name === name) state.scenario = d.loaded.scenario;
  return state;
}

// The panel's link, or null (said in the toolbar) when it would be too long.
async function linkOf(d) {
  const hash = `#${d.id}/${LINK_VERSION}/${await encodeState(await stateOf(d))}`;
  const link = `${location.origin}${location.pathname}${hash}`;
  if (hash.length > MAX_LINK_CHARS) {
    d.say(`This configuration needs a link of ${int(hash.length)} characters (at most `
      + `${int(MAX_LINK_CHARS)}): download the scenario file and share that instead.`);
    return null;
  }
  return link;
}

// The display options of the fragment (&present, &panel=…): the page rewrites the link part of
// the fragment as the controls move, and keeps them.
const keptOptions = () => fragmentOptions(location.hash).suffix;

// The URL follows the controls, debounced, so a slider's redraw never waits for it.
function syncUrl(d) {
  let timer = 0;
  const update = async () => {
    if (current !== d || navigating) return;
    const link = await linkOf(d);
    if (link && current === d) history.replaceState(null, '', link.slice(link.indexOf('#')) + keptOptions());
  };
  for (const ev of ['input', 'change']) {
    d.root().addEventListener(ev, () => { clearTimeout(timer); timer = setTimeout(update, 400); });
  }
}

// Put a decoded state into a mounted panel.
async function restore(d, state) {
  const api = await mounted.get(d.id);
  navigating++;
  try {
    if (state.scenario) addLoaded(d, api, state.preset, state.scenario);
    if (![...api.presetSelect.options].some((o) => o.value === state.preset)) {
      throw new Error(`the preset “${String(state.preset).slice(0, 40)}” does not exist (any more)`);
    }
    api.presetSelect.value = state.preset;
    api.presetSelect.dispatchEvent(new Event('change', { bubbles: true }));
    // The preset's compute is scheduled for the next frame: the fields set now join it.
    const unknown = await restoreFields(d.root(), state.fields || {}, d.busy);
    if (unknown.length) d.say(`restored; ${unknown.length} setting(s) of the link are not on this page: ${unknown.slice(0, 3).join(', ')}`);
  } finally {
    navigating--;
  }
}

// ----- scenario files -----

function addLoaded(d, api, name, scenario) {
  const file = name.replace(/^(file|data):/, '');
  // The file's title and notes are shown as text (menu label, description): strings only.
  const title = typeof scenario.title === 'string' ? scenario.title : '';
  const notes = typeof scenario.notes === 'string' ? scenario.notes : '';
  const p = name.startsWith('data:')
    ? { name, label: `your data: ${file}`.slice(0, 60), description: `${title || d.title}: measured data from ${file}`, scenario }
    : { name, label: `loaded: ${title || file}`.slice(0, 60), description: notes || `a scenario loaded from ${file}`, scenario };
  api.addPreset(p);
  d.loaded = p;
}

async function loadScenarioFile(file) {
  const fail = (msg) => (current ? current.say(msg) : homeNote(msg));
  if (file.size > 20e6) return fail(`${file.name} is ${(file.size / 1e6).toFixed(0)} MB: a scenario file has at most 20 MB`);
  let scenario;
  try {
    scenario = JSON.parse(await file.text());
  } catch (e) {
    return fail(`${file.name} is not a scenario file: ${e.message}`);
  }
  await openScenario(scenario, file.name);
}

// A panel asks to show a scenario in the panel of its method (the compare table's "open in its
// panel": a method's own scenario on the compared record), as a loaded file would be.
document.addEventListener('confset:open-scenario', (e) => openScenario(e.detail.scenario, e.detail.name));

async function openScenario(scenario, fileName) {
  const fail = (msg) => (current ? current.say(msg) : homeNote(msg));
  const file = { name: fileName };
  const methods = PANELS.flatMap((p) => p.methods).join(', ');
  if (!scenario || typeof scenario !== 'object' || Array.isArray(scenario)) {
    const what = Array.isArray(scenario) ? 'a list' : scenario === null ? 'null' : `a ${typeof scenario}`;
    return fail(`${file.name} is not a scenario file: a scenario is a JSON object with "method" (${methods}) and "model"; this file holds ${what}`);
  }
  const d = panelOf(scenario.method || 'scf');
  if (!d) return fail(`${file.name}: "method" must be one of ${methods}`);
  // The core reads it first: a scenario it refuses is said with the field it names, before a
  // panel takes it (a panel fills its controls from a scenario the core has read).
  try {
    confset.dataShape(JSON.stringify(scenario));
  } catch (e) {
    return fail(`${file.name} is not a scenario this page can open: ${(e && e.message) || e}`);
  }
  await show(d);
  const api = await mounted.get(d.id);
  d.beforeLoad = await stateOf(d);
  navigating++;
  try {
    addLoaded(d, api, `file:${file.name}`.slice(0, 80), scenario);
    api.presetSelect.value = d.loaded.name;
    api.presetSelect.dispatchEvent(new Event('change', { bubbles: true }));
    await idle(d.busy);
  } finally {
    navigating--;
  }
  d.showUndo();
  d.say(`loaded ${file.name}`);
  history.replaceState(null, '', (await linkOf(d) || `#${d.id}`).replace(/^[^#]*/, '') + keptOptions());
}

// ----- the core's limits on the controls -----

// Number boxes, and the sliders paired with them, take their range from the core (`limits()`):
// the same numbers as its messages.
function applyLimits(d) {
  const limits = JSON.parse(confset.limits());
  // Number boxes and the sliders paired with them (data-limit) take the core's ranges.
  for (const el of d.section().querySelectorAll('input[type=number][data-field], input[data-limit]')) {
    const key = el.dataset.limit || (/(^|\.)runs$/.test(el.dataset.field) ? 'runs' : el.dataset.field);
    let range = limits[key];
    if (range && !Array.isArray(range)) range = range[d.methods[0]];
    if (Array.isArray(range)) [el.min, el.max] = range.map(String);
  }
}

// ----- keyboard and screen readers -----

// A slider announces what its label shows ("= 40", "0.950"), not its raw value: the text of its
// <output>, updated after the panel has drawn.
function announceSliders(root) {
  const outputOf = (r) => root.querySelector(`label[for="${r.id}"] output`) || r.closest('label')?.querySelector('output')
    || root.querySelector(`#${r.id}-out`);
  const update = (r) => r.setAttribute('aria-valuetext', (outputOf(r)?.textContent || r.value).replace(/^=\s*/, '').trim() || r.value);
  for (const r of root.querySelectorAll('input[type=range]')) {
    r.addEventListener('input', () => requestAnimationFrame(() => update(r)));
    update(r);
  }
  // A figure's text alternative is the numbers table beside it.
  const numbers = root.querySelector('.numbers [id$="numbers"]');
  if (numbers) for (const c of root.querySelectorAll('canvas')) c.setAttribute('aria-describedby', numbers.id);
}

// ----- routing -----

function mount(d) {
  if (!mounted.has(d.id)) {
    if (!d.say) toolbar(d);
    const list = presets.filter((p) => d.methods.includes(p.scenario.method));
    mounted.set(d.id, Promise.all([import(d.module), fetch(d.view).then((r) => {
      if (!r.ok) throw new Error(`${d.view}: HTTP ${r.status}`);
      return r.text();
    })]).then(([m, markup]) => {
      const root = d.root();
      root.innerHTML = markup;
      for (const form of root.querySelectorAll('form')) form.addEventListener('submit', (e) => e.preventDefault());
      return m[d.mount](root, list);
    }).then((api) => {
      syncUrl(d);
      announceSliders(d.root());
      applyLimits(d);
      // The preset's "Things to try", under its menu (tries.js).
      mountTries(d.root(), api.presetSelect, d.busy);
      return api;
    }));
  }
  return mounted.get(d.id);
}

// Show a view, mounting it on its first visit. A panel computes once it is shown, unless a link
// is about to be restored into it (`restoring`): then the link's preset and fields make its first
// compute, not a second one.
async function show(d, restoring = false) {
  current = d;
  for (const v of views) v.hidden = v !== (d ? d.section() : views[0]);
  for (const a of document.querySelectorAll('nav.routes a')) a.toggleAttribute('aria-current', !!d && a.dataset.route === d.id);
  document.title = d ? `${d.title} — confset explorer` : 'confset explorer — guaranteed sets for state estimation';
  if (!d) return;
  try {
    const api = await mount(d);
    if (!restoring) api.start();
  } catch (e) {
    mounted.delete(d.id); // the next visit tries again
    d.banner(`This view could not be loaded (${e.message}): reload the page to try again.`);
    return;
  }
  await idle(d.busy);
}

async function route() {
  if (navigating) return;
  delete document.body.dataset.ready;
  const r = await parseFragment(location.hash);
  let d = panelById(r.id) || null;
  // A link (or a preset name) of another view's method opens in that view: `#ubb/preset/scf-robots`
  // is SCF's preset, and a state carrying an SCF scenario is SCF's, whatever view it names.
  const owner = ownerOf(r);
  let movedFrom = null;
  if (d && owner && owner !== d) {
    movedFrom = d;
    d = owner;
    history.replaceState(null, '', location.hash.replace(/^#[^/&]*/, `#${owner.id}`));
  }
  // A playing animation (one that loops never ends) pauses: the route waits for the view to be idle.
  if (d && mounted.has(d.id)) (await mounted.get(d.id).catch(() => null))?.pause?.();
  if (r.id && !d) {
    await show(null);
    homeNote(`There is no view “${r.id.slice(0, 24)}”: here are the views.`);
  } else {
    homeNote('');
    await show(d, !r.error && !!(r.state || r.preset));
  }
  if (d) {
    d.banner('');
    if (r.error) {
      d.banner(`${r.error[0].toUpperCase()}${r.error.slice(1)}. The panel shows its default scenario instead.`);
    } else if (r.state || r.preset) {
      try {
        await restore(d, r.state || { preset: r.preset, fields: {} });
      } catch (e) {
        d.banner(`This link could not be restored: ${e.message}. The panel shows its default scenario instead.`);
      }
      // The panel's first compute, if the link changed nothing (or could not be restored).
      (await mounted.get(d.id))?.start();
      await idle(d.busy);
    }
    if (movedFrom) d.say(`this link is of the ${d.nav} view, not the ${movedFrom.nav} view: it opened here`);
  }
  presentMode(d, !!d && r.present, r.panels);
  if (d) (await mounted.get(d.id).catch(() => null))?.redraw?.();
  document.body.dataset.route = d ? d.id : '';
  document.body.dataset.ready = '1';
}

// The view a route's state or preset belongs to (by its scenario's method, else its preset's),
// or null when it names none.
function ownerOf(r) {
  const scenario = r.state && r.state.scenario;
  let method = scenario && typeof scenario === 'object' && typeof scenario.method === 'string' ? scenario.method : null;
  if (!method) {
    const name = r.state ? r.state.preset : r.preset;
    method = presets.find((p) => p.name === name)?.scenario.method ?? null;
  }
  return method ? panelOf(method) || null : null;
}

// ----- present mode (&present, &panel=…): for a lecture hall or an iframe -----

// The body's class `present`; in the view, everything but its title, the chosen figure cards
// (the names in `panels`, or the first figure shown) and its animation's controls (its
// .cursor-box) is marked present-off (style.css hides it and lays the rest out in the window).
function presentMode(d, on, panels = []) {
  document.body.classList.toggle('present', on);
  for (const c of ['present-off', 'present-path', 'present-fig', 'present-keep']) {
    for (const e of document.querySelectorAll(`.${c}`)) e.classList.remove(c);
  }
  delete document.body.dataset.presentFigures;
  if (!on) return;
  const section = d.section();
  const cards = [...d.root().querySelectorAll('figure.card[data-panel]')];
  let chosen = panels.map((n) => cards.find((c) => c.dataset.panel === n && !c.hidden)).filter(Boolean);
  if (!chosen.length) chosen = cards.filter((c) => !c.hidden).slice(0, 1);
  for (const c of chosen) c.classList.add('present-fig');
  document.body.dataset.presentFigures = String(chosen.length);
  const keep = [...chosen, ...section.querySelectorAll('.section-head, .cursor-box')];
  for (const k of keep) k.classList.add('present-keep');
  const path = new Set();
  for (const k of keep) for (let e = k.parentElement; e && e !== section.parentElement; e = e.parentElement) path.add(e);
  for (const e of path) {
    e.classList.add('present-path');
    for (const child of e.children) if (!path.has(child) && !keep.includes(child)) child.classList.add('present-off');
  }
}

function homeNote(msg) {
  const p = document.getElementById('home-note');
  p.textContent = msg;
  p.hidden = !msg;
}

function landing() {
  const box = document.getElementById('landing');
  box.replaceChildren(...PANELS.map((d) => {
    const a = document.createElement('a');
    a.className = 'card promise';
    a.href = `#${d.id}`;
    a.innerHTML = `<img class="thumb" width="480" height="320" decoding="async"><h2></h2><p></p><span class="go">open →</span>`;
    const img = a.querySelector('img');
    img.src = `thumbs/${d.id}.png`;
    img.alt = d.thumb.alt;
    a.querySelector('h2').textContent = d.title;
    a.querySelector('p').textContent = d.promise;
    return a;
  }));
}

// The skip link moves the focus to the view shown (its heading's section), past the menu.
document.querySelector('[data-skip]')?.addEventListener('click', (e) => {
  e.preventDefault();
  const target = current ? current.section() : document.getElementById('home');
  target.setAttribute('tabindex', '-1');
  target.focus();
});

async function main() {
  landing();
  try {
    await load();
  } catch (e) {
    status.textContent = `The WebAssembly module could not be loaded: ${e.message}`;
    status.classList.add('bad');
    return;
  }
  // The module's exports, for the browser tests' timings (page.evaluate) and the console.
  window.confset = confset;
  status.textContent = '';
  presets = JSON.parse(confset.presets());
  window.addEventListener('hashchange', route);
  // Drop a scenario file on the landing view too.
  const home = views[0];
  home.addEventListener('dragover', (e) => e.preventDefault());
  home.addEventListener('drop', async (e) => { e.preventDefault(); if (e.dataTransfer.files[0]) await loadScenarioFile(e.dataTransfer.files[0]); });
  await route();
}

main();
