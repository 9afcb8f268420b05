// The conformal panel (split conformal prediction and ACI on the Kalman filter's score) end to
// end: every preset draws its two figures and its numbers card shows the downloaded report's own
// numbers (radius², χ² radius², the promise's bounds, the truth's verdicts from the report's
// booleans, ACI's coverages); N and the noise law rerun and move the radius; hostile values
// (N = 3, ν = 1, γ = 5, NaN, a level the N cannot serve) show the core's (or the parser's)
// message next to their field with no exception text and keep the last picture; the study runs
// to the end on conformal-gaussian and shows both counts with the core's bands and a verdict in
// words that agrees with them; conformal-far's study adds the fixed-state counts; a share link
// restores the controls, numbers and report. Screenshots of the heavy-tail and far-out presets
// at 1366 × 900 (DPR 1 and 2), on a 390 px phone and in a 1280 × 720 slide frame (present mode).
import { readFile } from 'node:fs/promises';
import { join } from 'node:path';
import { text, setField, choosePreset, openApp, shootSection, assertDrawnAtRatio, assertDrawnWell } from './helpers.mjs';

const PANELS = ['conformalset', 'aciband'];
const PRESETS = ['conformal-gaussian', 'conformal-heavy', 'conformal-far', 'conformal-aci-drift'];
const idle = (page) => page.waitForFunction(() => !document.body.dataset.conformalBusy, null, { timeout: 120_000 });
const sIdle = (page) => page.waitForFunction(() => !document.body.dataset.conformalStudyBusy, null, { timeout: 300_000 });
// The numbers card's title and table (not its timing line).
const numbers = (page) => page.$eval('#cf-numbers-card', (e) => `${e.querySelector('h2').innerText} ${e.querySelector('#cf-numbers').innerText}`.trim().replace(/\s+/g, ' '));
const pixels = (page, panel) => page.$eval(`#fig-${panel} canvas`, (c) => c.toDataURL());
const shownText = (page, sel) => page.$eval(sel, (e) => e.innerText.trim().replace(/\s+/g, ' '));
const set = (page, id, value) => setField(page, id, value, idle);
const choose = (page, name) => choosePreset(page, 'cf-preset', name, idle);
// The page's number format (format.js `fmt`: 4 significant digits) and percentages.
const fmt = (v) => (Math.abs(v) >= 1e4 || (v !== 0 && Math.abs(v) < 1e-3) ? v.toExponential(2) : String(Number(v.toPrecision(4))));
const pct = (v) => `${Number((100 * v).toPrecision(4))} %`;
const esc = (s) => s.replace(/[.*+?^${}()|[\]\\]/g, '\\$&');
// What an exception or a bug would leave in the page's words.
const EXCEPTION = /TypeError|ReferenceError|RangeError|SyntaxError|undefined|\[object|NaN|panicked|unreachable/;

async function report(page) {
  const [dl] = await Promise.all([page.waitForEvent('download'), page.click('#cf-dl-report')]);
  return JSON.parse(await readFile(await dl.path(), 'utf8'));
}

// The error messages shown in the panel's form (visible ones), joined.
const formErrors = (page) => page.$eval('#conformal', (root) => [...root.querySelectorAll('.err[data-for]')]
  .filter((e) => !e.closest('[hidden]')).map((e) => e.textContent.trim()).filter(Boolean).join(' | '));

// The numbers card shows the report's numbers and verdicts.
async function numbersAreTheReport(page, assert, what) {
  const r = await report(page);
  const c = r.conformal;
  const nb = await numbers(page);
  assert.match(nb, new RegExp(`^At t = ${c.time}: level α = ${esc(String(c.level))}, ${c.calibration} calibration runs`), `${what}: ${nb}`);
  assert.match(nb, new RegExp(`radius² conformal ${esc(fmt(c.radius2))} \\(the k = ${c.rank}th smallest of N = ${c.calibration} scores\\) · χ²₂\\(${esc(String(c.level))}\\) ${esc(fmt(c.chi2_radius2))}`), `${what}: radius² ${c.radius2}, χ² ${c.chi2_radius2} in "${nb}"`);
  assert.match(nb, new RegExp(`promise ${esc(pct(c.lower))} ≤ P ≤ ${esc(pct(c.upper))}`), `${what}: the promise's bounds`);
  const v = (b) => (b == null ? '–' : b ? '✓ inside' : '✗ outside');
  assert.match(nb, new RegExp(`truth in the regions conformal ${v(c.inside)} · Kalman ${v(c.kf_inside)}`), `${what}: the verdicts are the report's (${c.inside}, ${c.kf_inside})`);
  assert.match(nb, new RegExp(`ACI ${esc(pct(c.aci.coverage))} · Kalman ${esc(pct(c.aci.kf_coverage))}`), `${what}: ACI's coverages`);
  assert.match(nb, new RegExp(`ACI’s bound \\|miss rate − ${esc(fmt(c.aci.miss))}\\| ≤ ${esc(fmt(c.aci.bound))}`), `${what}: ACI's bound`);
  if (c.aci.worst) assert.match(nb, new RegExp(`worst ${c.aci.window}-step window ACI ${esc(pct(c.aci.worst[0]))} from t = ${c.aci.worst[1]}`));
  assert.doesNotMatch(nb, EXCEPTION, `${what}: no exception text`);
  return r;
}

export default async function conformal(env) {
  const { assert, screenshotDir, newPage, baseUrl, waitReady } = env;
  const page = await openApp(env, 2, idle, 'conformal');

  // The menu: the four presets, then the custom model; none of them in another panel's menu.
  const menu = (id) => page.$$eval(`#${id} option`, (os) => os.map((o) => o.value));
  assert.deepEqual(await menu('cf-preset'), [...PRESETS, 'custom']);
  for (const id of ['preset', 'l-preset', 'g-preset', 'u-preset', 'b-preset', 'c-preset']) {
    if (await page.$(`#${id}`)) assert.ok(!(await menu(id)).some((v) => v.startsWith('conformal')), `#${id} has no conformal preset`);
  }
  await assertDrawnAtRatio(page, assert, 2, PANELS, 380);

  // Every preset: both figures drawn, the numbers are the report's.
  const shown = {};
  for (const name of PRESETS) {
    await choose(page, name);
    await assertDrawnWell(page, assert, PANELS, name);
    assert.equal(await formErrors(page), '', `${name}: runs without a message`);
    shown[name] = await numbersAreTheReport(page, assert, name);
    if (name === 'conformal-heavy' || name === 'conformal-far') await shootSection(page, 'conformal-section', screenshotDir, `${name}-dpr2`);
  }
  // What the presets are about, from their reports.
  const heavy = shown['conformal-heavy'].conformal;
  assert.ok(heavy.radius2 > 1.4 * heavy.chi2_radius2, `heavy tails: the conformal radius² ${heavy.radius2} is well above χ² ${heavy.chi2_radius2}`);
  const far = shown['conformal-far'].conformal;
  assert.deepEqual(far.truth, [6, -2]);
  const drift = shown['conformal-aci-drift'];
  assert.equal(drift.x_true, undefined, 'the drifting record is measured data: no truth');
  assert.ok(drift.conformal.aci.coverage > drift.conformal.aci.kf_coverage + 0.1, 'ACI covers more than the Kalman interval on the drift');
  assert.equal(await page.$eval('#cf-steps', (e) => e.disabled), true, 'on data the simulation\'s controls are off');
  assert.equal(await page.$eval('#cf-study', (e) => e.hidden), true, 'on data the study (a simulation of the model) is not offered');

  // N reruns and moves the radius.
  await choose(page, 'conformal-gaussian');
  let before = { r: await report(page), px: await pixels(page, 'conformalset'), nb: await numbers(page) };
  await set(page, 'cf-calibration', '999');
  let after = await numbersAreTheReport(page, assert, 'N = 999');
  assert.equal(after.conformal.calibration, 999);
  assert.notEqual(after.conformal.radius2, before.r.conformal.radius2, 'N moves the radius');
  assert.notEqual(await pixels(page, 'conformalset'), before.px, 'N moves the picture');
  // The law reruns: ν's box shows for the Student-t only.
  assert.equal(await page.$eval('#cf-nu-row', (e) => e.hidden), true, 'Gaussian: no ν');
  before = { r: after, px: await pixels(page, 'conformalset') };
  await set(page, 'cf-noise', 'student_t');
  assert.equal(await page.$eval('#cf-nu-row', (e) => e.hidden), false, 'Student-t: ν shows');
  after = await numbersAreTheReport(page, assert, 'Student-t');
  assert.equal(after.conformal.noise, 'student_t');
  assert.notEqual(after.conformal.radius2, before.r.conformal.radius2, 'the law moves the radius');
  assert.notEqual(await pixels(page, 'conformalset'), before.px, 'the law moves the picture');
  assert.match(await numbers(page), /noise law Student-t, ν = 3/);

  // Hostile values: the message next to its field, no exception text, the last picture kept.
  await set(page, 'cf-calibration', '199');
  const good = { px: await pixels(page, 'conformalset'), nb: await numbers(page) };
  const hostile = [
    ['cf-calibration', '3', 'conformal.calibration', /^conformal\.calibration is 3: at level 0\.9 it must be from 9 \(/],
    ['cf-nu', '1', 'conformal.nu', /^conformal\.nu is 1: the Student-t's degrees of freedom must be above 2/],
    ['cf-gamma', '5', 'conformal.gamma', /^conformal\.gamma is 5: ACI's step size γ must lie in \(0, 1\]/],
    ['cf-gamma', 'NaN', 'conformal.gamma', /^conformal\.gamma must be a number$/],
    ['cf-calibration', 'NaN', 'conformal.calibration', /^conformal\.calibration must be a whole number ≥ 0$/],
    ['cf-steps', '5', 'simulate.steps', /^simulate\.steps gives 5 steps: ACI's quantile of the past needs at least 10/],
    ['cf-alpha', '0.999', 'conformal.calibration', /^conformal\.calibration is 199: at level 0\.999 it must be from 999 \(/],
  ];
  const reset = { 'cf-calibration': '199', 'cf-nu': '3', 'cf-gamma': '0.01', 'cf-steps': '120', 'cf-alpha': '0.9' };
  for (const [id, value, field, message] of hostile) {
    await set(page, id, value);
    // (A number box cannot hold "NaN", which a link could carry: the browser empties it, with a
    // console warning, and the page's parser names the field.)
    const err = await text(page, `#conformal form .err[data-for="${field}"]`);
    assert.match(err, message, `${id} = ${value}: "${err}"`);
    assert.doesNotMatch(await formErrors(page), EXCEPTION, `${id} = ${value}: no exception text`);
    assert.equal(await page.$eval(`#conformal form [data-field="${field}"]`, (e) => e.getAttribute('aria-invalid')), 'true', `${id} = ${value}: the field is marked`);
    assert.equal(await page.$eval('#cf-stale', (e) => e.hidden), false, `${id} = ${value}: the stale note shows`);
    assert.equal(await pixels(page, 'conformalset'), good.px, `${id} = ${value}: the last good picture stays`);
    assert.equal(await numbers(page), good.nb, `${id} = ${value}: the last good numbers stay`);
    if (id === 'cf-nu') {
      await page.$eval('#conformal form .err[data-for="conformal.nu"]', (e) => e.scrollIntoView({ block: 'center' }));
      await page.screenshot({ path: join(screenshotDir, 'error-conformal-nu.png') });
    }
    await set(page, id, reset[id]);
    assert.equal(await formErrors(page), '', `${id} back to ${reset[id]}: the message goes`);
  }
  assert.equal(await pixels(page, 'conformalset'), good.px, 'back to the good scenario: the same picture');

  // The study on conformal-gaussian: 200 runs to the end; the counts, the core's bands and the
  // words agree.
  await choose(page, 'conformal-gaussian');
  await set(page, 'cf-runs', '200');
  await page.click('#cf-go');
  await sIdle(page);
  assert.equal(await text(page, '#cf-s-err'), '');
  assert.match(await text(page, '#cf-s-status'), /^200 runs at t = 30 in \d+ ms/);
  const res = await shownText(page, '#cf-s-result');
  const m = res.match(/^conformal: (\d+) \/ 200 inside — band \[(\d+), (\d+)\] \(.*?\) — (in its band|below its band|above its band) Kalman: (\d+) \/ 200 inside — band \[(\d+), (\d+)\] \(.*?\) — (in its band|below its band|above its band)$/);
  assert.ok(m, `the study's result: "${res}"`);
  const words = (k, lo, hi) => (k < lo ? 'below its band' : k > hi ? 'above its band' : 'in its band');
  assert.equal(m[4], words(+m[1], +m[2], +m[3]), 'the conformal count\'s words agree with its band');
  assert.equal(m[8], words(+m[5], +m[6], +m[7]), 'the Kalman count\'s words agree with its band');
  // The bands are the core's for this scenario and run count.
  const core = await page.evaluate(async () => {
    const s = JSON.parse(window.confset.presets()).find((p) => p.name === 'conformal-gaussian').scenario;
    delete s.notes;
    const st = new window.confset.Study(JSON.stringify(s), 200);
    const r = JSON.parse(st.result());
    st.free();
    return r;
  });
  assert.deepEqual([+m[2], +m[3]], core.band, 'the conformal band is the core\'s');
  assert.deepEqual([+m[6], +m[7]], core.kf_band, 'the Kalman band is the core\'s');
  assert.equal(m[4], 'in its band', `under the assumed law the conformal count is in its band (${res})`);

  // conformal-far's study adds the state fixed at (6, −2): counts, no band.
  await choose(page, 'conformal-far');
  assert.equal(await text(page, '#cf-s-result'), '', 'another preset: the old counts go');
  await set(page, 'cf-runs', '100');
  await page.click('#cf-go');
  await sIdle(page);
  const fr = await shownText(page, '#cf-s-result');
  assert.match(fr, /at the fixed state \(6, -2\): conformal \d+ \/ 100, Kalman \d+ \/ 100 inside \(runs whose state at t is this one: neither promise is about a fixed state, so no band\)/, fr);
  await shootSection(page, 'conformal-section', screenshotDir, 'conformal-far-study-dpr2');

  // A share link round-trips the state.
  await choose(page, 'conformal-heavy');
  await set(page, 'cf-nu', '4');
  await set(page, 'cf-gamma', '0.02');
  await set(page, 'cf-seed', '5');
  await set(page, 'cf-time', '40');
  await page.waitForFunction(() => location.hash.startsWith('#conformal/v1/'), null, { timeout: 10_000 });
  await page.waitForTimeout(600); // the last debounced update of the address
  const link = await page.evaluate(() => location.hash);
  const mine = { r: await report(page), nb: await numbers(page), px: await pixels(page, 'aciband') };
  assert.equal(mine.r.conformal.time, 40);
  assert.equal(mine.r.conformal.nu, 4);
  const again = await openApp(env, 2, idle, link.slice(1));
  const fields = await again.$$eval('#conformal form [data-field]', (es) => es.map((e) => `${e.id}=${e.value}`));
  assert.ok(fields.includes('cf-preset=conformal-heavy') && fields.includes('cf-nu=4') && fields.includes('cf-gamma=0.02')
    && fields.includes('cf-seed=5') && fields.includes('cf-time=40'), `the link restores the controls: ${fields.join(', ')}`);
  assert.equal(await numbers(again), mine.nb, 'the link restores the numbers');
  assert.deepEqual(await report(again), mine.r, 'the link restores the report');
  assert.equal(await pixels(again, 'aciband'), mine.px, 'the link restores the picture');
  await again.close();
  await page.close();

  // Screenshots of the heavy-tail and far-out presets: desktop DPR 1, a phone, a slide frame.
  for (const name of ['conformal-heavy', 'conformal-far']) {
    const desk = await openApp(env, 1, idle, `conformal/preset/${name}`);
    await assertDrawnWell(desk, assert, PANELS, `${name} at DPR 1`);
    await desk.screenshot({ path: join(screenshotDir, `${name}-desktop.png`) });
    await shootSection(desk, 'conformal-section', screenshotDir, `${name}-dpr1`);
    await desk.close();

    const phone = await newPage({ viewport: { width: 390, height: 844 }, deviceScaleFactor: 2, isMobile: true, hasTouch: true });
    await phone.goto(`${baseUrl}#conformal/preset/${name}`);
    await waitReady(phone);
    await idle(phone);
    assert.equal(await phone.evaluate(() => document.documentElement.scrollWidth), 390, `${name}: no horizontal scrolling at 390 px`);
    await assertDrawnWell(phone, assert, PANELS, `${name} on a phone`);
    await phone.$eval('#fig-conformalset', (e) => e.scrollIntoView());
    await phone.screenshot({ path: join(screenshotDir, `${name}-phone.png`) });
    await phone.$eval('#cf-numbers-card', (e) => e.scrollIntoView());
    await phone.screenshot({ path: join(screenshotDir, `${name}-phone-numbers.png`) });
    await phone.close();

    for (const panel of PANELS) {
      const slide = await newPage({ viewport: { width: 1280, height: 720 } });
      await slide.goto(`${baseUrl}#conformal/preset/${name}&present&panel=${panel}`);
      await waitReady(slide);
      await idle(slide);
      assert.ok(await slide.evaluate(() => document.body.classList.contains('present')), 'present mode');
      await assertDrawnWell(slide, assert, [panel], `${name} ${panel} in a slide frame`);
      await slide.screenshot({ path: join(screenshotDir, `${name}-slide-${panel}.png`) });
      await slide.close();
    }
  }
}
