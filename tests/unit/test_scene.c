/* Scene core: ownership, validation errors, bounds, attribute ranges and the
 * derived attributes on hand-built lines and meshes with known answers. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "lc_test.h"
#include "scene.h"

static float *floats(uint32_t n, float v)
{
    float *f = malloc(n * sizeof *f);
    for (uint32_t i = 0; i < n; i++)
        f[i] = v;
    return f;
}

static const float *attr(const lc_scene *s, const char *name)
{
    int i = lc_scene_find_attribute(s, name);
    return i < 0 ? NULL : s->attributes[i].values;
}

/* One polyline through the given points. */
static lc_scene *make_lines(uint32_t nlines, const uint32_t *lens, const float *pos)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < nlines; i++)
        n += lens[i];
    lc_scene *s = lc_scene_create("lines", LC_PRIM_LINES);
    lc_scene_alloc_vertices(s, n, 0, NULL);
    memcpy(s->positions, pos, 3 * n * sizeof(float));
    s->line_count = nlines;
    s->line_offsets = malloc((nlines + 1) * sizeof(uint32_t));
    s->line_offsets[0] = 0;
    for (uint32_t i = 0; i < nlines; i++)
        s->line_offsets[i + 1] = s->line_offsets[i] + lens[i];
    return s;
}

static void test_basics(void)
{
    lc_scene *s = lc_scene_create("a name that is quite long but fits", LC_PRIM_POINTS);
    CHECK(s != NULL, "create");
    CHECK(strcmp(s->name, "a name that is quite long but fits") == 0, "name %s", s->name);
    char longname[200];
    memset(longname, 'x', sizeof longname - 1);
    longname[sizeof longname - 1] = '\0';
    lc_scene *t = lc_scene_create(longname, LC_PRIM_LINES);
    CHECK(strlen(t->name) == LC_NAME_LEN - 1, "name truncated to %zu", strlen(t->name));
    lc_scene_destroy(t);
    lc_scene_destroy(NULL);

    lc_error err = {0};
    CHECK(lc_scene_alloc_vertices(s, LC_MAX_VERTICES + 1u, 0, &err) == LC_ERR_LIMIT, "cap");
    CHECK(lc_scene_alloc_vertices(s, 4, 1, &err) == 0, "alloc");
    CHECK(s->rgb != NULL && s->vertex_count == 4, "rgb allocated");
    for (int i = 0; i < 12; i++) {
        s->positions[i] = (float)i;
        s->rgb[i] = 0.5f;
    }
    CHECK(strcmp(lc_prim_type_name(LC_PRIM_POINTS), "points") == 0, "points name");
    CHECK(strcmp(lc_prim_type_name(LC_PRIM_LINES), "lines") == 0, "lines name");
    CHECK(strcmp(lc_prim_type_name(LC_PRIM_TRIANGLES), "triangles") == 0, "triangles name");
    CHECK(lc_scene_primitive_count(s) == 4, "points count");

    float *a = floats(4, 1.0f);
    a[2] = NAN;
    a[3] = 7.0f;
    CHECK(lc_scene_add_attribute(s, "speed", a, &err) == 0, "add");
    CHECK(lc_scene_add_attribute(s, "temp", floats(4, -2.0f), &err) == 1, "add second");
    CHECK(lc_scene_add_attribute(s, "speed", floats(4, 3.0f), &err) == 0, "replace keeps index");
    CHECK(s->attribute_count == 2, "replace does not add");
    CHECK(lc_scene_find_attribute(s, "temp") == 1, "find");
    CHECK(lc_scene_find_attribute(s, "nope") == -1, "find missing");
    CHECK(lc_scene_add_attribute(s, "", floats(4, 0), &err) < 0, "empty name rejected (freed)");
    CHECK(lc_scene_add_attribute(s, longname, floats(4, 0), &err) == LC_ERR_INVALID, "long name");
    CHECK(lc_scene_add_attribute(s, "x", NULL, &err) == LC_ERR_INVALID, "NULL values");
    for (int i = 2; i < LC_MAX_ATTRIBUTES; i++) {
        char name[16];
        snprintf(name, sizeof name, "a%d", i);
        CHECK(lc_scene_add_attribute(s, name, floats(4, (float)i), &err) == i, "fill %d", i);
    }
    CHECK(lc_scene_add_attribute(s, "one-too-many", floats(4, 0), &err) == LC_ERR_LIMIT, "attribute cap: %s", err.msg);
    s->attributes[0].values[2] = NAN;  /* min/max must ignore it */
    s->attributes[0].values[3] = 9.5f; /* not a whole number: an amount, not a class label */
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize points: %s", err.msg);
    CHECK(s->finalized, "finalized");
    CHECK(s->attributes[0].min == 3.0f && s->attributes[0].max == 9.5f, "range over finite values");
    CHECK(s->bounds[0] == 0 && s->bounds[1] == 1 && s->bounds[2] == 2, "bounds min");
    CHECK(s->bounds[3] == 9 && s->bounds[4] == 10 && s->bounds[5] == 11, "bounds max");
    CHECK(strcmp(s->default_importance, "speed") == 0, "points: first attribute is default");
    CHECK(strcmp(s->default_color, "rgb") == 0, "default colour: the file's own colours");
    CHECK(s->elements.count == 4 && s->elements.adjacency_count == 0, "one element per point");
    CHECK(s->normals == NULL && s->tangents == NULL, "points have no normals/tangents");
    /* finalize twice is fine */
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize again");
    lc_scene_destroy(s);

    /* points without attributes: a derived density is their importance */
    s = lc_scene_create("bare", LC_PRIM_POINTS);
    lc_scene_alloc_vertices(s, 1, 0, NULL);
    s->positions[0] = s->positions[1] = s->positions[2] = 0;
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "single point");
    CHECK(strcmp(s->default_importance, "density") == 0 && s->attribute_count == 1 &&
              s->attributes[0].values[0] == 1.0f,
          "no attribute: density (%s, %d attributes)", s->default_importance, s->attribute_count);
    lc_scene_destroy(s);

    /* a dense cluster in a sparse cloud: the cluster's points are denser,
     * the densest neighbourhood is 1, and a flat cloud (z = 0) works too */
    for (int flat = 0; flat < 2; flat++) {
        s = lc_scene_create("cluster", LC_PRIM_POINTS);
        lc_scene_alloc_vertices(s, 2000, 0, NULL);
        for (uint32_t i = 0; i < 2000; i++) {
            double t = i * 0.618034, u = i * 0.414214, w = i * 0.732051;
            double spread = i < 1000 ? 0.05 : 1.0; /* the first half in a small box */
            s->positions[3 * i] = (float)(spread * (t - floor(t)));
            s->positions[3 * i + 1] = (float)(spread * (u - floor(u)));
            s->positions[3 * i + 2] = flat ? 0.0f : (float)(spread * (w - floor(w)));
        }
        CHECK(lc_scene_finalize(s, NULL, &err) == 0, "cluster (%s)", err.msg);
        int d = lc_scene_find_attribute(s, "density");
        if (d >= 0) {
            double in = 0, out = 0;
            for (uint32_t i = 0; i < 2000; i++)
                *(i < 1000 ? &in : &out) += s->attributes[d].values[i] / 1000.0;
            CHECK(in > 5 * out && s->attributes[d].max == 1.0f && s->attributes[d].min > 0,
                  "%s: density %.3f in the cluster, %.3f outside, range %g..%g", flat ? "flat" : "3D", in, out,
                  s->attributes[d].min, s->attributes[d].max);
        } else {
            CHECK(0, "cluster: no density");
        }
        lc_scene_destroy(s);
    }
}

static void test_validation(void)
{
    lc_error err = {0};
    lc_scene *s = lc_scene_create("empty", LC_PRIM_POINTS);
    CHECK(lc_scene_finalize(s, NULL, &err) == LC_ERR_INVALID, "no vertices");
    CHECK(strstr(err.msg, "empty") != NULL, "message names the scene: %s", err.msg);
    lc_scene_alloc_vertices(s, 2, 0, NULL);
    memset(s->positions, 0, 6 * sizeof(float));
    s->positions[4] = INFINITY;
    CHECK(lc_scene_finalize(s, NULL, &err) == LC_ERR_INVALID, "inf position");
    CHECK(strstr(err.msg, "vertex 1") != NULL, "names the vertex: %s", err.msg);
    s->positions[4] = NAN;
    CHECK(lc_scene_finalize(s, NULL, &err) == LC_ERR_INVALID, "nan position");
    lc_scene_destroy(s);

    float pos[12] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0};
    uint32_t lens[2] = {2, 2};
    s = make_lines(2, lens, pos);
    s->line_offsets[1] = 3;
    s->line_offsets[2] = 2;
    CHECK(lc_scene_finalize(s, NULL, &err) == LC_ERR_INVALID, "decreasing offsets");
    CHECK(strstr(err.msg, "line 1") != NULL, "names the line: %s", err.msg);
    s->line_offsets[1] = 2;
    s->line_offsets[2] = 5;
    CHECK(lc_scene_finalize(s, NULL, &err) == LC_ERR_INVALID, "offsets beyond vertices: %s", err.msg);
    s->line_offsets[2] = 3; /* ends inside the vertex range: allowed, vertex 3 is unused */
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "offsets within range: %s", err.msg);
    CHECK(lc_scene_primitive_count(s) == 1, "segments %llu", (unsigned long long)lc_scene_primitive_count(s));
    free(s->line_offsets);
    s->line_offsets = NULL;
    CHECK(lc_scene_finalize(s, NULL, &err) == LC_ERR_INVALID, "lines without offsets");
    lc_scene_destroy(s);

    s = lc_scene_create("tri", LC_PRIM_TRIANGLES);
    lc_scene_alloc_vertices(s, 3, 0, NULL);
    memcpy(s->positions, pos, 9 * sizeof(float));
    CHECK(lc_scene_finalize(s, NULL, &err) == LC_ERR_INVALID, "no triangles");
    s->triangle_count = 1;
    s->triangles = malloc(3 * sizeof(uint32_t));
    s->triangles[0] = 0;
    s->triangles[1] = 1;
    s->triangles[2] = 3;
    CHECK(lc_scene_finalize(s, NULL, &err) == LC_ERR_INVALID, "index out of range");
    CHECK(strstr(err.msg, "triangle 0") != NULL, "names the triangle: %s", err.msg);
    s->triangles[2] = 2; /* degenerate (collinear) but valid */
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "degenerate triangle accepted: %s", err.msg);
    const float *h = attr(s, "mean_curvature");
    CHECK(h && h[0] == 0 && h[1] == 0 && h[2] == 0, "degenerate: zero curvature, no NaN");
    CHECK(isfinite(s->normals[0]) && isfinite(s->normals[2]), "degenerate: finite normal");
    lc_scene_destroy(s);
}

static void test_straight_line(void)
{
    /* uneven spacing and a repeated vertex: curvature 0, exact arc length */
    float pos[] = {0, 0, 0, 0.5f, 0, 0, 0.5f, 0, 0, 2, 0, 0, 3, 0, 0};
    uint32_t lens[1] = {5};
    lc_scene *s = make_lines(1, lens, pos);
    lc_error err = {0};
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    const float *arc = attr(s, "arc_length"), *k = attr(s, "curvature"), *len = attr(s, "line_length");
    CHECK(arc && k && len, "derived attributes present");
    const float want[] = {0, 0.5f, 0.5f, 2, 3};
    for (int i = 0; i < 5; i++) {
        CHECK_NEAR(arc[i], want[i], 1e-6, "arc length");
        CHECK_NEAR(k[i], 0.0, 1e-6, "curvature of a straight line");
        CHECK_NEAR(len[i], 3.0, 1e-6, "line length");
        CHECK_NEAR(s->tangents[3 * i], 1.0, 1e-6, "tangent x");
        CHECK_NEAR(s->tangents[3 * i + 1], 0.0, 1e-6, "tangent y");
    }
    CHECK(strcmp(s->default_importance, "curvature") == 0, "lines default importance");
    CHECK(lc_scene_primitive_count(s) == 4, "segments");
    lc_scene_destroy(s);
}

static void test_circle(void)
{
    /* open circle polyline of radius R plus a second line of one vertex */
    enum { N = 200 };
    const double R = 2.5;
    float pos[3 * (N + 1)];
    for (int i = 0; i < N; i++) {
        double a = 2 * M_PI * i / N;
        pos[3 * i] = (float)(R * cos(a));
        pos[3 * i + 1] = (float)(R * sin(a));
        pos[3 * i + 2] = 1.0f;
    }
    pos[3 * N] = 9;
    pos[3 * N + 1] = 9;
    pos[3 * N + 2] = 9;
    uint32_t lens[2] = {N, 1};
    lc_scene *s = make_lines(2, lens, pos);
    lc_error err = {0};
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    const float *k = attr(s, "curvature"), *arc = attr(s, "arc_length");
    CHECK_NEAR(k[0], 0.0, 0, "end curvature 0");
    CHECK_NEAR(k[N - 1], 0.0, 0, "end curvature 0");
    double worst = 0;
    for (int i = 1; i < N - 1; i++)
        worst = fmax(worst, fabs(k[i] - 1.0 / R));
    CHECK_NEAR(worst, 0.0, 1e-3 / R, "circle curvature 1/R (max deviation)");
    double seg = 2 * R * sin(M_PI / N);
    CHECK_NEAR(arc[N - 1], (N - 1) * seg, 1e-4, "arc length of the chords");
    /* tangent at vertex 50 (angle pi/2) points along -x */
    CHECK_NEAR(s->tangents[3 * 50], -1.0, 1e-4, "tangent along circle");
    CHECK_NEAR(s->tangents[3 * N], 1.0, 0, "single-vertex line gets a unit tangent");
    CHECK(k[N] == 0 && arc[N] == 0, "single-vertex line attributes");
    CHECK(s->bounds[5] == 9 && s->bounds[2] == 1, "bounds z");
    lc_scene_destroy(s);
}

/* UV sphere as an indexed mesh with shared poles and seam. */
static lc_scene *make_sphere(double R, int stacks, int slices)
{
    uint32_t nv = (uint32_t)(2 + (stacks - 1) * slices);
    uint32_t nt = (uint32_t)(2 * slices * (stacks - 1));
    lc_scene *s = lc_scene_create("sphere", LC_PRIM_TRIANGLES);
    lc_scene_alloc_vertices(s, nv, 0, NULL);
    float *p = s->positions;
    p[0] = 0, p[1] = 0, p[2] = (float)R;
    p[3] = 0, p[4] = 0, p[5] = (float)-R;
    for (int i = 1; i < stacks; i++)
        for (int j = 0; j < slices; j++) {
            double th = M_PI * i / stacks, ph = 2 * M_PI * j / slices;
            float *q = p + 3 * (2 + (i - 1) * slices + j);
            q[0] = (float)(R * sin(th) * cos(ph));
            q[1] = (float)(R * sin(th) * sin(ph));
            q[2] = (float)(R * cos(th));
        }
    s->triangles = malloc(3 * nt * sizeof(uint32_t));
    uint32_t *t = s->triangles, k = 0;
#define V(i, j) (uint32_t)(2 + ((i)-1) * slices + ((j) % slices))
    for (int j = 0; j < slices; j++) {
        t[k++] = 0, t[k++] = V(1, j), t[k++] = V(1, j + 1);
        t[k++] = 1, t[k++] = V(stacks - 1, j + 1), t[k++] = V(stacks - 1, j);
    }
    for (int i = 1; i < stacks - 1; i++)
        for (int j = 0; j < slices; j++) {
            t[k++] = V(i, j), t[k++] = V(i + 1, j), t[k++] = V(i + 1, j + 1);
            t[k++] = V(i, j), t[k++] = V(i + 1, j + 1), t[k++] = V(i, j + 1);
        }
#undef V
    s->triangle_count = k / 3;
    return s;
}

static void test_sphere(void)
{
    const double R = 3.0;
    lc_scene *s = make_sphere(R, 60, 120);
    lc_error err = {0};
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    const float *h = attr(s, "mean_curvature");
    CHECK(h != NULL, "mean curvature present");
    double sum = 0, worst = 0;
    uint32_t n = 0;
    for (uint32_t v = 2; v < s->vertex_count; v++) {
        sum += h[v];
        worst = fmax(worst, fabs(h[v] - 1.0 / R));
        n++;
    }
    CHECK_NEAR(sum / n, 1.0 / R, 0.01 / R, "sphere mean |H| = 1/R");
    CHECK_NEAR(worst, 0.0, 0.05 / R, "sphere |H| everywhere near 1/R");
    /* outward unit normals */
    double worst_n = 0;
    for (uint32_t v = 0; v < s->vertex_count; v++) {
        const float *p = s->positions + 3 * v, *nr = s->normals + 3 * v;
        double d = (p[0] * nr[0] + p[1] * nr[1] + p[2] * nr[2]) / R;
        worst_n = fmax(worst_n, fabs(d - 1));
    }
    CHECK_NEAR(worst_n, 0.0, 1e-3, "normals are outward unit radial");
    CHECK(strcmp(s->default_importance, "mean_curvature") == 0, "surface default importance");
    CHECK_NEAR(s->bounds[2], -R, 1e-6, "bounds zmin");
    CHECK_NEAR(s->bounds[5], R, 1e-6, "bounds zmax");
    CHECK(lc_scene_primitive_count(s) == s->triangle_count, "triangle count");
    lc_scene_destroy(s);
}

static void test_plane_boundary(void)
{
    /* flat grid: |H| = 0 inside and on the boundary (normal projection) */
    enum { G = 10 };
    lc_scene *s = lc_scene_create("plane", LC_PRIM_TRIANGLES);
    lc_scene_alloc_vertices(s, G * G, 0, NULL);
    for (int i = 0; i < G; i++)
        for (int j = 0; j < G; j++) {
            float *p = s->positions + 3 * (i * G + j);
            p[0] = (float)j + (i % 2) * 0.3f;
            p[1] = (float)i;
            p[2] = 0;
        }
    s->triangle_count = 2 * (G - 1) * (G - 1);
    s->triangles = malloc(3 * s->triangle_count * sizeof(uint32_t));
    uint32_t k = 0;
    for (int i = 0; i + 1 < G; i++)
        for (int j = 0; j + 1 < G; j++) {
            uint32_t a = i * G + j, b = a + 1, c = a + G, d = c + 1;
            uint32_t *t = s->triangles + 3 * k;
            t[0] = a, t[1] = b, t[2] = d, t[3] = a, t[4] = d, t[5] = c;
            k += 2;
        }
    lc_error err = {0};
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    const float *h = attr(s, "mean_curvature");
    double worst = 0;
    for (uint32_t v = 0; v < s->vertex_count; v++)
        worst = fmax(worst, fabs(h[v]));
    CHECK_NEAR(worst, 0.0, 1e-5, "flat plane |H| = 0 including boundary");
    CHECK_NEAR(fabs(s->normals[2]), 1.0, 1e-6, "plane normal");
    lc_scene_destroy(s);
}

/* Robust percentiles: exact ranks on a known sequence, one huge outlier that
 * squashes min/max but not the 98th percentile, NaNs ignored, and the element
 * budget of a finalized scene rebuilt on request. */
static void test_percentiles_and_budget(void)
{
    enum { N = 10001 };
    float *v = malloc(N * sizeof(float));
    for (int i = 0; i < N; i++)
        v[i] = (float)i; /* 0..10000: rank p * 10000 is the value p * 10000 */
    CHECK(fabs(lc_scene_percentile(v, N, 0, N - 1, 0.02) - 200) < 1.0, "2nd percentile of 0..10000");
    CHECK(fabs(lc_scene_percentile(v, N, 0, N - 1, 0.98) - 9800) < 1.0, "98th percentile of 0..10000");
    v[N - 1] = 1e30f; /* an outlier */
    v[0] = NAN;
    float p98 = lc_scene_percentile(v, N, 1, 1e30f, 0.98);
    CHECK(p98 > 9700 && p98 < 9900, "98th percentile survives an outlier of 1e30: %g", p98);
    CHECK(lc_scene_percentile(v, 0, 0, 1, 0.5) == 0, "no values: lo");
    /* Integer codes around zero: the percentile is one of the values, not a
     * denormal next to 0 (the bins narrow towards 0 without ever being narrow
     * against it). */
    for (int i = 0; i < N; i++)
        v[i] = i < 100 ? -1.0f : (float)(i % 20);
    CHECK(lc_scene_percentile(v, N, -1, 19, 0.02) == 0.0f, "2nd percentile of integer codes: %g",
          lc_scene_percentile(v, N, -1, 19, 0.02));
    CHECK(lc_scene_percentile(v, N, -1, 19, 0.5) == 9.0f || lc_scene_percentile(v, N, -1, 19, 0.5) == 10.0f,
          "median of integer codes: %g", lc_scene_percentile(v, N, -1, 19, 0.5));

    /* The auto importance range. Values 0..0.99 have quartiles near 0.25 and
     * 0.75, so the far-out fences lie near -1.25 and 2.25. A tail of 3% up to
     * 2.2 is beyond the 98th percentile but inside the fence: kept whole. A
     * longer one is cut at the 98th percentile; outliers on both ends are cut
     * off at the last values inside the fences. */
    lc_attribute a = {.values = v};
    for (int i = 0; i < N; i++)
        v[i] = i < N - 300 ? (float)(i % 100) / 100.0f : 1.0f + (float)(i - (N - 300)) * 0.004f;
    lc_attribute_update_range(&a, N);
    CHECK(a.p98 < a.max && a.max > 2.19f, "the tail lies beyond the 98th percentile (%g)", a.p98);
    CHECK(a.auto_lo == a.min && a.auto_hi == a.max, "a tail inside the fence: [%g, %g] is min/max [%g, %g]", a.auto_lo,
          a.auto_hi, a.min, a.max);
    for (int i = N - 300; i < N; i++)
        v[i] = 1.0f + (float)(i - (N - 300)) * 0.03f; /* up to 9.97 */
    lc_attribute_update_range(&a, N);
    CHECK(a.auto_hi == a.p98 && a.auto_hi < 9.0f, "a tail beyond the fence is cut at the 98th percentile: %g",
          a.auto_hi);
    for (int i = 0; i < N; i++)
        v[i] = (float)(i % 100) / 100.0f;
    v[17] = 1e6f, v[18] = -5e3f, v[19] = NAN;
    lc_attribute_update_range(&a, N);
    CHECK(a.min == -5e3f && a.max == 1e6f, "min/max keep the outliers");
    CHECK(a.auto_lo == 0.0f && a.auto_hi == 0.99f, "outliers cut off on both ends: [%g, %g]", a.auto_lo, a.auto_hi);
    free(v);

    lc_scene *s = lc_scene_create("budget", LC_PRIM_LINES);
    lc_error err = {0};
    CHECK(lc_scene_alloc_vertices(s, 1000, 0, &err) == 0, "alloc");
    for (int i = 0; i < 1000; i++) {
        s->positions[3 * i] = (float)(i % 100);
        s->positions[3 * i + 1] = (float)(i / 100);
        s->positions[3 * i + 2] = 0;
    }
    s->line_count = 10;
    s->line_offsets = malloc(11 * sizeof(uint32_t));
    for (int l = 0; l <= 10; l++)
        s->line_offsets[l] = (uint32_t)(100 * l);
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    CHECK(s->elements.count == 990, "the default budget (10,000) gives every one of the 990 segments an element: %u",
          s->elements.count);
    CHECK(lc_scene_set_element_budget(s, 50, &err) == 0 && s->elements.count == 50, "budget 50: %u", s->elements.count);
    CHECK(lc_scene_set_element_budget(s, 5000, &err) != 0 && strcmp(err.field, "elements") == 0,
          "a budget above the segment count names the field: %s", err.msg);
    CHECK(s->elements.count == 50, "a refused budget keeps the elements");
    lc_scene_destroy(s);
}

/* The names whose smaller values matter more (docs/GUIDE.md "Default attributes"). */
static void test_smaller_matters(void)
{
    static const char *const yes[] = {"magnitude", "Vmag", "abs_mag", "mag", "p_value", "P-Value", "pval", "rank"};
    static const char *const no[] = {"speed", "image", "magnet", "pv", "value", "p", "ranking", "", "mean_curvature"};
    for (size_t i = 0; i < sizeof yes / sizeof yes[0]; i++)
        CHECK(lc_attribute_smaller_matters(yes[i]), "%s: smaller should matter", yes[i]);
    for (size_t i = 0; i < sizeof no / sizeof no[0]; i++)
        CHECK(!lc_attribute_smaller_matters(no[i]), "%s: larger should matter", no[i]);
}

/* A point cloud of n points on a line with the given attributes (values
 * value(i, k) for attribute k); the loader's pick is the first, as
 * lc_io_set_defaults does. */
static lc_scene *labelled(int rgb, int count, const char *const *names, float (*value)(uint32_t, int))
{
    enum { N = 64 };
    lc_scene *s = lc_scene_create("labels", LC_PRIM_POINTS);
    lc_scene_alloc_vertices(s, N, rgb, NULL);
    for (uint32_t i = 0; i < 3 * N; i++) {
        s->positions[i] = (float)(i * 7 % 13);
        if (rgb)
            s->rgb[i] = 0.5f;
    }
    for (int k = 0; k < count; k++) {
        float *v = floats(N, 0);
        for (uint32_t i = 0; i < N; i++)
            v[i] = value(i, k);
        lc_scene_add_attribute(s, names[k], v, NULL);
    }
    snprintf(s->default_importance, sizeof s->default_importance, "%s", names[0]);
    if (rgb)
        snprintf(s->default_color, sizeof s->default_color, "rgb");
    return s;
}

static float class_then_amount(uint32_t i, int k) { return k == 0 ? (float)(i % 4) - 1 : 0.25f * (float)i; }
static float wide_integers(uint32_t i, int k) { return k == 0 ? (float)(i * 3) : 1.5f; } /* 0..189: an amount */
static float halves(uint32_t i, int k) { return k == 0 ? 0.5f * (float)(i % 4) : 1.0f; }

/* The class-label rule (docs/GUIDE.md "Default attributes"): a categorical attribute
 * is never the default importance, and colours the points instead. */
static void test_class_labels(void)
{
    lc_error err = {0};
    static const char *const label_speed[] = {"label", "speed"}, *const label_only[] = {"label"};
    lc_scene *s = labelled(0, 2, label_speed, class_then_amount);
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    CHECK(s->attributes[0].categorical && !s->attributes[1].categorical, "label categorical, speed not");
    CHECK(strcmp(s->default_importance, "speed") == 0, "a label gives way to an amount: %s", s->default_importance);
    CHECK(strcmp(s->default_color, "label") == 0, "the label colours: %s", s->default_color);
    lc_scene_destroy(s);

    s = labelled(1, 1, label_only, class_then_amount);
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    CHECK(strcmp(s->default_importance, "density") == 0 && lc_scene_find_attribute(s, "density") == 1,
          "only a label: density derived and the importance (%s)", s->default_importance);
    CHECK(!s->attributes[1].categorical, "density is an amount");
    CHECK(strcmp(s->default_color, "rgb") == 0, "the file's colours win over the label: %s", s->default_color);
    lc_scene_destroy(s);

    static const char *const named[] = {"importance"};
    s = labelled(0, 1, named, class_then_amount);
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    CHECK(strcmp(s->default_importance, "importance") == 0 && s->attribute_count == 1,
          "an attribute named importance stays, whole numbers or not (%s)", s->default_importance);
    lc_scene_destroy(s);

    s = labelled(0, 1, label_only, wide_integers);
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    CHECK(!s->attributes[0].categorical && strcmp(s->default_importance, "label") == 0,
          "integers spanning %d or more are an amount", LC_CATEGORY_SPAN);
    CHECK(strcmp(s->default_color, "importance") == 0, "colour: %s", s->default_color);
    lc_scene_destroy(s);

    s = labelled(0, 1, label_only, halves);
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    CHECK(!s->attributes[0].categorical && strcmp(s->default_importance, "label") == 0, "halves are an amount");
    lc_scene_destroy(s);

    /* Lines: a label the loader picked gives way to the derived curvature;
     * the kinds 0 and 2 (span 2) repeat over 12 vertices (LC_CATEGORY_REPEATS
     * x 3), not over 4. */
    float pos[36];
    for (int i = 0; i < 12; i++)
        pos[3 * i] = (float)i, pos[3 * i + 1] = (float)(i % 3), pos[3 * i + 2] = (float)(i / 4);
    for (int pass = 0; pass < 2; pass++) {
        const uint32_t n = pass == 0 ? 12 : 4;
        const uint32_t lens[] = {n};
        s = make_lines(1, lens, pos);
        float *v = floats(n, 0);
        for (uint32_t i = 1; i < n; i += 2)
            v[i] = 2;
        lc_scene_add_attribute(s, "tract", v, NULL);
        snprintf(s->default_importance, sizeof s->default_importance, "tract");
        CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize lines: %s", err.msg);
        if (pass == 0) {
            CHECK(strcmp(s->default_importance, "curvature") == 0, "lines: %s", s->default_importance);
            CHECK(strcmp(s->default_color, "tract") == 0, "lines colour: %s", s->default_color);
            CHECK(lc_attribute_categorical(&s->attributes[0], s->vertex_count), "the public check agrees");
        } else {
            CHECK(!s->attributes[0].categorical && strcmp(s->default_importance, "tract") == 0,
                  "two kinds over 4 vertices do not repeat enough to be a label: %s", s->default_importance);
        }
        lc_scene_destroy(s);
    }
}

int main(void)
{
    test_smaller_matters();
    test_class_labels();
    test_basics();
    test_validation();
    test_straight_line();
    test_circle();
    test_sphere();
    test_plane_boundary();
    test_percentiles_and_budget();
    return lc_test_finish();
}
