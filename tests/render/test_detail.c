/* Level of detail and interactive frames (docs/ALGORITHM.md §11):
 * - still frames at the default line error bound stay within SSIM 0.99 of
 *   every segment on the line demos while drawing far fewer segments, and a
 *   closer camera picks a finer level;
 * - a frame that reuses the state's opacities skips P1-P3 and, with fading
 *   off, is pixel-identical to the frame that computed them;
 * - points drawn with a stride draw every n-th point. */
#include "demo.h"
#include "image.h"
#include "render_util.h"

#define SIZE 512

static void render(test_gl *t, const lc_gpu_scene *gs, const lc_render_params *p, lc_frame_state *st, uint8_t *rgba,
                   lc_frame_info *info)
{
    lc_error err = {0};
    int rc = lc_render_frame(t->renderer, gs, p, st, 1.0 / 30, rgba, info, &err);
    CHECK(rc == 0, "render: %s", err.msg);
}

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
    render(t, gs, &p, NULL, a, &full);
    p.detail.lod_pixels = LC_DEFAULT_LOD_PIXELS;
    render(t, gs, &p, NULL, b, &lod);
    double ssim = lc_image_ssim(a, b, SIZE, SIZE);
    printf("demo:%-8s %d levels; default %.2g px: level %d, %llu of %llu segments, SSIM %.4f vs every segment\n",
           name, lc_gpu_scene_levels(gs), LC_DEFAULT_LOD_PIXELS, lod.lod_level,
           (unsigned long long)lod.primitives_drawn, (unsigned long long)full.primitives_drawn, ssim);
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
    render(t, gs, &p, NULL, b, &closer);
    CHECK(closer.lod_level < lod.lod_level, "demo:%s: closer camera level %d, fitted %d", name, closer.lod_level,
          lod.lod_level);
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
    lc_frame_info opt, reused;
    render(t, gs, &p, st, a, &opt);
    p.detail.reuse_opacities = true;
    render(t, gs, &p, st, b, &reused);
    CHECK(!opt.reused_opacities && reused.reused_opacities, "reused flags %d, %d", opt.reused_opacities,
          reused.reused_opacities);
    CHECK(reused.pass_ms[LC_PASS_IMPORTANCE] < 0 && reused.pass_ms[LC_PASS_OPACITY] < 0 &&
              reused.pass_ms[LC_PASS_SMOOTH] < 0,
          "P1-P3 ran on a reusing frame");
    CHECK(memcmp(a, b, 256 * 256 * 4) == 0, "reusing the opacities changed the image (SSIM %.5f)",
          lc_image_ssim(a, b, 256, 256));
    /* A fresh state has nothing to reuse: the frame optimizes. */
    lc_frame_state_reset(st);
    render(t, gs, &p, st, b, &reused);
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
    lc_frame_info all, some;
    render(t, gs, &p, NULL, a, &all);
    p.detail.point_stride = 4;
    render(t, gs, &p, NULL, b, &some);
    CHECK(all.primitives_drawn == 40000 && some.primitives_drawn == 10000 && some.point_stride == 4,
          "drew %llu and %llu points", (unsigned long long)all.primitives_drawn,
          (unsigned long long)some.primitives_drawn);
    double ssim = lc_image_ssim(a, b, 256, 256);
    printf("demo:points every 4th point: SSIM %.4f vs all\n", ssim);
    CHECK(ssim > 0.5 && ssim < 0.9999, "stride 4 SSIM %.4f (expected a thinner but similar picture)", ssim);
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
    reuse_opacities(&t, a, b);
    point_stride(&t, a, b);
    free(a);
    free(b);
    test_gl_close(&t);
    return lc_test_finish();
}
