/* Opaque context layers (docs/ALGORITHM.md §24): a plane with the tornado
 * lines. Where the plane lies in front of every line, the picture is exactly
 * the plane's shaded colour (Fourier and exact alike) and no line fragment
 * behind it reaches the importance sums; with the plane through the middle of
 * the tornado, Fourier agrees with the exact method on the same scene; a
 * context layer of points is refused naming layers[i].role. A tiled still
 * with the plane as context equals the untiled one (SSIM >= 0.999: each tile
 * draws its part of the context), and antialiased stills jitter the context
 * too: the plane's edges get intermediate colours that one sample never has.
 * Prints the cost of the context pass (wall time with the plane as context
 * against hidden). */
#include <math.h>

#include "demo.h"
#include "image.h"
#include "lc_base.h"
#include "render_util.h"

#define SIZE 192
#define SSIM_MIN 0.98

/* A plane z = z0 over [x0, x1] x [y0, y1] (two triangles, one patch, rgb colour). */
static lc_scene *plane(double z0, double x0, double x1, double y0, double y1)
{
    lc_error err = {0};
    lc_scene *s = lc_scene_create("plane", LC_PRIM_TRIANGLES);
    if (!s || lc_scene_alloc_vertices(s, 4, 1, &err) != 0)
        return NULL;
    static const uint32_t tri[6] = {0, 1, 2, 0, 2, 3};
    float *g = malloc(4 * sizeof *g); /* the scene takes it */
    for (int v = 0; v < 4; v++)
        g[v] = 0.5f;
    s->triangles = malloc(sizeof tri);
    memcpy(s->triangles, tri, sizeof tri);
    s->triangle_count = 2;
    for (int v = 0; v < 4; v++) {
        s->positions[3 * v] = (float)(v == 0 || v == 3 ? x0 : x1);
        s->positions[3 * v + 1] = (float)(v < 2 ? y0 : y1);
        s->positions[3 * v + 2] = (float)z0;
        s->rgb[3 * v] = 0.8f, s->rgb[3 * v + 1] = 0.45f, s->rgb[3 * v + 2] = 0.2f;
    }
    return test_finish_scene(s, g, (lc_elements_desc){.patch_count = 1});
}

static int draw(test_gl *t, const lc_gpu_scene *const *scenes, const lc_layer_params *layers, const lc_render_params *p,
                uint8_t *rgba, double *ms)
{
    lc_error err = {0};
    lc_frame_info info;
    int rc = lc_render_layers(t->renderer, scenes, layers, 2, p, NULL, 0, rgba, &info, &err);
    CHECK(rc == 0, "render (%s): %s", lc_method_name(p->method), err.msg);
    if (ms)
        *ms = info.wall_ms;
    return rc;
}

static void params(lc_render_params *p, lc_method method)
{
    lc_render_params_default(p);
    p->width = p->height = SIZE;
    p->method = method;
    p->has_camera = true;
    lc_camera *c = &p->camera;
    c->position[0] = 0.5, c->position[1] = 0.5, c->position[2] = 4;
    c->focal_point[0] = 0.5, c->focal_point[1] = 0.5, c->focal_point[2] = 0.5;
    c->view_up[1] = 1;
    c->parallel_projection = true;
    c->parallel_scale = 0.6;
}

/* The plane's pixels: equal in the plane-alone renders over two backgrounds. */
static int plane_mask(test_gl *t, const lc_gpu_scene *const *scenes, lc_layer_params *layers, uint8_t *mask,
                      uint8_t *alone)
{
    lc_render_params p;
    params(&p, LC_METHOD_FOURIER);
    uint8_t *other = malloc(SIZE * SIZE * 4);
    layers[1].visible = false;
    int rc = draw(t, scenes, layers, &p, alone, NULL);
    p.style.background[0] = p.style.background[1] = p.style.background[2] = 0;
    rc |= draw(t, scenes, layers, &p, other, NULL);
    layers[1].visible = true;
    int n = 0;
    for (int i = 0; i < SIZE * SIZE; i++) {
        mask[i] = memcmp(alone + 4 * i, other + 4 * i, 3) == 0;
        n += mask[i];
    }
    free(other);
    return rc ? -1 : n;
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    lc_error err = {0};
    lc_scene *lines = NULL;
    lc_demo_desc desc = {.count = 200};
    CHECK(lc_demo_create("tornado", &desc, &lines, &err) == 0, "tornado: %s", err.msg);
    lc_scene *front = plane(1.2, -0.2, 0.5, -0.2, 1.2), *middle = plane(0.5, -0.2, 0.5, -0.2, 1.2),
             *back = plane(-0.5, -0.2, 0.5, -0.2, 1.2);
    lc_gpu_scene *gl = NULL, *gf = NULL, *gm = NULL, *gb = NULL;
    CHECK(lines && front && middle && back && lc_gpu_scene_create(lines, &gl, &err) == 0 &&
              lc_gpu_scene_create(front, &gf, &err) == 0 && lc_gpu_scene_create(middle, &gm, &err) == 0 &&
              lc_gpu_scene_create(back, &gb, &err) == 0,
          "scenes: %s", err.msg);
    if (!gl || !gf || !gm || !gb)
        return lc_test_finish();
    lc_layer_params layers[2];
    lc_layer_params_default(&layers[0]);
    lc_layer_params_default(&layers[1]);
    layers[0].role = LC_LAYER_CONTEXT;
    snprintf(layers[0].color.attribute, sizeof layers[0].color.attribute, "rgb");

    /* 1. The plane in front of every line of the left half. */
    const lc_gpu_scene *scenes[2] = {gf, gl};
    uint8_t *mask = malloc(SIZE * SIZE), *alone = malloc(SIZE * SIZE * 4), *img = malloc(SIZE * SIZE * 4);
    int covered = plane_mask(&t, scenes, layers, mask, alone);
    printf("the plane covers %d of %d pixels\n", covered, SIZE * SIZE);
    CHECK(covered > SIZE * SIZE / 4 && covered < SIZE * SIZE * 3 / 4, "the plane covers part of the view (%d)",
          covered);
    lc_method methods[2] = {LC_METHOD_FOURIER, LC_METHOD_EXACT};
    for (int m = 0; m < 2; m++) {
        lc_render_params p;
        params(&p, methods[m]);
        if (draw(&t, scenes, layers, &p, img, NULL) != 0)
            continue;
        int differ = 0, lines_seen = 0;
        for (int i = 0; i < SIZE * SIZE; i++) {
            differ += mask[i] && memcmp(img + 4 * i, alone + 4 * i, 4) != 0;
            lines_seen += !mask[i] && memcmp(img + 4 * i, alone + 4 * i, 4) != 0;
        }
        printf("%s: %d plane pixels differ from the plane alone; %d other pixels show lines\n",
               lc_method_name(p.method), differ, lines_seen);
        CHECK(differ == 0, "%s: every pixel where the plane is in front shows its shaded colour (%d differ)",
              lc_method_name(p.method), differ);
        CHECK(lines_seen > 500, "%s: the lines beside the plane are drawn (%d pixels)", lc_method_name(p.method),
              lines_seen);
        if (methods[m] != LC_METHOD_FOURIER)
            continue;
        /* No line fragment behind the plane reaches P1: the mass A'_0 is 0 under it. */
        size_t n = lc_renderer_read_targets(t.renderer, 0, NULL, 0);
        float *coef = malloc(n * sizeof *coef);
        lc_renderer_read_targets(t.renderer, 0, coef, n);
        int low = (SIZE + 1) / 2, under = 0, leaked = 0, beside = 0;
        for (int y = 0; y < low; y++)
            for (int x = 0; x < low; x++) {
                int all = 1; /* the low texel's 2x2 output pixels, image rows top-down */
                for (int k = 0; k < 4; k++)
                    all &= mask[(SIZE - 1 - (2 * y + k / 2)) * SIZE + 2 * x + k % 2];
                float mass = coef[4 * ((size_t)y * low + x)];
                under += all;
                leaked += all && mass != 0.0f;
                beside += !all && mass > 0.0f;
            }
        printf("P1 mass: %d texels under the plane, %d of them with mass; %d texels beside it with mass\n", under,
               leaked, beside);
        CHECK(under > 100 && leaked == 0 && beside > 100, "no importance behind the plane (%d of %d texels)", leaked,
              under);
        free(coef);
    }

    /* 2. The plane through the middle: Fourier against exact with the same context. */
    scenes[0] = gm;
    uint8_t *exact = malloc(SIZE * SIZE * 4);
    lc_render_params p;
    params(&p, LC_METHOD_FOURIER);
    double with_ms = 0, hidden_ms = 0, ms;
    draw(&t, scenes, layers, &p, img, NULL);
    params(&p, LC_METHOD_EXACT);
    draw(&t, scenes, layers, &p, exact, NULL);
    double ssim = lc_image_ssim(img, exact, SIZE, SIZE);
    printf("plane through the tornado as context, %dx%d: SSIM fourier against exact %.4f (threshold %.2f)\n", SIZE,
           SIZE, ssim, SSIM_MIN);
    CHECK(ssim >= SSIM_MIN, "SSIM %.4f below %.2f", ssim, SSIM_MIN);

    /* Tiles: the same frame from a renderer that tiles it into 64x64. */
    lc_renderer *tiler = NULL;
    lc_renderer_desc tdesc = {.tile_size = 64};
    CHECK(lc_renderer_create(&tdesc, &tiler, &err) == 0, "tiling renderer: %s", err.msg);
    params(&p, LC_METHOD_FOURIER);
    lc_frame_info tinfo = {0};
    uint8_t *tiled = malloc(SIZE * SIZE * 4);
    if (tiler && draw(&t, scenes, layers, &p, img, NULL) == 0 &&
        lc_render_layers(tiler, scenes, layers, 2, &p, NULL, 0, tiled, &tinfo, &err) == 0) {
        double tssim = lc_image_ssim(img, tiled, SIZE, SIZE);
        printf("tiled (%d tiles) against untiled with the plane as context: SSIM %.6f\n", tinfo.tiles, tssim);
        CHECK(tinfo.tiles > 1 && tssim >= 0.999, "tiled with context: %d tiles, SSIM %.6f", tinfo.tiles, tssim);
    } else {
        CHECK(0, "tiled frame with context: %s", err.msg);
    }
    lc_renderer_destroy(tiler);
    free(tiled);
    /* Antialiasing: a plane whose edges cross pixels (x 0.43, y 0.77), alone (lines hidden), one sample against 4. */
    lc_scene *odd = plane(0.5, -0.2, 0.43, -0.2, 0.77);
    lc_gpu_scene *go = NULL;
    CHECK(odd && lc_gpu_scene_create(odd, &go, &err) == 0, "plane: %s", err.msg);
    scenes[0] = go;
    layers[1].visible = false;
    int between[2] = {0, 0};
    for (int k = 0; k < 2; k++) {
        params(&p, LC_METHOD_FOURIER);
        p.style.antialias = k ? 4 : 1;
        if (draw(&t, scenes, layers, &p, img, NULL) != 0)
            continue;
        const uint8_t *bg = img + 4 * (SIZE - 1),
                      *fill = img + 4 * ((SIZE * 3 / 4) * SIZE + SIZE / 4); /* top right; in the plane */
        for (int i = 0; i < SIZE * SIZE; i++)
            between[k] += memcmp(img + 4 * i, bg, 3) != 0 && memcmp(img + 4 * i, fill, 3) != 0;
    }
    printf("plane alone as context: %d edge pixels of neither colour with one sample, %d with antialias 4\n",
           between[0], between[1]);
    CHECK(between[0] < SIZE / 8 && between[1] > SIZE / 2, "antialias jitters the context: %d against %d mixed pixels",
          between[1], between[0]);
    layers[1].visible = true;
    params(&p, LC_METHOD_FOURIER);
    p.style.antialias = 4;
    CHECK(draw(&t, scenes, layers, &p, img, NULL) == 0, "antialias 4 with the lines over the context");
    lc_gpu_scene_destroy(go);
    lc_scene_destroy(odd);

    /* The context pass's cost: a plane behind every line (it hides nothing)
     * as context against hidden (wall time; noisy on a loaded host). */
    scenes[0] = gb;
    params(&p, LC_METHOD_FOURIER);
    for (int k = 0; k < 5; k++) {
        layers[0].visible = true;
        draw(&t, scenes, layers, &p, img, &ms);
        with_ms += ms;
        layers[0].visible = false;
        draw(&t, scenes, layers, &p, img, &ms);
        hidden_ms += ms;
    }
    layers[0].visible = true;
    printf("context pass: %.1f ms a frame with a plane behind the lines as context, %.1f ms with it hidden (%dx%d, "
           "mean of 5)\n",
           with_ms / 5, hidden_ms / 5, SIZE, SIZE);

    /* 3. Points are no context. */
    lc_scene *pts = NULL;
    lc_gpu_scene *gp = NULL;
    lc_demo_desc pd = {.count = 1000};
    CHECK(lc_demo_create("points", &pd, &pts, &err) == 0 && lc_gpu_scene_create(pts, &gp, &err) == 0, "points: %s",
          err.msg);
    if (gp) {
        const lc_gpu_scene *bad[2] = {gp, gl};
        CHECK(lc_render_layers(t.renderer, bad, layers, 2, &p, NULL, 0, img, NULL, &err) != 0 &&
                  strcmp(err.field, "layers[0].role") == 0,
              "a context layer of points is refused naming layers[0].role (\"%s\": %s)", err.field, err.msg);
    }
    lc_gpu_scene_destroy(gp);
    lc_scene_destroy(pts);
    free(mask);
    free(alone);
    free(img);
    free(exact);
    lc_gpu_scene_destroy(gl);
    lc_gpu_scene_destroy(gf);
    lc_gpu_scene_destroy(gm);
    lc_gpu_scene_destroy(gb);
    lc_scene_destroy(back);
    lc_scene_destroy(lines);
    lc_scene_destroy(front);
    lc_scene_destroy(middle);
    test_gl_close(&t);
    return lc_test_finish();
}
