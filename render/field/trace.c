/* Particle tracing for integral surfaces and streamline sets: seed sampling,
 * RK4 forward, backward or both ways with ghost particles for normals, curves
 * traced on CPU threads (trace.h). */
#include "trace.h"
#include "lc_parallel.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double norm3(const double a[3]) { return sqrt(dot3(a, a)); }
static void cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static double diagonal(const lc_field *f)
{
    double d[3] = {f->bounds[3] - f->bounds[0], f->bounds[4] - f->bounds[1], f->bounds[5] - f->bounds[2]};
    return norm3(d);
}

int lc_seed_check(lc_seed *seed, const lc_field *field, lc_error *err)
{
    if (seed->count < 2 || seed->count > LC_SEED_MAX_POINTS)
        return lc_err_field(err, LC_ERR_INVALID, "seed.points", "%d points (2 to %d)", seed->count, LC_SEED_MAX_POINTS);
    seed->length = 0;
    for (int i = 0; i < seed->count; i++) {
        const double *p = seed->points[i];
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
            return lc_err_field(err, LC_ERR_INVALID, "seed.points", "point %d is not finite", i);
        if (i) {
            double d[3] = {p[0] - seed->points[i - 1][0], p[1] - seed->points[i - 1][1], p[2] - seed->points[i - 1][2]};
            double len = norm3(d);
            if (!(len > 0))
                return lc_err_field(err, LC_ERR_INVALID, "seed.points", "point %d repeats point %d", i, i - 1);
            seed->length += len;
        }
        seed->cumulative[i] = seed->length;
    }
    if (field && !lc_field_contains(field, seed->points[0]))
        return lc_err_field(err, LC_ERR_INVALID, "seed.points",
                            "point 0 (%g, %g, %g) lies outside %s's domain [%g, %g] x [%g, %g] x [%g, %g]",
                            seed->points[0][0], seed->points[0][1], seed->points[0][2], field->name, field->bounds[0],
                            field->bounds[3], field->bounds[1], field->bounds[4], field->bounds[2], field->bounds[5]);
    return 0;
}

int lc_seed_parse(const char *text, lc_seed *seed, const lc_field *field, lc_error *err)
{
    memset(seed, 0, sizeof *seed);
    const char *p = text;
    while (*p) {
        if (seed->count >= LC_SEED_MAX_POINTS)
            return lc_err_field(err, LC_ERR_INVALID, "seed.points", "more than %d points", LC_SEED_MAX_POINTS);
        double *q = seed->points[seed->count];
        for (int a = 0; a < 3; a++) {
            char *end;
            q[a] = strtod(p, &end);
            char want = a < 2 ? ',' : ';';
            if (end == p || (*end != want && !(a == 2 && *end == '\0')))
                return lc_err_field(err, LC_ERR_INVALID, "seed.points",
                                    "point %d: expected x,y,z numbers separated by ';' at '%.20s'", seed->count, p);
            p = *end ? end + 1 : end;
        }
        seed->count++;
    }
    return lc_seed_check(seed, field, err);
}

double lc_seed_param(uint64_t k)
{
    uint64_t n = k + 1;
    double u = 0.0, scale = 0.5;
    for (; n; n >>= 1, scale *= 0.5)
        if (n & 1)
            u += scale;
    return u;
}

void lc_seed_at(const lc_seed *seed, double u, double p[3], double tangent[3])
{
    double s = (u < 0 ? 0 : u > 1 ? 1 : u) * seed->length;
    int i = 1;
    while (i < seed->count - 1 && seed->cumulative[i] < s)
        i++;
    const double *a = seed->points[i - 1], *b = seed->points[i];
    double len = seed->cumulative[i] - seed->cumulative[i - 1], f = (s - seed->cumulative[i - 1]) / len;
    for (int k = 0; k < 3; k++) {
        p[k] = a[k] + (b[k] - a[k]) * f;
        tangent[k] = (b[k] - a[k]) / len;
    }
}

void lc_trace_resolve(const lc_field *field, const lc_trace_desc *desc, lc_trace_desc *out)
{
    *out = desc ? *desc : (lc_trace_desc){0};
    double diag = diagonal(field), vmax = field->mag_max > 0 ? field->mag_max : 1.0;
    if (out->step < 0) { /* a negative step integrates into the past */
        out->step = -out->step;
        out->direction = out->direction == LC_TRACE_BACKWARD  ? LC_TRACE_FORWARD
                         : out->direction == LC_TRACE_FORWARD ? LC_TRACE_BACKWARD
                                                              : LC_TRACE_BOTH;
    }
    if (!(out->step > 0))
        out->step = diag / (200.0 * vmax);
    if (!(out->max_length > 0))
        out->max_length = 2.0 * diag;
    if (!(out->max_time > 0))
        out->max_time = field->time_dependent ? field->t1 - field->t0 : INFINITY;
    if (out->max_steps <= 0 || out->max_steps > LC_TRACE_MAX_STEPS)
        out->max_steps = LC_TRACE_MAX_STEPS;
    if (!(out->ghost_delta > 0))
        out->ghost_delta = 1e-5 * diag;
    if (!isfinite(out->t0) || out->t0 == 0)
        out->t0 = field->t0;
    if (!(out->step_units > 0))
        out->step_units = LC_TRACE_STEP_UNITS;
}

/* Charges steps to d->work; nonzero once the budget is exceeded (by any thread). */
static int charge_steps(const lc_trace_desc *d, int steps)
{
    return d->work ? lc_work_charge(d->work, steps * d->step_units) : 0;
}

/* One RK4 step of h from (p, t); 0 when a stage leaves the domain. */
static int rk4(const lc_field *f, double p[3], double t, double h)
{
    double k1[3], k2[3], k3[3], k4[3], q[3];
    if (!lc_field_sample(f, p, t, k1))
        return 0;
    for (int a = 0; a < 3; a++)
        q[a] = p[a] + 0.5 * h * k1[a];
    if (!lc_field_sample(f, q, t + 0.5 * h, k2))
        return 0;
    for (int a = 0; a < 3; a++)
        q[a] = p[a] + 0.5 * h * k2[a];
    if (!lc_field_sample(f, q, t + 0.5 * h, k3))
        return 0;
    for (int a = 0; a < 3; a++)
        q[a] = p[a] + h * k3[a];
    if (!lc_field_sample(f, q, t + h, k4))
        return 0;
    for (int a = 0; a < 3; a++)
        q[a] = p[a] + h / 6.0 * (k1[a] + 2 * k2[a] + 2 * k3[a] + k4[a]);
    if (!lc_field_contains(f, q))
        return 0;
    memcpy(p, q, sizeof q);
    return 1;
}

static int push(lc_trace_curve *c, uint32_t *cap, const double p[3], const double n[3], double t, double speed)
{
    if (c->n == *cap) {
        uint32_t nc = *cap ? *cap * 2 : 64;
        float *xyz = realloc(c->xyz, 3 * (size_t)nc * sizeof *xyz);
        if (xyz)
            c->xyz = xyz;
        float *nrm = realloc(c->normal, 3 * (size_t)nc * sizeof *nrm);
        if (nrm)
            c->normal = nrm;
        float *tm = realloc(c->time, (size_t)nc * sizeof *tm);
        if (tm)
            c->time = tm;
        float *sp = realloc(c->speed, (size_t)nc * sizeof *sp);
        if (sp)
            c->speed = sp;
        if (!xyz || !nrm || !tm || !sp)
            return LC_ERR_NOMEM;
        *cap = nc;
    }
    for (int a = 0; a < 3; a++) {
        c->xyz[3 * c->n + a] = (float)p[a];
        c->normal[3 * c->n + a] = (float)n[a];
    }
    c->time[c->n] = (float)t;
    c->speed[c->n] = (float)speed;
    c->n++;
    return 0;
}

/* The normal at p: cross(v, d) normalized, or the previous one where v or
 * the ghost's offset across the flow vanishes. */
static void normal_at(const double v[3], const double d[3], double n[3])
{
    double c[3];
    cross3(v, d, c);
    double len = norm3(c);
    if (len > 1e-300 && isfinite(len))
        for (int a = 0; a < 3; a++)
            n[a] = c[a] / len;
}

/* One direction of a particle from p (ghost offset along `across`, unit):
 * RK4 steps of sign * d->step appended to c after its seed vertex, which is
 * pushed first. The ghost's normal is cross(v, offset) with the field's v in
 * both directions, so the halves of a two-way curve agree at the seed. */
static int trace_half(const lc_field *f, const double seed_p[3], const double across[3], const lc_trace_desc *d,
                      double sign, lc_trace_curve *c, uint32_t *cap)
{
    double p[3] = {seed_p[0], seed_p[1], seed_p[2]}, g[3], v[3], n[3] = {0, 0, 1}, off[3];
    const double delta = d->ghost_delta;
    for (int a = 0; a < 3; a++)
        g[a] = p[a] + delta * across[a];
    double t = d->t0, length = 0.0;
    int inside = lc_field_sample(f, p, t, v);
    for (int a = 0; a < 3; a++)
        off[a] = g[a] - p[a];
    normal_at(v, off, n);
    if (push(c, cap, p, n, t, norm3(v)))
        return LC_ERR_NOMEM;
    if (!inside)
        return 0;
    int step = 0, charged = 0;
    for (; step < d->max_steps; step++) {
        /* Counted as it happens: a curve slower than the estimate assumed
         * (slow regions of the field) stops at the request's budget. */
        if (step - charged == LC_TRACE_CHARGE_STEPS) {
            if (charge_steps(d, step - charged))
                return LC_ERR_BUDGET;
            charged = step;
        }
        double prev[3] = {p[0], p[1], p[2]};
        double h = d->step, elapsed = fabs(t - d->t0);
        if (elapsed + h > d->max_time)
            h = d->max_time - elapsed;
        if (!(h > 1e-9 * d->step) || !rk4(f, p, t, sign * h)) /* a remainder of rounding is no step */
            break;
        double moved[3] = {p[0] - prev[0], p[1] - prev[1], p[2] - prev[2]};
        length += norm3(moved);
        if (!rk4(f, g, t, sign * h)) /* the ghost left the domain: put it back beside the particle */
            for (int a = 0; a < 3; a++)
                g[a] = p[a] + off[a];
        t += sign * h;
        lc_field_sample(f, p, t, v);
        for (int a = 0; a < 3; a++)
            off[a] = g[a] - p[a];
        double dist = norm3(off);
        if (dist > delta * (1 + 1e-9)) {
            /* Pulled back to Δ, keeping only its offset across the flow: the
             * normal depends on that part alone, and a ghost left to drift
             * along the flow would make cross(v, d) ill-conditioned. */
            double speed = norm3(v), acr[3];
            double along = speed > 0 ? dot3(off, v) / (speed * speed) : 0.0;
            for (int a = 0; a < 3; a++)
                acr[a] = off[a] - along * v[a];
            double la = norm3(acr);
            const double *dir = la > 1e-12 * dist ? acr : off;
            double ld = la > 1e-12 * dist ? la : dist;
            for (int a = 0; a < 3; a++) {
                off[a] = delta * dir[a] / ld;
                g[a] = p[a] + off[a];
            }
            c->ghost_resets++;
        }
        normal_at(v, off, n);
        if (push(c, cap, p, n, t, norm3(v)))
            return LC_ERR_NOMEM;
        if (length >= d->max_length || fabs(t - d->t0) >= d->max_time || norm3(v) < 1e-12 * (f->mag_max + 1e-300)) {
            step++;
            break;
        }
    }
    return charge_steps(d, step - charged) ? LC_ERR_BUDGET : 0;
}

/* Reverses vertices [0, n) of c in place (a backward half runs from the seed
 * into the past; the joined curve runs from the past to the future). */
static void reverse_curve(lc_trace_curve *c)
{
    for (uint32_t i = 0, j = c->n ? c->n - 1 : 0; i < j; i++, j--) {
        for (int a = 0; a < 3; a++) {
            float x = c->xyz[3 * i + a];
            c->xyz[3 * i + a] = c->xyz[3 * j + a], c->xyz[3 * j + a] = x;
            x = c->normal[3 * i + a];
            c->normal[3 * i + a] = c->normal[3 * j + a], c->normal[3 * j + a] = x;
        }
        float x = c->time[i];
        c->time[i] = c->time[j], c->time[j] = x;
        x = c->speed[i];
        c->speed[i] = c->speed[j], c->speed[j] = x;
    }
}

/* A particle at p with its ghost along `across` into c (zeroed here), in
 * d->direction: forward, backward (ordered from the seed's past, the seed
 * last), or both (the backward half reversed, then the forward half without
 * its repeated seed vertex). */
static int trace_point(const lc_field *f, const double p[3], const double across[3], const lc_trace_desc *d,
                       lc_trace_curve *c)
{
    uint32_t cap = 0;
    memset(c, 0, sizeof *c);
    if (d->direction == LC_TRACE_FORWARD)
        return trace_half(f, p, across, d, 1.0, c, &cap);
    int rc = trace_half(f, p, across, d, -1.0, c, &cap);
    if (rc)
        return rc;
    reverse_curve(c);
    if (d->direction == LC_TRACE_BACKWARD)
        return 0;
    lc_trace_curve fwd;
    uint32_t fcap = 0;
    memset(&fwd, 0, sizeof fwd);
    rc = trace_half(f, p, across, d, 1.0, &fwd, &fcap);
    for (uint32_t i = 1; rc == 0 && i < fwd.n; i++) {
        double q[3] = {fwd.xyz[3 * i], fwd.xyz[3 * i + 1], fwd.xyz[3 * i + 2]};
        double nn[3] = {fwd.normal[3 * i], fwd.normal[3 * i + 1], fwd.normal[3 * i + 2]};
        rc = push(c, &cap, q, nn, fwd.time[i], fwd.speed[i]);
    }
    c->ghost_resets += fwd.ghost_resets;
    lc_trace_curves_free(&fwd, 1);
    return rc;
}

/* Traces the particle at seed parameter u (and its ghost) into c. */
static int trace_one(const lc_field *f, const lc_seed *seed, const lc_trace_desc *d, double u, lc_trace_curve *c)
{
    double p[3], tangent[3];
    lc_seed_at(seed, u, p, tangent);
    int rc = trace_point(f, p, tangent, d, c);
    c->u = u;
    return rc;
}

int lc_trace_curve_at(const lc_field *field, const lc_seed *seed, const lc_trace_desc *desc, double u,
                      lc_trace_curve *curve, lc_error *err)
{
    lc_trace_desc d;
    lc_trace_resolve(field, desc, &d);
    int rc = trace_one(field, seed, &d, u, curve);
    if (rc != 0) {
        lc_trace_curves_free(curve, 1);
        if (rc == LC_ERR_BUDGET)
            return lc_work_err(d.work, err, "tracing a curve");
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory tracing a curve", field->name);
    }
    return 0;
}

typedef struct trace_job {
    const lc_field *field;
    const lc_seed *seed;  /* particles along a seed polyline, or */
    const double *points; /* one particle per seed point (lc_trace_points) */
    const lc_trace_desc *desc;
    uint64_t first;
    uint32_t count;
    int stride, offset;
    lc_trace_curve *curves;
    int rc;
} trace_job;

/* Seed point i of count: its ghost starts across the flow (any direction
 * normal to v: a lone streamline has no seed curve to step along). */
static int trace_seed_point(const lc_field *f, const double p[3], const lc_trace_desc *d, uint32_t count, uint32_t i,
                            lc_trace_curve *c)
{
    double v[3], across[3] = {1, 0, 0};
    lc_field_sample(f, p, d->t0, v);
    int least = fabs(v[0]) <= fabs(v[1]) && fabs(v[0]) <= fabs(v[2]) ? 0 : fabs(v[1]) <= fabs(v[2]) ? 1 : 2;
    double e[3] = {0, 0, 0}, x[3];
    e[least] = 1;
    cross3(v, e, x);
    double len = norm3(x);
    if (len > 0 && isfinite(len))
        for (int a = 0; a < 3; a++)
            across[a] = x[a] / len;
    int rc = trace_point(f, p, across, d, c);
    c->u = count > 1 ? (double)i / (count - 1) : 0.0;
    return rc;
}

static void run_job(void *arg)
{
    trace_job *j = arg;
    for (uint32_t i = (uint32_t)j->offset; i < j->count && !j->rc; i += (uint32_t)j->stride)
        j->rc = j->points ? trace_seed_point(j->field, &j->points[3 * (size_t)i], j->desc, j->count, i, &j->curves[i])
                          : trace_one(j->field, j->seed, j->desc, lc_seed_param(j->first + i), &j->curves[i]);
}

#define MAX_TRACE_THREADS LC_PARALLEL_MAX

/* Traces count curves on threads: particles of seed (from lc_seed_param(first))
 * or, with points, one per seed point. */
static int trace_many(const lc_field *field, const lc_seed *seed, const double *points, const lc_trace_desc *desc,
                      uint64_t first, uint32_t count, int threads, lc_trace_curve *curves, lc_error *err)
{
    memset(curves, 0, (size_t)count * sizeof *curves);
    lc_trace_desc d;
    lc_trace_resolve(field, desc, &d);
    int nt = threads < 1 ? 1 : threads > MAX_TRACE_THREADS ? MAX_TRACE_THREADS : threads;
    if ((uint32_t)nt > count)
        nt = count ? (int)count : 1;
    trace_job jobs[MAX_TRACE_THREADS];
    for (int k = 0; k < nt; k++)
        jobs[k] = (trace_job){field, seed, points, &d, first, count, nt, k, curves, 0};
    lc_parallel_for((uint32_t)nt, run_job, jobs, sizeof jobs[0]);
    int rc = 0;
    for (int k = 0; k < nt; k++)
        if (!rc || rc == LC_ERR_BUDGET) /* out of memory says more than the budget another thread saw */
            rc = jobs[k].rc ? jobs[k].rc : rc;
    if (rc) {
        lc_trace_curves_free(curves, count);
        if (rc == LC_ERR_BUDGET) {
            char what[64];
            snprintf(what, sizeof what, "tracing %u curves", count);
            return lc_work_err(d.work, err, what);
        }
        return lc_err(err, rc, "%s: out of memory tracing %u curves", field->name, count);
    }
    return 0;
}

int lc_trace_curves(const lc_field *field, const lc_seed *seed, const lc_trace_desc *desc, uint64_t first,
                    uint32_t count, int threads, lc_trace_curve *curves, lc_error *err)
{
    return trace_many(field, seed, NULL, desc, first, count, threads, curves, err);
}

int lc_trace_points(const lc_field *field, const double *points, uint32_t count, const lc_trace_desc *desc, int threads,
                    lc_trace_curve *curves, lc_error *err)
{
    return trace_many(field, NULL, points, desc, 0, count, threads, curves, err);
}

void lc_trace_curves_free(lc_trace_curve *curves, uint32_t count)
{
    for (uint32_t i = 0; curves && i < count; i++) {
        free(curves[i].xyz);
        free(curves[i].normal);
        free(curves[i].time);
        free(curves[i].speed);
        memset(&curves[i], 0, sizeof curves[i]);
    }
}
