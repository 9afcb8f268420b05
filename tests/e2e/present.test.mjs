// The narratable animation and present/embed mode (issue 28). For each view with a time axis
// and an animation (scf, uniform, ubb, compare; lscr's data length t and glls's horizon s, whose
// steps recompute: their range is the one the bar gives, data-first … data-last, from the
// smallest value the core accepts; each step run and drawn before the next, none skipped, and a
// run that fails pauses the animation): ▶ and ◀ move the control by exactly one step;
// play at the last step (loop off) starts again from the first; at 20 steps/s play advances the
// slider by more than one step and ❚❚ pause stops it (the value stable across two reads 300 ms
// apart); with loop on, play wraps from the last step to the first; the step's read-out is a
// live region only while paused. Present mode (#<view>&present, &panel=…), opened directly at
// 1024×576 and 1920×1080 and as the embed code's iframe (960×540, 1024×576, 1920×1080): no scrolling, the figure's
// canvas inside the window (large, redrawn at its size), the step and play controls visible and
// inside it, the chrome (menu, toolbar, numbers) hidden; → steps the cursor (lscr, glls: ←, and
// the link the page rewrites, opened again, shows that step; Space plays and k pauses); the link keeps
// &present as the page rewrites it. "Copy embed code" copies the iframe snippet (or, without a
// clipboard, shows it to copy by hand). Screenshots of
// ubb's present mode: /tmp/present-1024.png and /tmp/present-1920.png (and tests/e2e/out/).
// No timing is asserted: only that the cursor moved, or stopped.
import { join } from 'node:path';
import { copyFileSync } from 'node:fs';

const VIEWS = [
  { id: 'scf', busy: 'busy', slider: 'time' },
  { id: 'uniform', busy: 'uniformBusy', slider: 'u-time' },
  { id: 'ubb', busy: 'ubbBusy', slider: 'b-time' },
  { id: 'compare', busy: 'compareBusy', slider: 'c-time' },
  // Controls that recompute: a number box (the data length) and a slider (the horizon).
  { id: 'lscr', busy: 'lscrBusy', slider: 'l-t', recompute: ['simulate', 'steps'] },
  { id: 'glls', busy: 'gllsBusy', slider: 'g-s', recompute: ['glls', 'horizon'] },
];

const idle = (page, d) => page.waitForFunction((k) => !document.body.dataset[k], d.busy, { timeout: 120_000 });
const value = (page, d) => page.$eval(`#${d.slider}`, (r) => Number(r.value));
const anim = (d, what) => `#${d.id} .anim-bar [data-anim=${what}]`;
const setSlider = async (page, d, v) => {
  await page.$eval(`#${d.slider}`, (r, x) => { r.value = String(x); r.dispatchEvent(new Event('input', { bubbles: true })); }, v);
  await idle(page, d);
};
// The first and last steps the animation plays over: the slider's range, or for a control that
// recomputes the range its bar gives (the first value the core accepts, found by asking it).
const steps = async (page, d) => {
  if (!d.recompute) return page.$eval(`#${d.slider}`, (r) => [Number(r.min), Number(r.max)]);
  // Asked as the pointer reaches the bar (not with every run).
  await page.hover(`#${d.id} .anim-bar`);
  await idle(page, d);
  const [lo, hi] = await page.$eval(`#${d.id} .anim-bar`, (b) => [Number(b.dataset.first), Number(b.dataset.last)]);
  const min = await page.$eval(`#${d.slider}`, (r) => Number(r.min));
  return [lo, hi, min];
};
const playing = (page, d) => page.$eval(anim(d, 'play'), (b) => b.getAttribute('aria-pressed') === 'true');
// Wait until the slider's value is `op` (below, at least, equal to) `a`.
const waitValue = (page, d, op, a) => page.waitForFunction(([id, o, x]) => {
  const v = Number(document.getElementById(id).value);
  return o === '<' ? v < x : o === '>=' ? v >= x : v === x;
}, [d.slider, op, a], { timeout: 60_000 });

async function animation(env, d) {
  const { newPage, baseUrl, waitReady, assert } = env;
  const page = await newPage({ viewport: { width: 1366, height: 900 } });
  await page.goto(`${baseUrl}#${d.id}`);
  await waitReady(page);
  await idle(page, d);
  const [lo, hi, min] = await steps(page, d);
  assert.ok(Number.isInteger(lo) && Number.isInteger(hi) && hi - lo >= 6, `${d.id}: a range of steps to play (${lo} … ${hi})`);
  if (d.recompute) {
    // The range starts at the first value the core accepts: the one below it is refused.
    assert.equal(await page.$eval(anim(d, 'range'), (e) => e.textContent), `${d.slider.slice(2)} = ${lo} … ${hi}`);
    assert.ok(lo > min, `${d.id}: the first step ${lo} is above the control's min ${min} (the core refuses ${min})`);
    await setSlider(page, d, lo - 1);
    assert.ok(await page.$eval(`#${d.slider.slice(0, 2)}stale`, (e) => !e.hidden), `${d.id}: ${lo - 1} is refused`);
    await setSlider(page, d, lo);
    assert.ok(await page.$eval(`#${d.slider.slice(0, 2)}stale`, (e) => e.hidden), `${d.id}: ${lo} is accepted`);
  }

  // The controls, labelled for a screen reader; play in one line.
  for (const [what, label] of [['prev', 'previous step'], ['play', 'play'], ['next', 'next step'], ['speed', 'animation speed']]) {
    assert.equal(await page.$eval(anim(d, what), (e) => e.getAttribute('aria-label')), label, `${d.id}: ${what} is labelled`);
  }
  assert.equal(await page.$eval(anim(d, 'play'), (b) => b.textContent), '▶ play');
  assert.equal(await page.$eval(anim(d, 'speed'), (s) => s.value), '2', `${d.id}: 2 steps/s by default`);
  const heights = await page.$$eval(`#${d.id} .anim-bar button`, (bs) => bs.map((b) => b.getBoundingClientRect().height));
  assert.ok(Math.max(...heights) - Math.min(...heights) < 2, `${d.id}: the buttons are one line each (${heights})`);

  // ▶ and ◀: exactly one step.
  const mid = Math.round((lo + hi) / 2);
  await setSlider(page, d, mid);
  await page.click(anim(d, 'next'));
  await idle(page, d);
  assert.equal(await value(page, d), mid + 1, `${d.id}: ▶ steps from ${mid} to ${mid + 1}`);
  await page.click(anim(d, 'prev'));
  await page.click(anim(d, 'prev'));
  await idle(page, d);
  assert.equal(await value(page, d), mid - 1, `${d.id}: ◀ ◀ steps back to ${mid - 1}`);

  // Play at the last step, loop off: from the first step again.
  await setSlider(page, d, hi);
  await page.click(anim(d, 'play'));
  await waitValue(page, d, '<', hi);
  assert.equal(await page.$eval(anim(d, 'play'), (b) => b.textContent), '❚❚ pause');
  const out = await page.$(`#${d.id} #${d.slider}-out`);
  if (out) assert.equal(await out.getAttribute('aria-live'), 'off', `${d.id}: the read-out is silent while playing`);
  await page.click(anim(d, 'play'));
  assert.ok(!(await playing(page, d)), `${d.id}: paused`);
  if (out) assert.equal(await out.getAttribute('aria-live'), 'polite', `${d.id}: the read-out speaks when paused`);

  // At 20 steps/s play advances by more than one step; pause stops it.
  await page.selectOption(anim(d, 'speed'), '20');
  await setSlider(page, d, mid);
  const v0 = await value(page, d);
  await page.click(anim(d, 'play'));
  await waitValue(page, d, '>=', v0 + 2);
  await page.click(anim(d, 'play'));
  const a = await value(page, d);
  await page.waitForTimeout(300);
  const b = await value(page, d);
  assert.ok(a >= v0 + 2, `${d.id}: played from ${v0} to ${a}`);
  assert.equal(b, a, `${d.id}: paused at ${a} (${b} 300 ms later)`);
  assert.equal(await page.$eval(anim(d, 'play'), (x) => x.textContent), '▶ play');

  if (d.recompute) {
    // Each step is run, and drawn, before the next is shown: with every run held 150 ms (longer
    // than a step at 20 steps/s), the runs the animation asks for are one step apart, none
    // skipped (without the wait, the control would run ahead and a run take the value it reached).
    await setSlider(page, d, lo);
    await page.evaluate(async ([id, path]) => {
      const c = (await import(new URL('compute.js', document.baseURI).href)).computeClients.get(id);
      c.testOnlySlowMs = 150;
      window.runsAsked = [];
      window.plainRun = c.run;
      c.run = (text) => { window.runsAsked.push(path.reduce((o, k) => o?.[k], JSON.parse(text))); return window.plainRun(text); };
    }, [d.id, d.recompute]);
    await page.click(anim(d, 'play'));
    await waitValue(page, d, '>=', lo + 4);
    await page.click(anim(d, 'play'));
    await idle(page, d);
    const asked = await page.evaluate(async (id) => {
      const c = (await import(new URL('compute.js', document.baseURI).href)).computeClients.get(id);
      Object.assign(c, { testOnlySlowMs: 0, run: window.plainRun });
      return window.runsAsked;
    }, d.id);
    assert.ok(asked.length >= 4, `${d.id}: a run per step (${asked})`);
    assert.deepEqual(asked, asked.map((_, i) => lo + 1 + i), `${d.id}: the runs follow the steps one by one`);
    assert.equal(await value(page, d), lo + asked.length, `${d.id}: paused at the step last run`);
    // A run that fails (the worker's instance aborts) pauses the animation at that step, with the
    // panel's message.
    await page.evaluate(async (id) => {
      (await import(new URL('compute.js', document.baseURI).href)).computeClients.get(id).testOnlyAbortNextRun = true;
    }, d.id);
    const before = await value(page, d);
    await page.click(anim(d, 'play'));
    await page.waitForFunction((sel) => document.querySelector(sel).getAttribute('aria-pressed') === 'false', anim(d, 'play'), { timeout: 60_000 });
    await idle(page, d);
    assert.equal(await value(page, d), before + 1, `${d.id}: paused at the step whose run failed`);
    assert.match(await page.$eval(`#${d.id} .compute-note`, (e) => (e.hidden ? '' : e.textContent)), /^The computation failed/, `${d.id}: the failure is said`);
  }

  // Loop off: play stops at the last step. Loop on: from the last step to the first.
  await setSlider(page, d, hi - 2);
  await page.click(anim(d, 'play'));
  await page.waitForFunction((sel) => document.querySelector(sel).getAttribute('aria-pressed') === 'false', anim(d, 'play'), { timeout: 60_000 });
  assert.equal(await value(page, d), hi, `${d.id}: the animation ends at the last step`);
  await page.check(anim(d, 'loop'));
  await setSlider(page, d, hi - 2);
  const seen = await page.evaluate(async ([id, play, top]) => {
    const r = document.getElementById(id);
    const values = [];
    document.querySelector(play).click();
    await new Promise((res) => {
      const poll = () => {
        if (values[values.length - 1] !== r.value) values.push(r.value);
        const wrapped = values.map(Number).some((v, i) => i > 0 && Number(values[i - 1]) === top && v < top);
        if (wrapped || values.length > 400) res(); else requestAnimationFrame(poll);
      };
      poll();
    });
    document.querySelector(play).click();
    return values.map(Number);
  }, [d.slider, anim(d, 'play'), hi]);
  assert.ok(seen.some((v, i) => i > 0 && seen[i - 1] === hi && v < hi), `${d.id}: with loop on, the last step is followed by the first (${seen.join(' ')})`);
  await page.close();
}

// The present mode's layout in a window of w × h.
async function checkPresent(page, assert, d, what, { figures = 1 } = {}) {
  const m = await page.evaluate(() => {
    const de = document.documentElement;
    const box = (e) => { const r = e.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; };
    return {
      present: document.body.classList.contains('present'),
      scroll: [de.scrollWidth, de.clientWidth, de.scrollHeight, de.clientHeight],
      view: [window.innerWidth, window.innerHeight],
      canvases: [...document.querySelectorAll('.present-fig canvas')].map((c) => ({ box: box(c), store: [c.width, c.height, c.clientWidth, c.clientHeight], dpr: devicePixelRatio })),
      figErr: [...document.querySelectorAll('.present-fig .fig-err')].map((e) => e.textContent).join(''),
    };
  });
  const [vw, vh] = m.view;
  assert.ok(m.present, `${what}: body.present`);
  assert.ok(m.scroll[0] <= m.scroll[1] && m.scroll[2] <= m.scroll[3], `${what}: no scrolling (${m.scroll})`);
  assert.equal(m.canvases.length, figures, `${what}: ${figures} figure(s)`);
  assert.equal(m.figErr, '', `${what}: drawn without error`);
  for (const c of m.canvases) {
    const [l, t, r, b] = c.box;
    assert.ok(l >= 0 && t >= 0 && r <= vw && b <= vh, `${what}: the canvas ${c.box.map(Math.round)} lies inside ${vw}×${vh}`);
    assert.ok(b - t >= 0.6 * vh && (r - l) * figures >= 0.6 * vw, `${what}: the figure is large (${Math.round(r - l)}×${Math.round(b - t)})`);
    assert.equal(c.store[0], Math.round(c.store[2] * c.dpr), `${what}: redrawn at its width`);
    assert.equal(c.store[1], Math.round(c.store[3] * c.dpr), `${what}: redrawn at its height`);
  }
  for (const what2 of ['prev', 'play', 'next']) {
    const sel = anim(d, what2);
    assert.ok(await page.isVisible(sel), `${what}: ${what2} is visible`);
    const bb = await (await page.$(sel)).boundingBox();
    assert.ok(bb.x >= 0 && bb.y >= 0 && bb.x + bb.width <= vw && bb.y + bb.height <= vh, `${what}: ${what2} inside the window (${JSON.stringify(bb)})`);
  }
  for (const hidden of ['nav.routes', `#${d.id}-section .toolbar`, `#${d.id} .numbers`, `#${d.id} .section-head .sub`]) {
    assert.ok(!(await page.isVisible(hidden)), `${what}: ${hidden} is hidden`);
  }
}

export default async function present(env) {
  const { newPage, baseUrl, waitReady, assert, screenshotDir } = env;
  for (const d of VIEWS) await animation(env, d);

  // Present mode, opened directly, at the two ends of a 16:9 projector.
  for (const [w, h] of [[1024, 576], [1920, 1080]]) {
    for (const d of VIEWS.filter((v) => v.id !== 'scf')) {
      const page = await newPage({ viewport: { width: w, height: h } });
      await page.goto(`${baseUrl}#${d.id}&present`);
      await waitReady(page);
      await idle(page, d);
      await checkPresent(page, assert, d, `${d.id} present ${w}×${h}`);
      if (d.id === 'ubb') {
        const file = `/tmp/present-${w}.png`;
        await page.screenshot({ path: file });
        copyFileSync(file, join(screenshotDir, `present-ubb-${w}.png`));
        // → steps, and the link the page rewrites keeps &present.
        const v = await value(page, d);
        await page.keyboard.press('ArrowRight');
        await waitValue(page, d, '=', v + 1);
        await page.waitForFunction(() => /^#ubb\/v1\/[A-Za-z0-9_-]+&present$/.test(location.hash), null, { timeout: 10_000 });
        // The rewritten link opens in present mode at the same step.
        const hash = await page.evaluate(() => location.hash);
        const stepped = await value(page, d);
        const again = await newPage({ viewport: { width: w, height: h } });
        await again.goto(`${baseUrl}${hash}`);
        await waitReady(again);
        await idle(again, d);
        assert.equal(await value(again, d), stepped, 'the present link restores the step');
        await checkPresent(again, assert, d, `ubb present link ${w}×${h}`);
        await again.close();
        // Space plays, k pauses.
        await page.keyboard.press('Space');
        assert.ok(await playing(page, d), 'ubb present: Space plays');
        await page.keyboard.press('k');
        assert.ok(!(await playing(page, d)), 'ubb present: k pauses');
      }
      if (d.recompute) {
        // ← steps back (a run), and the link the page rewrites opens at that step, in present mode.
        const v = await value(page, d);
        await page.keyboard.press('ArrowLeft');
        await waitValue(page, d, '=', v - 1);
        await idle(page, d);
        await checkPresent(page, assert, d, `${d.id} present ${w}×${h} after ←`);
        // The link of the step shown: rewritten once the step differs from the last one linked.
        let last = { hash: '', value: NaN };
        const linked = async (what) => {
          const shown = await value(page, d);
          await page.waitForFunction(([id, old]) => new RegExp(`^#${id}/v1/[A-Za-z0-9_-]+&present$`).test(location.hash)
            && location.hash !== old, [d.id, shown === last.value ? '' : last.hash], { timeout: 10_000 });
          const hash = await page.evaluate(() => location.hash);
          last = { hash, value: shown };
          const again = await newPage({ viewport: { width: w, height: h } });
          await again.goto(`${baseUrl}${hash}`);
          await waitReady(again);
          await idle(again, d);
          assert.equal(await value(again, d), await value(page, d), `${d.id} present: the link restores the step ${what}`);
          await again.close();
        };
        await linked('after ←');
        // Space plays, k pauses; paused, the link follows the step shown.
        await page.keyboard.press('Space');
        assert.ok(await playing(page, d), `${d.id} present: Space plays`);
        await page.keyboard.press('k');
        assert.ok(!(await playing(page, d)), `${d.id} present: k pauses`);
        await idle(page, d);
        await linked('after a pause');
      }
      await page.close();
    }
  }

  // SCF's time slider, and &panel= (one figure, or two side by side).
  {
    const d = VIEWS[0];
    const page = await newPage({ viewport: { width: 1024, height: 576 } });
    await page.goto(`${baseUrl}#scf&present`);
    await waitReady(page);
    await idle(page, d);
    await checkPresent(page, assert, d, 'scf present 1024×576');
    const v = await value(page, d);
    await page.keyboard.press('ArrowLeft');
    await waitValue(page, d, '=', v - 1);
    await page.close();
    const ubb = VIEWS[2];
    const p = await newPage({ viewport: { width: 1920, height: 1080 } });
    for (const [panel, figures] of [['ubbwidth', 1], ['ubbset,ubbwidth', 2]]) {
      if (figures === 1) {
        await p.goto(`${baseUrl}#ubb&present&panel=${panel}`);
        await waitReady(p);
      } else {
        // A new fragment while the animation loops (it never ends by itself): the view pauses
        // and shows what the fragment asks for.
        await p.check(anim(ubb, 'loop'));
        await p.click(anim(ubb, 'play'));
        await p.evaluate((x) => { location.hash = `#ubb&present&panel=${x}`; }, panel);
        await p.waitForFunction(() => document.body.dataset.ready === '1' && document.body.dataset.presentFigures === '2', null, { timeout: 60_000 });
        assert.ok(!(await playing(p, ubb)), 'the new route paused the loop');
      }
      await idle(p, ubb);
      await checkPresent(p, assert, ubb, `ubb &panel=${panel}`, { figures });
      assert.deepEqual(await p.$$eval('.present-fig', (fs) => fs.map((f) => f.dataset.panel)), panel.split(','));
    }
    await p.close();
  }

  // The embed code: copied, and the iframe it makes (960 × 540) shows the view in present mode.
  {
    const d = VIEWS[2];
    const page = await newPage({ viewport: { width: 1366, height: 900 }, permissions: ['clipboard-read', 'clipboard-write'] });
    await page.goto(`${baseUrl}#ubb`);
    await waitReady(page);
    await idle(page, d);
    await page.click('#ubb-section [data-act=embed]');
    await page.waitForFunction(() => /embed code/.test(document.querySelector('#ubb-section .share-status').textContent));
    const code = await page.evaluate(() => navigator.clipboard.readText());
    const m = code.match(/^<iframe src="([^"]+)" width="960" height="540" style="border:0" allowfullscreen><\/iframe>$/);
    assert.ok(m, `the embed code: ${code}`);
    assert.match(m[1], /#ubb\/v1\/[A-Za-z0-9_-]+&present$/);
    // Without a clipboard the code is shown, selected, in a read-only box.
    await page.evaluate(() => Object.defineProperty(navigator, 'clipboard', { value: undefined, configurable: true }));
    await page.click('#ubb-section [data-act=embed]');
    await page.waitForSelector('#ubb-section .embed-box textarea', { state: 'visible' });
    assert.equal(await page.$eval('#ubb-section .embed-box textarea', (t) => t.value), code, 'the code to copy by hand');
    assert.ok(await page.$eval('#ubb-section .embed-box textarea', (t) => t.readOnly), 'read-only');
    assert.match(await page.$eval('#ubb-section .share-status', (e) => e.textContent), /^the clipboard is not available here: copy the embed code/);
    // The snippet as pasted (960 × 540), and resized to the two ends of a 16:9 slide.
    for (const [w, h] of [[960, 540], [1024, 576], [1920, 1080]]) {
      const host = await newPage({ viewport: { width: w + 40, height: h + 40 } });
      const sized = code.replace('width="960" height="540"', `width="${w}" height="${h}"`);
      await host.setContent(`<!doctype html><body style="margin:0">${sized}</body>`);
      const frame = await (await host.waitForSelector('iframe')).contentFrame();
      await frame.waitForFunction(() => document.body && document.body.dataset.ready === '1', null, { timeout: 60_000 });
      await frame.waitForFunction(() => !document.body.dataset.ubbBusy, null, { timeout: 120_000 });
      assert.deepEqual(await frame.evaluate(() => [innerWidth, innerHeight]), [w, h], 'the iframe is the slide frame');
      await checkPresent(frame, assert, d, `ubb embedded ${w}×${h}`);
      await host.close();
    }
    await page.close();
  }
}
