// The render request's fields (protocol/README.md; mirrors the table in
// protocol/request_fields.h): where each lives in the JSON, its flat alias (the key of
// GET /api/v1/render query parameters, reused for the page's URL hash), its type
// and its range. Client-side checks use it to refuse what the server would
// refuse, with the same field names in the messages.

// Types: int, num, bool, str, enum, vec3, range (two numbers), color (three in [0,1]).
// methods / primitives: where a field applies (protocol/request_scope.c); absent = everywhere.
// The server refuses a field with a value other than its default elsewhere.
// when: [path, value]: the field applies only while that field has that value
// (the direct method's opacity parameters, render/gl/frame_check.c refuses them otherwise).
const DATASET_METHODS = Object.freeze(['fourier', 'exact', 'opaque', 'direct', 'wboit', 'weighted-average', 'binning', 'kanzler']);
export const FIELDS = Object.freeze([
  { section: null, name: 'dataset', alias: 'dataset', type: 'str', maxLength: 511 },
  {
    section: null, name: 'method', alias: 'method', type: 'enum',
    values: ['fourier', 'exact', 'opaque', 'direct', 'wboit', 'surface-layers', 'weighted-average', 'binning', 'kanzler'],
  },

  { section: 'camera', name: 'position', alias: 'position', type: 'vec3' },
  { section: 'camera', name: 'focalPoint', alias: 'focalPoint', type: 'vec3' },
  { section: 'camera', name: 'viewUp', alias: 'viewUp', type: 'vec3' },
  { section: 'camera', name: 'viewAngle', alias: 'viewAngle', type: 'num', min: 0, max: 180, loOpen: true, hiOpen: true },
  { section: 'camera', name: 'parallelProjection', alias: 'parallelProjection', type: 'bool' },
  { section: 'camera', name: 'parallelScale', alias: 'parallelScale', type: 'num', min: 0, loOpen: true },

  { section: 'params', name: 'q', alias: 'q', type: 'num', min: 0, max: 1e6, methods: ['fourier', 'exact', 'wboit', 'weighted-average', 'binning'] },
  { section: 'params', name: 'r', alias: 'r', type: 'num', min: 0, max: 1e6, methods: ['fourier', 'exact', 'wboit', 'weighted-average', 'binning'] },
  { section: 'params', name: 'lambda', alias: 'lambda', type: 'num', min: 0, max: 1000, methods: ['fourier', 'exact', 'wboit', 'weighted-average', 'binning'] },
  { section: 'params', name: 'bands', alias: 'bands', type: 'int', min: 1, max: 8, methods: ['fourier', 'direct', 'wboit', 'weighted-average', 'binning', 'kanzler'] },
  { section: 'params', name: 'smoothing', alias: 'smoothing', type: 'int', min: 0, max: 1000, methods: ['fourier', 'exact', 'wboit', 'weighted-average', 'binning'] },
  { section: 'params', name: 'smoothingWeight', alias: 'smoothingWeight', type: 'num', min: 0, max: 1, methods: ['fourier', 'exact', 'wboit', 'weighted-average', 'binning'] },
  { section: 'params', name: 'fadeHalfLife', alias: 'fadeHalfLife', type: 'num', min: 0, max: 60, methods: ['fourier', 'exact', 'wboit', 'weighted-average', 'binning'] },
  { section: 'params', name: 'resolutionScale', alias: 'resolutionScale', type: 'num', min: 0, max: 1, loOpen: true, methods: ['fourier', 'wboit', 'weighted-average', 'binning'] },
  { section: 'params', name: 'subset', alias: 'subset', type: 'int', min: 1, max: 1024, methods: ['fourier', 'direct', 'wboit', 'weighted-average', 'binning'] },
  { section: 'params', name: 'depthMargin', alias: 'depthMargin', type: 'num', min: 0, max: 0.25, methods: ['fourier', 'direct', 'wboit', 'weighted-average', 'binning', 'kanzler'] },
  { section: 'params', name: 'estimator', alias: 'estimator', type: 'enum', values: ['foo', 'midpoint'], methods: ['fourier', 'wboit', 'weighted-average', 'binning'] },
  { section: 'params', name: 'depthRange', alias: 'depthRange', type: 'enum', values: ['auto', 'global', 'pixel', 'moments'], methods: ['fourier', 'direct', 'wboit', 'weighted-average', 'binning', 'kanzler'] },
  { section: 'params', name: 'normalize', alias: 'normalize', type: 'enum', values: ['auto', 'off'], methods: DATASET_METHODS },
  { section: 'params', name: 'lod', alias: 'lod', type: 'num', min: 0, max: 16, methods: DATASET_METHODS, primitives: ['lines', 'surfaces'] },
  { section: 'params', name: 'directExponent', alias: 'directExponent', type: 'num', min: 0, max: 100, loOpen: true, methods: ['direct', 'kanzler'], when: ['params.alphaSource', 'importance'] },
  { section: 'params', name: 'alphaSource', alias: 'alphaSource', type: 'enum', values: ['importance', 'constant', 'angle', 'normalVariation'], methods: ['direct'] },
  { section: 'params', name: 'alphaConstant', alias: 'alphaConstant', type: 'num', min: 0, max: 1, methods: ['direct'], when: ['params.alphaSource', 'constant'] },
  { section: 'params', name: 'gamma', alias: 'gamma', type: 'num', min: 0, max: 100, loOpen: true, methods: ['direct'], when: ['params.alphaSource', 'normalVariation'] },
  { section: 'params', name: 'kanzlerImportance', alias: 'kanzlerImportance', type: 'num', min: 0, max: 1000, methods: ['kanzler'], primitives: ['points', 'lines'] },
  { section: 'params', name: 'kanzlerCoverage', alias: 'kanzlerCoverage', type: 'num', min: 0, max: 1000, methods: ['kanzler'], primitives: ['points', 'lines'] },
  { section: 'params', name: 'kanzlerVariance', alias: 'kanzlerVariance', type: 'num', min: 0, max: 1000, methods: ['kanzler'], primitives: ['lines'] },
  { section: 'params', name: 'kanzlerDepth', alias: 'kanzlerDepth', type: 'num', min: 0, max: 1000, methods: ['kanzler'], primitives: ['points', 'lines'] },
  { section: 'params', name: 'kanzlerLambda', alias: 'kanzlerLambda', type: 'num', min: 0, max: 1000, methods: ['kanzler'], primitives: ['points', 'lines'] },
  { section: 'params', name: 'targetOpacity', alias: 'targetOpacity', type: 'num', min: 0, max: 1, loOpen: true, methods: DATASET_METHODS },
  { section: 'params', name: 'smoothingWeights', alias: 'smoothingWeights', type: 'enum', values: ['uniform', 'distance'], methods: ['fourier', 'exact', 'wboit', 'weighted-average', 'binning'] },
  { section: 'params', name: 'guardBand', alias: 'guardBand', type: 'num', min: 0, max: 1, methods: ['fourier', 'wboit', 'weighted-average', 'binning'] },
  { section: 'params', name: 'clarity', alias: 'clarity', type: 'num', min: 0, max: 1, methods: ['fourier', 'exact', 'wboit', 'weighted-average', 'binning'] },
  { section: 'params', name: 'autoSubset', alias: 'autoSubset', type: 'int', min: 1, max: 64, methods: ['fourier', 'wboit', 'weighted-average', 'binning'] },
  { section: 'params', name: 'excludeSelf', alias: 'excludeSelf', type: 'bool', methods: ['exact'] },

  { section: 'importance', name: 'attribute', alias: 'importance', type: 'str', maxLength: 63, methods: DATASET_METHODS },
  { section: 'importance', name: 'range', alias: 'importanceRange', type: 'range', methods: DATASET_METHODS },
  { section: 'importance', name: 'exponent', alias: 'importanceExponent', type: 'num', min: 0, max: 1000, loOpen: true, methods: DATASET_METHODS },
  { section: 'importance', name: 'terms', alias: 'importanceTerms', type: 'terms', maxItems: 4, methods: DATASET_METHODS },
  { section: 'importance', name: 'curve', alias: 'importanceCurve', type: 'curve', maxItems: 64, methods: DATASET_METHODS },
  { section: 'importance', name: 'invert', alias: 'importanceInvert', type: 'bool', methods: DATASET_METHODS },

  { section: 'color', name: 'attribute', alias: 'color', type: 'str', maxLength: 63, methods: DATASET_METHODS },
  {
    section: 'color', name: 'colormap', alias: 'colormap', type: 'enum',
    values: ['viridis', 'coolwarm', 'grayscale', 'inferno', 'plasma', 'turbo'], methods: DATASET_METHODS,
  },
  { section: 'color', name: 'range', alias: 'colorRange', type: 'range', methods: DATASET_METHODS },
  { section: 'color', name: 'curve', alias: 'colorCurve', type: 'curve', maxItems: 64, methods: DATASET_METHODS },
  { section: 'color', name: 'equalize', alias: 'equalize', type: 'bool', methods: ['fourier', 'exact', 'direct'] },
  { section: 'color', name: 'fixed', alias: 'colorFixed', type: 'ranges', maxItems: 4, methods: ['fourier', 'exact', 'direct'] },
  { section: 'color', name: 'fadeHalfLife', alias: 'colorFadeHalfLife', type: 'num', min: 0, max: 60, methods: ['fourier', 'exact', 'direct'] },

  { section: 'style', name: 'background', alias: 'background', type: 'color' },
  { section: 'style', name: 'lineWidth', alias: 'lineWidth', type: 'num', min: 0, max: 1e9, methods: DATASET_METHODS, primitives: ['lines'] },
  { section: 'style', name: 'minLinePixels', alias: 'minLinePixels', type: 'num', min: 0, max: 64, methods: DATASET_METHODS, primitives: ['lines'] },
  { section: 'style', name: 'pointSize', alias: 'pointSize', type: 'num', min: 0, max: 256, loOpen: true, methods: DATASET_METHODS, primitives: ['points'] },
  { section: 'style', name: 'shading', alias: 'shading', type: 'enum', values: ['phong', 'none'], methods: DATASET_METHODS },
  { section: 'style', name: 'silhouetteExponent', alias: 'silhouetteExponent', type: 'num', min: 1, max: 100, methods: DATASET_METHODS, primitives: ['surfaces'] },
  { section: 'style', name: 'haloWidth', alias: 'haloWidth', type: 'num', min: 0, max: 64, methods: DATASET_METHODS, primitives: ['lines'] },
  { section: 'style', name: 'haloDepth', alias: 'haloDepth', type: 'num', min: 0, max: 1, methods: DATASET_METHODS, primitives: ['lines'] },
  { section: 'style', name: 'haloStrength', alias: 'haloStrength', type: 'num', min: 0, max: 1, methods: DATASET_METHODS, primitives: ['lines'] },
  { section: 'style', name: 'antialias', alias: 'antialias', type: 'int', min: 1, max: 16, methods: ['fourier', 'direct', 'wboit', 'weighted-average', 'binning', 'kanzler'] },
  { section: 'style', name: 'shadow', alias: 'shadow', type: 'num', min: 0, max: 1, methods: ['fourier', 'direct'] },
  { section: 'style', name: 'shadowLight', alias: 'shadowLight', type: 'vec3', methods: ['fourier', 'direct'] },
  { section: 'style', name: 'shadowColored', alias: 'shadowColored', type: 'bool', methods: ['fourier', 'direct'] },
  { section: 'style', name: 'ground', alias: 'ground', type: 'enum', values: ['auto', 'on', 'off'], methods: ['fourier', 'direct'] },
  { section: 'style', name: 'groundColor', alias: 'groundColor', type: 'color', methods: ['fourier', 'direct'] },
  { section: 'style', name: 'groundOffset', alias: 'groundOffset', type: 'num', min: 0, max: 1, methods: ['fourier', 'direct'] },
  { section: 'style', name: 'smartTransparency', alias: 'smartTransparency', type: 'num', min: 0, max: 1, methods: ['fourier', 'direct'] },
  { section: 'style', name: 'smartIterations', alias: 'smartIterations', type: 'int', min: 0, max: 32, methods: ['fourier', 'direct'] },

  { section: null, name: 'filter', alias: 'filter', type: 'filters', maxItems: 8, methods: DATASET_METHODS, primitives: ['points', 'lines'] },

  { section: 'lines', name: 'clusters', alias: 'clusters', type: 'int', min: 0, max: 1000000, methods: DATASET_METHODS, primitives: ['lines'] },
  {
    section: 'lines', name: 'representative', alias: 'representative', type: 'enum',
    values: ['important', 'mean', 'leastDistance'], methods: DATASET_METHODS, primitives: ['lines'],
  },
  { section: 'lines', name: 'linkage', alias: 'linkage', type: 'enum', values: ['complete', 'single', 'average'], methods: DATASET_METHODS, primitives: ['lines'] },
  { section: 'lines', name: 'liftImportance', alias: 'liftImportance', type: 'num', min: 0, max: 1000, methods: DATASET_METHODS, primitives: ['lines'] },
  { section: 'lines', name: 'liftColor', alias: 'liftColor', type: 'num', min: 0, max: 1000, methods: DATASET_METHODS, primitives: ['lines'] },

  { section: 'time', name: 'window', alias: 'timeWindow', type: 'range', methods: DATASET_METHODS, primitives: ['points', 'lines'] },
  { section: 'time', name: 'attribute', alias: 'timeAttribute', type: 'str', maxLength: 63, methods: DATASET_METHODS, primitives: ['points', 'lines'] },
  { section: 'time', name: 'markers', alias: 'timeMarkers', type: 'bool', methods: DATASET_METHODS, primitives: ['lines'] },

  // surface: method "surface-layers" (a vector field's integral surface)
  { section: 'surface', name: 'field', alias: 'surfaceField', type: 'str', maxLength: 127, methods: ['surface-layers'] },
  { section: 'surface', name: 'seed', alias: 'surfaceSeed', type: 'seed', maxItems: 64, methods: ['surface-layers'] },
  { section: 'surface', name: 'particles', alias: 'surfaceParticles', type: 'int', min: 1, max: 100000, methods: ['surface-layers'] },
  { section: 'surface', name: 'step', alias: 'surfaceStep', type: 'num', min: 0, methods: ['surface-layers'] },
  { section: 'surface', name: 'length', alias: 'surfaceLength', type: 'num', min: 0, methods: ['surface-layers'] },
  {
    section: 'surface', name: 'direction', alias: 'surfaceDirection', type: 'enum',
    values: ['forward', 'backward', 'both'], methods: ['surface-layers'],
  },
  { section: 'surface', name: 'epsilon', alias: 'surfaceEpsilon', type: 'num', min: 0, max: 1, methods: ['surface-layers'] },
  { section: 'surface', name: 'opacity', alias: 'surfaceOpacity', type: 'num', min: 0, max: 1, loOpen: true, methods: ['surface-layers'] },
  { section: 'surface', name: 'maxLayers', alias: 'surfaceMaxLayers', type: 'int', min: 1, max: 64, methods: ['surface-layers'] },
  {
    section: 'surface', name: 'composite', alias: 'surfaceComposite', type: 'enum',
    values: ['layers', 'weighted-average', 'weighted-sum'], methods: ['surface-layers'],
  },
  { section: 'surface', name: 'color', alias: 'surfaceColor', type: 'color', methods: ['surface-layers'] },
  { section: 'surface', name: 'curvesPerFrame', alias: 'surfaceCurvesPerFrame', type: 'int', min: 1, max: 100000, methods: ['surface-layers'] },

  // streamlines: a dataset that names a vector field, traced as a streamline set
  {
    section: 'streamlines', name: 'seeding', alias: 'streamlinesSeeding', type: 'enum',
    values: ['points', 'rake', 'box', 'density'], methods: DATASET_METHODS, primitives: ['lines'],
  },
  { section: 'streamlines', name: 'seeds', alias: 'streamlinesSeeds', type: 'seed', minItems: 1, maxItems: 64, methods: DATASET_METHODS, primitives: ['lines'] },
  { section: 'streamlines', name: 'count', alias: 'streamlinesCount', type: 'int', min: 1, max: 100000, methods: DATASET_METHODS, primitives: ['lines'] },
  { section: 'streamlines', name: 'step', alias: 'streamlinesStep', type: 'num', min: 0, methods: DATASET_METHODS, primitives: ['lines'] },
  { section: 'streamlines', name: 'length', alias: 'streamlinesLength', type: 'num', min: 0, methods: DATASET_METHODS, primitives: ['lines'] },
  {
    section: 'streamlines', name: 'direction', alias: 'streamlinesDirection', type: 'enum',
    values: ['forward', 'backward', 'both'], methods: DATASET_METHODS, primitives: ['lines'],
  },
  {
    section: 'streamlines', name: 'separation', alias: 'streamlinesSeparation', type: 'num', min: 0,
    methods: DATASET_METHODS, primitives: ['lines'], when: ['streamlines.seeding', 'density'],
  },
]);

// Top-level fields of a whole render request (POST /api/v1/render) besides
// dataset and method; sizes follow the server's limits (16..8192 by default).
export const REQUEST_TOP_FIELDS = Object.freeze([
  { section: null, name: 'version', alias: 'version', type: 'int', min: 1, max: 1 },
  { section: null, name: 'width', alias: 'width', type: 'int', min: 16, max: 8192, sizeLimit: true },
  { section: null, name: 'height', alias: 'height', type: 'int', min: 16, max: 8192, sizeLimit: true },
  { section: null, name: 'format', alias: 'format', type: 'enum', values: ['png', 'jpeg', 'jpg'] },
  { section: null, name: 'quality', alias: 'quality', type: 'int', min: 1, max: 100 },
  { section: null, name: 'dt', alias: 'dt', type: 'num', min: 0, max: 3600 },
  { section: null, name: 'layers', alias: 'layers', type: 'layers', maxItems: 8, keys: ['dataset', 'role', 'visible', 'importance', 'color', 'style', 'filter', 'time', 'lines'] },
]);

// Stream settings of the WebSocket session (hello/params top level), not part of a render request.
export const STREAM_FIELDS = Object.freeze([
  { section: null, name: 'quality', alias: 'quality', type: 'int', min: 1, max: 100 },
  { section: null, name: 'interactiveQuality', alias: 'interactiveQuality', type: 'int', min: 1, max: 100 },
  { section: null, name: 'interactiveScale', alias: 'interactiveScale', type: 'num', min: 0.25, max: 1 },
]);

/** The sections a params message may carry besides the stream settings. */
export const UPDATE_SECTIONS = Object.freeze(['params', 'importance', 'color', 'style', 'lines', 'time']);

export const fieldPath = (f) => (f.section ? `${f.section}.${f.name}` : f.name);

const byPath = new Map([...FIELDS, ...STREAM_FIELDS].map((f) => [fieldPath(f), f]));
const byAlias = new Map([...FIELDS, ...STREAM_FIELDS].map((f) => [f.alias, f]));

/** The field at a dotted path ("params.q", "quality"), or undefined. */
export const fieldByPath = (path) => byPath.get(path);
/** The field with a flat alias ("q", "importanceRange"), or undefined. */
export const fieldByAlias = (alias) => byAlias.get(alias);

const isNum = (v) => typeof v === 'number' && Number.isFinite(v);
const g15 = (x) => String(Number(x.toPrecision(15)));
const utf8Length = (s) => new TextEncoder().encode(s).length;

/**
 * Checks one value against its field as protocol/request.c does. Returns null
 * when valid, else {code, reason} with the C code's error code ("bad_field",
 * "out_of_range") and reason text ("expected an integer", "9 is outside [1, 8]").
 */
export function checkField(f, v) {
  const bad = (reason) => ({ code: 'bad_field', reason });
  const range = (reason) => ({ code: 'out_of_range', reason });
  switch (f.type) {
    case 'int':
    case 'num': {
      if (!isNum(v) || (f.type === 'int' && !Number.isInteger(v)))
        return bad(f.type === 'int' ? 'expected an integer' : 'expected a number');
      const lo = f.min ?? -Infinity, hi = f.max ?? Infinity;
      const loBad = f.loOpen ? !(v > lo) : !(v >= lo);
      const hiBad = f.hiOpen ? !(v < hi) : !(v <= hi);
      if (loBad || hiBad) {
        if (hi === Infinity) return range(`${g15(v)} is not ${f.loOpen ? '>' : '>='} ${g15(lo)}`);
        return range(`${g15(v)} is outside ${f.loOpen ? '(' : '['}${g15(lo)}, ${g15(hi)}${f.hiOpen ? ')' : ']'}`);
      }
      return null;
    }
    case 'bool':
      return typeof v === 'boolean' ? null : bad('expected true or false');
    case 'str':
      if (typeof v !== 'string') return bad('expected a string');
      return f.maxLength !== undefined && utf8Length(v) > f.maxLength ? range(`longer than ${f.maxLength} bytes`) : null;
    case 'enum':
      return typeof v === 'string' && f.values.includes(v) ? null : bad(`expected one of ${f.values.map((x) => `"${x}"`).join(', ')}`);
    case 'vec3':
    case 'color':
      if (!(Array.isArray(v) && v.length === 3 && v.every(isNum))) return bad('expected an array of 3 numbers');
      if (f.type === 'color' && !v.every((x) => x >= 0 && x <= 1)) return range('components must be in [0, 1]');
      return null;
    case 'range':
      return Array.isArray(v) && v.length === 2 && v.every(isNum) ? null : bad('expected an array of 2 numbers');
    case 'curve':
    case 'ranges':
    case 'terms':
    case 'filters':
      return checkList(f, v);
    case 'layers':
      return checkLayers(f, v);
    case 'seed':
      return checkSeed(f, v);
    default:
      return bad('unknown type');
  }
}

/** surface.seed, streamlines.seeds (protocol/request_lists.c lc_proto_parse_seed): minItems (default 2)..maxItems
 * finite [x, y, z], no repeats in a row. */
function checkSeed(f, v) {
  const min = f.minItems ?? 2;
  if (!Array.isArray(v)) return { code: 'bad_field', reason: 'expected an array of [x, y, z] points' };
  if (v.length < min || v.length > f.maxItems) return { code: 'out_of_range', reason: `${min} to ${f.maxItems} points (got ${v.length})` };
  for (let i = 0; i < v.length; i++) {
    const p = v[i], at = `[${i}]`;
    if (!(Array.isArray(p) && p.length === 3 && p.every(isNum)))
      return { code: 'bad_field', reason: 'expected an array of 3 finite numbers', at };
    if (i > 0 && p.every((x, k) => x === v[i - 1][k]))
      return { code: 'bad_field', reason: 'repeats the point before it (a segment of length 0)', at };
  }
  return null;
}

const isObject = (v) => v !== null && typeof v === 'object' && !Array.isArray(v);
const isPair = (v) => Array.isArray(v) && v.length === 2 && v.every(isNum);
const OVERS = ['vertex', 'min', 'max', 'mean', 'first', 'last', 'change'];

/** One element of terms or filters, key by key as protocol/request_lists.c checks it. */
function checkElement(kind, o, at) {
  const err = (code, where, reason) => ({ code, reason, at: where });
  if (!isObject(o)) return err('bad_field', at, 'expected an object');
  let attribute = false, bounds = 0, weight = 1;
  for (const [k, v] of Object.entries(o)) {
    const here = `${at}.${k}`;
    if (k === 'attribute') {
      if (typeof v !== 'string') return err('bad_field', here, 'expected a string');
      if (!v.length) return err('bad_field', here, 'must name an attribute');
      if (utf8Length(v) > 63) return err('out_of_range', here, 'longer than 63 bytes');
      attribute = true;
    } else if (k === 'range') {
      if (!isPair(v)) return err('bad_field', here, 'expected an array of 2 numbers');
      if (kind === 'filters' && v[0] > v[1]) return err('bad_field', here, `range [${g15(v[0])}, ${g15(v[1])}] is empty`);
      bounds |= 4;
    } else if (kind === 'terms' && k === 'weight') {
      if (!isNum(v)) return err('bad_field', here, 'expected a number');
      if (v < -1 || v > 1) return err('out_of_range', here, 'must be in [-1, 1]');
      weight = v;
    } else if (kind === 'terms' && k === 'invert') {
      if (typeof v !== 'boolean') return err('bad_field', here, 'expected true or false');
    } else if (kind === 'filters' && k === 'over') {
      if (!OVERS.includes(v)) return err('bad_field', here, `expected one of ${OVERS.join(', ')}`);
    } else if (kind === 'filters' && (k === 'gt' || k === 'lt')) {
      if (!isNum(v)) return err('bad_field', here, 'expected a number');
      bounds |= k === 'gt' ? 1 : 2;
    } else return err('unknown_field', here, 'unknown field');
  }
  if (!attribute) return err('missing_field', `${at}.attribute`, `every ${kind === 'terms' ? 'term' : 'filter'} names an attribute`);
  if (kind === 'filters' && (!bounds || ((bounds & 4) && (bounds & 3)))) return err('bad_field', at, 'give "gt" and/or "lt", or "range"');
  return { weight };
}

/** terms, filters and curves (protocol/request_lists.c); a problem's "at" extends the field's path ("[1].weight"). */
function checkList(f, v) {
  const what = { terms: 'an array of terms', filters: 'an array of filters', curve: 'an array of [x, y] points',
    ranges: 'an array of [lo, hi] ranges' }[f.type];
  if (!Array.isArray(v)) return { code: 'bad_field', reason: `expected ${what}` };
  if (f.type === 'ranges') {
    if (v.length > f.maxItems) return { code: 'out_of_range', reason: `at most ${f.maxItems} ranges` };
    for (let i = 0; i < v.length; i++) {
      const at = `[${i}]`;
      if (!isPair(v[i])) return { code: 'bad_field', reason: 'expected an array of 2 numbers', at };
      if (!(v[i][0] <= v[i][1])) return { code: 'bad_field', reason: 'lo must not exceed hi', at };
    }
    return null;
  }
  if (f.type === 'curve') {
    if (v.length === 1 || v.length > f.maxItems) return { code: 'out_of_range', reason: `2 to ${f.maxItems} points (none: the identity)` };
    for (let i = 0; i < v.length; i++) {
      const at = `[${i}]`;
      if (!isPair(v[i])) return { code: 'bad_field', reason: 'expected an array of 2 numbers', at };
      if (!v[i].every((x) => x >= 0 && x <= 1)) return { code: 'out_of_range', reason: 'x and y must lie in [0, 1]', at };
      if (i > 0 && !(v[i][0] >= v[i - 1][0])) return { code: 'bad_field', reason: 'x must not decrease', at };
    }
    return null;
  }
  if (v.length > f.maxItems) return { code: 'out_of_range', reason: `at most ${f.maxItems} ${f.type}` };
  let sumAbs = 0;
  for (let i = 0; i < v.length; i++) {
    const r = checkElement(f.type, v[i], `[${i}]`);
    if (r.code) return r;
    sumAbs += Math.abs(r.weight);
  }
  if (f.type === 'terms' && v.length && !(sumAbs > 0)) return { code: 'bad_field', reason: 'at least one weight must be non-zero' };
  return null;
}

/** layers[] (protocol/request_layers.c): the shape only; each layer's importance, colour, style, filter and time
 * keys are the server's to check against the layer's dataset. */
function checkLayers(f, v) {
  if (!Array.isArray(v)) return { code: 'bad_field', reason: 'expected an array of layers' };
  if (v.length > f.maxItems) return { code: 'out_of_range', reason: `at most ${f.maxItems} layers` };
  const keys = f.keys;
  for (let i = 0; i < v.length; i++) {
    const at = `[${i}]`, l = v[i];
    if (!isObject(l)) return { code: 'bad_field', reason: 'expected an object with a dataset', at };
    for (const k of Object.keys(l)) if (!keys.includes(k)) return { code: 'unknown_field', reason: 'unknown field', at: `${at}.${k}` };
    if (typeof l.dataset !== 'string' || !l.dataset.length) return { code: 'missing_field', reason: 'every layer names its dataset', at: `${at}.dataset` };
    if (l.role !== undefined && l.role !== 'transparent' && l.role !== 'context') return { code: 'bad_field', reason: 'expected "transparent" or "context"', at: `${at}.role` };
    if (l.visible !== undefined && typeof l.visible !== 'boolean') return { code: 'bad_field', reason: 'expected true or false', at: `${at}.visible` };
  }
  return null;
}

/** Like checkField but only the reason text (null when valid), for the panel and the URL. */
export function checkValue(f, v) {
  return checkField(f, v)?.reason ?? null;
}

/** Text of a value for a URL (vectors comma-separated, terms and filters as JSON), as GET /api/v1/render reads it. */
export function valueToText(f, v) {
  if (['terms', 'filters', 'curve', 'ranges', 'layers', 'seed'].includes(f.type)) return JSON.stringify(v); // JSON text, as request.c reads lists
  if (Array.isArray(v)) return v.map((x) => String(x)).join(',');
  return String(v);
}

/** Parses URL text back into a value for the field; returns undefined if malformed. */
export function valueFromText(f, text) {
  const num = (s) => (/^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/.test(s) ? Number(s) : NaN);
  switch (f.type) {
    case 'int':
    case 'num': {
      const n = num(text);
      return Number.isFinite(n) ? n : undefined;
    }
    case 'bool':
      if (text === 'true' || text === '1') return true;
      if (text === 'false' || text === '0') return false;
      return undefined;
    case 'str':
    case 'enum':
      return text;
    case 'vec3':
    case 'range':
    case 'color': {
      const parts = text.split(',').map(num);
      return parts.every(Number.isFinite) ? parts : undefined;
    }
    case 'terms':
    case 'filters':
    case 'curve':
    case 'ranges':
    case 'layers':
    case 'seed':
      try {
        const v = JSON.parse(text);
        return Array.isArray(v) ? v : undefined;
      } catch {
        return undefined;
      }
    default:
      return undefined;
  }
}

/** Reads a dotted path from a nested object. */
export function getPath(obj, path) {
  let o = obj;
  for (const k of path.split('.')) {
    if (o == null || typeof o !== 'object') return undefined;
    o = o[k];
  }
  return o;
}

/** Writes a dotted path into a nested object, creating sections. Returns obj. */
export function setPath(obj, path, value) {
  const keys = path.split('.');
  let o = obj;
  for (const k of keys.slice(0, -1)) {
    if (o[k] == null || typeof o[k] !== 'object') o[k] = {};
    o = o[k];
  }
  o[keys[keys.length - 1]] = value;
  return obj;
}

/** Deep merge of plain objects (arrays and scalars replace). Returns a new object. */
export function merge(base, update) {
  const out = { ...(base ?? {}) };
  for (const [k, v] of Object.entries(update ?? {})) {
    if (v && typeof v === 'object' && !Array.isArray(v) && out[k] && typeof out[k] === 'object' && !Array.isArray(out[k]))
      out[k] = merge(out[k], v);
    else out[k] = Array.isArray(v) ? [...v] : v && typeof v === 'object' ? merge({}, v) : v;
  }
  return out;
}

// The default of each field a `when` names (the server's).
const WHEN_DEFAULTS = Object.freeze({ 'params.alphaSource': 'importance' });
const scopeByPath = new Map([...FIELDS, ...REQUEST_TOP_FIELDS].map((f) => [fieldPath(f), f]));
const PRIMITIVE_NAMES = { points: 'points', lines: 'lines', triangles: 'surfaces', surfaces: 'surfaces' };

/** Whether field f applies under method (default fourier) to data of kind prim ('points', 'lines',
 *  'triangles'; null = not known, as with layers of several kinds). */
export function applies(f, method, prim) {
  if (f.methods && !f.methods.includes(method ?? 'fourier')) return false;
  return !(f.primitives && prim && !f.primitives.includes(PRIMITIVE_NAMES[prim] ?? prim));
}

/** update without the fields that do not apply under its method to data of kind prim: what the page
 *  sends, while its own state keeps the rest for when they apply again (the server refuses a field
 *  given where it does not apply). */
export function applicableUpdate(update, prim) {
  const method = update?.method ?? 'fourier';
  const holds = (f) => {
    if (!f?.when) return true; // when: [path, value], as the schema's
    const [section, name] = f.when[0].split('.');
    return (update?.[section]?.[name] ?? WHEN_DEFAULTS[f.when[0]]) === f.when[1];
  };
  const out = {};
  for (const [k, v] of Object.entries(update ?? {})) {
    const top = scopeByPath.get(k);
    if (top) {
      if (applies(top, method, prim)) out[k] = v;
    } else if (v && typeof v === 'object' && !Array.isArray(v) && k !== 'camera') {
      const kept = Object.fromEntries(Object.entries(v).filter(([n]) => {
        const f = scopeByPath.get(`${k}.${n}`);
        return !f || (applies(f, method, prim) && holds(f));
      }));
      if (Object.keys(kept).length) out[k] = kept;
    } else {
      out[k] = v;
    }
  }
  return out;
}
