// The settings panel: builds labelled, keyboard-accessible controls from a
// declarative list, shows each value as a number, and reports changes by the
// request path they edit ("params.q", "style.background", "quality"). It holds
// no state of its own beyond the DOM: the page state (app-state.js) owns the values.

import { fieldByPath, checkField } from './schema.js';
import { flatBounds } from './camera.js';
import { termsEditor, filtersEditor, curveEditor, rangesEditor } from './criteria.js';

const EDITORS = { terms: termsEditor, filters: filtersEditor, curve: curveEditor, ranges: rangesEditor };

const METHOD_LABELS = {
  fourier: 'Fourier (FOO)',
  exact: 'Exact (linked lists)',
  opaque: 'Opaque',
  direct: 'Direct (α = gᵏ)',
  wboit: 'Weighted blended OIT',
  'weighted-average': 'Weighted average OIT',
  binning: 'Binning (τ in 11 bins)',
  kanzler: 'Kanzler (occlusion penalty)',
};

/**
 * The groups and controls. kind: range (slider + number box), select, check,
 * color, range2 (two number boxes for [min, max]). min/max/step are the slider's;
 * the number box accepts the whole schema range. dynamic: options or bounds that
 * depend on the dataset (filled by Panel.setDataset).
 */
export const GROUPS = [
  {
    id: 'optimization',
    legend: 'Optimization',
    controls: [
      {
        path: 'method',
        label: 'Method',
        kind: 'select',
        options: Object.entries(METHOD_LABELS),
        help: 'How transparency is computed. Fourier: the fast optimization (default). Exact: the slow reference. Opaque: no transparency. Direct: opacity from importance alone. WBOIT, weighted average, binning: cheaper ways to blend the optimized opacities, for comparison (they lose more of the depth order). Kanzler: opacity from importance, lowered where a part hides a more important one, covers many layers or crosses other directions (lines and points).',
      },
      {
        path: 'params.q',
        label: 'q (importance behind)',
        kind: 'range',
        min: 0,
        max: 1000,
        step: 1,
        help: "How strongly a part fades where importance lies behind it. Higher: what hides important parts fades more, but on dense data the important parts fade too (they hide each other: q 300 on a dense trajectory file, the most important tenth 5% opaque). By default Clarity sets the strength for you; setting q, r or λ here, even to the value shown, turns Clarity off and uses these values: on dense data the picture falls back to the paper's strength (the same file: its most important tenth 8% opaque instead of 52%).",
      },
      {
        path: 'params.r',
        label: 'r (importance in front)',
        kind: 'range',
        min: 0,
        max: 2000,
        step: 1,
        help: 'How strongly a part fades where importance lies in front of it. Higher: less clutter behind what matters. Setting it turns Clarity off (see Clarity).',
      },
      {
        path: 'params.lambda',
        label: 'λ (emphasis)',
        kind: 'range',
        min: 0,
        max: 20,
        step: 0.1,
        help: 'How much important parts are protected from fading: their penalty is scaled by (1 − importance)^(2λ). Higher: the important parts stay more opaque, and the rest grows more opaque too, less so (a dense trajectory file at λ 4: the most important tenth 65% opaque, the least important half 27%; at λ 1: 8% and 2%). Clarity raises it for you; setting it turns Clarity off.',
      },
      {
        path: 'params.bands',
        label: 'Bands m',
        kind: 'range',
        min: 1,
        max: 8,
        step: 1,
        help: 'Accuracy of the depth approximation, 1 to 8. More bands: closer to the exact result, but slower.',
      },
      {
        path: 'params.smoothing',
        label: 'Smoothing iterations',
        kind: 'range',
        min: 0,
        max: 100,
        step: 1,
        help: 'How often opacities are averaged with their neighbours along a line or surface, so that neighbours fade together. 0: no smoothing.',
      },
      {
        path: 'params.smoothingWeight',
        label: 'Smoothing weight ω',
        kind: 'range',
        min: 0,
        max: 1,
        step: 0.01,
        help: 'How far each averaging step pulls a part toward its neighbours (0 to 1).',
      },
      {
        path: 'params.fadeHalfLife',
        label: 'Fade half-life (s)',
        kind: 'range',
        min: 0,
        max: 2,
        step: 0.01,
        help: 'How quickly opacities follow a change of view, in seconds. 0: they jump at once.',
      },
      {
        path: 'params.estimator',
        label: 'Estimator',
        kind: 'select',
        options: [
          ['midpoint', 'Midpoint'],
          ['foo', 'FOO (paper)'],
        ],
        help: "How the depth sums are evaluated: Midpoint (default, more accurate) or the paper's original.",
      },
      {
        path: 'params.resolutionScale',
        label: 'Optimization resolution',
        kind: 'range',
        min: 0.1,
        max: 1,
        step: 0.05,
        help: 'Resolution of the optimization relative to the image. Lower: faster but coarser.',
      },
      {
        path: 'params.subset',
        label: 'Subset (every n-th)',
        kind: 'range',
        min: 1,
        max: 64,
        step: 1,
        help: 'Use every n-th primitive for the optimization (for dense point clouds). 1: all of them.',
      },
      {
        path: 'params.depthMargin',
        label: 'Depth margin δ',
        kind: 'range',
        min: 0,
        max: 0.25,
        step: 0.005,
        help: 'Keeps depths away from the ends of the periodic depth range. Rarely needs changing.',
      },
      {
        path: 'params.depthRange',
        label: 'Depth range',
        kind: 'select',
        options: [
          ['auto', 'Auto'],
          ['global', 'Data bounds'],
          ['pixel', 'Per pixel'],
          ['moments', 'Around the important layers'],
        ],
        help: "How depth maps onto the Fourier series' period: over the whole data, over each pixel's own depth range, or spread around where each pixel's importance sits (closest to the exact method, one more pass at half resolution). Auto: around the important layers with density normalization, the whole data with it off (the paper's).",
      },
      {
        path: 'params.normalize',
        label: 'Density normalization',
        kind: 'select',
        options: [
          ['auto', 'Auto (adapts to density)'],
          ['off', 'Off (paper formula)'],
        ],
        help: "Auto: dense data does not wash out (opacities adapt to how many layers a pixel has, importance maps from min to max without outliers). Off: the paper's formula unchanged, and Clarity off with it; dense data then turns to fog (a dense trajectory file: its most important tenth 0.2% opaque).",
      },
      {
        path: 'params.lod',
        label: 'Line detail (px)',
        kind: 'range',
        min: 0,
        max: 4,
        step: 0.05,
        help: 'Lines: how far, in pixels, simplified lines may stray from the full ones in still frames. 0: draw every segment.',
      },
      {
        path: 'params.alphaSource',
        label: 'Opacity source',
        kind: 'select',
        options: [
          ['importance', 'Importance (gᵏ)'],
          ['constant', 'Constant'],
          ['angle', 'Angle to the view'],
          ['normalVariation', 'Normal variation'],
        ],
        help: "Direct method only: where each fragment's opacity comes from, without optimization. Importance: importance to the power k. Constant: one opacity for everything. Angle to the view: parts seen edge-on are opaque, parts facing you clear (the rims of a surface; for lines, lines pointing at you). Normal variation: opaque where the surface bends fast on screen (its contours). The local baselines the optimization is compared against.",
      },
      {
        path: 'params.directExponent',
        label: 'Direct exponent k',
        kind: 'range',
        min: 0.1,
        max: 10,
        step: 0.1,
        help: 'Direct method with opacity source importance, and the Kanzler method: opacity = importance to the power k (Kanzler then lowers it by its penalty).',
      },
      {
        path: 'params.alphaConstant',
        label: 'Constant opacity',
        kind: 'range',
        min: 0,
        max: 1,
        step: 0.01,
        help: 'Direct method, opacity source constant: the opacity of every fragment.',
      },
      {
        path: 'params.gamma',
        label: 'Normal variation γ',
        kind: 'range',
        min: 0.1,
        max: 4,
        step: 0.05,
        help: 'Direct method, opacity source normal variation: opacity = (change of the normal per pixel)^γ; below 1 shows more contour.',
      },
      {
        path: 'params.kanzlerImportance',
        label: 'Kanzler m (max importance)',
        kind: 'range',
        min: 0,
        max: 5,
        step: 0.05,
        help: 'Kanzler method only: how much a part fades where the pixel holds something important (the most important part there is spared).',
      },
      {
        path: 'params.kanzlerCoverage',
        label: 'Kanzler c (coverage)',
        kind: 'range',
        min: 0,
        max: 0.5,
        step: 0.005,
        help: 'Kanzler method only: how much a part fades per layer in its pixel. Sensitive: dense data have hundreds of layers.',
      },
      {
        path: 'params.kanzlerVariance',
        label: 'Kanzler v (directions)',
        kind: 'range',
        min: 0,
        max: 5,
        step: 0.05,
        help: 'Kanzler method only, lines: how much a part fades where lines of different directions cross (0 where they run alike).',
      },
      {
        path: 'params.kanzlerDepth',
        label: 'Kanzler d (in front)',
        kind: 'range',
        min: 0,
        max: 10,
        step: 0.1,
        help: 'Kanzler method only: how much a part fades when it lies in front of the most important part of its pixel.',
      },
      {
        path: 'params.kanzlerLambda',
        label: 'Kanzler λ',
        kind: 'range',
        min: 0,
        max: 10,
        step: 0.1,
        help: 'Kanzler method only: how much importance protects a part from the penalty (it is scaled by 1 − importance^λ; 0 turns the penalty off).',
      },
      {
        path: 'params.targetOpacity',
        label: 'Target opacity t',
        kind: 'range',
        min: 0.05,
        max: 1,
        step: 0.05,
        help: "Upper bound of every opacity: even parts that hide nothing let this much of what lies behind through (0.9 in the surface paper). 1: the paper's method.",
      },
      {
        path: 'params.smoothingWeights',
        label: 'Smoothing neighbours',
        kind: 'select',
        options: [
          ['uniform', 'Equal (FOO)'],
          ['distance', 'By distance (surface paper)'],
        ],
        help: 'How the smoothing averages a part with its neighbours: all equally, or nearer neighbours more (by the distance of their centres).',
      },
      {
        path: 'params.clarity',
        label: 'Clarity',
        kind: 'range',
        min: 0,
        max: 1,
        step: 0.05,
        help: "How opaque the most important tenth of what you see should be (0.5: at least half). The server strengthens the optimization (λ, and q and r together) frame by frame until the important parts reach it and the unimportant parts in front of them have faded to at most half of it; the line below shows what the last frame measured. Data that already meet it keep the paper's strength. Fourier, WBOIT and exact methods; setting q, r or λ yourself, or density normalization off, turns it off. It cannot help an importance that points the wrong way or a high exponent on dense data. 0: off.",
      },
      {
        path: 'params.excludeSelf',
        label: 'No self-occlusion',
        kind: 'check',
        help: "Exact method: a part does not fade for hiding itself (a line folding over itself, a surface seen at a grazing angle), only for hiding other parts (the surface paper's rule). Off: the paper's sums over every fragment.",
      },
      {
        path: 'params.guardBand',
        label: 'Guard band',
        kind: 'range',
        min: 0,
        max: 0.5,
        step: 0.05,
        help: 'The optimization also looks this far (fraction of the view) beyond each edge, so parts entering the view while you turn it already have their transparency instead of popping in opaque. 0: off.',
      },
    ],
  },
  {
    id: 'importance',
    legend: 'Importance',
    controls: [
      {
        path: 'importance.attribute',
        label: 'Attribute',
        kind: 'select',
        dynamic: 'attributes',
        help: "The data value that says what matters. Important parts stay visible; unimportant parts fade where they hide important ones. By default: an attribute named importance, vt or scalar, else the file's first one that is not a class label (whole numbers with fewer than 64 values never are the default), else one derived from the shape (curvature, density).",
      },
      {
        path: 'importance.range',
        label: 'Range',
        kind: 'range2',
        dynamic: 'importanceRange',
        help: 'Values at or below the minimum get importance 0, at or above the maximum 1. Minimum above maximum inverts.',
      },
      {
        path: 'importance.exponent',
        label: 'Exponent',
        kind: 'range',
        min: 0.1,
        max: 10,
        step: 0.1,
        help: 'Shapes the mapping: above 1 only the highest values count as important, below 1 importance spreads. On dense data a high exponent can leave almost nothing visible (3 on a dense trajectory file: the most important tenth under 1% opaque), and Clarity cannot make up for it there: keep it near 1. On a mesh Clarity can (3 on a scanned mesh: the most important tenth 51% opaque).',
      },
      {
        path: 'importance.invert',
        label: 'Invert',
        kind: 'check',
        help: "Flips which end of the range matters. Attributes named as a magnitude, rank or p-value (smaller matters: a star's magnitude is larger when fainter) already map inverted; checking this makes their larger values important instead. The range stays as it is.",
      },
    ],
  },
  {
    id: 'color',
    legend: 'Colour',
    controls: [
      {
        path: 'color.attribute',
        label: 'Colour by',
        kind: 'select',
        dynamic: 'colorAttributes',
        help: "The data value shown by colour: the importance, an attribute, or the file's own RGB colours. By default: the file's own colours if it has them, else its class label (kinds by colour, importance by opacity), else the importance.",
      },
      {
        path: 'color.colormap',
        label: 'Colormap',
        kind: 'select',
        options: fieldByPath('color.colormap').values.map((v) => [v, v]),
        help: 'Colours from the lowest to the highest value; the legend over the view shows them.',
      },
      {
        path: 'color.range',
        label: 'Range',
        kind: 'range2',
        dynamic: 'colorRange',
        help: 'The values at the two ends of the colormap. Minimum above maximum flips the colours.',
      },
      {
        path: 'color.equalize',
        label: 'Equalize colours',
        kind: 'check',
        help: 'Spread the colormap evenly over the colour values you can see in this view (weighted by how visible they are); the colours follow the view smoothly. Fourier, direct and exact methods.',
      },
      {
        path: 'color.fadeHalfLife',
        label: 'Colour half-life (s)',
        kind: 'range',
        min: 0,
        max: 10,
        step: 0.1,
        help: 'Equalized colours: how quickly the colours follow a change of view, in seconds (half the way in this time). 0: they jump at once.',
      },
      {
        path: 'color.fixed',
        label: 'Fixed ranges',
        kind: 'ranges',
        help: "Equalized colours: value ranges (in the colour attribute's units) that keep the plain colormap, so a threshold you know keeps its colour while the rest is spread over what you see. Up to 4.",
      },
    ],
  },
  {
    id: 'style',
    legend: 'Style',
    controls: [
      {
        path: 'style.lineWidth',
        label: 'Line width (0 = auto)',
        kind: 'range',
        min: 0,
        max: 0.05,
        step: 0.0005,
        dynamic: 'lineWidth',
        help: 'Width of lines in data units. 0: automatic from the size of the data.',
      },
      {
        path: 'style.minLinePixels',
        label: 'Minimum line pixels',
        kind: 'range',
        min: 0,
        max: 8,
        step: 0.5,
        help: 'Lines are never drawn thinner than this many pixels.',
      },
      {
        path: 'style.pointSize',
        label: 'Point size (px)',
        kind: 'range',
        min: 0.5,
        max: 20,
        step: 0.5,
        help: 'Diameter of points in pixels.',
      },
      {
        path: 'style.background',
        label: 'Background',
        kind: 'color',
        help: "Background colour of the image. The page opens on one that contrasts with the colormap's highest values: dark grey for viridis, inferno, plasma and grayscale, white for turbo and coolwarm.",
      },
      {
        path: 'style.shading',
        label: 'Shading',
        kind: 'select',
        options: [
          ['phong', 'Phong'],
          ['none', 'None (flat)'],
        ],
        help: 'Phong: lit like tubes and surfaces. None: flat colours.',
      },
      {
        path: 'camera.viewAngle',
        label: 'View angle (°)',
        kind: 'range',
        min: 5,
        max: 120,
        step: 1,
        help: 'Vertical field of view in degrees (perspective projection).',
      },
      {
        path: 'camera.parallelProjection',
        label: 'Parallel projection',
        kind: 'check',
        help: 'Orthographic view: sizes do not shrink with distance.',
      },
      {
        path: 'style.silhouetteExponent',
        label: 'Silhouette emphasis η',
        kind: 'range',
        min: 1,
        max: 20,
        step: 0.5,
        help: 'Surfaces: where a surface turns away from you (its outline) it becomes more opaque, as if seen through η layers (10 in the paper). 1: off.',
      },
      {
        path: 'style.haloWidth',
        label: 'Halo width (px)',
        kind: 'range',
        min: 0,
        max: 16,
        step: 0.5,
        help: 'Lines: a band in the background colour beside each line that cuts lines passing far enough behind it, so crossings read in depth. 0: off.',
      },
      {
        path: 'style.haloDepth',
        label: 'Halo depth offset',
        kind: 'range',
        min: 0,
        max: 0.2,
        step: 0.005,
        help: 'How far behind a line (fraction of the data size) another line must pass to be cut by its halo; lines closer than this (a bundle) are not cut.',
      },
      {
        path: 'style.haloStrength',
        label: 'Halo strength',
        kind: 'range',
        min: 0,
        max: 1,
        step: 0.05,
        help: 'Opacity of the halo relative to its line: 1 cuts fully, lower values only dim.',
      },
      {
        path: 'style.antialias',
        label: 'Anti-aliasing (still)',
        kind: 'range',
        min: 1,
        max: 16,
        step: 1,
        help: 'The sharp frame shown once you stop moving averages this many slightly shifted images, so thin lines and points do not flicker or stair-step. Costs that many compositing passes. 1: off.',
      },
      {
        path: 'style.shadow',
        label: 'Ground shadow',
        kind: 'range',
        min: 0,
        max: 1,
        step: 0.05,
        help: 'Transparent, see-through shadows of the data on a ground plane (or on a context layer): the ground darkens by this much under fully opaque parts and by less under faint ones. Without a context layer a ground plane is drawn. 0: off.',
      },
      {
        path: 'style.shadowLight',
        label: 'Light from (x, y, z)',
        kind: 'vec3',
        help: "Direction toward the light in data coordinates; the ground plane faces it. 0, 0, 0: the data's own up direction (else +y).",
      },
      {
        path: 'style.shadowColored',
        label: 'Coloured shadow',
        kind: 'check',
        help: 'The shadow takes the colour of what casts it, as light through coloured glass; off: grey.',
      },
      {
        path: 'style.ground',
        label: 'Ground plane',
        kind: 'select',
        options: [
          ['auto', 'With shadows'],
          ['on', 'Always'],
          ['off', 'Never'],
        ],
        help: 'An opaque plane beyond the data, facing the light. With shadows: drawn when a shadow is asked for and no context layer receives it.',
      },
      {
        path: 'style.groundColor',
        label: 'Ground colour',
        kind: 'color',
        help: 'Colour of the ground plane (unlit; the shadow alone darkens it).',
      },
      {
        path: 'style.groundOffset',
        label: 'Ground distance',
        kind: 'range',
        min: 0,
        max: 1,
        step: 0.01,
        help: 'Gap between the data and the ground plane, as a fraction of the data size.',
      },
      {
        path: 'style.smartTransparency',
        label: 'Smart transparency',
        kind: 'range',
        min: 0,
        max: 1,
        step: 0.05,
        help: 'Dark outlines where a transparent layer ends and light halos on what lies behind its edge, stronger the more opaque the layer, so the order of layers reads at their edges. 0: off.',
      },
      {
        path: 'style.smartIterations',
        label: 'Outline spread (px)',
        kind: 'range',
        min: 0,
        max: 32,
        step: 1,
        help: 'How many pixels the outlines and halos spread from the edge (diffusion steps; 5 in the paper).',
      },
    ],
  },
  {
    id: 'criteria',
    legend: 'Criteria, filters, transfer functions',
    controls: [
      {
        path: 'importance.terms',
        label: 'Importance terms',
        kind: 'terms',
        help: 'Up to four weighted criteria instead of one attribute: each maps its attribute from its range (empty: auto) to [0, 1], weight −1 to 1; g = Σ w·t / Σ|w|, and when the weights sum below 0, g = 1 + that sum (a penalty). Remove every term for the single attribute above.',
      },
      {
        path: 'filter',
        label: 'Filters',
        kind: 'filters',
        help: 'Lines (points) draw only where every filter holds: a statistic of the attribute over the line (min, max, mean, first, last, change = last − first; points: vertex) compared with a value. Changing a filter costs one frame, not a reload.',
      },
      {
        path: 'importance.curve',
        label: 'Importance curve',
        kind: 'curve',
        help: 'Transfer function of the importance before the exponent: drag the points, click to add one, double-click to remove one.',
      },
      {
        path: 'color.curve',
        label: 'Colour curve',
        kind: 'curve',
        help: 'Transfer function of the colormap coordinate: drag the points, click to add one, double-click to remove one.',
      },
    ],
  },
  {
    id: 'quality',
    legend: 'Quality',
    controls: [
      {
        path: 'quality',
        label: 'JPEG quality (still)',
        kind: 'range',
        min: 10,
        max: 100,
        step: 1,
        help: 'JPEG quality of the sharp frame shown once you stop moving.',
      },
      {
        path: 'interactiveQuality',
        label: 'JPEG quality (moving)',
        kind: 'range',
        min: 10,
        max: 100,
        step: 1,
        help: 'The most JPEG quality of the frames while you move the view; the server lowers it (then their size) where the link cannot carry them in time.',
      },
      {
        path: 'interactiveScale',
        label: 'Resolution while moving',
        kind: 'range',
        min: 0.25,
        max: 1,
        step: 0.05,
        help: 'Image resolution while you move the view (fraction per side). Lower: smoother motion.',
      },
    ],
  },
  {
    id: 'lines',
    legend: 'Line clusters',
    controls: [
      {
        path: 'lines.clusters',
        label: 'Clusters (0 = all lines)',
        kind: 'range',
        min: 0,
        max: 1000,
        step: 1,
        help: 'Lines: group similar lines and draw one line per group. 0 draws every line. The first use clusters the lines (seconds for large sets); then a new count costs one frame.',
      },
      {
        path: 'lines.representative',
        label: 'Representative',
        kind: 'select',
        options: [
          ['important', 'Most important'],
          ['mean', 'Closest to the mean'],
          ['leastDistance', 'Least distance to the rest'],
        ],
        help: "Which line stands in for its group: the most important one, the one closest to the group's average line, or the one nearest to all the others.",
      },
      {
        path: 'lines.linkage',
        label: 'Linkage',
        kind: 'select',
        options: [
          ['complete', 'Complete'],
          ['single', 'Single'],
          ['average', 'Average'],
        ],
        help: 'How groups are merged: complete keeps groups compact (recommended), single chains neighbours, average is in between.',
      },
      {
        path: 'lines.liftImportance',
        label: 'Importance weight λg',
        kind: 'range',
        min: 0,
        max: 2,
        step: 0.05,
        help: 'How much differences in importance separate lines, besides their position. Above 0.5: important lines form groups of their own.',
      },
      {
        path: 'lines.liftColor',
        label: 'Colour weight λc',
        kind: 'range',
        min: 0,
        max: 2,
        step: 0.05,
        help: 'How much differences in the colour value separate lines, besides their position.',
      },
    ],
  },
];

const idOf = (path) => `ctl-${path.replace(/\./g, '-')}`;
const decimals = (step) => (String(step).includes('.') ? String(step).split('.')[1].length : 0);

/** [0,1] RGB ↔ #rrggbb. */
export function rgbToHex(rgb) {
  const h = (x) =>
    Math.round(Math.min(1, Math.max(0, x)) * 255)
      .toString(16)
      .padStart(2, '0');
  return `#${h(rgb[0])}${h(rgb[1])}${h(rgb[2])}`;
}
export function hexToRgb(hex) {
  const m = /^#?([0-9a-f]{2})([0-9a-f]{2})([0-9a-f]{2})$/i.exec(hex);
  return m ? [1, 2, 3].map((i) => Number((parseInt(m[i], 16) / 255).toFixed(4))) : null;
}

/** Formats a number for a number box: at most 6 significant digits, no trailing zeros. */
export function formatNumber(v) {
  if (typeof v !== 'number' || !Number.isFinite(v)) return '';
  if (v === 0) return '0';
  return String(Number(v.toPrecision(6)));
}

export class Panel {
  /**
   * container: element to fill; onChange(path, value, {final}) is called on
   * every edit (final on 'change', not final on 'input' while dragging);
   * onNotice(text) tells the user about a value that was corrected or refused.
   */
  constructor(container, onChange, onNotice = () => {}) {
    this.onChange = onChange;
    this.onNotice = onNotice;
    this.controls = new Map(); // path -> {spec, el (main input), num, num2}
    for (const g of GROUPS) container.append(this.#group(g));
  }

  #group(g) {
    const fs = document.createElement('fieldset');
    fs.className = 'group';
    fs.id = `group-${g.id}`;
    const legend = document.createElement('legend');
    legend.textContent = g.legend;
    fs.append(legend);
    for (const c of g.controls) fs.append(this.#control(c));
    return fs;
  }

  #emit(path, value, final) {
    const f = fieldByPath(path);
    const ctl = this.controls.get(path);
    let problem = f ? checkField(f, value) : null;
    // a number outside the field's range is brought inside it and said so, so that the box,
    // the slider and the server show the same value (typing bands = 20 gives 8 everywhere)
    if (problem?.code === 'out_of_range' && ctl.spec.kind === 'range' && typeof value === 'number') {
      const fixed = clampToField(f, ctl.spec, value);
      if (!checkField(f, fixed)) {
        this.setValue(path, fixed);
        ctl.num.value = formatNumber(fixed); // setValue leaves a focused box alone
        this.#message(ctl, `${ctl.spec.label}: ${problem.reason}; set to ${formatNumber(fixed)}.`);
        this.onNotice(`${ctl.spec.label}: ${problem.reason}; set to ${formatNumber(fixed)}.`);
        this.onChange(path, fixed, { final });
        return;
      }
    }
    if (problem) {
      const text = `${ctl.spec.label}: ${problem.reason}; not applied.`;
      ctl.row.classList.add('invalid');
      this.#message(ctl, text);
      this.onNotice(text);
      return;
    }
    ctl.row.classList.remove('invalid');
    this.#message(ctl, '');
    this.onChange(path, value, { final });
  }

  #message(ctl, text) {
    ctl.msg.textContent = text;
    ctl.msg.hidden = !text;
  }

  #control(spec) {
    const row = document.createElement('div');
    row.className = `row kind-${spec.kind}`;
    row.dataset.path = spec.path;
    const id = idOf(spec.path);
    const label = document.createElement('label');
    label.htmlFor = id;
    label.textContent = spec.label;
    row.append(label);
    const ctl = { spec, row };
    if (spec.help) {
      row.title = spec.help;
      const hint = document.createElement('small');
      hint.className = 'hint';
      hint.id = `${id}-help`;
      hint.textContent = spec.help;
      ctl.hint = hint;
    }
    const msg = document.createElement('small');
    msg.className = 'row-msg';
    msg.setAttribute('role', 'status');
    msg.dataset.testid = `msg-${spec.path}`;
    msg.hidden = true;
    ctl.msg = msg;
    const f = fieldByPath(spec.path);
    const int = f?.type === 'int';
    const parseNum = (s) => (s.trim() === '' ? NaN : Number(s));

    if (spec.kind === 'range') {
      const range = document.createElement('input');
      range.type = 'range';
      range.id = id;
      range.name = spec.path;
      Object.assign(range, { min: spec.min, max: spec.max, step: spec.step });
      const num = document.createElement('input');
      num.type = 'number';
      num.className = 'num';
      num.setAttribute('aria-label', `${spec.label} value`);
      num.step = 'any';
      if (f?.min !== undefined) num.min = f.min;
      if (f?.max !== undefined) num.max = f.max;
      range.addEventListener('input', () => {
        const v = int ? Math.round(Number(range.value)) : Number(range.value);
        num.value = formatNumber(v);
        this.#emit(spec.path, v, false);
      });
      range.addEventListener('change', () =>
        this.#emit(spec.path, int ? Math.round(Number(range.value)) : Number(range.value), true),
      );
      num.addEventListener('change', () => {
        const v = parseNum(num.value);
        if (Number.isFinite(v)) range.value = String(v);
        this.#emit(spec.path, v, true);
      });
      row.append(range, num);
      Object.assign(ctl, { el: range, num });
    } else if (spec.kind === 'select') {
      const sel = document.createElement('select');
      sel.id = id;
      sel.name = spec.path;
      for (const [v, text] of spec.options ?? []) sel.append(new Option(text, v));
      sel.addEventListener('change', () => this.#emit(spec.path, sel.value, true));
      row.append(sel);
      ctl.el = sel;
    } else if (spec.kind === 'check') {
      const cb = document.createElement('input');
      cb.type = 'checkbox';
      cb.id = id;
      cb.name = spec.path;
      cb.addEventListener('change', () => this.#emit(spec.path, cb.checked, true));
      row.append(cb);
      ctl.el = cb;
    } else if (spec.kind === 'color') {
      const col = document.createElement('input');
      col.type = 'color';
      col.id = id;
      col.name = spec.path;
      const out = document.createElement('output');
      out.htmlFor = id;
      const fire = (final) => {
        out.textContent = col.value;
        this.#emit(spec.path, hexToRgb(col.value), final);
      };
      col.addEventListener('input', () => fire(false));
      col.addEventListener('change', () => fire(true));
      row.append(col, out);
      Object.assign(ctl, { el: col, out });
    } else if (EDITORS[spec.kind]) {
      const ed = EDITORS[spec.kind]((v, final) => this.#emit(spec.path, v, final));
      ed.el.id = id;
      row.append(ed.el);
      Object.assign(ctl, { el: ed.el, editor: ed });
    } else if (spec.kind === 'range2') {
      const lo = document.createElement('input');
      const hi = document.createElement('input');
      lo.type = hi.type = 'number';
      lo.step = hi.step = 'any';
      lo.id = id;
      lo.className = hi.className = 'num';
      lo.setAttribute('aria-label', `${spec.label} minimum`);
      hi.setAttribute('aria-label', `${spec.label} maximum`);
      lo.name = `${spec.path}.0`;
      hi.name = `${spec.path}.1`;
      const fire = () => this.#emit(spec.path, [parseNum(lo.value), parseNum(hi.value)], true);
      lo.addEventListener('change', fire);
      hi.addEventListener('change', fire);
      const span = document.createElement('span');
      span.className = 'pair';
      span.append(lo, document.createTextNode('–'), hi);
      row.append(span);
      Object.assign(ctl, { el: lo, num2: hi });
    } else if (spec.kind === 'vec3') {
      const inputs = [0, 1, 2].map((i) => {
        const n = document.createElement('input');
        n.type = 'number';
        n.step = 'any';
        n.className = 'num';
        n.name = `${spec.path}.${i}`;
        n.setAttribute('aria-label', `${spec.label} ${'xyz'[i]}`);
        return n;
      });
      inputs[0].id = id;
      const fire = () =>
        this.#emit(
          spec.path,
          inputs.map((n) => parseNum(n.value)),
          true,
        );
      for (const n of inputs) n.addEventListener('change', fire);
      const span = document.createElement('span');
      span.className = 'pair';
      span.append(...inputs);
      row.append(span);
      Object.assign(ctl, { el: inputs[0], vec: inputs });
    }
    if (ctl.hint) {
      row.append(ctl.hint);
      for (const el of [ctl.el, ctl.num, ctl.num2, ...(ctl.vec ?? [])])
        el?.setAttribute('aria-describedby', ctl.hint.id);
    }
    row.append(msg);
    this.controls.set(spec.path, ctl);
    return row;
  }

  /** Shows a value without firing onChange (values from the server, the URL, resets). */
  setValue(path, v) {
    const ctl = this.controls.get(path);
    if (!ctl || v === undefined || v === null) return;
    const { spec } = ctl;
    ctl.row.classList.remove('invalid');
    if (ctl.msg && !ctl.msg.hidden && !ctl.row.contains(document.activeElement)) this.#message(ctl, '');
    if (ctl.editor) {
      ctl.editor.set(v);
    } else if (spec.kind === 'range') {
      if (document.activeElement !== ctl.num) ctl.num.value = formatNumber(v);
      // widen the slider when a value lies beyond it (the number box takes any valid value)
      if (v > Number(ctl.el.max)) ctl.el.max = String(v);
      if (v < Number(ctl.el.min)) ctl.el.min = String(v);
      ctl.el.value = String(v);
    } else if (spec.kind === 'select') {
      if (![...ctl.el.options].some((o) => o.value === v)) ctl.el.append(new Option(String(v), v));
      ctl.el.value = v;
    } else if (spec.kind === 'check') {
      ctl.el.checked = !!v;
    } else if (spec.kind === 'color') {
      ctl.el.value = rgbToHex(v);
      ctl.out.textContent = ctl.el.value;
    } else if (spec.kind === 'range2') {
      if (document.activeElement !== ctl.el) ctl.el.value = formatNumber(v[0]);
      if (document.activeElement !== ctl.num2) ctl.num2.value = formatNumber(v[1]);
    } else if (spec.kind === 'vec3') {
      ctl.vec.forEach((n, i) => {
        if (document.activeElement !== n) n.value = formatNumber(v[i]);
      });
    }
  }

  /** Replaces a select's options ([[value, text], ...]). */
  setOptions(path, options) {
    const ctl = this.controls.get(path);
    if (!ctl || ctl.spec.kind !== 'select') return;
    const cur = ctl.el.value;
    ctl.el.replaceChildren(...options.map(([v, t]) => new Option(t, v)));
    if (options.some(([v]) => v === cur)) ctl.el.value = cur;
  }

  /** Sets a slider's bounds and step (line width follows the data's size). */
  setBounds(path, min, max, step) {
    const ctl = this.controls.get(path);
    if (!ctl || ctl.spec.kind !== 'range') return;
    Object.assign(ctl.el, { min, max, step });
  }

  /** Shows a row only when relevant (e.g. direct exponent for the direct method). */
  setVisible(path, visible) {
    const ctl = this.controls.get(path);
    if (ctl) ctl.row.hidden = !visible;
  }

  /** A line of feedback under a control (the clarity's measured visibility); '' hides it. */
  setFeedback(path, text) {
    const ctl = this.controls.get(path);
    if (!ctl) return;
    if (!ctl.feedback) {
      ctl.feedback = document.createElement('div');
      ctl.feedback.className = 'feedback';
      ctl.row.append(ctl.feedback);
    }
    ctl.feedback.textContent = text;
    ctl.feedback.hidden = !text;
  }

  /** Marks a control invalid with the server's reason (error message with field). */
  markInvalid(path, reason) {
    const ctl = this.controls.get(path);
    if (!ctl) return false;
    ctl.row.classList.add('invalid');
    this.#message(ctl, reason);
    return true;
  }

  /** The methods the server offers, when it says (ready/health may list them). */
  setMethods(names) {
    if (!Array.isArray(names) || !names.length) return;
    this.setOptions(
      'method',
      names.map((n) => [n, METHOD_LABELS[n] ?? n]),
    );
  }

  /** Fills the dataset-dependent choices from a dataset description. */
  setDataset(info) {
    const attrs = Array.isArray(info?.attributes) ? info.attributes : [];
    const names = attrs.map((a) => (typeof a === 'string' ? a : a.name)).filter(Boolean);
    this.setOptions(
      'importance.attribute',
      names.map((n) => [n, n]),
    );
    const colorOpts = [['importance', 'importance'], ...names.map((n) => [n, n])];
    if (info?.hasRgb) colorOpts.push(['rgb', 'RGB (per vertex)']);
    this.setOptions('color.attribute', colorOpts);
    for (const ctl of this.controls.values()) ctl.editor?.setAttributes(names);
    const b = flatBounds(info?.bounds);
    if (b) {
      const diag = Math.hypot(b[3] - b[0], b[4] - b[1], b[5] - b[2]) || 1;
      const step = Number((diag * 1e-4).toPrecision(2));
      this.setBounds('style.lineWidth', 0, Number((diag * 0.02).toPrecision(3)), step);
    }
  }
}

/**
 * value brought inside the field's range; open ends (resolutionScale's 0) use
 * the slider's end instead, integers are rounded.
 */
export function clampToField(f, spec, value) {
  const lo = f.loOpen ? Math.max(f.min ?? -Infinity, spec.min) : (f.min ?? -Infinity);
  const hi = f.hiOpen ? Math.min(f.max ?? Infinity, spec.max) : (f.max ?? Infinity);
  const v = Math.min(hi, Math.max(lo, value));
  return f.type === 'int' ? Math.round(v) : v;
}

/**
 * The range the server maps an attribute with when a request gives none, from a
 * dataset description, or null: its auto range (min/max without the outliers)
 * unless normalize is "off" or that range is empty, else [min, max]. The panel,
 * the legend and the link all take it, so the page shows what the server uses.
 */
export function attributeRange(info, name, normalize) {
  const a = (info?.attributes ?? []).find((x) => (typeof x === 'string' ? x : x.name) === name);
  const auto = a?.autoRange;
  if (normalize !== 'off' && Array.isArray(auto) && auto[1] > auto[0]) return [...auto];
  return a && Array.isArray(a.range) ? [...a.range] : null;
}

export { METHOD_LABELS, decimals };
