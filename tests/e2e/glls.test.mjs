// The GLLS panel end to end: the four core-drawn figures of glls-saturate, the horizon slider
// moving every figure's marker and the numbers, the state-noise estimator and its QP check on
// glls-unstable5, the chunked Monte Carlo redrawing the precision figure, bad input shown inline
// while the last pictures stay, wasm timings measured in the page, and screenshots at DPR 1 and 2.
import { text, setField, choosePreset, openApp, shootSection, assertDrawnAtRatio, assertDrawnWell } from './helpers.mjs';

const PANELS = ['singular', 'index', 'plane', 'precision'];
const idle = (page) => page.waitForFunction(
  () => !document.body.dataset.gllsBusy && !document.body.dataset.gllsMcBusy, null, { timeout: 60_000 });
const numbers = (page) => page.$eval('#g-numbers', (e) => e.innerText.trim().replace(/\s+/g, ' '));
const pixels = (page, panel) => page.$eval(`#fig-${panel} canvas`, (c) => c.toDataURL());
const allPixels = async (page) => Object.fromEntries(await Promise.all(PANELS.map(async (p) => [p, await pixels(page, p)])));

const set = (page, id, value) => setField(page, id, value, idle);
const choose = (page, name) => choosePreset(page, 'g-preset', name, idle);

const drawnWell = (page, assert, what) => assertDrawnWell(page, assert, PANELS, what);

async function monteCarlo(page, runs) {
  await page.fill('#g-mc-n', String(runs));
  await page.click('#g-mc-go');
  const re = new RegExp(`^${runs.toLocaleString('en-US')} runs in \\d+ ms`);
  await page.waitForFunction((src) => new RegExp(src).test(document.getElementById('g-mc-status').textContent),
    re.source, { timeout: 120_000 });
  await idle(page);
}

const shoot = (page, screenshotDir, name) => shootSection(page, 'glls-section', screenshotDir, name);

export default async function glls(env) {
  const { assert, screenshotDir } = env;
  for (const dpr of [1, 2]) {
    const page = await openApp(env, dpr, idle, 'glls');

    // glls-saturate: four figures at the pixel ratio, the Monte Carlo started with the scenario.
    assert.equal(await page.$eval('#g-preset', (e) => e.value), 'glls-saturate');
    await assertDrawnAtRatio(page, assert, dpr, PANELS, 380);
    assert.match(await text(page, '#g-mc-status'), /^2,000 runs in \d+ ms/, "the preset's 2000-run study ran with the scenario");
    await drawnWell(page, assert, 'glls-saturate');
    let nb = await numbers(page);
    assert.match(await text(page, '#g-num-title'), /^x\(39\) from y\(31\) … y\(39\): s = 8, k = 39, LLS$/);
    assert.match(nb, /best horizon s = 8 \(in use\)/, nb);
    assert.match(nb, /σ\(Γ9\) [\d.]+, [\d.]+, [\d.]+/);
    assert.match(nb, /max \|log₁₀ σ − log₁₀ σ′\| = [\d.]+: the singular values do NOT coincide/);
    assert.match(nb, /past x\(31\) [\d.]+ [\d.]+ [\d.]+ current x\(39\)/);
    assert.match(nb, /guaranteed ball radius [\d.]+ .*✓ inside/);
    assert.match(nb, /guaranteed box .*x₃ ∈ \[[-\d.e]+, [-\d.e]+\] ✓ inside/);
    assert.match(nb, /rounding estimate [\d.e-]+ \(negligible\)/);
    assert.match(nb, /Regularized, p = 2 of 3/);
    assert.match(nb, /vs projected truth/);
    assert.doesNotMatch(nb, /Rounding dominates/);
    assert.match(await text(page, '#g-timing'), /^rendered in [\d.]+ ms \(run [\d.]+ ms \+ draw [\d.]+ ms\)$/);
    assert.match(await text(page, '#g-s-out'), /= 8 \(best\)/);
    assert.equal(await page.$eval('#g-s', (e) => [e.value, e.max].join()), '8,39');

    if (dpr === 1) {
      // The cursor read-out: log axes read the value itself, not its log10.
      for (const p of PANELS) {
        const c = await page.$(`#fig-${p} canvas`);
        await c.scrollIntoViewIfNeeded();
        const bb = await c.boundingBox();
        await page.mouse.move(bb.x + bb.width * 0.55, bb.y + bb.height * 0.5);
        const cur = await text(page, `#fig-${p} .cursor`);
        assert.match(cur, /^.+ = -?[\d.e+-]+, .+ = -?[\d.e+-]+$/, `${p} cursor read-out: "${cur}"`);
        if (p === 'singular') assert.match(cur, /^horizon s = \d+, .*σ.* = [\d.]+$/, `singular cursor: "${cur}"`);
      }
      await page.mouse.move(1, 1);

      // The horizon slider: every figure's marker moves, and the numbers follow.
      const before = await allPixels(page);
      await set(page, 'g-s', 14);
      assert.equal(await page.$eval('#g-auto', (e) => e.checked), false, 'moving the slider leaves the best horizon');
      const after = await allPixels(page);
      for (const p of PANELS) assert.notEqual(after[p], before[p], `horizon 8 → 14 moves the ${p} figure's marker`);
      const nb14 = await numbers(page);
      assert.notEqual(nb14, nb, 'the numbers change with the horizon');
      assert.match(await text(page, '#g-num-title'), /s = 14, k = 39/);
      assert.match(nb14, /σ\(Γ15\)/);
      assert.match(nb14, /best horizon s = 8;/);
      assert.match(await text(page, '#g-s-out'), /^= 14$/);
      assert.match(await text(page, '#g-mc-status'), /^2,000 runs/, 'the study is kept: it does not depend on the horizon');
      await set(page, 'g-s', 8);
      const nb0 = await numbers(page);
      const back = await allPixels(page);
      for (const p of PANELS) assert.equal(back[p], before[p], `back to s = 8: the same ${p} figure`);

      // Worst-case noise on the ball ‖δ(j)‖ = μ, aligned with the gain of the horizon in use: the
      // truth lands on the edge of the box in the first plane component, still inside.
      await set(page, 'g-noise', 'worst');
      nb = await numbers(page);
      assert.match(nb, /largest ‖δ\(j\)‖ drawn 0\.1000 ≤ μ/, nb);
      assert.match(nb, /guaranteed box .*✓ inside/);
      const [lo, hi] = await page.evaluate(() => {
        const m = document.querySelector('#g-numbers').innerText.match(/x₂ ∈ \[(-?[\d.e+-]+), (-?[\d.e+-]+)\]/);
        return [Number(m[1]), Number(m[2])];
      });
      const truth2 = Number(nb.match(/truth x\(39\) \([^,]+, (-?[\d.e+-]+),/)[1]);
      assert.ok(Math.min(Math.abs(truth2 - lo), Math.abs(truth2 - hi)) < 2e-4 * (hi - lo) + 1e-4,
        `worst case: x₂ = ${truth2} on an edge of [${lo}, ${hi}]`);
      await set(page, 'g-noise', 'bounded');
      assert.equal(await numbers(page), nb0, 'back to bounded noise: the same numbers');

      // The Monte Carlo with N = 100 redraws the precision figure.
      const prec = await pixels(page, 'precision');
      await monteCarlo(page, 100);
      assert.match(await text(page, '#g-mc-status'), /^100 runs in \d+ ms on \d+ workers? \(computing \d+ ms in all, \d+ µs per run, \d+ horizons\)$/);
      assert.equal(await page.$eval('#g-mc-progress', (e) => [e.value, e.max].join()), '100,100');
      assert.match(await text(page, '#g-mc-verdict'), /^Smallest median error [\d.e-]+ at s = \d+ \(expected bound there [\d.e-]+\)\. Mean ‖x\(k\)‖ = [\d.]+\.$/);
      assert.equal(await text(page, '#g-mc-err'), '');
      assert.notEqual(await pixels(page, 'precision'), prec, 'the 100-run study redraws the precision figure');
      assert.equal(await text(page, '#fig-precision .fig-err'), '');

      // Cancel stops a long study (200,000 runs: the errors kept for the quartiles stay within
      // the core's memory budget).
      await page.fill('#g-mc-n', '200000');
      await page.click('#g-mc-go');
      await page.waitForFunction(() => /^\d[\d,]* \/ 200,000 runs$/.test(document.getElementById('g-mc-status').textContent), null, { timeout: 30_000 });
      await page.click('#g-mc-cancel');
      await page.waitForFunction(() => /cancelled after/.test(document.getElementById('g-mc-status').textContent), null, { timeout: 30_000 });
      await idle(page);
      await page.fill('#g-mc-n', '500');

      // Bad input: the core's message under the field it names; the last good pictures stay.
      const good = await allPixels(page);
      const bad = async (id, value, field, re) => {
        const last = await allPixels(page);
        await set(page, id, value);
        const err = await text(page, `#glls .err[data-for="${field}"]`);
        assert.match(err, re, `inline error for ${field}: "${err}"`);
        assert.equal(await page.$eval('#g-stale', (e) => e.hidden), false, `${field}: the stale-picture note is shown`);
        const now = await allPixels(page);
        for (const p of PANELS) assert.equal(now[p], last[p], `${field}: the last good ${p} figure stays`);
      };
      await bad('g-s', 0, 'glls.horizon', /^glls\.horizon s = 0: Γ_\{s\+1\} has rank 1 < n = 3: x\(k−s\) is not observable/);
      assert.equal(await page.$eval('#g-s', (e) => e.getAttribute('aria-invalid')), 'true');
      await set(page, 'g-s', 8);
      assert.equal(await text(page, '#glls .err[data-for="glls.horizon"]'), '', 'the error clears once s is valid');
      assert.equal(await page.$eval('#g-stale', (e) => e.hidden), true);
      await bad('g-p', 4, 'glls.p', /^glls\.p must be a whole number from 1 to 3/);
      await set(page, 'g-p', 2);
      await bad('g-mu', -1, 'glls.mu', /^glls\.mu must be a finite bound ≥ 0/);
      await set(page, 'g-mu', 0.1);
      await bad('g-estimator', 'state_noise', 'model.V', /^model\.V must be positive definite for the state-noise estimator/);
      await set(page, 'g-estimator', 'lls');
      await bad('g-steps', '', 'simulate.steps', /^simulate\.steps must be a whole number/);
      await set(page, 'g-steps', 40);
      await bad('g-max', 0, 'glls.max_horizon', /^glls\.max_horizon must be a whole number from 1 to 2000/);
      await set(page, 'g-max', 60);
      const again = await allPixels(page);
      for (const p of PANELS) assert.equal(again[p], good[p], `valid again: the same ${p} figure`);
      assert.equal(await page.$eval('#g-stale', (e) => e.hidden), true);

      // Custom model: non-numeric F, Ω not positive definite for GLLS, a wrong C.
      await choose(page, 'custom');
      await drawnWell(page, assert, 'custom');
      await bad('g-m-F', '0.95 x\n-0.3 0.95', 'model.F', /^model\.F has “x” in row 1, which is not a number/);
      assert.equal(await page.$eval('#g-m-F', (e) => e.getAttribute('aria-invalid')), 'true');
      await set(page, 'g-m-F', '0.95 0.3\n-0.3 0.95');
      await set(page, 'g-m-W', '0'); // fine for LLS (Ω = I) …
      assert.equal(await page.$eval('#g-stale', (e) => e.hidden), true);
      await bad('g-estimator', 'glls', 'model.W', /^model\.W must be positive definite for GLLS/); // … not for GLLS
      await set(page, 'g-m-W', '0.01');
      await bad('g-m-H', '1 0 0', 'model.H', /^model\.H /);
      await bad('g-x0', '1 a', 'model.x1_mean', /^model\.x1_mean must be numbers/);
      await set(page, 'g-x0', '1 0');
      await set(page, 'g-m-H', '1 0');
      assert.equal(await page.$eval('#g-stale', (e) => e.hidden), true);
      assert.match(await numbers(page), /GLLS/);
      await drawnWell(page, assert, 'custom, GLLS');

      // glls-grow on 80 steps at s = 30: ‖x(k)‖ ≈ 10¹⁵ and rounding swamps the bound — a visible warning.
      await choose(page, 'glls-grow');
      assert.match(await numbers(page), /best horizon s = 60 \(the end of the curves/);
      await set(page, 'g-steps', 80);
      await set(page, 'g-s', 30);
      nb = await numbers(page);
      assert.match(nb, /⚠ Rounding dominates: the estimated floating-point error [\d.e+-]+ rivals the statistical bound/, nb);
      assert.equal(await page.$eval('#g-numbers .alarm', (e) => getComputedStyle(e).display !== 'none' && e.offsetHeight > 0), true);
      await set(page, 'g-steps', 40); // ‖x(k)‖ ≈ 10⁷: rounding negligible again
      assert.doesNotMatch(await numbers(page), /Rounding dominates/);

      // The in-page wasm timings.
      const timing = await page.evaluate(() => {
        const { Session, Study, presets } = window.confset;
        const sc = JSON.parse(presets()).find((p) => p.name === 'glls-saturate').scenario;
        const best = (f, n) => {
          const ms = [];
          for (let i = 0; i < n; i++) { const t0 = performance.now(); f(); ms.push(performance.now() - t0); }
          ms.sort((a, b) => a - b);
          return { best: ms[0], median: ms[Math.floor(n / 2)] };
        };
        const plain = JSON.parse(JSON.stringify(sc));
        const mc = plain.glls.monte_carlo;
        delete plain.glls.monte_carlo;
        const s = new Session();
        const run60 = best(() => s.run(JSON.stringify(plain)), 20);
        plain.glls.max_horizon = 500;
        const run500 = best(() => s.run(JSON.stringify(plain)), 10);
        const withMc = JSON.parse(JSON.stringify(sc));
        withMc.glls.monte_carlo = { ...mc, runs: 2000 };
        const t0 = performance.now();
        const g = new Study(JSON.stringify(withMc), 0);
        let c;
        while (!g.finished()) c = JSON.parse(g.step(500));
        const study = performance.now() - t0;
        g.free();
        s.free();
        return { run60, run500, study, runs: c.runs, horizons: c.horizons.length };
      });
      const f = (x) => `${x.best.toFixed(2)} ms best, ${x.median.toFixed(2)} ms median`;
      console.log(`  [wasm timing] Session.run glls-saturate without monte_carlo (S = 60): ${f(timing.run60)} of 20`);
      console.log(`  [wasm timing] Session.run glls-saturate without monte_carlo, max_horizon = 500: ${f(timing.run500)} of 10`);
      console.log(`  [wasm timing] Study (GLLS) 2000 runs (glls-saturate, ${timing.horizons} horizons, step 500): ${timing.study.toFixed(0)} ms `
        + `(${(1000 * timing.study / timing.runs).toFixed(0)} µs per run)`);
      assert.equal(timing.runs, 2000);
    }

    // The screenshots: each preset after a 2000-run study.
    for (const name of ['glls-saturate', 'glls-unstable5']) {
      await choose(page, name);
      await monteCarlo(page, 2000);
      await drawnWell(page, assert, name);
      nb = await numbers(page);
      if (name === 'glls-unstable5') {
        assert.match(await text(page, '#g-num-title'), /s = 8, k = 15, state-noise estimator/);
        assert.match(nb, /State-noise estimator \(60\)–\(64\): x̂\(15\) = \(/, nb);
        assert.match(nb, /QP check \(clarabel vs closed form\): max difference [\d.e-]+ ✓ agree/);
        assert.match(await text(page, '#g-mc-kind'), /state-noise estimator vs LLS/);
        assert.match(await text(page, '#g-mc-verdict'), /the state-noise estimator has the smaller median at \d+ of \d+ horizons/);
      }
      await shoot(page, screenshotDir, `${name}-dpr${dpr}`);
    }
  }
}
