// The page's one fetch and compile of the wasm module. The main thread fetches and compiles it
// once (WebAssembly.compileStreaming: compiled while it downloads) and instantiates it through
// wasm-bindgen's init; every compute worker (compute.js) is sent the compiled
// WebAssembly.Module in its first message and instantiates it with the same init
// (worker.js), so no worker fetches or compiles the module again. A first visit moves the
// module once, not once per thread (README, "Module size").
import init from './pkg/confset.js';

const WASM_URL = new URL('./pkg/confset_bg.wasm', import.meta.url);

let compiling = null;

// The compiled module (a Promise of WebAssembly.Module), fetched and compiled on the first call.
// A server that does not send application/wasm makes compileStreaming refuse: the bytes are
// then compiled whole. A failure is not kept: the next call tries again.
export function compiledModule() {
  compiling ??= (async () => {
    const response = fetch(WASM_URL);
    try {
      return await WebAssembly.compileStreaming(response);
    } catch (e) {
      const r = await response;
      if (!r.ok) throw new Error(`${WASM_URL.pathname}: HTTP ${r.status}`);
      if (r.headers.get('Content-Type') === 'application/wasm') throw e;
      return WebAssembly.compile(await (await fetch(WASM_URL)).arrayBuffer());
    }
  })();
  compiling.catch(() => { compiling = null; });
  return compiling;
}

// The main thread's instance: the compiled module instantiated by wasm-bindgen's init.
export async function load() {
  await init({ module_or_path: await compiledModule() });
}

// A compute worker (worker.js) sent the compiled module as its first message: {module}, or
// {moduleError} when the page could not compile it (the worker's jobs then fail with it).
export function startWorker(url) {
  const w = new Worker(url, { type: 'module' });
  compiledModule().then((module) => w.postMessage({ module }), (e) => w.postMessage({ moduleError: `${e?.message || e}` }));
  return w;
}
