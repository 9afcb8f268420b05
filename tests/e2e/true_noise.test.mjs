// True noise apart from assumed noise (issue 29), SCF view: moving "True noise V ×" changes the
// simulated record (the true state in the numbers table) but not what the filter assumes (the KF
// variances P, a function of the assumed V and W only, (35c)); moving "Assumed V ×" changes P.
// The read-out says when the two differ, and a share link keeps both. Screenshots of the
// controls at 1280 × 800 and 390 × 844.
import { text, setField } from './helpers.mjs';

const idle = (page) => page.waitForFunction(() => !document.body.dataset.busy, null, { timeout: 60_000 });

const slide = (page, id, value) => setField(page, id, value, idle);

// The numbers table's row `label`: [centre, variances].
const row = (page, label) => page.$$eval('#numbers tr', (rows, l) => {
  const r = rows.find((tr) => tr.querySelector('th')?.textContent.startsWith(l));
  return r ? [...r.querySelectorAll('td')].map((td) => td.textContent.trim()) : null;
}, label);

export default async function trueNoise(env) {
  const { assert, newPage, baseUrl, waitReady, screenshotDir } = env;
  const page = await newPage({ viewport: { width: 1280, height: 800 } });
  await page.goto(`${baseUrl}#scf/preset/scf-scalar`);
  await waitReady(page);
  await idle(page);
  assert.match(await text(page, '#noise-readout'), /assumes/, 'the read-out is shown');

  const truth0 = await row(page, 'true state');
  const kf0 = await row(page, 'KF');
  assert.ok(truth0 && kf0, 'the numbers table has the true state and the KF row');

  // True V × 3.98 (the slider's step of 0.05 in log₁₀ puts 4 at 10^0.6): the record moves, the filter's P does not.
  await slide(page, 'tv', Math.log10(4));
  assert.equal(await page.$eval('#fig-state .fig-err', (e) => e.textContent.trim()), '', 'the state figure is drawn');
  const truth1 = await row(page, 'true state');
  const kf1 = await row(page, 'KF');
  assert.notEqual(truth1[0], truth0[0], 'moving the true V moves the truth');
  assert.equal(kf1[1], kf0[1], 'moving the true V leaves the KF variance P');
  const said = await text(page, '#noise-readout');
  assert.match(said, /the data have 3.98 V, W/, `the read-out names the difference: "${said}"`);

  // A share link keeps both groups.
  await page.waitForFunction(() => location.hash.includes('/v1/'));
  const link = await page.evaluate(() => location.href);
  await slide(page, 'sv', Math.log10(4));
  const kf2 = await row(page, 'KF');
  assert.notEqual(kf2[1], kf1[1], 'moving the assumed V changes P');
  const again = await newPage({ viewport: { width: 1280, height: 800 } });
  await again.goto(link);
  await waitReady(again);
  await idle(again);
  assert.equal(Number(await again.$eval('#tv', (e) => e.value)).toFixed(1), '0.6', 'the link keeps the true V');
  assert.deepEqual(await row(again, 'true state'), truth1, 'the link gives the same record');
  await again.close();

  // The controls, to look at (not compared).
  const dir = screenshotDir ?? '/tmp';
  await page.locator('#true-group').scrollIntoViewIfNeeded();
  await page.screenshot({ path: `${dir}/noise-1280.png` });
  await page.setViewportSize({ width: 390, height: 844 });
  await page.locator('#true-group').scrollIntoViewIfNeeded();
  await page.screenshot({ path: `${dir}/noise-390.png` });
  await page.close();
}
