// The list editors' pure parts (criteria.js): the legend's summaries of terms
// and filters, the curve normalization, and the client's checks of a params
// message that carries them.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { termsSummary, filtersSummary, normalizeCurve } from '../js/criteria.js';
import { legendModel } from '../js/legend.js';
import { paramsMessage } from '../js/protocol.js';

test('terms summary: the weighted sum, its normalization and the penalty form', () => {
  assert.equal(termsSummary([]), '');
  assert.equal(termsSummary([{ attribute: 'speed' }]), 'g = speed');
  assert.equal(
    termsSummary([
      { attribute: 'speed', weight: 0.5 },
      { attribute: 'disp', weight: -0.25, invert: true },
    ]),
    'g = (0.5·speed − 0.25·(1−disp)) / 0.75',
  );
  assert.equal(
    termsSummary([
      { attribute: 'a', weight: -1 },
      { attribute: 'b', weight: 0.5 },
    ]),
    'g = 1 + (−a + 0.5·b) / 1.5',
  );
});

test('filters summary and the legend', () => {
  const f = [
    { attribute: 'p', over: 'change', lt: -500 },
    { attribute: 'speed', over: 'max', range: [1, 2] },
    { attribute: 'q', gt: 0 },
  ];
  assert.equal(filtersSummary(f), 'change(p) < -500, max(speed) ∈ [1, 2], q > 0');
  const m = legendModel(
    {
      importance: {
        terms: [
          { attribute: 'a', weight: 0.5 },
          { attribute: 'b', weight: 0.5 },
        ],
      },
      filter: f,
    },
    {},
  );
  assert.equal(m.criteria.terms, 'g = 0.5·a + 0.5·b');
  assert.match(m.criteria.filters, /^change\(p\) < -500/);
  assert.equal(legendModel({}, {}).criteria.filters, '');
});

test('curves: sorted, clamped, the identity is no curve', () => {
  assert.deepEqual(
    normalizeCurve([
      [0, 0],
      [1, 1],
    ]),
    [],
  );
  assert.deepEqual(
    normalizeCurve([
      [1, 0.5],
      [0, 0],
      [0.5, 1.2],
    ]),
    [
      [0, 0],
      [0.5, 1],
      [1, 0.5],
    ],
  );
  assert.deepEqual(normalizeCurve([[0.3, 0.3]]), []);
});

test('params messages carry filters, terms and curves as the server checks them', () => {
  const msg = paramsMessage({
    filter: [{ attribute: 'p', over: 'change', lt: -500 }],
    importance: {
      terms: [{ attribute: 'a' }],
      curve: [
        [0, 0],
        [1, 0.5],
      ],
    },
  });
  assert.equal(msg.filter.length, 1);
  assert.throws(
    () => paramsMessage({ filter: [{ attribute: 'p', lt: 1 }, ...Array(8).fill({ attribute: 'p', gt: 0 })] }),
    /at most 8/,
  );
  assert.throws(
    () =>
      paramsMessage({
        importance: {
          curve: [
            [0.5, 0],
            [0.2, 1],
          ],
        },
      }),
    /x must not decrease/,
  );
});
