// The render request's fields, generated at build time from protocol/'s field table
// (schema_fields.js, the fields `lucent schema` prints): where each lives in the JSON,
// its flat alias (the key of GET /api/v1/render query parameters, reused for the page's
// URL hash), its type and its range. Client-side checks use it to refuse what the server
// would refuse, with the same field names in the messages.

// Types: int, num, bool, str, enum, vec3, range (two numbers), color (three in [0,1]).
// methods / primitives: where a field applies (protocol/request_scope.c); absent = everywhere.
// The server refuses a field with a value other than its default elsewhere.
// when: [path, value]: the field applies only while that field has that value
// (the direct method's opacity parameters, render/gl/frame_check.c refuses them otherwise).
import { SCHEMA } from './schema_fields.js';

// Top-level fields of a whole render request (POST /api/v1/render) that a session's
// params cannot change; sizes follow the server's limits (16..8192 by default).
const REQUEST_ONLY = new Set(['version', 'width', 'height', 'format', 'quality', 'dt', 'layers']);
const requestOnly = (f) => f.section === null && REQUEST_ONLY.has(f.name);
export const FIELDS = Object.freeze(SCHEMA.filter((f) => !requestOnly(f)));
export const REQUEST_TOP_FIELDS = Object.freeze(SCHEMA.filter(requestOnly));

// Stream settings of the WebSocket session (hello/params top level), not part of a render request.
export const STREAM_FIELDS = Object.freeze([
  { section: null, name: 'quality', alias: 'quality', type: 'int', min: 1, max: 100 },
  { section: null, name: 'interactiveQuality', alias: 'interactiveQuality', type: 'int', min: 1, max: 100 },
  { section: null, name: 'interactiveScale', alias: 'interactiveScale', type: 'num', min: 0.25, max: 1 },
]);

/** The sections a params message may carry besides the stream settings. */
export const UPDATE_SECTIONS = Object.freeze(['params', 'importance', 'color', 'style', 'lines', 'time']);

export const fieldPath = (f) => (f.section ? `${f.section}.${f.name}` : f.name);

const byPath = new Map([...FIELDS, ...STREAM_FIELDS].map((f) => [fieldPath(f), f]));
const byAlias = new Map([...FIELDS, ...STREAM_FIELDS].map((f) => [f.alias, f]));

/** The field at a dotted path ("params.q", "quality"), or undefined. */
export const fieldByPath = (path) => byPath.get(path);
/** The field with a flat alias ("q", "importanceRange"), or undefined. */
export const fieldByAlias = (alias) => byAlias.get(alias);

const isNum = (v) => typeof v === 'number' && Number.isFinite(v);
const g15 = (x) => String(Number(x.toPrecision(15)));
const utf8Length = (s) => new TextEncoder().encode(s).length;

/**
 * Checks one value against its field as protocol/request.c does. Returns null
 * when valid, else {code, reason} with the C code's error code ("bad_field",
 * "out_of_range") and reason text ("expected an integer", "9 is outside [1, 8]").
 */
export function checkField(f, v) {
  const bad = (reason) => ({ code: 'bad_field', reason });
  const range = (reason) => ({ code: 'out_of_range', reason });
  switch (f.type) {
    case 'int':
    case 'num': {
      if (!isNum(v) || (f.type === 'int' && !Number.isInteger(v)))
        return bad(f.type === 'int' ? 'expected an integer' : 'expected a number');
      const lo = f.min ?? -Infinity,
        hi = f.max ?? Infinity;
      const loBad = f.loOpen ? !(v > lo) : !(v >= lo);
      const hiBad = f.hiOpen ? !(v < hi) : !(v <= hi);
      if (loBad || hiBad) {
        if (hi === Infinity) return range(`${g15(v)} is not ${f.loOpen ? '>' : '>='} ${g15(lo)}`);
        return range(`${g15(v)} is outside ${f.loOpen ? '(' : '['}${g15(lo)}, ${g15(hi)}${f.hiOpen ? ')' : ']'}`);
      }
      return null;
    }
    case 'bool':
      return typeof v === 'boolean' ? null : bad('expected true or false');
    case 'str':
      if (typeof v !== 'string') return bad('expected a string');
      return f.maxLength !== undefined && utf8Length(v) > f.maxLength
        ? range(`longer than ${f.maxLength} bytes`)
        : null;
    case 'enum':
      return typeof v === 'string' && f.values.includes(v)
        ? null
        : bad(`expected one of ${f.values.map((x) => `"${x}"`).join(', ')}`);
    case 'vec3':
    case 'color':
      if (!(Array.isArray(v) && v.length === 3 && v.every(isNum))) return bad('expected an array of 3 numbers');
      if (f.type === 'color' && !v.every((x) => x >= 0 && x <= 1)) return range('components must be in [0, 1]');
      return null;
    case 'range':
      return Array.isArray(v) && v.length === 2 && v.every(isNum) ? null : bad('expected an array of 2 numbers');
    case 'curve':
    case 'ranges':
    case 'terms':
    case 'filters':
      return checkList(f, v);
    case 'layers':
      return checkLayers(f, v);
    case 'seed':
      return checkSeed(f, v);
    default:
      return bad('unknown type');
  }
}

/** surface.seed, streamlines.seeds (protocol/request_lists.c lc_proto_parse_seed): minItems (default 2)..maxItems
 * finite [x, y, z], no repeats in a row. */
function checkSeed(f, v) {
  const min = f.minItems ?? 2;
  if (!Array.isArray(v)) return { code: 'bad_field', reason: 'expected an array of [x, y, z] points' };
  if (v.length < min || v.length > f.maxItems)
    return { code: 'out_of_range', reason: `${min} to ${f.maxItems} points (got ${v.length})` };
  for (let i = 0; i < v.length; i++) {
    const p = v[i],
      at = `[${i}]`;
    if (!(Array.isArray(p) && p.length === 3 && p.every(isNum)))
      return { code: 'bad_field', reason: 'expected an array of 3 finite numbers', at };
    if (i > 0 && p.every((x, k) => x === v[i - 1][k]))
      return { code: 'bad_field', reason: 'repeats the point before it (a segment of length 0)', at };
  }
  return null;
}

const isObject = (v) => v !== null && typeof v === 'object' && !Array.isArray(v);
const isPair = (v) => Array.isArray(v) && v.length === 2 && v.every(isNum);
const OVERS = ['vertex', 'min', 'max', 'mean', 'first', 'last', 'change'];

/** One element of terms or filters, key by key as protocol/request_lists.c checks it. */
function checkElement(kind, o, at) {
  const err = (code, where, reason) => ({ code, reason, at: where });
  if (!isObject(o)) return err('bad_field', at, 'expected an object');
  let attribute = false,
    bounds = 0,
    weight = 1;
  for (const [k, v] of Object.entries(o)) {
    const here = `${at}.${k}`;
    if (k === 'attribute') {
      if (typeof v !== 'string') return err('bad_field', here, 'expected a string');
      if (!v.length) return err('bad_field', here, 'must name an attribute');
      if (utf8Length(v) > 63) return err('out_of_range', here, 'longer than 63 bytes');
      attribute = true;
    } else if (k === 'range') {
      if (!isPair(v)) return err('bad_field', here, 'expected an array of 2 numbers');
      if (kind === 'filters' && v[0] > v[1])
        return err('bad_field', here, `range [${g15(v[0])}, ${g15(v[1])}] is empty`);
      bounds |= 4;
    } else if (kind === 'terms' && k === 'weight') {
      if (!isNum(v)) return err('bad_field', here, 'expected a number');
      if (v < -1 || v > 1) return err('out_of_range', here, 'must be in [-1, 1]');
      weight = v;
    } else if (kind === 'terms' && k === 'invert') {
      if (typeof v !== 'boolean') return err('bad_field', here, 'expected true or false');
    } else if (kind === 'filters' && k === 'over') {
      if (!OVERS.includes(v)) return err('bad_field', here, `expected one of ${OVERS.join(', ')}`);
    } else if (kind === 'filters' && (k === 'gt' || k === 'lt')) {
      if (!isNum(v)) return err('bad_field', here, 'expected a number');
      bounds |= k === 'gt' ? 1 : 2;
    } else return err('unknown_field', here, 'unknown field');
  }
  if (!attribute)
    return err('missing_field', `${at}.attribute`, `every ${kind === 'terms' ? 'term' : 'filter'} names an attribute`);
  if (kind === 'filters' && (!bounds || (bounds & 4 && bounds & 3)))
    return err('bad_field', at, 'give "gt" and/or "lt", or "range"');
  return { weight };
}

/** terms, filters and curves (protocol/request_lists.c); a problem's "at" extends the field's path ("[1].weight"). */
function checkList(f, v) {
  const what = {
    terms: 'an array of terms',
    filters: 'an array of filters',
    curve: 'an array of [x, y] points',
    ranges: 'an array of [lo, hi] ranges',
  }[f.type];
  if (!Array.isArray(v)) return { code: 'bad_field', reason: `expected ${what}` };
  if (f.type === 'ranges') {
    if (v.length > f.maxItems) return { code: 'out_of_range', reason: `at most ${f.maxItems} ranges` };
    for (let i = 0; i < v.length; i++) {
      const at = `[${i}]`;
      if (!isPair(v[i])) return { code: 'bad_field', reason: 'expected an array of 2 numbers', at };
      if (!(v[i][0] <= v[i][1])) return { code: 'bad_field', reason: 'lo must not exceed hi', at };
    }
    return null;
  }
  if (f.type === 'curve') {
    if (v.length === 1 || v.length > f.maxItems)
      return { code: 'out_of_range', reason: `2 to ${f.maxItems} points (none: the identity)` };
    for (let i = 0; i < v.length; i++) {
      const at = `[${i}]`;
      if (!isPair(v[i])) return { code: 'bad_field', reason: 'expected an array of 2 numbers', at };
      if (!v[i].every((x) => x >= 0 && x <= 1))
        return { code: 'out_of_range', reason: 'x and y must lie in [0, 1]', at };
      if (i > 0 && !(v[i][0] >= v[i - 1][0])) return { code: 'bad_field', reason: 'x must not decrease', at };
    }
    return null;
  }
  if (v.length > f.maxItems) return { code: 'out_of_range', reason: `at most ${f.maxItems} ${f.type}` };
  let sumAbs = 0;
  for (let i = 0; i < v.length; i++) {
    const r = checkElement(f.type, v[i], `[${i}]`);
    if (r.code) return r;
    sumAbs += Math.abs(r.weight);
  }
  if (f.type === 'terms' && v.length && !(sumAbs > 0))
    return { code: 'bad_field', reason: 'at least one weight must be non-zero' };
  return null;
}

/** layers[] (protocol/request_layers.c): the shape only; each layer's importance, colour, style, filter and time
 * keys are the server's to check against the layer's dataset. */
function checkLayers(f, v) {
  if (!Array.isArray(v)) return { code: 'bad_field', reason: 'expected an array of layers' };
  if (v.length > f.maxItems) return { code: 'out_of_range', reason: `at most ${f.maxItems} layers` };
  const keys = f.keys;
  for (let i = 0; i < v.length; i++) {
    const at = `[${i}]`,
      l = v[i];
    if (!isObject(l)) return { code: 'bad_field', reason: 'expected an object with a dataset', at };
    for (const k of Object.keys(l))
      if (!keys.includes(k)) return { code: 'unknown_field', reason: 'unknown field', at: `${at}.${k}` };
    if (typeof l.dataset !== 'string' || !l.dataset.length)
      return { code: 'missing_field', reason: 'every layer names its dataset', at: `${at}.dataset` };
    if (l.role !== undefined && l.role !== 'transparent' && l.role !== 'context')
      return { code: 'bad_field', reason: 'expected "transparent" or "context"', at: `${at}.role` };
    if (l.visible !== undefined && typeof l.visible !== 'boolean')
      return { code: 'bad_field', reason: 'expected true or false', at: `${at}.visible` };
  }
  return null;
}

/** Like checkField but only the reason text (null when valid), for the panel and the URL. */
export function checkValue(f, v) {
  return checkField(f, v)?.reason ?? null;
}

/** Text of a value for a URL (vectors comma-separated, terms and filters as JSON), as GET /api/v1/render reads it. */
export function valueToText(f, v) {
  if (['terms', 'filters', 'curve', 'ranges', 'layers', 'seed'].includes(f.type)) return JSON.stringify(v); // JSON text, as request.c reads lists
  if (Array.isArray(v)) return v.map((x) => String(x)).join(',');
  return String(v);
}

/** Parses URL text back into a value for the field; returns undefined if malformed. */
export function valueFromText(f, text) {
  const num = (s) => (/^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/.test(s) ? Number(s) : NaN);
  switch (f.type) {
    case 'int':
    case 'num': {
      const n = num(text);
      return Number.isFinite(n) ? n : undefined;
    }
    case 'bool':
      if (text === 'true' || text === '1') return true;
      if (text === 'false' || text === '0') return false;
      return undefined;
    case 'str':
    case 'enum':
      return text;
    case 'vec3':
    case 'range':
    case 'color': {
      const parts = text.split(',').map(num);
      return parts.every(Number.isFinite) ? parts : undefined;
    }
    case 'terms':
    case 'filters':
    case 'curve':
    case 'ranges':
    case 'layers':
    case 'seed':
      try {
        const v = JSON.parse(text);
        return Array.isArray(v) ? v : undefined;
      } catch {
        return undefined;
      }
    default:
      return undefined;
  }
}

/** Reads a dotted path from a nested object. */
export function getPath(obj, path) {
  let o = obj;
  for (const k of path.split('.')) {
    if (o == null || typeof o !== 'object') return undefined;
    o = o[k];
  }
  return o;
}

/** Writes a dotted path into a nested object, creating sections. Returns obj. */
export function setPath(obj, path, value) {
  const keys = path.split('.');
  let o = obj;
  for (const k of keys.slice(0, -1)) {
    if (o[k] == null || typeof o[k] !== 'object') o[k] = {};
    o = o[k];
  }
  o[keys[keys.length - 1]] = value;
  return obj;
}

/** Deep merge of plain objects (arrays and scalars replace). Returns a new object. */
export function merge(base, update) {
  const out = { ...(base ?? {}) };
  for (const [k, v] of Object.entries(update ?? {})) {
    if (
      v &&
      typeof v === 'object' &&
      !Array.isArray(v) &&
      out[k] &&
      typeof out[k] === 'object' &&
      !Array.isArray(out[k])
    )
      out[k] = merge(out[k], v);
    else out[k] = Array.isArray(v) ? [...v] : v && typeof v === 'object' ? merge({}, v) : v;
  }
  return out;
}

// The default of each field a `when` names (the server's).
const WHEN_DEFAULTS = Object.freeze({ 'params.alphaSource': 'importance' });
const scopeByPath = new Map([...FIELDS, ...REQUEST_TOP_FIELDS].map((f) => [fieldPath(f), f]));
const PRIMITIVE_NAMES = { points: 'points', lines: 'lines', triangles: 'surfaces', surfaces: 'surfaces' };

/** Whether field f applies under method (default fourier) to data of kind prim ('points', 'lines',
 *  'triangles'; null = not known, as with layers of several kinds). */
export function applies(f, method, prim) {
  if (f.methods && !f.methods.includes(method ?? 'fourier')) return false;
  return !(f.primitives && prim && !f.primitives.includes(PRIMITIVE_NAMES[prim] ?? prim));
}

/** update without the fields that do not apply under its method to data of kind prim: what the page
 *  sends, while its own state keeps the rest for when they apply again (the server refuses a field
 *  given where it does not apply). */
export function applicableUpdate(update, prim) {
  const method = update?.method ?? 'fourier';
  const holds = (f) => {
    if (!f?.when) return true; // when: [path, value], as the schema's
    const [section, name] = f.when[0].split('.');
    return (update?.[section]?.[name] ?? WHEN_DEFAULTS[f.when[0]]) === f.when[1];
  };
  const out = {};
  for (const [k, v] of Object.entries(update ?? {})) {
    const top = scopeByPath.get(k);
    if (top) {
      if (applies(top, method, prim)) out[k] = v;
    } else if (v && typeof v === 'object' && !Array.isArray(v) && k !== 'camera') {
      const kept = Object.fromEntries(
        Object.entries(v).filter(([n]) => {
          const f = scopeByPath.get(`${k}.${n}`);
          return !f || (applies(f, method, prim) && holds(f));
        }),
      );
      if (Object.keys(kept).length) out[k] = kept;
    } else {
      out[k] = v;
    }
  }
  return out;
}
