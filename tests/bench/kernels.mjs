// The wasm side of `.ci/bench`, in Debian's Chromium over the served release build:
//   node tests/bench/kernels.mjs http://127.0.0.1:PORT/
// 1. The comparison's kernels (src/bench.rs, the same code `cargo bench --bench speed --
//    kernels` times natively) through the module's `BenchKernel`: one warm-up, then the
//    median of 11 in the page; one `BENCH <key> <ms> <what ran>` line each.
// 2. Slider → painted frame for every slider of every panel of the registry: the input event,
//    the panel's compute (in its worker) or redraw, then the next painted frame; median and max
//    of 10 moves, one `SLIDER <panel> <slider> <median> <max>` line each.
// 3. Load → first panel interactive (navigation start → the panel's ready flag), median of 5.
// 4. The page's studies (studypool.js) on one worker and on every core: the robot Monte Carlo
//    (10,000 runs), the set-membership guarantee (ubb-track, 2,000 runs) and the compare study
//    (compare-gaussian and compare-uniform, 200 runs each), best of 3 wall
//    times, one `STUDY <preset> <runs> <1 worker ms> <W workers ms> <W>` line each.
// It prints; it asserts nothing (timings belong to the machine).
import { PANELS } from '../../www/registry.js';
import { slideToPaint } from '../e2e/helpers.mjs';
import { args, launch, openReady } from './browser.mjs';

const [base] = args((a) => a[0], 'node tests/bench/kernels.mjs BASE_URL');
const browser = await launch();
const settled = (page) => page.waitForFunction(
  () => !Object.keys(document.body.dataset).some((k) => k === 'busy' || k.endsWith('Busy')), null, { timeout: 60_000 });
const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];

// 1. Kernels.
{
  const page = await openReady(browser, base);
  for (const key of ['robot_mc', 'lscr_raster', 'glls_curves', 'ubb_step', 'uniform_report']) {
    const r = await page.evaluate((k) => {
      const kernel = new window.confset.BenchKernel(k);
      let what = kernel.run();
      const ms = [];
      for (let i = 0; i < 11; i++) {
        const t0 = performance.now();
        what = kernel.run();
        ms.push(performance.now() - t0);
      }
      kernel.free();
      ms.sort((a, b) => a - b);
      return { ms: ms[5], what };
    }, key);
    console.log(`BENCH ${key} ${r.ms.toFixed(3)} ${r.what}`);
  }
  await page.close();
}

// 2. Every slider of every panel.
for (const d of PANELS) {
  const page = await openReady(browser, `${base}#${d.id}`, { viewport: { width: 1366, height: 900 } });
  await settled(page);
  const sliders = await page.evaluate((id) => [...document.getElementById(id).querySelectorAll('input[type=range]')]
    .filter((e) => e.offsetParent && !e.disabled)
    .map((e) => ({ id: e.id, range: [Number(e.min), Number(e.max), Number(e.step) || 1], value: Number(e.value) })), d.id);
  for (const s of sliders) {
    const [lo, hi, step] = s.range;
    const ms = [];
    for (let i = 0; i < 10; i++) {
      const v = lo + Math.round((((i % 5) + 1) / 6) * (hi - lo) / step) * step;
      ms.push(await slideToPaint(page, s.id, d.busy, v));
      await settled(page);
      await page.waitForTimeout(50);
    }
    console.log(`SLIDER ${d.id} #${s.id} ${median(ms).toFixed(1)} ${Math.max(...ms).toFixed(1)}`);
    // Back where it was, for the next slider.
    await slideToPaint(page, s.id, d.busy, s.value);
    await settled(page);
  }
  await page.close();
}

// 3. Load → first panel interactive.
for (const d of PANELS) {
  const ms = [];
  for (let i = 0; i < 5; i++) {
    const page = await openReady(browser, `${base}#${d.id}`, { viewport: { width: 1366, height: 900 } });
    ms.push(await page.evaluate(() => performance.now()));
    await page.close();
  }
  console.log(`LOAD ${d.id} ${median(ms).toFixed(0)} ${Math.max(...ms).toFixed(0)}`);
}
// 4. Studies on one worker and on every core.
{
  const page = await openReady(browser, `${base}#scf`);
  await settled(page);
  for (const [name, runs] of [['scf-robots', 10000], ['ubb-track', 2000],
    ['compare-gaussian', 200], ['compare-uniform', 200]]) {
    const r = await page.evaluate(async ([name, runs]) => {
      const { runStudy, poolSize } = await import(new URL('studypool.js', document.baseURI).href);
      const { Study, presets } = window.confset;
      const json = JSON.stringify(JSON.parse(presets()).find((p) => p.name === name).scenario);
      const wall = {};
      for (const w of [1, poolSize()]) {
        const best = [];
        for (let i = 0; i < 3; i++) {
          const merger = new Study(json, runs);
          best.push((await runStudy({ scenario: json, runs, merger, me: {}, onCounts() {}, workers: w })).wall);
          merger.free();
        }
        wall[w] = Math.min(...best);
      }
      return { one: wall[1], all: wall[poolSize()], cores: poolSize() };
    }, [name, runs]);
    console.log(`STUDY ${name} ${runs} ${r.one.toFixed(0)} ${r.all.toFixed(0)} ${r.cores}`);
  }
  await page.close();
}
await browser.close();
