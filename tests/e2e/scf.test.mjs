// The SCF vs KF panel end to end: presets, sliders that change the picture, a bad matrix shown
// inline while the last picture stays, the chunked Monte Carlo, and screenshots at DPR 1 and 2.
import { join } from 'node:path';
import { readFile } from 'node:fs/promises';
import { openApp, assertDrawnAtRatio, downloadFigure, setField } from './helpers.mjs';

const readDownload = async (d) => readFile(await d.path(), 'utf8');

const idle = (page) => page.waitForFunction(() => !document.body.dataset.busy, null, { timeout: 60_000 });
const pixels = (page, fig = 'fig-state') => page.$eval(`#${fig} canvas`, (c) => c.toDataURL());
const text = (page, sel) => page.$eval(sel, (e) => e.textContent.trim());

const slide = (page, id, value) => setField(page, id, value, idle);

async function choose(page, name) {
  await page.selectOption('#preset', name);
  await idle(page);
}

export default async function scf(env) {
  const { assert, screenshotDir } = env;
  for (const dpr of [1, 2]) {
    const page = await openApp(env, dpr, idle, 'scf');

    // Hi-DPI: the backing store is the CSS size times the pixel ratio, and a figure was drawn.
    await assertDrawnAtRatio(page, assert, dpr, ['state']);
    assert.equal(await text(page, '#fig-state .fig-err'), '', 'the state figure is drawn without error');
    assert.match(await text(page, '#t-run'), /^computed in [\d.]+ ms$/);
    assert.match(await text(page, '#t-draw'), /drawn in [\d.]+ ms/);

    // Every preset runs and draws; every simulated one has its Monte Carlo one click away.
    for (const name of ['scf-robots', 'scf-robots-literal', 'custom', 'scf-scalar']) {
      await choose(page, name);
      assert.equal(await text(page, '#fig-state .fig-err'), '', `${name}: state figure drawn`);
      assert.equal(await page.$eval('#mc', (e) => e.hidden), false, `${name}: Monte Carlo section`);
      assert.equal(await page.$eval('#mc tr.robots', (e) => e.hidden), !name.startsWith('scf-robots'), `${name}: collision warnings row`);
      assert.ok((await text(page, '#notes')).length > 20, `${name}: notes shown`);
    }

    // The scalar preset shows Fig. 1; its coverage curve changes with α.
    assert.equal(await page.$eval('#fig-coverage', (e) => e.hidden), false, 'Fig. 1 is shown for the scalar preset');
    const [state0, cov0] = [await pixels(page), await pixels(page, 'fig-coverage')];
    await slide(page, 'alpha', 0.8);
    assert.notEqual(await pixels(page), state0, 'moving α changes the state figure');
    assert.notEqual(await pixels(page, 'fig-coverage'), cov0, 'moving α changes Fig. 1');

    // The time slider changes the view only.
    const computed = await text(page, '#t-run');
    const before = await pixels(page);
    await slide(page, 'time', 20);
    assert.notEqual(await pixels(page), before, 'moving t changes the state figure');
    assert.equal(await text(page, '#num-t'), '20');
    assert.equal(await text(page, '#t-run'), computed, 'moving t does not recompute');

    // The cursor's position is read out in chart units.
    const box = await page.$eval('#fig-state canvas', (c) => { const r = c.getBoundingClientRect(); return [r.x, r.y, r.width, r.height]; });
    await page.mouse.move(box[0] + box[2] * 0.5, box[1] + box[3] * 0.45);
    assert.match(await text(page, '#fig-state .cursor'), /=\s*-?[\d.]/, 'cursor coordinates shown');

    // Robots: the time slider moves the ellipses.
    await choose(page, 'scf-robots');
    const r36 = await pixels(page);
    await slide(page, 'time', 20);
    assert.notEqual(await pixels(page), r36, 'robots: moving t changes the picture');
    // The axis names come with the report, as in `confset figure`: robot A's position.
    const rb = await page.$eval('#fig-state canvas', (c) => { const r = c.getBoundingClientRect(); return [r.x, r.y, r.width, r.height]; });
    await page.mouse.move(rb[0] + rb[2] * 0.5, rb[1] + rb[3] * 0.5);
    const readout = await text(page, '#fig-state .cursor');
    assert.match(readout, /^position p_x .* = .*, position p_y .* = /, `robots: cursor names the position axes: "${readout}"`);

    // Custom mode: a non-symmetric V is named inline, the last picture stays.
    await choose(page, 'custom');
    const good = await pixels(page);
    await page.fill('#m-V', '0.01 0.5\n0 0.04');
    await idle(page);
    const err = await text(page, '.err[data-for="model.V"]');
    assert.match(err, /^model\.V .*symmetric/, `inline error for V: "${err}"`);
    assert.equal(await page.$eval('#m-V', (e) => e.getAttribute('aria-invalid')), 'true');
    assert.equal(await page.$eval('#stale', (e) => e.hidden), false, 'the stale-picture note is shown');
    assert.equal(await pixels(page), good, 'the last good picture stays');
    await page.fill('#m-F', '0.9 x\n0 0.9');
    await idle(page);
    assert.match(await text(page, '.err[data-for="model.F"]'), /^model\.F .*not a number/);
    await page.fill('#m-F', '0.98 0.1\n0 0.9');
    await page.fill('#m-V', '0.01 0\n0 0.04');
    await idle(page);
    // The two fills may be two runs: the last one's answer clears the error (CI saw the first's
    // message still shown when the panel first went idle).
    await page.waitForFunction(() => !document.querySelector('.err[data-for="model.V"]').textContent && !document.body.dataset.busy, null, { timeout: 30_000 }).catch(() => {});
    assert.equal(await text(page, '.err[data-for="model.V"]'), '', 'the error clears once V is valid');
    assert.equal(await page.$eval('#stale', (e) => e.hidden), true);

    if (dpr === 1) {
      // Monte Carlo with a small N: counts and the binomial range appear.
      await choose(page, 'scf-robots');
      await page.fill('#mc-n', '300');
      await page.click('#mc-go');
      await page.waitForFunction(() => /runs in \d+ ms/.test(document.getElementById('mc-status').textContent), null, { timeout: 60_000 });
      await idle(page);
      const scfIn = await text(page, '#mc-scf-in');
      const m = scfIn.match(/^(\d+) \/ 300$/);
      assert.ok(m, `SCF count shown: "${scfIn}"`);
      assert.ok(Number(m[1]) >= 250, `SCF covers the colliding state in most runs: ${scfIn}`);
      assert.match(await text(page, '#mc-kf-in'), /^\d+ \/ 300$/);
      assert.match(await text(page, '#mc-scf-w'), /^\d+ \/ 300$/);
      assert.match(await text(page, '#mc-range'), /binomial range/);
      assert.equal(await text(page, '#mc-err'), '');
      // Counts belong to their scenario: switching preset clears them.
      await choose(page, 'scf-robots-literal');
      assert.equal(await text(page, '#mc-scf-in'), '–', 'Monte Carlo counts cleared on a preset change');

      // The scalar example: the state fixed at x̄ = 25 (about 10 σ of the prior). The SCF count
      // lies in the core's 99.9 % binomial range around α·N; the Kalman region, pulled to the
      // prior mean, holds x̄ far less often (Fig. 1: about 0.2 at x̄ = 25).
      await choose(page, 'scf-scalar');
      assert.match(await text(page, '#mc h2.fixed'), /x̄ = 25 at t = 50/);
      await page.fill('#mc-n', '2000');
      await page.click('#mc-go');
      await page.waitForFunction(() => /runs in \d+ ms/.test(document.getElementById('mc-status').textContent), null, { timeout: 60_000 });
      await idle(page);
      const [kfIn, scfIn2] = [await text(page, '#mc-kf-in'), await text(page, '#mc-scf-in')];
      const count = (t) => Number(t.match(/^([\d,]+) \/ 2,000$/)?.[1].replace(/,/g, ''));
      const [kfK, scfK] = [count(kfIn), count(scfIn2)];
      assert.ok(Number.isInteger(kfK) && Number.isInteger(scfK), `counts shown: KF "${kfIn}", SCF "${scfIn2}"`);
      assert.match(await text(page, '#mc-range'), /should lie in \[[\d,]+, [\d,]+\] .*it does\./, `SCF within its range: ${scfIn2}`);
      assert.ok(kfK < 0.5 * scfK, `KF holds x̄ = 25 far less often than SCF: ${kfIn} vs ${scfIn2}`);
      assert.equal(await text(page, '#mc-err'), '');
    }

    // Downloads: the figure as SVG (drawn by the same Rust code on plotters' SVG backend), the report.
    const svgDl = await downloadFigure(page, '#fig-state', 'svg');
    assert.match(svgDl.suggestedFilename(), /\.svg$/);
    const svgText = await readDownload(svgDl);
    assert.ok(svgText.includes('<svg'), 'the SVG download is SVG');
    const [jsonDl] = await Promise.all([page.waitForEvent('download'), page.click('#dl-report')]);
    const report = JSON.parse(await readDownload(jsonDl));
    assert.ok(Array.isArray(report.steps) && report.steps.length > 0, 'the report download is the report');
    const pngDl = await downloadFigure(page, '#fig-state', 'png-1');
    assert.match(pngDl.suggestedFilename(), /-state-1x\.png$/);

    // A resize refits the backing stores (no recompute needed).
    await page.setViewportSize({ width: 1000, height: 800 });
    await page.waitForFunction((r) => {
      const c = document.querySelector('#fig-state canvas');
      return c.width === Math.round(c.clientWidth * r) && !document.body.dataset.busy;
    }, dpr, { timeout: 10_000 });
    await page.setViewportSize({ width: 1366, height: 900 });
    await idle(page);

    for (const name of ['scf-scalar', 'scf-robots']) {
      await choose(page, name);
      await page.screenshot({ path: join(screenshotDir, `${name}-dpr${dpr}.png`), fullPage: true });
    }
  }
}
