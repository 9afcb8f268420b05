// The compare panel end to end: compare-gaussian draws all seven sets (each toggle changes the
// pixels: every method's set is in the picture), the table names each method's assumption and
// whether the truth is held (far out: Kalman misses, SCF and LSCR hold), the time cursor redraws
// (title and picture follow; input → painted frame measured), a click places the true state and
// a small study fills the table with counts, bands and verdicts, uniform noise meets the bounded
// methods' assumptions and bounds below the noise violate them, and screenshots at DPR 1, DPR 2
// and a phone (www/screenshot-compare*.png with CONFSET_REFRESH_SCREENSHOTS=1). The share link is
// the registry's (explorer.test.mjs).
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { text, setField, choosePreset, openApp, shootSection, slideToPaint, assertDrawnWell } from './helpers.mjs';

const METHODS = ['kf', 'conformal', 'scf', 'lscr', 'glls', 'ubb', 'uniform_lp'];
const idle = (page) => page.waitForFunction(() => !document.body.dataset.compareBusy, null, { timeout: 120_000 });
const pixels = (page) => page.$eval('#fig-compare canvas', (c) => c.toDataURL());
const set = (page, id, value) => setField(page, id, value, idle);
const rows = (page) => page.$$eval('#c-numbers tbody tr', (trs) => trs.map((tr) => tr.innerText.replace(/\s+/g, ' ').trim()));
const row = async (page, name) => (await rows(page)).find((r) => r.startsWith(name)) || '';
const www = join(dirname(fileURLToPath(import.meta.url)), '..', '..', 'www');

const drawnWell = (page, assert, what) => assertDrawnWell(page, assert, ['compare'], what);

export default async function compare(env) {
  const { assert, screenshotDir, newPage, baseUrl, waitReady } = env;
  const page = await openApp(env, 1, idle, 'compare');
  assert.deepEqual(await page.$$eval('#c-preset option', (os) => os.map((o) => o.value)), ['compare-gaussian', 'compare-uniform', 'custom']);
  await drawnWell(page, assert, 'compare-gaussian');
  assert.match(await text(page, '#c-num-title'), /^Every method, for x₃₁ predicted from y₁ … y₃₀$/);

  // The table: seven methods, each with a set and its area; far out, Kalman and conformal (both
  // promise an average) miss, SCF and LSCR hold.
  const table = await rows(page);
  assert.equal(table.length, 7, table.join('\n'));
  for (const r of table) assert.doesNotMatch(r, /no set/, r);
  assert.match(await row(page, 'Kalman'), /on average over states \(90 %\).*✓ met.*✗ no/);
  assert.match(await row(page, 'conformal'), /on average over runs, ≥ α, needs N labelled runs \(≥ 90 %\).*✓ met.*✗ no/);
  assert.match(await row(page, 'SCF'), /for every state \(90 %\).*✓ yes/);
  assert.match(await row(page, 'LSCR'), /for every state, at least \(≥ 90 %\).*✓ yes/);
  assert.match(await row(page, 'Tempo'), /✗ violated: Gaussian noise is unbounded/);
  assert.match(await row(page, 'GLLS'), /✗ violated: the system has state noise/);
  assert.match(await row(page, 'uniform LP'), /✗ violated: noise not uniform \(Gaussian\)/);
  for (const r of table) assert.match(r, /\d+\.\d ms/, `each method's run is timed: ${r}`);

  // Every set is in the picture: hiding any one method changes the pixels, and showing it again
  // restores them (a redraw, no run).
  const all = await pixels(page);
  for (const m of METHODS) {
    await page.click(`#c-show-${m}`);
    await idle(page);
    assert.notEqual(await pixels(page), all, `hiding ${m} changes the picture`);
    await page.click(`#c-show-${m}`);
    await idle(page);
    assert.equal(await pixels(page), all, `showing ${m} again gives the same picture`);
  }

  // The time cursor: title and picture follow (each step's sets come from the worker's cursor).
  const ms = [];
  for (const t of [20, 12, 25, 30]) ms.push(await slideToPaint(page, 'c-time', 'compareBusy', t));
  await idle(page);
  await set(page, 'c-time', '20');
  assert.match(await text(page, '#c-num-title'), /^Every method, for x₂₁ predicted from y₁ … y₂₀$/);
  assert.notEqual(await pixels(page), all, 't = 20 draws other sets');
  assert.equal((await rows(page)).length, 7);
  console.log(`    compare time cursor, input → painted frame: ${ms.map((v) => v.toFixed(0)).join(', ')} ms`);
  await set(page, 'c-time', '30');

  // "open in its panel": Tempo's own scenario on this record opens in the ubb panel, whose
  // report holds the same polygon; back to compare.
  await page.locator('#c-numbers tbody tr', { hasText: 'Tempo' }).locator('button.open-panel').click();
  await page.waitForFunction(() => !document.getElementById('ubb-section').hidden
    && /loaded compare-ubb-t30\.json/.test(document.querySelector('#ubb-section .share-status')?.textContent || ''), null, { timeout: 60_000 });
  await page.waitForFunction(() => !document.body.dataset.ubbBusy, null, { timeout: 60_000 });
  assert.match(await text(page, '#b-num-title'), /^At step k = 29: the set of x\(30\)/);
  assert.equal(await text(page, '#fig-ubbset .fig-err'), '');
  await page.goto(`${baseUrl}#compare`);
  await waitReady(page);
  await idle(page);

  // A click on the figure places the true state; a small study counts every method there.
  const c = await page.$('#fig-compare canvas');
  await c.scrollIntoViewIfNeeded();
  const bb = await c.boundingBox();
  await page.mouse.click(bb.x + bb.width * 0.3, bb.y + bb.height * 0.45);
  await idle(page);
  const xbar = await page.$eval('#c-xbar', (e) => e.value);
  assert.match(xbar, /^-?[\d.]+ -?[\d.]+$/, `the click placed x̄ = "${xbar}"`);
  assert.equal(await page.$eval('#c-fix', (e) => e.checked), true);
  await set(page, 'c-runs', '24');
  await page.click('#c-go');
  await page.waitForFunction(() => /^24 runs/.test(document.querySelector('#c-status').textContent), null, { timeout: 180_000 });
  assert.equal(await text(page, '#c-err'), '');
  assert.match(await text(page, '#c-study-how'), /^exact: every record drawn given x_31/);
  const counted = await rows(page);
  for (const r of counted) assert.match(r, /\d+ \/ 24/, `a count in every row: ${r}`);
  assert.match(await row(page, 'SCF'), /\[\d+, \d+\] (inside|below|above) the 99\.9 % band/);
  assert.match(await row(page, 'uniform LP'), /no probability promised/);
  await shootSection(page, 'compare-section', screenshotDir, 'compare-study');

  // Uniform noise: the bounded methods' assumptions are met and their sets hold the truth.
  await choosePreset(page, 'c-preset', 'compare-uniform', idle);
  await drawnWell(page, assert, 'compare-uniform');
  assert.match(await row(page, 'Tempo'), /always \(100 %\).*✓ met.*✓ yes/);
  assert.match(await row(page, 'uniform LP'), /✓ met .*✓ yes/);
  assert.match(await row(page, 'Kalman'), /✗ violated: noise not Gaussian \(uniform\)/);
  await shootSection(page, 'compare-section', process.env.CONFSET_REFRESH_SCREENSHOTS ? www : screenshotDir, 'screenshot-compare-uniform');
  // Bounds at half the noise's: Tempo's assumption is violated, in plain words.
  const good = await pixels(page);
  await set(page, 'c-scale', '0.5');
  assert.match(await row(page, 'Tempo'), /✗ violated: the bounds are 0\.5× the noise's own/);
  assert.match(await text(page, '#c-bounds-out'), /violated: the bounds are 0\.5× the noise's own/);
  if ((await text(page, '#fig-compare .fig-err')) === '') assert.notEqual(await pixels(page), good, 'tighter bounds, other sets');
  await page.close();

  // The README's pictures: the far-out Gaussian case at DPR 1 and 2, and a phone.
  for (const [dpr, viewport, name] of [[1, { width: 1366, height: 900 }, 'screenshot-compare'],
    [2, { width: 1366, height: 900 }, 'compare-dpr2'], [2, { width: 390, height: 844 }, 'compare-phone']]) {
    const p = await newPage({ viewport, deviceScaleFactor: dpr });
    await p.goto(`${baseUrl}#compare`);
    await waitReady(p);
    await idle(p);
    await drawnWell(p, assert, name);
    const size = await p.$eval('#fig-compare canvas', (e) => [e.width, e.clientWidth]);
    assert.equal(size[0], Math.round(size[1] * dpr), `${name}: backing store at DPR ${dpr}`);
    const dir = name === 'screenshot-compare' && process.env.CONFSET_REFRESH_SCREENSHOTS ? www : screenshotDir;
    await shootSection(p, 'compare-section', dir, name);
    await p.close();
  }
}
