/* Vector fields (render/field, render/io/vtk_field_read.c): the case table
 * tests/data/fields/cases.txt, trilinear sampling against the formulas the
 * files were written from, uniform = rectilinear, the demo fields against
 * their formulas, truncated inputs and the field-source opener; the curl
 * (vorticity) of the ABC flow, a Beltrami flow whose curl is the velocity
 * itself, analytic and sampled on a grid, and as the vorticity attribute of a
 * streamline set traced in it. */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "field.h"
#include "field_demo.h"
#include "lc_test.h"
#include "vtk_field.h"

#define DATA LUCENT_TEST_DATA "/fields/"

static char *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *b = malloc((size_t)n + 1);
    if (b && fread(b, 1, (size_t)n, f) != (size_t)n) {
        free(b);
        b = NULL;
    }
    fclose(f);
    *size = (size_t)n;
    return b;
}

/* The formulas gen_fields.py wrote the valid files from. */
static void formula_of(const char *file, const double p[3], double v[3])
{
    if (strstr(file, "uniform")) {
        v[0] = p[0], v[1] = p[1], v[2] = p[2];
    } else {
        v[0] = 2 * p[0] - p[1], v[1] = p[2] + 1, v[2] = 3.0;
    }
}

static uint64_t rng_state = 12345;
static double uniform01(void)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

static void check_valid(const char *file, const lc_field *f, char *save)
{
    char *kv;
    while ((kv = strtok_r(NULL, " ", &save))) {
        char *eq = strchr(kv, '=');
        if (!eq)
            continue;
        *eq++ = '\0';
        if (strcmp(kv, "kind") == 0) {
            CHECK(strcmp(lc_field_kind_name(f->kind), eq) == 0, "%s: kind %s, expected %s", file,
                  lc_field_kind_name(f->kind), eq);
        } else if (strcmp(kv, "dims") == 0) {
            char got[64];
            snprintf(got, sizeof got, "%ux%ux%u", f->dims[0], f->dims[1], f->dims[2]);
            CHECK(strcmp(got, eq) == 0, "%s: dims %s, expected %s", file, got, eq);
        } else if (strcmp(kv, "bounds") == 0) {
            double b[6];
            CHECK(sscanf(eq, "%lf,%lf,%lf,%lf,%lf,%lf", &b[0], &b[1], &b[2], &b[3], &b[4], &b[5]) == 6, "%s: bounds",
                  file);
            for (int i = 0; i < 6; i++)
                CHECK_NEAR(f->bounds[i], b[i], 1e-12, file);
        } else if (strcmp(kv, "mag") == 0) {
            double lo, hi;
            CHECK(sscanf(eq, "%lf,%lf", &lo, &hi) == 2, "%s: mag", file);
            CHECK_NEAR(f->mag_min, lo, 1e-6, file);
            CHECK_NEAR(f->mag_max, hi, 1e-6, file);
        } else if (strcmp(kv, "vectors") == 0) {
            CHECK(strcmp(f->vectors_name, eq) == 0, "%s: vectors '%s', expected %s", file, f->vectors_name, eq);
        }
    }
    /* Trilinear interpolation reproduces a linear field exactly (up to floats). */
    double worst = 0;
    for (int i = 0; i < 2000; i++) {
        double p[3], v[3], w[3];
        for (int a = 0; a < 3; a++)
            p[a] = f->bounds[a] + (f->bounds[a + 3] - f->bounds[a]) * uniform01();
        CHECK(lc_field_sample(f, p, 0.0, v) == 1, "%s: point inside reported outside", file);
        formula_of(file, p, w);
        for (int a = 0; a < 3; a++)
            worst = fmax(worst, fabs(v[a] - w[a]));
    }
    CHECK(worst < 1e-5, "%s: trilinear sample off by %g", file, worst);
    double out[3] = {f->bounds[3] + 1e-9, f->bounds[1], f->bounds[2]}, v[3] = {1, 1, 1};
    CHECK(lc_field_sample(f, out, 0.0, v) == 0 && v[0] == 0 && v[1] == 0 && v[2] == 0,
          "%s: a point outside samples (%g %g %g)", file, v[0], v[1], v[2]);
}

static void test_cases(void)
{
    FILE *t = fopen(DATA "cases.txt", "r");
    CHECK(t != NULL, "cannot open cases.txt: %s", strerror(errno));
    if (!t)
        return;
    char line[1024];
    int cases = 0;
    while (fgets(line, sizeof line, t)) {
        line[strcspn(line, "\r\n")] = '\0';
        if (!line[0] || line[0] == '#')
            continue;
        char *msg = strstr(line, " msg=");
        if (msg) {
            *msg = '\0';
            msg += 5;
        }
        char *save = NULL, *file = strtok_r(line, " ", &save), path[512];
        snprintf(path, sizeof path, DATA "%s", file);
        cases++;
        lc_field *f = NULL, *m = NULL;
        lc_error err = {0}, merr = {0};
        int rc = lc_load_vtk_field(path, &f, &err);
        size_t size = 0;
        char *bytes = read_all(path, &size);
        int mrc = bytes ? lc_load_vtk_field_memory(bytes, size, strrchr(file, '/') + 1, &m, &merr) : -99;
        CHECK(mrc == rc, "%s: memory reader rc %d vs %d", file, mrc, rc);
        if (msg) {
            char *status = strstr(save ? save : "", "error=");
            CHECK(rc != 0 && f == NULL && m == NULL, "%s: loaded, expected an error", file);
            CHECK(status && strcmp(lc_status_name(rc), status + 6) == 0, "%s: status %s (%s)", file, lc_status_name(rc),
                  err.msg);
            CHECK(strstr(err.msg, msg) != NULL, "%s: message '%s' lacks '%s'", file, err.msg, msg);
            CHECK(strcmp(err.msg, merr.msg) == 0, "%s: memory reader says '%s'", file, merr.msg);
            CHECK(!lc_field_is_source(path) || rc != LC_ERR_UNSUPPORTED, "%s: a polydata file counts as a field", file);
        } else {
            CHECK(rc == 0 && f, "%s: %s", file, err.msg);
            CHECK(lc_field_is_source(path), "%s: not recognized as a field source", file);
            if (f)
                check_valid(file, f, save);
            /* Every shorter prefix of a valid file is an error, never a crash or a field. */
            for (size_t cut = 0; bytes && cut + 1 < size; cut += 1 + size / 97) {
                lc_field *g = NULL;
                lc_error gerr = {0};
                int grc = lc_load_vtk_field_memory(bytes, cut, "cut.vtk", &g, &gerr);
                CHECK(grc != 0 && g == NULL && gerr.msg[0], "%s cut at %zu: rc %d", file, cut, grc);
                lc_field_destroy(g);
            }
            /* Each byte replaced by a few values: an error with a message or a field, never a crash
             * (run under ASan to see reads past the input). */
            char *copy = bytes ? malloc(size) : NULL;
            static const unsigned char subst[] = {0, '\n', ' ', '9', 'e', 0x7f, 0xff};
            for (size_t at = 0; copy && at < size; at++)
                for (size_t k = 0; k < sizeof subst; k++) {
                    memcpy(copy, bytes, size);
                    copy[at] = (char)subst[k];
                    lc_field *g = NULL;
                    lc_error gerr = {0};
                    int grc = lc_load_vtk_field_memory(copy, size, "mutant.vtk", &g, &gerr);
                    CHECK(grc == 0 ? g != NULL : (g == NULL && gerr.msg[0] != 0), "%s byte %zu = %d: rc %d", file, at,
                          subst[k], grc);
                    lc_field_destroy(g);
                }
            free(copy);
        }
        free(bytes);
        lc_field_destroy(f);
        lc_field_destroy(m);
    }
    fclose(t);
    CHECK(cases >= 15, "only %d field cases", cases);
}

/* A uniform grid and the same grid declared rectilinear sample alike. */
static void test_uniform_equals_rectilinear(void)
{
    uint32_t dims[3] = {5, 4, 3};
    lc_field *f[2] = {NULL, NULL};
    for (int k = 0; k < 2; k++) {
        double *c[3];
        for (int a = 0; a < 3; a++) {
            c[a] = malloc(dims[a] * sizeof *c[a]);
            for (uint32_t i = 0; i < dims[a]; i++)
                c[a][i] = -1.0 + 0.25 * (a + 1) * i;
        }
        size_t n = (size_t)dims[0] * dims[1] * dims[2];
        float *v = malloc(3 * n * sizeof *v);
        for (size_t i = 0; i < 3 * n; i++)
            v[i] = (float)sin(0.37 * (double)i); /* not linear: exercises the weights */
        lc_error err = {0};
        CHECK(lc_field_create_grid("g", k ? LC_FIELD_RECTILINEAR : LC_FIELD_UNIFORM, dims, c, v, &f[k], &err) == 0,
              "grid: %s", err.msg);
    }
    if (!f[0] || !f[1])
        return;
    double worst = 0;
    for (int i = 0; i < 1000; i++) {
        double p[3], a[3], b[3];
        for (int d = 0; d < 3; d++)
            p[d] = f[0]->bounds[d] + (f[0]->bounds[d + 3] - f[0]->bounds[d]) * uniform01();
        lc_field_sample(f[0], p, 0, a);
        lc_field_sample(f[1], p, 0, b);
        for (int d = 0; d < 3; d++)
            worst = fmax(worst, fabs(a[d] - b[d]));
    }
    CHECK(worst < 1e-12, "uniform and rectilinear differ by %g", worst);
    /* At a node the sample is the node's vector. */
    double p[3] = {f[0]->coords[0][2], f[0]->coords[1][1], f[0]->coords[2][2]}, v[3];
    lc_field_sample(f[0], p, 0, v);
    const float *q = f[0]->vectors + 3 * (2 + 1 * 5 + 2 * 20);
    CHECK(fabs(v[0] - q[0]) < 1e-6 && fabs(v[1] - q[1]) < 1e-6 && fabs(v[2] - q[2]) < 1e-6, "node sample");
    /* The midpoint of a cell edge averages its two nodes. */
    p[0] = 0.5 * (f[0]->coords[0][2] + f[0]->coords[0][3]);
    lc_field_sample(f[0], p, 0, v);
    CHECK_NEAR(v[1], 0.5 * (q[1] + q[4]), 1e-6, "edge midpoint");
    lc_field_destroy(f[0]);
    lc_field_destroy(f[1]);
}

static void test_bad_grids(void)
{
    uint32_t dims[3] = {3, 2, 2};
    double *c[3];
    for (int a = 0; a < 3; a++) {
        c[a] = calloc(3, sizeof *c[a]);
        c[a][1] = 1, c[a][2] = 2;
    }
    c[0][2] = 0.5; /* decreasing */
    float *v = calloc(36, sizeof *v);
    lc_field *f = NULL;
    lc_error err = {0};
    CHECK(lc_field_create_grid("bad", LC_FIELD_RECTILINEAR, dims, c, v, &f, &err) == LC_ERR_INVALID && !f &&
              strstr(err.msg, "bad: x coordinate 2 (0.5) is not finite or not increasing"),
          "decreasing axis: %s", err.msg);
}

static void test_demos(void)
{
    int n = 0;
    for (const char *const *name = lc_field_demo_names(); *name; name++, n++) {
        lc_field *f = NULL;
        lc_error err = {0};
        CHECK(lc_field_demo_create(*name, &f, &err) == 0 && f, "%s: %s", *name, err.msg);
        CHECK(lc_field_demo_description(*name) != NULL, "%s: no description", *name);
        char spec[80];
        snprintf(spec, sizeof spec, "demo:%s", *name);
        CHECK(lc_field_is_source(spec), "%s is not a field source", spec);
        if (!f)
            continue;
        CHECK(strcmp(f->name, spec) == 0, "name %s", f->name);
        CHECK(f->mag_max > f->mag_min && f->mag_min >= 0, "%s: magnitude range [%g, %g]", *name, f->mag_min,
              f->mag_max);
        lc_field_destroy(f);
    }
    CHECK(n == 4, "%d demo fields", n);
    CHECK(!lc_field_is_source("demo:tornado"), "the streamline demo is not a field");
    lc_field *f = NULL;
    lc_error err = {0};
    CHECK(lc_field_open("demo:nope", &f, &err) == LC_ERR_NOT_FOUND && strstr(err.msg, "demo:nope: unknown demo field"),
          "unknown demo: %s", err.msg);

    /* The ABC flow at a point, by hand; the shear flow's rate; the double gyre changes with t. */
    CHECK(lc_field_open("demo:abc-flow", &f, &err) == 0, "%s", err.msg);
    if (f) {
        double p[3] = {1.0, 2.0, 0.5}, v[3];
        CHECK(lc_field_sample(f, p, 0, v) == 1, "abc inside");
        CHECK_NEAR(v[0], sqrt(3.0) * sin(0.5) + cos(2.0), 1e-12, "abc u");
        CHECK_NEAR(v[1], sqrt(2.0) * sin(1.0) + sqrt(3.0) * cos(0.5), 1e-12, "abc v");
        CHECK_NEAR(v[2], sin(2.0) + sqrt(2.0) * cos(1.0), 1e-12, "abc w");
        /* The lattice's range holds what random points sample, within the lattice's resolution. */
        double lo = INFINITY, hi = 0;
        for (int i = 0; i < 20000; i++) {
            double q[3], w[3];
            for (int a = 0; a < 3; a++)
                q[a] = 2 * M_PI * uniform01();
            lc_field_sample(f, q, 0, w);
            double m = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
            lo = fmin(lo, m), hi = fmax(hi, m);
        }
        CHECK(f->mag_min <= lo + 0.05 && f->mag_max >= hi - 0.05 && f->mag_max <= 1 + sqrt(2.0) + sqrt(3.0),
              "abc |v| range [%g, %g], sampled [%g, %g]", f->mag_min, f->mag_max, lo, hi);
        lc_field_destroy(f);
    }
    CHECK(lc_field_open("demo:shear-flow", &f, &err) == 0, "%s", err.msg);
    if (f) {
        double p[3] = {0.2, 0.6, -0.3}, v[3];
        lc_field_sample(f, p, 0, v);
        CHECK_NEAR(v[0], 1 + LC_FIELD_SHEAR_RATE * 0.6, 1e-15, "shear u");
        CHECK(v[1] == 0 && v[2] == 0 && !f->time_dependent, "shear is planar and steady");
        lc_field_destroy(f);
    }
    CHECK(lc_field_open("demo:double-gyre-flow", &f, &err) == 0, "%s", err.msg);
    if (f) {
        double p[3] = {0.3, 0.4, 0.5}, a[3], b[3];
        lc_field_sample(f, p, 0.0, a);
        lc_field_sample(f, p, 2.5, b);
        CHECK(f->time_dependent && f->t1 > f->t0, "double gyre is unsteady");
        CHECK(fabs(a[0] - b[0]) > 1e-3, "double gyre at t = 0 and 2.5: %g vs %g", a[0], b[0]);
        /* At t = 0 the gyre is steady's: u = -pi A sin(pi x) cos(pi y). */
        CHECK_NEAR(a[0], -M_PI * 0.1 * sin(M_PI * 0.3) * cos(M_PI * 0.4), 1e-12, "double gyre u at t = 0");
        lc_field_destroy(f);
    }
}

/* curl v = v for the ABC flow: by central differences (analytic) and over a
 * 97^3 grid of it (trilinear, half-cell steps: the grid's own error). */
static void test_curl(void)
{
    lc_field *f = NULL;
    lc_error err = {0};
    CHECK(lc_field_demo_create("abc-flow", &f, &err) == 0, "demo:abc-flow: %s", err.msg);
    if (!f)
        return;
    double worst = 0, worst_grid = 0;
    enum { N = 97 };
    uint32_t dims[3] = {N, N, N};
    double *c[3];
    float *v = malloc(sizeof(float) * 3 * N * N * N);
    for (int a = 0; a < 3; a++) {
        c[a] = malloc(sizeof(double) * N);
        for (int i = 0; i < N; i++)
            c[a][i] = f->bounds[a] + (f->bounds[a + 3] - f->bounds[a]) * i / (N - 1);
    }
    for (int k = 0; k < N; k++)
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                double p[3] = {c[0][i], c[1][j], c[2][k]}, w[3];
                lc_field_abc(p, 0, w);
                for (int a = 0; a < 3; a++)
                    v[3 * ((size_t)i + N * ((size_t)j + (size_t)N * k)) + a] = (float)w[a];
            }
    lc_field *g = NULL;
    CHECK(lc_field_create_grid("abc-grid", LC_FIELD_UNIFORM, dims, c, v, &g, &err) == 0, "grid: %s", err.msg);
    for (int s = 0; s < 200 && g; s++) {
        double p[3], w[3], want[3], wg[3];
        for (int a = 0; a < 3; a++) /* inside, away from the faces (one-sided there) */
            p[a] = f->bounds[a] +
                   (f->bounds[a + 3] - f->bounds[a]) * (0.05 + 0.9 * ((s * (a + 3) * 7919) % 1000) / 1000.0);
        lc_field_abc(p, 0, want);
        CHECK(lc_field_curl(f, p, 0, w) == 1 && lc_field_curl(g, p, 0, wg) == 1, "curl inside the domain");
        for (int a = 0; a < 3; a++) {
            worst = fmax(worst, fabs(w[a] - want[a]));
            worst_grid = fmax(worst_grid, fabs(wg[a] - want[a]));
        }
    }
    printf("ABC flow: curl v - v at most %.2g analytic, %.2g on a %d^3 grid\n", worst, worst_grid, N);
    CHECK(worst < 1e-4, "analytic curl off by %g", worst);
    CHECK(worst_grid < 0.02, "gridded curl off by %g", worst_grid);
    double out[3] = {f->bounds[3] + 1, 0, 0}, w[3];
    CHECK(lc_field_curl(f, out, 0, w) == 0 && w[0] == 0, "outside: 0");
    lc_field_destroy(g);
    lc_field_destroy(f);
}

int main(void)
{
    test_curl();
    test_cases();
    test_uniform_equals_rectilinear();
    test_bad_grids();
    test_demos();
    return lc_test_finish();
}
