/* Specialized programs (programs.c, docs/ALGORITHM.md §36): the frame's and
 * the scene's branch values compiled in as macros give the same image, byte
 * for byte, as the programs that read them as uniforms. Every value the
 * specialization covers is switched at least once (estimator, projection,
 * shading, halos, silhouettes, the per-pixel depth range and the moments; the
 * vertex stage's colour mode, curves, importance terms, a filter that hides
 * lines, the cluster mask and the float buffers), over lines, points, a
 * surface and layers of all three (each layer its own buffer layout and
 * colour mode), with each method that draws geometry programs. The cases
 * follow each other in one renderer, so a program cached for one case's
 * values must not serve the next. */
#include "demo.h"
#include "image.h"
#include "render_util.h"

#define SIZE 160

typedef struct demo {
    lc_scene *s;
    lc_gpu_scene *gs;
} demo;

/* A demo uploaded compact, or as the float buffers (exact 1). */
static demo load(const char *name, int exact)
{
    lc_error err = {0};
    demo d = {0};
    lc_demo_desc desc = {0};
    CHECK(lc_demo_create(name, &desc, &d.s, &err) == 0, "demo %s: %s", name, err.msg);
    lc_gpu_scene_desc gd = {.exact_positions = exact};
    CHECK(d.s && lc_gpu_scene_create_ex(d.s, &gd, &d.gs, &err) == 0, "upload %s: %s", name, err.msg);
    return d;
}

static void base_params(lc_render_params *p)
{
    lc_render_params_default(p);
    p->width = p->height = SIZE;
    p->foo.fade_half_life = 0;
}

/* Renders p both ways (of the layers when n > 0, else of d) and requires the same bytes. */
static void compare_ways(test_gl *t, const demo *d, const lc_gpu_scene *const *scenes, const lc_layer_params *layers,
                         int n, const lc_render_params *p, const char *name, uint8_t *a, uint8_t *b)
{
    for (int k = 0; k < 2; k++) {
        lc_error err = {0};
        lc_renderer_set_specialize(t->renderer, k);
        int rc = n > 0 ? lc_render_layers(t->renderer, scenes, layers, n, p, NULL, 0, k ? b : a, NULL, &err)
                       : lc_render_frame(t->renderer, d->gs, p, NULL, 1.0 / 30, k ? b : a, NULL, &err);
        CHECK(rc == 0, "%s: render: %s", name, err.msg);
    }
    size_t differing = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE * 4; i++)
        differing += a[i] != b[i];
    long ink = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE; i++)
        ink += b[4 * i] + b[4 * i + 1] + b[4 * i + 2] != 3 * 255;
    printf("%-36s %zu channels differ, %ld pixels drawn\n", name, differing, ink);
    CHECK(ink > SIZE * SIZE / 50, "%s: the frame draws something (%ld pixels)", name, ink);
    CHECK(differing == 0, "%s: %zu channels differ between the specialized and the uniform programs", name, differing);
}

static void check_case(test_gl *t, const demo *d, const lc_render_params *p, const char *name, uint8_t *a, uint8_t *b)
{
    if (d->gs)
        compare_ways(t, d, NULL, NULL, 0, p, name, a, b);
}

int main(void)
{
    unsetenv("LUCENT_SPECIALIZE"); /* it would turn specialization off in both ways */
    test_gl t;
    test_gl_open(&t);
    uint8_t *a = malloc((size_t)SIZE * SIZE * 4), *b = malloc((size_t)SIZE * SIZE * 4);
    demo lines = load("tornado", 0), points = load("points", 0), surface = load("surface", 0);
    demo exact = load("tornado", 1);
    lc_render_params p;

    base_params(&p);
    check_case(&t, &lines, &p, "lines, defaults", a, b);
    check_case(&t, &lines, &p, "lines, defaults again", a, b);
    p.foo.estimator = LC_ESTIMATOR_FOO;
    p.camera.parallel_projection = true;
    p.style.shading = LC_SHADING_NONE;
    check_case(&t, &lines, &p, "lines, foo, parallel, unshaded", a, b);
    base_params(&p);
    p.style.halo_width = 2;
    p.foo.depth_range = LC_DEPTH_RANGE_PIXEL;
    check_case(&t, &lines, &p, "lines, halos, per-pixel range", a, b);
    base_params(&p);
    p.foo.normalize = LC_NORMALIZE_OFF;
    p.foo.depth_range = LC_DEPTH_RANGE_GLOBAL;
    check_case(&t, &lines, &p, "lines, the paper's formula", a, b);
    static const struct {
        lc_method method;
        const char *name;
    } methods[] = {{LC_METHOD_OPAQUE, "lines, opaque"},   {LC_METHOD_DIRECT, "lines, direct"},
                   {LC_METHOD_WBOIT, "lines, wboit"},     {LC_METHOD_WEIGHTED_AVERAGE, "lines, weighted average"},
                   {LC_METHOD_BINNING, "lines, binning"}, {LC_METHOD_KANZLER, "lines, kanzler"}};
    for (size_t i = 0; i < sizeof methods / sizeof methods[0]; i++) {
        base_params(&p);
        p.method = methods[i].method;
        check_case(&t, &lines, &p, methods[i].name, a, b);
    }
    /* The vertex stage's values: the colour mode, transfer curves, importance
     * terms, a filter, cluster representatives (the line mask), float buffers. */
    base_params(&p);
    snprintf(p.color.attribute, sizeof p.color.attribute, "importance");
    p.color.curve = (lc_curve){.count = 2, .points = {{0, 0.2}, {1, 0.9}}};
    p.importance.curve = (lc_curve){.count = 3, .points = {{0, 0}, {0.5, 0.8}, {1, 1}}};
    check_case(&t, &lines, &p, "lines, importance colours, curves", a, b);
    base_params(&p);
    p.importance.term_count = 2;
    snprintf(p.importance.terms[0].attribute, LC_NAME_LEN, "curvature");
    p.importance.terms[0].weight = 0.7;
    snprintf(p.importance.terms[1].attribute, LC_NAME_LEN, "velocity");
    p.importance.terms[1].weight = 0.3;
    p.filter_count = 1;
    p.filters[0] = (lc_filter){.attribute = "line_length", .over = LC_FILTER_MIN, .lo = 1.5, .hi = 1e30};
    check_case(&t, &lines, &p, "lines, importance terms, a filter", a, b);
    base_params(&p);
    p.clusters.count = 40;
    check_case(&t, &lines, &p, "lines, 40 cluster representatives", a, b);
    base_params(&p);
    check_case(&t, &exact, &p, "lines, float buffers", a, b);

    /* Layers: each draws with its own scene's layout and its own colour mode
     * (the weighted average chooses a program per layer). */
    if (lines.gs && exact.gs && surface.gs) {
        const lc_gpu_scene *scenes[3] = {lines.gs, exact.gs, surface.gs};
        lc_layer_params layers[3];
        for (int i = 0; i < 3; i++)
            lc_layer_params_default(&layers[i]);
        snprintf(layers[1].color.attribute, sizeof layers[1].color.attribute, "importance");
        snprintf(layers[2].color.colormap, sizeof layers[2].color.colormap, "coolwarm");
        base_params(&p);
        compare_ways(&t, NULL, scenes, layers, 3, &p, "layers: lines, float lines, surface", a, b);
        p.method = LC_METHOD_WEIGHTED_AVERAGE;
        compare_ways(&t, NULL, scenes, layers, 3, &p, "layers, weighted average", a, b);
    }

    base_params(&p);
    check_case(&t, &points, &p, "points, defaults", a, b);
    p.camera.parallel_projection = true;
    check_case(&t, &points, &p, "points, parallel", a, b);
    base_params(&p);
    check_case(&t, &surface, &p, "surface, defaults", a, b);
    p.style.silhouette_exponent = 4;
    check_case(&t, &surface, &p, "surface, silhouettes", a, b);

    demo all[] = {lines, points, surface, exact};
    for (int i = 0; i < 4; i++) {
        lc_gpu_scene_destroy(all[i].gs);
        lc_scene_destroy(all[i].s);
    }
    free(a);
    free(b);
    test_gl_close(&t);
    return lc_test_finish();
}
