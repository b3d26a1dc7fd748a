/* The compute rasterizer of P4 and P5 (compute_raster.c, docs/ALGORITHM.md
 * "Compute rasterization") gives the drawn passes' image on explicit small
 * scenes, each rendered both ways with lc_renderer_set_raster_path:
 * - point splats that cross every edge of the image (a camera close to the
 *   cloud): Fourier, direct, Fourier with normalize "off" (the paper's
 *   formula), a P4 subset stride and a tiled frame within SSIM >= 0.999 of
 *   the drawn frame, at most 0.2 % of the pixels more than 3/255 off (a pixel
 *   centre at a splat's rim may fall either side: GL snaps the corners to
 *   its sub-pixel grid);
 * - line ribbons (the tornado demo, halos on and off) within SSIM >= 0.999
 *   and 1 % of the pixels: coverage and interpolation as the drawn
 *   triangles'; with a P4 stride of 2 (whose drawn P4 pulls segments, each
 *   weighing twice, so that a rim pixel decided the other way counts double)
 *   SSIM >= 0.998;
 * - the same frame computed twice is the same bit for bit (the sums are
 *   integer atomics, so their order does not matter);
 * - a frame the compute path does not cover (surfaces) draws and says so;
 * - pre-emption (desc.preempted) between the dispatches of a computed pass of
 *   300k points, as at every other stopping point of the frame, ends it with
 *   LC_ERR_CANCELLED, and the next frame is byte for byte the frame before. */
#include <math.h>

#include "demo.h"
#include "image.h"
#include "render_util.h"

#define W 192
#define H 144

typedef struct diff {
    int max;
    double off; /* share of pixels more than 3/255 off in a channel */
    double ssim;
    double covered; /* share of pixels off the white background in the drawn frame */
} diff;

static diff compare(const uint8_t *drawn, const uint8_t *computed)
{
    diff d = {0, 0, lc_image_ssim(drawn, computed, W, H), 0};
    int covered = 0, off = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        int worst = 0;
        for (int c = 0; c < 3; c++) {
            int e = abs((int)drawn[4 * i + c] - (int)computed[4 * i + c]);
            worst = e > worst ? e : worst;
        }
        d.max = worst > d.max ? worst : d.max;
        off += worst > 3;
        covered += drawn[4 * i] + drawn[4 * i + 1] + drawn[4 * i + 2] < 3 * 250;
    }
    d.covered = (double)covered / ((double)W * H);
    d.off = (double)off / ((double)W * H);
    return d;
}

static void render(test_gl *t, const lc_gpu_scene *gs, const lc_render_params *p, int path, uint8_t *rgba,
                   lc_frame_info *info)
{
    lc_renderer_set_raster_path(t->renderer, path);
    test_render_frame(t, gs, p, NULL, rgba, info);
    lc_renderer_set_raster_path(t->renderer, -1);
}

/* Renders p drawn and computed; checks which path each took and the images. */
static void check_case(test_gl *t, const lc_gpu_scene *gs, const lc_render_params *p, const char *name, double min_ssim,
                       double max_off, uint8_t *drawn, uint8_t *computed)
{
    lc_frame_info di, ci;
    render(t, gs, p, 0, drawn, &di);
    render(t, gs, p, 1, computed, &ci);
    CHECK(di.computed_passes == 0 && ci.computed_passes == 3, "%s: drawn frame computed %d, computed frame %d (3)",
          name, di.computed_passes, ci.computed_passes);
    diff d = compare(drawn, computed);
    printf("%s: SSIM %.6f, %.4f of the pixels more than 3/255 off (max %d/255), %.2f of the pixels covered\n", name,
           d.ssim, d.off, d.max, d.covered);
    CHECK(d.covered > 0.1, "%s: the scene covers the image (%.2f)", name, d.covered);
    CHECK(d.ssim >= min_ssim, "%s: SSIM %.6f against the drawn passes (>= %.3f)", name, d.ssim, min_ssim);
    CHECK(d.off <= max_off, "%s: %.4f of the pixels more than 3/255 off (<= %.4f)", name, d.off, max_off);
}

typedef struct stopper {
    int calls, stop_at; /* preempted calls this frame; the one that says stop (0: none) */
} stopper;

static int preempted(void *ctx)
{
    stopper *st = ctx;
    return ++st->calls == st->stop_at;
}

static lc_gpu_scene *demo(const char *name, uint64_t count, lc_scene **s)
{
    lc_error err = {0};
    lc_demo_desc desc = {.count = count};
    lc_gpu_scene *gs = NULL;
    CHECK(lc_demo_create(name, &desc, s, &err) == 0 && lc_gpu_scene_create(*s, &gs, &err) == 0, "%s: %s", name,
          err.msg);
    return gs;
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    lc_error err = {0};
    uint8_t *drawn = malloc((size_t)W * H * 4), *computed = malloc((size_t)W * H * 4),
            *again = malloc((size_t)W * H * 4);
    lc_frame_info info;

    /* Points: one corner of the cloud from close by, splats across all four edges. */
    lc_scene *s = NULL;
    lc_gpu_scene *gs = demo("points", 3000, &s);
    if (gs) {
        double c[3], e = 0;
        for (int i = 0; i < 3; i++) {
            c[i] = 0.5 * (s->bounds[2 * i] + s->bounds[2 * i + 1]);
            e = fmax(e, s->bounds[2 * i + 1] - s->bounds[2 * i]);
        }
        lc_render_params p;
        lc_render_params_default(&p);
        p.width = W, p.height = H;
        p.has_camera = true;
        p.camera = (lc_camera){.position = {c[0] + 0.2 * e, c[1] + 0.1 * e, c[2] + 0.9 * e},
                               .focal_point = {c[0] + 0.2 * e, c[1] + 0.1 * e, c[2]},
                               .view_up = {0, 1, 0},
                               .view_angle = 30};
        p.style.point_size = 7;
        p.style.background[0] = p.style.background[1] = p.style.background[2] = 1;
        check_case(&t, gs, &p, "points, fourier", 0.999, 0.002, drawn, computed);
        render(&t, gs, &p, 1, again, &info);
        CHECK(memcmp(computed, again, (size_t)W * H * 4) == 0, "points: two computed frames differ");
        p.method = LC_METHOD_DIRECT;
        check_case(&t, gs, &p, "points, direct", 0.999, 0.002, drawn, computed);
        p.method = LC_METHOD_FOURIER;
        p.foo.normalize = LC_NORMALIZE_OFF;
        check_case(&t, gs, &p, "points, normalize off", 0.999, 0.002, drawn, computed);
        p.foo.normalize = LC_NORMALIZE_AUTO;
        p.foo.subset = 2;
        check_case(&t, gs, &p, "points, subset 2", 0.999, 0.002, drawn, computed);
        p.foo.subset = 1;

        /* Tiles: a renderer that tiles every frame above 64x64, computed,
         * against the untiled drawn frame (no seams, no shifted splats). */
        render(&t, gs, &p, 0, drawn, &info);
        lc_gl_release_current(t.gl);
        test_gl tiled = {.gl = t.gl};
        lc_renderer_desc td = {.tile_size = 64};
        CHECK(lc_gl_make_current(tiled.gl, &err) == 0 && lc_renderer_create(&td, &tiled.renderer, &err) == 0,
              "tiled renderer: %s", err.msg);
        if (tiled.renderer) {
            render(&tiled, gs, &p, 1, computed, &info);
            diff d = compare(drawn, computed);
            printf("points, tiled (%d tiles) computed against untiled drawn: SSIM %.6f, %.4f more than 3/255 off\n",
                   info.tiles, d.ssim, d.off);
            CHECK(info.tiles > 1 && info.computed_passes == 3, "tiled: %d tiles, computed %d", info.tiles,
                  info.computed_passes);
            CHECK(d.off <= 0.002 && d.ssim >= 0.999, "tiled: %.4f more than 3/255 off, SSIM %.6f", d.off, d.ssim);
            lc_renderer_destroy(tiled.renderer);
            lc_gl_release_current(tiled.gl);
        }
        CHECK(lc_gl_make_current(t.gl, &err) == 0, "context: %s", err.msg);
        lc_gpu_scene_destroy(gs);
        lc_scene_destroy(s);
    }

    /* Lines: the tornado's ribbons, 1.5 px wide, halos, a P4 stride. */
    s = NULL;
    gs = demo("tornado", 400, &s);
    if (gs) {
        lc_render_params p;
        lc_render_params_default(&p);
        p.width = W, p.height = H;
        p.style.background[0] = p.style.background[1] = p.style.background[2] = 1;
        check_case(&t, gs, &p, "lines, fourier", 0.999, 0.01, drawn, computed);
        render(&t, gs, &p, 1, again, &info);
        CHECK(memcmp(computed, again, (size_t)W * H * 4) == 0, "lines: two computed frames differ");
        p.style.halo_width = 2;
        check_case(&t, gs, &p, "lines, halos", 0.999, 0.01, drawn, computed);
        p.style.halo_width = 0;
        p.foo.subset = 2;
        check_case(&t, gs, &p, "lines, subset 2", 0.998, 0.01, drawn, computed);
        lc_gpu_scene_destroy(gs);
        lc_scene_destroy(s);
    }

    /* Pre-emption inside the computed passes: 300k points make two dispatches a pass. */
    s = NULL;
    gs = demo("points", 300000, &s);
    stopper st = {0, 0};
    test_gl pre = {.gl = t.gl};
    lc_renderer_desc pd = {.preempted = preempted, .yield_ctx = &st};
    lc_gl_release_current(t.gl);
    CHECK(lc_gl_make_current(pre.gl, &err) == 0 && lc_renderer_create(&pd, &pre.renderer, &err) == 0,
          "pre-empted renderer: %s", err.msg);
    if (gs && pre.renderer) {
        lc_render_params p;
        lc_render_params_default(&p);
        p.width = W, p.height = H;
        render(&pre, gs, &p, 1, drawn, &info);
        int calls = st.calls, stopped = 0, same = 0;
        CHECK(info.computed_passes == 3 && calls >= 4, "computed (%d) with %d pre-emption points", info.computed_passes,
              calls);
        for (int at = 1; at <= calls; at++) {
            st.calls = 0, st.stop_at = at;
            lc_renderer_set_raster_path(pre.renderer, 1);
            int rc = lc_render_frame(pre.renderer, gs, &p, NULL, 0.0, computed, &info, &err);
            stopped += rc == LC_ERR_CANCELLED;
            st.calls = 0, st.stop_at = 0;
            render(&pre, gs, &p, 1, again, &info);
            same += memcmp(drawn, again, (size_t)W * H * 4) == 0;
        }
        printf("pre-emption: %d points in a computed frame, %d stopped it, the next frame identical after %d\n", calls,
               stopped, same);
        CHECK(stopped == calls && same == calls, "pre-emption: %d of %d stopped, %d identical after", stopped, calls,
              same);
    }
    if (pre.renderer)
        lc_renderer_destroy(pre.renderer);
    lc_gl_release_current(pre.gl);
    CHECK(lc_gl_make_current(t.gl, &err) == 0, "context: %s", err.msg);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);

    /* Surfaces stay drawn whatever the path asks. */
    s = NULL;
    gs = demo("surface", 0, &s);
    if (gs) {
        lc_render_params p;
        lc_render_params_default(&p);
        p.width = W, p.height = H;
        render(&t, gs, &p, 1, computed, &info);
        CHECK(info.computed_passes == 0, "surface: computed %d (drawn)", info.computed_passes);
        lc_gpu_scene_destroy(gs);
        lc_scene_destroy(s);
    }
    free(drawn), free(computed), free(again);
    test_gl_close(&t);
    return lc_test_finish();
}
