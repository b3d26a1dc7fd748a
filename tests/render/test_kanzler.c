/* Method "kanzler" (docs/ALGORITHM.md §28) on explicit line scenes, viewed
 * orthographically down -Z, read back through lc_kanzler_read_maps:
 * - three parallel lines over each other: coverage C = 3, directional
 *   variance V = 0, M the largest importance and D the normalized depth of
 *   that line (in either order of depth);
 * - two orthogonal lines where they cross: C = 2, V = 1 - 1/sqrt 2 = 0.293;
 * - the image: with one colour on black every pixel is 255 (1 - prod(1 -
 *   alpha_i)) exactly (P6's transmittance is exact), and alpha_i = g_i^k rho_i
 *   with rho from lc_foo_kanzler_rho on the read maps: at the crossing (both
 *   fragments, the front one penalized by less(i, D)) and where a line is alone;
 *   the penalty darkens the crossing against method "direct";
 * - two stacked point splats: C = 2, V = 0, M and D of the more important,
 *   the pixel against the CPU penalty;
 * - the visibility report of a line alone: its least fragment opacity;
 * - refusals: a surface (naming method), a tiled frame (naming width). */
#include <math.h>

#include "foo_math.h"
#include "render_util.h"

enum { SIZE = 65, PER_LINE = 9 };

typedef struct test_line {
    double a[3], b[3], g;
} test_line;

/* White lines of PER_LINE vertices each, attribute "importance" = g, one element per line. */
static lc_scene *line_scene(const test_line *l, int n)
{
    lc_error err = {0};
    lc_scene *s = lc_scene_create("lines", LC_PRIM_LINES);
    if (!s || lc_scene_alloc_vertices(s, (uint32_t)(n * PER_LINE), 1, &err) != 0)
        return NULL;
    s->line_count = (uint32_t)n;
    s->line_offsets = malloc(sizeof(uint32_t) * ((size_t)n + 1));
    float *g = malloc(sizeof(float) * (size_t)(n * PER_LINE));
    for (int i = 0; i < n; i++) {
        s->line_offsets[i] = (uint32_t)(i * PER_LINE);
        for (int k = 0; k < PER_LINE; k++) {
            int v = i * PER_LINE + k;
            double t = (double)k / (PER_LINE - 1);
            for (int c = 0; c < 3; c++) {
                s->positions[3 * v + c] = (float)(l[i].a[c] + t * (l[i].b[c] - l[i].a[c]));
                s->rgb[3 * v + c] = 1.0f;
            }
            g[v] = (float)l[i].g;
        }
    }
    s->line_offsets[n] = (uint32_t)(n * PER_LINE);
    lc_scene_add_attribute(s, "importance", g, &err);
    lc_elements_desc desc = {.line_budget = (uint32_t)n};
    if (lc_scene_finalize(s, &desc, &err) != 0) {
        fprintf(stderr, "finalize: %s\n", err.msg);
        lc_scene_destroy(s);
        return NULL;
    }
    return s;
}

static void params(lc_render_params *p, lc_method method)
{
    test_quad_params(p, SIZE);
    p->method = method;
    p->camera.parallel_scale = 1.1;
    p->detail.lod_pixels = 0;
    p->style.line_width = 0.3; /* about 9 pixels: the 5x5 blur sees one stack */
    p->style.background[0] = p->style.background[1] = p->style.background[2] = 0;
}

/* Renders s; maps (SIZE^2 x 4, may be NULL) gets the frame's maps. */
static int render(test_gl *t, const lc_scene *s, const lc_render_params *p, uint8_t *rgba, float *maps, lc_error *err)
{
    lc_gpu_scene *gs = NULL;
    lc_gpu_scene_desc desc = {.exact_positions = 1};
    if (lc_gpu_scene_create_ex(s, &desc, &gs, err) != 0)
        return -1;
    int rc = lc_render_frame(t->renderer, gs, p, NULL, 0, rgba, NULL, err);
    if (rc == 0 && maps && lc_kanzler_read_maps(t->renderer, maps, SIZE, SIZE) != 0)
        rc = lc_err(err, LC_ERR_INTERNAL, "no maps to read");
    lc_gpu_scene_destroy(gs);
    return rc;
}

/* The maps at pixel (x, y) of the image (y down; the maps are bottom-up). */
static const float *map_at(const float *maps, int x, int y) { return maps + 4 * ((size_t)(SIZE - 1 - y) * SIZE + x); }

/* Normalized depth of world z with the data's z range [z0, z1] and the camera
 * above z1: the bounds' view depths padded by 1% of their extent (camera.c). */
static double depth_of(double z, double z0, double z1)
{
    double e = z1 - z0;
    return 0.02 + 0.96 * (z1 + 0.01 * e - z) / (1.02 * e);
}

static void parallel_lines(test_gl *t)
{
    for (int order = 0; order < 2; order++) {
        /* The most important line in the middle, then in front. */
        double z_max = order == 0 ? 0.5 : 1.0;
        test_line l[3] = {{{-1, 0, 0}, {1, 0, 0}, 0.3},
                          {{-1, 0, z_max}, {1, 0, z_max}, 0.9},
                          {{-1, 0, 1.5 - z_max}, {1, 0, 1.5 - z_max}, 0.6}};
        lc_scene *s = line_scene(l, 3);
        lc_render_params p;
        params(&p, LC_METHOD_KANZLER);
        uint8_t *rgba = malloc(SIZE * SIZE * 4);
        float *maps = malloc(sizeof(float) * SIZE * SIZE * 4);
        lc_error err = {0};
        CHECK(render(t, s, &p, rgba, maps, &err) == 0, "parallel: %s", err.msg);
        for (int x = 12; x <= 52; x += 20) {
            const float *m = map_at(maps, x, SIZE / 2);
            CHECK_NEAR(m[0], 3, 0, "parallel lines: coverage");
            const double along_x[9] = {1, 0, 0, 1, 0, 0, 1, 0, 0};
            CHECK_NEAR(m[3], lc_foo_direction_variance(along_x, 3), 1e-5, "parallel lines: directional variance");
            CHECK_NEAR(m[1], 0.9, 1e-4, "parallel lines: maximum importance");
            CHECK_NEAR(m[2], depth_of(z_max, 0, 1), 1e-4, "parallel lines: depth of the maximum");
        }
        const float *empty = map_at(maps, SIZE / 2, 3);
        CHECK(empty[0] == 0 && empty[1] == 0, "an empty pixel: C %g M %g", empty[0], empty[1]);
        free(rgba);
        free(maps);
        lc_scene_destroy(s);
    }
}

/* Expected 8-bit value of a pixel whose fragments (g, d) share the colour white on black. */
static double expected_pixel(const lc_foo_params *f, const float *m, const double *g, const double *d, int n,
                             int kanzler)
{
    double through = 1;
    for (int i = 0; i < n; i++) {
        double alpha = fmin(pow(g[i], f->direct_exponent), 0.9999);
        if (kanzler)
            alpha *= lc_foo_kanzler_rho(f, g[i], d[i], m[0], m[1], m[2], m[3]);
        through *= 1 - alpha;
    }
    return 255.0 * (1 - through);
}

static void crossing_lines(test_gl *t)
{
    /* The unimportant line in front (z 0.8) crosses the important one behind (z 0.2). */
    test_line l[2] = {{{-1, 0, 0.8}, {1, 0, 0.8}, 0.2}, {{0, -1, 0.2}, {0, 1, 0.2}, 0.7}};
    lc_scene *s = line_scene(l, 2);
    lc_render_params p;
    params(&p, LC_METHOD_KANZLER);
    /* alpha = g, so that every term of P moves the crossing by more than the tolerance (less(i, D) by ~6 levels) */
    p.foo.direct_exponent = 1;
    uint8_t *rgba = malloc(SIZE * SIZE * 4), *direct = malloc(SIZE * SIZE * 4);
    float *maps = malloc(sizeof(float) * SIZE * SIZE * 4);
    lc_error err = {0};
    CHECK(render(t, s, &p, rgba, maps, &err) == 0, "crossing: %s", err.msg);
    const int c = SIZE / 2;
    const float *m = map_at(maps, c, c);
    CHECK_NEAR(m[0], 2, 0, "crossing: coverage");
    const double crossed[6] = {1, 0, 0, 0, 1, 0};
    CHECK_NEAR(lc_foo_direction_variance(crossed, 2), 1 - sqrt(0.5), 1e-12, "CPU variance of orthogonal tangents");
    CHECK_NEAR(m[3], 1 - sqrt(0.5), 1e-4, "crossing: directional variance of orthogonal lines");
    CHECK_NEAR(m[1], 0.7, 1e-4, "crossing: maximum importance");
    CHECK_NEAR(m[2], depth_of(0.2, 0.2, 0.8), 1e-4, "crossing: depth of the maximum");

    double g[2] = {0.2, 0.7}, d[2] = {depth_of(0.8, 0.2, 0.8), depth_of(0.2, 0.2, 0.8)};
    double want = expected_pixel(&p.foo, m, g, d, 2, 1);
    CHECK_NEAR(rgba[4 * (c * SIZE + c)], want, 1.5, "crossing: pixel against the CPU penalty");
    /* Each line alone: one fragment, not in front of its own maximum. */
    const int alone[2][2] = {{10, c}, {c, 10}};
    for (int i = 0; i < 2; i++) {
        const float *ma = map_at(maps, alone[i][0], alone[i][1]);
        CHECK_NEAR(ma[0], 1, 0, "a line alone: coverage");
        CHECK_NEAR(ma[1], g[i], 1e-4, "a line alone: maximum importance");
        double w = expected_pixel(&p.foo, ma, &g[i], &d[i], 1, 1);
        CHECK_NEAR(rgba[4 * (alone[i][1] * SIZE + alone[i][0])], w, 1.5, "a line alone: pixel against the CPU penalty");
    }
    params(&p, LC_METHOD_DIRECT);
    p.foo.direct_exponent = 1;
    CHECK(render(t, s, &p, direct, NULL, &err) == 0, "direct: %s", err.msg);
    double plain = expected_pixel(&p.foo, m, g, d, 2, 0);
    CHECK_NEAR(direct[4 * (c * SIZE + c)], plain, 1.5, "crossing, direct: pixel against the CPU");
    CHECK(plain - want > 20 && direct[4 * (c * SIZE + c)] > rgba[4 * (c * SIZE + c)] + 20,
          "the penalty lightens the crossing: kanzler %d, direct %d", rgba[4 * (c * SIZE + c)],
          direct[4 * (c * SIZE + c)]);
    free(rgba);
    free(direct);
    free(maps);
    lc_scene_destroy(s);
}

/* Points: two splats over each other count twice, have no direction (V = 0)
 * and give M and D of the more important one. */
static void stacked_points(test_gl *t)
{
    lc_error err = {0};
    lc_scene *s = lc_scene_create("points", LC_PRIM_POINTS);
    CHECK(s && lc_scene_alloc_vertices(s, 2, 1, &err) == 0, "points: %s", err.msg);
    float *g = malloc(2 * sizeof(float)); /* the scene takes it */
    g[0] = 0.8f, g[1] = 0.4f;
    for (int v = 0; v < 2; v++) {
        s->positions[3 * v] = s->positions[3 * v + 1] = 0;
        s->positions[3 * v + 2] = (float)v; /* the more important point behind */
        s->rgb[3 * v] = s->rgb[3 * v + 1] = s->rgb[3 * v + 2] = 1;
    }
    lc_scene_add_attribute(s, "importance", g, &err);
    lc_elements_desc desc = {0};
    CHECK(lc_scene_finalize(s, &desc, &err) == 0, "points: %s", err.msg);
    lc_render_params p;
    params(&p, LC_METHOD_KANZLER);
    p.style.point_size = 24;
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    float *maps = malloc(sizeof(float) * SIZE * SIZE * 4);
    CHECK(render(t, s, &p, rgba, maps, &err) == 0, "points: %s", err.msg);
    const float *m = map_at(maps, SIZE / 2, SIZE / 2);
    CHECK_NEAR(m[0], 2, 0, "stacked points: coverage");
    CHECK_NEAR(m[3], 0, 0, "stacked points: no directional variance");
    CHECK_NEAR(m[1], 0.8, 1e-4, "stacked points: maximum importance");
    CHECK_NEAR(m[2], depth_of(0, 0, 1), 1e-4, "stacked points: depth of the maximum");
    double gs[2] = {0.4, 0.8}, d[2] = {depth_of(1, 0, 1), depth_of(0, 0, 1)};
    CHECK_NEAR(rgba[4 * ((SIZE / 2) * SIZE + SIZE / 2)], expected_pixel(&p.foo, m, gs, d, 2, 1), 1.5,
               "stacked points: pixel against the CPU penalty");
    free(rgba);
    free(maps);
    lc_scene_destroy(s);
}

/* The visibility report of one line alone (g 0.5): its opacity is its least
 * fragment opacity, where the maps hold M = g: g^k / (1 + (1 - g)(m g + c)). */
static void report(test_gl *t)
{
    test_line l[1] = {{{-1, 0, 0}, {1, 0, 0}, 0.5}};
    lc_scene *s = line_scene(l, 1);
    lc_gpu_scene *gs = NULL;
    lc_error err = {0};
    lc_gpu_scene_desc desc = {.exact_positions = 1};
    CHECK(lc_gpu_scene_create_ex(s, &desc, &gs, &err) == 0, "report: %s", err.msg);
    lc_render_params p;
    params(&p, LC_METHOD_KANZLER);
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    lc_frame_info info;
    test_render_frame(t, gs, &p, NULL, rgba, &info);
    const lc_foo_params *f = &p.foo;
    double want = pow(0.5, f->direct_exponent) / (1 + 0.5 * (f->kanzler_importance * 0.5 + f->kanzler_coverage));
    CHECK(info.has_visibility && info.visible_elements == 1, "report: %d, %u elements", info.has_visibility,
          info.visible_elements);
    CHECK_NEAR(info.top_decile_alpha, want, 1e-3, "report: the line's least opacity");
    CHECK_NEAR(info.occluder_alpha, 0, 0, "report: a line alone hides nothing");
    CHECK(info.covered_fraction > 0.05 && info.covered_fraction < 0.2, "report: covered %g", info.covered_fraction);
    free(rgba);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

static void refusals(test_gl *t)
{
    test_quad q[1] = {{0, 0.5, {1, 1, 1}, 0.5}};
    lc_scene *s = test_quad_scene(q, 1);
    lc_render_params p;
    params(&p, LC_METHOD_KANZLER);
    snprintf(p.importance.attribute, sizeof p.importance.attribute, "importance");
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    lc_error err = {0};
    CHECK(render(t, s, &p, rgba, NULL, &err) != 0 && strcmp(err.field, "method") == 0,
          "a surface is refused naming method: %s (%s)", err.msg, err.field);
    lc_scene_destroy(s);
    test_line l[1] = {{{-1, 0, 0}, {1, 0, 0}, 0.5}};
    s = line_scene(l, 1);
    lc_renderer_set_tile_size(t->renderer, 32);
    err = (lc_error){0};
    CHECK(render(t, s, &p, rgba, NULL, &err) != 0 && strcmp(err.field, "width") == 0,
          "a tiled frame is refused naming width: %s (%s)", err.msg, err.field);
    lc_renderer_set_tile_size(t->renderer, 0);
    lc_scene_destroy(s);
    free(rgba);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    parallel_lines(&t);
    crossing_lines(&t);
    stacked_points(&t);
    report(&t);
    refusals(&t);
    test_gl_close(&t);
    return lc_test_finish();
}
