/* Ground shadows and smart transparency (docs/ALGORITHM.md §29), by pixel
 * values against the CPU:
 * 1. A slab of alpha 0.5 (q = r = 0, target opacity 0.5) above the ground,
 *    seen obliquely so that the slab does not hide its shadow: the ground in
 *    the shadow is C (1 - s/2) for s = style.shadow (grey), and with
 *    style.shadowColored and a red slab its red channel stays C; the ground
 *    beside the shadow keeps C exactly; style.shadow 0 is the frame without it.
 * 2. A small quad in front of a larger one, seen head-on: style.smartTransparency
 *    changes the image exactly as the CPU's injection, diffusion and blend of
 *    the two quads' coverage give (every pixel within 1 of 255), and a frame
 *    with strength 0 is bit for bit the plain frame.
 * 3. A flat context layer as the floor receives the shadow the same way: s = 1
 *    halves it under the slab, and leaves it beside the shadow.
 * Refusals name their fields. */
#include <math.h>

#include "lc_base.h"
#include "render_util.h"

#define SIZE 128
#define STEP 0.0039293 /* smart.comp.glsl's SMART_MIN_STEP */

/* rgb colours, importance 1, as render_util.h's quads are drawn. */
static void quad_mapping(lc_render_params *p)
{
    snprintf(p->color.attribute, sizeof p->color.attribute, "rgb");
    snprintf(p->importance.attribute, sizeof p->importance.attribute, "importance");
    p->importance.has_range = true;
    p->importance.range[0] = 0, p->importance.range[1] = 1;
}

static void slab_params(lc_render_params *p)
{
    lc_render_params_default(p);
    quad_mapping(p);
    p->width = p->height = SIZE;
    p->foo.q = 0, p->foo.r = 0, p->foo.target_opacity = 0.5, p->foo.clarity = 0;
    p->has_camera = true;
    lc_camera *c = &p->camera;
    const double focal[3] = {0, 0, 0.3}, v[3] = {0, M_SQRT1_2, -M_SQRT1_2};
    for (int i = 0; i < 3; i++)
        c->focal_point[i] = focal[i], c->position[i] = focal[i] - 4 * v[i];
    c->view_up[1] = c->view_up[2] = M_SQRT1_2;
    c->parallel_projection = true;
    c->parallel_scale = 1.2;
    p->style.shadow_light[2] = 1;
    p->style.ground_offset = 1; /* the ground at z = 1 - sqrt(2): its shadow lies below the slab on screen */
}

/* Pixel (x, y) of an image (rows top-down), channel ch. */
static int px(const uint8_t *img, int x, int y, int ch) { return img[4 * (y * SIZE + x) + ch]; }

/* The image pixel of world point w under slab_params' parallel camera. */
static void project(const double w[3], int *x, int *y)
{
    const double focal[3] = {0, 0, 0.3}, up[3] = {0, M_SQRT1_2, M_SQRT1_2};
    double u = 0, r = w[0] - focal[0];
    for (int i = 0; i < 3; i++)
        u += (w[i] - focal[i]) * up[i];
    *x = (int)floor((r / 1.2 + 1) * 0.5 * SIZE);
    *y = (int)floor((1 - u / 1.2) * 0.5 * SIZE);
}

static void shadows(test_gl *t)
{
    test_quad grey = {.z = 1, .g = 1, .rgb = {0.5, 0.5, 0.5}, .half = 0.5}, red = grey;
    red.rgb[0] = 1, red.rgb[1] = red.rgb[2] = 0;
    lc_scene *sg = test_quad_scene(&grey, 1), *sr = test_quad_scene(&red, 1);
    lc_gpu_scene *gg = NULL, *gr = NULL;
    lc_error err = {0};
    CHECK(sg && sr && lc_gpu_scene_create(sg, &gg, &err) == 0 && lc_gpu_scene_create(sr, &gr, &err) == 0, "scenes: %s",
          err.msg);
    if (!gg || !gr)
        return;
    uint8_t *img = malloc(SIZE * SIZE * 4), *plain = malloc(SIZE * SIZE * 4);
    const double ground_z = 1 - sqrt(2.0), under[3] = {0, 0, ground_z}, beside[3] = {1.0, 0, ground_z};
    int ux, uy, bx, by;
    project(under, &ux, &uy);
    project(beside, &bx, &by);
    const int C = (int)lround(0.8 * 255);
    lc_render_params p;
    static const double opacities[3] = {1, 0.6, 0.25};
    for (int k = 0; k < 3; k++) {
        double s = opacities[k];
        for (int colored = 0; colored < 2; colored++) {
            slab_params(&p);
            p.style.shadow = s, p.style.shadow_colored = colored;
            test_render_frame(t, colored ? gr : gg, &p, NULL, img, NULL);
            double expect = C * (1 - 0.5 * s); /* T = exp(-(-ln 0.5)) = 1/2 */
            int r = px(img, ux, uy, 0), g = px(img, ux, uy, 1), b = px(img, ux, uy, 2);
            printf("shadow %.2f%s: ground under the slab (%d, %d) = %d %d %d, CPU %.2f (red channel %s); beside it "
                   "(%d, %d) = %d (CPU %d)\n",
                   s, colored ? " coloured" : "", ux, uy, r, g, b, expect, colored ? "kept" : "shadowed", bx, by,
                   px(img, bx, by, 1), C);
            CHECK(fabs(g - expect) <= 1 && fabs(b - expect) <= 1, "shadow %.2f: %d %d against %.2f", s, g, b, expect);
            CHECK(fabs(r - (colored ? C : expect)) <= 1, "shadow %.2f%s: red %d", s, colored ? " coloured" : "", r);
            for (int ch = 0; ch < 3; ch++)
                CHECK(px(img, bx, by, ch) == C, "no shadow where nothing is above: %d", px(img, bx, by, ch));
        }
    }
    /* shadow 0 with the ground on: the ground unshadowed, the slab as before. */
    slab_params(&p);
    p.style.ground = LC_GROUND_ON;
    test_render_frame(t, gg, &p, NULL, plain, NULL);
    CHECK(px(plain, ux, uy, 1) == C, "style.shadow 0 leaves the ground as it is (%d)", px(plain, ux, uy, 1));
    /* Refusals: nothing receives the shadow; antialias with the ground. */
    slab_params(&p);
    p.style.shadow = 1, p.style.ground = LC_GROUND_OFF;
    int rc = lc_render_frame(t->renderer, gg, &p, NULL, 0, img, NULL, &err);
    CHECK(rc != 0 && strcmp(err.field, "style.shadow") == 0, "no receiver refused naming style.shadow (%s)", err.field);
    /* Another method draws none of it (the scope table refuses a request giving it there; a
     * session keeping it from an earlier update draws without it): wboit's frame is its plain one. */
    slab_params(&p);
    p.method = LC_METHOD_WBOIT;
    test_render_frame(t, gg, &p, NULL, plain, NULL);
    p.style.shadow = 1, p.style.ground = LC_GROUND_ON, p.style.smart = 1;
    test_render_frame(t, gg, &p, NULL, img, NULL);
    CHECK(memcmp(img, plain, SIZE * SIZE * 4) == 0, "wboit draws no shadow, ground or outline");
    slab_params(&p);
    p.style.ground = LC_GROUND_ON, p.style.antialias = 4;
    rc = lc_render_frame(t->renderer, gg, &p, NULL, 0, img, NULL, &err);
    CHECK(rc != 0 && strcmp(err.field, "style.ground") == 0, "antialias refused naming style.ground (%s)", err.field);
    free(img);
    free(plain);
    lc_gpu_scene_destroy(gg);
    lc_gpu_scene_destroy(gr);
    lc_scene_destroy(sg);
    lc_scene_destroy(sr);
}

/* A context layer receives the shadow: a flat grey floor at z = 0 under the
 * slab (the ground plane then not drawn); its pixel under the slab is the
 * unshadowed render's times 1 - s/2. */
static void context_receiver(test_gl *t)
{
    test_quad floor_q = {.z = 0, .g = 1, .rgb = {0.5, 0.5, 0.5}, .half = 1.2},
              slab = {.z = 1, .g = 1, .rgb = {0.5, 0.5, 0.5}, .half = 0.5};
    lc_scene *sf = test_quad_scene(&floor_q, 1), *ss = test_quad_scene(&slab, 1);
    lc_gpu_scene *gf = NULL, *gs = NULL;
    lc_error err = {0};
    CHECK(sf && ss && lc_gpu_scene_create(sf, &gf, &err) == 0 && lc_gpu_scene_create(ss, &gs, &err) == 0, "scenes: %s",
          err.msg);
    if (!gf || !gs)
        return;
    const lc_gpu_scene *scenes[2] = {gf, gs};
    lc_layer_params layers[2];
    for (int i = 0; i < 2; i++) {
        lc_layer_params_default(&layers[i]);
        snprintf(layers[i].color.attribute, sizeof layers[i].color.attribute, "rgb");
        snprintf(layers[i].importance.attribute, sizeof layers[i].importance.attribute, "importance");
        layers[i].importance.has_range = true;
        layers[i].importance.range[1] = 1;
    }
    layers[0].role = LC_LAYER_CONTEXT;
    layers[0].style.shading = LC_SHADING_NONE;
    uint8_t *lit = malloc(SIZE * SIZE * 4), *shadowed = malloc(SIZE * SIZE * 4);
    lc_render_params p;
    slab_params(&p);
    int rc = lc_render_layers(t->renderer, scenes, layers, 2, &p, NULL, 0, lit, NULL, &err);
    CHECK(rc == 0, "render: %s", err.msg);
    p.style.shadow = 1;
    rc = lc_render_layers(t->renderer, scenes, layers, 2, &p, NULL, 0, shadowed, NULL, &err);
    CHECK(rc == 0, "render: %s", err.msg);
    const double under[3] = {0, 0, 0}, beside[3] = {1.0, 0, 0};
    int ux, uy, bx, by;
    project(under, &ux, &uy);
    project(beside, &bx, &by);
    int c = px(lit, ux, uy, 1), d = px(shadowed, ux, uy, 1);
    printf("context floor under the slab (%d, %d): %d unshadowed, %d with shadow 1 (CPU %.1f); beside it %d and %d\n",
           ux, uy, c, d, c * 0.5, px(lit, bx, by, 1), px(shadowed, bx, by, 1));
    CHECK(fabs(d - c * 0.5) <= 1, "a context layer receives the shadow: %d against %.1f", d, c * 0.5);
    CHECK(px(lit, bx, by, 1) == px(shadowed, bx, by, 1), "and none beside it");
    free(lit), free(shadowed);
    lc_gpu_scene_destroy(gf), lc_gpu_scene_destroy(gs);
    lc_scene_destroy(sf), lc_scene_destroy(ss);
}

static void head_on(lc_render_params *p)
{
    lc_render_params_default(p);
    quad_mapping(p);
    p->width = p->height = SIZE;
    p->foo.q = 0, p->foo.r = 0, p->foo.target_opacity = 0.5, p->foo.clarity = 0;
    p->has_camera = true;
    lc_camera *c = &p->camera;
    c->position[2] = 4;
    c->view_up[1] = 1;
    c->parallel_projection = true;
    c->parallel_scale = 1.0;
}

/* The pixels a scene covers: those that differ from the white background. */
static void coverage(test_gl *t, const lc_gpu_scene *gs, uint8_t *mask, uint8_t *img)
{
    lc_render_params p;
    head_on(&p);
    test_render_frame(t, gs, &p, NULL, img, NULL);
    for (int i = 0; i < SIZE * SIZE; i++)
        mask[i] = img[4 * i] != 255 || img[4 * i + 1] != 255 || img[4 * i + 2] != 255;
}

static void smart(test_gl *t)
{
    test_quad q[2] = {{.z = 0, .g = 1, .rgb = {0.2, 0.3, 0.9}, .half = 0.7},
                      {.z = 0.5, .g = 1, .rgb = {0.9, 0.2, 0.1}, .half = 0.3}};
    lc_scene *both = test_quad_scene(q, 2), *back = test_quad_scene(&q[0], 1), *front = test_quad_scene(&q[1], 1);
    lc_gpu_scene *gb = NULL, *gback = NULL, *gfront = NULL;
    lc_error err = {0};
    CHECK(both && back && front && lc_gpu_scene_create(both, &gb, &err) == 0 &&
              lc_gpu_scene_create(back, &gback, &err) == 0 && lc_gpu_scene_create(front, &gfront, &err) == 0,
          "scenes: %s", err.msg);
    if (!gb || !gback || !gfront)
        return;
    size_t n = SIZE * SIZE;
    uint8_t *mb = malloc(n), *mf = malloc(n), *off = malloc(4 * n), *on = malloc(4 * n), *zero = malloc(4 * n);
    coverage(t, gback, mb, on);
    coverage(t, gfront, mf, on);
    lc_render_params p;
    head_on(&p);
    test_render_frame(t, gb, &p, NULL, off, NULL);
    p.style.smart = 0;
    p.style.smart_iterations = 9;
    test_render_frame(t, gb, &p, NULL, zero, NULL);
    CHECK(memcmp(zero, off, 4 * n) == 0, "strength 0 is the plain frame");
    const double strength = 0.8;
    p.style.smart = strength, p.style.smart_iterations = 5;
    test_render_frame(t, gb, &p, NULL, on, NULL);

    /* The CPU: optical depth per pixel (rows top-down, as the image). */
    double tau = -log(0.5), *a0 = malloc(n * sizeof *a0), *inj = calloc(2 * n, sizeof *inj),
           *v = malloc(2 * n * sizeof *v), *w = malloc(2 * n * sizeof *w);
    for (size_t i = 0; i < n; i++)
        a0[i] = tau * (mb[i] + mf[i]);
    static const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
    for (int y = 0; y < SIZE; y++)
        for (int x = 0; x < SIZE; x++) {
            size_t i = (size_t)y * SIZE + x;
            for (int k = 0; k < 4; k++) {
                int qx = x + dx[k], qy = y + dy[k];
                if (qx < 0 || qy < 0 || qx >= SIZE || qy >= SIZE)
                    continue;
                size_t j = (size_t)qy * SIZE + qx;
                double d = a0[i] - a0[j];
                if (d > STEP)
                    inj[2 * i] = fmax(inj[2 * i], 1 - exp(-d));
                else if (-d > STEP && a0[i] > STEP) /* the layer p lacks is the front quad: in front */
                    inj[2 * i + 1] = fmax(inj[2 * i + 1], 1 - exp(d));
            }
        }
    memcpy(v, inj, 2 * n * sizeof *v);
    for (int it = 0; it < p.style.smart_iterations; it++) {
        for (int y = 0; y < SIZE; y++)
            for (int x = 0; x < SIZE; x++) {
                size_t i = (size_t)y * SIZE + x;
                double s0 = 0, s1 = 0;
                for (int k = 0; k < 4; k++) {
                    int qx = x + dx[k], qy = y + dy[k];
                    if (qx < 0 || qy < 0 || qx >= SIZE || qy >= SIZE)
                        continue;
                    size_t j = (size_t)qy * SIZE + qx;
                    s0 += a0[i] >= a0[j] - STEP ? v[2 * j] : 0;
                    s1 += a0[i] <= a0[j] + STEP ? v[2 * j + 1] : 0;
                }
                w[2 * i] = fmax(inj[2 * i], 0.25 * s0);
                w[2 * i + 1] = fmax(inj[2 * i + 1], 0.25 * s1);
            }
        memcpy(v, w, 2 * n * sizeof *v);
    }
    int worst = 0, changed = 0, darker = 0, lighter = 0;
    for (size_t i = 0; i < n; i++) {
        for (int ch = 0; ch < 3; ch++) {
            double c = off[4 * i + ch] / 255.0 * (1 - strength * v[2 * i]);
            c += (1 - c) * strength * v[2 * i + 1];
            int e = (int)lround(c * 255), d = abs(e - on[4 * i + ch]);
            worst = d > worst ? d : worst;
        }
        changed += memcmp(on + 4 * i, off + 4 * i, 3) != 0;
        darker += on[4 * i] < off[4 * i] && mf[i];
        lighter += on[4 * i] > off[4 * i] && mb[i] && !mf[i];
    }
    printf("smart transparency %.1f, 5 steps: %d pixels changed (%d darker on the front quad, %d lighter beside it); "
           "largest difference from the CPU %d\n",
           strength, changed, darker, lighter, worst);
    CHECK(worst <= 1, "every pixel within 1 of the CPU (%d)", worst);
    CHECK(darker > 4 * 40 && lighter > 4 * 40, "silhouettes inside the front quad's edge (%d), halos outside (%d)",
          darker, lighter);
    /* Tiled stills refuse it. */
    lc_renderer_set_tile_size(t->renderer, 64);
    int rc = lc_render_frame(t->renderer, gb, &p, NULL, 0, on, NULL, &err);
    CHECK(rc != 0 && strcmp(err.field, "style.smartTransparency") == 0, "tiles refused naming it (%s)", err.field);
    lc_renderer_set_tile_size(t->renderer, 0);
    free(a0), free(inj), free(v), free(w), free(mb), free(mf), free(off), free(on), free(zero);
    lc_gpu_scene_destroy(gb), lc_gpu_scene_destroy(gback), lc_gpu_scene_destroy(gfront);
    lc_scene_destroy(both), lc_scene_destroy(back), lc_scene_destroy(front);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    shadows(&t);
    context_receiver(&t);
    smart(&t);
    test_gl_close(&t);
    return lc_test_finish();
}
