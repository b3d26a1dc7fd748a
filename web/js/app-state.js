// The page's state: one object every controller reads and writes, made from
// the link it was opened with; and the values the panel shows (the server's
// defaults, the stream settings and the user's changes on top).

import { cloneCamera, validateCamera } from './camera.js';
import { merge } from './schema.js';
import { contrastBackground } from './colormaps.js';

/** A camera from a link, or null when it is missing or degenerate. */
export function linkCamera(camera) {
  return camera && !validateCamera(cloneCamera(camera)) ? cloneCamera(camera) : null;
}

/** initial: parseHash() of the link; token: from the link or the session's storage. */
export function createState(initial, token) {
  return {
    dataset: initial.dataset, // requested or current dataset name (null = server default)
    datasets: [], // descriptions from GET /api/v1/datasets
    info: null, // ready.dataset
    defaults: null, // ready.defaults (a render request)
    pageDefaults: {}, // what the page chose for the session where the user, link and preset chose nothing (pageDefaults())
    stream: null, // ready.stream
    limits: null, // ready.limits
    session: null,
    camera: linkCamera(initial.camera),
    update: initial.update, // the user's changes to the defaults (sections, method, stream settings)
    seq: 0, // last camera seq sent
    confirmedSeq: 0, // newest cameraSeq a drawn frame reflects
    lastFrame: null, // header of the newest drawn frame
    received: [], // headers of the newest 64 frames received, drawn or not (the view drops frames a newer one replaces)
    framesDrawn: 0,
    token: token ?? null,
    error: null, // last error shown {code, message}
    viewport: { width: 0, height: 0, dpr: 1 },
    cameras: new Map(), // camera seq -> the camera sent with it (0: the hello's), to warp frames
    fitted: false, // the camera is a fit the user has not moved since: refit when the view's shape changes
    preset: null, // {dataset, preset, applied, cameraApplied} of the preset in effect
    responses: [], // input -> warped picture on screen, ms (the newest 200)
    retryDelays: [], // reconnection delays chosen, ms
  };
}

/**
 * What the page asks for in a session's hello beyond the user's changes
 * (docs/GUIDE.md "Contrast by default"): without a background from the user, the link
 * or a preset, the background that contrasts with the colormap in force (the
 * changes' colormap, else the server's default viridis).
 */
export function pageDefaults(update) {
  if (update?.style?.background !== undefined) return {};
  return { style: { background: contrastBackground(update?.color?.colormap ?? 'viridis') } };
}

/** The values shown: defaults + the page's defaults + stream settings + the user's changes. */
export function currentValues(state) {
  const s = state.stream;
  const streamDefaults = s
    ? { quality: s.quality, interactiveQuality: s.interactiveQuality, interactiveScale: s.interactiveScale }
    : {};
  return merge(merge(merge(state.defaults ?? {}, state.pageDefaults ?? {}), streamDefaults), state.update);
}

/** The description of the chosen dataset: the session's, else the list's. */
export function datasetInfo(state, name = state.dataset) {
  return state.datasets.find((d) => d.name === name) ?? null;
}
