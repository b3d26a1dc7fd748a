/* FOO's importance measures of line sets (render/scene/scene_measures.c) on
 * explicit lines, against their definitions: parallel straight evenly
 * sampled lines have direction variance 0, angular entropy 0 and linear
 * entropy 1; two perpendicular families in one cell 1 - 1/sqrt(2); a circle
 * sampled evenly turns alike at every vertex (angular entropy 1), a line bent
 * once turns at one vertex only (0); the boundary distance is 0 on the
 * bounds' faces and 1 at the centre of their thinnest direction. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lc_test.h"
#include "scene.h"

typedef struct {
    float xyz[4096 * 3];
    uint32_t offsets[512];
    uint32_t lines, n;
} builder;

static void vertex(builder *b, double x, double y, double z)
{
    b->xyz[3 * b->n] = (float)x, b->xyz[3 * b->n + 1] = (float)y, b->xyz[3 * b->n + 2] = (float)z;
    b->n++;
}

static void begin_line(builder *b) { b->offsets[b->lines++] = b->n; }

static lc_scene *finish(const builder *b)
{
    lc_error err = {0};
    lc_scene *s = lc_scene_create("measures", LC_PRIM_LINES);
    if (!s || lc_scene_alloc_vertices(s, b->n, 0, &err) != 0)
        return NULL;
    memcpy(s->positions, b->xyz, sizeof(float) * 3 * b->n);
    s->line_count = b->lines;
    s->line_offsets = malloc(sizeof(uint32_t) * (b->lines + 1));
    memcpy(s->line_offsets, b->offsets, sizeof(uint32_t) * b->lines);
    s->line_offsets[b->lines] = b->n;
    lc_elements_desc desc = {.line_budget = b->lines};
    if (lc_scene_finalize(s, &desc, &err) != 0) {
        fprintf(stderr, "finalize: %s\n", err.msg);
        lc_scene_destroy(s);
        return NULL;
    }
    return s;
}

static const float *values(const lc_scene *s, const char *name)
{
    int i = lc_scene_find_attribute(s, name);
    CHECK(i >= 0, "attribute %s", name);
    return i >= 0 ? s->attributes[i].values : NULL;
}

/* Largest |value - want| over the vertices [a, b). */
static double off(const float *v, uint32_t a, uint32_t b, double want)
{
    double worst = 0;
    for (uint32_t i = a; v && i < b; i++)
        worst = fmax(worst, fabs(v[i] - want));
    return v ? worst : INFINITY;
}

int main(void)
{
    static builder b;
    /* 1. Ten parallel straight lines along x, evenly sampled, in a box 4 x 2 x 2. */
    memset(&b, 0, sizeof b);
    for (int l = 0; l < 10; l++) {
        begin_line(&b);
        for (int k = 0; k <= 20; k++)
            vertex(&b, -2 + 0.2 * k, -1 + 2.0 * (l % 5) / 4, l < 5 ? -1 : 1);
    }
    lc_scene *s = finish(&b);
    CHECK(s != NULL, "parallel lines");
    if (s) {
        double dv = off(values(s, "direction_variance"), 0, s->vertex_count, 0);
        double ae = off(values(s, "angular_entropy"), 0, s->vertex_count, 0);
        double le = off(values(s, "linear_entropy"), 0, s->vertex_count, 1);
        printf("parallel lines: direction variance off 0 by %.2g, angular entropy off 0 by %.2g, linear entropy off "
               "1 by %.2g\n",
               dv, ae, le);
        CHECK(dv < 1e-4 && ae < 1e-6 && le < 1e-5, "parallel straight even lines: %g %g %g", dv, ae, le);
        /* boundary distance: the box's faces are y = +-1 and z = +-1 (thinnest half extent 1) */
        const float *bd = values(s, "boundary_distance");
        CHECK(bd && fabsf(bd[0]) < 1e-6, "a line's first vertex lies on a face: %g", bd ? bd[0] : -1);
        /* line 2 (y = 0, z = -1) lies on the face z = -1; its middle vertex 0 */
        CHECK(bd && fabsf(bd[2 * 21 + 10]) < 1e-6, "on the face z = -1: %g", bd ? bd[2 * 21 + 10] : -1);
        lc_scene_destroy(s);
    }
    /* 2. Two perpendicular families of equal weight, all in one cell (few vertices). */
    memset(&b, 0, sizeof b);
    for (int l = 0; l < 4; l++) {
        begin_line(&b);
        for (int k = 0; k <= 10; k++)
            vertex(&b, 0.1 * k, 0.25 + 0.15 * l, 0.3 * l);
        begin_line(&b);
        for (int k = 0; k <= 10; k++)
            vertex(&b, 0.25 + 0.15 * l, 0.1 * k, 0.3 * l + 0.1);
    }
    s = finish(&b);
    CHECK(s != NULL, "crossing lines");
    if (s) {
        double dv = off(values(s, "direction_variance"), 0, s->vertex_count, 1 - 1 / sqrt(2.0));
        printf("two perpendicular families: direction variance off 1 - 1/sqrt(2) by %.2g\n", dv);
        CHECK(dv < 1e-4, "perpendicular families: off by %g", dv);
        lc_scene_destroy(s);
    }
    /* 3. A circle of 64 even segments, a line bent once, and a straight line sampled unevenly;
     * a centre vertex for the boundary distance: a cube's middle. */
    memset(&b, 0, sizeof b);
    begin_line(&b);
    for (int k = 0; k <= 64; k++)
        vertex(&b, cos(2 * M_PI * k / 64), sin(2 * M_PI * k / 64), 0);
    begin_line(&b);
    vertex(&b, -1, -1, -1), vertex(&b, -0.5, -1, -1), vertex(&b, 0, -1, -1), vertex(&b, 0, -0.5, -1),
        vertex(&b, 0, 0, -1);
    uint32_t uneven = b.n;
    begin_line(&b);
    vertex(&b, -1, 1, 1), vertex(&b, -0.9, 1, 1), vertex(&b, 1, 1, 1);
    uint32_t centre = b.n;
    begin_line(&b);
    vertex(&b, 0, 0, 0), vertex(&b, 0.001, 0, 0);
    s = finish(&b);
    CHECK(s != NULL, "circle and bends");
    if (s) {
        const float *ae = values(s, "angular_entropy"), *le = values(s, "linear_entropy");
        const float *bd = values(s, "boundary_distance");
        printf("circle: angular entropy %.6f, linear %.6f; one bend: angular %.6f; uneven straight line: linear "
               "%.4f; the cube's centre: boundary distance %.4f\n",
               ae ? ae[0] : -1, le ? le[0] : -1, ae ? ae[65] : -1, le ? le[uneven] : -1, bd ? bd[centre] : -1);
        CHECK(ae && fabs(ae[0] - 1) < 1e-5 && le && fabs(le[0] - 1) < 1e-5, "the even circle: 1 and 1");
        CHECK(ae && fabs(ae[65]) < 1e-6, "one bend: angular entropy 0");
        /* segments 0.1 and 1.9 of 2: -(0.05 ln 0.05 + 0.95 ln 0.95) / ln 2 */
        double want = -(0.05 * log(0.05) + 0.95 * log(0.95)) / log(2.0);
        CHECK(le && fabs(le[uneven] - want) < 1e-4, "uneven straight line: %g, expected %g", le ? le[uneven] : -1,
              want);
        CHECK(bd && fabs(bd[centre] - 1) < 1e-6, "the centre of the cube: boundary distance 1");
        lc_scene_destroy(s);
    }
    return lc_test_finish();
}
