// A researcher's record in the data box (issue 39): a header whose names are not the model's
// (year,flow,rain) is refused with the core's words and a column picker beside it (one labelled
// select per output, defaulting past the time column); the choice reruns the core's reader, and
// the preview shows the record's time. A record with a gap is read with its gap in place ("—" in
// the preview, and the method's refusal names the row and its time).

const status = (page, id) => page.$eval(`#${id}-section .share-status`, (e) => e.textContent);
const dataErr = (page) => page.$eval('#lscr-section .data-err', (e) => e.textContent);

export default async function records({ newPage, baseUrl, waitReady, assert }) {
  const page = await newPage({ viewport: { width: 1366, height: 900 } });
  await page.goto(`${baseUrl}#lscr`);
  await waitReady(page);
  const paste = async (text) => {
    if (await page.isHidden('#lscr-section .data-box')) await page.click('#lscr-section [data-act=paste]');
    await page.fill('#lscr-section [data-act=csv-text]', text);
    await page.$eval('#lscr-section .share-status', (e) => { e.textContent = ''; });
    await page.$eval('#lscr-section .data-err', (e) => { e.textContent = ''; });
    await page.click('#lscr-section [data-act=use-data]');
  };
  const settled = () => page.waitForFunction(() => !document.body.dataset.lscrBusy
    && (document.querySelector('#lscr-section .share-status').textContent || document.querySelector('#lscr-section .data-err').textContent));

  // Three columns besides none the model names: refused, the header listed, a picker offered.
  const rows = Array.from({ length: 40 }, (_, i) => `${1871 + i},${(Math.sin(i / 3) + 0.01 * i).toFixed(4)},${(0.5 * Math.cos(i / 2)).toFixed(4)}`);
  await paste(`year,flow,rain\n${rows.join('\n')}\n`);
  await settled();
  assert.match(await dataErr(page), /'flow' is not a column name: .*the header's columns are 'year', 'flow', 'rain'.*column picker \(page\)/);
  const picker = '#lscr-section fieldset.column-picker';
  assert.equal(await page.$$eval(`${picker} select`, (s) => s.length), 1, 'one select: LSCR has one output');
  assert.equal(await page.$eval(`${picker} label`, (l) => l.textContent.trim().split(/\s/)[0]), 'y1', 'the select is labelled y1');
  assert.equal(await page.$eval(`${picker} select`, (s) => s.selectedOptions[0].textContent), 'flow', 'the default skips the time column');
  await page.selectOption(`${picker} select`, { label: 'rain' });
  // The old refusal and status cleared first, so `settled` waits for this run's answer.
  await page.$eval('#lscr-section .share-status', (e) => { e.textContent = ''; });
  await page.$eval('#lscr-section .data-err', (e) => { e.textContent = ''; });
  await page.click(`${picker} button`);
  await settled();
  assert.equal(await dataErr(page), '', 'the chosen column is read and run');
  assert.match(await status(page, 'lscr'), /^running on pasted: 40 rows$/);
  assert.deepEqual(await page.$$eval('#lscr-section table.preview thead th', (t) => t.map((e) => e.textContent)), ['row', 'time', 'y1']);
  assert.deepEqual(await page.$$eval('#lscr-section table.preview tbody tr:first-child td', (t) => t.map((e) => e.textContent)), ['1871', '0.5']);
  assert.equal(await page.$eval(`${picker} select`, (s) => s.selectedOptions[0].textContent), 'rain', 'the choice stays on offer');

  // One value column beside the year: read as y1; a gap keeps its row and is named by LSCR's
  // refusal with its time; the preview shows it as "—"; no picker (nothing to choose).
  const nile = rows.map((r, i) => { const [y, f] = r.split(','); return i === 2 ? `${y},` : `${y},${f}`; });
  await paste(`year,volume\n${nile.join('\n')}\n`);
  await settled();
  assert.match(await dataErr(page), /^pasted: 40 rows read, but the method refused them: .*row 3 \(t = 3, time 1873\)/);
  assert.equal(await page.$eval('#lscr-section table.preview tbody tr:nth-child(3) td:last-child', (e) => e.textContent), '—');
  assert.equal(await page.$$eval(picker, (p) => p.length), 0, 'no picker for a file read by its own names');
  await page.close();
}
