// The Streamlines group's object (web/js/streamlines-panel.js): the keys each seeding reads, errors for points that
// do not suit it, and the link carrying a seed list as JSON text (the server's query parser reads it so).
import { test } from 'node:test';
import assert from 'node:assert/strict';

import { streamlinesObject, STREAMLINE_DEFAULTS } from '../js/streamlines-panel.js';
import { formatHash, parseHash } from '../js/url-state.js';

const form = (over) => ({ ...STREAMLINE_DEFAULTS, seeds: '', ...over });

test('each seeding sends the keys it reads', () => {
  assert.deepEqual(streamlinesObject(form({})), { seeding: 'density', direction: 'forward', count: 64 });
  assert.deepEqual(
    streamlinesObject(form({ seeding: 'rake', seeds: '0,0,0; 1, 2, 3', count: 5, length: 0.4, separation: 0.2 })),
    {
      seeding: 'rake',
      direction: 'forward',
      seeds: [
        [0, 0, 0],
        [1, 2, 3],
      ],
      count: 5,
      length: 0.4,
    },
  );
  assert.deepEqual(
    streamlinesObject(form({ seeding: 'points', seeds: '1,1,1', count: 9, step: 0.01, direction: 'both' })),
    { seeding: 'points', direction: 'both', seeds: [[1, 1, 1]], step: 0.01 },
  );
  assert.deepEqual(streamlinesObject(form({ separation: 0.3 })), {
    seeding: 'density',
    direction: 'forward',
    count: 64,
    separation: 0.3,
  });
});

test('points that do not suit the seeding are an error, not a request', () => {
  assert.match(streamlinesObject(form({ seeding: 'rake', seeds: '0,0,0' })).error, /two ends/);
  assert.match(streamlinesObject(form({ seeding: 'points' })).error, /at least one/);
  assert.match(streamlinesObject(form({ seeding: 'box', seeds: '0,0,0' })).error, /two corners/);
  assert.match(streamlinesObject(form({ seeds: '0,0' })).error, /x, y, z/);
});

test('the link carries the seeds as JSON text and reads them back', () => {
  const update = {
    streamlines: {
      seeding: 'rake',
      seeds: [
        [0, -0.8, 0],
        [0, 0.8, 0.5],
      ],
      count: 5,
    },
  };
  const hash = formatHash({ dataset: 'demo:shear-flow', update });
  assert.match(hash, /streamlinesSeeds=%5B%5B0,-0\.8,0%5D,%5B0,0\.8,0\.5%5D%5D/);
  assert.deepEqual(parseHash(hash).update.streamlines, update.streamlines);
});
