/* PLY reader (ASCII, binary little and big endian). */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_util.h"
#include "ply.h"
#include "scene_shard.h"

/* Header caps: real files have a handful of elements and properties; these
 * bound the header tables, not the data. */
#define MAX_ELEMENTS 32
#define MAX_PROPERTIES 128
#define MAX_HEADER_BYTES (1u << 20)

typedef enum { PT_NONE = 0, PT_I8, PT_U8, PT_I16, PT_U16, PT_I32, PT_U32, PT_F32, PT_F64 } ptype;

static const int type_size[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};

static ptype type_from_name(const char *s)
{
    static const struct {
        const char *name;
        ptype type;
    } names[] = {{"char", PT_I8},   {"int8", PT_I8},     {"uchar", PT_U8},   {"uint8", PT_U8},
                 {"short", PT_I16}, {"int16", PT_I16},   {"ushort", PT_U16}, {"uint16", PT_U16},
                 {"int", PT_I32},   {"int32", PT_I32},   {"uint", PT_U32},   {"uint32", PT_U32},
                 {"float", PT_F32}, {"float32", PT_F32}, {"double", PT_F64}, {"float64", PT_F64}};
    for (size_t i = 0; i < sizeof names / sizeof *names; i++)
        if (strcmp(s, names[i].name) == 0)
            return names[i].type;
    return PT_NONE;
}

static int is_integer_type(ptype t) { return t >= PT_I8 && t <= PT_U32; }

/* What a property feeds in the scene. */
typedef enum { R_SKIP = 0, R_X, R_Y, R_Z, R_RED, R_GREEN, R_BLUE, R_ATTR, R_INDICES, R_V1, R_V2 } prole;

typedef struct prop {
    char name[LC_NAME_LEN];
    ptype type;       /* scalar type, or the list's item type */
    ptype count_type; /* PT_NONE for scalars */
    prole role;
    int slot; /* attribute slot for R_ATTR */
} prop;

typedef enum { EK_OTHER = 0, EK_VERTEX, EK_FACE, EK_LINE, EK_EDGE } ekind;

typedef struct element {
    char name[LC_NAME_LEN];
    uint64_t count;
    size_t header_line;
    ekind kind;
    int nprops;
    prop props[MAX_PROPERTIES];
} element;

enum { FMT_ASCII = 0, FMT_LE, FMT_BE };

typedef struct ply_reader {
    const unsigned char *data;
    size_t size, pos;
    int format;
    size_t line;      /* ASCII: 1-based line of pos */
    size_t value_pos; /* start of the last value read: where a bad value is reported */
    const char *file;
    lc_error *err;
    int nelements;
    element *elements; /* MAX_ELEMENTS */
} ply_reader;

/* Error at the reader's position: line for ASCII, byte offset for binary. */
static int fail(ply_reader *r, int code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int fail(ply_reader *r, int code, const char *fmt, ...)
{
    char reason[LC_ERROR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    int ascii = r->format == FMT_ASCII;
    return lc_io_fail(r->err, code, r->file, ascii ? "line" : "byte offset", ascii ? r->line : r->pos, "%s", reason);
}

/* ---- header */

/* Splits a header line into at most max whitespace-separated words, in place. */
static int split_words(char *line, char **words, int max)
{
    int n = 0;
    char *p = line;
    while (*p && n < max) {
        while (*p == ' ' || *p == '\t')
            p++;
        if (!*p)
            break;
        words[n++] = p;
        while (*p && *p != ' ' && *p != '\t')
            p++;
        if (*p)
            *p++ = '\0';
    }
    return n;
}

static int parse_count(const char *s, uint64_t *out)
{
    uint64_t v = 0;
    if (!*s)
        return -1;
    for (; *s; s++) {
        if (*s < '0' || *s > '9' || v > (UINT64_MAX - 9) / 10)
            return -1;
        v = v * 10 + (uint64_t)(*s - '0');
    }
    *out = v;
    return 0;
}

static int parse_header(ply_reader *r)
{
    size_t limit = r->size < MAX_HEADER_BYTES ? r->size : MAX_HEADER_BYTES;
    char line[1024];
    int have_format = 0;
    r->line = 0;
    for (;;) {
        if (r->pos >= limit) {
            r->line++;
            return fail(r, LC_ERR_INVALID,
                        r->size > MAX_HEADER_BYTES ? "header longer than 1 MiB" : "missing end_header");
        }
        const unsigned char *nl = memchr(r->data + r->pos, '\n', limit - r->pos);
        size_t len = nl ? (size_t)(nl - (r->data + r->pos)) : limit - r->pos;
        r->line++;
        if (len >= sizeof line)
            return fail(r, LC_ERR_INVALID, "header line longer than %zu bytes", sizeof line - 1);
        memcpy(line, r->data + r->pos, len);
        line[len] = '\0';
        if (memchr(line, '\0', len))
            return fail(r, LC_ERR_INVALID, "NUL byte in header");
        r->pos += len + (nl ? 1 : 0);
        if (len && line[len - 1] == '\r') /* tolerate "\r\n" line ends */
            line[--len] = '\0';

        char *w[8];
        int n = split_words(line, w, 8);
        if (r->line == 1) {
            if (n != 1 || strcmp(w[0], "ply") != 0)
                return fail(r, LC_ERR_INVALID, "not a PLY file (missing 'ply' magic)");
            continue;
        }
        if (n == 0 || strcmp(w[0], "comment") == 0 || strcmp(w[0], "obj_info") == 0)
            continue;
        if (strcmp(w[0], "format") == 0) {
            if (n < 3 || strcmp(w[2], "1.0") != 0)
                return fail(r, LC_ERR_INVALID, "bad format line (expected 'format <type> 1.0')");
            if (strcmp(w[1], "ascii") == 0)
                r->format = FMT_ASCII;
            else if (strcmp(w[1], "binary_little_endian") == 0)
                r->format = FMT_LE;
            else if (strcmp(w[1], "binary_big_endian") == 0)
                r->format = FMT_BE;
            else
                return fail(r, LC_ERR_INVALID, "unknown format '%.40s'", w[1]);
            have_format = 1;
        } else if (strcmp(w[0], "element") == 0) {
            if (n != 3)
                return fail(r, LC_ERR_INVALID, "bad element line (expected 'element <name> <count>')");
            if (r->nelements == MAX_ELEMENTS)
                return fail(r, LC_ERR_LIMIT, "more than %d elements", MAX_ELEMENTS);
            element *e = &r->elements[r->nelements++];
            memset(e, 0, sizeof *e);
            snprintf(e->name, sizeof e->name, "%s", w[1]);
            e->header_line = r->line;
            if (parse_count(w[2], &e->count) || e->count > UINT32_MAX)
                return fail(r, LC_ERR_INVALID, "bad count '%.40s' for element '%.40s'", w[2], w[1]);
            if (strcmp(w[1], "vertex") == 0)
                e->kind = EK_VERTEX;
            else if (strcmp(w[1], "face") == 0)
                e->kind = EK_FACE;
            else if (strcmp(w[1], "line") == 0 || strcmp(w[1], "polyline") == 0)
                e->kind = EK_LINE;
            else if (strcmp(w[1], "edge") == 0)
                e->kind = EK_EDGE;
            for (int i = 0; i < r->nelements - 1; i++)
                if (e->kind != EK_OTHER && r->elements[i].kind == e->kind)
                    return fail(r, LC_ERR_INVALID, "duplicate element '%.40s'", w[1]);
        } else if (strcmp(w[0], "property") == 0) {
            if (r->nelements == 0)
                return fail(r, LC_ERR_INVALID, "property before any element");
            element *e = &r->elements[r->nelements - 1];
            if (e->nprops == MAX_PROPERTIES)
                return fail(r, LC_ERR_LIMIT, "more than %d properties in element '%.40s'", MAX_PROPERTIES, e->name);
            prop *p = &e->props[e->nprops];
            memset(p, 0, sizeof *p);
            if (n >= 2 && strcmp(w[1], "list") == 0) {
                if (n != 5)
                    return fail(r, LC_ERR_INVALID,
                                "bad list property (expected 'property list <count type> "
                                "<item type> <name>')");
                p->count_type = type_from_name(w[2]);
                p->type = type_from_name(w[3]);
                if (p->count_type == PT_NONE || p->type == PT_NONE)
                    return fail(r, LC_ERR_INVALID, "unknown property type in list '%.40s'", w[4]);
                if (!is_integer_type(p->count_type))
                    return fail(r, LC_ERR_INVALID, "list '%.40s' has a non-integer count type", w[4]);
                snprintf(p->name, sizeof p->name, "%s", w[4]);
            } else {
                if (n != 3)
                    return fail(r, LC_ERR_INVALID, "bad property line (expected 'property <type> <name>')");
                p->type = type_from_name(w[1]);
                if (p->type == PT_NONE)
                    return fail(r, LC_ERR_INVALID, "unknown property type '%.40s'", w[1]);
                snprintf(p->name, sizeof p->name, "%s", w[2]);
            }
            e->nprops++;
        } else if (strcmp(w[0], "end_header") == 0) {
            if (!have_format)
                return fail(r, LC_ERR_INVALID, "missing format line");
            return 0;
        } else {
            return fail(r, LC_ERR_INVALID, "unknown header keyword '%.40s'", w[0]);
        }
    }
}

/* ---- values */

static double decode(const unsigned char *p, ptype t, int big)
{
    uint64_t u = 0;
    int n = type_size[t];
    if (big)
        for (int i = 0; i < n; i++)
            u = u << 8 | p[i];
    else
        for (int i = n - 1; i >= 0; i--)
            u = u << 8 | p[i];
    switch (t) {
    case PT_I8: return (int8_t)u;
    case PT_U8: return (uint8_t)u;
    case PT_I16: return (int16_t)u;
    case PT_U16: return (uint16_t)u;
    case PT_I32: return (int32_t)u;
    case PT_U32: return (uint32_t)u;
    case PT_F32: {
        uint32_t b = (uint32_t)u;
        float f;
        memcpy(&f, &b, 4);
        return f;
    }
    case PT_F64: {
        double d;
        memcpy(&d, &u, 8);
        return d;
    }
    default: return 0;
    }
}

static int is_space(unsigned char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

/* Error about the value just read: binary offsets point at its first byte. */
#define fail_value(r, ...) ((r)->pos = (r)->value_pos, fail((r), __VA_ARGS__))

/* Reads one value of type t of element e's record `record`. */
static int read_value(ply_reader *r, ptype t, double *out, const element *e, uint64_t record)
{
    r->value_pos = r->pos;
    if (r->format != FMT_ASCII) {
        int n = type_size[t];
        if (r->size - r->pos < (size_t)n)
            return fail(r, LC_ERR_INVALID, "file ends inside element '%.40s' %llu", e->name,
                        (unsigned long long)record);
        *out = decode(r->data + r->pos, t, r->format == FMT_BE);
        r->pos += (size_t)n;
        return 0;
    }
    while (r->pos < r->size && is_space(r->data[r->pos])) {
        if (r->data[r->pos] == '\n')
            r->line++;
        r->pos++;
    }
    if (r->pos == r->size) {
        if (r->size && r->data[r->size - 1] == '\n')
            r->line--; /* report the last line an editor shows, not the empty one after it */
        return fail(r, LC_ERR_INVALID, "file ends inside element '%.40s' %llu", e->name, (unsigned long long)record);
    }
    const char *start = (const char *)r->data + r->pos, *end = (const char *)r->data + r->size;
    const char *q = lc_io_parse_double(start, end, out);
    if (!q || (q < end && !is_space((unsigned char)*q))) {
        size_t len = 0;
        while (start + len < end && len < 24 && !is_space((unsigned char)start[len]))
            len++;
        return fail(r, LC_ERR_INVALID, "bad number '%.*s' in element '%.40s' %llu", (int)len, start, e->name,
                    (unsigned long long)record);
    }
    r->pos = (size_t)(q - (const char *)r->data);
    return 0;
}

/* Reads a list count, checking that the items can still be in the file. */
static int read_list_count(ply_reader *r, const prop *p, const element *e, uint64_t record, uint32_t *count)
{
    double v;
    int rc = read_value(r, p->count_type, &v, e, record);
    if (rc)
        return rc;
    if (!(v >= 0) || v != floor(v) || v > UINT32_MAX)
        return fail_value(r, LC_ERR_INVALID, "bad list length %g in element '%.40s' %llu", v, e->name,
                          (unsigned long long)record);
    /* ASCII items take at least two bytes each (digit and separator). */
    size_t item = r->format == FMT_ASCII ? 2 : (size_t)type_size[p->type];
    size_t left = r->size - r->pos;
    if ((uint64_t)v > (left + 1) / item)
        return fail_value(r, LC_ERR_INVALID, "list length %.0f in element '%.40s' %llu exceeds the file size", v,
                          e->name, (unsigned long long)record);
    *count = (uint32_t)v;
    return 0;
}

static int skip_values(ply_reader *r, ptype t, uint32_t count, const element *e, uint64_t record)
{
    if (r->format != FMT_ASCII) {
        size_t bytes = (size_t)count * (size_t)type_size[t]; /* bounded by read_list_count */
        if (r->size - r->pos < bytes)
            return fail(r, LC_ERR_INVALID, "file ends inside element '%.40s' %llu", e->name,
                        (unsigned long long)record);
        r->pos += bytes;
        return 0;
    }
    double v;
    for (uint32_t i = 0; i < count; i++) {
        int rc = read_value(r, t, &v, e, record);
        if (rc)
            return rc;
    }
    return 0;
}

/* Smallest size a record of e can have in this format: the size check that
 * runs before anything is allocated. */
static uint64_t min_record_size(const ply_reader *r, const element *e)
{
    uint64_t size = 0;
    for (int i = 0; i < e->nprops; i++) {
        const prop *p = &e->props[i];
        if (r->format == FMT_ASCII)
            size += 2;
        else
            size += (uint64_t)type_size[p->count_type != PT_NONE ? p->count_type : p->type];
    }
    return size;
}

/* ---- body */

typedef struct ply_load {
    ply_reader r;
    lc_scene *s;
    uint32_t vertex_count;  /* in the file */
    uint32_t first, kept;   /* the vertices this process keeps (all, or its share of a point cloud) */
    const lc_io_part *part; /* NULL or size 0: the whole file */
    float *attr[LC_MAX_ATTRIBUTES];
    float rgb_scale[3];
    lc_io_u32vec triangles;
    lc_io_u32vec poly; /* one face's indices */
    lc_io_u32vec line_idx, line_off;
    uint64_t faces_skipped, lines_skipped;
} ply_load;

static double color_scale(ptype t)
{
    switch (t) {
    case PT_U8: return 1.0 / 255.0;
    case PT_U16: return 1.0 / 65535.0;
    case PT_I8: return 1.0 / 127.0;
    case PT_I16: return 1.0 / 32767.0;
    case PT_I32:
    case PT_U32: return 1.0 / 255.0; /* integer colours are almost always 0..255 */
    default: return 1.0;
    }
}

/* Assigns roles to the vertex properties and creates the attribute arrays. */
static int setup_vertex(ply_load *L, element *e)
{
    ply_reader *r = &L->r;
    int have[7] = {0};
    for (int i = 0; i < e->nprops; i++) {
        prop *p = &e->props[i];
        if (p->count_type != PT_NONE)
            continue; /* lists on vertices carry nothing we use */
        static const char *names[] = {"", "x", "y", "z", "red", "green", "blue"};
        for (int k = 1; k <= 6; k++)
            if (strcmp(p->name, names[k]) == 0 && !have[k]) {
                p->role = (prole)k;
                have[k] = 1;
            }
    }
    if (!have[R_X] || !have[R_Y] || !have[R_Z]) {
        r->line = e->header_line;
        return lc_err(r->err, LC_ERR_INVALID, "%.80s: line %zu: vertex element lacks x, y or z", r->file,
                      e->header_line);
    }
    int with_rgb = have[R_RED] && have[R_GREEN] && have[R_BLUE];
    int rc = lc_scene_alloc_vertices(L->s, L->kept, with_rgb, r->err);
    if (rc)
        return rc;
    int warned = 0;
    for (int i = 0; i < e->nprops; i++) {
        prop *p = &e->props[i];
        if (p->role >= R_RED && p->role <= R_BLUE) {
            if (!with_rgb)
                p->role = R_SKIP; /* a lone 'red' becomes an attribute below */
            else {
                L->rgb_scale[p->role - R_RED] = (float)color_scale(p->type);
                continue;
            }
        }
        if (p->role != R_SKIP || p->count_type != PT_NONE)
            continue;
        if (strcmp(p->name, "nx") == 0 || strcmp(p->name, "ny") == 0 || strcmp(p->name, "nz") == 0)
            continue; /* finalize computes the normals it needs */
        if (lc_scene_find_attribute(L->s, p->name) >= 0)
            continue; /* duplicate name: keep the first */
        if (L->s->attribute_count >= LC_IO_MAX_FILE_ATTRIBUTES) {
            if (!warned++)
                LC_WARN(LC_IO_LOG, "%s: more than %d vertex attributes, ignoring '%s' and later ones", r->file,
                        LC_IO_MAX_FILE_ATTRIBUTES, p->name);
            continue;
        }
        float *values = calloc(L->kept ? L->kept : 1, sizeof *values);
        if (!values)
            return lc_err(r->err, LC_ERR_NOMEM, "%s: out of memory for attribute '%s'", r->file, p->name);
        int slot = lc_scene_add_attribute(L->s, p->name, values, r->err);
        if (slot < 0)
            return slot;
        p->role = R_ATTR;
        p->slot = slot;
        L->attr[slot] = values;
    }
    return 0;
}

static int read_vertices(ply_load *L, const element *e)
{
    ply_reader *r = &L->r;
    lc_scene *s = L->s;
    for (uint32_t i = 0; i < L->vertex_count; i++) {
        /* Every vertex is read and checked (each process fails as the whole
         * does); a share keeps only its own. */
        int keep = i - L->first < L->kept;
        uint32_t at = i - L->first;
        for (int k = 0; k < e->nprops; k++) {
            const prop *p = &e->props[k];
            double v;
            int rc;
            if (p->count_type != PT_NONE) {
                uint32_t n;
                if ((rc = read_list_count(r, p, e, i, &n)) || (rc = skip_values(r, p->type, n, e, i)))
                    return rc;
                continue;
            }
            if ((rc = read_value(r, p->type, &v, e, i)))
                return rc;
            switch (keep ? p->role : R_SKIP) {
            case R_X:
            case R_Y:
            case R_Z:
                if (!isfinite(v) || fabs(v) > 3.4e38)
                    return fail_value(r, LC_ERR_INVALID, "vertex %u has a non-finite or out-of-range coordinate", i);
                s->positions[3 * (size_t)at + (p->role - R_X)] = (float)v;
                break;
            case R_RED:
            case R_GREEN:
            case R_BLUE: {
                float c = (float)v * L->rgb_scale[p->role - R_RED];
                s->rgb[3 * (size_t)at + (p->role - R_RED)] = c > 0 ? (c < 1 ? c : 1) : 0; /* NaN -> 0 */
                break;
            }
            case R_ATTR: L->attr[p->slot][at] = (float)v; break;
            default:
                /* Another process's vertex: its coordinates are checked all the same. */
                if (!keep && p->role >= R_X && p->role <= R_Z && (!isfinite(v) || fabs(v) > 3.4e38))
                    return fail_value(r, LC_ERR_INVALID, "vertex %u has a non-finite or out-of-range coordinate", i);
                break;
            }
        }
    }
    return 0;
}

static int read_index(ply_load *L, const prop *p, const element *e, uint64_t record, uint32_t *out)
{
    ply_reader *r = &L->r;
    double v;
    int rc = read_value(r, p->type, &v, e, record);
    if (rc)
        return rc;
    if (!(v >= 0) || v >= L->vertex_count || v != floor(v))
        return fail_value(r, LC_ERR_INVALID, "%.40s %llu: vertex index %.10g out of range (%u vertices)", e->name,
                          (unsigned long long)record, v, L->vertex_count);
    *out = (uint32_t)v;
    return 0;
}

/* Faces, polylines and edges: every property is read (to stay in step) and
 * the index lists feed triangles or lines. */
static int read_connectivity(ply_load *L, const element *e)
{
    ply_reader *r = &L->r;
    int rc;
    for (uint64_t i = 0; i < e->count; i++) {
        uint32_t v1 = 0, v2 = 0;
        int have_v1 = 0, have_v2 = 0;
        for (int k = 0; k < e->nprops; k++) {
            const prop *p = &e->props[k];
            if (p->count_type == PT_NONE) {
                if (p->role == R_V1 || p->role == R_V2) {
                    if ((rc = read_index(L, p, e, i, p->role == R_V1 ? &v1 : &v2)))
                        return rc;
                    *(p->role == R_V1 ? &have_v1 : &have_v2) = 1;
                } else {
                    double v;
                    if ((rc = read_value(r, p->type, &v, e, i)))
                        return rc;
                }
                continue;
            }
            uint32_t n;
            if ((rc = read_list_count(r, p, e, i, &n)))
                return rc;
            if (p->role != R_INDICES) {
                if ((rc = skip_values(r, p->type, n, e, i)))
                    return rc;
                continue;
            }
            L->poly.n = 0;
            if ((rc = lc_io_u32vec_reserve(&L->poly, n, UINT32_MAX, r->file, "polygon vertices", r->err)))
                return rc;
            for (uint32_t j = 0; j < n; j++)
                if ((rc = read_index(L, p, e, i, &L->poly.v[j])))
                    return rc;
            L->poly.n = n;
            if (e->kind == EK_FACE) {
                if (n < 3) {
                    L->faces_skipped++;
                    continue;
                }
                if ((rc = lc_io_u32vec_reserve(&L->triangles, 3 * (size_t)(n - 2), 3 * (size_t)LC_MAX_PRIMITIVES,
                                               r->file, "triangle indices", r->err)))
                    return rc;
                for (uint32_t j = 1; j + 1 < n; j++) { /* fan around the first corner */
                    uint32_t *t = L->triangles.v + L->triangles.n;
                    t[0] = L->poly.v[0];
                    t[1] = L->poly.v[j];
                    t[2] = L->poly.v[j + 1];
                    L->triangles.n += 3;
                }
            } else {
                if (n < 2) {
                    L->lines_skipped++;
                    continue;
                }
                if ((rc = lc_io_u32vec_reserve(&L->line_idx, n, LC_MAX_VERTICES, r->file, "line vertices", r->err)))
                    return rc;
                memcpy(L->line_idx.v + L->line_idx.n, L->poly.v, n * sizeof(uint32_t));
                L->line_idx.n += n;
                if ((rc = lc_io_u32vec_push(&L->line_off, (uint32_t)L->line_idx.n, (size_t)LC_MAX_PRIMITIVES + 1,
                                            r->file, "lines", r->err)))
                    return rc;
            }
        }
        if (have_v1 && have_v2) {
            uint32_t pair[2] = {v1, v2};
            if ((rc = lc_io_u32vec_reserve(&L->line_idx, 2, LC_MAX_VERTICES, r->file, "line vertices", r->err)))
                return rc;
            memcpy(L->line_idx.v + L->line_idx.n, pair, sizeof pair);
            L->line_idx.n += 2;
            if ((rc = lc_io_u32vec_push(&L->line_off, (uint32_t)L->line_idx.n, (size_t)LC_MAX_PRIMITIVES + 1, r->file,
                                        "lines", r->err)))
                return rc;
        }
    }
    return 0;
}

static int skip_element(ply_load *L, const element *e)
{
    ply_reader *r = &L->r;
    int has_list = 0;
    for (int k = 0; k < e->nprops; k++)
        has_list |= e->props[k].count_type != PT_NONE;
    if (e->nprops == 0)
        return 0; /* records without properties take no bytes */
    if (r->format != FMT_ASCII && !has_list) {
        /* Fixed-size records: one jump. */
        uint64_t bytes = e->count * min_record_size(r, e); /* no overflow: checked in load_body */
        if (bytes > r->size - r->pos)
            return fail(r, LC_ERR_INVALID, "file ends inside element '%.40s'", e->name);
        r->pos += (size_t)bytes;
        return 0;
    }
    for (uint64_t i = 0; i < e->count; i++)
        for (int k = 0; k < e->nprops; k++) {
            const prop *p = &e->props[k];
            int rc;
            if (p->count_type != PT_NONE) {
                uint32_t n;
                if ((rc = read_list_count(r, p, e, i, &n)) || (rc = skip_values(r, p->type, n, e, i)))
                    return rc;
            } else {
                double v;
                if ((rc = read_value(r, p->type, &v, e, i)))
                    return rc;
            }
        }
    return 0;
}

/* Marks which properties of a face/line/edge element carry vertex indices. */
static int setup_connectivity(ply_load *L, element *e)
{
    ply_reader *r = &L->r;
    int found = 0;
    for (int k = 0; k < e->nprops; k++) {
        prop *p = &e->props[k];
        if (e->kind == EK_EDGE) {
            if (p->count_type == PT_NONE && strcmp(p->name, "vertex1") == 0)
                p->role = R_V1, found |= 1;
            else if (p->count_type == PT_NONE && strcmp(p->name, "vertex2") == 0)
                p->role = R_V2, found |= 2;
        } else if (p->count_type != PT_NONE && !found &&
                   (strcmp(p->name, "vertex_indices") == 0 || strcmp(p->name, "vertex_index") == 0)) {
            p->role = R_INDICES;
            found = 3;
        }
    }
    for (int k = 0; k < e->nprops; k++) {
        prop *p = &e->props[k];
        if (p->role != R_SKIP && !is_integer_type(p->type))
            return lc_err(r->err, LC_ERR_INVALID, "%.80s: line %zu: vertex indices of '%.40s' are not integers",
                          r->file, e->header_line, e->name);
    }
    if (found != 3) {
        LC_WARN(LC_IO_LOG, "%s: element '%s' has no vertex index property; skipped", r->file, e->name);
        e->kind = EK_OTHER;
    }
    return 0;
}

/* The first element with faces, lines or edges that the header declares, or
 * NULL for a point cloud. */
static const element *connectivity(const ply_reader *r)
{
    for (int i = 0; i < r->nelements; i++)
        if (r->elements[i].kind != EK_VERTEX && r->elements[i].kind != EK_OTHER && r->elements[i].count)
            return &r->elements[i];
    return NULL;
}

static int load_body(ply_load *L)
{
    ply_reader *r = &L->r;
    element *vertex = NULL;
    for (int i = 0; i < r->nelements; i++)
        if (r->elements[i].kind == EK_VERTEX)
            vertex = &r->elements[i];
    if (!vertex || vertex->count == 0)
        return lc_err(r->err, LC_ERR_INVALID, "%.80s: no vertices", r->file);

    /* Counts against the bytes left, before any allocation: a hostile
     * "element vertex 4000000000" fails here, not in malloc. */
    size_t left = r->size - r->pos;
    uint64_t need = 0;
    for (int i = 0; i < r->nelements; i++) {
        element *e = &r->elements[i];
        uint64_t rec = min_record_size(r, e);
        uint64_t avail = r->format == FMT_ASCII ? (uint64_t)left + 1 : (uint64_t)left;
        if (rec && (e->count > avail / rec || need + e->count * rec > avail)) {
            /* Reported at the header line that declared the count. */
            if (e->kind == EK_VERTEX)
                return lc_err(r->err, LC_ERR_INVALID, "%.80s: line %zu: vertex count %llu exceeds the file size",
                              r->file, e->header_line, (unsigned long long)e->count);
            return lc_err(r->err, LC_ERR_INVALID, "%.80s: line %zu: element '%.40s' count %llu exceeds the file size",
                          r->file, e->header_line, e->name, (unsigned long long)e->count);
        }
        need += e->count * rec;
    }
    if (vertex->count > LC_MAX_VERTICES)
        return lc_err(r->err, LC_ERR_LIMIT, "%.80s: line %zu: vertex count %llu exceeds the limit of %u", r->file,
                      vertex->header_line, (unsigned long long)vertex->count, (unsigned)LC_MAX_VERTICES);
    L->vertex_count = (uint32_t)vertex->count;
    L->first = 0, L->kept = L->vertex_count;
    if (lc_io_part_active(L->part)) { /* a point cloud's share, split as lc_scene_shard splits points */
        const element *c = connectivity(r);
        if (c)
            return lc_err(r->err, LC_ERR_UNSUPPORTED,
                          "%.80s: has %s: only point clouds are read in parts (surfaces and polylines are split "
                          "after loading)",
                          r->file, c->name);
        L->first = lc_scene_split_points(L->vertex_count, L->part->rank, L->part->size);
        L->kept = lc_scene_split_points(L->vertex_count, L->part->rank + 1, L->part->size) - L->first;
    }

    int rc = setup_vertex(L, vertex);
    if (rc)
        return rc;
    for (int i = 0; i < r->nelements; i++) {
        element *e = &r->elements[i];
        if (e->kind == EK_FACE || e->kind == EK_LINE || e->kind == EK_EDGE)
            if ((rc = setup_connectivity(L, e)))
                return rc;
        if (e->kind == EK_FACE && e->count) {
            /* Room for one triangle per face, but never more than the bytes
             * left could describe (a face takes at least 8 bytes), so a
             * lying count cannot make us reserve far more than the file. */
            uint64_t guess = e->count < left / 8 ? e->count : left / 8;
            if (guess > LC_MAX_PRIMITIVES)
                guess = LC_MAX_PRIMITIVES;
            if ((rc = lc_io_u32vec_reserve(&L->triangles, 3 * (size_t)guess, 3 * (size_t)LC_MAX_PRIMITIVES, r->file,
                                           "triangle indices", r->err)))
                return rc;
        }
    }
    if ((rc = lc_io_u32vec_push(&L->line_off, 0, (size_t)LC_MAX_PRIMITIVES + 1, r->file, "lines", r->err)))
        return rc;

    if (r->format == FMT_ASCII) { /* the body starts on the line after end_header */
        r->line++;
    }
    for (int i = 0; i < r->nelements; i++) {
        element *e = &r->elements[i];
        switch (e->kind) {
        case EK_VERTEX: rc = read_vertices(L, e); break;
        case EK_FACE:
        case EK_LINE:
        case EK_EDGE: rc = read_connectivity(L, e); break;
        default: rc = skip_element(L, e); break;
        }
        if (rc)
            return rc;
    }
    if (L->faces_skipped)
        LC_WARN(LC_IO_LOG, "%s: %llu faces with fewer than 3 vertices skipped", r->file,
                (unsigned long long)L->faces_skipped);
    if (L->lines_skipped)
        LC_WARN(LC_IO_LOG, "%s: %llu lines with fewer than 2 vertices skipped", r->file,
                (unsigned long long)L->lines_skipped);
    return 0;
}

/* Picks the primitive type: polylines win over faces (as in OBJ), faces over
 * points. */
static int assemble(ply_load *L)
{
    lc_scene *s = L->s;
    size_t line_count = L->line_off.n - 1;
    if (line_count > 0) {
        if (L->triangles.n)
            LC_WARN(LC_IO_LOG, "%s: %zu triangles ignored because the file has lines", L->r.file, L->triangles.n / 3);
        uint32_t *offsets = L->line_off.v;
        memset(&L->line_off, 0, sizeof L->line_off); /* ownership moves to the scene */
        int rc =
            lc_io_make_lines(&L->s, L->line_idx.v, L->line_idx.n, offsets, (uint32_t)line_count, L->r.file, L->r.err);
        if (rc)
            return rc;
    } else if (L->triangles.n) {
        s->type = LC_PRIM_TRIANGLES;
        s->triangle_count = (uint32_t)(L->triangles.n / 3);
        s->triangles = L->triangles.v;
        memset(&L->triangles, 0, sizeof L->triangles);
    } else {
        s->type = LC_PRIM_POINTS;
    }
    lc_io_set_defaults(L->s);
    return 0;
}

static int load_ply(const void *data, size_t size, const char *name, lc_io_part *part, lc_scene **out, lc_error *err)
{
    *out = NULL;
    if (!name)
        name = "<memory>";
    ply_load L;
    memset(&L, 0, sizeof L);
    L.r.data = data;
    L.r.size = data ? size : 0;
    L.r.file = name;
    L.r.err = err;
    L.part = part;
    L.r.elements = calloc(MAX_ELEMENTS, sizeof *L.r.elements);
    L.s = lc_scene_create(name, LC_PRIM_POINTS);
    int rc;
    if (!L.r.elements || !L.s)
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory", name);
    else if (!(rc = parse_header(&L.r)) && !(rc = load_body(&L)))
        rc = assemble(&L);
    free(L.r.elements);
    lc_io_u32vec_free(&L.triangles);
    lc_io_u32vec_free(&L.poly);
    lc_io_u32vec_free(&L.line_idx);
    lc_io_u32vec_free(&L.line_off);
    if (rc) {
        lc_scene_destroy(L.s);
        return rc;
    }
    *out = L.s;
    return 0;
}

int lc_load_ply_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err)
{
    return load_ply(data, size, name, NULL, out, err);
}

int lc_load_ply(const char *path, lc_scene **out, lc_error *err)
{
    return lc_io_load_path(path, lc_load_ply_memory, out, err);
}

int lc_load_ply_part(const char *path, int rank, int size, lc_scene **out, lc_error *err)
{
    return lc_io_load_path_part(path, load_ply, rank, size, out, err);
}

static int is_point_cloud(const char *data, size_t size, const char *name)
{
    lc_error err = {0};
    ply_reader r;
    memset(&r, 0, sizeof r);
    r.data = (const unsigned char *)data;
    r.size = size;
    r.file = name;
    r.err = &err;
    r.elements = calloc(MAX_ELEMENTS, sizeof *r.elements);
    int points = r.elements && parse_header(&r) == 0 && !connectivity(&r);
    free(r.elements);
    return points;
}

int lc_ply_file_is_point_cloud(const char *path) { return lc_io_file_test(path, is_point_cloud); }
