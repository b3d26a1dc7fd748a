// The seed line's handles over the view (web/js/seed-handles.js): projection and
// unprojection agree, and a drag moves the endpoint in the plane facing the camera.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { projectSeed, unprojectAt, hitHandle, dragSeed } from '../js/seed-handles.js';
import { cameraFrame, fitCamera, DEFAULT_CAMERA, sub, dot, length } from '../js/camera.js';

const W = 640,
  H = 400;
const bounds = [
  [0, 0, 0],
  [6.28319, 6.28319, 6.28319],
];
const persp = fitCamera(DEFAULT_CAMERA, [0, 0, 0, 6.28319, 6.28319, 6.28319], [-1, 1.5, -0.8], [0, 0, 1], W / H);
const para = { ...persp, parallelProjection: true };
const close = (a, b, eps, what) => a.forEach((v, i) => assert.ok(Math.abs(v - b[i]) <= eps, `${what}: ${a} vs ${b}`));

test('the focal point projects to the view centre; a point right of it to the right', () => {
  const [c, r] = projectSeed(persp, W, H, [
    persp.focalPoint,
    persp.focalPoint.map((f, i) => f + cameraFrame(persp).right[i]),
  ]);
  close(c, [W / 2, H / 2], 1e-9, 'centre');
  assert.ok(r[0] > W / 2 + 10 && Math.abs(r[1] - H / 2) < 1e-6, `right: ${r}`);
});

test("unproject at a point's depth inverts projection, perspective and parallel", () => {
  for (const cam of [persp, para]) {
    for (const p of [
      [1, 2, 3],
      [5, 0.5, 4],
      [3.1, 3.1, 3.1],
    ]) {
      const [px] = projectSeed(cam, W, H, [p]);
      close(unprojectAt(cam, W, H, px, p), p, 1e-9, `round trip ${cam.parallelProjection}`);
      // another pixel lands in the same plane facing the camera, and projects back there
      const q = unprojectAt(cam, W, H, [px[0] + 37, px[1] - 21], p);
      const { dir } = cameraFrame(cam);
      assert.ok(Math.abs(dot(sub(q, p), dir)) < 1e-9, 'same depth');
      close(projectSeed(cam, W, H, [q])[0], [px[0] + 37, px[1] - 21], 1e-6, 'moved pixel');
    }
  }
});

test('a point behind a perspective camera has no pixel and no plane', () => {
  const behind = sub(persp.position, sub(persp.focalPoint, persp.position));
  assert.equal(projectSeed(persp, W, H, [behind])[0], null);
  assert.equal(unprojectAt(persp, W, H, [10, 10], behind), null);
});

test('hitHandle: the nearer handle within the radius, else -1', () => {
  const pts = [
    [100, 100],
    [110, 100],
  ];
  assert.equal(hitHandle(pts, [103, 100]), 0);
  assert.equal(hitHandle(pts, [108, 101]), 1);
  assert.equal(hitHandle(pts, [100, 120]), -1);
  assert.equal(hitHandle([null, [50, 50]], [50, 52]), 1);
});

test("dragging a handle moves only that endpoint, by the pointer's offset in its screen plane", () => {
  const seed = [
    [3.14159, 0.628319, 3.14159],
    [3.14159, 5.65487, 3.14159],
  ];
  const [pa] = projectSeed(persp, W, H, seed);
  const from = [pa[0] + 2, pa[1] - 3]; // grabbed a little off centre
  const to = [from[0] + 40, from[1] + 25];
  const out = dragSeed(persp, W, H, seed, 0, from, to);
  assert.deepEqual(out[1], seed[1], 'the other endpoint stays');
  assert.notDeepEqual(out[0], seed[0]);
  // the endpoint keeps its depth and now appears 40 px right, 25 px down
  const { dir } = cameraFrame(persp);
  assert.ok(Math.abs(dot(sub(out[0], seed[0]), dir)) < 1e-4, 'same depth');
  close(projectSeed(persp, W, H, out)[0], [pa[0] + 40, pa[1] + 25], 1e-3, 'follows the pointer');
  // rounded as the typed field shows it
  for (const v of out[0]) assert.equal(v, Number(v.toPrecision(6)));
  // the input seed is not changed
  assert.deepEqual(seed[0], [3.14159, 0.628319, 3.14159]);
});

test("a drag is clamped to the field's bounds when they are given; no move, no change", () => {
  const seed = [
    [3, 3, 3],
    [3, 5, 3],
  ];
  const [, pb] = projectSeed(persp, W, H, seed);
  const far = dragSeed(persp, W, H, seed, 1, pb, [pb[0] + 5000, pb[1] - 5000], bounds);
  far[1].forEach((v, i) => assert.ok(v >= bounds[0][i] && v <= bounds[1][i], `inside: ${far[1]}`));
  assert.ok(length(sub(far[1], seed[1])) > 1);
  assert.deepEqual(dragSeed(persp, W, H, seed, 1, pb, pb, bounds), seed);
});
