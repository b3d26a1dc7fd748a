// The colour legend over the view: which attribute colours the image and its
// range on the colormap's bar, how importance (which drives the optimized
// opacity) is mapped from its attribute (range and exponent, as a small
// curve), and a warning when the colour of the highest values matches the
// background. legendModel is pure (Node-tested); Legend writes the DOM.

import { gradientCss, topColorClash } from './colormaps.js';
import { attributeRange } from './ui.js';
import { termsSummary, filtersSummary } from './criteria.js';

const fmt = (v) => (typeof v === 'number' && Number.isFinite(v) ? String(Number(v.toPrecision(3))) : '–');

/**
 * What the legend shows for the page's current request values (defaults +
 * changes) and the dataset description: {color: {attribute, colormap, range,
 * rgb}, importance: {attribute, range, exponent}, method, opacity (a sentence),
 * clash (top colour ≈ background), top, background}.
 */
export function legendModel(values, info) {
  const color = values?.color ?? {};
  const imp = values?.importance ?? {};
  const colorAttr = color.attribute || info?.defaultColor || 'importance';
  const impAttr = imp.attribute || info?.defaultImportance || '';
  const colorRange = color.range ??
    (colorAttr === 'importance' ? [0, 1] : attributeRange(info, colorAttr, values?.params?.normalize)) ?? [0, 1];
  // Without an explicit range the server maps importance from the attribute's
  // auto range, min/max without the outliers (params.normalize "auto", the default), else min/max.
  const auto = (info?.attributes ?? []).find((x) => x?.name === impAttr)?.autoRange;
  const robust = values?.params?.normalize !== 'off' && Array.isArray(auto) && auto[1] > auto[0];
  const impRange = imp.range ??
    (robust ? [...auto] : attributeRange(info, impAttr, values?.params?.normalize)) ?? [0, 1];
  const exponent = imp.exponent ?? 1;
  const colormap = color.colormap ?? 'viridis';
  const background = values?.style?.background ?? [1, 1, 1];
  const method = values?.method ?? 'fourier';
  const rgb = colorAttr === 'rgb';
  const { top, clash } = rgb ? { top: null, clash: false } : topColorClash(colormap, colorRange, background);
  let opacity;
  if (method === 'opaque') opacity = 'Opaque: importance does not change opacity.';
  else if (method === 'direct') {
    const source = values?.params?.alphaSource ?? 'importance';
    if (source === 'constant')
      opacity = `Constant opacity α = ${fmt(values?.params?.alphaConstant ?? 0.3)}: importance does not change opacity.`;
    else if (source === 'angle')
      opacity =
        'Opacity from the angle to the view: parts seen edge-on are opaque, parts facing you clear; importance does not change opacity.';
    else if (source === 'normalVariation')
      opacity =
        "Opacity from the normal's change per pixel: contours are opaque, flat parts clear; importance does not change opacity.";
    else opacity = `Opacity α = g^${fmt(values?.params?.directExponent ?? 2)}: important parts are more opaque.`;
  } else if (method === 'kanzler')
    opacity =
      `Opacity α = g^${fmt(values?.params?.directExponent ?? 2)} times Kanzler's penalty: a part fades where it lies in front of ` +
      'the most important part of its pixel, where layers pile up and where directions cross; important parts are spared.';
  else
    opacity =
      'Opacity is optimized: a part fades where it hides parts more important than itself (r: in front, q: behind). ' +
      'Values below the range minimum get g = 0; if little is important, little is cleared, so clutter stays opaque.';
  // Direction: the server maps an attribute where smaller matters (smallerMatters,
  // a magnitude) inverted by default; importance.invert and a range given max
  // first each flip it once more.
  const impInfo = (info?.attributes ?? []).find((x) => x?.name === impAttr);
  const smallerMatters = !imp.terms?.length && !!impInfo?.smallerMatters;
  const smallerFirst = !imp.terms?.length && (!!imp.invert !== smallerMatters) !== impRange[0] > impRange[1];
  // Ticks in data units under the bar: linear over the colour range unless the
  // colours are equalized (then the frames' warped colorTicks take the row).
  const ticks = rgb || color.equalize ? null : linearTicks(colorRange);
  return {
    color: { attribute: colorAttr, colormap, range: colorRange, rgb },
    ticks,
    equalize: !!color.equalize,
    direction: { smallerMatters, smallerFirst, text: smallerFirst ? 'smaller = more important' : '' },
    importance: { attribute: impAttr, range: impRange, exponent },
    criteria: { terms: termsSummary(imp.terms), filters: filtersSummary(values?.filter) },
    method,
    opacity,
    clash,
    top,
    background,
  };
}

/**
 * The note beside the panel's Invert box for the importance attribute in force:
 * says when it already maps inverted by default (smallerMatters) and what the
 * box then does; '' for an attribute with the plain direction.
 */
export function invertNote(values, info) {
  const imp = values?.importance ?? {};
  if (imp.terms?.length) return '';
  const name = imp.attribute || info?.defaultImportance || '';
  if (!(info?.attributes ?? []).find((x) => x?.name === name)?.smallerMatters) return '';
  return imp.invert
    ? `${name}: inverted back, larger values are important (by default smaller ones are).`
    : `${name}: smaller values are important by default (its name says smaller matters); check to make larger values important.`;
}

/** SVG path of g = clamp((v − min)/(max − min))^exponent over the range, in a w × h box (y down). */
export function importanceCurvePath(exponent, w = 36, h = 18, n = 16) {
  const pts = [];
  for (let i = 0; i <= n; i++) {
    const t = i / n;
    const g = Math.pow(t, exponent > 0 ? exponent : 1);
    pts.push(`${(t * w).toFixed(1)},${(h - g * h).toFixed(1)}`);
  }
  return `M${pts.join(' L')}`;
}

/**
 * The warped ticks of an equalized frame (color.equalize): the frame header's
 * colorTicks, the data values at 0, ¼, ½, ¾ and 1 of the bar, as
 * [{at: percent along the bar, text}], or null when the frame has none (not
 * equalized, or malformed). inverted: the bar is drawn flipped (range max
 * first), so the values run right to left as the colours do.
 */
export function equalizedTicks(colorTicks, inverted = false) {
  if (
    !Array.isArray(colorTicks) ||
    colorTicks.length !== 5 ||
    !colorTicks.every((v) => typeof v === 'number' && Number.isFinite(v))
  )
    return null;
  return colorTicks.map((v, i) => ({ at: inverted ? 100 - 25 * i : 25 * i, text: fmt(v) }));
}

/**
 * Ticks of a linear colour bar in data units: the range's minimum, quarter
 * points and maximum as [{at: percent along the bar, text}], values running
 * right to left when the range is given max first (the bar is drawn flipped);
 * null for a range that is not two finite numbers.
 */
export function linearTicks(range) {
  if (!Array.isArray(range) || range.length !== 2 || !range.every((v) => typeof v === 'number' && Number.isFinite(v)))
    return null;
  const lo = Math.min(range[0], range[1]),
    hi = Math.max(range[0], range[1]);
  return equalizedTicks(
    [0, 1, 2, 3, 4].map((i) => (i === 4 ? hi : lo + ((hi - lo) * i) / 4)),
    range[0] > range[1],
  );
}

const NS = 'http://www.w3.org/2000/svg';

export class Legend {
  /** el: the legend's container; onFlip() is called by the warning's "Flip range" button. */
  constructor(el, { onFlip } = {}) {
    this.el = el;
    el.innerHTML = `
      <button type="button" class="legend-more" aria-expanded="false" title="What the legend means">i</button>
      <div class="legend-color"><span class="legend-label">Colour: <b data-role="color-attr"></b></span>
        <div class="legend-bar" data-role="bar"></div>
        <div class="legend-ticks"><span data-role="cmin"></span><span data-role="cmap"></span><span data-role="cmax"></span></div>
        <div class="legend-eq" data-role="eq-ticks" hidden title="Equalized colours: the data value at each mark of the bar in this view"></div>
      </div>
      <div class="legend-imp" title="Importance g from its attribute: g = clamp((v − min)/(max − min))^exponent">
        <svg width="36" height="18" viewBox="-1 -1 38 20" aria-hidden="true"><rect x="0" y="0" width="36" height="18" class="legend-curve-box"/><path data-role="curve"/></svg>
        <span>importance ← <b data-role="imp-attr"></b> <span data-role="imp-range"></span></span>
      </div>
      <div class="legend-criteria" data-role="criteria" hidden></div>
      <p class="legend-note" data-role="note" hidden></p>
      <p class="legend-warn" data-role="warn" hidden><span data-role="warn-text"></span> <button type="button" data-role="flip">Flip range</button></p>`;
    this.q = (r) => el.querySelector(`[data-role="${r}"]`);
    this.more = el.querySelector('.legend-more');
    this.more.addEventListener('click', () => {
      const open = this.more.getAttribute('aria-expanded') !== 'true';
      this.more.setAttribute('aria-expanded', String(open));
      this.q('note').hidden = !open;
    });
    this.q('flip').addEventListener('click', () => onFlip?.());
    this.model = null;
  }

  update(values, info) {
    const m = legendModel(values, info);
    this.model = m;
    const c = m.color;
    this.q('color-attr').textContent = c.rgb ? 'per-vertex RGB' : c.attribute;
    const bar = this.q('bar');
    bar.hidden = c.rgb;
    const inverted = c.range[0] > c.range[1];
    bar.style.background = gradientCss(c.colormap, inverted);
    const lo = Math.min(c.range[0], c.range[1]),
      hi = Math.max(c.range[0], c.range[1]);
    // min and max stand beside the colormap's name only when the tick row is empty (equalized, awaiting a frame)
    this.q('cmin').textContent = c.rgb || m.ticks ? '' : fmt(lo);
    this.q('cmax').textContent = c.rgb || m.ticks ? '' : fmt(hi);
    this.q('cmap').textContent = c.rgb ? '' : `${c.colormap}${inverted ? ' (flipped)' : ''}`;
    const i = m.importance;
    this.q('imp-attr').textContent = i.attribute || 'default';
    const dir = m.direction.text ? ` (${m.direction.text})` : '';
    this.q('imp-range').textContent =
      `[${fmt(i.range[0])}, ${fmt(i.range[1])}]${i.exponent !== 1 ? ` ^${fmt(i.exponent)}` : ''}${dir}`;
    this.q('curve').setAttribute('d', importanceCurvePath(i.exponent));
    // the curve falls from left to right when the smaller values are the important ones
    this.q('curve').setAttribute('transform', m.direction.smallerFirst ? 'translate(36 0) scale(-1 1)' : '');
    this.el.dataset.importanceDirection = m.direction.smallerFirst ? 'smaller' : 'larger';
    // terms replace the single attribute; filters say what is hidden
    const k = m.criteria;
    if (k.terms) this.q('imp-attr').textContent = k.terms;
    if (k.terms) this.q('imp-range').textContent = i.exponent !== 1 ? `^${fmt(i.exponent)}` : '';
    this.q('criteria').hidden = !k.filters;
    this.q('criteria').textContent = k.filters ? `shown: ${k.filters}` : '';
    this.q('note').textContent = m.opacity;
    this.q('warn').hidden = !m.clash;
    this.q('warn-text').textContent = m.clash
      ? `The colour of the highest values (${c.colormap}) matches the background: they are invisible.`
      : '';
    this.el.dataset.colorAttribute = c.attribute;
    this.el.dataset.colorRange = c.range.map(fmt).join(',');
    this.el.dataset.clash = String(m.clash);
    this.setColorTicks(this.colorTicks);
  }

  /**
   * The latest frame header's colorTicks (color.equalize): warped ticks under
   * the bar; without them the linear ticks of the colour range (equalize off).
   */
  setColorTicks(colorTicks) {
    this.colorTicks = colorTicks;
    const c = this.model?.color;
    const warped = c && !c.rgb && this.model.equalize ? equalizedTicks(colorTicks, c.range[0] > c.range[1]) : null;
    const ticks = warped ?? this.model?.ticks ?? null;
    const row = this.q('eq-ticks');
    const key = ticks ? `${warped ? 'eq' : 'lin'}:${ticks.map((t) => t.text).join(',')}` : '';
    if (row.dataset.ticks === key) return; // every frame carries them: touch the DOM on change only
    row.dataset.ticks = key;
    row.dataset.kind = warped ? 'equalized' : 'linear';
    row.title = warped
      ? 'Equalized colours: the data value at each mark of the bar in this view'
      : "The data value at each mark of the bar (the colour range, in the attribute's units)";
    row.hidden = !ticks;
    row.replaceChildren(
      ...(ticks ?? []).map((t) => {
        const span = document.createElement('span');
        span.style.left = `${t.at}%`;
        span.style.transform = `translateX(${-t.at}%)`; // the ends stay inside the bar
        span.textContent = t.text;
        return span;
      }),
    );
    this.el.dataset.colorTicks = ticks ? ticks.map((t) => t.text).join(',') : '';
  }
}
