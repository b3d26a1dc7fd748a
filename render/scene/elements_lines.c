/* Line elements (docs/ALGORITHM.md "Elements"): each line cut into
 * equal-arc-length segments, the budget split over the lines in proportion to
 * their length; and the elements of parts of a scene read by several
 * processes, numbered as the whole scene's. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "elements.h"

/* ---- lines */

typedef struct {
    double frac;
    uint32_t line;
} line_share;

static int cmp_remainder(const void *a, const void *b)
{
    const line_share *x = a, *y = b;
    if (x->frac != y->frac)
        return x->frac > y->frac ? -1 : 1;
    return x->line < y->line ? -1 : x->line > y->line;
}

/* Splits the budget over lines in proportion to their length (largest
 * line_share), at least one element per non-empty line and at most one per
 * segment: an element without a vertex of its own would never be drawn. */
static uint32_t *line_element_counts(const lc_element_geometry *s, uint32_t budget, const float *line_len,
                                     uint64_t *total_out)
{
    uint32_t L = s->line_count;
    uint32_t *cnt = calloc(L ? L : 1, sizeof(uint32_t));
    line_share *rem = malloc((L ? L : 1) * sizeof(line_share));
    if (!cnt || !rem) {
        free(cnt);
        free(rem);
        return NULL;
    }
    double total_len = 0;
    uint32_t nonempty = 0;
    for (uint32_t l = 0; l < L; l++)
        if (s->line_offsets[l + 1] > s->line_offsets[l]) {
            total_len += line_len[l];
            nonempty++;
        }
    uint64_t total = 0;
    size_t nrem = 0;
    for (uint32_t l = 0; l < L; l++) {
        uint32_t nv = s->line_offsets[l + 1] - s->line_offsets[l];
        if (nv == 0)
            continue;
        uint32_t cap = nv > 1 ? nv - 1 : 1;
        double ideal = total_len > 0 ? (double)budget * line_len[l] / total_len : (double)budget / nonempty;
        double fl = floor(ideal);
        uint32_t c = !(fl >= 1) ? 1 : fl > cap ? cap : (uint32_t)fl; /* NaN -> 1: never cast it */
        cnt[l] = c;
        total += c;
        if (c < cap && ideal > c)
            rem[nrem++] = (line_share){ideal - c, l};
    }
    if (total < budget && nrem > 0) {
        qsort(rem, nrem, sizeof *rem, cmp_remainder);
        for (size_t i = 0; i < nrem && total < budget; i++) {
            cnt[rem[i].line]++;
            total++;
        }
    }
    free(rem);
    *total_out = total;
    return cnt;
}

/* Each line's arc length, finite (so that the shares above are numbers). */
static void line_lengths(const lc_element_geometry *s, float *line_len)
{
    const float *P = s->positions;
    for (uint32_t l = 0; l < s->line_count; l++) {
        double acc = 0;
        for (uint32_t i = s->line_offsets[l] + 1; i < s->line_offsets[l + 1]; i++) {
            const float *a = P + 3 * (size_t)(i - 1), *b = P + 3 * (size_t)i;
            double dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
            acc += sqrt(dx * dx + dy * dy + dz * dz);
        }
        line_len[l] = (float)fmin(acc, FLT_MAX);
    }
}

/* The blends of the vertices [a, b) of one line of length len cut into n
 * equal-arc-length elements numbered from base. */
static void line_blends(lc_elements *e, const float *P, uint32_t a, uint32_t b, uint32_t n, float len, uint32_t base)
{
    double h = len / n; /* segment length */
    double arc = 0;
    for (uint32_t i = a; i < b; i++) {
        if (i > a) {
            const float *p = P + 3 * (size_t)(i - 1), *q = P + 3 * (size_t)i;
            double dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
            arc += sqrt(dx * dx + dy * dy + dz * dz);
        }
        double t = h > 0 ? arc / h : 0; /* arc in segment units; centres at j + 0.5 */
        uint32_t seg = t >= n ? n - 1 : (uint32_t)t;
        uint32_t ids[2];
        float w[2];
        double c = t - 0.5;
        if (c <= 0 || c >= n - 1) { /* before the first or after the last centre */
            ids[0] = base + seg;
            w[0] = 1.0f;
            lc_elements_set_vertex(e, i, 1, ids, w, base + seg);
        } else {
            uint32_t j = (uint32_t)c;
            double f = c - j;
            ids[0] = base + j;
            ids[1] = base + j + 1;
            w[0] = (float)(1.0 - f);
            w[1] = (float)f;
            lc_elements_set_vertex(e, i, 2, ids, w, base + seg);
        }
    }
}

/* The element counts of all lines of g (lengths line_len) and the per-vertex
 * arrays for e's vertices, every vertex first on element 0 (vertices outside
 * every line, allowed by the offsets, are never drawn). */
static int line_elements_start(const lc_element_geometry *g, uint32_t budget, const float *line_len, uint32_t vertices,
                               lc_elements *e, uint32_t **cnt_out, lc_error *err)
{
    uint64_t total = 0;
    uint32_t *cnt = line_element_counts(g, budget, line_len, &total);
    if (!cnt)
        return lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate line elements", g->name);
    if (total > UINT32_MAX - 1) { /* cannot happen below LC_MAX_VERTICES, kept for safety */
        free(cnt);
        return lc_err(err, LC_ERR_LIMIT, "%s: too many line elements", g->name);
    }
    /* a scene whose lines are all empty still gets one element for stray vertices */
    int rc = lc_elements_alloc(e, vertices, total ? (uint32_t)total : 1, g->name, err);
    if (rc) {
        free(cnt);
        return rc;
    }
    for (uint32_t v = 0; v < vertices; v++) {
        uint32_t zero = 0;
        float one = 1.0f;
        lc_elements_set_vertex(e, v, 1, &zero, &one, 0);
    }
    *cnt_out = cnt;
    return 0;
}

/* Neighbours along each line of g: its consecutive elements. Frees cnt. */
static int line_adjacency(const lc_element_geometry *g, uint32_t *cnt, lc_elements *e, lc_error *err)
{
    uint64_t pairs_max = 0;
    for (uint32_t l = 0; l < g->line_count; l++)
        pairs_max += cnt[l] ? 2 * ((uint64_t)cnt[l] - 1) : 0;
    uint64_t *pairs = malloc((pairs_max ? pairs_max : 1) * sizeof(uint64_t));
    if (!pairs) {
        free(cnt);
        return lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate line adjacency", g->name);
    }
    size_t npairs = 0;
    uint32_t base = 0;
    for (uint32_t l = 0; l < g->line_count; l++) {
        uint32_t n = cnt[l];
        for (uint32_t j = 0; j + 1 < n; j++) {
            pairs[npairs++] = (uint64_t)(base + j) << 32 | (base + j + 1);
            pairs[npairs++] = (uint64_t)(base + j + 1) << 32 | (base + j);
        }
        base += n;
    }
    free(cnt);
    return lc_elements_adjacency_from_pairs(e, pairs, npairs, g->name, err);
}

int lc_elements_build_lines(const lc_element_geometry *s, lc_elements *e, uint32_t budget, lc_error *err)
{
    uint32_t L = s->line_count;
    float *line_len = malloc((L ? L : 1) * sizeof(float));
    if (!line_len)
        return lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate line lengths", s->name);
    line_lengths(s, line_len);
    uint32_t *cnt = NULL;
    int rc = line_elements_start(s, budget, line_len, s->vertex_count, e, &cnt, err);
    if (rc) {
        free(line_len);
        return rc;
    }
    uint32_t base = 0;
    for (uint32_t l = 0; l < L; l++) {
        uint32_t a = s->line_offsets[l], b = s->line_offsets[l + 1];
        if (b > a)
            line_blends(e, s->positions, a, b, cnt[l], line_len[l], base);
        base += cnt[l];
    }
    free(line_len);
    return line_adjacency(s, cnt, e, err);
}

int lc_elements_line_lengths(const lc_element_geometry *g, float *out)
{
    if (!g || g->type != LC_PRIM_LINES)
        return LC_ERR_INVALID;
    line_lengths(g, out);
    return 0;
}

int lc_elements_build_lines_part(const lc_element_geometry *part, const lc_elements_desc *desc,
                                 const lc_line_census *whole, lc_elements *e, lc_error *err)
{
    lc_elements_free(e);
    uint32_t L = whole->line_count;
    if (whole->first_line > L || part->line_count > L - whole->first_line || whole->vertex_count > UINT32_MAX)
        return lc_err(err, LC_ERR_INVALID, "%s: lines %u..%u of a part lie outside the %u lines of the whole",
                      part->name, whole->first_line, whole->first_line + part->line_count, L);
    /* The whole scene's line table, as build_lines sees it in one process. */
    uint32_t *offsets = malloc(((size_t)L + 1) * sizeof *offsets);
    if (!offsets)
        return lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate the line table of %u lines", part->name, L);
    offsets[0] = 0;
    for (uint32_t l = 0; l < L; l++)
        offsets[l + 1] = offsets[l] + whole->vertex_counts[l];
    lc_element_geometry g = {.name = part->name,
                             .type = LC_PRIM_LINES,
                             .vertex_count = (uint32_t)whole->vertex_count,
                             .line_count = L,
                             .line_offsets = offsets};
    uint32_t budget = desc && desc->line_budget ? desc->line_budget : lc_elements_default_count(&g);
    uint32_t *cnt = NULL;
    int rc = line_elements_start(&g, budget, whole->lengths, part->vertex_count, e, &cnt, err);
    if (rc) {
        free(offsets);
        return rc;
    }
    uint32_t base = 0;
    for (uint32_t l = 0; l < whole->first_line; l++)
        base += cnt[l];
    for (uint32_t l = 0; l < part->line_count; l++) {
        uint32_t a = part->line_offsets[l], b = part->line_offsets[l + 1], n = cnt[whole->first_line + l];
        if (b > a)
            line_blends(e, part->positions, a, b, n, whole->lengths[whole->first_line + l], base);
        base += n;
    }
    rc = line_adjacency(&g, cnt, e, err);
    free(offsets);
    if (rc)
        lc_elements_free(e);
    return rc;
}

int lc_elements_build_points_part(const lc_element_geometry *part, uint64_t first_point, uint64_t total_points,
                                  lc_elements *e, lc_error *err)
{
    lc_elements_free(e);
    if (total_points > UINT32_MAX - 1 || first_point + part->vertex_count > total_points)
        return lc_err(err, LC_ERR_INVALID, "%s: points %llu..%llu of a part lie outside the %llu points of the whole",
                      part->name, (unsigned long long)first_point,
                      (unsigned long long)(first_point + part->vertex_count), (unsigned long long)total_points);
    int rc = lc_elements_alloc(e, part->vertex_count, (uint32_t)total_points, part->name, err);
    if (!rc && !(e->adjacency = malloc(sizeof(uint32_t))))
        rc = lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate element adjacency", part->name);
    if (rc) {
        lc_elements_free(e);
        return rc;
    }
    for (uint32_t v = 0; v < part->vertex_count; v++) {
        uint32_t id = (uint32_t)first_point + v;
        float w = 1.0f;
        lc_elements_set_vertex(e, v, 1, &id, &w, id);
    }
    e->adjacency_count = 0;
    return 0;
}
