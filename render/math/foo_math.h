/* CPU reference of the Fourier opacity optimization formulas (docs/ALGORITHM.md) on
 * explicit fragment lists. The shaders implement the same math; tests compare. */
#ifndef LC_FOO_MATH_H
#define LC_FOO_MATH_H

#include <stddef.h>
#include <stdint.h>

#include "lc_params.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Coefficient sums A_k = sum f cos(2 pi k d), B_k = sum f sin(2 pi k d), k = 0..m. */
typedef struct lc_fourier {
    int m;
    double a[LC_MAX_BANDS + 1];
    double b[LC_MAX_BANDS + 1]; /* b[0] is always 0 */
} lc_fourier;

void lc_fourier_init(lc_fourier *f, int m);
void lc_fourier_add(lc_fourier *f, double d, double value);
/* Reconstructed running sum F(d) = A0 d + sum_k [A_k sin(2pi k d) + B_k (1 - cos(2pi k d))]/(pi k).
 * F(1) = A0 exactly. */
double lc_fourier_eval(const lc_fourier *f, double d);

/* Normalized depth d = delta + (1 - 2 delta)(z - zmin)/(zmax - zmin), clamped to [0,1]. */
double lc_foo_normalize_depth(double z, double zmin, double zmax, double delta);

/* The depth normalization in effect: params.depthRange with "auto" resolved
 * (moments with density normalization, global with the paper's formula). */
lc_depth_range lc_foo_depth_range(const lc_foo_params *p);

/* Moment-warped depth (depthRange "moments", docs/ALGORITHM.md "Depth
 * normalization"). A pixel's importance mass sums m[0] = sum g^2, m[1] = sum
 * g^2 u, m[2] = sum g^2 u^2 with u = d - 1/2 and d the bounds-normalized depth
 * (margin delta) give the mass's mean mu and spread sigma; the fragment at d
 * goes to delta + (1 - 2 delta) L((u - mu) / s), L the logistic function and
 * s = max(sigma, LC_MOMENT_MIN_SPREAD). Monotone, so the depth order holds,
 * and it spreads the layers where the mass sits over most of the period that
 * the truncated series resolves. A pixel without mass (m[0] = 0) keeps d.
 * depth_moments.frag.glsl and series_depth (common.glsl) do the same. */
#define LC_MOMENT_MIN_SPREAD 1e-3
double lc_foo_moment_depth(double d, const double m[3], double delta);

/* Optimal opacity, FOO Eq. 10: 1 / (1 + (1-g)^(2 lambda) (r max(front,0) + q max(behind,0))).
 * front = importance (sum g^2) in front of the fragment, behind = behind it. */
double lc_foo_optimal_alpha(double g, double front, double behind, double q, double r, double lambda);

/* Density normalization (params.normalize, docs/ALGORITHM.md "Density
 * normalization"): in auto mode a pixel whose total importance mass sum g^2
 * exceeds LC_NORM_REFERENCE_MASS has its front and behind sums scaled by
 * LC_NORM_REFERENCE_MASS / total = k, and the emphasis exponent grows with the
 * density to lambda (1 + LC_NORM_EMPHASIS (1 - k)^2): the paper's where the
 * sums are not scaled, little more where they are scaled a little, 4 lambda in
 * the densest. The shaders repeat the formula (p2_opacity, exact_opacity). */
#define LC_NORM_REFERENCE_MASS 0.6
#define LC_NORM_EMPHASIS 3.0
/* The reference mass the shaders use (0 = normalization off). */
double lc_foo_norm_mass(const lc_foo_params *p);
/* The lambda of Eq. 10 in effect in a pixel whose sums are scaled by k
 * (lc_foo_norm_factor): lambda (1 + 3 (1 - k)^2) in auto mode, lambda when off. */
double lc_foo_effective_lambda(const lc_foo_params *p, double k);
/* The factor on the front/behind sums of a pixel with total mass `total`. */
double lc_foo_norm_factor(const lc_foo_params *p, double total);

/* Target opacity t (params.targetOpacity, OOS Eq. 7): every optimal opacity
 * is scaled by t, alpha = t / (1 + ...), so nothing is more opaque than t.
 * Returns t, or 1 when the field is outside (0, 1] (zero-initialized params). */
double lc_foo_target_opacity(const lc_foo_params *p);
/* Silhouette opacity transfer (style.silhouetteExponent eta, OOS Eq. 8) with
 * the smooth silhouette measure s = 1 - |n.v| in [0, 1]: alpha' = 1 - (1 -
 * alpha)^(1 + (eta - 1) s), so eta applies in full on silhouettes (s = 1) and
 * not at all facing the viewer (s = 0). eta <= 1 returns alpha unchanged. */
double lc_foo_silhouette_alpha(double alpha, double eta, double s);
/* Kanzler's occlusion penalty (M3D Eq. 3.2-3.3; docs/ALGORITHM.md §28) of a
 * fragment of importance g at normalized depth d in a pixel whose maps hold
 * coverage C, maximum importance M at depth D and directional variance V:
 * rho = 1/(1 + (1 - g^lambda) P), P = m M + c C + v V + d' less, less = 1
 * where the fragment lies in front of D by more than one 16-bit step (D is
 * kept rounded to half a step, so the maximum's own fragment is never in front
 * of itself). The shaders' reference (fragment_common.glsl). */
double lc_foo_kanzler_rho(const lc_foo_params *p, double g, double d, double C, double M, double D, double V);
/* V = 1 - |sum t|/n of n unit tangents (xyz triples). */
double lc_foo_direction_variance(const double *t, int n);

/* One fragment of a pixel. alpha and color are outputs/inputs as documented below. */
typedef struct lc_fragment {
    double depth;      /* normalized, [0,1] */
    double importance; /* g */
    double alpha;
    double color[3];
} lc_fragment;

/* Sets frag[i].alpha from exact front/behind sums (sorted sums, DOO). Fragments
 * at equal depth count as in front of each other in list order after a stable sort. */
void lc_foo_alpha_exact(lc_fragment *frags, size_t n, const lc_foo_params *p);
/* Sets frag[i].alpha from the Fourier reconstruction with p->bands and p->estimator. */
void lc_foo_alpha_fourier(lc_fragment *frags, size_t n, const lc_foo_params *p);

/* Exact front-to-back compositing of frags (any order; sorted internally) over bg. */
void lc_foo_composite_exact(const lc_fragment *frags, size_t n, const double bg[3], double out[3]);
/* FOO compositing (P4..P6): optical depth series with m bands, weights by
 * estimator, normalized (Eq. 19), exact background transmittance. alpha clamped
 * to [0, 0.9999]. Writes the background transmittance to *transmittance if not NULL. */
void lc_foo_composite_fourier(const lc_fragment *frags, size_t n, int m, lc_estimator est, const double bg[3],
                              double out[3], double *transmittance);
/* The baselines at equal memory (FOO §5.3), alpha clamped as above.
 * Weighted average (Bavoil & Myers 2008): C = (sum a c / sum a)(1 - (1 - a_mean)^n) + (1 - a_mean)^n bg,
 * a_mean = sum a / n (weighted_average.glsl). */
void lc_foo_composite_weighted_average(const lc_fragment *frags, size_t n, const double bg[3], double out[3]);
/* Binning: f = -ln(1 - alpha) summed into `bins` equal bins of depth [0, 1]; tau(d) = the bins before d's plus
 * its own bin times d's position in it; then the weights of estimator and the resolve of
 * lc_foo_composite_fourier, the background transmittance exp(-sum f) exact (method "binning"). */
void lc_foo_composite_binned(const lc_fragment *frags, size_t n, int bins, lc_estimator est, const double bg[3],
                             double out[3]);

/* Same normalized compositing but with the exact tau(d_i) (sum of -ln(1-alpha)
 * of fragments strictly in front): equals lc_foo_composite_exact. */
void lc_foo_composite_normalized_exact_tau(const lc_fragment *frags, size_t n, const double bg[3], double out[3]);

/* One Laplacian smoothing iteration over a CSR adjacency: dst[e] = src[e] + omega
 * (mean(neighbours) - src[e]); elements without neighbours keep their value. */
void lc_foo_smooth_step(const float *src, float *dst, uint32_t count, const uint32_t *adj_offsets, const uint32_t *adj,
                        double omega);
/* The same with a weight per CSR entry (params.smoothingWeights "distance",
 * lc_elements_adjacency_weights): dst[e] = src[e] + omega (sum w src / sum w
 * - src[e]) over the neighbours. */
void lc_foo_smooth_step_weighted(const float *src, float *dst, uint32_t count, const uint32_t *adj_offsets,
                                 const uint32_t *adj, const float *weights, double omega);
/* Fading factor 1 - 2^(-dt/half_life); 1 when half_life <= 0. */
double lc_foo_fade_factor(double dt, double half_life);

#ifdef __cplusplus
}
#endif
#endif
