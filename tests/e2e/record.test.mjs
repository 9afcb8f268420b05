// A user's record with its own times (data.t) and the report's warnings (issue 39), in the
// set-membership view: a scenario file on the record of ubb-track with years 1871 … loads; the
// step read-out and the numbers' title name the step with its year ("= 19 · 1890"); the width
// figure draws; the report's warnings show above the figure cards as a list (role=status), and a
// report without warnings hides the box. No method of this build writes a warning for this
// record yet, so the worker here adds two sentences to each report of a scenario titled
// "… [warn]" (the page shows what the report says, whoever wrote it). Screenshot:
// record-ubb-1366.png (desktop: the warnings box above the figures) and record-ubbwidth-1366.png
// (the width figure's year axis).
import { join } from 'node:path';
import { writeFileSync, mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { text } from './helpers.mjs';

const WARNINGS = [
  'The record has no measurement at row 21 (t = 21, time 1891): the set is widened by the model alone there.',
  'The noise bound ε is below the largest residual of a least-squares fit: the data may contradict it.',
];

// Prepended to worker.js: every report of a scenario titled "… [warn]" carries WARNINGS.
const addWarnings = `{
  const post = self.postMessage.bind(self);
  self.postMessage = (m, ...rest) => {
    if (m && typeof m.report === 'string') {
      const r = JSON.parse(m.report);
      if (/\\[warn\\]/.test(r.figure?.title || '')) m = { ...m, report: JSON.stringify({ ...r, warnings: ${JSON.stringify(WARNINGS)} }) };
    }
    return post(m, ...rest);
  };
}
`;

const idle = (page) => page.waitForFunction(() => !document.body.dataset.ubbBusy, null, { timeout: 60_000 });

export default async function record(env) {
  const { assert, newPage, baseUrl, waitReady, screenshotDir } = env;
  const page = await newPage({ viewport: { width: 1366, height: 900 } });
  await page.context().route('**/worker.js', async (route) => {
    const response = await route.fetch();
    await route.fulfill({ response, body: addWarnings + (await response.text()) });
  });
  await page.goto(`${baseUrl}#ubb`);
  await waitReady(page);
  await idle(page);
  const box = '#ubb-section .warnings';
  // ubb-track's own report states the Kalman comparison's assumption (variances bound²/3): the
  // box shows the core's words.
  assert.equal(await page.$eval(box, (e) => e.hidden), false, 'a report with warnings: the box shows');
  assert.notEqual(await text(page, box), '', 'the box holds the core\'s sentences');
  assert.doesNotMatch(await text(page, '#b-time-out'), /·/, 'a simulation has no record time');

  // ubb-track's record as the user's data, with years: row k is 1871 + k.
  const scenario = await page.evaluate(() => {
    const s = JSON.parse(window.confset.presets()).find((p) => p.name === 'ubb-track').scenario;
    const session = new window.confset.Session();
    const r = JSON.parse(session.run(JSON.stringify(s)));
    session.free();
    delete s.simulate;
    delete s.ubb.sim_eps;
    delete s.ubb.sim_tau;
    s.data = { y: r.ubb.y, t: r.ubb.y.map((_, k) => 1871 + k) };
    s.title = 'ubb-track as a record [warn]';
    return s;
  });
  const file = join(mkdtempSync(join(tmpdir(), 'confset-record-')), 'record.json');
  writeFileSync(file, JSON.stringify(scenario));
  await page.setInputFiles('#ubb-section input[type=file]', file);
  await page.waitForFunction(() => /loaded/.test(document.querySelector('#ubb-section .share-status').textContent), null, { timeout: 30_000 });
  await idle(page);
  assert.equal(await text(page, '#fig-ubbwidth .fig-err'), '', 'the width figure draws the record');

  // The step read-out and the numbers' title say the step's year.
  const k = Number(await page.$eval('#b-time', (e) => e.value));
  assert.equal(await text(page, '#b-time-out'), `= ${k} · ${1871 + k}`);
  assert.match(await text(page, '#b-num-title'), new RegExp(`^At step k = ${k} · ${1871 + k}`));
  // A step back: the read-out follows.
  await page.$eval('#b-time', (e) => { e.value = String(Number(e.value) - 1); e.dispatchEvent(new Event('input', { bubbles: true })); });
  await idle(page);
  assert.equal(await text(page, '#b-time-out'), `= ${k - 1} · ${1870 + k}`);

  // The warnings: shown, one item each, as a status, above the figure cards.
  assert.equal(await page.$eval(box, (e) => e.hidden), false, 'the report has warnings: the box shows');
  assert.equal(await page.$eval(box, (e) => e.getAttribute('role')), 'status');
  assert.deepEqual(await page.$$eval(`${box} li`, (li) => li.map((e) => e.textContent)), WARNINGS);
  assert.ok(await page.$eval(box, (e) => {
    const card = e.parentElement.querySelector('figure.card');
    return !!card && (e.compareDocumentPosition(card) & Node.DOCUMENT_POSITION_FOLLOWING) !== 0;
  }), 'the warnings stand above the figure cards');

  await page.$eval('#ubb-section .figures', (e) => e.scrollIntoView());
  await page.screenshot({ path: join(screenshotDir, 'record-ubb-1366.png') });
  await (await page.$('#fig-ubbwidth')).screenshot({ path: join(screenshotDir, 'record-ubbwidth-1366.png') });

  // Back to the preset: the box holds its report's own warnings, not the record's.
  await page.selectOption('#b-preset', 'ubb-track');
  await idle(page);
  const after = await text(page, box);
  assert.ok(!WARNINGS.some((w) => after.includes(w)), `the record's warnings are gone: ${after}`);
  await page.close();
}
