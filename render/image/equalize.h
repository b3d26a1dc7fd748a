/* View-dependent colour equalization (DLS §3.4): from a visibility-weighted
 * histogram of colour values to an equalizing transfer F with ranges kept as
 * the identity, its exponential approach over time, and the colormap table
 * T(F(c)) that the shaders read in place of T(c).
 * Pure functions on caller-owned arrays; thread-safe. */
#ifndef LC_EQUALIZE_H
#define LC_EQUALIZE_H

#ifdef __cplusplus
extern "C" {
#endif

#define LC_EQUALIZE_BINS 256 /* DLS §5.1: no visible change beyond 256 bins */
#define LC_EQUALIZE_MAX_FIXED 8
#define LC_EQUALIZE_DEFAULT_HALF_LIFE 0.8 /* seconds (DLS §5.3) */

/* The target transfer F̂ of DLS Eq. 7 as bins + 1 knots: knot b is F̂(b / bins),
 * F̂ piecewise linear between knots. hist[b] is the weight of colour values in
 * [b/bins, (b+1)/bins) (H_b of Eq. 6). fixed[i] = {lo, hi} in [0, 1] are kept as
 * the identity (F̂(c) = c there); each stretch between them (and the ends) is
 * equalized onto itself by its own share of the histogram, so F̂ stays
 * continuous and monotone; a stretch without weight stays the identity.
 * Knots are snapped to the bin grid: a fixed range covers the bins it
 * overlaps. Returns 0, or -1 for bins < 1 or a range outside [0, 1] or
 * reversed. */
int lc_equalize_target(const double *hist, int bins, const double (*fixed)[2], int fixed_count, float *knots);

/* One step of the decay of DLS Eq. 8-10: knots move toward target by
 * alpha = 1 - 2^(-dt / half_life) (half_life <= 0: all the way). */
void lc_equalize_approach(float *knots, const float *target, int bins, double dt, double half_life);

/* F(c) for c in [0, 1] (clamped), linear between the knots. */
float lc_equalize_map(const float *knots, int bins, float c);

/* The inverse: the least c in [0, 1] with F(c) = x (x clamped to [F(0), F(1)]),
 * for knots that do not decrease; the legend's tick positions. */
float lc_equalize_inverse(const float *knots, int bins, float x);

/* The equalized colormap: entry k of out (size entries, 3 floats each) is the
 * colour of table (LC_COLORMAP_SIZE entries, lc_colormap_table) at F(k / (size - 1)). */
void lc_equalize_table(const float *table, int table_size, const float *knots, int bins, float *out, int size);

#ifdef __cplusplus
}
#endif
#endif
