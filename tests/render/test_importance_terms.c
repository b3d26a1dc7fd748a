/* Importance terms and filters (docs/ALGORITHM.md "Importance terms",
 * "Filters") on a bundle of lines:
 * - terms that pre-combine two attributes render bit for bit like the single
 *   form on an attribute holding the combination written by hand (exact and
 *   Fourier), and a negative weight penalizes as documented;
 * - the filter "line's change of p > x" renders like a scene built without the
 *   lines that fail it (exact: identical pixels; Fourier: SSIM >= 0.999);
 * - points: the filter "value > x" renders like the cloud without those points;
 * - transfer functions: the identity curve renders today's image bit for bit,
 *   and the curve [[0,0],[1,0.5]] like the attribute a/2 written by hand. */
#include <math.h>

#include "image.h"
#include "render_util.h"

enum { SIZE = 96, LINES = 40, PER_LINE = 24 };

/* Deterministic pseudo-random numbers in [0, 1). */
static double rnd(uint32_t *state)
{
    *state = *state * 1664525u + 1013904223u;
    return (double)(*state >> 8) / 16777216.0;
}

/* Line i of the bundle: a wavy polyline through the box [-1, 1]^3; lines 0 and
 * 1 are diagonals that pin the bounds (they pass every filter of the test). */
static void line_vertex(int i, int k, float out[3])
{
    double t = (double)k / (PER_LINE - 1);
    if (i < 2) {
        double s = i == 0 ? 1 : -1;
        out[0] = (float)(-1 + 2 * t), out[1] = (float)(s * (-1 + 2 * t)), out[2] = (float)(-1 + 2 * t);
        return;
    }
    uint32_t st = (uint32_t)i * 7919u;
    double y0 = -0.8 + 1.6 * rnd(&st), z0 = -0.8 + 1.6 * rnd(&st), ph = 6.28 * rnd(&st), amp = 0.1 + 0.2 * rnd(&st);
    out[0] = (float)(-0.9 + 1.8 * t);
    out[1] = (float)(y0 + amp * sin(ph + 5 * t));
    out[2] = (float)(z0 + amp * cos(ph + 3 * t));
}

/* Attributes of vertex k of line i: a, b in [0, 1]; p rises over the line
 * by an amount that differs per line (its change decides the filter). */
static void line_attrs(int i, int k, float *a, float *b, float *p)
{
    uint32_t st = (uint32_t)i * 104729u + (uint32_t)k * 31u + 1u;
    *a = (float)rnd(&st);
    *b = (float)rnd(&st);
    double rise = i < 2 ? 900 : 1000.0 * ((i * 37) % LINES) / LINES;
    *p = (float)(1000 - rise * k / (PER_LINE - 1));
}

/* The bundle; keep (NULL = all) chooses the lines. Attributes a, b, p and the
 * hand-written combinations: half = a/2 + b/2, diff = (a - b)/2, inv = 1 - a,
 * a_half = a/2. */
static lc_scene *bundle(const int *keep)
{
    lc_error err = {0};
    int n = 0;
    for (int i = 0; i < LINES; i++)
        n += !keep || keep[i];
    lc_scene *s = lc_scene_create("bundle", LC_PRIM_LINES);
    if (!s || lc_scene_alloc_vertices(s, (uint32_t)(n * PER_LINE), 0, &err) != 0)
        return NULL;
    s->line_count = (uint32_t)n;
    s->line_offsets = malloc(sizeof(uint32_t) * ((size_t)n + 1));
    float *attr[7];
    for (int j = 0; j < 7; j++)
        attr[j] = malloc(sizeof(float) * (size_t)n * PER_LINE);
    uint32_t v = 0;
    int l = 0;
    for (int i = 0; i < LINES; i++) {
        if (keep && !keep[i])
            continue;
        s->line_offsets[l++] = v;
        for (int k = 0; k < PER_LINE; k++, v++) {
            line_vertex(i, k, s->positions + 3 * v);
            float a, b, p;
            line_attrs(i, k, &a, &b, &p);
            attr[0][v] = a, attr[1][v] = b, attr[2][v] = p;
            attr[3][v] = 0.5f * a + 0.5f * b;
            attr[4][v] = (a - b) * 0.5f;
            attr[5][v] = 1.0f - a;
            attr[6][v] = 0.5f * a;
        }
    }
    s->line_offsets[n] = v;
    static const char *const names[7] = {"a", "b", "p", "half", "diff", "inv", "a_half"};
    for (int j = 0; j < 7; j++)
        lc_scene_add_attribute(s, names[j], attr[j], &err);
    lc_elements_desc desc = {.line_budget = (uint32_t)n}; /* one element per line */
    if (lc_scene_finalize(s, &desc, &err) != 0) {
        fprintf(stderr, "finalize: %s\n", err.msg);
        lc_scene_destroy(s);
        return NULL;
    }
    return s;
}

static void params(lc_render_params *p, lc_method method)
{
    lc_render_params_default(p);
    p->width = p->height = SIZE;
    p->method = method;
    p->has_camera = true;
    lc_camera *c = &p->camera;
    c->position[0] = 0.4, c->position[1] = 0.3, c->position[2] = 4;
    c->view_up[1] = 1;
    c->view_angle = 35;
    p->detail.lod_pixels = 0;
    p->style.line_width = 0.03;
    snprintf(p->color.attribute, sizeof p->color.attribute, "a");
    p->color.has_range = true;
    p->color.range[0] = 0, p->color.range[1] = 1;
    p->importance.has_range = true;
    p->importance.range[0] = 0, p->importance.range[1] = 1;
}

static int render(test_gl *t, const lc_scene *s, const lc_render_params *p, uint8_t *rgba)
{
    lc_error err = {0};
    lc_gpu_scene *gs = NULL;
    lc_gpu_scene_desc desc = {.exact_positions = 1};
    if (lc_gpu_scene_create_ex(s, &desc, &gs, &err) != 0) {
        CHECK(0, "gpu scene: %s", err.msg);
        return -1;
    }
    int rc = lc_render_frame(t->renderer, gs, p, NULL, 0, rgba, NULL, &err);
    CHECK(rc == 0, "render: %s", err.msg);
    lc_gpu_scene_destroy(gs);
    return rc;
}

static int differing(const uint8_t *x, const uint8_t *y)
{
    int n = 0;
    for (int i = 0; i < SIZE * SIZE * 4; i++)
        n += x[i] != y[i];
    return n;
}

static lc_importance_term term(const char *name, double weight, bool invert)
{
    lc_importance_term t = {.has_range = true, .range = {0, 1}, .weight = weight, .invert = invert};
    snprintf(t.attribute, sizeof t.attribute, "%s", name);
    return t;
}

/* Terms against the hand-written attribute, both methods. */
static void check_terms(test_gl *t, const lc_scene *s)
{
    static uint8_t want[SIZE * SIZE * 4], got[SIZE * SIZE * 4];
    struct {
        const char *hand;
        lc_importance_term terms[2];
        int count;
    } cases[] = {
        {"half", {term("a", 0.5, false), term("b", 0.5, false)}, 2},
        {"diff", {term("a", 1, false), term("b", -1, false)}, 2}, /* sum w = 0: b penalizes a */
        {"inv", {term("a", -1, false)}, 1},                       /* sum w < 0: g = 1 + s */
        {"inv", {term("a", 1, true)}, 1},                         /* inverted term */
    };
    lc_method methods[2] = {LC_METHOD_EXACT, LC_METHOD_FOURIER};
    for (int m = 0; m < 2; m++)
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
            lc_render_params p;
            params(&p, methods[m]);
            snprintf(p.importance.attribute, sizeof p.importance.attribute, "%s", cases[c].hand);
            if (render(t, s, &p, want) != 0)
                return;
            for (int i = 0; i < cases[c].count; i++)
                p.importance.terms[i] = cases[c].terms[i];
            p.importance.term_count = cases[c].count;
            snprintf(p.importance.attribute, sizeof p.importance.attribute, "p"); /* the terms replace it */
            if (render(t, s, &p, got) != 0)
                return;
            int d = differing(want, got);
            printf("%s terms = \"%s\" case %zu: %d differing bytes\n", lc_method_name(methods[m]), cases[c].hand, c, d);
            CHECK(d == 0, "%s: terms for \"%s\" (case %zu) differ from the hand-written attribute in %d bytes",
                  lc_method_name(methods[m]), cases[c].hand, c, d);
        }
}

/* The filter against the scene without the failing lines. */
static void check_filter(test_gl *t, const lc_scene *all)
{
    static uint8_t want[SIZE * SIZE * 4], got[SIZE * SIZE * 4];
    const double cut = 450; /* the lines whose p falls by more than this pass (p's change < -cut) */
    int keep[LINES], kept = 0;
    for (int i = 0; i < LINES; i++) {
        float a, b, p0, p1;
        line_attrs(i, 0, &a, &b, &p0);
        line_attrs(i, PER_LINE - 1, &a, &b, &p1);
        keep[i] = (double)(p1 - p0) < -cut;
        kept += keep[i];
    }
    CHECK(kept > 4 && kept < LINES - 4, "the filter keeps %d of %d lines", kept, LINES);
    lc_scene *part = bundle(keep);
    CHECK(part != NULL, "scene without the filtered lines");
    if (!part)
        return;
    for (int m = 0; m < 2; m++) {
        lc_method method = m == 0 ? LC_METHOD_EXACT : LC_METHOD_FOURIER;
        lc_render_params p;
        params(&p, method);
        snprintf(p.importance.attribute, sizeof p.importance.attribute, "a");
        if (render(t, part, &p, want) != 0)
            break;
        p.filter_count = 1;
        lc_filter *f = &p.filters[0];
        snprintf(f->attribute, sizeof f->attribute, "p");
        f->over = LC_FILTER_CHANGE;
        f->lo = -HUGE_VAL, f->hi = -cut, f->hi_open = true;
        if (render(t, all, &p, got) != 0)
            break;
        int d = differing(want, got);
        double ssim = lc_image_ssim(want, got, SIZE, SIZE);
        printf("%s filter (%d of %d lines kept): %d differing bytes, SSIM %.6f\n", lc_method_name(method), kept, LINES,
               d, ssim);
        if (method == LC_METHOD_EXACT)
            CHECK(d == 0, "exact: the filtered scene differs from the reduced file in %d bytes", d);
        else
            CHECK(ssim >= 0.999, "fourier: SSIM %.5f of the filtered scene against the reduced file", ssim);
        /* The same frame without the filter must differ: the filter did something. */
        p.filter_count = 0;
        if (render(t, all, &p, got) != 0)
            break;
        CHECK(differing(want, got) > 0, "%s: the unfiltered frame equals the filtered one", lc_method_name(method));
    }
    lc_scene_destroy(part);
}

/* A cloud of POINTS points; point i has value v = (i * 37 % 100) / 100; the
 * first 8 (v < 0.08 or so are not among them) sit at the corners and pin the bounds. */
enum { POINTS = 400 };
static double point_value(int i) { return i < 8 ? 0.99 : (double)((i * 37) % 100) / 100.0; }

static lc_scene *cloud(double keep_above)
{
    lc_error err = {0};
    int n = 0;
    for (int i = 0; i < POINTS; i++)
        n += point_value(i) > keep_above;
    lc_scene *s = lc_scene_create("cloud", LC_PRIM_POINTS);
    if (!s || lc_scene_alloc_vertices(s, (uint32_t)n, 0, &err) != 0)
        return NULL;
    float *v = malloc(sizeof(float) * (size_t)n);
    int k = 0;
    for (int i = 0; i < POINTS; i++) {
        if (!(point_value(i) > keep_above))
            continue;
        uint32_t st = (uint32_t)i * 2654435761u + 7u;
        for (int c = 0; c < 3; c++)
            s->positions[3 * k + c] = i < 8 ? (float)(((i >> c) & 1) ? 1 : -1) : (float)(-0.9 + 1.8 * rnd(&st));
        v[k++] = (float)point_value(i);
    }
    lc_scene_add_attribute(s, "v", v, &err);
    if (lc_scene_finalize(s, NULL, &err) != 0) {
        fprintf(stderr, "finalize: %s\n", err.msg);
        lc_scene_destroy(s);
        return NULL;
    }
    return s;
}

static void check_point_filter(test_gl *t)
{
    static uint8_t want[SIZE * SIZE * 4], got[SIZE * SIZE * 4];
    const double cut = 0.5;
    lc_scene *all = cloud(-1), *part = cloud(cut);
    CHECK(all && part && part->vertex_count < all->vertex_count, "point clouds");
    for (int m = 0; all && part && m < 2; m++) {
        lc_method method = m == 0 ? LC_METHOD_EXACT : LC_METHOD_FOURIER;
        lc_render_params p;
        params(&p, method);
        snprintf(p.importance.attribute, sizeof p.importance.attribute, "v");
        snprintf(p.color.attribute, sizeof p.color.attribute, "v");
        p.style.point_size = 6;
        if (render(t, part, &p, want) != 0)
            break;
        p.filter_count = 1;
        snprintf(p.filters[0].attribute, sizeof p.filters[0].attribute, "v");
        p.filters[0].over = LC_FILTER_VERTEX;
        p.filters[0].lo = cut, p.filters[0].lo_open = true, p.filters[0].hi = HUGE_VAL;
        if (render(t, all, &p, got) != 0)
            break;
        int d = differing(want, got);
        double ssim = lc_image_ssim(want, got, SIZE, SIZE);
        printf("%s point filter (%u of %u points kept): %d differing bytes, SSIM %.6f\n", lc_method_name(method),
               part->vertex_count, all->vertex_count, d, ssim);
        if (method == LC_METHOD_EXACT)
            CHECK(d == 0, "exact: the filtered cloud differs from the reduced one in %d bytes", d);
        else
            CHECK(ssim >= 0.999, "fourier: SSIM %.5f of the filtered cloud against the reduced one", ssim);
    }
    lc_scene_destroy(all);
    lc_scene_destroy(part);
}

static void set_curve(lc_curve *c, double y1)
{
    c->count = 2;
    c->points[0][0] = 0, c->points[0][1] = 0;
    c->points[1][0] = 1, c->points[1][1] = y1;
}

/* Importance and colour curves: identity = no curve; a halving curve = the
 * attribute a/2 written by hand. */
static void check_curves(test_gl *t, const lc_scene *s)
{
    static uint8_t want[SIZE * SIZE * 4], got[SIZE * SIZE * 4];
    for (int m = 0; m < 2; m++) {
        lc_method method = m == 0 ? LC_METHOD_EXACT : LC_METHOD_FOURIER;
        for (int which = 0; which < 2; which++) { /* 0 importance, 1 colour */
            for (int half = 0; half < 2; half++) {
                lc_render_params p;
                params(&p, method);
                snprintf(p.importance.attribute, sizeof p.importance.attribute, "%s",
                         which == 0 && half ? "a_half" : "a");
                snprintf(p.color.attribute, sizeof p.color.attribute, "%s", which == 1 && half ? "a_half" : "a");
                if (render(t, s, &p, want) != 0)
                    return;
                snprintf(p.importance.attribute, sizeof p.importance.attribute, "a");
                snprintf(p.color.attribute, sizeof p.color.attribute, "a");
                set_curve(which == 0 ? &p.importance.curve : &p.color.curve, half ? 0.5 : 1.0);
                if (render(t, s, &p, got) != 0)
                    return;
                int d = differing(want, got);
                printf("%s %s curve %s: %d differing bytes\n", lc_method_name(method),
                       which == 0 ? "importance" : "colour", half ? "y = x/2" : "identity", d);
                CHECK(d == 0, "%s: %s curve %s differs in %d bytes", lc_method_name(method),
                      which == 0 ? "importance" : "colour", half ? "y = x/2" : "identity", d);
            }
        }
    }
}

int main(void)
{
    test_gl t;
    test_gl_open(&t);
    lc_scene *s = bundle(NULL);
    CHECK(s != NULL, "bundle");
    if (s) {
        check_terms(&t, s);
        check_filter(&t, s);
        check_curves(&t, s);
        check_point_filter(&t);
        lc_scene_destroy(s);
    }
    test_gl_close(&t);
    return lc_test_finish();
}
