// Where a kernel of src/bench.rs spends its time in wasm, in Debian's Chromium: V8's sampling
// profiler (DevTools protocol) over repeated `BenchKernel` runs, self time summed by function.
//   node tests/bench/wasm-profile.mjs http://127.0.0.1:PORT/ [KERNEL] [RUNS]
// The release module has no name section (wasm-opt drops it), so serve a copy of www/ whose pkg/
// comes straight from wasm-bindgen, which keeps the Rust names:
//   wasm-bindgen --target web --out-dir DIR/pkg target/wasm32-unknown-unknown/release/confset.wasm
// It prints the top functions by self time; it asserts nothing.
import { args, launch, openReady } from './browser.mjs';

const [base, kernel = 'robot_mc', runs = '30'] = args(
  (a) => a[0], 'node tests/bench/wasm-profile.mjs BASE_URL [KERNEL] [RUNS]');
const browser = await launch();
const page = await openReady(browser, base);
const cdp = await page.context().newCDPSession(page);
await cdp.send('Profiler.enable');
await cdp.send('Profiler.setSamplingInterval', { interval: 100 });
// Warm up to the optimizing tier first, so the profile is of the code the benchmark times.
await page.evaluate(([k, n]) => {
  const b = new window.confset.BenchKernel(k);
  for (let i = 0; i < n; i++) b.run();
  b.free();
}, [kernel, 5]);
await cdp.send('Profiler.start');
await page.evaluate(([k, n]) => {
  const b = new window.confset.BenchKernel(k);
  for (let i = 0; i < n; i++) b.run();
  b.free();
}, [kernel, Number(runs)]);
const { profile } = await cdp.send('Profiler.stop');
await browser.close();

// Self time per sample: each sample is one leaf node; the interval between samples is its time.
const byId = new Map(profile.nodes.map((n) => [n.id, n]));
const self = new Map();
let total = 0;
profile.samples.forEach((id, i) => {
  const dt = profile.timeDeltas[i + 1] ?? 0;
  const name = byId.get(id).callFrame.functionName || '(anonymous)';
  self.set(name, (self.get(name) ?? 0) + dt);
  total += dt;
});
const idle = new Set(['(idle)', '(program)', '(garbage collector)']);
const busy = [...self].filter(([n]) => !idle.has(n)).reduce((s, [, t]) => s + t, 0);
console.log(`PROFILE ${kernel}: ${runs} runs, ${(busy / 1000).toFixed(0)} ms sampled (of ${(total / 1000).toFixed(0)} ms)`);
for (const [name, t] of [...self].filter(([n]) => !idle.has(n)).sort((a, b) => b[1] - a[1]).slice(0, 15)) {
  console.log(`${((100 * t) / busy).toFixed(1).padStart(5)} %  ${name.length > 110 ? `${name.slice(0, 107)}...` : name}`);
}
