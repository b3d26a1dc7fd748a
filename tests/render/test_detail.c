/* Level of detail and interactive frames (docs/ALGORITHM.md §11):
 * - still frames at the default line error bound stay within SSIM 0.99 of
 *   every segment on the line demos while drawing far fewer segments, and a
 *   closer camera picks a finer level;
 * - a frame that reuses the state's opacities skips P1-P3 and, with fading
 *   off, is pixel-identical to the frame that computed them;
 * - points drawn with a stride draw every n-th point, or (the default) the
 *   most important in full and every n-th of the rest, closer to all. */
#include <math.h>

#include "demo.h"
#include "image.h"
#include "render_util.h"

#define SIZE 512

static lc_gpu_scene *open_demo(const char *name, int count, lc_scene **s)
{
    lc_error err = {0};
    lc_demo_desc desc = {.count = (uint32_t)count};
    lc_gpu_scene *gs = NULL;
    CHECK(lc_demo_create(name, &desc, s, &err) == 0, "demo:%s: %s", name, err.msg);
    if (*s)
        CHECK(lc_gpu_scene_create(*s, &gs, &err) == 0, "demo:%s: %s", name, err.msg);
    return gs;
}

static void still_frames(test_gl *t, const char *name, uint8_t *a, uint8_t *b)
{
    lc_scene *s = NULL;
    lc_gpu_scene *gs = open_demo(name, 0, &s);
    if (!gs)
        return;
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    lc_frame_info full, lod;
    p.detail.lod_pixels = 0;
    test_render_frame(t, gs, &p, NULL, a, &full);
    p.detail.lod_pixels = LC_DEFAULT_LOD_PIXELS;
    test_render_frame(t, gs, &p, NULL, b, &lod);
    double ssim = lc_image_ssim(a, b, SIZE, SIZE);
    printf("demo:%-8s %d levels; default %.2g px: level %d, %llu of %llu segments, SSIM %.4f vs every segment\n", name,
           lc_gpu_scene_levels(gs), LC_DEFAULT_LOD_PIXELS, lod.lod_level, (unsigned long long)lod.primitives_drawn,
           (unsigned long long)full.primitives_drawn, ssim);
    CHECK(full.lod_level == 0 && full.primitives_drawn == lc_scene_primitive_count(s), "lod 0 drew level %d",
          full.lod_level);
    CHECK(lod.lod_level > 0 && lod.primitives_drawn * 2 < full.primitives_drawn,
          "demo:%s: the default bound drew %llu of %llu segments", name, (unsigned long long)lod.primitives_drawn,
          (unsigned long long)full.primitives_drawn);
    CHECK(ssim >= 0.99, "demo:%s: SSIM %.4f below 0.99", name, ssim);
    CHECK(lc_gpu_scene_lod_bytes(gs) <= lc_scene_bytes(s), "demo:%s: levels cost %llu bytes, the scene %zu", name,
          (unsigned long long)lc_gpu_scene_lod_bytes(gs), lc_scene_bytes(s));

    /* Three quarters of the way to the focal point, near data is many times
     * closer: a finer level. */
    lc_frame_info closer;
    p.camera = full.camera;
    p.has_camera = true;
    for (int i = 0; i < 3; i++)
        p.camera.position[i] = 0.25 * p.camera.position[i] + 0.75 * p.camera.focal_point[i];
    test_render_frame(t, gs, &p, NULL, b, &closer);
    CHECK(closer.lod_level < lod.lod_level, "demo:%s: closer camera level %d, fitted %d", name, closer.lod_level,
          lod.lod_level);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

/* The surface demo keeps every triangle at the still bound and simplifies at
 * the bounds of interactive frames. */
static void surface_levels(test_gl *t, uint8_t *a, uint8_t *b)
{
    lc_scene *s = NULL;
    lc_gpu_scene *gs = open_demo("surface", 0, &s);
    if (!gs)
        return;
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    lc_frame_info still, coarse;
    test_render_frame(t, gs, &p, NULL, a, &still);
    p.detail.lod_pixels = 2;
    test_render_frame(t, gs, &p, NULL, b, &coarse);
    double ssim = lc_image_ssim(a, b, SIZE, SIZE);
    printf("demo:surface %d levels; still: level %d; 2 px: level %d, %llu of %llu triangles, SSIM %.4f\n",
           lc_gpu_scene_levels(gs), still.lod_level, coarse.lod_level, (unsigned long long)coarse.primitives_drawn,
           (unsigned long long)still.primitives_drawn, ssim);
    CHECK(lc_gpu_scene_levels(gs) >= 3 && coarse.lod_level > still.lod_level &&
              coarse.primitives_drawn * 2 < still.primitives_drawn,
          "surface: 2 px drew %llu of %llu triangles", (unsigned long long)coarse.primitives_drawn,
          (unsigned long long)still.primitives_drawn);
    CHECK(ssim > 0.9, "surface at 2 px: SSIM %.4f", ssim);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

static void reuse_opacities(test_gl *t, uint8_t *a, uint8_t *b)
{
    lc_scene *s = NULL;
    lc_gpu_scene *gs = open_demo("tornado", 0, &s);
    if (!gs)
        return;
    lc_frame_state *st = lc_frame_state_create(s->elements.count);
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = 256;
    p.foo.fade_half_life = 0; /* the state holds exactly the last targets */
    /* The bounds' depth range, which a reusing frame composites by whatever
     * depthRange says (checked below): then reuse changes nothing. */
    p.foo.depth_range = LC_DEPTH_RANGE_GLOBAL;
    lc_frame_info opt, reused;
    test_render_frame(t, gs, &p, st, a, &opt);
    p.detail.reuse_opacities = true;
    test_render_frame(t, gs, &p, st, b, &reused);
    CHECK(!opt.reused_opacities && reused.reused_opacities, "reused flags %d, %d", opt.reused_opacities,
          reused.reused_opacities);
    CHECK(reused.pass_ms[LC_PASS_IMPORTANCE] < 0 && reused.pass_ms[LC_PASS_OPACITY] < 0 &&
              reused.pass_ms[LC_PASS_SMOOTH] < 0,
          "P1-P3 ran on a reusing frame");
    CHECK(memcmp(a, b, 256 * 256 * 4) == 0, "reusing the opacities changed the image (SSIM %.5f)",
          lc_image_ssim(a, b, 256, 256));
    /* With the default moments the optimizing frame warps depth by its P0;
     * a reusing one skips P0 and draws what the bounds' range draws. */
    p.foo.depth_range = LC_DEPTH_RANGE_AUTO;
    p.detail.reuse_opacities = false;
    test_render_frame(t, gs, &p, st, a, &opt);
    CHECK(opt.pass_ms[LC_PASS_DEPTH_RANGE] >= 0, "the default optimizing frame ran no P0 moments pass");
    p.detail.reuse_opacities = true;
    test_render_frame(t, gs, &p, st, a, &reused);
    CHECK(reused.reused_opacities && reused.pass_ms[LC_PASS_DEPTH_RANGE] < 0, "a reusing frame ran P0");
    p.foo.depth_range = LC_DEPTH_RANGE_GLOBAL;
    test_render_frame(t, gs, &p, st, b, &reused);
    CHECK(memcmp(a, b, 256 * 256 * 4) == 0, "a reusing frame with moments differs from the bounds' (SSIM %.5f)",
          lc_image_ssim(a, b, 256, 256));
    p.foo.depth_range = LC_DEPTH_RANGE_AUTO;
    /* A fresh state has nothing to reuse: the frame optimizes. */
    lc_frame_state_reset(st);
    test_render_frame(t, gs, &p, st, b, &reused);
    CHECK(!reused.reused_opacities && reused.pass_ms[LC_PASS_OPACITY] >= 0, "a fresh state reused opacities");
    lc_frame_state_destroy(st);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

static void point_stride(test_gl *t, uint8_t *a, uint8_t *b)
{
    lc_scene *s = NULL;
    lc_gpu_scene *gs = open_demo("points", 40000, &s);
    if (!gs)
        return;
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = 256;
    lc_frame_info all, some, uniform;
    test_render_frame(t, gs, &p, NULL, a, &all);
    p.detail.point_stride = 4;
    p.detail.uniform_points = true;
    test_render_frame(t, gs, &p, NULL, b, &uniform);
    CHECK(all.primitives_drawn == 40000 && uniform.primitives_drawn == 10000 && uniform.point_stride == 4 &&
              uniform.kept_points == 0,
          "drew %llu and %llu points", (unsigned long long)all.primitives_drawn,
          (unsigned long long)uniform.primitives_drawn);
    double ssim_uniform = lc_image_ssim(a, b, 256, 256);
    /* Importance-aware (the default): the top 1/16 by importance in full, the
     * rest every 4th; the kept ones replace the quarter of them the stride drew. */
    p.detail.uniform_points = false;
    test_render_frame(t, gs, &p, NULL, b, &some);
    CHECK(some.kept_points >= 2500 && some.kept_points <= 10000 &&
              some.primitives_drawn == 10000 + some.kept_points - some.kept_points / 4,
          "kept %u important points, drew %llu", some.kept_points, (unsigned long long)some.primitives_drawn);
    double ssim = lc_image_ssim(a, b, 256, 256);
    printf("demo:points every 4th point: SSIM %.4f vs all, %.4f thinned uniformly (%u kept in full)\n", ssim,
           ssim_uniform, some.kept_points);
    CHECK(ssim_uniform > 0.5 && ssim_uniform < 0.9999, "stride 4 SSIM %.4f (expected a thinner but similar picture)",
          ssim_uniform);
    CHECK(ssim >= ssim_uniform - 1e-3 && ssim < 0.9999, "keeping the important points: SSIM %.4f vs %.4f uniform", ssim,
          ssim_uniform);
    /* The floor: a point per LC_POINT_SUBSET_PIXELS pixels (8192 at 256x256).
     * Stride 16 would leave 2500 of the 40000: it halves to 4 (10000). */
    p.detail.point_stride = 16;
    p.detail.uniform_points = true;
    test_render_frame(t, gs, &p, NULL, b, &uniform);
    CHECK(uniform.point_stride == 4 && uniform.primitives_drawn == 10000,
          "stride 16 on 40000 points at 256x256: stride %d, %llu points drawn (the floor keeps 8192)",
          uniform.point_stride, (unsigned long long)uniform.primitives_drawn);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

/* 2x2 box average of an RGBA image (w, h even): the still as a frame of half its size shows it. */
static void halve_rgba(const uint8_t *in, int w, int h, uint8_t *out)
{
    for (int y = 0; y < h / 2; y++)
        for (int x = 0; x < w / 2; x++)
            for (int c = 0; c < 4; c++) {
                const uint8_t *p = in + 4 * ((size_t)2 * y * w + 2 * x) + c;
                out[4 * ((size_t)y * (w / 2) + x) + c] =
                    (uint8_t)((p[0] + p[4] + p[4 * (size_t)w] + p[4 * (size_t)w + 4] + 2) / 4);
            }
}

static double mean_luma(const uint8_t *rgba, size_t n)
{
    double sum = 0;
    for (size_t i = 0; i < n; i++)
        sum += 0.2126 * rgba[4 * i] + 0.7152 * rgba[4 * i + 1] + 0.0722 * rgba[4 * i + 2];
    return sum / (double)n;
}

/* A moving frame drawn at half its view's size (detail.pixel_scale, as a
 * session draws it) with a stride: its splats keep their size in the view's
 * pixels (lc_point_splat), so it looks like the still shown at that size,
 * where splats of the still's pixel size cover four times the share of the
 * frame and the picture darkens. */
static void point_pixel_scale(test_gl *t, uint8_t *a, uint8_t *b)
{
    lc_scene *s = NULL;
    lc_gpu_scene *gs = open_demo("points", 40000, &s);
    if (!gs)
        return;
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = 256;
    test_render_frame(t, gs, &p, NULL, a, NULL);
    uint8_t *still = malloc(128 * 128 * 4), *scaled = malloc(128 * 128 * 4);
    halve_rgba(a, 256, 256, still);
    p.width = p.height = 128;
    p.detail.point_stride = 4;
    p.detail.uniform_points = true;
    test_render_frame(t, gs, &p, NULL, b, NULL); /* the view's size unknown: splats of the still's pixel size */
    p.detail.pixel_scale = 0.5;
    test_render_frame(t, gs, &p, NULL, scaled, NULL);
    double s_plain = lc_image_ssim(still, b, 128, 128), s_scaled = lc_image_ssim(still, scaled, 128, 128);
    double l_still = mean_luma(still, 128 * 128), l_plain = mean_luma(b, 128 * 128),
           l_scaled = mean_luma(scaled, 128 * 128);
    printf("demo:points every 4th point at half size: SSIM %.4f with splats of the view's size, %.4f of the frame's; "
           "mean luminance %.1f and %.1f, the still's %.1f\n",
           s_scaled, s_plain, l_scaled, l_plain, l_still);
    CHECK(s_scaled > s_plain + 0.02, "half size: SSIM %.4f (view's splats) vs %.4f", s_scaled, s_plain);
    CHECK(fabs(l_scaled - l_still) * 2 < fabs(l_plain - l_still), "mean luminance %.1f / %.1f, the still's %.1f",
          l_scaled, l_plain, l_still);
    free(still);
    free(scaled);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

/* 32x32-pixel blocks of a 256x256 image with a pixel off the white background. */
static int covered_blocks(const uint8_t *rgba)
{
    int n = 0;
    for (int by = 0; by < 8; by++)
        for (int bx = 0; bx < 8; bx++) {
            int hit = 0;
            for (int y = by * 32; y < by * 32 + 32 && !hit; y++)
                for (int x = bx * 32; x < bx * 32 + 32 && !hit; x++)
                    hit = rgba[4 * (y * 256 + x)] < 250 || rgba[4 * (y * 256 + x) + 1] < 250;
            n += hit;
        }
    return n;
}

/* Data stored in periods (an MD dump's atoms, frame after frame): point i
 * lies in cell i % 8 of a 4x2 grid. A stride of 8 that took every 8th point
 * would draw one cell; each instance takes a point of its block at random,
 * so the strided frame covers the cells the full one does. */
static void periodic_stride(test_gl *t, uint8_t *a, uint8_t *b)
{
    enum { PERIOD = 8, N = PERIOD * 8192 };
    lc_error err = {0};
    lc_scene *s = lc_scene_create("periodic", LC_PRIM_POINTS);
    CHECK(s && lc_scene_alloc_vertices(s, N, 0, &err) == 0, "scene: %s", err.msg);
    uint32_t seed = 11;
    for (int i = 0; i < N; i++) {
        float u[3];
        for (int k = 0; k < 3; k++) {
            seed = seed * 1664525u + 1013904223u;
            u[k] = (float)(seed >> 8) / 16777216.0f;
        }
        int c = i % PERIOD;
        s->positions[3 * i] = (float)(c % 4) + 0.5f * u[0];
        s->positions[3 * i + 1] = (float)(c / 4) * 2.0f + 0.5f * u[1];
        s->positions[3 * i + 2] = 0.5f * u[2];
    }
    lc_gpu_scene *gs = test_upload_scene(s);
    if (!gs)
        return;
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = 256;
    lc_frame_info info;
    test_render_frame(t, gs, &p, NULL, a, &info);
    p.detail.point_stride = PERIOD;
    p.detail.uniform_points = true;
    test_render_frame(t, gs, &p, NULL, b, &info);
    int all = covered_blocks(a), some = covered_blocks(b);
    printf("points stored in periods of %d, every %dth: %d of the %d blocks the full frame covers\n", PERIOD,
           info.point_stride, some, all);
    CHECK(info.point_stride == PERIOD, "stride %d", info.point_stride);
    CHECK(all >= 8 && some * 10 >= all * 9, "the strided frame covers %d blocks, the full one %d", some, all);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

/* Where it matters: a small cluster of important points (g = 0.8) in front
 * of a faint cloud. Thinned uniformly, the cluster's points each count n times in P1, so
 * they hide each other as if the cluster were n times denser and fade; kept in
 * full, the cluster looks as with every point. */
static void important_cluster(test_gl *t, uint8_t *a, uint8_t *b)
{
    enum { CLOUD = 36000, CLUSTER = 4000, N = CLOUD + CLUSTER, STRIDE = 8 };
    lc_error err = {0};
    lc_scene *s = lc_scene_create("cluster", LC_PRIM_POINTS);
    float *imp = malloc(N * sizeof(float));
    CHECK(s && imp && lc_scene_alloc_vertices(s, N, 0, &err) == 0, "scene: %s", err.msg);
    uint32_t seed = 7;
    for (int i = 0; i < N; i++) {
        float u[3];
        for (int k = 0; k < 3; k++) {
            seed = seed * 1664525u + 1013904223u;
            u[k] = (float)(seed >> 8) / 16777216.0f;
        }
        for (int k = 0; k < 3; k++) /* the cloud: a slab at the back; the cluster: a small cube in front of it */
            s->positions[3 * i + k] = i < CLOUD ? (k == 2 ? 0.3f * u[k] : u[k]) : 0.45f + 0.1f * u[k];
        imp[i] = i < CLOUD ? 0.05f : 0.8f;
    }
    CHECK(lc_scene_add_attribute(s, "importance", imp, &err) >= 0, "attribute: %s", err.msg);
    lc_gpu_scene *gs = test_upload_scene(s);
    if (!gs)
        return;
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = 256;
    p.importance.has_range = true, p.importance.range[0] = 0, p.importance.range[1] = 1;
    p.style.point_size = 3;
    uint8_t *all = malloc(256 * 256 * 4);
    lc_frame_info info;
    test_render_frame(t, gs, &p, NULL, all, &info);
    p.detail.point_stride = STRIDE;
    p.detail.uniform_points = true;
    test_render_frame(t, gs, &p, NULL, a, &info);
    p.detail.uniform_points = false;
    test_render_frame(t, gs, &p, NULL, b, &info);
    CHECK(info.kept_points == CLUSTER, "kept %u points, the cluster has %d", info.kept_points, CLUSTER);
    /* The cluster's colour (viridis at 0.8, green) against the cloud's (dark
     * purple): the pixels that show the cluster. */
    int n_all = 0, n_uniform = 0, n_kept = 0;
    for (size_t i = 0; i < 256 * 256; i++) {
        const uint8_t *px[3] = {all + 4 * i, a + 4 * i, b + 4 * i};
        int *n[3] = {&n_all, &n_uniform, &n_kept};
        for (int k = 0; k < 3; k++)
            *n[k] += px[k][1] > px[k][0] + 20 && px[k][1] > px[k][2] + 20 && px[k][1] > 80;
    }
    double s_uniform = lc_image_ssim(all, a, 256, 256), s_kept = lc_image_ssim(all, b, 256, 256);
    printf("important cluster, every %dth point: %d pixels show it (all points), %d kept in full, %d thinned "
           "uniformly; SSIM %.4f vs %.4f\n",
           STRIDE, n_all, n_kept, n_uniform, s_kept, s_uniform);
    CHECK(n_all > 20 && abs(n_kept - n_all) * 5 <= n_all, "kept in full, the cluster shows in %d pixels, all in %d",
          n_kept, n_all);
    CHECK(n_uniform * 2 < n_all, "thinned uniformly, the cluster shows in %d pixels, all in %d", n_uniform, n_all);
    CHECK(s_kept > s_uniform, "SSIM %.4f kept vs %.4f uniform", s_kept, s_uniform);
    free(all);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    uint8_t *a = malloc(SIZE * SIZE * 4), *b = malloc(SIZE * SIZE * 4);
    still_frames(&t, "tornado", a, b);
    still_frames(&t, "abc", a, b);
    surface_levels(&t, a, b);
    reuse_opacities(&t, a, b);
    point_stride(&t, a, b);
    point_pixel_scale(&t, a, b);
    important_cluster(&t, a, b);
    periodic_stride(&t, a, b);
    free(a);
    free(b);
    test_gl_close(&t);
    return lc_test_finish();
}
