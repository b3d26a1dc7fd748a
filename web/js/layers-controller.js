// The layer list (issue 27; docs/ALGORITHM.md §24): several of the server's datasets in one view. Adding a
// layer turns the view into a layered scene whose first layer is the dataset shown so far; each layer can be
// hidden, drawn as opaque context (lines and surfaces), given its own importance and colour attribute, and
// its own time window (datasets with a time attribute), filter (lines and points) and clustering (lines), as
// the request's layers[i].time, layers[i].filter and layers[i].lines.
// Every edit sends the whole list as `layers` through the params controller, so the session draws it in its
// next frame (a change of the layers' datasets starts its opacities afresh) and the link carries it
// (layers=[...]). Removing every layer but none (the last one's ×) goes back to the single dataset. The legend
// box gets one line per visible layer: its dataset, colour attribute, colormap bar and range.

import { gradientCss } from './colormaps.js';
import { attributeRange } from './ui.js';

export const MAX_LAYERS = 8;
const ROLE_LABELS = [
  ['transparent', 'Transparent'],
  ['context', 'Opaque context'],
];
const attrName = (a) => (typeof a === 'string' ? a : a?.name);
// The server's time attribute when time.attribute is "" (lc_scene_time_attribute): the first of these.
export const TIME_NAMES = ['time', 't', 'frame', 'timestep'];
const LINE_OVER = [
  ['max', 'max'],
  ['min', 'min'],
  ['mean', 'mean'],
  ['first', 'first'],
  ['last', 'last'],
  ['change', 'change'],
];

/** The list with a layer of dataset `name` added; the first addition keeps `current` (the shown dataset) as layer 0. */
export function addLayer(layers, current, name) {
  const list =
    Array.isArray(layers) && layers.length ? layers.map((l) => ({ ...l })) : current ? [{ dataset: current }] : [];
  if (list.length >= MAX_LAYERS) return list;
  list.push({ dataset: name });
  return list;
}

/**
 * The list with layer i's field set: visible, role, importance.attribute or color.attribute ('' = the
 * dataset's default), time ({window: [t0, t1]}, undefined = none), filter (an array, [] or undefined = none) or
 * lines ({clusters: n}, undefined = every line).
 */
export function setLayer(layers, i, path, value) {
  return layers.map((l, k) => {
    if (k !== i) return l;
    const out = { ...l, importance: l.importance && { ...l.importance }, color: l.color && { ...l.color } };
    if (path === 'visible' || path === 'role') {
      out[path] = value;
      if (path === 'role' && value === 'context' && out.color) delete out.color.equalize; // drawn before any visibility
    } else if (path === 'time' || path === 'filter' || path === 'lines') {
      if (value === undefined || (Array.isArray(value) && !value.length)) delete out[path];
      else out[path] = value;
    } else {
      const [section, key] = path.split('.');
      out[section] = { ...(out[section] ?? {}) };
      if (value === '' || value === undefined) delete out[section][key];
      else out[section][key] = value;
      // a new colour attribute brings its own range (the previous attribute's would not fit)
      if (section === 'color' && key === 'attribute') delete out.color.range;
      if (section === 'importance' && key === 'attribute') delete out.importance.range;
    }
    if (!out.importance || !Object.keys(out.importance).length) delete out.importance;
    if (!out.color || !Object.keys(out.color).length) delete out.color;
    return out;
  });
}

/** The time window of two typed bounds (numbers or ''): {window: [t0, t1]} when both are numbers, else undefined. */
export function timeWindow(t0, t1) {
  const a = Number.parseFloat(t0),
    b = Number.parseFloat(t1);
  return Number.isFinite(a) && Number.isFinite(b) ? { window: [Math.min(a, b), Math.max(a, b)] } : undefined;
}

/** A one-predicate filter list ({attribute, over, gt|lt: value}), [] without an attribute or a number. */
export function layerFilter(attribute, over, op, value) {
  const v = Number.parseFloat(value);
  if (!attribute || !Number.isFinite(v)) return [];
  return [{ attribute, over, [op === 'lt' ? 'lt' : 'gt']: v }];
}

/** The list without layer i ([] when none is left: the single dataset again). */
export function removeLayer(layers, i) {
  return layers.filter((_, k) => k !== i);
}

/**
 * What the legend shows for each visible layer: dataset, role, colour attribute (the layer's, else the
 * dataset's default, else importance), colormap (the layer's, else the server's default viridis) and range
 * (the layer's, else the attribute's range in the dataset's description; importance: [0, 1]).
 */
export function layerLegend(layers, infoOf) {
  return (layers ?? [])
    .filter((l) => l.visible !== false)
    .map((l) => {
      const info = infoOf(l.dataset);
      const by = l.color?.attribute || info?.defaultColor || 'importance';
      const rgb = by === 'rgb';
      const range = l.color?.range ?? (by === 'importance' ? [0, 1] : attributeRange(info, by, 'off'));
      return {
        dataset: l.dataset,
        role: l.role ?? 'transparent',
        attribute: by,
        rgb,
        colormap: l.color?.colormap || 'viridis',
        range,
      };
    });
}

const fmt = (x) => (typeof x === 'number' ? String(Number(x.toPrecision(3))) : '');

/**
 * ctx: doc; state (datasets, dataset); values() (the values shown: defaults + changes); apply(path, value)
 * (the params controller's applyChange). Elements: #layer-list, #layer-add, #legend.
 */
export function createLayersController(ctx) {
  const { doc, state } = ctx;
  const $ = (id) => doc.getElementById(id);
  const list = $('layer-list'),
    add = $('layer-add'),
    legendBox = $('legend');
  const legend = doc.createElement('div');
  legend.className = 'legend-layers';
  legend.dataset.testid = 'layer-legend';
  legend.hidden = true;
  legendBox.append(legend);
  const infoOf = (name) => state.datasets.find((d) => d.name === name) ?? null;
  const current = () => ctx.values().layers ?? [];
  const el = (tag, props = {}, ...kids) => {
    const e = Object.assign(doc.createElement(tag), props);
    e.append(...kids);
    return e;
  };
  const select = (label, options, value, onChange) => {
    const s = el('select', { title: label });
    s.setAttribute('aria-label', label);
    for (const [v, t] of options) s.append(new Option(t, v));
    s.value = value;
    s.addEventListener('change', () => onChange(s.value));
    return s;
  };

  add.addEventListener('change', () => {
    const name = add.value;
    add.value = '';
    if (name) ctx.apply('layers', addLayer(current(), state.dataset, name));
  });

  function showList(layers) {
    list.replaceChildren();
    layers.forEach((l, i) => {
      const info = infoOf(l.dataset);
      const attrs = (info?.attributes ?? []).map(attrName).filter(Boolean);
      const vis = el('input', { type: 'checkbox', checked: l.visible !== false, title: 'Visible' });
      vis.setAttribute('aria-label', `Show layer ${i + 1} (${l.dataset})`);
      vis.addEventListener('change', () => ctx.apply('layers', setLayer(current(), i, 'visible', vis.checked)));
      const roles = info?.type === 'points' ? ROLE_LABELS.slice(0, 1) : ROLE_LABELS; // context: lines or surfaces
      const role = select(`Role of layer ${i + 1}`, roles, l.role ?? 'transparent', (v) =>
        ctx.apply('layers', setLayer(current(), i, 'role', v)),
      );
      const imp = select(
        `Importance attribute of layer ${i + 1}`,
        [['', 'importance: default'], ...attrs.map((a) => [a, `importance: ${a}`])],
        l.importance?.attribute ?? '',
        (v) => ctx.apply('layers', setLayer(current(), i, 'importance.attribute', v)),
      );
      const col = select(
        `Colour attribute of layer ${i + 1}`,
        [['', 'colour: default'], ['importance', 'colour: importance'], ...attrs.map((a) => [a, `colour: ${a}`])],
        l.color?.attribute ?? '',
        (v) => ctx.apply('layers', setLayer(current(), i, 'color.attribute', v)),
      );
      const remove = el('button', {
        type: 'button',
        textContent: '×',
        title: `Remove layer ${i + 1}`,
        className: 'layer-remove',
      });
      remove.setAttribute('aria-label', `Remove layer ${i + 1} (${l.dataset})`);
      remove.addEventListener('click', () => ctx.apply('layers', removeLayer(current(), i)));
      const row = el(
        'div',
        { className: 'layer-row' },
        el('label', { className: 'layer-name' }, vis, ` ${l.dataset}`),
        role,
        imp,
        col,
        remove,
      );
      const sections = el('div', { className: 'layer-sections' });
      const timeAttr = TIME_NAMES.find((n) => attrs.includes(n));
      if (timeAttr && info?.type !== 'triangles') {
        const range = attributeRange(info, timeAttr, 'off') ?? [];
        const bound = (k, label) => {
          const input = el('input', {
            type: 'number',
            step: 'any',
            placeholder: fmt(range[k]),
            title: label,
            value: l.time?.window?.[k] ?? '',
          });
          input.setAttribute('aria-label', `${label} of layer ${i + 1}`);
          return input;
        };
        const t0 = bound(0, 'Time window start'),
          t1 = bound(1, 'Time window end');
        const send = () => {
          const w = timeWindow(t0.value, t1.value);
          if (w || (t0.value === '' && t1.value === '')) ctx.apply('layers', setLayer(current(), i, 'time', w)); // else: the other bound comes
        };
        t0.addEventListener('change', send);
        t1.addEventListener('change', send);
        sections.append(el('label', { className: 'layer-time' }, `${timeAttr} `, t0, ' – ', t1));
      }
      if (info?.type === 'lines' || info?.type === 'points') {
        const f = l.filter?.[0];
        const overs = info.type === 'points' ? [['vertex', 'value']] : LINE_OVER;
        const fAttr = select(
          `Filter attribute of layer ${i + 1}`,
          [['', 'filter: none'], ...attrs.map((a) => [a, `filter: ${a}`])],
          f?.attribute ?? '',
          () => send(),
        );
        const fOver = select(`Filter statistic of layer ${i + 1}`, overs, f?.over ?? overs[0][0], () => send());
        const fOp = select(
          `Filter comparison of layer ${i + 1}`,
          [
            ['gt', '>'],
            ['lt', '<'],
          ],
          f && 'lt' in f && !('gt' in f) ? 'lt' : 'gt',
          () => send(),
        );
        const fValue = el('input', { type: 'number', step: 'any', title: 'Filter value', value: f?.gt ?? f?.lt ?? '' });
        fValue.setAttribute('aria-label', `Filter value of layer ${i + 1}`);
        fValue.addEventListener('change', () => send());
        const send = () => {
          const list = layerFilter(fAttr.value, fOver.value, fOp.value, fValue.value);
          if (list.length || !fAttr.value) ctx.apply('layers', setLayer(current(), i, 'filter', list)); // else: the value comes
        };
        sections.append(el('span', { className: 'layer-filter' }, fAttr, fOver, fOp, fValue));
      }
      if (l.role !== 'context') {
        const eq = el('input', {
          type: 'checkbox',
          checked: l.color?.equalize === true,
          title: "Equalize this layer's colours over what is visible of it (Fourier and direct methods)",
        });
        eq.setAttribute('aria-label', `Equalize the colours of layer ${i + 1}`);
        eq.addEventListener('change', () =>
          ctx.apply('layers', setLayer(current(), i, 'color.equalize', eq.checked || undefined)),
        );
        sections.append(el('label', { className: 'layer-equalize' }, eq, ' equalize'));
      }
      if (info?.type === 'lines') {
        const n = el('input', {
          type: 'number',
          min: 0,
          step: 1,
          placeholder: 'all',
          title: 'Clusters (one representative line each; empty: every line)',
          value: l.lines?.clusters ?? '',
        });
        n.setAttribute('aria-label', `Clusters of layer ${i + 1}`);
        n.addEventListener('change', () => {
          const k = Number.parseInt(n.value, 10);
          ctx.apply(
            'layers',
            setLayer(current(), i, 'lines', Number.isFinite(k) && k > 0 ? { clusters: k } : undefined),
          );
        });
        sections.append(el('label', { className: 'layer-clusters' }, 'clusters ', n));
      }
      if (sections.childNodes.length) row.append(sections);
      row.dataset.index = String(i);
      list.append(row);
    });
  }

  function showLegend(layers) {
    const rows = layerLegend(layers, infoOf);
    legend.hidden = rows.length === 0;
    legendBox.classList.toggle('layered', layers.length > 0);
    legend.replaceChildren(
      ...rows.map((r) => {
        const bar = el('div', { className: 'legend-bar' });
        bar.hidden = r.rgb;
        if (!r.rgb) bar.style.background = gradientCss(r.colormap, Array.isArray(r.range) && r.range[0] > r.range[1]);
        const ticks = el(
          'div',
          { className: 'legend-ticks' },
          el('span', { textContent: fmt(r.range?.[0]) }),
          el('span', { textContent: r.rgb ? '' : r.colormap }),
          el('span', { textContent: fmt(r.range?.[1]) }),
        );
        const label = el(
          'span',
          { className: 'legend-label' },
          el('b', { textContent: r.dataset }),
          `${r.role === 'context' ? ' (context)' : ''}: ${r.rgb ? 'per-vertex RGB' : r.attribute}`,
        );
        const row = el('div', { className: 'legend-layer' }, label, bar, ticks);
        row.dataset.dataset = r.dataset;
        return row;
      }),
    );
  }

  return {
    /** The values shown and the server's datasets: the list, the add menu and the legends. */
    show(values) {
      const layers = values.layers ?? [];
      const names = state.datasets.filter((d) => d.kind !== 'field').map((d) => d.name); // a field's set draws alone
      const have = [...add.options].slice(1).map((o) => o.value);
      if (have.join('\n') !== names.join('\n'))
        add.replaceChildren(new Option('Add a layer…', ''), ...names.map((n) => new Option(n, n)));
      add.disabled = layers.length >= MAX_LAYERS;
      showList(layers);
      showLegend(layers);
    },
  };
}
