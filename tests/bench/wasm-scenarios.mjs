// Times scenario files in wasm in Chromium: `Session.run` of each file in the served page, three
// times, best and median. With the slowest accepted scenario of each method (written by
// `CONFSET_WORK_DUMP=target/work cargo test --release --test suite fuzz::work_at_the_limits --
// --ignored --nocapture`), it gives the wasm side of the README's "Limits":
//   node tests/bench/wasm-scenarios.mjs http://127.0.0.1:PORT/ target/work/*.json
import { readFileSync } from 'node:fs';
import { basename } from 'node:path';
import { args, launch, openReady } from './browser.mjs';

const [base, ...files] = args(
  (a) => a[0] && a.length > 1, 'node tests/bench/wasm-scenarios.mjs BASE_URL SCENARIO.json…');
const browser = await launch();
const page = await openReady(browser, base);
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
