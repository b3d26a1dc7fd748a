/* Helpers shared by the dataset readers and writers of this folder: file
 * mapping, bounded number parsing, capped growable index arrays and polyline
 * assembly. Internal to render/io/; the public API is loaders.h. */
#ifndef LC_IO_UTIL_H
#define LC_IO_UTIL_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "lc_base.h"
#include "scene.h"

#define LC_IO_LOG "loader" /* module tag of the loaders' log lines */

/* A whole input file, read-only. Regular files are mmap'd so that a dataset of
 * several GB is parsed without a copy. */
typedef struct lc_io_file {
    const char *data;
    size_t size;
    void *map; /* munmap target, or NULL */
} lc_io_file;

int lc_io_file_open(const char *path, lc_io_file *f, lc_error *err);
void lc_io_file_close(lc_io_file *f);

/* Pointer to the last path component. */
const char *lc_io_basename(const char *path);
/* File name without folders and without its last extension, truncated to n. */
void lc_io_stem(const char *path, char *out, size_t n);

/* Copies an attribute name for a writer's header line, where names cannot hold
 * whitespace (PLY properties, VTK arrays): blanks become '_', "" becomes "attribute". */
void lc_io_header_name(const char *name, char *out, size_t n);

/* Maps path and runs a memory loader on it (messages name the file's base
 * name); the scene is named after the file stem. */
typedef int (*lc_io_memory_loader)(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_io_load_path(const char *path, lc_io_memory_loader load, lc_scene **out, lc_error *err);

/* Parses a decimal floating-point number (also "nan", "inf", "infinity") at
 * p, never reading at or past end. Returns the end of the number, or NULL when
 * p does not start one. The result is exact for the usual short decimals
 * (Clinger's fast path) and falls back to strtod on a bounded copy. */
const char *lc_io_parse_double(const char *p, const char *end, double *out);

/* Growable uint32 array whose length never exceeds `limit` elements. */
typedef struct lc_io_u32vec {
    uint32_t *v;
    size_t n, cap;
} lc_io_u32vec;

/* Makes room for `extra` more elements; LC_ERR_LIMIT beyond limit. `what`
 * names the array in the message ("triangles"). */
int lc_io_u32vec_reserve(lc_io_u32vec *a, size_t extra, size_t limit, const char *file, const char *what,
                         lc_error *err);
static inline int lc_io_u32vec_push(lc_io_u32vec *a, uint32_t x, size_t limit, const char *file, const char *what,
                                    lc_error *err)
{
    if (a->n == a->cap) {
        int rc = lc_io_u32vec_reserve(a, 1, limit, file, what, err);
        if (rc)
            return rc;
    }
    a->v[a->n++] = x;
    return 0;
}
void lc_io_u32vec_free(lc_io_u32vec *a);

/* A process's share of a file (lc_scene_read_file_part). For lines, a
 * reader's first pass records each kept line's point count with
 * lc_io_part_count, lc_io_part_choose picks the whole lines [first, last)
 * that lc_scene_shard would give the process, and the second pass keeps only
 * those (points before the share counted, not stored); a point-cloud reader
 * uses rank and size alone. size 0: the whole file. Only the process of rank
 * 0 warns about what the file holds (every process reads it). */
typedef struct lc_io_part {
    int rank, size;
    lc_io_u32vec counts;   /* first pass: points of each kept line */
    uint32_t first, last;  /* kept lines of the share */
    uint64_t base, points; /* kept points before the share, in it */
} lc_io_part;

static inline int lc_io_part_active(const lc_io_part *p) { return p && p->size > 0; }
int lc_io_part_count(lc_io_part *p, uint32_t points, const char *file, lc_error *err);
/* After the first pass found `lines` kept lines of total_points points in
 * all: picks the share (all of them for the whole file). */
int lc_io_part_choose(lc_io_part *p, uint32_t lines, uint64_t total_points, const char *file, lc_error *err);
/* Whether kept line `line` belongs to the share. */
static inline int lc_io_part_keeps(const lc_io_part *p, uint64_t line) { return line >= p->first && line < p->last; }
/* Whether this process reports what the file holds (warnings): rank 0 or the whole. */
static inline int lc_io_part_speaks(const lc_io_part *p) { return !lc_io_part_active(p) || p->rank == 0; }
void lc_io_part_free(lc_io_part *p);

/* Maps path and returns test(data, size, name), or 0 when the file cannot be
 * opened: a cheap look at a file's contents (which reader applies). */
int lc_io_file_test(const char *path, int (*test)(const char *data, size_t size, const char *name));

/* Maps path and runs a part reader on it, as lc_io_load_path does. */
typedef int (*lc_io_part_loader)(const void *data, size_t size, const char *name, lc_io_part *part, lc_scene **out,
                                 lc_error *err);
int lc_io_load_path_part(const char *path, lc_io_part_loader load, int rank, int size, lc_scene **out, lc_error *err);

/* Turns the points scene *sp into a LINES scene whose line i holds the source
 * vertices idx[offsets[i] .. offsets[i+1]) (duplicated where lines share
 * vertices, because a scene's line owns a contiguous vertex range). When idx is
 * the identity over all vertices the scene is converted in place; otherwise a
 * new scene with gathered positions, rgb and attributes replaces *sp (the old
 * one is destroyed). Takes ownership of offsets (line_count + 1 entries) in
 * every case. */
int lc_io_make_lines(lc_scene **sp, const uint32_t *idx, size_t idx_count, uint32_t *offsets, uint32_t line_count,
                     const char *file, lc_error *err);

/* Sets default_importance (an attribute named importance, vt or scalar, else
 * the first attribute, else "" so that finalize derives one) and default_color
 * ("rgb" when the file has colours, else "importance"). */
void lc_io_set_defaults(lc_scene *s);

/* The text readers' line cursor: the next line of [*p, end) as [*ls, *le)
 * without its end of line; a trailing CR goes too, and with trim every blank
 * (space, tab, CR) at either end. Advances *p past the line; 0 at the end. */
static inline int lc_io_next_line(const char **p, const char *end, int trim, const char **ls, const char **le)
{
    if (*p >= end)
        return 0;
    const char *nl = memchr(*p, '\n', (size_t)(end - *p));
    *ls = *p;
    *le = nl ? nl : end;
    *p = nl ? nl + 1 : end;
    while (*le > *ls && ((*le)[-1] == '\r' || (trim && ((*le)[-1] == ' ' || (*le)[-1] == '\t'))))
        (*le)--;
    while (trim && *ls < *le && (**ls == ' ' || **ls == '\t' || **ls == '\r'))
        (*ls)++;
    return 1;
}

/* Unaligned little/big-endian reads of the binary readers. */
static inline uint32_t lc_io_get_u32(const void *at, int big)
{
    const unsigned char *p = at;
    if (big)
        return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
    return (uint32_t)p[3] << 24 | (uint32_t)p[2] << 16 | (uint32_t)p[1] << 8 | p[0];
}
static inline uint64_t lc_io_get_u64(const void *at, int big)
{
    const unsigned char *p = at;
    uint64_t lo = lc_io_get_u32(p + (big ? 4 : 0), big), hi = lc_io_get_u32(p + (big ? 0 : 4), big);
    return hi << 32 | lo;
}
static inline float lc_io_get_f32(const void *at, int big)
{
    uint32_t u = lc_io_get_u32(at, big);
    float f;
    memcpy(&f, &u, 4);
    return f;
}
static inline double lc_io_get_f64(const void *at, int big)
{
    uint64_t u = lc_io_get_u64(at, big);
    double d;
    memcpy(&d, &u, 8);
    return d;
}

/* A reader's error: "FILE: WHERE POS: reason" (WHERE is "byte offset" or
 * "line"), the file name cut to 80 bytes. Returns code. */
int lc_io_fail(lc_error *err, int code, const char *file, const char *where, size_t pos, const char *fmt, ...)
    __attribute__((format(printf, 6, 7)));

/* Progress of a long load: a reader calls lc_io_progress_report every so often
 * with the work done of the total (bytes, vertices); once the load has run
 * longer than a second a line "file: loading, N % after T s" goes to stderr,
 * then one a second. */
typedef struct lc_io_progress {
    const char *file;
    double started, next; /* lc_now() seconds */
} lc_io_progress;
void lc_io_progress_start(lc_io_progress *p, const char *file);
void lc_io_progress_report(lc_io_progress *p, size_t done, size_t total);

/* The memory budget of one load (docs/MEMORY.md "Refusing what does not fit").
 * A file may not make us allocate more than LC_IO_LOAD_RATIO times its own
 * size (at least LC_IO_LOAD_FLOOR bytes): a load needs at least
 * LC_IO_LOAD_BYTES_PER_VERTEX per vertex (positions, vertex elements, the
 * level of detail's error, parent and order arrays) beside what the reader
 * inflates. Nor may a dataset whose resident size is surely over the
 * --max-memory left (lc_io_set_memory_limit; process-wide, set before
 * loading; 0 = none) be read at all: LC_IO_RESIDENT_BYTES_PER_VERTEX is below
 * what any layout keeps a vertex, so this never refuses what the estimate
 * after loading would accept. Readers whose declared counts can expand
 * (compressed entries) check with lc_io_check_load from the counts before
 * allocating; every load is checked again before finalize. */
#define LC_IO_LOAD_RATIO 64
#define LC_IO_LOAD_FLOOR (64ull << 20)
#define LC_IO_LOAD_BYTES_PER_VERTEX 64
#define LC_IO_RESIDENT_BYTES_PER_VERTEX 24
void lc_io_set_memory_limit(uint64_t bytes);
/* LC_ERR_LIMIT, naming file, what, the estimate and the limit it exceeds,
 * when a load of `vertices` (and `extra` bytes more, e.g. inflated arrays)
 * from a file_bytes input is over the budget. */
int lc_io_check_load(const char *file, uint64_t file_bytes, uint64_t vertices, uint64_t extra, const char *what,
                     lc_error *err);
/* The same for a load measured in bytes (a vector field's grid): resident
 * bytes over the --max-memory left, or need bytes over the load budget. */
int lc_io_check_bytes(const char *file, uint64_t file_bytes, uint64_t resident, uint64_t need, const char *what,
                      lc_error *err);

/* Attribute slots a loader may fill: finalize adds up to four derived ones. */
#define LC_IO_MAX_FILE_ATTRIBUTES (LC_MAX_ATTRIBUTES - 4)

#endif
