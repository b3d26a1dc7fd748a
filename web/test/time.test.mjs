// The time bar's arithmetic (js/time-controller.js): which attribute is time, the window at t, its inverse,
// and play's steps.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { timeAttribute, windowAt, fromWindow, nextT, createTimeController } from '../js/time-controller.js';

const dump = {
  type: 'lines',
  attributes: [
    { name: 'type', range: [1, 3] },
    { name: 'timestep', range: [0, 190] },
  ],
};

test("the time attribute: the server's names in its order, a named one, none on surfaces", () => {
  assert.deepEqual(timeAttribute(dump), { name: 'timestep', range: [0, 190] });
  const both = {
    type: 'lines',
    attributes: [
      { name: 'timestep', range: [0, 9] },
      { name: 't', range: [0, 1] },
    ],
  };
  assert.equal(timeAttribute(both).name, 't'); // t comes before timestep, as in render/gl/filter.c
  assert.deepEqual(timeAttribute(dump, 'type'), { name: 'type', range: [1, 3] });
  assert.equal(timeAttribute(dump, 'nope'), null);
  assert.equal(timeAttribute({ type: 'points', attributes: ['time'] }), null); // no range: nothing to slide over
  assert.equal(timeAttribute({ ...dump, type: 'triangles' }), null);
  assert.equal(timeAttribute(undefined), null);
});

test('the window at t and back', () => {
  assert.deepEqual(windowAt(60, 0, [0, 190]), [0, 60]);
  assert.deepEqual(windowAt(60, 30, [0, 190]), [30, 60]);
  assert.deepEqual(windowAt(20, 30, [0, 190]), [0, 20]);
  assert.deepEqual(windowAt(500, 30, [0, 190]), [160, 190]);
  assert.deepEqual(fromWindow([30, 60], [0, 190]), { t: 60, length: 30 });
  assert.deepEqual(fromWindow([0, 60], [0, 190]), { t: 60, length: 0 });
  assert.deepEqual(fromWindow(undefined, [0, 190]), { t: 190, length: 0 });
});

test('play steps on a grid of a hundredth of the range and wraps', () => {
  assert.equal(nextT(0, [0, 190]), 1.9);
  assert.equal(nextT(60, [0, 190]), 60.8); // onto the grid from anywhere
  let t = 0;
  for (let i = 0; i < 47; i++) t = nextT(t, [0, 190]);
  assert.equal(t, 89.3); // no drift after many steps
  assert.equal(nextT(190, [0, 190]), 1.9);
  assert.equal(nextT(189, [0, 190]), 190);
});

test('play steps only once the last step is on screen, and the label says the rate', () => {
  const el = () => ({
    listeners: {},
    addEventListener(k, f) {
      this.listeners[k] = f;
    },
    setAttribute() {},
    value: '',
    textContent: '',
    hidden: false,
    checked: false,
    disabled: false,
  });
  const els = Object.fromEntries(
    ['time', 'time-t', 'time-length', 'time-play', 'time-markers', 'time-label'].map((id) => [id, el()]),
  );
  let frames = 0,
    now = 0,
    tick = null;
  const sent = [];
  const ctl = createTimeController({
    doc: { getElementById: (id) => els[id] },
    apply: (path, v) => sent.push(v),
    setInterval: (f) => ((tick = f), 1),
    clearInterval() {},
    framesDrawn: () => frames,
    now: () => now,
  });
  ctl.show({ time: { window: [0, 10] } }, { type: 'lines', attributes: [{ name: 'time', range: [0, 100] }] });
  els['time-play'].listeners.click(); // the first step goes out at once
  const first = sent.length;
  now += 200;
  tick();
  now += 200;
  tick(); // no frame of it yet: no step
  assert.equal(sent.length, first);
  for (let i = 0; i < 4; i++) {
    frames++;
    now += 400;
    tick();
  } // a frame every 400 ms: a step each
  assert.equal(sent.length, first + 4);
  assert.match(els['time-label'].textContent, / · 2\.[0-9] steps\/s$/);
  ctl.stop();
});
