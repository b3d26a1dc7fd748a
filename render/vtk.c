/* VTK legacy reader (POLYDATA, ASCII and big-endian BINARY, classic and 5.1
 * OFFSETS/CONNECTIVITY cell layouts) and binary VTK legacy writer. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "loaders.h"
#include "scene_io.h"

#define MAX_WORD 256

typedef enum { VT_NONE = 0, VT_I8, VT_U8, VT_I16, VT_U16, VT_I32, VT_U32, VT_I64, VT_U64, VT_F32, VT_F64 } vtype;

static const int type_size[] = {0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8};

static vtype type_from_name(const char *s)
{
    /* "vtkIdType" is written as a 32-bit int by VTK's legacy writer; "long"
     * follows LP64, which is what every VTK binary of the last decade used. */
    static const struct {
        const char *name;
        vtype type;
    } names[] = {{"char", VT_I8},           {"signed_char", VT_I8},         {"unsigned_char", VT_U8},
                 {"short", VT_I16},         {"unsigned_short", VT_U16},     {"int", VT_I32},
                 {"unsigned_int", VT_U32},  {"vtkidtype", VT_I32},          {"long", VT_I64},
                 {"unsigned_long", VT_U64}, {"vtktypeint64", VT_I64},       {"vtktypeuint64", VT_U64},
                 {"long_long", VT_I64},     {"unsigned_long_long", VT_U64}, {"float", VT_F32},
                 {"double", VT_F64},        {"vtktypeint32", VT_I32},       {"vtktypeuint32", VT_U32}};
    for (size_t i = 0; i < sizeof names / sizeof *names; i++)
        if (strcasecmp(s, names[i].name) == 0)
            return names[i].type;
    return VT_NONE;
}

static int is_integer_type(vtype t) { return t >= VT_I8 && t <= VT_U64; }

/* Where attribute arrays go: POINT_DATA feeds the scene, CELL_DATA and
 * dataset FIELD data are parsed and dropped. */
typedef enum { SEC_NONE = 0, SEC_POINT, SEC_CELL, SEC_FIELD } section;

typedef struct vtk_load {
    const unsigned char *data;
    size_t size, pos;
    int binary;
    size_t line;    /* 1-based line of pos (meaningful in ASCII files) */
    size_t kw_line; /* line of the last keyword: where count errors are reported */
    size_t kw_pos;  /* its byte offset */
    const char *file;
    lc_error *err;
    int version_major;

    lc_scene *s;
    uint32_t npoints; /* 0 until POINTS */
    section sec;
    uint64_t cell_count; /* cells read so far: what CELL_DATA must match */
    lc_io_u32vec cell;   /* one cell's point ids */
    lc_io_u32vec line_idx, line_off, triangles;
    uint64_t skipped_attrs;
} vtk_load;

/* Error at the current keyword: line for ASCII, byte offset for binary. */
static int fail_at(vtk_load *L, int code, size_t line, size_t pos, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
static int fail_at(vtk_load *L, int code, size_t line, size_t pos, const char *fmt, ...)
{
    char reason[LC_ERROR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    if (!L->binary)
        return lc_err(L->err, code, "%.80s: line %zu: %s", L->file, line, reason);
    return lc_err(L->err, code, "%.80s: byte offset %zu: %s", L->file, pos, reason);
}
#define fail_kw(L, code, ...) fail_at((L), (code), (L)->kw_line, (L)->kw_pos, __VA_ARGS__)
#define fail_here(L, code, ...) fail_at((L), (code), (L)->line, (L)->pos, __VA_ARGS__)

/* ---- tokens */

static int is_space(unsigned char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
}

static void skip_ws(vtk_load *L)
{
    while (L->pos < L->size && is_space(L->data[L->pos]))
        L->line += L->data[L->pos++] == '\n';
}

/* Next whitespace-separated word into w (NUL-terminated); 0 at end of file. */
static int next_word(vtk_load *L, char *w, int *got)
{
    skip_ws(L);
    *got = 0;
    w[0] = '\0';
    if (L->pos >= L->size)
        return 0;
    size_t n = 0;
    while (L->pos + n < L->size && !is_space(L->data[L->pos + n])) {
        if (n + 1 >= MAX_WORD)
            return fail_here(L, LC_ERR_INVALID, "word longer than %d bytes", MAX_WORD - 1);
        if (L->data[L->pos + n] == '\0') /* would cut the C string short of what the file says */
            return fail_here(L, LC_ERR_INVALID, "NUL byte in a keyword line");
        w[n] = (char)L->data[L->pos + n];
        n++;
    }
    w[n] = '\0';
    L->pos += n;
    *got = 1;
    return 0;
}

/* A word the grammar requires; `what` says what was expected. */
static int need_word(vtk_load *L, char *w, const char *what)
{
    int got, rc = next_word(L, w, &got);
    if (rc)
        return rc;
    if (!got)
        return fail_here(L, LC_ERR_INVALID, "file ends before %s", what);
    return 0;
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

static int need_count(vtk_load *L, const char *what, uint64_t *out)
{
    char w[MAX_WORD];
    int rc = need_word(L, w, what);
    if (rc)
        return rc;
    if (parse_count(w, out))
        return fail_kw(L, LC_ERR_INVALID, "bad %s '%.40s'", what, w);
    return 0;
}

static int need_type(vtk_load *L, const char *what, vtype *out)
{
    char w[MAX_WORD];
    int rc = need_word(L, w, what);
    if (rc)
        return rc;
    *out = type_from_name(w);
    if (*out == VT_NONE)
        return fail_kw(L, LC_ERR_INVALID, "unsupported data type '%.40s' for %s", w, what);
    return 0;
}

/* Binary data starts right after the newline that ends its keyword line. */
static int end_keyword_line(vtk_load *L)
{
    if (!L->binary)
        return 0;
    while (L->pos < L->size && L->data[L->pos] != '\n') {
        unsigned char c = L->data[L->pos];
        if (c != ' ' && c != '\t' && c != '\r')
            return fail_kw(L, LC_ERR_INVALID, "unexpected text after the keyword line");
        L->pos++;
    }
    if (L->pos < L->size) {
        L->pos++;
        L->line++;
    }
    return 0;
}

/* Skips the rest of the current line (ASCII headers, METADATA). */
static void skip_line(vtk_load *L)
{
    while (L->pos < L->size && L->data[L->pos] != '\n')
        L->pos++;
    if (L->pos < L->size) {
        L->pos++;
        L->line++;
    }
}

/* Whether the next word is kw. Right after a keyword line (after_data = 0)
 * binary files are looked at exactly at pos, since skipping "whitespace"
 * there could walk into binary values. */
static int at_keyword(const vtk_load *L, const char *kw, int after_data)
{
    size_t pos = L->pos, n = strlen(kw);
    if (!L->binary || after_data)
        while (pos < L->size && is_space(L->data[pos]))
            pos++;
    return L->size - pos >= n && strncasecmp((const char *)L->data + pos, kw, n) == 0 &&
           (pos + n == L->size || is_space(L->data[pos + n]));
}

/* VTK 5.x follows arrays with "METADATA" and lines of key/value pairs up to
 * a blank line; nothing in them matters for rendering. */
static void skip_metadata_block(vtk_load *L)
{
    skip_line(L); /* the rest of the METADATA line */
    while (L->pos < L->size) {
        size_t p = L->pos;
        while (p < L->size && (L->data[p] == ' ' || L->data[p] == '\t' || L->data[p] == '\r'))
            p++;
        int blank = p >= L->size || L->data[p] == '\n';
        skip_line(L);
        if (blank)
            break;
    }
}

static void skip_metadata(vtk_load *L)
{
    if (at_keyword(L, "METADATA", 1)) {
        skip_ws(L);
        skip_metadata_block(L);
    }
}

/* VTK 5.x escapes spaces and other bytes in names as %XX. */
static void decode_name(const char *in, char *out, size_t n)
{
    size_t k = 0;
    for (size_t i = 0; in[i] && k + 1 < n; i++) {
        unsigned hi, lo;
        if (in[i] == '%' && in[i + 1] && in[i + 2] && sscanf(in + i + 1, "%1x%1x", &hi, &lo) == 2) {
            char c = (char)(hi * 16 + lo);
            out[k++] = c == ' ' ? '_' : c; /* attribute names travel in URLs and PLY headers */
            i += 2;
        } else {
            out[k++] = in[i];
        }
    }
    out[k] = '\0';
    if (!out[0]) /* "%00" and the like: a scene attribute needs a name */
        snprintf(out, n, "attribute");
}

/* ---- values */

/* Fails unless `count` values of type t can still fit in the file: a lying
 * count is caught here, before anything is allocated. An ASCII value takes at
 * least one digit and one separator. */
static int check_room(vtk_load *L, uint64_t count, vtype t, const char *what, uint64_t shown)
{
    uint64_t left = L->size - L->pos;
    int over = L->binary ? count > left / (uint64_t)type_size[t] : count > (left + 1) / 2;
    if (over)
        return fail_kw(L, LC_ERR_INVALID, "%s %llu exceeds the file size", what, (unsigned long long)shown);
    return 0;
}

static uint64_t get_be(const unsigned char *p, int n)
{
    uint64_t v = 0;
    for (int i = 0; i < n; i++)
        v = v << 8 | p[i];
    return v;
}

/* Reads one value of type t. `what` names the array in messages. */
static int read_value(vtk_load *L, vtype t, double *out, const char *what)
{
    if (L->binary) {
        int n = type_size[t];
        if ((size_t)n > L->size - L->pos)
            return fail_here(L, LC_ERR_INVALID, "file ends inside %s", what);
        uint64_t u = get_be(L->data + L->pos, n);
        L->pos += (size_t)n;
        switch (t) {
        case VT_I8: *out = (int8_t)u; break;
        case VT_I16: *out = (int16_t)u; break;
        case VT_I32: *out = (int32_t)u; break;
        case VT_I64: *out = (double)(int64_t)u; break;
        case VT_F32: {
            uint32_t b = (uint32_t)u;
            float f;
            memcpy(&f, &b, 4);
            *out = f;
            break;
        }
        case VT_F64: memcpy(out, &u, 8); break;
        default: *out = (double)u; break; /* unsigned */
        }
        return 0;
    }
    skip_ws(L);
    if (L->pos >= L->size)
        return fail_here(L, LC_ERR_INVALID, "file ends inside %s", what);
    const char *p = (const char *)L->data + L->pos, *end = (const char *)L->data + L->size;
    const char *q = lc_io_parse_double(p, end, out);
    if (!q || (q < end && !is_space((unsigned char)*q))) {
        size_t n = 0;
        while (p + n < end && n < 20 && !is_space((unsigned char)p[n]))
            n++;
        return fail_here(L, LC_ERR_INVALID, "bad number '%.*s' in %s", (int)n, p, what);
    }
    L->pos = (size_t)(q - (const char *)L->data);
    return 0;
}

/* Reads count values; out (count floats) may be NULL to drop them. Binary
 * arrays that are dropped are jumped over in one step. */
static int read_floats(vtk_load *L, vtype t, uint64_t count, float *out, size_t stride, const char *what)
{
    if (!out && L->binary) {
        L->pos += (size_t)(count * (uint64_t)type_size[t]); /* check_room passed */
        return 0;
    }
    for (uint64_t i = 0; i < count; i++) {
        double v;
        int rc = read_value(L, t, &v, what);
        if (rc)
            return rc;
        if (out)
            out[i * stride] = (float)v;
    }
    return 0;
}

/* A point id: an integer within [0, npoints). */
static int read_index(vtk_load *L, vtype t, uint32_t *out, const char *what)
{
    size_t line = L->line, pos = L->pos;
    double v;
    int rc = read_value(L, t, &v, what);
    if (rc)
        return rc;
    if (!(v >= 0 && v < L->npoints) || v != floor(v))
        return fail_at(L, LC_ERR_INVALID, line, pos, "%s: point index %.17g out of range (%u points)", what, v,
                       L->npoints);
    *out = (uint32_t)v;
    return 0;
}

/* ---- cells */

typedef enum { CELL_VERTS, CELL_LINES, CELL_POLYS, CELL_STRIPS } cell_kind;

static const char *cell_name[] = {"VERTICES", "LINES", "POLYGONS", "TRIANGLE_STRIPS"};

/* Turns the cell in L->cell into lines or triangles. */
static int emit_cell(vtk_load *L, cell_kind kind)
{
    const uint32_t *v = L->cell.v;
    size_t n = L->cell.n;
    int rc;
    L->cell_count++;
    if (kind == CELL_VERTS)
        return 0; /* the scene is all points anyway when nothing else is given */
    if (kind == CELL_LINES) {
        if (n < 2)
            return 0;
        if ((rc = lc_io_u32vec_reserve(&L->line_idx, n, LC_MAX_VERTICES, L->file, "line vertices", L->err)))
            return rc;
        memcpy(L->line_idx.v + L->line_idx.n, v, n * sizeof *v);
        L->line_idx.n += n;
        return lc_io_u32vec_push(&L->line_off, (uint32_t)L->line_idx.n, (size_t)LC_MAX_PRIMITIVES + 1, L->file, "lines",
                                 L->err);
    }
    if (n < 3)
        return 0;
    if ((rc = lc_io_u32vec_reserve(&L->triangles, 3 * (n - 2), 3 * (size_t)LC_MAX_PRIMITIVES, L->file,
                                   "triangle indices", L->err)))
        return rc;
    uint32_t *t = L->triangles.v + L->triangles.n;
    for (size_t j = 0; j + 2 < n; j++, t += 3) {
        if (kind == CELL_POLYS) { /* fan around the first corner */
            t[0] = v[0], t[1] = v[j + 1], t[2] = v[j + 2];
        } else if (j % 2 == 0) { /* strips alternate winding to keep a consistent orientation */
            t[0] = v[j], t[1] = v[j + 1], t[2] = v[j + 2];
        } else {
            t[0] = v[j + 1], t[1] = v[j], t[2] = v[j + 2];
        }
    }
    L->triangles.n += 3 * (n - 2);
    return 0;
}

/* Classic layout: "LINES n size", then n cells "k i0 .. ik-1" holding size
 * integers in all. */
static int read_cells_classic(vtk_load *L, cell_kind kind, uint64_t ncells, uint64_t size)
{
    const char *what = cell_name[kind];
    int rc;
    if (size < ncells)
        return fail_kw(L, LC_ERR_INVALID, "%s size %llu is smaller than its %llu cells", what, (unsigned long long)size,
                       (unsigned long long)ncells);
    uint64_t used = 0;
    for (uint64_t c = 0; c < ncells; c++) {
        double k;
        if ((rc = read_value(L, VT_I32, &k, what)))
            return rc;
        if (used >= size || !(k >= 0) || k != floor(k) || k > (double)(size - used - 1))
            return fail_here(L, LC_ERR_INVALID, "%s cell %llu: point count %.17g exceeds the declared size %llu", what,
                             (unsigned long long)c, k, (unsigned long long)size);
        used += 1 + (uint64_t)k;
        L->cell.n = 0;
        if ((rc = lc_io_u32vec_reserve(&L->cell, (size_t)k, LC_MAX_VERTICES, L->file, "cell points", L->err)))
            return rc;
        for (uint32_t j = 0; j < (uint32_t)k; j++)
            if ((rc = read_index(L, VT_I32, &L->cell.v[j], what)))
                return rc;
        L->cell.n = (size_t)k;
        if ((rc = emit_cell(L, kind)))
            return rc;
    }
    if (used != size)
        return fail_kw(L, LC_ERR_INVALID, "%s size %llu does not match its cells (%llu values)", what,
                       (unsigned long long)size, (unsigned long long)used);
    return 0;
}

/* 5.1 layout: "LINES noffsets nconn", "OFFSETS type" + noffsets values,
 * "CONNECTIVITY type" + nconn point ids. The offsets are read into memory
 * (bounded by the file size) because they precede the ids they slice. */
static int read_cells_offsets(vtk_load *L, cell_kind kind, uint64_t noffsets, uint64_t nconn)
{
    const char *what = cell_name[kind];
    char w[MAX_WORD];
    vtype t;
    int rc;
    lc_io_u32vec offs = {0};
    skip_ws(L);
    L->kw_line = L->line, L->kw_pos = L->pos;
    if ((rc = need_word(L, w, "OFFSETS")))
        return rc;
    if ((rc = need_type(L, "OFFSETS", &t)) || (rc = end_keyword_line(L)))
        return rc;
    if (!is_integer_type(t))
        return fail_kw(L, LC_ERR_INVALID, "%s OFFSETS are not integers", what);
    if ((rc = check_room(L, noffsets, t, "OFFSETS count", noffsets)))
        return rc;
    if (noffsets > (uint64_t)LC_MAX_PRIMITIVES + 1)
        return fail_kw(L, LC_ERR_LIMIT, "%s: %llu cells exceed the limit of %u", what, (unsigned long long)noffsets - 1,
                       (unsigned)LC_MAX_PRIMITIVES);
    if (noffsets && (rc = lc_io_u32vec_reserve(&offs, (size_t)noffsets, (size_t)LC_MAX_PRIMITIVES + 1, L->file,
                                               "cell offsets", L->err)))
        return rc;
    for (uint64_t i = 0; i < noffsets; i++) {
        double v;
        if ((rc = read_value(L, t, &v, "OFFSETS")))
            goto done;
        /* Offsets start at 0, never decrease and end at the connectivity size. */
        double prev = i ? offs.v[i - 1] : 0;
        if (!(v >= prev) || v != floor(v) || v > (double)nconn || (i == 0 && v != 0)) {
            rc = fail_here(L, LC_ERR_INVALID,
                           "%s offset %llu is %.17g (must start at 0, not decrease and stay "
                           "within %llu)",
                           what, (unsigned long long)i, v, (unsigned long long)nconn);
            goto done;
        }
        offs.v[offs.n++] = (uint32_t)v;
    }
    if (noffsets && offs.v[noffsets - 1] != nconn) {
        rc = fail_here(L, LC_ERR_INVALID, "%s offsets end at %u, not at the connectivity size %llu", what,
                       offs.v[noffsets - 1], (unsigned long long)nconn);
        goto done;
    }
    skip_ws(L);
    L->kw_line = L->line, L->kw_pos = L->pos;
    if ((rc = need_word(L, w, "CONNECTIVITY")))
        goto done;
    if (strcasecmp(w, "CONNECTIVITY") != 0) {
        rc = fail_here(L, LC_ERR_INVALID, "expected CONNECTIVITY in %s, found '%.40s'", what, w);
        goto done;
    }
    if ((rc = need_type(L, "CONNECTIVITY", &t)) || (rc = end_keyword_line(L)))
        goto done;
    if (!is_integer_type(t)) {
        rc = fail_kw(L, LC_ERR_INVALID, "%s CONNECTIVITY is not integer", what);
        goto done;
    }
    if ((rc = check_room(L, nconn, t, "CONNECTIVITY size", nconn)))
        goto done;
    for (uint64_t c = 0; c + 1 < noffsets; c++) {
        uint32_t k = offs.v[c + 1] - offs.v[c];
        L->cell.n = 0;
        if ((rc = lc_io_u32vec_reserve(&L->cell, k, LC_MAX_VERTICES, L->file, "cell points", L->err)))
            goto done;
        for (uint32_t j = 0; j < k; j++)
            if ((rc = read_index(L, t, &L->cell.v[j], what)))
                goto done;
        L->cell.n = k;
        if ((rc = emit_cell(L, kind)))
            goto done;
    }
done:
    lc_io_u32vec_free(&offs);
    return rc;
}

static int read_cells(vtk_load *L, cell_kind kind)
{
    const char *what = cell_name[kind];
    uint64_t a, b;
    int rc;
    if (!L->npoints)
        return fail_kw(L, LC_ERR_INVALID, "%s before POINTS", what);
    if ((rc = need_count(L, "cell count", &a)) || (rc = need_count(L, "cell size", &b)))
        return rc;
    if ((rc = end_keyword_line(L)))
        return rc;
    if (at_keyword(L, "OFFSETS", 0))
        return read_cells_offsets(L, kind, a, b);
    char label[64];
    snprintf(label, sizeof label, "%s size", what);
    if ((rc = check_room(L, b, VT_I32, label, b)))
        return rc;
    return read_cells_classic(L, kind, a, b);
}

/* ---- points and attributes */

static int read_points(vtk_load *L)
{
    uint64_t n;
    vtype t;
    int rc;
    if (L->npoints)
        return fail_kw(L, LC_ERR_INVALID, "duplicate POINTS");
    if ((rc = need_count(L, "POINTS count", &n)) || (rc = need_type(L, "POINTS", &t)) || (rc = end_keyword_line(L)))
        return rc;
    if (n == 0)
        return fail_kw(L, LC_ERR_INVALID, "no points");
    if (n > UINT64_MAX / 3 || (rc = check_room(L, 3 * n, t, "POINTS count", n)))
        return rc ? rc : fail_kw(L, LC_ERR_INVALID, "POINTS count %llu exceeds the file size", (unsigned long long)n);
    if (n > LC_MAX_VERTICES)
        return fail_kw(L, LC_ERR_LIMIT, "POINTS count %llu exceeds the limit of %u", (unsigned long long)n,
                       (unsigned)LC_MAX_VERTICES);
    if ((rc = lc_scene_alloc_vertices(L->s, (uint32_t)n, 0, L->err)))
        return rc;
    for (uint64_t i = 0; i < n; i++) {
        size_t line = L->line, pos = L->pos;
        if ((rc = read_floats(L, t, 3, L->s->positions + 3 * i, 1, "POINTS")))
            return rc;
        const float *p = L->s->positions + 3 * i;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
            skip_ws(L);
            return fail_at(L, LC_ERR_INVALID, L->binary ? line : L->line, pos,
                           "point %llu has a non-finite or out-of-range coordinate", (unsigned long long)i);
        }
    }
    L->npoints = (uint32_t)n;
    return 0;
}

/* Attribute slot check: beyond LC_IO_MAX_FILE_ATTRIBUTES arrays are dropped. */
static int room_for_attributes(vtk_load *L, int n) { return L->s->attribute_count + n <= LC_IO_MAX_FILE_ATTRIBUTES; }

/* Reads `tuples` x `ncomp` values. In POINT_DATA, keep says what to make:
 * 1 = one attribute per component (name, or name_0..), 2 = the vector
 * magnitude as name_magnitude, 0 = drop. */
static int read_array(vtk_load *L, const char *raw_name, vtype t, uint64_t ncomp, uint64_t tuples, int keep)
{
    char name[LC_NAME_LEN];
    decode_name(raw_name, name, sizeof name);
    if (ncomp == 0 || ncomp > 1024)
        return fail_kw(L, LC_ERR_INVALID, "array '%.40s' has %llu components", name, (unsigned long long)ncomp);
    if (tuples > UINT64_MAX / ncomp)
        return fail_kw(L, LC_ERR_INVALID, "array '%.40s' size exceeds the file size", name);
    char label[LC_NAME_LEN + 16];
    snprintf(label, sizeof label, "'%s' size", name);
    int rc = check_room(L, tuples * ncomp, t, label, tuples * ncomp);
    if (rc)
        return rc;
    if (L->sec != SEC_POINT)
        keep = 0;
    int nattr = keep == 1 ? (int)ncomp : 1;
    if (keep == 1 && ncomp > 16) { /* a spectrum or a matrix, not scalars to look at */
        LC_WARN(LC_IO_LOG, "%s: array '%s' has %llu components; skipped", L->file, name, (unsigned long long)ncomp);
        keep = 0;
    }
    if (keep && !room_for_attributes(L, nattr)) {
        L->skipped_attrs++;
        keep = 0;
    }
    if (!keep)
        return read_floats(L, t, tuples * ncomp, NULL, 1, name);
    /* tuples == npoints here (checked by POINT_DATA). */
    float *vals = malloc((size_t)tuples * (size_t)ncomp * sizeof *vals + 1);
    if (!vals)
        return lc_err(L->err, LC_ERR_NOMEM, "%s: out of memory for array '%s'", L->file, name);
    if ((rc = read_floats(L, t, tuples * ncomp, vals, 1, name))) {
        free(vals);
        return rc;
    }
    if (keep == 2) { /* magnitude, computed in place into the first tuples floats */
        for (uint64_t i = 0; i < tuples; i++) {
            double m = 0;
            for (uint64_t c = 0; c < ncomp; c++)
                m += (double)vals[i * ncomp + c] * vals[i * ncomp + c];
            vals[i] = (float)sqrt(m);
        }
        char mname[LC_NAME_LEN];
        snprintf(mname, sizeof mname, "%.*s_magnitude", LC_NAME_LEN - 11, name);
        int idx = lc_scene_add_attribute(L->s, mname, vals, L->err);
        return idx < 0 ? idx : 0;
    }
    if (ncomp == 1) {
        int idx = lc_scene_add_attribute(L->s, name, vals, L->err);
        return idx < 0 ? idx : 0;
    }
    for (uint64_t c = 0; c < ncomp; c++) {
        float *comp = malloc((size_t)tuples * sizeof *comp + 1);
        if (!comp) {
            free(vals);
            return lc_err(L->err, LC_ERR_NOMEM, "%s: out of memory for array '%s'", L->file, name);
        }
        for (uint64_t i = 0; i < tuples; i++)
            comp[i] = vals[i * ncomp + c];
        char cname[LC_NAME_LEN];
        snprintf(cname, sizeof cname, "%.*s_%u", LC_NAME_LEN - 6, name, (unsigned)c);
        int idx = lc_scene_add_attribute(L->s, cname, comp, L->err);
        if (idx < 0) {
            free(vals);
            return idx;
        }
    }
    free(vals);
    return 0;
}

static int read_scalars(vtk_load *L, uint64_t tuples)
{
    char name[MAX_WORD], w[MAX_WORD];
    vtype t;
    uint64_t ncomp = 1;
    int got, rc;
    if ((rc = need_word(L, name, "SCALARS name")) || (rc = need_type(L, "SCALARS", &t)))
        return rc;
    /* The component count is optional: look at the rest of this line only. */
    size_t save_pos = L->pos, save_line = L->line;
    while (L->pos < L->size && (L->data[L->pos] == ' ' || L->data[L->pos] == '\t' || L->data[L->pos] == '\r'))
        L->pos++;
    if (L->pos < L->size && L->data[L->pos] != '\n') {
        if ((rc = need_count(L, "SCALARS component count", &ncomp)))
            return rc;
    } else {
        L->pos = save_pos, L->line = save_line;
    }
    /* LOOKUP_TABLE is required by VTK but some writers omit it. */
    if ((rc = end_keyword_line(L)))
        return rc;
    if (at_keyword(L, "LOOKUP_TABLE", 0)) {
        if ((rc = next_word(L, w, &got)) || (rc = need_word(L, w, "LOOKUP_TABLE name")) || (rc = end_keyword_line(L)))
            return rc;
    }
    return read_array(L, name, t, ncomp, tuples, 1);
}

/* COLOR_SCALARS name n: floats in [0,1] (ASCII) or uchar (binary). */
static int read_color_scalars(vtk_load *L, uint64_t tuples)
{
    char name[MAX_WORD];
    uint64_t ncomp;
    int rc;
    if ((rc = need_word(L, name, "COLOR_SCALARS name")) || (rc = need_count(L, "COLOR_SCALARS count", &ncomp)) ||
        (rc = end_keyword_line(L)))
        return rc;
    vtype t = L->binary ? VT_U8 : VT_F32;
    if (ncomp == 0 || ncomp > 1024)
        return fail_kw(L, LC_ERR_INVALID, "COLOR_SCALARS has %llu components", (unsigned long long)ncomp);
    if (tuples > UINT64_MAX / ncomp || (rc = check_room(L, tuples * ncomp, t, "COLOR_SCALARS size", tuples * ncomp)))
        return rc ? rc : fail_kw(L, LC_ERR_INVALID, "COLOR_SCALARS size exceeds the file size");
    if (L->sec != SEC_POINT || (ncomp != 3 && ncomp != 4) || L->s->rgb) {
        if (L->sec == SEC_POINT)
            LC_WARN(LC_IO_LOG, "%s: COLOR_SCALARS '%s' with %llu components skipped", L->file, name,
                    (unsigned long long)ncomp);
        return read_floats(L, t, tuples * ncomp, NULL, 1, "COLOR_SCALARS");
    }
    float *rgb = malloc(3 * (size_t)tuples * sizeof *rgb + 1);
    if (!rgb)
        return lc_err(L->err, LC_ERR_NOMEM, "%s: out of memory for colours", L->file);
    for (uint64_t i = 0; i < tuples; i++)
        for (uint64_t c = 0; c < ncomp; c++) {
            double v;
            if ((rc = read_value(L, t, &v, "COLOR_SCALARS"))) {
                free(rgb);
                return rc;
            }
            if (L->binary)
                v /= 255.0;
            if (c < 3)
                rgb[3 * i + c] = (float)(v > 0 ? (v < 1 ? v : 1) : 0); /* NaN becomes 0 */
        }
    L->s->rgb = rgb;
    return 0;
}

/* FIELD name k, then k arrays "name ncomp ntuples type". */
static int read_field(vtk_load *L, uint64_t tuples)
{
    char w[MAX_WORD], name[MAX_WORD];
    uint64_t narrays;
    int rc;
    if ((rc = need_word(L, w, "FIELD name")) || (rc = need_count(L, "FIELD array count", &narrays)))
        return rc;
    for (uint64_t i = 0; i < narrays; i++) {
        uint64_t ncomp, ntuples;
        vtype t;
        if ((rc = need_word(L, name, "FIELD array name")))
            return rc;
        L->kw_line = L->line, L->kw_pos = L->pos;
        if (strcasecmp(name, "NULL_ARRAY") == 0)
            continue;
        if ((rc = need_count(L, "FIELD array component count", &ncomp)) ||
            (rc = need_count(L, "FIELD array tuple count", &ntuples)) || (rc = need_type(L, "FIELD array", &t)) ||
            (rc = end_keyword_line(L)))
            return rc;
        int keep = L->sec == SEC_POINT && ncomp == 1 && ntuples == tuples;
        if (L->sec == SEC_POINT && !keep)
            LC_WARN(LC_IO_LOG, "%s: field array '%s' (%llu components, %llu tuples) skipped", L->file, name,
                    (unsigned long long)ncomp, (unsigned long long)ntuples);
        if ((rc = read_array(L, name, t, ncomp, ntuples, keep)))
            return rc;
        skip_metadata(L);
    }
    return 0;
}

/* LOOKUP_TABLE name n: n RGBA entries (floats in ASCII, uchar in binary). */
static int skip_lookup_table(vtk_load *L)
{
    char name[MAX_WORD];
    uint64_t n;
    int rc;
    if ((rc = need_word(L, name, "LOOKUP_TABLE name")) || (rc = need_count(L, "LOOKUP_TABLE size", &n)) ||
        (rc = end_keyword_line(L)))
        return rc;
    vtype t = L->binary ? VT_U8 : VT_F32;
    if (n > UINT64_MAX / 4 || (rc = check_room(L, 4 * n, t, "LOOKUP_TABLE size", n)))
        return rc ? rc
                  : fail_kw(L, LC_ERR_INVALID, "LOOKUP_TABLE size %llu exceeds the file size", (unsigned long long)n);
    return read_floats(L, t, 4 * n, NULL, 1, "LOOKUP_TABLE");
}

/* "KEYWORD name type" arrays with a fixed component count. */
static int read_named_array(vtk_load *L, const char *kw, uint64_t ncomp, int keep, uint64_t tuples)
{
    char name[MAX_WORD];
    vtype t;
    int rc;
    if ((rc = need_word(L, name, kw)))
        return rc;
    if (strcasecmp(kw, "TEXTURE_COORDINATES") == 0 && (rc = need_count(L, "TEXTURE_COORDINATES dimension", &ncomp)))
        return rc;
    if ((rc = need_type(L, kw, &t)) || (rc = end_keyword_line(L)))
        return rc;
    return read_array(L, name, t, ncomp, tuples, keep);
}

static int read_data_count(vtk_load *L, const char *kw, uint64_t *out)
{
    int rc = need_count(L, kw, out);
    if (rc)
        return rc;
    return end_keyword_line(L);
}

/* "# vtk DataFile Version x.y", a title line, ASCII|BINARY. */
static int read_preamble(vtk_load *L)
{
    static const char magic[] = "# vtk DataFile Version";
    size_t n = sizeof magic - 1;
    L->line = 1;
    if (L->size < n || strncasecmp((const char *)L->data, magic, n) != 0)
        return fail_here(L, LC_ERR_INVALID, "not a VTK legacy file (missing '# vtk DataFile Version')");
    L->pos = n;
    char w[MAX_WORD];
    int got, rc;
    while (L->pos < L->size && (L->data[L->pos] == ' ' || L->data[L->pos] == '\t'))
        L->pos++;
    L->version_major = L->pos < L->size && L->data[L->pos] >= '0' && L->data[L->pos] <= '9' ? L->data[L->pos] - '0' : 0;
    skip_line(L);
    skip_line(L); /* the title: free text */
    L->kw_line = L->line, L->kw_pos = L->pos;
    if ((rc = next_word(L, w, &got)))
        return rc;
    if (got && strcasecmp(w, "BINARY") == 0)
        L->binary = 1;
    else if (!got || strcasecmp(w, "ASCII") != 0)
        return fail_kw(L, LC_ERR_INVALID, "expected ASCII or BINARY, found '%.40s'", w);
    return 0;
}

static int parse(vtk_load *L)
{
    char kw[MAX_WORD], w[MAX_WORD];
    int got, rc, have_dataset = 0;
    uint64_t tuples = 0; /* of the current POINT_DATA / CELL_DATA section */
    if ((rc = read_preamble(L)))
        return rc;
    for (;;) {
        skip_ws(L);
        L->kw_line = L->line, L->kw_pos = L->pos;
        if ((rc = next_word(L, kw, &got)))
            return rc;
        if (!got)
            break;
        if (strcasecmp(kw, "DATASET") == 0) {
            if ((rc = need_word(L, w, "dataset type")))
                return rc;
            if (have_dataset)
                return fail_kw(L, LC_ERR_INVALID, "second DATASET");
            if (strcasecmp(w, "POLYDATA") != 0)
                return fail_kw(L, LC_ERR_UNSUPPORTED, "dataset type '%.40s' is not supported (only POLYDATA)", w);
            have_dataset = 1;
            if ((rc = end_keyword_line(L)))
                return rc;
            continue;
        }
        if (strcasecmp(kw, "FIELD") == 0) { /* dataset field data (before DATASET too), or point/cell arrays */
            if ((rc = read_field(L, tuples)))
                return rc;
            continue;
        }
        if (strcasecmp(kw, "METADATA") == 0) {
            skip_metadata_block(L);
            continue;
        }
        if (!have_dataset)
            return fail_kw(L, LC_ERR_INVALID, "expected DATASET, found '%.40s'", kw);
        if (strcasecmp(kw, "POINTS") == 0)
            rc = read_points(L);
        else if (strcasecmp(kw, "VERTICES") == 0)
            rc = read_cells(L, CELL_VERTS);
        else if (strcasecmp(kw, "LINES") == 0)
            rc = read_cells(L, CELL_LINES);
        else if (strcasecmp(kw, "POLYGONS") == 0)
            rc = read_cells(L, CELL_POLYS);
        else if (strcasecmp(kw, "TRIANGLE_STRIPS") == 0)
            rc = read_cells(L, CELL_STRIPS);
        else if (strcasecmp(kw, "POINT_DATA") == 0) {
            if (!L->npoints)
                return fail_kw(L, LC_ERR_INVALID, "POINT_DATA before POINTS");
            if ((rc = read_data_count(L, "POINT_DATA count", &tuples)))
                return rc;
            if (tuples != L->npoints)
                return fail_kw(L, LC_ERR_INVALID, "POINT_DATA count %llu differs from the %u points",
                               (unsigned long long)tuples, L->npoints);
            L->sec = SEC_POINT;
        } else if (strcasecmp(kw, "CELL_DATA") == 0) {
            if ((rc = read_data_count(L, "CELL_DATA count", &tuples)))
                return rc;
            L->sec = SEC_CELL;
        } else if (L->sec == SEC_NONE) {
            return fail_kw(L, LC_ERR_INVALID, "unknown or misplaced keyword '%.40s'", kw);
        } else if (strcasecmp(kw, "SCALARS") == 0)
            rc = read_scalars(L, tuples);
        else if (strcasecmp(kw, "COLOR_SCALARS") == 0)
            rc = read_color_scalars(L, tuples);
        else if (strcasecmp(kw, "LOOKUP_TABLE") == 0)
            rc = skip_lookup_table(L);
        else if (strcasecmp(kw, "VECTORS") == 0)
            rc = read_named_array(L, kw, 3, 2, tuples);
        else if (strcasecmp(kw, "NORMALS") == 0)
            rc = read_named_array(L, kw, 3, 0, tuples);
        else if (strcasecmp(kw, "TEXTURE_COORDINATES") == 0)
            rc = read_named_array(L, kw, 0, 0, tuples);
        else if (strcasecmp(kw, "TENSORS") == 0)
            rc = read_named_array(L, kw, 9, 0, tuples);
        else if (strcasecmp(kw, "TENSORS6") == 0)
            rc = read_named_array(L, kw, 6, 0, tuples);
        else if (strcasecmp(kw, "GLOBAL_IDS") == 0 || strcasecmp(kw, "PEDIGREE_IDS") == 0)
            rc = read_named_array(L, kw, 1, 0, tuples);
        else
            return fail_kw(L, LC_ERR_INVALID, "unknown keyword '%.40s'", kw);
        if (rc)
            return rc;
    }
    if (!have_dataset)
        return fail_here(L, LC_ERR_INVALID, "no DATASET");
    if (!L->npoints)
        return fail_here(L, LC_ERR_INVALID, "file ends without POINTS");
    if (L->skipped_attrs)
        LC_WARN(LC_IO_LOG, "%s: %llu arrays skipped (at most %d attributes)", L->file,
                (unsigned long long)L->skipped_attrs, LC_IO_MAX_FILE_ATTRIBUTES);
    return 0;
}

/* Lines win over surfaces (as in PLY and OBJ), surfaces over points. */
static int assemble(vtk_load *L)
{
    size_t line_count = L->line_off.n - 1;
    if (line_count > 0) {
        if (L->triangles.n)
            LC_WARN(LC_IO_LOG, "%s: %zu triangles ignored because the file has lines", L->file, L->triangles.n / 3);
        uint32_t *offsets = L->line_off.v;
        memset(&L->line_off, 0, sizeof L->line_off); /* ownership moves to the scene */
        int rc = lc_io_make_lines(&L->s, L->line_idx.v, L->line_idx.n, offsets, (uint32_t)line_count, L->file, L->err);
        if (rc)
            return rc;
    } else if (L->triangles.n) {
        L->s->type = LC_PRIM_TRIANGLES;
        L->s->triangle_count = (uint32_t)(L->triangles.n / 3);
        L->s->triangles = L->triangles.v;
        memset(&L->triangles, 0, sizeof L->triangles);
    } else {
        L->s->type = LC_PRIM_POINTS;
    }
    lc_io_set_defaults(L->s);
    return 0;
}

int lc_load_vtk_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err)
{
    *out = NULL;
    if (!name)
        name = "<memory>";
    vtk_load L;
    memset(&L, 0, sizeof L);
    L.data = data ? data : (const void *)"";
    L.size = data ? size : 0;
    L.file = name;
    L.err = err;
    L.s = lc_scene_create(name, LC_PRIM_POINTS);
    int rc;
    if (!L.s)
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory", name);
    else if (!(rc = lc_io_u32vec_push(&L.line_off, 0, (size_t)LC_MAX_PRIMITIVES + 1, name, "lines", err)) &&
             !(rc = parse(&L)))
        rc = assemble(&L);
    lc_io_u32vec_free(&L.cell);
    lc_io_u32vec_free(&L.line_idx);
    lc_io_u32vec_free(&L.line_off);
    lc_io_u32vec_free(&L.triangles);
    if (rc) {
        lc_scene_destroy(L.s);
        return rc;
    }
    *out = L.s;
    return 0;
}

int lc_load_vtk(const char *path, lc_scene **out, lc_error *err)
{
    return lc_io_load_path(path, lc_load_vtk_memory, out, err);
}

/* ---- writer */

static void put_be32(FILE *f, uint32_t v)
{
    unsigned char b[4] = {(unsigned char)(v >> 24), (unsigned char)(v >> 16), (unsigned char)(v >> 8),
                          (unsigned char)v};
    fwrite(b, 1, 4, f);
}

static void put_f32(FILE *f, float x)
{
    uint32_t u;
    memcpy(&u, &x, 4);
    put_be32(f, u);
}

int lc_save_vtk(const lc_scene *s, const char *path, lc_error *err)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return lc_err(err, LC_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
    setvbuf(f, NULL, _IOFBF, 1 << 20);
    fprintf(f, "# vtk DataFile Version 3.0\n%s (written by Lucent)\nBINARY\nDATASET POLYDATA\nPOINTS %u float\n",
            s->name[0] ? s->name : "scene", s->vertex_count);
    for (size_t i = 0; i < 3 * (size_t)s->vertex_count; i++)
        put_f32(f, s->positions[i]);
    fprintf(f, "\n");
    if (s->type == LC_PRIM_LINES) {
        fprintf(f, "LINES %u %llu\n", s->line_count, (unsigned long long)s->line_count + s->vertex_count);
        for (uint32_t l = 0; l < s->line_count; l++) {
            put_be32(f, s->line_offsets[l + 1] - s->line_offsets[l]);
            for (uint32_t v = s->line_offsets[l]; v < s->line_offsets[l + 1]; v++)
                put_be32(f, v);
        }
        fprintf(f, "\n");
    } else if (s->type == LC_PRIM_TRIANGLES) {
        fprintf(f, "POLYGONS %u %llu\n", s->triangle_count, 4ull * s->triangle_count);
        for (size_t t = 0; t < s->triangle_count; t++) {
            put_be32(f, 3);
            for (int k = 0; k < 3; k++)
                put_be32(f, s->triangles[3 * t + k]);
        }
        fprintf(f, "\n");
    } else {
        /* One VERTICES cell with every point, so that VTK tools show them. */
        fprintf(f, "VERTICES 1 %llu\n", (unsigned long long)s->vertex_count + 1);
        put_be32(f, s->vertex_count);
        for (uint32_t v = 0; v < s->vertex_count; v++)
            put_be32(f, v);
        fprintf(f, "\n");
    }
    if (s->attribute_count || s->rgb)
        fprintf(f, "POINT_DATA %u\n", s->vertex_count);
    for (int a = 0; a < s->attribute_count; a++) {
        char name[LC_NAME_LEN];
        lc_io_header_name(s->attributes[a].name, name, sizeof name);
        fprintf(f, "SCALARS %s float 1\nLOOKUP_TABLE default\n", name);
        for (uint32_t i = 0; i < s->vertex_count; i++)
            put_f32(f, s->attributes[a].values[i]);
        fprintf(f, "\n");
    }
    if (s->rgb) {
        fprintf(f, "COLOR_SCALARS rgb 3\n");
        for (size_t i = 0; i < 3 * (size_t)s->vertex_count; i++) {
            float c = s->rgb[i];
            fputc((unsigned char)(c > 0 ? (c < 1 ? c * 255.0f + 0.5f : 255) : 0), f);
        }
        fprintf(f, "\n");
    }
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        remove(path);
        return lc_err(err, LC_ERR_IO, "%s: write failed", path);
    }
    return 0;
}
