/* `lucent gen FIELD --seed-line ...`: the curves of render/field/trace.c from a
 * seed polyline, or with --seeding a streamline set (render/field/seeding.c),
 * written as a line dataset, or with --mesh the meshed reference of
 * render/field/stream_mesh.c as a triangle dataset (cli.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "seeding.h"
#include "stream_mesh.h"
#include "streamlines.h"
#include "trace.h"
#include "vtk_field.h"

/* Opens the field spec and parses the --seed-line text against it; *f is
 * NULL when the field did not open, else the caller's (also when the seed
 * was refused: rc says so). */
static int open_field_seed(const char *spec, const char *seed_text, lc_field **f, lc_seed *seed, lc_error *err)
{
    int rc = lc_field_open(spec, f, err);
    if (rc)
        return rc;
    if (!seed_text)
        return lc_err_field(err, LC_ERR_INVALID, "seed.points", "%s is a vector field: give --seed-line X,Y,Z;X,Y,Z",
                            spec);
    return lc_seed_parse(seed_text, seed, *f, err);
}

/* Parses "x,y,z;x,y,z..." into a malloc'd array of 3 * *n doubles (at most
 * max points). Errors name flag. */
static int parse_points(const char *text, const char *flag, uint32_t max, double **out, uint32_t *n, lc_error *err)
{
    *out = NULL, *n = 0;
    double *pts = malloc(3 * (size_t)max * sizeof *pts);
    if (!pts)
        return lc_err(err, LC_ERR_NOMEM, "out of memory for %s", flag);
    const char *p = text;
    while (*p) {
        if (*n >= max) {
            free(pts);
            return lc_err(err, LC_ERR_INVALID, "%s: more than %u points", flag, max);
        }
        double *q = &pts[3 * (size_t)*n];
        int used = 0;
        if (sscanf(p, " %lf , %lf , %lf %n", &q[0], &q[1], &q[2], &used) != 3 || (p[used] != ';' && p[used] != '\0')) {
            free(pts);
            return lc_err(err, LC_ERR_INVALID, "%s: point %u: expected x,y,z numbers separated by ';' at '%.20s'", flag,
                          *n, p);
        }
        (*n)++;
        p += used + (p[used] == ';');
    }
    *out = pts;
    return 0;
}

static int parse_seeding(const char *kind, const char *direction, lc_seeding_desc *d, lc_error *err)
{
    static const char *const kinds[] = {"points", "rake", "box", "density"};
    static const char *const dirs[] = {"forward", "backward", "both"};
    int k = -1, dir = 0;
    for (int i = 0; kind && i < 4; i++)
        if (strcmp(kind, kinds[i]) == 0)
            k = i;
    if (kind && k < 0)
        return lc_err(err, LC_ERR_INVALID, "--seeding: '%s' is not points, rake, box or density", kind);
    if (direction) {
        dir = -1;
        for (int i = 0; i < 3; i++)
            if (strcmp(direction, dirs[i]) == 0)
                dir = i;
        if (dir < 0)
            return lc_err(err, LC_ERR_INVALID, "--direction: '%s' is not forward, backward or both", direction);
    }
    d->kind = k < 0 ? LC_SEEDING_POINTS : (lc_seeding_kind)k;
    d->trace.direction = (lc_trace_direction)dir;
    return 0;
}

int lc_cli_trace_scene(const char *spec, const char *seed_text, const lc_cli_streamlines *sl, lc_scene **out,
                       lc_error *err)
{
    *out = NULL;
    lc_field *f = NULL;
    lc_seed seed;
    int set = sl->seeding != NULL; /* a streamline set, not the curves of a seed line */
    int rc = set ? lc_field_open(spec, &f, err) : open_field_seed(spec, seed_text, &f, &seed, err);
    if (!f)
        return rc;
    lc_seeding_desc sd = {.count = sl->curves, .separation = sl->separation};
    if (!rc)
        rc = parse_seeding(sl->seeding, sl->direction, &sd, err);
    sd.trace.step = sl->step, sd.trace.max_length = sl->length;
    double *pts = NULL;
    uint32_t npts = 0;
    if (!rc && set) {
        if (!sl->seeds && sd.kind != LC_SEEDING_BOX && sd.kind != LC_SEEDING_DENSITY)
            rc = lc_err(err, LC_ERR_INVALID, "--seeding %s needs --seeds X,Y,Z;X,Y,Z", sl->seeding);
        else if (sl->seeds)
            rc = parse_points(sl->seeds, "--seeds", LC_SEEDING_MAX_LINES, &pts, &npts, err);
        if (!rc && sd.kind != LC_SEEDING_POINTS && sl->seeds && npts != 2)
            rc = lc_err(err, LC_ERR_INVALID, "--seeds: %s takes two points (%s), not %u",
                        sd.kind == LC_SEEDING_RAKE ? "a rake" : "a box",
                        sd.kind == LC_SEEDING_RAKE ? "its ends" : "its corners", npts);
        if (!rc && sd.kind == LC_SEEDING_POINTS)
            sd.points = pts, sd.point_count = npts;
        else if (!rc && pts)
            for (int a = 0; a < 3; a++)
                sd.from[a] = pts[a], sd.to[a] = pts[3 + a];
    }
    uint32_t curves = set ? 0 : sl->curves;
    lc_trace_curve *c = NULL;
    if (!rc && !set && !(c = calloc(curves, sizeof *c)))
        rc = lc_err(err, LC_ERR_NOMEM, "out of memory for %u curves", curves);
    if (!rc) {
        long cpus = sysconf(_SC_NPROCESSORS_ONLN);
        int threads = cpus > 0 ? (int)cpus : 1;
        double t0 = lc_now();
        lc_seeding_stats st = {0};
        rc = set ? lc_seeding_trace(f, &sd, threads, &c, &curves, NULL, &st, err)
                 : lc_trace_curves(f, &seed, &sd.trace, 0, curves, threads, c, err);
        uint64_t vertices = 0;
        for (uint32_t i = 0; !rc && i < curves; i++)
            vertices += c[i].n;
        if (!rc) /* the tracer alone, without the scene's finalize and the writer */
            printf("traced %u curves (%llu vertices) in %.1f ms on %d thread(s)%s\n", curves,
                   (unsigned long long)vertices, (lc_now() - t0) * 1e3, threads,
                   sd.kind == LC_SEEDING_DENSITY && set ? " (density: one thread, sequential)" : "");
        if (!rc && set && sd.kind == LC_SEEDING_DENSITY)
            printf("density seeding: %u of %u candidates kept at separation %g\n", curves, st.candidates,
                   st.separation);
    }
    if (!rc) {
        char name[160];
        snprintf(name, sizeof name, "%s-%s", f->name, set ? "streamlines" : "curves");
        rc = lc_streamlines_scene(name, c, curves, f, out, err);
    }
    if (c)
        lc_trace_curves_free(c, curves);
    free(c);
    free(pts);
    lc_field_destroy(f);
    return rc;
}

int lc_cli_mesh_scene(const char *spec, const char *seed_text, double split, double step, double length, lc_scene **out,
                      lc_error *err)
{
    *out = NULL;
    lc_field *f = NULL;
    lc_seed seed;
    int rc = open_field_seed(spec, seed_text, &f, &seed, err);
    if (!f)
        return rc;
    lc_stream_mesh m = {0};
    lc_stream_mesh_desc desc = {.trace = {.step = step, .max_length = length}, .split = split};
    double t0 = lc_now();
    if (!rc && (rc = lc_stream_mesh_build(f, &seed, &desc, &m, err)) == 0)
        printf("meshed %u particles: %u vertices, %u triangles in %.1f ms\n", m.particles, m.vertex_count,
               m.triangle_count, (lc_now() - t0) * 1e3);
    if (!rc && m.triangle_count == 0)
        rc = lc_err(err, LC_ERR_INVALID,
                    "%s: the surface has no triangle (does the seed line lie in a stalled region?)", spec);
    if (!rc && m.vertex_count > LC_MAX_VERTICES)
        rc = lc_err(err, LC_ERR_LIMIT, "%s: %u vertices exceed the limit of %u", spec, m.vertex_count,
                    (unsigned)LC_MAX_VERTICES);
    lc_scene *s = NULL;
    if (!rc) {
        char name[160];
        snprintf(name, sizeof name, "%s-mesh", f->name);
        s = lc_scene_create(name, LC_PRIM_TRIANGLES);
        if (!s)
            rc = lc_err(err, LC_ERR_NOMEM, "out of memory");
    }
    if (!rc) { /* the scene takes the arrays */
        s->positions = m.xyz, s->vertex_count = m.vertex_count;
        s->triangles = m.triangles, s->triangle_count = m.triangle_count;
        m.xyz = NULL, m.triangles = NULL;
        rc = lc_scene_finalize(s, NULL, err);
    }
    lc_stream_mesh_free(&m);
    lc_field_destroy(f);
    if (rc) {
        lc_scene_destroy(s);
        return rc;
    }
    *out = s;
    return 0;
}
