// The page's stream-surface controls (web/js/surface-panel.js) and the seed's
// check in the protocol mirror, without a browser.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { defaultSeed, surfaceChanges, surfaceStatus, parsePoints, SURFACE_LOOK } from '../js/surface-panel.js';
import { fieldByPath, checkField } from '../js/schema.js';
import { checkClientMessage, paramsMessage } from '../js/protocol.js';

test('default seed: across the middle along y, a tenth in from the faces', () => {
  assert.deepEqual(
    defaultSeed([
      [0, 0, 0],
      [2, 10, 4],
    ]),
    [
      [1, 1, 2],
      [1, 9, 2],
    ],
  );
});

test('showing the surface sends surface then method; hiding goes back to the previous method', () => {
  const v = {
    field: 'demo:abc-flow',
    seed: [
      [1, 2, 3],
      [1, 4, 3],
    ],
    particles: 600,
    curvesPerFrame: 150,
    direction: 'both',
  };
  assert.deepEqual(surfaceChanges(true, v), [
    ['surface', v],
    ['method', 'surface-layers'],
  ]);
  assert.deepEqual(surfaceChanges(false, v, 'exact'), [['method', 'exact']]);
});

test("the seed's points between its ends and the look of the surface go with the surface object", () => {
  assert.deepEqual(parsePoints(''), []);
  assert.deepEqual(parsePoints('1,2,3; 4, 5, 6'), [
    [1, 2, 3],
    [4, 5, 6],
  ]);
  assert.equal(parsePoints('1,2; 4,5,6'), null);
  assert.equal(parsePoints('1,2,x'), null);
  const v = {
    field: 'f',
    seed: [
      [0, 0, 0],
      [1, 1, 1],
      [2, 0, 0],
    ],
    particles: 10,
    curvesPerFrame: 5,
    direction: 'forward',
    epsilon: 0.02,
    opacity: 0.5,
    maxLayers: 4,
    composite: 'weighted-sum',
    color: [1, 0, 0],
  };
  assert.deepEqual(surfaceChanges(true, v)[0], ['surface', v]);
  for (const [k, val] of Object.entries(SURFACE_LOOK)) {
    const f = fieldByPath(`surface.${k}`);
    assert.ok(f, `surface.${k} is a field`);
    assert.equal(checkField(f, val), null, `the page's default ${k} is valid`);
  }
});

test('status line from the frame header', () => {
  assert.equal(
    surfaceStatus({ curves: 450, particles: 600, layersPerPixel: 1.104, overflow: 0, k: 8 }),
    'curves 450 / 600 · 1.10 layers per pixel',
  );
  assert.match(
    surfaceStatus({ curves: 600, particles: 600, layersPerPixel: 2, overflow: 12, k: 4 }),
    /complete.*12 fragments beyond 4 layers/,
  );
  assert.equal(
    surfaceStatus({
      curves: 450,
      particles: 600,
      layersPerPixel: 1.104,
      overflow: 0,
      k: 8,
      drawnCurves: 150,
      drawnFragments: 9000,
      kept: true,
    }),
    'curves 450 / 600 · 1.10 layers per pixel · 150 added',
  );
  assert.match(
    surfaceStatus({
      curves: 450,
      particles: 600,
      layersPerPixel: 1,
      overflow: 0,
      k: 8,
      drawnCurves: 450,
      drawnFragments: 27000,
      kept: false,
    }),
    /450 drawn anew$/,
  );
  assert.equal(surfaceStatus(undefined), '');
});

test('surface.seed is checked as the server checks it', () => {
  const f = fieldByPath('surface.seed');
  assert.equal(
    checkField(f, [
      [0, 0, 0],
      [0, 1, 0],
    ]),
    null,
  );
  assert.equal(checkField(f, [[0, 0, 0]]).reason, '2 to 64 points (got 1)');
  assert.equal(
    checkField(f, [
      [0, 0, 0],
      [0, 0, 0],
    ]).at,
    '[1]',
  );
  assert.equal(
    checkField(f, [
      [0, 0, 'x'],
      [0, 1, 0],
    ]).reason,
    'expected an array of 3 finite numbers',
  );
});

test('params messages carry the surface object', () => {
  const msg = paramsMessage({
    method: 'surface-layers',
    surface: {
      field: 'demo:abc-flow',
      seed: [
        [1, 2, 3],
        [1, 4, 3],
      ],
    },
  });
  assert.doesNotThrow(() => checkClientMessage(msg));
  assert.throws(() => checkClientMessage({ type: 'params', surface: { seed: [[1, 2, 3]] } }), /surface\.seed/);
});
