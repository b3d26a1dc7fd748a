/* FOO §5.5.5's importance measures of line sets, derived at load beside the
 * shape's (scene_derive.c): how far a vertex lies inside the data, how much
 * the directions around it disagree, and how irregularly its line turns and
 * is sampled (docs/ALGORITHM.md "Derived attributes"). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene_derive.h"

#define MEASURES 4
#define GRID_MAX 32           /* cells along an axis of the directions' grid */
#define VERTICES_PER_CELL 512 /* about this many vertices a cell, on average over the bounding box */
#define FIXED_ONE 65536.0     /* the grid's sums summed over processes in 16.16 fixed point */

/* Distance to the nearest face of the bounds over half the thinnest non-flat
 * extent: 0 on the boundary, 1 at the centre of the thinnest direction. */
static float boundary_distance(const lc_scene *s, const float *p)
{
    double best = INFINITY, half = INFINITY;
    for (int a = 0; a < 3; a++) {
        double lo = s->bounds[a], hi = s->bounds[a + 3];
        if (!(hi > lo))
            continue; /* a flat axis has no inside */
        double d = fmin(p[a] - lo, hi - p[a]);
        best = fmin(best, d);
        half = fmin(half, 0.5 * (hi - lo));
    }
    if (!isfinite(best) || !(half > 0))
        return 0.0f;
    double v = best / half;
    return (float)(v < 0 ? 0 : v > 1 ? 1 : v);
}

/* Cells per axis: cubic cells with about VERTICES_PER_CELL vertices each over
 * the box, a flat axis one cell. */
static void grid_size(const lc_scene *s, uint64_t total, int g[3])
{
    double ext[3], vol = 1;
    int dims = 0;
    for (int a = 0; a < 3; a++) {
        ext[a] = s->bounds[a + 3] - s->bounds[a];
        if (ext[a] > 0)
            vol *= ext[a], dims++;
    }
    double cells = fmax(1.0, (double)total / VERTICES_PER_CELL);
    double edge = dims ? pow(vol / cells, 1.0 / dims) : 1;
    for (int a = 0; a < 3; a++) {
        double n = ext[a] > 0 && edge > 0 ? ceil(ext[a] / edge) : 1;
        g[a] = n < 1 ? 1 : n > GRID_MAX ? GRID_MAX : (int)n;
    }
}

static size_t cell_of(const lc_scene *s, const int g[3], const float *p)
{
    size_t idx = 0;
    for (int a = 2; a >= 0; a--) {
        double ext = s->bounds[a + 3] - s->bounds[a];
        int c = ext > 0 ? (int)((p[a] - s->bounds[a]) / ext * g[a]) : 0;
        c = c < 0 ? 0 : c >= g[a] ? g[a] - 1 : c;
        idx = idx * (size_t)g[a] + (size_t)c;
    }
    return idx;
}

/* The unit tangent with its largest component made positive: a line and the
 * same line traversed the other way count as one direction. */
static void folded(const float *t, double out[3])
{
    int big = 0;
    for (int a = 1; a < 3; a++)
        if (fabsf(t[a]) > fabsf(t[big]))
            big = a;
    double sign = t[big] < 0 ? -1 : 1;
    for (int a = 0; a < 3; a++)
        out[a] = sign * t[a];
}

/* 1 - |sum of folded tangents| / n per grid cell (0: the lines in the cell run
 * alike; 1 - 1/sqrt(2) for two perpendicular families of equal weight). With
 * c (a part) the cells' sums are added over the processes. */
static int direction_variance(const lc_scene *s, uint64_t total, const lc_scene_collective *c, float *out,
                              lc_error *err)
{
    int g[3];
    grid_size(s, total, g);
    size_t cells = (size_t)g[0] * g[1] * g[2];
    uint64_t *sums = calloc(cells * 4, sizeof *sums); /* (t + 1) in fixed point, then the count */
    if (!sums)
        return lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate the directions' grid", s->name);
    for (uint32_t l = 0; l < s->line_count; l++)
        for (uint32_t v = s->line_offsets[l]; v < s->line_offsets[l + 1]; v++) {
            double t[3];
            folded(s->tangents + 3 * (size_t)v, t);
            uint64_t *q = sums + 4 * cell_of(s, g, s->positions + 3 * (size_t)v);
            for (int a = 0; a < 3; a++)
                q[a] += (uint64_t)llround((t[a] + 1.0) * FIXED_ONE);
            q[3]++;
        }
    if (c && c->sum_u64(c->ctx, sums, cells * 4, err)) {
        free(sums);
        return LC_ERR_INTERNAL;
    }
    for (uint32_t l = 0; l < s->line_count; l++)
        for (uint32_t v = s->line_offsets[l]; v < s->line_offsets[l + 1]; v++) {
            const uint64_t *q = sums + 4 * cell_of(s, g, s->positions + 3 * (size_t)v);
            double n = (double)q[3], len = 0;
            for (int a = 0; a < 3; a++) {
                double sum = (double)q[a] / FIXED_ONE - n;
                len += sum * sum;
            }
            double var = n > 0 ? 1.0 - sqrt(len) / n : 0.0;
            out[v] = (float)(var < 0 ? 0 : var > 1 ? 1 : var);
        }
    free(sums);
    return 0;
}

/* Shannon entropy of the shares w[i] / sum w over n >= 2 items, over log n:
 * 1 when every item has the same share, 0 when one has all (or all none). */
static double entropy(const double *w, int n)
{
    double sum = 0, h = 0;
    for (int i = 0; i < n; i++)
        sum += w[i];
    if (n < 2 || !(sum > 0))
        return 0.0;
    for (int i = 0; i < n; i++)
        if (w[i] > 0)
            h -= (w[i] / sum) * log(w[i] / sum);
    return h / log((double)n);
}

/* Per line: the entropy of its segments' lengths (linear) and of its turning
 * angles at the inner vertices (angular; 0 for a straight line). */
static int line_entropies(const lc_scene *s, float *linear, float *angular, lc_error *err)
{
    uint32_t most = 0;
    for (uint32_t l = 0; l < s->line_count; l++)
        most = s->line_offsets[l + 1] - s->line_offsets[l] > most ? s->line_offsets[l + 1] - s->line_offsets[l] : most;
    double *w = malloc(((size_t)most + 1) * sizeof *w);
    if (!w)
        return lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate the entropies' buffer", s->name);
    const float *p = s->positions;
    for (uint32_t l = 0; l < s->line_count; l++) {
        uint32_t a = s->line_offsets[l], b = s->line_offsets[l + 1];
        int n = 0;
        for (uint32_t v = a + 1; v < b; v++) {
            double d[3] = {p[3 * v] - p[3 * v - 3], p[3 * v + 1] - p[3 * v - 2], p[3 * v + 2] - p[3 * v - 1]};
            w[n++] = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        }
        float lin = (float)entropy(w, n);
        n = 0;
        for (uint32_t v = a + 1; v + 1 < b; v++) {
            double u[3], x[3], lu = 0, lx = 0, dot = 0;
            for (int k = 0; k < 3; k++) {
                u[k] = p[3 * v + k] - p[3 * (v - 1) + k], x[k] = p[3 * (v + 1) + k] - p[3 * v + k];
                lu += u[k] * u[k], lx += x[k] * x[k], dot += u[k] * x[k];
            }
            double cosine = lu > 0 && lx > 0 ? dot / sqrt(lu * lx) : 1.0;
            w[n++] = acos(cosine < -1 ? -1 : cosine > 1 ? 1 : cosine);
        }
        float ang = (float)entropy(w, n);
        for (uint32_t v = a; v < b; v++)
            linear[v] = lin, angular[v] = ang;
    }
    free(w);
    return 0;
}

int lc_scene_derive_line_measures(lc_scene *s, uint64_t total, const lc_scene_collective *c, lc_error *err)
{
    if (s->attribute_count + MEASURES > LC_MAX_ATTRIBUTES)
        return 0; /* the file's own attributes come first; the measures are left out (docs/ALGORITHM.md) */
    static const char *const names[MEASURES] = {"boundary_distance", "direction_variance", "linear_entropy",
                                                "angular_entropy"};
    uint32_t n = s->vertex_count;
    float *out[MEASURES];
    int rc = 0;
    for (int k = 0; k < MEASURES; k++)
        if (!(out[k] = calloc(n ? n : 1, sizeof(float))))
            rc = lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate the line measures", s->name);
    for (uint32_t v = 0; !rc && v < n; v++)
        out[0][v] = boundary_distance(s, s->positions + 3 * (size_t)v);
    if (!rc)
        rc = direction_variance(s, total, c, out[1], err);
    if (!rc)
        rc = line_entropies(s, out[2], out[3], err);
    for (int k = 0; k < MEASURES; k++) {
        if (rc) {
            free(out[k]);
            continue;
        }
        int idx = lc_scene_add_attribute(s, names[k], out[k], err); /* the scene owns the values */
        rc = idx < 0 ? idx : 0;
    }
    return rc;
}
