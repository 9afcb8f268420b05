// Issue 29's newcomer defects in links and scenario files, each with its regression check:
// a link naming another view's preset or carrying another view's scenario opens in that view
// (it used to say the preset "does not exist", or throw "Cannot set properties of undefined");
// damaged link tokens are said in words, never in the browser's texts ("Failed to fetch",
// "Failed to execute 'atob'", "Unexpected token"); a scenario file that is not a JSON object
// ([1,2,3]) or that the core refuses is said next to the toolbar, and no panel takes it; own
// data the method refuses is said by the data box; "Reset to preset" drops measured data.
import { readFile } from 'node:fs/promises';
import { downloadFigure } from './helpers.mjs';

const BROWSER_TEXT = /Failed to|atob|Unexpected token|Cannot (read|set) properties|undefined|null|JSON\.parse/;

const status = (page, id) => page.$eval(`#${id}-section .share-status`, (e) => e.textContent);
const banner = (page, id) => page.$eval(`#${id}-section .banner`, (e) => (e.hidden ? '' : e.textContent));

export default async function newcomer(env) {
  const { newPage, baseUrl, waitReady, assert } = env;
  // Each link in a fresh page, as a visitor opens it.
  let page = null;
  const open = async (fragment) => {
    if (page) await page.close();
    page = await newPage({ viewport: { width: 1366, height: 900 } });
    await page.goto(`${baseUrl}${fragment}`);
    await waitReady(page);
  };

  // Another view's preset: opened in its own view, and said.
  await open('#ubb/preset/scf-robots');
  assert.equal(await page.evaluate(() => document.body.dataset.route), 'scf', '#ubb/preset/scf-robots opens SCF');
  assert.match(await page.evaluate(() => location.hash), /^#scf\//, 'the address names the view it opened in');
  assert.equal(await page.$eval('#preset', (s) => s.value), 'scf-robots');
  assert.match(await status(page, 'scf'), /this link is of the SCF vs KF view, not the Set-membership|this link is of the SCF vs KF view/);
  assert.equal(await banner(page, 'scf'), '', 'no error banner');

  // A ubb link carrying an SCF scenario (a loaded file's state): opened in SCF.
  const token = await page.evaluate(async () => {
    const { encodeState } = await import('./share.js');
    const scenario = JSON.parse(window.confset.presets()).find((p) => p.name === 'scf-scalar').scenario;
    return encodeState({ preset: 'file:mine.json', fields: {}, scenario });
  });
  await open(`#ubb/v1/${token}`);
  assert.equal(await page.evaluate(() => document.body.dataset.route), 'scf', 'a state with an SCF scenario opens SCF');
  assert.doesNotMatch(`${await banner(page, 'scf')} ${await status(page, 'scf')}`, BROWSER_TEXT);
  const shown = await page.evaluate(() => [location.hash.slice(0, 12), document.querySelector('#preset').value, document.querySelector('#scf-section .banner').textContent, document.querySelector('#scf-section .share-status').textContent]);
  assert.match(shown[1], /^file:mine\.json/, JSON.stringify(shown));

  // Damaged tokens: the default scenario, and why, in words.
  const deflatedText = await page.evaluate(async () => {
    const out = new Blob([new TextEncoder().encode('not json at all')]).stream().pipeThrough(new CompressionStream('deflate-raw'));
    const b = new Uint8Array(await new Response(out).arrayBuffer());
    return btoa(String.fromCharCode(...b)).replace(/\+/g, '-').replace(/\//g, '_').replace(/=+$/, '');
  });
  for (const [what, t] of [['bad characters', 'abc$def'], ['not base64 (length 1 mod 4)', 'A'], ['does not unpack', 'AAAAAAAA'],
    ['cut in half', token.slice(0, Math.floor(token.length / 2))], ['unpacks to no JSON', deflatedText]]) {
    await open(`#ubb/v1/${t}`);
    const b = await banner(page, 'ubb');
    assert.match(b, /^This link could not be read: its data are damaged: .+\. The panel shows its default scenario instead\.$/, `${what}: ${b}`);
    assert.doesNotMatch(b, BROWSER_TEXT, `${what}: words, not the browser's text`);
  }

  // Scenario files that are not scenarios: said, and no panel takes them.
  await open('#ubb');
  // Screen readers: a figure is named by what it shows (not "pointer over the plot … SVG PNG");
  // the first Tab reaches a skip link that moves the focus to the view, past the menu.
  const names = await page.$$eval('#ubb figure.card:not([hidden])', (fs) => fs.map((f) => [f.getAttribute('aria-label'), f.querySelector('canvas').getAttribute('aria-label')]));
  assert.ok(names.length >= 2, `ubb figures: ${names.length}`);
  for (const [fig, canvas] of names) {
    assert.ok(fig && canvas.startsWith(fig), `figure named by its picture: ${fig}`);
    assert.doesNotMatch(fig, /SVG|PNG|pointer|download/i);
  }
  assert.equal(await page.evaluate(() => document.querySelector('a[href], button, input, select, textarea').textContent), 'Skip to the view',
    'the skip link is the first thing the keyboard reaches');
  await page.focus('[data-skip]');
  await page.keyboard.press('Enter');
  assert.equal(await page.evaluate(() => document.activeElement.id), 'ubb-section', 'the skip link focuses the view');
  assert.match(await page.evaluate(() => location.hash), /^#ubb/, 'and does not route');
  for (const [name, body, want] of [
    ['list.json', '[1,2,3]', /^list\.json is not a scenario file: a scenario is a JSON object with "method" .+; this file holds a list$/],
    ['number.json', '42', /^number\.json is not a scenario file: .+this file holds a number$/],
    ['empty-scf.json', '{"method":"scf"}', /^empty-scf\.json is not a scenario this page can open: \S+/],
    ['ubb-nomodel.json', '{"method":"ubb","model":{"F":"x"}}', /^ubb-nomodel\.json is not a scenario this page can open: model/],
  ]) {
    await page.setInputFiles('#ubb-section [data-act=file]', { name, mimeType: 'application/json', buffer: Buffer.from(body) });
    await page.waitForFunction((id) => document.querySelector(`#${id}-section .share-status`).textContent.length > 0, 'ubb');
    const said = await status(page, 'ubb');
    assert.match(said, want, `${name}: ${said}`);
    assert.doesNotMatch(said.replace(name, ''), /Cannot|properties|undefined/, `${name}: words, not the browser's text`);
    assert.equal(await page.evaluate(() => document.body.dataset.route), 'ubb', `${name}: the view stays`);
    await page.$eval('#ubb-section .share-status', (e) => { e.textContent = ''; });
  }

  // A file's name is shown as it is: the descriptions' subscript rule (x_t → x<sub>t</sub>)
  // made "compare-uniform<sub>lp</sub>-t30.json" of it.
  {
    await open('#compare');
    await page.waitForFunction(() => !document.body.dataset.compareBusy);
    const name = 'compare-uniform_lp-t30.json';
    const body = await page.evaluate(() => {
      const { notes, ...scenario } = JSON.parse(window.confset.presets()).find((p) => p.name === 'compare-uniform').scenario;
      return JSON.stringify(scenario); // no notes: the description says where it comes from
    });
    await page.setInputFiles('#compare-section [data-act=file]', { name, mimeType: 'application/json', buffer: Buffer.from(body) });
    await page.waitForFunction(() => /loaded/.test(document.querySelector('#compare-section #c-preset')?.selectedOptions[0]?.textContent || ''));
    const desc = await page.$eval('#compare-section #c-preset-desc', (e) => [e.textContent, e.innerHTML]);
    assert.ok(desc[0].includes(name), `the description names the file as it is: ${desc[0]}`);
    assert.doesNotMatch(desc[1], /<sub>lp<\/sub>/, `no subscript in a file's name: ${desc[1]}`);
  }

  // Compare → "open in its panel" for every row, the uniform LP's included (it failed with
  // "uniform.xr must be numbers" and left uniform-paper's figures under a slider at t = 30).
  await open('#compare');
  await page.waitForFunction(() => !document.body.dataset.compareBusy);
  const rowsToOpen = await page.$$eval('#compare button.open-panel', (bs) => bs.map((b) => b.closest('tr').querySelector('th b').textContent));
  assert.ok(rowsToOpen.length >= 5, `rows with "open in its panel": ${rowsToOpen.join(', ')}`);
  for (let i = 0; i < rowsToOpen.length; i++) {
    await open('#compare');
    await page.waitForFunction(() => !document.body.dataset.compareBusy);
    await page.$$eval('#compare button.open-panel', (bs, k) => bs[k].click(), i);
    await page.waitForFunction(() => {
      const v = document.querySelector('main > .view:not([hidden])');
      return v && v.id !== 'compare-section' && /\S/.test(v.querySelector('.share-status')?.textContent || '')
        && !Object.keys(document.body.dataset).some((k) => /Busy$|^busy$/.test(k));
    }, null, { timeout: 60_000 });
    const route = await page.evaluate(() => document.querySelector('main > .view:not([hidden])').id.replace(/-section$/, ''));
    const said = await page.evaluate((r) => [...document.querySelectorAll(`#${r}-section .err, #${r}-section .banner:not([hidden])`)]
      .map((e) => e.textContent).filter(Boolean), route);
    assert.deepEqual(said, [], `compare → ${rowsToOpen[i]} opens in #${route} without an error`);
    assert.match(await status(page, route), /^loaded /, `${rowsToOpen[i]}: loaded`);
    if (route === 'uniform') assert.equal(await page.$eval('#u-time', (r) => r.value), '30', 'the uniform view at the compared time');
  }

  // A state placed by a click under non-Gaussian noise survives the share link (x̄ "1.086 0.451"
  // came back as "0 0").
  await open('#compare');
  await page.waitForFunction(() => !document.body.dataset.compareBusy);
  await page.selectOption('#c-noise', 'uniform');
  await page.waitForFunction(() => !document.body.dataset.compareBusy);
  const before = await page.$eval('#c-xbar', (i) => i.value);
  const box = await (await page.$('#fig-compare canvas')).boundingBox();
  await page.mouse.click(box.x + box.width * 0.45, box.y + box.height * 0.4);
  await page.waitForFunction((b) => document.querySelector('#c-xbar').value !== b && !document.body.dataset.compareBusy, before);
  const placed = await page.$eval('#c-xbar', (i) => i.value);
  assert.match(placed, /^-?\d.* -?\d/, `a click places x̄ (${placed})`);
  // The address follows the controls (debounced): wait until it holds the placed state.
  // (A polled evaluate: waitForFunction takes an async predicate's Promise for a true value.)
  let link = null;
  for (let tries = 0; tries < 300 && !link; tries++) {
    link = await page.evaluate(async (x) => {
      const h = location.hash;
      if (!h.startsWith('#compare/v1/')) return null;
      const r = await (await import('./share.js')).parseFragment(h);
      return r.state?.fields?.['c-xbar'] === x ? h : null;
    }, placed);
    if (!link) await page.waitForTimeout(100);
  }
  assert.ok(link, `the address holds the placed state ${placed}`);
  await open(link);
  await page.waitForFunction(() => !document.body.dataset.compareBusy);
  const got = await page.evaluate(() => [document.querySelector('#c-noise').value, document.querySelector('#c-xbar').value, document.querySelector('#c-fix').checked, document.querySelector('#compare-section .banner').textContent, document.querySelector('#compare-section .share-status').textContent, [...document.querySelectorAll('#compare .err')].map((e) => e.textContent).join('|'), location.hash === '' ]);
  assert.equal(got[0], 'uniform', JSON.stringify(got));
  assert.equal(await page.$eval('#c-xbar', (i) => i.value), placed, 'the link keeps the clicked state');

  // The ubb custom model runs by default (it was refused: "ubb.window must be given", with no
  // window control on the page); emptying its window says why next to the window's box.
  await open('#ubb');
  await page.selectOption('#b-preset', 'custom');
  await page.waitForFunction(() => !document.body.dataset.ubbBusy);
  const errs = await page.$$eval('#ubb .err', (es) => es.map((e) => e.textContent).filter(Boolean));
  assert.deepEqual(errs, [], `the custom model runs: ${errs.join(' | ')}`);
  assert.equal(await page.$eval('#b-window', (i) => i.value), '20');
  await page.fill('#b-window', '');
  await page.waitForFunction(() => !document.body.dataset.ubbBusy && document.querySelector('#ubb .err[data-for="ubb.window"]').textContent);
  assert.match(await page.$eval('#ubb .err[data-for="ubb.window"]', (e) => e.textContent), /^ubb\.window must be given: Theorem 5/);
  await page.fill('#b-window', '12');
  await page.waitForFunction(() => !document.body.dataset.ubbBusy && !document.querySelector('#ubb .err[data-for="ubb.window"]').textContent);
  assert.match(await page.$eval('#ubb .numbers', (e) => e.textContent), /12 steps/, 'the window in use is the one typed');

  // Own data the method refuses (3 rows: LSCR needs 2^t ≥ M strings): said by the data, not
  // "running on …" with the refusal far below. Then data it takes, and "Reset to preset" drops
  // them: the preset they were run with, its simulation.
  await open('#lscr');
  const useData = async (text) => {
    if (await page.isHidden('#lscr-section .data-box')) await page.click('#lscr-section [data-act=paste]');
    await page.fill('#lscr-section [data-act=csv-text]', text);
    await page.click('#lscr-section [data-act=use-data]');
    await page.waitForFunction(() => !document.body.dataset.lscrBusy && document.querySelector('#lscr-section .share-status').textContent);
  };
  await useData('0.1\n0.2\n0.3');
  const refused = await page.$eval('#lscr-section .data-err', (e) => e.textContent);
  assert.match(refused, /^pasted: 3 rows read, but the method refused them: \S+/, refused);
  assert.match(await status(page, 'lscr'), /^pasted was refused by the method/);
  const rows = Array.from({ length: 40 }, (_, i) => (Math.sin(i / 3) + 0.01 * i).toFixed(4)).join('\n');
  await page.$eval('#lscr-section .share-status', (e) => { e.textContent = ''; });
  await useData(rows);
  assert.equal(await page.$eval('#lscr-section .data-err', (e) => e.textContent), '', 'data it takes: no refusal');
  assert.match(await status(page, 'lscr'), /^running on pasted: 40 rows$/);
  assert.match(await page.$eval('#l-preset', (s) => s.value), /^data:/);
  // The figure names the data, not the paper figure of the preset.
  const card = '#lscr figure.card:not([hidden])';
  const svg = await readFile(await (await downloadFigure(page, card, 'svg')).path(), 'utf8');
  assert.match(svg, /measured data: pasted/, 'the figure names the data');
  assert.doesNotMatch(svg, /paper|Fig\. \d/, 'and makes no claim about the paper');
  await page.click('#lscr-section [data-act=reset]');
  await page.waitForFunction(() => !document.body.dataset.lscrBusy);
  assert.equal(await page.$eval('#l-preset', (s) => s.value), 'lscr-predict', 'reset: the preset the data were run with');
  assert.ok(await page.isHidden('#lscr-section .data-box'), 'reset: the data box is put away');
  assert.match(await status(page, 'lscr'), /measured data are set aside/);
  await page.close();
  await phone(env);
}

// On a 390 px phone: the compare table's stacked values each name their column, and running
// the SCF robots study leaves the page no wider than the phone.
async function phone({ newPage, baseUrl, waitReady, assert, screenshotDir }) {
  const page = await newPage({ viewport: { width: 390, height: 844 }, deviceScaleFactor: 2, isMobile: true, hasTouch: true });
  await page.goto(`${baseUrl}#compare`);
  await waitReady(page);
  await page.waitForFunction(() => !document.body.dataset.compareBusy);
  const cells = await page.$$eval('#compare .compare-table tbody td', (tds) => tds.map((td) => getComputedStyle(td, '::before').content));
  assert.ok(cells.length >= 5 * 5, `compare table cells: ${cells.length}`);
  for (const c of cells) assert.match(c, /^".+: "$/, `a stacked value names its column (${c})`);
  const cell = await page.$eval('#compare .compare-table tbody td', (td) => td.getAttribute('data-label'));
  assert.equal(cell, 'promises');
  await page.$eval('#compare .compare-table', (t) => t.scrollIntoView());
  await page.screenshot({ path: `${screenshotDir}/phone-compare-table.png` });
  assert.ok(await page.evaluate(() => document.documentElement.scrollWidth <= innerWidth), 'compare: no sideways scroll');

  await page.goto(`${baseUrl}#scf/preset/scf-robots`);
  await page.reload();
  await waitReady(page);
  await page.waitForFunction(() => !document.body.dataset.busy);
  await page.click('#mc-go');
  await page.waitForFunction(() => !document.querySelector('#mc-cancel').disabled || /runs/.test(document.querySelector('#mc-status').textContent), null, { timeout: 60_000 });
  await page.waitForFunction(() => document.querySelector('#mc-cancel').disabled && document.querySelector('#mc-kf-in').textContent !== '–', null, { timeout: 120_000 });
  const wide = await page.evaluate(() => {
    const over = [...document.querySelectorAll('#scf-section *')].filter((e) => e.getBoundingClientRect().right > innerWidth + 0.5 && e.offsetParent)
      .slice(0, 3).map((e) => `${e.tagName.toLowerCase()}#${e.id}.${e.className}`);
    return [document.documentElement.scrollWidth, innerWidth, over];
  });
  assert.ok(wide[0] <= wide[1], `after the SCF robots study the page is ${wide[0]} px wide in a ${wide[1]} px phone (${wide[2].join(', ')})`);
  await page.close();
}
