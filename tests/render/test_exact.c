/* Image tests of the exact (linked-list) method on stacked quads: GPU pixels
 * against the CPU reference of decoupled opacity optimization (exact sums,
 * exact compositing in foo_math.c), and the reports of a pool or a per-pixel
 * list that is too small; fragment reduction and the front-to-back queue
 * within their bound of one grey level; params.excludeSelf on a line folding
 * over itself. */
#include <math.h>

#include "camera.h"
#include "foo_math.h"
#include "render_util.h"

/* The fragments of one pixel covered by every quad, at the depths the GPU
 * normalizes them to. */
static void quad_fragments(const test_quad *q, int n, const lc_render_params *p, const lc_scene *s, lc_fragment *frags)
{
    lc_view view;
    lc_camera_view(&p->camera, s->bounds, 1.0, p->height, &view);
    for (int i = 0; i < n; i++) {
        double zview = p->camera.position[2] - q[i].z;
        frags[i].depth = lc_foo_normalize_depth(zview, view.depth_min, view.depth_max, p->foo.depth_margin);
        frags[i].importance = q[i].g;
        for (int c = 0; c < 3; c++)
            frags[i].color[c] = q[i].rgb[c];
    }
}

/* CPU evaluation of one pixel covered by every quad: DOO with exact sums,
 * opacities clamped as both GPU methods clamp them, exact "over". */
static void expected_pixel(const test_quad *q, int n, const lc_render_params *p, const lc_scene *s, double out[3])
{
    lc_fragment frags[32];
    quad_fragments(q, n, p, s, frags);
    lc_foo_alpha_exact(frags, (size_t)n, &p->foo);
    for (int i = 0; i < n; i++)
        frags[i].alpha = fmin(frags[i].alpha, 0.9999);
    lc_foo_composite_exact(frags, (size_t)n, p->style.background, out);
}

static int render(lc_renderer *r, const lc_scene *s, const lc_render_params *p, uint8_t *rgba, lc_frame_info *info)
{
    lc_error err = {0};
    lc_gpu_scene *gs = NULL;
    CHECK(lc_gpu_scene_create(s, &gs, &err) == 0, "gpu scene: %s", err.msg);
    if (!gs)
        return -1;
    int rc = lc_render_frame(r, gs, p, NULL, 0, rgba, info, &err);
    CHECK(rc == 0, "render: %s", err.msg);
    lc_gpu_scene_destroy(gs);
    return rc;
}

static void check_stack(test_gl *t, const test_quad *q, int n, double qw, double rw, double lambda)
{
    enum { SIZE = 40 };
    lc_scene *s = test_quad_scene(q, n);
    CHECK(s != NULL, "scene");
    if (!s)
        return;
    lc_render_params p;
    test_quad_params(&p, SIZE);
    p.method = LC_METHOD_EXACT;
    p.foo.q = qw, p.foo.r = rw, p.foo.lambda = lambda;
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    lc_frame_info info;
    if (render(t->renderer, s, &p, rgba, &info) == 0) {
        double want[3];
        expected_pixel(q, n, &p, s, want);
        double worst = 0;
        for (int i = 0; i < SIZE * SIZE; i++)
            for (int c = 0; c < 3; c++)
                worst = fmax(worst, fabs(rgba[4 * i + c] / 255.0 - want[c]));
        CHECK(worst <= 2.0 / 255.0,
              "exact, %d quads, q=%g r=%g lambda=%g: worst pixel error %.4f (want %.3f %.3f %.3f, got %d %d %d)", n, qw,
              rw, lambda, worst, want[0], want[1], want[2], rgba[0], rgba[1], rgba[2]);
        /* Every pixel is covered by all n quads. */
        CHECK(info.fragments == (uint64_t)n * SIZE * SIZE, "fragments %llu, want %d",
              (unsigned long long)info.fragments, n * SIZE * SIZE);
        CHECK(info.max_layers == (uint32_t)n && fabs(info.mean_layers - n) < 1e-9, "layers: max %u mean %g, want %d",
              info.max_layers, info.mean_layers, n);
        CHECK(info.dropped_fragments == 0, "dropped %llu", (unsigned long long)info.dropped_fragments);
        for (int k = 0; k < LC_PASS_SMOOTH + 1; k++)
            CHECK(info.pass_ms[k] >= 0, "pass %s has no time", lc_pass_name(k));
        printf("exact, %d quads, q=%-4g r=%-4g lambda=%-3g: expected (%.4f %.4f %.4f), worst error %.4f, "
               "%.2f ms GPU\n",
               n, qw, rw, lambda, want[0], want[1], want[2], worst, info.gpu_ms);
    }
    free(rgba);
    lc_scene_destroy(s);
}

/* Renders q with a renderer whose node pool holds `nodes` (exact_pool_bytes). */
static int render_pool(const test_quad *q, int n, int size, uint32_t nodes, uint8_t *rgba, lc_frame_info *info)
{
    lc_error err = {0};
    lc_renderer *small = NULL;
    lc_renderer_desc desc = {.exact_pool_bytes = 16ull * nodes};
    CHECK(lc_renderer_create(&desc, &small, &err) == 0, "renderer: %s", err.msg);
    if (!small)
        return -1;
    lc_scene *s = test_quad_scene(q, n);
    lc_render_params p;
    test_quad_params(&p, size);
    p.method = LC_METHOD_EXACT;
    memset(rgba, 0, (size_t)size * size * 4);
    int rc = render(small, s, &p, rgba, info);
    lc_scene_destroy(s);
    lc_renderer_destroy(small);
    return rc;
}

/* A pool smaller than the frame's fragments: the full-resolution list pass
 * takes the frame in bands of rows that each fit, so the image is the one a
 * pool large enough gives, byte for byte, and nothing is dropped. The quads
 * here are denser in the middle rows (small ones over three that cover the
 * frame), so a band sized from the mean overflows and is halved; the
 * optimization resolution's list pass is banded the same way, built again
 * for every try of the clarity loop. A pool smaller than one row's fragments
 * still produces the frame and reports what it dropped. */
static void check_pool_bands(test_gl *t, const test_quad *three)
{
    enum { SIZE = 32, SMALL = 12 };
    test_quad q[3 + SMALL];
    memcpy(q, three, 3 * sizeof *q);
    for (int i = 0; i < SMALL; i++)
        q[3 + i] = (test_quad){-0.45 + 0.07 * i, 0.1 + 0.07 * i, {i % 3 == 0, i % 3 == 1, i % 3 == 2}, 0.25};
    /* 3 x 32^2 + 12 x 8^2 = 3840 fragments at full resolution, 192 in each of the 8 middle rows and 96 in the
     * others; 3 x 16^2 + 12 x 4^2 = 960 at the optimization resolution, which 1100 nodes hold. */
    uint8_t want[SIZE * SIZE * 4], got[SIZE * SIZE * 4];
    lc_frame_info info, whole;
    lc_scene *s = test_quad_scene(q, 3 + SMALL);
    lc_render_params p;
    test_quad_params(&p, SIZE);
    p.method = LC_METHOD_EXACT;
    int ok = render(t->renderer, s, &p, want, &whole) == 0;
    lc_scene_destroy(s);
    /* 3200 nodes hold the optimization resolution's 960 but not the full one's 3840, which they are near enough
     * to be tried whole first (exact.c's foretelling); 1100 are far from it, whose bands start at once; 600 hold
     * neither resolution (each try of the clarity loop then builds list pass 0 in bands too). */
    static const uint32_t pools[] = {3200, 1100, 600};
    for (int k = 0; ok && k < 3; k++) {
        if (render_pool(q, 3 + SMALL, SIZE, pools[k], got, &info) != 0)
            continue;
        CHECK(whole.exact_bands == 1 && whole.dropped_fragments == 0, "the default pool: %d bands, %llu dropped",
              whole.exact_bands, (unsigned long long)whole.dropped_fragments);
        CHECK(info.dropped_fragments == 0, "%u nodes: dropped %llu", pools[k],
              (unsigned long long)info.dropped_fragments);
        /* From the mean, 1100 nodes take 5 bands of 7 rows, the third of which (rows 14-20, six of them dense)
         * overflows and is halved: nothing is dropped only if it was. */
        CHECK(k == 0 ? info.exact_bands == 2 : info.exact_bands >= 5,
              "%u nodes: %d bands (3200: 2; else 5 or more from the mean)", pools[k], info.exact_bands);
        CHECK(info.fragments == 3840 && whole.fragments == 3840, "fragments %llu and %llu, want 3840",
              (unsigned long long)info.fragments, (unsigned long long)whole.fragments);
        CHECK(info.max_layers == whole.max_layers && info.mean_layers == whole.mean_layers,
              "layers: max %u mean %g in bands, %u %g whole", info.max_layers, info.mean_layers, whole.max_layers,
              whole.mean_layers);
        CHECK(info.top_decile_alpha == whole.top_decile_alpha && info.occluder_alpha == whole.occluder_alpha,
              "%u nodes: the visibility report differs (top decile %g against %g, occluders %g against %g)", pools[k],
              info.top_decile_alpha, whole.top_decile_alpha, info.occluder_alpha, whole.occluder_alpha);
        int differ = 0;
        for (int i = 0; i < SIZE * SIZE * 4; i++)
            differ += got[i] != want[i];
        CHECK(differ == 0, "%u nodes in %d bands: %d channels differ from the whole frame's", pools[k],
              info.exact_bands, differ);
        printf("pool of %u nodes: %llu fragments in %d bands of rows, none dropped, the image byte for byte\n",
               pools[k], (unsigned long long)info.fragments, info.exact_bands);
    }
    /* 40 nodes: every row is a band of its own and still drops what is past 40, 3 x 32 - 40 at full resolution
     * and 3 x 16 - 40 at the optimization resolution. */
    if (render_pool(three, 3, SIZE, 40, got, &info) == 0) {
        uint64_t want_dropped = (uint64_t)SIZE / 2 * (3 * SIZE / 2 - 40) + (uint64_t)SIZE * (3 * SIZE - 40);
        CHECK(info.dropped_fragments == want_dropped, "pool of 40 nodes: dropped %llu, want %llu",
              (unsigned long long)info.dropped_fragments, (unsigned long long)want_dropped);
        CHECK(info.exact_bands == SIZE, "pool of 40 nodes: %d bands, want a row each", info.exact_bands);
        CHECK(info.fragments == 3 * SIZE * SIZE, "fragments %llu", (unsigned long long)info.fragments);
        CHECK(got[3] == 255, "the frame was produced");
        printf("pool of 40 nodes: %llu fragments, %llu dropped (reported)\n", (unsigned long long)info.fragments,
               (unsigned long long)info.dropped_fragments);
    }
}

/* More layers in one pixel than a sort pass holds at once (a chunk of 64):
 * both passes take the list in rounds of one chunk, nearest first, so every
 * fragment gets its exact optimal opacity (the elements' opacities against
 * the CPU's Eq. 10 over the whole stack) and the composite is the CPU's over
 * all of them, with no fragment dropped and no list stopped by the driver's
 * loop limit (300 fragments a pixel took one pass's loops past llvmpipe's
 * 65535 iterations when a list was sorted whole). */
static void check_long_lists(test_gl *t)
{
    enum { SIZE = 8, N = 300, CHUNK = 64 };
    test_quad *q = calloc(N, sizeof *q);
    lc_fragment *frags = calloc(N, sizeof *frags);
    for (int i = 0; i < N; i++) {
        q[i].z = 0.5 - (double)i / N;
        q[i].g = (double)((i * 37) % N) / N; /* the far ones include important quads */
        q[i].rgb[i % 3] = 1;
        q[i].half = 2;
    }
    lc_scene *s = test_quad_scene(q, N);
    lc_render_params p;
    test_quad_params(&p, SIZE);
    p.method = LC_METHOD_EXACT;
    uint8_t rgba[SIZE * SIZE * 4];
    lc_frame_info info;
    lc_error err = {0};
    lc_gpu_scene *gs = NULL;
    lc_frame_state *st = lc_frame_state_create(s->elements.count);
    CHECK(lc_gpu_scene_create(s, &gs, &err) == 0 && st, "gpu scene: %s", err.msg);
    if (gs && st && lc_render_frame(t->renderer, gs, &p, st, 0, rgba, &info, &err) == 0) {
        CHECK(info.max_layers == N, "max layers %u, want %d", info.max_layers, N);
        CHECK(info.dropped_fragments == 0 && info.cut_lists == 0, "long lists: dropped %llu, lists cut %llu",
              (unsigned long long)info.dropped_fragments, (unsigned long long)info.cut_lists);
        quad_fragments(q, N, &p, s, frags);
        lc_foo_alpha_exact(frags, N, &p.foo);
        const float *alpha = lc_frame_state_alphas(st);
        double worst_near = 0, worst_far = 0;
        for (int i = 0; i < N; i++) {
            double e = fabs(alpha[s->elements.vertex_elements[4 * (4 * i) + 3]] - frags[i].alpha);
            if (i < CHUNK)
                worst_near = fmax(worst_near, e);
            else
                worst_far = fmax(worst_far, e);
        }
        CHECK(worst_near < 2e-3 && worst_far < 2e-3,
              "opacities of long lists: worst error %.4f of the nearest %d, %.4f of the %d farther", worst_near, CHUNK,
              worst_far, N - CHUNK);
        for (int i = 0; i < N; i++)
            frags[i].alpha = fmin(frags[i].alpha, 0.9999);
        double want[3];
        lc_foo_composite_exact(frags, N, p.style.background, want);
        const uint8_t *px = rgba + 4 * ((SIZE / 2) * SIZE + SIZE / 2);
        double worst_px = 0;
        for (int c = 0; c < 3; c++)
            worst_px = fmax(worst_px, fabs(px[c] / 255.0 - want[c]));
        CHECK(worst_px <= 2.0 / 255, "composite of %d layers: (%d %d %d), the CPU's (%.1f %.1f %.1f)", N, px[0], px[1],
              px[2], 255 * want[0], 255 * want[1], 255 * want[2]);
        printf("%d layers per pixel: max_layers %u, %llu dropped, %llu lists cut; opacities exact to %.1e (nearest %d) "
               "and %.1e (farther %d); composite within %.2f grey levels of the CPU's\n",
               N, info.max_layers, (unsigned long long)info.dropped_fragments, (unsigned long long)info.cut_lists,
               worst_near, CHUNK, worst_far, N - CHUNK, 255 * worst_px);
    } else {
        CHECK(0, "render: %s", err.msg);
    }
    lc_frame_state_destroy(st);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
    free(frags);
    free(q);
}

/* Fragment reduction: a stack of faint quads (opacity below 1/255 by a
 * strong q) in front of an opaque important one. Some of the faint fragments
 * are left out, never more than their pixel's budget (0.5/255 of opacity),
 * and the image stays within one grey level of the CPU's composite of every
 * fragment. */
static void check_reduction(test_gl *t)
{
    enum { SIZE = 16, N = 12 };
    test_quad q[N];
    for (int i = 0; i < N; i++)
        q[i] = (test_quad){0.5 - 0.05 * i, i == N - 1 ? 1.0 : 0.0, {(double)(i % 2), 0.3, (double)(i % 3) / 2}, 2};
    lc_scene *s = test_quad_scene(q, N);
    lc_render_params p;
    test_quad_params(&p, SIZE);
    p.method = LC_METHOD_EXACT;
    p.foo.normalize = LC_NORMALIZE_OFF;
    p.foo.q = 5000, p.foo.r = 0, p.foo.lambda = 1; /* the faint quads hide the important one: alpha ~ 1/5001 */
    uint8_t rgba[SIZE * SIZE * 4];
    lc_frame_info info;
    if (render(t->renderer, s, &p, rgba, &info) == 0) {
        double want[3];
        expected_pixel(q, N, &p, s, want);
        double worst = 0;
        for (int i = 0; i < SIZE * SIZE; i++)
            for (int c = 0; c < 3; c++)
                worst = fmax(worst, fabs(rgba[4 * i + c] / 255.0 - want[c]));
        lc_fragment f[N];
        quad_fragments(q, N, &p, s, f);
        lc_foo_alpha_exact(f, N, &p.foo);
        /* Per pixel at most floor(budget / alpha) faint fragments fit the budget. */
        uint64_t most = (uint64_t)floor(0.5 / 255.0 / f[0].alpha) * SIZE * SIZE;
        CHECK(f[0].alpha < 1.0 / 255.0, "the faint quads' opacity %g is below 1/255", f[0].alpha);
        CHECK(info.reduced_fragments > 0 && info.reduced_fragments <= most, "reduced %llu fragments, want 1..%llu",
              (unsigned long long)info.reduced_fragments, (unsigned long long)most);
        CHECK(info.fragments == (uint64_t)N * SIZE * SIZE, "fragments %llu count the reduced too",
              (unsigned long long)info.fragments);
        CHECK(worst <= 1.0 / 255.0, "reduction: worst pixel error %.5f (%.2f grey levels)", worst, worst * 255);
        printf("reduction: %llu of %llu fragments left out (at most %llu fit the budget), worst error %.2f grey "
               "levels\n",
               (unsigned long long)info.reduced_fragments, (unsigned long long)info.fragments, (unsigned long long)most,
               worst * 255);
    }
    lc_scene_destroy(s);
}

/* A hairpin line (one element) whose two legs overlap exactly in an
 * orthographic view: front leg at z = 0, back leg at z = -0.5. By default
 * each leg's fragments count the other's (DOO), so the element fades for
 * hiding itself; with params.excludeSelf they do not (OOS h_ii = 0) and it
 * stays opaque. A second line (another element) crossing in front still
 * counts: the hairpin's opacity is then Eq. 10 with that line alone. */
static lc_scene *hairpin_scene(int crossing)
{
    lc_error err = {0};
    lc_scene *s = lc_scene_create("hairpin", LC_PRIM_LINES);
    int nv = 4 + (crossing ? 2 : 0);
    if (!s || lc_scene_alloc_vertices(s, (uint32_t)nv, 1, &err) != 0)
        return NULL;
    const float pts[6][3] = {{-0.8f, 0, 0},     {0.8f, 0, 0},        {0.8f, 0, -0.5f},
                             {-0.8f, 0, -0.5f}, {0.2f, -0.8f, 0.5f}, {0.2f, 0.8f, 0.5f}};
    float *g = malloc(sizeof(float) * 6); /* the scene takes it */
    for (int v = 0; v < nv; v++) {
        memcpy(s->positions + 3 * v, pts[v], sizeof pts[v]);
        s->rgb[3 * v] = s->rgb[3 * v + 1] = s->rgb[3 * v + 2] = 0.4f;
        g[v] = 0.5f;
    }
    s->line_count = crossing ? 2 : 1;
    s->line_offsets = malloc(3 * sizeof(uint32_t));
    s->line_offsets[0] = 0, s->line_offsets[1] = 4, s->line_offsets[2] = 6;
    lc_scene_add_attribute(s, "importance", g, &err);
    snprintf(s->default_importance, sizeof s->default_importance, "importance");
    snprintf(s->default_color, sizeof s->default_color, "rgb");
    lc_elements_desc desc = {.line_budget = (uint32_t)s->line_count};
    if (lc_scene_finalize(s, &desc, &err) != 0) {
        lc_scene_destroy(s);
        return NULL;
    }
    return s;
}

static void check_exclude_self(test_gl *t)
{
    enum { SIZE = 48 };
    for (int crossing = 0; crossing < 2; crossing++) {
        lc_scene *s = hairpin_scene(crossing);
        CHECK(s != NULL, "hairpin scene");
        if (!s)
            return;
        double alpha[2] = {0, 0};
        for (int exclude = 0; exclude < 2; exclude++) {
            lc_render_params p;
            test_quad_params(&p, SIZE);
            p.method = LC_METHOD_EXACT;
            p.foo.normalize = LC_NORMALIZE_OFF;
            p.foo.q = 60, p.foo.r = 500, p.foo.lambda = 1;
            p.foo.smoothing = 0;
            p.style.line_width = 0.1;
            p.foo.exclude_self = exclude;
            uint8_t *rgba = malloc(SIZE * SIZE * 4);
            lc_frame_info info;
            lc_error err = {0};
            lc_gpu_scene *gs = NULL;
            lc_frame_state *st = lc_frame_state_create(s->elements.count);
            CHECK(lc_gpu_scene_create(s, &gs, &err) == 0 && st, "gpu scene: %s", err.msg);
            if (gs && st && lc_render_frame(t->renderer, gs, &p, st, 0, rgba, &info, &err) == 0)
                alpha[exclude] = lc_frame_state_alphas(st)[s->elements.vertex_elements[3]];
            else
                CHECK(0, "render: %s", err.msg);
            lc_frame_state_destroy(st);
            lc_gpu_scene_destroy(gs);
            free(rgba);
        }
        /* Eq. 10 at g = 0.5 over the hairpin's overlap: one leg's g^2 = 0.25 in front of the back leg (r) and
         * behind the front leg (q); the crossing line (g = 0.5, in front of both legs) adds 0.25 in front. */
        double c = crossing ? 0.25 : 0.0;
        double with_self =
            fmin(lc_foo_optimal_alpha(0.5, 0.25 + c, 0, 60, 500, 1), lc_foo_optimal_alpha(0.5, c, 0.25, 60, 500, 1));
        double without = lc_foo_optimal_alpha(0.5, c, 0, 60, 500, 1);
        printf("hairpin%s: alpha %.4f (cpu %.4f) summing itself, %.4f (cpu %.4f) with excludeSelf\n",
               crossing ? " under a crossing line" : "", alpha[0], with_self, alpha[1], without);
        CHECK(fabs(alpha[0] - with_self) < 2e-3, "hairpin%s: alpha %g, want %g", crossing ? " crossed" : "", alpha[0],
              with_self);
        CHECK(fabs(alpha[1] - without) < 2e-3, "hairpin%s, excludeSelf: alpha %g, want %g", crossing ? " crossed" : "",
              alpha[1], without);
        lc_scene_destroy(s);
    }
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    printf("renderer: %s\n", lc_gl_renderer(t.gl));

    const test_quad three[3] = {{0.3, 0.2, {1, 0, 0}, 2}, {0.0, 0.9, {0, 0.8, 0}, 2}, {-0.3, 0.5, {0, 0, 1}, 2}};
    check_stack(&t, three, 3, 60, 500, 1);
    check_stack(&t, three, 3, 20, 5, 1);
    check_stack(&t, three, 3, 100, 200, 2);
    const test_quad five[5] = {{0.4, 0.1, {1, 0, 0}, 2},
                               {0.2, 0.6, {1, 1, 0}, 2},
                               {0.0, 0.3, {0, 1, 1}, 2},
                               {-0.2, 0.95, {0, 0, 1}, 2},
                               {-0.4, 0.0, {1, 0, 1}, 2}};
    check_stack(&t, five, 5, 60, 500, 1);
    check_stack(&t, five, 5, 80, 40, 1.5);
    /* Depths in a shuffled order, and longer than the insertion-sort limit (16): heap sort. */
    test_quad twenty[20];
    for (int i = 0; i < 20; i++) {
        twenty[i] = (test_quad){-0.5 + 0.05 * ((7 * i) % 20), fmod(0.37 * (i + 1), 1.0), {0, 0, 0}, 2};
        twenty[i].rgb[i % 3] = 1;
        twenty[i].rgb[(i + 1) % 3] = 0.5;
    }
    check_stack(&t, twenty, 20, 20, 50, 1);
    check_stack(&t, twenty, 20, 2, 3, 0.5);

    check_pool_bands(&t, three);
    check_reduction(&t);
    check_exclude_self(&t);
    check_long_lists(&t);

    test_gl_close(&t);
    return lc_test_finish();
}
