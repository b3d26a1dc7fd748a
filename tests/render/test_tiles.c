/* Tiled stills (frame.c "Tiled stills"): a frame composited in tiles after one
 * optimization of the whole view is the image of one untiled frame. */
#include <math.h>
#include <string.h>

#include "demo.h"
#include "equalize.h"
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
    int tile;     /* lc_renderer_desc.tile_size */
    int tiles;    /* tiles expected */
    int equalize; /* color.equalize: 1 one-shot, 2 a session's second frame */
} case_;

static int render(lc_renderer *r, const lc_gpu_scene *gs, const lc_render_params *p, lc_frame_state *st, uint8_t *rgba,
                  lc_frame_info *info)
{
    lc_error err = {0};
    int rc = lc_render_frame(r, gs, p, st, 0.1, rgba, info, &err);
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
        {"fourier (moments)", LC_METHOD_FOURIER, LC_DEPTH_RANGE_AUTO, 1, 0, 400, 6, 0},
        {"fourier pixel range, antialias 2", LC_METHOD_FOURIER, LC_DEPTH_RANGE_PIXEL, 2, 0, 512, 4, 0},
        /* the guard band widens the moments' view (with a pixel range it has none to widen: refused) */
        {"fourier (moments), guard band", LC_METHOD_FOURIER, LC_DEPTH_RANGE_AUTO, 1, 0.1, 512, 4, 0},
        {"wboit", LC_METHOD_WBOIT, LC_DEPTH_RANGE_AUTO, 1, 0, 512, 4, 0},
        {"weighted-average", LC_METHOD_WEIGHTED_AVERAGE, LC_DEPTH_RANGE_AUTO, 1, 0, 512, 4, 0},
        {"binning, pixel range, antialias 2", LC_METHOD_BINNING, LC_DEPTH_RANGE_PIXEL, 2, 0, 512, 4, 0},
        {"opaque", LC_METHOD_OPAQUE, LC_DEPTH_RANGE_AUTO, 1, 0, 400, 6, 0},
        {"fourier, color.equalize", LC_METHOD_FOURIER, LC_DEPTH_RANGE_AUTO, 1, 0, 400, 6, 1},
        {"direct, color.equalize, antialias 2", LC_METHOD_DIRECT, LC_DEPTH_RANGE_AUTO, 2, 0, 512, 4, 1},
        {"fourier, color.equalize, session", LC_METHOD_FOURIER, LC_DEPTH_RANGE_AUTO, 1, 0, 512, 4, 2},
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
        if (k->equalize) {
            snprintf(p.color.attribute, sizeof p.color.attribute, "velocity");
            p.color.equalize = true;
        }
        lc_frame_info a = {0}, b = {0};
        lc_frame_state *sa = NULL, *sb = NULL;
        if (k->equalize == 2) { /* the second frame measures the tiles as it draws them */
            sa = lc_frame_state_create(s->elements.count), sb = lc_frame_state_create(s->elements.count);
            CHECK(render(t.renderer, gs, &p, sa, whole, NULL) == 0, "%s: first", k->name);
            CHECK(small && render(small, gs, &p, sb, tiled, NULL) == 0, "%s: first", k->name);
        }
        if (small && render(t.renderer, gs, &p, sa, whole, &a) == 0 && render(small, gs, &p, sb, tiled, &b) == 0) {
            if (k->equalize) { /* one histogram over the tiles: the untiled frame's */
                double ha[LC_EQUALIZE_BINS], hb[LC_EQUALIZE_BINS], diff = 0, total = 0, knot = 0;
                float ka[LC_EQUALIZE_BINS + 1], kb[LC_EQUALIZE_BINS + 1];
                CHECK(lc_renderer_color_histogram(t.renderer, ha, ka) == 0 &&
                          lc_renderer_color_histogram(small, hb, kb) == 0,
                      "%s: histograms", k->name);
                for (int i = 0; i < LC_EQUALIZE_BINS; i++)
                    diff += fabs(ha[i] - hb[i]), total += ha[i];
                for (int i = 0; i <= LC_EQUALIZE_BINS; i++)
                    knot = fmax(knot, fabs(ka[i] - kb[i]));
                if (sa)
                    for (int i = 0; i <= LC_EQUALIZE_BINS; i++)
                        knot = fmax(knot,
                                    fabs(lc_frame_state_equalize_knots(sa)[i] - lc_frame_state_equalize_knots(sb)[i]));
                printf("%-45s histogram: sum %.1f, tiled differs by %.4f%%; transfer by %.5f\n", k->name, total,
                       100 * diff / total, knot);
                CHECK(total > 0.03 * W * H && diff <= 0.002 * total, "%s: tiled histogram off by %.4f%%", k->name,
                      100 * diff / total);
                CHECK(knot <= 0.002, "%s: tiled transfer off by %.5f", k->name, knot);
            }
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
        lc_frame_state_destroy(sa);
        lc_frame_state_destroy(sb);
        lc_renderer_destroy(small);
    }
    /* A work budget (lc_work.h): the renderer charges the time elapsed at its
     * yield points, here every tile. Counting only, it charges the frame's
     * time at the rate and no more; over its limit the frame ends with
     * LC_ERR_BUDGET naming the budget's field, writes no image, and the
     * renderer's next frame renders as before. */
    {
        lc_renderer *small = NULL;
        lc_renderer_desc desc = {.tile_size = 400};
        CHECK(lc_renderer_create(&desc, &small, &err) == 0, "renderer: %s", err.msg);
        lc_render_params p;
        lc_render_params_default(&p);
        p.width = W, p.height = H;
        lc_work_budget count, tight;
        lc_work_init(&count, 0, "width");
        lc_work_time(&count, 1e6);
        lc_renderer_set_work(small, &count);
        double t0 = lc_now();
        CHECK(small && render(small, gs, &p, NULL, tiled, NULL) == 0, "a counted frame renders");
        double elapsed = lc_now() - t0;
        CHECK(lc_work_used(&count) > 0 && lc_work_used(&count) <= elapsed * 1e6 + 1,
              "the frame's %.3f s charged at 1e6 units/s: %g", elapsed, lc_work_used(&count));
        lc_work_init(&tight, 1000, "width");
        lc_work_time(&tight, 1e12);
        lc_renderer_set_work(small, &tight);
        memset(tiled, 7, (size_t)W * H * 4);
        lc_error e = {0};
        int rc = small ? lc_render_frame(small, gs, &p, NULL, 0.1, tiled, NULL, &e) : 0;
        CHECK(rc == LC_ERR_BUDGET && strcmp(e.field, "width") == 0 && strstr(e.msg, "granted"),
              "over its budget the frame stops naming width: %d %s", rc, e.msg);
        CHECK(tiled[0] == 7 && tiled[(size_t)W * H * 4 - 1] == 7, "and writes no image");
        lc_renderer_set_work(small, NULL);
        CHECK(small && render(small, gs, &p, NULL, tiled, NULL) == 0, "the next frame renders");
        lc_renderer_destroy(small);
    }
    free(whole);
    free(tiled);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
    test_gl_close(&t);
    return lc_test_finish();
}
