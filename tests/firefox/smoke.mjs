// Firefox smoke test of the explorer through WebDriver: node tests/firefox/smoke.mjs BASE_URL
//
// Drives Debian's firefox-esr (headless) through geckodriver with selenium-webdriver, over the
// release build served at BASE_URL. For every panel of the registry (www/registry.js): a fresh
// page on #<id> loads, computes and goes idle; every visible figure has ink and no drawing error;
// the panel's share link (deflate-raw through CompressionStream) reopens in a fresh page with the
// same controls and pixels (DecompressionStream). Then one study runs to its end (the
// set-membership guarantee, 200 runs). A check fails if it throws, or if any page logged a
// console error, threw an uncaught exception or broke its Content-Security-Policy.
//
// The console is read through WebDriver BiDi (log.entryAdded, selenium's LogInspector): Firefox
// reports there the pages' console entries and uncaught exceptions, its workers' too (checked by
// hand with a page whose worker logs and throws), and a Content-Security-Policy violation as an
// exception entry. The check "console" provokes a console error, an uncaught exception and a CSP
// violation in the page and fails unless all three are recorded, so a silent log route fails
// the run instead of passing it.
//
// Environment: FIREFOX (default /usr/bin/firefox-esr), GECKODRIVER (default: geckodriver on PATH).
import { createRequire } from 'node:module';
import { mkdtempSync, rmSync, mkdirSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { execFileSync } from 'node:child_process';
import assert from 'node:assert/strict';
import { PANELS } from '../../www/registry.js';

const here = dirname(fileURLToPath(import.meta.url));
const root = join(here, '..', '..');
const require = createRequire(join(root, 'www', 'package.json'));
const { Builder } = require('selenium-webdriver');
const firefox = require('selenium-webdriver/firefox');
const LogInspector = require('selenium-webdriver/bidi/logInspector');

const [baseArg] = process.argv.slice(2);
if (!baseArg) { console.error('usage: node tests/firefox/smoke.mjs BASE_URL'); process.exit(2); }
const baseUrl = baseArg.endsWith('/') ? baseArg : baseArg + '/';
const FIREFOX = process.env.FIREFOX || '/usr/bin/firefox-esr';
const GECKODRIVER = process.env.GECKODRIVER || execFileSync('sh', ['-c', 'command -v geckodriver']).toString().trim();
const WAIT_MS = 60_000;
const outDir = join(here, 'out');
mkdirSync(outDir, { recursive: true });

// Firefox and geckodriver keep their profile and temp files apart, removed at the end.
const tmp = mkdtempSync(join(tmpdir(), 'confset-firefox-'));
process.env.TMPDIR = tmp;
const options = new firefox.Options()
  .setBinary(FIREFOX)
  .addArguments('-headless')
  .windowSize({ width: 1366, height: 900 })
  .enableBidi();
// The driver's path is given: selenium's own driver manager (which would go online) never runs.
const service = new firefox.ServiceBuilder(GECKODRIVER);
const driver = await new Builder().forBrowser('firefox').setFirefoxOptions(options).setFirefoxService(service).build();
const caps = await driver.getCapabilities();
console.log(`firefox: ${caps.getBrowserName()} ${caps.getBrowserVersion()} via ${GECKODRIVER}, ${PANELS.length} panels, base ${baseUrl}`);

const errors = [], warnings = [];
const logs = await LogInspector(driver);
await logs.onConsoleEntry((e) => {
  const line = `console.${e.method}: ${e.text}`;
  if (e.level === 'error') errors.push(line); else if (e.level === 'warn') warnings.push(line);
});
await logs.onJavascriptException((e) => errors.push(`uncaught exception: ${e.text}`));
const run = (fn, ...args) => driver.executeScript(fn, ...args);
const waitFor = async (fn, arg, what) => {
  try {
    await driver.wait(() => run(fn, arg), WAIT_MS);
  } catch (e) {
    throw new Error(`${what} within ${WAIT_MS} ms (${e.name})`);
  }
};
// A fresh document on `url` (about:blank first: a new fragment alone would not reload), loaded
// and with the panel idle (`busyKey`: the registry's flag of the panel).
async function open(url, busyKey) {
  await driver.get('about:blank');
  await driver.get(url);
  await waitFor(() => document.body && document.body.dataset.ready === '1', null,
    `${url}: document.body.dataset.ready === "1"`);
  await waitFor((k) => !document.body.dataset[k], busyKey, `${url}: the panel idle (dataset.${busyKey} cleared)`);
  // A study the panel starts by itself (GLLS's precision Monte Carlo) holds a flag of its own,
  // named …Busy too, and keeps redrawing its figure until it ends.
  await waitFor(() => !Object.keys(document.body.dataset).some((k) => /busy$/i.test(k)), null,
    `${url}: the panel's own studies done (no dataset.…Busy left)`);
}

// Every visible figure canvas of a panel: its size, the fraction of device pixels that are
// neither white nor transparent, a digest of its pixels; and the text of its drawing errors.
const figures = (id) => run((id) => {
  const root = document.getElementById(id);
  const canvases = [...root.querySelectorAll('figure.card canvas')].filter((c) => c.offsetParent && c.width > 1).map((c) => {
    const copy = Object.assign(document.createElement('canvas'), { width: c.width, height: c.height });
    const g = copy.getContext('2d', { willReadFrequently: true });
    g.drawImage(c, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    let ink = 0, h = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i + 3] > 0 && (d[i] < 245 || d[i + 1] < 245 || d[i + 2] < 245)) ink++;
    for (let i = 0; i < d.length; i += 7) h = (h * 31 + d[i]) >>> 0;
    return { panel: c.dataset.panel, size: `${c.width}x${c.height}`, ink: ink / (c.width * c.height), digest: h };
  });
  const figErr = [...root.querySelectorAll('.fig-err')].map((e) => e.textContent.trim()).filter(Boolean).join(' | ');
  const banner = [...document.querySelectorAll(`#${id}-section .banner`)].map((b) => (b.hidden ? '' : b.textContent)).join('');
  const controls = [...root.querySelectorAll('form input[id], form select[id], form textarea[id]')]
    .filter((e) => e.type !== 'file').map((e) => `${e.id}=${e.type === 'checkbox' ? e.checked : e.value}`);
  return { canvases, figErr, banner, controls };
}, id);

function assertDrawn(id, f) {
  assert.ok(f.canvases.length > 0, `${id}: no visible figure`);
  for (const c of f.canvases) assert.ok(c.ink > 0.005, `${id}: figure ${c.panel} (${c.size}) is blank: ${(100 * c.ink).toFixed(2)} % ink`);
  assert.equal(f.figErr, '', `${id}: drawing error`);
  assert.equal(f.banner, '', `${id}: banner`);
}

async function checkPanel(d) {
  await open(`${baseUrl}#${d.id}`, d.busy);
  const first = await figures(d.id);
  assertDrawn(d.id, first);
  // The link follows the controls (debounced after an input event in the panel); an input event
  // that changes no control makes the link of the current state without a new compute.
  await run((id) => document.getElementById(id).dispatchEvent(new Event('input', { bubbles: true })), d.id);
  await waitFor((id) => location.hash.startsWith(`#${id}/v1/`), d.id, `${d.id}: the share link in the address bar`);
  const link = await driver.getCurrentUrl();
  await open(link, d.busy);
  const restored = await figures(d.id);
  assertDrawn(`${d.id} (link)`, restored);
  assert.deepEqual(restored.controls, first.controls, `${d.id}: the link restores the controls`);
  assert.deepEqual(restored.canvases.map((c) => c.digest), first.canvases.map((c) => c.digest), `${d.id}: the link restores the pixels`);
  return `${first.canvases.length} figures (ink ${first.canvases.map((c) => (100 * c.ink).toFixed(1)).join(', ')} %), link of ${link.length} characters reopens`;
}

// One study to its end: the set-membership guarantee, 200 runs.
async function checkStudy() {
  const d = PANELS.find((p) => p.id === 'ubb');
  await open(`${baseUrl}#ubb`, d.busy);
  await run(() => {
    const runs = document.getElementById('b-runs');
    runs.value = '200';
    runs.dispatchEvent(new Event('input', { bubbles: true }));
  });
  await waitFor((k) => !document.body.dataset[k], d.busy, 'ubb: idle after setting the runs');
  await run(() => document.getElementById('b-go').click());
  await waitFor(() => /runs/.test(document.getElementById('b-g-status').textContent) && !document.getElementById('b-go').disabled,
    null, 'ubb: the guarantee study finished (status says runs, Run enabled again)');
  const [status, err] = await run(() => [document.getElementById('b-g-status').textContent.trim(), document.getElementById('b-g-err')?.textContent.trim() || '']);
  assert.match(status, /\b200 runs\b/, `ubb study status: ${status}`);
  assert.doesNotMatch(status, /cancel/i, `ubb study status: ${status}`);
  assert.equal(err, '', 'ubb study error');
  assertDrawn('ubb (after the study)', await figures('ubb'));
  return status;
}

const checks = [
  ['landing', async () => {
    await open(baseUrl, 'busy');
    const cards = await run(() => document.querySelectorAll('#landing a.promise').length);
    assert.equal(cards, PANELS.length, 'landing cards');
    return `${cards} cards`;
  }],
  ['console', async () => {
    // The log route works: three errors provoked in the page are recorded, then taken back.
    await run(() => {
      console.error('confset-probe: console.error');
      setTimeout(() => { throw new Error('confset-probe: uncaught'); }, 0);
      document.head.append(Object.assign(document.createElement('script'), { textContent: 'window.confsetProbe = 1' }));
    });
    const kinds = [/^console\.error: confset-probe: console\.error/, /^uncaught exception: .*confset-probe: uncaught/,
      /^uncaught exception: Content-Security-Policy: .*inline script/];
    try {
      await driver.wait(() => kinds.every((re) => errors.some((e) => re.test(e))), 10_000);
    } catch {
      throw new Error(`the provoked errors were not all recorded: ${JSON.stringify(errors)}`);
    }
    assert.equal(await run(() => window.confsetProbe), null, 'the inline script did not run');
    const provoked = errors.length;
    errors.length = 0;
    return `a console error, an uncaught exception and a CSP violation are recorded (${provoked} entries, taken back)`;
  }],
  ...PANELS.map((d) => [d.id, () => checkPanel(d)]),
  ['study', checkStudy],
];

let passed = 0, failed = 0;
for (const [name, check] of checks) {
  errors.length = 0;
  warnings.length = 0;
  const t0 = Date.now();
  let failure = null, note = '';
  try {
    note = await check();
    await driver.sleep(100); // log entries of the last moment arrive
    if (errors.length) failure = new Error(`${errors.length} console error(s) recorded`);
  } catch (e) {
    failure = e;
  }
  const secs = ((Date.now() - t0) / 1000).toFixed(1);
  for (const w of warnings) console.log(`  ${name}: ${w}`);
  if (failure) {
    failed++;
    for (const e of errors) console.log(`  ${name}: ${e}`);
    const shot = join(outDir, `${name}-FAILED.png`);
    await driver.takeScreenshot().then((png) => { writeFileSync(shot, png, 'base64'); console.log(`  failure screenshot: ${shot}`); }, () => {});
    console.log(`FAIL ${name} (${secs} s): ${failure.stack || failure}`);
  } else {
    passed++;
    console.log(`PASS ${name} (${secs} s): ${note}`);
  }
}
await driver.quit();
rmSync(tmp, { recursive: true, force: true });
console.log(`firefox: ${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
