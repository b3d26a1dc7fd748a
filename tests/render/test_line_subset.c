/* Importance-aware line subsets of moving frames (render/gl/line_subset.c,
 * docs/ALGORITHM.md §11): a frame with a frame state's opacities and
 * detail.lineStride n draws the most important lines in full and about one
 * in n of the others, whole lines, weighted n in P1 and P4:
 * - it draws about 1/n of the segments plus the important lines, and looks
 *   like the same frame with every line (SSIM), with the background covered
 *   about as much (the weight n keeps the optical depth; unweighted, the
 *   tornado's coverage halves);
 * - the important lines are the ones kept in full: a bundle of important
 *   lines in front of faint clutter shows in as many pixels as with every line;
 * - a frame that re-optimizes thinned keeps the opacities of the elements it
 *   drops and looks like the one that re-optimizes with every line;
 * - a fresh state's frame draws every line, and a coarse level is thinned
 *   only as far as a segment per LC_LINE_SUBSET_PIXELS pixels;
 * - with params.subset n as well, P4 draws every n-th segment of the kept
 *   lines (the vertices its draws issue, lc_frame_info.pass_vertices), not
 *   every n-th of all the lines. */
#include <math.h>

#include "demo.h"
#include "image.h"
#include "render_util.h"

#define SIZE 256

/* Mean over the pixels of the distance to the white background (0..255). */
static double coverage(const uint8_t *rgba)
{
    double sum = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE; i++)
        sum += 3 * 255 - (rgba[4 * i] + rgba[4 * i + 1] + rgba[4 * i + 2]);
    return sum / (3.0 * SIZE * SIZE);
}

static void tornado(test_gl *t, uint8_t *a, uint8_t *b)
{
    lc_error err = {0};
    lc_scene *s = NULL;
    lc_demo_desc desc = {0};
    CHECK(lc_demo_create("tornado", &desc, &s, &err) == 0, "demo: %s", err.msg);
    lc_gpu_scene *gs = NULL;
    CHECK(s && lc_gpu_scene_create(s, &gs, &err) == 0, "upload: %s", err.msg);
    if (!gs)
        return;
    lc_frame_state *st = lc_frame_state_create(s->elements.count);
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    p.detail.lod_pixels = 0; /* every segment: 266k, over the floor */
    p.style.background[0] = p.style.background[1] = p.style.background[2] = 1;
    p.foo.fade_half_life = 0;
    lc_frame_info info, all, some;
    p.detail.line_stride = 4;
    test_render_frame(t, gs, &p, st, a, &info); /* a fresh state: no thinning */
    CHECK(info.line_stride == 1 && info.primitives_drawn == lc_scene_primitive_count(s),
          "a fresh state's frame thinned lines (stride %d, %llu segments)", info.line_stride,
          (unsigned long long)info.primitives_drawn);
    /* Re-optimizing, thinned and with every line, from the same opacities. */
    lc_frame_state *st2 = lc_frame_state_create(s->elements.count);
    p.detail.line_stride = 1;
    test_render_frame(t, gs, &p, st2, b, &info);
    test_render_frame(t, gs, &p, st2, b, &info);
    p.detail.line_stride = 4;
    test_render_frame(t, gs, &p, st2, a, &info);
    double ssim_opt = lc_image_ssim(a, b, SIZE, SIZE);
    printf("demo:tornado, a frame that re-optimizes with line stride 4: stride %d, P1 %s, SSIM %.4f vs every line\n",
           info.line_stride, info.pass_ms[LC_PASS_IMPORTANCE] >= 0 ? "ran" : "skipped", ssim_opt);
    CHECK(info.line_stride == 4 && !info.reused_opacities, "re-optimizing: stride %d, reused %d", info.line_stride,
          info.reused_opacities);
    CHECK(ssim_opt > 0.7 && ssim_opt < 0.9999, "re-optimizing with stride 4: SSIM %.4f vs every line", ssim_opt);
    /* Every line again with the opacities now in the state: the dropped
     * lines' elements kept theirs, the drawn ones moved only a little. */
    p.detail.line_stride = 1;
    p.detail.reuse_opacities = true;
    test_render_frame(t, gs, &p, st2, a, &info);
    double ssim_after = lc_image_ssim(a, b, SIZE, SIZE);
    printf("  then every line with those opacities: SSIM %.4f vs before\n", ssim_after);
    CHECK(ssim_after > 0.95, "after a thinned re-optimization, every line: SSIM %.4f vs before", ssim_after);
    p.detail.reuse_opacities = false;
    lc_frame_state_destroy(st2);
    p.detail.line_stride = 4;
    p.detail.reuse_opacities = true;
    p.detail.line_stride = 1;
    test_render_frame(t, gs, &p, st, a, &all);
    p.detail.line_stride = 4;
    test_render_frame(t, gs, &p, st, b, &some);
    uint64_t n = lc_scene_primitive_count(s);
    double ssim = lc_image_ssim(a, b, SIZE, SIZE), ca = coverage(a), cb = coverage(b);
    printf("demo:tornado, every segment (%llu), moving frame with line stride 4: %llu segments of important lines "
           "in full, %llu strided; SSIM %.4f vs every line; coverage %.2f vs %.2f\n",
           (unsigned long long)n, (unsigned long long)some.kept_line_segments[0],
           (unsigned long long)some.kept_line_segments[1], ssim, cb, ca);
    CHECK(all.line_stride == 1 && all.primitives_drawn == n, "stride 1 drew %llu of %llu",
          (unsigned long long)all.primitives_drawn, (unsigned long long)n);
    CHECK(some.line_stride == 4 && some.kept_line_segments[0] > 0 && some.primitives_drawn > n / 8 &&
              some.primitives_drawn < n / 2,
          "stride 4: %llu + %llu of %llu segments", (unsigned long long)some.kept_line_segments[0],
          (unsigned long long)some.kept_line_segments[1], (unsigned long long)n);
    CHECK(ssim > 0.75 && ssim < 0.9999, "stride 4: SSIM %.4f vs every line", ssim);
    CHECK(fabs(cb - ca) < 0.25 * ca, "stride 4 covers the background %.2f, every line %.2f", cb, ca);

    /* With params.subset 2 as well, P4 takes every other segment of the
     * kept lines (weighted 2), not every other segment of all of them; P5
     * draws the kept lines as without the subset. The subset costs the
     * thinned frame about what it costs the frame of every line. */
    lc_frame_info sub_all, sub_some;
    uint8_t *every = malloc((size_t)SIZE * SIZE * 4), *c = malloc((size_t)SIZE * SIZE * 4);
    p.detail.line_stride = 1;
    test_render_frame(t, gs, &p, st, every, NULL);
    p.foo.subset = 2;
    test_render_frame(t, gs, &p, st, c, &sub_all);
    p.detail.line_stride = 4;
    test_render_frame(t, gs, &p, st, a, &sub_some);
    p.foo.subset = 1;
    double ssim_sub = lc_image_ssim(a, b, SIZE, SIZE), ssim_alone = lc_image_ssim(c, every, SIZE, SIZE);
    free(every);
    free(c);
    uint64_t p4_all = sub_all.pass_vertices[LC_PASS_OPTICAL_DEPTH], p4 = sub_some.pass_vertices[LC_PASS_OPTICAL_DEPTH];
    printf("subset 2: P4 issued %llu vertices with line stride 4, %llu with every line (%.2f); P5 %llu, %llu "
           "without the subset; SSIM %.4f vs the stride without it (every line: %.4f vs without it)\n",
           (unsigned long long)p4, (unsigned long long)p4_all, p4_all ? (double)p4 / (double)p4_all : 0,
           (unsigned long long)sub_some.pass_vertices[LC_PASS_ACCUMULATE],
           (unsigned long long)some.pass_vertices[LC_PASS_ACCUMULATE], ssim_sub, ssim_alone);
    CHECK(sub_some.line_stride == 4 && p4 > 0 && p4 * 2 < p4_all,
          "subset 2 with line stride 4: P4 issued %llu vertices, %llu with every line", (unsigned long long)p4,
          (unsigned long long)p4_all);
    CHECK(sub_some.pass_vertices[LC_PASS_ACCUMULATE] == some.pass_vertices[LC_PASS_ACCUMULATE],
          "subset 2 changed P5's draw: %llu vertices against %llu",
          (unsigned long long)sub_some.pass_vertices[LC_PASS_ACCUMULATE],
          (unsigned long long)some.pass_vertices[LC_PASS_ACCUMULATE]);
    CHECK(ssim_sub > ssim_alone - 0.05 && ssim_sub < 0.9999,
          "subset 2 with line stride 4: SSIM %.4f vs without the subset (every line: %.4f)", ssim_sub, ssim_alone);

    /* A coarse level keeps a segment per LC_LINE_SUBSET_PIXELS pixels: the
     * stride halves until it does, down to every line. */
    p.detail.lod_pixels = 4;
    p.detail.line_stride = 1;
    test_render_frame(t, gs, &p, st, b, &all);
    p.detail.line_stride = 16;
    test_render_frame(t, gs, &p, st, b, &some);
    uint64_t floor_segments = (uint64_t)SIZE * SIZE / LC_LINE_SUBSET_PIXELS;
    printf("4 px level: %llu segments; stride 16 asked, %d used\n", (unsigned long long)all.primitives_drawn,
           some.line_stride);
    CHECK(all.primitives_drawn / (uint64_t)some.line_stride >= floor_segments &&
              (some.line_stride == 1 || all.primitives_drawn / (2 * (uint64_t)some.line_stride) < floor_segments),
          "4 px level of %llu segments: stride %d", (unsigned long long)all.primitives_drawn, some.line_stride);
    lc_frame_state_destroy(st);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

/* BUNDLE important lines (g = 0.9) in front of CLUTTER faint ones (g = 0.05),
 * every line 40 segments: thinned 8-fold, the bundle stays whole. */
static void important_bundle(test_gl *t, uint8_t *a, uint8_t *b)
{
    enum { CLUTTER = 3000, BUNDLE = 60, SEGS = 40, LINES = CLUTTER + BUNDLE, V = LINES * (SEGS + 1), STRIDE = 8 };
    lc_error err = {0};
    lc_scene *s = lc_scene_create("bundle", LC_PRIM_LINES);
    float *imp = malloc(V * sizeof(float)), *time = malloc(V * sizeof(float));
    CHECK(s && imp && time && lc_scene_alloc_vertices(s, V, 0, &err) == 0, "scene: %s", err.msg);
    if (!s || !imp || !time)
        return;
    s->line_count = LINES;
    s->line_offsets = malloc((LINES + 1) * sizeof(uint32_t));
    uint32_t seed = 11;
    for (int l = 0; l < LINES; l++) {
        s->line_offsets[l] = (uint32_t)(l * (SEGS + 1));
        float y0, z0;
        seed = seed * 1664525u + 1013904223u;
        y0 = (float)(seed >> 8) / 16777216.0f;
        seed = seed * 1664525u + 1013904223u;
        z0 = (float)(seed >> 8) / 16777216.0f;
        int important = l >= CLUTTER;
        for (int k = 0; k <= SEGS; k++) {
            float *p = s->positions + 3 * (size_t)(l * (SEGS + 1) + k);
            /* clutter: wavy lines filling a slab at the back; the bundle: a
             * sparse sheet of straight lines in front */
            p[0] = (float)k / SEGS;
            p[1] = important ? 0.1f + 0.8f * y0 : y0 + 0.02f * sinf(9.0f * p[0] + 6.0f * z0);
            p[2] = important ? 0.9f + 0.05f * z0 : 0.4f * z0;
            imp[l * (SEGS + 1) + k] = important ? 0.9f : 0.05f;
            time[l * (SEGS + 1) + k] = (float)k;
        }
    }
    s->line_offsets[LINES] = V;
    CHECK(lc_scene_add_attribute(s, "importance", imp, &err) >= 0, "attribute: %s", err.msg);
    CHECK(lc_scene_add_attribute(s, "time", time, &err) >= 0, "attribute: %s", err.msg);
    lc_gpu_scene *gs = test_upload_scene(s);
    if (!gs)
        return;
    lc_frame_state *st = lc_frame_state_create(s->elements.count);
    lc_render_params p;
    lc_render_params_default(&p);
    p.width = p.height = SIZE;
    p.detail.lod_pixels = 0;
    snprintf(p.importance.attribute, sizeof p.importance.attribute, "importance");
    snprintf(p.color.attribute, sizeof p.color.attribute, "importance");
    p.importance.has_range = true, p.importance.range[0] = 0, p.importance.range[1] = 1;
    p.foo.fade_half_life = 0;
    lc_frame_info info;
    test_render_frame(t, gs, &p, st, a, &info);
    p.detail.reuse_opacities = true;
    test_render_frame(t, gs, &p, st, a, &info);
    p.detail.line_stride = STRIDE;
    test_render_frame(t, gs, &p, st, b, &info);
    /* The bundle's colour (viridis at 0.9, yellow-green) against the clutter's (dark purple). */
    int n_all = 0, n_kept = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE; i++) {
        const uint8_t *pa = a + 4 * i, *pb = b + 4 * i;
        n_all += pa[1] > 150 && pa[1] > pa[2] + 40;
        n_kept += pb[1] > 150 && pb[1] > pb[2] + 40;
    }
    printf("important bundle, stride %d: stride used %d, %llu segments in full (the bundle has %d), %llu strided; "
           "the bundle shows in %d pixels (every line: %d)\n",
           STRIDE, info.line_stride, (unsigned long long)info.kept_line_segments[0], BUNDLE * SEGS,
           (unsigned long long)info.kept_line_segments[1], n_kept, n_all);
    CHECK(info.line_stride == STRIDE, "stride %d used (%d asked, %d segments)", info.line_stride, STRIDE, LINES * SEGS);
    CHECK(info.kept_line_segments[0] >= (uint64_t)BUNDLE * SEGS * 9 / 10 &&
              info.kept_line_segments[0] <= (uint64_t)LINES * SEGS / STRIDE,
          "%llu segments in full, the bundle has %d", (unsigned long long)info.kept_line_segments[0], BUNDLE * SEGS);
    CHECK(n_all > 100 && abs(n_kept - n_all) * 10 <= n_all, "the bundle shows in %d pixels thinned, %d with all",
          n_kept, n_all);

    /* Under a time window (segments drawn one by one from the kept strip's
     * ribbon slots): the first half of every line, the bundle still whole. */
    p.time.has_window = true, p.time.window[0] = 0, p.time.window[1] = SEGS / 2;
    p.detail.line_stride = 1;
    test_render_frame(t, gs, &p, st, a, &info);
    p.detail.line_stride = STRIDE;
    test_render_frame(t, gs, &p, st, b, &info);
    int w_all = 0, w_kept = 0, w_right = 0;
    for (int y = 0; y < SIZE; y++)
        for (int x = 0; x < SIZE; x++) {
            const uint8_t *pa = a + 4 * ((size_t)y * SIZE + x), *pb = b + 4 * ((size_t)y * SIZE + x);
            w_all += pa[1] > 150 && pa[1] > pa[2] + 40;
            w_kept += pb[1] > 150 && pb[1] > pb[2] + 40;
            w_right += x > SIZE * 3 / 4 && pb[0] + pb[1] + pb[2] < 3 * 250; /* the window's far end: nothing */
        }
    printf("  under the time window [0, %d]: stride %d, the bundle shows in %d pixels (every line: %d), %d pixels "
           "drawn past the window\n",
           SEGS / 2, info.line_stride, w_kept, w_all, w_right);
    CHECK(info.line_stride == STRIDE && w_all > 50 && abs(w_kept - w_all) * 10 <= w_all && w_kept < n_kept &&
              w_right == 0,
          "time window: stride %d, the bundle in %d pixels thinned, %d with every line, %d without the window; %d past "
          "it",
          info.line_stride, w_kept, w_all, n_kept, w_right);
    p.time.has_window = false;
    lc_frame_state_destroy(st);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    uint8_t *a = malloc(SIZE * SIZE * 4), *b = malloc(SIZE * SIZE * 4);
    tornado(&t, a, b);
    important_bundle(&t, a, b);
    free(a);
    free(b);
    test_gl_close(&t);
    return lc_test_finish();
}
