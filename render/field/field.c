/* Vector fields: creation, trilinear sampling of grids, magnitude range. */
#include "field.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *lc_field_kind_name(lc_field_kind kind)
{
    return kind == LC_FIELD_UNIFORM ? "uniform" : kind == LC_FIELD_RECTILINEAR ? "rectilinear" : "analytic";
}

uint64_t lc_field_node_count(const lc_field *f)
{
    if (!f || f->kind == LC_FIELD_ANALYTIC)
        return 0;
    return (uint64_t)f->dims[0] * f->dims[1] * f->dims[2];
}

uint64_t lc_field_bytes(const lc_field *f)
{
    if (!f || f->kind == LC_FIELD_ANALYTIC)
        return 0;
    return lc_field_node_count(f) * 3 * sizeof(float) +
           ((uint64_t)f->dims[0] + f->dims[1] + f->dims[2]) * sizeof(double);
}

void lc_field_destroy(lc_field *f)
{
    if (!f)
        return;
    for (int a = 0; a < 3; a++)
        free(f->coords[a]);
    free(f->vectors);
    free(f);
}

int lc_field_contains(const lc_field *f, const double p[3])
{
    for (int a = 0; a < 3; a++)
        if (!(p[a] >= f->bounds[a] && p[a] <= f->bounds[a + 3]))
            return 0; /* NaN is outside too */
    return 1;
}

/* The cell index i (coords[i] <= x <= coords[i+1]) and the fraction within
 * it; x must lie within [coords[0], coords[n-1]]. Uniform grids compute it,
 * rectilinear ones bisect. */
static void locate(const lc_field *f, int a, double x, uint32_t *cell, double *frac)
{
    const double *c = f->coords[a];
    uint32_t n = f->dims[a];
    uint32_t i;
    if (f->kind == LC_FIELD_UNIFORM) {
        double s = (x - c[0]) / (c[n - 1] - c[0]) * (double)(n - 1);
        i = s <= 0 ? 0 : (uint32_t)s;
        if (i > n - 2)
            i = n - 2;
    } else {
        uint32_t lo = 0, hi = n - 1; /* c[lo] <= x <= c[hi] */
        while (hi - lo > 1) {
            uint32_t mid = lo + (hi - lo) / 2;
            if (c[mid] <= x)
                lo = mid;
            else
                hi = mid;
        }
        i = lo;
    }
    double t = (x - c[i]) / (c[i + 1] - c[i]);
    *cell = i;
    *frac = t < 0 ? 0 : t > 1 ? 1 : t;
}

int lc_field_sample(const lc_field *f, const double p[3], double t, double v[3])
{
    v[0] = v[1] = v[2] = 0.0;
    if (!lc_field_contains(f, p))
        return 0;
    if (f->kind == LC_FIELD_ANALYTIC) {
        f->fn(p, t, v);
        return 1;
    }
    uint32_t c[3];
    double w[3];
    for (int a = 0; a < 3; a++)
        locate(f, a, p[a], &c[a], &w[a]);
    const size_t nx = f->dims[0], nxy = nx * f->dims[1];
    for (int k = 0; k < 8; k++) {
        int dx = k & 1, dy = (k >> 1) & 1, dz = k >> 2;
        double wk = (dx ? w[0] : 1 - w[0]) * (dy ? w[1] : 1 - w[1]) * (dz ? w[2] : 1 - w[2]);
        const float *q = f->vectors + 3 * ((c[0] + dx) + (c[1] + dy) * nx + (c[2] + dz) * nxy);
        v[0] += wk * q[0];
        v[1] += wk * q[1];
        v[2] += wk * q[2];
    }
    return 1;
}

/* d v / d x_a at p: central where both neighbours lie inside, else one-sided. */
static void derivative(const lc_field *f, const double p[3], double t, int a, double h, double dv[3])
{
    double lo[3] = {p[0], p[1], p[2]}, hi[3] = {p[0], p[1], p[2]}, vl[3], vh[3];
    lo[a] = p[a] - h > f->bounds[a] ? p[a] - h : f->bounds[a];
    hi[a] = p[a] + h < f->bounds[a + 3] ? p[a] + h : f->bounds[a + 3];
    double d = hi[a] - lo[a];
    lc_field_sample(f, lo, t, vl);
    lc_field_sample(f, hi, t, vh);
    for (int k = 0; k < 3; k++)
        dv[k] = d > 0 ? (vh[k] - vl[k]) / d : 0.0;
}

int lc_field_curl(const lc_field *f, const double p[3], double t, double w[3])
{
    w[0] = w[1] = w[2] = 0.0;
    if (!lc_field_contains(f, p))
        return 0;
    double diag = 0, d[3][3];
    for (int a = 0; a < 3; a++)
        diag += (f->bounds[a + 3] - f->bounds[a]) * (f->bounds[a + 3] - f->bounds[a]);
    for (int a = 0; a < 3; a++) {
        double h = 1e-3 * sqrt(diag);
        if (f->kind != LC_FIELD_ANALYTIC) {
            uint32_t c;
            double frac;
            locate(f, a, p[a], &c, &frac);
            h = 0.5 * (f->coords[a][c + 1] - f->coords[a][c]);
        }
        derivative(f, p, t, a, h, d[a]); /* d[a][k] = d v_k / d x_a */
    }
    w[0] = d[1][2] - d[2][1];
    w[1] = d[2][0] - d[0][2];
    w[2] = d[0][1] - d[1][0];
    return 1;
}

static lc_field *field_new(const char *name)
{
    lc_field *f = calloc(1, sizeof *f);
    if (f)
        snprintf(f->name, sizeof f->name, "%s", name ? name : "field");
    return f;
}

int lc_field_create_analytic(const char *name, lc_field_fn fn, const double bounds[6], int time_dependent, double t0,
                             double t1, lc_field **out, lc_error *err)
{
    *out = NULL;
    for (int a = 0; a < 3; a++)
        if (!(bounds[a] < bounds[a + 3]) || !isfinite(bounds[a]) || !isfinite(bounds[a + 3]))
            return lc_err(err, LC_ERR_INVALID, "%s: empty or non-finite domain on axis %c", name ? name : "field",
                          "xyz"[a]);
    lc_field *f = field_new(name);
    if (!f)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", name ? name : "field");
    f->kind = LC_FIELD_ANALYTIC;
    f->fn = fn;
    memcpy(f->bounds, bounds, sizeof f->bounds);
    f->time_dependent = time_dependent;
    f->t0 = t0;
    f->t1 = t1;
    /* The magnitude range on a 33^3 lattice: what a description needs, not exact. */
    double lo = INFINITY, hi = 0.0;
    for (int k = 0; k <= 32; k++)
        for (int j = 0; j <= 32; j++)
            for (int i = 0; i <= 32; i++) {
                double p[3] = {bounds[0] + (bounds[3] - bounds[0]) * i / 32.0,
                               bounds[1] + (bounds[4] - bounds[1]) * j / 32.0,
                               bounds[2] + (bounds[5] - bounds[2]) * k / 32.0},
                       v[3];
                fn(p, t0, v);
                double m = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
                if (m < lo)
                    lo = m;
                if (m > hi)
                    hi = m;
            }
    f->mag_min = lo;
    f->mag_max = hi;
    *out = f;
    return 0;
}

int lc_field_create_grid(const char *name, lc_field_kind kind, const uint32_t dims[3], double *coords[3],
                         float *vectors, lc_field **out, lc_error *err)
{
    *out = NULL;
    const char *nm = name ? name : "field";
    lc_field *f = field_new(name);
    if (!f) {
        for (int a = 0; a < 3; a++)
            free(coords[a]);
        free(vectors);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", nm);
    }
    f->kind = kind == LC_FIELD_UNIFORM ? LC_FIELD_UNIFORM : LC_FIELD_RECTILINEAR;
    for (int a = 0; a < 3; a++) {
        f->dims[a] = dims[a];
        f->coords[a] = coords[a];
    }
    f->vectors = vectors;
    uint64_t nodes = (uint64_t)dims[0] * dims[1] * dims[2];
    for (int a = 0; a < 3; a++) {
        if (dims[a] < 2 || !coords[a]) {
            lc_field_destroy(f);
            return lc_err(err, LC_ERR_INVALID, "%s: the grid needs at least 2 nodes on axis %c (has %u)", nm, "xyz"[a],
                          dims[a]);
        }
        for (uint32_t i = 0; i < dims[a]; i++)
            if (!isfinite(coords[a][i]) || (i && !(coords[a][i] > coords[a][i - 1]))) {
                double bad = coords[a][i]; /* read before the arrays go with f */
                lc_field_destroy(f);
                return lc_err(err, LC_ERR_INVALID, "%s: %c coordinate %u (%g) is not finite or not increasing", nm,
                              "xyz"[a], i, bad);
            }
        f->bounds[a] = coords[a][0];
        f->bounds[a + 3] = coords[a][dims[a] - 1];
    }
    if (nodes > LC_FIELD_MAX_NODES || !vectors) {
        lc_field_destroy(f);
        return lc_err(err, LC_ERR_LIMIT, "%s: %llu grid nodes exceed the limit of %llu", nm, (unsigned long long)nodes,
                      (unsigned long long)LC_FIELD_MAX_NODES);
    }
    double lo = INFINITY, hi = 0.0;
    for (uint64_t i = 0; i < nodes; i++) {
        float *q = vectors + 3 * i;
        if (!isfinite(q[0]) || !isfinite(q[1]) || !isfinite(q[2]))
            q[0] = q[1] = q[2] = 0.0f;
        double m = sqrt((double)q[0] * q[0] + (double)q[1] * q[1] + (double)q[2] * q[2]);
        if (m < lo)
            lo = m;
        if (m > hi)
            hi = m;
    }
    f->mag_min = lo;
    f->mag_max = hi;
    *out = f;
    return 0;
}
