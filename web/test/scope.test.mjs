// Where fields apply (schema.js's methods/primitives, the server's scope table):
// what the page sends keeps only the fields that apply; the rest stay in its state.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { applicableUpdate, applies, fieldByPath } from '../js/schema.js';
import { createParamsController } from '../js/params-controller.js';

test('fields apply by method and kind of data', () => {
  assert.equal(applies(fieldByPath('style.antialias'), 'exact', 'lines'), false);
  assert.equal(applies(fieldByPath('style.antialias'), 'fourier', 'lines'), true);
  assert.equal(applies(fieldByPath('style.pointSize'), 'fourier', 'lines'), false);
  assert.equal(applies(fieldByPath('style.silhouetteExponent'), 'fourier', 'triangles'), true);
  assert.equal(applies(fieldByPath('lines.clusters'), 'fourier', null), true); // kind unknown: layers
  assert.equal(applies(fieldByPath('params.q'), 'surface-layers', 'lines'), false);
});

test('a hello keeps what applies; the rest stays out', () => {
  const update = {
    method: 'exact',
    params: { q: 80, bands: 7 },
    style: { antialias: 2, lineWidth: 0.01, pointSize: 3 },
  };
  assert.deepEqual(applicableUpdate(update, 'lines'), {
    method: 'exact',
    params: { q: 80 },
    style: { lineWidth: 0.01 },
  });
  assert.deepEqual(applicableUpdate({ style: { pointSize: 3 } }, 'lines'), {});
  assert.deepEqual(applicableUpdate({ dataset: 'a', width: 10, camera: { viewAngle: 30 } }, 'lines'), {
    dataset: 'a',
    width: 10,
    camera: { viewAngle: 30 },
  });
});

test('the direct method\'s opacity parameters go only with their alphaSource (schema "when")', () => {
  const update = { method: 'direct', params: { directExponent: 3, alphaConstant: 0.5, gamma: 2 } };
  assert.deepEqual(applicableUpdate(update, 'triangles'), { method: 'direct', params: { directExponent: 3 } });
  update.params.alphaSource = 'constant';
  assert.deepEqual(applicableUpdate(update, 'triangles'), {
    method: 'direct',
    params: { alphaConstant: 0.5, alphaSource: 'constant' },
  });
  update.params.alphaSource = 'normalVariation';
  assert.deepEqual(applicableUpdate(update, 'triangles'), {
    method: 'direct',
    params: { gamma: 2, alphaSource: 'normalVariation' },
  });
  assert.deepEqual(applicableUpdate({ method: 'fourier', params: { alphaSource: 'angle' } }, 'triangles'), {
    method: 'fourier',
  });
});

test('changing method sends the kept fields that apply again', () => {
  const sent = [];
  let queued = null;
  const state = { update: { params: { bands: 7 } }, info: { type: 'lines' } };
  const ctl = createParamsController({
    state,
    send: (m) => (sent.push(m), true),
    frame: (fn) => ((queued = fn), 1),
    changed() {},
    toast(t) {
      throw new Error(t);
    },
  });
  ctl.applyChange('method', 'exact'); // bands does not apply to exact: not sent, kept
  queued();
  assert.deepEqual(sent.at(-1), { type: 'params', method: 'exact' });
  assert.equal(state.update.params.bands, 7);
  ctl.applyChange('method', 'fourier'); // applies again: sent with the method
  queued();
  assert.deepEqual(sent.at(-1), { type: 'params', method: 'fourier', params: { bands: 7 } });
});
