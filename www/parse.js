// Text fields → numbers for the scenario. Errors are {field, message} like the core's, so the
// page shows them next to the field they name.

// "1 0; 0 1" or one row per line → [[1, 0], [0, 1]]; errors name the field like the core does.
export function parseMatrix(field, text) {
  const rows = text.split(/[;\n]/).map((r) => r.trim()).filter((r) => r !== '');
  if (rows.length === 0) throw { field, message: `${field} is empty: enter one row per line` };
  return rows.map((r, i) => r.split(/[\s,]+/).map((s) => {
    const v = Number(s);
    if (s === '' || !Number.isFinite(v)) throw { field, message: `${field} has “${s}” in row ${i + 1}, which is not a number` };
    return v;
  }));
}
export const matrixText = (m) => (Array.isArray(m) && Array.isArray(m[0]) && !Array.isArray(m[0][0])
  ? m.map((r) => r.map((v) => +v.toPrecision(6)).join(' ')).join('\n') : '');

export function wholeNumber(field, text) {
  const v = Number(text);
  if (text.trim() === '' || !Number.isSafeInteger(v) || v < 0) throw { field, message: `${field} must be a whole number ≥ 0` };
  return v;
}

export function parseVector(field, text) {
  const parts = text.split(/[\s,;]+/).filter((s) => s !== '');
  const v = parts.map(Number);
  if (v.length === 0 || v.some((x) => !Number.isFinite(x))) throw { field, message: `${field} must be numbers separated by spaces or commas` };
  return v;
}

// A finite number; an empty or non-numeric field is an error naming the field.
export function parseNumber(field, text) {
  const v = Number(text);
  if (String(text).trim() === '' || !Number.isFinite(v)) throw { field, message: `${field} must be a number` };
  return v;
}
