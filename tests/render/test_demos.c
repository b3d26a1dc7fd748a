/* Every demo dataset renders a non-trivial, deterministic image with each
 * method, and a fading sequence converges to the one-shot frame. */
#include <math.h>

#include "demo.h"
#include "render_util.h"

#define SIZE 128

static int render(test_gl *t, const lc_gpu_scene *gs, const lc_render_params *p, lc_frame_state *st, double dt,
                  uint8_t *rgba, lc_frame_info *info)
{
    lc_error err = {0};
    int rc = lc_render_frame(t->renderer, gs, p, st, dt, rgba, info, &err);
    CHECK(rc == 0, "render %s: %s", lc_method_name(p->method), err.msg);
    return rc;
}

static int max_diff(const uint8_t *a, const uint8_t *b)
{
    int worst = 0;
    for (int i = 0; i < SIZE * SIZE * 4; i++) {
        int d = abs((int)a[i] - (int)b[i]);
        worst = d > worst ? d : worst;
    }
    return worst;
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    uint8_t *a = malloc(SIZE * SIZE * 4), *b = malloc(SIZE * SIZE * 4);
    for (const char *const *name = lc_demo_names(); *name; name++) {
        lc_error err = {0};
        lc_scene *s = NULL;
        /* Small instances keep llvmpipe fast; the generators scale the same way. */
        lc_demo_desc desc = {.seed = 7, .count = strcmp(*name, "points") == 0 ? 20000 : 0};
        int rc = lc_demo_create(*name, &desc, &s, &err);
        CHECK(rc == 0, "demo %s: %s", *name, err.msg);
        if (rc)
            continue;
        lc_gpu_scene *gs = NULL;
        CHECK(lc_gpu_scene_create(s, &gs, &err) == 0, "%s: %s", *name, err.msg);
        lc_render_params p;
        lc_render_params_default(&p);
        p.width = p.height = SIZE;
        lc_frame_info info;

        for (int m = 0; m < LC_METHOD_COUNT; m++) {
            if (m == LC_METHOD_EXACT || m == LC_METHOD_SURFACE_LAYERS)
                continue; /* covered by their own tests (surface-layers renders a field, not a scene) */
            if (m == LC_METHOD_KANZLER && s->type == LC_PRIM_TRIANGLES)
                continue; /* lines and points only (test_kanzler checks the refusal) */
            p.method = (lc_method)m;
            if (render(&t, gs, &p, NULL, 0, a, &info) || render(&t, gs, &p, NULL, 0, b, &info))
                continue;
            CHECK(memcmp(a, b, SIZE * SIZE * 4) == 0, "%s %s: two renders differ", *name, lc_method_name(p.method));
            /* Non-trivial: a good share of pixels differ from the white background,
             * and the image has more than a handful of distinct colours. */
            int covered = 0, distinct = 0;
            static unsigned char seen[1 << 15];
            memset(seen, 0, sizeof seen);
            for (int i = 0; i < SIZE * SIZE; i++) {
                const uint8_t *px = a + 4 * i;
                if (px[0] < 250 || px[1] < 250 || px[2] < 250)
                    covered++;
                int key = (px[0] >> 3) << 10 | (px[1] >> 3) << 5 | (px[2] >> 3);
                if (!seen[key]++)
                    distinct++;
            }
            printf("%-8s %-8s covered %5.1f%%, %4d colours, %7.1f ms\n", *name, lc_method_name(p.method),
                   100.0 * covered / (SIZE * SIZE), distinct, info.wall_ms);
            /* alpha = g^k leaves unimportant data nearly invisible: a lower bar. */
            int min_cover = p.method == LC_METHOD_DIRECT ? SIZE * SIZE / 100 : SIZE * SIZE / 20;
            CHECK(covered > min_cover, "%s %s: only %d pixels covered", *name, lc_method_name(p.method), covered);
            CHECK(distinct > 20, "%s %s: only %d distinct colours", *name, lc_method_name(p.method), distinct);
        }

        /* Subset draws (P1/P4 take every 3rd primitive, weighted 3) take the
         * unindexed path; the image stays close to the full one. Surfaces get
         * holes in the sums (the option is meant for dense lines and points),
         * hence the loose bound. */
        p.method = LC_METHOD_FOURIER;
        render(&t, gs, &p, NULL, 0, a, &info);
        p.foo.subset = 3;
        render(&t, gs, &p, NULL, 0, b, &info);
        p.foo.subset = 1;
        double sum = 0;
        for (int i = 0; i < SIZE * SIZE * 4; i++)
            sum += abs((int)a[i] - (int)b[i]);
        double mean = sum / (SIZE * SIZE * 4) / 255.0;
        printf("%-8s subset 3: mean absolute difference to subset 1: %.4f\n", *name, mean);
        CHECK(mean < 0.1, "%s: subset 3 differs from the full render by %.4f on average", *name, mean);

        /* Fading: the first frame of a fresh state equals the one-shot render;
         * after a camera change, frames approach the new one-shot frame and
         * report convergence. */
        p.method = LC_METHOD_FOURIER;
        /* At full optimization resolution every element drawn in P4/P5 also had
         * fragments in P2, so elements without fragments (whose value is
         * history-dependent by design) cannot show in the image. */
        p.foo.resolution_scale = 1.0;
        lc_frame_state *st = lc_frame_state_create(s->elements.count);
        render(&t, gs, &p, NULL, 0, a, &info);
        render(&t, gs, &p, st, 0.05, b, &info);
        CHECK(max_diff(a, b) == 0, "%s: first faded frame differs from one-shot by %d", *name, max_diff(a, b));
        p.has_camera = true;
        p.camera = info.camera;
        for (int i = 0; i < 3; i++) /* orbit: look from another side */
            p.camera.position[i] = 2 * p.camera.focal_point[i] - p.camera.position[i];
        render(&t, gs, &p, NULL, 0, a, &info);
        int frames = 0, first_diff = -1, last_diff = 0;
        for (; frames < 60; frames++) {
            render(&t, gs, &p, st, 0.05, b, &info);
            last_diff = max_diff(a, b);
            if (first_diff < 0)
                first_diff = last_diff;
            if (info.converged)
                break;
        }
        printf("%-8s fading: first frame off by %d/255, converged after %d frames (last change %.2g), off by %d/255\n",
               *name, first_diff, frames + 1, info.max_alpha_change, last_diff);
        CHECK(info.converged, "%s: fading did not converge in 60 frames", *name);
        /* "Converged" leaves each opacity within about 1e-3 / fade factor (0.005
         * here) of its target; where many nearly opaque points overlap (the
         * dense clusters that normalize auto makes visible) that adds up to a
         * few more levels than on lines. */
        int bound = s->type == LC_PRIM_POINTS ? 6 : 3;
        CHECK(last_diff <= bound, "%s: converged frame differs from one-shot by %d/255", *name, last_diff);
        lc_frame_state_destroy(st);
        lc_gpu_scene_destroy(gs);
        lc_scene_destroy(s);
    }
    free(a);
    free(b);
    test_gl_close(&t);
    return lc_test_finish();
}
