// The shell, for every panel of the registry: share links restore the same controls, numbers and
// pixels in a fresh page; a fixture link of every emitted version decodes; a corrupt link says so
// and shows the default; the landing view computes nothing; a scenario file loads into its panel.
import { join } from 'node:path';
import { writeFileSync, mkdtempSync, readFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { execFileSync } from 'node:child_process';
import { existsSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { PANELS } from '../../www/registry.js';
import { slideToPaint } from './helpers.mjs';

// The native CLI that `cargo test --profile bench` (the first test layer) builds.
const CLI = fileURLToPath(new URL('../../target/release/confset', import.meta.url));

// The first place two reports differ beyond 1e-9 relative (numbers) or at all (the rest), compute
// times aside.
function difference(a, b, path = '') {
  if (typeof a === 'number' && typeof b === 'number') {
    return Math.abs(a - b) <= 1e-9 * Math.max(1, Math.abs(a), Math.abs(b)) ? null : `${path}: ${a} vs ${b}`;
  }
  if (Array.isArray(a) && Array.isArray(b)) {
    if (a.length !== b.length) return `${path}: ${a.length} vs ${b.length} entries`;
    for (let i = 0; i < a.length; i++) { const d = difference(a[i], b[i], `${path}[${i}]`); if (d) return d; }
    return null;
  }
  if (a && b && typeof a === 'object' && typeof b === 'object') {
    // `seconds`: a compare's per-method compute time, by the caller's clock (the page's worker
    // has one, `confset run` none): not a number of the estimate.
    for (const k of new Set([...Object.keys(a), ...Object.keys(b)])) {
      if (k === 'seconds') continue;
      const d = difference(a[k], b[k], `${path}.${k}`);
      if (d) return d;
    }
    return null;
  }
  return a === b ? null : `${path}: ${JSON.stringify(a)?.slice(0, 40)} vs ${JSON.stringify(b)?.slice(0, 40)}`;
}

const ready = (page) => page.waitForFunction(() => document.body.dataset.ready === '1', null, { timeout: 60_000 });
const idle = (page, key) => page.waitForFunction((k) => !document.body.dataset[k], key, { timeout: 60_000 });
// No computation of any panel left: its run and its studies (the GLLS Monte Carlo starts with the
// scenario and draws the precision figure when its workers report).
const settled = (page) => page.waitForFunction(() => !Object.keys(document.body.dataset).some((k) => k === 'busy' || k.endsWith('Busy')), null, { timeout: 60_000 });

// What a user sees of a panel: every control's value, the numbers' text, and a digest of every
// visible canvas's pixels.
const snapshot = (page, id) => page.evaluate((id) => {
  const root = document.getElementById(id);
  const controls = [...root.querySelectorAll('form input[id], form select[id], form textarea[id]')]
    .filter((e) => e.type !== 'file').map((e) => `${e.id}=${e.type === 'checkbox' ? e.checked : e.value}`);
  const numbers = [...root.querySelectorAll('.numbers')].map((e) => e.textContent.replace(/\s+/g, ' ')
    .replace(/[\d.]+ ?(ms|µs)/g, '').replace(/[\d.]+ ?s\b/g, '')).join('|');
  const pixels = [...root.querySelectorAll('canvas')].filter((c) => c.offsetParent && c.width > 1).map((c) => {
    const copy = Object.assign(document.createElement('canvas'), { width: c.width, height: c.height });
    const g = copy.getContext('2d', { willReadFrequently: true });
    g.drawImage(c, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    let h = 0;
    for (let i = 0; i < d.length; i += 7) h = (h * 31 + d[i]) >>> 0;
    return `${c.width}x${c.height}:${h}`;
  });
  return { controls, numbers, pixels };
}, id);

// Move a panel's controls as a user would: the first three visible sliders to 30 % of their
// range and the seed one up, then wait for the panel to compute.
async function moveControls(page, d) {
  const moved = await page.evaluate((id) => {
    const root = document.getElementById(id);
    const visible = (e) => e.offsetParent !== null && !e.disabled;
    const out = [];
    for (const r of [...root.querySelectorAll('form input[type=range]')].filter(visible).slice(0, 3)) {
      const [lo, hi, step] = [Number(r.min), Number(r.max), Number(r.step) || 1];
      const v = lo + Math.round((0.3 * (hi - lo)) / step) * step;
      if (String(v) === r.value) continue;
      r.value = String(v);
      r.dispatchEvent(new Event('input', { bubbles: true }));
      out.push(`${r.id}=${r.value}`);
    }
    for (const n of [...root.querySelectorAll('form input[type=number][id$=seed]')].filter(visible).slice(0, 1)) {
      n.value = String(Number(n.value) + 1);
      n.dispatchEvent(new Event('input', { bubbles: true }));
      out.push(`${n.id}=${n.value}`);
    }
    return out;
  }, d.id);
  await settled(page);
  return moved;
}

export default async function explorer({ newPage, baseUrl, assert, screenshotDir }) {
  // A fresh 1366 × 900 page on a route of the app (`''`: the landing view), loaded.
  const open = async (route) => {
    const page = await newPage({ viewport: { width: 1366, height: 900 } });
    await page.goto(route ? `${baseUrl}#${route}` : baseUrl);
    await ready(page);
    return page;
  };
  // The landing view: five cards, no panel mounted, so nothing computed.
  {
    const page = await open('');
    assert.equal(await page.$$eval('#landing a.promise', (a) => a.length), PANELS.length);
    const drawn = await page.$$eval('canvas', (cs) => cs.filter((c) => c.width !== 300).length);
    assert.equal(drawn, 0, 'the landing view draws no figure');
    await page.screenshot({ path: join(screenshotDir, 'explorer-landing.png') });
    // A click on a card opens that panel, and only that one computes.
    await page.click('#landing a[href="#lscr"]');
    await page.waitForFunction(() => document.body.dataset.route === 'lscr' && document.body.dataset.ready === '1');
    assert.equal(await page.$eval('#scf-section', (e) => e.hidden), true);
    const others = await page.$$eval('#scf canvas, #glls canvas, #ubb canvas, #uniform canvas', (cs) => cs.filter((c) => c.width !== 300).length);
    assert.equal(others, 0, 'panels not shown compute nothing');
    await page.close();
  }

  for (const d of PANELS) {
    const page = await open(d.id);
    await settled(page);
    const before = await snapshot(page, d.id);
    const moved = await moveControls(page, d);
    assert.ok(moved.length > 0, `${d.id}: some slider moved`);
    await settled(page);
    const after = await snapshot(page, d.id);
    assert.notDeepEqual(after.pixels, before.pixels, `${d.id}: moving ${moved.join(', ')} changes the picture`);
    // The URL follows (debounced), and a fresh page on it is the same panel.
    await page.waitForFunction((id) => location.hash.startsWith(`#${id}/v1/`), d.id, { timeout: 10_000 });
    await page.waitForTimeout(600); // the last debounced update
    const link = await page.evaluate(() => location.href);
    assert.ok(link.length < 32_000, `${d.id}: link of ${link.length} characters`);
    const copy = await newPage({ viewport: { width: 1366, height: 900 } });
    await copy.goto(link);
    await ready(copy);
    await settled(copy);
    await settled(copy);
    const restored = await snapshot(copy, d.id);
    assert.deepEqual(restored.controls, after.controls, `${d.id}: the link restores the controls`);
    assert.equal(restored.numbers, after.numbers, `${d.id}: the link restores the numbers`);
    assert.deepEqual(restored.pixels, after.pixels, `${d.id}: the link restores the picture`);
    console.log(`    ${d.id}: moved ${moved.join(', ')}; link ${link.length} characters restores controls, numbers and ${restored.pixels.length} canvases`);
    await copy.close();

    // A preset link.
    const presetName = await page.$eval(`#${d.id} form select[data-field=preset]`, (s) => s.options[1] ? s.options[1].value : s.options[0].value);
    const byPreset = await newPage({ viewport: { width: 1366, height: 900 } });
    await byPreset.goto(`${baseUrl}#${d.id}/preset/${presetName}`);
    await ready(byPreset);
    assert.equal(await byPreset.$eval(`#${d.id} form select[data-field=preset]`, (s) => s.value), presetName);
    await byPreset.close();

    // A corrupt link: a message in words, and the default scenario.
    const broken = await newPage({ viewport: { width: 1366, height: 900 } });
    await broken.goto(`${baseUrl}#${d.id}/v1/AAAA-not-a-token`);
    await ready(broken);
    await settled(broken);
    const banner = await broken.$eval(`#${d.id}-section .banner`, (b) => (b.hidden ? '' : b.textContent));
    assert.match(banner, /could not be read.*default scenario/, `${d.id}: corrupt link message: ${banner}`);
    assert.deepEqual((await snapshot(broken, d.id)).controls, before.controls, `${d.id}: a corrupt link shows the default`);
    await broken.close();
    await page.close();

    // The panel's custom model: one good and three bad F, each message next to the model's
    // fields, the last good picture kept, and the message gone once F is good again.
    {
      const custom = await newPage({ viewport: { width: 1366, height: 900 } });
      await custom.goto(`${baseUrl}#${d.id}`);
      await ready(custom);
      await custom.selectOption(`#${d.id} form select[data-field=preset]`, 'custom');
      await settled(custom);
      const f = `#${d.id} textarea[data-field="model.F"]`;
      const good = await custom.$eval(f, (t) => t.value);
      const n = good.trim().split('\n').length;
      const pixels = (await snapshot(custom, d.id)).pixels;
      assert.ok(pixels.length > 0, `${d.id}: the custom model draws`);
      const modelError = () => custom.$$eval(`#${d.id} .err[data-for^="model"]`, (ps) => ps.map((p) => p.textContent).join(' ').trim());
      for (const [bad, what] of [['1 2\n3', /model\.F/], ['0.5 abc', /model\.F/], [Array(n + 1).fill(Array(n + 1).fill('0.1').join(' ')).join('\n'), /model|F|H|column|row|dimension|size|n ?×|shape/i]]) {
        await custom.fill(f, bad);
        await settled(custom);
        const msg = await modelError();
        assert.match(msg, what, `${d.id}: F = ${JSON.stringify(bad)} gives a message next to the model: "${msg}"`);
        assert.equal(await custom.$eval(`#${d.id} .stale`, (e) => e.hidden), false, `${d.id}: the stale note shows`);
        assert.deepEqual((await snapshot(custom, d.id)).pixels, pixels, `${d.id}: the last good picture stays`);
        if (d.id === 'glls' && bad === '1 2\n3') {
          await custom.$eval(`#${d.id} .err[data-for^="model"]:not(:empty)`, (e) => e.scrollIntoView({ block: 'center' }));
          await custom.screenshot({ path: join(screenshotDir, 'error-ragged-model.png') });
        }
      }
      await custom.fill(f, good);
      await settled(custom);
      assert.equal(await modelError(), '', `${d.id}: the message goes once F is good again`);
      if (d.id === 'scf') {
        // An unstable F has no stationary prior: the message asks for the prior's box, which is there.
        await custom.fill(f, '1.1 0.1\n0 0.9');
        await settled(custom);
        assert.match(await custom.$eval('#scf .err[data-for="model.x1_cov"]', (e) => e.textContent), /is needed: no stationary prior/);
        await custom.fill('#m-P1', '1 0\n0 1');
        await settled(custom);
        assert.equal(await modelError(), '', 'scf: an unstable F runs with a given prior');
        await custom.fill('#m-P1', '');
        await custom.fill(f, good);
        await settled(custom);
      }
      await custom.close();
    }

    // One source of limits: every box and slider bound to a limited field spans the core's range
    // (a slider beside its box spans the same), and a value past it gets the core's message.
    {
      const lim = await newPage();
      await lim.goto(`${baseUrl}#${d.id}`);
      await ready(lim);
      await settled(lim);
      const ranges = await lim.evaluate(([id, method]) => {
        const limits = JSON.parse(window.confset.limits());
        return [...document.querySelectorAll(`#${id} input[data-limit], #${id} input[type=number][data-field]`)].flatMap((el) => {
          const key = el.dataset.limit || (/(^|\.)runs$/.test(el.dataset.field) ? 'runs' : el.dataset.field);
          const r = Array.isArray(limits[key]) ? limits[key] : limits[key]?.[method];
          return r ? [[el.id, key, [el.min, el.max].map(Number), r]] : [];
        });
      }, [d.id, d.methods[0]]);
      for (const [id, key, got, want] of ranges) assert.deepEqual(got, want, `${d.id}: #${id} spans the core's ${key} range`);
      if (d.id === 'uniform') {
        assert.ok(ranges.some(([id]) => id === 'u-window-range') && ranges.some(([id]) => id === 'u-window'), 'uniform: the window slider and box both take the core\'s range');
        const [, , [, max]] = ranges.find(([id]) => id === 'u-window');
        await lim.fill('#u-window', String(max + 1));
        await settled(lim);
        assert.match(await lim.$eval('#uniform .err[data-for="uniform.window"]', (e) => e.textContent), new RegExp(`from 1 to ${max}\\b`), 'uniform: the message names the same limit');
        await lim.$eval('#uniform .err[data-for="uniform.window"]', (e) => e.scrollIntoView({ block: 'center' }));
        await lim.screenshot({ path: join(screenshotDir, 'error-window-limit.png') });
      }
      await lim.close();
    }

    // A phone: no horizontal scrolling.
    const phone = await newPage({ viewport: { width: 390, height: 844 }, deviceScaleFactor: 2 });
    await phone.goto(`${baseUrl}#${d.id}`);
    await ready(phone);
    await settled(phone);
    assert.equal(await phone.evaluate(() => document.documentElement.scrollWidth), 390, `${d.id}: document width at 390 px`);
    // No legend box over a chart: the core's frames give both rectangles.
    const layouts = await phone.$$eval(`#${d.id} figure.card:not([hidden]) canvas`, (cs) => cs.map((c) => [c.dataset.panel, c.dataset.layout]));
    assert.ok(layouts.length >= 1, `${d.id}: no figure shown on a phone`);
    for (const [panel, layout] of layouts) {
      assert.ok(layout, `${d.id} ${panel}: not drawn on a phone`);
      const { plots, legends } = JSON.parse(layout);
      for (const [l, t, r, b] of legends) {
        for (const [pl, pt, pr, pb] of plots) {
          assert.ok(!(l < pr && r > pl && t < pb && b > pt), `${d.id} ${panel}: legend [${l}, ${t}, ${r}, ${b}] over the plot area [${pl}, ${pt}, ${pr}, ${pb}] at 390 px`);
        }
      }
    }
    await phone.screenshot({ path: join(screenshotDir, `explorer-${d.id}-phone.png`) });
    await phone.close();
  }

  // A fixture link of every emitted version (v1: lscr-smooth, seed 7) decodes to those controls.
  {
    const page = await open('');
    // A v1 token as this page emitted it for {preset: 'lscr-smooth', fields: {'l-seed': '7'}}:
    // pinned, so that a later change of the format cannot break old links unnoticed.
    const FIXTURE_V1 = 'q1YqKEotTi1RslLKKU4u0i3Ozc8vyVDSUUrLTM1JKVayqlbK0S1OTU0BKjBXqq0FAA';
    await page.goto(`${baseUrl}#lscr/v1/${FIXTURE_V1}`);
    await page.reload();
    await ready(page);
    await idle(page, 'lscrBusy');
    assert.equal(await page.$eval('#l-preset', (s) => s.value), 'lscr-smooth');
    assert.equal(await page.$eval('#l-seed', (s) => s.value), '7');
    await page.close();
  }

  // A scenario file (the panel's own download) loads by the file picker into its panel, from
  // another panel; undo brings the previous scenario back.
  {
    const page = await open('scf');
    await idle(page, 'busy');
    const dir = mkdtempSync(join(tmpdir(), 'confset-scenario-'));
    const file = join(dir, 'my-ubb.json');
    const scenario = await page.evaluate(() => JSON.parse(window.confset.presets()).find((p) => p.name === 'ubb-series').scenario);
    scenario.title = 'my series';
    writeFileSync(file, JSON.stringify(scenario));
    await page.setInputFiles('#scf-section input[type=file]', file);
    await page.waitForFunction(() => document.body.dataset.route !== 'scf' || !document.getElementById('ubb-section').hidden, null, { timeout: 30_000 });
    await page.waitForFunction(() => !document.getElementById('ubb-section').hidden && /loaded/.test(document.querySelector('#ubb-section .share-status').textContent), null, { timeout: 30_000 });
    await idle(page, 'ubbBusy');
    assert.match(await page.$eval('#b-preset', (s) => s.selectedOptions[0].textContent), /loaded: my series/);
    await page.click('#ubb-section [data-act=undo]');
    await idle(page, 'ubbBusy');
    assert.equal(await page.$eval('#b-preset', (s) => s.value), 'ubb-track');
    await page.close();
  }

  // Measured data as CSV (the LSCR panel, q = 1): the page runs on them with no truth, and its
  // report equals the scenario with the same data given directly; a bad cell on row 7 names the
  // row and keeps the picture; a wrong number of columns names both counts.
  {
    const page = await open('lscr');
    await idle(page, 'lscrBusy');
    const download = async (id) => {
      const [dl] = await Promise.all([page.waitForEvent('download'), page.click(`#${id}`)]);
      return JSON.parse(readFileSync(await dl.path(), 'utf8'));
    };
    const simulated = await download('l-dl-scenario');
    const y = (await download('l-dl-report')).y;
    const dir = mkdtempSync(join(tmpdir(), 'confset-csv-'));
    const good = join(dir, 'measured.csv');
    writeFileSync(good, `y1\n${y.map((r) => r.join(',')).join('\n')}\n`);
    await page.setInputFiles('#lscr-section input[data-act=csv]', good);
    await page.waitForFunction(() => /running on measured\.csv/.test(document.querySelector('#lscr-section .share-status').textContent));
    await idle(page, 'lscrBusy');
    const onData = await download('l-dl-scenario');
    assert.equal(onData.simulate, undefined, 'no simulation on data');
    assert.deepEqual(onData.data.y, y, 'the CSV rows are the data');
    const report = await download('l-dl-report');
    assert.equal(report.x_true, undefined, 'a report on data has no truth');
    const direct = await page.evaluate((s) => JSON.parse(new window.confset.Session().run(JSON.stringify(s))), {
      ...Object.fromEntries(Object.entries(simulated).filter(([k]) => k !== 'simulate')), data: { y }, title: onData.title,
    });
    assert.deepEqual(report.lscr, direct.lscr, 'the page on the CSV = the scenario with the same data');
    assert.match(await page.$eval('#lscr-section .data-preview', (e) => e.textContent), new RegExp(`${y.length} rows · 1 output`));
    await page.$eval('#lscr-section .toolbar', (e) => e.scrollIntoView());
    await page.screenshot({ path: join(screenshotDir, 'explorer-data-preview.png') });
    const pixels = (await snapshot(page, 'lscr')).pixels;

    const bad = y.map((r) => r.join(','));
    bad[5] = 'abc'; // the file's row 7: the header is row 1
    writeFileSync(join(dir, 'bad.csv'), `y1\n${bad.join('\n')}\n`);
    await page.setInputFiles('#lscr-section input[data-act=csv]', join(dir, 'bad.csv'));
    await page.waitForFunction(() => document.querySelector('#lscr-section .data-err').textContent !== '');
    const err = await page.$eval('#lscr-section .data-err', (e) => e.textContent);
    assert.match(err, /row 7, column y1: 'abc' is not a number/, err);
    assert.deepEqual((await snapshot(page, 'lscr')).pixels, pixels, 'a bad file keeps the last picture');
    await page.$eval('#lscr-section .toolbar', (e) => e.scrollIntoView());
    await page.screenshot({ path: join(screenshotDir, 'explorer-data-error.png') });

    writeFileSync(join(dir, 'wide.csv'), y.map((r) => `${r[0]},1,2`).join('\n'));
    await page.setInputFiles('#lscr-section input[data-act=csv]', join(dir, 'wide.csv'));
    await page.waitForFunction(() => /3 columns/.test(document.querySelector('#lscr-section .data-err').textContent));
    assert.match(await page.$eval('#lscr-section .data-err', (e) => e.textContent), /3 columns.*q = 1 output/);
    await page.close();
  }

  // Speed (printed, not asserted): switching back to a visited panel, restoring a link against a
  // first visit, and slider → painted frame with the URL following the slider.
  {
    const page = await newPage({ viewport: { width: 1366, height: 900 } });
    const since = () => page.evaluate(() => performance.now());
    await page.goto(`${baseUrl}#scf`);
    await ready(page);
    const firstScf = await since();
    const toRoute = (id) => page.evaluate((id) => new Promise((resolve) => {
      const t0 = performance.now();
      location.hash = `#${id}`;
      const check = () => (document.body.dataset.ready === '1' && document.body.dataset.route === id
        ? requestAnimationFrame(() => resolve(performance.now() - t0)) : requestAnimationFrame(check));
      requestAnimationFrame(check);
    }), id);
    const firstLscr = await toRoute('lscr');
    const back = [];
    for (let i = 0; i < 5; i++) { back.push(await toRoute('scf')); back.push(await toRoute('lscr')); }
    back.sort((a, b) => a - b);
    console.log(`    [page timing] first visit: scf ready ${firstScf.toFixed(0)} ms after navigation start, lscr ${firstLscr.toFixed(0)} ms after the click; `
      + `switching to a visited panel ${back[5].toFixed(1)} ms median, ${back[9].toFixed(1)} ms max of 10 (hash change → painted frame)`);
    for (const d of PANELS) {
      await toRoute(d.id);
      await settled(page);
      // With the URL following (450 ms between moves: the debounced update runs between them)
      // and without it (150 ms: the update never fires within the burst).
      // The frame counted is the first one painted after the panel drew the new report (the run
      // is asynchronous: it happens in the panel's compute worker).
      const slide = async (pause) => {
        const r = await page.evaluate((id) => {
          const e = [...document.getElementById(id).querySelectorAll('form input[type=range]')].find((x) => x.offsetParent);
          return e && { id: e.id, range: [Number(e.min), Number(e.max), Number(e.step) || 1] };
        }, d.id);
        if (!r) return null;
        const [lo, hi, step] = r.range;
        const out = [];
        for (let i = 0; i < 8; i++) {
          out.push(await slideToPaint(page, r.id, d.busy, lo + Math.round((((i % 4) + 1) / 5) * (hi - lo) / step) * step));
          await page.waitForTimeout(pause);
        }
        return { id: r.id, ms: out.sort((a, b) => a - b) };
      };
      const moves = await slide(450);
      const link = await page.evaluate(() => location.hash.length);
      if (!moves) continue; // no slider (LSCR: number fields and a click on the figure)
      const bare = await slide(150);
      await page.waitForTimeout(450);
      console.log(`    [page timing] ${d.id}: slider #${moves.id} → painted frame ${moves.ms[4].toFixed(0)} ms median, ${moves.ms[7].toFixed(0)} ms max of 8 with the URL following (${link} characters); `
        + `${bare.ms[4].toFixed(0)} ms median, ${bare.ms[7].toFixed(0)} ms max without`);
    }
    await page.close();
    for (const d of PANELS) {
      const plain = await newPage({ viewport: { width: 1366, height: 900 } });
      await plain.goto(`${baseUrl}#${d.id}`);
      await ready(plain);
      const first = await plain.evaluate(() => performance.now());
      const moved = await moveControls(plain, d);
      await plain.waitForFunction((id) => location.hash.startsWith(`#${id}/v1/`), d.id);
      await plain.waitForTimeout(500);
      const link = await plain.evaluate(() => location.href);
      // Count the core's runs: a link restores in one compute, not the preset's and then its own.
      // The runs happen in the panel's compute worker: its global counts them.
      const counted = await newPage({ viewport: { width: 1366, height: 900 } });
      await counted.route('**/pkg/confset.js', async (route) => {
        const response = await route.fetch();
        const body = (await response.text()).replace(/(\n    run\(scenario_json\) \{)/, '$1 globalThis.__runs = (globalThis.__runs || 0) + 1;');
        await route.fulfill({ response, body });
      });
      await counted.goto(link);
      await ready(counted);
      let runs = await counted.evaluate(() => globalThis.__runs || 0);
      for (const w of counted.workers()) runs += await w.evaluate(() => globalThis.__runs || 0);
      assert.equal(runs, 1, `${d.id}: the link restores in one run of the core`);
      await counted.close();
      const restored = await newPage({ viewport: { width: 1366, height: 900 } });
      await restored.goto(link);
      await ready(restored);
      const again = await restored.evaluate(() => performance.now());
      // The link's scenario is not the preset's (its sliders moved): its own compute time says
      // how much of the difference is the scenario, not the restore.
      const own = await restored.$eval(`#${d.id} .timing-line`, (e) => e.textContent.replace(/\s+/g, ' ').trim()).catch(() => '');
      console.log(`    [page timing] ${d.id}: ready ${first.toFixed(0)} ms after navigation start on the preset, ${again.toFixed(0)} ms on a link (${moved.join(', ')}; ${own})`);
      await restored.close();
      await plain.close();
    }
  }

  // One view mounted twice (the compare view and the gallery will): ids are looked up under each
  // root, so the second copy computes and draws on its own and leaves the first alone.
  {
    const page = await open('lscr');
    await idle(page, 'lscrBusy');
    const first = (await snapshot(page, 'lscr')).pixels;
    await page.evaluate(async () => {
      const { panelById } = await import('./registry.js');
      const d = panelById('lscr');
      const root = Object.assign(document.createElement('div'), { id: 'lscr-copy', className: 'panel' });
      d.section().append(root);
      root.innerHTML = await (await fetch(d.view)).text();
      const list = JSON.parse(window.confset.presets()).filter((p) => d.methods.includes(p.scenario.method));
      (await (await import(d.module))[d.mount](root, list)).start();
    });
    await idle(page, 'lscrBusy');
    const copy = await snapshot(page, 'lscr-copy');
    assert.deepEqual(copy.pixels, first, 'the second mount of the same preset draws the same picture');
    await page.$eval('#lscr-copy #l-dseed', (e) => { e.value = '9'; e.dispatchEvent(new Event('input', { bubbles: true })); });
    await idle(page, 'lscrBusy');
    assert.notDeepEqual((await snapshot(page, 'lscr-copy')).pixels, first, 'the copy follows its own controls');
    assert.deepEqual((await snapshot(page, 'lscr')).pixels, first, 'the first mount is left alone');
    assert.notEqual(await page.$eval('#lscr #l-dseed', (e) => e.value), '9');
    await page.close();
  }

  // Scenario export → `confset run` (native) → the page's report, to 1e-9, for every panel with
  // its controls moved.
  {
    assert.ok(existsSync(CLI), `${CLI} is built by the native test layer`);
    const dir = mkdtempSync(join(tmpdir(), 'confset-export-'));
    for (const d of PANELS) {
      const page = await open(d.id);
      await settled(page);
      await moveControls(page, d);
      const download = async (kind) => {
        const [dl] = await Promise.all([page.waitForEvent('download'),
          page.click(`#${d.id} button[id$="dl-${kind}"]`)]);
        return readFileSync(await dl.path(), 'utf8');
      };
      const file = join(dir, `${d.id}.json`);
      writeFileSync(file, await download('scenario'));
      const page_report = JSON.parse(await download('report'));
      const cli = JSON.parse(execFileSync(CLI, ['run', file], { encoding: 'utf8', maxBuffer: 1 << 28 }));
      // GLLS's download carries the panel's study beside the report; the CLI runs no study.
      if (page_report.glls) delete page_report.glls.precision;
      if (cli.glls) delete cli.glls.precision;
      const diff = difference(page_report, cli);
      assert.equal(diff, null, `${d.id}: the page's report and confset run on its scenario differ at ${diff}`);
      await page.close();
    }
    console.log(`    scenario export → confset run = the page's report (1e-9) in all ${PANELS.length} panels`);
  }
}
