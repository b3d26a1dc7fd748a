// Per-dataset presets: a dataset description (GET /api/v1/datasets) may carry
// "preset", a partial render request ({params, importance, color, style,
// camera, method}, any subset). The page applies it when the dataset is chosen,
// under whatever the link itself says (the URL wins), and can take it back.
// Pure functions, Node-tested.

import { fieldByPath, checkField, getPath, setPath, merge, UPDATE_SECTIONS } from './schema.js';

const CAMERA_KEYS = ['position', 'focalPoint', 'viewUp', 'viewAngle', 'parallelProjection', 'parallelScale'];

/**
 * Reads a preset object. Returns {update, camera, errors}: update the request
 * sections and method it sets (only valid fields), camera its partial camera
 * (null when none), errors one line per field that was unknown or invalid.
 */
export function readPreset(preset) {
  const out = { update: {}, camera: null, errors: [] };
  if (!preset || typeof preset !== 'object' || Array.isArray(preset)) return out;
  for (const [section, body] of Object.entries(preset)) {
    if (section === 'method') {
      const problem = checkField(fieldByPath('method'), body);
      if (problem) out.errors.push(`method: ${problem.reason}`);
      else out.update.method = body;
      continue;
    }
    if (!UPDATE_SECTIONS.includes(section) && section !== 'camera') {
      out.errors.push(`${section}: not a preset section`);
      continue;
    }
    if (!body || typeof body !== 'object' || Array.isArray(body)) {
      out.errors.push(`${section}: expected an object`);
      continue;
    }
    for (const [key, value] of Object.entries(body)) {
      const path = `${section}.${key}`;
      const f = fieldByPath(path);
      if (!f || (section === 'camera' && !CAMERA_KEYS.includes(key))) {
        out.errors.push(`${path}: unknown field`);
        continue;
      }
      const problem = checkField(f, value);
      if (problem) {
        out.errors.push(`${path}: ${problem.reason}`);
        continue;
      }
      if (section === 'camera') (out.camera ??= {})[key] = Array.isArray(value) ? [...value] : value;
      else setPath(out.update, path, Array.isArray(value) ? [...value] : value);
    }
  }
  return out;
}

/** The dotted paths a partial update sets ("params.q", "method"). */
export function updatePaths(update) {
  const paths = [];
  for (const [k, v] of Object.entries(update ?? {})) {
    if (v && typeof v === 'object' && !Array.isArray(v)) for (const k2 of Object.keys(v)) paths.push(`${k}.${k2}`);
    else paths.push(k);
  }
  return paths;
}

/**
 * Applies a preset under the link's own values: returns {update, camera,
 * applied, cameraApplied, errors}. update = preset fields overridden by
 * linkUpdate; applied lists the preset paths that took effect; camera is the
 * preset's partial camera unless the link has a camera (then null).
 */
export function applyPreset(preset, linkUpdate = {}, linkCamera = null) {
  const p = readPreset(preset);
  const linkPaths = new Set(updatePaths(linkUpdate));
  const applied = updatePaths(p.update).filter((path) => !linkPaths.has(path));
  const cameraApplied = !!p.camera && !linkCamera;
  return {
    update: merge(p.update, linkUpdate),
    camera: cameraApplied ? p.camera : null,
    applied,
    cameraApplied,
    errors: p.errors,
  };
}

const same = (a, b) => JSON.stringify(a) === JSON.stringify(b);

/** update without the preset's paths that still hold the preset's value (the user's later edits stay). */
export function removePreset(update, preset, applied) {
  const p = readPreset(preset);
  const out = merge({}, update);
  for (const path of applied) {
    const want = getPath(p.update, path);
    if (!same(getPath(out, path), want)) continue;
    const [section, key] = path.split('.');
    if (key === undefined) delete out[section];
    else {
      delete out[section][key];
      if (!Object.keys(out[section]).length) delete out[section];
    }
  }
  return out;
}
