// Lucent's web client: wires the WebSocket session, the canvas, navigation, the
// settings panel, the statistics overlay and the URL hash together. The page's
// state is one object (`state`); every module below is told about changes
// through it and the server is the judge of every value (defaults come from its
// ready message, its errors are shown as they are).

import { helloMessage, cameraMessage, paramsMessage, resizeMessage, ackMessage, describeError, DEFAULT_WINDOW, tokenSubprotocols } from './js/protocol.js';
import { DEFAULT_CAMERA, flatBounds, cloneCamera, fitCamera, refitCamera, viewAlongAxis, validateCamera, roundCamera } from './js/camera.js';
import { parseHash, formatHash, tokenFromLocation } from './js/url-state.js';
import { getPath, setPath, merge, UPDATE_SECTIONS, STREAM_FIELDS } from './js/schema.js';
import { Connection } from './js/connection.js';
import { FrameView } from './js/view.js';
import { Navigation } from './js/navigation.js';
import { Panel, GROUPS, attributeRange } from './js/ui.js';
import { FrameStats, renderStats, formatBytes } from './js/stats.js';
import { Api, ApiError } from './js/api.js';
import { Legend } from './js/legend.js';
import { AxesTriad } from './js/axes.js';
import { applyPreset, removePreset } from './js/preset.js';
import { rgbToHex } from './js/ui.js';

const $ = (id) => document.getElementById(id);
const TOKEN_KEY = 'lucent.token';

const initial = parseHash(location.hash);
const state = {
  dataset: initial.dataset, // requested or current dataset name (null = server default)
  datasets: [], // descriptions from GET /api/v1/datasets
  info: null, // ready.dataset
  defaults: null, // ready.defaults (a render request)
  stream: null, // ready.stream
  limits: null, // ready.limits
  session: null,
  camera: initial.camera && !validateCamera(cloneCamera(initial.camera)) ? cloneCamera(initial.camera) : null,
  update: initial.update, // the user's changes to the defaults (sections, method, stream settings)
  seq: 0, // last camera seq sent
  confirmedSeq: 0, // newest cameraSeq a drawn frame reflects
  lastFrame: null, // header of the newest drawn frame
  framesDrawn: 0,
  token: tokenFromLocation(location.search, location.hash) ?? sessionStorage.getItem(TOKEN_KEY),
  error: null, // last error shown {code, message}
  viewport: { width: 0, height: 0, dpr: 1 },
  cameras: new Map(), // camera seq -> the camera sent with it (0: the hello's), to warp frames
  fitted: false, // the camera is a fit the user has not moved since: refit when the view's shape changes
  preset: null, // {dataset, preset, applied, cameraApplied} of the preset in effect
  responses: [], // input -> warped picture on screen, ms (the newest 200)
  retryDelays: [], // reconnection delays chosen, ms
};
if (initial.errors.length) queueMicrotask(() => toast(`Ignored in the link: ${initial.errors.join('; ')}`));
const linkAtStart = { update: merge({}, initial.update), camera: state.camera }; // the preset goes under these

const base = new URL('.', location.href);
const wsUrl = new URL('api/v1/ws', base);
wsUrl.protocol = location.protocol === 'https:' ? 'wss:' : 'ws:';
const api = new Api(base, () => state.token);
const stats = new FrameStats();

// ---------------------------------------------------------------- view
const canvas = $('canvas');
const view = new FrameView(canvas, {
  ack: (id) => conn.send(ackMessage(id)),
  onDrawn: (frame) => {
    state.lastFrame = frame.header;
    state.framesDrawn++;
    if (frame.header.cameraSeq > state.confirmedSeq) state.confirmedSeq = frame.header.cameraSeq;
    stats.frameDrawn(frame.header, frame.bytes, frame.drawnAt);
    canvas.dataset.frame = String(frame.header.frame);
    canvas.dataset.converged = String(!!frame.header.converged);
    document.body.dataset.frames = String(state.framesDrawn);
    refreshStats();
  },
  onError: (e) => toast(e.message),
  frameCamera: (h) => state.cameras.get(h.cameraSeq) ?? null,
  background: () => rgbToHex(currentValues().style?.background ?? [1, 1, 1]),
});
const axes = new AxesTriad($('axes'), 72);
const legend = new Legend($('legend'), {
  onFlip: () => {
    const r = legend.model?.color.range;
    if (r) applyChange('color.range', [r[1], r[0]]);
  },
});

// ---------------------------------------------------------------- values shown = defaults + stream + user changes
function currentValues() {
  const streamDefaults = state.stream ? { quality: state.stream.quality, interactiveQuality: state.stream.interactiveQuality, interactiveScale: state.stream.interactiveScale } : {};
  return merge(merge(state.defaults ?? {}, streamDefaults), state.update);
}

function showValues() {
  const values = currentValues();
  for (const g of GROUPS) {
    for (const c of g.controls) {
      if (c.path.startsWith('camera.')) continue;
      let v = getPath(values, c.path);
      if (c.path === 'importance.attribute' && !v) v = state.info?.defaultImportance;
      if (c.path === 'color.attribute' && !v) v = state.info?.defaultColor ?? 'importance';
      if (v === undefined && c.path === 'importance.range') v = attributeRange(state.info, values.importance?.attribute || state.info?.defaultImportance, values.params?.normalize);
      if (v === undefined && c.path === 'color.range') {
        const by = values.color?.attribute || state.info?.defaultColor || 'importance';
        v = by === 'importance' ? [0, 1] : attributeRange(state.info, by, values.params?.normalize);
      }
      panel.setValue(c.path, v);
    }
  }
  if (state.camera) {
    panel.setValue('camera.viewAngle', state.camera.viewAngle);
    panel.setValue('camera.parallelProjection', state.camera.parallelProjection);
  }
  panel.setVisible('params.directExponent', values.method === 'direct');
  const colorBy = values.color?.attribute;
  panel.setVisible('color.colormap', colorBy !== 'rgb');
  panel.setVisible('color.range', colorBy !== 'rgb');
  legend.update(values, state.info);
}

// ---------------------------------------------------------------- panel
let pendingParams = null;
let paramsFrame = 0;

const panel = new Panel($('generated'), (path, value) => applyChange(path, value), (text) => toast(text));

/** One edit of a request field (the panel, the legend's flip): to the page's state, the server and the URL. */
function applyChange(path, value) {
  if (path.startsWith('camera.')) {
    if (!state.camera) return;
    const cam = cloneCamera(state.camera);
    cam[path.slice(7)] = value;
    if (path === 'camera.parallelProjection' && value) {
      // keep the apparent size: the half height seen at the focal distance
      const d = Math.hypot(...cam.position.map((p, i) => p - cam.focalPoint[i]));
      cam.parallelScale = d * Math.tan((cam.viewAngle * Math.PI) / 360);
    }
    setCamera(cam);
    return;
  }
  const change = {};
  setPath(change, path, value);
  // a new attribute brings its own range, sent and written into the link (the previous
  // attribute's range would not fit, and the server would keep it); importance is [0, 1]
  if (path === 'importance.attribute' || path === 'color.attribute') {
    const section = path.split('.')[0];
    let r = value === 'importance' && section === 'color' ? [0, 1] : attributeRange(state.info, value, currentValues().params?.normalize);
    if (r && r[0] === r[1]) r = [r[0] - 0.5, r[1] + 0.5];
    if (r) setPath(change, `${section}.range`, r);
    else if (state.update[section]) delete state.update[section].range;
  }
  state.update = merge(state.update, change);
  pendingParams = merge(pendingParams ?? {}, change);
  if (!paramsFrame) paramsFrame = requestAnimationFrame(flushParams);
  showValues();
  scheduleHash();
}

function flushParams() {
  paramsFrame = 0;
  if (!pendingParams) return;
  const update = pendingParams;
  pendingParams = null;
  try {
    const msg = paramsMessage(update);
    if (!conn.send(msg)) return; // the next hello carries state.update
    document.body.dataset.paramsSent = String(Number(document.body.dataset.paramsSent ?? 0) + 1);
  } catch (e) {
    toast(e.message);
  }
}

// ---------------------------------------------------------------- camera: one message per animation frame, latest wins
let cameraFrame = 0;
let cameraDirty = false;

/**
 * The page's camera changed: the triad and the warped last frame follow at once
 * (input → visible response without a server round trip), the server gets it on
 * the next animation frame. opts.at: the input event's time stamp (for the
 * response measurement); opts.fitted: the camera is a fit (refit on resize).
 */
function setCamera(cam, { at, fitted = false } = {}) {
  if (validateCamera(cam)) return; // a degenerate camera from extreme input: keep the previous one
  state.camera = cam;
  state.fitted = fitted;
  axes.update(cam);
  const painted = view.setCamera(cam);
  if (at !== undefined && painted) {
    requestAnimationFrame(() => {
      state.responses.push(performance.now() - at);
      if (state.responses.length > 200) state.responses.shift();
    });
  }
  cameraDirty = true;
  if (!cameraFrame) cameraFrame = requestAnimationFrame(flushCamera);
  scheduleHash();
}

function flushCamera() {
  cameraFrame = 0;
  if (!cameraDirty || !state.camera) return;
  cameraDirty = false;
  if (!conn.isOpen) return;
  const seq = ++state.seq;
  const cam = roundCamera(state.camera, 12);
  conn.send(cameraMessage(seq, cam));
  state.cameras.set(seq, cam);
  if (state.cameras.size > 64) state.cameras.delete(state.cameras.keys().next().value);
  stats.cameraSent(seq);
}

function bounds() {
  return flatBounds(state.info?.bounds);
}

/**
 * The camera a new view starts from: the dataset's suggested view when its
 * description carries one (view.direction/up or viewDirection/viewUp), else
 * ParaView's default (looking down -Z, +Y up), fitted as lc_camera_fit does.
 */
function initialCamera(info) {
  const b = flatBounds(info?.bounds);
  if (!b) return null;
  const dir = info.view?.direction ?? info.viewDirection;
  const up = info.view?.up ?? info.viewUp;
  return fitCamera(DEFAULT_CAMERA, b, Array.isArray(dir) ? dir : undefined, Array.isArray(up) ? up : undefined, aspect());
}

/** width / height of the view (fits use the narrower angle of a portrait view). */
function aspect() {
  const v = state.viewport.width ? state.viewport : measure();
  return v.width / v.height;
}

function toggleFullscreen() {
  if (document.fullscreenElement) document.exitFullscreen?.().catch(() => {});
  else $('view').requestFullscreen?.().catch((e) => toast(`Fullscreen is not available: ${e.message}`));
}

function command(name) {
  if (name === 'fullscreen') return toggleFullscreen();
  const b = bounds();
  if (!b || !state.camera) return;
  let cam;
  if (name === 'home') {
    cam = initialCamera(state.info);
    if (!cam) return;
    cam.viewAngle = state.camera.viewAngle;
    cam.parallelProjection = state.camera.parallelProjection;
    cam = fitCamera(cam, b, cam.focalPoint.map((f, i) => f - cam.position[i]), cam.viewUp, aspect());
  } else if (name === 'reset') cam = refitCamera(state.camera, b, aspect());
  else cam = viewAlongAxis(state.camera, b, name, aspect());
  setCamera(cam, { fitted: true });
}

new Navigation(canvas, {
  getCamera: () => state.camera,
  onCamera: setCamera,
  onCommand: command,
});
for (const btn of document.querySelectorAll('[data-view]')) btn.addEventListener('click', () => command(btn.dataset.view));

// ---------------------------------------------------------------- URL hash (replaceState, so no history spam)
let hashTimer = 0;
let lastHash = location.hash;
function scheduleHash() {
  clearTimeout(hashTimer);
  hashTimer = setTimeout(writeHash, 200);
}
function writeHash() {
  hashTimer = 0;
  // every value the user changed, even one equal to a default: ready.defaults already holds the hello's values
  const hash = formatHash({ dataset: state.dataset, camera: state.camera, update: state.update });
  if (hash !== location.hash) {
    history.replaceState(history.state, '', `${location.pathname}${location.search}${hash}`);
  }
  lastHash = location.hash;
}
window.addEventListener('hashchange', () => {
  if (location.hash === lastHash) return;
  // a pasted or edited link: take it over as a fresh start, as a fresh load would
  const s = parseHash(location.hash);
  if (s.token) setToken(s.token);
  if (s.errors.length) toast(`Ignored in the link: ${s.errors.join('; ')}`);
  state.update = s.update;
  state.camera = s.camera && !validateCamera(cloneCamera(s.camera)) ? cloneCamera(s.camera) : null;
  const switched = s.dataset && s.dataset !== state.dataset;
  if (s.dataset) state.dataset = s.dataset;
  state.info = state.datasets.find((d) => d.name === state.dataset) ?? null;
  if (switched) view.clear();
  // the old error (an unknown dataset, a refused value) is about the old link
  hideBanner();
  state.error = null;
  hidePresetNote();
  usePreset({ update: s.update, camera: state.camera });
  if (!checkDataset()) showDataset();
  lastHash = location.hash;
  conn.start();
});

// ---------------------------------------------------------------- viewport
function measure() {
  const r = $('view').getBoundingClientRect();
  const dpr = Math.min(Math.max(window.devicePixelRatio || 1, 0.25), 8);
  return { width: Math.max(16, Math.round(r.width)), height: Math.max(16, Math.round(r.height)), dpr };
}
let resizeFrame = 0;
function onResize() {
  if (resizeFrame) return;
  resizeFrame = requestAnimationFrame(() => {
    resizeFrame = 0;
    const v = measure();
    const old = state.viewport;
    if (v.width === old.width && v.height === old.height && v.dpr === old.dpr) return;
    state.viewport = v;
    view.setSize(Math.round(v.width * v.dpr), Math.round(v.height * v.dpr));
    conn.send(resizeMessage(v.width, v.height, v.dpr));
    // a view the user has not moved since it was fitted is fitted again to its new shape
    // (folding the panel away on a phone makes the view taller and narrower than the fit)
    const b = bounds();
    if (b && state.camera && state.fitted) setCamera(refitCamera(state.camera, b, aspect()), { fitted: true });
  });
}
new ResizeObserver(onResize).observe($('view'));
let dprQuery = null;
function watchDpr() {
  dprQuery?.removeEventListener('change', watchDpr);
  dprQuery = matchMedia(`(resolution: ${window.devicePixelRatio}dppx)`);
  dprQuery.addEventListener('change', watchDpr);
  onResize();
}
watchDpr();

// ---------------------------------------------------------------- connection
function hello() {
  // send a camera from the start, so that the page and the server agree on it before the first drag
  if (!state.camera) {
    state.camera = initialCamera(state.datasets.find((d) => d.name === state.dataset));
    state.fitted = !!state.camera;
  }
  state.cameras.clear();
  if (state.camera) {
    state.cameras.set(0, roundCamera(state.camera, 12));
    // the view warps toward this camera from now on (not toward the previous dataset's)
    axes.update(state.camera);
    view.setCamera(state.camera);
  }
  state.viewport = measure();
  const v = state.viewport;
  view.setSize(Math.round(v.width * v.dpr), Math.round(v.height * v.dpr));
  const msg = { dataset: state.dataset ?? undefined, width: v.width, height: v.height, devicePixelRatio: v.dpr, window: DEFAULT_WINDOW, token: state.token ?? undefined };
  if (state.camera) msg.camera = roundCamera(state.camera, 12);
  for (const s of UPDATE_SECTIONS) if (state.update[s] && Object.keys(state.update[s]).length) msg[s] = state.update[s];
  if (state.update.method) msg.method = state.update.method;
  for (const f of STREAM_FIELDS) if (state.update[f.name] !== undefined) msg[f.name] = state.update[f.name];
  pendingParams = null; // the hello carries them
  cameraDirty = false;
  return helloMessage(msg);
}

let countdown = 0;
const conn = new Connection(wsUrl.href, hello, {
  // the server refuses an upgrade without the token, so it goes with the handshake
  protocols: () => tokenSubprotocols(state.token),
  onState(s, detail) {
    const el = $('connection');
    el.dataset.state = s;
    clearInterval(countdown);
    document.body.dataset.connection = s;
    if (s === 'connecting') {
      el.textContent = detail.attempt ? 'Reconnecting…' : 'Connecting…';
      view.reset();
      state.lastFrame = null; // frames of the new session only
      state.seq = 0;
      state.confirmedSeq = 0;
      stats.lastMeasuredSeq = 0;
      stats.sent.clear();
    } else if (s === 'open') {
      el.textContent = 'Connected';
      state.retryDelays = [];
      if (state.error?.kind === 'connection') hideBanner();
    } else if (s === 'waiting') {
      state.retryDelays.push(detail.delay);
      if (state.retryDelays.length > 50) state.retryDelays.shift();
      // a refused handshake (401) only shows as a closed socket: ask the API why
      api.datasets().catch((e) => {
        if (e instanceof ApiError && (e.status === 401 || e.code === 'unauthorized')) {
          askToken(state.token ? 'The token was not accepted.' : 'This server requires an access token.');
        }
      });
      const until = performance.now() + detail.delay;
      const tick = () => {
        const left = Math.max(0, Math.ceil((until - performance.now()) / 1000));
        el.textContent = `Disconnected — retrying in ${left} s`;
        showBanner(`Connection to the server lost: ${detail.reason}. Reconnecting in ${left} s (attempt ${detail.attempt})…`, { retry: true, kind: 'connection' });
      };
      tick();
      countdown = setInterval(tick, 1000);
    } else if (s === 'stopped') {
      el.textContent = 'Disconnected';
    }
  },
  onReady(msg) {
    state.lastReady = msg;
    state.session = msg.session;
    state.info = msg.dataset && typeof msg.dataset === 'object' ? msg.dataset : state.datasets.find((d) => d.name === state.dataset) ?? null;
    state.defaults = msg.defaults ?? {};
    state.stream = msg.stream ?? null;
    state.limits = msg.limits ?? null;
    state.dataset = state.info?.name ?? msg.defaults?.dataset ?? state.dataset;
    if (msg.defaults?.camera && !validateCamera(cloneCamera(msg.defaults.camera))) {
      state.camera = cloneCamera(msg.defaults.camera);
      axes.update(state.camera);
      view.setCamera(state.camera);
    } else if (!state.camera) {
      // the server fits the data itself; take the same fit and tell it, so both agree from here on
      state.camera = initialCamera(state.info);
      if (state.camera) setCamera(state.camera, { fitted: true });
    }
    if (state.error && (state.error.code === 'not_found' || state.error.field === 'dataset')) {
      hideBanner(); // a session for this dataset exists: an old "not available" no longer holds
      state.error = null;
    }
    panel.setMethods(msg.methods ?? state.health?.methods);
    panel.setDataset(state.info);
    showDataset();
    showValues();
    writeHash();
    document.body.dataset.session = String(msg.session);
    document.body.dataset.dataset = state.dataset ?? '';
  },
  onFrame(frame) {
    view.push(frame);
  },
  onStats(msg) {
    stats.server = Object.fromEntries(Object.entries(msg).filter(([k]) => k !== 'type'));
    if (typeof msg.renderer === 'string') stats.renderer = msg.renderer;
    state.serverStats = msg;
  },
  onError(msg, { fatal }) {
    state.error = { code: msg.code, message: msg.message, field: msg.field ?? '' };
    document.body.dataset.lastError = msg.code;
    if (msg.code === 'unauthorized') {
      askToken(state.token ? 'The token was not accepted.' : 'This server requires an access token.');
      return;
    }
    const field = msg.field ?? '';
    if (!fatal && field && panel.markInvalid(field, describeError(msg))) {
      toast(`Not applied — ${describeError(msg)}`);
      return;
    }
    if (fatal || /dataset/.test(msg.code) || msg.code === 'not_found') {
      let text = describeError(msg);
      if (/dataset/.test(msg.code) || msg.code === 'not_found' || field === 'dataset') {
        const names = state.datasets.map((d) => d.name).join(', ');
        const why = /[.!?]$/.test(msg.message) ? msg.message : `${msg.message}.`;
        text = `Dataset “${state.dataset ?? ''}” is not available: ${why}${names ? ` Available: ${names}.` : ''}`;
        showDataset();
      }
      showBanner(text, { retry: !conn.terminal, kind: 'error' });
    } else {
      toast(describeError(msg));
    }
  },
});

// ---------------------------------------------------------------- dataset picker
function describeDataset(d) {
  if (!d) return '';
  const n = (x) => (typeof x === 'number' ? x.toLocaleString('en-US') : x);
  const parts = [];
  if (d.type && !d.lines && !d.triangles && !d.vertices) parts.push(d.type);
  if (d.lines) parts.push(`${n(d.lines)} lines`);
  if (d.triangles) parts.push(`${n(d.triangles)} triangles`);
  if (!d.lines && !d.triangles && d.vertices) parts.push(`${n(d.vertices)} points`);
  else if (d.vertices) parts.push(`${n(d.vertices)} vertices`);
  if (d.elements) parts.push(`${n(d.elements)} elements`);
  return parts.join(', ');
}

function shortSize(d) {
  const k = (x) => (x >= 1e6 ? `${Number((x / 1e6).toPrecision(2))}M` : x >= 1e4 ? `${Math.round(x / 1e3)}k` : String(x));
  if (d.lines) return `${k(d.lines)} lines`;
  if (d.triangles) return `${k(d.triangles)} triangles`;
  if (d.vertices) return `${k(d.vertices)} points`;
  return d.type ?? '';
}

function showDataset() {
  const sel = $('dataset');
  const names = state.datasets.map((d) => d.name);
  if (state.dataset && !names.includes(state.dataset)) names.unshift(state.dataset);
  // the option says name and size only (it must fit a phone's picker); the line below has the details
  const wanted = names.map((n) => {
    const d = state.datasets.find((x) => x.name === n);
    return [n, d ? `${n} · ${shortSize(d)}` : `${n} (unknown)`];
  });
  const same = sel.options.length === wanted.length && wanted.every(([v, t], i) => sel.options[i].value === v && sel.options[i].text === t);
  if (!same) sel.replaceChildren(...wanted.map(([v, t]) => new Option(t, v)));
  if (state.dataset) sel.value = state.dataset;
  const d = state.info?.name === state.dataset ? state.info : state.datasets.find((x) => x.name === state.dataset);
  $('dataset-title').textContent = state.dataset ?? '';
  const info = $('dataset-info');
  info.replaceChildren();
  if (!d) return;
  if (d.description) info.append(Object.assign(document.createElement('span'), { className: 'desc', textContent: d.description }));
  info.append(Object.assign(document.createElement('span'), { textContent: describeDataset(d) }));
  const attrs = (d.attributes ?? []).map((a) => (typeof a === 'string' ? a : `${a.name}${Array.isArray(a.range) ? ` [${a.range.map((x) => Number(x.toPrecision(3))).join(', ')}]` : ''}`));
  if (attrs.length) {
    const ul = document.createElement('ul');
    ul.className = 'attributes';
    ul.setAttribute('aria-label', 'Attributes');
    for (const a of attrs) ul.append(Object.assign(document.createElement('li'), { textContent: a }));
    info.append(ul);
  }
}

$('dataset').addEventListener('change', (e) => {
  state.dataset = e.target.value;
  state.camera = null; // fit the new data
  state.info = state.datasets.find((d) => d.name === state.dataset) ?? null;
  view.clear();
  // attributes belong to the old dataset, and so does the old preset
  delete state.update.importance;
  delete state.update.color;
  if (state.preset) state.update = removePreset(state.update, state.preset.preset, state.preset.applied);
  hideBanner();
  state.error = null;
  usePreset({ update: state.update, camera: null });
  writeHash();
  conn.start();
});

// ---------------------------------------------------------------- per-dataset presets
/**
 * Puts the chosen dataset's preset (its description's "preset") under the
 * given link values (the link wins), into state.update and state.camera, and
 * says so with an undo. link: {update, camera}.
 */
function usePreset(link) {
  hidePresetNote();
  state.preset = null;
  const preset = state.datasets.find((d) => d.name === state.dataset)?.preset;
  if (!preset || typeof preset !== 'object') return;
  const r = applyPreset(preset, link.update, link.camera);
  if (r.errors.length) toast(`Preset of ${state.dataset}: ignored ${r.errors.join('; ')}`);
  if (!r.applied.length && !r.cameraApplied) return;
  state.update = r.update;
  if (r.cameraApplied) {
    const home = initialCamera(state.datasets.find((d) => d.name === state.dataset));
    const cam = cloneCamera({ ...(home ?? {}), ...r.camera });
    if (!validateCamera(cam)) {
      state.camera = cam;
      state.fitted = false;
    }
  }
  state.preset = { dataset: state.dataset, preset, applied: r.applied, cameraApplied: r.cameraApplied };
  const what = [...r.applied, ...(r.cameraApplied ? ['camera'] : [])];
  $('preset-text').textContent = 'Preset applied';
  $('preset-note').title = `The preset of ${state.dataset} set ${what.join(', ')}; “undo” goes back to the server's defaults`;
  $('preset-note').hidden = false;
  document.body.dataset.preset = state.dataset;
}
function hidePresetNote() {
  $('preset-note').hidden = true;
}
$('preset-close').addEventListener('click', hidePresetNote);
$('preset-undo').addEventListener('click', () => {
  const p = state.preset;
  hidePresetNote();
  if (!p) return;
  state.update = removePreset(state.update, p.preset, p.applied);
  if (p.cameraApplied) state.camera = null; // back to the dataset's own view
  state.preset = null;
  delete document.body.dataset.preset;
  toast(`Preset for ${p.dataset} undone: the server's defaults apply.`);
  writeHash();
  conn.start(); // a fresh session: its defaults replace what the preset had set
});

/** An unknown dataset in the link is said at once (the server's answer to hello confirms it). Returns true when shown. */
function checkDataset() {
  if (state.dataset && state.datasets.length && !state.datasets.some((d) => d.name === state.dataset)) {
    showBanner(`Dataset “${state.dataset}” is not available on this server. Available: ${state.datasets.map((d) => d.name).join(', ')}.`, { kind: 'error' });
    showDataset();
    return true;
  }
  return false;
}

// ---------------------------------------------------------------- banner, toast, token
function showBanner(text, { retry = false, kind = 'error' } = {}) {
  $('banner-text').textContent = text;
  $('banner-retry').hidden = !retry;
  $('banner').hidden = false;
  $('banner').dataset.kind = kind;
  state.error = { ...(state.error ?? {}), kind, text };
}
function hideBanner() {
  $('banner').hidden = true;
}
$('banner-close').addEventListener('click', hideBanner);
$('banner-retry').addEventListener('click', () => {
  hideBanner();
  conn.start();
});

let toastTimer = 0;
function toast(text) {
  const el = $('toast');
  el.textContent = text;
  el.hidden = false;
  clearTimeout(toastTimer);
  toastTimer = setTimeout(() => (el.hidden = true), 6000);
}

function setToken(t) {
  state.token = t || null;
  if (t) sessionStorage.setItem(TOKEN_KEY, t);
  else sessionStorage.removeItem(TOKEN_KEY);
}

let tokenWaiters = [];
function askToken(reason) {
  const dlg = $('token-dialog');
  $('token-reason').textContent = reason;
  conn.stop('waiting for a token');
  if (!dlg.open) {
    $('token-input').value = '';
    dlg.showModal();
  }
  showBanner(`${reason} Enter it to connect.`, { retry: true, kind: 'auth' });
  return new Promise((resolve) => tokenWaiters.push(resolve));
}
$('token-dialog').addEventListener('close', () => {
  const dlg = $('token-dialog');
  const ok = dlg.returnValue === 'ok' && $('token-input').value;
  if (ok) {
    setToken($('token-input').value);
    hideBanner();
    start();
  }
  const waiters = tokenWaiters;
  tokenWaiters = [];
  for (const w of waiters) w(ok);
});

// ---------------------------------------------------------------- share and save
$('copy-link').addEventListener('click', async () => {
  writeHash();
  const link = location.href;
  try {
    await navigator.clipboard.writeText(link);
    toast('Link copied to the clipboard.');
  } catch {
    window.prompt('Copy this link:', link);
  }
});

$('shot-size').addEventListener('change', () => ($('shot-custom').hidden = $('shot-size').value !== 'custom'));

function screenshotSize() {
  const v = $('shot-size').value;
  if (v === 'view') return [canvas.width, canvas.height];
  if (v === 'custom') return [Number($('shot-width').value), Number($('shot-height').value)];
  return v.split('x').map(Number);
}

/** The render request of the current view at a given size (POST /api/v1/render). */
function renderRequest(width, height) {
  const values = currentValues();
  const req = { dataset: state.dataset, width, height, format: 'png' };
  if (values.method) req.method = values.method;
  if (state.camera) req.camera = roundCamera(state.camera, 12);
  for (const s of UPDATE_SECTIONS) if (values[s]) req[s] = values[s];
  return req;
}

$('screenshot').addEventListener('click', async () => {
  const btn = $('screenshot');
  const [w, h] = screenshotSize();
  const lim = state.limits ?? {};
  const lo = lim.minSize ?? 16, hi = lim.maxSize ?? 4096;
  if (!(Number.isInteger(w) && Number.isInteger(h) && w >= lo && h >= lo && w <= hi && h <= hi)) {
    toast(`Screenshot size must be whole numbers between ${lo} and ${hi}.`);
    return;
  }
  btn.disabled = true;
  btn.textContent = 'Rendering…';
  try {
    const { blob } = await api.render(renderRequest(w, h));
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    const safe = (state.dataset ?? 'view').replace(/[^A-Za-z0-9._-]+/g, '-');
    a.download = `lucent-${safe}-${w}x${h}.png`;
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 10000);
    toast(`Saved ${a.download} (${formatBytes(blob.size)}).`);
  } catch (e) {
    if (e instanceof ApiError && e.code === 'unauthorized') askToken('This server requires an access token.');
    else showBanner(`Screenshot failed: ${e.message}`, { kind: 'error' });
  } finally {
    btn.disabled = false;
    btn.textContent = 'Save PNG';
  }
});

$('reset-params').addEventListener('click', () => {
  // a fresh session without the user's changes (or a preset's): its ready message brings the server's defaults
  state.update = {};
  state.preset = null;
  hidePresetNote();
  writeHash();
  conn.start();
});

// ---------------------------------------------------------------- stats: one line, the full table on demand
const statsLine = $('stats');
const statsEl = $('stats-full');
const showStats = $('show-stats');
function statsVisible(full) {
  showStats.checked = full;
  statsEl.hidden = !full;
  statsLine.setAttribute('aria-expanded', String(full));
  refreshStats();
}
showStats.addEventListener('change', () => statsVisible(showStats.checked));
statsLine.addEventListener('click', () => statsVisible(statsEl.hidden));
let statsFrame = 0;
function refreshStats() {
  if (statsFrame) return;
  statsFrame = requestAnimationFrame(() => {
    statsFrame = 0;
    statsLine.textContent = stats.summary();
    if (!statsEl.hidden) renderStats(statsEl, stats);
  });
}
setInterval(refreshStats, 250); // fps decays when frames stop

$('panel-toggle').addEventListener('click', () => {
  const collapsed = document.body.classList.toggle('panel-collapsed');
  $('panel-toggle').setAttribute('aria-expanded', String(!collapsed));
  onResize(); // the view changes shape; a fitted camera is fitted to it again
});
$('show-help').addEventListener('change', (e) => $('panel').classList.toggle('explain', e.target.checked));

// ---------------------------------------------------------------- help overlay (?)
const help = $('help');
function toggleHelp() {
  if (help.open) help.close();
  else help.showModal();
}
$('help-button').addEventListener('click', toggleHelp);
document.addEventListener('keydown', (e) => {
  if (e.key !== '?' || e.ctrlKey || e.metaKey || e.altKey) return;
  const t = e.target;
  if (t instanceof HTMLInputElement || t instanceof HTMLTextAreaElement || t instanceof HTMLSelectElement) return;
  e.preventDefault();
  toggleHelp();
});

// ---------------------------------------------------------------- start
async function start() {
  try {
    state.datasets = await api.datasets();
  } catch (e) {
    if (e instanceof ApiError && (e.status === 401 || e.code === 'unauthorized')) {
      askToken(state.token ? 'The token was not accepted.' : 'This server requires an access token.');
      return;
    }
    // the WebSocket may still work (or will report the problem itself)
    toast(`Dataset list unavailable: ${e.message}`);
  }
  api.health().then((h) => {
    state.health = h;
    const r = h?.renderer ?? h?.gl?.renderer;
    if (typeof r === 'string') stats.renderer = r;
    if (Array.isArray(h?.methods)) panel.setMethods(h.methods);
  }, () => {});
  checkDataset();
  if (!state.dataset && state.datasets.length) state.dataset = state.datasets[0].name;
  usePreset(linkAtStart);
  showDataset();
  conn.start();
}

// Read-only view of the page for tests and the console.
window.lucent = {
  get state() {
    return state;
  },
  get stats() {
    return stats;
  },
  get camera() {
    return state.camera ? cloneCamera(state.camera) : null;
  },
  values: currentValues,
  renderRequest,
  /** Input → warped picture on screen (ms), the newest samples. */
  get responses() {
    return [...state.responses];
  },
  get view() {
    return { warped: view.warped, canvasFrame: view.lastDrawn };
  },
  /** Drops the connection and opens a new session from the page's state (as after a lost connection). */
  reconnect: () => conn.start(),
};

start();
