/* LineVis .binlines reader (versions 1 and 2): lines with per-point float
 * attributes, validated against the file size before anything is allocated. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "binlines.h"
#include "io_util.h"

#define HEADER_BYTES 12
#define MAX_FILE_ATTRIBUTES 4096 /* in the file; the scene keeps LC_IO_MAX_FILE_ATTRIBUTES */
#define MAX_NAME_BYTES 4096

typedef struct bl_load {
    const unsigned char *data;
    size_t size;
    const char *file;
    lc_error *err;
    uint32_t version, lines, nattr_file;
    int nattr;   /* attributes kept */
    size_t body; /* offset of the first line */
    lc_io_progress progress;
    lc_io_part *part; /* the lines this process keeps (the second pass) */
} bl_load;

/* An error at byte offset pos of the file. */
#define fail(B, code, pos, ...) lc_io_fail((B)->err, code, (B)->file, "byte offset", pos, __VA_ARGS__)

static uint32_t u32_at(const bl_load *B, size_t pos) { return lc_io_get_u32(B->data + pos, 0); }
static float f32_at(const bl_load *B, size_t pos) { return lc_io_get_f32(B->data + pos, 0); }

/* Header and (version 2) names; names[k] for the kept attributes. */
static int read_header(bl_load *B, char names[][LC_NAME_LEN])
{
    if (B->size < HEADER_BYTES)
        return fail(B, LC_ERR_INVALID, 0, "file is %zu bytes, shorter than the %d-byte header", B->size, HEADER_BYTES);
    B->version = u32_at(B, 0);
    if (B->version != 1 && B->version != 2)
        return fail(B, LC_ERR_INVALID, 0, "version %u is not 1 or 2 (not a LineVis .binlines file?)", B->version);
    B->lines = u32_at(B, 4);
    B->nattr_file = u32_at(B, 8);
    if (B->nattr_file > MAX_FILE_ATTRIBUTES)
        return fail(B, LC_ERR_LIMIT, 8, "%u attributes (limit %d)", B->nattr_file, MAX_FILE_ATTRIBUTES);
    if ((uint64_t)B->lines > (B->size - HEADER_BYTES) / 4) /* each line takes at least its count */
        return fail(B, LC_ERR_INVALID, 4, "line count %u exceeds the file size", B->lines);
    B->nattr = B->nattr_file < LC_IO_MAX_FILE_ATTRIBUTES ? (int)B->nattr_file : LC_IO_MAX_FILE_ATTRIBUTES;
    if ((uint32_t)B->nattr < B->nattr_file)
        LC_WARN(LC_IO_LOG, "%s: %u attributes, only the first %d kept", B->file, B->nattr_file, B->nattr);
    size_t pos = HEADER_BYTES;
    for (uint32_t a = 0; a < B->nattr_file; a++) {
        char name[LC_NAME_LEN] = "";
        if (B->version >= 2) {
            if (B->size - pos < 4)
                return fail(B, LC_ERR_INVALID, pos, "file ends before the name of attribute %u", a);
            uint32_t len = u32_at(B, pos);
            if (len > MAX_NAME_BYTES || len > B->size - pos - 4)
                return fail(B, LC_ERR_INVALID, pos, "attribute %u: name length %u exceeds %s", a, len,
                            len > MAX_NAME_BYTES ? "the 4096-byte cap" : "the file size");
            size_t n = len < LC_NAME_LEN - 1 ? len : LC_NAME_LEN - 1;
            memcpy(name, B->data + pos + 4, n);
            name[n] = '\0';
            for (char *c = name; *c; c++) /* names travel in URLs and PLY headers */
                if (*c == ' ' || (unsigned char)*c < 32)
                    *c = '_';
            pos += 4 + (size_t)len;
        }
        if ((int)a < B->nattr) {
            int taken = !name[0];
            for (uint32_t b = 0; b < a && !taken; b++)
                taken = strcmp(names[b], name) == 0;
            if (taken)
                snprintf(name, sizeof name, "attribute_%u", a);
            memcpy(names[a], name, LC_NAME_LEN);
        }
    }
    B->body = pos;
    return 0;
}

/* One pass over the lines. Without a scene it validates every count against
 * the bytes left and counts the points and lines kept; with one it fills
 * positions, attributes and line offsets of the kept lines in B->part. */
static int walk(bl_load *B, lc_scene *s, float **attr, uint64_t *points_out, uint64_t *lines_out)
{
    size_t pos = B->body;
    uint64_t points = 0, kept = 0, dropped = 0, short_lines = 0;
    size_t first_bad = 0;
    uint64_t attr_bytes = 4 * (uint64_t)B->nattr_file;
    lc_io_part *P = B->part;
    for (uint32_t l = 0; l < B->lines; l++) {
        if ((l & 0xFFF) == 0) /* the first pass is the first half of the work */
            lc_io_progress_report(&B->progress, pos + (s ? B->size : 0), 2 * B->size);
        if (B->size - pos < 4)
            return fail(B, LC_ERR_INVALID, pos, "line %u: file ends before its point count", l);
        uint32_t n = u32_at(B, pos);
        uint64_t need = (uint64_t)n * (12 + attr_bytes);
        if (need > B->size - pos - 4)
            return fail(B, LC_ERR_INVALID, pos, "line %u: %u points exceed the file size", l, n);
        size_t xyz = pos + 4, values = xyz + 12 * (size_t)n;
        uint64_t run = 0, at_run = points - P->base; /* where this line's points go in s */
        int keep = s && lc_io_part_keeps(P, kept);
        for (uint32_t i = 0; i < n; i++) {
            size_t at = xyz + 12 * (size_t)i;
            float p[3] = {f32_at(B, at), f32_at(B, at + 4), f32_at(B, at + 8)};
            if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
                if (!dropped++)
                    first_bad = at;
                continue;
            }
            if (keep && at_run + run < s->vertex_count) {
                memcpy(s->positions + 3 * (at_run + run), p, sizeof p);
                for (int a = 0; a < B->nattr; a++)
                    attr[a][at_run + run] = f32_at(B, values + 4 * ((size_t)a * n + i));
            }
            run++;
        }
        if (run >= 2) {
            points += run;
            kept++;
            if (points > LC_MAX_VERTICES)
                return fail(B, LC_ERR_LIMIT, pos, "more than %u points", (unsigned)LC_MAX_VERTICES);
            if (keep)
                s->line_offsets[kept - P->first] = (uint32_t)(points - P->base);
            else if (!s && lc_io_part_count(P, (uint32_t)run, B->file, B->err))
                return LC_ERR_NOMEM;
        } else {
            short_lines++;
        }
        pos += 4 + (size_t)need;
    }
    if (!s && lc_io_part_speaks(P)) {
        if (pos < B->size)
            LC_WARN(LC_IO_LOG, "%s: %zu bytes after the %u lines ignored", B->file, B->size - pos, B->lines);
        if (dropped)
            LC_WARN(LC_IO_LOG, "%s: byte offset %zu: %llu points with NaN/Inf coordinates dropped", B->file, first_bad,
                    (unsigned long long)dropped);
        if (short_lines)
            LC_WARN(LC_IO_LOG, "%s: %llu lines with fewer than 2 points skipped", B->file,
                    (unsigned long long)short_lines);
    }
    *points_out = points;
    *lines_out = kept;
    return 0;
}

static int load_binlines(const void *data, size_t size, const char *name, lc_io_part *part, lc_scene **out,
                         lc_error *err)
{
    *out = NULL;
    if (!name)
        name = "<memory>";
    bl_load B = {
        .data = data ? data : (const void *)"", .size = data ? size : 0, .file = name, .err = err, .part = part};
    lc_io_progress_start(&B.progress, name);
    char names[LC_IO_MAX_FILE_ATTRIBUTES][LC_NAME_LEN];
    int rc = read_header(&B, names);
    if (rc)
        return rc;
    uint64_t points = 0, lines = 0;
    if ((rc = walk(&B, NULL, NULL, &points, &lines)))
        return rc;
    if (lines == 0)
        return fail(&B, LC_ERR_INVALID, B.body, "no line with two or more points");
    if ((rc = lc_io_part_choose(part, (uint32_t)lines, points, name, err)))
        return rc;
    lc_scene *s = lc_scene_create(name, LC_PRIM_LINES);
    float *attr[LC_IO_MAX_FILE_ATTRIBUTES] = {0};
    if (!s)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", name);
    points = part->points, lines = part->last - part->first;
    if ((rc = lc_scene_alloc_vertices(s, (uint32_t)points, 0, err)))
        goto fail;
    s->line_offsets = calloc((size_t)lines + 1, sizeof *s->line_offsets);
    s->line_count = (uint32_t)lines;
    if (!s->line_offsets) {
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory for %llu lines", name, (unsigned long long)lines);
        goto fail;
    }
    for (int a = 0; a < B.nattr; a++) { /* the scene owns them on every path */
        float *values = malloc((size_t)points * sizeof *values);
        if (!values) {
            rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory for attributes", name);
            goto fail;
        }
        for (int k = 0; lc_scene_find_attribute(s, names[a]) >= 0; k++) /* never replace an earlier one */
            snprintf(names[a], LC_NAME_LEN, "attribute_%d_%d", a, k);
        int idx = lc_scene_add_attribute(s, names[a], values, err);
        if (idx < 0) {
            rc = idx;
            goto fail;
        }
        attr[a] = s->attributes[idx].values;
    }
    if ((rc = walk(&B, s, attr, &points, &lines)))
        goto fail;
    lc_io_set_defaults(s);
    *out = s;
    return 0;
fail:
    lc_scene_destroy(s);
    return rc;
}

int lc_load_binlines_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err)
{
    lc_io_part whole = {0};
    return load_binlines(data, size, name, &whole, out, err);
}

int lc_load_binlines(const char *path, lc_scene **out, lc_error *err)
{
    return lc_io_load_path(path, lc_load_binlines_memory, out, err);
}

int lc_load_binlines_part(const char *path, int rank, int size, lc_scene **out, lc_error *err)
{
    return lc_io_load_path_part(path, load_binlines, rank, size, out, err);
}
