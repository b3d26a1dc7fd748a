// The page's keyframe interpolation (js/camera-path.js) against the server's
// (render/math/camera_path.c). The expected cameras were printed by a small C
// program that called lc_camera_path(keys, 3, i, 7) and
// lc_camera_interpolate(keys[0], keys[1], 0.3) on the keyframes below.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { cameraPathFrame, interpolateCamera } from '../js/camera-path.js';

const keys = [
  { position: [0, 0, 10], focalPoint: [0, 0, 0], viewUp: [0, 1, 0], viewAngle: 30, parallelScale: 2 },
  { position: [6, 2, 1], focalPoint: [0.5, 0, 0], viewUp: [0, 0.8, 0.6], viewAngle: 40, parallelScale: 1 },
  { position: [-3, 4, -20], focalPoint: [1, 1, 1], viewUp: [1, 0, 0], viewAngle: 25, parallelScale: 8 },
];

const fromC = {
  0: {
    position: [0, 0, 10.000000000000002],
    focalPoint: [0, 0, 0],
    viewUp: [0, 1, 0],
    viewAngle: 30,
    parallelScale: 2,
  },
  1: {
    position: [4.0626083680186929, -0.0090982962228577432, 7.4472772003852779],
    focalPoint: [0.16666666666666666, 0, 0],
    viewUp: [-0.23961162013873902, 0.96258898674649784, 0.1265255471785805],
    viewAngle: 33.333333333333336,
    parallelScale: 1.5874010519681996,
  },
  2: {
    position: [6.0299007694118183, 0.87312139318861126, 4.085023191980147],
    focalPoint: [0.33333333333333331, 0, 0],
    viewUp: [-0.37640207902314099, 0.86151456530663084, 0.34075523278679676],
    viewAngle: 36.666666666666664,
    parallelScale: 1.2599210498948732,
  },
  3: {
    position: [6.0000000000000009, 2.0000000000000004, 0.99999999999999944],
    focalPoint: [0.5, 0, 0],
    viewUp: [-0.36957075705348758, 0.726924298997769, 0.57879056579864385],
    viewAngle: 40,
    parallelScale: 1,
  },
  4: {
    position: [8.8707390773008292, 1.0817126497052691, -3.6014239422620644],
    focalPoint: [0.66666666666666663, 0.33333333333333326, 0.33333333333333326],
    viewUp: [0.29522953360450099, 0.61368013994617909, 0.7322815089317134],
    viewAngle: 35,
    parallelScale: 1.9999999999999996,
  },
  5: {
    position: [7.1111587226753157, 0.68929172730186927, -11.889960855805963],
    focalPoint: [0.83333333333333337, 0.66666666666666674, 0.66666666666666674],
    viewUp: [0.84437218855683938, 0.3291218475983414, 0.42274627925646791],
    viewAngle: 30,
    parallelScale: 4,
  },
  6: {
    position: [-2.9999999999999996, 4, -20],
    focalPoint: [1, 1, 1],
    viewUp: [0.98268267312062751, 0.02620487128321658, -0.1834340989825172],
    viewAngle: 25,
    parallelScale: 7.9999999999999982,
  },
  t03: {
    position: [3.7460681932888238, -0.059361090389815165, 7.7590949188060909],
    focalPoint: [0.14999999999999999, 0, 0],
    viewUp: [-0.21927912252449316, 0.96954922256919029, 0.10904573095892839],
    viewAngle: 33,
    parallelScale: 1.6245047927124709,
  },
};

const close = (a, b, what) => {
  if (Array.isArray(a)) a.forEach((x, i) => close(x, b[i], `${what}[${i}]`));
  else assert.ok(Math.abs(a - b) <= 1e-12 * Math.max(1, Math.abs(b)), `${what}: ${a} != ${b} (C)`);
};
const same = (cam, ref, what) => {
  for (const f of ['position', 'focalPoint', 'viewUp', 'viewAngle', 'parallelScale'])
    close(cam[f], ref[f], `${what} ${f}`);
};

test("cameraPathFrame gives lc_camera_path's cameras through three keyframes", () => {
  for (let i = 0; i < 7; i++) same(cameraPathFrame(keys, i, 7), fromC[i], `frame ${i}`);
});

test("interpolateCamera gives lc_camera_interpolate's camera at t = 0.3", () => {
  same(interpolateCamera(keys[0], keys[1], 0.3), fromC.t03, 't 0.3');
});

test('the zoom is log-linear and the up vector stays unit', () => {
  const mid = interpolateCamera(keys[0], keys[2], 0.5);
  const d = (c) => Math.hypot(...c.position.map((x, i) => x - c.focalPoint[i]));
  close(d(mid), Math.sqrt(d(keys[0]) * d(keys[2])), 'geometric mean distance');
  close(Math.hypot(...mid.viewUp), 1, '|up|');
});
