/* Yield points (renderer.h desc.yield): a frame stopped at any of its yield
 * points returns LC_ERR_CANCELLED, and the renderer and the frame state stay
 * usable: the next frame is byte for byte the frame that would have come
 * without the stopped one (one-shot), and a session's next frame is the one
 * after as many frames as ran P3 (a stop after P3 leaves the state moved on,
 * as any frame does; before it, untouched). The session's first frame looks
 * from elsewhere, so that its opacities fade and the second and third frames
 * differ. On a software rasterizer the draws of P0, P1, P2, P4 and P5 are
 * batched and ask desc.preempted between batches too (pipeline.c
 * batch_yield; the test counts both callbacks as one): a frame then has more
 * stopping points than its passes give, every one of them stops it, and the
 * stops that leave the state moved on are those from the one after P3 on. */
#include <string.h>

#include "demo.h"
#include "render_util.h"

#define W 384
#define H 288

typedef struct stopper {
    int calls;   /* yield points reached this frame */
    int stop_at; /* stop at this call (0 = never) */
} stopper;

static int on_yield(void *ctx)
{
    stopper *s = ctx;
    return ++s->calls == s->stop_at;
}

typedef struct case_ {
    const char *name;
    lc_method method;
    int tile;   /* lc_renderer_desc.tile_size (0: untiled) */
    int points; /* yield points between the passes of a frame, expected */
    int p3;     /* of those, the one right after P3 (0: the method has none) */
} case_;

static int frame(lc_renderer *r, stopper *st, int stop_at, const lc_gpu_scene *gs, const lc_render_params *p,
                 lc_frame_state *state, uint8_t *rgba, lc_error *err)
{
    st->calls = 0, st->stop_at = stop_at;
    return lc_render_frame(r, gs, p, state, 0.1, rgba, NULL, err);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    lc_error err = {0};
    lc_scene *s = NULL;
    lc_gpu_scene *gs = NULL;
    lc_demo_desc dd = {.count = 200};
    if (lc_demo_create("tornado", &dd, &s, &err) != 0 || lc_gpu_scene_create(s, &gs, &err) != 0) {
        fprintf(stderr, "tornado: %s\n", err.msg);
        return 1;
    }
    /* fourier: after P0 (moments), P1, P2, the optimization (P3), P4, P5; tiles add one between each two. */
    static const case_ cases[] = {
        {"fourier", LC_METHOD_FOURIER, 0, 6, 4},
        {"fourier in 4 tiles", LC_METHOD_FOURIER, 192, 6 + 3 * 3, 4},
        {"direct", LC_METHOD_DIRECT, 0, 4, 0},
        {"wboit", LC_METHOD_WBOIT, 0, 4, 4},
    };
    size_t bytes = (size_t)W * H * 4;
    uint8_t *ref = malloc(bytes), *img = malloc(bytes), *ref2 = malloc(bytes), *ref3 = malloc(bytes);
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        const case_ *k = &cases[c];
        stopper st = {0};
        lc_renderer *plain = NULL, *r = NULL;
        lc_renderer_desc dp = {.tile_size = k->tile},
                         dy = {.tile_size = k->tile, .yield = on_yield, .preempted = on_yield, .yield_ctx = &st};
        CHECK(lc_renderer_create(&dp, &plain, &err) == 0 && lc_renderer_create(&dy, &r, &err) == 0, "renderer: %s",
              err.msg);
        lc_render_params p;
        lc_render_params_default(&p);
        p.width = W, p.height = H;
        p.method = k->method;
        /* The session's first frame, from elsewhere. */
        lc_render_params first = p;
        first.has_camera = true;
        first.camera = (lc_camera){
            .position = {3.5, 0.5, 0.5}, .focal_point = {0.5, 0.5, 0.5}, .view_up = {0, 0, 1}, .view_angle = 30};
        /* The references: a one-shot frame, and a session's second and third frames. */
        lc_frame_state *sa = lc_frame_state_create(s->elements.count);
        CHECK(lc_render_frame(plain, gs, &p, NULL, 0.1, ref, NULL, &err) == 0, "%s: reference: %s", k->name, err.msg);
        CHECK(lc_render_frame(plain, gs, &first, sa, 0.1, ref2, NULL, &err) == 0 &&
                  lc_render_frame(plain, gs, &p, sa, 0.1, ref2, NULL, &err) == 0 &&
                  lc_render_frame(plain, gs, &p, sa, 0.1, ref3, NULL, &err) == 0,
              "%s: session reference: %s", k->name, err.msg);
        CHECK(!k->p3 || memcmp(ref2, ref3, bytes) != 0, "%s: the session's second and third frames differ", k->name);
        CHECK(frame(r, &st, 0, gs, &p, NULL, img, &err) == 0 && memcmp(img, ref, bytes) == 0,
              "%s: a frame that never yields is the plain one", k->name);
        CHECK(st.calls >= k->points, "%s: %d yield points, at least %d", k->name, st.calls, k->points);
        int points = st.calls, stopped = 0, same = 0, same_state = 0, moved = 0, first_moved = 0;
        for (int at = 1; at <= points; at++) {
            lc_error e = {0};
            int rc = frame(r, &st, at, gs, &p, NULL, img, &e);
            stopped += rc == LC_ERR_CANCELLED && e.code == LC_ERR_CANCELLED;
            same += frame(r, &st, 0, gs, &p, NULL, img, &err) == 0 && memcmp(img, ref, bytes) == 0;
            /* A session: its first frame, one stopped at this point, then the next. */
            lc_frame_state *sb = lc_frame_state_create(s->elements.count);
            int ok = frame(r, &st, 0, gs, &first, sb, img, &err) == 0;
            ok = ok && frame(r, &st, at, gs, &p, sb, img, &e) == LC_ERR_CANCELLED;
            ok = ok && frame(r, &st, 0, gs, &p, sb, img, &err) == 0;
            int is2 = ok && memcmp(img, ref2, bytes) == 0;
            int is3 = ok && k->p3 && memcmp(img, ref3, bytes) == 0; /* without P3 the two are one image */
            /* Untouched before the point after P3, moved on from it: the moved ones are a suffix. */
            same_state += is2 || is3;
            if (is3 && !moved++)
                first_moved = at;
            if (is2 && moved)
                CHECK(0, "%s: stop %d left the state untouched after stop %d had moved it", k->name, at, first_moved);
            lc_frame_state_destroy(sb);
        }
        printf("%-20s %d yield points (%d between passes): %d stopped, next one-shot frame identical after %d, "
               "session frame after %d, the state moved on from stop %d\n",
               k->name, points, k->points, stopped, same, same_state, first_moved);
        CHECK(stopped == points, "%s: %d of %d yield points stopped the frame", k->name, stopped, points);
        CHECK(same == points, "%s: the next frame differs after %d of %d stops", k->name, points - same, points);
        CHECK(same_state == points,
              "%s: the session's next frame is neither the second nor the third after %d of "
              "%d stops",
              k->name, points - same_state, points);
        /* As many stops leave it moved on as there are yield points from the one after P3 on. */
        CHECK(k->p3 ? moved >= k->points - k->p3 + 1 && first_moved > k->p3 - 1 : moved == 0,
              "%s: %d stops left the state moved on, from stop %d (the point after P3 is the %d-th of %d between "
              "passes)",
              k->name, moved, first_moved, k->p3, k->points);
        lc_frame_state_destroy(sa);
        lc_renderer_destroy(plain);
        lc_renderer_destroy(r);
    }
    free(ref);
    free(img);
    free(ref2);
    free(ref3);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
    test_gl_close(&t);
    return lc_test_finish();
}
