// The page's one number format: every panel module writes the core's numbers with these. A value
// that is not a finite number is '–'; a magnitude of 10⁴ or more, or below 10⁻³ (not zero), is
// written 1.23e+4; the rest as the format says (`plain`). The formats differ only there: a panel
// shows as many digits as its numbers carry (LSCR's and SCF's regions on a fixed scale: 3
// decimals; GLLS's errors: 4 significant digits, trailing zeros kept so the columns line up).
// Each takes one argument only, so it can be handed to Array.map.
const scientific = (v) => Math.abs(v) >= 1e4 || (v !== 0 && Math.abs(v) < 1e-3);

export const numberFormat = (plain) => (v) => (typeof v !== 'number' || !Number.isFinite(v) ? '–'
  : scientific(v) ? v.toExponential(2) : plain(v));

// 4 significant digits without trailing zeros (0.5, 12.25, 0): the set-membership and
// uniform-innovation numbers.
export const fmt = numberFormat((v) => String(Number(v.toPrecision(4))));
// 3 significant digits without trailing zeros: the compare table.
export const fmt3 = numberFormat((v) => String(Number(v.toPrecision(3))));
// 4 significant digits with trailing zeros (0.5000), zero as 0: GLLS's numbers.
export const fmtPrecision = numberFormat((v) => (v === 0 ? '0' : v.toPrecision(4)));
// 4 significant digits with trailing zeros, zero too (0.000): a figure's pointer coordinates.
export const fmtPointer = numberFormat((v) => v.toPrecision(4));
// 3 decimals (0.500, 0.000): the LSCR and SCF numbers.
export const fmtFixed = numberFormat((v) => v.toFixed(3));

// A vector "(a, b, …)" with a format (default `fmt`); '–' for what is not an array.
export const vec = (v, format = fmt) => (Array.isArray(v) ? `(${v.map((x) => format(x)).join(', ')})` : '–');

// A count with thousands separators: 12,345.
export const int = (v) => v.toLocaleString('en-US');

// The read-out of a view's two noises (the scales of the true noise from its sliders, the
// assumed noise's names): the same, or what the filter assumes beside what the data have
// ("the filter assumes V, W; the data have 4 V, W"). Words only: the scales are the page's own.
export function noiseReadout([tv, tw], [v, w]) {
  if (tv === 1 && tw === 1) return `The data have the noise the filter assumes (${v}, ${w}).`;
  const k = (x) => (x === 1 ? '' : `${Number(x.toPrecision(3))} `);
  return `The filter assumes ${v}, ${w}; the data have ${k(tv)}${v}, ${k(tw)}${w}.`;
}
