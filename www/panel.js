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

// The shell's handle on a mounted panel: its preset menu, and how to add a loaded scenario.
export const panelApi = (select, menu) => ({ presetSelect: select, addPreset: menu.add });
