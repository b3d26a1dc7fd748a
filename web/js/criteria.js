// Editors of the request's list fields (protocol/README.md): importance terms
// (weighted criteria), filters, and transfer-function curves edited by
// control points. Each editor is {el, set(value), setAttributes(names)} and
// reports a new value through onChange(value, final); the panel (ui.js) hosts
// them. The summaries are pure (Node-tested) and feed the legend.

const fmt = (v) => (typeof v === 'number' && Number.isFinite(v) ? String(Number(v.toPrecision(3))) : '–');
const OPS = { gt: '>', lt: '<', range: '∈' };

/** "g = (0.5·speed − 0.25·(1−disp)) / 0.75", the penalty form "g = 1 − (...)/…" (docs/ALGORITHM.md §14). */
export function termsSummary(terms) {
  if (!Array.isArray(terms) || !terms.length) return '';
  const sumAbs = terms.reduce((s, t) => s + Math.abs(t.weight ?? 1), 0);
  const sum = terms.reduce((s, t) => s + (t.weight ?? 1), 0);
  const parts = terms.map((t, i) => {
    const w = t.weight ?? 1;
    const name = t.invert ? `(1−${t.attribute})` : t.attribute;
    const mag = Math.abs(w) === 1 ? '' : `${fmt(Math.abs(w))}·`;
    return `${i === 0 ? (w < 0 ? '−' : '') : w < 0 ? ' − ' : ' + '}${mag}${name}`;
  });
  const body = sumAbs === 1 ? parts.join('') : `(${parts.join('')}) / ${fmt(sumAbs)}`;
  return sum < 0 ? `g = 1 + ${body}` : `g = ${body}`;
}

/** "change(p) < −500, max(speed) ∈ [1, 2]". */
export function filtersSummary(filters) {
  if (!Array.isArray(filters) || !filters.length) return '';
  return filters
    .map((f) => {
      const what = !f.over || f.over === 'vertex' ? f.attribute : `${f.over}(${f.attribute})`;
      if (Array.isArray(f.range)) return `${what} ∈ [${fmt(f.range[0])}, ${fmt(f.range[1])}]`;
      const b = [];
      if (f.gt !== undefined) b.push(`> ${fmt(f.gt)}`);
      if (f.lt !== undefined) b.push(`< ${fmt(f.lt)}`);
      return `${what} ${b.join(' and ')}`;
    })
    .join(', ');
}

const el = (tag, props = {}, ...kids) => {
  const e = document.createElement(tag);
  Object.assign(e, props);
  e.append(...kids);
  return e;
};
const num = (value, label, step = 'any') =>
  el('input', { type: 'number', className: 'num', step, value: String(value ?? ''), ariaLabel: label });
const select = (options, value, label) => {
  const s = el('select', { ariaLabel: label });
  for (const [v, t] of options) s.append(new Option(t, v));
  if (value !== undefined) {
    if (![...s.options].some((o) => o.value === value)) s.append(new Option(value, value));
    s.value = value;
  }
  return s;
};

const ITEM_NAMES = { terms: 'term', filters: 'filter', ranges: 'range' };

/**
 * Rows of items with a remove button each and an add button; build(item) returns {row, read()}. Terms and
 * filters name attributes (no row until the dataset's are known); ranges do not.
 */
function listEditor(kind, max, blank, build, onChange) {
  const root = el('div', { className: `list-editor ${kind}` });
  const rows = el('div');
  const item = ITEM_NAMES[kind];
  const needsNames = kind !== 'ranges';
  const add = el('button', { type: 'button', textContent: `+ ${item}` });
  root.append(rows, add);
  let items = [];
  let names = [];
  const fire = () => onChange(items.map((it) => it.read()).filter(Boolean), true);
  const render = (values) => {
    items = values.map((v) => {
      const it = build(v, names, fire);
      const del = el('button', { type: 'button', textContent: '×', ariaLabel: `remove this ${item}` });
      del.addEventListener('click', () => {
        const next = items
          .filter((x) => x !== it)
          .map((x) => x.read())
          .filter(Boolean);
        render(next);
        onChange(next, true);
      });
      it.row.append(del);
      return it;
    });
    rows.replaceChildren(...items.map((it) => it.row));
    add.disabled = items.length >= max || (needsNames && !names.length);
  };
  add.addEventListener('click', () => {
    const next = [...items.map((x) => x.read()).filter(Boolean), blank(names)];
    render(next);
    onChange(next, true);
  });
  return {
    el: root,
    set: (v) => {
      if (!root.contains(document.activeElement)) render(Array.isArray(v) ? v : []);
    },
    setAttributes: (list) => {
      names = list;
      render(items.map((x) => x.read()).filter(Boolean));
    },
  };
}

function termRow(t, names, fire) {
  const attr = select(
    names.map((n) => [n, n]),
    t.attribute,
    'term attribute',
  );
  const weight = num(t.weight ?? 1, 'term weight (−1 to 1)');
  Object.assign(weight, { min: -1, max: 1, step: 0.05 });
  const invert = el('input', { type: 'checkbox', checked: !!t.invert, ariaLabel: 'invert the term' });
  const lo = num(t.range?.[0], 'term range minimum (empty: auto)');
  const hi = num(t.range?.[1], 'term range maximum (empty: auto)');
  const row = el('div', { className: 'list-row' }, attr, ' w ', weight, el('label', {}, invert, ' 1−t'), lo, '–', hi);
  for (const e of [attr, weight, invert, lo, hi]) e.addEventListener('change', fire);
  return {
    row,
    read: () => {
      const out = { attribute: attr.value, weight: Number(weight.value) };
      if (!out.attribute || !Number.isFinite(out.weight)) return null;
      if (invert.checked) out.invert = true;
      if (lo.value !== '' && hi.value !== '') out.range = [Number(lo.value), Number(hi.value)];
      return out;
    },
  };
}

function filterRow(f, names, fire) {
  const attr = select(
    names.map((n) => [n, n]),
    f.attribute,
    'filter attribute',
  );
  const over = select(
    ['vertex', 'min', 'max', 'mean', 'first', 'last', 'change'].map((o) => [o, o]),
    f.over ?? 'change',
    'over the line',
  );
  const op0 = Array.isArray(f.range) ? 'range' : f.lt !== undefined && f.gt === undefined ? 'lt' : 'gt';
  const op = select(Object.entries(OPS), op0, 'comparison');
  const a = num(op0 === 'range' ? f.range[0] : op0 === 'lt' ? f.lt : (f.gt ?? 0), 'filter value');
  const b = num(op0 === 'range' ? f.range[1] : '', 'filter upper bound');
  b.hidden = op0 !== 'range';
  const row = el('div', { className: 'list-row' }, attr, over, op, a, b);
  op.addEventListener('change', () => {
    b.hidden = op.value !== 'range';
  });
  for (const e of [attr, over, op, a, b]) e.addEventListener('change', fire);
  return {
    row,
    read: () => {
      const x = Number(a.value);
      if (!attr.value || a.value === '' || !Number.isFinite(x)) return null;
      const out = { attribute: attr.value, over: over.value };
      if (op.value === 'range') {
        const y = Number(b.value);
        if (b.value === '' || !Number.isFinite(y)) return null;
        out.range = [Math.min(x, y), Math.max(x, y)];
      } else out[op.value] = x;
      return out;
    },
  };
}

/** A fixed range of color.fixed: [lo, hi] in data units, kept as the identity by equalization. */
function rangeRow(r, names, fire) {
  const lo = num(r?.[0], 'fixed range minimum');
  const hi = num(r?.[1], 'fixed range maximum');
  const row = el('div', { className: 'list-row' }, lo, '–', hi);
  for (const e of [lo, hi]) e.addEventListener('change', fire);
  return {
    row,
    read: () => {
      const a = Number(lo.value),
        b = Number(hi.value);
      if (lo.value === '' || hi.value === '' || !Number.isFinite(a) || !Number.isFinite(b)) return null;
      return [Math.min(a, b), Math.max(a, b)];
    },
  };
}

export const rangesEditor = (onChange) => listEditor('ranges', 4, () => [0, 1], rangeRow, onChange);
export const termsEditor = (onChange) =>
  listEditor('terms', 4, (names) => ({ attribute: names[0], weight: 1 }), termRow, onChange);
export const filtersEditor = (onChange) =>
  listEditor('filters', 8, (names) => ({ attribute: names[0], over: 'change', gt: 0 }), filterRow, onChange);

/** Sorted, clamped control points; [] for the identity through (0,0) and (1,1). */
export function normalizeCurve(points) {
  const p = (points ?? [])
    .filter((q) => Array.isArray(q) && q.length === 2 && q.every(Number.isFinite))
    .map(([x, y]) => [Math.min(1, Math.max(0, Number(x.toFixed(4)))), Math.min(1, Math.max(0, Number(y.toFixed(4))))])
    .sort((a, b) => a[0] - b[0])
    .slice(0, 64);
  const identity = p.length === 2 && p[0][0] === 0 && p[0][1] === 0 && p[1][0] === 1 && p[1][1] === 1;
  return p.length < 2 || identity ? [] : p;
}

const SVG = 'http://www.w3.org/2000/svg';

/**
 * A transfer-function editor: a 120 × 60 box with the curve through its
 * control points; drag a point, click empty space to add one, double-click a
 * point to remove it, "reset" for the identity. Values as the request's curve.
 */
export function curveEditor(onChange) {
  const W = 120,
    H = 60;
  const root = el('div', { className: 'curve-editor' });
  const svg = document.createElementNS(SVG, 'svg');
  svg.setAttribute('viewBox', `-4 -4 ${W + 8} ${H + 8}`);
  svg.setAttribute('width', String(W + 8));
  svg.setAttribute('height', String(H + 8));
  svg.setAttribute('role', 'img');
  const box = document.createElementNS(SVG, 'rect');
  Object.entries({ x: 0, y: 0, width: W, height: H, class: 'legend-curve-box' }).forEach(([k, v]) =>
    box.setAttribute(k, String(v)),
  );
  const path = document.createElementNS(SVG, 'path');
  path.setAttribute('fill', 'none');
  path.setAttribute('stroke', 'currentColor');
  svg.append(box, path);
  const reset = el('button', { type: 'button', textContent: 'reset' });
  root.append(svg, reset);
  let pts = [
    [0, 0],
    [1, 1],
  ];
  let drag = -1;
  const toXY = (e) => {
    const r = svg.getBoundingClientRect();
    const x = ((e.clientX - r.left) / r.width) * (W + 8) - 4,
      y = ((e.clientY - r.top) / r.height) * (H + 8) - 4;
    return [Math.min(1, Math.max(0, x / W)), Math.min(1, Math.max(0, 1 - y / H))];
  };
  const draw = () => {
    path.setAttribute('d', `M${pts.map(([x, y]) => `${(x * W).toFixed(1)},${((1 - y) * H).toFixed(1)}`).join(' L')}`);
    svg.querySelectorAll('circle').forEach((c) => c.remove());
    pts.forEach(([x, y], i) => {
      const c = document.createElementNS(SVG, 'circle');
      c.setAttribute('cx', String(x * W));
      c.setAttribute('cy', String((1 - y) * H));
      c.setAttribute('r', '3.5');
      c.addEventListener('pointerdown', (e) => {
        drag = i;
        svg.setPointerCapture(e.pointerId);
        e.stopPropagation();
      });
      c.addEventListener('dblclick', () => {
        if (pts.length > 2) pts.splice(i, 1);
        commit();
      });
      svg.append(c);
    });
  };
  const commit = () => {
    draw();
    onChange(normalizeCurve(pts), true);
  };
  svg.addEventListener('pointerdown', (e) => {
    if (drag >= 0 || pts.length >= 64) return;
    pts.push(toXY(e));
    pts.sort((a, b) => a[0] - b[0]);
    commit();
  });
  svg.addEventListener('pointermove', (e) => {
    if (drag < 0) return;
    pts[drag] = toXY(e);
    draw();
  });
  svg.addEventListener('pointerup', () => {
    if (drag < 0) return;
    drag = -1;
    pts.sort((a, b) => a[0] - b[0]);
    commit();
  });
  reset.addEventListener('click', () => {
    pts = [
      [0, 0],
      [1, 1],
    ];
    commit();
  });
  draw();
  return {
    el: root,
    set: (v) => {
      if (drag >= 0) return;
      pts =
        Array.isArray(v) && v.length >= 2
          ? v.map((p) => [...p])
          : [
              [0, 0],
              [1, 1],
            ];
      draw();
    },
    setAttributes: () => {},
  };
}
