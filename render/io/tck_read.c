/* MRtrix .tck reader: a text header, then xyz triplets with NaN separators and
 * an Inf end marker, float32 or float64 of either byte order. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "io_util.h"
#include "tck.h"

#define MAGIC "mrtrix tracks"
#define MAX_HEADER_LINES 100000 /* a header is a few dozen lines; this bounds a file of newlines */

typedef struct tck_load {
    const unsigned char *data;
    size_t size;
    const char *file;
    lc_error *err;
    size_t offset;   /* first byte of the data */
    int elem;        /* 4 or 8 */
    int big;         /* big endian */
    long long count; /* the header's "count", or -1 */
    lc_io_progress progress;
    lc_io_part *part; /* the streamlines this process keeps (the second pass) */
} tck_load;

/* An error at byte offset pos of the file. */
#define fail_at(T, code, pos, ...) lc_io_fail((T)->err, code, (T)->file, "byte offset", pos, __VA_ARGS__)

#define fail_line(T, line, ...) lc_io_fail((T)->err, LC_ERR_INVALID, (T)->file, "line", line, __VA_ARGS__)

/* Value of a "key: value" line [p, le) when its key is `key`, else NULL. */
static const char *value_of(const char *p, const char *le, const char *key)
{
    size_t n = strlen(key);
    if ((size_t)(le - p) <= n || strncasecmp(p, key, n) != 0 || p[n] != ':')
        return NULL;
    p += n + 1;
    while (p < le && (*p == ' ' || *p == '\t'))
        p++;
    return p;
}

static int parse_u64(const char *p, const char *le, unsigned long long *out)
{
    unsigned long long v = 0;
    const char *start = p;
    while (p < le && *p >= '0' && *p <= '9') {
        if (v > (~0ull - 9) / 10)
            return -1;
        v = v * 10 + (unsigned)(*p++ - '0');
    }
    while (p < le && (*p == ' ' || *p == '\t'))
        p++;
    *out = v;
    return p > start && p == le ? 0 : -1;
}

static int read_header(tck_load *T)
{
    const char *text = (const char *)T->data, *end = text + T->size;
    const char *p = text;
    size_t line = 0;
    int have_type = 0, ended = 0;
    size_t have_file = 0; /* line of 'file:' */
    T->count = -1;
    while (p < end && !ended) {
        if (++line > MAX_HEADER_LINES)
            return fail_line(T, line, "header longer than %d lines without END", MAX_HEADER_LINES);
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        if (!nl)
            return fail_line(T, line, "header has no END line (file ends inside the header)");
        const char *le = nl;
        if (le > p && le[-1] == '\r')
            le--;
        const char *v;
        if (line == 1) {
            if ((size_t)(le - p) != strlen(MAGIC) || memcmp(p, MAGIC, strlen(MAGIC)) != 0)
                return fail_line(T, 1, "not an MRtrix tracks file (first line is not '" MAGIC "')");
        } else if (le - p == 3 && memcmp(p, "END", 3) == 0) {
            ended = 1;
        } else if ((v = value_of(p, le, "datatype"))) {
            size_t n = (size_t)(le - v);
            static const char *const types[4] = {"Float32LE", "Float32BE", "Float64LE", "Float64BE"};
            int t = 0;
            while (t < 4 && !(n == 9 && strncasecmp(v, types[t], 9) == 0))
                t++;
            if (t == 4)
                return fail_line(T, line, "datatype '%.*s' is not Float32LE, Float32BE, Float64LE or Float64BE",
                                 (int)(n < 40 ? n : 40), v);
            T->elem = t < 2 ? 4 : 8;
            T->big = t % 2;
            have_type = 1;
        } else if ((v = value_of(p, le, "file"))) {
            unsigned long long off;
            if (v >= le || *v != '.' || v + 1 >= le || (v[1] != ' ' && v[1] != '\t'))
                return fail_line(T, line, "data in another file ('file: %.*s') is not supported",
                                 (int)(le - v < 60 ? le - v : 60), v);
            v += 2;
            while (v < le && (*v == ' ' || *v == '\t'))
                v++;
            if (parse_u64(v, le, &off) != 0)
                return fail_line(T, line, "'file: .' needs a byte offset");
            T->offset = off > T->size ? SIZE_MAX : (size_t)off;
            have_file = line;
        } else if ((v = value_of(p, le, "count"))) {
            unsigned long long c;
            if (parse_u64(v, le, &c) == 0 && c < (1ull << 62))
                T->count = (long long)c;
        }
        p = nl + 1;
    }
    if (!ended)
        return fail_line(T, line, "header has no END line");
    if (!have_type)
        return fail_line(T, line, "header has no datatype");
    if (!have_file)
        return fail_line(T, line, "header has no 'file: . OFFSET' line");
    if (T->offset == SIZE_MAX)
        return fail_line(T, have_file, "data offset exceeds the file size %zu", T->size);
    size_t header_end = (size_t)(p - text);
    if (T->offset < header_end)
        return fail_line(T, line, "data offset %zu lies inside the header (which ends at byte %zu)", T->offset,
                         header_end);
    return 0;
}

enum { POINT, SEPARATOR, END_MARK, NONFINITE };

static int classify(const double v[3])
{
    if (isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]))
        return POINT;
    if (isnan(v[0]) && isnan(v[1]) && isnan(v[2]))
        return SEPARATOR;
    if (isinf(v[0]) && isinf(v[1]) && isinf(v[2]))
        return END_MARK;
    return NONFINITE;
}

static void get_triplet(const tck_load *T, size_t pos, double v[3])
{
    for (int k = 0; k < 3; k++) {
        const unsigned char *at = T->data + pos + (size_t)k * (size_t)T->elem;
        v[k] = T->elem == 4 ? (double)lc_io_get_f32(at, T->big) : lc_io_get_f64(at, T->big);
    }
}

/* Walks the triplets once. Without a scene it counts the points and lines that
 * will be kept; with one it fills positions and line offsets (the counts of
 * the first walk). */
/* A streamline of run points is kept: the first pass records it for the
 * split, the second stores its end if it belongs to the share. */
static int end_line(tck_load *T, lc_scene *s, uint64_t run, uint64_t *points, uint64_t *lines)
{
    lc_io_part *P = T->part;
    int keep = lc_io_part_keeps(P, *lines);
    *points += run;
    ++*lines;
    if (s && keep)
        s->line_offsets[*lines - P->first] = (uint32_t)(*points - P->base);
    return s ? 0 : lc_io_part_count(P, (uint32_t)run, T->file, T->err); /* run <= LC_MAX_VERTICES */
}

static int walk(tck_load *T, lc_scene *s, uint64_t *points_out, uint64_t *lines_out)
{
    size_t tsz = 3 * (size_t)T->elem, pos = T->offset;
    uint64_t points = 0, lines = 0, run = 0, dropped_points = 0, short_lines = 0, raw_lines = 0;
    int rc;
    size_t first_bad = 0;
    int ended = 0;
    lc_io_part *P = T->part;
    for (uint64_t i = 0; pos + tsz <= T->size; pos += tsz, i++) {
        if ((i & 0x3FFFF) == 0) /* the first pass is the first half of the work */
            lc_io_progress_report(&T->progress, pos + (s ? T->size : 0), 2 * T->size);
        double v[3];
        get_triplet(T, pos, v);
        int kind = classify(v);
        if (kind == POINT) {
            uint64_t at = points - P->base + run; /* a short last line is not stored */
            if (s && lc_io_part_keeps(P, lines) && at < s->vertex_count) {
                float *d = s->positions + 3 * at;
                d[0] = (float)v[0], d[1] = (float)v[1], d[2] = (float)v[2];
            }
            run++;
            if (points + run > LC_MAX_VERTICES)
                return fail_at(T, LC_ERR_LIMIT, pos, "more than %u points", (unsigned)LC_MAX_VERTICES);
            continue;
        }
        if (kind == NONFINITE) {
            if (!dropped_points++)
                first_bad = pos;
            continue;
        }
        if (kind == SEPARATOR || run > 0)
            raw_lines++;
        if (run >= 2) { /* a line needs two points */
            if ((rc = end_line(T, s, run, &points, &lines)))
                return rc;
            if (lines > LC_MAX_PRIMITIVES)
                return fail_at(T, LC_ERR_LIMIT, pos, "more than %u streamlines", (unsigned)LC_MAX_PRIMITIVES);
        } else if (kind == SEPARATOR || run > 0) {
            short_lines++;
        }
        run = 0;
        if (kind == END_MARK) {
            ended = 1;
            break;
        }
    }
    if (!ended) {
        if (pos != T->size && T->size - pos < tsz)
            return fail_at(T, LC_ERR_INVALID, pos, "truncated: %zu bytes left, less than one %zu-byte point",
                           T->size - pos, tsz);
        if (run > 0) { /* the last streamline lost its terminator: keep what is there */
            raw_lines++;
            if (run >= 2) {
                if ((rc = end_line(T, s, run, &points, &lines)))
                    return rc;
            } else {
                short_lines++;
            }
        }
        if (!s && lc_io_part_speaks(P))
            LC_WARN(LC_IO_LOG, "%s: byte offset %zu: no end-of-data marker (Inf triplet); the file may be truncated",
                    T->file, pos);
    }
    if (!s && lc_io_part_speaks(P)) {
        if (dropped_points)
            LC_WARN(LC_IO_LOG, "%s: byte offset %zu: %llu points with NaN/Inf coordinates dropped", T->file, first_bad,
                    (unsigned long long)dropped_points);
        if (short_lines)
            LC_WARN(LC_IO_LOG, "%s: %llu streamlines with fewer than 2 points skipped", T->file,
                    (unsigned long long)short_lines);
        if (T->count >= 0 && (uint64_t)T->count != raw_lines)
            LC_WARN(LC_IO_LOG, "%s: header count %lld, file holds %llu streamlines", T->file, T->count,
                    (unsigned long long)raw_lines);
    }
    *points_out = points;
    *lines_out = lines;
    return 0;
}

static int load_tck(const void *data, size_t size, const char *name, lc_io_part *part, lc_scene **out, lc_error *err)
{
    *out = NULL;
    if (!name)
        name = "<memory>";
    tck_load T = {
        .data = data ? data : (const void *)"", .size = data ? size : 0, .file = name, .err = err, .part = part};
    lc_io_progress_start(&T.progress, name);
    int rc = read_header(&T);
    if (rc)
        return rc;
    uint64_t points = 0, lines = 0;
    if ((rc = walk(&T, NULL, &points, &lines)))
        return rc;
    if (lines == 0)
        return fail_at(&T, LC_ERR_INVALID, T.offset, "no streamline with two or more points");
    if ((rc = lc_io_part_choose(part, (uint32_t)lines, points, name, err)))
        return rc;
    lc_scene *s = lc_scene_create(name, LC_PRIM_LINES);
    if (!s)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", name);
    points = part->points, lines = part->last - part->first;
    if ((rc = lc_scene_alloc_vertices(s, (uint32_t)points, 0, err)))
        goto fail;
    s->line_offsets = calloc((size_t)lines + 1, sizeof *s->line_offsets);
    s->line_count = (uint32_t)lines;
    if (!s->line_offsets) {
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory for %llu streamlines", name, (unsigned long long)lines);
        goto fail;
    }
    if ((rc = walk(&T, s, &points, &lines)))
        goto fail;
    lc_io_set_defaults(s);
    *out = s;
    return 0;
fail:
    lc_scene_destroy(s);
    return rc;
}

int lc_load_tck_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err)
{
    lc_io_part whole = {0};
    return load_tck(data, size, name, &whole, out, err);
}

int lc_load_tck(const char *path, lc_scene **out, lc_error *err)
{
    return lc_io_load_path(path, lc_load_tck_memory, out, err);
}

int lc_load_tck_part(const char *path, int rank, int size, lc_scene **out, lc_error *err)
{
    return lc_io_load_path_part(path, load_tck, rank, size, out, err);
}
