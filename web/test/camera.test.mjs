// Camera math: ParaView conventions, fitting as render/camera.c, navigation.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import * as C from '../js/camera.js';

const close = (a, b, eps = 1e-9, what = '') => {
  if (Array.isArray(a)) a.forEach((x, i) => close(x, b[i], eps, `${what}[${i}]`));
  else assert.ok(Math.abs(a - b) <= eps, `${what}: ${a} != ${b}`);
};
const base = () => C.cloneCamera({ position: [0, 0, 10], focalPoint: [0, 0, 0], viewUp: [0, 1, 0], viewAngle: 30 });

test('fit matches lc_camera_fit: bounding sphere fills the view', () => {
  const b = [-1, -2, -3, 1, 2, 3];
  const cam = C.fitCamera(base(), b);
  const r = Math.sqrt(1 + 4 + 9);
  close(cam.focalPoint, [0, 0, 0]);
  close(cam.position, [0, 0, r / Math.sin((15 * Math.PI) / 180)], 1e-9, 'position');
  close(cam.viewUp, [0, 1, 0]);
  close(cam.parallelScale, r);
  assert.equal(C.validateCamera(cam), null);
});

test('degenerate bounds get radius 0.5 and a parallel up is replaced', () => {
  const cam = C.fitCamera(base(), [2, 2, 2, 2, 2, 2], [0, 1, 0], [0, 1, 0]);
  close(cam.focalPoint, [2, 2, 2]);
  close(C.length(C.sub(cam.position, cam.focalPoint)), 0.5 / Math.sin((15 * Math.PI) / 180));
  assert.equal(C.validateCamera(cam), null);
  close(C.dot(cam.viewUp, [0, 1, 0]), 0, 1e-12);
});

test('refit keeps direction and up', () => {
  const cam = C.orbit(base(), 37, -21, 640, 480);
  const fit = C.refitCamera(cam, [0, 0, 0, 2, 2, 2]);
  const d0 = C.normalize(C.sub(cam.focalPoint, cam.position));
  const d1 = C.normalize(C.sub(fit.focalPoint, fit.position));
  close(d1, d0, 1e-9, 'dir');
  close(fit.focalPoint, [1, 1, 1]);
  close(C.dot(fit.viewUp, C.cameraFrame(cam).up), 1, 1e-9);
});

test('axis views follow ParaView (+X looks along +X with Z up)', () => {
  for (const [axis, v] of Object.entries(C.AXIS_VIEWS)) {
    const cam = C.viewAlongAxis(base(), [-1, -1, -1, 1, 1, 1], axis);
    close(C.normalize(C.sub(cam.focalPoint, cam.position)), v.direction, 1e-12, axis);
    close(cam.viewUp, v.up, 1e-12, axis);
  }
  assert.throws(() => C.viewAlongAxis(base(), [0, 0, 0, 1, 1, 1], '+w'));
});

test('orbit keeps the focal point and distance, a full-width drag turns 360°', () => {
  const cam = base();
  const o = C.orbit(cam, 160, 0, 640, 480); // quarter turn about +Y
  close(o.focalPoint, [0, 0, 0]);
  close(C.length(o.position), 10, 1e-9);
  // dragging right turns the data right: the camera moves to -X
  close(o.position, [-10, 0, 0], 1e-9, 'position');
  const full = C.orbit(cam, 640, 0, 640, 480);
  close(full.position, cam.position, 1e-9, 'full turn');
  const up = C.orbit(cam, 0, -120, 640, 480); // drag up a quarter: camera goes below
  close(up.position, [0, -10, 0], 1e-9, 'elevation');
  close(C.dot(up.viewUp, C.normalize(C.sub(up.focalPoint, up.position))), 0, 1e-12);
  assert.equal(C.validateCamera(up), null);
});

test('orbit composed many times stays orthonormal', () => {
  let cam = base();
  for (let i = 0; i < 500; i++) cam = C.orbit(cam, 7 * Math.sin(i), 5 * Math.cos(i * 1.3), 640, 480);
  close(C.length(C.sub(cam.position, cam.focalPoint)), 10, 1e-6);
  close(C.length(cam.viewUp), 1, 1e-9);
  assert.equal(C.validateCamera(cam), null);
});

test('pan moves position and focal point together, one viewport height = view height', () => {
  const cam = base();
  const p = C.pan(cam, 0, 480, 640, 480); // drag down by the full height
  const h = 2 * 10 * Math.tan((15 * Math.PI) / 180);
  close(p.focalPoint, [0, h, 0], 1e-9, 'focal'); // data moves down = camera moves up
  close(C.sub(p.position, p.focalPoint), [0, 0, 10]);
  const q = C.pan({ ...cam, parallelProjection: true, parallelScale: 2 }, 64, 0, 640, 480);
  close(q.focalPoint, [-64 * (4 / 480), 0, 0], 1e-12);
});

test('dolly: factor > 1 approaches, parallel scales, never reaches the focal point', () => {
  const cam = base();
  close(C.dolly(cam, 2).position, [0, 0, 5]);
  close(C.dolly(cam, 0.5).position, [0, 0, 20]);
  assert.deepEqual(C.dolly(cam, NaN), cam);
  const par = C.dolly({ ...cam, parallelProjection: true, parallelScale: 4 }, 2);
  close(par.parallelScale, 2);
  close(par.position, [0, 0, 10]);
  let c = cam;
  for (let i = 0; i < 2000; i++) c = C.dolly(c, 10);
  assert.ok(C.length(c.position) > 0);
  assert.equal(C.validateCamera(c), null);
  assert.ok(C.wheelDollyFactor(-100) > 1 && C.wheelDollyFactor(100) < 1);
  close(C.wheelDollyFactor(-100), 1.1, 1e-12);
  assert.ok(C.dragDollyFactor(-10, 480) > 1, 'dragging up zooms in');
});

test('validateCamera rejects what the server rejects', () => {
  assert.match(C.validateCamera({ ...base(), position: [0, 0, 0] }), /focalPoint/);
  assert.match(C.validateCamera({ ...base(), viewUp: [0, 0, 1] }), /parallel/);
  assert.match(C.validateCamera({ ...base(), viewAngle: 180 }), /viewAngle/);
  assert.match(C.validateCamera({ ...base(), position: [0, NaN, 1] }), /position/);
  assert.match(C.validateCamera({ ...base(), parallelProjection: true, parallelScale: 0 }), /parallelScale/);
});

test('cameras compare and round', () => {
  const a = base();
  assert.equal(C.camerasDiffer(a, C.cloneCamera(a)), false);
  assert.equal(C.camerasDiffer(a, C.orbit(a, 1, 0, 640, 480)), true);
  const r = C.roundCamera({ ...a, position: [0.1 + 0.2, 1 / 3, 10] });
  assert.deepEqual(r.position, [0.3, 0.3333333, 10]);
});
