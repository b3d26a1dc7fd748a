/* Optimization elements: line budgets and blends, surface patches (coverage,
 * components, Shepard weights against an independent Dijkstra), adjacency. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "lc_test.h"
#include "scene.h"

/* Common invariants: ids in range, weights >= 0 summing to 1, slot 3 weight 0,
 * unused slots repeat e0, adjacency symmetric without duplicates or loops. */
static void check_invariants(const lc_scene *s, const char *what)
{
    const lc_elements *e = &s->elements;
    int ok_ids = 1, ok_w = 1, ok_unused = 1;
    for (uint32_t v = 0; v < s->vertex_count; v++) {
        const uint32_t *ve = e->vertex_elements + 4 * v;
        const float *vw = e->vertex_weights + 4 * v;
        for (int k = 0; k < 4; k++)
            ok_ids &= ve[k] < e->count;
        double sum = vw[0] + vw[1] + vw[2];
        ok_w &= fabs(sum - 1.0) < 1e-5 && vw[0] >= 0 && vw[1] >= 0 && vw[2] >= 0 && vw[3] == 0;
        for (int k = 1; k < 3; k++)
            if (vw[k] == 0)
                ok_unused &= ve[k] == ve[0];
    }
    CHECK(ok_ids, "%s: element ids in range", what);
    CHECK(ok_w, "%s: weights sum to 1", what);
    CHECK(ok_unused, "%s: unused slots repeat e0", what);
    int ok_adj = 1;
    const uint32_t *off = e->adjacency_offsets, *adj = e->adjacency;
    CHECK(off[0] == 0 && off[e->count] == e->adjacency_count, "%s: CSR bounds", what);
    for (uint32_t a = 0; a < e->count; a++)
        for (uint32_t i = off[a]; i < off[a + 1]; i++) {
            uint32_t b = adj[i];
            ok_adj &= b != a && b < e->count;
            if (i > off[a])
                ok_adj &= adj[i - 1] < b; /* sorted, hence no duplicates */
            int back = 0;
            for (uint32_t j = off[b]; j < off[b + 1]; j++)
                back |= adj[j] == a;
            ok_adj &= back;
        }
    CHECK(ok_adj, "%s: adjacency symmetric, no loops, no duplicates", what);
}

static int adjacent(const lc_elements *e, uint32_t a, uint32_t b)
{
    for (uint32_t i = e->adjacency_offsets[a]; i < e->adjacency_offsets[a + 1]; i++)
        if (e->adjacency[i] == b)
            return 1;
    return 0;
}

static void test_points(void)
{
    lc_scene *s = lc_scene_create("pts", LC_PRIM_POINTS);
    lc_scene_alloc_vertices(s, 5, 0, NULL);
    for (int i = 0; i < 15; i++)
        s->positions[i] = (float)i;
    lc_error err = {0};
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    CHECK(s->elements.count == 5, "one element per point");
    CHECK(s->elements.adjacency_count == 0, "points have no adjacency");
    for (uint32_t v = 0; v < 5; v++)
        CHECK(s->elements.vertex_elements[4 * v] == v && s->elements.vertex_elements[4 * v + 3] == v &&
                  s->elements.vertex_weights[4 * v] == 1.0f,
              "point %u is its own element", v);
    check_invariants(s, "points");
    lc_scene_destroy(s);
}

/* nlines straight lines along x with given lengths, `per_unit` segments per unit. */
static lc_scene *straight_lines(int nlines, const double *len, int per_unit)
{
    uint32_t n = 0;
    for (int l = 0; l < nlines; l++)
        n += (uint32_t)(len[l] * per_unit) + 1;
    lc_scene *s = lc_scene_create("lines", LC_PRIM_LINES);
    lc_scene_alloc_vertices(s, n, 0, NULL);
    s->line_count = (uint32_t)nlines;
    s->line_offsets = malloc((nlines + 1) * sizeof(uint32_t));
    uint32_t v = 0;
    for (int l = 0; l < nlines; l++) {
        s->line_offsets[l] = v;
        int segs = (int)(len[l] * per_unit);
        for (int i = 0; i <= segs; i++, v++) {
            s->positions[3 * v] = (float)(i / (double)per_unit);
            s->positions[3 * v + 1] = (float)l;
            s->positions[3 * v + 2] = 0;
        }
    }
    s->line_offsets[nlines] = v;
    return s;
}

static void test_lines(void)
{
    double len[2] = {1.0, 3.0};
    lc_scene *s = straight_lines(2, len, 100);
    lc_elements_desc desc = {.line_budget = 40};
    lc_error err = {0};
    CHECK(lc_scene_finalize(s, &desc, &err) == 0, "finalize: %s", err.msg);
    const lc_elements *e = &s->elements;
    CHECK(e->count == 40, "budget used: %u", e->count);
    /* line 0 (length 1) gets 10 segments of 0.1, line 1 gets 30 */
    uint32_t last0 = e->vertex_elements[4 * 100 + 3], first1 = e->vertex_elements[4 * 101 + 3];
    CHECK(last0 == 9 && first1 == 10, "proportional split: %u %u", last0, first1);
    CHECK(e->vertex_elements[4 * (s->vertex_count - 1) + 3] == 39, "last element");
    CHECK(!adjacent(e, 9, 10), "no adjacency across lines");
    CHECK(adjacent(e, 3, 4) && adjacent(e, 4, 3) && adjacent(e, 20, 21), "consecutive adjacent");
    CHECK(e->adjacency_count == 2 * (9 + 29), "adjacency count %u", e->adjacency_count);
    /* vertex 5 (x = 0.05) is the centre of segment 0: all weight on it */
    CHECK(e->vertex_elements[4 * 5] == 0 && fabsf(e->vertex_weights[4 * 5] - 1.0f) < 1e-5,
          "centre vertex has one element");
    /* vertex 10 (x = 0.1) is the border of segments 0 and 1: half and half */
    CHECK(e->vertex_elements[4 * 10] == 0 && e->vertex_elements[4 * 10 + 1] == 1, "border blend ids");
    CHECK_NEAR(e->vertex_weights[4 * 10], 0.5, 1e-4, "border blend w0");
    CHECK_NEAR(e->vertex_weights[4 * 10 + 1], 0.5, 1e-4, "border blend w1");
    /* vertex 13 (x = 0.13): between centres 0.15 (seg 1) and 0.05 (seg 0) */
    CHECK_NEAR(e->vertex_weights[4 * 13], 0.2, 1e-4, "linear weight toward seg 0");
    CHECK_NEAR(e->vertex_weights[4 * 13 + 1], 0.8, 1e-4, "linear weight toward seg 1");
    CHECK(e->vertex_elements[4 * 13 + 3] == 1, "primary = containing segment");
    /* line ends: one element only */
    CHECK(e->vertex_weights[0] == 1.0f && e->vertex_weights[1] == 0.0f, "start vertex");
    CHECK(e->vertex_weights[4 * 100] == 1.0f, "end vertex");
    check_invariants(s, "lines");

    /* budget below the line count: still one element per line */
    desc.line_budget = 1;
    CHECK(lc_scene_finalize(s, &desc, &err) == 0, "refinalize: %s", err.msg);
    CHECK(s->elements.count == 2, "at least one per line: %u", s->elements.count);
    CHECK(s->elements.adjacency_count == 0, "single-element lines have no neighbours");
    check_invariants(s, "lines budget 1");
    lc_scene_destroy(s);

    /* many lines of equal length, budget not divisible: total is exact */
    double many[7] = {1, 1, 1, 1, 1, 1, 1};
    s = straight_lines(7, many, 50);
    desc.line_budget = 100;
    CHECK(lc_scene_finalize(s, &desc, &err) == 0, "finalize 7: %s", err.msg);
    CHECK(s->elements.count == 100, "largest remainder hits the budget: %u", s->elements.count);
    check_invariants(s, "7 lines");
    lc_scene_destroy(s);

    /* default budget 10000, but never more elements than segments */
    s = straight_lines(2, len, 10);
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize default: %s", err.msg);
    CHECK(s->elements.count == 40, "capped at segment count: %u", s->elements.count);
    check_invariants(s, "capped");
    lc_scene_destroy(s);
}

/* Grid mesh of (nx x ny) vertices at spacing h with origin (ox, oy, z). */
static void grid(lc_scene *s, uint32_t base, uint32_t *tri, uint32_t nx, uint32_t ny, double h, double ox, double oy,
                 double z)
{
    for (uint32_t j = 0; j < ny; j++)
        for (uint32_t i = 0; i < nx; i++) {
            float *p = s->positions + 3 * (base + j * nx + i);
            p[0] = (float)(ox + i * h);
            p[1] = (float)(oy + j * h);
            p[2] = (float)z;
        }
    uint32_t k = 0;
    for (uint32_t j = 0; j + 1 < ny; j++)
        for (uint32_t i = 0; i + 1 < nx; i++) {
            uint32_t a = base + j * nx + i, b = a + 1, c = a + nx, d = c + 1;
            uint32_t q[6] = {a, b, d, a, d, c};
            memcpy(tri + 3 * k, q, sizeof q);
            k += 2;
        }
}

/* Reference Dijkstra over the mesh graph (O(n^2), fine for tests). */
static void reference_dijkstra(const lc_scene *s, uint32_t src, double *dist)
{
    uint32_t n = s->vertex_count;
    char *done = calloc(n, 1);
    for (uint32_t v = 0; v < n; v++)
        dist[v] = INFINITY;
    dist[src] = 0;
    for (;;) {
        uint32_t u = UINT32_MAX;
        for (uint32_t v = 0; v < n; v++)
            if (!done[v] && isfinite(dist[v]) && (u == UINT32_MAX || dist[v] < dist[u]))
                u = v;
        if (u == UINT32_MAX)
            break;
        done[u] = 1;
        for (uint32_t t = 0; t < s->triangle_count; t++) {
            const uint32_t *tr = s->triangles + 3 * t;
            for (int k = 0; k < 3; k++) {
                if (tr[k] != u)
                    continue;
                for (int m = 1; m < 3; m++) {
                    uint32_t w = tr[(k + m) % 3];
                    const float *a = s->positions + 3 * u, *b = s->positions + 3 * w;
                    double l = sqrt(pow(a[0] - b[0], 2) + pow(a[1] - b[1], 2) + pow(a[2] - b[2], 2));
                    if (dist[u] + l < dist[w])
                        dist[w] = dist[u] + l;
                }
            }
        }
    }
    free(done);
}

static void test_patches(void)
{
    /* a 14 x 10 grid plus a disconnected 3 x 3 grid far away */
    const uint32_t nx = 14, ny = 10, n1 = nx * ny, n2 = 9;
    lc_scene *s = lc_scene_create("patches", LC_PRIM_TRIANGLES);
    lc_scene_alloc_vertices(s, n1 + n2 + 1, 0, NULL); /* +1: a vertex in no triangle */
    s->triangle_count = 2 * (nx - 1) * (ny - 1) + 2 * 2 * 2;
    s->triangles = malloc(3 * s->triangle_count * sizeof(uint32_t));
    grid(s, 0, s->triangles, nx, ny, 0.1, 0, 0, 0);
    grid(s, n1, s->triangles + 3 * 2 * (nx - 1) * (ny - 1), 3, 3, 0.1, 10, 10, 1);
    float *stray = s->positions + 3 * (n1 + n2);
    stray[0] = stray[1] = stray[2] = 5;
    lc_elements_desc desc = {.patch_count = 6};
    lc_error err = {0};
    CHECK(lc_scene_finalize(s, &desc, &err) == 0, "finalize: %s", err.msg);
    const lc_elements *e = &s->elements;
    check_invariants(s, "patches");
    CHECK(e->count >= 6, "at least the requested patches: %u", e->count);
    /* the small component has its own patch(es), shared with no big-grid vertex */
    uint32_t small = e->vertex_elements[4 * n1 + 3];
    int shared = 0;
    for (uint32_t v = 0; v < n1; v++)
        for (int k = 0; k < 3; k++)
            shared |= e->vertex_weights[4 * v + k] > 0 && e->vertex_elements[4 * v + k] == small;
    CHECK(!shared, "disconnected component gets its own patch");
    int isolated = 1; /* and no adjacency to a big-grid patch */
    for (uint32_t v = 0; v < n1; v++)
        isolated &= !adjacent(e, small, e->vertex_elements[4 * v + 3]);
    CHECK(isolated, "disconnected component has no adjacency to the other");

    /* centres: vertices whose blend is entirely their own primary with 3+ centres around */
    uint32_t centre_of[64];
    for (int i = 0; i < 64; i++)
        centre_of[i] = UINT32_MAX;
    for (uint32_t v = 0; v < n1; v++)
        if (e->vertex_weights[4 * v] == 1.0f)
            centre_of[e->vertex_elements[4 * v]] = v;
    int all_found = 1, covered = 1;
    for (uint32_t v = 0; v < n1; v++)
        covered &= e->vertex_elements[4 * v + 3] == e->vertex_elements[4 * v];
    CHECK(covered, "primary = nearest (e0)");
    double *dist[64] = {0};
    for (uint32_t p = 0; p < e->count; p++) {
        if (p == small)
            continue;
        if (centre_of[p] == UINT32_MAX) {
            all_found = 0;
            continue;
        }
        dist[p] = malloc(s->vertex_count * sizeof(double));
        reference_dijkstra(s, centre_of[p], dist[p]);
    }
    CHECK(all_found, "every big-grid patch has a centre vertex");
    if (all_found) {
        int ok_nearest = 1, ok_weights = 1;
        for (uint32_t v = 0; v < n1; v++) {
            /* the three smallest reference distances */
            double best[3] = {INFINITY, INFINITY, INFINITY};
            for (uint32_t p = 0; p < e->count; p++) {
                if (!dist[p])
                    continue;
                double d = dist[p][v];
                for (int k = 0; k < 3; k++)
                    if (d < best[k]) {
                        for (int m = 2; m > k; m--)
                            best[m] = best[m - 1];
                        best[k] = d;
                        break;
                    }
            }
            const uint32_t *ve = e->vertex_elements + 4 * v;
            const float *vw = e->vertex_weights + 4 * v;
            double got[3], inv[3], sum = 0;
            for (int k = 0; k < 3; k++)
                got[k] = dist[ve[k]][v];
            if (got[0] < 1e-9) { /* a centre: all weight on its own patch */
                ok_weights &= vw[0] == 1.0f && best[0] < 1e-9;
                continue;
            }
            for (int k = 0; k < 3; k++)
                ok_nearest &= fabs(got[k] - best[k]) < 1e-5;
            for (int k = 0; k < 3; k++)
                sum += inv[k] = 1.0 / (got[k] * got[k]);
            for (int k = 0; k < 3; k++)
                ok_weights &= fabs(vw[k] - inv[k] / sum) < 1e-4;
        }
        CHECK(ok_nearest, "blends use the 3 nearest centres by mesh distance");
        CHECK(ok_weights, "Shepard weights d^-2");
    }
    for (int p = 0; p < 64; p++)
        free(dist[p]);
    /* adjacency: patches meet along mesh edges */
    int ok_edges = 1;
    for (uint32_t t = 0; t < s->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = s->triangles[3 * t + k], b = s->triangles[3 * t + (k + 1) % 3];
            uint32_t pa = e->vertex_elements[4 * a + 3], pb = e->vertex_elements[4 * b + 3];
            if (pa != pb)
                ok_edges &= adjacent(e, pa, pb);
        }
    CHECK(ok_edges, "patches sharing a mesh edge are adjacent");
    /* stray vertex: valid single element */
    CHECK(e->vertex_weights[4 * (n1 + n2)] == 1.0f, "unreferenced vertex gets a valid blend");
    lc_scene_destroy(s);
}

static void test_patch_defaults(void)
{
    /* 40 x 40 grid: default patch count = 1600 / 8 = 200 */
    lc_scene *s = lc_scene_create("grid", LC_PRIM_TRIANGLES);
    lc_scene_alloc_vertices(s, 1600, 0, NULL);
    s->triangle_count = 2 * 39 * 39;
    s->triangles = malloc(3 * s->triangle_count * sizeof(uint32_t));
    grid(s, 0, s->triangles, 40, 40, 1.0, 0, 0, 0);
    lc_error err = {0};
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    CHECK(s->elements.count == 200, "default patches: %u", s->elements.count);
    /* every patch owns at least its centre */
    char *owned = calloc(s->elements.count, 1);
    for (uint32_t v = 0; v < s->vertex_count; v++)
        owned[s->elements.vertex_elements[4 * v + 3]] = 1;
    int all = 1;
    for (uint32_t p = 0; p < s->elements.count; p++)
        all &= owned[p];
    free(owned);
    CHECK(all, "every patch is some vertex's primary");
    check_invariants(s, "default patches");
    /* more patches than vertices requested: capped */
    lc_elements_desc desc = {.patch_count = 100000};
    CHECK(lc_scene_finalize(s, &desc, &err) == 0, "finalize many: %s", err.msg);
    CHECK(s->elements.count == 1600, "capped at vertex count: %u", s->elements.count);
    check_invariants(s, "one patch per vertex");
    lc_scene_destroy(s);
}

/* Grid sampling (the default above LC_GRID_SAMPLING_VERTICES), forced on a
 * small mesh: about the requested count on a flat grid, valid blends, and a
 * disconnected part with patches of its own. */
static void test_grid_sampling(void)
{
    const uint32_t nx = 120, ny = 80, n1 = nx * ny, n2 = 100;
    lc_scene *s = lc_scene_create("grid sampling", LC_PRIM_TRIANGLES);
    lc_scene_alloc_vertices(s, n1 + n2, 0, NULL);
    s->triangle_count = 2 * (nx - 1) * (ny - 1) + 2 * 9 * 9;
    s->triangles = malloc(3 * s->triangle_count * sizeof(uint32_t));
    grid(s, 0, s->triangles, nx, ny, 0.01, 0, 0, 0);
    grid(s, n1, s->triangles + 3 * 2 * (nx - 1) * (ny - 1), 10, 10, 0.01, 5, 5, 1);
    lc_elements_desc desc = {.patch_count = 200, .patch_sampling = LC_PATCH_SAMPLING_GRID};
    lc_error err = {0};
    CHECK(lc_scene_finalize(s, &desc, &err) == 0, "finalize: %s", err.msg);
    const lc_elements *e = &s->elements;
    check_invariants(s, "grid sampling");
    /* the flat grid's area asks for about 200 cells; the small part adds its own */
    CHECK(e->count >= 150 && e->count <= 260, "grid sampling made %u patches for 200", e->count);
    uint32_t small = e->vertex_elements[4 * n1 + 3];
    int shared = 0;
    for (uint32_t v = 0; v < n1; v++)
        shared |= e->vertex_elements[4 * v + 3] == small;
    CHECK(!shared, "the disconnected part has a patch of its own");
    /* every patch is some vertex's primary, and patches are about equal: none
     * holds more than four times the mean */
    uint32_t *size = calloc(e->count, sizeof *size);
    for (uint32_t v = 0; v < n1 + n2; v++)
        size[e->vertex_elements[4 * v + 3]]++;
    uint32_t empty = 0, largest = 0;
    for (uint32_t i = 0; i < e->count; i++) {
        empty += size[i] == 0;
        largest = size[i] > largest ? size[i] : largest;
    }
    CHECK(empty == 0, "%u patches are nobody's primary", empty);
    CHECK(largest <= 4 * (n1 + n2) / e->count, "largest patch %u vertices, mean %u", largest, (n1 + n2) / e->count);
    free(size);
    lc_scene_destroy(s);
}

int main(void)
{
    test_points();
    test_lines();
    test_patches();
    test_patch_defaults();
    test_grid_sampling();
    return lc_test_finish();
}
