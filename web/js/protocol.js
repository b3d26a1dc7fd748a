// The WebSocket session protocol (protocol/websocket.md): builders for the
// client's JSON messages, parsing of the server's JSON messages, and the binary
// frame layout. Pure functions with no DOM: Node's test runner replays the
// shared vectors in protocol/vectors/ through this module.

import { FIELDS, STREAM_FIELDS, REQUEST_TOP_FIELDS, UPDATE_SECTIONS, checkField } from './schema.js';

export const MAX_WINDOW = 8;
export const MAX_DEVICE_PIXEL_RATIO = 8;
export const MAX_SEQ = Number.MAX_SAFE_INTEGER; // 2^53 - 1, as protocol/messages.h
export const MAX_FRAME_HEADER = 4096; // bytes of header JSON a frame may carry
export const MAX_TIMINGS = 16;
export const TOKEN_MAX_BYTES = 255; // token < 256 bytes
export const DATASET_MAX_BYTES = 511; // dataset < 512 bytes
export const MIN_INTERACTIVE_SCALE = 0.25;

export const SUBPROTOCOL = 'lucent';
export const TOKEN_SUBPROTOCOL_PREFIX = 'lucent.token.';

/**
 * WebSocket subprotocols that carry an access token at the handshake (a
 * browser cannot set an Authorization header there, and a server with a token
 * refuses upgrades without one): 'lucent' (the one the server selects) and
 * 'lucent.token.' + base64url of the token's UTF-8 bytes without padding.
 */
export function tokenSubprotocols(token) {
  if (!token) return [];
  const bytes = new TextEncoder().encode(token);
  let bin = '';
  for (const b of bytes) bin += String.fromCharCode(b);
  const b64 = btoa(bin).replace(/\+/g, '-').replace(/\//g, '_').replace(/=+$/, '');
  return [SUBPROTOCOL, TOKEN_SUBPROTOCOL_PREFIX + b64];
}

export const CLIENT_TYPES = Object.freeze(['hello', 'camera', 'params', 'resize', 'ack']);
export const SERVER_TYPES = Object.freeze(['ready', 'error', 'stats', 'progress']);

/** A message that breaks the protocol; field is the dotted path when known. */
export class ProtocolError extends Error {
  constructor(code, message, field = '') {
    super(field ? `${field}: ${message}` : message);
    this.name = 'ProtocolError';
    this.code = code;
    this.field = field;
  }
}

const fail = (code, field, reason) => {
  throw new ProtocolError(code, reason, field);
};
const isObj = (v) => v !== null && typeof v === 'object' && !Array.isArray(v);
const g15 = (x) => String(Number(x.toPrecision(15)));
const utf8Length = (s) => new TextEncoder().encode(s).length;

/** Default caps (lc_proto_limits_default); ready.limits reports a server's own. */
export const DEFAULT_LIMITS = Object.freeze({
  minSize: 16,
  maxSize: 8192,
  maxPixels: 8192 * 4608,
  maxDepth: 16,
  maxText: 65536,
});

// ---- text loading under limits (lc_proto_load)

/** Deepest {}/[] nesting of raw JSON text, brackets inside strings ignored. */
export function nestingDepth(text, max = Infinity) {
  let depth = 0,
    deepest = 0,
    inString = false;
  for (let i = 0; i < text.length; i++) {
    const c = text[i];
    if (inString) {
      if (c === '\\') i++;
      else if (c === '"') inString = false;
    } else if (c === '"') inString = true;
    else if (c === '{' || c === '[') {
      if (++depth > deepest && (deepest = depth) > max) return deepest;
    } else if (c === '}' || c === ']') depth--;
  }
  return deepest;
}

/**
 * One pass over valid JSON text outside strings: the first key that appears
 * twice in one object (duplicate) and whether an integer literal overflows 64
 * bits (jansson refuses both; JSON.parse does not).
 */
export function scanJson(text) {
  const stack = []; // per open container: a Set of keys (objects) or null (arrays)
  let expectKey = false;
  let duplicate = null,
    bigInteger = false;
  for (let i = 0; i < text.length; i++) {
    const c = text[i];
    if (c === '"') {
      let j = i + 1;
      while (j < text.length && text[j] !== '"') j += text[j] === '\\' ? 2 : 1;
      const top = stack[stack.length - 1];
      if (expectKey && top) {
        const key = JSON.parse(text.slice(i, j + 1));
        if (top.has(key) && duplicate === null) duplicate = key;
        top.add(key);
        expectKey = false;
      }
      i = j;
    } else if (c === '{') {
      stack.push(new Set());
      expectKey = true;
    } else if (c === '[') {
      stack.push(null);
    } else if (c === '}' || c === ']') {
      stack.pop();
    } else if (c === ',') {
      expectKey = !!stack[stack.length - 1];
    } else if (c === '-' || (c >= '0' && c <= '9')) {
      const m = /^-?\d+([.eE][-+\d.eE]*)?/.exec(text.slice(i, i + 400));
      if (m && !m[1]) {
        const big = BigInt(m[0]);
        if (big > 9223372036854775807n || big < -9223372036854775808n) bigInteger = true;
      }
      i += (m ? m[0].length : 1) - 1;
    }
  }
  return { duplicate, bigInteger };
}

/**
 * Parses JSON text as the server does: too_large beyond limits.maxText bytes,
 * too_deep beyond limits.maxDepth, bad_json for malformed text, NaN/Infinity
 * (JSON.parse refuses them), numbers that overflow a double, duplicate keys.
 */
export function loadJson(text, limits = DEFAULT_LIMITS) {
  const lim = { ...DEFAULT_LIMITS, ...limits };
  if (typeof text !== 'string') {
    const bytes = asBytes(text);
    if (bytes.length > lim.maxText)
      fail('too_large', '', `document of ${bytes.length} bytes exceeds the limit of ${lim.maxText} bytes`);
    try {
      text = utf8.decode(bytes);
    } catch {
      fail('bad_json', '', 'invalid JSON: not UTF-8');
    }
  }
  const bytes = utf8Length(text);
  if (bytes > lim.maxText)
    fail('too_large', '', `document of ${bytes} bytes exceeds the limit of ${lim.maxText} bytes`);
  if (nestingDepth(text, lim.maxDepth) > lim.maxDepth)
    fail('too_deep', '', `nesting deeper than ${lim.maxDepth} levels`);
  let value;
  let overflow = false;
  try {
    value = JSON.parse(text, (k, v) => {
      if (typeof v === 'number' && !Number.isFinite(v)) overflow = true;
      return v;
    });
  } catch (e) {
    fail('bad_json', '', `invalid JSON: ${e.message}`);
  }
  if (overflow) fail('bad_json', '', 'invalid JSON: number out of range');
  if (text.includes('\\u0000')) fail('bad_json', '', 'invalid JSON: \\u0000 in a string');
  const scan = scanJson(text);
  if (scan.duplicate !== null) fail('bad_json', '', `invalid JSON: duplicate object key "${scan.duplicate}"`);
  if (scan.bigInteger) fail('bad_json', '', 'invalid JSON: integer overflows 64 bits');
  return value;
}

// ---- render-request parts (lc_proto_check_update)

const throwField = (path, problem) => fail(problem.code, `${path}${problem.at ?? ''}`, problem.reason);

function checkMembers(obj, section, lim, top) {
  for (const [key, v] of Object.entries(obj)) {
    const path = section ? `${section}.${key}` : key;
    if (!section && ['camera', ...UPDATE_SECTIONS, 'surface', 'streamlines'].includes(key)) {
      if (key === 'camera' && v === null) continue; // sessions: back to fitting the data
      if (!isObj(v)) fail('bad_field', path, 'expected an object');
      checkMembers(v, key, lim, top);
      continue;
    }
    const f = (section ? FIELDS : top).find((x) => x.section === section && x.name === key);
    if (!f) fail('unknown_field', path, 'unknown field');
    const fs = f.sizeLimit ? { ...f, min: lim.minSize, max: lim.maxSize } : f;
    const problem = checkField(fs, v);
    if (problem) throwField(path, problem);
  }
}

/** position != focalPoint and, when checkUp, viewUp not parallel to the view direction (check_camera). */
export function checkCameraPose(cam, checkUp = true) {
  const d = [0, 1, 2].map((i) => cam.focalPoint[i] - cam.position[i]);
  const u = cam.viewUp;
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const dd = dot(d, d),
    uu = dot(u, u);
  if (!(dd > 0) || !Number.isFinite(dd)) fail('bad_field', 'camera.focalPoint', 'must differ from camera.position');
  if (!checkUp) return;
  if (!(uu > 0) || !Number.isFinite(uu)) fail('bad_field', 'camera.viewUp', 'must not be zero');
  const c = [d[1] * u[2] - d[2] * u[1], d[2] * u[0] - d[0] * u[2], d[0] * u[1] - d[1] * u[0]];
  if (!(dot(c, c) > 1e-12 * dd * uu)) fail('bad_field', 'camera.viewUp', 'must not be parallel to the view direction');
}

const DEFAULT_POSE = { position: [0, 0, 0], focalPoint: [0, 0, 0], viewUp: [0, 1, 0] };

/**
 * Field checks of a partial render request (camera, params, importance, color,
 * style, method) with the same codes and dotted paths as the server; the camera
 * is cross-checked as far as the update pins it down. Throws ProtocolError.
 */
export function checkUpdate(update, limits = DEFAULT_LIMITS) {
  if (!isObj(update)) fail('bad_field', '', 'expected a JSON object');
  const lim = { ...DEFAULT_LIMITS, ...limits };
  // layers[] is a session update too (hello, params), unlike the request's other top-level fields
  checkMembers(update, null, lim, [...FIELDS, ...REQUEST_TOP_FIELDS.filter((f) => f.name === 'layers')]);
  const cam = update.camera;
  if (isObj(cam) && cam.position !== undefined && cam.focalPoint !== undefined)
    checkCameraPose({ ...DEFAULT_POSE, ...cam }, cam.viewUp !== undefined);
}

/**
 * Checks a whole render request (POST /api/v1/render body) with the server's
 * rules, including the pixel cap and the camera. Throws ProtocolError.
 */
export function checkRequest(req, limits = DEFAULT_LIMITS) {
  if (!isObj(req)) fail('bad_field', '', 'expected a JSON object');
  const lim = { ...DEFAULT_LIMITS, ...limits };
  checkMembers(req, null, lim, [...FIELDS, ...REQUEST_TOP_FIELDS]);
  const w = req.width ?? 1024,
    h = req.height ?? 768;
  if (w * h > lim.maxPixels)
    fail('out_of_range', 'width', `${w} x ${h} = ${w * h} pixels exceeds the limit ${lim.maxPixels}`);
  if (isObj(req.camera)) checkCameraPose({ ...DEFAULT_POSE, ...req.camera }, true);
}

// ---- client messages (lc_proto_parse_client_message)

// surface: method surface-layers (a field's surface); streamlines: a field's traced set; not panel sections
const UPDATE_KEYS = ['camera', ...UPDATE_SECTIONS, 'method', 'filter', 'surface', 'streamlines', 'layers'];
const STREAM_KEYS = STREAM_FIELDS.map((f) => f.name);
const ALLOWED = {
  hello: ['dataset', 'width', 'height', 'devicePixelRatio', 'window', 'token', ...STREAM_KEYS, ...UPDATE_KEYS],
  camera: ['seq', 'camera'],
  params: [...STREAM_KEYS, ...UPDATE_SECTIONS, 'method', 'filter', 'surface', 'streamlines', 'layers'],
  resize: ['width', 'height', 'devicePixelRatio'],
  ack: ['frame'],
};

function getInt(obj, key, lo, hi) {
  const v = obj[key];
  if (v === undefined) return false;
  if (typeof v !== 'number' || !Number.isFinite(v) || !Number.isInteger(v))
    fail('bad_field', key, 'expected an integer');
  if (v < lo || v > hi) fail('out_of_range', key, `${g15(v)} is outside [${lo}, ${hi}]`);
  return true;
}
function getUint(obj, key) {
  const v = obj[key];
  if (v === undefined) return false;
  if (typeof v !== 'number' || !Number.isFinite(v) || !Number.isInteger(v))
    fail('bad_field', key, 'expected a non-negative integer');
  if (v < 0 || v > MAX_SEQ) fail('out_of_range', key, 'must be in [0, 2^53-1]');
  return true;
}
function getNum(obj, key, lo, loOpen, hi) {
  const v = obj[key];
  if (v === undefined) return false;
  if (typeof v !== 'number' || !Number.isFinite(v)) fail('bad_field', key, 'expected a number');
  if ((loOpen ? !(v > lo) : !(v >= lo)) || !(v <= hi))
    fail('out_of_range', key, `${g15(v)} is outside ${loOpen ? '(' : '['}${g15(lo)}, ${g15(hi)}]`);
  return true;
}
function getStr(obj, key, maxBytes) {
  const v = obj[key];
  if (v === undefined) return false;
  if (typeof v !== 'string') fail('bad_field', key, 'expected a string');
  if (utf8Length(v) > maxBytes) fail('out_of_range', key, `longer than ${maxBytes} bytes`);
  return true;
}
const needs = (present, key) => {
  if (!present) fail('missing_field', key, 'required');
};

/**
 * Checks a client message object as the server does, in the server's order
 * (type, unknown keys, the type's own fields, then the render-request parts), so
 * the first error has the same code and field as in C. Returns the message;
 * throws ProtocolError.
 */
export function checkClientMessage(obj, limits = DEFAULT_LIMITS) {
  const lim = { ...DEFAULT_LIMITS, ...limits };
  if (!isObj(obj)) fail('bad_field', '', 'expected a JSON object');
  if (obj.type === undefined) fail('missing_field', 'type', 'required');
  const t = obj.type;
  if (typeof t !== 'string' || !CLIENT_TYPES.includes(t))
    fail('bad_field', 'type', 'expected one of "hello", "camera", "params", "resize", "ack"');
  for (const key of Object.keys(obj))
    if (key !== 'type' && !ALLOWED[t].includes(key)) fail('unknown_field', key, `unknown field in a ${t} message`);
  if (t === 'hello') {
    getStr(obj, 'dataset', DATASET_MAX_BYTES);
    getStr(obj, 'token', TOKEN_MAX_BYTES);
    getInt(obj, 'window', 1, MAX_WINDOW);
  }
  if (t === 'hello' || t === 'resize') {
    needs(getInt(obj, 'width', 1, lim.maxSize), 'width');
    needs(getInt(obj, 'height', 1, lim.maxSize), 'height');
    getNum(obj, 'devicePixelRatio', 0, true, MAX_DEVICE_PIXEL_RATIO);
  }
  if (t === 'hello' || t === 'params') {
    getInt(obj, 'quality', 1, 100);
    getInt(obj, 'interactiveQuality', 1, 100);
    getNum(obj, 'interactiveScale', MIN_INTERACTIVE_SCALE, false, 1);
  }
  if (t === 'camera') {
    needs(getUint(obj, 'seq'), 'seq');
    needs(obj.camera !== undefined, 'camera');
  }
  if (t === 'ack') needs(getUint(obj, 'frame'), 'frame');
  const update = {};
  for (const key of Object.keys(obj)) if (UPDATE_KEYS.includes(key)) update[key] = obj[key];
  if (Object.keys(update).length) checkUpdate(update, lim);
  return obj;
}

/** Parses client message text (vectors, mock server): loadJson + checkClientMessage. */
export function parseClientMessage(text, limits = DEFAULT_LIMITS) {
  return checkClientMessage(loadJson(text, limits), limits);
}

// ---- builders: assemble, then check as the server will

const defined = (o) => Object.fromEntries(Object.entries(o).filter(([, v]) => v !== undefined && v !== null));

/**
 * hello: opens a session. width/height are the viewport in CSS pixels; the server
 * renders width × height × devicePixelRatio (capped by its pixel limit).
 * Optional: dataset, token, window (unacknowledged frames, 1..8), camera, any of
 * params/importance/color/style/method and the stream settings.
 */
export function helloMessage(o) {
  const msg = defined({
    type: 'hello',
    dataset: o.dataset,
    width: o.width,
    height: o.height,
    devicePixelRatio: o.devicePixelRatio,
    window: o.window,
    token: o.token || undefined,
  });
  for (const k of [...STREAM_KEYS, ...UPDATE_KEYS])
    if (o[k] !== undefined && o[k] !== null) msg[k] = structuredClone(o[k]);
  return checkClientMessage(msg);
}

/** camera: a pose with a sequence number that grows with each message (null = fit the data again). */
export function cameraMessage(seq, camera) {
  return checkClientMessage({ type: 'camera', seq, camera: camera === null ? null : structuredClone(camera) });
}

/** params: any subset of params, importance, color, style, method and the stream settings. */
export function paramsMessage(update) {
  if (!isObj(update)) fail('bad_field', '', 'expected a JSON object');
  return checkClientMessage({ type: 'params', ...structuredClone(update) });
}

/** resize: the new viewport in CSS pixels and, optionally, devicePixelRatio. */
export function resizeMessage(width, height, devicePixelRatio) {
  return checkClientMessage(defined({ type: 'resize', width, height, devicePixelRatio }));
}

/** ack: the client has displayed frame id (acknowledges every frame ≤ id). */
export function ackMessage(frame) {
  return checkClientMessage({ type: 'ack', frame });
}

/** The wire text of a client message. */
export const encodeMessage = (msg) => JSON.stringify(msg);

/**
 * Parses a server text message (ready, error, stats, progress; unknown types pass through
 * for forward compatibility). Throws ProtocolError when it is not a JSON object
 * with a string type, or a known type lacks its required fields.
 */
export function parseServerMessage(text) {
  let obj;
  try {
    obj = JSON.parse(text);
  } catch (e) {
    throw new ProtocolError('bad_json', `server sent invalid JSON: ${e.message}`);
  }
  if (!isObj(obj)) fail('bad_json', '', 'server message is not a JSON object');
  if (typeof obj.type !== 'string') fail('missing_field', 'type', 'server message without a type');
  if (obj.type === 'ready') {
    if (typeof obj.session !== 'string' && typeof obj.session !== 'number')
      fail('missing_field', 'session', 'required');
    if (obj.defaults !== undefined && !isObj(obj.defaults)) fail('bad_field', 'defaults', 'expected a JSON object');
  } else if (obj.type === 'error') {
    if (typeof obj.code !== 'string') fail('missing_field', 'code', 'required');
    if (typeof obj.message !== 'string') fail('missing_field', 'message', 'required');
  } else if (obj.type === 'progress') {
    if (typeof obj.stage !== 'string') fail('missing_field', 'stage', 'required');
    if (obj.fraction !== null && typeof obj.fraction !== 'number')
      fail('bad_field', 'fraction', 'expected a number or null');
    if (typeof obj.elapsed !== 'number') fail('missing_field', 'elapsed', 'required');
  }
  return obj;
}

const utf8 = new TextDecoder('utf-8', { fatal: true });
const utf8enc = new TextEncoder();

function asBytes(buf) {
  if (buf instanceof Uint8Array) return buf;
  if (buf instanceof ArrayBuffer) return new Uint8Array(buf);
  if (ArrayBuffer.isView(buf)) return new Uint8Array(buf.buffer, buf.byteOffset, buf.byteLength);
  throw new ProtocolError('bad_field', '', 'frame is not binary data');
}

/**
 * Splits a binary frame message: uint32 LE header length N | N bytes UTF-8 JSON
 * header | image bytes. Returns {header, image} where image is a Uint8Array view
 * into the message (no copy). Same rules as lc_proto_unpack_frame: frame, width,
 * height, format, quality, cameraSeq and converged are required, timings and
 * encodeMs optional, unknown keys kept and ignored. Throws ProtocolError.
 */
export function unpackFrame(buf) {
  const bytes = asBytes(buf);
  if (bytes.length < 4) fail('bad_field', '', 'frame message shorter than its 4-byte length');
  const n = (bytes[0] | (bytes[1] << 8) | (bytes[2] << 16)) + bytes[3] * 0x1000000;
  if (n > bytes.length - 4) fail('bad_field', '', `header length ${n} exceeds the message (${bytes.length - 4} bytes)`);
  let text;
  try {
    text = utf8.decode(bytes.subarray(4, 4 + n));
  } catch {
    fail('bad_json', '', 'frame header is not UTF-8');
  }
  const header = loadJson(text, { maxText: MAX_FRAME_HEADER, maxDepth: 4 }); // visibility.layers[] objects
  if (!isObj(header)) fail('bad_field', '', 'frame header is not a JSON object');
  needs(getUint(header, 'frame'), 'frame');
  needs(getInt(header, 'width', 1, 1 << 30), 'width');
  needs(getInt(header, 'height', 1, 1 << 30), 'height');
  needs(getInt(header, 'quality', 0, 100), 'quality');
  needs(getUint(header, 'cameraSeq'), 'cameraSeq');
  if (header.format !== 'jpeg' && header.format !== 'png') fail('bad_field', 'format', 'expected "jpeg" or "png"');
  if (typeof header.converged !== 'boolean') fail('bad_field', 'converged', 'expected true or false');
  getNum(header, 'encodeMs', 0, false, 1e12);
  if (header.timings !== undefined) {
    if (!isObj(header.timings)) fail('bad_field', 'timings', 'expected an object');
    const entries = Object.entries(header.timings);
    if (
      entries.length > MAX_TIMINGS ||
      entries.some(([k, v]) => typeof v !== 'number' || !Number.isFinite(v) || utf8Length(k) >= 32)
    )
      fail('bad_field', 'timings', `expected at most ${MAX_TIMINGS} pass names with numbers`);
  }
  return { header, image: bytes.subarray(4 + n) };
}

/** A number as jansson prints a JSON real with 15 significant digits ("1.5", "0.0", "1e+21"). */
export function realText(x) {
  let t = String(Number(x.toPrecision(15)));
  if (/e/.test(t)) t = t.replace(/e([+-])(\d)$/, 'e$10$2'); // %g pads the exponent to 2 digits
  return /[.e]/.test(t) ? t : `${t}.0`;
}

/**
 * Builds a binary frame message exactly as lc_proto_pack_frame does (compact
 * JSON in websocket.md's key order, reals for timings and encodeMs), so a mock
 * server and the tests speak the server's bytes. Returns a Uint8Array.
 */
export function packFrame(header, image) {
  const h = header;
  const timings = Object.entries(h.timings ?? {})
    .map(([k, v]) => `${JSON.stringify(k)}:${realText(v)}`)
    .join(',');
  const text =
    `{"frame":${h.frame},"width":${h.width},"height":${h.height},"format":${JSON.stringify(h.format)},` +
    `"quality":${h.quality ?? 0},"cameraSeq":${h.cameraSeq ?? 0},"converged":${!!h.converged},` +
    `"timings":{${timings}},"encodeMs":${realText(h.encodeMs ?? 0)}}`;
  const hb = utf8enc.encode(text);
  const img = asBytes(image);
  const out = new Uint8Array(4 + hb.length + img.length);
  new DataView(out.buffer).setUint32(0, hb.length, true);
  out.set(hb, 4);
  out.set(img, 4 + hb.length);
  return out;
}

const jsonValue = (v) => (typeof v === 'number' && !Number.isInteger(v) ? realText(v) : JSON.stringify(v));

/** {"type":"error",...} as lc_proto_error_message_json writes it (field omitted when empty). */
export function errorMessageText(code, message, field, fatal) {
  const f = field ? `,"field":${JSON.stringify(field)}` : '';
  return `{"type":"error","code":${JSON.stringify(code || 'error')},"message":${JSON.stringify(message ?? '')}${f},"fatal":${!!fatal}}`;
}

/** HTTP error body {"error":{...}} as lc_proto_error_json writes it. */
export function httpErrorText(code, message, field) {
  const f = field ? `,"field":${JSON.stringify(field)}` : '';
  return `{"error":{"code":${JSON.stringify(code || 'error')},"message":${JSON.stringify(message ?? '')}${f}}}`;
}

/** {"type":"stats",...fields} as lc_proto_stats_json writes it (a "type" key in fields is ignored). */
export function statsText(fields) {
  const parts = Object.entries(fields)
    .filter(([k]) => k !== 'type')
    .map(([k, v]) => `${JSON.stringify(k)}:${jsonValue(v)}`);
  return `{"type":"stats"${parts.length ? ',' : ''}${parts.join(',')}}`;
}

/** A readable sentence for a server error message or an HTTP error body. */
export function describeError(err) {
  const e = isObj(err?.error) ? err.error : err;
  if (!isObj(e)) return 'Unknown error';
  const friendly = {
    unauthorized: 'This server needs an access token.',
    unknown_dataset: 'The dataset is not available on this server.',
    not_found: 'Not found.',
    overloaded: 'The server is busy; retrying shortly.',
    too_many_sessions: 'The server has too many sessions open; try again later.',
  };
  const msg = typeof e.message === 'string' && e.message ? e.message : '';
  const lead = friendly[e.code];
  if (lead && msg) return `${lead} (${msg})`;
  return msg || lead || `Error ${e.code ?? ''}`.trim();
}
