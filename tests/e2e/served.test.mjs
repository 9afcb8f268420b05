// What a visitor's browser is sent: the module precompressed (brotli, else gzip) with
// Content-Encoding and Content-Type application/wasm, byte for byte the file .ci/build wrote,
// and the whole of it to a client that accepts neither; the page's text files as brotli. Also the bytes a first visit of each
// view moves over the wire (printed, not asserted: a size target is measured, README).
import { get } from 'node:http';
import { readFileSync } from 'node:fs';
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';

const pkg = join(dirname(fileURLToPath(import.meta.url)), '..', '..', 'www', 'pkg');

// The raw response (no decoding): status, headers, body bytes.
function fetchRaw(url, acceptEncoding) {
  return new Promise((resolve, reject) => {
    get(url, { headers: { 'Accept-Encoding': acceptEncoding } }, (res) => {
      const chunks = [];
      res.on('data', (c) => chunks.push(c));
      res.on('end', () => resolve({ status: res.statusCode, headers: res.headers, body: Buffer.concat(chunks) }));
    }).on('error', reject);
  });
}

export default async function served({ baseUrl, newPage, waitReady, assert }) {
  const url = `${baseUrl}pkg/confset_bg.wasm`;
  for (const [accept, encoding, file] of [
    ['gzip, deflate, br, zstd', 'br', 'confset_bg.wasm.br'],
    ['gzip', 'gzip', 'confset_bg.wasm.gz'],
    ['identity', undefined, 'confset_bg.wasm'],
  ]) {
    const r = await fetchRaw(url, accept);
    assert.equal(r.status, 200, `${url} with Accept-Encoding: ${accept}`);
    assert.equal(r.headers['content-type'], 'application/wasm', `Content-Type with Accept-Encoding: ${accept}`);
    assert.equal(r.headers['content-encoding'], encoding, `Content-Encoding with Accept-Encoding: ${accept}`);
    assert.ok(r.body.equals(readFileSync(join(pkg, file))), `the body sent for Accept-Encoding: ${accept} is not ${file}`);
  }

  // The page's scripts, styles and pages are sent precompressed too (.ci/build writes their
  // .br/.gz), with their own Content-Type, and decode to the file as written; so is the vendored
  // ZIP writer (.ci/build copies it to www/vendor/).
  const www = join(pkg, '..');
  for (const [path, type] of [['', 'text/html'], ['app.js', 'application/javascript'],
    ['style.css', 'text/css'], ['views/ubb.html', 'text/html'], ['pkg/confset.js', 'application/javascript'],
    ['vendor/fflate.js', 'application/javascript']]) {
    const r = await fetchRaw(baseUrl + path, 'gzip, deflate, br');
    assert.equal(r.status, 200, `/${path}`);
    assert.equal(r.headers['content-encoding'], 'br', `/${path} is sent as brotli`);
    assert.ok(String(r.headers['content-type']).startsWith(type), `/${path}: Content-Type ${r.headers['content-type']}`);
    const { brotliDecompressSync } = await import('node:zlib');
    assert.ok(brotliDecompressSync(r.body).equals(readFileSync(join(www, path || 'index.html'))),
      `/${path}: the brotli body decodes to the file as written (a stale .br?)`);
  }

  // Bytes over the wire on a first visit of each view, from a fresh context (no cache), counted
  // by the browser context: its requests include the workers' (a CDP session of the page sees
  // only the page's own, which hid the worker's second copy of the module). The module is fetched
  // once per visit (wasm.js compiles it once and sends it compiled to the workers).
  const lines = [];
  for (const route of ['', '#scf', '#lscr', '#glls', '#uniform', '#ubb', '#compare']) {
    const page = await newPage({ viewport: { width: 1280, height: 900 } });
    const sizes = [];
    const wasm = [];
    // A request that finishes after the count (a late thumbnail, a lazy import) must not reject
    // unhandled when the page closes: that crashed the whole harness once (TargetClosedError).
    const onFinished = (r) => {
      sizes.push(r.sizes().then((z) => z.responseBodySize + z.responseHeadersSize, () => 0));
      if (new URL(r.url()).pathname.endsWith('.wasm')) wasm.push(new URL(r.url()).pathname);
    };
    page.context().on('requestfinished', onFinished);
    await page.goto(baseUrl + route);
    await waitReady(page);
    const bytes = (await Promise.all(sizes)).reduce((a, b) => a + b, 0);
    assert.ok(wasm.length <= 1, `${route || 'the landing view'}: the module is fetched once, not by every thread (${wasm.join(', ')})`);
    lines.push(`${route || 'landing'} ${(bytes / 1024).toFixed(0)} KiB`);
    page.context().off('requestfinished', onFinished);
    await page.close();
  }
  console.log(`    [page bytes] a first visit moves (encoded, workers included): ${lines.join(', ')}`);
}
