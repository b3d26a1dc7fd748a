// The page's controllers (app.js's createApp wires them to the DOM) with fake
// connections, frames and timers: panel edits, the camera's one-message-per-frame
// rule, the link, the stream's hello/ready/error handling, the picker and presets.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createState, currentValues } from '../js/app-state.js';
import { createParamsController } from '../js/params-controller.js';
import { createCameraController, CAMERAS_KEPT } from '../js/camera-controller.js';
import { createUrlController, HASH_DELAY_MS } from '../js/url-controller.js';
import { createSessionController, progressText } from '../js/session-controller.js';
import { createDatasetController, datasetView, describeDataset, shortSize } from '../js/dataset-controller.js';
import { parseHash } from '../js/url-state.js';
import { fitCamera, cloneCamera } from '../js/camera.js';

const BOUNDS = [0, 0, 0, 1, 2, 3]; // flat: x0 y0 z0 x1 y1 z1
const INFO = {
  name: 'demo:a',
  type: 'lines',
  lines: 12000,
  vertices: 3000000,
  elements: 2000,
  bounds: BOUNDS,
  attributes: [
    { name: 'speed', range: [2, 10] },
    { name: 'flat', range: [4, 4] },
  ],
};

/** Animation frames that run only when the test says so. */
function frames() {
  const queue = [];
  return {
    frame: (fn) => (queue.push(fn), queue.length),
    run: () => queue.splice(0).forEach((fn) => fn()),
    get size() {
      return queue.length;
    },
  };
}

function newState(hash = '') {
  return createState(parseHash(hash), null);
}

test('params: edits merge into the state at once and go out as one message per frame', () => {
  const state = newState();
  state.info = INFO;
  const f = frames(),
    sent = [];
  let changed = 0,
    counted = 0;
  const params = createParamsController({
    state,
    frame: f.frame,
    send: (m) => (sent.push(m), true),
    changed: () => changed++,
    sent: () => counted++,
    toast: assert.fail,
  });
  params.applyChange('params.q', 80);
  params.applyChange('params.r', 300);
  assert.deepEqual(state.update.params, { q: 80, r: 300 });
  assert.equal(changed, 2);
  assert.equal(f.size, 1, 'one frame for both edits');
  assert.equal(sent.length, 0, 'nothing before the frame');
  f.run();
  assert.equal(sent.length, 1);
  assert.equal(sent[0].type, 'params');
  assert.deepEqual(sent[0].params, { q: 80, r: 300 });
  assert.equal(counted, 1);
  // an attribute brings its range; one without extent is widened around its value
  params.applyChange('color.attribute', 'speed');
  assert.deepEqual(state.update.color, { attribute: 'speed', range: [2, 10] });
  params.applyChange('importance.attribute', 'flat');
  assert.deepEqual(state.update.importance.range, [3.5, 4.5]);
  params.applyChange('color.attribute', 'importance');
  assert.deepEqual(state.update.color.range, [0, 1]);
  f.run();
  assert.equal(sent.length, 2);
  assert.deepEqual(sent[1].color, { attribute: 'importance', range: [0, 1] }, 'the latest colour edit wins');
  // a closed socket: the edit stays in the state for the next hello, nothing counted
  const closed = createParamsController({
    state,
    frame: f.frame,
    send: () => false,
    changed() {},
    sent: assert.fail,
    toast: assert.fail,
  });
  closed.applyChange('params.lambda', 2);
  f.run();
  assert.equal(state.update.params.lambda, 2);
  // camera fields go to the camera
  const seen = [];
  createParamsController({
    state,
    frame: f.frame,
    send: assert.fail,
    setCameraField: (p, v) => seen.push([p, v]),
    changed: assert.fail,
  }).applyChange('camera.viewAngle', 45);
  assert.deepEqual(seen, [['camera.viewAngle', 45]]);
});

test('params: a value the protocol refuses is toasted, not sent', () => {
  const state = newState();
  const f = frames(),
    toasts = [];
  const params = createParamsController({
    state,
    frame: f.frame,
    send: assert.fail,
    changed() {},
    toast: (t) => toasts.push(t),
  });
  params.applyChange('params', 5); // not an object: paramsMessage throws
  f.run();
  assert.equal(toasts.length, 1);
});

function cameraRig({ open = true } = {}) {
  const state = newState();
  state.info = INFO;
  state.viewport = { width: 400, height: 300, dpr: 1 };
  const f = frames(),
    sent = [],
    seqs = [],
    shown = [];
  let clock = 100,
    changed = 0;
  const camera = createCameraController({
    state,
    frame: f.frame,
    now: () => clock,
    isOpen: () => open,
    send: (m) => sent.push(m),
    axes: { update: (c) => shown.push(c) },
    view: { setCamera: () => true },
    stats: { cameraSent: (s) => seqs.push(s) },
    aspect: () => 4 / 3,
    changed: () => changed++,
  });
  return { state, f, sent, seqs, shown, camera, tick: (ms) => (clock += ms), changes: () => changed };
}

test('camera: latest wins, one message per animation frame, sequence numbers grow', () => {
  const r = cameraRig();
  const a = r.camera.initial(INFO),
    b = cloneCamera(a);
  b.position = b.position.map((x) => x * 1.5);
  r.camera.setCamera(a);
  r.camera.setCamera(b);
  assert.equal(r.f.size, 1, 'one flush per frame, however many changes');
  r.camera.setCamera(b, { at: 90 });
  assert.equal(r.f.size, 2, 'and one response measurement');
  assert.equal(r.shown.length, 3, 'the triad follows every change at once');
  r.f.run();
  assert.equal(r.sent.length, 1, 'two changes in one frame: one message');
  assert.equal(r.sent[0].seq, 1);
  assert.deepEqual(
    r.sent[0].camera.position,
    b.position.map((x) => Number(x.toPrecision(12))),
  );
  assert.deepEqual(r.seqs, [1]);
  assert.equal(r.state.responses.length, 1, 'the painted response is measured');
  assert.equal(r.state.responses[0], 10);
  r.f.run();
  assert.equal(r.sent.length, 1, 'nothing new: nothing sent');
  r.camera.setCamera(a);
  r.f.run();
  assert.equal(r.sent[1].seq, 2);
  assert.equal(
    r.state.cameras.get(2).position[0],
    r.sent[1].camera.position[0],
    'the camera sent is kept to warp its frames',
  );
  // a degenerate camera is ignored
  const bad = cloneCamera(a);
  bad.position = [...bad.focalPoint];
  r.camera.setCamera(bad);
  assert.deepEqual(r.state.camera, a);
  // the map of sent cameras stays bounded
  for (let i = 0; i < CAMERAS_KEPT + 10; i++) {
    r.camera.setCamera(i % 2 ? a : b);
    r.f.run();
  }
  assert.equal(r.state.cameras.size, CAMERAS_KEPT);
});

test('camera: nothing is sent while the socket is closed; a hello takes the pending camera', () => {
  const r = cameraRig({ open: false });
  r.camera.setCamera(r.camera.initial(INFO));
  r.f.run();
  assert.equal(r.sent.length, 0);
  assert.equal(r.state.seq, 0);
  const o = cameraRig();
  o.camera.setCamera(o.camera.initial(INFO));
  o.camera.drop();
  o.f.run();
  assert.equal(o.sent.length, 0, 'dropped: the hello carried it');
});

test('camera: commands fit the data; a fitted view is refitted when it changes shape, a moved one is not', () => {
  const r = cameraRig();
  r.camera.setCamera(r.camera.initial(INFO), { fitted: true });
  r.camera.command('+x');
  assert.equal(r.state.fitted, true);
  const dir = r.state.camera.focalPoint.map((f, i) => f - r.state.camera.position[i]);
  assert.ok(
    Math.abs(dir[0]) > 0 && Math.abs(dir[1]) < 1e-9 && Math.abs(dir[2]) < 1e-9,
    `an axis view looks along x: ${dir}`,
  );
  const before = cloneCamera(r.state.camera);
  r.camera.viewResized();
  assert.equal(r.state.fitted, true);
  r.camera.setCamera(before); // the user moved it
  const moved = cloneCamera(r.state.camera);
  r.camera.viewResized();
  assert.deepEqual(r.state.camera, moved);
  r.camera.setField('camera.parallelProjection', true);
  assert.ok(r.state.camera.parallelScale > 0, 'parallel projection keeps the apparent size');
});

test('url: the link is written once, after the last change, and a pasted link is taken over', () => {
  const state = newState('#dataset=demo:a');
  const location = { hash: '#dataset=demo:a', pathname: '/', search: '' };
  const writes = [];
  const history = {
    state: null,
    replaceState: (s, t, u) => (writes.push(u), (location.hash = u.slice(u.indexOf('#')))),
  };
  const timers = [];
  const url = createUrlController({
    state,
    location,
    history,
    setTimeout: (fn, ms) => timers.push({ fn, ms }) && timers.length,
    clearTimeout: (id) => id && (timers[id - 1].fn = null),
  });
  state.update = { params: { q: 80 } };
  url.schedule();
  url.schedule();
  assert.equal(timers.filter((t) => t.fn).length, 1, 'the earlier write was cancelled');
  assert.equal(timers[1].ms, HASH_DELAY_MS);
  timers[1].fn();
  assert.equal(writes.length, 1);
  assert.deepEqual(parseHash(location.hash).update, { params: { q: 80 } });
  assert.equal(url.taken(), null, "the page's own write is not a new link");
  location.hash = '#dataset=demo:b';
  const s = url.taken();
  assert.equal(s.dataset, 'demo:b');
  assert.equal(url.taken(), null, 'taken once');
});

function sessionRig() {
  return sessionRigWith({ terminal: false });
}

function sessionRigWith(conn) {
  const state = newState('#dataset=demo:a&q=80');
  state.datasets = [INFO, { name: 'demo:b', type: 'points', vertices: 5 }];
  const log = [];
  const ui = new Proxy(
    {},
    {
      get:
        (_, k) =>
        (...a) =>
          log.push([k, ...a]),
    },
  );
  const marked = [];
  const panel = {
    setMethods() {},
    setDataset() {},
    markInvalid: (field, text) => (marked.push([field, text]), field.startsWith('params.')),
  };
  const adopted = [];
  let dropped = 0;
  const camera = {
    initial: (info) => fitCamera(cloneCamera(), info.bounds),
    adopt: (c) => ((state.camera = c), adopted.push(c)),
    setCamera: (c) => (state.camera = c),
    drop: () => dropped++,
  };
  const view = { setSize() {}, reset() {}, push() {} };
  const stats = { sent: new Map(), lastMeasuredSeq: 0 };
  const s = createSessionController({
    state,
    stats,
    view,
    camera,
    panel,
    params: { drop: () => dropped++ },
    api: { datasets: () => Promise.resolve([]) },
    conn: () => conn,
    measure: () => ({ width: 320, height: 200, dpr: 2 }),
    timers: { setInterval: () => 1, clearInterval() {}, now: () => 0 },
    ui,
  });
  return { state, s, log, marked, adopted, dropped: () => dropped };
}

test('session: the hello restores dataset, camera, viewport and changes', () => {
  const r = sessionRig();
  const hello = r.s.hello();
  assert.equal(hello.type, 'hello');
  assert.equal(hello.dataset, 'demo:a');
  assert.deepEqual([hello.width, hello.height, hello.devicePixelRatio], [320, 200, 2]);
  assert.deepEqual(hello.params, { q: 80 });
  assert.ok(hello.camera, 'a fitted camera from the start');
  assert.equal(r.state.cameras.size, 1, "the hello's camera is kept as seq 0");
  assert.equal(r.dropped(), 2, 'pending params and camera are dropped: the hello carries them');
});

test('session: ready takes the server defaults and camera; errors go to the field, the banner or the token', () => {
  const r = sessionRig();
  const cam = fitCamera(cloneCamera(), BOUNDS, [1, 0, 0]);
  r.s.handlers.onReady({
    session: 's1',
    dataset: INFO,
    defaults: { params: { q: 60 }, camera: cam },
    stream: { quality: 80 },
    limits: { maxSize: 4096 },
  });
  assert.equal(r.state.session, 's1');
  assert.equal(r.state.dataset, 'demo:a');
  assert.deepEqual(r.adopted[0], cam);
  assert.equal(currentValues(r.state).params.q, 80, "the user's change stays over the default");
  assert.equal(currentValues(r.state).quality, 80);
  assert.ok(r.log.some(([k, key, v]) => k === 'body' && key === 'session' && v === 's1'));
  r.log.length = 0;
  r.s.handlers.onError({ code: 'out_of_range', message: 'params.q: too large', field: 'params.q' }, { fatal: false });
  assert.deepEqual(
    r.marked.map((m) => m[0]),
    ['params.q'],
  );
  assert.equal(r.log.filter(([k]) => k === 'toast').length, 1);
  r.log.length = 0;
  r.s.handlers.onError({ code: 'unknown_dataset', message: 'no such dataset', field: 'dataset' }, { fatal: true });
  const banner = r.log.find(([k]) => k === 'showBanner');
  assert.match(banner[1], /“demo:a” is not available: no such dataset\. Available: demo:a, demo:b\./);
  r.log.length = 0;
  r.s.handlers.onError({ code: 'unauthorized', message: 'token' }, { fatal: true });
  assert.deepEqual(
    r.log.map(([k]) => k),
    ['body', 'askToken'],
  );
  // a ready for the dataset clears the old "not available"
  r.state.error = { code: 'not_found', field: 'dataset' };
  r.s.handlers.onReady({ session: 's2', dataset: INFO, defaults: {} });
  assert.equal(r.state.error, null);
});

test('session: a dataset the server refuses to open takes the page back to the last one, once, with a lasting message', () => {
  let started = 0;
  const rig = sessionRigWith({ terminal: false, ready: false, start: () => started++ });
  rig.s.handlers.onReady({ session: 's1', dataset: INFO, defaults: {} });
  rig.state.dataset = 'demo:b'; // the picker chose it; its hello is refused before ready
  rig.log.length = 0;
  rig.s.handlers.onError(
    { code: 'too_expensive', message: 'width: estimated cost 2e9 exceeds the budget', field: 'width' },
    { fatal: true },
  );
  assert.equal(rig.state.dataset, 'demo:a', 'back to the dataset that last opened');
  const banner = rig.log.find(([k]) => k === 'showBanner');
  assert.match(
    banner[1],
    /“demo:b” was not opened: width: estimated cost 2e9 exceeds the budget\. Showing “demo:a” again\./,
  );
  assert.ok(
    rig.log.some(([k]) => k === 'showDataset'),
    'the picker shows the dataset in view',
  );
  assert.equal(started, 0, 'no reconnect before this connection has ended');
  rig.s.handlers.onState('stopped', { reason: 'refused' });
  assert.equal(started, 1, 'one new session for the last dataset');
  rig.s.handlers.onState('stopped', { reason: 'again' });
  assert.equal(started, 1, 'and no loop');
  rig.log.length = 0;
  rig.s.handlers.onReady({ session: 's2', dataset: INFO, defaults: {} });
  assert.ok(!rig.log.some(([k]) => k === 'hideBanner'), 'the message stays once the last dataset is back');
  // a first dataset refused (nothing opened before): the banner, no reopening
  const first = sessionRigWith({ terminal: false, ready: false, start: () => started++ });
  first.s.handlers.onError({ code: 'too_expensive', message: 'too costly', field: 'width' }, { fatal: true });
  first.s.handlers.onState('stopped', { reason: 'refused' });
  assert.equal(started, 1);
  assert.equal(first.state.dataset, 'demo:a');
});

test('session: connection states reset the frame bookkeeping and keep the retry delays', () => {
  const r = sessionRig();
  r.state.seq = 7;
  r.state.lastFrame = { frame: 3 };
  r.s.handlers.onState('connecting', { attempt: 1 });
  assert.equal(r.state.seq, 0);
  assert.equal(r.state.lastFrame, null);
  r.s.handlers.onState('waiting', { delay: 500, reason: 'closed', attempt: 1 });
  assert.deepEqual(r.state.retryDelays, [500]);
  assert.ok(r.log.some(([k, , text]) => k === 'connection' && /retrying in 1 s/.test(text)));
  r.s.handlers.onState('open', {});
  assert.deepEqual(r.state.retryDelays, []);
});

test('session: progress messages show a bar until the frame comes, and nothing after it', () => {
  const r = sessionRig();
  const shown = () => r.log.filter(([k]) => k === 'progress').map(([, p]) => p);
  r.s.handlers.onReady({ session: 's1', dataset: INFO, defaults: {} });
  r.log.length = 0;
  r.s.handlers.onProgress({ type: 'progress', stage: 'queued', fraction: null, elapsed: 0.3 });
  r.s.handlers.onProgress({ type: 'progress', stage: 'opticalDepth', fraction: 0.5, elapsed: 1.25 });
  assert.deepEqual(shown(), [
    { stage: 'queued', fraction: null, elapsed: 0.3, text: 'Waiting for a render worker · 0.3 s' },
    { stage: 'opticalDepth', fraction: 0.5, elapsed: 1.25, text: 'Optical depth 50% · 1.3 s' },
  ]);
  assert.deepEqual(r.state.progress, { stage: 'opticalDepth', fraction: 0.5, elapsed: 1.25 });
  // the frame hides the bar once, and is still shown
  r.log.length = 0;
  const view = r.s.handlers.onFrame;
  view({ header: { frame: 1 } });
  view({ header: { frame: 2 } });
  assert.deepEqual(shown(), [null], 'hidden once when the frame comes, not again for later frames');
  assert.equal(r.state.progress, null);
  // an unknown stage is shown by its name; a fraction out of range is clamped
  r.log.length = 0;
  r.s.handlers.onProgress({ type: 'progress', stage: 'tiles', fraction: 1.5, elapsed: 2 });
  assert.equal(shown()[0].text, 'tiles 100% · 2.0 s');
  // a failed frame or a lost connection hides it as well
  r.log.length = 0;
  r.s.handlers.onError({ code: 'render_failed', message: 'GL error' }, { fatal: false });
  assert.deepEqual(shown(), [null]);
  r.s.handlers.onProgress({ type: 'progress', stage: 'accumulate', fraction: 0.7, elapsed: 3 });
  r.log.length = 0;
  r.s.handlers.onState('connecting', { attempt: 1 });
  assert.deepEqual(shown(), [null]);
});

test('session: after stage 1 of a staged still, the progress says the refinement is stage 2 of 2', () => {
  const r = sessionRig();
  const shown = () => r.log.filter(([k]) => k === 'progress').map(([, p]) => p);
  r.s.handlers.onReady({ session: 's1', dataset: INFO, defaults: {} });
  r.s.handlers.onFrame({ header: { frame: 1, stage: 1, stages: 2, final: false } });
  r.log.length = 0;
  r.s.handlers.onProgress({ type: 'progress', stage: 'importance', fraction: 0.25, elapsed: 0.5 });
  assert.equal(shown()[0].text, 'Refining, stage 2 of 2: Importance 25% · 0.5 s');
  assert.deepEqual(r.state.progress.refine, { stage: 2, stages: 2 });
  // the final stage (or a moving frame) ends it: later progress is a plain frame's
  r.s.handlers.onFrame({ header: { frame: 2, stage: 2, stages: 2, final: true } });
  r.log.length = 0;
  r.s.handlers.onProgress({ type: 'progress', stage: 'opacity', fraction: 0.5, elapsed: 0.4 });
  assert.equal(shown()[0].text, 'Opacities 50% · 0.4 s');
  assert.equal(r.state.progress.refine, undefined);
});

test('progress text: stage words, per cent when known, seconds so far', () => {
  assert.equal(progressText({ stage: 'prepare', fraction: null, elapsed: 0.42 }), 'Preparing the frame · 0.4 s');
  assert.equal(progressText({ stage: 'encode', fraction: 1, elapsed: 10 }), 'Encoding 100% · 10.0 s');
});

test('datasets: the picker model, descriptions and sizes', () => {
  assert.equal(describeDataset(INFO), '12,000 lines, 3,000,000 vertices, 2,000 elements');
  assert.equal(shortSize(INFO), '12k lines');
  assert.equal(shortSize({ vertices: 2500000 }), '2.5M points');
  const state = newState('#dataset=demo:x');
  state.datasets = [INFO];
  let m = datasetView(state);
  assert.deepEqual(m.options, [
    ['demo:x', 'demo:x (unknown)'],
    ['demo:a', 'demo:a · 12k lines'],
  ]);
  assert.equal(m.details, null);
  state.dataset = 'demo:a';
  m = datasetView(state);
  assert.deepEqual(m.details.attributes, ['speed [2, 10]', 'flat [4, 4]']);
});

test('datasets: a preset goes under the link, says so, and undo takes it back out', () => {
  const state = newState('#dataset=demo:a&r=100');
  state.datasets = [
    { ...INFO, preset: { params: { q: 70, r: 900 }, color: { colormap: 'plasma' } } },
    { name: 'demo:b' },
  ];
  const log = [];
  const ui = new Proxy(
    {},
    {
      get:
        (_, k) =>
        (...a) =>
          log.push([k, ...a]),
    },
  );
  const d = createDatasetController({ state, camera: { initial: () => null }, ui });
  d.usePreset({ update: state.update, camera: null });
  assert.deepEqual(state.update.params, { q: 70, r: 100 }, "the link's r wins over the preset's");
  assert.equal(state.update.color.colormap, 'plasma');
  assert.ok(log.some(([k, title]) => k === 'showPresetNote' && /params\.q/.test(title)));
  assert.equal(d.undoPreset(), true);
  assert.deepEqual(state.update.params, { r: 100 });
  assert.equal(state.update.color, undefined);
  assert.equal(d.undoPreset(), false, 'nothing left to undo');
  // choosing another dataset drops the old attributes and refits
  state.update.importance = { attribute: 'speed' };
  state.camera = fitCamera(cloneCamera(), BOUNDS);
  d.choose('demo:b');
  assert.equal(state.update.importance, undefined);
  assert.equal(state.camera, null);
  assert.equal(d.checkDataset(), false);
  state.dataset = 'demo:zz';
  assert.equal(d.checkDataset(), true);
  assert.ok(log.some(([k, text]) => k === 'showBanner' && /demo:zz/.test(text)));
});

test('session: the hello asks for a background that contrasts with the colormap unless one was chosen', () => {
  let r = sessionRig();
  assert.deepEqual(r.s.hello().style, { background: [0.1, 0.1, 0.1] }, "viridis' yellow end: dark");
  assert.deepEqual(currentValues(r.state).style.background, [0.1, 0.1, 0.1], 'the panel and legend show it');
  r = sessionRig();
  r.state.update = { ...r.state.update, color: { colormap: 'turbo' } };
  assert.deepEqual(r.s.hello().style, { background: [1, 1, 1] }, "turbo's dark red end: white");
  r = sessionRig();
  r.state.update = { ...r.state.update, style: { background: [1, 1, 1], lineWidth: 0.01 } };
  assert.deepEqual(r.s.hello().style, { background: [1, 1, 1], lineWidth: 0.01 }, 'a chosen background wins');
  assert.deepEqual(r.state.pageDefaults, {});
});
