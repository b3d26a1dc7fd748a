// The orientation triad: the world X, Y and Z axes as seen by the page's
// camera, drawn into an inline SVG on every camera change (client-side, so it
// turns with the pointer even while frames are in flight).

import { axesDirections } from './warp.js';

const NS = 'http://www.w3.org/2000/svg';
const COLORS = { X: '#e5534b', Y: '#57ab5a', Z: '#539bf5' };

export class AxesTriad {
  /** svg: an empty <svg> element; size: its side in CSS pixels. */
  constructor(svg, size = 64) {
    this.svg = svg;
    this.size = size;
    svg.setAttribute('viewBox', `0 0 ${size} ${size}`);
    svg.setAttribute('width', String(size));
    svg.setAttribute('height', String(size));
    this.items = ['X', 'Y', 'Z'].map((axis) => {
      const g = document.createElementNS(NS, 'g');
      const line = document.createElementNS(NS, 'line');
      line.setAttribute('stroke', COLORS[axis]);
      line.setAttribute('stroke-width', '2.5');
      line.setAttribute('stroke-linecap', 'round');
      const text = document.createElementNS(NS, 'text');
      text.textContent = axis;
      text.setAttribute('fill', COLORS[axis]);
      text.setAttribute('font-size', '11');
      text.setAttribute('font-weight', '700');
      text.setAttribute('text-anchor', 'middle');
      text.setAttribute('dominant-baseline', 'central');
      g.append(line, text);
      svg.append(g);
      return { axis, g, line, text };
    });
    this.directions = null;
  }

  /** Redraws for a camera (null hides the axes). */
  update(cam) {
    this.svg.style.visibility = cam ? '' : 'hidden';
    if (!cam) return;
    const c = this.size / 2,
      len = this.size / 2 - 10;
    const dirs = axesDirections(cam);
    this.directions = dirs;
    // farther axes first, so the one pointing at the viewer is on top
    const order = [...dirs].sort((a, b) => a.toward - b.toward);
    for (const d of order) {
      const it = this.items.find((x) => x.axis === d.axis);
      const x2 = c + d.x * len,
        y2 = c - d.y * len;
      it.line.setAttribute('x1', String(c));
      it.line.setAttribute('y1', String(c));
      it.line.setAttribute('x2', x2.toFixed(2));
      it.line.setAttribute('y2', y2.toFixed(2));
      it.line.setAttribute('opacity', d.toward < -0.2 ? '0.55' : '1');
      it.text.setAttribute('x', (c + d.x * (len + 6)).toFixed(2));
      it.text.setAttribute('y', (c - d.y * (len + 6)).toFixed(2));
      this.svg.append(it.g);
    }
    this.svg.dataset.axes = dirs.map((d) => `${d.axis}:${d.x.toFixed(3)},${d.y.toFixed(3)}`).join(' ');
  }
}
