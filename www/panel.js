// What every panel module shares with the shell: its preset menu and the small API the shell
// (router, share links, scenario import) drives it through.

// The preset menu: the core's presets, named for people (the core's label, the id in links and
// the CLI), then the panel's custom model if it has one. `add(p)` puts a scenario loaded from a
// file into the menu (replacing one of the same name) before the custom model.
export function presetMenu(select, presets, custom) {
  const all = custom ? [...presets, custom] : [...presets];
  const label = (p) => (p === custom ? 'custom model' : p.label || p.name);
  const fill = () => select.replaceChildren(...all.map((p) => Object.assign(new Option(label(p), p.name), { title: p.description || '' })));
  fill();
  return {
    all,
    add(p) {
      const i = all.findIndex((x) => x.name === p.name);
      if (i >= 0) all.splice(i, 1, p); else all.splice(custom ? all.length - 1 : all.length, 0, p);
      fill();
    },
  };
}

// The shell's handle on a mounted panel: its preset menu, how to add a loaded scenario, and the
// scenario it last ran.
export const panelApi = (select, menu, scenario) => ({ presetSelect: select, addPreset: menu.add, scenario });

// On the user's data (`data` instead of `simulate`) the simulation's controls have nothing to
// set: they are disabled, and the panel's note says that the run has no truth.
export function dataMode(root, scenario) {
  const onData = !scenario.simulate && !!scenario.data;
  for (const el of root.querySelectorAll('form [data-field^="simulate."]')) el.disabled = onData;
  let note = root.querySelector('.data-note');
  if (!note) {
    note = Object.assign(document.createElement('p'), { className: 'data-note' });
    root.querySelector('form').prepend(note);
  }
  const y = scenario.data?.y || [];
  note.textContent = onData
    ? `Your data: ${y.length} measurement${y.length === 1 ? '' : 's'} of ${y[0]?.length ?? 0} output${y[0]?.length === 1 ? '' : 's'}`
      + `${scenario.data.u?.length ? ` with inputs u (${scenario.data.u[0].length} per row)` : ''}. No simulation, so no true state and no verdict against one.`
    : '';
  note.hidden = !onData;
}
