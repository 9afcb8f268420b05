// The time cursors (the set-membership step k, the uniform-innovation time t) only redraw: for
// each panel, once its worker has prefetched every step's detail, ten cursor moves issue no run
// of the core and no detail computation (both counted in the page and in the workers), every
// move changes the picture and the way back gives the report's own pixels; a move right after a
// new report (its details not yet there) draws the step complete once its detail comes, at the
// cost of that report's one run; ▶ play (at its fastest, 20 steps/s) plays to the last step
// without a run. Printed, not asserted: input → painted frame of the moves (median and max of 10)
// and the animation's steps per second.

import { slideToPaint } from './helpers.mjs';

const PANELS = [
  { id: 'ubb', busy: 'ubbBusy', slider: 'b-time', animate: 'b-animate', seed: 'b-seed', figure: 'ubbset',
    title: '#b-num-title', complete: /^At step k = (\d+): the set of .* from y\(\d+\) … y\(\d+\)/ },
  { id: 'uniform', busy: 'uniformBusy', slider: 'u-time', animate: 'u-animate', seed: 'u-seed', figure: 'upolygon',
    title: '#u-num-title', complete: /^At the time cursor t = (\d+): window \d+ … \d+ /, },
];

const idle = (page, key, timeout = 60_000) => page.waitForFunction((k) => !document.body.dataset[k], key, { timeout });
const text = (page, sel) => page.$eval(sel, (e) => e.textContent.trim().replace(/\s+/g, ' '));
const pixels = (page, id, figure) => page.$eval(`#${id} figure.card[data-panel="${figure}"] canvas`, (c) => c.toDataURL());
const figureErrors = (page, id) => page.$$eval(`#${id} .fig-err`, (es) => es.map((e) => e.textContent).join(''));

// The core's runs (Session.run) and detail computations (Cursor.at), in the page and in its workers.
async function counts(page) {
  const get = () => ({ runs: globalThis.__runs || 0, ats: globalThis.__ats || 0 });
  const all = [await page.evaluate(get)];
  for (const w of page.workers()) all.push(await w.evaluate(get));
  return all.reduce((a, c) => ({ runs: a.runs + c.runs, ats: a.ats + c.ats }), { runs: 0, ats: 0 });
}

// Move the cursor to `v`; the time to the painted frame (the explorer's slider → paint measure).
const move = (page, d, v) => slideToPaint(page, d.slider, d.busy, v);

export default async function cursor({ newPage, baseUrl, waitReady, assert }) {
  for (const d of PANELS) {
    const page = await newPage({ viewport: { width: 1366, height: 900 } });
    await page.route('**/pkg/confset.js', async (route) => {
      const response = await route.fetch();
      const body = (await response.text())
        .replace(/(\n    run\(scenario_json\) \{)/, '$1 globalThis.__runs = (globalThis.__runs || 0) + 1;')
        .replace(/(\n    at\(t\) \{)/, '$1 globalThis.__ats = (globalThis.__ats || 0) + 1;');
      await route.fulfill({ response, body });
    });
    await page.goto(`${baseUrl}#${d.id}`);
    await waitReady(page);
    await idle(page, d.busy);
    const range = await page.$eval(`#${d.slider}`, (r) => [Number(r.min), Number(r.max), Number(r.value)]);
    const [lo, hi, start] = range;

    // Every step's detail prefetched: the worker's count of details stops growing at one per step.
    const steps = hi - lo + 1;
    let c0;
    for (let i = 0; i < 240; i++) {
      c0 = await counts(page);
      if (c0.ats >= steps) break;
      await page.waitForTimeout(250);
    }
    await page.waitForTimeout(300);
    c0 = await counts(page);
    assert.ok(c0.ats <= steps + 1, `${d.id}: each step's detail computed once (${c0.ats} for ${steps} steps)`);
    assert.equal(c0.runs, 1, `${d.id}: one run of the core for the first report`);

    // Ten moves: no run, no detail computed, the picture follows the cursor.
    const before = await pixels(page, d.id, d.figure);
    const values = [...Array(10)].map((_, i) => lo + Math.round((((i * 7) % 10) + 0.5) / 10 * (hi - lo)));
    const ms = [];
    let last = before;
    for (const v of values) {
      ms.push(await move(page, d, v));
      const now = await pixels(page, d.id, d.figure);
      assert.notEqual(now, last, `${d.id}: the cursor at ${v} changes the picture`);
      last = now;
      const m = (await text(page, d.title)).match(d.complete);
      assert.ok(m, `${d.id}: at ${v} the numbers are complete: "${await text(page, d.title)}"`);
      assert.ok(Number(m[1]) >= v, `${d.id}: the numbers are those of step ${v} (or the first bounded step)`);
      await page.waitForTimeout(100);
    }
    assert.equal(await figureErrors(page, d.id), '', `${d.id}: every figure draws at every step`);
    const c1 = await counts(page);
    assert.deepEqual(c1, c0, `${d.id}: ten cursor moves issue no run and compute no detail`);
    await move(page, d, start);
    assert.equal(await pixels(page, d.id, d.figure), before, `${d.id}: back at ${start}, the report's own picture`);
    ms.sort((a, b) => a - b);
    console.log(`    [cursor] ${d.id}: input → painted frame ${((ms[4] + ms[5]) / 2).toFixed(1)} ms median, ${ms[9].toFixed(1)} ms max of 10 moves `
      + `(${c0.ats} details prefetched for ${steps} steps; 0 runs, 0 details during the moves)`);

    // ▶ play from the first step to the last, at 20 steps/s over the cached steps.
    await move(page, d, lo);
    await page.selectOption(`#${d.id} .anim-bar [data-anim=speed]`, '20');
    const anim = await page.evaluate(async ([id, btn, busy]) => {
      const r = document.getElementById(id);
      const changes = [];
      let seen = r.value;
      const t0 = performance.now();
      document.getElementById(btn).click();
      await new Promise((res) => {
        const poll = () => {
          if (r.value !== seen) { seen = r.value; changes.push(performance.now()); }
          if (document.body.dataset[busy] || performance.now() - t0 < 100) requestAnimationFrame(poll); else res();
        };
        requestAnimationFrame(poll);
      });
      return { steps: changes.length, s: (changes[changes.length - 1] - changes[0]) / 1000, value: Number(r.value) };
    }, [d.slider, d.animate, d.busy]);
    assert.equal(anim.value, hi, `${d.id}: the animation plays to the last step`);
    assert.deepEqual(await counts(page), c0, `${d.id}: the animation issues no run and computes no detail`);
    console.log(`    [cursor] ${d.id}: ▶ play at 20 steps/s: ${((anim.steps - 1) / anim.s).toFixed(1)} steps/s (${anim.steps} steps in ${anim.s.toFixed(2)} s)`);

    // Right after a new report, a far step before its detail came: drawn complete once it comes,
    // with the one run of the new report.
    await page.$eval(`#${d.seed}`, (e) => { e.value = String(Number(e.value) + 1); e.dispatchEvent(new Event('input', { bubbles: true })); });
    await idle(page, d.busy);
    const far = lo + Math.round(0.15 * (hi - lo));
    await move(page, d, far);
    await idle(page, d.busy);
    assert.equal(await figureErrors(page, d.id), '', `${d.id}: drawn at ${far} after a new report`);
    assert.match(await text(page, d.title), d.complete, `${d.id}: the numbers at ${far} complete once its detail came`);
    assert.equal((await counts(page)).runs, c0.runs + 1, `${d.id}: the new seed is one run; the cursor none`);
    await page.close();
  }
}
