// The view's camera: the triad and the warped last frame follow every change
// at once (input → visible response without a server round trip); the server
// gets one camera message per animation frame, the latest.

import { cameraMessage } from './protocol.js';
import {
  DEFAULT_CAMERA,
  flatBounds,
  cloneCamera,
  fitCamera,
  refitCamera,
  viewAlongAxis,
  validateCamera,
  roundCamera,
} from './camera.js';

/** Cameras sent and remembered to warp the frames that reflect them. */
export const CAMERAS_KEPT = 64;
/** Input-to-picture response samples kept. */
export const RESPONSES_KEPT = 200;

/**
 * The camera a new view starts from: the dataset's suggested view when its
 * description carries one (view.direction/up or viewDirection/viewUp), else
 * ParaView's default (looking down -Z, +Y up), fitted as lc_camera_fit does.
 */
export function initialCamera(info, aspect) {
  const b = flatBounds(info?.bounds);
  if (!b) return null;
  const dir = info.view?.direction ?? info.viewDirection;
  const up = info.view?.up ?? info.viewUp;
  return fitCamera(DEFAULT_CAMERA, b, Array.isArray(dir) ? dir : undefined, Array.isArray(up) ? up : undefined, aspect);
}

/**
 * ctx: state; frame(fn) (requestAnimationFrame); now() (performance.now);
 * isOpen() and send(msg) of the connection; axes.update(cam); view.setCamera(cam)
 * → true when a frame was repainted; stats.cameraSent(seq); aspect() of the view;
 * changed() after every change (the link).
 */
export function createCameraController(ctx) {
  const { state } = ctx;
  let frame = 0;
  let dirty = false;

  const bounds = () => flatBounds(state.info?.bounds);

  /** opts.at: the input event's time stamp (response measurement); opts.fitted: the camera is a fit (refit on resize). */
  function setCamera(cam, { at, fitted = false } = {}) {
    if (validateCamera(cam)) return; // a degenerate camera from extreme input: keep the previous one
    state.camera = cam;
    state.fitted = fitted;
    ctx.axes.update(cam);
    const painted = ctx.view.setCamera(cam);
    if (at !== undefined && painted) {
      ctx.frame(() => {
        state.responses.push(ctx.now() - at);
        if (state.responses.length > RESPONSES_KEPT) state.responses.shift();
      });
    }
    dirty = true;
    if (!frame) frame = ctx.frame(flush);
    ctx.changed();
  }

  function flush() {
    frame = 0;
    if (!dirty || !state.camera) return;
    dirty = false;
    if (!ctx.isOpen()) return;
    const seq = ++state.seq;
    const cam = roundCamera(state.camera, 12);
    ctx.send(cameraMessage(seq, cam));
    state.cameras.set(seq, cam);
    if (state.cameras.size > CAMERAS_KEPT) state.cameras.delete(state.cameras.keys().next().value);
    ctx.stats.cameraSent(seq);
  }

  /** camera.viewAngle, camera.parallelProjection from the panel. */
  function setField(path, value) {
    if (!state.camera) return;
    const cam = cloneCamera(state.camera);
    cam[path.slice(7)] = value;
    if (path === 'camera.parallelProjection' && value) {
      // keep the apparent size: the half height seen at the focal distance
      const d = Math.hypot(...cam.position.map((p, i) => p - cam.focalPoint[i]));
      cam.parallelScale = d * Math.tan((cam.viewAngle * Math.PI) / 360);
    }
    setCamera(cam);
  }

  /** home, reset, or an axis view (+x, -y, ...). */
  function command(name) {
    const b = bounds();
    if (!b || !state.camera) return;
    let cam;
    if (name === 'home') {
      cam = initialCamera(state.info, ctx.aspect());
      if (!cam) return;
      cam.viewAngle = state.camera.viewAngle;
      cam.parallelProjection = state.camera.parallelProjection;
      cam = fitCamera(
        cam,
        b,
        cam.focalPoint.map((f, i) => f - cam.position[i]),
        cam.viewUp,
        ctx.aspect(),
      );
    } else if (name === 'reset') cam = refitCamera(state.camera, b, ctx.aspect());
    else cam = viewAlongAxis(state.camera, b, name, ctx.aspect());
    setCamera(cam, { fitted: true });
  }

  /** The view changed shape: a camera the user has not moved since it was fitted is fitted again. */
  function viewResized() {
    const b = bounds();
    if (b && state.camera && state.fitted) setCamera(refitCamera(state.camera, b, ctx.aspect()), { fitted: true });
  }

  /** Shows a camera the server or a new session set, without sending it. */
  function adopt(cam) {
    state.camera = cam;
    ctx.axes.update(cam);
    ctx.view.setCamera(cam);
  }

  return {
    setCamera,
    flush,
    setField,
    command,
    viewResized,
    adopt,
    initial: (info) => initialCamera(info, ctx.aspect()),
    /** A hello carries the camera: nothing is left to send. */
    drop() {
      dirty = false;
    },
  };
}
