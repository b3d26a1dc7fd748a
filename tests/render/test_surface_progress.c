/* Progressive insertion into kept surface layers (docs/ALGORITHM.md §23,
 * PRT §2.2): a session's frames of a growing curve set, drawn through one
 * lc_surface_keep, must each draw only the new curves (the fragments
 * rasterized per frame stay those of one batch while the total grows), and
 * the last frame must equal the one-shot image of all the curves; a camera
 * change, other parameters or another curve set must draw every curve again;
 * frames alternating between two contexts of a share group (the daemon's
 * render workers) must continue the same layers. */
#include <math.h>
#include <pthread.h>

#include "field.h"
#include "gl_context.h"
#include "image.h"
#include "render_util.h"
#include "surface_render.h"

#define SIZE 128
#define CURVES 800
#define BATCH 100
#define FRAMES (CURVES / BATCH)
#define SEED "3.14159,0.63,3.14159;3.14159,5.65,3.14159"

static lc_surface_params params(void)
{
    lc_surface_params sp = {.particles = CURVES, .length = 4.0, .epsilon = 1e-2, .opacity = 0.3, .max_layers = 8};
    sp.color[0] = 0.95, sp.color[1] = 0.6, sp.color[2] = 0.2;
    return sp;
}

/* One frame through keep, on gl made current on the calling thread (NULL: the current context). */
typedef struct frame_job {
    const lc_field *f;
    const lc_trace_curve *curves;
    uint32_t n;
    lc_surface_keep *keep;
    lc_surface_params sp;
    const lc_render_params *p;
    uint8_t *img;
    lc_gl *gl;
    lc_surface_info si;
    lc_error err;
    int rc;
} frame_job;

static void *draw_frame(void *arg)
{
    frame_job *j = arg;
    memset(&j->si, 0, sizeof j->si);
    memset(&j->err, 0, sizeof j->err);
    j->rc = j->gl ? lc_gl_make_current(j->gl, &j->err) : 0;
    if (!j->rc)
        j->rc = lc_surface_draw(j->f, j->curves, j->n, 9, j->keep, &j->sp, j->p, j->f->bounds, j->img, &j->si, NULL,
                                &j->err);
    if (j->gl)
        lc_gl_release_current(j->gl);
    return NULL;
}

/* Largest channel difference and the SSIM of a and b. */
static void compare(const uint8_t *a, const uint8_t *b, int *max_diff, double *ssim)
{
    *max_diff = 0;
    for (int i = 0; i < SIZE * SIZE * 4; i++)
        if (i % 4 != 3 && abs((int)a[i] - (int)b[i]) > *max_diff)
            *max_diff = abs((int)a[i] - (int)b[i]);
    *ssim = lc_image_ssim(a, b, SIZE, SIZE);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    lc_error err = {0};
    lc_field *f = NULL;
    CHECK(lc_field_demo_create("abc-flow", &f, &err) == 0, "field: %s", err.msg);
    lc_seed seed;
    CHECK(lc_seed_parse(SEED, &seed, f, &err) == 0, "seed: %s", err.msg);
    lc_trace_curve *curves = calloc(CURVES, sizeof *curves);
    lc_trace_desc td = {.max_length = 4.0};
    CHECK(lc_trace_curves(f, &seed, &td, 0, CURVES, 2, curves, &err) == 0, "trace: %s", err.msg);

    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    lc_surface_params sp = params();
    uint8_t *img = malloc(SIZE * SIZE * 4), *once = malloc(SIZE * SIZE * 4);
    lc_surface_info si = {0};
    lc_camera cam;

    /* The one-shot image: every curve into fresh layers. */
    CHECK(lc_surface_draw(f, curves, CURVES, 0, NULL, &sp, &p, f->bounds, once, &si, &cam, &err) == 0, "one-shot: %s",
          err.msg);
    uint64_t all_fragments = si.stats.fragments;
    CHECK(si.drawn_curves == CURVES && si.drawn_fragments == all_fragments && !si.kept,
          "one-shot draws all %d curves (%llu) and all %llu fragments (%llu)", CURVES,
          (unsigned long long)si.drawn_curves, (unsigned long long)all_fragments,
          (unsigned long long)si.drawn_fragments);

    /* Frames of a session: BATCH more curves each, the camera still. */
    lc_surface_keep *keep = lc_surface_keep_create();
    CHECK(keep != NULL, "keep");
    uint64_t sum = 0, most = 0;
    for (int k = 1; k <= FRAMES; k++) {
        CHECK(lc_surface_draw(f, curves, (uint32_t)(k * BATCH), 7, keep, &sp, &p, f->bounds, img, &si, NULL, &err) == 0,
              "frame %d: %s", k, err.msg);
        CHECK(si.drawn_curves == BATCH && si.stats.curves == (uint64_t)k * BATCH && si.kept == (k > 1),
              "frame %d draws its %d new curves (%llu of %llu, kept %d)", k, BATCH, (unsigned long long)si.drawn_curves,
              (unsigned long long)si.stats.curves, si.kept);
        sum += si.drawn_fragments;
        most = si.drawn_fragments > most ? si.drawn_fragments : most;
        printf("frame %d: %llu curves, %llu drawn, %llu fragments drawn of %llu\n", k,
               (unsigned long long)si.stats.curves, (unsigned long long)si.drawn_curves,
               (unsigned long long)si.drawn_fragments, (unsigned long long)si.stats.fragments);
    }
    /* Each frame's fragments are its batch's: together they are the one-shot's, none near the whole. */
    CHECK(sum == si.stats.fragments && si.stats.fragments == all_fragments,
          "the frames' fragments add up to the one-shot's (%llu, %llu, %llu)", (unsigned long long)sum,
          (unsigned long long)si.stats.fragments, (unsigned long long)all_fragments);
    CHECK(most * 3 < all_fragments, "no frame draws near all fragments (most %llu of %llu)", (unsigned long long)most,
          (unsigned long long)all_fragments);
    int diff;
    double s;
    compare(img, once, &diff, &s);
    printf("progressive vs one-shot: max channel difference %d, SSIM %.5f\n", diff, s);
    CHECK(s >= 0.999 && diff == 0, "the last frame is the one-shot image (SSIM %.5f, max difference %d)", s, diff);

    /* Nothing new: nothing drawn, the same picture. */
    CHECK(lc_surface_draw(f, curves, CURVES, 7, keep, &sp, &p, f->bounds, img, &si, NULL, &err) == 0, "again: %s",
          err.msg);
    CHECK(si.kept && si.drawn_curves == 0 && si.drawn_fragments == 0, "a frame with no new curves draws none (%llu)",
          (unsigned long long)si.drawn_fragments);

    /* A camera move rebuilds from every curve. */
    lc_render_params moved = p;
    moved.has_camera = true;
    moved.camera = cam;
    moved.camera.position[0] += 1.0;
    CHECK(lc_surface_draw(f, curves, CURVES, 7, keep, &sp, &moved, f->bounds, img, &si, NULL, &err) == 0, "moved: %s",
          err.msg);
    CHECK(!si.kept && si.drawn_curves == CURVES, "a camera move draws every curve (%llu)",
          (unsigned long long)si.drawn_curves);
    /* Other parameters (opacity) and another curve set (id) rebuild too. */
    sp.opacity = 0.5;
    CHECK(lc_surface_draw(f, curves, CURVES, 7, keep, &sp, &moved, f->bounds, img, &si, NULL, &err) == 0 && !si.kept &&
              si.drawn_curves == CURVES,
          "an opacity change draws every curve (%llu)", (unsigned long long)si.drawn_curves);
    CHECK(lc_surface_draw(f, curves, BATCH, 8, keep, &sp, &moved, f->bounds, img, &si, NULL, &err) == 0 && !si.kept &&
              si.drawn_curves == BATCH && si.stats.curves == BATCH,
          "another curve set starts again (%llu)", (unsigned long long)si.stats.curves);
    /* Fewer curves of the same set (a smaller particle count): again from the start. */
    CHECK(lc_surface_draw(f, curves, BATCH / 2, 8, keep, &sp, &moved, f->bounds, img, &si, NULL, &err) == 0 &&
              !si.kept && si.stats.curves == BATCH / 2,
          "fewer curves start again (%llu)", (unsigned long long)si.stats.curves);
    CHECK(lc_surface_keep_holds(keep), "the keep holds layers");
    lc_surface_keep_release(keep);
    CHECK(!lc_surface_keep_holds(keep), "released");

    /* The daemon's frames of one session land on any render worker: frames
     * alternating between this thread's context and another thread's context
     * of the same share group continue the same layers (each context with
     * its own programs) to the same image. */
    lc_gl *other = NULL;
    lc_gl_desc od = {.device = -1, .share = t.gl};
    CHECK(lc_gl_create(&od, &other, &err) == 0, "second context: %s", err.msg);
    CHECK(lc_gl_make_current(t.gl, &err) == 0, "make current: %s", err.msg); /* creating one left none current */
    frame_job job = {.f = f, .curves = curves, .keep = keep, .sp = params(), .p = &p, .img = img};
    for (int k = 1; other && k <= FRAMES; k++) {
        job.n = (uint32_t)(k * BATCH);
        job.gl = k % 2 ? NULL : other;
        pthread_t th;
        if (job.gl) { /* the other worker's thread */
            CHECK(pthread_create(&th, NULL, draw_frame, &job) == 0, "thread");
            pthread_join(th, NULL);
        } else {
            draw_frame(&job);
        }
        CHECK(job.rc == 0, "frame %d on context %d: %s", k, 2 - k % 2, job.err.msg);
        CHECK(job.si.drawn_curves == BATCH && job.si.kept == (k > 1),
              "frame %d on context %d draws its %d new curves (%llu)", k, 2 - k % 2, BATCH,
              (unsigned long long)job.si.drawn_curves);
    }
    compare(img, once, &diff, &s);
    CHECK(diff == 0, "frames on alternating contexts end on the one-shot image (max difference %d)", diff);
    lc_surface_keep_destroy(keep); /* shared buffers: freed from either context */
    lc_gl_destroy(other);

    lc_trace_curves_free(curves, CURVES);
    free(curves);
    free(img);
    free(once);
    lc_field_destroy(f);
    test_gl_close(&t);
    return lc_test_finish();
}
