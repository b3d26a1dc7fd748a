// Client bookkeeping without a browser: reconnect back-off, frame statistics,
// colour and number formatting of the panel.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { backoffDelay, BACKOFF_MIN_MS, BACKOFF_MAX_MS, TERMINAL_CODES } from '../js/connection.js';
import { FrameStats, formatBytes } from '../js/stats.js';
import { rgbToHex, hexToRgb, formatNumber, GROUPS } from '../js/ui.js';
import { fieldByPath, checkField } from '../js/schema.js';

test('back-off: 0.5 s, 1 s, then a probe every 1.5 s (1.2–1.8 s with ±20 % jitter)', () => {
  const mid = (a) => backoffDelay(a, () => 0.5);
  assert.deepEqual([0, 1, 2, 3, 4, 5, 6].map(mid), [500, 1000, 1500, 1500, 1500, 1500, 1500]);
  for (let a = 2; a < 60; a++)
    assert.ok(backoffDelay(a, () => 0) >= 1000 && backoffDelay(a, () => 1) <= 2000, `attempt ${a}`);
  assert.equal(
    backoffDelay(0, () => 0),
    BACKOFF_MIN_MS * 0.8,
  );
  assert.equal(
    backoffDelay(50, () => 1),
    BACKOFF_MAX_MS * 1.2,
  );
  for (const code of ['unauthorized', 'not_found']) assert.ok(TERMINAL_CODES.has(code), code);
  for (const code of ['overloaded', 'internal', 'too_many_sessions']) assert.ok(!TERMINAL_CODES.has(code), code);
});

test('frame stats: fps over the last second, latency from camera seq to drawn frame', () => {
  let now = 0;
  const s = new FrameStats(() => now);
  s.cameraSent(1);
  now = 40;
  s.cameraSent(2);
  now = 100;
  const h = (frame, cameraSeq, extra = {}) => ({
    frame,
    width: 640,
    height: 480,
    format: 'jpeg',
    quality: 70,
    cameraSeq,
    converged: false,
    timings: { importance: 1.5, resolve: 0.5 },
    encodeMs: 2,
    ...extra,
  });
  s.frameDrawn(h(1, 1), 1000, 100);
  assert.equal(s.latency, 100);
  s.frameDrawn(h(2, 1), 1000, 150); // same seq: no new latency sample
  assert.equal(s.latency, 100);
  s.frameDrawn(h(3, 2), 3000, 200);
  assert.equal(s.latency, 160);
  assert.equal(s.sent.size, 0);
  assert.equal(s.fps(200), 3);
  assert.equal(s.fps(1160), 1);
  assert.equal(s.fps(5000), 0);
  const lines = Object.fromEntries(s.lines(200));
  assert.equal(lines.render, '2.0 ms');
  assert.equal(lines['  importance'], '1.5 ms');
  assert.equal(lines.encode, '2.0 ms');
  assert.equal(lines.state, 'fading');
  assert.match(lines.frame, /#3 640×480 jpeg q70/);
  assert.match(lines['bytes/frame'], /^2\.9 KiB/);
  s.server = { fps: 12.345678, framesDropped: 3, nested: { x: 1 } };
  const l2 = Object.fromEntries(s.lines(200));
  assert.equal(l2.fps, '3'); // the page's own fps; the server's is labelled as such
  assert.equal(l2['server fps'], '12.35');
  assert.equal(l2.framesDropped, '3');
  assert.equal(l2.nested, undefined);
  s.server = { linkMbps: 1.98765, linkMeasured: true };
  const l3 = Object.fromEntries(s.lines(200));
  assert.equal(l3.link, '1.99 Mbit/s (measured)');
  assert.equal(l3.linkMbps, undefined);
  s.server = { linkMbps: 2.5, linkMeasured: false };
  assert.equal(Object.fromEntries(s.lines(200)).link, '≥ 2.5 Mbit/s (carried; no frame waited)');
  s.server = { linkMbps: null, linkMeasured: false };
  assert.equal(Object.fromEntries(s.lines(200)).link, undefined);
  s.frameDrawn(h(4, 2, { converged: true }), 10, 300);
  assert.equal(Object.fromEntries(s.lines(300)).state, 'converged');
});

test('byte and number formatting', () => {
  assert.equal(formatBytes(512), '512 B');
  assert.equal(formatBytes(2048), '2.0 KiB');
  assert.equal(formatBytes(3 * 1024 * 1024), '3.00 MiB');
  assert.equal(formatNumber(0.1 + 0.2), '0.3');
  assert.equal(formatNumber(1000), '1000');
  assert.equal(formatNumber(NaN), '');
});

test('colours round-trip between [0,1] RGB and #rrggbb', () => {
  assert.equal(rgbToHex([1, 1, 1]), '#ffffff');
  assert.equal(rgbToHex([0, 0.5, 2]), '#0080ff');
  assert.deepEqual(hexToRgb('#ff8000'), [1, 0.502, 0]);
  assert.equal(hexToRgb('nope'), null);
});

test('every panel control edits a request field whose slider range is valid for the server', () => {
  const paths = new Set();
  for (const g of GROUPS) {
    for (const c of g.controls) {
      assert.ok(!paths.has(c.path), `${c.path} twice`);
      paths.add(c.path);
      const f = fieldByPath(c.path);
      assert.ok(f, `${c.path} is not a request field`);
      if (c.kind === 'range') {
        // both ends of the slider (except an open lower bound at 0) are valid values
        for (const v of [c.min, c.max]) {
          const p = checkField(f, f.type === 'int' ? Math.round(v) : v);
          if (p && !(f.loOpen && v === f.min)) assert.fail(`${c.path}: slider end ${v}: ${p.reason}`);
        }
      }
      if (c.kind === 'select' && c.options)
        for (const [v] of c.options) assert.equal(checkField(f, v), null, `${c.path}: ${v}`);
    }
  }
  for (const p of [
    'params.q',
    'params.r',
    'params.lambda',
    'params.bands',
    'params.smoothing',
    'params.fadeHalfLife',
    'params.estimator',
    'method',
    'importance.attribute',
    'importance.range',
    'importance.exponent',
    'color.attribute',
    'color.colormap',
    'color.range',
    'style.lineWidth',
    'style.pointSize',
    'style.background',
    'style.shading',
    'quality',
    'interactiveScale',
  ])
    assert.ok(paths.has(p), `the panel lacks ${p}`);
});

test('the token travels as a WebSocket subprotocol: base64url without padding, next to "lucent"', async () => {
  const { tokenSubprotocols } = await import('../js/protocol.js');
  assert.deepEqual(tokenSubprotocols(null), []);
  assert.deepEqual(tokenSubprotocols('s3cret-token'), ['lucent', 'lucent.token.czNjcmV0LXRva2Vu']);
  const [, p] = tokenSubprotocols('ä?>~ x');
  assert.match(p, /^lucent\.token\.[A-Za-z0-9_-]+$/); // only characters a subprotocol name may hold
  assert.equal(Buffer.from(p.slice('lucent.token.'.length), 'base64url').toString('utf8'), 'ä?>~ x');
});

test('visibility text and the warning when important structures hide each other (importantOccluded)', async () => {
  const { visibilityText, occlusionWarning, IMPORTANT_OCCLUDED_WARN } = await import('../js/stats.js');
  const v = {
    topDecileAlpha: 0.9,
    bottomHalfAlpha: 0.1,
    coveredFraction: 0.3,
    occluderAlpha: 0.05,
    importantOccluded: 0.4,
  };
  assert.match(visibilityText(v), /40% of the important fragments hidden by importance/);
  assert.match(occlusionWarning(v), /^40% of the important fragments lie behind other important ones/);
  assert.equal(occlusionWarning({ ...v, importantOccluded: IMPORTANT_OCCLUDED_WARN - 0.01 }), '');
  assert.equal(occlusionWarning({ ...v, importantOccluded: undefined }), ''); // an older server
  assert.doesNotMatch(visibilityText({ ...v, importantOccluded: undefined }), /hidden/);
  // topDecileReach: below 1 the top tenth is shown less than it is drawn (behind the rest), above 1 more.
  assert.match(visibilityText({ ...v, topDecileReach: 0.58 }), /most important tenth ×0\.58 \(behind the rest\)/);
  assert.match(visibilityText({ ...v, topDecileReach: 1.3 }), /×1\.30 \(in front of the rest\)/);
  assert.doesNotMatch(visibilityText(v), /×/); // methods other than fourier, older servers
});

test('the clarity note names the smoothing the loop cut to, where it did', async () => {
  const { clarityNote } = await import('../js/stats.js');
  const c = { lambdaFactor: 3, penaltyFactor: 2.5, reached: false };
  assert.match(clarityNote({ ...c, smoothing: 7 }), /q and r ×2\.5, smoothing 7 iterations, the strength/);
  assert.doesNotMatch(clarityNote(c), /smoothing/);
  assert.equal(clarityNote({ ...c, reached: true, smoothing: 0 }), '');
});
