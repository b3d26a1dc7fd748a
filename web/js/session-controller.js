// The stream: the hello of each attempt (dataset, camera, viewport and the
// user's changes, so a reconnect restores them) and what the server's
// messages do to the page: ready, frames, statistics, errors, the
// connection's state.

import { helloMessage, describeError } from './protocol.js';
import { cloneCamera, validateCamera, roundCamera } from './camera.js';
import { UPDATE_SECTIONS, STREAM_FIELDS, merge, applicableUpdate } from './schema.js';
import { datasetInfo, pageDefaults } from './app-state.js';

export const RETRY_DELAYS_KEPT = 50;

/** Words for the stages of the server's progress messages (protocol/websocket.md "progress"). */
export const PROGRESS_STAGES = Object.freeze({
  queued: 'Waiting for a render worker',
  prepare: 'Preparing the frame',
  depthRange: 'Depth range',
  importance: 'Importance',
  opacity: 'Opacities',
  smooth: 'Smoothing',
  opticalDepth: 'Optical depth',
  accumulate: 'Accumulating',
  resolve: 'Resolving',
  readback: 'Reading back',
  encode: 'Encoding',
});

/** The line under the progress bar: stage, per cent when known, time so far; while a staged
 * still refines (protocol/websocket.md "Staged stills"), which stage of how many. */
export function progressText(p) {
  const pct = p.fraction === null ? '' : ` ${Math.round(100 * p.fraction)}%`;
  const pre = p.refine ? `Refining, stage ${p.refine.stage} of ${p.refine.stages}: ` : '';
  return `${pre}${PROGRESS_STAGES[p.stage] ?? p.stage}${pct} · ${p.elapsed.toFixed(1)} s`;
}
const TOKEN_REFUSED = 'The token was not accepted.';
const TOKEN_NEEDED = 'This server requires an access token.';

/**
 * ctx: state; stats (FrameStats); view (push, reset, setSize); camera and params
 * (the controllers); panel (setMethods, setDataset, markInvalid); api (datasets());
 * conn() → the Connection (terminal); measure() → {width, height, dpr};
 * ui: {connection(state, text), progress({stage, fraction, elapsed} | null),
 * showBanner(text, opts), hideBanner(), toast(text),
 * askToken(reason), showDataset(), showValues(), writeHash(), body(key, value)};
 * timers: {setInterval, clearInterval, now}.
 */
export function createSessionController(ctx) {
  const { state, ui } = ctx;
  let countdown = 0;
  let waiting = false; // a progress bar is shown: the frame it is about has not come yet
  let refining = null; // after a staged still's non-final stage: {stage, stages} of the one under way
  let reopen = false; // a refused hello went back to the last dataset: connect again once this one has stopped

  // The server's progress messages while a frame is awaited (the first one,
  // a long still): shown until the next frame or the end of the connection.
  function onProgress(msg) {
    waiting = true;
    const fraction = typeof msg.fraction === 'number' ? Math.min(1, Math.max(0, msg.fraction)) : null;
    state.progress = { stage: msg.stage, fraction, elapsed: msg.elapsed };
    if (refining) state.progress.refine = refining;
    ui.progress({ ...state.progress, text: progressText(state.progress) });
  }

  function endProgress() {
    if (!waiting) return;
    waiting = false;
    state.progress = null;
    ui.progress(null);
  }

  function onFrame(frame) {
    endProgress();
    const h = frame.header ?? {};
    state.received.push(h);
    if (state.received.length > 64) state.received.shift();
    refining =
      Number.isInteger(h.stages) && Number.isInteger(h.stage) && h.stage < h.stages && h.final === false
        ? { stage: h.stage + 1, stages: h.stages }
        : null;
    ctx.view.push(frame);
  }

  function hello() {
    // send a camera from the start, so that the page and the server agree on it before the first drag
    if (!state.camera) {
      state.camera = ctx.camera.initial(datasetInfo(state));
      state.fitted = !!state.camera;
    }
    state.cameras.clear();
    if (state.camera) {
      state.cameras.set(0, roundCamera(state.camera, 12));
      // the view warps toward this camera from now on (not toward the previous dataset's)
      ctx.camera.adopt(state.camera);
    }
    state.viewport = ctx.measure();
    const v = state.viewport;
    ctx.view.setSize(Math.round(v.width * v.dpr), Math.round(v.height * v.dpr));
    // no window: the server keeps as many frames in flight as cover the round trip (up to its maximum)
    const msg = {
      dataset: state.dataset ?? undefined,
      width: v.width,
      height: v.height,
      devicePixelRatio: v.dpr,
      token: state.token ?? undefined,
    };
    if (state.camera) msg.camera = roundCamera(state.camera, 12);
    // the page's own defaults (a contrasting background) go first: the user's changes win
    state.pageDefaults = pageDefaults(state.update);
    const sent = merge(state.pageDefaults, state.update);
    for (const s of UPDATE_SECTIONS) if (sent[s] && Object.keys(sent[s]).length) msg[s] = sent[s];
    if (state.update.method) msg.method = state.update.method;
    if (state.update.filter) msg.filter = state.update.filter;
    if (state.update.surface) msg.surface = state.update.surface;
    if (state.update.layers?.length) msg.layers = state.update.layers;
    for (const f of STREAM_FIELDS) if (state.update[f.name] !== undefined) msg[f.name] = state.update[f.name];
    ctx.params.drop(); // the hello carries them
    ctx.camera.drop();
    // fields that do not apply to this method or kind of data stay in the page's state, not in the hello
    const prim = state.update.layers?.length ? null : (datasetInfo(state)?.type ?? null);
    return helloMessage(applicableUpdate(msg, prim));
  }

  function onState(s, detail) {
    ctx.timers.clearInterval(countdown);
    ui.body('connection', s);
    if (s !== 'open') endProgress();
    if (s === 'connecting') {
      ui.connection(s, detail.attempt ? 'Reconnecting…' : 'Connecting…');
      ctx.view.reset();
      state.lastFrame = null; // frames of the new session only
      state.seq = 0;
      state.confirmedSeq = 0;
      ctx.stats.lastMeasuredSeq = 0;
      ctx.stats.sent.clear();
    } else if (s === 'open') {
      ui.connection(s, 'Connected');
      state.retryDelays = [];
      if (state.error?.kind === 'connection') ui.hideBanner();
    } else if (s === 'waiting') {
      state.retryDelays.push(detail.delay);
      if (state.retryDelays.length > RETRY_DELAYS_KEPT) state.retryDelays.shift();
      // a refused handshake (401) only shows as a closed socket: ask the API why
      ctx.api.datasets().catch((e) => {
        if (e?.status === 401 || e?.code === 'unauthorized') ui.askToken(state.token ? TOKEN_REFUSED : TOKEN_NEEDED);
      });
      const until = ctx.timers.now() + detail.delay;
      const tick = () => {
        const left = Math.max(0, Math.ceil((until - ctx.timers.now()) / 1000));
        ui.connection(s, `Disconnected — retrying in ${left} s`);
        ui.showBanner(
          `Connection to the server lost: ${detail.reason}. Reconnecting in ${left} s (attempt ${detail.attempt})…`,
          { retry: true, kind: 'connection' },
        );
      };
      tick();
      countdown = ctx.timers.setInterval(tick, 1000);
    } else if (s === 'stopped') {
      ui.connection(s, 'Disconnected');
      if (reopen) {
        reopen = false;
        ctx.conn().start();
      }
    }
  }

  // A hello the server refused for what it asked of the dataset (too costly to draw, not there) after another
  // dataset had opened: the page goes back to that one, with a message that stays, instead of retrying what
  // cannot succeed or leaving the picker on a dataset the view does not show.
  function backToLastDataset(msg) {
    const last = state.lastReady?.dataset?.name ?? state.lastReady?.defaults?.dataset;
    const refusal =
      msg.code === 'too_expensive' ||
      msg.code === 'not_found' ||
      msg.code === 'unknown_dataset' ||
      msg.field === 'dataset';
    if (!refusal || ctx.conn().ready || !last || last === state.dataset) return false;
    const refused = state.dataset;
    state.dataset = last;
    state.camera = null; // the last dataset's own view
    state.info = datasetInfo(state);
    state.error = { code: 'dataset_refused', message: msg.message, field: '' };
    reopen = true;
    ui.showDataset();
    const why = /[.!?]$/.test(msg.message) ? msg.message : `${msg.message}.`;
    ui.showBanner(`Dataset “${refused}” was not opened: ${why} Showing “${last}” again.`, { kind: 'error' });
    return true;
  }

  function onReady(msg) {
    state.lastReady = msg;
    state.session = msg.session;
    state.info = msg.dataset && typeof msg.dataset === 'object' ? msg.dataset : datasetInfo(state);
    state.defaults = msg.defaults ?? {};
    state.stream = msg.stream ?? null;
    state.limits = msg.limits ?? null;
    state.dataset = state.info?.name ?? msg.defaults?.dataset ?? state.dataset;
    if (msg.defaults?.camera && !validateCamera(cloneCamera(msg.defaults.camera))) {
      ctx.camera.adopt(cloneCamera(msg.defaults.camera));
    } else if (!state.camera) {
      // the server fits the data itself; take the same fit and tell it, so both agree from here on
      const cam = ctx.camera.initial(state.info);
      if (cam) ctx.camera.setCamera(cam, { fitted: true });
    }
    if (state.error && (state.error.code === 'not_found' || state.error.field === 'dataset')) {
      ui.hideBanner(); // a session for this dataset exists: an old "not available" no longer holds
      state.error = null;
    }
    ctx.panel.setMethods(msg.methods ?? state.health?.methods);
    ctx.panel.setDataset(state.info);
    ui.showDataset();
    ui.showValues();
    ui.writeHash();
    ui.body('session', String(msg.session));
    ui.body('dataset', state.dataset ?? '');
  }

  function onStats(msg) {
    ctx.stats.server = Object.fromEntries(Object.entries(msg).filter(([k]) => k !== 'type'));
    if (typeof msg.renderer === 'string') ctx.stats.renderer = msg.renderer;
    state.serverStats = msg;
  }

  function onError(msg, { fatal }) {
    if (msg.code === 'render_failed' || msg.code === 'bad_field' || msg.code === 'too_expensive' || fatal)
      endProgress(); // no frame is coming
    state.error = { code: msg.code, message: msg.message, field: msg.field ?? '' };
    ui.body('lastError', msg.code);
    if (msg.code === 'unauthorized') {
      ui.askToken(state.token ? TOKEN_REFUSED : TOKEN_NEEDED);
      return;
    }
    if (fatal && backToLastDataset(msg)) return;
    const field = msg.field ?? '';
    if (!fatal && field && ctx.panel.markInvalid(field, describeError(msg))) {
      ui.toast(`Not applied — ${describeError(msg)}`);
      return;
    }
    const aboutDataset = /dataset/.test(msg.code) || msg.code === 'not_found';
    if (fatal || aboutDataset) {
      let text = describeError(msg);
      if (aboutDataset || field === 'dataset') {
        const names = state.datasets.map((d) => d.name).join(', ');
        const why = /[.!?]$/.test(msg.message) ? msg.message : `${msg.message}.`;
        text = `Dataset “${state.dataset ?? ''}” is not available: ${why}${names ? ` Available: ${names}.` : ''}`;
        ui.showDataset();
      }
      ui.showBanner(text, { retry: !ctx.conn().terminal, kind: 'error' });
    } else {
      ui.toast(describeError(msg));
    }
  }

  return {
    hello,
    handlers: { onState, onReady, onFrame, onStats, onError, onProgress },
  };
}
