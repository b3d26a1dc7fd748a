/* Colormaps for scalar-to-colour mapping: named tables of 256 RGB entries
 * (sRGB, [0,1]) built once from published control points. Thread-safe: the
 * tables are built on first use under a once-guard and never change. */
#ifndef LC_COLORMAP_H
#define LC_COLORMAP_H

#ifdef __cplusplus
extern "C" {
#endif

#define LC_COLORMAP_SIZE 256

/* Number of colormaps; indices 0..count-1 are stable within a build. */
int lc_colormap_count(void);
/* Name of colormap i ("viridis", "coolwarm", ...), or NULL when out of range. */
const char *lc_colormap_name(int i);
/* Index of the colormap named name (exact, case-sensitive), or -1 if unknown. */
int lc_colormap_find(const char *name);
/* Colour at t: t is clamped to [0,1] (NaN maps to 0) and the 256-entry table is
 * interpolated linearly. An unknown index yields black. */
void lc_colormap_sample(int i, float t, float rgb[3]);
/* WCAG contrast ratio of colormap i's colour at t against bg (sRGB, [0,1]):
 * 1 (the same luminance) to 21 (black on white). */
double lc_colormap_contrast(int i, float t, const double bg[3]);
/* Below this ratio the colour is lost in the background (the page's legend
 * warns at the same ratio, web/js/colormaps.js CLASH_RATIO). */
#define LC_COLORMAP_CLASH_RATIO 1.5
/* LC_COLORMAP_SIZE x 3 floats, entry k at t = k/255 (a GPU texture source), or
 * NULL when out of range. Valid for the life of the process. */
const float *lc_colormap_table(int i);

#ifdef __cplusplus
}
#endif
#endif
