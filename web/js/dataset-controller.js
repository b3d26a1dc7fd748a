// The dataset picker and the per-dataset presets: what the picker and the
// line below it show, choosing a dataset, and a preset put under the link's
// values with an undo.

import { cloneCamera, validateCamera } from './camera.js';
import { applyPreset, removePreset } from './preset.js';
import { datasetInfo } from './app-state.js';

/** "12,000 lines, 3,000,000 vertices, 2,000 elements". */
export function describeDataset(d) {
  if (!d) return '';
  const n = (x) => (typeof x === 'number' ? x.toLocaleString('en-US') : x);
  if (d.kind === 'field') return 'vector field: the streamline set of the Streamlines group, traced by the server';
  const parts = [];
  if (d.type && !d.lines && !d.triangles && !d.vertices) parts.push(d.type);
  if (d.lines) parts.push(`${n(d.lines)} lines`);
  if (d.triangles) parts.push(`${n(d.triangles)} triangles`);
  if (!d.lines && !d.triangles && d.vertices) parts.push(`${n(d.vertices)} points`);
  else if (d.vertices) parts.push(`${n(d.vertices)} vertices`);
  if (d.elements) parts.push(`${n(d.elements)} elements`);
  return parts.join(', ');
}

/** "12k lines": short enough for a phone's picker. */
export function shortSize(d) {
  const k = (x) =>
    x >= 1e6 ? `${Number((x / 1e6).toPrecision(2))}M` : x >= 1e4 ? `${Math.round(x / 1e3)}k` : String(x);
  if (d.kind === 'field') return 'vector field';
  if (d.lines) return `${k(d.lines)} lines`;
  if (d.triangles) return `${k(d.triangles)} triangles`;
  if (d.vertices) return `${k(d.vertices)} points`;
  return d.type ?? '';
}

/**
 * What the picker shows: options [value, text] (the chosen name first when the
 * server does not list it), and the chosen dataset's description, summary and
 * attribute lines (null when unknown).
 */
export function datasetView(state) {
  const names = state.datasets.map((d) => d.name);
  if (state.dataset && !names.includes(state.dataset)) names.unshift(state.dataset);
  // the option says name and size only (it must fit a phone's picker); the line below has the details
  const options = names.map((n) => {
    const d = datasetInfo(state, n);
    return [n, d ? `${n} · ${shortSize(d)}` : `${n} (unknown)`];
  });
  const d = state.info?.name === state.dataset ? state.info : datasetInfo(state);
  const details = d && {
    description: d.description ?? null,
    summary: describeDataset(d),
    attributes: (d.attributes ?? []).map((a) =>
      typeof a === 'string'
        ? a
        : `${a.name}${Array.isArray(a.range) ? ` [${a.range.map((x) => Number(x.toPrecision(3))).join(', ')}]` : ''}`,
    ),
  };
  return { options, selected: state.dataset ?? null, title: state.dataset ?? '', details };
}

/**
 * ctx: state; camera (the controller: initial(info)); ui: {toast(text),
 * showPresetNote(title) / hidePresetNote(), showBanner(text, opts), showDataset(),
 * body(key, value)}.
 */
export function createDatasetController(ctx) {
  const { state, ui } = ctx;

  /**
   * Puts the chosen dataset's preset (its description's "preset") under the
   * given link values (the link wins), into state.update and state.camera, and
   * says so with an undo. link: {update, camera}.
   */
  function usePreset(link) {
    ui.hidePresetNote();
    state.preset = null;
    const preset = datasetInfo(state)?.preset;
    if (!preset || typeof preset !== 'object') return;
    const r = applyPreset(preset, link.update, link.camera);
    if (r.errors.length) ui.toast(`Preset of ${state.dataset}: ignored ${r.errors.join('; ')}`);
    if (!r.applied.length && !r.cameraApplied) return;
    state.update = r.update;
    if (r.cameraApplied) {
      const home = ctx.camera.initial(datasetInfo(state));
      const cam = cloneCamera({ ...(home ?? {}), ...r.camera });
      if (!validateCamera(cam)) {
        state.camera = cam;
        state.fitted = false;
      }
    }
    state.preset = { dataset: state.dataset, preset, applied: r.applied, cameraApplied: r.cameraApplied };
    const what = [...r.applied, ...(r.cameraApplied ? ['camera'] : [])];
    ui.showPresetNote(
      `The preset of ${state.dataset} set ${what.join(', ')}; “undo” goes back to the server's defaults`,
    );
    ui.body('preset', state.dataset);
  }

  /** Takes the preset's values back out; returns false when there was none. */
  function undoPreset() {
    const p = state.preset;
    ui.hidePresetNote();
    if (!p) return false;
    state.update = removePreset(state.update, p.preset, p.applied);
    if (p.cameraApplied) state.camera = null; // back to the dataset's own view
    state.preset = null;
    ui.body('preset', undefined);
    ui.toast(`Preset for ${p.dataset} undone: the server's defaults apply.`);
    return true;
  }

  /** The picker chose name: a fitted camera, no attributes or preset of the old dataset. */
  function choose(name) {
    state.dataset = name;
    state.camera = null; // fit the new data
    state.info = datasetInfo(state);
    // attributes belong to the old dataset, and so does the old preset
    delete state.update.importance;
    delete state.update.color;
    delete state.update.streamlines; // a field's seeding (the new dataset's, if a field, starts at the defaults)
    if (state.preset) state.update = removePreset(state.update, state.preset.preset, state.preset.applied);
    state.error = null;
    usePreset({ update: state.update, camera: null });
  }

  /** An unknown dataset in the link is said at once (the server's answer to hello confirms it). Returns true when shown. */
  function checkDataset() {
    if (state.dataset && state.datasets.length && !state.datasets.some((d) => d.name === state.dataset)) {
      ui.showBanner(
        `Dataset “${state.dataset}” is not available on this server. Available: ${state.datasets.map((d) => d.name).join(', ')}.`,
        { kind: 'error' },
      );
      ui.showDataset();
      return true;
    }
    return false;
  }

  return { usePreset, undoPreset, choose, checkDataset };
}
