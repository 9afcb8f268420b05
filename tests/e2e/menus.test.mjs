// Issue 28 on the page: no cut text in the controls. For every view at a 1366 × 900 desktop and a
// 390 × 844 phone, and every option of the view's preset menu chosen in turn:
//  * the preset menu shows the chosen name whole: its text, measured with a canvas in the
//    select's computed font, fits the select's content box (clientWidth less its padding and
//    the ~20 px of the arrow);
//  * so does every other select of the controls (their chosen option: "l∞ — per sample");
//  * no text or number box of the controls holds more than it shows (its value measured the same
//    way against its content box: the ubb-markov δ box);
//  * no label of the controls is cut (scrollWidth ≤ clientWidth);
//  * no button of the view wraps: its content is at most one line high (its line-height).
// Every failure is collected and reported together, with the view, size, preset and element.

const SIZES = [
  { name: 'desktop 1366×900', viewport: { width: 1366, height: 900 }, deviceScaleFactor: 1 },
  { name: 'phone 390×844', viewport: { width: 390, height: 844 }, deviceScaleFactor: 2, isMobile: true, hasTouch: true },
];
// The select's arrow takes about this many CSS pixels of its content box.
const ARROW = 20;

// No view computes: no body.dataset key holds a busy flag.
const idle = (page) => page.waitForFunction(
  () => !Object.keys(document.body.dataset).some((k) => /busy/i.test(k) && document.body.dataset[k]),
  null, { timeout: 120_000 });

// What is cut in the shown view's controls (and which buttons wrap), measured in the page.
const cutInView = (page, sectionId, arrow) => page.$eval(`#${sectionId}`, (section, arrow) => {
  const g = document.createElement('canvas').getContext('2d');
  const fontOf = (cs) => `${cs.fontStyle} ${cs.fontWeight} ${cs.fontSize} ${cs.fontFamily}`;
  const px = (v) => parseFloat(v) || 0;
  const name = (el) => el.id ? `#${el.id}` : `${el.tagName.toLowerCase()}${el.className ? `.${String(el.className).split(' ')[0]}` : ''} "${(el.textContent || '').trim().slice(0, 30)}"`;
  const contentWidth = (el, cs) => el.clientWidth - px(cs.paddingLeft) - px(cs.paddingRight);
  const shown = (el) => el.getClientRects().length > 0 && getComputedStyle(el).visibility !== 'hidden';
  const out = [];
  const controls = section.querySelector('.controls') || section.querySelector('form');
  for (const s of controls.querySelectorAll('select')) {
    if (!shown(s) || s.selectedIndex < 0) continue;
    const cs = getComputedStyle(s);
    g.font = fontOf(cs);
    const text = s.options[s.selectedIndex].text;
    const w = g.measureText(text).width;
    const box = contentWidth(s, cs) - arrow;
    if (w > box + 0.5) out.push(`select ${name(s)} shows "${text}": ${w.toFixed(0)} px of text in ${box.toFixed(0)} px`);
  }
  for (const i of controls.querySelectorAll('input[type=text], input[type=number], input:not([type])')) {
    if (!shown(i) || !i.value) continue;
    const cs = getComputedStyle(i);
    g.font = fontOf(cs);
    const w = g.measureText(i.value).width;
    const box = contentWidth(i, cs);
    if (w > box + 0.5 || i.scrollWidth > i.clientWidth) {
      out.push(`input ${name(i)} holds "${i.value}": ${w.toFixed(0)} px of text in ${box.toFixed(0)} px`);
    }
  }
  for (const l of controls.querySelectorAll('label')) {
    if (!shown(l)) continue;
    if (l.scrollWidth > l.clientWidth + 0.5) out.push(`label ${name(l)} is cut: ${l.scrollWidth} px of content in ${l.clientWidth} px`);
  }
  for (const b of section.querySelectorAll('button')) {
    if (!shown(b) || !b.textContent.trim()) continue;
    const cs = getComputedStyle(b);
    const line = cs.lineHeight === 'normal' ? 1.2 * px(cs.fontSize) : px(cs.lineHeight);
    const h = b.clientHeight - px(cs.paddingTop) - px(cs.paddingBottom);
    if (h > 1.5 * line) out.push(`button ${name(b)} wraps: ${h.toFixed(0)} px high, a line is ${line.toFixed(0)} px`);
  }
  return out;
}, arrow);

export default async function menus({ newPage, baseUrl, waitReady, assert, screenshotDir }) {
  const problems = [];
  let checked = 0;
  for (const size of SIZES) {
    const page = await newPage({ viewport: size.viewport, deviceScaleFactor: size.deviceScaleFactor, isMobile: size.isMobile, hasTouch: size.hasTouch });
    await page.goto(baseUrl);
    await waitReady(page);
    const views = await page.$$eval('nav.routes a[href^="#"]', (as) => as.map((a) => a.getAttribute('href').slice(1)));
    assert.ok(views.length >= 6, `the menu lists the views (${views.join(', ')})`);
    for (const id of views) {
      await page.evaluate((h) => { location.hash = h; }, id);
      const select = `#${id}-section .controls select[data-field=preset]`;
      await page.waitForSelector(select, { state: 'visible', timeout: 60_000 });
      await idle(page);
      const options = await page.$$eval(`${select} option`, (os) => os.map((o) => o.value));
      assert.ok(options.length >= 2, `${id}: its preset menu has options`);
      for (const value of options) {
        await page.selectOption(select, value);
        await idle(page);
        const where = `${size.name}, ${id}, ${value}`;
        for (const p of await cutInView(page, `${id}-section`, ARROW)) problems.push(`${where}: ${p}`);
        checked++;
      }
      if (size.deviceScaleFactor === 2 && id === 'glls') {
        await page.$eval(select, (e) => e.scrollIntoView({ block: 'start' }));
        await page.screenshot({ path: `${screenshotDir}/menus-phone-glls.png` });
      }
    }
    await page.close();
  }
  // Each size's every view and option, so a view lost from the menu shows here.
  assert.ok(checked >= 40, `only ${checked} menu choices checked`);
  const unique = [...new Set(problems)];
  assert.equal(unique.length, 0, `${unique.length} cut or wrapped controls:\n${unique.join('\n')}`);
}
