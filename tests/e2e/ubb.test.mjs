// The set-membership (ubb) panel end to end: the two core-drawn figures of ubb-track and its
// numbers, ε moving the polygon and the numbers, an ε so small the data contradict the bounds
// shown inline (field ubb.eps, "infeasible") while the last picture stays, the l1 and l2 norms,
// the chunked guarantee (truth never outside the set), every preset, the animation of k, and
// screenshots at DPR 1 and 2 (www/screenshot-ubb.png from DPR 1 with CONFSET_REFRESH_SCREENSHOTS=1).
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { text, setField, choosePreset, openApp, shootSection, assertDrawnAtRatio, assertDrawnWell } from './helpers.mjs';

const PANELS = ['ubbset', 'ubbwidth'];
const PRESETS = ['ubb-track', 'ubb-series', 'ubb-leontief', 'ubb-markov'];
const idle = (page) => page.waitForFunction(() => !document.body.dataset.ubbBusy, null, { timeout: 60_000 });
const gIdle = (page) => page.waitForFunction(() => !document.body.dataset.ubbGuaranteeBusy, null, { timeout: 120_000 });
const numbers = (page) => page.$eval('#b-numbers-card', (e) => e.innerText.trim().replace(/\s+/g, ' '));
const pixels = (page, panel) => page.$eval(`#fig-${panel} canvas`, (c) => c.toDataURL());
const set = (page, id, value) => setField(page, id, value, idle);
const choose = (page, name) => choosePreset(page, 'b-preset', name, idle);
const NUM = '-?[\\d.]+(?:e[+-]?\\d+)?';
const www = join(dirname(fileURLToPath(import.meta.url)), '..', '..', 'www');

async function drawnWell(page, assert, what) {
  await assertDrawnWell(page, assert, PANELS, what);
  assert.equal(await text(page, '#ubb form .err[data-for="ubb.eps"]'), '', `${what}: no ε error`);
}

export default async function ubb(env) {
  const { assert, screenshotDir } = env;
  for (const dpr of [1, 2]) {
    const page = await openApp(env, dpr, idle, 'ubb');

    // The ubb presets live in this panel's menu only.
    const menu = (id) => page.$$eval(`#${id} option`, (os) => os.map((o) => o.value));
    assert.deepEqual(await menu('b-preset'), [...PRESETS, 'custom']); // then the custom model, as in every panel
    for (const id of ['preset', 'l-preset', 'g-preset', 'u-preset']) {
      assert.ok(!(await menu(id)).some((v) => v.startsWith('ubb')), `#${id} has no ubb preset`);
    }

    // ubb-track at k = 40: two figures at the pixel ratio, the numbers.
    assert.equal(await page.$eval('#b-preset', (e) => e.value), 'ubb-track');
    await assertDrawnAtRatio(page, assert, dpr, PANELS, 380);
    await drawnWell(page, assert, 'ubb-track');
    let nb = await numbers(page);
    assert.match(await text(page, '#b-num-title'), /^At step k = 40: the set of x\(41\) from y\(11\) … y\(40\), l∞ bounds$/);
    assert.match(nb, /window 30 steps/);
    assert.match(nb, /LP size \d+ variables, \d+ rows/);
    assert.match(nb, new RegExp(`polygon \\d+ vertices from \\d+ LPs — exact`));
    // The central estimate (31) beside Theorem 2's linear optimal one, each ± its error.
    assert.match(nb, new RegExp(`estimates central \\(strongly optimal, \\(31\\)\\): x₁ = ${NUM} ± ${NUM}, x₂ = ${NUM} ± ${NUM}; `
      + `linear optimal \\(Theorem 2\\): x₁ = ${NUM} ± ${NUM}, x₂ = ${NUM} ± ${NUM}`));
    assert.match(nb, /Theorem 2 active rows x₁: u at t = [\d–, ]+; η at t = [\d–, ]+ \(32 rows\)/);
    assert.match(nb, new RegExp(`radius ${NUM}`));
    assert.match(nb, /Theorem 4 bound 1\.222/);
    assert.match(nb, /Theorem 5 j 29/);
    assert.match(nb, /truth inside the set ✓ yes/);
    assert.match(nb, /truth inside the KF 99 % ellipsoid [✓✗]/);
    assert.match(nb, new RegExp(`prediction of y\\(41\\) ∈ \\[${NUM}, ${NUM}\\]`));
    assert.match(nb, /over the run truth outside the set 0 \/ 60 steps/);
    assert.match(await text(page, '#b-window-out'), /^Theorem 5: j = 29, window 30 steps$/);
    assert.match(await text(page, '#b-timing'), /^rendered in [\d.]+ ms \(run [\d.]+ ms \+ draw [\d.]+ ms\)$/);
    assert.match(await text(page, '#b-time-out'), /^= 40$/);

    if (dpr === 1) {
      // Timings of the page's wasm run (report of 60 steps, 30-step windows, the polygon).
      const ms = await page.evaluate(() => {
        const s = new window.confset.Session();
        const sc = JSON.parse(window.confset.presets()).find((p) => p.name === 'ubb-track').scenario;
        const t0 = performance.now();
        for (let i = 0; i < 3; i++) s.run(JSON.stringify(sc));
        const dt = (performance.now() - t0) / 3;
        s.free();
        return dt;
      });
      console.log(`    ubb-track Session.run in the page: ${ms.toFixed(1)} ms`);

      // ε moves the polygon and the numbers.
      const before = { set: await pixels(page, 'ubbset'), nb };
      await set(page, 'b-eps', '0.3');
      await drawnWell(page, assert, 'ε = 0.3');
      assert.notEqual(await pixels(page, 'ubbset'), before.set, 'ε changes the polygon picture');
      nb = await numbers(page);
      assert.notEqual(nb, before.nb, 'ε changes the numbers');
      assert.match(nb, /truth inside the set ✓ yes/);

      // ε so small the data contradict the bounds: inline error naming ε, last picture kept.
      const good = await pixels(page, 'ubbset');
      const goodNb = await numbers(page);
      await set(page, 'b-eps', '0.001');
      const err = await text(page, '#ubb form .err[data-for="ubb.eps"]');
      assert.match(err, /^ubb\.eps leaves no state consistent with the data under these bounds/, `inline ε error: "${err}"`);
      assert.equal(await page.$eval('#b-eps', (e) => e.getAttribute('aria-invalid')), 'true');
      assert.equal(await page.$eval('#b-stale', (e) => e.hidden), false, 'the stale note shows');
      assert.equal(await pixels(page, 'ubbset'), good, 'the last good picture stays');
      assert.equal(await numbers(page), goodNb, 'the last good numbers stay');
      if (dpr === 1) {
        await page.$eval('#ubb form .err[data-for="ubb.eps"]', (e) => e.scrollIntoView({ block: 'center' }));
        await page.screenshot({ path: join(screenshotDir, 'error-ubb-eps.png') });
      }
      await set(page, 'b-eps', '0.2');
      await drawnWell(page, assert, 'ε back to 0.2');
      assert.equal(await page.$eval('#b-stale', (e) => e.hidden), true);

      // The l1 and l2 norms: other pictures, no error.
      let last = await pixels(page, 'ubbset');
      for (const [norm, name] of [['l1', 'l₁'], ['l2', 'l₂']]) {
        await set(page, 'b-norm', norm);
        await drawnWell(page, assert, `norm ${norm}`);
        const now = await pixels(page, 'ubbset');
        assert.notEqual(now, last, `${norm} changes the picture`);
        last = now;
        assert.match(await text(page, '#b-num-title'), new RegExp(`${name} bounds$`));
        assert.match(await numbers(page), /truth inside the set ✓ yes/);
      }
      await set(page, 'b-norm', 'linf');

      // Noise at the bound and empty α, β (∞): still guaranteed.
      await set(page, 'b-noise', 'true');
      await drawnWell(page, assert, 'noise at the bound');
      assert.match(await numbers(page), /truth inside the set ✓ yes/);
      await set(page, 'b-noise', 'false');

      // δ = ∞ (empty) and α = ∞: the set is unbounded until the data fix the state; no error.
      await set(page, 'b-delta', '');
      await set(page, 'b-alpha', '∞');
      await drawnWell(page, assert, 'δ = ∞, α = ∞');
      assert.match(await numbers(page), /truth inside the set ✓ yes/);
      await set(page, 'b-delta', '2');
      await set(page, 'b-alpha', '50');

      // The guarantee: a few runs, never outside the set.
      await set(page, 'b-runs', '60');
      await page.click('#b-go');
      await gIdle(page);
      assert.equal(await text(page, '#b-g-err'), '');
      const g = await text(page, '#b-g-result');
      assert.match(g, /^truth outside the set: 0 \/ 60; outside the KF 99 % ellipse: \d+ \/ 60/, g);
      assert.match(await text(page, '#b-g-status'), /^60 runs at k = 40 in \d+ ms/);

      // Theorem 2 in the read-out is the report's: φ ± E of each plane component, E at least
      // the hull's half-width (the central algorithm is optimal).
      const rep = await page.evaluate(() => {
        const s = new window.confset.Session();
        const sc = JSON.parse(window.confset.presets()).find((p) => p.name === 'ubb-track').scenario;
        const r = JSON.parse(s.run(JSON.stringify(sc)));
        s.free();
        return r.ubb.at;
      });
      assert.equal(rep.linear.length, 2);
      const shown = (await numbers(page)).match(new RegExp(`linear optimal \\(Theorem 2\\): x₁ = (${NUM}) ± (${NUM}), x₂ = (${NUM}) ± (${NUM})`));
      assert.ok(shown, 'the linear optimal estimate is read out');
      rep.linear.forEach((l, c) => {
        assert.ok(Math.abs(Number(shown[1 + 2 * c]) - l.estimate) <= 5e-3 * (1 + Math.abs(l.estimate)), `φ${c}`);
        assert.ok(Math.abs(Number(shown[2 + 2 * c]) - l.error) <= 5e-3 * l.error, `E${c}`);
        assert.ok(0.5 * (rep.hi[c] - rep.lo[c]) <= l.error + 1e-9, `half-width ≤ E (${c})`);
      });

      // True noise apart from the assumed bounds: within them no miss; above them (|η| ≤ 0.25,
      // |u| ≤ 0.12 against ε = 0.2, τ = 0.1) the read-out says there is no guarantee and the
      // guarantee study counts misses (runs whose data contradict the bounds among them).
      assert.equal(await page.$eval('#b-sim-eps', (e) => e.value), '0.2');
      assert.equal(await page.$eval('#b-sim-tau', (e) => e.value), '0.1');
      assert.match(await text(page, '#b-sim-out'), /^within the assumed bounds/);
      await set(page, 'b-sim-eps', '0.25');
      await set(page, 'b-sim-tau', '0.12');
      await drawnWell(page, assert, 'true noise above the bounds');
      assert.match(await text(page, '#b-sim-out'), /^the noise exceeds the bounds the estimator assumes: no guarantee/);
      assert.match(await numbers(page), /\(the noise exceeds the bounds the estimator assumes: no guarantee\)/);
      await page.waitForFunction(() => location.hash.startsWith('#ubb/v1/'), null, { timeout: 10_000 });
      await page.waitForTimeout(600); // the last debounced update of the address
      const link = await page.evaluate(() => location.hash);
      await set(page, 'b-runs', '300');
      await page.click('#b-go');
      await gIdle(page);
      assert.equal(await text(page, '#b-g-err'), '');
      const over = await text(page, '#b-g-result');
      const missed = Number((over.match(/^truth outside the set: (\d+) \/ 300/) || [])[1]);
      assert.ok(missed > 0, `true noise above the bounds: misses counted (${over})`);
      assert.match(over, /no guarantee$/);
      // The share link keeps the true noise.
      assert.match(link, /^#ubb\/v1\//, link);
      const again = await openApp(env, 1, idle, link.slice(1));
      await again.waitForFunction(() => document.querySelector('#b-sim-eps')?.value === '0.25'
        && document.querySelector('#b-sim-tau')?.value === '0.12', null, { timeout: 30_000 });
      await idle(again);
      assert.match(await text(again, '#b-sim-out'), /^the noise exceeds the bounds/);
      await again.close();
      // Back within the bounds (true below assumed): no miss.
      await set(page, 'b-sim-eps', '0.15');
      await set(page, 'b-sim-tau', '0.1');
      await drawnWell(page, assert, 'true noise within the bounds');
      assert.match(await text(page, '#b-sim-out'), /^within the assumed bounds/);
      await page.click('#b-go');
      await gIdle(page);
      assert.match(await text(page, '#b-g-result'), /^truth outside the set: 0 \/ 300;/);
      await set(page, 'b-sim-eps', '0.2');
      await set(page, 'b-runs', '60');

      // The step slider moves the set (a redraw: cursor.test.mjs counts the runs); the
      // animation steps k to the last step, and the share link follows.
      await set(page, 'b-time', '20');
      assert.match(await text(page, '#b-num-title'), /^At step k = 20: the set of x\(21\) from y\(0\) … y\(20\)/);
      await page.selectOption('#ubb .anim-bar [data-anim=speed]', '20');
      await page.click('#b-animate');
      await page.waitForFunction(() => Number(document.querySelector('#b-time').value) >= 22, null, { timeout: 30_000 });
      await idle(page);
      const k = Number(await page.$eval('#b-time', (e) => e.value));
      assert.equal(k, 59, `animated to the last step k = ${k}`);
      assert.match(await text(page, '#b-num-title'), new RegExp(`^At step k = ${k}: the set of x\\(${k + 1}\\) from`));
      assert.equal(await text(page, '#b-animate'), '▶ play');
      await set(page, 'b-time', '40');

      // The cursor read-out of both figures.
      for (const p of PANELS) {
        const c = await page.$(`#fig-${p} canvas`);
        await c.scrollIntoViewIfNeeded();
        const bb = await c.boundingBox();
        let cur = '';
        for (const [fx, fy] of [0.3, 0.5, 0.7].flatMap((y) => [0.55, 0.35, 0.8].map((x) => [x, y]))) {
          await page.mouse.move(bb.x + bb.width * fx, bb.y + bb.height * fy);
          cur = await text(page, `#fig-${p} .cursor`);
          if (cur) break;
        }
        assert.match(cur, /^.+ = -?[\d.e+-]+, .+ = -?[\d.e+-]+$/, `${p} cursor read-out: "${cur}"`);
      }
      await page.mouse.move(0, 0);

      // Every preset loads and draws without error.
      for (const name of PRESETS) {
        await choose(page, name);
        await drawnWell(page, assert, name);
        const n = await numbers(page);
        assert.match(n, /truth inside the set ✓ yes/, `${name}: ${n}`);
        await shootSection(page, 'ubb-section', screenshotDir, `ubb-${name}`);
      }
      await choose(page, 'ubb-track');
      await set(page, 'b-runs', '200');
      await page.click('#b-go');
      await gIdle(page);
      assert.match(await text(page, '#b-g-result'), /^truth outside the set: 0 \/ 200;/);
      // The README picture is refreshed on purpose only (CONFSET_REFRESH_SCREENSHOTS=1): a test
      // run must not rewrite tracked files.
      await shootSection(page, 'ubb-section', process.env.CONFSET_REFRESH_SCREENSHOTS ? www : screenshotDir, 'screenshot-ubb');
    }
    await shootSection(page, 'ubb-section', screenshotDir, `ubb-dpr${dpr}`);
  }
}
