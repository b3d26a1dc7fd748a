// The page's shareable state in the URL hash: dataset, camera and the parameters
// that differ from the server's defaults, written with the same flat keys as the
// query parameters of GET /api/v1/render (protocol/README.md), e.g.
//   #dataset=demo:tornado&position=0,0,5&focalPoint=0,0,0&viewUp=0,1,0&q=80&colormap=turbo
// so a link reopens the same view and its keys can be pasted into an <img> URL.
// Pure functions: no window access; the page passes location.hash / location.search.

import {
  FIELDS,
  STREAM_FIELDS,
  REQUEST_TOP_FIELDS,
  fieldByAlias,
  fieldByPath,
  fieldPath,
  checkField,
  valueToText,
  getPath,
  setPath,
} from './schema.js';
import { ProtocolError, checkCameraPose, DEFAULT_LIMITS } from './protocol.js';
import { roundCamera } from './camera.js';

const CAMERA_KEYS = ['position', 'focalPoint', 'viewUp', 'viewAngle', 'parallelProjection', 'parallelScale'];

// Keep ':' ',' '/' readable in the hash; everything else percent-encoded.
const enc = (s) => encodeURIComponent(s).replace(/%3A/gi, ':').replace(/%2C/gi, ',').replace(/%2F/gi, '/');
const dec = (s) => {
  try {
    return decodeURIComponent(s.replace(/\+/g, ' '));
  } catch {
    return null;
  }
};

function splitPairs(text) {
  const out = [];
  for (const part of text.replace(/^[#?]/, '').split('&')) {
    if (!part) continue;
    const i = part.indexOf('=');
    const k = dec(i < 0 ? part : part.slice(0, i));
    const v = dec(i < 0 ? '' : part.slice(i + 1));
    if (k !== null && v !== null) out.push([k, v]);
  }
  return out;
}

// Plain decimal only, as the server's parse_decimal: no "nan", "inf" or hex.
function decimal(text) {
  if (text.length === 0 || text.length > 64 || !/^[0-9+\-.eE]+$/.test(text)) return undefined;
  if (!/^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/.test(text)) return undefined;
  const n = Number(text);
  return Number.isFinite(n) ? n : undefined;
}

/** Converts query text into the value a field expects (query_value in request.c); undefined = malformed. */
export function queryValue(f, text) {
  switch (f.type) {
    case 'int':
    case 'num':
      return decimal(text);
    case 'bool':
      return text === 'true' || text === '1' ? true : text === 'false' || text === '0' ? false : undefined;
    case 'str':
    case 'enum':
      return text;
    case 'terms':
    case 'filters':
    case 'curve':
    case 'ranges':
    case 'seed':
    case 'layers': // list fields travel as JSON text, as the server reads them
      try {
        const v = JSON.parse(text);
        return Array.isArray(v) ? v : undefined;
      } catch {
        return undefined;
      }
    default: {
      const parts = text.split(',');
      if (parts.length > 3) return undefined;
      const nums = parts.map(decimal);
      return nums.every((x) => x !== undefined) ? nums : undefined;
    }
  }
}

const ALL_FIELDS = [...FIELDS, ...REQUEST_TOP_FIELDS, ...STREAM_FIELDS];
const DEFAULT_CAMERA_FIELDS = {
  position: [0, 0, 0],
  focalPoint: [0, 0, 0],
  viewUp: [0, 1, 0],
  viewAngle: 30,
  parallelProjection: false,
  parallelScale: 1,
};

/** The field a query key names: a flat alias or a dotted path; stream settings only when allowed. */
function queryField(key, stream) {
  const f = key.includes('.')
    ? ALL_FIELDS.find((x) => x.section && fieldPath(x) === key)
    : ALL_FIELDS.find((x) => x.alias === key && (x.section || !STREAM_FIELDS.includes(x)));
  if (f) return f;
  if (stream) return STREAM_FIELDS.find((x) => x.alias === key && x.name !== 'quality');
  return undefined;
}

/**
 * Applies one query parameter to a partial request (lc_proto_apply_query): key
 * as a flat alias or dotted path, value as decoded text. "token" and "_…" keys
 * are ignored. Any camera key starts from the default camera. Throws
 * ProtocolError naming the key as written.
 */
export function applyQueryParam(req, key, text, { limits = DEFAULT_LIMITS, stream = false } = {}) {
  if (!key || key[0] === '_' || key === 'token') return req;
  const f = queryField(key, stream);
  if (!f) throw new ProtocolError('unknown_field', 'unknown query parameter', key);
  const v = queryValue(f, text ?? '');
  const lim = { ...DEFAULT_LIMITS, ...limits };
  const fs = f.sizeLimit ? { ...f, min: lim.minSize, max: lim.maxSize } : f;
  const problem = v === undefined ? { code: 'bad_field', reason: `malformed value "${text}"` } : checkField(fs, v);
  if (problem) throw new ProtocolError(problem.code, problem.reason, `${key}${problem.at ?? ''}`);
  if (f.section === 'camera' && !req.camera) req.camera = structuredClone(DEFAULT_CAMERA_FIELDS);
  setPath(req, fieldPath(f), f.name === 'format' && v === 'jpg' ? 'jpeg' : v);
  return req;
}

/** Cross-field checks after the last parameter (lc_proto_validate_request): pixel cap, camera. */
export function validateQueryRequest(req, limits = DEFAULT_LIMITS) {
  const lim = { ...DEFAULT_LIMITS, ...limits };
  const w = req.width ?? 1024,
    h = req.height ?? 768;
  if (w * h > lim.maxPixels)
    throw new ProtocolError(
      'out_of_range',
      `${w} x ${h} = ${w * h} pixels exceeds the limit ${lim.maxPixels}`,
      'width',
    );
  if (req.camera) checkCameraPose(req.camera, true);
  return req;
}

/** A whole query string (GET /api/v1/render) as a partial request; throws ProtocolError. */
export function parseQuery(text, limits = DEFAULT_LIMITS) {
  const req = {};
  for (const [k, v] of splitPairs(text ?? '')) applyQueryParam(req, k, v, { limits });
  return validateQueryRequest(req, limits);
}

/**
 * Reads the hash. Returns {dataset, camera, update, token, errors}: camera holds
 * the camera keys given (null when none), update the request sections and stream
 * settings ({params:{q:80}, style:{...}, method, quality}), errors one readable
 * line per key that was unknown or invalid (those keys are skipped). Keys are
 * those of GET /api/v1/render (flat or dotted) plus the stream settings.
 */
export function parseHash(hash) {
  const state = { dataset: null, camera: null, update: {}, token: null, errors: [] };
  for (const [key, text] of splitPairs(hash ?? '')) {
    if (key === 'token') {
      state.token = text;
      continue;
    }
    const f = STREAM_FIELDS.find((x) => x.alias === key) ?? queryField(key, true);
    if (!f || (f.section === null && !['dataset', 'method', 'layers'].includes(f.name) && !STREAM_FIELDS.includes(f))) {
      state.errors.push(`${key}: unknown key in the link`);
      continue;
    }
    const v = queryValue(f, text);
    const problem = v === undefined ? { reason: 'malformed value' } : checkField(f, v);
    if (problem) {
      state.errors.push(`${key}: ${problem.reason}`);
      continue;
    }
    if (f.name === 'dataset') state.dataset = v;
    else if (f.section === 'camera') (state.camera ??= {})[f.name] = v;
    else setPath(state.update, fieldPath(f), v);
  }
  return state;
}

/**
 * Writes the hash for dataset, camera and update (the same shapes parseHash
 * returns; update may also be a full request: pass defaults to leave out the
 * values equal to them). The token is never written: a shared link should not
 * carry a secret. Returns text starting with '#', or '' when there is nothing.
 */
export function formatHash({ dataset, camera, update }, defaults = null) {
  const parts = [];
  if (dataset) parts.push(`dataset=${enc(dataset)}`);
  if (camera) {
    const c = roundCamera(camera);
    for (const k of CAMERA_KEYS) {
      if (k === 'parallelProjection' && !c.parallelProjection) continue;
      if (k === 'parallelScale' && !c.parallelProjection) continue;
      const f = FIELDS.find((x) => x.section === 'camera' && x.name === k);
      parts.push(`${k}=${enc(valueToText(f, c[k]))}`);
    }
  }
  for (const f of [...FIELDS, ...STREAM_FIELDS, ...REQUEST_TOP_FIELDS.filter((x) => x.name === 'layers')]) {
    if (f.name === 'dataset' || f.section === 'camera') continue;
    const path = fieldPath(f);
    const v = getPath(update ?? {}, path);
    if (v === undefined || v === null) continue;
    if (defaults && sameValue(v, getPath(defaults, path))) continue;
    if (f.name === 'layers' && Array.isArray(v) && !v.length) continue; // [] = the single dataset, the default
    const list = ['terms', 'filters', 'curve', 'ranges', 'layers', 'seed'].includes(f.type); // JSON text, as it is
    const r =
      typeof v === 'number'
        ? Number(v.toPrecision(7))
        : Array.isArray(v) && !list
          ? v.map((x) => Number(Number(x).toPrecision(7)))
          : v;
    parts.push(`${f.alias}=${enc(valueToText(f, r))}`);
  }
  return parts.length ? `#${parts.join('&')}` : '';
}

function sameValue(a, b) {
  if (Array.isArray(a) && Array.isArray(b)) return a.length === b.length && a.every((x, i) => sameValue(x, b[i]));
  if (typeof a === 'number' && typeof b === 'number')
    return Math.abs(a - b) <= 1e-9 * Math.max(1, Math.abs(a), Math.abs(b));
  return a === b;
}

/** The access token from ?token= or #token= (search wins), or null. */
export function tokenFromLocation(search, hash) {
  for (const text of [search, hash]) {
    for (const [k, v] of splitPairs(text ?? '')) if (k === 'token' && v) return v;
  }
  return null;
}
