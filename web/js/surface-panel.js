// The page's stream-surface controls (method "surface-layers", docs/ALGORITHM.md
// §23): pick a vector field, type the seed line's endpoints (and points between:
// a polyline of up to 64), and the session streams the surface, more curves each
// frame; the layers' merge distance ε, opacity, layer cap, compositing and colour;
// a new seed or field restarts it.

/** The defaults of the surface's look (the request's surface.* defaults, protocol/README.md). */
export const SURFACE_LOOK = Object.freeze({
  epsilon: 0.01,
  opacity: 0.3,
  maxLayers: 8,
  composite: 'layers',
  color: [0.95, 0.6, 0.2],
});

/** Points typed as "x,y,z; x,y,z; ..." (empty: none), or null when one is not three numbers. */
export function parsePoints(text) {
  const parts = String(text ?? '')
    .split(';')
    .map((s) => s.trim())
    .filter(Boolean);
  const points = parts.map((s) => s.split(',').map((x) => Number(x.trim())));
  return points.every((p) => p.length === 3 && p.every(Number.isFinite)) ? points : null;
}

/** The default seed line of a field: across the middle along y, a tenth in from the faces. */
export function defaultSeed(bounds) {
  const [lo, hi] = bounds;
  const c = [0, 1, 2].map((i) => (lo[i] + hi[i]) / 2);
  const ey = hi[1] - lo[1];
  const r = (x) => Number(x.toPrecision(6));
  return [
    [r(c[0]), r(lo[1] + 0.1 * ey), r(c[2])],
    [r(c[0]), r(hi[1] - 0.1 * ey), r(c[2])],
  ];
}

/**
 * The request changes that show the surface (on) or go back to the dataset
 * (off, to previousMethod): a list of [path, value] for the params controller.
 */
export function surfaceChanges(
  on,
  { field, seed, particles, curvesPerFrame, direction, ...look },
  previousMethod = 'fourier',
) {
  if (!on) return [['method', previousMethod]];
  return [
    ['surface', { field, seed, particles, curvesPerFrame, direction, ...look }],
    ['method', 'surface-layers'],
  ];
}

/**
 * "curves 450 / 600 · 1.10 layers per pixel · 150 added" from a frame header's surface object: the
 * frame's own work is the curves it added to the layers kept from the frame before, or all of them
 * drawn again (a camera or parameter change).
 */
export function surfaceStatus(s) {
  if (!s) return '';
  const done = s.curves >= s.particles ? ' (complete)' : '';
  const drawn =
    s.drawnCurves === undefined ? '' : s.kept ? ` · ${s.drawnCurves} added` : ` · ${s.drawnCurves} drawn anew`;
  return (
    `curves ${s.curves} / ${s.particles}${done} · ${Number(s.layersPerPixel).toFixed(2)} layers per pixel` +
    (s.overflow ? ` · ${s.overflow} fragments beyond ${s.k} layers` : '') +
    drawn
  );
}

/**
 * A fieldset in the settings panel; apply(path, value) edits the request,
 * toast(text) reports, fit(bounds) points the camera at a field's domain (the
 * dataset's view would miss it).
 */
export class SurfacePanel {
  constructor(parent, doc, apply, toast, fit = () => {}) {
    this.apply = apply;
    this.toast = toast;
    this.fit = fit;
    this.fitted = null; // the field the camera was last fitted to
    this.fields = [];
    this.previousMethod = 'fourier';
    const el = (tag, props = {}) => Object.assign(doc.createElement(tag), props);
    const box = el('fieldset', { className: 'group', id: 'group-surface' });
    box.dataset.testid = 'surface';
    box.append(el('legend', { textContent: 'Stream surface' }));
    const row = (label, input) => {
      const r = el('div', { className: 'row', title: input.title }); // the tooltip covers label and control
      r.append(el('label', { textContent: label, htmlFor: input.id }), input);
      box.append(r);
      return input;
    };
    this.on = row(
      'Show',
      el('input', {
        type: 'checkbox',
        id: 'surface-on',
        title: 'Show the stream surface of the vector field instead of the dataset; it fills in frame by frame.',
      }),
    );
    this.field = row('Vector field', el('select', { id: 'surface-field', title: 'The flow the surface follows.' }));
    this.a = row(
      'Seed start x,y,z',
      el('input', {
        type: 'text',
        id: 'surface-a',
        size: 18,
        title:
          'Where the seed line starts: three numbers x, y, z inside the field. Changing it starts the surface again.',
      }),
    );
    this.b = row(
      'Seed end x,y,z',
      el('input', {
        type: 'text',
        id: 'surface-b',
        size: 18,
        title: 'Where the seed line ends: three numbers x, y, z. Changing it starts the surface again.',
      }),
    );
    this.via = row(
      'Seed via x,y,z; …',
      el('input', {
        type: 'text',
        id: 'surface-via',
        size: 18,
        placeholder: 'none (a straight seed)',
        title:
          'Points the seed passes through between start and end, "x,y,z; x,y,z" (up to 62): a bent seed line. Empty: straight. Changing it starts the surface again.',
      }),
    );
    this.direction = row(
      'Direction',
      el('select', {
        id: 'surface-direction',
        title:
          'Which way the flow lines run from the seed: downstream, upstream, or both ways. Changing it starts the surface again.',
      }),
    );
    this.direction.append(...['forward', 'backward', 'both'].map((d) => el('option', { value: d, textContent: d })));
    this.particles = row(
      'Curves',
      el('input', {
        type: 'number',
        id: 'surface-particles',
        min: 1,
        max: 100000,
        value: 2000,
        title: 'How many flow lines make up the finished surface. More: a smoother surface, slower to finish.',
      }),
    );
    this.perFrame = row(
      'Curves per frame',
      el('input', {
        type: 'number',
        id: 'surface-per-frame',
        min: 1,
        max: 100000,
        value: 200,
        title: 'How many flow lines each new frame adds. More: the surface appears in fewer, slower frames.',
      }),
    );
    this.epsilon = row(
      'Layer merge ε',
      el('input', {
        type: 'number',
        id: 'surface-epsilon',
        min: 0,
        max: 1,
        step: 0.001,
        value: SURFACE_LOOK.epsilon,
        title:
          "Fragments of the surface closer than this in depth (fraction of the field's size) count as one layer. Larger: fewer, merged layers.",
      }),
    );
    this.opacity = row(
      'Layer opacity',
      el('input', {
        type: 'number',
        id: 'surface-opacity',
        min: 0.01,
        max: 1,
        step: 0.05,
        value: SURFACE_LOOK.opacity,
        title: 'The opacity of every layer of the surface.',
      }),
    );
    this.maxLayers = row(
      'Layers kept',
      el('input', {
        type: 'number',
        id: 'surface-max-layers',
        min: 1,
        max: 64,
        step: 1,
        value: SURFACE_LOOK.maxLayers,
        title:
          'How many layers a pixel keeps (the server may keep fewer on large views: the status line says how many).',
      }),
    );
    this.composite = row(
      'Compositing',
      el('select', {
        id: 'surface-composite',
        title:
          'Layers: blend the kept layers front to back. Weighted average / weighted sum: the order-independent baselines of the same fragments, for comparison.',
      }),
    );
    this.composite.append(
      ...[
        ['layers', 'layers'],
        ['weighted-average', 'weighted average'],
        ['weighted-sum', 'weighted sum'],
      ].map(([v, t]) => el('option', { value: v, textContent: t })),
    );
    this.color = row(
      'Colour',
      el('input', {
        type: 'color',
        id: 'surface-color',
        value: '#f29933',
        title: "The surface's base colour, shaded by a headlight.",
      }),
    );
    this.status = el('p', { className: 'info', id: 'surface-status' });
    this.status.setAttribute('role', 'status');
    box.append(this.status);
    box.hidden = true; // until the server lists a field
    this.box = box;
    parent.append(box);
    this.field.addEventListener('change', () => {
      this.resetSeed();
      this.send();
    });
    this.on.addEventListener('change', () => this.send());
    for (const input of [
      this.a,
      this.b,
      this.via,
      this.direction,
      this.particles,
      this.perFrame,
      this.epsilon,
      this.opacity,
      this.maxLayers,
      this.composite,
      this.color,
    ])
      input.addEventListener('change', () => this.send());
  }

  /** The server's fields (GET /api/v1/datasets "fields"). */
  setFields(fields) {
    this.fields = Array.isArray(fields) ? fields : [];
    this.field.replaceChildren(
      ...this.fields.map((f) =>
        Object.assign(this.field.ownerDocument.createElement('option'), { value: f.name, textContent: f.name }),
      ),
    );
    this.box.hidden = this.fields.length === 0;
    if (this.fields.length) this.resetSeed();
  }

  resetSeed() {
    const f = this.fields.find((x) => x.name === this.field.value);
    if (!f?.bounds) return;
    const [a, b] = defaultSeed(f.bounds);
    this.a.value = a.join(', ');
    this.b.value = b.join(', ');
    this.via.value = '';
  }

  /** The form's values, or null (with a toast) when a seed point is not three numbers. */
  values() {
    const point = (input, name) => {
      const p = input.value.split(',').map((x) => Number(x.trim()));
      if (p.length !== 3 || !p.every(Number.isFinite)) {
        this.toast(`${name}: expected three numbers x, y, z`);
        return null;
      }
      return p;
    };
    const a = point(this.a, 'Seed start'),
      b = point(this.b, 'Seed end');
    const via = parsePoints(this.via.value);
    if (!via) this.toast('Seed via: expected points x, y, z separated by ";"');
    if (!a || !b || !via) return null;
    const hex = /^#([0-9a-f]{2})([0-9a-f]{2})([0-9a-f]{2})$/i.exec(this.color.value);
    const color = hex ? [1, 2, 3].map((i) => Number((parseInt(hex[i], 16) / 255).toFixed(4))) : [...SURFACE_LOOK.color];
    return {
      field: this.field.value,
      seed: [a, ...via, b],
      particles: Number(this.particles.value),
      curvesPerFrame: Number(this.perFrame.value),
      direction: this.direction.value,
      epsilon: Number(this.epsilon.value),
      opacity: Number(this.opacity.value),
      maxLayers: Number(this.maxLayers.value),
      composite: this.composite.value,
      color,
    };
  }

  /**
   * What the view's seed overlay draws: { seed, bounds } of the shown surface's
   * typed seed ends (the handles move them; points between stay as typed), or
   * null while hidden or a typed point is not three numbers.
   */
  shownSeed() {
    if (!this.on.checked || this.box.hidden) return null;
    const point = (input) => {
      const p = input.value.split(',').map((x) => Number(x.trim()));
      return p.length === 3 && p.every(Number.isFinite) ? p : null;
    };
    const a = point(this.a),
      b = point(this.b);
    const f = this.fields.find((x) => x.name === this.field.value);
    return a && b ? { seed: [a, b], bounds: f?.bounds ?? null } : null; // the handles: the seed's two ends
  }

  /** A dragged seed endpoint (0 start, 1 end) into its typed field; send() sends it. */
  setPoint(index, p) {
    (index ? this.b : this.a).value = p.join(', ');
  }

  /** Sends the form: a new seed or field restarts the surface on the server. */
  send() {
    const v = this.on.checked ? this.values() : {};
    if (!v) return;
    const f = this.fields.find((x) => x.name === v.field);
    if (this.on.checked && f?.bounds && this.fitted !== f.name) {
      this.fitted = f.name;
      this.fit(f.bounds);
    }
    if (!this.on.checked) this.fitted = null;
    for (const [path, value] of surfaceChanges(this.on.checked, v, this.previousMethod)) this.apply(path, value);
    if (!this.on.checked) this.status.textContent = '';
  }

  /** The method the dataset had, to go back to. */
  setMethod(method) {
    if (method && method !== 'surface-layers') this.previousMethod = method;
  }

  /** A drawn frame's header: its surface statistics. */
  frame(header) {
    if (header?.surface) this.status.textContent = surfaceStatus(header.surface);
  }
}
