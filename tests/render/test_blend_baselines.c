/* The baselines at equal memory (FOO §5.3) on stacked quads: methods
 * "weighted-average" and "binning" composite the optimized opacities, and
 * every pixel covered by all quads equals the CPU formula on the same
 * fragments (foo_math.c: FOO opacities, then the baseline's compositing;
 * binning also under the moments warp). */
#include <math.h>

#include "camera.h"
#include "foo_math.h"
#include "render_util.h"

/* CPU evaluation of a pixel covered by every quad. */
static void expected_pixel(const test_quad *q, int n, const lc_render_params *p, const lc_scene *s, double out[3])
{
    /* Binning shares the Fourier method's moments warp (P0 at the optimization resolution). */
    lc_fragment frags[16];
    test_quad_fragments(q, n, p, s,
                        p->method == LC_METHOD_BINNING && lc_foo_depth_range(&p->foo) == LC_DEPTH_RANGE_MOMENTS, frags);
    lc_foo_alpha_fourier(frags, (size_t)n, &p->foo);
    if (p->method == LC_METHOD_WEIGHTED_AVERAGE)
        lc_foo_composite_weighted_average(frags, (size_t)n, p->style.background, out);
    else
        lc_foo_composite_binned(frags, (size_t)n, 11, p->foo.estimator, p->style.background, out);
}

/* Renders the stack with method m and returns the worst channel error of the image. */
static double check_stack(test_gl *t, const test_quad *q, int n, lc_method m, lc_estimator est, lc_depth_range range)
{
    lc_scene *s = test_quad_scene(q, n);
    CHECK(s != NULL, "scene");
    if (!s)
        return 1;
    lc_render_params p;
    test_quad_params(&p, 48);
    p.method = m;
    p.foo.estimator = est;
    p.foo.depth_range = range;
    uint8_t *rgba = malloc(48 * 48 * 4);
    lc_error err = {0};
    lc_gpu_scene *gs = NULL;
    CHECK(lc_gpu_scene_create(s, &gs, &err) == 0, "gpu scene: %s", err.msg);
    lc_frame_info info;
    CHECK(lc_render_frame(t->renderer, gs, &p, NULL, 0, rgba, &info, &err) == 0, "render: %s", err.msg);
    lc_gpu_scene_destroy(gs);
    double want[3], worst = 0;
    expected_pixel(q, n, &p, s, want);
    for (int i = 0; i < 48 * 48; i++)
        for (int c = 0; c < 3; c++)
            worst = fmax(worst, fabs(rgba[4 * i + c] / 255.0 - want[c]));
    CHECK(worst <= 2.0 / 255.0, "%s, %d quads, %s: worst pixel error %.4f (want %.3f %.3f %.3f, got %d %d %d)",
          lc_method_name(m), n, lc_estimator_name(est), worst, want[0], want[1], want[2], rgba[0], rgba[1], rgba[2]);
    printf("%-16s %d quads %-8s %s range: expected (%.4f %.4f %.4f), worst error %.4f\n", lc_method_name(m), n,
           lc_estimator_name(est),
           range == LC_DEPTH_RANGE_PIXEL     ? "pixel  "
           : range == LC_DEPTH_RANGE_MOMENTS ? "moments"
                                             : "global ",
           want[0], want[1], want[2], worst);
    free(rgba);
    lc_scene_destroy(s);
    return worst;
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    printf("renderer: %s\n", lc_gl_renderer(t.gl));

    /* Two fragments: the weighted average of the brief's row. */
    const test_quad two[2] = {{0.3, 0.2, {1, 0, 0}, 2}, {-0.3, 0.9, {0, 0.8, 0}, 2}};
    const test_quad three[3] = {{0.3, 0.2, {1, 0, 0}, 2}, {0.0, 0.9, {0, 0.8, 0}, 2}, {-0.3, 0.5, {0, 0, 1}, 2}};
    /* Five quads, two of them in one depth bin (normalized depths 0.5 and 0.52). */
    const test_quad five[5] = {{0.4, 0.1, {1, 0, 0}, 2},
                               {0.02, 0.6, {1, 1, 0}, 2},
                               {0.0, 0.3, {0, 1, 1}, 2},
                               {-0.2, 0.95, {0, 0, 1}, 2},
                               {-0.4, 0.0, {1, 0, 1}, 2}};
    const lc_method methods[2] = {LC_METHOD_WEIGHTED_AVERAGE, LC_METHOD_BINNING};
    for (int k = 0; k < 2; k++) {
        check_stack(&t, two, 2, methods[k], LC_ESTIMATOR_MIDPOINT, LC_DEPTH_RANGE_GLOBAL);
        check_stack(&t, three, 3, methods[k], LC_ESTIMATOR_FOO, LC_DEPTH_RANGE_GLOBAL);
        check_stack(&t, five, 5, methods[k], LC_ESTIMATOR_MIDPOINT, LC_DEPTH_RANGE_GLOBAL);
        check_stack(&t, five, 5, methods[k], LC_ESTIMATOR_FOO, LC_DEPTH_RANGE_PIXEL);
    }
    check_stack(&t, three, 3, LC_METHOD_BINNING, LC_ESTIMATOR_MIDPOINT, LC_DEPTH_RANGE_MOMENTS);
    check_stack(&t, five, 5, LC_METHOD_BINNING, LC_ESTIMATOR_MIDPOINT, LC_DEPTH_RANGE_MOMENTS);

    /* The order matters to binning, not to the weighted average: swapping the
     * colours of the two-quad stack's layers changes the first only. */
    lc_fragment a[2] = {{0.3, 0.5, 0.6, {1, 0, 0}}, {0.7, 0.5, 0.6, {0, 0, 1}}};
    lc_fragment b[2] = {{0.3, 0.5, 0.6, {0, 0, 1}}, {0.7, 0.5, 0.6, {1, 0, 0}}};
    const double white[3] = {1, 1, 1};
    double wa[3], wb[3], ba[3], bb[3];
    lc_foo_composite_weighted_average(a, 2, white, wa);
    lc_foo_composite_weighted_average(b, 2, white, wb);
    lc_foo_composite_binned(a, 2, 11, LC_ESTIMATOR_MIDPOINT, white, ba);
    lc_foo_composite_binned(b, 2, 11, LC_ESTIMATOR_MIDPOINT, white, bb);
    CHECK(fabs(wa[0] - wb[0]) < 1e-12 && fabs(wa[2] - wb[2]) < 1e-12, "weighted average ignores order");
    CHECK(ba[0] > bb[0] + 0.1 && bb[2] > ba[2] + 0.1, "binning puts the front layer first (%.3f vs %.3f)", ba[0],
          bb[0]);
    test_gl_close(&t);
    return lc_test_finish();
}
