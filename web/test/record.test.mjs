// The page's "Record" controller (js/record-controller.js): keyframes from the
// view, the preview's cameras, the movie request and the job's polling.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRecordController } from '../js/record-controller.js';
import { cameraPathFrame } from '../js/camera-path.js';

const cam = (z, x = 0) => ({
  position: [x, 0, z],
  focalPoint: [0, 0, 0],
  viewUp: [0, 1, 0],
  viewAngle: 30,
  parallelScale: 1,
  parallelProjection: false,
});

function harness(polls = []) {
  const calls = [];
  let current = cam(10);
  let clock = 0;
  const frames = [];
  const api = {
    async createMovie(body) {
      calls.push(['create', body]);
      return { id: 'abc', state: 'queued', progress: 0 };
    },
    async movie(id) {
      calls.push(['get', id]);
      return polls.shift();
    },
    movieFileUrl: (id) => `http://x/api/v1/movies/${id}/file`,
  };
  const changes = [];
  const rec = createRecordController({
    getCamera: () => current,
    setCamera: (c) => (current = c),
    request: () => ({
      dataset: 'demo:tornado',
      width: 640,
      height: 480,
      format: 'png',
      camera: current,
      params: { q: 60 },
    }),
    api,
    onChange: () => changes.push(rec.view()),
    now: () => clock,
    frame: (fn) => frames.push(fn),
    sleep: async () => {},
  });
  return {
    rec,
    calls,
    changes,
    frames,
    setCamera: (c) => (current = c),
    get camera() {
      return current;
    },
    tick: (ms) => (clock += ms),
  };
}

test('keyframes come from the current view; remove takes one out', () => {
  const h = harness();
  h.rec.add();
  h.setCamera(cam(5, 3));
  h.rec.add();
  h.setCamera(cam(20));
  h.rec.add();
  assert.equal(h.rec.view().keys.length, 3);
  h.rec.remove(1);
  const keys = h.rec.keys();
  assert.deepEqual(
    keys.map((k) => k.position),
    [
      [0, 0, 10],
      [0, 0, 20],
    ],
  );
  assert.equal(h.rec.view().canRender, true);
  h.rec.remove(0);
  assert.equal(h.rec.view().canRender, false, 'one keyframe cannot make a path');
});

test("the movie request carries the keyframes and the view's request without size, camera or format", () => {
  const h = harness();
  h.rec.add();
  h.setCamera(cam(5, 3));
  h.rec.add();
  const body = h.rec.movieBody({ duration: 2, fps: 3, width: 160, height: 96, codec: 'h264' });
  assert.deepEqual(body.request, { dataset: 'demo:tornado', params: { q: 60 } });
  assert.equal(body.path, 'keyframes');
  assert.deepEqual(
    body.keyframes.map((k) => k.position),
    [
      [0, 0, 10],
      [3, 0, 5],
    ],
  );
  assert.deepEqual([body.duration, body.fps, body.width, body.height, body.codec], [2, 3, 160, 96, 'h264']);
});

test("the preview moves the view along the movie's path and ends on the last keyframe", async () => {
  const h = harness();
  h.rec.add();
  h.setCamera(cam(5, 3));
  h.rec.add();
  const done = h.rec.preview(2);
  assert.ok(
    Math.abs(h.camera.position[2] - 10) < 1e-9 && Math.abs(h.camera.position[0]) < 1e-9,
    `starts at ${h.camera.position}`,
  );
  h.tick(1000);
  h.frames.shift()();
  const mid = cameraPathFrame(h.rec.keys(), Math.round(0.5 * 999), 1000);
  assert.deepEqual(h.camera.position, mid.position, "half way in time is the path's middle");
  h.tick(1000);
  h.frames.shift()();
  assert.equal(await done, true);
  assert.ok(
    Math.abs(h.camera.position[0] - 3) < 1e-9 && Math.abs(h.camera.position[2] - 5) < 1e-9,
    `ends at ${h.camera.position}`,
  );
});

test('render posts the job, polls its progress and gives the file link when done', async () => {
  const h = harness([
    { id: 'abc', state: 'running', progress: 0.5 },
    { id: 'abc', state: 'done', progress: 1 },
  ]);
  h.rec.add();
  h.setCamera(cam(5, 3));
  h.rec.add();
  const job = await h.rec.render({ duration: 2, fps: 3, width: 160, height: 96, codec: 'h264' }, 0);
  assert.equal(job.state, 'done');
  assert.equal(job.url, 'http://x/api/v1/movies/abc/file');
  assert.deepEqual(
    h.calls.map((c) => c[0]),
    ['create', 'get', 'get'],
  );
  assert.ok(
    h.changes.some((v) => v.job?.state === 'running' && v.job.progress === 0.5),
    'progress was shown',
  );
});

test("a failed job shows the server's message; too few keyframes never reach the server", async () => {
  const h = harness([{ id: 'abc', state: 'failed', progress: 0.2, error: { code: 'x', message: 'encoder broke' } }]);
  h.rec.add();
  let job = await h.rec.render({ duration: 1, fps: 6, width: 160, height: 96, codec: 'h264' }, 0);
  assert.equal(job.state, 'failed');
  assert.equal(h.calls.length, 0);
  h.setCamera(cam(5, 3));
  h.rec.add();
  job = await h.rec.render({ duration: 1, fps: 6, width: 160, height: 96, codec: 'h264' }, 0);
  assert.equal(job.state, 'failed');
  assert.equal(job.error, 'encoder broke');
});
