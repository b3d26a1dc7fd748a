// The legend's defaults that suit the data (issue 26): ticks in data units
// under a linear colour bar, the importance direction of attributes where
// smaller matters, and the background/colormap contrast.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { legendModel, linearTicks, invertNote } from '../js/legend.js';
import {
  colorAt,
  contrastRatio,
  topColorClash,
  contrastBackground,
  COLORMAP_STOPS,
  DARK_BACKGROUND,
} from '../js/colormaps.js';
import { pageDefaults, currentValues } from '../js/app-state.js';

const DARK = [...DARK_BACKGROUND];

const stars = {
  defaultImportance: 'magnitude',
  attributes: [
    { name: 'magnitude', range: [-1.44, 8.99], autoRange: [4.62, 8.99], smallerMatters: true },
    { name: 'bv', range: [-0.4, 5.46], autoRange: [-0.4, 2.1] },
  ],
};
const at = (t) => t.map((x) => x.at);
const text = (t) => t.map((x) => x.text);

test('legend ticks: min, quarter points and max of the colour range in data units', () => {
  // colour by an attribute: the server's auto range (params.normalize auto), ticks evenly spaced
  let m = legendModel({ color: { attribute: 'bv' } }, stars);
  assert.deepEqual(at(m.ticks), [0, 25, 50, 75, 100]);
  assert.deepEqual(text(m.ticks), ['-0.4', '0.225', '0.85', '1.48', '2.1']);
  // normalize off: min/max, as the server maps it
  m = legendModel({ color: { attribute: 'bv' }, params: { normalize: 'off' } }, stars);
  assert.deepEqual(text(m.ticks), ['-0.4', '1.06', '2.53', '4', '5.46']);
  // colour by importance: the importance scale 0…1
  assert.deepEqual(text(legendModel({}, stars).ticks), ['0', '0.25', '0.5', '0.75', '1']);
  // an explicit range, given max first: the bar is flipped, the values run right to left
  m = legendModel({ color: { attribute: 'bv', range: [3, -1] } }, stars);
  assert.deepEqual(text(m.ticks), ['-1', '0', '1', '2', '3']);
  assert.deepEqual(at(m.ticks), [100, 75, 50, 25, 0]);
  // equalized colours (the frames' warped ticks take the row) and per-vertex RGB have none
  assert.equal(legendModel({ color: { attribute: 'bv', equalize: true } }, stars).ticks, null);
  assert.equal(legendModel({ color: { attribute: 'rgb' } }, stars).ticks, null);
  for (const bad of [undefined, [1], [0, NaN], ['a', 1]]) assert.equal(linearTicks(bad), null);
});

test('smaller matters: the legend says so, the curve falls, the Invert box has a note', () => {
  // the default importance of the stars is their magnitude: smaller (brighter) is more important
  let m = legendModel({}, stars);
  assert.equal(m.importance.attribute, 'magnitude');
  assert.deepEqual(m.importance.range, [4.62, 8.99]);
  assert.deepEqual(m.direction, { smallerMatters: true, smallerFirst: true, text: 'smaller = more important' });
  assert.match(invertNote({}, stars), /^magnitude: smaller values are important by default/);
  // Invert maps it the plain way (as the server: invert != smallerMatters)
  m = legendModel({ importance: { invert: true } }, stars);
  assert.equal(m.direction.smallerFirst, false);
  assert.equal(m.direction.text, '');
  assert.match(invertNote({ importance: { invert: true } }, stars), /larger values are important/);
  // a range given max first flips once more
  assert.equal(legendModel({ importance: { range: [9, 4] } }, stars).direction.smallerFirst, false);
  assert.equal(legendModel({ importance: { range: [9, 4], invert: true } }, stars).direction.smallerFirst, true);
  // an attribute with the plain direction: no label, no note unless inverted by hand
  m = legendModel({ importance: { attribute: 'bv' } }, stars);
  assert.deepEqual(m.direction, { smallerMatters: false, smallerFirst: false, text: '' });
  assert.equal(invertNote({ importance: { attribute: 'bv' } }, stars), '');
  assert.equal(
    legendModel({ importance: { attribute: 'bv', invert: true } }, stars).direction.text,
    'smaller = more important',
  );
  // terms replace the single attribute: their own 1−t flags say the direction
  const terms = { importance: { terms: [{ attribute: 'magnitude', weight: 1 }] } };
  assert.equal(legendModel(terms, stars).direction.smallerFirst, false);
  assert.equal(invertNote(terms, stars), '');
});

test('contrast: the warning measures luminance contrast; the page opens on a background that contrasts with the colormap', () => {
  assert.equal(contrastRatio([0, 0, 0], [1, 1, 1]), 21);
  assert.equal(contrastRatio([0.3, 0.6, 0.2], [0.3, 0.6, 0.2]), 1);
  // viridis' top (yellow #fde725) on white: the issue's "yellow on white"
  const yellow = contrastRatio(colorAt('viridis', 1), [1, 1, 1]);
  assert.ok(yellow > 1.2 && yellow < 1.3, `yellow on white ${yellow}`);
  assert.equal(topColorClash('viridis', [0, 1], [1, 1, 1]).clash, true);
  // the rule: white when the top colour has ≥ 3:1 against white, else the dark background
  const bg = Object.fromEntries(Object.keys(COLORMAP_STOPS).map((c) => [c, contrastBackground(c)]));
  assert.deepEqual(bg, {
    viridis: DARK,
    coolwarm: [1, 1, 1],
    grayscale: DARK,
    inferno: DARK,
    plasma: DARK,
    turbo: [1, 1, 1],
  });
  for (const [c, b] of Object.entries(bg)) {
    assert.ok(contrastRatio(colorAt(c, 1), b) >= 3, `${c}: the most important colour stands out`);
    assert.equal(legendModel({ color: { colormap: c }, style: { background: b } }, stars).clash, false, c);
  }
  // the page's defaults: the background for the colormap in force, unless the user, link or preset chose one
  assert.deepEqual(pageDefaults({}), { style: { background: DARK } });
  assert.deepEqual(pageDefaults({ color: { colormap: 'turbo' } }), { style: { background: [1, 1, 1] } });
  assert.deepEqual(pageDefaults({ style: { background: [1, 1, 1] } }), {});
  const state = {
    defaults: { style: { background: [1, 1, 1], lineWidth: 0 } },
    pageDefaults: pageDefaults({}),
    stream: null,
    update: {},
  };
  assert.deepEqual(currentValues(state).style, { background: DARK, lineWidth: 0 });
  state.update = { style: { background: [0, 0, 1] } };
  assert.deepEqual(currentValues(state).style.background, [0, 0, 1], 'the user wins');
});

test('legend opacity sentence: method kanzler names its base g^k and the penalty', () => {
  const m = legendModel({ method: 'kanzler', params: { directExponent: 1.5 } }, stars);
  assert.equal(m.method, 'kanzler');
  assert.match(m.opacity, /g\^1\.5/);
  assert.match(m.opacity, /Kanzler's penalty/);
  assert.doesNotMatch(legendModel({ method: 'direct' }, stars).opacity, /Kanzler/);
});
