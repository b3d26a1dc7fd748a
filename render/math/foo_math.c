/* CPU reference of the FOO formulas (docs/ALGORITHM.md) on explicit per-pixel fragment lists: the ground truth the
 * shaders and the exact (linked-list) renderer are tested against. Plain double math, no GL, no allocation
 * beyond a per-call sort index. */
#include "foo_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Alpha ceiling of the optical-depth path (P4): keeps -ln(1 - alpha) finite. */
#define ALPHA_MAX 0.9999

static int clamp_bands(int m) { return m < LC_MIN_BANDS ? LC_MIN_BANDS : m > LC_MAX_BANDS ? LC_MAX_BANDS : m; }

static double clamp01(double x) { return !(x > 0) ? 0 : x > 1 ? 1 : x; /* NaN -> 0 */ }

void lc_fourier_init(lc_fourier *f, int m)
{
    memset(f, 0, sizeof *f);
    f->m = clamp_bands(m);
}

void lc_fourier_add(lc_fourier *f, double d, double value)
{
    /* FOO Eq. 8 without its factor 2. k = 0 separately: cos(0) = 1 and sin(0) = 0 exactly, so A_0 is the
     * plain sum and F(1) = A_0 holds. */
    f->a[0] += value;
    for (int k = 1; k <= f->m; k++) {
        double phase = 2.0 * M_PI * k * d;
        f->a[k] += value * cos(phase);
        f->b[k] += value * sin(phase);
    }
}

double lc_fourier_eval(const lc_fourier *f, double d)
{
    /* Integral over [0, d] of the band-limited delta train A_0 + 2 sum_k (A_k cos + B_k sin); the papers'
     * a_k = 2 A_k, b_k = 2 B_k (FOO Eq. 5 with the discrete coefficients of Eq. 8). */
    double sum = f->a[0] * d;
    for (int k = 1; k <= f->m; k++) {
        double phase = 2.0 * M_PI * k * d;
        sum += (f->a[k] * sin(phase) + f->b[k] * (1.0 - cos(phase))) / (M_PI * k);
    }
    return sum;
}

double lc_foo_normalize_depth(double z, double zmin, double zmax, double delta)
{
    /* A degenerate range puts everything in the middle: all fragments at one depth are then equally in front
     * and behind, and far from the periodic seam at 0/1. */
    if (!(zmax > zmin))
        return 0.5;
    double d = delta + (1.0 - 2.0 * delta) * (z - zmin) / (zmax - zmin);
    if (isnan(d))
        return 0.5;
    return clamp01(d);
}

double lc_foo_optimal_alpha(double g, double front, double behind, double q, double r, double lambda)
{
    /* FOO Eq. 10 with p = 1; r weighs importance in front, q importance behind (Eq. 10 and the public DOO
     * codes agree; FOO Eq. 1 has them swapped). g is clamped so (1 - g)^(2 lambda) stays real. */
    g = clamp01(g);
    double occlusion = r * fmax(front, 0.0) + q * fmax(behind, 0.0);
    double emphasis = pow(1.0 - g, 2.0 * lambda);
    return 1.0 / (1.0 + emphasis * occlusion);
}

/* Stable depth order: sort (depth, list index) pairs; the index breaks ties so equal depths keep list order. */
typedef struct depth_key {
    double depth;
    size_t index;
} depth_key;

static int compare_depth_key(const void *pa, const void *pb)
{
    const depth_key *a = pa, *b = pb;
    if (a->depth < b->depth)
        return -1;
    if (a->depth > b->depth)
        return 1;
    return (a->index > b->index) - (a->index < b->index);
}

/* Returns a malloc'd front-to-back order of frags (caller frees), or NULL when n == 0 or out of memory. */
static size_t *depth_order(const lc_fragment *frags, size_t n)
{
    if (n == 0)
        return NULL;
    depth_key *keys = malloc(n * sizeof *keys);
    size_t *order = malloc(n * sizeof *order);
    if (!keys || !order) {
        free(keys);
        free(order);
        return NULL;
    }
    for (size_t i = 0; i < n; i++) {
        keys[i].depth = isnan(frags[i].depth) ? 0 : frags[i].depth;
        keys[i].index = i;
    }
    qsort(keys, n, sizeof *keys, compare_depth_key);
    for (size_t i = 0; i < n; i++)
        order[i] = keys[i].index;
    free(keys);
    return order;
}

lc_depth_range lc_foo_depth_range(const lc_foo_params *p)
{
    if (p->depth_range != LC_DEPTH_RANGE_AUTO)
        return p->depth_range;
    return p->normalize == LC_NORMALIZE_AUTO ? LC_DEPTH_RANGE_MOMENTS : LC_DEPTH_RANGE_GLOBAL;
}

double lc_foo_moment_depth(double d, const double m[3], double delta)
{
    if (!(m[0] > 0))
        return d;
    double mu = m[1] / m[0];
    double sigma = sqrt(fmax(m[2] / m[0] - mu * mu, 0.0));
    double s = fmax(sigma, LC_MOMENT_MIN_SPREAD);
    double t = 1.0 / (1.0 + exp(-((d - 0.5) - mu) / s));
    return delta + (1.0 - 2.0 * delta) * t;
}

double lc_foo_norm_mass(const lc_foo_params *p)
{
    return p->normalize == LC_NORMALIZE_AUTO ? LC_NORM_REFERENCE_MASS : 0.0;
}

double lc_foo_effective_lambda(const lc_foo_params *p, double k)
{
    return p->normalize == LC_NORMALIZE_AUTO ? (1.0 + LC_NORM_EMPHASIS * (1.0 - k) * (1.0 - k)) * p->lambda : p->lambda;
}

double lc_foo_norm_factor(const lc_foo_params *p, double total)
{
    double ref = lc_foo_norm_mass(p);
    return ref > 0 && total > ref ? ref / total : 1.0;
}

double lc_foo_target_opacity(const lc_foo_params *p)
{
    return p->target_opacity > 0 && p->target_opacity <= 1 ? p->target_opacity : 1.0;
}

double lc_foo_kanzler_rho(const lc_foo_params *p, double g, double d, double C, double M, double D, double V)
{
    double less = d < D - 1.0 / 65535.0 ? 1.0 : 0.0;
    double P = p->kanzler_importance * M + p->kanzler_coverage * C + p->kanzler_variance * V + p->kanzler_depth * less;
    return 1.0 / (1.0 + (1.0 - pow(clamp01(g), p->kanzler_lambda)) * P);
}

double lc_foo_direction_variance(const double *t, int n)
{
    if (n <= 0)
        return 0;
    double s[3] = {0, 0, 0};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            s[k] += t[3 * i + k];
    return 1.0 - sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) / n;
}

double lc_foo_silhouette_alpha(double alpha, double eta, double s)
{
    if (!(eta > 1))
        return alpha;
    return 1.0 - pow(1.0 - clamp01(alpha), 1.0 + (eta - 1.0) * clamp01(s));
}

void lc_foo_alpha_exact(lc_fragment *frags, size_t n, const lc_foo_params *p)
{
    size_t *order = depth_order(frags, n);
    if (!order)
        return;
    double total = 0;
    for (size_t i = 0; i < n; i++)
        total += frags[i].importance * frags[i].importance;
    double k = lc_foo_norm_factor(p, total), lambda = lc_foo_effective_lambda(p, k);
    double t = lc_foo_target_opacity(p);
    /* DOO's exact sums: front = sum of g^2 strictly in front, behind = strictly behind; the fragment's own g^2
     * is in neither. behind is total - front - own, computed as a running sum to avoid cancellation. */
    double front = 0;
    for (size_t s = 0; s < n; s++) {
        lc_fragment *fr = &frags[order[s]];
        double own = fr->importance * fr->importance;
        double behind = total - front - own;
        fr->alpha = t * lc_foo_optimal_alpha(fr->importance, k * front, k * behind, p->q, p->r, lambda);
        front += own;
    }
    free(order);
}

void lc_foo_alpha_fourier(lc_fragment *frags, size_t n, const lc_foo_params *p)
{
    /* P1: project g^2 into the bands. */
    lc_fourier importance_coeffs;
    lc_fourier_init(&importance_coeffs, p->bands);
    for (size_t i = 0; i < n; i++)
        lc_fourier_add(&importance_coeffs, frags[i].depth, frags[i].importance * frags[i].importance);
    double total = importance_coeffs.a[0];
    double k = lc_foo_norm_factor(p, total), lambda = lc_foo_effective_lambda(p, k);
    double t = lc_foo_target_opacity(p);

    /* P2: sample G at the fragment's depth. The truncated series passes a step at its midpoint, so G holds about
     * half of the fragment's own g^2; FOO subtracts all of it from the front, the midpoint estimator half from
     * each side (docs/ALGORITHM.md). Negative sums are clamped inside lc_foo_optimal_alpha. */
    for (size_t i = 0; i < n; i++) {
        lc_fragment *fr = &frags[i];
        double own = fr->importance * fr->importance;
        double G = lc_fourier_eval(&importance_coeffs, fr->depth);
        double front, behind;
        if (p->estimator == LC_ESTIMATOR_MIDPOINT) {
            front = G - 0.5 * own;
            behind = total - G - 0.5 * own;
        } else {
            front = G - own; /* FOO Eq. 10 with G(d_i) including the fragment */
            behind = total - G;
        }
        fr->alpha = t * lc_foo_optimal_alpha(fr->importance, k * front, k * behind, p->q, p->r, lambda);
    }
}

void lc_foo_composite_exact(const lc_fragment *frags, size_t n, const double bg[3], double out[3])
{
    /* Front-to-back "over": C = sum C_i alpha_i prod_{j<i}(1 - alpha_j) + bg prod_j (1 - alpha_j). */
    double color[3] = {0, 0, 0};
    double transmittance = 1;
    size_t *order = depth_order(frags, n);
    for (size_t s = 0; order && s < n; s++) {
        const lc_fragment *fr = &frags[order[s]];
        double alpha = clamp01(fr->alpha);
        for (int c = 0; c < 3; c++)
            color[c] += fr->color[c] * alpha * transmittance;
        transmittance *= 1.0 - alpha;
    }
    free(order);
    for (int c = 0; c < 3; c++)
        out[c] = color[c] + bg[c] * transmittance;
}

/* FOO Eq. 19: the fragments as one weighted-average layer over the background with exact transmittance. */
static void resolve(const double weighted_color[3], double weight_sum, double transmittance, const double bg[3],
                    double out[3])
{
    for (int c = 0; c < 3; c++) {
        if (weight_sum > 0)
            out[c] = weighted_color[c] / weight_sum * (1.0 - transmittance) + bg[c] * transmittance;
        else
            out[c] = bg[c];
    }
}

static double clamped_alpha(double alpha)
{
    return !(alpha > 0) ? 0 : alpha > ALPHA_MAX ? ALPHA_MAX : alpha; /* NaN -> 0 */
}

void lc_foo_composite_fourier(const lc_fragment *frags, size_t n, int m, lc_estimator est, const double bg[3],
                              double out[3], double *transmittance)
{
    /* P4: project the optical depth f = -ln(1 - alpha) (FOO Eqs. 16-17). */
    lc_fourier optical_depth;
    lc_fourier_init(&optical_depth, m);
    for (size_t i = 0; i < n; i++)
        lc_fourier_add(&optical_depth, frags[i].depth, -log1p(-clamped_alpha(frags[i].alpha)));

    /* P5: weights from tau(d_i). FOO: alpha/(1 - alpha) e^-tau, which is exact when tau includes the whole
     * fragment; the series holds about half of it, so the midpoint estimator removes that half instead. */
    double weighted_color[3] = {0, 0, 0}, weight_sum = 0;
    for (size_t i = 0; i < n; i++) {
        const lc_fragment *fr = &frags[i];
        double alpha = clamped_alpha(fr->alpha);
        double tau = fmax(lc_fourier_eval(&optical_depth, fr->depth), 0.0);
        double w;
        if (est == LC_ESTIMATOR_MIDPOINT)
            w = alpha * exp(-fmax(tau + 0.5 * log1p(-alpha), 0.0)); /* tau - f_i/2, f_i = -ln(1 - alpha) */
        else
            w = alpha / (1.0 - alpha) * exp(-tau);
        for (int c = 0; c < 3; c++)
            weighted_color[c] += w * fr->color[c];
        weight_sum += w;
    }

    /* P6: e^-A''_0 = prod (1 - alpha_i) exactly (FOO Eq. 18). */
    double T = exp(-optical_depth.a[0]);
    resolve(weighted_color, weight_sum, T, bg, out);
    if (transmittance)
        *transmittance = T;
}

/* P5's weight of a fragment behind optical depth tau (composite_weight in common.glsl). */
static double composite_weight(double alpha, double tau, lc_estimator est)
{
    if (est == LC_ESTIMATOR_MIDPOINT)
        return alpha * exp(-fmax(tau + 0.5 * log1p(-alpha), 0.0));
    return alpha / (1.0 - alpha) * exp(-tau);
}

void lc_foo_composite_weighted_average(const lc_fragment *frags, size_t n, const double bg[3], double out[3])
{
    double sum_color[3] = {0, 0, 0}, sum_alpha = 0;
    for (size_t i = 0; i < n; i++) {
        double a = clamped_alpha(frags[i].alpha);
        for (int c = 0; c < 3; c++)
            sum_color[c] += a * frags[i].color[c];
        sum_alpha += a;
    }
    double T = n > 0 ? pow(1.0 - sum_alpha / (double)n, (double)n) : 1.0;
    resolve(sum_color, sum_alpha, T, bg, out);
}

void lc_foo_composite_binned(const lc_fragment *frags, size_t n, int bins, lc_estimator est, const double bg[3],
                             double out[3])
{
    double bin[64] = {0}, total = 0;
    bins = bins < 1 ? 1 : bins > 64 ? 64 : bins;
    for (size_t i = 0; i < n; i++) {
        double f = -log1p(-clamped_alpha(frags[i].alpha));
        int k = (int)(fmin(fmax(frags[i].depth, 0.0), 1.0) * bins);
        bin[k < bins ? k : bins - 1] += f;
        total += f;
    }
    double weighted_color[3] = {0, 0, 0}, weight_sum = 0;
    for (size_t i = 0; i < n; i++) {
        double x = fmin(fmax(frags[i].depth, 0.0), 1.0) * bins, tau = 0;
        int k = (int)x < bins ? (int)x : bins - 1;
        for (int j = 0; j < k; j++)
            tau += bin[j];
        tau += (x - k) * bin[k];
        double w = composite_weight(clamped_alpha(frags[i].alpha), tau, est);
        for (int c = 0; c < 3; c++)
            weighted_color[c] += w * frags[i].color[c];
        weight_sum += w;
    }
    resolve(weighted_color, weight_sum, exp(-total), bg, out);
}

void lc_foo_composite_normalized_exact_tau(const lc_fragment *frags, size_t n, const double bg[3], double out[3])
{
    /* Eq. 19 with the exact optical depth. With tau_i = sum_{j<i} f_j (strictly in front), the FOO weight over
     * the inclusive depth, alpha_i/(1 - alpha_i) e^-(tau_i + f_i), equals alpha_i e^-tau_i = alpha_i
     * prod_{j<i}(1 - alpha_j), the exact front-to-back weight; the form used here also holds at alpha = 1.
     * The weights then sum to 1 - T, so normalization changes nothing and this equals exact compositing. */
    double weighted_color[3] = {0, 0, 0}, weight_sum = 0, tau = 0;
    size_t *order = depth_order(frags, n);
    for (size_t s = 0; order && s < n; s++) {
        const lc_fragment *fr = &frags[order[s]];
        double alpha = clamp01(fr->alpha);
        double w = alpha * exp(-tau);
        for (int c = 0; c < 3; c++)
            weighted_color[c] += w * fr->color[c];
        weight_sum += w;
        tau += -log1p(-alpha); /* +inf at alpha = 1: everything behind gets weight 0 */
    }
    free(order);
    resolve(weighted_color, weight_sum, exp(-tau), bg, out);
}

void lc_foo_smooth_step(const float *src, float *dst, uint32_t count, const uint32_t *adj_offsets, const uint32_t *adj,
                        double omega)
{
    /* Jacobi-style Laplacian step (docs/ALGORITHM.md §4 P3): reads only src, so src and dst must not alias. Neighbour
     * indices outside [0, count) are skipped rather than trusted. */
    for (uint32_t e = 0; e < count; e++) {
        double sum = 0;
        uint32_t neighbours = 0;
        for (uint32_t k = adj_offsets[e]; k < adj_offsets[e + 1]; k++) {
            if (adj[k] >= count)
                continue;
            sum += src[adj[k]];
            neighbours++;
        }
        if (neighbours == 0)
            dst[e] = src[e];
        else
            dst[e] = (float)(src[e] + omega * (sum / neighbours - src[e]));
    }
}

void lc_foo_smooth_step_weighted(const float *src, float *dst, uint32_t count, const uint32_t *adj_offsets,
                                 const uint32_t *adj, const float *weights, double omega)
{
    for (uint32_t e = 0; e < count; e++) {
        double sum = 0, wsum = 0;
        for (uint32_t k = adj_offsets[e]; k < adj_offsets[e + 1]; k++) {
            if (adj[k] >= count)
                continue;
            sum += (double)weights[k] * src[adj[k]];
            wsum += weights[k];
        }
        dst[e] = wsum > 0 ? (float)(src[e] + omega * (sum / wsum - src[e])) : src[e];
    }
}

double lc_foo_fade_factor(double dt, double half_life)
{
    /* alpha_cur += (alpha_target - alpha_cur)(1 - 2^(-dt/t_half)): frame-rate independent exponential decay. */
    if (!(half_life > 0))
        return 1.0;
    if (!(dt > 0))
        return 0.0;
    return 1.0 - exp2(-dt / half_life);
}
