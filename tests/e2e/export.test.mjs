// Exports a lecturer can print (issue 28), for the ubb and uniform views: each figure card's
// export menu gives PNG at 1×, 2× and 4× the figure's size (rasterised from the core's SVG: the 4×
// image is exactly 4 × 4 the 1× one, read from the PNG header) and SVG at the figure's size or a
// slide's (1920 × 1080 in its root); the view's "Download table (CSV)" is the core's table
// (Session.csv), the same text a Session given the page's report returns, one row per time step of
// the report, and what `confset run --format csv` prints for the downloaded scenario (to 1e-9). No download leaves an error in the page
// (the harness also fails on any page error or console error).
// The animation's frames (a ZIP of PNG, in views with an animation: ubb, scf, compare here): one
// frame-0001.png … per step the animation plays over (the core's cursor steps of the page's report,
// or the slider's range without a cursor), numbered in order, each a PNG at the figure's CSS size;
// the frame of the step the slider was on is the PNG 1× download of it, byte for byte; the first
// and last frames differ; the slider is back where it was; the ZIP writer (vendor/fflate.js) is
// loaded only when frames are asked for.
import { readFile, writeFile } from 'node:fs/promises';
import { existsSync, mkdtempSync, writeFileSync } from 'node:fs';
import { execFileSync } from 'node:child_process';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { createRequire } from 'node:module';
import { openApp, downloadFigure, text } from './helpers.mjs';

const { unzipSync } = createRequire(new URL('../../www/package.json', import.meta.url))('fflate');

// The PNG's width and height: big-endian uint32 at bytes 16..24 of its IHDR chunk.
function pngSize(buf, what, assert) {
  assert.equal(buf.subarray(0, 8).toString('latin1'), '\x89PNG\r\n\x1a\n', `${what}: a PNG signature`);
  assert.equal(buf.subarray(12, 16).toString('latin1'), 'IHDR', `${what}: IHDR first`);
  return [buf.readUInt32BE(16), buf.readUInt32BE(20)];
}

const CLI = fileURLToPath(new URL('../../target/release/confset', import.meta.url));

// CSV texts with the same header and rows, every number equal to 1e-9 (relative to its size, at
// least 1): the page's wasm and the native CLI may differ in the last bits (the explorer test's
// tolerance for their reports); the first difference, or null.
function csvDifference(a, b) {
  const [ra, rb] = [a.trimEnd().split('\n'), b.trimEnd().split('\n')];
  if (ra[0] !== rb[0]) return `header ${ra[0]} vs ${rb[0]}`;
  if (ra.length !== rb.length) return `${ra.length} vs ${rb.length} lines`;
  for (let i = 1; i < ra.length; i++) {
    const [ca, cb] = [ra[i].split(','), rb[i].split(',')];
    if (ca.length !== cb.length) return `line ${i + 1}: ${ca.length} vs ${cb.length} cells`;
    for (let j = 0; j < ca.length; j++) {
      if (ca[j] === cb[j]) continue;
      const [x, y] = [Number(ca[j]), Number(cb[j])];
      if (ca[j] === '' || cb[j] === '' || !(Math.abs(x - y) <= 1e-9 * Math.max(1, Math.abs(x), Math.abs(y)))) {
        return `line ${i + 1}, column ${ra[0].split(',')[j]}: ${ca[j]} vs ${cb[j]}`;
      }
    }
  }
  return null;
}

const VIEWS = [
  { id: 'ubb', prefix: 'b-', busy: 'ubbBusy', steps: (r) => r.ubb.track.length, stem: /^ubb-track-/ },
  { id: 'uniform', prefix: 'u-', busy: 'uniformBusy', steps: (r) => r.uniform.steps.length, stem: /^uniform-/ },
];

// Views whose animation's frames are exported: the slider, and the step it is put on first (not
// an end, so that putting it back is seen).
const FRAMES = [
  { id: 'ubb', prefix: 'b-', busy: 'ubbBusy', slider: 'b-time', at: 45 },
  { id: 'scf', prefix: '', busy: 'busy', slider: 'time', at: 20 },
  { id: 'compare', prefix: 'c-', busy: 'compareBusy', slider: 'c-time', at: 10 },
];

async function framesExport(env, v) {
  const { assert, screenshotDir } = env;
  const idle = (page) => page.waitForFunction((k) => !document.body.dataset[k], v.busy, { timeout: 120_000 });
  const page = await openApp(env, 1, idle, v.id);
  const vendored = () => page.evaluate(() => performance.getEntriesByType('resource').some((r) => r.name.endsWith('/vendor/fflate.js')));
  assert.equal(await vendored(), false, `${v.id}: the ZIP writer is not loaded before frames are asked for`);
  const id = await page.$$eval(`#${v.id} figure.card[data-panel]`, (cs) => cs.find((c) => !c.hidden && c.offsetParent).id);
  const card = `#${v.id} #${id}`;
  const what = `${v.id} ${id} frames`;
  await page.$eval(`#${v.slider}`, (r, x) => { r.value = String(x); r.dispatchEvent(new Event('input', { bubbles: true })); }, v.at);
  await idle(page);
  const before = await page.$eval(`#${v.slider}`, (r) => Number(r.value));
  assert.equal(before, v.at, `${v.id}: the slider is at ${v.at}`);

  // The steps the animation plays over: the core's cursor steps of the page's report (a time
  // cursor), else the slider's range.
  const [reportDl] = await Promise.all([page.waitForEvent('download'), page.click(`#${v.prefix}dl-report`)]);
  const reportJson = await readFile(await reportDl.path(), 'utf8');
  const [first, last] = await page.evaluate(([r, slider]) => {
    const s = new window.confset.Session();
    s.setReport(r);
    const c = s.cursorSteps();
    const el = document.getElementById(slider);
    return c ? [c[0], c[1]] : [Number(el.min), Number(el.max)];
  }, [reportJson, v.slider]);
  assert.ok(first < before && before < last, `${v.id}: the slider (${before}) is inside the steps ${first}…${last}`);
  const [cw, ch] = await page.$eval(`${card} canvas`, (c) => [c.clientWidth, c.clientHeight]);
  const shown = await readFile(await (await downloadFigure(page, card, 'png-1')).path());

  await page.selectOption(`${card} [data-dl-choice]`, 'frames');
  assert.equal(await page.$eval(`${card} [data-dl=go]`, (b) => b.getAttribute('aria-label')),
    'download this figure as a ZIP of PNG images at its size on the page, one per step of the animation');
  const [dl] = await Promise.all([page.waitForEvent('download', { timeout: 300_000 }), page.click(`${card} [data-dl=go]`)]);
  await idle(page);
  assert.match(dl.suggestedFilename(), new RegExp(`-${id.replace(/^fig-/, '')}-frames\\.zip$`), `${what}: file name`);
  const zip = await readFile(await dl.path());
  const entries = unzipSync(new Uint8Array(zip));
  const names = Object.keys(entries);
  const n = last - first + 1;
  assert.equal(names.length, n, `${what}: one frame per step ${first}…${last}`);
  assert.deepEqual(names, Array.from({ length: n }, (_, i) => `frame-${String(i + 1).padStart(4, '0')}.png`), `${what}: numbered in order`);
  for (const name of names) {
    const [w, h] = pngSize(Buffer.from(entries[name]), `${what} ${name}`, assert);
    assert.deepEqual([w, h], [cw, ch], `${what} ${name}: the figure's CSS size`);
  }
  const frame = (i) => Buffer.from(entries[names[i]]);
  assert.ok(frame(before - first).equals(shown), `${what}: the frame of step ${before} is the PNG 1× download of it`);
  assert.ok(!frame(0).equals(frame(n - 1)), `${what}: the first and last frames differ`);
  assert.equal(await page.$eval(`#${v.slider}`, (r) => Number(r.value)), before, `${what}: the slider is back at ${before}`);
  assert.equal(await text(page, `${card} .fig-err`), '', `${what}: no error or progress left in the card`);
  assert.equal(await vendored(), true, `${v.id}: the ZIP writer was loaded for the frames`);
  await writeFile(join(screenshotDir, `export-${v.id}-${id}-frames.zip`), zip);
  console.log(`  ${what}: ${n} frames (steps ${first}…${last}) of ${cw}×${ch}, ZIP ${zip.length} bytes`);
  await page.close();
}

export default async function exportTest(env) {
  const { assert, screenshotDir } = env;
  for (const v of FRAMES) await framesExport(env, v);
  for (const v of VIEWS) {
    const idle = (page) => page.waitForFunction((k) => !document.body.dataset[k], v.busy, { timeout: 60_000 });
    const page = await openApp(env, 1, idle, v.id);
    const root = `#${v.id}`;
    const cards = await page.$$eval(`${root} figure.card[data-panel]`,
      (cs) => cs.filter((c) => !c.hidden && c.offsetParent).map((c) => c.id));
    assert.ok(cards.length >= 1, `${v.id}: a figure card shows`);

    for (const id of cards) {
      const card = `${root} #${id}`;
      const what = `${v.id} ${id}`;
      // The export control: one menu and one button on one line, named for what it downloads.
      const choices = await page.$$eval(`${card} [data-dl-choice] option`, (os) => os.map((o) => o.textContent));
      assert.deepEqual(choices, ['SVG', 'SVG 1280×720', 'SVG 1920×1080', 'PNG 1×', 'PNG 2×', 'PNG 4×', 'animation frames (ZIP of PNG)']);
      await page.selectOption(`${card} [data-dl-choice]`, 'png-2');
      assert.equal(await page.$eval(`${card} [data-dl=go]`, (b) => b.getAttribute('aria-label')),
        'download this figure as PNG at 2× size');
      const rows = await page.$eval(`${card} .dl`, (d) => [...d.children].map((c) => Math.round(c.getBoundingClientRect().top)));
      assert.equal(new Set(rows).size, 1, `${what}: the export control is on one line (${rows})`);
      const [cw, ch] = await page.$eval(`${card} canvas`, (c) => [c.clientWidth, c.clientHeight]);

      // PNG at 1× is the figure's CSS size; at 4× exactly four times each way.
      const png1 = await downloadFigure(page, card, 'png-1');
      const png4 = await downloadFigure(page, card, 'png-4');
      assert.match(png4.suggestedFilename(), new RegExp(`-${id.replace(/^fig-/, '')}-4x\\.png$`));
      const [w1, h1] = pngSize(await readFile(await png1.path()), `${what} 1×`, assert);
      const [w4, h4] = pngSize(await readFile(await png4.path()), `${what} 4×`, assert);
      assert.deepEqual([w1, h1], [cw, ch], `${what}: the 1× PNG is the figure's CSS size`);
      assert.deepEqual([w4, h4], [4 * w1, 4 * h1], `${what}: the 4× PNG is 4 × the 1× one`);
      // A copy to look at (text crisp at 4×, nothing cut at the edges): tests/e2e/out.
      await writeFile(join(screenshotDir, `export-${v.id}-${id}-4x.png`), await readFile(await png4.path()));

      // SVG at a slide's size: its root says so.
      const svgDl = await downloadFigure(page, card, 'svg-1920x1080');
      assert.match(svgDl.suggestedFilename(), /-1920x1080\.svg$/);
      const svg = await readFile(await svgDl.path(), 'utf8');
      const rootTag = svg.match(/<svg\b[^>]*>/)?.[0] || '';
      assert.ok(/\bwidth="1920"/.test(rootTag) && /\bheight="1080"/.test(rootTag), `${what}: SVG root ${rootTag}`);
      assert.equal(await text(page, `${card} .fig-err`), '', `${what}: no error after the downloads`);
    }

    // The table: the core's CSV of the report, one row per time step.
    const [csvDl] = await Promise.all([page.waitForEvent('download'), page.click(`#${v.prefix}dl-csv`)]);
    const [reportDl] = await Promise.all([page.waitForEvent('download'), page.click(`#${v.prefix}dl-report`)]);
    const [scenarioDl] = await Promise.all([page.waitForEvent('download'), page.click(`#${v.prefix}dl-scenario`)]);
    const stem = csvDl.suggestedFilename().replace(/\.csv$/, '');
    assert.match(stem, v.stem, `${v.id}: CSV file name ${csvDl.suggestedFilename()}`);
    const csv = await readFile(await csvDl.path(), 'utf8');
    const reportJson = await readFile(await reportDl.path(), 'utf8');
    const scenarioJson = await readFile(await scenarioDl.path(), 'utf8');
    const core = await page.evaluate(([r, s]) => {
      const { Session } = window.confset;
      const kept = new Session();
      kept.setReport(r);
      const ran = new Session();
      ran.run(s);
      let before = '';
      try { new Session().csv(); } catch (e) { before = e.message; }
      return { kept: kept.csv(), ran: ran.csv(), before };
    }, [reportJson, scenarioJson]);
    const lines = (t) => t.trimEnd().split('\n');
    assert.equal(lines(csv)[0], lines(core.kept)[0], `${v.id}: the CSV header is the core's`);
    assert.equal(lines(csv).length, lines(core.kept).length, `${v.id}: the CSV has the core's rows`);
    assert.equal(csv, core.kept, `${v.id}: the CSV is Session.csv() of the page's report`);
    assert.equal(csv, core.ran, `${v.id}: the CSV is what running the page's scenario gives (confset run --format csv)`);
    // `# warning:` lines (the report's warnings) stand above the header.
    assert.equal(lines(csv).filter((l) => !l.startsWith('#')).length - 1, v.steps(JSON.parse(reportJson)), `${v.id}: one row per time step`);
    // …and what the native CLI prints for the downloaded scenario (built by the native test layer).
    assert.ok(existsSync(CLI), `${CLI} is built by the native test layer`);
    const file = join(mkdtempSync(join(tmpdir(), 'confset-csv-')), `${v.id}.json`);
    writeFileSync(file, scenarioJson);
    const cliCsv = execFileSync(CLI, ['run', file, '--format', 'csv'], { encoding: 'utf8', maxBuffer: 1 << 28 });
    assert.equal(csvDifference(csv, cliCsv), null, `${v.id}: the CSV download and confset run --format csv differ`);
    assert.match(lines(csv).find((l) => !l.startsWith('#')), v.id === 'ubb' ? /^k,center_1,/ : /^t,y_1,/);
    assert.equal(core.before, 'no report yet: run a scenario first', 'a Session with no report says so in words');
    assert.equal(await text(page, `#${v.prefix}dl-err`), '', `${v.id}: no CSV error`);

    // Nothing in the page reads like a JS exception.
    const body = await page.evaluate(() => document.body.innerText);
    assert.doesNotMatch(body, /TypeError|ReferenceError|RangeError|SyntaxError|is not a function|undefined|\[object /,
      `${v.id}: no exception text in the page`);
    await page.close();
  }
}
