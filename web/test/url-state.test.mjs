// URL hash state: round trip, defaults left out, bad keys reported, token handling.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { parseHash, formatHash, tokenFromLocation } from '../js/url-state.js';

const cam = {
  position: [1.5, -2, 30],
  focalPoint: [0, 0.25, 0],
  viewUp: [0, 1, 0],
  viewAngle: 30,
  parallelProjection: false,
  parallelScale: 1,
};

test('round trip of dataset, camera and parameters', () => {
  const update = {
    method: 'exact',
    params: { q: 80, r: 40, lambda: 1.5, bands: 7, estimator: 'foo', fadeHalfLife: 0.2 },
    importance: { attribute: 'speed', range: [0, 2.5], exponent: 2 },
    color: { attribute: 'rgb', colormap: 'turbo', range: [-1, 1] },
    style: { background: [0, 0, 0.1], lineWidth: 0.02, pointSize: 3, shading: 'none' },
    quality: 85,
    interactiveScale: 0.5,
  };
  const hash = formatHash({ dataset: 'demo:tornado', camera: cam, update });
  assert.match(hash, /^#dataset=demo:tornado&position=1.5,-2,30&/);
  assert.ok(!hash.includes('parallelScale'), 'perspective cameras leave parallelScale out');
  const back = parseHash(hash);
  assert.deepEqual(back.errors, []);
  assert.equal(back.dataset, 'demo:tornado');
  assert.deepEqual(back.camera, {
    position: cam.position,
    focalPoint: cam.focalPoint,
    viewUp: cam.viewUp,
    viewAngle: 30,
  });
  assert.deepEqual(back.update, update);
});

test('parallel projection is kept', () => {
  const c = { ...cam, parallelProjection: true, parallelScale: 4.5 };
  const back = parseHash(formatHash({ camera: c }));
  assert.equal(back.camera.parallelProjection, true);
  assert.equal(back.camera.parallelScale, 4.5);
});

test('values equal to the defaults are left out', () => {
  const defaults = { params: { q: 60, r: 500 }, style: { background: [1, 1, 1] } };
  const hash = formatHash(
    { dataset: 'x', update: { params: { q: 60, r: 40 }, style: { background: [1, 1, 1] } } },
    defaults,
  );
  assert.equal(hash, '#dataset=x&r=40');
});

test('unknown keys and invalid values are reported and skipped', () => {
  const s = parseHash('#dataset=demo:abc&bogus=1&bands=99&q=abc&lambda=2&position=1,2&viewAngle=200');
  assert.equal(s.dataset, 'demo:abc');
  assert.deepEqual(s.update, { params: { lambda: 2 } });
  assert.equal(s.camera, null);
  assert.equal(s.errors.length, 5);
  assert.ok(s.errors.some((e) => e.startsWith('bogus:')));
  assert.ok(s.errors.some((e) => /^bands: 99 is outside \[1, 8\]/.test(e)));
});

test('names with special characters survive', () => {
  const name = 'my data/set #1 & more=ok';
  const h = formatHash({ dataset: name, update: { importance: { attribute: 'ä b' } } });
  const back = parseHash(h);
  assert.equal(back.dataset, name);
  assert.equal(back.update.importance.attribute, 'ä b');
  assert.deepEqual(parseHash('#%E0%A4%A=1').errors, []); // undecodable pairs are dropped silently
});

test('empty state gives an empty hash; numbers are rounded to 7 digits', () => {
  assert.equal(formatHash({}), '');
  assert.equal(formatHash({ update: { params: { q: 1 / 3 } } }), '#q=0.3333333');
});

test('token from the query or the hash, never written back', () => {
  assert.equal(tokenFromLocation('?token=abc', ''), 'abc');
  assert.equal(tokenFromLocation('', '#dataset=x&token=s%20t'), 's t');
  assert.equal(tokenFromLocation('?token=a', '#token=b'), 'a');
  assert.equal(tokenFromLocation('', ''), null);
  const s = parseHash('#token=zz&q=3');
  assert.equal(s.token, 'zz');
  assert.ok(!formatHash({ dataset: 'd', update: s.update }).includes('token'));
});
