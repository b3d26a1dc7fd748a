/* Fourier against the exact reference on every demo dataset at default
 * parameters: prints SSIM and RMSE per demo and fails below the threshold.
 *
 * Threshold: SSIM >= 0.96 at 256x256. The FOO paper reports 0.959 (m = 1) to
 * 0.984 (m = 5) against linked lists on TREFOIL. Measured here on llvmpipe
 * (lucent compare --dataset demo:NAME --size 256x256 --repeat 0 [flags]):
 * default (m = 5, midpoint estimator) 0.977-0.995 over the four demos (tornado
 * lowest); m = 5 with the FOO estimator 0.954-0.994 (abc 0.954); m = 1
 * 0.944-0.988 (tornado 0.944); the baselines without optimized opacities,
 * opaque 0.71-0.86 and direct 0.55-0.80. 0.96 keeps a margin of 0.017 below
 * the worst default result for driver differences, while a pipeline that
 * loses its bands (m = 1 on tornado), its optimized opacities, or switches to
 * the estimator that measured worse (abc) fails.
 *
 * Then, at 512x512 with every demo at its default size (as docs/EVALUATION.md
 * §7 measures it): the defaults (density normalization, depth warped by the
 * moments) must agree with exact at least as well as the paper's formula
 * ("normalize": "off", the bounds' depth range) agrees with its own exact
 * image. Measured 2026-11-25: auto 0.9890 / 0.9990 / 0.9980 / 0.9993 against
 * off 0.9803 / 0.9906 / 0.9963 / 0.9972 (tornado, abc, points, surface); auto
 * with the bounds' range, 0.9774 / 0.9896 / 0.9921 / 0.9976, fails on three.
 * (At 256x256 with 50k points auto stays below: 0.9937 against 0.9950.) */
#include <math.h>

#include "demo.h"
#include "image.h"
#include "render_util.h"

#define SIZE 256
#define SSIM_THRESHOLD 0.96
#define PARITY_SIZE 512

static void render(test_gl *t, const lc_gpu_scene *gs, const lc_render_params *p, uint8_t *rgba, lc_frame_info *info)
{
    lc_error err = {0};
    int rc = lc_render_frame(t->renderer, gs, p, NULL, 0, rgba, info, &err);
    CHECK(rc == 0, "render (%s): %s", lc_method_name(p->method), err.msg);
}

/* Fourier against exact at PARITY_SIZE with the request's parameters. */
static double ssim_against_exact(test_gl *t, const lc_gpu_scene *gs, lc_render_params p, uint8_t *a, uint8_t *b)
{
    lc_frame_info info;
    p.width = p.height = PARITY_SIZE;
    p.method = LC_METHOD_FOURIER;
    render(t, gs, &p, a, &info);
    p.method = LC_METHOD_EXACT;
    render(t, gs, &p, b, &info);
    return lc_image_ssim(a, b, PARITY_SIZE, PARITY_SIZE);
}

static void check_parity(test_gl *t)
{
    uint8_t *a = malloc(PARITY_SIZE * PARITY_SIZE * 4), *b = malloc(PARITY_SIZE * PARITY_SIZE * 4);
    for (const char *const *name = lc_demo_names(); *name; name++) {
        lc_error err = {0};
        lc_scene *s = NULL;
        lc_gpu_scene *gs = NULL;
        lc_demo_desc desc = {0};
        CHECK(lc_demo_create(*name, &desc, &s, &err) == 0, "demo:%s: %s", *name, err.msg);
        if (s && lc_gpu_scene_create(s, &gs, &err) == 0) {
            lc_render_params p;
            lc_render_params_default(&p);
            double automatic = ssim_against_exact(t, gs, p, a, b);
            p.foo.normalize = LC_NORMALIZE_OFF;
            double paper = ssim_against_exact(t, gs, p, a, b);
            printf("demo:%-8s %dx%d SSIM against exact: defaults %.4f, normalize off %.4f\n", *name, PARITY_SIZE,
                   PARITY_SIZE, automatic, paper);
            CHECK(automatic >= paper,
                  "demo:%s: the defaults agree with exact less (SSIM %.4f) than the paper's "
                  "formula (%.4f)",
                  *name, automatic, paper);
            lc_gpu_scene_destroy(gs);
        }
        lc_scene_destroy(s);
    }
    free(a);
    free(b);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    printf("renderer: %s, %dx%d, default parameters, threshold SSIM %.2f\n", lc_gl_renderer(t.gl), SIZE, SIZE,
           SSIM_THRESHOLD);
    uint8_t *fourier = malloc(SIZE * SIZE * 4), *exact = malloc(SIZE * SIZE * 4);
    for (const char *const *name = lc_demo_names(); *name; name++) {
        lc_error err = {0};
        lc_scene *s = NULL;
        lc_gpu_scene *gs = NULL;
        /* 2-pixel splats of the default 200k points pile up to ~500 layers a pixel at 256^2 (more at the
         * half-resolution optimization pass), beyond the exact method's 256-layer cap; 50k points keep the
         * reference nearly exact (and the test fast). */
        lc_demo_desc desc = {.count = strcmp(*name, "points") == 0 ? 50000 : 0};
        CHECK(lc_demo_create(*name, &desc, &s, &err) == 0, "demo:%s: %s", *name, err.msg);
        if (!s)
            continue;
        CHECK(lc_gpu_scene_create(s, &gs, &err) == 0, "demo:%s: %s", *name, err.msg);
        if (gs) {
            lc_render_params p;
            lc_render_params_default(&p);
            p.width = p.height = SIZE;
            lc_frame_info fi, ei;
            render(&t, gs, &p, fourier, &fi);
            p.method = LC_METHOD_EXACT;
            render(&t, gs, &p, exact, &ei);
            double ssim = lc_image_ssim(fourier, exact, SIZE, SIZE);
            double rmse = lc_image_rmse(fourier, exact, SIZE, SIZE);
            printf("demo:%-8s SSIM %.4f  RMSE %.4f  (m=%d %s; exact: %llu fragments, mean %.1f / max %u layers, "
                   "%llu dropped)\n",
                   *name, ssim, rmse, p.foo.bands, lc_estimator_name(p.foo.estimator), (unsigned long long)ei.fragments,
                   ei.mean_layers, ei.max_layers, (unsigned long long)ei.dropped_fragments);
            /* A few fragments beyond the 256-layer cap of the optimization-resolution lists (points: 0.3%) are
             * tolerable: the kept ones are the nearest, with exact sums; the dropped ones sit behind 256 others. */
            CHECK(ei.dropped_fragments <= ei.fragments / 100, "demo:%s: the exact reference dropped %llu fragments",
                  *name, (unsigned long long)ei.dropped_fragments);
            CHECK(ssim >= SSIM_THRESHOLD, "demo:%s: SSIM %.4f below %.2f", *name, ssim, SSIM_THRESHOLD);
            lc_gpu_scene_destroy(gs);
        }
        lc_scene_destroy(s);
    }
    free(fourier);
    free(exact);
    check_parity(&t);
    test_gl_close(&t);
    return lc_test_finish();
}
