/* Image tests of the FOO pipeline on stacked quads: GPU pixels against the CPU
 * reference of the same math (foo_math.c), and the q-term behaviour. */
#include <math.h>

#include "camera.h"
#include "foo_math.h"
#include "render_util.h"

/* CPU evaluation of one pixel covered by every quad. */
static void expected_pixel(const test_quad *q, int n, const lc_render_params *p, const lc_scene *s, double out[3])
{
    lc_fragment frags[16];
    test_quad_fragments(q, n, p, s, lc_foo_depth_range(&p->foo) == LC_DEPTH_RANGE_MOMENTS, frags);
    lc_foo_alpha_fourier(frags, (size_t)n, &p->foo);
    lc_foo_composite_fourier(frags, (size_t)n, p->foo.bands, p->foo.estimator, p->style.background, out, NULL);
}

static void render(test_gl *t, const lc_scene *s, const lc_render_params *p, uint8_t *rgba)
{
    lc_error err = {0};
    lc_gpu_scene *gs = NULL;
    CHECK(lc_gpu_scene_create(s, &gs, &err) == 0, "gpu scene: %s", err.msg);
    lc_frame_info info;
    int rc = lc_render_frame(t->renderer, gs, p, NULL, 0, rgba, &info, &err);
    CHECK(rc == 0, "render: %s", err.msg);
    lc_gpu_scene_destroy(gs);
}

static void check_stack(test_gl *t, const test_quad *q, int n, int bands, lc_estimator est, double qw, double rw,
                        lc_depth_range range)
{
    lc_scene *s = test_quad_scene(q, n);
    CHECK(s != NULL, "scene");
    if (!s)
        return;
    lc_render_params p;
    test_quad_params(&p, 48);
    p.foo.bands = bands;
    p.foo.estimator = est;
    p.foo.q = qw, p.foo.r = rw;
    p.foo.depth_range = range;
    uint8_t *rgba = malloc(48 * 48 * 4);
    render(t, s, &p, rgba);
    double want[3];
    expected_pixel(q, n, &p, s, want);
    double worst = 0;
    for (int i = 0; i < 48 * 48; i++)
        for (int c = 0; c < 3; c++)
            worst = fmax(worst, fabs(rgba[4 * i + c] / 255.0 - want[c]));
    CHECK(worst <= 2.0 / 255.0, "m=%d %s q=%g r=%g: worst pixel error %.4f (want %.3f %.3f %.3f, got %d %d %d)", bands,
          lc_estimator_name(est), qw, rw, worst, want[0], want[1], want[2], rgba[0], rgba[1], rgba[2]);
    printf("stack of %d, m=%d, %-8s q=%-4g r=%-4g %s range: expected (%.4f %.4f %.4f), worst error %.4f\n", n, bands,
           lc_estimator_name(est), qw, rw,
           range == LC_DEPTH_RANGE_PIXEL     ? "pixel  "
           : range == LC_DEPTH_RANGE_MOMENTS ? "moments"
                                             : "global ",
           want[0], want[1], want[2], worst);
    free(rgba);
    lc_scene_destroy(s);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    printf("renderer: %s\n", lc_gl_renderer(t.gl));

    const test_quad three[3] = {{0.3, 0.2, {1, 0, 0}, 2}, {0.0, 0.9, {0, 0.8, 0}, 2}, {-0.3, 0.5, {0, 0, 1}, 2}};
    for (int m = 1; m <= 8; m++)
        check_stack(&t, three, 3, m, LC_ESTIMATOR_MIDPOINT, 60, 500, LC_DEPTH_RANGE_GLOBAL);
    check_stack(&t, three, 3, 5, LC_ESTIMATOR_FOO, 60, 500, LC_DEPTH_RANGE_GLOBAL);
    check_stack(&t, three, 3, 3, LC_ESTIMATOR_FOO, 20, 5, LC_DEPTH_RANGE_GLOBAL);
    const test_quad five[5] = {{0.4, 0.1, {1, 0, 0}, 2},
                               {0.2, 0.6, {1, 1, 0}, 2},
                               {0.0, 0.3, {0, 1, 1}, 2},
                               {-0.2, 0.95, {0, 0, 1}, 2},
                               {-0.4, 0.0, {1, 0, 1}, 2}};
    check_stack(&t, five, 5, 5, LC_ESTIMATOR_MIDPOINT, 60, 500, LC_DEPTH_RANGE_GLOBAL);
    check_stack(&t, five, 5, 8, LC_ESTIMATOR_FOO, 100, 200, LC_DEPTH_RANGE_GLOBAL);
    /* Per-pixel depth ranges (P0): the pixel's stack spans [1/4, 3/4]. */
    for (int m = 1; m <= 8; m += 7)
        check_stack(&t, three, 3, m, LC_ESTIMATOR_MIDPOINT, 60, 500, LC_DEPTH_RANGE_PIXEL);
    check_stack(&t, five, 5, 5, LC_ESTIMATOR_FOO, 60, 500, LC_DEPTH_RANGE_PIXEL);
    /* Depth warped around the pixel's importance mass (P0 "moments"). */
    for (int m = 1; m <= 8; m += 3)
        check_stack(&t, three, 3, m, LC_ESTIMATOR_MIDPOINT, 60, 500, LC_DEPTH_RANGE_MOMENTS);
    check_stack(&t, five, 5, 5, LC_ESTIMATOR_MIDPOINT, 60, 500, LC_DEPTH_RANGE_MOMENTS);
    check_stack(&t, five, 5, 8, LC_ESTIMATOR_FOO, 100, 200, LC_DEPTH_RANGE_MOMENTS);

    /* An unimportant layer in front of an important one: q > 0 clears it,
     * q = 0 (and r = 0) leaves it opaque. */
    const test_quad two[2] = {{0.3, 0.1, {1, 0, 0}, 2}, {-0.3, 0.9, {0, 1, 0}, 2}};
    lc_scene *s = test_quad_scene(two, 2);
    lc_render_params p;
    test_quad_params(&p, 32);
    uint8_t rgba[32 * 32 * 4];
    p.foo.q = 0, p.foo.r = 0;
    render(&t, s, &p, rgba);
    int c = (16 * 32 + 16) * 4;
    CHECK(rgba[c] > 240 && rgba[c + 1] < 15, "q=0: front red layer stays opaque (got %d %d %d)", rgba[c], rgba[c + 1],
          rgba[c + 2]);
    p.foo.q = 60;
    render(&t, s, &p, rgba);
    CHECK(rgba[c + 1] > 180 && rgba[c] < 60, "q=60: front layer clears to show green (got %d %d %d)", rgba[c],
          rgba[c + 1], rgba[c + 2]);
    lc_scene_destroy(s);

    test_gl_close(&t);
    return lc_test_finish();
}
