// What the wasm bench scripts (kernels.mjs, wasm-profile.mjs, wasm-scenarios.mjs) share: their
// command line, Debian's Chromium (through www's playwright-core) and the served page, loaded.
import { createRequire } from 'node:module';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { CHROMIUM } from '../e2e/helpers.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const { chromium } = createRequire(join(root, 'www', 'package.json'))('playwright-core');

// The script's arguments; when `ok(args)` is false, its usage line and exit status 2.
export function args(ok, usage) {
  const a = process.argv.slice(2);
  if (!ok(a)) {
    console.error(`usage: ${usage}`);
    process.exit(2);
  }
  return a;
}

export const launch = () => chromium.launch(CHROMIUM);

// The page's module is loaded (the app sets body data-ready="1").
export const ready = (page) => page.waitForFunction(() => document.body.dataset.ready === '1', null, { timeout: 60_000 });

// A new page of `browser` at `url` (page options `options`), once its module is loaded.
export async function openReady(browser, url, options = {}) {
  const page = await browser.newPage(options);
  await page.goto(url);
  await ready(page);
  return page;
}
