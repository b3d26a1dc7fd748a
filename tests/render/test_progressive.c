/* params.progressive (render/gl/progressive.c, docs/ALGORITHM.md §34): a
 * still drawn in n batches, one a frame, each added to the sums the batches
 * before it left. On the tornado's lines and on a point cloud:
 * - with depthRange "global", P1's importance sums after batch k equal the
 *   sums of a one-shot frame of the first k + 1 batches (float tolerance),
 *   and after the last batch those of the one-shot frame of everything,
 *   also when one call runs every batch (batch 0), which reports batch n of
 *   n and the first picture's time before the whole one's;
 * - the last batch's image equals the one-shot image (SSIM >= 0.999, every
 *   channel within 1), with the default depth range (the moments) too;
 * - the picture after batch k resembles the one-shot frame of the first
 *   k + 1 batches (SSIM > 0.8: each batch's elements keep the opacity they
 *   got against the importance that had arrived, higher than the one-shot
 *   frame gives them; 0.84-0.94 on the tornado), the first one equals it
 *   where P0 does not see the later batches (depthRange "global"), and the
 *   pictures come no further from the whole one as batches arrive;
 * - with a fresh frame state too (each batch takes its targets whole);
 * - with params.clarity the last batch runs the loop over every primitive:
 *   the image is the one-shot's again;
 * - a batch that does not follow its predecessor on the renderer, and a
 *   method other than fourier, are refused naming params.progressive. */
#include <math.h>

#include "demo.h"
#include "image.h"
#include "render_util.h"

#define SIZE 192
#define BATCHES 6

static int max_diff(const uint8_t *a, const uint8_t *b)
{
    int m = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE * 4; i++) {
        int d = abs((int)a[i] - (int)b[i]);
        m = d > m ? d : m;
    }
    return m;
}

/* Largest |a - b| over the largest |b| of P1's sums. */
static double sums_error(const float *a, const float *b, size_t n)
{
    double diff = 0, mag = 0;
    for (size_t i = 0; i < n; i++) {
        diff = fmax(diff, fabs((double)a[i] - b[i]));
        mag = fmax(mag, fabs((double)b[i]));
    }
    return mag > 0 ? diff / mag : diff;
}

static int frame(test_gl *t, const lc_gpu_scene *gs, const lc_render_params *p, uint8_t *rgba, lc_error *err)
{
    memset(err, 0, sizeof *err);
    return lc_render_frame(t->renderer, gs, p, NULL, 0, rgba, NULL, err);
}

static size_t read_sums(test_gl *t, float *out, size_t n) { return lc_renderer_read_targets(t->renderer, 0, out, n); }

static void check_dataset(test_gl *t, const char *spec, uint64_t count, lc_depth_range range, double min_first_ssim)
{
    lc_error err = {0};
    lc_scene *s = NULL;
    lc_demo_desc desc = {.count = count};
    CHECK(lc_demo_create(spec, &desc, &s, &err) == 0, "demo %s: %s", spec, err.msg);
    lc_gpu_scene *gs = NULL;
    CHECK(s && lc_gpu_scene_create(s, &gs, &err) == 0, "upload: %s", err.msg);
    if (!gs) {
        lc_scene_destroy(s);
        return;
    }
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    p.detail.lod_pixels = 0; /* every segment */
    p.foo.depth_range = range;
    size_t cap = (size_t)SIZE * SIZE * 4 * 3;
    float *one = malloc(cap * sizeof(float)), *sums = malloc(cap * sizeof(float));
    uint8_t *whole = malloc(SIZE * SIZE * 4), *img = malloc(SIZE * SIZE * 4), *ref = malloc(SIZE * SIZE * 4);
    CHECK(frame(t, gs, &p, whole, &err) == 0, "one-shot: %s", err.msg);
    size_t n = read_sums(t, one, cap);
    CHECK(n > 0 && n <= cap, "one-shot sums: %zu floats", n);

    lc_render_params q = p;
    q.foo.progressive = BATCHES;
    double prev_ssim = 0;
    for (int k = 0; k < BATCHES; k++) {
        q.foo.batch = k + 1, q.foo.batch_prefix = false;
        CHECK(frame(t, gs, &q, img, &err) == 0, "%s batch %d: %s", spec, k, err.msg);
        CHECK(read_sums(t, sums, cap) == n, "sums' size");
        /* The one-shot frame of batches [0, k]. */
        lc_render_params r = q;
        r.foo.batch = k + 1, r.foo.batch_prefix = true;
        float *prefix = malloc(n * sizeof(float));
        CHECK(frame(t, gs, &r, ref, &err) == 0, "%s prefix %d: %s", spec, k + 1, err.msg);
        read_sums(t, prefix, n);
        double e = sums_error(sums, prefix, n), ssim = lc_image_ssim(img, ref, SIZE, SIZE);
        double to_whole = lc_image_ssim(img, whole, SIZE, SIZE);
        printf("  %s batch %d/%d: sums vs first %d batches %.2e, SSIM %.4f vs them (max diff %d), %.4f vs all\n", spec,
               k + 1, BATCHES, k + 1, e, ssim, max_diff(img, ref), to_whole);
        if (range == LC_DEPTH_RANGE_GLOBAL)
            CHECK(e < 1e-5, "%s: P1's sums after batch %d differ from the first %d batches' by %.2e", spec, k, k + 1,
                  e);
        if (k == 0)
            CHECK(ssim >= min_first_ssim, "%s: first batch SSIM %.4f vs its one-shot frame (want >= %.3f)", spec, ssim,
                  min_first_ssim);
        else if (k < BATCHES - 1)
            CHECK(ssim > 0.8, "%s: batch %d SSIM %.4f vs the first %d batches' frame", spec, k, ssim, k + 1);
        CHECK(to_whole >= prev_ssim - 0.02, "%s: batch %d's picture moved away from the whole (%.4f after %.4f)", spec,
              k, to_whole, prev_ssim);
        prev_ssim = to_whole;
        free(prefix);
        /* The reference frame in between ended the still: rerun batches 0..k to continue it. */
        for (int j = 0; j <= k && k + 1 < BATCHES; j++) {
            q.foo.batch = j + 1;
            CHECK(frame(t, gs, &q, img, &err) == 0, "%s rerun %d: %s", spec, j, err.msg);
        }
    }
    /* After the last batch: the one-shot sums and image. */
    CHECK(frame(t, gs, &p, whole, &err) == 0, "one-shot again: %s", err.msg);
    q.foo.batch = 0, q.foo.batch_prefix = false; /* every batch in one call */
    lc_frame_info info;
    memset(&err, 0, sizeof err);
    CHECK(lc_render_frame(t->renderer, gs, &q, NULL, 0, img, &info, &err) == 0, "%s all batches: %s", spec, err.msg);
    CHECK(info.batch == BATCHES && info.batches == BATCHES && info.first_batch_ms > 0 &&
              info.first_batch_ms < info.wall_ms,
          "%s all batches: batch %d of %d, first picture %.1f ms of %.1f", spec, info.batch, info.batches,
          info.first_batch_ms, info.wall_ms);
    read_sums(t, sums, n);
    double e = sums_error(sums, one, n), ssim = lc_image_ssim(img, whole, SIZE, SIZE);
    int md = max_diff(img, whole);
    printf("  %s all %d batches: sums vs one-shot %.2e, image SSIM %.5f, max diff %d\n", spec, BATCHES, e, ssim, md);
    CHECK(e < 1e-5, "%s: the batches' sums differ from the one-shot sums by %.2e", spec, e);
    CHECK(ssim >= 0.999 && md <= 1, "%s: last batch SSIM %.5f, max diff %d vs one-shot", spec, ssim, md);

    /* A fresh frame state: every batch takes its targets whole, so the last
     * image is the one-shot image of a fresh state. */
    lc_frame_state *st = lc_frame_state_create(s->elements.count);
    q.foo.batch = 0;
    memset(&err, 0, sizeof err);
    CHECK(lc_render_frame(t->renderer, gs, &q, st, 1.0 / 30, img, NULL, &err) == 0, "%s batches with a state: %s", spec,
          err.msg);
    md = max_diff(img, whole);
    CHECK(md <= 1, "%s: batches with a fresh frame state: max diff %d vs one-shot", spec, md);
    lc_frame_state_destroy(st);

    /* The clarity loop: the batches before the last run one try, the last
     * the loop over every primitive, so the image is still the one-shot's. */
    p.foo.clarity = q.foo.clarity = 0.5;
    CHECK(frame(t, gs, &p, whole, &err) == 0, "one-shot with clarity: %s", err.msg);
    q.foo.batch = 0;
    CHECK(frame(t, gs, &q, img, &err) == 0, "%s batches with clarity: %s", spec, err.msg);
    md = max_diff(img, whole);
    CHECK(md <= 1, "%s: batches with params.clarity 0.5: max diff %d vs one-shot", spec, md);
    p.foo.clarity = q.foo.clarity = 0;

    /* Refusals: a batch out of order, another method. */
    q.foo.batch = 3;
    CHECK(frame(t, gs, &q, img, &err) != 0 && strcmp(err.field, "params.progressive") == 0,
          "batch 3 after a finished still: rc 0 or field \"%s\"", err.field);
    q.foo.batch = 1;
    q.method = LC_METHOD_EXACT;
    CHECK(frame(t, gs, &q, img, &err) != 0 && strcmp(err.field, "params.progressive") == 0,
          "method exact with batches: field \"%s\"", err.field);
    free(one), free(sums), free(whole), free(img), free(ref);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    check_dataset(&t, "tornado", 0, LC_DEPTH_RANGE_GLOBAL, 0.999);
    check_dataset(&t, "tornado", 0, LC_DEPTH_RANGE_AUTO, 0.9);
    check_dataset(&t, "points", 200000, LC_DEPTH_RANGE_GLOBAL, 0.999);
    test_gl_close(&t);
    return lc_test_finish();
}
