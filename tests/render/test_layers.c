/* Layers (docs/ALGORITHM.md "Layers"): the points demo and the tornado lines
 * in one view. The summed targets of the two-layer frame equal the sums of
 * each layer's alone (the other hidden, so that camera and depth range stay
 * the same), the Fourier image agrees with the exact method on the same
 * scene, a one-layer frame equals the plain frame of its dataset bit for bit,
 * and a bad layer mapping is refused naming layers[i].field. */
#include <math.h>

#include "demo.h"
#include "image.h"
#include "render_util.h"

#define SIZE 256
#define SSIM_MIN 0.99

static lc_gpu_scene *demo(const char *name, uint64_t count, lc_scene **keep)
{
    lc_error err = {0};
    lc_demo_desc desc = {.count = count};
    lc_gpu_scene *gs = NULL;
    CHECK(lc_demo_create(name, &desc, keep, &err) == 0, "demo:%s: %s", name, err.msg);
    if (*keep)
        CHECK(lc_gpu_scene_create(*keep, &gs, &err) == 0, "upload demo:%s: %s", name, err.msg);
    return gs;
}

static int render_layers(test_gl *t, const lc_gpu_scene *const *scenes, const lc_layer_params *layers, int n,
                         const lc_render_params *p, lc_frame_state *st, uint8_t *rgba)
{
    lc_error err = {0};
    int rc = lc_render_layers(t->renderer, scenes, layers, n, p, st, 0, rgba, NULL, &err);
    CHECK(rc == 0, "render layers (%s): %s", lc_method_name(p->method), err.msg);
    return rc;
}

/* Reads target set `which` of the last frame into a new array (*n floats). */
static float *targets(test_gl *t, int which, size_t *n)
{
    *n = lc_renderer_read_targets(t->renderer, which, NULL, 0);
    float *v = *n ? malloc(*n * sizeof *v) : NULL;
    if (v)
        lc_renderer_read_targets(t->renderer, which, v, *n);
    return v;
}

/* Both-visible targets against the sum of each layer's (the other hidden). */
static void check_sum(test_gl *t, const lc_gpu_scene *const *scenes, lc_layer_params *layers, lc_render_params p,
                      int which, const char *what)
{
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    float *part[3] = {NULL, NULL, NULL};
    size_t n[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++) {
        layers[0].visible = k != 1; /* k = 0: layer 0 alone, 1: layer 1 alone, 2: both */
        layers[1].visible = k != 0;
        if (render_layers(t, scenes, layers, 2, &p, NULL, rgba) == 0)
            part[k] = targets(t, which, &n[k]);
    }
    layers[0].visible = layers[1].visible = true;
    CHECK(part[0] && part[1] && part[2] && n[0] == n[2] && n[1] == n[2], "%s: targets read back", what);
    if (part[0] && part[1] && part[2] && n[0] == n[2] && n[1] == n[2]) {
        double scale = 0, worst = 0;
        int both = 0; /* texels where both layers have mass: the sum is not one layer's */
        for (size_t i = 0; i < n[2]; i++)
            scale = fmax(scale, fabs(part[2][i]));
        for (size_t i = 0; i < n[2]; i++) {
            worst = fmax(worst, fabs(part[2][i] - (part[0][i] + part[1][i])));
            both += part[0][i] != 0 && part[1][i] != 0;
        }
        printf("%s: %zu floats, max |both - (a + b)| = %.3g of max |both| %.3g; %d floats from both layers\n", what,
               n[2], worst, scale, both);
        CHECK(scale > 0 && both > 100, "%s: the layers overlap on screen (%d floats from both)", what, both);
        CHECK(worst <= 1e-5 * scale, "%s: both-visible targets differ from the sum by %.3g (scale %.3g)", what, worst,
              scale);
    }
    for (int k = 0; k < 3; k++)
        free(part[k]);
    free(rgba);
}

static void check_one_layer_is_plain(test_gl *t, const lc_gpu_scene *gs)
{
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    lc_layer_params l;
    lc_layer_params_default(&l);
    uint8_t *a = malloc(SIZE * SIZE * 4), *b = malloc(SIZE * SIZE * 4);
    lc_error err = {0};
    CHECK(lc_render_frame(t->renderer, gs, &p, NULL, 0, a, NULL, &err) == 0, "plain frame: %s", err.msg);
    render_layers(t, &gs, &l, 1, &p, NULL, b);
    size_t differ = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE * 4; i++)
        differ += a[i] != b[i];
    CHECK(differ == 0, "a one-layer frame differs from the plain frame in %zu bytes", differ);
    free(a);
    free(b);
}

static void check_errors(test_gl *t, const lc_gpu_scene *const *scenes, lc_layer_params *layers)
{
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = 32;
    uint8_t rgba[32 * 32 * 4];
    lc_error err = {0};
    lc_layer_params bad[2] = {layers[0], layers[1]};
    snprintf(bad[1].importance.attribute, sizeof bad[1].importance.attribute, "no_such_attribute");
    CHECK(lc_render_layers(t->renderer, scenes, bad, 2, &p, NULL, 0, rgba, NULL, &err) != 0 &&
              strcmp(err.field, "layers[1].importance.attribute") == 0 && strstr(err.msg, "no_such_attribute"),
          "unknown attribute of layer 1: field \"%s\", \"%s\"", err.field, err.msg);
    p.method = LC_METHOD_OPAQUE;
    CHECK(lc_render_layers(t->renderer, scenes, layers, 2, &p, NULL, 0, rgba, NULL, &err) != 0 &&
              strcmp(err.field, "method") == 0,
          "opaque method with layers: field \"%s\"", err.field);
    p.method = LC_METHOD_FOURIER;
    lc_frame_state *st = lc_frame_state_create(10); /* not the layers' element count */
    CHECK(lc_render_layers(t->renderer, scenes, layers, 2, &p, st, 0, rgba, NULL, &err) != 0,
          "a frame state of the wrong size is refused");
    lc_frame_state_destroy(st);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    lc_scene *sp = NULL, *sl = NULL;
    lc_gpu_scene *points = demo("points", 20000, &sp), *lines = demo("tornado", 200, &sl);
    if (!points || !lines)
        return lc_test_finish();
    const lc_gpu_scene *scenes[2] = {points, lines};
    lc_layer_params layers[2];
    lc_layer_params_default(&layers[0]);
    lc_layer_params_default(&layers[1]);
    snprintf(layers[1].color.colormap, sizeof layers[1].color.colormap, "coolwarm");

    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    /* P1's sums add over layers when the depth map is the bounds' (the moments
     * warp each depth by both layers' mass); the moments themselves add too. */
    p.foo.depth_range = LC_DEPTH_RANGE_GLOBAL;
    check_sum(&t, scenes, layers, p, 0, "P1 importance coefficients");
    p.foo.depth_range = LC_DEPTH_RANGE_MOMENTS;
    check_sum(&t, scenes, layers, p, 1, "P0 depth moments");

    /* Fourier against exact on the two-layer scene, defaults. */
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    uint8_t *a = malloc(SIZE * SIZE * 4), *b = malloc(SIZE * SIZE * 4);
    render_layers(&t, scenes, layers, 2, &p, NULL, a);
    p.method = LC_METHOD_EXACT;
    render_layers(&t, scenes, layers, 2, &p, NULL, b);
    double ssim = lc_image_ssim(a, b, SIZE, SIZE);
    printf("points + tornado, %dx%d: SSIM fourier against exact %.4f (threshold %.2f)\n", SIZE, SIZE, ssim, SSIM_MIN);
    CHECK(ssim >= SSIM_MIN, "SSIM %.4f below %.2f", ssim, SSIM_MIN);
    /* The layers' elements follow each other: a state of their sum is taken. */
    lc_frame_state *st = lc_frame_state_create(sp->elements.count + sl->elements.count);
    p.method = LC_METHOD_FOURIER;
    CHECK(st && render_layers(&t, scenes, layers, 2, &p, st, a) == 0, "two-layer frame with a state");
    /* Each layer's fragments reach its own elements: the lines' ids start after the points'. */
    const float *alpha = st ? lc_frame_state_alphas(st) : NULL;
    uint32_t seen[2] = {0, 0}, n0 = sp->elements.count, n = n0 + sl->elements.count;
    for (uint32_t e = 0; alpha && e < n; e++)
        seen[e >= n0] += alpha[e] < 0.999f;
    printf("elements below opacity 1: %u of %u points, %u of %u line segments\n", seen[0], n0, seen[1], n - n0);
    CHECK(seen[0] > n0 / 10 && seen[1] > (n - n0) / 10, "each layer's elements are optimized (%u, %u)", seen[0],
          seen[1]);
    lc_frame_state_destroy(st);
    free(a);
    free(b);

    check_one_layer_is_plain(&t, lines);
    check_errors(&t, scenes, layers);

    lc_gpu_scene_destroy(points);
    lc_gpu_scene_destroy(lines);
    lc_scene_destroy(sp);
    lc_scene_destroy(sl);
    test_gl_close(&t);
    return lc_test_finish();
}
