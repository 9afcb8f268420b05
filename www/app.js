// Bootstrap: load the wasm module, then hand the presets to the SCF vs KF panel, the LSCR panel,
// the GLLS panel, the uniform-innovation panel and the set-membership (ubb) panel. The page computes nothing itself: every number and every picture comes from
// ./pkg/confset.js.
import init, * as confset from './pkg/confset.js';
import { mountScf } from './scf.js';
import { mountLscr } from './lscr.js';
import { mountGlls } from './glls.js';
import { mountUniform } from './uniform.js';
import { mountUbb } from './ubb.js';

// No form submits (Enter in a field must not reload the page); a listener, not an inline
// handler, so the page runs under a strict Content-Security-Policy.
for (const form of document.querySelectorAll('form')) form.addEventListener('submit', (e) => e.preventDefault());

async function main() {
  const status = document.getElementById('t-run');
  try {
    await init();
  } catch (e) {
    status.textContent = `The WebAssembly module could not be loaded: ${e.message}`;
    status.classList.add('bad');
    return;
  }
  // The module's exports, for the browser tests' timings (page.evaluate) and the console.
  window.confset = confset;
  const list = JSON.parse(confset.presets());
  const method = (p) => p.scenario.method;
  await mountScf(document.getElementById('scf'), list.filter((p) => !['lscr', 'glls', 'uniform_lp', 'ubb'].includes(method(p))));
  await mountLscr(document.getElementById('lscr'), list.filter((p) => method(p) === 'lscr'));
  await mountGlls(document.getElementById('glls'), list.filter((p) => method(p) === 'glls'));
  await mountUniform(document.getElementById('uniform'), list.filter((p) => method(p) === 'uniform_lp'));
  await mountUbb(document.getElementById('ubb'), list.filter((p) => method(p) === 'ubb'));
  document.body.dataset.ready = '1';
}

main();
