// Lucent's web client: createApp() wires the WebSocket session, the canvas,
// navigation, the settings panel, the statistics overlay and the URL hash
// together. The page's state is one object (js/app-state.js); the controllers
// that change it have no DOM of their own and are tested in node (web/test/):
// js/params-controller.js (panel edits), js/camera-controller.js (view and
// camera input), js/session-controller.js (the stream: hello, ready, frames,
// stats, errors), js/url-controller.js (the link), js/dataset-controller.js
// (picker and presets). This file only builds the page's parts and connects
// them. The server is the judge of every value (defaults come from its ready
// message, its errors are shown as they are).

import { ackMessage, resizeMessage, tokenSubprotocols } from './js/protocol.js';
import { cloneCamera, roundCamera, DEFAULT_CAMERA, fitCamera, flatBounds } from './js/camera.js';
import { parseHash, tokenFromLocation } from './js/url-state.js';
import { getPath, merge, UPDATE_SECTIONS, applies, fieldByPath } from './js/schema.js';
import { Connection } from './js/connection.js';
import { FrameView } from './js/view.js';
import { Navigation } from './js/navigation.js';
import { Panel, GROUPS, attributeRange, rgbToHex } from './js/ui.js';
import { FrameStats, renderStats, formatBytes, visibilityText, clarityNote, occlusionWarning } from './js/stats.js';
import { Api, ApiError } from './js/api.js';
import { Legend, invertNote } from './js/legend.js';
import { AxesTriad } from './js/axes.js';
import { createState, currentValues, linkCamera, datasetInfo } from './js/app-state.js';
import { createParamsController } from './js/params-controller.js';
import { createTimeController } from './js/time-controller.js';
import { createLayersController } from './js/layers-controller.js';
import { createCameraController } from './js/camera-controller.js';
import { createSessionController } from './js/session-controller.js';
import { createUrlController } from './js/url-controller.js';
import { createDatasetController, datasetView } from './js/dataset-controller.js';
import { createRecordController } from './js/record-controller.js';
import { SurfacePanel } from './js/surface-panel.js';
import { SeedOverlay } from './js/seed-handles.js';
import { StreamlinesPanel } from './js/streamlines-panel.js';

const TOKEN_KEY = 'lucent.token';

/** Builds the page on document and window; returns {start(), debug} (debug: the read-only view for tests). */
export function createApp(doc = document, win = window) {
  const $ = (id) => doc.getElementById(id);
  const body = (key, value) => {
    if (value === undefined) delete doc.body.dataset[key];
    else doc.body.dataset[key] = String(value);
  };
  const { location, history } = win;
  const initial = parseHash(location.hash);
  const state = createState(
    initial,
    tokenFromLocation(location.search, location.hash) ?? win.sessionStorage.getItem(TOKEN_KEY),
  );
  const linkAtStart = { update: merge({}, initial.update), camera: state.camera }; // the preset goes under these
  const base = new URL('.', location.href);
  const wsUrl = new URL('api/v1/ws', base);
  wsUrl.protocol = location.protocol === 'https:' ? 'wss:' : 'ws:';
  const api = new Api(base, () => state.token);
  const stats = new FrameStats();
  const values = () => currentValues(state);
  let conn = null; // made last: its hello needs the controllers
  const frame = (fn) => win.requestAnimationFrame(fn);

  // ---------------------------------------------------------------- banner, toast, token
  function showBanner(text, { retry = false, kind = 'error' } = {}) {
    $('banner-text').textContent = text;
    $('banner-retry').hidden = !retry;
    $('banner').hidden = false;
    $('banner').dataset.kind = kind;
    state.error = { ...(state.error ?? {}), kind, text };
  }
  const hideBanner = () => ($('banner').hidden = true);
  let toastTimer = 0;
  function toast(text) {
    const el = $('toast');
    el.textContent = text;
    el.hidden = false;
    win.clearTimeout(toastTimer);
    toastTimer = win.setTimeout(() => (el.hidden = true), 6000);
  }
  function setToken(t) {
    state.token = t || null;
    if (t) win.sessionStorage.setItem(TOKEN_KEY, t);
    else win.sessionStorage.removeItem(TOKEN_KEY);
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

  // ---------------------------------------------------------------- view, triad, legend
  const canvas = $('canvas');
  let clarityOutcome = ''; // the last optimizing frame's clarity note (moving frames reuse its opacities)
  const view = new FrameView(canvas, {
    ack: (id) => conn.send(ackMessage(id)),
    onDrawn: (f) => {
      state.lastFrame = f.header;
      state.framesDrawn++;
      if (f.header.cameraSeq > state.confirmedSeq) state.confirmedSeq = f.header.cameraSeq;
      stats.frameDrawn(f.header, f.bytes, f.drawnAt);
      const seen = visibilityText(f.header.visibility);
      if (seen && f.header.clarity) clarityOutcome = clarityNote(f.header.clarity);
      if (seen) panel.setFeedback('params.clarity', `Last frame: ${seen}.${clarityOutcome}`);
      if (seen) {
        // frames without a report (moving frames reusing opacities) keep the last word
        const warn = occlusionWarning(f.header.visibility);
        $('occlusion-warning').textContent = warn;
        $('occlusion-warning').hidden = !warn;
      }
      legend.setColorTicks(f.header.colorTicks);
      surface.frame(f.header);
      seeds?.update();
      canvas.dataset.frame = String(f.header.frame);
      canvas.dataset.converged = String(!!f.header.converged);
      body('frames', state.framesDrawn);
      refreshStats();
    },
    onError: (e) => toast(e.message),
    frameCamera: (h) => state.cameras.get(h.cameraSeq) ?? null,
    background: () => rgbToHex(values().style?.background ?? [1, 1, 1]),
  });
  const axes = new AxesTriad($('axes'), 72);
  let seeds = null; // the seed line over the view, made with the surface panel below
  const legend = new Legend($('legend'), {
    onFlip: () => {
      const r = legend.model?.color.range;
      if (r) params.applyChange('color.range', [r[1], r[0]]);
    },
  });

  // ---------------------------------------------------------------- controllers
  const url = createUrlController({
    state,
    location,
    history,
    setTimeout: (f, ms) => win.setTimeout(f, ms),
    clearTimeout: (t) => win.clearTimeout(t),
  });
  const camera = createCameraController({
    state,
    frame,
    now: () => win.performance.now(),
    isOpen: () => conn.isOpen,
    send: (msg) => conn.send(msg),
    axes: {
      update: (c) => {
        axes.update(c);
        seeds?.update();
      },
    },
    view,
    stats,
    aspect,
    changed: () => url.schedule(),
  });
  const params = createParamsController({
    state,
    frame,
    send: (msg) => conn.send(msg),
    setCameraField: camera.setField,
    changed: () => {
      showValues();
      url.schedule();
    },
    sent: () => body('paramsSent', Number(doc.body.dataset.paramsSent ?? 0) + 1),
    toast,
  });
  const panel = new Panel(
    $('generated'),
    (path, value) => params.applyChange(path, value),
    (text) => toast(text),
  );
  const surface = new SurfacePanel(
    $('generated'),
    doc,
    (path, value) => {
      if (path === 'method' || path === 'surface') surface.setMethod(values().method);
      params.applyChange(path, value);
      seeds?.update();
    },
    (text) => toast(text),
    (bounds) => camera.setCamera(fitCamera(DEFAULT_CAMERA, flatBounds(bounds), [-1, 1.5, -0.8], [0, 0, 1], aspect())),
  );
  // a vector field's streamline set: the whole streamlines object goes with each change (the server re-traces)
  const streamlines = new StreamlinesPanel(
    $('generated'),
    doc,
    (value) => {
      delete state.update.streamlines;
      params.applyChange('streamlines', value);
      seeds?.update();
    },
    (text) => toast(text),
  );
  // the seed handles: the stream surface's seed line, else a streamline rake's ends
  const seedOwner = () => (surface.shownSeed() ? surface : streamlines.shownSeed() ? streamlines : null);
  seeds = new SeedOverlay($('seed-overlay'), {
    get: () => {
      const s = seedOwner()?.shownSeed();
      return s && state.camera ? { ...s, cam: state.camera } : null;
    },
    onMove: (i, p) => seedOwner()?.setPoint(i, p),
    onEnd: () => seedOwner()?.send(),
  });
  const layers = createLayersController({
    doc,
    state,
    values: () => values(),
    apply: (path, value) => params.applyChange(path, value),
  });
  const time = createTimeController({
    doc,
    apply: (path, value) => params.applyChange(path, value),
    setInterval: (f, ms) => win.setInterval(f, ms),
    clearInterval: (id) => win.clearInterval(id),
    framesDrawn: () => state.framesDrawn,
    now: () => win.performance.now(),
  });
  const datasets = createDatasetController({
    state,
    camera,
    ui: {
      toast,
      showBanner,
      showDataset,
      body,
      hidePresetNote,
      showPresetNote(title) {
        $('preset-text').textContent = 'Preset applied';
        $('preset-note').title = title;
        $('preset-note').hidden = false;
      },
    },
  });
  const session = createSessionController({
    state,
    stats,
    view,
    camera,
    params,
    panel,
    api,
    conn: () => conn,
    measure,
    timers: {
      setInterval: (f, ms) => win.setInterval(f, ms),
      clearInterval: (t) => win.clearInterval(t),
      now: () => win.performance.now(),
    },
    ui: {
      connection(s, text) {
        const el = $('connection');
        el.dataset.state = s;
        el.textContent = text;
      },
      progress(p) {
        const box = $('progress');
        box.hidden = !p;
        if (!p) return;
        const bar = $('progress-bar');
        if (p.fraction === null)
          bar.removeAttribute('value'); // indeterminate
        else bar.value = p.fraction;
        $('progress-text').textContent = p.text;
      },
      showBanner,
      hideBanner,
      toast,
      askToken,
      showDataset,
      showValues,
      writeHash: url.write,
      body,
    },
  });
  conn = new Connection(wsUrl.href, session.hello, {
    // the server refuses an upgrade without the token, so it goes with the handshake
    protocols: () => tokenSubprotocols(state.token),
    ...session.handlers,
  });

  // ---------------------------------------------------------------- values shown = defaults + stream + user changes
  function showValues() {
    const v = values();
    for (const g of GROUPS) {
      for (const c of g.controls) {
        if (c.path.startsWith('camera.')) continue;
        let x = getPath(v, c.path);
        if (c.path === 'importance.attribute' && !x) x = state.info?.defaultImportance;
        if (c.path === 'color.attribute' && !x) x = state.info?.defaultColor ?? 'importance';
        if (x === undefined && c.path === 'importance.range')
          x = attributeRange(state.info, v.importance?.attribute || state.info?.defaultImportance, v.params?.normalize);
        if (x === undefined && c.path === 'color.range') {
          const by = v.color?.attribute || state.info?.defaultColor || 'importance';
          x = by === 'importance' ? [0, 1] : attributeRange(state.info, by, v.params?.normalize);
        }
        panel.setValue(c.path, x);
      }
    }
    if (state.camera) {
      panel.setValue('camera.viewAngle', state.camera.viewAngle);
      panel.setValue('camera.parallelProjection', state.camera.parallelProjection);
    }
    // the controls of fields this method and kind of data read (the server refuses the others)
    const prim = v.layers?.length ? null : (state.info?.type ?? null);
    for (const path of panel.controls.keys()) {
      const f = fieldByPath(path);
      if (f) panel.setVisible(path, applies(f, v.method, prim));
    }
    const colorBy = v.color?.attribute;
    if (colorBy === 'rgb') {
      panel.setVisible('color.colormap', false);
      panel.setVisible('color.range', false);
    }
    panel.setFeedback('importance.invert', invertNote(v, state.info));
    legend.update(v, state.info);
    time.show(v, state.info);
    layers.show(v);
  }

  // ---------------------------------------------------------------- viewport and navigation
  function measure() {
    const r = $('view').getBoundingClientRect();
    const dpr = Math.min(Math.max(win.devicePixelRatio || 1, 0.25), 8);
    return { width: Math.max(16, Math.round(r.width)), height: Math.max(16, Math.round(r.height)), dpr };
  }
  /** width / height of the view (fits use the narrower angle of a portrait view). */
  function aspect() {
    const v = state.viewport.width ? state.viewport : measure();
    return v.width / v.height;
  }
  let resizeFrame = 0;
  function onResize() {
    if (resizeFrame) return;
    resizeFrame = frame(() => {
      resizeFrame = 0;
      const v = measure();
      const old = state.viewport;
      if (v.width === old.width && v.height === old.height && v.dpr === old.dpr) return;
      state.viewport = v;
      seeds?.update();
      view.setSize(Math.round(v.width * v.dpr), Math.round(v.height * v.dpr));
      conn.send(resizeMessage(v.width, v.height, v.dpr));
      // a view the user has not moved since it was fitted is fitted again to its new shape
      // (folding the panel away on a phone makes the view taller and narrower than the fit)
      camera.viewResized();
    });
  }
  let dprQuery = null;
  function watchDpr() {
    dprQuery?.removeEventListener('change', watchDpr);
    dprQuery = win.matchMedia(`(resolution: ${win.devicePixelRatio}dppx)`);
    dprQuery.addEventListener('change', watchDpr);
    onResize();
  }
  function toggleFullscreen() {
    if (doc.fullscreenElement) doc.exitFullscreen?.().catch(() => {});
    else
      $('view')
        .requestFullscreen?.()
        .catch((e) => toast(`Fullscreen is not available: ${e.message}`));
  }
  const command = (name) => (name === 'fullscreen' ? toggleFullscreen() : camera.command(name));

  // ---------------------------------------------------------------- dataset picker
  function showDataset() {
    const m = datasetView(state);
    const field = datasetInfo(state);
    streamlines.show(field?.kind === 'field' ? field : null, state.update.streamlines);
    seeds?.update();
    const sel = $('dataset');
    const same =
      sel.options.length === m.options.length &&
      m.options.every(([v, t], i) => sel.options[i].value === v && sel.options[i].text === t);
    if (!same) sel.replaceChildren(...m.options.map(([v, t]) => new Option(t, v)));
    if (m.selected) sel.value = m.selected;
    $('dataset-title').textContent = m.title;
    const info = $('dataset-info');
    info.replaceChildren();
    if (!m.details) return;
    const span = (props) => Object.assign(doc.createElement('span'), props);
    if (m.details.description) info.append(span({ className: 'desc', textContent: m.details.description }));
    info.append(span({ textContent: m.details.summary }));
    if (m.details.attributes.length) {
      const ul = doc.createElement('ul');
      ul.className = 'attributes';
      ul.setAttribute('aria-label', 'Attributes');
      for (const a of m.details.attributes) ul.append(Object.assign(doc.createElement('li'), { textContent: a }));
      info.append(ul);
    }
  }
  function hidePresetNote() {
    $('preset-note').hidden = true;
  }

  // ---------------------------------------------------------------- statistics: one line, the full table on demand
  const statsLine = $('stats');
  const statsEl = $('stats-full');
  const showStats = $('show-stats');
  function statsVisible(full) {
    showStats.checked = full;
    statsEl.hidden = !full;
    statsLine.setAttribute('aria-expanded', String(full));
    refreshStats();
  }
  let statsFrame = 0;
  function refreshStats() {
    if (statsFrame) return;
    statsFrame = frame(() => {
      statsFrame = 0;
      statsLine.textContent = stats.summary();
      if (!statsEl.hidden) renderStats(statsEl, stats);
    });
  }

  // ---------------------------------------------------------------- screenshot
  function screenshotSize() {
    const v = $('shot-size').value;
    if (v === 'view') return [canvas.width, canvas.height];
    if (v === 'custom') return [Number($('shot-width').value), Number($('shot-height').value)];
    return v.split('x').map(Number);
  }
  /** The render request of the current view at a given size (POST /api/v1/render). */
  function renderRequest(width, height) {
    const v = values();
    const req = { dataset: state.dataset, width, height, format: 'png' };
    if (v.method) req.method = v.method;
    if (state.camera) req.camera = roundCamera(state.camera, 12);
    for (const s of UPDATE_SECTIONS) if (v[s]) req[s] = v[s];
    if (v.filter?.length) req.filter = v.filter;
    if (v.layers?.length) req.layers = v.layers; // the screenshot and the movie draw the layers the view shows
    return req;
  }
  async function screenshot() {
    const btn = $('screenshot');
    const [w, h] = screenshotSize();
    const lim = state.limits ?? {};
    const lo = lim.minSize ?? 16,
      hi = lim.maxSize ?? 8192;
    if (!(Number.isInteger(w) && Number.isInteger(h) && w >= lo && h >= lo && w <= hi && h <= hi)) {
      toast(`Screenshot size must be whole numbers between ${lo} and ${hi}.`);
      return;
    }
    if (lim.maxPixels && w * h > lim.maxPixels) {
      toast(`Screenshot of ${w} × ${h} exceeds this server's ${lim.maxPixels} pixels.`);
      return;
    }
    btn.disabled = true;
    btn.textContent = 'Rendering…';
    try {
      const { blob } = await api.render(renderRequest(w, h));
      const a = doc.createElement('a');
      a.href = URL.createObjectURL(blob);
      const safe = (state.dataset ?? 'view').replace(/[^A-Za-z0-9._-]+/g, '-');
      a.download = `lucent-${safe}-${w}x${h}.png`;
      doc.body.append(a);
      a.click();
      a.remove();
      win.setTimeout(() => URL.revokeObjectURL(a.href), 10000);
      toast(`Saved ${a.download} (${formatBytes(blob.size)}).`);
    } catch (e) {
      if (e instanceof ApiError && e.code === 'unauthorized') askToken('This server requires an access token.');
      else showBanner(`Screenshot failed: ${e.message}`, { kind: 'error' });
    } finally {
      btn.disabled = false;
      btn.textContent = 'Save PNG';
    }
  }

  // ---------------------------------------------------------------- record: keyframes, preview, movie job
  const record = createRecordController({
    getCamera: () => state.camera,
    setCamera: (cam) => camera.setCamera(cam),
    request: () => renderRequest(0, 0),
    api,
    onChange: () => showRecord(),
    now: () => win.performance.now(),
    frame,
    sleep: (ms) => new Promise((resolve) => win.setTimeout(resolve, ms)),
  });
  function showRecord() {
    const v = record.view();
    const list = $('record-keys');
    list.replaceChildren(
      ...v.keys.map((k) => {
        const li = doc.createElement('li');
        const rm = doc.createElement('button');
        rm.type = 'button';
        rm.textContent = '×';
        rm.title = 'Remove this keyframe';
        rm.setAttribute('aria-label', `Remove keyframe ${k.index + 1}`);
        rm.addEventListener('click', () => record.remove(k.index));
        li.append(k.label, ' ', rm);
        return li;
      }),
    );
    $('record-preview').disabled = !v.canPreview;
    $('record-render').disabled = !v.canRender;
    const job = v.job;
    const bar = $('record-progress');
    bar.hidden = !job || job.state === 'failed';
    bar.value = job?.progress ?? 0;
    $('record-status').textContent = !job
      ? ''
      : job.state === 'failed'
        ? `Failed: ${job.error ?? 'unknown error'}`
        : job.state === 'done'
          ? 'Done.'
          : `${job.state} ${Math.round(100 * (job.progress ?? 0))}%`;
    const link = $('record-download');
    link.hidden = !job?.url;
    if (job?.url) {
      link.href = job.url;
      link.download = `lucent-${(state.dataset ?? 'view').replace(/[^A-Za-z0-9._-]+/g, '-')}.${$('record-codec').value === 'vp9' ? 'webm' : 'mp4'}`;
    }
  }
  function recordOptions() {
    const num = (id) => Number($(id).value);
    return {
      duration: num('record-duration'),
      fps: num('record-fps'),
      width: num('record-width'),
      height: num('record-height'),
      codec: $('record-codec').value,
    };
  }

  // ---------------------------------------------------------------- the page's events
  function listen() {
    $('record-add').addEventListener('click', () => record.add());
    $('record-preview').addEventListener('click', () => record.preview(recordOptions().duration));
    $('record-render').addEventListener('click', () => record.render(recordOptions()));
    new Navigation(canvas, { getCamera: () => state.camera, onCamera: camera.setCamera, onCommand: command });
    for (const btn of doc.querySelectorAll('[data-view]'))
      btn.addEventListener('click', () => command(btn.dataset.view));
    new ResizeObserver(onResize).observe($('view'));
    watchDpr();
    win.addEventListener('hashchange', () => {
      const s = url.taken();
      if (!s) return;
      // a pasted or edited link: take it over as a fresh start, as a fresh load would
      if (s.token) setToken(s.token);
      if (s.errors.length) toast(`Ignored in the link: ${s.errors.join('; ')}`);
      state.update = s.update;
      state.camera = linkCamera(s.camera);
      const switched = s.dataset && s.dataset !== state.dataset;
      if (s.dataset) state.dataset = s.dataset;
      state.info = datasetInfo(state);
      if (switched) view.clear();
      // the old error (an unknown dataset, a refused value) is about the old link
      hideBanner();
      state.error = null;
      datasets.usePreset({ update: s.update, camera: state.camera });
      if (!datasets.checkDataset()) showDataset();
      conn.start();
    });
    $('dataset').addEventListener('change', (e) => {
      view.clear();
      hideBanner();
      datasets.choose(e.target.value);
      url.write();
      conn.start();
    });
    $('preset-close').addEventListener('click', hidePresetNote);
    $('preset-undo').addEventListener('click', () => {
      if (!datasets.undoPreset()) return;
      url.write();
      conn.start(); // a fresh session: its defaults replace what the preset had set
    });
    $('banner-close').addEventListener('click', hideBanner);
    $('banner-retry').addEventListener('click', () => {
      hideBanner();
      conn.start();
    });
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
    $('copy-link').addEventListener('click', async () => {
      url.write();
      const link = location.href;
      try {
        await win.navigator.clipboard.writeText(link);
        toast('Link copied to the clipboard.');
      } catch {
        win.prompt('Copy this link:', link);
      }
    });
    $('shot-size').addEventListener('change', () => ($('shot-custom').hidden = $('shot-size').value !== 'custom'));
    $('screenshot').addEventListener('click', screenshot);
    $('reset-params').addEventListener('click', () => {
      // a fresh session without the user's changes (or a preset's): its ready message brings the server's defaults
      state.update = {};
      state.preset = null;
      hidePresetNote();
      url.write();
      conn.start();
    });
    showStats.addEventListener('change', () => statsVisible(showStats.checked));
    statsLine.addEventListener('click', () => statsVisible(statsEl.hidden));
    win.setInterval(refreshStats, 250); // fps decays when frames stop
    $('panel-toggle').addEventListener('click', () => {
      const collapsed = doc.body.classList.toggle('panel-collapsed');
      $('panel-toggle').setAttribute('aria-expanded', String(!collapsed));
      onResize(); // the view changes shape; a fitted camera is fitted to it again
    });
    $('show-help').addEventListener('change', (e) => $('panel').classList.toggle('explain', e.target.checked));
    const help = $('help');
    const toggleHelp = () => (help.open ? help.close() : help.showModal());
    $('help-button').addEventListener('click', toggleHelp);
    doc.addEventListener('keydown', (e) => {
      if (e.key !== '?' || e.ctrlKey || e.metaKey || e.altKey) return;
      const t = e.target;
      if (t instanceof HTMLInputElement || t instanceof HTMLTextAreaElement || t instanceof HTMLSelectElement) return;
      e.preventDefault();
      toggleHelp();
    });
  }

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
    api.fields().then(
      (f) => surface.setFields(f),
      () => {},
    );
    api.health().then(
      (h) => {
        state.health = h;
        const r = h?.renderer ?? h?.gl?.renderer;
        if (typeof r === 'string') stats.renderer = r;
        if (Array.isArray(h?.methods)) panel.setMethods(h.methods);
      },
      () => {},
    );
    datasets.checkDataset();
    if (!state.dataset && state.datasets.length) state.dataset = state.datasets[0].name;
    datasets.usePreset(linkAtStart);
    showDataset();
    conn.start();
  }

  listen();
  if (initial.errors.length) queueMicrotask(() => toast(`Ignored in the link: ${initial.errors.join('; ')}`));

  // Read-only view of the page for tests and the console.
  const debug = {
    get state() {
      return state;
    },
    get stats() {
      return stats;
    },
    get camera() {
      return state.camera ? cloneCamera(state.camera) : null;
    },
    values,
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
  return { start, debug };
}

const app = createApp();
window.lucent = app.debug;
app.start();
