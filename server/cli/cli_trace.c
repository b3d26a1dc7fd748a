/* `lucent gen FIELD --seed-line ...`: the curves of render/field/trace.c from a
 * seed polyline, written as a line dataset, or with --mesh the meshed
 * reference of render/field/stream_mesh.c as a triangle dataset (cli.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "stream_mesh.h"
#include "trace.h"
#include "vtk_field.h"

/* Moves count curves into a line scene with their time, speed, seed
 * parameter and ghost normal as attributes; frees the curves' arrays. */
static int curves_to_scene(const char *name, lc_trace_curve *c, uint32_t count, lc_scene **out, lc_error *err)
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
    static const char *const names[] = {"time", "speed", "seed_u", "normal_x", "normal_y", "normal_z"};
    lc_scene *s = lc_scene_create(name, LC_PRIM_LINES);
    float *attr[6] = {0};
    if (s) {
        s->positions = malloc(3 * nv * sizeof *s->positions);
        s->line_offsets = malloc(((size_t)lines + 1) * sizeof *s->line_offsets);
        for (int k = 0; k < 6; k++)
            attr[k] = malloc(nv * sizeof *attr[k]);
    }
    int ok = s && s->positions && s->line_offsets;
    for (int k = 0; k < 6; k++)
        ok = ok && attr[k];
    if (!ok) {
        for (int k = 0; k < 6; k++)
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
        }
    }
    s->line_offsets[lines] = v;
    s->vertex_count = v;
    s->line_count = lines;
    int rc = 0;
    for (int k = 0; k < 6; k++) {
        if (rc == 0) {
            int idx = lc_scene_add_attribute(s, names[k], attr[k], err);
            rc = idx < 0 ? idx : 0;
        } else {
            free(attr[k]);
        }
    }
    if (rc == 0) {
        snprintf(s->default_importance, sizeof s->default_importance, "speed");
        rc = lc_scene_finalize(s, NULL, err);
    }
    if (rc) {
        lc_scene_destroy(s);
        return rc;
    }
    *out = s;
    return 0;
}

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

int lc_cli_trace_scene(const char *spec, const char *seed_text, uint32_t curves, double step, double length,
                       lc_scene **out, lc_error *err)
{
    *out = NULL;
    lc_field *f = NULL;
    lc_seed seed;
    int rc = open_field_seed(spec, seed_text, &f, &seed, err);
    if (!f)
        return rc;
    lc_trace_curve *c = rc ? NULL : calloc(curves, sizeof *c);
    if (!rc && !c)
        rc = lc_err(err, LC_ERR_NOMEM, "out of memory for %u curves", curves);
    lc_trace_desc desc = {.step = step, .max_length = length};
    if (!rc) {
        long cpus = sysconf(_SC_NPROCESSORS_ONLN);
        double t0 = lc_now();
        rc = lc_trace_curves(f, &seed, &desc, 0, curves, cpus > 0 ? (int)cpus : 1, c, err);
        uint64_t vertices = 0;
        for (uint32_t i = 0; !rc && i < curves; i++)
            vertices += c[i].n;
        if (!rc) /* the tracer alone, without the scene's finalize and the writer */
            printf("traced %u curves (%llu vertices) in %.1f ms on %ld thread(s)\n", curves,
                   (unsigned long long)vertices, (lc_now() - t0) * 1e3, cpus > 0 ? cpus : 1);
    }
    if (!rc) {
        char name[160];
        snprintf(name, sizeof name, "%s-curves", f->name);
        rc = curves_to_scene(name, c, curves, out, err);
    }
    if (c)
        lc_trace_curves_free(c, curves);
    free(c);
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
