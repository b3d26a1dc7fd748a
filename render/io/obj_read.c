/* Wavefront OBJ reader (v, vt, f, l; vt carries a per-vertex attribute as in
 * the small-doo and LineVis line files, named by a "# vt: NAME" comment). */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_util.h"
#include "obj.h"

#define NO_VT UINT32_MAX

typedef struct obj_load {
    const char *file;
    lc_error *err;
    size_t line;            /* 1-based line being parsed */
    uint32_t nv, nvt;       /* totals from the pre-pass */
    uint32_t cur_v, cur_vt; /* defined so far: relative indices count back from here */
    int with_rgb;
    lc_scene *s;
    float *vt;
    lc_io_u32vec tris, tri_vt;
    lc_io_u32vec line_idx, line_vt, line_off;
    lc_io_u32vec poly, poly_vt;
    uint64_t short_lines;
    int rgb_warned;
    char vt_name[LC_NAME_LEN]; /* "# vt: NAME" names the vt attribute; "" = "vt" */
} obj_load;

static int fail(obj_load *L, int code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int fail(obj_load *L, int code, const char *fmt, ...)
{
    char reason[LC_ERROR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    return lc_err(L->err, code, "%.80s: line %zu: %s", L->file, L->line, reason);
}

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/* Skips blanks; a '#' ends the useful part of a line. */
static const char *skip_blank(const char *p, const char *le)
{
    while (p < le && is_blank(*p))
        p++;
    return p;
}

static int at_end(const char *p, const char *le) { return p == le || *p == '#'; }

/* Reads up to max numbers of the rest of the line; returns how many or < 0. */
static int read_numbers(obj_load *L, const char *p, const char *le, double *out, int max)
{
    int n = 0;
    for (;;) {
        p = skip_blank(p, le);
        if (at_end(p, le) || n == max)
            return n;
        const char *q = lc_io_parse_double(p, le, &out[n]);
        if (!q || (q < le && !is_blank(*q) && *q != '#')) {
            int len = 0;
            while (p + len < le && len < 24 && !is_blank(p[len]))
                len++;
            return fail(L, LC_ERR_INVALID, "bad number '%.*s'", len, p);
        }
        n++;
        p = q;
    }
}

static const char *parse_index(const char *p, const char *le, long long *out)
{
    int neg = 0;
    if (p < le && (*p == '-' || *p == '+'))
        neg = *p++ == '-';
    if (p == le || (unsigned)(*p - '0') >= 10)
        return NULL;
    long long v = 0;
    while (p < le && (unsigned)(*p - '0') < 10) {
        if (v < 10000000000000LL) /* saturate: anything this large is out of range anyway */
            v = v * 10 + (*p - '0');
        p++;
    }
    *out = neg ? -v : v;
    return p;
}

/* OBJ indices are 1-based; negative ones count back from the last defined. */
static int resolve(obj_load *L, long long idx, uint32_t defined, uint32_t total, const char *what, uint32_t *out)
{
    long long r = idx > 0 ? idx - 1 : (long long)defined + idx;
    if (idx == 0 || r < 0 || r >= (long long)total)
        return fail(L, LC_ERR_INVALID, "%s index %lld out of range (%u defined)", what, idx, idx > 0 ? total : defined);
    *out = (uint32_t)r;
    return 0;
}

/* Parses the corners of an f or l line ("v", "v/vt", "v//vn", "v/vt/vn") into
 * L->poly and L->poly_vt. */
static int read_corners(obj_load *L, const char *p, const char *le)
{
    L->poly.n = L->poly_vt.n = 0;
    for (;;) {
        p = skip_blank(p, le);
        if (at_end(p, le))
            return 0;
        long long vi, ti = 0, ni;
        int has_vt = 0;
        const char *q = parse_index(p, le, &vi);
        if (q && q < le && *q == '/') {
            q++;
            if (q < le && *q != '/' && !is_blank(*q)) {
                q = parse_index(q, le, &ti);
                has_vt = 1;
            }
            if (q && q < le && *q == '/') {
                q++;
                if (q < le && !is_blank(*q))
                    q = parse_index(q, le, &ni); /* normals: finalize computes its own */
            }
        }
        if (!q || (q < le && !is_blank(*q) && *q != '#')) {
            int len = 0;
            while (p + len < le && len < 24 && !is_blank(p[len]))
                len++;
            return fail(L, LC_ERR_INVALID, "bad vertex reference '%.*s'", len, p);
        }
        uint32_t v = 0, t = NO_VT; /* v is set unless resolve() fails */
        int rc = resolve(L, vi, L->cur_v, L->nv, "vertex", &v);
        if (!rc && has_vt)
            rc = resolve(L, ti, L->cur_vt, L->nvt, "texture coordinate", &t);
        if (rc)
            return rc;
        /* A line longer than the vertex cap cannot become a scene. */
        if ((rc = lc_io_u32vec_push(&L->poly, v, LC_MAX_VERTICES, L->file, "vertices in one face or line", L->err)) ||
            (rc = lc_io_u32vec_push(&L->poly_vt, t, LC_MAX_VERTICES, L->file, "vertices in one face or line", L->err)))
            return rc;
        p = q;
    }
}

static int add_face(obj_load *L)
{
    uint32_t n = (uint32_t)L->poly.n;
    if (n < 3)
        return fail(L, LC_ERR_INVALID, "face with %u vertices (at least 3 needed)", n);
    int rc = lc_io_u32vec_reserve(&L->tris, 3 * (size_t)(n - 2), 3 * (size_t)LC_MAX_PRIMITIVES, L->file,
                                  "triangle indices", L->err);
    if (!rc && L->nvt)
        rc = lc_io_u32vec_reserve(&L->tri_vt, 3 * (size_t)(n - 2), 3 * (size_t)LC_MAX_PRIMITIVES, L->file,
                                  "triangle indices", L->err);
    if (rc)
        return rc;
    for (uint32_t j = 1; j + 1 < n; j++) { /* fan around the first corner */
        uint32_t c[3] = {0, j, j + 1};
        for (int k = 0; k < 3; k++) {
            L->tris.v[L->tris.n++] = L->poly.v[c[k]];
            if (L->nvt)
                L->tri_vt.v[L->tri_vt.n++] = L->poly_vt.v[c[k]];
        }
    }
    return 0;
}

static int add_line(obj_load *L)
{
    size_t n = L->poly.n;
    if (n < 2) { /* a one-vertex "line" draws nothing */
        L->short_lines++;
        return 0;
    }
    int rc = lc_io_u32vec_reserve(&L->line_idx, n, LC_MAX_VERTICES, L->file, "line vertices", L->err);
    if (!rc && L->nvt)
        rc = lc_io_u32vec_reserve(&L->line_vt, n, LC_MAX_VERTICES, L->file, "line vertices", L->err);
    if (!rc)
        rc = lc_io_u32vec_push(&L->line_off, (uint32_t)(L->line_idx.n + n), (size_t)LC_MAX_PRIMITIVES + 1, L->file,
                               "lines", L->err);
    if (rc)
        return rc;
    memcpy(L->line_idx.v + L->line_idx.n, L->poly.v, n * sizeof(uint32_t));
    L->line_idx.n += n;
    if (L->nvt) {
        memcpy(L->line_vt.v + L->line_vt.n, L->poly_vt.v, n * sizeof(uint32_t));
        L->line_vt.n += n;
    }
    return 0;
}

/* "# vt: NAME": the name of the attribute vt carries (a time column, say);
 * the first such comment counts. */
static void read_vt_name(obj_load *L, const char *p, const char *le)
{
    p = skip_blank(p + 1, le);
    if (L->vt_name[0] || le - p < 3 || memcmp(p, "vt:", 3) != 0)
        return;
    p = skip_blank(p + 3, le);
    size_t n = 0;
    while (p + n < le && n + 1 < LC_NAME_LEN &&
           (isalnum((unsigned char)p[n]) || p[n] == '_' || p[n] == '-' || p[n] == '.'))
        n++;
    memcpy(L->vt_name, p, n);
    L->vt_name[n] = '\0';
}

static int parse_line(obj_load *L, const char *p, const char *le)
{
    p = skip_blank(p, le);
    if (p < le && *p == '#')
        read_vt_name(L, p, le);
    if (at_end(p, le))
        return 0;
    const char *kw = p;
    while (p < le && !is_blank(*p))
        p++;
    size_t kwlen = (size_t)(p - kw);
    double num[7];
    int n;
    if (kwlen == 1 && kw[0] == 'v') {
        if ((n = read_numbers(L, p, le, num, 7)) < 0)
            return n;
        if (n < 3)
            return fail(L, LC_ERR_INVALID, "vertex with %d coordinates (3 needed)", n);
        for (int k = 0; k < 3; k++)
            if (!isfinite(num[k]) || fabs(num[k]) > 3.4e38)
                return fail(L, LC_ERR_INVALID, "vertex %u has a non-finite or out-of-range coordinate", L->cur_v + 1);
        if (L->cur_v >= L->nv) /* cannot happen: the pre-pass counted the same lines */
            return fail(L, LC_ERR_INTERNAL, "vertex count changed between passes");
        float *pos = L->s->positions + 3 * (size_t)L->cur_v;
        for (int k = 0; k < 3; k++)
            pos[k] = (float)num[k];
        if (L->with_rgb) {
            /* "v x y z r g b" (MeshLab, small-doo); a vertex without colour is white. */
            float *c = L->s->rgb + 3 * (size_t)L->cur_v;
            for (int k = 0; k < 3; k++) {
                float v = n >= 6 ? (float)num[3 + k] : 1.0f;
                c[k] = v > 0 ? (v < 1 ? v : 1) : 0;
            }
        } else if (n >= 6 && !L->rgb_warned++) {
            LC_WARN(LC_IO_LOG, "%s: line %zu: vertex colours ignored (the first vertex has none)", L->file, L->line);
        }
        L->cur_v++;
    } else if (kwlen == 2 && kw[0] == 'v' && kw[1] == 't') {
        if ((n = read_numbers(L, p, le, num, 3)) < 0)
            return n;
        if (n < 1)
            return fail(L, LC_ERR_INVALID, "texture coordinate without a value");
        if (L->cur_vt >= L->nvt)
            return fail(L, LC_ERR_INTERNAL, "texture coordinate count changed between passes");
        L->vt[L->cur_vt++] = (float)num[0];
    } else if (kwlen == 1 && kw[0] == 'f') {
        int rc = read_corners(L, p, le);
        return rc ? rc : add_face(L);
    } else if (kwlen == 1 && kw[0] == 'l') {
        int rc = read_corners(L, p, le);
        return rc ? rc : add_line(L);
    }
    /* Everything else (vn, vp, o, g, s, usemtl, mtllib, curves) carries nothing
     * Lucent draws. */
    return 0;
}

/* Counts v and vt lines so that the arrays are allocated once at their final
 * size, and looks at the first vertex to decide whether there are colours. */
static int prepass(obj_load *L, const char *data, const char *end)
{
    uint64_t nv = 0, nvt = 0;
    for (const char *p = data; p < end;) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *le = nl ? nl : end;
        p = skip_blank(p, le);
        if (le - p >= 2 && p[0] == 'v' && is_blank(p[1])) {
            if (nv++ == 0) {
                double num[7];
                lc_error quiet;
                lc_error *keep = L->err;
                L->err = &quiet; /* a bad first vertex is reported by the real pass */
                L->with_rgb = read_numbers(L, p + 1, le, num, 7) >= 6;
                L->err = keep;
            }
        } else if (le - p >= 3 && p[0] == 'v' && p[1] == 't' && is_blank(p[2])) {
            nvt++;
        }
        p = nl ? nl + 1 : end;
    }
    if (nv == 0)
        return lc_err(L->err, LC_ERR_INVALID, "%.80s: no vertices", L->file);
    if (nv > LC_MAX_VERTICES || nvt > LC_MAX_VERTICES)
        return lc_err(L->err, LC_ERR_LIMIT, "%.80s: %llu vertices exceed the limit of %u", L->file,
                      (unsigned long long)(nv > nvt ? nv : nvt), (unsigned)LC_MAX_VERTICES);
    L->nv = (uint32_t)nv;
    L->nvt = (uint32_t)nvt;
    return 0;
}

/* The vt value of one vertex reference: its own vt index, else the vt with
 * the vertex's index (files that write one vt per v), else 0. */
static float vt_value(const obj_load *L, uint32_t v, uint32_t t)
{
    if (t != NO_VT)
        return L->vt[t];
    return v < L->nvt ? L->vt[v] : 0.0f;
}

static int assemble(obj_load *L)
{
    int rc;
    size_t line_count = L->line_off.n - 1;
    float *values = NULL;
    if (line_count > 0) {
        if (L->tris.n)
            LC_WARN(LC_IO_LOG, "%s: %zu faces' triangles ignored because the file has lines", L->file, L->tris.n / 3);
        uint32_t *offsets = L->line_off.v;
        memset(&L->line_off, 0, sizeof L->line_off); /* owned by the scene from here */
        if ((rc =
                 lc_io_make_lines(&L->s, L->line_idx.v, L->line_idx.n, offsets, (uint32_t)line_count, L->file, L->err)))
            return rc;
        if (L->nvt) {
            if (!(values = malloc(L->line_idx.n * sizeof *values)))
                return lc_err(L->err, LC_ERR_NOMEM, "%s: out of memory", L->file);
            for (size_t k = 0; k < L->line_idx.n; k++)
                values[k] = vt_value(L, L->line_idx.v[k], L->line_vt.v[k]);
        }
    } else {
        if (L->tris.n) {
            L->s->type = LC_PRIM_TRIANGLES;
            L->s->triangle_count = (uint32_t)(L->tris.n / 3);
            L->s->triangles = L->tris.v;
            memset(&L->tris, 0, sizeof L->tris);
        }
        if (L->nvt) {
            if (!(values = malloc((size_t)L->nv * sizeof *values)))
                return lc_err(L->err, LC_ERR_NOMEM, "%s: out of memory", L->file);
            for (uint32_t v = 0; v < L->nv; v++)
                values[v] = vt_value(L, v, NO_VT);
            /* A face corner's explicit v/vt pairing wins (the last one seen). */
            const uint32_t *tri = L->s->triangles;
            for (size_t k = 0; k < L->tri_vt.n && tri; k++)
                if (L->tri_vt.v[k] != NO_VT)
                    values[tri[k]] = L->vt[L->tri_vt.v[k]];
        }
    }
    if (values && (rc = lc_scene_add_attribute(L->s, L->vt_name[0] ? L->vt_name : "vt", values, L->err)) < 0)
        return rc;
    if (L->short_lines)
        LC_WARN(LC_IO_LOG, "%s: %llu lines with fewer than 2 vertices skipped", L->file,
                (unsigned long long)L->short_lines);
    lc_io_set_defaults(L->s);
    return 0;
}

static int load(obj_load *L, const char *data, size_t size)
{
    const char *end = data + size;
    int rc = prepass(L, data, end);
    if (rc)
        return rc;
    if ((rc = lc_scene_alloc_vertices(L->s, L->nv, L->with_rgb, L->err)))
        return rc;
    if (L->nvt && !(L->vt = malloc((size_t)L->nvt * sizeof *L->vt)))
        return lc_err(L->err, LC_ERR_NOMEM, "%s: out of memory", L->file);
    if ((rc = lc_io_u32vec_push(&L->line_off, 0, 1, L->file, "lines", L->err)))
        return rc;
    L->line = 0;
    for (const char *p = data; p < end;) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *le = nl ? nl : end;
        L->line++;
        if ((rc = parse_line(L, p, le)))
            return rc;
        p = nl ? nl + 1 : end;
    }
    return assemble(L);
}

int lc_load_obj_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err)
{
    *out = NULL;
    if (!name)
        name = "<memory>";
    obj_load L;
    memset(&L, 0, sizeof L);
    L.file = name;
    L.err = err;
    L.s = lc_scene_create(name, LC_PRIM_POINTS);
    int rc = L.s ? load(&L, data ? data : "", data ? size : 0) : lc_err(err, LC_ERR_NOMEM, "%s: out of memory", name);
    free(L.vt);
    lc_io_u32vec_free(&L.tris);
    lc_io_u32vec_free(&L.tri_vt);
    lc_io_u32vec_free(&L.line_idx);
    lc_io_u32vec_free(&L.line_vt);
    lc_io_u32vec_free(&L.line_off);
    lc_io_u32vec_free(&L.poly);
    lc_io_u32vec_free(&L.poly_vt);
    if (rc) {
        lc_scene_destroy(L.s);
        return rc;
    }
    *out = L.s;
    return 0;
}

int lc_load_obj(const char *path, lc_scene **out, lc_error *err)
{
    return lc_io_load_path(path, lc_load_obj_memory, out, err);
}
