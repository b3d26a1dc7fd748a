/* Unit tests of the CPU FOO reference (render/foo_math.c) against exact sums and exact compositing on explicit
 * fragment lists, plus the FOO-vs-midpoint estimator comparison that docs/ALGORITHM.md reports. */
#include <stdint.h>
#include <string.h>

#include "foo_math.h"
#include "lc_test.h"

#define MAX_FRAGS 40
#define DELTA 0.02

/* splitmix64: fixed seed, so every run sees the same fragment lists. */
static uint64_t rng_state = 0x5eed1234abcdULL;

static double uniform(void)
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return (double)(z >> 11) / 9007199254740992.0; /* [0, 1) */
}

static int uniform_int(int lo, int hi) { return lo + (int)(uniform() * (hi - lo + 1)); }

/* A random pixel: n fragments with depths inside the margin, importance, alpha and colour in [0,1). */
static void random_stack(lc_fragment *frags, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        frags[i].depth = DELTA + (1 - 2 * DELTA) * uniform();
        frags[i].importance = uniform();
        frags[i].alpha = uniform();
        for (int c = 0; c < 3; c++)
            frags[i].color[c] = uniform();
    }
}

static int compare_double(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

static double exact_running_sum(const double *depth, const double *value, size_t n, double d)
{
    double sum = 0;
    for (size_t i = 0; i < n; i++)
        if (depth[i] <= d)
            sum += value[i];
    return sum;
}

static void test_fourier_reconstruction(void)
{
    enum { LISTS = 300 };
    double mean_error[LC_MAX_BANDS + 1] = {0};
    printf("Fourier running-sum reconstruction, %d random lists of 2-40 fragments, sampled between fragments\n", LISTS);
    printf("   m   mean |F(d) - exact|\n");
    for (int m = LC_MIN_BANDS; m <= LC_MAX_BANDS; m++) {
        rng_state = 42; /* same lists for every m */
        double error_sum = 0;
        long samples = 0;
        for (int l = 0; l < LISTS; l++) {
            size_t n = (size_t)uniform_int(2, MAX_FRAGS);
            double depth[MAX_FRAGS], value[MAX_FRAGS], sorted[MAX_FRAGS];
            lc_fourier f;
            lc_fourier_init(&f, m);
            double total = 0;
            for (size_t i = 0; i < n; i++) {
                depth[i] = DELTA + (1 - 2 * DELTA) * uniform();
                value[i] = uniform();
                total += value[i];
                lc_fourier_add(&f, depth[i], value[i]);
            }
            CHECK(f.m == m, "m stored: %d vs %d", f.m, m);
            CHECK_NEAR(f.a[0], total, 1e-12, "A_0 is the plain sum");
            /* F(1) = A_0 (FOO Eq. 7) to float precision: the GPU targets are RGBA32F. */
            CHECK(fabs(lc_fourier_eval(&f, 1.0) - f.a[0]) <= 1e-6 * (1 + f.a[0]), "F(1) %.9g vs A_0 %.9g",
                  lc_fourier_eval(&f, 1.0), f.a[0]);
            CHECK_NEAR(lc_fourier_eval(&f, 0.0), 0.0, 1e-12, "F(0) = 0");

            memcpy(sorted, depth, n * sizeof *depth);
            qsort(sorted, n, sizeof *sorted, compare_double);
            for (size_t i = 0; i + 1 < n; i++) {
                double d = 0.5 * (sorted[i] + sorted[i + 1]);
                error_sum += fabs(lc_fourier_eval(&f, d) - exact_running_sum(depth, value, n, d));
                samples++;
            }
        }
        mean_error[m] = error_sum / (double)samples;
        printf("   %d   %.5f\n", m, mean_error[m]);
    }
    CHECK(mean_error[8] < 0.5 * mean_error[1], "error(m=8) %.5f not clearly below error(m=1) %.5f", mean_error[8],
          mean_error[1]);
    /* Monotone-ish: truncation error of step functions falls roughly like 1/m; allow small wiggles. */
    for (int m = LC_MIN_BANDS + 1; m <= LC_MAX_BANDS; m++)
        CHECK(mean_error[m] < 1.05 * mean_error[m - 1], "error(m=%d) %.5f vs error(m=%d) %.5f", m, mean_error[m], m - 1,
              mean_error[m - 1]);

    /* One fragment: the coefficients are the plain cosine/sine of its phase. */
    lc_fourier f;
    lc_fourier_init(&f, 3);
    lc_fourier_add(&f, 0.125, 2.0);
    CHECK_NEAR(f.a[1], 2.0 * cos(2 * M_PI * 0.125), 1e-12, "A_1");
    CHECK_NEAR(f.b[2], 2.0 * sin(2 * M_PI * 0.25), 1e-12, "B_2");
    CHECK_NEAR(f.b[0], 0.0, 0.0, "B_0");
    lc_fourier_init(&f, 0);
    CHECK(f.m == LC_MIN_BANDS, "m clamped up to %d, got %d", LC_MIN_BANDS, f.m);
    lc_fourier_init(&f, 99);
    CHECK(f.m == LC_MAX_BANDS, "m clamped down to %d, got %d", LC_MAX_BANDS, f.m);
}

static void test_normalize_depth(void)
{
    CHECK_NEAR(lc_foo_normalize_depth(2.0, 2.0, 6.0, 0.02), 0.02, 1e-15, "zmin -> delta");
    CHECK_NEAR(lc_foo_normalize_depth(6.0, 2.0, 6.0, 0.02), 0.98, 1e-15, "zmax -> 1 - delta");
    CHECK_NEAR(lc_foo_normalize_depth(4.0, 2.0, 6.0, 0.02), 0.5, 1e-15, "middle");
    CHECK_NEAR(lc_foo_normalize_depth(-100.0, 2.0, 6.0, 0.02), 0.0, 0.0, "clamped below");
    CHECK_NEAR(lc_foo_normalize_depth(100.0, 2.0, 6.0, 0.02), 1.0, 0.0, "clamped above");
    CHECK_NEAR(lc_foo_normalize_depth(3.0, 3.0, 3.0, 0.02), 0.5, 0.0, "degenerate range");
}

static void test_optimal_alpha(void)
{
    /* (1 - 0.5)^2 = 0.25; r front + q behind = 5*2 + 3*1 = 13; 1 / (1 + 3.25) */
    CHECK_NEAR(lc_foo_optimal_alpha(0.5, 2, 1, 3, 5, 1), 1.0 / 4.25, 1e-12, "hand case lambda 1");
    /* lambda 2: 0.0625 * 13 = 0.8125 */
    CHECK_NEAR(lc_foo_optimal_alpha(0.5, 2, 1, 3, 5, 2), 1.0 / 1.8125, 1e-12, "hand case lambda 2");
    CHECK_NEAR(lc_foo_optimal_alpha(1.0, 10, 10, 100, 100, 1), 1.0, 0.0, "g = 1 stays opaque");
    CHECK_NEAR(lc_foo_optimal_alpha(0.3, -5, -5, 100, 100, 1), 1.0, 0.0, "negative sums clamp to 0");

    lc_foo_params p;
    lc_foo_params_default(&p);
    p.normalize = LC_NORMALIZE_OFF; /* the paper's formula; auto is test_density_normalization */

    /* Three fragments, list order shuffled; middle one (g 0.6) has 0.09 in front and 0.81 behind.
     * q = 2, r = 4, lambda = 1: 0.16 * (4 * 0.09 + 2 * 0.81) = 0.3168. */
    lc_fragment three[3] = {
        {.depth = 0.5, .importance = 0.6}, {.depth = 0.8, .importance = 0.9}, {.depth = 0.2, .importance = 0.3}};
    p.q = 2, p.r = 4, p.lambda = 1;
    lc_foo_alpha_exact(three, 3, &p);
    CHECK_NEAR(three[0].alpha, 1.0 / 1.3168, 1e-12, "middle fragment");
    /* front (g 0.3): 0.49 * (2 * (0.36 + 0.81)) = 1.1466 */
    CHECK_NEAR(three[2].alpha, 1.0 / 2.1466, 1e-12, "front fragment");
    /* back (g 0.9): 0.01 * (4 * (0.09 + 0.36)) = 0.018 */
    CHECK_NEAR(three[1].alpha, 1.0 / 1.018, 1e-12, "back fragment");

    /* r weighs importance in front, q behind (FOO Eq. 10). An unimportant fragment in front of an important
     * one has only importance behind it: q > 0 clears it, q = 0 leaves it opaque whatever r is. */
    lc_fragment pair[2] = {{.depth = 0.2, .importance = 0.0}, {.depth = 0.8, .importance = 1.0}};
    p.q = 10, p.r = 0, p.lambda = 1;
    lc_foo_alpha_exact(pair, 2, &p);
    CHECK_NEAR(pair[0].alpha, 1.0 / 11.0, 1e-12, "q clears the occluder");
    CHECK_NEAR(pair[1].alpha, 1.0, 0.0, "important fragment stays");
    p.q = 0, p.r = 100;
    lc_foo_alpha_exact(pair, 2, &p);
    CHECK_NEAR(pair[0].alpha, 1.0, 0.0, "q = 0: occluder stays opaque");
    /* Swap depths: the unimportant fragment is now behind, so r acts on it. */
    pair[0].depth = 0.9;
    lc_foo_alpha_exact(pair, 2, &p);
    CHECK_NEAR(pair[0].alpha, 1.0 / 101.0, 1e-12, "r clears the background clutter");

    /* Equal depths: after the stable sort, earlier in the list is in front. */
    lc_fragment tie[2] = {{.depth = 0.5, .importance = 0.0}, {.depth = 0.5, .importance = 1.0}};
    p.q = 10, p.r = 0;
    lc_foo_alpha_exact(tie, 2, &p);
    CHECK_NEAR(tie[0].alpha, 1.0 / 11.0, 1e-12, "tie: first in list is in front");

    /* The Fourier path with both estimators, written out by hand from the series. */
    lc_fragment frags[6];
    rng_state = 7;
    random_stack(frags, 6);
    p.q = 3, p.r = 7, p.lambda = 1.5, p.bands = 4;
    lc_fourier G;
    lc_fourier_init(&G, 4);
    for (int i = 0; i < 6; i++)
        lc_fourier_add(&G, frags[i].depth, frags[i].importance * frags[i].importance);
    for (int est = 0; est < 2; est++) {
        p.estimator = (lc_estimator)est;
        lc_foo_alpha_fourier(frags, 6, &p);
        for (int i = 0; i < 6; i++) {
            double g = frags[i].importance, Gi = lc_fourier_eval(&G, frags[i].depth);
            double front = est ? Gi - g * g / 2 : Gi - g * g;
            double behind = est ? G.a[0] - Gi - g * g / 2 : G.a[0] - Gi;
            double expect = 1.0 / (1.0 + pow(1 - g, 3.0) * (7 * fmax(front, 0) + 3 * fmax(behind, 0)));
            CHECK_NEAR(frags[i].alpha, expect, 1e-12, est ? "midpoint alpha" : "foo alpha");
        }
    }
}

static void test_compositing_identities(void)
{
    const double bg[3] = {0.2, 0.5, 0.9};
    double max_diff = 0, max_t_diff = 0;
    rng_state = 99;
    for (int l = 0; l < 500; l++) {
        lc_fragment frags[MAX_FRAGS];
        size_t n = (size_t)uniform_int(1, MAX_FRAGS);
        random_stack(frags, n);
        for (size_t i = 0; i < n; i++)
            frags[i].alpha *= 0.99;
        if (l % 50 == 0)
            frags[0].alpha = 1.0; /* a fully opaque fragment hides everything behind it */
        if (l % 70 == 0)
            frags[n - 1].depth = frags[0].depth; /* a depth tie */

        double exact[3], normalized[3];
        lc_foo_composite_exact(frags, n, bg, exact);
        lc_foo_composite_normalized_exact_tau(frags, n, bg, normalized);
        for (int c = 0; c < 3; c++)
            max_diff = fmax(max_diff, fabs(exact[c] - normalized[c]));

        /* Background transmittance is exact for any m (FOO Eq. 18), with alpha clamped to 0.9999. */
        double product = 1;
        for (size_t i = 0; i < n; i++)
            product *= 1 - fmin(frags[i].alpha, 0.9999);
        for (int m = LC_MIN_BANDS; m <= LC_MAX_BANDS; m++) {
            double out[3], T = -1;
            lc_foo_composite_fourier(frags, n, m, (lc_estimator)(m & 1), bg, out, &T);
            max_t_diff = fmax(max_t_diff, fabs(T - product));
        }
    }
    CHECK(max_diff <= 1e-5, "normalized compositing with exact tau vs exact: max diff %.3g", max_diff);
    CHECK(max_t_diff <= 1e-9, "background transmittance vs prod(1 - alpha): max diff %.3g", max_t_diff);

    /* Hand case: red 0.5 over green 0.5 over blue background: 0.5 R + 0.25 G + 0.25 B. */
    lc_fragment two[2] = {{.depth = 0.7, .alpha = 0.5, .color = {0, 1, 0}},
                          {.depth = 0.3, .alpha = 0.5, .color = {1, 0, 0}}};
    const double blue[3] = {0, 0, 1};
    double out[3];
    lc_foo_composite_exact(two, 2, blue, out);
    CHECK(fabs(out[0] - 0.5) < 1e-12 && fabs(out[1] - 0.25) < 1e-12 && fabs(out[2] - 0.25) < 1e-12, "over: %g %g %g",
          out[0], out[1], out[2]);

    /* No fragments: the background, with transmittance 1. */
    double T = 0;
    lc_foo_composite_fourier(NULL, 0, 5, LC_ESTIMATOR_FOO, bg, out, &T);
    CHECK(out[0] == bg[0] && out[1] == bg[1] && out[2] == bg[2] && T == 1.0, "empty pixel: %g %g %g T %g", out[0],
          out[1], out[2], T);
    lc_foo_composite_exact(NULL, 0, bg, out);
    CHECK(out[0] == bg[0] && out[2] == bg[2], "empty exact pixel");
    lc_foo_composite_normalized_exact_tau(NULL, 0, bg, out);
    CHECK(out[0] == bg[0] && out[2] == bg[2], "empty normalized pixel");
}

static void test_smoothing_and_fading(void)
{
    /* Chain 0-1-2-3-4 plus an isolated element 5. */
    const uint32_t chain_offsets[7] = {0, 1, 3, 5, 7, 8, 8};
    const uint32_t chain_adj[8] = {1, 0, 2, 1, 3, 2, 4, 3};
    const float src[6] = {1.0f, 0.0f, 1.0f, 0.2f, 0.6f, 0.3f};
    float dst[6];
    const double omega = 0.1;
    lc_foo_smooth_step(src, dst, 6, chain_offsets, chain_adj, omega);
    CHECK_NEAR(dst[0], 1.0 + omega * (0.0 - 1.0), 1e-6, "end of chain");
    CHECK_NEAR(dst[1], 0.0 + omega * (1.0 - 0.0), 1e-6, "inner element");
    CHECK_NEAR(dst[3], 0.2 + omega * (0.8 - 0.2), 1e-6, "inner element 3");
    CHECK(dst[5] == src[5], "isolated element unchanged: %g", dst[5]);
    for (int e = 0; e < 5; e++) {
        double mean = 0;
        for (uint32_t k = chain_offsets[e]; k < chain_offsets[e + 1]; k++)
            mean += src[chain_adj[k]];
        mean /= chain_offsets[e + 1] - chain_offsets[e];
        CHECK(fabs(dst[e] - mean) < fabs(src[e] - mean) || src[e] == mean, "element %d moves toward %g", e, mean);
    }

    /* A ring (every element has degree 2): s iterations keep the sum and shrink the spread. */
    enum { RING = 16 };
    uint32_t ring_offsets[RING + 1], ring_adj[2 * RING];
    float a[RING], b[RING];
    double sum0 = 0;
    rng_state = 5;
    for (uint32_t e = 0; e < RING; e++) {
        ring_offsets[e] = 2 * e;
        ring_adj[2 * e] = (e + RING - 1) % RING;
        ring_adj[2 * e + 1] = (e + 1) % RING;
        a[e] = (float)uniform();
        sum0 += a[e];
    }
    ring_offsets[RING] = 2 * RING;
    float lo0 = 1, hi0 = 0;
    for (int e = 0; e < RING; e++)
        lo0 = fminf(lo0, a[e]), hi0 = fmaxf(hi0, a[e]);
    for (int it = 0; it < 15; it++) {
        lc_foo_smooth_step(a, b, RING, ring_offsets, ring_adj, 0.1);
        memcpy(a, b, sizeof a);
    }
    double sum1 = 0;
    float lo1 = 1, hi1 = 0;
    for (int e = 0; e < RING; e++)
        sum1 += a[e], lo1 = fminf(lo1, a[e]), hi1 = fmaxf(hi1, a[e]);
    CHECK_NEAR(sum1, sum0, 1e-5, "ring sum preserved");
    CHECK(hi1 - lo1 < hi0 - lo0, "spread shrinks: %g -> %g", hi0 - lo0, hi1 - lo1);

    CHECK_NEAR(lc_foo_fade_factor(0.15, 0.15), 0.5, 1e-15, "half-life");
    CHECK_NEAR(lc_foo_fade_factor(0.30, 0.15), 0.75, 1e-15, "two half-lives");
    CHECK_NEAR(lc_foo_fade_factor(0.05, 0.0), 1.0, 0.0, "no fading");
    CHECK_NEAR(lc_foo_fade_factor(0.0, 0.15), 0.0, 0.0, "no time passed");
    CHECK_NEAR(lc_foo_fade_factor(1e9, 0.15), 1.0, 1e-15, "long pause");
}

/* Mean errors of both estimators over random stacks of 2-40 fragments for m = 3..8: per-pixel mean |alpha -
 * exact alpha| (P2) and mean |colour - exact colour| (P4-P6). The compositing uses the exact optimal opacities
 * (what P4 blends) or, with random_alpha, uniform random ones. Prints the table when verbose. */
static void estimator_errors(double q, double r, double lambda, int random_alpha, int verbose, double alpha_err[2],
                             double color_err[2])
{
    enum { STACKS = 1000 };
    const double bg[3] = {1, 1, 1};
    lc_foo_params p;
    lc_foo_params_default(&p);
    p.q = q, p.r = r, p.lambda = lambda;
    alpha_err[0] = alpha_err[1] = color_err[0] = color_err[1] = 0;
    if (verbose)
        printf("   m   opacity err foo  midpoint   colour err foo  midpoint\n");
    for (int m = 3; m <= 8; m++) {
        double a_m[2] = {0, 0}, c_m[2] = {0, 0};
        rng_state = 1000 + (uint64_t)m;
        p.bands = m;
        for (int s = 0; s < STACKS; s++) {
            lc_fragment frags[MAX_FRAGS], exact[MAX_FRAGS];
            size_t n = (size_t)uniform_int(2, MAX_FRAGS);
            random_stack(frags, n);
            memcpy(exact, frags, n * sizeof *frags);
            lc_foo_alpha_exact(exact, n, &p);
            const lc_fragment *blend = random_alpha ? frags : exact;
            double exact_color[3];
            lc_foo_composite_exact(blend, n, bg, exact_color);
            for (int est = 0; est < 2; est++) {
                lc_fragment approx[MAX_FRAGS];
                memcpy(approx, frags, n * sizeof *frags);
                p.estimator = (lc_estimator)est;
                lc_foo_alpha_fourier(approx, n, &p);
                double pixel = 0;
                for (size_t i = 0; i < n; i++)
                    pixel += fabs(approx[i].alpha - exact[i].alpha);
                a_m[est] += pixel / (double)n;

                double out[3];
                lc_foo_composite_fourier(blend, n, m, (lc_estimator)est, bg, out, NULL);
                c_m[est] +=
                    (fabs(out[0] - exact_color[0]) + fabs(out[1] - exact_color[1]) + fabs(out[2] - exact_color[2])) / 3;
            }
        }
        for (int est = 0; est < 2; est++) {
            a_m[est] /= STACKS, c_m[est] /= STACKS;
            alpha_err[est] += a_m[est] / 6, color_err[est] += c_m[est] / 6;
        }
        if (verbose)
            printf("   %d   %.5f          %.5f    %.5f         %.5f\n", m, a_m[0], a_m[1], c_m[0], c_m[1]);
    }
}

/* docs/ALGORITHM.md: the midpoint estimator beats FOO's own at equal bands, in opacity and in colour. The margin
 * depends on q, r, lambda and the opacities, so several settings are checked and all are printed. */
static void test_estimators(void)
{
    static const struct {
        const char *name;
        double q, r, lambda;
        int random_alpha;
    } cases[] = {
        {"tornado q=60 r=500 lambda=1", 60, 500, 1, 0}, {"rings q=80 r=40 lambda=1.5", 80, 40, 1.5, 0},
        {"mild q=2 r=5 lambda=1", 2, 5, 1, 0},          {"benzene q=20 r=50 lambda=10", 20, 50, 10, 0},
        {"mild, uniform random alphas", 2, 5, 1, 1},
    };
    printf("Estimators vs exact (1000 random stacks of 2-40 fragments per m, m = 3..8)\n");
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        double alpha_err[2], color_err[2];
        if (c == 0)
            printf(" %s:\n", cases[c].name);
        estimator_errors(cases[c].q, cases[c].r, cases[c].lambda, cases[c].random_alpha, c == 0, alpha_err, color_err);
        printf(" avg %-30s opacity foo %.5f midpoint %.5f (%.2fx)  colour foo %.5f midpoint %.5f (%.2fx)\n",
               cases[c].name, alpha_err[0], alpha_err[1], alpha_err[0] / alpha_err[1], color_err[0], color_err[1],
               color_err[0] / color_err[1]);
        CHECK(alpha_err[1] < alpha_err[0], "%s: midpoint opacity error %.5f not below foo %.5f", cases[c].name,
              alpha_err[1], alpha_err[0]);
        CHECK(color_err[1] < color_err[0], "%s: midpoint colour error %.5f not below foo %.5f", cases[c].name,
              color_err[1], color_err[0]);
    }
}

/* normalize auto: a pixel whose total mass exceeds LC_NORM_REFERENCE_MASS has
 * its sums scaled by k = reference / total and the emphasis exponent raised to
 * lambda (1 + 3 (1 - k)^2); a pixel at or below the reference keeps the paper's formula
 * (only the importance mapping differs). */
static void test_density_normalization(void)
{
    lc_foo_params p;
    lc_foo_params_default(&p);
    CHECK(p.normalize == LC_NORMALIZE_AUTO, "auto is the default");
    p.q = 3, p.r = 7, p.lambda = 1.25;
    CHECK_NEAR(lc_foo_effective_lambda(&p, 1.0), 1.25, 0.0, "auto keeps lambda where the sums are not scaled");
    CHECK_NEAR(lc_foo_effective_lambda(&p, 0.5), 1.75 * 1.25, 1e-15, "auto raises lambda with the density");
    CHECK_NEAR(lc_foo_effective_lambda(&p, 0.0), 4 * 1.25, 0.0, "auto quadruples lambda in the densest pixels");
    CHECK_NEAR(lc_foo_norm_factor(&p, 0.5 * LC_NORM_REFERENCE_MASS), 1.0, 0.0, "sparse pixel: no scaling");
    CHECK_NEAR(lc_foo_norm_factor(&p, 4 * LC_NORM_REFERENCE_MASS), 0.25, 1e-15, "dense pixel: reference / total");

    /* A dense stack written out by hand (exact sums), then the Fourier path's total from A_0. */
    lc_fragment frags[12];
    rng_state = 11;
    random_stack(frags, 12);
    double total = 0;
    for (int i = 0; i < 12; i++)
        total += frags[i].importance * frags[i].importance;
    CHECK(total > LC_NORM_REFERENCE_MASS, "the stack is dense (total %.3f)", total);
    double k = LC_NORM_REFERENCE_MASS / total;
    lc_foo_alpha_exact(frags, 12, &p);
    for (int i = 0; i < 12; i++) {
        double g = frags[i].importance, front = 0, behind = 0;
        for (int j = 0; j < 12; j++)
            if (j != i && (frags[j].depth < frags[i].depth || (frags[j].depth == frags[i].depth && j < i)))
                front += frags[j].importance * frags[j].importance;
        behind = total - front - g * g;
        double expect =
            1.0 / (1.0 + pow(1 - g, 2 * (1 + 3 * (1 - k) * (1 - k)) * 1.25) * k * (7 * front + 3 * fmax(behind, 0)));
        CHECK_NEAR(frags[i].alpha, expect, 1e-9, "normalized exact alpha");
    }
    /* The same stack with normalize off is the paper's formula: never more opaque. */
    lc_fragment off[12];
    memcpy(off, frags, sizeof off);
    p.normalize = LC_NORMALIZE_OFF;
    lc_foo_alpha_exact(off, 12, &p);
    for (int i = 0; i < 12; i++)
        CHECK(off[i].alpha <= frags[i].alpha + 1e-12 || frags[i].importance < 0.5, "off %.4f vs auto %.4f (g %.2f)",
              off[i].alpha, frags[i].alpha, frags[i].importance);
}

/* The importance-mass moments of a stack, as P0 "moments" sums them. */
static void stack_moments(const lc_fragment *frags, size_t n, double m[3])
{
    m[0] = m[1] = m[2] = 0;
    for (size_t i = 0; i < n; i++) {
        double w = frags[i].importance * frags[i].importance, u = frags[i].depth - 0.5;
        m[0] += w, m[1] += w * u, m[2] += w * u * u;
    }
}

static void test_depth_moments(void)
{
    lc_foo_params p;
    lc_foo_params_default(&p);
    CHECK(p.depth_range == LC_DEPTH_RANGE_AUTO, "auto is the default depth range");
    CHECK(lc_foo_depth_range(&p) == LC_DEPTH_RANGE_MOMENTS, "auto with density normalization: moments");
    p.normalize = LC_NORMALIZE_OFF;
    CHECK(lc_foo_depth_range(&p) == LC_DEPTH_RANGE_GLOBAL, "auto with the paper's formula: the bounds");
    p.depth_range = LC_DEPTH_RANGE_MOMENTS;
    CHECK(lc_foo_depth_range(&p) == LC_DEPTH_RANGE_MOMENTS, "an explicit range wins");
    p.normalize = LC_NORMALIZE_AUTO, p.depth_range = LC_DEPTH_RANGE_PIXEL;
    CHECK(lc_foo_depth_range(&p) == LC_DEPTH_RANGE_PIXEL, "an explicit range wins");

    const double none[3] = {0, 0, 0};
    CHECK_NEAR(lc_foo_moment_depth(0.37, none, DELTA), 0.37, 0.0, "a pixel without mass keeps its depth");
    /* Mass at 0.3 +- 0.05: the mean goes to 1/2, one spread either side to L(+-1). */
    double m[3] = {2.0, 2.0 * (0.3 - 0.5), 2.0 * ((0.3 - 0.5) * (0.3 - 0.5) + 0.05 * 0.05)};
    CHECK_NEAR(lc_foo_moment_depth(0.3, m, DELTA), 0.5, 1e-12, "the mean maps to the middle");
    double l1 = 1.0 / (1.0 + exp(-1.0));
    CHECK_NEAR(lc_foo_moment_depth(0.35, m, DELTA), DELTA + (1 - 2 * DELTA) * l1, 1e-12, "one spread behind");
    CHECK_NEAR(lc_foo_moment_depth(0.25, m, DELTA), DELTA + (1 - 2 * DELTA) * (1 - l1), 1e-12, "one spread in front");
    /* All mass at one depth: the spread is LC_MOMENT_MIN_SPREAD, not 0. */
    double point[3] = {1.0, 0.1, 0.01};
    CHECK_NEAR(lc_foo_moment_depth(0.6 + LC_MOMENT_MIN_SPREAD, point, DELTA), DELTA + (1 - 2 * DELTA) * l1, 1e-9,
               "the spread has a floor");
    /* Monotone and inside the margins for random moments. */
    rng_state = 21;
    for (int trial = 0; trial < 200; trial++) {
        lc_fragment frags[MAX_FRAGS];
        size_t n = (size_t)uniform_int(1, MAX_FRAGS);
        random_stack(frags, n);
        double mm[3];
        stack_moments(frags, n, mm);
        double prev = -1;
        for (int i = 0; i <= 1000; i++) {
            double d = DELTA + (1 - 2 * DELTA) * i / 1000.0, w = lc_foo_moment_depth(d, mm, DELTA);
            CHECK(w >= prev && w >= DELTA && w <= 1 - DELTA, "warp at %.3f: %.6f after %.6f", d, w, prev);
            prev = w;
        }
    }

    /* What it is for: compositing a tight cluster of important, semi-opaque layers
     * (plus a few scattered unimportant ones) with m = 5, against the exact
     * front-to-back result. The warp keeps the depth order, so the exact image is
     * the same for both depths. */
    rng_state = 23;
    double err_bounds = 0, err_moments = 0;
    const int pixels = 400;
    const double bg[3] = {1, 1, 1};
    for (int px = 0; px < pixels; px++) {
        lc_fragment frags[12], warped[12];
        double centre = 0.2 + 0.6 * uniform();
        for (int i = 0; i < 12; i++) {
            int cluster = i < 8;
            frags[i].depth = cluster ? centre + 0.03 * (uniform() - 0.5) : DELTA + (1 - 2 * DELTA) * uniform();
            frags[i].importance = cluster ? 0.6 + 0.4 * uniform() : 0.3 * uniform();
            frags[i].alpha = cluster ? 0.15 + 0.5 * uniform() : 0.3 * uniform();
            for (int c = 0; c < 3; c++)
                frags[i].color[c] = uniform();
        }
        double mm[3];
        stack_moments(frags, 12, mm);
        memcpy(warped, frags, sizeof warped);
        for (int i = 0; i < 12; i++)
            warped[i].depth = lc_foo_moment_depth(frags[i].depth, mm, DELTA);
        double exact[3], fb[3], fm[3];
        lc_foo_composite_exact(frags, 12, bg, exact);
        lc_foo_composite_fourier(frags, 12, 5, LC_ESTIMATOR_MIDPOINT, bg, fb, NULL);
        lc_foo_composite_fourier(warped, 12, 5, LC_ESTIMATOR_MIDPOINT, bg, fm, NULL);
        for (int c = 0; c < 3; c++) {
            err_bounds += fabs(fb[c] - exact[c]) / (3.0 * pixels);
            err_moments += fabs(fm[c] - exact[c]) / (3.0 * pixels);
        }
    }
    printf("clustered stacks, m=5: mean compositing error %.4f with the bounds' depth, %.4f warped by the moments\n",
           err_bounds, err_moments);
    CHECK(err_moments < 0.5 * err_bounds, "the moments warp should at least halve the error (%.4f vs %.4f)",
          err_moments, err_bounds);
}

int main(void)
{
    test_fourier_reconstruction();
    test_normalize_depth();
    test_optimal_alpha();
    test_compositing_identities();
    test_smoothing_and_fading();
    test_estimators();
    test_density_normalization();
    test_depth_moments();
    return lc_test_finish();
}
