/* Built-in demos: names, determinism per seed, counts, domains, finite data,
 * defaults that name real attributes, and the error paths. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "demo.h"
#include "lc_test.h"

static uint64_t hash_floats(const float *f, size_t n)
{
    uint64_t h = 1469598103934665603ull; /* FNV-1a */
    const unsigned char *b = (const unsigned char *)f;
    for (size_t i = 0; i < n * sizeof(float); i++)
        h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

static lc_scene *make(const char *name, uint64_t seed, uint64_t count)
{
    lc_demo_desc d = {.seed = seed, .count = count};
    lc_scene *s = NULL;
    lc_error err = {0};
    int rc = lc_demo_create(name, &d, &s, &err);
    CHECK(rc == 0 && s, "demo %s: %s", name, err.msg);
    return s;
}

/* Finite positions and attributes, bounds inside [lo, hi] per axis. */
static void check_scene(const lc_scene *s, const double lo[3], const double hi[3])
{
    int finite = 1;
    for (size_t i = 0; i < 3 * (size_t)s->vertex_count; i++)
        finite &= isfinite(s->positions[i]);
    for (int a = 0; a < s->attribute_count; a++)
        for (uint32_t v = 0; v < s->vertex_count; v++)
            finite &= isfinite(s->attributes[a].values[v]);
    CHECK(finite, "%s: finite positions and attributes", s->name);
    for (int k = 0; k < 3; k++)
        CHECK(s->bounds[k] >= lo[k] && s->bounds[3 + k] <= hi[k], "%s: axis %d in [%g, %g]: [%g, %g]", s->name, k,
              lo[k], hi[k], s->bounds[k], s->bounds[3 + k]);
    CHECK(s->finalized, "%s: finalized", s->name);
    CHECK(lc_scene_find_attribute(s, s->default_importance) >= 0, "%s: default importance '%s' exists", s->name,
          s->default_importance);
    CHECK(s->default_color[0] != '\0', "%s: default colour set", s->name);
    CHECK(s->elements.count > 0, "%s: elements built", s->name);
}

static void test_names(void)
{
    const char *const *names = lc_demo_names();
    int n = 0;
    while (names[n])
        n++;
    CHECK(n == 4, "four demos, got %d", n);
    for (int i = 0; i < n; i++)
        CHECK(lc_demo_description(names[i]) != NULL, "%s has a description", names[i]);
    CHECK(lc_demo_description("nope") == NULL && lc_demo_description(NULL) == NULL, "unknown");
    lc_scene *s = (lc_scene *)1;
    lc_error err = {0};
    CHECK(lc_demo_create("nope", NULL, &s, &err) == LC_ERR_NOT_FOUND && s == NULL, "unknown demo");
    CHECK(strstr(err.msg, "nope") != NULL, "message names it: %s", err.msg);
    lc_demo_desc big = {.count = 1ull << 40};
    CHECK(lc_demo_create("points", &big, &s, &err) == LC_ERR_LIMIT, "absurd count: %s", err.msg);
    CHECK(lc_demo_create("tornado", &big, &s, &err) == LC_ERR_LIMIT, "absurd line count");
    CHECK(lc_demo_create("surface", &big, &s, &err) == LC_ERR_LIMIT, "absurd resolution");
}

static void test_lines(const char *name, double size, uint64_t default_lines)
{
    lc_scene *a = make(name, 7, 60), *b = make(name, 7, 60), *c = make(name, 8, 60);
    if (!a || !b || !c)
        return;
    CHECK(a->type == LC_PRIM_LINES, "%s: lines", name);
    char want[64];
    snprintf(want, sizeof want, "demo:%s", name);
    CHECK(strcmp(a->name, want) == 0, "scene name %s", a->name);
    CHECK(a->line_count == 60, "%s: %u lines", name, a->line_count);
    CHECK(a->vertex_count == b->vertex_count &&
              hash_floats(a->positions, 3 * a->vertex_count) == hash_floats(b->positions, 3 * b->vertex_count),
          "%s: same seed, same lines", name);
    CHECK(a->vertex_count != c->vertex_count ||
              hash_floats(a->positions, 3 * a->vertex_count) != hash_floats(c->positions, 3 * c->vertex_count),
          "%s: different seed, different lines", name);
    double lo[3] = {0, 0, 0}, hi[3] = {size, size, size};
    check_scene(a, lo, hi);
    for (uint32_t l = 0; l < a->line_count; l++)
        CHECK(a->line_offsets[l + 1] - a->line_offsets[l] >= 2, "%s: line %u has a segment", name, l);
    CHECK(lc_scene_find_attribute(a, "velocity") >= 0, "%s: velocity", name);
    int lc = lc_scene_find_attribute(a, "line_curvature");
    CHECK(lc >= 0 && a->attributes[lc].max <= 1.0f && a->attributes[lc].min >= 0.0f &&
              a->attributes[lc].max > a->attributes[lc].min,
          "%s: line_curvature in [0,1] with spread", name);
    /* equal-arc-length sampling: every segment has the RK4 step length */
    const float *p = a->positions;
    double smin = INFINITY, smax = 0;
    for (uint32_t l = 0; l < a->line_count; l++)
        for (uint32_t i = a->line_offsets[l] + 1; i < a->line_offsets[l + 1]; i++) {
            double d = sqrt(pow(p[3 * i] - p[3 * i - 3], 2) + pow(p[3 * i + 1] - p[3 * i - 2], 2) +
                            pow(p[3 * i + 2] - p[3 * i - 1], 2));
            smin = fmin(smin, d);
            smax = fmax(smax, d);
        }
    CHECK(smax < 1.01 * smin + 1e-6 * size, "%s: uniform steps %g..%g", name, smin, smax);
    lc_scene_destroy(a);
    lc_scene_destroy(b);
    lc_scene_destroy(c);
    /* default size */
    lc_scene *d = make(name, 0, 0);
    if (d) {
        CHECK(d->line_count == default_lines, "%s: default %u lines", name, d->line_count);
        CHECK(d->elements.count >= 9000 && d->elements.count <= 10000 + d->line_count, "%s: default element budget, %u",
              name, d->elements.count);
        check_scene(d, lo, hi);
        lc_scene_destroy(d);
    }
}

static void test_points(void)
{
    lc_scene *a = make("points", 3, 30000), *b = make("points", 3, 30000), *c = make("points", 4, 30000);
    if (!a || !b || !c)
        return;
    CHECK(a->type == LC_PRIM_POINTS && a->vertex_count == 30000, "30000 points");
    CHECK(hash_floats(a->positions, 90000) == hash_floats(b->positions, 90000), "same seed");
    CHECK(hash_floats(a->positions, 90000) != hash_floats(c->positions, 90000), "different seed");
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    check_scene(a, lo, hi);
    int di = lc_scene_find_attribute(a, "density"), ci = lc_scene_find_attribute(a, "cluster");
    CHECK(di >= 0 && ci >= 0, "density and cluster attributes");
    if (di >= 0 && ci >= 0) {
        CHECK(a->attributes[di].max == 1.0f && a->attributes[di].min > 0.0f, "density in (0,1]");
        CHECK(a->attributes[ci].min == 0.0f && a->attributes[ci].max == 8.0f, "cluster ids 0..8");
        /* clustered points sit in denser cells than the background */
        double dc = 0, db = 0;
        uint32_t nc = 0, nb = 0;
        for (uint32_t v = 0; v < a->vertex_count; v++) {
            if (a->attributes[ci].values[v] == 0)
                db += a->attributes[di].values[v], nb++;
            else
                dc += a->attributes[di].values[v], nc++;
        }
        CHECK(nb > 0.05 * a->vertex_count && nb < 0.15 * a->vertex_count, "about 10%% background");
        CHECK(dc / nc > 2 * db / nb, "clusters denser than background: %g vs %g", dc / nc, db / nb);
    }
    CHECK(strcmp(a->default_importance, "density") == 0, "density is the default importance");
    lc_scene_destroy(a);
    lc_scene_destroy(b);
    lc_scene_destroy(c);
    lc_scene *d = make("points", 0, 0);
    if (d) {
        CHECK(d->vertex_count == 200000, "default 200k points");
        lc_scene_destroy(d);
    }
}

static void test_surface(void)
{
    lc_scene *a = make("surface", 1, 32), *b = make("surface", 1, 32);
    if (!a || !b)
        return;
    CHECK(a->type == LC_PRIM_TRIANGLES, "triangles");
    CHECK(hash_floats(a->positions, 3 * a->vertex_count) == hash_floats(b->positions, 3 * b->vertex_count),
          "deterministic");
    double lo[3] = {-4.5, -4.5, -2.4}, hi[3] = {4.5, 4.5, 2.4};
    check_scene(a, lo, hi);
    /* closed shared-vertex meshes: every edge is used by exactly two triangles,
     * checked through Euler's formula V - E + F = 0 for a torus and 2 for a
     * sphere: total 2 with shared vertices (a soup would give much more) */
    uint64_t V = a->vertex_count, F = a->triangle_count, E = 3 * F / 2;
    CHECK(V + F - E == 2, "Euler characteristic torus + sphere = 2: %lld", (long long)(V + F - E));
    int pi = lc_scene_find_attribute(a, "part");
    int hi_idx = lc_scene_find_attribute(a, "mean_curvature");
    CHECK(pi >= 0 && hi_idx >= 0, "part and mean_curvature");
    if (pi >= 0 && hi_idx >= 0) {
        double hk = 0, he = 0;
        uint32_t nk = 0, ne = 0;
        int outward = 1;
        for (uint32_t v = 0; v < a->vertex_count; v++) {
            const float *p = a->positions + 3 * v, *n = a->normals + 3 * v;
            if (a->attributes[pi].values[v] == 1)
                hk += a->attributes[hi_idx].values[v], nk++;
            else {
                he += a->attributes[hi_idx].values[v], ne++;
                outward &= p[0] * n[0] + p[1] * n[1] + p[2] * n[2] > 0;
            }
        }
        CHECK(outward, "ellipsoid normals point outward");
        CHECK(hk / nk > 2 * he / ne, "knot tube is more curved than the shell: %g vs %g", hk / nk, he / ne);
    }
    CHECK(strcmp(a->default_importance, "mean_curvature") == 0, "mean curvature is the default");
    lc_scene_destroy(a);
    lc_scene_destroy(b);
    lc_scene *d = make("surface", 0, 0);
    if (d) {
        CHECK(d->vertex_count > 50000 && d->vertex_count < 100000, "default size %u", d->vertex_count);
        CHECK(d->elements.count == 4000, "default 4000 patches: %u", d->elements.count);
        lc_scene_destroy(d);
    }
}

int main(void)
{
    lc_log_set_level(LC_LOG_WARN);
    test_names();
    test_lines("tornado", 1.0, 500);
    test_lines("abc", 2 * M_PI, 400);
    test_points();
    test_surface();
    return lc_test_finish();
}
