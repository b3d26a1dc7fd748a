// Client-side image warp between frames: while a frame for the newest camera is
// on its way, the last frame is redrawn with the 2D affine transform that moves
// its focal plane to where the current camera sees it. Exact for pans, zooms
// and rolls, a first-order approximation for rotations (depth away from the
// focal plane shifts by parallax the warp cannot know). Pure math, Node-tested.

import { cameraFrame, sub, add, scale, dot } from './camera.js';

/**
 * A projection of world points to canvas pixels (x right, y down) for a camera
 * and a canvas of width × height pixels, as the server renders it (vertical
 * view angle, square pixels). Returns p => [x, y] or null behind the camera.
 */
export function projector(cam, width, height) {
  const { dir, right, up } = cameraFrame(cam);
  const h2 = height / 2,
    w2 = width / 2;
  if (cam.parallelProjection) {
    const k = h2 / (cam.parallelScale || 1);
    return (p) => {
      const v = sub(p, cam.position);
      return [w2 + k * dot(v, right), h2 - k * dot(v, up)];
    };
  }
  const f = h2 / Math.tan((cam.viewAngle * Math.PI) / 360);
  return (p) => {
    const v = sub(p, cam.position);
    const z = dot(v, dir);
    if (!(z > 1e-9)) return null;
    return [w2 + (f * dot(v, right)) / z, h2 - (f * dot(v, up)) / z];
  };
}

/**
 * The canvas transform [a, b, c, d, e, f] (as CanvasRenderingContext2D.setTransform)
 * that draws an image rendered with camera `from` so that it approximates the
 * view of camera `to`: three points of from's focal plane (the focal point and
 * one step right and up) map to where `to` projects them. null when the warp is
 * meaningless (a point behind the camera, a degenerate or extreme result): the
 * caller then shows the frame as it is.
 */
export function warpTransform(from, to, width, height) {
  const { right, up, distance } = cameraFrame(from);
  const s = (cam) =>
    (cam.parallelProjection ? cam.parallelScale : distance * Math.tan((cam.viewAngle * Math.PI) / 360)) * 0.5;
  const step = s(from) || 1;
  const pts = [from.focalPoint, add(from.focalPoint, scale(right, step)), add(from.focalPoint, scale(up, step))];
  const P = projector(from, width, height),
    Q = projector(to, width, height);
  const a = pts.map(P),
    b = pts.map(Q);
  if (a.some((x) => !x) || b.some((x) => !x)) return null;
  // solve for M (2×2) and t: b_i = M a_i + t, with a_1 - a_0 and a_2 - a_0 as the basis
  const u1 = [a[1][0] - a[0][0], a[1][1] - a[0][1]],
    u2 = [a[2][0] - a[0][0], a[2][1] - a[0][1]];
  const v1 = [b[1][0] - b[0][0], b[1][1] - b[0][1]],
    v2 = [b[2][0] - b[0][0], b[2][1] - b[0][1]];
  const det = u1[0] * u2[1] - u2[0] * u1[1];
  if (Math.abs(det) < 1e-9) return null;
  // M = [v1 v2] · [u1 u2]^-1
  const inv = [u2[1] / det, -u2[0] / det, -u1[1] / det, u1[0] / det]; // rows of the inverse
  const m00 = v1[0] * inv[0] + v2[0] * inv[2],
    m01 = v1[0] * inv[1] + v2[0] * inv[3];
  const m10 = v1[1] * inv[0] + v2[1] * inv[2],
    m11 = v1[1] * inv[1] + v2[1] * inv[3];
  const e = b[0][0] - (m00 * a[0][0] + m01 * a[0][1]);
  const f = b[0][1] - (m10 * a[0][0] + m11 * a[0][1]);
  const m = [m00, m10, m01, m11, e, f];
  const sx = Math.hypot(m00, m10),
    sy = Math.hypot(m01, m11);
  if (!m.every(Number.isFinite) || sx > 50 || sy > 50 || sx < 0.02 || sy < 0.02) return null;
  return m;
}

/** True when the transform is the identity within a tenth of a pixel. */
export function isIdentity(m, width = 1000) {
  if (!m) return true;
  const eps = 0.1 / Math.max(width, 1);
  return (
    Math.abs(m[0] - 1) < eps &&
    Math.abs(m[1]) < eps &&
    Math.abs(m[2]) < eps &&
    Math.abs(m[3] - 1) < eps &&
    Math.abs(m[4]) < 0.1 &&
    Math.abs(m[5]) < 0.1
  );
}

/**
 * The screen directions of the world axes for an orientation triad: for X, Y, Z
 * the unit vector's projection onto the camera's right and up ([x, y] with y up)
 * and its depth toward the viewer (positive = pointing at the viewer).
 */
export function axesDirections(cam) {
  const { dir, right, up } = cameraFrame(cam);
  return [
    [1, 0, 0],
    [0, 1, 0],
    [0, 0, 1],
  ].map((e, i) => ({ axis: 'XYZ'[i], x: dot(e, right), y: dot(e, up), toward: -dot(e, dir) }));
}
