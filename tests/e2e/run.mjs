// Browser end-to-end harness: node tests/e2e/run.mjs http://127.0.0.1:PORT/ [name-filter]
//                         or: node tests/e2e/run.mjs http://127.0.0.1:PORT/explorer/ --site
//
// Runs every tests/e2e/*.test.mjs (sorted by name) against Debian's Chromium through
// playwright-core. A test module exports `default async function (ctx)`, where ctx is
//   browser       the playwright Browser
//   baseUrl       the served www/ root, always ending in "/"
//   newPage(opts) a fresh context + page (opts go to browser.newContext: viewport,
//                 deviceScaleFactor, ...); its console errors/warnings and page errors are recorded
//   waitReady(page, timeoutMs?)  waits for document.body.dataset.ready === "1"
//   assert        node:assert/strict
//   screenshotDir tests/e2e/out (absolute; gitignored)
//   takeErrors(re) removes the recorded errors matching `re` and returns them: for a test that
//                 provokes one on purpose and checks that it was caught
// A test fails if it throws or if any of its pages logged a console error, threw a page error or
// broke its Content-Security-Policy (every securitypolicyviolation event is logged as an error).
// With --site the base is the explorer inside a site written by `confset gallery`, and the files
// run are tests/e2e/*.site.mjs (the gallery's tests; the site's root is the base's parent).
import { createRequire } from 'node:module';
import { readdirSync, mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, dirname } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import assert from 'node:assert/strict';
import { CHROMIUM } from './helpers.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const root = join(here, '..', '..');
const require = createRequire(join(root, 'www', 'package.json'));
const { chromium } = require('playwright-core');

const [baseArg, filter = ''] = process.argv.slice(2);
if (!baseArg) { console.error('usage: node tests/e2e/run.mjs BASE_URL [name-filter]'); process.exit(2); }
const baseUrl = baseArg.endsWith('/') ? baseArg : baseArg + '/';
const screenshotDir = join(here, 'out');
mkdirSync(screenshotDir, { recursive: true });
for (const f of readdirSync(screenshotDir)) if (f.includes('-FAILED-')) rmSync(join(screenshotDir, f));
const testTimeoutMs = Number(process.env.E2E_TEST_TIMEOUT_MS || 420_000);

const site = filter === '--site';
const files = readdirSync(here)
  .filter((f) => (site ? f.endsWith('.site.mjs') : f.endsWith('.test.mjs') && f.includes(filter))).sort();
if (files.length === 0) { console.error(`no tests/e2e/*.test.mjs matching "${filter}"`); process.exit(1); }

// Playwright gives each launch its own fresh temporary profile; keep its temp files apart too.
const tmp = mkdtempSync(join(tmpdir(), 'confset-e2e-'));
process.env.TMPDIR = tmp;
let browser = await chromium.launch(CHROMIUM);
console.log(`e2e: Chromium ${browser.version()}, ${files.length} test file(s), base ${baseUrl}`);

async function waitReady(page, timeoutMs = 60_000) {
  try {
    await page.waitForFunction(() => document.body && document.body.dataset.ready === '1', null, { timeout: timeoutMs });
  } catch (e) {
    throw new Error(`page ${page.url()} did not set document.body.dataset.ready === "1" within ${timeoutMs} ms ` +
      '(the page sets it once the wasm module is loaded and the first figure is drawn)');
  }
}

let passed = 0, failed = 0;
// A promise a test left behind that rejects later (e.g. a response read after its page closed)
// is a failure in words, not a crash of the harness that hides the other tests' results.
let current = '(between tests)';
process.on('unhandledRejection', (e) => {
  failed++;
  console.log(`FAIL ${current}: a promise it left rejected later: ${e?.stack || e}`);
});
for (const file of files) {
  const name = file.replace(/\.(test|site)\.mjs$/, '');
  current = name;
  // A browser or a page's renderer that crashes under a test (Chromium's process dying, its
  // 'crash' event: seen once each in full local runs, the test passing alone 6 of 6 times) is
  // relaunched or replaced and that test runs once more, saying so; an assertion failure is
  // never rerun.
  for (let attempt = 1; attempt <= 2; attempt++) {
  if (!browser.isConnected()) browser = await chromium.launch(CHROMIUM);
  const contexts = [], pages = [], errors = [], warnings = [], crashed = [];
  const newPage = async (opts = {}) => {
    const context = await browser.newContext(opts);
    contexts.push(context);
    // A CSP violation is an error of the page's, whether or not the browser logs one.
    await context.addInitScript(() => {
      document.addEventListener('securitypolicyviolation', (e) => {
        console.error(`CSP violation: ${e.violatedDirective} blocked ${e.blockedURI || 'inline'} (${e.sourceFile || ''}:${e.lineNumber})`);
      });
    });
    const page = await context.newPage();
    pages.push(page);
    page.on('crash', () => { crashed.push(page.url()); });
    page.on('console', (m) => {
      const loc = m.location(), where = loc && loc.url ? ` (${loc.url}:${loc.lineNumber})` : '';
      if (loc && /\/favicon\.ico$/.test(loc.url)) return; // browser-initiated, not the page's doing
      if (m.type() === 'error') errors.push(`console.error: ${m.text()}${where}`);
      else if (m.type() === 'warning') warnings.push(`console.warn: ${m.text()}${where}`);
    });
    page.on('pageerror', (e) => errors.push(`page error: ${e.stack || e.message}`));
    // The panels' compute workers log to their own console (a panic's message lands there).
    page.on('worker', (w) => w.on('console', (m) => {
      if (m.type() === 'error') errors.push(`worker console.error: ${m.text()} (${w.url()})`);
      else if (m.type() === 'warning') warnings.push(`worker console.warn: ${m.text()} (${w.url()})`);
    }));
    return page;
  };
  const takeErrors = (re) => {
    const taken = errors.filter((e) => re.test(e));
    errors.splice(0, errors.length, ...errors.filter((e) => !re.test(e)));
    return taken;
  };
  const ctx = { browser, baseUrl, newPage, waitReady, assert, screenshotDir, takeErrors };
  const t0 = Date.now();
  let failure = null;
  try {
    const mod = await import(pathToFileURL(join(here, file)).href);
    if (typeof mod.default !== 'function') throw new Error(`${file} has no default export function`);
    let timer;
    const timeout = new Promise((_, reject) => {
      timer = setTimeout(() => reject(new Error(`test timed out after ${testTimeoutMs} ms`)), testTimeoutMs);
    });
    try { await Promise.race([mod.default(ctx), timeout]); } finally { clearTimeout(timer); }
    if (errors.length) failure = new Error(`${errors.length} console/page error(s) recorded`);
  } catch (e) {
    failure = e;
  }
  const secs = ((Date.now() - t0) / 1000).toFixed(1);
  if (failure && (!browser.isConnected() || crashed.length) && attempt === 1) {
    const what = browser.isConnected() ? `a page's renderer crashed (${crashed.join(', ')})` : 'the browser crashed';
    console.log(`  ${name}: ${what} during the test (${failure.message || failure}): the test runs once more`);
    for (const c of contexts) await c.close().catch(() => {});
    continue;
  }
  for (const w of warnings) console.log(`  ${name}: ${w}`);
  if (failure) {
    failed++;
    for (const [i, p] of pages.entries()) {
      const shot = join(screenshotDir, `${name}-FAILED-${i}.png`);
      await p.screenshot({ path: shot, fullPage: true }).then(() => console.log(`  failure screenshot: ${shot}`), () => {});
    }
    for (const err of errors) console.log(`  ${name}: ${err}`);
    console.log(`FAIL ${name} (${secs} s): ${failure.stack || failure}`);
  } else {
    passed++;
    console.log(`PASS ${name} (${secs} s)`);
  }
  for (const c of contexts) await c.close().catch(() => {});
  break;
  }
}
await browser.close();
rmSync(tmp, { recursive: true, force: true });
console.log(`e2e: ${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
