// Exports a lecturer can print (issue 28), for the ubb and uniform views: each figure card's
// export menu gives PNG at 1×, 2× and 4× the figure's size (rasterised from the core's SVG: the 4×
// image is exactly 4 × 4 the 1× one, read from the PNG header) and SVG at the figure's size or a
// slide's (1920 × 1080 in its root); the view's "Download table (CSV)" is the core's table
// (Session.csv), the same text a Session given the page's report returns, one row per time step of
// the report, and what `confset run --format csv` prints for the downloaded scenario (to 1e-9). No download leaves an error in the page
// (the harness also fails on any page error or console error).
import { readFile, writeFile } from 'node:fs/promises';
import { existsSync, mkdtempSync, writeFileSync } from 'node:fs';
import { execFileSync } from 'node:child_process';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { openApp, downloadFigure, text } from './helpers.mjs';

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

export default async function exportTest(env) {
  const { assert, screenshotDir } = env;
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
      assert.deepEqual(choices, ['SVG', 'SVG 1280×720', 'SVG 1920×1080', 'PNG 1×', 'PNG 2×', 'PNG 4×']);
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
    assert.equal(lines(csv).length - 1, v.steps(JSON.parse(reportJson)), `${v.id}: one row per time step`);
    // …and what the native CLI prints for the downloaded scenario (built by the native test layer).
    assert.ok(existsSync(CLI), `${CLI} is built by the native test layer`);
    const file = join(mkdtempSync(join(tmpdir(), 'confset-csv-')), `${v.id}.json`);
    writeFileSync(file, scenarioJson);
    const cliCsv = execFileSync(CLI, ['run', file, '--format', 'csv'], { encoding: 'utf8', maxBuffer: 1 << 28 });
    assert.equal(csvDifference(csv, cliCsv), null, `${v.id}: the CSV download and confset run --format csv differ`);
    assert.match(lines(csv)[0], v.id === 'ubb' ? /^k,center_1,/ : /^t,y_1,/);
    assert.equal(core.before, 'no report yet: run a scenario first', 'a Session with no report says so in words');
    assert.equal(await text(page, `#${v.prefix}dl-err`), '', `${v.id}: no CSV error`);

    // Nothing in the page reads like a JS exception.
    const body = await page.evaluate(() => document.body.innerText);
    assert.doesNotMatch(body, /TypeError|ReferenceError|RangeError|SyntaxError|is not a function|undefined|\[object /,
      `${v.id}: no exception text in the page`);
    await page.close();
  }
}
