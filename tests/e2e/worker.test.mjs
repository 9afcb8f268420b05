// The compute worker end to end: a long run (uniform-paper, its worker held 3 s first by the
// test-only `testOnlySlowMs`, as a long wasm call would: the work budget keeps every accepted
// scenario to about 2 s, too close to the 1 s of Cancel to rely on) leaves the page responsive, shows Cancel after 1 s, is cancelled or replaced by a newer
// scenario, and the panel stays usable; a crash of the worker's wasm instance is contained (the
// message, the scenario to download, the last picture, a fresh worker, no console error); the
// page's Content-Security-Policy holds, and a violation of it is an error the harness fails on.
import { join } from 'node:path';
import { readFileSync } from 'node:fs';

const idle = (page, key, timeout = 60_000) => page.waitForFunction((k) => !document.body.dataset[k], key, { timeout });
const busy = (page, key) => page.evaluate((k) => !!document.body.dataset[k], key);
const pixels = (page, id) => page.$$eval(`#${id} figure.card:not([hidden]) canvas`, (cs) => cs.map((c) => c.toDataURL()));
const note = (page, id) => page.$eval(`#${id} .compute-note`, (e) => (e.hidden ? '' : e.textContent.trim().replace(/\s+/g, ' ')));
const figureErrors = (page, id) => page.$$eval(`#${id} .fig-err`, (es) => es.map((e) => e.textContent).join(''));
// The page's compute module is the same instance the panels use (the same URL):
// `await import(new URL('compute.js', document.baseURI).href)` in the page.
const input = (page, id, value) => page.$eval(`#${id}`, (el, v) => {
  el.value = v;
  el.dispatchEvent(new Event('input', { bubbles: true }));
}, String(value));

async function open(newPage, waitReady, url, key) {
  const page = await newPage({ viewport: { width: 1366, height: 900 } });
  await page.goto(url);
  await waitReady(page);
  await idle(page, key);
  return page;
}

export default async function worker({ newPage, baseUrl, waitReady, assert, screenshotDir, takeErrors }) {
  // ----- the Content-Security-Policy -----
  {
    const page = await open(newPage, waitReady, `${baseUrl}#scf`, 'busy');
    const csp = await page.$eval('meta[http-equiv="Content-Security-Policy"]', (m) => m.content);
    const directive = Object.fromEntries(csp.split(';').map((d) => d.trim().split(/\s+/)).map(([k, ...v]) => [k, v.join(' ')]));
    assert.equal(directive['script-src'], "'self' 'wasm-unsafe-eval'", 'no inline script, no eval');
    assert.equal(directive['worker-src'], "'self'");
    assert.equal(directive['style-src'], "'self'", 'no inline style sheets (style attributes only: plotters measures text with one)');
    assert.doesNotMatch(csp, /'unsafe-eval'|blob:|\*/, csp);
    // The panel drew under it (its module compiled, its worker ran the scenario).
    assert.equal(await figureErrors(page, 'scf'), '');
    // An inline script is refused, and the refusal is an error of the test.
    const ran = await page.evaluate(async () => {
      document.head.append(Object.assign(document.createElement('script'), { textContent: 'window.inlineRan = true' }));
      await new Promise((r) => setTimeout(r, 200));
      return !!window.inlineRan;
    });
    assert.equal(ran, false, 'the inline script did not run');
    const caught = takeErrors(/CSP violation|Content Security Policy/);
    assert.ok(caught.some((e) => /^console\.error: CSP violation: script-src/.test(e)), `the violation is recorded as an error: ${caught.join(' | ')}`);
    console.log(`    CSP: an inline script is refused and recorded (${caught.length} error(s), taken back by this test)`);
    await page.close();
  }

  // ----- a long run: responsive page, Cancel, replacement by a newer scenario -----
  {
    const page = await open(newPage, waitReady, `${baseUrl}#uniform`, 'uniformBusy');
    const before = await pixels(page, 'uniform');
    // Past the work budget: refused before any work, with the field and the limit.
    await input(page, 'u-window', 80);
    await idle(page, 'uniformBusy');
    const refusal = await page.$eval('#uniform .err[data-for="uniform.window"]', (e) => e.textContent);
    assert.match(refusal, /^uniform\.window = 80 .*operations.*limited to about 2\.0e9 operations/, `∂ = 80: ${refusal}`);
    console.log(`    ∂ = 80 refused by the work budget: "${refusal}"`);
    await input(page, 'u-window', 5);
    await idle(page, 'uniformBusy');
    assert.deepEqual(await pixels(page, 'uniform'), before, 'back to the first picture');
    const slow = (ms) => page.evaluate(async (t) => {
      (await import(new URL('compute.js', document.baseURI).href)).computeClients.get('uniform').testOnlySlowMs = t;
    }, ms);
    await slow(3000);
    // Frame gaps and the delay of a real click (its event's time stamp → its handler), with
    // whether the compute was still pending when the handler ran.
    await page.evaluate(() => {
      const probe = { gaps: [], clicks: [], stop: false };
      window.probe = probe;
      let last = performance.now();
      const frame = (t) => { probe.gaps.push(t - last); last = t; if (!probe.stop) requestAnimationFrame(frame); };
      requestAnimationFrame(frame);
      document.addEventListener('pointerdown', (e) => {
        probe.clicks.push({ delay: performance.now() - e.timeStamp, pending: !!document.body.dataset.uniformBusy });
      }, true);
    });
    const t0 = Date.now();
    await input(page, 'u-window', 9);
    await page.waitForFunction(() => document.body.dataset.uniformBusy);
    await page.waitForTimeout(300);
    // Another control while it runs: the toolbar's "Paste data…" opens its box (no compute).
    const paste = '#uniform-section [data-act=paste]';
    const c0 = Date.now();
    await page.click(paste);
    const clickMs = Date.now() - c0;
    assert.equal(await page.$eval('#uniform-section .data-box', (b) => b.hidden), false, 'the click was handled: the box is open');
    await page.click(paste);
    const [click] = await page.evaluate(() => window.probe.clicks);
    assert.ok(click.pending, 'the click was handled while the compute was pending');
    // (Its delay is printed, not asserted: a loaded machine may take any time; that it ran while
    // the compute was pending is what shows the main thread free.)
    console.log(`    long run (∂ = 9, held 3 s): a click handled ${click.delay.toFixed(1)} ms after its event while the run was pending (playwright's click returned in ${clickMs} ms)`);

    // Cancel after 1 s.
    const cancel = '#uniform .compute-note button';
    await page.waitForSelector(cancel, { state: 'visible', timeout: 5_000 });
    const shownMs = Date.now() - t0;
    assert.ok(shownMs >= 1000, `Cancel shows after 1 s (${shownMs} ms)`);
    assert.ok(await busy(page, 'uniformBusy'), 'still computing when Cancel shows');
    assert.match(await note(page, 'uniform'), /^Still computing… Cancel$/);
    await page.$eval('#uniform .compute-note', (e) => e.scrollIntoView({ block: 'center' }));
    await page.screenshot({ path: join(screenshotDir, 'worker-cancel.png') });
    const k0 = Date.now();
    await page.click(cancel);
    await idle(page, 'uniformBusy', 5_000);
    const cancelMs = Date.now() - k0;
    assert.match(await note(page, 'uniform'), /cancelled: the figures show the last computed scenario/);
    assert.deepEqual(await pixels(page, 'uniform'), before, 'the last picture stays');
    console.log(`    Cancel shown ${shownMs} ms after the input; the panel idle ${cancelMs} ms after the click`);

    // Usable afterwards (a fresh worker): ∂ = 10 computes and draws.
    await input(page, 'u-window', 10);
    await idle(page, 'uniformBusy');
    assert.equal(await note(page, 'uniform'), '', 'the note is gone');
    assert.match(await page.$eval('#u-num-title', (e) => e.textContent), /∂ = 10\)/);
    const w10 = await pixels(page, 'uniform');
    assert.notDeepEqual(w10, before, '∂ = 10 draws');

    // A newer scenario replaces a run past 1 s: ∂ = 9, then ∂ = 5 once Cancel shows.
    await input(page, 'u-window', 9);
    await page.waitForSelector(cancel, { state: 'visible', timeout: 5_000 });
    const r0 = Date.now();
    await slow(0);
    await input(page, 'u-window', 5);
    await idle(page, 'uniformBusy', 5_000);
    const replacedMs = Date.now() - r0;
    assert.match(await page.$eval('#u-num-title', (e) => e.textContent), /∂ = 5\)/);
    assert.deepEqual(await pixels(page, 'uniform'), before, 'back to the first picture');
    console.log(`    a newer scenario replaced the long run: drawn ${replacedMs} ms after its input`);

    // The long run to its end, the frames coming all along.
    await slow(3000);
    await page.evaluate(() => { window.probe.gaps.length = 0; });
    const l0 = Date.now();
    await input(page, 'u-window', 12);
    await idle(page, 'uniformBusy', 120_000);
    const longMs = Date.now() - l0;
    assert.match(await page.$eval('#u-num-title', (e) => e.textContent), /∂ = 12\)/);
    assert.equal(await figureErrors(page, 'uniform'), '');
    const gaps = await page.evaluate(() => { window.probe.stop = true; return window.probe.gaps.slice(1); });
    const worst = Math.max(...gaps);
    const timing = await page.$eval('#u-timing', (e) => e.textContent);
    console.log(`    ∂ = 12, held 3 s, to its end: ${longMs} ms (${timing}); ${gaps.length} frames, longest gap ${worst.toFixed(0)} ms (the report's setReport + draw)`);
    await page.close();
  }

  // ----- a crash of the worker's instance -----
  {
    const page = await open(newPage, waitReady, `${baseUrl}#ubb`, 'ubbBusy');
    const before = await pixels(page, 'ubb');
    const seed = Number(await page.$eval('#b-seed', (e) => e.value));
    await page.evaluate(async () => {
      (await import(new URL('compute.js', document.baseURI).href)).computeClients.get('ubb').testOnlyAbortNextRun = true;
    });
    const f0 = Date.now();
    await input(page, 'b-seed', seed + 1);
    await idle(page, 'ubbBusy');
    const faultMs = Date.now() - f0;
    assert.equal(await note(page, 'ubb'), 'The computation failed — this is a bug. Download the scenario to report it. Download the scenario');
    assert.equal(await page.$eval('#ubb .compute-note', (e) => e.getAttribute('role')), 'alert');
    assert.deepEqual(await pixels(page, 'ubb'), before, 'the last picture stays');
    assert.equal(await figureErrors(page, 'ubb'), '');
    await page.$eval('#ubb .compute-note', (e) => e.scrollIntoView({ block: 'center' }));
    await page.screenshot({ path: join(screenshotDir, 'worker-crash.png') });
    // The scenario that failed, to report it.
    const [download] = await Promise.all([page.waitForEvent('download'), page.click('#ubb .compute-note button')]);
    const failed = JSON.parse(readFileSync(await download.path(), 'utf8'));
    assert.equal(failed.method, 'ubb');
    assert.equal(failed.simulate.seed, seed + 1, 'the download holds the scenario that failed');
    assert.match(download.suggestedFilename(), /-failed-scenario\.json$/);
    // A fresh worker, warm before the next input.
    const restart = await page.evaluate(async () => {
      const { workerStarts } = await import(new URL('compute.js', document.baseURI).href);
      const fresh = () => workerStarts.find((s) => s.panel === 'ubb' && s.reason === 'crash' && s.readyMs != null);
      for (let i = 0; i < 200 && !fresh(); i++) await new Promise((r) => setTimeout(r, 50));
      return fresh()?.readyMs;
    });
    assert.ok(restart != null, 'a fresh worker loaded after the crash');
    // Usable afterwards: the next input computes and draws.
    const n0 = Date.now();
    await input(page, 'b-seed', seed + 2);
    await idle(page, 'ubbBusy');
    const nextMs = Date.now() - n0;
    assert.equal(await note(page, 'ubb'), '', 'the message is gone');
    assert.notDeepEqual(await pixels(page, 'ubb'), before, 'a new seed draws');
    assert.equal(await figureErrors(page, 'ubb'), '');
    console.log(`    crash: contained in ${faultMs} ms (message shown, picture kept); a fresh worker loaded in ${restart.toFixed(0)} ms; the next input drawn in ${nextMs} ms`);
    await page.close();
  }

  // ----- the watchdog: a run without an answer is stopped (shortened here to 0.4 s) -----
  {
    const page = await open(newPage, waitReady, `${baseUrl}#uniform`, 'uniformBusy');
    const before = await pixels(page, 'uniform');
    await page.evaluate(async () => {
      const client = (await import(new URL('compute.js', document.baseURI).href)).computeClients.get('uniform');
      Object.assign(client, { watchdogMs: 400, testOnlySlowMs: 2000 });
    });
    const w0 = Date.now();
    await input(page, 'u-window', 9);
    await idle(page, 'uniformBusy', 10_000);
    const stoppedMs = Date.now() - w0;
    assert.equal(await note(page, 'uniform'), 'The computation gave no answer within 0.4 s and was stopped — this is a bug. Download the scenario to report it. Download the scenario');
    assert.deepEqual(await pixels(page, 'uniform'), before, 'the last picture stays');
    const restarted = await page.evaluate(async () => {
      const { workerStarts, computeClients } = await import(new URL('compute.js', document.baseURI).href);
      Object.assign(computeClients.get('uniform'), { watchdogMs: 60_000, testOnlySlowMs: 0 });
      return workerStarts.some((s) => s.panel === 'uniform' && s.reason === 'timeout');
    });
    assert.ok(restarted, 'the silent worker was replaced');
    await input(page, 'u-window', 6);
    await idle(page, 'uniformBusy');
    assert.equal(await note(page, 'uniform'), '', 'the message is gone');
    assert.match(await page.$eval('#u-num-title', (e) => e.textContent), /∂ = 6\)/);
    console.log(`    watchdog (0.4 s): the silent run stopped and reported ${stoppedMs} ms after its input; the next input computes`);
    await page.close();
  }

  // ----- studies on every core: the counts of W workers are the single-run counts -----
  {
    const page = await open(newPage, waitReady, `${baseUrl}#scf`, 'busy');
    const out = await page.evaluate(async () => {
      const { runStudy, poolSize } = await import(new URL('studypool.js', document.baseURI).href);
      const { Study, presets } = window.confset;
      const all = JSON.parse(presets());
      const cases = [['scf-robots', 0], ['ubb-track', 60], ['lscr-predict', 300], ['glls-saturate', 40]];
      const rows = [];
      for (const [name, runs] of cases) {
        const sc = all.find((p) => p.name === name).scenario;
        if (name === 'lscr-predict') Object.assign(sc, { simulate: { ...sc.simulate, condition: { t: 31, x: [0.5, -0.5] } }, lscr: { ...sc.lscr, coverage: { runs, seed: 1 } } });
        const json = JSON.stringify(sc);
        const one = new Study(json, runs);
        const t0 = performance.now();
        let single;
        while (!one.finished()) single = one.step(100000);
        const mainMs = performance.now() - t0;
        one.free();
        const pooled = {};
        for (const w of [1, 2, 3]) {
          const merger = new Study(json, runs);
          const r = await runStudy({ scenario: json, runs, merger, me: {}, onCounts() {}, workers: w });
          pooled[w] = { same: JSON.stringify(r.counts) === single, wall: r.wall };
          merger.free();
        }
        rows.push({ name, runs: JSON.parse(single).runs ?? JSON.parse(single).runs_done, mainMs, pooled });
      }
      return { rows, cores: poolSize() };
    });
    for (const r of out.rows) {
      for (const [w, p] of Object.entries(r.pooled)) assert.ok(p.same, `${r.name}: ${w} worker(s) give the single-run counts`);
      console.log(`    study ${r.name}: ${r.runs} runs — one call on the main thread ${r.mainMs.toFixed(0)} ms; workers 1 / 2 / 3: `
        + `${[1, 2, 3].map((w) => r.pooled[w].wall.toFixed(0)).join(' / ')} ms (wall, same counts; ${out.cores} cores)`);
    }
    await page.close();
  }
}
