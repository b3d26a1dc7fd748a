// Replays the shared protocol vectors (protocol/vectors/*.json, the same files the
// C tests read) through the page's protocol code.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import * as P from '../js/protocol.js';
import { parseQuery } from '../js/url-state.js';
import { merge } from '../js/schema.js';

const dir = new URL('../../protocol/vectors/', import.meta.url);
const load = (name) => JSON.parse(readFileSync(fileURLToPath(new URL(name, dir)), 'utf8'));
const hex = (h) => Uint8Array.from(h.match(/../g) ?? [], (x) => parseInt(x, 16));
const toHex = (b) => Buffer.from(b).toString('hex');
const caseText = (c) =>
  c.inputHex !== undefined ? hex(c.inputHex) : c.input !== undefined ? c.input : JSON.stringify(c.json);

/** expect is a subset of actual: objects by key, numbers within 1e-9 relative. */
function subset(actual, expect, path = '') {
  if (expect === null || typeof expect !== 'object') {
    if (typeof expect === 'number') {
      assert.equal(typeof actual, 'number', `${path}: expected a number, got ${JSON.stringify(actual)}`);
      assert.ok(Math.abs(actual - expect) <= 1e-9 * Math.max(1, Math.abs(expect)), `${path}: ${actual} != ${expect}`);
    } else assert.deepEqual(actual, expect, path);
    return;
  }
  assert.ok(actual !== null && typeof actual === 'object', `${path}: missing (expected ${JSON.stringify(expect)})`);
  if (Array.isArray(expect)) {
    assert.equal(actual.length, expect.length, `${path}: length`);
    expect.forEach((e, i) => subset(actual[i], e, `${path}[${i}]`));
  } else for (const [k, e] of Object.entries(expect)) subset(actual[k], e, path ? `${path}.${k}` : k);
}
function absent(actual, paths) {
  for (const p of paths ?? []) {
    let o = actual;
    for (const k of p.split('.')) o = o?.[k];
    assert.equal(o, undefined, `${p} must be absent`);
  }
}
function expectError(fn, c) {
  assert.throws(fn, (e) => {
    assert.ok(e instanceof P.ProtocolError, `${c.name}: not a ProtocolError: ${e}`);
    assert.equal(e.code, c.code, `${c.name}: code (${e.message})`);
    assert.equal(e.field, c.field, `${c.name}: field (${e.message})`);
    return true;
  });
}

// Normalized request: the defaults (requests.json's first case) + the fields given,
// a camera merged onto the default camera, "jpg" emitted as "jpeg".
const requests = load('requests.json');
const DEFAULTS = requests.cases[0].expect;
const DEFAULT_CAMERA = {
  position: [0, 0, 0],
  focalPoint: [0, 0, 0],
  viewUp: [0, 1, 0],
  viewAngle: 30,
  parallelProjection: false,
  parallelScale: 1,
};
function normalize(req) {
  const out = merge(DEFAULTS, { ...req, camera: undefined });
  delete out.camera;
  if (req.camera) out.camera = merge(DEFAULT_CAMERA, req.camera);
  if (out.format === 'jpg') out.format = 'jpeg';
  delete out.version;
  // list fields are emitted only when they hold something
  for (const [section, key] of [
    ['importance', 'terms'],
    ['importance', 'curve'],
    ['color', 'curve'],
  ])
    if (out[section]?.[key]?.length === 0) delete out[section][key];
  if (out.filter?.length === 0) delete out.filter;
  return out;
}

const builders = {
  hello: (m) => P.helloMessage(m),
  camera: (m) => P.cameraMessage(m.seq, m.camera),
  params: (m) => {
    const { type, ...rest } = m;
    return P.paramsMessage(rest);
  },
  resize: (m) => P.resizeMessage(m.width, m.height, m.devicePixelRatio),
  ack: (m) => P.ackMessage(m.frame),
};

test("client_messages.json: every case gives the C parser's result", () => {
  const v = load('client_messages.json');
  assert.ok(v.cases.length >= 70);
  for (const c of v.cases) {
    const text = caseText(c);
    if (c.valid) {
      const m = P.parseClientMessage(text, c.limits);
      subset(m, c.expect ?? {}, c.name);
      absent(m, c.absent);
      // the page's builders produce the same message, which parses back unchanged
      const built = builders[m.type](m);
      assert.deepEqual(built, m, `${c.name}: builder`);
      assert.deepEqual(P.parseClientMessage(P.encodeMessage(built)), m, `${c.name}: round trip`);
    } else {
      expectError(() => P.parseClientMessage(text, c.limits), c);
    }
  }
});

test('frames.json: byte-exact packing, unpacking and rejection', () => {
  const v = load('frames.json');
  assert.ok(v.cases.length >= 11);
  for (const c of v.cases) {
    const packed = hex(c.packedHex);
    if (c.valid) {
      const { header, image } = P.unpackFrame(packed.buffer);
      subset(header, c.header, c.name);
      assert.deepEqual(Object.keys(header), Object.keys(c.header), `${c.name}: keys`);
      assert.equal(toHex(image), c.imageHex, `${c.name}: image`);
      assert.equal(toHex(P.packFrame(c.header, hex(c.imageHex))), c.packedHex, `${c.name}: packed bytes`);
      // a view into a larger buffer unpacks the same
      const big = new Uint8Array(packed.length + 8);
      big.set(packed, 8);
      assert.equal(toHex(P.unpackFrame(big.subarray(8)).image), c.imageHex);
    } else {
      assert.throws(() => P.unpackFrame(packed), P.ProtocolError, c.name);
    }
  }
});

test('server_messages.json: byte-exact builders and parsing', () => {
  const v = load('server_messages.json');
  for (const c of v.cases) {
    const a = c.args;
    if (c.kind === 'error') {
      assert.equal(P.errorMessageText(a.code, a.message, a.field, a.fatal), c.output, c.name);
      const m = P.parseServerMessage(c.output);
      assert.equal(m.type, 'error');
      assert.equal(m.code, a.code);
      assert.equal(m.fatal, a.fatal);
      assert.ok(P.describeError(m).includes(a.message), c.name);
    } else if (c.kind === 'httpError') {
      assert.equal(P.httpErrorText(a.code, a.message, a.field), c.output, c.name);
      assert.ok(P.describeError(JSON.parse(c.output)).includes(a.message));
    } else if (c.kind === 'stats') {
      assert.equal(P.statsText(a.fields), c.output, c.name);
      subset(P.parseServerMessage(c.output), { type: 'stats', ...a.fields });
    } else if (c.kind === 'progress') {
      const m = P.parseServerMessage(c.output);
      assert.equal(m.stage, a.stage, c.name);
      assert.equal(m.fraction, a.fraction < 0 ? null : Math.round(a.fraction * 1000) / 1000, c.name);
      assert.equal(m.elapsed, Math.round(a.elapsed * 1000) / 1000, c.name);
    } else assert.fail(`unknown kind ${c.kind}`);
  }
});

test('requests.json: the page checks a render request as the server does', () => {
  assert.ok(requests.cases.length >= 100);
  for (const c of requests.cases) {
    const text = caseText(c);
    if (c.valid) {
      const req = P.loadJson(text, c.limits);
      P.checkRequest(req, c.limits);
      const n = normalize(req);
      subset(n, c.expect ?? {}, c.name);
      absent(n, c.absent);
    } else {
      expectError(() => P.checkRequest(P.loadJson(text, c.limits), c.limits), c);
    }
  }
});

test("query.json: URL parameters (the keys of the page's share links) as the server reads them", () => {
  const v = load('query.json');
  for (const c of v.cases) {
    if (c.valid) {
      const n = normalize(parseQuery(c.input, c.limits));
      subset(n, c.expect ?? {}, c.name);
      absent(n, c.absent);
    } else {
      expectError(() => parseQuery(c.input, c.limits), c);
    }
  }
});

test('server messages that break the protocol are refused', () => {
  assert.throws(() => P.parseServerMessage('nope'), /invalid JSON/);
  assert.throws(() => P.parseServerMessage('[1]'), /not a JSON object/);
  assert.throws(() => P.parseServerMessage('{"code":"x"}'), /type/);
  assert.throws(() => P.parseServerMessage('{"type":"error","message":"m"}'), /code/);
  assert.throws(() => P.parseServerMessage('{"type":"ready"}'), /session/);
  assert.equal(P.parseServerMessage('{"type":"future","x":1}').type, 'future');
});
