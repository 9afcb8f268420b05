// A researcher's own record in the page: the Nile (Durbin & Koopman's local level example) as a
// data frame writes it, `year,volume`, with its missing stretches (observations 21–40 and
// 61–80 blank), loaded into the SCF/KF view under a local level model. Every row is a step,
// the axis and the cursor read out the years, the Kalman band widens through each gap, and
// the report's warnings name the gaps beside the figures.
import { join } from 'node:path';
import { writeFileSync, mkdtempSync, readFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { fileURLToPath } from 'node:url';
import { openApp, downloadFigure } from './helpers.mjs';

const idle = (page) => page.waitForFunction(() => !document.body.dataset.busy, null, { timeout: 60_000 });
const NILE_GAPS = fileURLToPath(new URL('../data/nile-gaps.csv', import.meta.url));

export default async function nile(env) {
  const { assert, screenshotDir } = env;
  const page = await openApp(env, 1, idle, 'scf');
  const dir = mkdtempSync(join(tmpdir(), 'confset-nile-'));
  // The local level model with Durbin & Koopman's variances, as a scenario file.
  const model = join(dir, 'local-level.json');
  writeFileSync(model, JSON.stringify({
    method: 'kf',
    title: 'Nile, local level',
    model: { F: [[1]], H: [[1]], V: [[1469.1]], W: [[15099]], x1_mean: [0], x1_cov: [[1e7]] },
    simulate: { steps: 100, seed: 1 },
    alpha: 0.9,
  }));
  await page.setInputFiles('#scf-section input[type=file]', model);
  await page.waitForFunction(() => /loaded/.test(document.querySelector('#scf-section .share-status').textContent), null, { timeout: 30_000 });
  await idle(page);
  await page.setInputFiles('#scf-section input[data-act=csv]', NILE_GAPS);
  await page.waitForFunction(() => /running on nile-gaps\.csv/.test(document.querySelector('#scf-section .share-status').textContent), null, { timeout: 30_000 });
  await idle(page);
  assert.equal(await page.$eval('#scf-section .data-err', (e) => e.textContent), '', 'the file is read');

  const [dl] = await Promise.all([page.waitForEvent('download'), page.click('#dl-report')]);
  const report = JSON.parse(readFileSync(await dl.path(), 'utf8'));
  assert.equal(report.steps.length, 100, 'one step per row: no row dropped or shifted');
  assert.equal(report.figure.times[19], '1890');
  assert.equal(report.y.filter((r) => r[0] === null).length, 40, 'the two stretches of 20 are gaps');
  const variance = (t) => report.steps[t - 1].kf.cov[0][0];
  for (const [a, b] of [[21, 40], [61, 80]]) {
    for (let t = a; t < b; t++) assert.ok(variance(t + 1) > variance(t), `the band widens through the gap at t = ${t}`);
  }
  assert.ok(variance(40) > 5 * variance(20), `${variance(40)} vs ${variance(20)}`);

  // The warnings box names the gaps; the series figure's time axis reads the years.
  const warnings = await page.$eval('#scf-section .warnings', (e) => (e.hidden ? '' : e.textContent));
  assert.match(warnings, /gap/, warnings);
  assert.match(warnings, /1891/, warnings);
  const svg = readFileSync(await (await downloadFigure(page, '#fig-series', 'svg')).path(), 'utf8');
  for (const year of ['1880', '1900', '1950']) assert.ok(new RegExp(`>\\s*${year}\\s*<`).test(svg), `the axis reads ${year}`);
  assert.ok(!svg.includes('NaN'), 'no NaN drawn');
  await page.$eval('#fig-series', (e) => e.scrollIntoView());
  await page.screenshot({ path: join(screenshotDir, 'nile-gaps-series.png'), fullPage: false });
  await page.close();
}
