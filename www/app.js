// Bootstrap: load the wasm module, then hand the presets to the SCF vs KF panel.
// The page computes nothing itself: every number and every picture comes from ./pkg/confset.js.
import init, { presets } from './pkg/confset.js';
import { mountScf } from './scf.js';

async function main() {
  const status = document.getElementById('t-run');
  try {
    await init();
  } catch (e) {
    status.textContent = `The WebAssembly module could not be loaded: ${e.message}`;
    status.classList.add('bad');
    return;
  }
  const list = JSON.parse(presets());
  await mountScf(document.getElementById('scf'), list);
  document.body.dataset.ready = '1';
}

main();
