// Keyframe interpolation of cameras for the page's movie preview: the same
// cameras as the server's movies (render/math/camera_path.c): focal point and
// view angle linear, orientation (right, up, back frame) by slerp, distance to
// the focal point and parallel scale log-linear; keyframe segments share the
// frames evenly, frames 0 and n-1 are the first and last keyframes.

const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const normalize = (v) => {
  const l = Math.sqrt(dot(v, v));
  return l > 0 ? [v[0] / l, v[1] / l, v[2] / l] : v;
};

// Unit quaternion [w, x, y, z] of the rotation whose columns are right, up, back.
function cameraQuat(cam) {
  const d = normalize([0, 1, 2].map((i) => cam.focalPoint[i] - cam.position[i]));
  const r = normalize(cross(d, cam.viewUp));
  const u = cross(r, d);
  const [m00, m10, m20, m01, m11, m21] = [r[0], r[1], r[2], u[0], u[1], u[2]];
  const [m02, m12, m22] = [-d[0], -d[1], -d[2]];
  const tr = m00 + m11 + m22;
  let q, s;
  if (tr > 0) {
    s = Math.sqrt(tr + 1.0) * 2;
    q = [0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s];
  } else if (m00 > m11 && m00 > m22) {
    s = Math.sqrt(1.0 + m00 - m11 - m22) * 2;
    q = [(m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s];
  } else if (m11 > m22) {
    s = Math.sqrt(1.0 + m11 - m00 - m22) * 2;
    q = [(m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s];
  } else {
    s = Math.sqrt(1.0 + m22 - m00 - m11) * 2;
    q = [(m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s];
  }
  const n = Math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  return q.map((x) => x / n);
}

function quatRotate(q, v) {
  const u = [q[1], q[2], q[3]];
  const t = cross(u, v).map((x) => 2 * x);
  const ut = cross(u, t);
  return [0, 1, 2].map((i) => v[i] + q[0] * t[i] + ut[i]);
}

function slerp(a, b0, t) {
  let d = 0;
  for (let i = 0; i < 4; i++) d += a[i] * b0[i];
  const b = b0.map((x) => (d < 0 ? -x : x));
  d = Math.abs(d);
  let s0 = 1 - t,
    s1 = t;
  if (d < 0.9995) {
    // otherwise linear, then normalized: sin(th) would vanish
    const th = Math.acos(d);
    s0 = Math.sin((1 - t) * th) / Math.sin(th);
    s1 = Math.sin(t * th) / Math.sin(th);
  }
  const out = a.map((x, i) => s0 * x + s1 * b[i]);
  const n = Math.sqrt(out.reduce((acc, x) => acc + x * x, 0));
  return out.map((x) => x / n);
}

const loglerp = (a, b, t) => (a > 0 && b > 0 ? Math.exp((1 - t) * Math.log(a) + t * Math.log(b)) : a + t * (b - a));

// The camera a fraction t in [0, 1] of the way from a to b (lc_camera_interpolate).
export function interpolateCamera(a, b, t) {
  const q = slerp(cameraQuat(a), cameraQuat(b), t);
  const da = [0, 1, 2].map((i) => a.position[i] - a.focalPoint[i]);
  const db = [0, 1, 2].map((i) => b.position[i] - b.focalPoint[i]);
  const dist = loglerp(Math.sqrt(dot(da, da)), Math.sqrt(dot(db, db)), t);
  const back = quatRotate(q, [0, 0, 1]);
  const focalPoint = [0, 1, 2].map((i) => a.focalPoint[i] + t * (b.focalPoint[i] - a.focalPoint[i]));
  return {
    ...a,
    focalPoint,
    position: [0, 1, 2].map((i) => focalPoint[i] + back[i] * dist),
    viewUp: quatRotate(q, [0, 1, 0]),
    viewAngle: a.viewAngle + t * (b.viewAngle - a.viewAngle),
    parallelScale: loglerp(a.parallelScale, b.parallelScale, t),
  };
}

// Frame i of n (n >= 2) through keys (at least 2), as lc_camera_path.
export function cameraPathFrame(keys, i, n) {
  const segs = keys.length - 1;
  const u = n > 1 ? (i * segs) / (n - 1) : 0;
  const k = Math.max(0, Math.min(segs - 1, Math.floor(u)));
  return interpolateCamera(keys[k], keys[k + 1], u - k);
}
