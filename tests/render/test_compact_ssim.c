/* The compact GPU layout (16-bit positions in chunks, 32-bit directions,
 * 16-bit attributes and blend weights, 16-bit session opacities) against the
 * float buffers of --exact-positions on every demo: SSIM >= 0.999 for the
 * Fourier method one-shot and after four fading frames of a session, and for
 * the exact reference. That the float layout reproduces the committed images
 * bit for bit is render.test_references. */
#include "demo.h"
#include "image.h"
#include "render_util.h"

#define WIDTH 256
#define HEIGHT 192
#define SSIM_THRESHOLD 0.999

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    uint8_t *exact = malloc(WIDTH * HEIGHT * 4), *compact = malloc(WIDTH * HEIGHT * 4);
    for (const char *const *name = lc_demo_names(); *name; name++) {
        lc_error err = {0};
        lc_scene *s = NULL;
        lc_gpu_scene *gx = NULL, *gc = NULL;
        lc_demo_desc desc = {.count = strcmp(*name, "points") == 0 ? 50000 : 0};
        CHECK(lc_demo_create(*name, &desc, &s, &err) == 0, "demo:%s: %s", *name, err.msg);
        if (!s)
            continue;
        CHECK(lc_gpu_scene_create_ex(s, &(lc_gpu_scene_desc){.exact_positions = 1}, &gx, &err) == 0, "demo:%s: %s",
              *name, err.msg);
        CHECK(lc_gpu_scene_create(s, &gc, &err) == 0, "demo:%s: %s", *name, err.msg);
        lc_gpu_memory mx = {0}, mc = {0};
        if (gx && gc) {
            lc_gpu_scene_memory(gx, &mx);
            lc_gpu_scene_memory(gc, &mc);
            CHECK(mc.total < mx.total, "demo:%s: compact %llu bytes, exact %llu", *name, (unsigned long long)mc.total,
                  (unsigned long long)mx.total);
            static const struct {
                const char *what;
                lc_method method;
                int frames;
            } cases[] = {{"fourier", LC_METHOD_FOURIER, 1},
                         {"fourier, 4 fading frames", LC_METHOD_FOURIER, 4},
                         {"exact", LC_METHOD_EXACT, 1}};
            for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
                lc_render_params p;
                lc_render_params_default(&p);
                p.width = WIDTH, p.height = HEIGHT;
                p.method = cases[c].method;
                p.foo.fade_half_life = 0.1;
                for (int k = 0; k < 2; k++) {
                    lc_frame_state *st = cases[c].frames > 1 ? (k ? lc_frame_state_create_compact(s->elements.count)
                                                                  : lc_frame_state_create(s->elements.count))
                                                             : NULL;
                    for (int f = 0; f < cases[c].frames; f++) {
                        int rc =
                            lc_render_frame(t.renderer, k ? gc : gx, &p, st, 0.05, k ? compact : exact, NULL, &err);
                        CHECK(rc == 0, "demo:%s %s: %s", *name, cases[c].what, err.msg);
                    }
                    lc_frame_state_destroy(st);
                }
                double ssim = lc_image_ssim(compact, exact, WIDTH, HEIGHT);
                printf("demo:%-8s %-26s SSIM %.5f  RMSE %.5f  (GPU buffers %.1f -> %.1f bytes per vertex)\n", *name,
                       cases[c].what, ssim, lc_image_rmse(compact, exact, WIDTH, HEIGHT),
                       (double)mx.total / s->vertex_count, (double)mc.total / s->vertex_count);
                CHECK(ssim >= SSIM_THRESHOLD, "demo:%s %s: SSIM %.5f below %.3f", *name, cases[c].what, ssim,
                      SSIM_THRESHOLD);
            }
        }
        lc_gpu_scene_destroy(gx);
        lc_gpu_scene_destroy(gc);
        lc_scene_destroy(s);
    }
    free(exact);
    free(compact);
    test_gl_close(&t);
    return lc_test_finish();
}
