// The page's streamline controls (docs/ALGORITHM.md §22): when the chosen
// dataset is a vector field, the server traces the streamline set the
// request's streamlines object describes and draws it as a line dataset. This
// group edits that object: the seeding (points, a rake, a box, density-driven
// seeds), its points (a rake's two ends are drawn as the view's seed handles),
// the curve count, the RK4 step, the curve length, the direction and the
// density's separation. Every change sends the whole object (the server takes
// it as the whole set); the server re-traces only then, not on camera moves.

import { defaultSeed, parsePoints } from './surface-panel.js';

/** The server's defaults (lc_request_default): density seeding, 64 curves, the tracer's own step and length. */
export const STREAMLINE_DEFAULTS = Object.freeze({
  seeding: 'density',
  count: 64,
  step: 0,
  length: 0,
  direction: 'forward',
  separation: 0,
});

/**
 * The streamlines object of the form's values: every key the seeding reads
 * (count not for points, separation for density only, seeds where typed);
 * { error } when the points do not suit the seeding.
 */
export function streamlinesObject({ seeding, seeds, count, step, length, direction, separation }) {
  const points = parsePoints(seeds);
  if (!points) return { error: 'Seeds: expected points x, y, z separated by ";"' };
  if (seeding === 'points' && points.length < 1) return { error: 'Seeds: point seeding needs at least one point' };
  if (seeding === 'rake' && points.length !== 2) return { error: 'Seeds: a rake takes its two ends' };
  if ((seeding === 'box' || seeding === 'density') && points.length !== 0 && points.length !== 2)
    return { error: "Seeds: a box takes two corners (none: the field's bounds)" };
  const o = { seeding, direction };
  if (points.length) o.seeds = points;
  if (seeding !== 'points') o.count = count;
  if (step > 0) o.step = step;
  if (length > 0) o.length = length;
  if (seeding === 'density' && separation > 0) o.separation = separation;
  return o;
}

/** "x, y, z; x, y, z" of points. */
const pointsText = (points) => (points ?? []).map((p) => p.join(', ')).join('; ');

/**
 * A fieldset in the settings panel; apply(value) sends the whole streamlines
 * object, toast(text) reports.
 */
export class StreamlinesPanel {
  constructor(parent, doc, apply, toast) {
    this.apply = apply;
    this.toast = toast;
    this.field = null; // the field shown (its description: name, bounds)
    const el = (tag, props = {}) => Object.assign(doc.createElement(tag), props);
    const box = el('fieldset', { className: 'group', id: 'group-streamlines' });
    box.dataset.testid = 'streamlines';
    box.append(el('legend', { textContent: 'Streamlines' }));
    const row = (label, input) => {
      const r = el('div', { className: 'row', title: input.title });
      r.append(el('label', { textContent: label, htmlFor: input.id }), input);
      box.append(r);
      return input;
    };
    this.seeding = row(
      'Seeding',
      el('select', {
        id: 'streamlines-seeding',
        title:
          'Where the curves start: the typed points, evenly along a rake between two points, spread through a box, or density-driven (a new seed only where no curve runs nearby).',
      }),
    );
    this.seeding.append(
      ...[
        ['points', 'points'],
        ['rake', 'rake'],
        ['box', 'box'],
        ['density', 'density-driven'],
      ].map(([v, t]) => el('option', { value: v, textContent: t })),
    );
    this.seeds = row(
      'Seeds x,y,z; …',
      el('input', {
        type: 'text',
        id: 'streamlines-seeds',
        size: 22,
        title:
          'Points: the seed points. Rake: its two ends (drag the handles in the view). Box and density: its two corners; empty: the whole field.',
      }),
    );
    this.count = row(
      'Curves',
      el('input', {
        type: 'number',
        id: 'streamlines-count',
        min: 1,
        max: 100000,
        value: 64,
        title: 'How many curves a rake, box or density seeding traces (points: one per point).',
      }),
    );
    this.step = row(
      'Step',
      el('input', {
        type: 'number',
        id: 'streamlines-step',
        min: 0,
        step: 'any',
        value: 0,
        title: "The RK4 time step; 0: the field's size over 200 times its largest speed.",
      }),
    );
    this.length = row(
      'Length',
      el('input', {
        type: 'number',
        id: 'streamlines-length',
        min: 0,
        step: 'any',
        value: 0,
        title: "Arc length of a curve (each half of a two-way curve); 0: twice the field's diagonal.",
      }),
    );
    this.direction = row(
      'Direction',
      el('select', { id: 'streamlines-direction', title: 'Downstream, upstream, or both ways from each seed.' }),
    );
    this.direction.append(...['forward', 'backward', 'both'].map((d) => el('option', { value: d, textContent: d })));
    this.separation = row(
      'Separation',
      el('input', {
        type: 'number',
        id: 'streamlines-separation',
        min: 0,
        step: 'any',
        value: 0,
        title:
          'Density-driven seeding: how close a new seed may come to the curves so far; 0: from the box and the curve count.',
      }),
    );
    box.hidden = true; // until the dataset is a field
    this.box = box;
    parent.append(box);
    this.seeding.addEventListener('change', () => {
      this.suggestSeeds();
      this.send();
    });
    for (const input of [this.seeds, this.count, this.step, this.length, this.direction, this.separation])
      input.addEventListener('change', () => this.send());
  }

  /**
   * The chosen dataset: field is its description when it is a vector field
   * (kind "field"), else null (the group hides). value: the request's
   * streamlines object the form shows (the link's, or none: the defaults).
   */
  show(field, value) {
    const changed = (field?.name ?? null) !== (this.field?.name ?? null);
    this.field = field;
    this.box.hidden = !field;
    if (!field || !changed) return;
    const v = { ...STREAMLINE_DEFAULTS, ...(value ?? {}) };
    this.seeding.value = v.seeding;
    this.seeds.value = pointsText(v.seeds);
    this.count.value = v.count;
    this.step.value = v.step;
    this.length.value = v.length;
    this.direction.value = v.direction;
    this.separation.value = v.separation;
    this.separationShown();
  }

  separationShown() {
    this.separation.parentElement.hidden = this.seeding.value !== 'density';
    this.count.parentElement.hidden = this.seeding.value === 'points';
  }

  /** A rake needs its two ends: the default seed line across the field when none are typed. */
  suggestSeeds() {
    this.separationShown();
    const n = (parsePoints(this.seeds.value) ?? []).length;
    if (this.seeding.value === 'rake' && n !== 2 && this.field?.bounds)
      this.seeds.value = pointsText(defaultSeed(this.field.bounds));
    if (this.seeding.value === 'points' && n === 0 && this.field?.bounds)
      this.seeds.value = pointsText(defaultSeed(this.field.bounds));
  }

  /** The form's streamlines object, or null (with a toast) when it does not suit the seeding. */
  values() {
    const o = streamlinesObject({
      seeding: this.seeding.value,
      seeds: this.seeds.value,
      count: Number(this.count.value),
      step: Number(this.step.value),
      length: Number(this.length.value),
      direction: this.direction.value,
      separation: Number(this.separation.value),
    });
    if (o.error) {
      this.toast(o.error);
      return null;
    }
    return o;
  }

  /** Sends the form as the whole streamlines object. */
  send() {
    const v = this.values();
    if (v) this.apply(v);
  }

  /** What the view's seed overlay draws: the rake's two ends and the field's bounds, or null. */
  shownSeed() {
    if (this.box.hidden || this.seeding.value !== 'rake') return null;
    const p = parsePoints(this.seeds.value);
    return p && p.length === 2 ? { seed: p, bounds: this.field?.bounds ?? null } : null;
  }

  /** A dragged rake end (0, 1) into the typed seeds; send() sends it. */
  setPoint(index, point) {
    const p = parsePoints(this.seeds.value);
    if (!p || p.length !== 2) return;
    p[index] = point;
    this.seeds.value = pointsText(p);
  }
}
