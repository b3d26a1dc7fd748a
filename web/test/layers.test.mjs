// The layer list's model (js/layers-controller.js): adding keeps the shown dataset as layer 1, edits touch one
// layer, removing the last layer goes back to the single dataset, and the legend's line per visible layer.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  addLayer,
  setLayer,
  removeLayer,
  layerLegend,
  layerFilter,
  timeWindow,
  MAX_LAYERS,
} from '../js/layers-controller.js';

test('adding: the first addition keeps the shown dataset as layer 1; at most 8', () => {
  assert.deepEqual(addLayer([], 'demo:points', 'demo:tornado'), [
    { dataset: 'demo:points' },
    { dataset: 'demo:tornado' },
  ]);
  assert.deepEqual(addLayer([{ dataset: 'a' }], 'x', 'b'), [{ dataset: 'a' }, { dataset: 'b' }]);
  let l = [];
  for (let i = 0; i < 12; i++) l = addLayer(l, 'a', `d${i}`);
  assert.equal(l.length, MAX_LAYERS);
});

test('editing one layer: visible, role, attributes (a new one drops its range; "" = the default)', () => {
  const l = [{ dataset: 'a' }, { dataset: 'b', color: { attribute: 'x', range: [0, 1] } }];
  assert.deepEqual(setLayer(l, 1, 'visible', false)[1], {
    dataset: 'b',
    visible: false,
    color: { attribute: 'x', range: [0, 1] },
  });
  assert.equal(setLayer(l, 0, 'role', 'context')[0].role, 'context');
  assert.deepEqual(setLayer(l, 1, 'color.attribute', 'y')[1].color, { attribute: 'y' });
  assert.equal(setLayer(l, 1, 'color.attribute', '')[1].color, undefined);
  assert.deepEqual(setLayer(l, 0, 'importance.attribute', 'speed')[0], {
    dataset: 'a',
    importance: { attribute: 'speed' },
  });
  assert.deepEqual(l[1].color, { attribute: 'x', range: [0, 1] }); // the input is left alone
  assert.deepEqual(removeLayer(l, 0), [l[1]]);
  assert.deepEqual(removeLayer([l[0]], 0), []);
});

test("a layer's time window and filter: set from typed values, cleared when incomplete", () => {
  assert.deepEqual(timeWindow('10', '40'), { window: [10, 40] });
  assert.deepEqual(timeWindow('40', '10'), { window: [10, 40] }); // the bounds in order
  assert.equal(timeWindow('10', ''), undefined);
  assert.deepEqual(layerFilter('speed', 'max', 'gt', '2.5'), [{ attribute: 'speed', over: 'max', gt: 2.5 }]);
  assert.deepEqual(layerFilter('speed', 'vertex', 'lt', '1'), [{ attribute: 'speed', over: 'vertex', lt: 1 }]);
  assert.deepEqual(layerFilter('', 'max', 'gt', '1'), []);
  assert.deepEqual(layerFilter('speed', 'max', 'gt', ''), []);
  const l = [{ dataset: 'a' }, { dataset: 'b' }];
  const timed = setLayer(l, 1, 'time', timeWindow('1', '2'));
  assert.deepEqual(timed[1], { dataset: 'b', time: { window: [1, 2] } });
  assert.deepEqual(setLayer(timed, 1, 'time', undefined)[1], { dataset: 'b' });
  const filtered = setLayer(l, 0, 'filter', layerFilter('g', 'mean', 'gt', '0.5'));
  assert.deepEqual(filtered[0].filter, [{ attribute: 'g', over: 'mean', gt: 0.5 }]);
  assert.deepEqual(setLayer(filtered, 0, 'filter', [])[0], { dataset: 'a' });
  assert.deepEqual(setLayer(l, 1, 'lines', { clusters: 12 })[1], { dataset: 'b', lines: { clusters: 12 } });
  assert.deepEqual(setLayer(setLayer(l, 1, 'lines', { clusters: 12 }), 1, 'lines', undefined)[1], { dataset: 'b' });
  assert.deepEqual(setLayer(l, 0, 'color.equalize', true)[0], { dataset: 'a', color: { equalize: true } });
  assert.deepEqual(setLayer(setLayer(l, 0, 'color.equalize', true), 0, 'color.equalize', undefined)[0], {
    dataset: 'a',
  });
  assert.deepEqual(setLayer(setLayer(l, 0, 'color.equalize', true), 0, 'role', 'context')[0], {
    dataset: 'a',
    role: 'context',
  });
  assert.equal(l[1].time, undefined); // the input is left alone
});

test('the legend: visible layers, their colour attribute, colormap and range', () => {
  const infos = {
    a: { defaultColor: 'speed', attributes: [{ name: 'speed', range: [2, 9] }] },
    b: { attributes: [{ name: 't', range: [0, 5] }] },
  };
  const rows = layerLegend(
    [
      { dataset: 'a' },
      { dataset: 'b', visible: false },
      { dataset: 'b', role: 'context', color: { attribute: 't', colormap: 'turbo' } },
    ],
    (n) => infos[n],
  );
  assert.deepEqual(rows, [
    { dataset: 'a', role: 'transparent', attribute: 'speed', rgb: false, colormap: 'viridis', range: [2, 9] },
    { dataset: 'b', role: 'context', attribute: 't', rgb: false, colormap: 'turbo', range: [0, 5] },
  ]);
  assert.deepEqual(layerLegend([{ dataset: 'b' }], (n) => infos[n])[0].range, [0, 1]); // importance
});

test('the link carries layers as JSON text and reads them back; [] is left out', async () => {
  const { formatHash, parseHash } = await import('../js/url-state.js');
  const layers = [
    { dataset: 'demo:points' },
    { dataset: 'demo:tornado', role: 'context', color: { attribute: 'speed' } },
  ];
  const hash = formatHash({ dataset: 'demo:points', update: { layers } });
  assert.match(hash, /&layers=/);
  const back = parseHash(hash);
  assert.deepEqual(back.errors, []);
  assert.deepEqual(back.update.layers, layers);
  assert.equal(formatHash({ dataset: 'a', update: { layers: [] } }), '#dataset=a');
});
