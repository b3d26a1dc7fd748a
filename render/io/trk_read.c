/* TrackVis .trk reader: fiber tracts as polylines with per-point scalars and
 * per-track properties, either byte order, mapped to RAS+ mm (trk_space.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_util.h"
#include "trk.h"
#include "trk_space.h"

#define HEADER_SIZE 1000
#define NAME_SLOTS 10 /* scalar_name / property_name: 10 names of 20 bytes */
#define NAME_BYTES 20

typedef struct trk_load {
    const unsigned char *data;
    size_t size;
    int swap; /* file is big endian */
    const char *file;
    lc_error *err;
    int n_scalars, n_properties;
    lc_io_part *part; /* the tracks this process keeps (the second pass) */
} trk_load;

/* An error at byte offset pos of the file. */
#define fail(T, code, pos, ...) lc_io_fail((T)->err, code, (T)->file, "byte offset", pos, __VA_ARGS__)

static uint32_t get_u32(const trk_load *T, size_t pos)
{
    const unsigned char *p = T->data + pos;
    if (T->swap)
        return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
    return (uint32_t)p[3] << 24 | (uint32_t)p[2] << 16 | (uint32_t)p[1] << 8 | p[0];
}

static int32_t get_i32(const trk_load *T, size_t pos) { return (int32_t)get_u32(T, pos); }

static int16_t get_i16(const trk_load *T, size_t pos)
{
    const unsigned char *p = T->data + pos;
    return (int16_t)(T->swap ? (p[0] << 8 | p[1]) : (p[1] << 8 | p[0]));
}

static float get_f32(const trk_load *T, size_t pos)
{
    uint32_t u = get_u32(T, pos);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* Attribute names for `count` values from a TrackVis name table. A name may
 * stand for several values: nibabel and DIPY write "name\0N" (N in ASCII
 * after the terminator), which becomes name_0 .. name_N-1. Values without a
 * usable name are called <fallback>_K. */
static void name_values(const trk_load *T, size_t table, int count, const char *fallback, char names[][LC_NAME_LEN])
{
    int k = 0;
    for (int slot = 0; slot < NAME_SLOTS && k < count; slot++) {
        const char *raw = (const char *)T->data + table + (size_t)slot * NAME_BYTES;
        char base[NAME_BYTES + 1];
        size_t len = strnlen(raw, NAME_BYTES);
        memcpy(base, raw, len);
        base[len] = '\0';
        if (!len)
            break;
        int n = 1;
        size_t d = len;
        while (d < NAME_BYTES && raw[d] == '\0')
            d++;
        if (d < NAME_BYTES && raw[d] >= '1' && raw[d] <= '9') {
            n = 0;
            while (d < NAME_BYTES && raw[d] >= '0' && raw[d] <= '9' && n < 1000)
                n = n * 10 + (raw[d++] - '0');
        }
        for (char *c = base; *c; c++) /* names travel in URLs and PLY headers */
            if (*c == ' ' || (unsigned char)*c < 32)
                *c = '_';
        for (int j = 0; j < n && k < count; j++, k++) {
            if (n == 1)
                snprintf(names[k], LC_NAME_LEN, "%s", base);
            else
                snprintf(names[k], LC_NAME_LEN, "%s_%d", base, j);
        }
    }
    for (; k < count; k++)
        snprintf(names[k], LC_NAME_LEN, "%s_%d", fallback, k);
}

static int read_header(trk_load *T, int32_t *n_count)
{
    if (T->size < HEADER_SIZE)
        return lc_err(T->err, LC_ERR_INVALID,
                      "%.80s: byte offset 0: file is %zu bytes, shorter than the %d-byte header", T->file, T->size,
                      HEADER_SIZE);
    if (memcmp(T->data, "TRACK", 5) != 0)
        return fail(T, LC_ERR_INVALID, 0, "not a TrackVis file (missing 'TRACK' magic)");
    /* hdr_size is 1000 in the file's byte order: that is how the order is told. */
    T->swap = 0;
    int32_t hdr = get_i32(T, 996);
    if (hdr != HEADER_SIZE) {
        T->swap = 1;
        if (get_i32(T, 996) != HEADER_SIZE) {
            T->swap = 0;
            return fail(T, LC_ERR_INVALID, 996, "hdr_size %d is not %d in either byte order", (int)hdr, HEADER_SIZE);
        }
    }
    T->n_scalars = get_i16(T, 36);
    T->n_properties = get_i16(T, 238);
    if (T->n_scalars < 0)
        return fail(T, LC_ERR_INVALID, 36, "n_scalars %d is negative", T->n_scalars);
    if (T->n_properties < 0)
        return fail(T, LC_ERR_INVALID, 238, "n_properties %d is negative", T->n_properties);
    *n_count = get_i32(T, 988);
    if (*n_count < 0)
        return fail(T, LC_ERR_INVALID, 988, "n_count %d is negative", (int)*n_count);
    return 0;
}

/* A kept track's coordinates must be finite. Checked in the first pass, which
 * walks every track, not when copying, so that a process reading a share
 * refuses the file as the whole reader does. */
static int check_points(trk_load *T, uint32_t t, size_t first, int32_t m, uint64_t point_bytes)
{
    for (int32_t i = 0; i < m; i++) {
        size_t at = first + (size_t)i * (size_t)point_bytes;
        if (!isfinite(get_f32(T, at)) || !isfinite(get_f32(T, at + 4)) || !isfinite(get_f32(T, at + 8)))
            return fail(T, LC_ERR_INVALID, at, "track %u point %d has a non-finite coordinate", t, (int)i);
    }
    return 0;
}

/* First pass: walks the tracks without copying, validating every count
 * against the bytes left and the coordinates of the tracks kept, and sums
 * what the scene will hold. */
static int scan(trk_load *T, uint32_t tracks, uint64_t *points_out, uint32_t *tracks_out, uint32_t *kept_out)
{
    uint64_t point_bytes = 4 * (3 + (uint64_t)T->n_scalars), prop_bytes = 4 * (uint64_t)T->n_properties;
    size_t pos = HEADER_SIZE;
    uint64_t points = 0;
    uint32_t t = 0, kept = 0;
    for (; tracks ? t < tracks : pos < T->size; t++) {
        if (T->size - pos < 4)
            return fail(T, LC_ERR_INVALID, pos, "track %u: file ends before its point count", t);
        int32_t m = get_i32(T, pos);
        if (m < 0)
            return fail(T, LC_ERR_INVALID, pos, "track %u: point count %d is negative", t, (int)m);
        uint64_t need = (uint64_t)m * point_bytes + prop_bytes;
        if (need > T->size - pos - 4)
            return fail(T, LC_ERR_INVALID, pos, "track %u: %d points exceed the file size", t, (int)m);
        size_t first = pos + 4;
        pos += 4 + (size_t)need;
        if (m >= 2) { /* a line needs two points; shorter tracks are dropped */
            int rc = check_points(T, t, first, m, point_bytes);
            if (rc)
                return rc;
            points += (uint64_t)m;
            kept++;
            if (lc_io_part_count(T->part, (uint32_t)m, T->file, T->err))
                return LC_ERR_NOMEM;
            if (points > LC_MAX_VERTICES)
                return fail(T, LC_ERR_LIMIT, pos, "more than %u points", (unsigned)LC_MAX_VERTICES);
        }
        if (t == UINT32_MAX || kept > LC_MAX_PRIMITIVES)
            return fail(T, LC_ERR_LIMIT, pos, "more than %u tracks", (unsigned)LC_MAX_PRIMITIVES);
    }
    if (pos < T->size && lc_io_part_speaks(T->part))
        LC_WARN(LC_IO_LOG, "%s: %zu bytes after the %u tracks of n_count ignored", T->file, T->size - pos, tracks);
    if (t > kept && lc_io_part_speaks(T->part))
        LC_WARN(LC_IO_LOG, "%s: %u tracks with fewer than 2 points skipped", T->file, t - kept);
    *points_out = points;
    *tracks_out = t;
    *kept_out = kept;
    return 0;
}

/* Second pass: copies positions, scalars and properties of the kept tracks
 * in T->part. */
static int fill(trk_load *T, lc_scene *s, uint32_t tracks, float **attr, int nattr)
{
    int ns = T->n_scalars, np = T->n_properties;
    size_t pos = HEADER_SIZE;
    uint32_t v = 0, line = 0, kept = 0;
    for (uint32_t t = 0; t < tracks; t++) {
        int32_t m = get_i32(T, pos);
        pos += 4;
        int keep = m >= 2 && lc_io_part_keeps(T->part, kept);
        kept += m >= 2;
        if (!keep) { /* skipped: validated by the first pass */
            pos += (size_t)m * (12 + 4 * (size_t)ns) + 4 * (size_t)np;
            continue;
        }
        uint32_t first = v;
        for (int32_t i = 0; i < m; i++, v++, pos += 12 + 4 * (size_t)ns) {
            float *p = s->positions + 3 * (size_t)v;
            for (int k = 0; k < 3; k++) /* finite: checked by the first pass */
                p[k] = get_f32(T, pos + 4 * (size_t)k);
            for (int k = 0; k < ns && k < nattr; k++)
                attr[k][v] = get_f32(T, pos + 12 + 4 * (size_t)k);
        }
        for (int k = 0; k < np; k++, pos += 4) /* a track's properties hold for each of its points */
            if (ns + k < nattr) {
                float value = get_f32(T, pos);
                for (uint32_t j = first; j < v; j++)
                    attr[ns + k][j] = value;
            }
        s->line_offsets[++line] = v;
    }
    return 0;
}

static int load_trk(const void *data, size_t size, const char *name, lc_io_part *part, lc_scene **out, lc_error *err)
{
    *out = NULL;
    if (!name)
        name = "<memory>";
    trk_load T = {
        .data = data ? data : (const void *)"", .size = data ? size : 0, .file = name, .err = err, .part = part};
    int32_t n_count = 0;
    int rc = read_header(&T, &n_count);
    if (rc)
        return rc;
    double to_ras[12];
    if ((rc = lc_trk_voxmm_to_rasmm(T.data, T.swap, name, to_ras, err)))
        return rc;
    uint64_t points = 0;
    uint32_t tracks = 0, kept = 0; /* set by scan() on success */
    /* Each track takes at least its 4-byte count: a lying n_count fails here. */
    if ((uint64_t)n_count > (T.size - HEADER_SIZE) / 4)
        return fail(&T, LC_ERR_INVALID, 988, "n_count %d exceeds the file size", (int)n_count);
    if ((rc = scan(&T, (uint32_t)n_count, &points, &tracks, &kept)))
        return rc;
    if (kept == 0)
        return fail(&T, LC_ERR_INVALID, HEADER_SIZE, "no track with two or more points");
    if ((rc = lc_io_part_choose(part, kept, points, name, err)))
        return rc;
    points = part->points, kept = part->last - part->first;

    int nattr = T.n_scalars + T.n_properties;
    if (nattr > LC_IO_MAX_FILE_ATTRIBUTES) {
        LC_WARN(LC_IO_LOG, "%s: %d scalars and properties, only the first %d kept", name, nattr,
                LC_IO_MAX_FILE_ATTRIBUTES);
        nattr = LC_IO_MAX_FILE_ATTRIBUTES;
    }
    char names[2 * LC_IO_MAX_FILE_ATTRIBUTES][LC_NAME_LEN];
    int ns = T.n_scalars < nattr ? T.n_scalars : nattr;
    name_values(&T, 38, ns, "scalar", names);
    name_values(&T, 240, nattr - ns, "property", names + ns);

    lc_scene *s = lc_scene_create(name, LC_PRIM_LINES);
    float *attr[LC_IO_MAX_FILE_ATTRIBUTES] = {0};
    if (!s)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", name);
    if ((rc = lc_scene_alloc_vertices(s, (uint32_t)points, 0, err)))
        goto fail;
    s->line_offsets = calloc((size_t)kept + 1, sizeof *s->line_offsets);
    s->line_count = kept;
    if (!s->line_offsets) {
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory for %u tracks", name, kept);
        goto fail;
    }
    /* Attributes join the scene before filling so that it owns them on every
     * path. A name taken by an earlier value gets a free one: adding a taken
     * name would replace (and free) the attribute that attr[] still points to. */
    for (int k = 0; k < nattr; k++) {
        float *values = malloc((size_t)points * sizeof *values);
        if (!values) {
            rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory for attributes", name);
            goto fail;
        }
        char unique[LC_NAME_LEN];
        lc_scene_unique_attribute_name(s, names[k], unique);
        int idx = lc_scene_add_attribute(s, unique, values, err);
        if (idx < 0) {
            rc = idx;
            goto fail;
        }
        attr[k] = s->attributes[idx].values;
    }
    if ((rc = fill(&T, s, tracks, attr, nattr)))
        goto fail;
    lc_trk_apply_affine(to_ras, s->positions, s->vertex_count);
    lc_io_set_defaults(s);
    *out = s;
    return 0;
fail:
    lc_scene_destroy(s);
    return rc;
}

int lc_load_trk_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err)
{
    lc_io_part whole = {0};
    return load_trk(data, size, name, &whole, out, err);
}

int lc_load_trk(const char *path, lc_scene **out, lc_error *err)
{
    return lc_io_load_path(path, lc_load_trk_memory, out, err);
}

int lc_load_trk_part(const char *path, int rank, int size, lc_scene **out, lc_error *err)
{
    return lc_io_load_path_part(path, load_trk, rank, size, out, err);
}
