/* Seeding of streamline sets: points, rakes, Halton boxes and density-driven
 * evenly spaced seeds, traced with trace.c (seeding.h). */
#include "seeding.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void lc_seeding_rake(const double a[3], const double b[3], uint32_t count, double *out)
{
    for (uint32_t i = 0; i < count; i++) {
        double f = count > 1 ? (double)i / (count - 1) : 0.5;
        for (int k = 0; k < 3; k++)
            out[3 * (size_t)i + k] = a[k] + (b[k] - a[k]) * f;
    }
}

/* The radical inverse of n in base b. */
static double radical_inverse(uint64_t n, unsigned b)
{
    double u = 0.0, scale = 1.0 / b;
    for (; n; n /= b, scale /= b)
        u += (double)(n % b) * scale;
    return u;
}

void lc_seeding_halton(const double lo[3], const double hi[3], uint64_t k, double out[3])
{
    static const unsigned bases[3] = {2, 3, 5};
    for (int a = 0; a < 3; a++)
        out[a] = lo[a] + (hi[a] - lo[a]) * radical_inverse(k + 1, bases[a]);
}

/* The box of box and density seeding: desc's corners, or the field's bounds
 * when both are all zero. */
static void seeding_box(const lc_field *f, const lc_seeding_desc *d, double lo[3], double hi[3])
{
    int given = 0;
    for (int a = 0; a < 3; a++)
        given |= d->from[a] != 0 || d->to[a] != 0;
    for (int a = 0; a < 3; a++) {
        lo[a] = given ? d->from[a] : f->bounds[a];
        hi[a] = given ? d->to[a] : f->bounds[3 + a];
    }
}

static uint32_t wanted(const lc_seeding_desc *d)
{
    return d->kind == LC_SEEDING_POINTS ? d->point_count : d->count ? d->count : 64;
}

/* The default d_sep: half the edge of the cube each of n seeds would own. */
static double default_separation(const double lo[3], const double hi[3], uint32_t n)
{
    double vol = 1.0, diag = 0.0;
    for (int a = 0; a < 3; a++) {
        double e = hi[a] - lo[a];
        diag += e * e;
        vol *= e > 0 ? e : 1.0;
    }
    double s = 0.5 * cbrt(vol / (n ? n : 1));
    return s > 0 && isfinite(s) ? s : 0.01 * sqrt(diag);
}

int lc_seeding_check(const lc_field *f, const lc_seeding_desc *d, lc_error *err)
{
    if (d->kind < LC_SEEDING_POINTS || d->kind > LC_SEEDING_DENSITY)
        return lc_err_field(err, LC_ERR_INVALID, "seeding.kind", "unknown seeding %d", (int)d->kind);
    if (d->kind == LC_SEEDING_POINTS) {
        if (!d->points || d->point_count < 1 || d->point_count > LC_SEEDING_MAX_LINES)
            return lc_err_field(err, LC_ERR_INVALID, "seeding.points", "%u points (1 to %d)", d->point_count,
                                LC_SEEDING_MAX_LINES);
        for (uint32_t i = 0; i < 3 * d->point_count; i++)
            if (!isfinite(d->points[i]))
                return lc_err_field(err, LC_ERR_INVALID, "seeding.points", "point %u is not finite", i / 3);
        return 0;
    }
    if (d->count > LC_SEEDING_MAX_LINES)
        return lc_err_field(err, LC_ERR_LIMIT, "seeding.count", "%u curves (at most %d)", d->count,
                            LC_SEEDING_MAX_LINES);
    for (int a = 0; a < 3; a++)
        if (!isfinite(d->from[a]) || !isfinite(d->to[a]))
            return lc_err_field(err, LC_ERR_INVALID, d->kind == LC_SEEDING_RAKE ? "seeding.rake" : "seeding.box",
                                "a corner is not finite");
    if (d->kind == LC_SEEDING_RAKE)
        return 0;
    double lo[3], hi[3];
    seeding_box(f, d, lo, hi);
    for (int a = 0; a < 3; a++)
        if (!(hi[a] > lo[a]))
            return lc_err_field(err, LC_ERR_INVALID, "seeding.box", "axis %c: max %g is not above min %g", "xyz"[a],
                                hi[a], lo[a]);
    if (d->kind == LC_SEEDING_DENSITY && (d->separation < 0 || !isfinite(d->separation)))
        return lc_err_field(err, LC_ERR_INVALID, "seeding.separation", "%g is not a positive distance", d->separation);
    return 0;
}

/* ---- density-driven seeding: the occupied set as a uniform grid of vertex lists */

typedef struct occupancy {
    double lo[3], cell, sep2;
    int dims[3];
    int32_t *head; /* first vertex of each cell, -1 = none */
    int32_t *next; /* the next vertex of the same cell */
    double *xyz;   /* 3 per vertex */
    uint32_t n, cap;
} occupancy;

static int occupancy_init(occupancy *o, const lc_field *f, double sep)
{
    memset(o, 0, sizeof *o);
    double ext = 0;
    for (int a = 0; a < 3; a++) {
        o->lo[a] = f->bounds[a];
        double e = f->bounds[3 + a] - f->bounds[a];
        ext = e > ext ? e : ext;
    }
    /* cells at least d_sep wide, so a vertex within d_sep lies in the 27 around */
    o->cell = sep > ext / 128 ? sep : ext / 128;
    o->sep2 = sep * sep;
    size_t cells = 1;
    for (int a = 0; a < 3; a++) {
        double e = f->bounds[3 + a] - f->bounds[a];
        o->dims[a] = (int)floor(e / o->cell) + 1;
        cells *= (size_t)o->dims[a];
    }
    o->head = malloc(cells * sizeof *o->head);
    if (!o->head)
        return LC_ERR_NOMEM;
    memset(o->head, 0xff, cells * sizeof *o->head);
    return 0;
}

static void cell_of(const occupancy *o, const double p[3], int c[3])
{
    for (int a = 0; a < 3; a++) {
        int i = (int)floor((p[a] - o->lo[a]) / o->cell);
        c[a] = i < 0 ? 0 : i >= o->dims[a] ? o->dims[a] - 1 : i;
    }
}

/* 1 when a vertex of the set lies closer to p than d_sep. */
static int occupied(const occupancy *o, const double p[3])
{
    int c[3];
    cell_of(o, p, c);
    for (int z = c[2] - 1; z <= c[2] + 1; z++)
        for (int y = c[1] - 1; y <= c[1] + 1; y++)
            for (int x = c[0] - 1; x <= c[0] + 1; x++) {
                if (x < 0 || y < 0 || z < 0 || x >= o->dims[0] || y >= o->dims[1] || z >= o->dims[2])
                    continue;
                for (int32_t v = o->head[((size_t)z * o->dims[1] + y) * o->dims[0] + x]; v >= 0; v = o->next[v]) {
                    const double *q = &o->xyz[3 * (size_t)v];
                    double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
                    if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < o->sep2)
                        return 1;
                }
            }
    return 0;
}

/* Adds a curve's vertices (as the floats the curve holds) to the set. */
static int occupy(occupancy *o, const lc_trace_curve *c)
{
    if (o->n + (uint64_t)c->n > INT32_MAX)
        return LC_ERR_LIMIT;
    if (o->n + c->n > o->cap) {
        uint32_t cap = o->cap ? o->cap : 1024;
        while (cap < o->n + c->n)
            cap *= 2;
        double *xyz = realloc(o->xyz, 3 * (size_t)cap * sizeof *xyz);
        if (xyz)
            o->xyz = xyz;
        int32_t *next = realloc(o->next, (size_t)cap * sizeof *next);
        if (next)
            o->next = next;
        if (!xyz || !next)
            return LC_ERR_NOMEM;
        o->cap = cap;
    }
    for (uint32_t i = 0; i < c->n; i++, o->n++) {
        double *q = &o->xyz[3 * (size_t)o->n];
        for (int a = 0; a < 3; a++)
            q[a] = c->xyz[3 * i + a];
        int cc[3];
        cell_of(o, q, cc);
        size_t cell = ((size_t)cc[2] * o->dims[1] + cc[1]) * o->dims[0] + cc[0];
        o->next[o->n] = o->head[cell];
        o->head[cell] = (int32_t)o->n;
    }
    return 0;
}

static void occupancy_free(occupancy *o)
{
    free(o->head);
    free(o->next);
    free(o->xyz);
}

/* Density seeding: candidates in Halton order, each traced only when it is
 * free (a sequential rule: every kept curve changes what is free). */
static int trace_density(const lc_field *f, const lc_seeding_desc *d, lc_trace_curve *curves, double *seeds,
                         uint32_t *kept, lc_seeding_stats *st, lc_error *err)
{
    uint32_t want = wanted(d);
    double lo[3], hi[3];
    seeding_box(f, d, lo, hi);
    double sep = d->separation > 0 ? d->separation : default_separation(lo, hi, want);
    st->separation = sep;
    occupancy o;
    if (occupancy_init(&o, f, sep))
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for the density grid", f->name);
    uint64_t tries = (uint64_t)LC_SEEDING_CANDIDATES * want;
    int rc = 0;
    *kept = 0;
    for (uint64_t k = 0; k < tries && *kept < want && !rc; k++) {
        double p[3], v[3];
        lc_seeding_halton(lo, hi, k, p);
        st->candidates++;
        if (!lc_field_sample(f, p, d->trace.t0 != 0 ? d->trace.t0 : f->t0, v) ||
            (v[0] == 0 && v[1] == 0 && v[2] == 0) || occupied(&o, p))
            continue;
        lc_trace_curve *c = &curves[*kept];
        rc = lc_trace_points(f, p, 1, &d->trace, 1, c, err);
        if (rc)
            break;
        if (occupy(&o, c)) {
            lc_trace_curves_free(c, 1);
            rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory for the density grid", f->name);
            break;
        }
        memcpy(&seeds[3 * (size_t)*kept], p, sizeof p);
        c->u = (double)*kept / (want > 1 ? want - 1 : 1);
        (*kept)++;
    }
    occupancy_free(&o);
    if (rc)
        lc_trace_curves_free(curves, *kept);
    return rc;
}

int lc_seeding_trace(const lc_field *f, const lc_seeding_desc *d, int threads, lc_trace_curve **curves_out,
                     uint32_t *count_out, double **seeds_out, lc_seeding_stats *stats, lc_error *err)
{
    *curves_out = NULL, *count_out = 0;
    if (seeds_out)
        *seeds_out = NULL;
    lc_seeding_stats st = {0};
    int rc = lc_seeding_check(f, d, err);
    if (rc)
        return rc;
    uint32_t n = wanted(d);
    double *seeds = malloc(3 * (size_t)n * sizeof *seeds);
    lc_trace_curve *curves = calloc(n, sizeof *curves);
    if (!seeds || !curves) {
        free(seeds), free(curves);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for %u curves", f->name, n);
    }
    if (d->kind == LC_SEEDING_DENSITY) {
        rc = trace_density(f, d, curves, seeds, &n, &st, err);
    } else {
        if (d->kind == LC_SEEDING_POINTS)
            memcpy(seeds, d->points, 3 * (size_t)n * sizeof *seeds);
        else if (d->kind == LC_SEEDING_RAKE)
            lc_seeding_rake(d->from, d->to, n, seeds);
        else {
            double lo[3], hi[3];
            seeding_box(f, d, lo, hi);
            for (uint32_t k = 0; k < n; k++)
                lc_seeding_halton(lo, hi, k, &seeds[3 * (size_t)k]);
        }
        st.candidates = n;
        rc = lc_trace_points(f, seeds, n, &d->trace, threads, curves, err);
    }
    if (rc) {
        free(seeds), free(curves);
        return rc;
    }
    *curves_out = curves, *count_out = n;
    if (seeds_out)
        *seeds_out = seeds;
    else
        free(seeds);
    if (stats)
        *stats = st;
    return 0;
}
