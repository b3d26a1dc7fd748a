/* The visibility report on stacked full-screen quads (one element each, every
 * pixel covered by all of them): topDecileAlpha, bottomHalfAlpha and
 * occluderAlpha of the exact method against a CPU computation from the exact
 * opacities (foo_math.c) and the exact importance behind each quad; the
 * Fourier path against the same figures within its estimate's error. An
 * unimportant quad in front of nothing weighs nothing in occluderAlpha.
 * importance.invert gives the image of the range given max first.
 * importantOccluded (important fragments with important mass in front) on
 * stacked quads against the count of the quads, and on two crossing lines
 * where one important line hides another, and where it does not.
 * topDecileReach (the top decile's share of the importance shown over its
 * share of the importance drawn) against a CPU composite of the frame's own
 * opacities, with the important quad behind and in front of the others. */
#include <math.h>

#include "camera.h"
#include "foo_math.h"
#include "render_util.h"

typedef struct expected {
    double top, bottom, occluder;
} expected;

/* The report computed on the CPU: element opacities from the exact sums
 * (every pixel alike), weights = importance mass behind each quad. */
static expected cpu_report(const test_quad *q, int n, const lc_render_params *p, const lc_scene *s)
{
    lc_fragment f[16];
    lc_view view;
    lc_camera_view(&p->camera, s->bounds, 1.0, p->height, &view);
    for (int i = 0; i < n; i++) {
        double zview = p->camera.position[2] - q[i].z;
        f[i].depth = lc_foo_normalize_depth(zview, view.depth_min, view.depth_max, p->foo.depth_margin);
        f[i].importance = q[i].g;
    }
    lc_foo_alpha_exact(f, (size_t)n, &p->foo);
    int order[16]; /* by importance, least first */
    for (int i = 0; i < n; i++)
        order[i] = i;
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && q[order[j]].g < q[order[j - 1]].g; j--) {
            int t = order[j];
            order[j] = order[j - 1], order[j - 1] = t;
        }
    expected e = {0, 0, 0};
    int top = (int)ceil(0.1 * n), half = (int)ceil(0.5 * n);
    for (int k = 0; k < top; k++)
        e.top += f[order[n - 1 - k]].alpha / top;
    double w = 0, wa = 0;
    for (int k = 0; k < half; k++) {
        int i = order[k];
        e.bottom += f[i].alpha / half;
        double behind = 0; /* the quads farther from the camera (lower z) */
        for (int j = 0; j < n; j++)
            if (q[j].z < q[i].z)
                behind += q[j].g * q[j].g;
        w += behind, wa += behind * f[i].alpha;
    }
    e.occluder = w > 0 ? wa / w : 0;
    return e;
}

static void check(test_gl *t, const char *what, const test_quad *q, int n, lc_method method, double tol)
{
    enum { SIZE = 32 };
    lc_scene *s = test_quad_scene(q, n);
    CHECK(s != NULL, "scene");
    if (!s)
        return;
    lc_render_params p;
    test_quad_params(&p, SIZE);
    p.method = method;
    lc_error err = {0};
    lc_gpu_scene *gs = NULL;
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    lc_frame_info info = {0};
    CHECK(lc_gpu_scene_create(s, &gs, &err) == 0, "gpu scene: %s", err.msg);
    if (gs && lc_render_frame(t->renderer, gs, &p, NULL, 0, rgba, &info, &err) == 0) {
        expected e = cpu_report(q, n, &p, s);
        const char *m = method == LC_METHOD_EXACT ? "exact" : "fourier";
        printf("%s, %s: top %.4f (cpu %.4f), bottom %.4f (cpu %.4f), occluder %.4f (cpu %.4f)\n", what, m,
               info.top_decile_alpha, e.top, info.bottom_half_alpha, e.bottom, info.occluder_alpha, e.occluder);
        CHECK(info.has_visibility && info.visible_elements == (uint32_t)n, "%s %s: %u visible", what, m,
              info.visible_elements);
        CHECK_NEAR(info.top_decile_alpha, e.top, tol, "topDecileAlpha");
        CHECK_NEAR(info.bottom_half_alpha, e.bottom, tol, "bottomHalfAlpha");
        CHECK_NEAR(info.occluder_alpha, e.occluder, tol, "occluderAlpha");
    } else {
        CHECK(0, "%s: render: %s", what, err.msg);
    }
    free(rgba);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

/* importance.invert: the same pixels as the range [1, 0], others than [0, 1]. */
static void check_invert(test_gl *t, const test_quad *q, int n)
{
    enum { SIZE = 32 };
    lc_scene *s = test_quad_scene(q, n);
    lc_error err = {0};
    lc_gpu_scene *gs = NULL;
    CHECK(s && lc_gpu_scene_create(s, &gs, &err) == 0, "gpu scene: %s", err.msg);
    uint8_t *img[3];
    lc_frame_info info[3];
    for (int k = 0; k < 3 && gs; k++) {
        lc_render_params p;
        test_quad_params(&p, SIZE);
        p.importance.invert = k == 1;
        p.importance.range[0] = k == 2 ? 1 : 0, p.importance.range[1] = k == 2 ? 0 : 1;
        img[k] = malloc(SIZE * SIZE * 4);
        CHECK(lc_render_frame(t->renderer, gs, &p, NULL, 0, img[k], &info[k], &err) == 0, "render: %s", err.msg);
    }
    if (gs) {
        CHECK(memcmp(img[1], img[2], SIZE * SIZE * 4) == 0, "invert renders as the range [1, 0]");
        CHECK(memcmp(img[0], img[1], SIZE * SIZE * 4) != 0, "invert changes the image");
        CHECK(info[1].top_decile_alpha == info[2].top_decile_alpha && info[1].occluder_alpha == info[2].occluder_alpha,
              "invert reports as the range [1, 0]");
        printf("invert: top decile %.4f (not inverted %.4f)\n", info[1].top_decile_alpha, info[0].top_decile_alpha);
        for (int k = 0; k < 3; k++)
            free(img[k]);
    }
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

/* importantOccluded on full-screen quads: every pixel alike, so the share is
 * the share of the important quads (g > 0.8) with >= 0.64 of g^2 in front,
 * and the important fragments are their count times the optimization
 * resolution's pixels (half the output's width and height). */
static void check_important_quads(test_gl *t, const char *what, const test_quad *q, int n, lc_method method)
{
    enum { SIZE = 32 };
    int important = 0, hidden = 0;
    for (int i = 0; i < n; i++) {
        if (q[i].g <= LC_IMPORTANT_G)
            continue;
        important++;
        double front = 0; /* the quads nearer the camera (higher z) */
        for (int j = 0; j < n; j++)
            if (q[j].z > q[i].z)
                front += q[j].g * q[j].g;
        hidden += front >= LC_IMPORTANT_MASS;
    }
    double want = important ? (double)hidden / important : 0.0;
    lc_scene *s = test_quad_scene(q, n);
    lc_render_params p;
    test_quad_params(&p, SIZE);
    p.method = method;
    lc_error err = {0};
    lc_gpu_scene *gs = NULL;
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    lc_frame_info info = {0};
    CHECK(s && lc_gpu_scene_create(s, &gs, &err) == 0, "gpu scene: %s", err.msg);
    if (gs && lc_render_frame(t->renderer, gs, &p, NULL, 0, rgba, &info, &err) == 0) {
        const char *m = lc_method_name(method);
        printf("%s, %s: importantOccluded %.4f (cpu %.4f) of %llu important fragments\n", what, m,
               info.important_occluded, want, (unsigned long long)info.important_fragments);
        CHECK(info.important_occluded == want, "%s %s: importantOccluded %g, want %g", what, m, info.important_occluded,
              want);
        uint64_t low = (uint64_t)(SIZE / 2) * (SIZE / 2);
        CHECK(info.important_fragments == (uint64_t)important * low, "%s %s: %llu important fragments, want %llu", what,
              m, (unsigned long long)info.important_fragments, (unsigned long long)important * low);
    } else {
        CHECK(0, "%s: render: %s", what, err.msg);
    }
    free(rgba);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
}

/* topDecileReach on full-screen quads (every pixel alike), fourier: from the
 * frame's own element opacities (the state's), the CPU composite in depth
 * order, T the product of (1 - alpha) in front: (top decile's share of
 * sum g alpha T) / (its share of sum g alpha); the Fourier estimate of T
 * within tol. Returns the measured value. */
static double check_reach(test_gl *t, const char *what, const test_quad *q, int n, double tol)
{
    enum { SIZE = 32 };
    lc_scene *s = test_quad_scene(q, n);
    lc_render_params p;
    test_quad_params(&p, SIZE);
    /* The paper's formula without emphasis, so that every quad keeps an
     * opacity near a half and what lies in front matters. */
    p.foo.normalize = LC_NORMALIZE_OFF;
    p.foo.q = p.foo.r = 1, p.foo.lambda = 0;
    lc_error err = {0};
    lc_gpu_scene *gs = NULL;
    lc_frame_state *st = s ? lc_frame_state_create(s->elements.count) : NULL;
    uint8_t *rgba = malloc(SIZE * SIZE * 4);
    lc_frame_info info = {0};
    double got = -1;
    CHECK(s && st && lc_gpu_scene_create(s, &gs, &err) == 0, "gpu scene: %s", err.msg);
    if (gs && lc_render_frame(t->renderer, gs, &p, st, 0, rgba, &info, &err) == 0) {
        const float *alpha = lc_frame_state_alphas(st);
        double gmax = 0;
        for (int i = 0; i < n; i++)
            gmax = q[i].g > gmax ? q[i].g : gmax;
        double sums[4] = {0, 0, 0, 0}; /* all g w, all g alpha, top g w, top g alpha */
        for (int i = 0; i < n; i++) {
            double a = alpha[i], T = 1;
            for (int j = 0; j < n; j++)
                if (q[j].z > q[i].z) /* nearer the camera */
                    T *= 1 - alpha[j];
            int top = q[i].g == gmax; /* the top decile of n <= 10 quads: the most important */
            sums[0] += q[i].g * a * T, sums[1] += q[i].g * a;
            sums[2] += top * q[i].g * a * T, sums[3] += top * q[i].g * a;
        }
        double want = (sums[2] / sums[0]) / (sums[3] / sums[1]);
        got = info.top_decile_reach;
        printf("%s: topDecileReach %.4f (cpu %.4f; opacities %.3f %.3f %.3f)\n", what, got, want, alpha[0], alpha[1],
               alpha[2]);
        CHECK(info.has_reach, "%s: topDecileReach measured", what);
        CHECK(fabs(got - want) <= tol * want, "%s: topDecileReach %g, want %g", what, got, want);
    } else {
        CHECK(0, "%s: render: %s", what, err.msg);
    }
    free(rgba);
    lc_frame_state_destroy(st);
    lc_gpu_scene_destroy(gs);
    lc_scene_destroy(s);
    return got;
}

/* The rank emphasis of lines beyond the paper's strength: ten distinct
 * importances (heavy-tailed, as speeds are) give max(0, 2 (i + 1/2) / 10 - 1)
 * by their order whatever their values; ties share their mid-rank. */
static void check_emphasis_ranks(void)
{
    const float g[10] = {0.01f, 0.02f, 0.03f, 0.04f, 0.05f, 0.06f, 0.08f, 0.12f, 0.3f, 1.0f};
    float *e = lc_emphasis_ranks(g, 10);
    CHECK(e != NULL, "emphasis ranks");
    for (int i = 0; e && i < 10; i++) {
        double want = fmax(0, 2 * (i + 0.5) / 10 - 1);
        CHECK(fabs(e[i] - want) < 1e-6, "element %d: rank emphasis %g, want %g", i, e[i], want);
    }
    free(e);
    const float tied[4] = {0.5f, 0.5f, 0.9f, 0.9f}; /* mid-ranks 1/4 and 3/4 */
    e = lc_emphasis_ranks(tied, 4);
    CHECK(e && e[0] == 0 && e[1] == 0 && fabs(e[2] - 0.5) < 1e-6 && fabs(e[3] - 0.5) < 1e-6,
          "ties share their mid-rank: %g %g %g %g", e ? e[0] : -1, e ? e[1] : -1, e ? e[2] : -1, e ? e[3] : -1);
    free(e);
}

/* Two crossing lines, one element each: a (horizontal, z = 0, importance ga)
 * in front of b (vertical, z = -1, importance gb). */
static lc_scene *crossing_lines(double ga, double gb)
{
    enum { PER = 9 };
    lc_error err = {0};
    lc_scene *s = lc_scene_create("crossing", LC_PRIM_LINES);
    if (!s || lc_scene_alloc_vertices(s, 2 * PER, 1, &err) != 0)
        return NULL;
    float *g = malloc(sizeof(float) * 2 * PER);
    s->line_count = 2;
    s->line_offsets = malloc(3 * sizeof(uint32_t));
    for (int l = 0; l < 2; l++) {
        s->line_offsets[l] = (uint32_t)(l * PER);
        for (int i = 0; i < PER; i++) {
            int v = l * PER + i;
            float u = (float)(-0.9 + 1.8 * i / (PER - 1)), *P = s->positions + 3 * v;
            P[0] = l ? 0 : u, P[1] = l ? u : 0, P[2] = l ? -1.0f : 0.0f;
            s->rgb[3 * v] = s->rgb[3 * v + 1] = s->rgb[3 * v + 2] = 0.5f;
            g[v] = (float)(l ? gb : ga);
        }
    }
    s->line_offsets[2] = 2 * PER;
    lc_scene_add_attribute(s, "importance", g, &err);
    snprintf(s->default_importance, sizeof s->default_importance, "importance");
    snprintf(s->default_color, sizeof s->default_color, "rgb");
    lc_elements_desc desc = {.line_budget = 2};
    if (lc_scene_finalize(s, &desc, &err) != 0) {
        lc_scene_destroy(s);
        return NULL;
    }
    return s;
}

/* An important line hides another only where they cross: a share above 0
 * (the back line's fragments under the front one) and below a half (the
 * front line is never hidden); none when either line is unimportant. */
static void check_important_lines(test_gl *t, lc_method method)
{
    enum { SIZE = 48 };
    const double cases[3][2] = {{1.0, 1.0}, {0.3, 1.0}, {1.0, 0.5}};
    for (int k = 0; k < 3; k++) {
        lc_scene *s = crossing_lines(cases[k][0], cases[k][1]);
        lc_render_params p;
        test_quad_params(&p, SIZE);
        p.method = method;
        p.style.line_width = 0.1;
        lc_error err = {0};
        lc_gpu_scene *gs = NULL;
        uint8_t *rgba = malloc(SIZE * SIZE * 4);
        lc_frame_info info = {0};
        CHECK(s && lc_gpu_scene_create(s, &gs, &err) == 0, "gpu scene: %s", err.msg);
        if (gs && lc_render_frame(t->renderer, gs, &p, NULL, 0, rgba, &info, &err) == 0) {
            printf("lines g %.1f over g %.1f, %s: importantOccluded %.4f of %llu important fragments\n", cases[k][0],
                   cases[k][1], lc_method_name(method), info.important_occluded,
                   (unsigned long long)info.important_fragments);
            CHECK(info.important_fragments > 0, "%s: important fragments counted", lc_method_name(method));
            if (k == 0)
                CHECK(info.important_occluded > 0 && info.important_occluded < 0.5,
                      "%s: an important line over another: importantOccluded %g, want in (0, 0.5)",
                      lc_method_name(method), info.important_occluded);
            else
                CHECK(info.important_occluded == 0, "%s: g %.1f over g %.1f hides no importance: importantOccluded %g",
                      lc_method_name(method), cases[k][0], cases[k][1], info.important_occluded);
        } else {
            CHECK(0, "render: %s", err.msg);
        }
        free(rgba);
        lc_gpu_scene_destroy(gs);
        lc_scene_destroy(s);
    }
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    printf("renderer: %s\n", lc_gl_renderer(t.gl));
    /* Two unimportant quads hide important ones (0.1 in front of all, 0.05
     * between 0.9 and 0.6); the least important (0.02) lies behind them all
     * and hides nothing, so it must not count: occluderAlpha is twice
     * bottomHalfAlpha here. */
    const test_quad hiding[5] = {{0.4, 0.1, {1, 0, 0}, 2},
                                 {0.2, 0.9, {0, 1, 0}, 2},
                                 {0.0, 0.05, {0, 0, 1}, 2},
                                 {-0.2, 0.6, {1, 1, 0}, 2},
                                 {-0.4, 0.02, {0, 1, 1}, 2}};
    check(&t, "occluders in front", hiding, 5, LC_METHOD_EXACT, 2e-3);
    check(&t, "occluders in front", hiding, 5, LC_METHOD_FOURIER, 0.05);
    /* Every unimportant quad behind every important one: nothing is hidden. */
    const test_quad context[4] = {
        {0.4, 0.9, {1, 0, 0}, 2}, {0.2, 0.7, {0, 1, 0}, 2}, {0.0, 0.1, {0, 0, 1}, 2}, {-0.2, 0.0, {1, 1, 0}, 2}};
    check(&t, "context behind", context, 4, LC_METHOD_EXACT, 2e-3);
    check_invert(&t, hiding, 5);
    /* importantOccluded: the 0.9 quad has 0.01 in front (nothing important);
     * two important quads stacked: the back one has 0.95^2 in front. */
    const test_quad stacked[3] = {{0.4, 0.95, {1, 0, 0}, 2}, {0.0, 0.9, {0, 1, 0}, 2}, {-0.4, 0.1, {0, 0, 1}, 2}};
    for (int m = 0; m < 2; m++) {
        lc_method method = m ? LC_METHOD_FOURIER : LC_METHOD_EXACT;
        check_important_quads(&t, "occluders in front", hiding, 5, method);
        check_important_quads(&t, "two important stacked", stacked, 3, method);
        check_important_lines(&t, method);
    }
    /* topDecileReach: the important quad behind two unimportant ones ("fog
     * with bright specks") reads below 1, in front of them ("structure in
     * front of context") above 1; the exact method does not measure it. */
    const test_quad fog[3] = {{0.4, 0.3, {1, 0, 0}, 2}, {0.0, 0.2, {0, 1, 0}, 2}, {-0.4, 0.9, {0, 0, 1}, 2}};
    const test_quad front[3] = {{0.4, 0.9, {1, 0, 0}, 2}, {0.0, 0.2, {0, 1, 0}, 2}, {-0.4, 0.3, {0, 0, 1}, 2}};
    double behind = check_reach(&t, "important behind", fog, 3, 0.03);
    double ahead = check_reach(&t, "important in front", front, 3, 0.03);
    CHECK(behind < 1 && ahead > 1, "topDecileReach tells them apart: %g behind, %g in front", behind, ahead);
    check_emphasis_ranks();
    test_gl_close(&t);
    return lc_test_finish();
}
