/* Particle tracing (render/field/trace.c): the progressive seed order, seed
 * validation naming the field, RK4 against closed-form path lines, ghost
 * normals against the analytic normals of known stream surfaces (within 1
 * degree), length and time limits, and threads giving the same curves. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "field.h"
#include "field_demo.h"
#include "lc_test.h"
#include "trace.h"

static lc_seed make_seed(double x0, double y0, double z0, double x1, double y1, double z1)
{
    lc_seed s;
    memset(&s, 0, sizeof s);
    s.count = 2;
    double p[2][3] = {{x0, y0, z0}, {x1, y1, z1}};
    memcpy(s.points, p, sizeof p);
    return s;
}

static void test_seed_order(void)
{
    const double want[] = {0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875};
    for (int k = 0; k < 7; k++)
        CHECK_NEAR(lc_seed_param((uint64_t)k), want[k], 0, "radical inverse");
    /* Any prefix of 2^m - 1 particles is the evenly spaced set j / 2^m. */
    int seen[64] = {0};
    for (int k = 0; k < 63; k++) {
        double u = lc_seed_param((uint64_t)k) * 64;
        CHECK(u == floor(u) && u >= 1 && u <= 63, "u*64 = %g", u);
        seen[(int)u]++;
    }
    int once = 1;
    for (int j = 1; j < 64; j++)
        once &= seen[j] == 1;
    CHECK(once, "the first 63 particles fill 1/64 .. 63/64 once each");

    lc_seed s;
    memset(&s, 0, sizeof s);
    s.count = 3;
    double pts[3][3] = {{0, 0, 0}, {1, 0, 0}, {1, 3, 0}};
    memcpy(s.points, pts, sizeof pts);
    lc_error err = {0};
    CHECK(lc_seed_check(&s, NULL, &err) == 0 && s.length == 4, "polyline length %g", s.length);
    double p[3], t[3];
    lc_seed_at(&s, 0.5, p, t); /* arc length 2: on the second segment */
    CHECK(fabs(p[0] - 1) < 1e-12 && fabs(p[1] - 1) < 1e-12 && t[1] == 1, "seed point (%g %g %g)", p[0], p[1], p[2]);
}

static void test_seed_errors(void)
{
    lc_field *f = NULL;
    lc_error err = {0};
    lc_field_demo_create("shear-flow", &f, &err);
    struct {
        lc_seed seed;
        const char *msg;
    } cases[] = {
        {make_seed(0, 0, 0, 0, 0, 0), "seed.points: point 1 repeats point 0"},
        {make_seed(0, NAN, 0, 0, 1, 0), "seed.points: point 0 is not finite"},
        {make_seed(5, 0, 0, 0, 1, 0), "seed.points: point 0 (5, 0, 0) lies outside demo:shear-flow's domain"},
    };
    cases[0].seed.points[1][0] = 0; /* the same point twice */
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        memset(&err, 0, sizeof err);
        CHECK(lc_seed_check(&cases[i].seed, f, &err) == LC_ERR_INVALID && strcmp(err.field, "seed.points") == 0 &&
                  strstr(err.msg, cases[i].msg),
              "case %zu: '%s' (field '%s')", i, err.msg, err.field);
    }
    /* The command-line form. */
    lc_seed parsed;
    CHECK(lc_seed_parse("-0.5,0,0.25;0.5,0.5,0.25;0.5,-0.5,0", &parsed, f, &err) == 0 && parsed.count == 3 &&
              parsed.points[1][1] == 0.5 && parsed.points[2][2] == 0,
          "parse: %s", err.msg);
    const char *bad[][2] = {{"1,2;3,4,5", "seed.points: point 0: expected x,y,z numbers separated by ';' at '2;3,4,5'"},
                            {"0,0,0;x", "seed.points: point 1: expected x,y,z"},
                            {"0,0,0", "seed.points: 1 points (2 to 256)"},
                            {"", "seed.points: 0 points"}};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++)
        CHECK(lc_seed_parse(bad[i][0], &parsed, f, &err) == LC_ERR_INVALID && strstr(err.msg, bad[i][1]),
              "parse '%s': %s", bad[i][0], err.msg);
    lc_seed one = make_seed(0, 0, 0, 0, 1, 0);
    one.count = 1;
    CHECK(lc_seed_check(&one, f, &err) == LC_ERR_INVALID && strstr(err.msg, "seed.points: 1 points (2 to 256)"),
          "one point: %s", err.msg);
    lc_field_destroy(f);
}

static double angle_deg(const float n[3], const double want[3])
{
    double a = sqrt(want[0] * want[0] + want[1] * want[1] + want[2] * want[2]);
    double c = (n[0] * want[0] + n[1] * want[1] + n[2] * want[2]) / a; /* n is unit */
    return acos(fmin(1.0, fabs(c))) * 180.0 / M_PI;                    /* the surface's side is free */
}

/* v = (1, 0, y): from the seed x = z = 0, the particle at y0 follows
 * (t, y0, y0 t), so the stream surface is z = x y with normal (-y, -x, 1). */
static void saddle_flow(const double p[3], double t, double v[3])
{
    (void)t;
    v[0] = 1.0, v[1] = 0.0, v[2] = p[1];
}

static void rotation_flow(const double p[3], double t, double v[3])
{
    (void)t;
    v[0] = -p[1], v[1] = p[0], v[2] = 0.25;
}

static void test_shear(void)
{
    lc_field *f = NULL;
    lc_error err = {0};
    CHECK(lc_field_demo_create("shear-flow", &f, &err) == 0, "%s", err.msg);
    if (!f)
        return;
    /* A seed across y and z: the surface is the plane through the x axis and (0, 1, 1). */
    lc_seed s = make_seed(-0.95, -0.8, -0.8, -0.95, 0.8, 0.8);
    CHECK(lc_seed_check(&s, f, &err) == 0, "%s", err.msg);
    lc_trace_curve c[16];
    lc_trace_desc d = {.step = 0.01, .max_length = 1.5};
    CHECK(lc_trace_curves(f, &s, &d, 0, 16, 1, c, &err) == 0, "%s", err.msg);
    const double plane_n[3] = {0, -1, 1};
    double worst_angle = 0, worst_x = 0, worst_len = 0;
    for (int i = 0; i < 16; i++) {
        double y0 = c[i].xyz[1], x0 = c[i].xyz[0], len = 0;
        CHECK(c[i].n > 100, "curve %d has %u vertices", i, c[i].n);
        for (uint32_t k = 0; k < c[i].n; k++) {
            worst_angle = fmax(worst_angle, angle_deg(c[i].normal + 3 * k, plane_n));
            /* x(t) = x0 + (1 + y0 / 2) t exactly: RK4 is exact on a constant velocity. */
            double x = x0 + (1 + LC_FIELD_SHEAR_RATE * y0) * (c[i].time[k] - c[i].time[0]);
            worst_x = fmax(worst_x, fabs(c[i].xyz[3 * k] - x));
            if (k)
                len += fabs(c[i].xyz[3 * k] - c[i].xyz[3 * k - 3]);
        }
        worst_len = fmax(worst_len, len);
    }
    CHECK(worst_angle < 1.0, "shear: ghost normals off the plane's by up to %g degrees", worst_angle);
    CHECK(worst_x < 1e-5, "shear: positions off the closed form by %g", worst_x);
    CHECK(worst_len >= 1.5 - 1e-4 && worst_len < 1.5 + 0.02, "max_length 1.5: longest curve %g", worst_len);
    lc_trace_curves_free(c, 16);
    lc_field_destroy(f);
}

static void test_saddle_normals(void)
{
    const double box[6] = {-1, -1, -3, 2, 1, 3};
    lc_field *f = NULL;
    lc_error err = {0};
    CHECK(lc_field_create_analytic("saddle", saddle_flow, box, 0, 0, 0, &f, &err) == 0, "%s", err.msg);
    if (!f)
        return;
    lc_seed s = make_seed(0, -0.9, 0, 0, 0.9, 0);
    CHECK(lc_seed_check(&s, f, &err) == 0, "%s", err.msg);
    enum { N = 31 };
    lc_trace_curve c[N];
    CHECK(lc_trace_curves(f, &s, &(lc_trace_desc){.step = 0.005, .max_length = 3}, 0, N, 2, c, &err) == 0, "%s",
          err.msg);
    double worst = 0, worst_pos = 0;
    int resets = 0;
    for (int i = 0; i < N; i++) {
        resets += c[i].ghost_resets;
        for (uint32_t k = 0; k < c[i].n; k++) {
            const float *p = c[i].xyz + 3 * k;
            double want[3] = {-p[1], -p[0], 1};
            worst = fmax(worst, angle_deg(c[i].normal + 3 * k, want));
            worst_pos = fmax(worst_pos, fabs(p[2] - p[0] * p[1]));
        }
    }
    CHECK(worst < 1.0, "saddle z = xy: ghost normals off the analytic ones by up to %g degrees", worst);
    CHECK(worst_pos < 1e-5, "saddle: particles off the surface z = xy by %g", worst_pos);
    CHECK(resets > 0, "the ghosts drifted beyond delta and were reset (%d)", resets);
    lc_trace_curves_free(c, N);
    lc_field_destroy(f);
}

static void test_rk4_and_threads(void)
{
    const double box[6] = {-2, -2, -1, 2, 2, 10};
    lc_field *f = NULL;
    lc_error err = {0};
    CHECK(lc_field_create_analytic("rotation", rotation_flow, box, 0, 0, 0, &f, &err) == 0, "%s", err.msg);
    if (!f)
        return;
    lc_seed s = make_seed(0.5, 0, 0, 1.5, 0, 0);
    lc_seed_check(&s, f, &err);
    enum { N = 9 };
    lc_trace_curve a[N], b[N];
    lc_trace_desc d = {.step = 0.01, .max_time = 2 * M_PI, .max_length = 100};
    CHECK(lc_trace_curves(f, &s, &d, 3, N, 1, a, &err) == 0 && lc_trace_curves(f, &s, &d, 3, N, 4, b, &err) == 0, "%s",
          err.msg);
    double worst_r = 0;
    int same = 1;
    for (int i = 0; i < N; i++) {
        double r0 = hypot(a[i].xyz[0], a[i].xyz[1]);
        for (uint32_t k = 0; k < a[i].n; k++)
            worst_r = fmax(worst_r, fabs(hypot(a[i].xyz[3 * k], a[i].xyz[3 * k + 1]) - r0));
        /* After one period the particle is back above its seed. */
        uint32_t last = a[i].n - 1;
        CHECK(fabs(a[i].time[last] - 2 * M_PI) < 1e-5, "curve %d ends at t = %g", i, a[i].time[last]);
        CHECK(fabs(a[i].xyz[3 * last] - a[i].xyz[0]) < 1e-6 && fabs(a[i].xyz[3 * last + 1]) < 1e-6,
              "curve %d after one turn at (%g, %g)", i, a[i].xyz[3 * last], a[i].xyz[3 * last + 1]);
        same &= a[i].n == b[i].n && a[i].u == b[i].u && memcmp(a[i].xyz, b[i].xyz, 12 * (size_t)a[i].n) == 0 &&
                memcmp(a[i].normal, b[i].normal, 12 * (size_t)a[i].n) == 0;
        CHECK(a[i].u == lc_seed_param(3 + (uint64_t)i), "curve %d is particle %d", i, 3 + i);
    }
    CHECK(worst_r < 1e-6, "RK4 keeps the radius of a rotation to %g", worst_r);
    CHECK(same, "4 threads trace the same curves as 1");
    lc_trace_curves_free(a, N);
    lc_trace_curves_free(b, N);
    lc_field_destroy(f);
}

static void test_path_surface(void)
{
    lc_field *f = NULL;
    lc_error err = {0};
    CHECK(lc_field_demo_create("double-gyre-flow", &f, &err) == 0, "%s", err.msg);
    if (!f)
        return;
    lc_seed s = make_seed(0.2, 0.5, 0.1, 0.2, 0.5, 0.9);
    CHECK(lc_seed_check(&s, f, &err) == 0, "%s", err.msg);
    lc_trace_curve c[4];
    CHECK(lc_trace_curves(f, &s, NULL, 0, 4, 2, c, &err) == 0, "%s", err.msg);
    for (int i = 0; i < 4; i++) {
        uint32_t last = c[i].n - 1;
        CHECK(c[i].n > 10 && c[i].time[last] <= f->t1 + 1e-4 && c[i].time[last] > c[i].time[0],
              "path line %d: %u vertices, t from %g to %g", i, c[i].n, c[i].time[0], c[i].time[last]);
        /* w = 0: a path line keeps its z, and the path surface's normal lies in the xy plane. */
        double worst = 0;
        for (uint32_t k = 0; k < c[i].n; k++)
            worst = fmax(worst, fabs(c[i].xyz[3 * k + 2] - c[i].xyz[2]) + fabs(c[i].normal[3 * k + 2]));
        CHECK(worst < 1e-4, "path line %d leaves its plane or tilts its normal by %g", i, worst);
    }
    lc_trace_curves_free(c, 4);
    lc_field_destroy(f);
}

int main(void)
{
    test_seed_order();
    test_seed_errors();
    test_shear();
    test_saddle_normals();
    test_rk4_and_threads();
    test_path_surface();
    return lc_test_finish();
}
