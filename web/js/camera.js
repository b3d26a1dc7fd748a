// Camera math in ParaView/VTK conventions (position, focalPoint, viewUp,
// viewAngle in degrees, parallelProjection, parallelScale). Pure functions on
// plain objects: every operation returns a new camera and never mutates its
// input, so the page, the URL state and the Node tests share one code path.
// Fitting matches render/camera.c (lc_camera_fit) so "R" agrees with the server.

export const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
export const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
export const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
export const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
export const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
export const length = (a) => Math.sqrt(dot(a, a));
export function normalize(a) {
  const l = length(a);
  return l > 0 ? scale(a, 1 / l) : [0, 0, 0];
}

/** Rotates v about the unit axis by angle radians (Rodrigues). */
export function rotate(v, axis, angle) {
  const c = Math.cos(angle),
    s = Math.sin(angle);
  const k = normalize(axis);
  const kxv = cross(k, v);
  const kdv = dot(k, v);
  return [0, 1, 2].map((i) => v[i] * c + kxv[i] * s + k[i] * kdv * (1 - c));
}

export const DEFAULT_CAMERA = Object.freeze({
  position: [0, 0, 1],
  focalPoint: [0, 0, 0],
  viewUp: [0, 1, 0],
  viewAngle: 30,
  parallelProjection: false,
  parallelScale: 1,
});

/** A complete, independent copy of cam with missing fields filled from DEFAULT_CAMERA. */
export function cloneCamera(cam = {}) {
  const d = DEFAULT_CAMERA;
  return {
    position: [...(cam.position ?? d.position)],
    focalPoint: [...(cam.focalPoint ?? d.focalPoint)],
    viewUp: [...(cam.viewUp ?? d.viewUp)],
    viewAngle: cam.viewAngle ?? d.viewAngle,
    parallelProjection: cam.parallelProjection ?? d.parallelProjection,
    parallelScale: cam.parallelScale ?? d.parallelScale,
  };
}

const finite3 = (v) => Array.isArray(v) && v.length === 3 && v.every(Number.isFinite);

/** Same rules as lc_camera_validate: returns null if usable, else a reason. */
export function validateCamera(cam) {
  if (!cam || typeof cam !== 'object') return 'camera is not an object';
  if (!finite3(cam.position)) return 'position must be 3 finite numbers';
  if (!finite3(cam.focalPoint)) return 'focalPoint must be 3 finite numbers';
  if (!finite3(cam.viewUp)) return 'viewUp must be 3 finite numbers';
  const dir = sub(cam.focalPoint, cam.position);
  if (length(dir) === 0) return 'position equals focalPoint';
  if (length(cam.viewUp) === 0) return 'viewUp is zero';
  if (length(cross(normalize(dir), normalize(cam.viewUp))) < 1e-6) return 'viewUp is parallel to the view direction';
  if (!(cam.viewAngle > 0 && cam.viewAngle < 180)) return 'viewAngle must be in (0, 180)';
  if (cam.parallelProjection && !(cam.parallelScale > 0 && Number.isFinite(cam.parallelScale)))
    return 'parallelScale must be > 0';
  return null;
}

/** Orthonormal camera frame: unit direction (to focal point), right, up. */
export function cameraFrame(cam) {
  let dir = normalize(sub(cam.focalPoint, cam.position));
  if (length(dir) === 0) dir = [0, 0, -1];
  let right = normalize(cross(dir, cam.viewUp));
  if (length(right) === 0) right = normalize(cross(dir, Math.abs(dir[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0]));
  const up = normalize(cross(right, dir));
  return { dir, right, up, distance: length(sub(cam.focalPoint, cam.position)) };
}

/**
 * Bounds as a flat [xmin,ymin,zmin,xmax,ymax,zmax]; accepts that form or the
 * [[xmin,ymin,zmin],[xmax,ymax,zmax]] of GET /api/v1/datasets. null if malformed.
 */
export function flatBounds(b) {
  if (Array.isArray(b) && b.length === 2 && Array.isArray(b[0]) && Array.isArray(b[1])) b = [...b[0], ...b[1]];
  return Array.isArray(b) && b.length === 6 && b.every(Number.isFinite) ? b : null;
}

/** Bounding sphere of [xmin,ymin,zmin,xmax,ymax,zmax] as in render/camera.c. */
export function boundsSphere(bounds) {
  const b = flatBounds(bounds) ?? [-0.5, -0.5, -0.5, 0.5, 0.5, 0.5];
  const center = [0.5 * (b[0] + b[3]), 0.5 * (b[1] + b[4]), 0.5 * (b[2] + b[5])];
  const h = [0.5 * (b[3] - b[0]), 0.5 * (b[4] - b[1]), 0.5 * (b[5] - b[2])];
  const r = length(h);
  return { center, radius: r > 0 ? r : 0.5 };
}

/**
 * ParaView's ResetCamera: look at the bounds along direction (camera → focal
 * point; default -Z) with the given up (default +Y) so that the bounding sphere
 * fills the view. Keeps viewAngle and projection, sets parallelScale to the radius.
 * aspect (width / height) < 1, a portrait view such as a phone's, fits the sphere
 * into the narrower horizontal angle instead, as vtkRenderer::ResetCamera does;
 * the default 1 is lc_camera_fit's fit.
 */
export function fitCamera(cam, bounds, direction = [0, 0, -1], up = [0, 1, 0], aspect = 1) {
  const out = cloneCamera(cam);
  let dir = normalize(direction);
  if (length(dir) === 0) dir = [0, 0, -1];
  let side = normalize(cross(dir, up));
  if (length(side) < 1e-9) side = normalize(cross(dir, Math.abs(dir[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0]));
  const vup = normalize(cross(side, dir));
  const { center, radius } = boundsSphere(bounds);
  if (!(out.viewAngle > 0 && out.viewAngle < 180)) out.viewAngle = 30;
  const a = aspect > 0 && aspect < 1 ? aspect : 1;
  const half = Math.atan(Math.tan((out.viewAngle * Math.PI) / 360) * a);
  const dist = radius / Math.sin(half);
  out.focalPoint = center;
  out.position = sub(center, scale(dir, dist));
  out.viewUp = vup;
  out.parallelScale = radius / a;
  return out;
}

/** Refit keeping the current direction and up (the "R" key). */
export function refitCamera(cam, bounds, aspect = 1) {
  return fitCamera(cam, bounds, sub(cam.focalPoint, cam.position), cam.viewUp, aspect);
}

/** ParaView's "Set view direction to ±X/±Y/±Z" buttons: the view direction and its up vector. */
export const AXIS_VIEWS = Object.freeze({
  '+x': { direction: [1, 0, 0], up: [0, 0, 1] },
  '-x': { direction: [-1, 0, 0], up: [0, 0, 1] },
  '+y': { direction: [0, 1, 0], up: [0, 0, 1] },
  '-y': { direction: [0, -1, 0], up: [0, 0, 1] },
  '+z': { direction: [0, 0, 1], up: [0, 1, 0] },
  '-z': { direction: [0, 0, -1], up: [0, 1, 0] },
});

/** Looks along an axis ('+x', '-z', ...) at the whole data. */
export function viewAlongAxis(cam, bounds, axis, aspect = 1) {
  const v = AXIS_VIEWS[axis];
  if (!v) throw new Error(`unknown axis view "${axis}"`);
  return fitCamera(cam, bounds, v.direction, v.up, aspect);
}

/**
 * Left-drag rotation about the focal point (ParaView's trackball rotate: a drag
 * across the whole viewport turns 360° about the view up; vertical drags turn
 * about the screen's right axis). dx, dy are CSS pixels in DOM coordinates (y down);
 * width, height the viewport size. Dragging right turns the data to the right.
 */
export function orbit(cam, dx, dy, width, height) {
  const { right, up } = cameraFrame(cam);
  const azimuth = (-2 * Math.PI * dx) / Math.max(width, 1);
  const elevation = (-2 * Math.PI * dy) / Math.max(height, 1);
  let offset = sub(cam.position, cam.focalPoint);
  let viewUp = up;
  offset = rotate(offset, up, azimuth);
  const right2 = rotate(right, up, azimuth);
  offset = rotate(offset, right2, elevation);
  viewUp = rotate(viewUp, right2, elevation);
  const out = cloneCamera(cam);
  out.position = add(cam.focalPoint, offset);
  out.viewUp = normalize(viewUp);
  return out;
}

/** World length of one CSS pixel at the focal plane. */
export function worldPerPixel(cam, height) {
  const h = Math.max(height, 1);
  if (cam.parallelProjection) return (2 * cam.parallelScale) / h;
  const dist = length(sub(cam.focalPoint, cam.position));
  return (2 * dist * Math.tan((cam.viewAngle * Math.PI) / 360)) / h;
}

/** Pan (middle/shift drag, two fingers): the data follows the pointer. */
export function pan(cam, dx, dy, width, height) {
  const { right, up } = cameraFrame(cam);
  const k = worldPerPixel(cam, height);
  const delta = add(scale(right, -dx * k), scale(up, dy * k));
  const out = cloneCamera(cam);
  out.position = add(cam.position, delta);
  out.focalPoint = add(cam.focalPoint, delta);
  return out;
}

/**
 * Dolly by factor (> 1 moves closer, as vtkCamera::Dolly). In parallel
 * projection the view height shrinks instead. minDistance keeps the camera off the
 * focal point.
 */
export function dolly(cam, factor, minDistance = 1e-9) {
  if (!(factor > 0) || !Number.isFinite(factor)) return cloneCamera(cam);
  const out = cloneCamera(cam);
  if (cam.parallelProjection) {
    out.parallelScale = Math.max(cam.parallelScale / factor, minDistance);
    return out;
  }
  const offset = sub(cam.position, cam.focalPoint);
  const dist = length(offset);
  const newDist = Math.max(dist / factor, minDistance);
  out.position = add(cam.focalPoint, scale(offset, newDist / (dist || 1)));
  return out;
}

/** Dolly factor of a right-drag (VTK: 1.1^(10·dy/half height); dragging up zooms in). */
export function dragDollyFactor(dy, height) {
  return Math.pow(1.1, (-10 * dy) / Math.max(height / 2, 1));
}

/** Dolly factor of a wheel event's deltaY in pixels (one 100 px notch = 1.1×, forward zooms in). */
export function wheelDollyFactor(deltaY) {
  return Math.pow(1.1, -deltaY / 100);
}

/** True when two cameras differ by more than eps (relative to the focal distance). */
export function camerasDiffer(a, b, eps = 1e-6) {
  const d = Math.max(length(sub(a.focalPoint, a.position)), 1e-12);
  const far = (u, v, s) => length(sub(u, v)) > eps * s;
  return (
    far(a.position, b.position, d) ||
    far(a.focalPoint, b.focalPoint, d) ||
    far(normalize(a.viewUp), normalize(b.viewUp), 1) ||
    Math.abs(a.viewAngle - b.viewAngle) > eps ||
    a.parallelProjection !== b.parallelProjection ||
    (a.parallelProjection && Math.abs(a.parallelScale - b.parallelScale) > eps * d)
  );
}

/** Rounds a camera for URLs and messages: significant digits keep it stable and short. */
export function roundCamera(cam, digits = 7) {
  const r = (x) => Number(Number(x).toPrecision(digits));
  const c = cloneCamera(cam);
  return {
    position: c.position.map(r),
    focalPoint: c.focalPoint.map(r),
    viewUp: c.viewUp.map(r),
    viewAngle: r(c.viewAngle),
    parallelProjection: !!c.parallelProjection,
    parallelScale: r(c.parallelScale),
  };
}
