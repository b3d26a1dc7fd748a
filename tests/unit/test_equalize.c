/* Colour equalization (DLS §3.4): the equalized values of a skewed,
 * visibility-weighted sample are near uniform; fixed ranges map as the
 * identity; the decay halves the distance to the target every half-life. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "colormap.h"
#include "equalize.h"
#include "lc_test.h"

#define BINS LC_EQUALIZE_BINS
#define SAMPLES 200000

static uint64_t state = 99;
static double uniform(void)
{
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return ((double)(state >> 11) + 0.5) * 0x1.0p-53;
}

/* Values crowded at the low end (c = u^2) with visibility weights T·α in (0, 1]. */
static void sample(float *c, float *w)
{
    for (int i = 0; i < SAMPLES; i++) {
        double u = uniform();
        c[i] = (float)(u * u);
        w[i] = (float)uniform();
    }
}

static void histogram(const float *c, const float *w, double *h)
{
    memset(h, 0, BINS * sizeof *h);
    for (int i = 0; i < SAMPLES; i++) {
        int b = (int)(c[i] * BINS);
        h[b < BINS ? b : BINS - 1] += w[i];
    }
}

static void test_uniform(void)
{
    float *c = malloc(SAMPLES * sizeof *c), *w = malloc(SAMPLES * sizeof *w), knots[BINS + 1];
    double h[BINS];
    sample(c, w);
    histogram(c, w, h);
    CHECK(lc_equalize_target(h, BINS, NULL, 0, knots) == 0, "target");
    /* The visibility-weighted histogram of the mapped values, 16 coarse bins. */
    double coarse[16] = {0}, before[16] = {0}, total = 0;
    for (int i = 0; i < SAMPLES; i++) {
        float f = lc_equalize_map(knots, BINS, c[i]);
        int b = (int)(f * 16), a = (int)(c[i] * 16);
        coarse[b < 16 ? b : 15] += w[i];
        before[a < 16 ? a : 15] += w[i];
        total += w[i];
    }
    double worst = 0, worst_before = 0;
    for (int b = 0; b < 16; b++) {
        worst = fmax(worst, fabs(coarse[b] / (total / 16) - 1));
        worst_before = fmax(worst_before, fabs(before[b] / (total / 16) - 1));
    }
    printf("equalized: largest deviation from uniform %.3f (before: %.3f)\n", worst, worst_before);
    CHECK(worst < 0.10, "equalized histogram within 10%% of uniform: %.3f", worst);
    CHECK(worst_before > 1.0, "the sample is skewed to begin with: %.3f", worst_before);
    for (int b = 0; b < BINS; b++)
        CHECK(knots[b] <= knots[b + 1], "monotone at knot %d", b);
    CHECK(knots[0] == 0.0f && knots[BINS] == 1.0f, "ends fixed");
    free(c);
    free(w);
}

static void test_fixed(void)
{
    float *c = malloc(SAMPLES * sizeof *c), *w = malloc(SAMPLES * sizeof *w), knots[BINS + 1];
    double h[BINS];
    sample(c, w);
    histogram(c, w, h);
    /* A diverging map's centre, and the top end. */
    const double fixed[2][2] = {{0.45, 0.55}, {0.9, 1.0}};
    CHECK(lc_equalize_target(h, BINS, fixed, 2, knots) == 0, "target with fixed ranges");
    double worst = 0;
    for (int r = 0; r < 2; r++)
        for (double x = fixed[r][0]; x <= fixed[r][1]; x += 0.0005)
            worst = fmax(worst, fabs(lc_equalize_map(knots, BINS, (float)x) - x));
    CHECK(worst < 1e-6, "fixed ranges map as the identity (largest error %.3g)", worst);
    /* The free stretch below the first range is still equalized: its low values spread. */
    CHECK(lc_equalize_map(knots, BINS, 0.05f) > 0.12f, "F(0.05) = %.3f (identity: 0.05)",
          lc_equalize_map(knots, BINS, 0.05f));
    for (int b = 0; b < BINS; b++)
        CHECK(knots[b] <= knots[b + 1], "monotone at knot %d", b);
    /* The colormap table keeps the fixed range's colours. */
    const float *table = lc_colormap_table(lc_colormap_find("coolwarm"));
    float out[LC_COLORMAP_SIZE * 3];
    lc_equalize_table(table, LC_COLORMAP_SIZE, knots, BINS, out, LC_COLORMAP_SIZE);
    int k = 128; /* t = 128/255, inside [0.45, 0.55] */
    float ref[3];
    lc_colormap_sample(lc_colormap_find("coolwarm"), (float)k / 255, ref);
    CHECK(fabsf(out[3 * k] - ref[0]) < 1e-5f && fabsf(out[3 * k + 2] - ref[2]) < 1e-5f, "table keeps the centre");
    const double bad[1][2] = {{0.6, 0.4}};
    CHECK(lc_equalize_target(h, BINS, bad, 1, knots) == -1, "reversed range refused");
    free(c);
    free(w);
}

static void test_decay(void)
{
    float cur[BINS + 1], target[BINS + 1];
    for (int b = 0; b <= BINS; b++) {
        cur[b] = (float)b / BINS;           /* identity */
        target[b] = sqrtf((float)b / BINS); /* after a jump of the camera */
    }
    double d0 = 0;
    for (int b = 0; b <= BINS; b++)
        d0 = fmax(d0, fabs(cur[b] - target[b]));
    const double half = LC_EQUALIZE_DEFAULT_HALF_LIFE, dt = 1.0 / 60;
    for (int period = 1; period <= 3; period++) {
        for (int s = 0; s < (int)lround(half / dt); s++)
            lc_equalize_approach(cur, target, BINS, dt, half);
        double d = 0;
        for (int b = 0; b <= BINS; b++)
            d = fmax(d, fabs(cur[b] - target[b]));
        CHECK_NEAR(d / d0, pow(0.5, period), 1e-4, "distance after n half-lives");
    }
    lc_equalize_approach(cur, target, BINS, 0.01, 0);
    CHECK(memcmp(cur, target, sizeof cur) == 0, "half-life 0 jumps to the target");
}

/* F^-1 (the legend's ticks): the least c with F(c) = x; flat stretches answer their start. */
static void test_inverse(void)
{
    float knots[BINS + 1];
    for (int b = 0; b <= BINS; b++) /* F(c) = c^2, then a flat stretch in the middle third */
        knots[b] = (float)((double)b / BINS * b / BINS);
    for (int i = 0; i <= 40; i++) {
        float c = (float)i / 40, x = lc_equalize_map(knots, BINS, c);
        CHECK(fabsf(lc_equalize_inverse(knots, BINS, x) - c) < 1e-5f, "F^-1(F(%g)) = %g", c,
              lc_equalize_inverse(knots, BINS, x));
    }
    for (int b = BINS / 3; b <= 2 * BINS / 3; b++)
        knots[b] = knots[BINS / 3];
    CHECK(fabsf(lc_equalize_inverse(knots, BINS, knots[BINS / 3]) - (float)(BINS / 3) / BINS) < 1e-6f,
          "a flat stretch: its start");
    CHECK(lc_equalize_inverse(knots, BINS, -1) == 0 && lc_equalize_inverse(knots, BINS, 2) == 1, "clamped");
}

int main(void)
{
    test_uniform();
    test_fixed();
    test_decay();
    test_inverse();
    return lc_test_finish();
}
