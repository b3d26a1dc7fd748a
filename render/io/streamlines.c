/* Streamline-set datasets: the "streamlines:FIELD?..." spec parsed, the set
 * traced with seeding.c and turned into a line scene (streamlines.h). */
#include "streamlines.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "seeding.h"
#include "vtk_field.h"

int lc_streamlines_is_spec(const char *spec)
{
    return spec && strncmp(spec, LC_STREAMLINES_PREFIX, strlen(LC_STREAMLINES_PREFIX)) == 0;
}

int lc_streamlines_scene(const char *name, const lc_trace_curve *c, uint32_t count, const lc_field *f, lc_scene **out,
                         lc_error *err)
{
    uint64_t nv = 0;
    uint32_t lines = 0;
    for (uint32_t i = 0; i < count; i++)
        if (c[i].n >= 2)
            nv += c[i].n, lines++;
    if (lines == 0)
        return lc_err(err, LC_ERR_INVALID,
                      "%s: no curve has two vertices (does the seed line lie in a stalled region?)", name);
    if (nv > LC_MAX_VERTICES)
        return lc_err(err, LC_ERR_LIMIT, "%s: %llu vertices exceed the limit of %u", name, (unsigned long long)nv,
                      (unsigned)LC_MAX_VERTICES);
    static const char *const names[] = {"time", "speed", "seed_u", "normal_x", "normal_y", "normal_z", "vorticity"};
    const int nattr = f ? 7 : 6; /* the vorticity |curl v| where the field is at hand */
    lc_scene *s = lc_scene_create(name, LC_PRIM_LINES);
    float *attr[7] = {0};
    if (s) {
        s->positions = malloc(3 * nv * sizeof *s->positions);
        s->line_offsets = malloc(((size_t)lines + 1) * sizeof *s->line_offsets);
        for (int k = 0; k < nattr; k++)
            attr[k] = malloc(nv * sizeof *attr[k]);
    }
    int ok = s && s->positions && s->line_offsets;
    for (int k = 0; k < nattr; k++)
        ok = ok && attr[k];
    if (!ok) {
        for (int k = 0; k < nattr; k++)
            free(attr[k]);
        lc_scene_destroy(s);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for %llu vertices", name, (unsigned long long)nv);
    }
    uint32_t v = 0, l = 0;
    for (uint32_t i = 0; i < count; i++) {
        if (c[i].n < 2)
            continue;
        s->line_offsets[l++] = v;
        memcpy(s->positions + 3 * (size_t)v, c[i].xyz, 3 * (size_t)c[i].n * sizeof(float));
        for (uint32_t k = 0; k < c[i].n; k++, v++) {
            attr[0][v] = c[i].time[k];
            attr[1][v] = c[i].speed[k];
            attr[2][v] = (float)c[i].u;
            for (int a = 0; a < 3; a++)
                attr[3 + a][v] = c[i].normal[3 * k + a];
            if (f) { /* FOO §5.5.5's vorticity: |curl v| where the particle is, at its time */
                const double p[3] = {c[i].xyz[3 * k], c[i].xyz[3 * k + 1], c[i].xyz[3 * k + 2]};
                double w[3];
                lc_field_curl(f, p, c[i].time[k], w);
                attr[6][v] = (float)sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
            }
        }
    }
    s->line_offsets[lines] = v;
    s->vertex_count = v;
    s->line_count = lines;
    int rc = 0;
    for (int k = 0; k < nattr; k++) {
        if (rc == 0) {
            int idx = lc_scene_add_attribute(s, names[k], attr[k], err);
            rc = idx < 0 ? idx : 0;
        } else {
            free(attr[k]);
        }
    }
    if (rc == 0) {
        snprintf(s->default_importance, sizeof s->default_importance, "speed");
        s->trajectory.no_rates = 1; /* seed_u and the normals are the tracer's, not data to differentiate */
        rc = lc_scene_finalize(s, NULL, err);
    }
    if (rc) {
        lc_scene_destroy(s);
        return rc;
    }
    *out = s;
    return 0;
}

#define MAX_SEEDS 4096 /* points of a spec's seeds= (a URL-sized list) */

/* The spec's settings; points owned. */
typedef struct spec_args {
    char field[512];
    lc_seeding_desc d;
    double *points;
    uint32_t npoints;
    int has_seeds;
} spec_args;

static int parse_points(const char *v, spec_args *a, lc_error *err)
{
    a->points = malloc(3 * MAX_SEEDS * sizeof *a->points);
    if (!a->points)
        return lc_err(err, LC_ERR_NOMEM, "out of memory for streamlines.seeds");
    const char *p = v;
    while (*p && *p != '&') {
        if (a->npoints >= MAX_SEEDS)
            return lc_err_field(err, LC_ERR_LIMIT, "streamlines.seeds", "more than %d points", MAX_SEEDS);
        double *q = &a->points[3 * (size_t)a->npoints];
        char *end = NULL;
        for (int k = 0; k < 3; k++) {
            q[k] = strtod(p, &end);
            if (end == p || !isfinite(q[k]) || (k < 2 && *end != ','))
                return lc_err_field(err, LC_ERR_INVALID, "streamlines.seeds",
                                    "point %u: expected x,y,z numbers separated by ';' at '%.20s'", a->npoints, p);
            p = end + (k < 2);
        }
        if (*p && *p != ';' && *p != '&')
            return lc_err_field(err, LC_ERR_INVALID, "streamlines.seeds",
                                "point %u: expected x,y,z numbers separated by ';' at '%.20s'", a->npoints, p);
        a->npoints++;
        p += *p == ';';
    }
    a->has_seeds = 1;
    return 0;
}

/* The value of key=VALUE up to the next '&' as a number in [lo, hi]. */
static int number(const char *key, const char *v, double lo, double hi, double *out, lc_error *err)
{
    char *end = NULL;
    double x = strtod(v, &end);
    char field[48];
    snprintf(field, sizeof field, "streamlines.%s", key);
    if (end == v || (*end && *end != '&') || !isfinite(x) || x < lo || x > hi)
        return lc_err_field(err, LC_ERR_INVALID, field, "'%.*s' is not a number in [%g, %g]", (int)strcspn(v, "&"), v,
                            lo, hi);
    *out = x;
    return 0;
}

/* One of names (NULL-terminated) as its index. */
static int word(const char *key, const char *v, const char *const *names, int *out, lc_error *err)
{
    size_t n = strcspn(v, "&");
    for (int i = 0; names[i]; i++)
        if (strlen(names[i]) == n && strncmp(v, names[i], n) == 0) {
            *out = i;
            return 0;
        }
    char field[48];
    snprintf(field, sizeof field, "streamlines.%s", key);
    return lc_err_field(err, LC_ERR_INVALID, field, "'%.*s' is not one of %s, %s, %s%s%s", (int)n, v, names[0],
                        names[1], names[2], names[3] ? ", " : "", names[3] ? names[3] : "");
}

static int parse_spec(const char *spec, spec_args *a, lc_error *err)
{
    memset(a, 0, sizeof *a);
    a->d.kind = LC_SEEDING_DENSITY;
    const char *s = spec + strlen(LC_STREAMLINES_PREFIX);
    size_t flen = strcspn(s, "?");
    if (flen == 0 || flen >= sizeof a->field)
        return lc_err_field(err, LC_ERR_INVALID, "streamlines.field",
                            "%s: name a vector field, e.g. streamlines:demo:abc-flow?seeding=rake&seeds=1,1,1;5,5,5",
                            spec);
    memcpy(a->field, s, flen);
    a->field[flen] = '\0';
    static const char *const kinds[] = {"points", "rake", "box", "density", NULL};
    static const char *const dirs[] = {"forward", "backward", "both", NULL, NULL};
    for (const char *p = s[flen] == '?' ? s + flen + 1 : s + flen; *p;) {
        size_t klen = strcspn(p, "=&");
        if (p[klen] != '=')
            return lc_err_field(err, LC_ERR_INVALID, "streamlines", "%.*s: expected key=value", (int)klen, p);
        char key[24];
        snprintf(key, sizeof key, "%.*s", (int)(klen < sizeof key - 1 ? klen : sizeof key - 1), p);
        const char *v = p + klen + 1;
        int rc, k = 0;
        double x = 0;
        if (strcmp(key, "seeding") == 0)
            rc = word(key, v, kinds, &k, err), a->d.kind = (lc_seeding_kind)k;
        else if (strcmp(key, "direction") == 0)
            rc = word(key, v, dirs, &k, err), a->d.trace.direction = (lc_trace_direction)k;
        else if (strcmp(key, "seeds") == 0)
            rc = a->has_seeds ? lc_err_field(err, LC_ERR_INVALID, "streamlines.seeds", "given twice")
                              : parse_points(v, a, err);
        else if (strcmp(key, "count") == 0)
            rc = number(key, v, 1, LC_SEEDING_MAX_LINES, &x, err), a->d.count = (uint32_t)x;
        else if (strcmp(key, "separation") == 0)
            rc = number(key, v, 1e-300, 1e300, &x, err), a->d.separation = x;
        else if (strcmp(key, "step") == 0)
            rc = number(key, v, -1e300, 1e300, &x, err), a->d.trace.step = x;
        else if (strcmp(key, "length") == 0)
            rc = number(key, v, 0, 1e300, &x, err), a->d.trace.max_length = x;
        else
            rc = lc_err_field(err, LC_ERR_INVALID, "streamlines",
                              "unknown key '%s' (seeding, seeds, count, direction, separation, step, length)", key);
        if (rc)
            return rc;
        p = v + strcspn(v, "&");
        p += *p == '&';
    }
    if (a->d.count && a->d.kind == LC_SEEDING_POINTS)
        return lc_err_field(err, LC_ERR_INVALID, "streamlines.count", "seeding=points traces one curve per seed");
    if (a->d.separation > 0 && a->d.kind != LC_SEEDING_DENSITY)
        return lc_err_field(err, LC_ERR_INVALID, "streamlines.separation",
                            "applies to seeding=density only (streamlines.seeding density)");
    if (a->d.kind == LC_SEEDING_POINTS) {
        if (!a->has_seeds)
            return lc_err_field(err, LC_ERR_INVALID, "streamlines.seeds", "seeding=points needs seeds=x,y,z;...");
        a->d.points = a->points, a->d.point_count = a->npoints;
    } else if (a->has_seeds || a->d.kind == LC_SEEDING_RAKE) {
        if (a->npoints != 2)
            return lc_err_field(err, LC_ERR_INVALID, "streamlines.seeds", "seeding=%s takes two points (%s), not %u",
                                kinds[a->d.kind], a->d.kind == LC_SEEDING_RAKE ? "its ends" : "its corners",
                                a->npoints);
        memcpy(a->d.from, a->points, sizeof a->d.from);
        memcpy(a->d.to, a->points + 3, sizeof a->d.to);
    }
    return 0;
}

double lc_streamlines_estimate(const lc_field *f, const lc_seeding_desc *d, double *steps)
{
    lc_trace_desc t;
    lc_trace_resolve(f, &d->trace, &t);
    uint32_t curves = d->kind == LC_SEEDING_POINTS ? d->point_count : d->count ? d->count : 64;
    double halves = t.direction == LC_TRACE_BOTH ? 2.0 : 1.0;
    double vmax = f->mag_max > 0 ? f->mag_max : 1.0;
    double s = fmin(t.max_length / (fabs(t.step) * vmax), (double)t.max_steps);
    if (steps)
        *steps = halves * s;
    return curves * halves * (s + 1);
}

/* The trace budget: refuses a set whose curves would hold more than
 * LC_STREAMLINES_MAX_VERTICES by the step estimate, and caps each curve's
 * steps so that no set can exceed it. */
static int budget(const lc_field *f, lc_seeding_desc *d, lc_error *err)
{
    lc_trace_desc t;
    lc_trace_resolve(f, &d->trace, &t);
    uint32_t curves = d->kind == LC_SEEDING_POINTS ? d->point_count : d->count ? d->count : 64;
    double halves = t.direction == LC_TRACE_BOTH ? 2.0 : 1.0;
    double steps = 0;
    double vertices = lc_streamlines_estimate(f, d, &steps);
    if (vertices > LC_STREAMLINES_MAX_VERTICES)
        return lc_err_field(err, LC_ERR_LIMIT, "streamlines.count",
                            "%u curves of up to %.0f steps (%.3g vertices) exceed the trace budget of %u vertices; "
                            "trace fewer or shorter curves (count, length) or a larger step",
                            curves, steps, vertices, (unsigned)LC_STREAMLINES_MAX_VERTICES);
    double cap = floor(LC_STREAMLINES_MAX_VERTICES / (curves * halves)) - 1;
    d->trace.max_steps = cap < t.max_steps ? (int)fmax(1, cap) : t.max_steps;
    return 0;
}

int lc_streamlines_trace(const lc_field *f, const lc_seeding_desc *desc, int threads, const char *name, lc_scene **out,
                         lc_error *err)
{
    *out = NULL;
    lc_seeding_desc d = *desc;
    int rc = budget(f, &d, err);
    lc_trace_curve *c = NULL;
    uint32_t n = 0;
    if (!rc)
        rc = lc_seeding_trace(f, &d, threads, &c, &n, NULL, NULL, err);
    if (!rc)
        rc = lc_streamlines_scene(name, c, n, f, out, err);
    if (c)
        lc_trace_curves_free(c, n);
    free(c);
    return rc;
}

/* Parses spec and checks its seeding against f (the keys of the spec named
 * in errors): *d points into a->points (free it after). */
static int open_spec(const char *spec, spec_args *a, const lc_field *f, lc_seeding_desc *d, lc_error *err)
{
    int rc = parse_spec(spec, a, err);
    if (rc)
        return rc;
    *d = a->d;
    lc_error e = {0};
    if (lc_seeding_check(f, d, &e) != 0) { /* the seeding's names turned into the spec's keys */
        const char *key = strcmp(e.field, "seeding.count") == 0        ? "streamlines.count"
                          : strcmp(e.field, "seeding.separation") == 0 ? "streamlines.separation"
                                                                       : "streamlines.seeds";
        return lc_err_field(err, e.code, key, "%s", e.msg);
    }
    return 0;
}

int lc_streamlines_check(const char *spec, const lc_field *f, double *vertices, double *steps, lc_error *err)
{
    spec_args a;
    lc_seeding_desc d;
    int rc = open_spec(spec, &a, f, &d, err);
    if (!rc) {
        double v = lc_streamlines_estimate(f, &d, steps);
        if (vertices)
            *vertices = v;
        rc = budget(f, &d, err);
    }
    free(a.points);
    return rc;
}

int lc_streamlines_load_field(const char *spec, const lc_field *f, int threads, lc_scene **out, lc_error *err)
{
    *out = NULL;
    spec_args a;
    lc_seeding_desc d;
    int rc = open_spec(spec, &a, f, &d, err);
    if (!rc) {
        char name[LC_NAME_LEN];
        snprintf(name, sizeof name, LC_STREAMLINES_PREFIX "%.*s", (int)(sizeof name - sizeof LC_STREAMLINES_PREFIX),
                 f->name);
        rc = lc_streamlines_trace(f, &d, threads, name, out, err);
    }
    free(a.points);
    return rc;
}

int lc_streamlines_load(const char *spec, int threads, lc_scene **out, lc_error *err)
{
    *out = NULL;
    spec_args a;
    int rc = parse_spec(spec, &a, err);
    lc_field *f = NULL;
    if (!rc && !lc_field_is_source(a.field))
        rc = lc_err_field(err, LC_ERR_NOT_FOUND, "streamlines.field",
                          "%s is no vector field (demo:abc-flow, ... or a "
                          "grid .vtk or .nc file)",
                          a.field);
    if (!rc)
        rc = lc_field_open(a.field, &f, err);
    free(a.points);
    if (!rc)
        rc = lc_streamlines_load_field(spec, f, threads, out, err);
    lc_field_destroy(f);
    return rc;
}
