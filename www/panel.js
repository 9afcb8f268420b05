// What every panel module shares: the skeleton of a panel (mountPanel), its preset menu and the
// small API the shell (router, share links, scenario import) drives it through.
import { Session } from './pkg/confset.js';
import { Figure, figureCards, download, drawFigures, redrawOnResize } from './figure.js';
import { fieldErrors, frameScheduler, busyFlag } from './chunked.js';
import { computeClient, ComputeFault } from './compute.js';
import { parseMatrix, matrixText } from './parse.js';
import { timeCursor, animation } from './cursor.js';
import { mountStepCard } from './stepcard.js';

export const clone = (v) => JSON.parse(JSON.stringify(v));

// The preset menu: the core's presets, named for people (the core's short menu name, short
// enough to show whole in the controls' column and on a phone; its full label and description
// are the option's tooltip, the description is also shown under the menu), then the panel's
// custom model if it has one. `add(p)` puts a scenario loaded from a file into the menu
// (replacing one of the same name) before the custom model.
export function presetMenu(select, presets, custom) {
  const all = custom ? [...presets, custom] : [...presets];
  const label = (p) => (p === custom ? 'custom model' : p.menu || p.label || p.name);
  const tip = (p) => [p.menu && p.label !== p.menu ? p.label : '', p.description || ''].filter(Boolean).join('\n');
  const fill = () => select.replaceChildren(...all.map((p) => Object.assign(new Option(label(p), p.name), { title: tip(p) })));
  fill();
  return {
    all,
    add(p) {
      const i = all.findIndex((x) => x.name === p.name);
      if (i >= 0) all.splice(i, 1, p); else all.splice(custom ? all.length - 1 : all.length, 0, p);
      fill();
    },
  };
}

// The shell's handle on a mounted panel: its preset menu, how to add a loaded scenario, and the
// scenario it last ran.
export const panelApi = (select, menu, scenario, start) => ({ presetSelect: select, addPreset: menu.add, scenario, start });

// On the user's data (`data` instead of `simulate`) the simulation's controls have nothing to
// set: they are disabled, and the panel's note says that the run has no truth.
export function dataMode(root, scenario) {
  const onData = !scenario.simulate && !!scenario.data;
  for (const el of root.querySelectorAll('form [data-field^="simulate."]')) el.disabled = onData;
  let note = root.querySelector('.data-note');
  if (!note) {
    note = Object.assign(document.createElement('p'), { className: 'data-note' });
    root.querySelector('form').prepend(note);
  }
  const y = scenario.data?.y || [];
  note.textContent = onData
    ? `Your data: ${y.length} measurement${y.length === 1 ? '' : 's'} of ${y[0]?.length ?? 0} output${y[0]?.length === 1 ? '' : 's'}`
      + `${scenario.data.u?.length ? ` with inputs u (${scenario.data.u[0].length} per row)` : ''}. No simulation, so no true state and no verdict against one.`
    : '';
  note.hidden = !onData;
}

// A run still going after this long shows its Cancel control, and a newer scenario replaces it
// (rather than queueing behind it).
const CANCEL_AFTER_MS = 1000;

// What a panel says about a run that did not end in a report (or a core error), beside its
// stale-picture note: Cancel while a run takes long, "cancelled" after it, and the message of a
// crash with the scenario that caused it to download.
function computeNote(staleNote, saveScenario) {
  const note = Object.assign(document.createElement('p'), { className: 'stale compute-note', hidden: true });
  staleNote.after(note);
  const say = (text, button, onClick, role = 'status') => {
    note.setAttribute('role', role);
    const b = button ? Object.assign(document.createElement('button'), { type: 'button', className: 'compute-act', textContent: button }) : null;
    b?.addEventListener('click', onClick);
    note.replaceChildren(Object.assign(document.createElement('span'), { textContent: text }), ...(b ? [' ', b] : []));
    note.hidden = false;
  };
  let timer = 0;
  return {
    // A run starts: nothing to say until it takes long, then its Cancel.
    running(cancel) {
      clearTimeout(timer);
      note.hidden = true;
      timer = setTimeout(() => say('Still computing…', 'Cancel', cancel), CANCEL_AFTER_MS);
    },
    done() { clearTimeout(timer); note.hidden = true; },
    cancelled() { clearTimeout(timer); say('Computation cancelled: the figures show the last computed scenario.'); },
    // A crash or a silent worker stopped by the watchdog: a bug either way.
    failed(fault, scenario) {
      clearTimeout(timer);
      const what = fault.kind === 'timeout' ? fault.message : 'The computation failed';
      say(`${what} — this is a bug. Download the scenario to report it.`, 'Download the scenario', () => saveScenario(scenario), 'alert');
    },
  };
}

// The report's warnings beside the figures (report.warnings: the core's sentences the reader must
// know about this answer — an assumption of the method's promise not met, an estimate on an
// artificial bound, the record's gaps and what the method did with them): a calm box after the
// stale and compute notes, above the figure cards, one list item each, hidden when there are none.
// `show(report)` puts a new report's warnings in; the page adds no words of its own.
function warningsBox(staleNote) {
  const box = Object.assign(document.createElement('div'), { className: 'warnings', hidden: true });
  box.setAttribute('role', 'status');
  const head = Object.assign(document.createElement('p'), { className: 'warnings-head', textContent: 'Read this answer with:' });
  head.id = `${staleNote.id}-warnings-head`;
  box.setAttribute('aria-labelledby', head.id);
  const list = document.createElement('ul');
  box.append(head, list);
  staleNote.after(box);
  return {
    show(report) {
      const said = Array.isArray(report?.warnings) ? report.warnings.filter((w) => typeof w === 'string' && w) : [];
      list.replaceChildren(...said.map((w) => Object.assign(document.createElement('li'), { textContent: w })));
      box.hidden = !said.length;
    },
  };
}

// What the skeleton writes into an element of the view marked data-part="<name>", given the
// panel's id prefix: the numbers card's downloads, and the notes card's heading and notes.
const PARTS = {
  downloads: (p) => `<button type="button" id="${p}dl-report">Download report (JSON)</button>\n`
    + `<button type="button" id="${p}dl-scenario">Download scenario (JSON)</button>\n`
    + `<button type="button" id="${p}dl-csv" aria-label="download the report's table as CSV: one row per time step">`
    + `Download table (CSV)</button>\n<span class="err" id="${p}dl-err" role="alert"></span>`,
  notes: (p) => `<h2>About this scenario</h2>\n<p id="${p}notes"></p>`,
};

// The skeleton of a panel: a wasm Session, the controls ⇄ scenario ⇄ report loop, its figures,
// preset menu, inline errors, busy flag, downloads (#<prefix>dl-report, #<prefix>dl-scenario,
// #<prefix>dl-csv: the report's table) and timing line. The scenarios run in the panel's compute worker (compute.js); the Session here
// keeps the report it sends back (setReport) and draws it. A panel module describes itself in `spec`; the hooks get the panel `p` = { root,
// session, ui, st, figures, errors, setBusy, schedule, build(), compute(), redraw(), isCustom(),
// model(), stem(), cursorTime() } with st = { preset, report, reportJson, scenario, runMs, drawMs,
// cursorSteps } (a hook may keep its own fields in p and st).
//   presets, custom  the core's presets for the panel and its custom model (one more preset)
//   prefix           of the panel's element ids ('l-' → #l-preset); ui[id] is #<prefix><id>
//   ids              the elements the hooks use besides preset, preset-desc, custom, stale, notes,
//                    numbers, timing, the model's text boxes and the inputs below
//   busy             the document.body.dataset key held while it computes (the registry's)
//   Figure           the class of its figure cards (figure.card under root)
//   model            the custom model's matrices (text boxes m-F …); p.model() parses them
//   prose(text)      the description and notes as HTML (default: plain text)
//   stepCard         {point(p)}: the view shows the core's step-through at the time shown
//                    (Session.explain; point: LSCR's point in the plane, or undefined)
//   errorsWithin     what the inline errors clear ('form ' by default)
//   compute, redraw  the inputs that change the scenario, and those that change only the view;
//   cursor           a time cursor whose report keeps one step's detail (cursor.js): {control
//                    (the slider's id, in `redraw`), animate (its play button's id, optional:
//                    the animation's controls, cursor.js),
//                    block(report) (the report's block holding `at`), setTime(scenario, v)}
//                    (cursor.js's timeOf(key) for the slider `time` over report[key]);
//                    the steps it moves over come from the core with each report
//                    (st.cursorSteps = Session.cursorSteps(): [first, last]), and a slider value
//                    outside them shows the nearest (p.cursorTime()); `time` defaults to that step
//   animate          {control, button}: a time slider without a cursor (every step drawn from the
//                    report) and its play button: the same animation controls (cursor.js);
//                    with compute: true, a control that recomputes (in `compute`: LSCR's data
//                    length, GLLS's horizon): each step is a run, the next one waits for it; it
//                    plays from the smallest value the core accepts (found by asking it, once per
//                    scenario, when the animation first needs it) to the
//                    control's max, or with end: 'chosen' to the value last chosen by hand, a link
//                    or the preset; name: the control's symbol for the bar's range ("t = 7 … 30");
//                    scenario(p, v): the scenario with the control at v (default: build() with it)
//   input(p, id)     what a control shows at once (before the run, next frame)
//   stem(p)          the stem of the file names
//   init(p)          the panel's own wiring, once, before the first preset loads
//   leave(p)         another preset is chosen: stop what runs on this one
//   load(p, s)       controls ← the preset's scenario s (the skeleton has shown its description,
//                    notes, custom box and data mode)
//   build(p, s)      controls → scenario: sets the fields of s, a copy of the preset's scenario
//   run(runInWorker, scenario)  a Promise of the report's JSON (default: runInWorker(scenario),
//                    one run in the worker; a hook may run twice when the first report fixes
//                    something the scenario must be run with)
//   after(p)         after a run succeeded, before the redraw
//   time(p)          the time the figures are drawn at (default: none)
//   draw(p, time)    the numbers of the report, after the figures
//   timing(p)        the timing line (default: run + draw in #<prefix>timing)
//   reportFile(p), scenarioFile(p)  what the downloads hold (default: the report, the scenario)
// Returns the panel's API for the shell.
export function mountPanel(root, spec) {
  const session = new Session();
  const worker = computeClient(root.id);
  const prefix = spec.prefix || '';
  // The parts every view marks and the skeleton writes: the notes card and the downloads.
  for (const el of root.querySelectorAll('[data-part]')) {
    el.innerHTML = PARTS[el.dataset.part](prefix);
    el.removeAttribute('data-part');
  }
  // Every panel's form opens with its preset menu and the preset's description.
  const row = Object.assign(document.createElement('label'), { className: 'row', textContent: 'Scenario' });
  row.append(Object.assign(document.createElement('select'), { id: `${prefix}preset` }));
  row.lastChild.dataset.field = 'preset';
  root.querySelector('form').prepend(row, Object.assign(document.createElement('p'), { id: `${prefix}preset-desc`, className: 'desc' }));
  const ids = new Set(['preset', 'preset-desc', 'custom', 'stale', 'notes', 'numbers', ...(spec.timing ? [] : ['timing']),
    ...(spec.model || []).map((k) => `m-${k}`), ...(spec.compute || []), ...(spec.redraw || []), ...(spec.ids || []),
    ...(spec.cursor?.animate ? [spec.cursor.animate] : []), ...(spec.animate ? [spec.animate.button] : [])]);
  // Ids are looked up under the panel's root only, so the same view can be mounted twice.
  const byId = (id) => root.querySelector(`#${CSS.escape(id)}`);
  const ui = Object.fromEntries([...ids].map((id) => [id, byId(`${prefix}${id}`)]));
  const menu = presetMenu(ui.preset, spec.presets, spec.custom);
  const all = menu.all;
  const st = { preset: all[0], report: null, reportJson: '', scenario: null, runMs: 0, drawMs: 0 };
  const stem = () => spec.stem(p);
  const FigureClass = spec.Figure || Figure;
  // The figure cards: the core's figures for the methods of the panel's presets.
  figureCards(root, [...new Set([...spec.presets, spec.custom].filter(Boolean).map((x) => x.scenario.method))]);
  const figures = [...root.querySelectorAll('figure.card')].map((c) => new FigureClass(c, session, stem));
  // The report's warnings, above the figure cards (made before the compute note, which goes
  // between them and the stale note).
  const warnings = warningsBox(ui.stale);
  const errors = fieldErrors(root, ui.stale, spec.errorsWithin ?? 'form ');
  const setBusy = busyFlag(spec.busy);
  const isCustom = () => st.preset === spec.custom;
  const model = () => Object.fromEntries(spec.model.map((k) => [k, parseMatrix(`model.${k}`, ui[`m-${k}`].value)]));
  for (const k of spec.model || []) ui[`m-${k}`].value = matrixText(spec.custom.scenario.model[k]);
  // Descriptions and notes may come from a scenario file (any JSON value): always as text, and
  // as HTML only through the panel's prose(), which escapes it first (richtext.js).
  const prose = (el, value) => {
    const text = typeof value === 'string' ? value : '';
    if (spec.prose) el.innerHTML = spec.prose(text); else el.textContent = text;
  };

  let onReport = null; // what the animation of a recomputing control does after each report
  let onLoad = null; // … and after a preset loads
  function loadPreset(name) {
    st.preset = all.find((x) => x.name === name) || all[0];
    const s = st.preset.scenario;
    ui.custom.hidden = !isCustom();
    prose(ui['preset-desc'], st.preset.description);
    prose(ui.notes, s.notes || '');
    dataMode(root, s);
    spec.load(p, s);
    onLoad?.();
  }

  // The scenario the controls describe: the preset's, with the fields the controls set (the
  // notes are the preset's, not part of what runs).
  function build() {
    const s = clone(st.preset.scenario);
    spec.build(p, s);
    delete s.notes;
    return s;
  }

  // The runs. At most one is in flight; input meanwhile marks the controls' scenario as wanted
  // (`again`), and it is built and sent when the one in flight ends — so a burst of input costs
  // one more run, not one per event. A run past CANCEL_AFTER_MS is replaced by the newer
  // scenario instead of waited for. A result is drawn unless another preset was chosen while
  // it ran (`preset` changed: it belongs to the old one).
  let computed = false;
  let inFlight = null; // the Promise of the runs going on
  let again = false;
  let runStarted = 0;
  let presetChoice = 0;
  function compute() {
    computed = true;
    if (inFlight) {
      again = true;
      if (performance.now() - runStarted > CANCEL_AFTER_MS) worker.replace('superseded');
      return inFlight;
    }
    // Busy until drawn, whoever asked (the frame scheduler, or a panel's own loop like ubb's animation).
    setBusy(+1);
    inFlight = (async () => {
      let ok;
      do {
        again = false;
        ok = await computeOnce();
      } while (again);
      return ok;
    })().finally(() => { inFlight = null; setBusy(-1); });
    return inFlight;
  }

  // The scenario text of the last report and the worker's cursor for it (the time cursor's).
  let ran = null;
  const runInWorker = async (s) => {
    const text = JSON.stringify(s);
    const r = await worker.run(text);
    ran = { text, cursor: r.cursor };
    return r.report;
  };
  const cancel = () => { again = false; worker.replace('cancelled'); };

  // One run of the scenario the controls describe, and its redraw; whether it succeeded. A core
  // error shows next to its field, a crash or a cancel in the compute note; the last good
  // picture stays.
  async function computeOnce() {
    const choice = presetChoice;
    let scenario, json;
    try {
      scenario = build();
    } catch (e) {
      errors.show(e, !!st.report);
      return false;
    }
    const t0 = performance.now();
    runStarted = t0;
    note.running(cancel);
    try {
      json = await (spec.run ? spec.run(runInWorker, scenario) : runInWorker(scenario));
    } catch (e) {
      if (choice !== presetChoice || e?.kind === 'superseded') { note.done(); return false; }
      if (e instanceof ComputeFault) {
        again = false; // what was asked meanwhile waits for the next input
        errors.clear();
        if (e.kind === 'crash' || e.kind === 'timeout') note.failed(e, scenario); else note.cancelled();
        return false;
      }
      note.done();
      errors.show(e, !!st.report);
      return false;
    }
    note.done();
    if (choice !== presetChoice) return false;
    st.runMs = performance.now() - t0; // the round trip to the worker
    try {
      session.setReport(json);
    } catch (e) {
      errors.show(e, !!st.report);
      return false;
    }
    st.report = JSON.parse(json);
    st.reportJson = json;
    warnings.show(st.report);
    // The figures' pointer read-outs name a step with the record's time (report.figure.times).
    for (const f of figures) f.report = st.report;
    if (cur) st.cursorSteps = session.cursorSteps();
    st.scenario = scenario;
    p.cursor?.reset(ran.text, ran.cursor);
    errors.clear();
    // The cards of the figures the core finds worth drawing for this report.
    const useful = JSON.parse(session.usefulPanels());
    for (const f of figures) f.card.hidden = !f.shownFor(useful);
    spec.after?.(p);
    redraw();
    onReport?.();
    return true;
  }

  function redraw() {
    if (!st.report) return;
    const time = spec.time?.(p) ?? cursorTime();
    // A time cursor's step: the kept report shows it (its detail from the cache), or the
    // figures draw it from what the report holds for every step until the detail comes.
    if (time != null) p.cursor?.show(time);
    st.drawMs = drawFigures(figures, time);
    spec.draw(p, time);
    p.stepCard?.update(time);
    if (spec.timing) spec.timing(p);
    else ui.timing.textContent = `rendered in ${(st.runMs + st.drawMs).toFixed(1)} ms (run ${st.runMs.toFixed(1)} ms + draw ${st.drawMs.toFixed(1)} ms)`;
  }

  // Bursts of input events coalesce into one run (or redraw) per frame.
  const schedule = frameScheduler(setBusy, compute, redraw);
  const p = { root, session, ui, st, figures, errors, setBusy, schedule, build, compute, redraw, isCustom, model, stem };
  // The "One step, step by step" card (stepcard.js) of a view whose method has one (spec.stepCard:
  // {point(p)}, LSCR's point in the plane), after the numbers card.
  if (spec.stepCard) {
    p.stepCard = mountStepCard(p, { after: ui.numbers.closest('.card') || ui.numbers, point: spec.stepCard.point });
  }
  // The time cursor: the step the slider shows, its details, its animation.
  const cur = spec.cursor;
  // The step a slider value shows: the nearest of the report's cursor steps (the core's).
  const shown = (v) => Math.min(Math.max(v, st.cursorSteps[0]), st.cursorSteps[1]);
  const cursorTime = () => (cur && st.report ? shown(Number(ui[cur.control].value)) : undefined);
  p.cursorTime = cursorTime;
  if (cur) {
    const showError = (e) => {
      if (!(e instanceof ComputeFault)) errors.show(e, true);
      else if (e.kind === 'crash' || e.kind === 'timeout') note.failed(e, st.scenario);
    };
    p.cursor = timeCursor({ worker, session, st, setBusy, redraw, showError }, cur);
    const moved = () => p.cursor.moved(Number(ui[cur.control].value));
    ui[cur.control].addEventListener('input', moved);
    if (cur.animate) {
      p.animation = animation({
        button: ui[cur.animate], control: ui[cur.control], root, cursor: p.cursor, setBusy,
        first: () => st.cursorSteps?.[0] ?? Number(ui[cur.control].min),
        last: () => st.cursorSteps?.[1] ?? Number(ui[cur.control].max),
        at: (v) => (st.cursorSteps ? shown(v) : v),
        moved: () => { spec.input?.(p, cur.control); moved(); },
        draw: redraw,
        showError,
      });
    }
  } else if (spec.animate?.compute) {
    // A control that recomputes (a data length, a horizon): each step of its animation is a run.
    const a = spec.animate;
    const c = ui[a.control];
    // The scenario the controls describe with the control at v.
    const scenarioAt = a.scenario ? (v) => a.scenario(p, v) : (v) => {
      const old = c.value;
      c.value = String(v);
      try { return build(); } finally { c.value = old; }
    };
    // The first step is the smallest value the core accepts (firstAccepted: what it refuses
    // below depends on the rest of the scenario: LSCR t ≥ n, 2^t ≥ M, t above the smoothed
    // index; GLLS the first horizon at which the state is observable), asked in the worker once
    // per scenario but the control (`key`), when the animation first needs it.
    let range = null; // {key, first (null until known), asking (a Promise)}
    // a.end === 'chosen': the animation ends at the value chosen by hand, a link or the preset,
    // not at the control's max (LSCR's data length goes to 800).
    let chosen = null;
    // The last report's scenario but the control (`key`) and its value there (accepted).
    let report = null;
    const keyOf = () => { try { return JSON.stringify(scenarioAt(Number(c.min))); } catch { return null; } };
    // The range, asked of the core when the animation first needs it (play, a step, the pointer
    // or the focus reaching the bar), not with every run: a Promise that resolves when it is known.
    const ensureRange = () => {
      const key = keyOf();
      if (range?.key === key) return range.asking;
      // Controls changed since the last report (not run yet, or refused): nothing known to ask from.
      if (key === null || key !== report?.key) return Promise.resolve();
      const mine = { key, first: null };
      range = mine;
      setBusy(+1);
      mine.asking = worker.firstAccepted(JSON.stringify(scenarioAt(report.value)))
        .then(({ value }) => { if (range === mine) mine.first = Math.max(value, Number(c.min)); })
        .catch(() => { if (range === mine) range = null; })
        .finally(() => { setBusy(-1); p.animation?.refresh(); });
      return mine.asking;
    };
    const first = () => range?.first ?? Number(c.min);
    const last = () => (a.end === 'chosen' && chosen != null
      ? Math.min(Math.max(chosen, first()), Number(c.max)) : Number(c.max));
    p.animation = animation({
      button: ui[a.button], control: c, root, setBusy, first, last,
      moved: () => spec.input?.(p, a.control),
      draw: compute, // a Promise of whether the run succeeded (a core error shows at its field)
      showError: (e) => {
        if (!(e instanceof ComputeFault)) errors.show(e, true);
        else if (e.kind === 'crash' || e.kind === 'timeout') note.failed(e, st.scenario);
      },
      ready: ensureRange,
      // Until the core has been asked, only the end is known.
      rangeText: a.name && (() => (range?.first != null ? `${a.name} = ${first()} … ${last()}` : `${a.name} up to ${last()}`)),
    });
    onReport = () => {
      report = { key: keyOf(), value: Number(c.value) };
      if (range && range.key !== report.key) range = null; // another scenario: asked again when needed
      p.animation.refresh();
    };
    onLoad = () => { chosen = Number(c.value); p.animation.refresh(); };
    // A value committed by hand (or by a link) is the new end; the bar's own steps are not.
    c.addEventListener('change', () => {
      if (p.animation.stepping) return;
      const v = Number(c.value);
      if (Number.isInteger(v) && v >= Number(c.min) && v <= Number(c.max)) chosen = v;
      p.animation.refresh();
    });
  } else if (spec.animate) {
    // A time slider that only redraws (every step is in the report): its animation needs no cursor.
    const { control, button } = spec.animate;
    p.animation = animation({
      button: ui[button], control: ui[control], root, setBusy,
      first: () => Number(ui[control].min), last: () => Number(ui[control].max),
      moved: () => spec.input?.(p, control),
      draw: redraw,
      showError: (e) => errors.show(e, true),
    });
  }
  // Moving the slider by hand pauses the animation.
  const animated = cur?.animate ? cur.control : spec.animate?.control;
  if (animated) ui[animated].addEventListener('input', () => p.animation?.stop());

  ui.preset.addEventListener('change', () => {
    presetChoice++;
    p.animation?.stop();
    spec.leave?.(p);
    loadPreset(ui.preset.value);
    schedule('compute');
  });
  for (const [list, what] of [[spec.compute, 'compute'], [spec.redraw, 'redraw']]) {
    for (const id of list || []) ui[id].addEventListener('input', () => { spec.input?.(p, id); schedule(what); });
  }
  // Hi-DPI: refit the backing stores when the layout or the pixel ratio changes (no recompute).
  redrawOnResize(figures, () => schedule('redraw'));

  const save = (kind, json) => download(`${stem()}-${kind}.json`, new Blob([json], { type: 'application/json' }));
  const note = computeNote(ui.stale, (s) => save('failed-scenario', JSON.stringify(s, null, 2)));
  byId(`${prefix}dl-report`).addEventListener('click', async () => {
    if (!st.reportJson) return;
    // With a time cursor, the report at the cursor: its step's detail in the kept report.
    const t = cursorTime();
    if (t != null) {
      try {
        while (!p.cursor.has(t) && cursorTime() === t) await p.cursor.ready(t);
      } catch (e) {
        errors.show(e, true);
        return;
      }
      p.cursor.show(t);
    }
    // A panel whose figures show a time of their own (spec.time: SCF's slider only redraws, and
    // its scenario leaves the time out): the report's `time` is the one shown.
    const shown = spec.time?.(p);
    save('report', spec.reportFile ? spec.reportFile(p)
      : shown != null ? JSON.stringify({ ...st.report, time: shown })
        : t != null ? JSON.stringify(st.report) : st.reportJson);
  });
  // The report's table (Session.csv, the core's): what `confset run --format csv` prints.
  byId(`${prefix}dl-csv`).addEventListener('click', () => {
    if (!st.reportJson) return;
    const err = byId(`${prefix}dl-err`);
    try {
      download(`${stem()}.csv`, new Blob([session.csv()], { type: 'text/csv' }));
      err.textContent = '';
    } catch (e) {
      err.textContent = `The table could not be written: ${(e && e.message) || e}`;
    }
  });
  byId(`${prefix}dl-scenario`).addEventListener('click', () => {
    if (st.scenario) save('scenario', JSON.stringify(spec.scenarioFile ? spec.scenarioFile(p) : st.scenario, null, 2));
  });

  spec.init?.(p);
  // A view with an animation (made above, or by the panel's init): each figure's export menu
  // offers its frames as a ZIP of PNG (figure.js), made by stepping the animation.
  if (p.animation) for (const f of figures) f.animated((capture) => p.animation.frames(capture));
  ui.preset.value = all[0].name;
  loadPreset(all[0].name);
  // The first compute is the shell's to start (`start()`), once it knows whether a share link
  // sets the controls first; a compute already scheduled (by the link's preset) makes it a no-op.
  const start = () => { if (!computed) schedule('compute'); };
  // pause(): the shell stops a playing animation before it routes to the view again (a loop
  // would hold the busy flag it waits on).
  // redraw(): the shell's layout changed (present mode on or off, another &panel=): the figures
  // are drawn at their new sizes now, not a frame later by the ResizeObserver.
  return {
    ...panelApi(ui.preset, menu, () => st.scenario, start), pause: () => p.animation?.stop(), redraw,
    // The scenario with a CSV file's data, read by the core in this panel's worker.
    withCsvData: (scenarioJson, text, name, columns) => worker.withCsvData(scenarioJson, text, name, columns),
  };
}
