// The server's colormaps as eleven evenly spaced stops each (sampled from the
// tables of render/image/colormap.c, which the renderer interpolates linearly),
// for the legend's colour bar and the background contrast check. Pure.

export const COLORMAP_STOPS = Object.freeze({
  viridis: [
    '#440154',
    '#482575',
    '#414487',
    '#345f8d',
    '#2a788e',
    '#21908c',
    '#22a884',
    '#43bf71',
    '#7ad151',
    '#bcdf27',
    '#fde725',
  ],
  coolwarm: [
    '#3b4cc0',
    '#5978e3',
    '#7b9ff9',
    '#9fbeff',
    '#c0d4f5',
    '#dddddd',
    '#f2cbb7',
    '#f7ad8f',
    '#ee8468',
    '#d75344',
    '#b40426',
  ],
  grayscale: [
    '#000000',
    '#1a1a1a',
    '#333333',
    '#4c4c4c',
    '#666666',
    '#808080',
    '#999999',
    '#b2b2b2',
    '#cccccc',
    '#e6e6e6',
    '#ffffff',
  ],
  inferno: [
    '#000004',
    '#170b3b',
    '#420a68',
    '#6b176e',
    '#932667',
    '#bb3755',
    '#dd513a',
    '#f3771a',
    '#fca50a',
    '#f6d644',
    '#fcffa4',
  ],
  plasma: [
    '#0d0887',
    '#42039d',
    '#6a00a8',
    '#900ea3',
    '#b12a90',
    '#cb4778',
    '#e16462',
    '#f2834c',
    '#fca636',
    '#fcce25',
    '#f0f921',
  ],
  turbo: [
    '#23171b',
    '#4958dd',
    '#2f9ef5',
    '#27d7c3',
    '#4ef983',
    '#96fa50',
    '#dfdc32',
    '#ffa323',
    '#f45c17',
    '#b82008',
    '#900d00',
  ],
});

const hexRgb = (h) => [1, 3, 5].map((i) => parseInt(h.slice(i, i + 2), 16) / 255);

/** The colour of a colormap at t ∈ [0, 1] as [r, g, b] in [0, 1] (linear between the stops). */
export function colorAt(name, t) {
  const stops = COLORMAP_STOPS[name] ?? COLORMAP_STOPS.viridis;
  const x = Math.min(1, Math.max(0, Number.isFinite(t) ? t : 0.5)) * (stops.length - 1);
  const i = Math.min(stops.length - 2, Math.floor(x));
  const a = hexRgb(stops[i]),
    b = hexRgb(stops[i + 1]);
  return a.map((v, k) => v + (b[k] - v) * (x - i));
}

/** CSS linear-gradient of a colormap, left = range minimum; reversed when the range is (max > min reversed). */
export function gradientCss(name, reversed = false) {
  const stops = [...(COLORMAP_STOPS[name] ?? COLORMAP_STOPS.viridis)];
  if (reversed) stops.reverse();
  return `linear-gradient(to right, ${stops.join(', ')})`;
}

/** Euclidean distance of two RGB colours in [0, 1]³ (0 = same, √3 = black vs white). */
export const rgbDistance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

/** WCAG relative luminance of an sRGB colour in [0, 1]³. */
export function relativeLuminance(rgb) {
  const lin = (c) => (c <= 0.04045 ? c / 12.92 : Math.pow((c + 0.055) / 1.055, 2.4));
  return 0.2126 * lin(rgb[0]) + 0.7152 * lin(rgb[1]) + 0.0722 * lin(rgb[2]);
}

/** WCAG contrast ratio of two colours: 1 (same luminance) to 21 (black on white). */
export function contrastRatio(a, b) {
  const la = relativeLuminance(a),
    lb = relativeLuminance(b);
  return (Math.max(la, lb) + 0.05) / (Math.min(la, lb) + 0.05);
}

/** Below this luminance contrast the legend warns: the colour is lost in the background. */
export const CLASH_RATIO = 1.5;

/**
 * The colour drawn for the highest value of the colour range (t = 1, or t = 0
 * when the range is inverted), and whether it is too close to the background to
 * be seen: luminance contrast below minRatio (viridis' yellow on white is 1.26,
 * grayscale's white on white 1). With colour by importance this is the most
 * important structure.
 */
export function topColorClash(colormap, range, background, minRatio = CLASH_RATIO) {
  const inverted = Array.isArray(range) && range[0] > range[1];
  const top = colorAt(colormap, inverted ? 0 : 1);
  const bg = Array.isArray(background) && background.length === 3 ? background : [1, 1, 1];
  return { top, clash: contrastRatio(top, bg) < minRatio };
}

/** The page's dark background (docs/GUIDE.md "Contrast by default"). */
export const DARK_BACKGROUND = Object.freeze([0.1, 0.1, 0.1]);

/**
 * The background the page opens with for a colormap (docs/GUIDE.md "Contrast by
 * default"): white when the colormap's top colour (the highest values, with
 * colour by importance the most important parts) has a contrast ratio of at
 * least 3:1 against white (turbo, coolwarm), else dark (viridis, inferno,
 * plasma and grayscale end near white).
 */
export function contrastBackground(colormap) {
  return contrastRatio(colorAt(colormap, 1), [1, 1, 1]) >= 3 ? [1, 1, 1] : [...DARK_BACKGROUND];
}
