// The uniform-innovation panel end to end: the four core-drawn figures of uniform-paper, the time
// cursor moving every figure and the numbers, the window length and the method changing them,
// bad input shown inline while the last pictures stay, wasm timings measured in the page
// (Session.run of the paper's 120 samples; a 5-sample window LP), and screenshots at DPR 1 and 2.
import { text, setField, choosePreset, openApp, shootSection, assertDrawnAtRatio, assertDrawnWell } from './helpers.mjs';

const PANELS = ['ustates', 'uoutput', 'uparams', 'upolygon'];
const idle = (page) => page.waitForFunction(() => !document.body.dataset.uniformBusy, null, { timeout: 60_000 });
// NFC: the page writes hats as combining marks (A + ̂), the regexes below as Â where one exists.
const numbers = (page) => page.$eval('#u-numbers-card', (e) => e.innerText.trim().replace(/\s+/g, ' ').normalize('NFC'));
const pixels = (page, panel) => page.$eval(`#fig-${panel} canvas`, (c) => c.toDataURL());
const allPixels = async (page) => Object.fromEntries(await Promise.all(PANELS.map(async (p) => [p, await pixels(page, p)])));
const set = (page, id, value) => setField(page, id, value, idle);
const choose = (page, name) => choosePreset(page, 'u-preset', name, idle);
const NUM = '-?[\\d.]+(?:e[+-]?\\d+)?';

const drawnWell = (page, assert, what) => assertDrawnWell(page, assert, PANELS, what);

const shoot = (page, screenshotDir, name) => shootSection(page, 'uniform-section', screenshotDir, name);

export default async function uniform(env) {
  const { assert, screenshotDir } = env;
  for (const dpr of [1, 2]) {
    const page = await openApp(env, dpr, idle, 'uniform');

    // The uniform presets live in this panel's menu only.
    const menu = (id) => page.$$eval(`#${id} option`, (os) => os.map((o) => o.value));
    assert.deepEqual(await menu('u-preset'), ['uniform-paper', 'custom']);
    for (const id of ['preset', 'l-preset', 'g-preset']) {
      assert.ok(!(await menu(id)).some((v) => v.startsWith('uniform')), `#${id} has no uniform preset`);
    }

    // uniform-paper: four figures at the pixel ratio.
    assert.equal(await page.$eval('#u-preset', (e) => e.value), 'uniform-paper');
    await assertDrawnAtRatio(page, assert, dpr, PANELS, 380);
    await drawnWell(page, assert, 'uniform-paper');
    let nb = await numbers(page);
    assert.match(await text(page, '#u-num-title'), /^At the time cursor t = 120: window 116 … 120 \(∂ = 5\), swapping \(4\.1\)$/);
    assert.match(nb, new RegExp(`true x120 \\(${NUM}, ${NUM}\\) LP estimate \\(${NUM}, ${NUM}\\) Kalman filter \\(${NUM}, ${NUM}\\)`), nb);
    assert.match(nb, new RegExp(`optimal face of x120 x₁ ∈ \\[${NUM}, ${NUM}\\] x₂ ∈ \\[${NUM}, ${NUM}\\]`));
    assert.match(nb, new RegExp(`objective Σx̂r \\+ Σŷr ${NUM} vs the truth’s 0\\.9 ✓ the optimum is never above the truth’s`));
    assert.match(nb, /truth in polygon ✓ inside \(polygon with the estimated Θ̂120, not the true Θ: no guarantee\)/);
    assert.match(nb, new RegExp(`RMS state error t = 5 … 120 LP ${NUM} vs KF ${NUM} — the hard bounds (help|hurt) here`));
    assert.match(nb, new RegExp(`RMS prediction error ${NUM}`));
    assert.match(nb, new RegExp(`final Â \\[${NUM} ${NUM}; ${NUM} ${NUM}\\] true \\[1 0\\.5; -0\\.5 0\\]`));
    assert.match(nb, /final B̂ \[.+\] true \[1; 3\]/);
    assert.match(nb, /final Ĉ \[.+\] true \[1 1\]/);
    assert.match(nb, /final x̂r, ŷr \(.+\), \(.+\) true \(0\.3, 0\.3\), \(0\.3\)/);
    assert.match(nb, /half-width bounds extended \d+ times?/);
    assert.match(await text(page, '#u-timing'), /^rendered in [\d.]+ ms \(run [\d.]+ ms \+ draw [\d.]+ ms\)$/);
    assert.match(await text(page, '#u-time-out'), /^= 120$/);
    assert.match(await text(page, '#u-time-window'), /^window 116 … 120: polygon, face ranges$/);
    assert.equal(await page.$eval('#u-time', (e) => [e.value, e.min, e.max].join()), '120,1,120');

    if (dpr === 1) {
      // The cursor read-out of every figure.
      for (const p of PANELS) {
        const c = await page.$(`#fig-${p} canvas`);
        await c.scrollIntoViewIfNeeded();
        const bb = await c.boundingBox();
        let cur = '';
        for (const [fx, fy] of [0.3, 0.5, 0.7, 0.9].flatMap((y) => [0.55, 0.35, 0.8].map((x) => [x, y]))) {
          await page.mouse.move(bb.x + bb.width * fx, bb.y + bb.height * fy);
          cur = await text(page, `#fig-${p} .cursor`);
          if (cur) break;
        }
        assert.match(cur, /^.+ = -?[\d.e+-]+, .+ = -?[\d.e+-]+$/, `${p} cursor read-out: "${cur}"`);
      }
      await page.mouse.move(1, 1);

      // The time cursor: every figure's marker moves, and the numbers follow.
      const before = await allPixels(page);
      await set(page, 'u-time', 60);
      const after = await allPixels(page);
      for (const p of PANELS) assert.notEqual(after[p], before[p], `time 120 → 60 moves the ${p} figure`);
      const nb60 = await numbers(page);
      assert.notEqual(nb60, nb, 'the numbers change with the cursor');
      assert.match(await text(page, '#u-num-title'), /^At the time cursor t = 60: window 56 … 60/);
      assert.match(nb60, /true x60 \(/);
      assert.match(await text(page, '#u-time-out'), /^= 60$/);
      assert.match(await text(page, '#u-time-window'), /^window 56 … 60/);
      await set(page, 'u-time', 120);
      const back = await allPixels(page);
      for (const p of PANELS) assert.equal(back[p], before[p], `back to t = 120: the same ${p} figure`);
      assert.equal(await numbers(page).then((s) => s.replace(/rendered in .*$/, '')), nb.replace(/rendered in .*$/, ''));

      // The window length: the estimates, hence the pictures and the numbers, change.
      await set(page, 'u-window-range', 10);
      assert.equal(await page.$eval('#u-window', (e) => e.value), '10', 'the slider sets the window field');
      const w10 = await allPixels(page);
      const nbw = await numbers(page);
      assert.match(await text(page, '#u-num-title'), /window 111 … 120 \(∂ = 10\)/);
      assert.match(nbw, /RMS state error t = 10 … 120/);
      assert.notEqual(nbw, nb, 'the numbers change with the window');
      for (const p of ['ustates', 'upolygon']) assert.notEqual(w10[p], before[p], `∂ = 10 changes the ${p} figure`);
      await set(page, 'u-window-range', 5);

      // The method: Θ known — the polygon uses the true Θ and must hold the truth.
      await set(page, 'u-estimator', 'states');
      const known = await allPixels(page);
      const nbs = await numbers(page);
      assert.match(await text(page, '#u-num-title'), /Θ known$/);
      assert.match(nbs, /truth in polygon ✓ inside \(polygon with the true Θ: it must hold the truth\)/, nbs);
      assert.match(nbs, /✓ the optimum is never above the truth’s/);
      // Not observable (C·A = 0.5·C): with the true Θ the optimal face of x_t is a segment along x₁ − x₂.
      const face = nbs.match(new RegExp(`x₁ ∈ \\[(${NUM}), (${NUM})\\] x₂ ∈ \\[(${NUM}), (${NUM})\\]`)).slice(1).map(Number);
      assert.ok(face[1] - face[0] > 0.1 && face[3] - face[2] > 0.1, `Θ known: a long optimal face ${face}`);
      assert.match(nbs, /final Â \[1 0\.5; -0\.5 0\] true \[1 0\.5; -0\.5 0\]/);
      for (const p of ['ustates', 'uparams', 'upolygon']) assert.notEqual(known[p], before[p], `Θ known changes the ${p} figure`);
      await set(page, 'u-estimator', 'expansion');
      assert.match(await text(page, '#u-num-title'), /expansion \(4\.2\)$/);
      await drawnWell(page, assert, 'expansion');
      assert.notEqual(await numbers(page), nbs);
      await set(page, 'u-estimator', 'swapping');

      // Bad input: the message under the field it names; the last good pictures stay.
      const good = await allPixels(page);
      const bad = async (id, value, field, re) => {
        const last = await allPixels(page);
        await set(page, id, value);
        const err = await text(page, `#uniform .err[data-for="${field}"]`);
        assert.match(err, re, `inline error for ${field}: "${err}"`);
        assert.equal(await page.$eval('#u-stale', (e) => e.hidden), false, `${field}: the stale-picture note is shown`);
        const now = await allPixels(page);
        for (const p of PANELS) assert.equal(now[p], last[p], `${field}: the last good ${p} figure stays`);
      };
      const fine = async () => {
        assert.equal(await page.$eval('#u-stale', (e) => e.hidden), true, 'valid again: no stale note');
        assert.equal(await page.$$eval('#uniform .err[data-for]', (es) => es.map((e) => e.textContent).join('')), '');
      };
      await bad('u-window', 0, 'uniform.window', /^uniform\.window must be a whole number from 1 to 80, found 0/);
      assert.equal(await page.$eval('#u-window', (e) => e.getAttribute('aria-invalid')), 'true');
      await set(page, 'u-window', 5);
      await fine();
      await bad('u-xr', '-0.3', 'uniform.xr', /^uniform\.xr must hold half-widths > 0/);
      await set(page, 'u-xr', 'a');
      assert.match(await text(page, '#uniform .err[data-for="uniform.xr"]'), /^uniform\.xr must be numbers/);
      await set(page, 'u-xr', '0.3');
      await bad('u-xbound', 0.5, 'uniform.x_bound', /^uniform\.x_bound = 0\.5 is violated by the simulated states \(\|x\| reaches [\d.]+\)/);
      await set(page, 'u-xbound', 5);
      await bad('u-uhalf', -1, 'uniform.u_half', /^uniform\.u_half must be a finite half-width ≥ 0/);
      await set(page, 'u-uhalf', 0.5);
      await page.$eval('#u-estimator', (el) => { el.append(new Option('kalman', 'kalman')); });
      await bad('u-estimator', 'kalman', 'uniform.estimator', /^uniform\.estimator must be one of "states", "parameters", "swapping" or "expansion", found "kalman"$/);
      await page.$eval('#u-estimator', (el) => { el.value = 'swapping'; el.querySelector('option[value=kalman]').remove(); el.dispatchEvent(new Event('input', { bubbles: true })); });
      await idle(page);
      await bad('u-steps', '', 'simulate.steps', /^simulate\.steps must be a whole number/);
      await set(page, 'u-steps', 120);
      await fine();
      const again = await allPixels(page);
      for (const p of PANELS) assert.equal(again[p], good[p], `valid again: the same ${p} figure`);

      // Custom model: non-numeric matrices, wrong dimensions.
      await choose(page, 'custom');
      await drawnWell(page, assert, 'custom');
      assert.match(await numbers(page), /final Â \[.+\] true \[0\.8 0\.3; -0\.3 0\.7\]/);
      await bad('u-m-F', '0.8 x\n-0.3 0.7', 'model.F', /^model\.F has “x” in row 1, which is not a number/);
      assert.equal(await page.$eval('#u-m-F', (e) => e.getAttribute('aria-invalid')), 'true');
      await set(page, 'u-m-F', '0.8 0.3\n-0.3 0.7');
      await bad('u-m-H', '1 0 0', 'model.H', /^model\.H /);
      await set(page, 'u-m-H', '1 0');
      await bad('u-m-D', '0 0', 'uniform.D', /^uniform\.D /);
      await set(page, 'u-m-D', '0');
      await fine();
      await drawnWell(page, assert, 'custom again');
      await choose(page, 'uniform-paper');

      // The in-page wasm timings.
      const timing = await page.evaluate(() => {
        const { Session, presets } = window.confset;
        const sc = JSON.parse(presets()).find((p) => p.name === 'uniform-paper').scenario;
        const best = (f, n) => {
          const ms = [];
          for (let i = 0; i < n; i++) { const t0 = performance.now(); f(); ms.push(performance.now() - t0); }
          ms.sort((a, b) => a - b);
          return { best: ms[0], median: ms[Math.floor(n / 2)] };
        };
        const s = new Session();
        const paper = JSON.stringify(sc);
        const run = best(() => s.run(paper), 7);
        // Five growing windows, the LP at the cursor, 2n(∂ + 1) + 2(n + m) face LPs on one
        // loaded problem and the exact polygon's support LPs (at most `directions`, its budget):
        // the difference between budgets 64 and 8 is the difference of the calls reported.
        const one = JSON.parse(paper);
        one.simulate.steps = 5;
        Object.assign(one.uniform, { estimator: 'states', window: 5, directions: 64 });
        const j64 = JSON.stringify(one);
        const lp = best(() => s.run(j64), 30);
        const calls = JSON.parse(s.run(j64)).uniform.at.polygon.calls;
        one.uniform.directions = 8;
        const j8 = JSON.stringify(one);
        const lp8 = best(() => s.run(j8), 30);
        const calls8 = JSON.parse(s.run(j8)).uniform.at.polygon.calls;
        const r = JSON.parse(s.run(paper)).uniform;
        s.free();
        return { run, lp, lp8, calls, calls8, steps: r.steps.length, estimator: r.estimator };
      });
      const f = (x) => `${x.best.toFixed(2)} ms best, ${x.median.toFixed(2)} ms median`;
      console.log(`  [wasm timing] Session.run uniform-paper (${timing.steps} samples, ${timing.estimator}, ∂ = 5): ${f(timing.run)} of 7 (target ≤ 500 ms)`);
      console.log(`  [wasm timing] Session.run with steps = 5, estimator "states", ∂ = 5 (5 on line + 1 + 30 face LPs + ${timing.calls} polygon support LPs, budget 64): ${f(timing.lp)} of 30`);
      console.log(`  [wasm timing]   the same with the polygon's budget 8 (${timing.calls8} support LPs): ${f(timing.lp8)} of 30`);
      const extra = timing.calls - timing.calls8;
      if (extra > 0) console.log(`  [wasm timing]   one support LP of the window (∂ = 5, n = 2) ≈ run difference / ${extra} = ${((timing.lp.median - timing.lp8.median) / extra).toFixed(3)} ms (medians; target ≤ 2 ms)`);
      assert.equal(timing.steps, 120);
    }

    await drawnWell(page, assert, `uniform-paper at DPR ${dpr}`);
    await shoot(page, screenshotDir, `uniform-paper-dpr${dpr}`);
  }
}
