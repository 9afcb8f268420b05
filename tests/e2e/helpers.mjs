// Page helpers shared by the panels' end-to-end tests (not a test file: run.mjs only loads
// *.test.mjs).
import { join } from 'node:path';

// How every script of the repository launches Debian's Chromium through playwright-core (the
// e2e harness, the benchmarks, the profiler): no sandbox (root in CI), no GPU, and none of the
// background network calls a machine without internet would stall on.
export const CHROMIUM = {
  executablePath: '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage', '--disable-background-networking',
    '--disable-component-update', '--disable-sync', '--no-first-run', '--disable-quic'],
};

// Text content with runs of whitespace folded.
export const text = (page, sel) => page.$eval(sel, (e) => e.textContent.trim().replace(/\s+/g, ' '));

// Fraction of a canvas's device pixels that are neither white nor transparent, read through a
// fresh canvas (one readback each: no willReadFrequently warning on the page's own canvas).
export const inked = (page, canvasSelector) => page.$eval(canvasSelector, (c) => {
  const copy = Object.assign(document.createElement('canvas'), { width: c.width, height: c.height });
  const g = copy.getContext('2d', { willReadFrequently: true });
  g.drawImage(c, 0, 0);
  const d = g.getImageData(0, 0, c.width, c.height).data;
  let k = 0;
  for (let i = 0; i < d.length; i += 4) if (d[i + 3] > 0 && (d[i] < 245 || d[i + 1] < 245 || d[i + 2] < 245)) k++;
  return k / (c.width * c.height);
});

// Set a control's value (or a checkbox's state) as a user would, then wait for the panel.
export async function setField(page, id, value, idle) {
  await page.$eval(`#${id}`, (el, v) => {
    if (el.type === 'checkbox') el.checked = v === 'true'; else el.value = v;
    el.dispatchEvent(new Event('input', { bubbles: true }));
  }, String(value));
  await idle(page);
}

// Pick a preset in a panel's menu and wait for the panel.
export async function choosePreset(page, selectId, name, idle) {
  await page.selectOption(`#${selectId}`, name);
  await idle(page);
}

// A fresh 1366 × 900 page at device pixel ratio `dpr` on one route of the app (`#scf`, `#lscr/v1/…`),
// loaded and with the panel idle.
export async function openApp({ newPage, baseUrl, waitReady }, dpr, idle, route) {
  const page = await newPage({ viewport: { width: 1366, height: 900 }, deviceScaleFactor: dpr });
  await page.goto(`${baseUrl}#${route}`);
  await waitReady(page);
  await idle(page);
  return page;
}

// Each panel's figure canvas (#fig-<panel>) is drawn at the device pixel ratio: its backing store
// is its CSS size × dpr; with `minWidth`, it is at least that many CSS pixels wide.
export async function assertDrawnAtRatio(page, assert, dpr, panels, minWidth = 0) {
  for (const p of panels) {
    const size = await page.$eval(`#fig-${p} canvas`, (c) => [c.width, c.height, c.clientWidth, c.clientHeight]);
    assert.equal(size[0], Math.round(size[2] * dpr), `${p}: canvas width ${size[0]} for CSS ${size[2]} at DPR ${dpr}`);
    assert.equal(size[1], Math.round(size[3] * dpr), `${p}: canvas height ${size[1]} for CSS ${size[3]} at DPR ${dpr}`);
    if (minWidth) assert.ok(size[2] >= minWidth, `${p}: the figure is large enough (${size[2]} CSS px wide)`);
  }
}

// Each panel's figure (#fig-<panel>) is drawn without an error and has ink (over 2 % of its
// pixels); `what` names the state of the page in the messages.
export async function assertDrawnWell(page, assert, panels, what) {
  for (const p of panels) {
    assert.equal(await text(page, `#fig-${p} .fig-err`), '', `${what}: the ${p} figure is drawn without error`);
    const ink = await inked(page, `#fig-${p} canvas`);
    assert.ok(ink > 0.02, `${what}: the ${p} figure has ink (${(100 * ink).toFixed(1)} % of the pixels)`);
  }
}

// Screenshot of one panel's section (scrolled into view first) as `<name>.png`.
export async function shootSection(page, sectionId, screenshotDir, name) {
  await page.$eval(`#${sectionId}`, (e) => e.scrollIntoView());
  await (await page.$(`#${sectionId}`)).screenshot({ path: join(screenshotDir, `${name}.png`) });
}

// Move a slider to `value` as a user does (an input event) and measure, in the page, the time to
// the first frame painted after the panel drew it: the panel's busy flag (`busyKey`) is clear on
// an animation frame, then one more frame.
export const slideToPaint = (page, sliderId, busyKey, value) => page.evaluate(async ([id, busy, v]) => {
  const r = document.getElementById(id);
  const t0 = performance.now();
  r.value = String(v);
  r.dispatchEvent(new Event('input', { bubbles: true }));
  await new Promise((res) => {
    const drawn = () => requestAnimationFrame(() => (document.body.dataset[busy] ? drawn() : requestAnimationFrame(res)));
    drawn();
  });
  return performance.now() - t0;
}, [sliderId, busyKey, String(value)]);

// Download a figure card's export (`choice`: a value of figure.js's EXPORTS, 'svg', 'svg-1920x1080',
// 'png-1', 'png-4', …) as a user does: pick it in the card's menu, click Download; the Download.
export async function downloadFigure(page, card, choice) {
  await page.selectOption(`${card} [data-dl-choice]`, choice);
  const [dl] = await Promise.all([page.waitForEvent('download'), page.click(`${card} [data-dl=go]`)]);
  return dl;
}
