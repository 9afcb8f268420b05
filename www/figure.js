import { methodPanels } from './pkg/confset.js';
import { fmtPointer as fmt } from './format.js';
import { FramesCancelled } from './cursor.js';

// One figure card: a canvas whose backing store is CSS size × devicePixelRatio, drawn by the wasm
// Session; the cursor's position in chart units (from the returned Frame); SVG/PNG downloads
// (EXPORTS: SVG at a chosen size, PNG at 1×, 2×, 4×; in a view with an animation, a ZIP of its
// frames as PNG).

export function download(name, blob) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

const el = (tag, props = {}) => Object.assign(document.createElement(tag), props);

// A figure card's export choices: SVG text from the core at the figure's size or a slide's, and
// PNG at 1×, 2×, 4× the figure's size, rasterised by the browser from that SVG (the core's
// renderer, so a larger PNG is drawn sharper, not scaled up). `text` is the menu's, `says` ends
// the Download button's accessible name; `size` null: the figure's CSS size.
export const EXPORTS = [
  { value: 'svg', text: 'SVG', kind: 'svg', size: null, says: 'SVG at its size on the page' },
  { value: 'svg-1280x720', text: 'SVG 1280×720', kind: 'svg', size: [1280, 720], says: 'SVG, 1280 by 720' },
  { value: 'svg-1920x1080', text: 'SVG 1920×1080', kind: 'svg', size: [1920, 1080], says: 'SVG, 1920 by 1080' },
  { value: 'png-1', text: 'PNG 1×', kind: 'png', scale: 1, says: 'PNG at 1× size' },
  { value: 'png-2', text: 'PNG 2×', kind: 'png', scale: 2, says: 'PNG at 2× size' },
  { value: 'png-4', text: 'PNG 4×', kind: 'png', scale: 4, says: 'PNG at 4× size' },
  // Only in the menu of a figure whose view has an animation (Figure.animated).
  { value: 'frames', text: 'animation frames (ZIP of PNG)', kind: 'frames', animated: true,
    says: 'a ZIP of PNG images at its size on the page, one per step of the animation' },
];

// SVG text as a data: URL (the page's CSP allows data: images, not blob:): base64 of its UTF-8.
function svgDataUrl(svg) {
  const bytes = new TextEncoder().encode(svg);
  let bin = '';
  for (let i = 0; i < bytes.length; i += 0x8000) bin += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return `data:image/svg+xml;base64,${btoa(bin)}`;
}

// A PNG Blob of SVG text `w` × `h` drawn at `scale` × that size on a white ground.
export async function svgToPng(svg, w, h, scale) {
  const img = new Image();
  img.src = svgDataUrl(svg);
  await img.decode();
  const canvas = el('canvas', { width: Math.round(w * scale), height: Math.round(h * scale) });
  const g = canvas.getContext('2d');
  g.fillStyle = '#fff';
  g.fillRect(0, 0, canvas.width, canvas.height);
  g.drawImage(img, 0, 0, canvas.width, canvas.height);
  const blob = await new Promise((resolve) => canvas.toBlob(resolve, 'image/png'));
  if (!blob) throw new Error(`the browser could not make a ${canvas.width} × ${canvas.height} PNG`);
  return blob;
}

// A panel's figure cards, made from the core's list of its methods' figures (methodPanels): each
// <figure class="card" data-panel="…"> of the view is filled with its caption (cursor read-out,
// an export menu and its Download button), a canvas whose text alternative is the core's (plus
// the card's data-hint) and an error line. What the view put into a card is kept: [data-caption]
// children go into the caption, the others below the canvas. A figure of the method the view has
// no place for is added to its figure grid; a card naming no figure of the method is a mistake in
// the view.
export function figureCards(root, methods) {
  const panels = new Map(methods.flatMap((m) => JSON.parse(methodPanels(m))).map((f) => [f.panel, f.alt]));
  for (const card of root.querySelectorAll('figure.card[data-panel]')) {
    if (!panels.has(card.dataset.panel)) throw new Error(`figure "${card.dataset.panel}" is not a figure of ${methods.join('/')}`);
  }
  for (const [panel, alt] of panels) {
    let card = root.querySelector(`figure.card[data-panel="${panel}"]`);
    if (!card) {
      card = el('figure', { className: 'card', id: `fig-${panel}` });
      card.dataset.panel = panel;
      (root.querySelector('.figures .grid4') || root.querySelector('.figures')).append(card);
    }
    const kept = [...card.children];
    const dl = el('span', { className: 'dl' });
    const choice = el('select', { title: 'what the download holds' });
    choice.dataset.dlChoice = '';
    choice.setAttribute('aria-label', 'export format of this figure');
    for (const c of EXPORTS.filter((x) => !x.animated)) choice.append(el('option', { value: c.value, textContent: c.text }));
    const go = el('button', { type: 'button', textContent: 'Download' });
    go.dataset.dl = 'go';
    dl.append(choice, go);
    const caption = el('figcaption');
    caption.append(el('span', { className: 'cursor' }), ...kept.filter((k) => k.hasAttribute('data-caption')), dl);
    const canvas = el('canvas');
    canvas.dataset.panel = panel;
    canvas.setAttribute('role', 'img');
    canvas.setAttribute('aria-label', card.dataset.hint ? `${alt}; ${card.dataset.hint}` : alt);
    card.replaceChildren(caption, canvas, ...kept.filter((k) => !k.hasAttribute('data-caption')), el('p', { className: 'err fig-err' }));
    // The figure's accessible name is what it shows, not its caption's contents (the pointer
    // read-out and the export controls).
    card.setAttribute('aria-label', alt);
  }
}

// Hi-DPI: `redraw()` (a refit of the backing stores, no recompute) when the layout of a figure's
// canvas or the pixel ratio changes.
export function redrawOnResize(figures, redraw) {
  const ro = new ResizeObserver(() => redraw());
  for (const f of figures) ro.observe(f.canvas);
  const watchDpr = () => matchMedia(`(resolution: ${window.devicePixelRatio}dppx)`)
    .addEventListener('change', () => { redraw(); watchDpr(); }, { once: true });
  watchDpr();
}

// Draw every figure (at `time`, for the panels whose figures have one); the time it took (ms).
export function drawFigures(figures, time) {
  const t0 = performance.now();
  for (const f of figures) f.draw(time);
  return performance.now() - t0;
}


export class Figure {
  constructor(card, session, fileStem) {
    this.card = card;
    this.session = session;
    this.fileStem = fileStem; // () => "scf-robots-t36"
    this.canvas = card.querySelector('canvas');
    this.panel = this.canvas.dataset.panel;
    this.err = card.querySelector('.fig-err');
    this.cursor = card.querySelector('.cursor');
    this.frame = null;
    this.time = null;
    this.report = null; // the report drawn (the panel sets it): its record times for read-outs
    this.cssPerPx = 1; // CSS pixels per pixel of the frame (presentZoom)
    this.canvas.addEventListener('mousemove', (e) => this.showCursor(e.offsetX, e.offsetY));
    this.canvas.addEventListener('mouseleave', () => { this.cursor.textContent = ''; });
    this.choice = card.querySelector('[data-dl-choice]');
    this.go = card.querySelector('[data-dl=go]');
    const label = () => {
      const c = EXPORTS.find((x) => x.value === this.choice.value) || EXPORTS[0];
      this.go.setAttribute('aria-label', `download this figure as ${c.says}`);
    };
    label();
    this.label = label;
    this.choice.addEventListener('change', label);
    this.go.addEventListener('click', () => this.download(this.choice.value));
  }

  get visible() { return !this.card.hidden; }

  // The view has an animation: `frames(capture)` runs it step by step for an export (cursor.js's
  // animation().frames), and the export menu offers the ZIP of frames.
  animated(frames) {
    this.frames = frames;
    for (const c of EXPORTS.filter((x) => x.animated)) this.choice.append(el('option', { value: c.value, textContent: c.text }));
    this.label();
  }

  // Whether the card shows for a report whose useful figures (the core's) are `useful`.
  shownFor(useful) { return useful.includes(this.panel); }

  view() { return JSON.stringify({ panel: this.panel, time: this.time }); }

  // Size the backing store to the CSS box times the pixel ratio; true if it changed.
  fit() {
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(this.canvas.clientWidth * dpr));
    const h = Math.max(1, Math.round(this.canvas.clientHeight * dpr));
    if (this.canvas.width === w && this.canvas.height === h) return false;
    this.canvas.width = w;
    this.canvas.height = h;
    return true;
  }

  // Present mode (body.present): a figure filling a lecture hall's screen is drawn as one of
  // at least 640 × 480 CSS pixels scaled up (its type, lines and marks grow with it), at the full
  // resolution of the screen; elsewhere 1.
  presentZoom() {
    if (!document.body.classList.contains('present')) return 1;
    return Math.max(1, Math.min(this.canvas.clientWidth / 640, this.canvas.clientHeight / 480, 3));
  }

  draw(time) {
    this.time = time;
    if (!this.visible) return;
    // A card laid out at no size (hidden by present mode, or not yet in the layout) is drawn when
    // it gets one (redrawOnResize), not now at 1 × 1 with a "too small" message.
    if (!this.canvas.clientWidth || !this.canvas.clientHeight) return;
    this.fit();
    try {
      const zoom = this.presentZoom();
      this.cssPerPx = zoom;
      this.frame = JSON.parse(this.session.draw(this.canvas, this.view(), (window.devicePixelRatio || 1) * zoom));
      // Where the charts and the legends landed (CSS pixels), for the page's layout checks.
      const css = (r) => (zoom === 1 || !Array.isArray(r) ? r : r.map((v) => (typeof v === 'number' ? v * zoom : v)));
      this.canvas.dataset.layout = JSON.stringify({
        plots: [this.frame, ...(this.frame.more || [])].map((f) => css(f.plot_area)),
        legends: (this.frame.legends || []).map(css),
      });
      this.err.textContent = '';
    } catch (e) {
      this.frame = null;
      this.err.textContent = e.message;
    }
  }

  // The chart under (cssX, cssY) (CSS pixels, as offsetX/Y) and the point there in its axis units, by
  // a linear map of its plotting box to its ranges; null off the charts. A figure that stacks
  // charts (`stacked`) finds the others in frame.more.
  locate(cssX, cssY) {
    const f = this.frame;
    const px = cssX / this.cssPerPx, py = cssY / this.cssPerPx; // the frame's pixels (presentZoom)
    const chart = (this.stacked ? [f, ...(f.more || [])] : [f])
      .find(({ plot_area: [l, t, r, b] }) => px >= l && px <= r && py >= t && py <= b && r > l && b > t);
    if (!chart) return null;
    const [l, t, r, b] = chart.plot_area;
    const x = chart.x_range[0] + ((px - l) / (r - l)) * (chart.x_range[1] - chart.x_range[0]);
    const y = chart.y_range[1] - ((py - t) / (b - t)) * (chart.y_range[1] - chart.y_range[0]);
    return { chart, x, y };
  }

  showCursor(px, py) {
    if (!this.frame) return;
    const at = this.locate(px, py);
    this.cursor.textContent = at ? this.cursorText(at) : '';
  }

  // The read-out of a point (a panel's figure names its axes or rounds its values its own way).
  cursorText({ chart, x, y }) {
    return `${chart.x_label || 'x'} = ${fmt(x)}, ${chart.y_label || 'y'} = ${fmt(y)}`;
  }

  // The figure's CSS size (what it is drawn at on the page), at least the core's 16 pixels.
  size() {
    return [Math.max(16, Math.round(this.canvas.clientWidth)), Math.max(16, Math.round(this.canvas.clientHeight))];
  }

  // Download one of EXPORTS (its value); a failure is said in the card's error line.
  async download(value) {
    const c = EXPORTS.find((x) => x.value === value);
    if (!c) return;
    try {
      if (c.kind === 'svg') this.downloadSvg(c.size);
      else if (c.kind === 'frames') await this.downloadFrames();
      else await this.downloadPng(c.scale);
    } catch (e) {
      this.err.classList.remove('progress');
      this.err.textContent = e instanceof FramesCancelled ? 'The frame export stopped: the animation was played or moved, or another scenario chosen.'
        : `The download failed: ${(e && e.message) || e}`;
    }
  }

  // SVG from the core, `size` [w, h] (default: the figure's size on the page).
  downloadSvg(size = null) {
    const [w, h] = size || this.size();
    const svg = this.session.svg(this.view(), w, h);
    const tag = size ? `-${w}x${h}` : '';
    download(`${this.fileStem()}-${this.panel}${tag}.svg`, new Blob([svg], { type: 'image/svg+xml' }));
  }

  // The animation's frames (frames()): each step drawn as the animation shows it, as a PNG at the
  // figure's size on the page when the export started (rasterised from the core's SVG, as PNG 1×),
  // frame-0001.png … in step order in a ZIP (stored: PNG is compressed already). fflate, the ZIP
  // writer, is loaded only now (www/vendor/, copied by .ci/build). The progress is said in the
  // card's error line; the animation puts the slider back afterwards.
  async downloadFrames() {
    if (!this.frames || this.exporting) return;
    this.exporting = true;
    try {
      const { zipSync } = await import('./vendor/fflate.js').catch(() => {
        throw new Error('the ZIP writer (vendor/fflate.js) could not be loaded');
      });
      const [w, h] = this.size();
      const name = `${this.fileStem()}-${this.panel}-frames.zip`;
      const files = {};
      this.err.classList.add('progress');
      await this.frames(async (i, n) => {
        const svg = this.session.svg(this.view(), w, h); // now: the step drawn
        this.err.textContent = `Making the frames: frame ${i + 1} of ${n}`;
        const png = await svgToPng(svg, w, h, 1);
        files[`frame-${String(i + 1).padStart(4, '0')}.png`] = new Uint8Array(await png.arrayBuffer());
        // Let the page breathe between frames (input, paint).
        await new Promise((r) => setTimeout(r, 0));
      });
      this.err.textContent = `Zipping ${Object.keys(files).length} frames`;
      const zip = zipSync(files, { level: 0 });
      download(name, new Blob([zip], { type: 'application/zip' }));
      this.err.classList.remove('progress');
      this.err.textContent = '';
    } finally {
      this.exporting = false;
    }
  }

  // PNG at `scale` × the figure's size, rasterised from the core's SVG of it.
  async downloadPng(scale = 1) {
    const [w, h] = this.size();
    const name = `${this.fileStem()}-${this.panel}-${scale}x.png`;
    const svg = this.session.svg(this.view(), w, h);
    download(name, await svgToPng(svg, w, h, scale));
  }
}
