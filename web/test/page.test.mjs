// The page's pure helpers of issue 13: the image warp between frames, the
// orientation triad, colormaps and the background check, the legend's model,
// presets, out-of-range values and the aspect-aware fit.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { projector, warpTransform, isIdentity, axesDirections } from '../js/warp.js';
import { fitCamera, orbit, pan, dolly, cloneCamera } from '../js/camera.js';
import { colorAt, topColorClash, gradientCss, COLORMAP_STOPS } from '../js/colormaps.js';
import { legendModel, importanceCurvePath, equalizedTicks } from '../js/legend.js';
import { readPreset, applyPreset, removePreset } from '../js/preset.js';
import { clampToField, GROUPS, attributeRange } from '../js/ui.js';
import { fieldByPath } from '../js/schema.js';

const BOUNDS = [0, 0, 0, 1, 1, 1];
const W = 640,
  H = 480;
const cam0 = fitCamera(cloneCamera(), BOUNDS, [0, 1, 0], [0, 0, 1]);
const apply = (m, p) => [m[0] * p[0] + m[2] * p[1] + m[4], m[1] * p[0] + m[3] * p[1] + m[5]];
const close = (a, b, eps) => a.every((x, i) => Math.abs(x - b[i]) <= eps);

test('warp: identity for the same camera, exact for pan and dolly, close for small orbits', () => {
  assert.ok(isIdentity(warpTransform(cam0, cam0, W, H), W));
  const m = warpTransform(cam0, pan(cam0, 40, -25, W, H), W, H);
  assert.ok(close(m, [1, 0, 0, 1, 40, -25], 1e-6), `a pan is a translation by the dragged pixels: ${m}`);
  const z = warpTransform(cam0, dolly(cam0, 2), W, H);
  assert.ok(close(z, [2, 0, 0, 2, -W / 2, -H / 2], 1e-6), `a 2× dolly doubles about the centre: ${z}`);
  const turned = orbit(cam0, 30, 10, W, H);
  const o = warpTransform(cam0, turned, W, H);
  const P = projector(cam0, W, H),
    Q = projector(turned, W, H);
  assert.ok(
    close(apply(o, P(cam0.focalPoint)), Q(cam0.focalPoint), 1e-6),
    'the focal point stays where the new camera sees it',
  );
  const side = [cam0.focalPoint[0] + 0.2, cam0.focalPoint[1], cam0.focalPoint[2] + 0.1]; // in from's focal plane
  // other points of the focal plane: a first-order approximation (a rotation is a homography, not affine)
  const err = Math.hypot(...apply(o, P(side)).map((x, i) => x - Q(side)[i]));
  assert.ok(err < 0.02 * W, `focal-plane point off by ${err.toFixed(2)} px after a 17° turn`);
  // a quarter turn sees the focal plane edge-on: no meaningful warp
  assert.equal(warpTransform(cam0, orbit(cam0, W / 4, 0, W, H), W, H), null);
});

test('triad: the world axes as the camera sees them', () => {
  // looking along +Y with +Z up: X points right, Z up, Y away from the viewer
  const d = Object.fromEntries(axesDirections(cam0).map((a) => [a.axis, a]));
  assert.ok(close([d.X.x, d.X.y], [1, 0], 1e-9) && close([d.Z.x, d.Z.y], [0, 1], 1e-9));
  assert.ok(Math.abs(d.Y.toward + 1) < 1e-9, 'Y points away');
  const turned = Object.fromEntries(axesDirections(orbit(cam0, W / 4, 0, W, H)).map((a) => [a.axis, a]));
  assert.ok(Math.abs(turned.X.x) < 1e-9, 'a quarter turn puts X along the view');
});

test('colormaps: stops, interpolation, the top colour against the background', () => {
  for (const [name, stops] of Object.entries(COLORMAP_STOPS)) {
    assert.equal(stops.length, 11, name);
    assert.match(gradientCss(name), /^linear-gradient\(to right, #/);
  }
  assert.deepEqual(
    colorAt('grayscale', 0.5).map((x) => Math.round(x * 255)),
    [128, 128, 128],
  );
  assert.equal(topColorClash('grayscale', [0, 1], [1, 1, 1]).clash, true, 'white on white');
  assert.equal(topColorClash('grayscale', [1, 0], [1, 1, 1]).clash, false, 'flipped: black on white');
  assert.equal(topColorClash('grayscale', [0, 1], [0, 0, 0]).clash, false, 'white on black');
  assert.equal(
    topColorClash('viridis', [0, 1], [1, 1, 1]).clash,
    true,
    "viridis' yellow on white: luminance contrast 1.26",
  );
  assert.equal(topColorClash('viridis', [1, 0], [1, 1, 1]).clash, false, 'flipped: purple on white');
  assert.equal(topColorClash('inferno', [1, 0], [0, 0, 0]).clash, true, 'inferno flipped on black');
});

test('legend model: names, ranges, importance mapping and the opacity sentence', () => {
  const info = {
    defaultImportance: 'line_curvature',
    attributes: [
      { name: 'velocity', range: [0.03, 0.31] },
      { name: 'line_curvature', range: [0.08, 1] },
    ],
  };
  let m = legendModel({}, info);
  assert.deepEqual(m.color, { attribute: 'importance', colormap: 'viridis', range: [0, 1], rgb: false });
  assert.deepEqual(m.importance, { attribute: 'line_curvature', range: [0.08, 1], exponent: 1 });
  assert.match(m.opacity, /optimized/);
  m = legendModel(
    {
      color: { attribute: 'velocity', colormap: 'plasma' },
      importance: { range: [0.5, 1], exponent: 2 },
      method: 'direct',
      params: { directExponent: 3 },
    },
    info,
  );
  assert.deepEqual(m.color.range, [0.03, 0.31]);
  assert.deepEqual(m.importance.range, [0.5, 1]);
  assert.match(m.opacity, /g\^3/);
  assert.equal(legendModel({ color: { attribute: 'rgb' } }, info).clash, false);
  // normalize auto (default) maps importance from the auto range the server reports; off from min/max.
  const robust = {
    ...info,
    attributes: [{ name: 'line_curvature', range: [0.08, 1], percentiles: [0.1, 0.9], autoRange: [0.15, 0.97] }],
  };
  assert.deepEqual(legendModel({}, robust).importance.range, [0.15, 0.97]);
  assert.deepEqual(legendModel({ params: { normalize: 'off' } }, robust).importance.range, [0.08, 1]);
  // colour by an attribute takes the same robust range, and so does the panel (attributeRange)
  const stars = { attributes: [{ name: 'bv', range: [-0.4, 5.46], autoRange: [-0.4, 2.1] }] };
  assert.deepEqual(legendModel({ color: { attribute: 'bv' } }, stars).color.range, [-0.4, 2.1]);
  assert.deepEqual(
    legendModel({ color: { attribute: 'bv' }, params: { normalize: 'off' } }, stars).color.range,
    [-0.4, 5.46],
  );
  assert.deepEqual(attributeRange(stars, 'bv'), [-0.4, 2.1]);
  assert.deepEqual(attributeRange(stars, 'bv', 'off'), [-0.4, 5.46]);
  assert.deepEqual(attributeRange({ attributes: [{ name: 'c', range: [2, 2], autoRange: [2, 2] }] }, 'c'), [2, 2]);
  assert.match(importanceCurvePath(2), /^M0\.0,18\.0 L/);
});

test('presets: validated, under the link, undone without touching later edits', () => {
  const preset = {
    params: { q: 80, r: 40, bands: 99 },
    color: { colormap: 'plasma' },
    camera: { viewAngle: 20 },
    extra: {},
  };
  const p = readPreset(preset);
  assert.deepEqual(p.update, { params: { q: 80, r: 40 }, color: { colormap: 'plasma' } });
  assert.deepEqual(p.camera, { viewAngle: 20 });
  assert.deepEqual(p.errors, ['params.bands: 99 is outside [1, 8]', 'extra: not a preset section']);
  const r = applyPreset(preset, { params: { q: 5 } }, null);
  assert.deepEqual(r.update, { params: { q: 5, r: 40 }, color: { colormap: 'plasma' } });
  assert.deepEqual(r.applied, ['params.r', 'color.colormap']);
  assert.equal(r.cameraApplied, true);
  assert.equal(applyPreset(preset, {}, { position: [0, 0, 1] }).cameraApplied, false, 'a link camera wins');
  const edited = { ...r.update, color: { colormap: 'turbo' } };
  assert.deepEqual(removePreset(edited, preset, r.applied), { params: { q: 5 }, color: { colormap: 'turbo' } });
  assert.deepEqual(readPreset(null), { update: {}, camera: null, errors: [] });
});

test('out-of-range numbers are brought inside the field (slider end for open bounds)', () => {
  const spec = (path) => GROUPS.flatMap((g) => g.controls).find((c) => c.path === path);
  assert.equal(clampToField(fieldByPath('params.bands'), spec('params.bands'), 20), 8);
  assert.equal(clampToField(fieldByPath('params.bands'), spec('params.bands'), -3), 1);
  assert.equal(clampToField(fieldByPath('params.resolutionScale'), spec('params.resolutionScale'), 0), 0.1);
  assert.equal(clampToField(fieldByPath('params.q'), spec('params.q'), 5e6), 1e6);
  for (const c of GROUPS.flatMap((g) => g.controls))
    assert.ok(c.help && c.help.length > 20, `${c.path} has a plain-words help text`);
});

test('portrait views fit the bounding sphere into the horizontal angle', () => {
  const wide = fitCamera(cloneCamera(), BOUNDS, [0, 1, 0], [0, 0, 1], 1.5);
  const tall = fitCamera(cloneCamera(), BOUNDS, [0, 1, 0], [0, 0, 1], 0.5);
  const dist = (c) => Math.hypot(...c.position.map((p, i) => p - c.focalPoint[i]));
  assert.ok(Math.abs(dist(wide) - dist(cam0)) < 1e-12, 'landscape: as lc_camera_fit');
  assert.ok(dist(tall) > 1.9 * dist(cam0), 'portrait 1:2 backs off');
  const P = projector(tall, 100, 200);
  for (const x of [0, 1])
    for (const y of [0, 1])
      for (const z of [0, 1]) {
        const [u, v] = P([x, y, z]);
        assert.ok(u >= 0 && u <= 100 && v >= 0 && v <= 200, `corner ${x}${y}${z} at ${u}, ${v}`);
      }
});

test("legend: an equalized frame's colorTicks become warped ticks along the bar", () => {
  const t = equalizedTicks([0.1, 1.234567, 2.5, 4, 10]);
  assert.deepEqual(
    t.map((x) => x.at),
    [0, 25, 50, 75, 100],
  );
  assert.deepEqual(
    t.map((x) => x.text),
    ['0.1', '1.23', '2.5', '4', '10'],
  );
  // a flipped bar (range max first) runs the values right to left, as the colours
  assert.deepEqual(
    equalizedTicks([0, 1, 2, 3, 4], true).map((x) => x.at),
    [100, 75, 50, 25, 0],
  );
  // frames without equalization (or a malformed header) have none
  for (const bad of [undefined, null, [1, 2, 3], [0, 1, 2, 3, 'x'], [0, 1, 2, 3, NaN]])
    assert.equal(equalizedTicks(bad), null);
});
