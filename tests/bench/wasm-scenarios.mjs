// Times scenario files in wasm in Chromium: `Session.run` of each file in the served page, three
// times, best and median. With the slowest accepted scenario of each method (written by
// `CONFSET_WORK_DUMP=target/work cargo test --release --test suite fuzz::work_at_the_limits --
// --ignored --nocapture`), it gives the wasm side of the README's "Limits":
//   node tests/bench/wasm-scenarios.mjs http://127.0.0.1:PORT/ target/work/*.json
import { createRequire } from 'node:module';
import { readFileSync } from 'node:fs';
import { basename, dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { CHROMIUM } from '../e2e/helpers.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const { chromium } = createRequire(join(root, 'www', 'package.json'))('playwright-core');

const [base, ...files] = process.argv.slice(2);
if (!base || files.length === 0) {
  console.error('usage: node tests/bench/wasm-scenarios.mjs BASE_URL SCENARIO.json…');
  process.exit(2);
}
const browser = await chromium.launch(CHROMIUM);
const page = await browser.newPage();
await page.goto(base);
await page.waitForFunction(() => document.body.dataset.ready === '1', null, { timeout: 60_000 });
for (const file of files) {
  const json = readFileSync(file, 'utf8');
  const r = await page.evaluate((text) => {
    const s = new window.confset.Session();
    const ms = [];
    let bytes = 0;
    for (let i = 0; i < 3; i++) {
      const t0 = performance.now();
      bytes = s.run(text).length;
      ms.push(performance.now() - t0);
    }
    s.free();
    ms.sort((a, b) => a - b);
    return { best: ms[0], median: ms[1], bytes };
  }, json);
  console.log(`${basename(file)}: Session.run ${(r.best / 1000).toFixed(2)} s best, ${(r.median / 1000).toFixed(2)} s median of 3 (report ${(r.bytes / 1e6).toFixed(1)} MB of JSON)`);
}
await browser.close();
