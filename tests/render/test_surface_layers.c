/* Surface layers (docs/ALGORITHM.md §23): curves traced through the shear
 * flow from straight seed lines sweep planes; the per-pixel layers must hold
 * one layer per plane, composite front to back to the closed-form colour,
 * merge only within epsilon, and report overflow beyond K. */
#include <math.h>

#include "field.h"
#include "render_util.h"
#include "surface_layers.h"
#include "trace.h"

#define W 64
#define H 64
#define CURVES 255
#define EPS 0.02 /* view depth: a plane z = y/4 spans 0.008 across one pixel */
#define ALPHA 0.5
#define AMBIENT 0.3 /* surface_layers.c */

static const float BG[3] = {0.1f, 0.1f, 0.1f};

/* Camera at z = 3 looking down -z, orthographic over [-1, 1]^2: view depth 3 - z. */
static lc_surface_layers_desc make_desc(int k, double eps)
{
    lc_surface_layers_desc d = {
        .width = W, .height = H, .max_layers = k, .epsilon = eps, .opacity = ALPHA, .pool_fragments = 1u << 20};
    for (int c = 0; c < 3; c++)
        d.background[c] = BG[c];
    for (int i = 0; i < 4; i++)
        d.view[5 * i] = d.projection[5 * i] = 1.0f;
    d.view[14] = -3.0f;
    double n = 0.1, f = 10.0;
    d.projection[10] = (float)(-2.0 / (f - n));
    d.projection[14] = (float)(-(f + n) / (f - n));
    return d;
}

/* Curves of the seed line from (-0.9, -0.8, z0) to (-0.9, 0.8, z0 + 0.4): in
 * the shear flow (v along x) they sweep the plane z = z0 + 0.2 + y/4. */
static lc_trace_curve *trace_plane(const lc_field *f, double z0, uint32_t first, uint32_t count)
{
    lc_error err = {0};
    char text[128];
    snprintf(text, sizeof text, "-0.9,-0.8,%g;-0.9,0.8,%g", z0, z0 + 0.4);
    lc_seed seed;
    lc_trace_curve *c = calloc(count, sizeof *c);
    CHECK(lc_seed_parse(text, &seed, f, &err) == 0, "seed: %s", err.msg);
    CHECK(lc_trace_curves(f, &seed, &(lc_trace_desc){0}, first, count, 2, c, &err) == 0, "trace: %s", err.msg);
    return c;
}

/* Pixel (column i, row r from the top) lies well inside the planes' footprint
 * x in [-0.9, 1], y in [-0.8, 0.8]. */
static int interior(int i, int r)
{
    double x = -1 + (i + 0.5) * 2.0 / W, y = 1 - (r + 0.5) * 2.0 / H;
    return x > -0.8 && x < 0.9 && fabs(y) < 0.7;
}

/* Shade of a layer of the plane z = c + y/4 under the headlight: normal (0, -1/4, 1). */
static double plane_shade(void) { return AMBIENT + (1 - AMBIENT) * (1 / sqrt(1 + 1.0 / 16)); }

static void test_one_plane(const lc_field *f)
{
    lc_error err = {0};
    lc_surface_layers_desc d = make_desc(16, EPS);
    lc_surface_layers *sl = NULL;
    CHECK(lc_surface_layers_create(&d, &sl, &err) == 0, "create: %s", err.msg);
    if (!sl)
        return;
    static const float rgb[3] = {0.8f, 0.6f, 0.2f};
    static uint32_t counts[W * H];
    /* Two batches: the state persists and fills in. */
    lc_trace_curve *a = trace_plane(f, -0.2, 0, 31), *b = trace_plane(f, -0.2, 31, CURVES - 31);
    lc_surface_layers_stats s1, s2;
    CHECK(lc_surface_layers_add(sl, a, 31, rgb, &err) == 0, "add: %s", err.msg);
    CHECK(lc_surface_layers_read(sl, counts, &s1, &err) == 0, "read: %s", err.msg);
    CHECK(lc_surface_layers_add(sl, b, CURVES - 31, rgb, &err) == 0, "add: %s", err.msg);
    CHECK(lc_surface_layers_read(sl, counts, &s2, &err) == 0, "read: %s", err.msg);
    CHECK(s1.max_layers == 1 && s2.max_layers == 1, "one plane: at most one layer per pixel (got %u, %u)",
          s1.max_layers, s2.max_layers);
    CHECK(s2.covered_pixels > s1.covered_pixels, "more curves cover more pixels (%u then %u)", s1.covered_pixels,
          s2.covered_pixels);
    CHECK(s2.curves == CURVES && s2.overflow == 0 && s2.pool_dropped == 0, "curves %llu, overflow %llu, pool %llu",
          (unsigned long long)s2.curves, (unsigned long long)s2.overflow, (unsigned long long)s2.pool_dropped);
    /* Several fragments per pixel were merged: fragments = layers + merged. */
    CHECK(s2.fragments > 2ull * s2.covered_pixels && s2.fragments == s2.merged + s2.covered_pixels,
          "fragments %llu, merged %llu, covered %u", (unsigned long long)s2.fragments, (unsigned long long)s2.merged,
          s2.covered_pixels);
    int missing = 0, wrong = 0;
    static uint8_t img[W * H * 4];
    CHECK(lc_surface_layers_composite(sl, img, &err) == 0, "composite: %s", err.msg);
    double shade = plane_shade();
    for (int r = 0; r < H; r++)
        for (int i = 0; i < W; i++) {
            const uint8_t *px = img + 4 * (r * W + i);
            if (!interior(i, r)) {
                if (!counts[r * W + i])
                    for (int c = 0; c < 3; c++)
                        wrong += fabs(px[c] / 255.0 - BG[c]) > 1.5 / 255;
                continue;
            }
            missing += counts[r * W + i] != 1;
            for (int c = 0; c < 3; c++) {
                double want = ALPHA * shade * rgb[c] + (1 - ALPHA) * BG[c];
                wrong += fabs(px[c] / 255.0 - want) > 2.0 / 255;
            }
        }
    CHECK(missing == 0, "one plane: %d interior pixels without exactly one layer", missing);
    CHECK(wrong == 0, "one plane: %d channels off the closed-form colour", wrong);
    lc_trace_curves_free(a, 31);
    lc_trace_curves_free(b, CURVES - 31);
    free(a);
    free(b);
    lc_surface_layers_destroy(sl);
}

static void test_two_planes(const lc_field *f)
{
    lc_error err = {0};
    lc_surface_layers_desc d = make_desc(16, EPS);
    lc_surface_layers *sl = NULL;
    CHECK(lc_surface_layers_create(&d, &sl, &err) == 0, "create: %s", err.msg);
    if (!sl)
        return;
    static const float back[3] = {0.2f, 0.4f, 0.9f}, front[3] = {0.9f, 0.3f, 0.1f};
    lc_trace_curve *a = trace_plane(f, -0.6, 0, CURVES), *b = trace_plane(f, 0.2, 0, CURVES);
    /* The back plane first: the front plane's layers (nearer the camera at z = 3) must go before them. */
    CHECK(lc_surface_layers_add(sl, a, CURVES, back, &err) == 0 &&
              lc_surface_layers_add(sl, b, CURVES, front, &err) == 0,
          "add: %s", err.msg);
    static uint32_t counts[W * H];
    static uint8_t img[W * H * 4];
    lc_surface_layers_stats s;
    CHECK(lc_surface_layers_read(sl, counts, &s, &err) == 0, "read: %s", err.msg);
    CHECK(lc_surface_layers_composite(sl, img, &err) == 0, "composite: %s", err.msg);
    CHECK(s.max_layers == 2 && s.overflow == 0, "two planes: max %u layers, overflow %llu", s.max_layers,
          (unsigned long long)s.overflow);
    int missing = 0, wrong = 0;
    double shade = plane_shade();
    for (int r = 0; r < H; r++)
        for (int i = 0; i < W; i++) {
            if (!interior(i, r))
                continue;
            missing += counts[r * W + i] != 2;
            const uint8_t *px = img + 4 * (r * W + i);
            for (int c = 0; c < 3; c++) {
                double want = ALPHA * shade * front[c] + (1 - ALPHA) * ALPHA * shade * back[c] +
                              (1 - ALPHA) * (1 - ALPHA) * BG[c];
                wrong += fabs(px[c] / 255.0 - want) > 2.0 / 255;
            }
        }
    CHECK(missing == 0, "two planes: %d interior pixels without exactly two layers", missing);
    CHECK(wrong == 0, "two planes: %d channels off the front-to-back colour", wrong);
    lc_trace_curves_free(a, CURVES);
    lc_trace_curves_free(b, CURVES);
    free(a);
    free(b);
    lc_surface_layers_destroy(sl);
}

/* One plane at (k, eps): returns the stats after all curves. */
static lc_surface_layers_stats plane_stats(const lc_field *f, int k, double eps)
{
    lc_error err = {0};
    lc_surface_layers_stats s = {0};
    lc_surface_layers_desc d = make_desc(k, eps);
    lc_surface_layers *sl = NULL;
    CHECK(lc_surface_layers_create(&d, &sl, &err) == 0, "create: %s", err.msg);
    if (!sl)
        return s;
    static const float rgb[3] = {1, 1, 1};
    lc_trace_curve *c = trace_plane(f, -0.2, 0, CURVES);
    CHECK(lc_surface_layers_add(sl, c, CURVES, rgb, &err) == 0, "add: %s", err.msg);
    CHECK(lc_surface_layers_read(sl, NULL, &s, &err) == 0, "read: %s", err.msg);
    /* Every fragment is accounted for: a layer, merged into one, or overflow. */
    CHECK(s.fragments == s.merged + s.overflow + (uint64_t)llround(s.mean_layers * s.covered_pixels),
          "K = %d, epsilon %g: %llu fragments, %llu merged, %llu overflow, %.0f layers", k, eps,
          (unsigned long long)s.fragments, (unsigned long long)s.merged, (unsigned long long)s.overflow,
          s.mean_layers * s.covered_pixels);
    /* A reset empties the layers. */
    lc_surface_layers_stats e;
    lc_surface_layers_reset(sl);
    CHECK(lc_surface_layers_read(sl, NULL, &e, &err) == 0 && e.covered_pixels == 0 && e.fragments == 0,
          "reset: %u pixels covered", e.covered_pixels);
    lc_trace_curves_free(c, CURVES);
    free(c);
    lc_surface_layers_destroy(sl);
    return s;
}

static void test_epsilon_and_overflow(const lc_field *f)
{
    lc_surface_layers_stats merged = plane_stats(f, 16, EPS);
    lc_surface_layers_stats split = plane_stats(f, LC_SURFACE_LAYERS_MAX_K, 0.0);
    lc_surface_layers_stats capped = plane_stats(f, 2, 0.0);
    printf("epsilon %g: %.3f layers/pixel (max %u); epsilon 0: %.3f (max %u); K = 2: overflow %llu\n", EPS,
           merged.mean_layers, merged.max_layers, split.mean_layers, split.max_layers,
           (unsigned long long)capped.overflow);
    CHECK(merged.mean_layers == 1.0 && split.mean_layers > 2.0, "epsilon 0 keeps every fragment a layer (%.3f vs %.3f)",
          split.mean_layers, merged.mean_layers);
    CHECK(split.merged == 0 && split.overflow == 0, "epsilon 0: merged %llu, overflow %llu",
          (unsigned long long)split.merged, (unsigned long long)split.overflow);
    CHECK(capped.max_layers == 2 && capped.overflow > 0 &&
              capped.overflow + capped.mean_layers * capped.covered_pixels == capped.fragments,
          "K = 2: max %u layers, overflow %llu of %llu fragments", capped.max_layers,
          (unsigned long long)capped.overflow, (unsigned long long)capped.fragments);
    CHECK(merged.overflow == 0, "epsilon %g: no overflow (%llu)", EPS, (unsigned long long)merged.overflow);
}

/* A perspective camera (at z = 3, 2 atan(1/3) field of view): view depth is
 * interpolated perspective-correctly, so each plane stays one layer. */
static void test_perspective(const lc_field *f)
{
    lc_error err = {0};
    lc_surface_layers_desc d = make_desc(16, EPS);
    double n = 0.1, fa = 10.0;
    memset(d.projection, 0, sizeof d.projection);
    d.projection[0] = d.projection[5] = 3.0f;
    d.projection[10] = (float)((fa + n) / (n - fa));
    d.projection[11] = -1.0f;
    d.projection[14] = (float)(2 * fa * n / (n - fa));
    lc_surface_layers *sl = NULL;
    CHECK(lc_surface_layers_create(&d, &sl, &err) == 0, "create: %s", err.msg);
    if (!sl)
        return;
    static const float rgb[3] = {1, 1, 1};
    static uint32_t counts[W * H];
    lc_trace_curve *a = trace_plane(f, -0.6, 0, CURVES), *b = trace_plane(f, 0.2, 0, CURVES);
    lc_surface_layers_stats s1, s2;
    CHECK(lc_surface_layers_add(sl, a, CURVES, rgb, &err) == 0, "add: %s", err.msg);
    CHECK(lc_surface_layers_read(sl, counts, &s1, &err) == 0, "read: %s", err.msg);
    CHECK(lc_surface_layers_add(sl, b, CURVES, rgb, &err) == 0, "add: %s", err.msg);
    CHECK(lc_surface_layers_read(sl, counts, &s2, &err) == 0, "read: %s", err.msg);
    int both = 0;
    for (int i = 0; i < W * H; i++)
        both += counts[i] == 2;
    CHECK(s1.max_layers == 1 && s1.covered_pixels > 1500, "perspective, one plane: max %u layers over %u pixels",
          s1.max_layers, s1.covered_pixels);
    CHECK(s2.max_layers == 2 && both > 1500 && s2.overflow == 0,
          "perspective, two planes: max %u layers, %d pixels with two", s2.max_layers, both);
    lc_trace_curves_free(a, CURVES);
    lc_trace_curves_free(b, CURVES);
    free(a);
    free(b);
    lc_surface_layers_destroy(sl);
}

static void test_bad_desc(void)
{
    lc_error err = {0};
    lc_surface_layers *sl = NULL;
    lc_surface_layers_desc d = make_desc(16, -1.0);
    CHECK(lc_surface_layers_create(&d, &sl, &err) != 0 && sl == NULL && strstr(err.msg, "epsilon"),
          "negative epsilon: %s", err.msg);
    d = make_desc(LC_SURFACE_LAYERS_MAX_K + 1, EPS);
    CHECK(lc_surface_layers_create(&d, &sl, &err) != 0 && strstr(err.msg, "max_layers"), "K too large: %s", err.msg);
    d = make_desc(16, EPS);
    d.opacity = 1.5;
    CHECK(lc_surface_layers_create(&d, &sl, &err) != 0 && strstr(err.msg, "opacity"), "opacity: %s", err.msg);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    lc_error err = {0};
    lc_field *f = NULL;
    CHECK(lc_field_demo_create("shear-flow", &f, &err) == 0, "%s", err.msg);
    if (f) {
        test_one_plane(f);
        test_two_planes(f);
        test_epsilon_and_overflow(f);
        test_perspective(f);
    }
    test_bad_desc();
    lc_field_destroy(f);
    test_gl_close(&t);
    return lc_test_finish();
}
