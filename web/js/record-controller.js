// "Record" in the panel: keyframes taken from the current view, a preview that
// moves the page's camera through them as the server's movie will
// (js/camera-path.js), and the movie job (POST /api/v1/movies, polled for its
// progress, then the file's link). No DOM: app.js shows `view()` after each
// change (onChange) and supplies the camera, the request and the API.

import { cameraPathFrame } from './camera-path.js';
import { cloneCamera, roundCamera } from './camera.js';

export const RECORD_CODECS = Object.freeze(['h264', 'vp9']);

/**
 * deps: getCamera() -> the current camera; setCamera(cam) moves the view;
 * request() -> the render request of the current view without width/height;
 * api: createMovie(body), movie(id), movieFileUrl(id); onChange(); now() ms;
 * frame(fn) (requestAnimationFrame); sleep(ms) -> Promise (polling).
 */
export function createRecordController(deps) {
  const keys = [];
  let job = null; // {id, state, progress, error, url}
  let previewing = 0; // serial of the running preview (0: none)
  let busy = false;
  const changed = () => deps.onChange?.();

  function add() {
    const cam = deps.getCamera();
    if (!cam) return false;
    keys.push(cloneCamera(cam));
    changed();
    return true;
  }
  function remove(i) {
    if (i >= 0 && i < keys.length) keys.splice(i, 1);
    changed();
  }
  function clear() {
    keys.length = 0;
    changed();
  }

  /** The movie request of the keyframes: opts {duration, fps, width, height, codec}. */
  function movieBody({ duration, fps, width, height, codec }) {
    const request = { ...deps.request() };
    delete request.width;
    delete request.height;
    delete request.camera;
    delete request.format;
    return {
      request,
      path: 'keyframes',
      keyframes: keys.map((k) => roundCamera(k, 12)),
      duration,
      fps,
      width,
      height,
      codec,
    };
  }

  /** Moves the view through the keyframes over `seconds` (the movie's camera at each moment); resolves when done. */
  function preview(seconds) {
    if (keys.length < 2) return Promise.resolve(false);
    const serial = ++previewing;
    const start = deps.now();
    const frames = 1000; // fine enough that the page's camera follows the path continuously
    return new Promise((resolve) => {
      const step = () => {
        if (previewing !== serial) return resolve(false);
        const t = Math.min(1, (deps.now() - start) / (1000 * seconds));
        deps.setCamera(cameraPathFrame(keys, Math.round(t * (frames - 1)), frames));
        if (t < 1) deps.frame(step);
        else {
          previewing = 0;
          changed();
          resolve(true);
        }
      };
      changed();
      step();
    });
  }
  function stopPreview() {
    previewing = 0;
    changed();
  }

  /** Starts the movie job and polls it until done, failed or cancelled; resolves with the job. */
  async function render(opts, pollMs = 500) {
    if (busy) return job;
    if (keys.length < 2) {
      job = { state: 'failed', progress: 0, error: 'Add at least two keyframes first.' };
      changed();
      return job;
    }
    busy = true;
    try {
      job = { state: 'submitting', progress: 0 };
      changed();
      let j = await deps.api.createMovie(movieBody(opts));
      job = { id: j.id, state: j.state, progress: j.progress ?? 0 };
      changed();
      while (job.state === 'queued' || job.state === 'running') {
        await deps.sleep(pollMs);
        j = await deps.api.movie(job.id);
        job = { id: j.id, state: j.state, progress: j.progress ?? 0, error: j.error?.message ?? j.error };
        changed();
      }
      if (job.state === 'done') job.url = deps.api.movieFileUrl(job.id);
    } catch (e) {
      job = { ...(job ?? {}), state: 'failed', error: e.message };
    } finally {
      busy = false;
    }
    changed();
    return job;
  }

  /** What the panel shows. */
  function view() {
    return {
      keys: keys.map((k, i) => ({ index: i, label: `${i + 1}: (${k.position.map((x) => x.toFixed(2)).join(', ')})` })),
      canPreview: keys.length >= 2 && !previewing,
      previewing: previewing !== 0,
      canRender: keys.length >= 2 && !busy,
      job,
    };
  }

  return { add, remove, clear, movieBody, preview, stopPreview, render, view, keys: () => keys.map(cloneCamera) };
}
