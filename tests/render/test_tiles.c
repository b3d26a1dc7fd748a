/* Tiled stills (frame.c "Tiled stills"): a frame composited in tiles after one
 * optimization of the whole view is the image of one untiled frame. */
#include "demo.h"
#include "image.h"
#include "render_util.h"

#define W 1024
#define H 768

typedef struct case_ {
    const char *name;
    lc_method method;
    lc_depth_range range;
    int antialias;
    double guard;
    int tile; /* lc_renderer_desc.tile_size */
    int tiles; /* tiles expected */
} case_;

static int render(lc_renderer *r, const lc_gpu_scene *gs, const lc_render_params *p, uint8_t *rgba,
                  lc_frame_info *info)
{
    lc_error err = {0};
    int rc = lc_render_frame(r, gs, p, NULL, 0.0, rgba, info, &err);
    if (rc)
        fprintf(stderr, "render: %s\n", err.msg);
    return rc;
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    lc_error err = {0};
    lc_scene *s = NULL;
    lc_gpu_scene *gs = NULL;
    lc_demo_desc dd = {.count = 300};
    if (lc_demo_create("tornado", &dd, &s, &err) != 0 || lc_gpu_scene_create(s, &gs, &err) != 0) {
        fprintf(stderr, "tornado: %s\n", err.msg);
        return 1;
    }
    static const case_ cases[] = {
        {"fourier (moments)", LC_METHOD_FOURIER, LC_DEPTH_RANGE_AUTO, 1, 0, 400, 6},
        {"fourier pixel range, antialias 2, guard band", LC_METHOD_FOURIER, LC_DEPTH_RANGE_PIXEL, 2, 0.1, 512, 4},
        {"wboit", LC_METHOD_WBOIT, LC_DEPTH_RANGE_AUTO, 1, 0, 512, 4},
        {"opaque", LC_METHOD_OPAQUE, LC_DEPTH_RANGE_AUTO, 1, 0, 400, 6},
    };
    uint8_t *whole = malloc((size_t)W * H * 4), *tiled = malloc((size_t)W * H * 4);
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        const case_ *k = &cases[c];
        lc_renderer *small = NULL;
        lc_renderer_desc desc = {.tile_size = k->tile};
        CHECK(lc_renderer_create(&desc, &small, &err) == 0, "renderer: %s", err.msg);
        lc_render_params p;
        lc_render_params_default(&p);
        p.width = W, p.height = H;
        p.method = k->method;
        p.foo.depth_range = k->range;
        p.style.antialias = k->antialias;
        p.foo.guard_band = k->guard;
        lc_frame_info a = {0}, b = {0};
        if (small && render(t.renderer, gs, &p, whole, &a) == 0 && render(small, gs, &p, tiled, &b) == 0) {
            size_t same = 0, n = (size_t)W * H * 4;
            for (size_t i = 0; i < n; i++)
                same += whole[i] == tiled[i];
            double ssim = lc_image_ssim(whole, tiled, W, H);
            printf("%-45s %d tiles of <= %d: SSIM %.6f, %.4f%% of bytes identical\n", k->name, b.tiles, k->tile, ssim,
                   100.0 * same / n);
            CHECK(a.tiles == 0, "%s: the default renderer tiled a %dx%d frame", k->name, W, H);
            CHECK(b.tiles == k->tiles, "%s: %d tiles, expected %d", k->name, b.tiles, k->tiles);
            CHECK(ssim >= 0.999, "%s: tiled SSIM %.6f below 0.999", k->name, ssim);
            /* The background must not be the whole agreement: the tornado covers the frame's centre. */
            size_t covered = 0;
            for (size_t i = 0; i < (size_t)W * H; i++)
                covered += whole[4 * i] != whole[0] || whole[4 * i + 1] != whole[1] || whole[4 * i + 2] != whole[2];
            CHECK(covered > (size_t)W * H / 20, "%s: only %zu pixels show data", k->name, covered);
        } else {
            CHECK(0, "%s: render failed", k->name);
        }
        lc_renderer_destroy(small);
    }
    free(whole);
    free(tiled);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
    test_gl_close(&t);
    return lc_test_finish();
}
