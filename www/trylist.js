// The "Things to try" list of a panel (its prompts: tries.js), under the preset menu and its
// description. It follows the menu: the prompts of the preset shown, none (the list hidden) for
// the custom model, a loaded file or the user's data, where they would not hold. "Try it" starts
// again from the preset (the menu's own change event, as "Reset to preset" does) and sets the
// prompt's controls as a link does (share.js: input and change events on each control, one
// run), so the panel reruns exactly as if the user had moved them. The list holds no numbers
// and judges nothing: what the prompt promises is read from the panel's own figures and numbers.
import { TRIES } from './tries.js';
import { restoreFields } from './share.js';

export function mountTries(root, select, busyKey) {
  const box = document.createElement('details');
  box.className = 'tries';
  // Open beside the figures; folded where the controls stack above them (a phone), so the
  // controls stay near the top.
  box.open = !window.matchMedia('(max-width: 860px)').matches;
  box.innerHTML = '<summary>Things to try <span class="try-count"></span> <span class="hint">each starts from the preset</span></summary>'
    + '<ol></ol><p class="hint try-status" role="status" aria-live="polite"></p>';
  const list = box.querySelector('ol');
  const status = box.querySelector('.try-status');
  // Under the preset's description, at the top of the controls.
  const desc = select.closest('form').querySelector('.desc');
  (desc || select.closest('label')).after(box);

  let running = false;
  async function tryIt(preset, t, button) {
    if (running) return;
    running = true;
    box.dataset.running = '1';
    button.setAttribute('aria-busy', 'true');
    try {
      select.value = preset;
      select.dispatchEvent(new Event('change', { bubbles: true }));
      const fields = Object.fromEntries(Object.entries(t.apply).map(([id, v]) => [id, String(v)]));
      await restoreFields(root, fields, busyKey);
      for (const li of list.children) li.classList.toggle('tried', li.dataset.try === t.id);
      status.textContent = `Tried: ${t.name}. ${t.watch}`;
    } finally {
      button.removeAttribute('aria-busy');
      delete box.dataset.running;
      running = false;
    }
  }

  function render() {
    const preset = select.value;
    const tries = TRIES[preset] || [];
    box.hidden = tries.length === 0;
    if (box.dataset.preset === preset) return;
    box.dataset.preset = preset;
    status.textContent = '';
    box.querySelector('.try-count').textContent = `(${tries.length})`;
    list.replaceChildren(...tries.map((t) => {
      const li = document.createElement('li');
      li.dataset.try = t.id;
      const p = document.createElement('p');
      const move = Object.assign(document.createElement('span'), { className: 'move', textContent: t.move });
      const watch = Object.assign(document.createElement('span'), { className: 'watch', textContent: t.watch });
      p.append(move, ' ', watch);
      const b = Object.assign(document.createElement('button'), { type: 'button', className: 'try', textContent: 'Try it' });
      b.setAttribute('aria-label', `Try: ${t.name}`);
      b.addEventListener('click', () => tryIt(preset, t, b));
      li.append(p, b);
      return li;
    }));
  }
  // The shell and the panel choose presets through the menu's change event (the menu, a link,
  // "Reset to preset", a loaded file): the list follows it.
  select.addEventListener('change', render);
  render();
  return { render };
}
