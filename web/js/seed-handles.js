// The stream surface's seed line drawn over the view: its two endpoints as
// handles projected with the page's camera; dragging a handle moves that
// endpoint in the plane through it facing the camera. The math is pure (Node
// tests); SeedOverlay is the SVG that shows it and turns drags into seeds.

import { cameraFrame, add, sub, scale, dot } from './camera.js';
import { projector } from './warp.js';

/** Handle radius in CSS pixels: the pointer grabs a handle within this distance. */
export const HANDLE_RADIUS = 8;

/** The seed's endpoints in view pixels (x right, y down) for a w × h view: [[x, y], [x, y]], null where behind the camera. */
export function projectSeed(cam, w, h, seed) {
  const P = projector(cam, w, h);
  return seed.map((p) => P(p));
}

/**
 * The world point under view pixel [x, y] in the plane through `through` facing
 * the camera (normal: the view direction), the inverse of projector() at that
 * depth. null when `through` is behind a perspective camera.
 */
export function unprojectAt(cam, w, h, [x, y], through) {
  const { dir, right, up } = cameraFrame(cam);
  const z = dot(sub(through, cam.position), dir);
  if (cam.parallelProjection) {
    const k = h / 2 / (cam.parallelScale || 1);
    return add(add(cam.position, scale(dir, z)), add(scale(right, (x - w / 2) / k), scale(up, (h / 2 - y) / k)));
  }
  if (!(z > 1e-9)) return null;
  const f = h / 2 / Math.tan((cam.viewAngle * Math.PI) / 360);
  const ray = add(dir, add(scale(right, (x - w / 2) / f), scale(up, (h / 2 - y) / f)));
  return add(cam.position, scale(ray, z));
}

/** The handle (0 start, 1 end) within radius pixels of [x, y], the nearer one; -1 when none. */
export function hitHandle(points, [x, y], radius = HANDLE_RADIUS) {
  let best = -1,
    bestD = radius;
  points.forEach((p, i) => {
    if (!p) return;
    const d = Math.hypot(p[0] - x, p[1] - y);
    if (d <= bestD) [best, bestD] = [i, d];
  });
  return best;
}

const round6 = (x) => Number(x.toPrecision(6));

/**
 * The seed after dragging handle `index` from view pixel `from` to `to`: that
 * endpoint moves by the world offset between the two pixels in the plane through
 * it facing the camera (so the grab point stays under the pointer), clamped to
 * bounds [[lo], [hi]] when given, rounded to 6 significant digits as the typed
 * fields show it. The seed unchanged when the endpoint is behind the camera.
 */
export function dragSeed(cam, w, h, seed, index, from, to, bounds = null) {
  const p = seed[index];
  const a = unprojectAt(cam, w, h, from, p),
    b = unprojectAt(cam, w, h, to, p);
  if (!a || !b) return seed.map((q) => [...q]);
  let q = add(p, sub(b, a));
  if (bounds) q = q.map((v, i) => Math.min(Math.max(v, bounds[0][i]), bounds[1][i]));
  return seed.map((s, i) => (i === index ? q.map(round6) : [...s]));
}

const SVG = 'http://www.w3.org/2000/svg';

/**
 * The SVG over the view. get() returns { cam, seed, bounds } or null (nothing
 * shown); onMove(index, point) while dragging, onEnd() when a drag that moved
 * the endpoint ends (the caller sends the seed then: one restart per drag). Only the handles take the pointer: elsewhere the
 * canvas below orbits as before.
 */
export class SeedOverlay {
  constructor(svg, { get, onMove, onEnd }) {
    this.svg = svg;
    this.get = get;
    this.onMove = onMove;
    this.onEnd = onEnd;
    this.drag = null; // { index, from, seed, cam, w, h }
    const doc = svg.ownerDocument;
    const make = (tag, attrs) => {
      const e = doc.createElementNS(SVG, tag);
      for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
      svg.append(e);
      return e;
    };
    this.line = make('line', { class: 'seed-line' });
    this.handles = ['seed-start', 'seed-end'].map((id, i) => {
      const c = make('circle', { class: 'seed-handle', r: HANDLE_RADIUS, 'data-testid': id, 'data-index': i });
      const title = doc.createElementNS(SVG, 'title');
      title.textContent = `Seed ${i ? 'end' : 'start'}: drag to move it across the view (the surface starts again)`;
      c.append(title);
      c.addEventListener('pointerdown', (e) => this.#down(e, i));
      c.addEventListener('pointermove', (e) => this.#move(e));
      c.addEventListener('pointerup', (e) => this.#up(e));
      c.addEventListener('pointercancel', (e) => this.#up(e));
      return c;
    });
    this.update();
  }

  #size() {
    const r = this.svg.parentElement.getBoundingClientRect(); // the view's: the overlay covers it, even while hidden
    return [r.width || 1, r.height || 1];
  }

  #pos(e) {
    const r = this.svg.getBoundingClientRect();
    return [e.clientX - r.left, e.clientY - r.top];
  }

  #down(e, index) {
    const v = this.get();
    if (!v || e.button !== 0) return;
    e.preventDefault();
    e.stopPropagation();
    e.target.setPointerCapture?.(e.pointerId);
    const [w, h] = this.#size();
    this.drag = { index, from: this.#pos(e), seed: v.seed, cam: v.cam, bounds: v.bounds, w, h };
    this.svg.dataset.dragging = String(index);
  }

  #move(e) {
    const d = this.drag;
    if (!d) return;
    const seed = dragSeed(d.cam, d.w, d.h, d.seed, d.index, d.from, this.#pos(e), d.bounds);
    d.last = seed[d.index];
    this.onMove(d.index, d.last);
    this.update();
  }

  #up(e) {
    const d = this.drag;
    if (!d) return;
    this.#move(e);
    this.drag = null;
    delete this.svg.dataset.dragging;
    if (d.last && d.last.some((v, i) => v !== d.seed[d.index][i])) this.onEnd(); // a click alone restarts nothing
  }

  /** Redraws at the current camera and seed (or hides). */
  update() {
    const v = this.get();
    const [w, h] = this.#size();
    const pts = v ? projectSeed(v.cam, w, h, v.seed) : [null, null];
    const hide = !v || !pts[0] || !pts[1];
    this.svg.toggleAttribute('hidden', hide); // an attribute: SVG elements have no .hidden property
    if (hide) return;
    this.line.setAttribute('x1', pts[0][0]);
    this.line.setAttribute('y1', pts[0][1]);
    this.line.setAttribute('x2', pts[1][0]);
    this.line.setAttribute('y2', pts[1][1]);
    this.handles.forEach((c, i) => {
      c.setAttribute('cx', pts[i][0]);
      c.setAttribute('cy', pts[i][1]);
    });
  }
}
