/* Streamline sets (render/field/seeding.c, trace.c's directions): a two-way
 * curve through a seed is its backward half reversed joined to its forward
 * half, vertex for vertex; a negative step traces backward; a rake of n seeds
 * gives n curves starting at the evenly spaced seeds; box seeds follow the
 * Halton sequence; density-driven seeds obey the separation rule, checked
 * against a brute-force replay of the candidates; bad settings name their field;
 * a streamline set of the ABC flow carries the vorticity |curl v|, which that
 * Beltrami flow makes equal to its speed. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "field.h"
#include "lc_test.h"
#include "scene.h"
#include "seeding.h"
#include "streamlines.h"
#include "trace.h"

static void rotation_flow(const double p[3], double t, double v[3])
{
    (void)t;
    v[0] = -p[1], v[1] = p[0], v[2] = 0.25;
}

static void uniform_x(const double p[3], double t, double v[3])
{
    (void)p, (void)t;
    v[0] = 1, v[1] = 0, v[2] = 0;
}

static int same_vertex(const lc_trace_curve *a, uint32_t i, const lc_trace_curve *b, uint32_t j)
{
    for (int k = 0; k < 3; k++)
        if (a->xyz[3 * i + k] != b->xyz[3 * j + k] || a->normal[3 * i + k] != b->normal[3 * j + k])
            return 0;
    return a->time[i] == b->time[j] && a->speed[i] == b->speed[j];
}

static void test_two_way(void)
{
    lc_field *f = NULL;
    lc_error err = {0};
    const double box[6] = {-2, -2, -2, 2, 2, 2};
    if (lc_field_create_analytic("rotation", rotation_flow, box, 0, 0, 0, &f, &err) != 0) {
        CHECK(0, "field: %s", err.msg);
        return;
    }
    const double seed[3] = {1, 0, 0};
    lc_trace_curve fwd, bwd, both, neg;
    lc_trace_desc d = {.step = 0.01, .max_length = 3};
    CHECK(lc_trace_points(f, seed, 1, &d, 1, &fwd, &err) == 0, "forward: %s", err.msg);
    d.direction = LC_TRACE_BACKWARD;
    CHECK(lc_trace_points(f, seed, 1, &d, 1, &bwd, &err) == 0, "backward: %s", err.msg);
    d.direction = LC_TRACE_BOTH;
    CHECK(lc_trace_points(f, seed, 1, &d, 1, &both, &err) == 0, "both: %s", err.msg);
    lc_trace_desc dn = {.step = -0.01, .max_length = 3};
    CHECK(lc_trace_points(f, seed, 1, &dn, 1, &neg, &err) == 0, "negative step: %s", err.msg);

    CHECK(fwd.n > 100 && bwd.n > 100, "halves of %u and %u vertices", fwd.n, bwd.n);
    CHECK(both.n == fwd.n + bwd.n - 1, "two-way %u vertices = %u + %u - 1", both.n, fwd.n, bwd.n);
    int joined = both.n == fwd.n + bwd.n - 1;
    for (uint32_t i = 0; joined && i < bwd.n; i++)
        joined &= same_vertex(&both, i, &bwd, i);
    for (uint32_t i = 1; joined && i < fwd.n; i++)
        joined &= same_vertex(&both, bwd.n - 1 + i, &fwd, i);
    CHECK(joined, "the two-way curve is the backward half and the forward half joined, vertex for vertex");
    /* the backward half ends at the seed and starts in the past; z rises with time (v_z = 0.25) */
    CHECK(bwd.xyz[3 * (bwd.n - 1)] == 1.0f && bwd.xyz[3 * (bwd.n - 1) + 1] == 0.0f && bwd.time[bwd.n - 1] == 0.0f,
          "the backward half ends at the seed");
    CHECK(bwd.time[0] < 0 && bwd.xyz[2] < 0 && fwd.xyz[3 * (fwd.n - 1) + 2] > 0, "backward in the past: t %g, z %g",
          bwd.time[0], bwd.xyz[2]);
    /* closed form: x(t) = (cos t, sin t, t / 4) from (1, 0, 0) */
    double t = bwd.time[0];
    CHECK(fabs(bwd.xyz[0] - cos(t)) < 1e-5 && fabs(bwd.xyz[1] - sin(t)) < 1e-5 && fabs(bwd.xyz[2] - t / 4) < 1e-5,
          "backward RK4 at t = %g: (%g %g %g)", t, bwd.xyz[0], bwd.xyz[1], bwd.xyz[2]);
    int same = neg.n == bwd.n;
    for (uint32_t i = 0; same && i < neg.n; i++)
        same &= same_vertex(&neg, i, &bwd, i);
    CHECK(same, "a negative step traces the backward curve (%u vs %u vertices)", neg.n, bwd.n);
    lc_trace_curves_free(&fwd, 1);
    lc_trace_curves_free(&bwd, 1);
    lc_trace_curves_free(&both, 1);
    lc_trace_curves_free(&neg, 1);
    lc_field_destroy(f);
}

static void test_rake_and_box(void)
{
    lc_field *f = NULL;
    lc_error err = {0};
    const double box[6] = {0, 0, 0, 1, 1, 1};
    if (lc_field_create_analytic("uniform", uniform_x, box, 0, 0, 0, &f, &err) != 0) {
        CHECK(0, "field: %s", err.msg);
        return;
    }
    enum { N = 7 };
    lc_seeding_desc d = {.kind = LC_SEEDING_RAKE, .count = N, .from = {0.1, 0.2, 0.3}, .to = {0.1, 0.8, 0.9}};
    d.trace.step = 0.01;
    lc_trace_curve *c = NULL;
    double *seeds = NULL;
    uint32_t n = 0;
    CHECK(lc_seeding_trace(f, &d, 2, &c, &n, &seeds, NULL, &err) == 0, "rake: %s", err.msg);
    CHECK(n == N, "a rake of %d seeds gives %u curves", N, n);
    for (uint32_t i = 0; c && i < n; i++) {
        double want[3] = {0.1, 0.2 + 0.6 * i / (N - 1), 0.3 + 0.6 * i / (N - 1)};
        CHECK(fabs(c[i].xyz[0] - want[0]) < 1e-6 && fabs(c[i].xyz[1] - want[1]) < 1e-6 &&
                  fabs(c[i].xyz[2] - want[2]) < 1e-6,
              "curve %u starts at (%g %g %g), want (%g %g %g)", i, c[i].xyz[0], c[i].xyz[1], c[i].xyz[2], want[0],
              want[1], want[2]);
        /* uniform flow along x: the curve runs from the seed to the face x = 1 */
        CHECK(c[i].n > 2 && fabs(c[i].xyz[3 * (c[i].n - 1) + 1] - want[1]) < 1e-6 && c[i].xyz[3 * (c[i].n - 1)] > 0.98f,
              "curve %u runs along x to the face", i);
    }
    lc_trace_curves_free(c, n);
    free(c), free(seeds);

    /* box seeds: the Halton points (1/2, 1/3, 1/5), (1/4, 2/3, 2/5), (3/4, 1/9, 3/5) scaled into the box */
    lc_seeding_desc b = {.kind = LC_SEEDING_BOX, .count = 3, .from = {0, 0, 0}, .to = {1, 0.5, 1}};
    b.trace.step = 0.01;
    CHECK(lc_seeding_trace(f, &b, 1, &c, &n, &seeds, NULL, &err) == 0 && n == 3, "box: %s", err.msg);
    const double want[3][3] = {{0.5, 0.5 / 3, 0.2}, {0.25, 1.0 / 3, 0.4}, {0.75, 0.5 / 9, 0.6}};
    for (int i = 0; seeds && i < 3; i++)
        CHECK(fabs(seeds[3 * i] - want[i][0]) < 1e-12 && fabs(seeds[3 * i + 1] - want[i][1]) < 1e-12 &&
                  fabs(seeds[3 * i + 2] - want[i][2]) < 1e-12,
              "box seed %d (%g %g %g)", i, seeds[3 * i], seeds[3 * i + 1], seeds[3 * i + 2]);
    lc_trace_curves_free(c, n);
    free(c), free(seeds);

    /* refusals name the setting */
    lc_seeding_desc bad = {.kind = LC_SEEDING_BOX, .count = 4, .from = {0, 0, 0}, .to = {1, 0, 1}};
    CHECK(lc_seeding_trace(f, &bad, 1, &c, &n, NULL, NULL, &err) != 0 && strstr(err.msg, "seeding.box"),
          "a flat box is refused: %s", err.msg);
    lc_seeding_desc many = {.kind = LC_SEEDING_RAKE, .count = LC_SEEDING_MAX_LINES + 1, .to = {1, 1, 1}};
    CHECK(lc_seeding_trace(f, &many, 1, &c, &n, NULL, NULL, &err) != 0 && strstr(err.msg, "seeding.count"),
          "too many curves are refused: %s", err.msg);
    lc_seeding_desc none = {.kind = LC_SEEDING_POINTS};
    CHECK(lc_seeding_trace(f, &none, 1, &c, &n, NULL, NULL, &err) != 0 && strstr(err.msg, "seeding.points"),
          "no points are refused: %s", err.msg);
    lc_field_destroy(f);
}

/* The rule replayed by brute force: candidate k (a Halton point) is kept iff
 * no vertex of the curves kept before it lies closer than d_sep. */
static void test_density_rule(void)
{
    lc_field *f = NULL;
    lc_error err = {0};
    const double box[6] = {0, 0, 0, 1, 1, 1};
    if (lc_field_create_analytic("rotation", rotation_flow, box, 0, 0, 0, &f, &err) != 0) {
        CHECK(0, "field: %s", err.msg);
        return;
    }
    lc_seeding_desc d = {.kind = LC_SEEDING_DENSITY, .count = 40, .separation = 0.15};
    d.trace.step = 0.02, d.trace.direction = LC_TRACE_BOTH;
    lc_trace_curve *c = NULL;
    double *seeds = NULL;
    uint32_t n = 0;
    lc_seeding_stats st = {0};
    if (lc_seeding_trace(f, &d, 1, &c, &n, &seeds, &st, &err) != 0) {
        CHECK(0, "density: %s", err.msg);
        return;
    }
    CHECK(n >= 5 && st.separation == 0.15, "%u curves kept of %u candidates", n, st.candidates);
    CHECK(n < st.candidates, "some candidates were refused (%u of %u kept)", n, st.candidates);
    uint32_t kept = 0;
    int agree = 1;
    for (uint32_t k = 0; k < st.candidates && agree; k++) {
        double p[3];
        lc_seeding_halton(box, box + 3, k, p);
        double nearest = INFINITY;
        for (uint32_t l = 0; l < kept; l++)
            for (uint32_t i = 0; i < c[l].n; i++) {
                double dx = p[0] - c[l].xyz[3 * i], dy = p[1] - c[l].xyz[3 * i + 1], dz = p[2] - c[l].xyz[3 * i + 2];
                double d2 = dx * dx + dy * dy + dz * dz;
                nearest = d2 < nearest ? d2 : nearest;
            }
        int free_here = !(nearest < 0.15 * 0.15);
        int taken = kept < n && seeds[3 * kept] == p[0] && seeds[3 * kept + 1] == p[1] && seeds[3 * kept + 2] == p[2];
        agree = free_here == taken;
        if (!agree)
            CHECK(0, "candidate %u (%g %g %g): nearest vertex %g, taken %d", k, p[0], p[1], p[2], sqrt(nearest), taken);
        kept += (uint32_t)taken;
    }
    CHECK(agree && kept == n, "the %u kept seeds are exactly the free candidates in order", kept);
    /* the two-way curve passes through its seed */
    int through = 1;
    for (uint32_t l = 0; l < n; l++) {
        int hit = 0;
        for (uint32_t i = 0; i < c[l].n && !hit; i++)
            hit = c[l].time[i] == 0.0f && fabs(c[l].xyz[3 * i] - seeds[3 * l]) < 1e-6;
        through &= hit;
    }
    CHECK(through, "every kept curve passes through its seed at t = 0");
    lc_trace_curves_free(c, n);
    free(c), free(seeds);
    lc_field_destroy(f);
}

static void test_vorticity(void)
{
    lc_scene *s = NULL;
    lc_error err = {0};
    int rc = lc_streamlines_load("streamlines:demo:abc-flow?seeding=rake&seeds=1,1,1;5,5,5&count=5", 1, &s, &err);
    CHECK(rc == 0 && s, "ABC streamline set: %s", err.msg);
    if (!s)
        return;
    int w = lc_scene_find_attribute(s, "vorticity"), v = lc_scene_find_attribute(s, "speed");
    CHECK(w >= 0 && v >= 0, "vorticity and speed attributes (%d, %d)", w, v);
    double worst = 0;
    for (uint32_t i = 0; w >= 0 && v >= 0 && i < s->vertex_count; i++) {
        double a = s->attributes[w].values[i], b = s->attributes[v].values[i];
        worst = fmax(worst, fabs(a - b) / fmax(b, 1e-6));
    }
    printf("ABC streamlines: %u vertices, vorticity against speed at most %.2g relative\n", s->vertex_count, worst);
    CHECK(worst < 1e-3, "vorticity off the speed by %g", worst);
    lc_scene_destroy(s);
}

int main(void)
{
    test_vorticity();
    test_two_way();
    test_rake_and_box();
    test_density_rule();
    return lc_test_finish();
}
