/* Loader plumbing shared by the dataset readers (file mapping, number parsing,
 * polyline assembly) and lc_scene_load_file, which picks the format by extension. */
#include "io_util.h"
#include "scene_shard.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

int lc_io_file_open(const char *path, lc_io_file *f, lc_error *err)
{
    memset(f, 0, sizeof *f);
    f->data = "";
    /* O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer
     * before the regular-file check below could refuse it. */
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
    if (fd < 0)
        return lc_err(err, LC_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0) {
        int e = errno;
        close(fd);
        return lc_err(err, LC_ERR_IO, "%s: cannot stat: %s", path, strerror(e));
    }
    if (!S_ISREG(st.st_mode)) {
        close(fd);
        return lc_err(err, LC_ERR_IO, "%s: not a regular file", path);
    }
    if (st.st_size == 0) { /* mmap rejects length 0; an empty file is a parse error later */
        close(fd);
        return 0;
    }
    if ((uint64_t)st.st_size > (uint64_t)SIZE_MAX) {
        close(fd);
        return lc_err(err, LC_ERR_LIMIT, "%s: file too large", path);
    }
    void *map = mmap(NULL, (size_t)st.st_size, PROT_READ, MAP_PRIVATE, fd, 0);
    int e = errno;
    close(fd);
    if (map == MAP_FAILED)
        return lc_err(err, LC_ERR_IO, "%s: cannot map: %s", path, strerror(e));
    madvise(map, (size_t)st.st_size, MADV_SEQUENTIAL); /* parsers read front to back */
    f->map = map;
    f->data = map;
    f->size = (size_t)st.st_size;
    return 0;
}

void lc_io_file_close(lc_io_file *f)
{
    if (f->map)
        munmap(f->map, f->size);
    memset(f, 0, sizeof *f);
}

const char *lc_io_basename(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

void lc_io_header_name(const char *name, char *out, size_t n)
{
    snprintf(out, n, "%s", name[0] ? name : "attribute");
    for (char *c = out; *c; c++)
        if (*c == ' ' || *c == '\t' || *c == '\n' || *c == '\r')
            *c = '_';
}

int lc_io_load_path(const char *path, lc_io_memory_loader load, lc_scene **out, lc_error *err)
{
    *out = NULL;
    lc_io_file f;
    int rc = lc_io_file_open(path, &f, err);
    if (rc)
        return rc;
    rc = load(f.data, f.size, lc_io_basename(path), out, err);
    lc_io_file_close(&f);
    if (!rc)
        lc_io_stem(path, (*out)->name, sizeof(*out)->name);
    return rc;
}

int lc_io_load_path_part(const char *path, lc_io_part_loader load, int rank, int size, lc_scene **out, lc_error *err)
{
    *out = NULL;
    lc_io_file f;
    int rc = lc_io_file_open(path, &f, err);
    if (rc)
        return rc;
    lc_io_part part = {.rank = rank, .size = size};
    rc = load(f.data, f.size, lc_io_basename(path), &part, out, err);
    lc_io_part_free(&part);
    lc_io_file_close(&f);
    if (!rc)
        lc_io_stem(path, (*out)->name, sizeof(*out)->name);
    return rc;
}

static _Atomic uint64_t memory_limit;

void lc_io_set_memory_limit(uint64_t bytes) { memory_limit = bytes; }

int lc_io_check_load(const char *file, uint64_t file_bytes, uint64_t vertices, uint64_t extra, const char *what,
                     lc_error *err)
{
    uint64_t big = UINT64_MAX / LC_IO_LOAD_BYTES_PER_VERTEX;
    uint64_t need = vertices > big ? UINT64_MAX : vertices * LC_IO_LOAD_BYTES_PER_VERTEX;
    need = need > UINT64_MAX - extra ? UINT64_MAX : need + extra;
    return lc_io_check_bytes(file, file_bytes, vertices > big ? UINT64_MAX : vertices * LC_IO_RESIDENT_BYTES_PER_VERTEX,
                             need, what, err);
}

int lc_io_check_bytes(const char *file, uint64_t file_bytes, uint64_t resident, uint64_t need, const char *what,
                      lc_error *err)
{
    uint64_t ratio = file_bytes > UINT64_MAX / LC_IO_LOAD_RATIO ? UINT64_MAX : file_bytes * LC_IO_LOAD_RATIO;
    uint64_t budget = ratio > LC_IO_LOAD_FLOOR ? ratio : LC_IO_LOAD_FLOOR, limit = memory_limit;
    if (limit && resident > limit)
        return lc_err(err, LC_ERR_LIMIT,
                      "%.80s: refused before loading: %s stay resident with at least %.1f MB, over --max-memory "
                      "%.1f MB",
                      file, what, resident / 1e6, limit / 1e6);
    if (need > budget)
        return lc_err(err, LC_ERR_LIMIT,
                      "%.80s: refused before loading: %s need an estimated %.1f MB, over the load budget of %.1f MB "
                      "(%d times the file's %.3f MB, at least %.0f MB)",
                      file, what, need / 1e6, budget / 1e6, LC_IO_LOAD_RATIO, file_bytes / 1e6, LC_IO_LOAD_FLOOR / 1e6);
    return 0;
}

int lc_io_file_test(const char *path, int (*test)(const char *data, size_t size, const char *name))
{
    lc_io_file f;
    lc_error err = {0};
    if (lc_io_file_open(path, &f, &err) != 0)
        return 0;
    int rc = test(f.data, f.size, lc_io_basename(path));
    lc_io_file_close(&f);
    return rc;
}

int lc_io_part_count(lc_io_part *p, uint32_t points, const char *file, lc_error *err)
{
    if (!lc_io_part_active(p))
        return 0;
    return lc_io_u32vec_push(&p->counts, points, LC_MAX_PRIMITIVES, file, "lines", err);
}

int lc_io_part_choose(lc_io_part *p, uint32_t lines, uint64_t total_points, const char *file, lc_error *err)
{
    p->first = 0, p->last = lines, p->base = 0, p->points = total_points;
    if (!lc_io_part_active(p))
        return 0;
    if (p->counts.n != lines)
        return lc_err(err, LC_ERR_INTERNAL, "%s: %zu line counts for %u lines", file, p->counts.n, lines);
    if (lc_scene_split_lines(p->counts.v, lines, p->rank, p->size, &p->first, &p->last))
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for the split of %u lines", file, lines);
    p->points = 0;
    for (uint32_t l = 0; l < p->last; l++)
        *(l < p->first ? &p->base : &p->points) += p->counts.v[l];
    return 0;
}

void lc_io_part_free(lc_io_part *p)
{
    if (p)
        lc_io_u32vec_free(&p->counts);
}

void lc_io_stem(const char *path, char *out, size_t n)
{
    const char *base = lc_io_basename(path);
    const char *dot = strrchr(base, '.');
    size_t len = dot && dot != base ? (size_t)(dot - base) : strlen(base);
    if (n == 0)
        return;
    if (len >= n)
        len = n - 1;
    memcpy(out, base, len);
    out[len] = '\0';
}

/* ---- numbers */

static int match_word(const char *p, const char *end, const char *word)
{
    size_t n = strlen(word);
    return (size_t)(end - p) >= n && strncasecmp(p, word, n) == 0;
}

const char *lc_io_parse_double(const char *p, const char *end, double *out)
{
    /* Exact powers of ten for Clinger's fast path: a mantissa below 2^53 times
     * or divided by one of these is a single correctly rounded operation. */
    static const double pow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                   1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const char *start = p;
    int neg = 0;
    if (p < end && (*p == '+' || *p == '-'))
        neg = *p++ == '-';
    uint64_t mant = 0;
    int digits = 0, exp10 = 0, any = 0, exact = 1;
    while (p < end && (unsigned)(*p - '0') < 10) {
        any = 1;
        if (digits < 19) {
            mant = mant * 10 + (uint64_t)(*p - '0');
            digits += mant != 0; /* leading zeros are not significant */
        } else {
            exp10++;
            exact = 0;
        }
        p++;
    }
    if (p < end && *p == '.') {
        p++;
        while (p < end && (unsigned)(*p - '0') < 10) {
            any = 1;
            if (digits < 19) {
                mant = mant * 10 + (uint64_t)(*p - '0');
                digits += mant != 0;
                exp10--;
            } else {
                exact = 0;
            }
            p++;
        }
    }
    if (!any) {
        /* nan / inf are not numbers a dataset should hold, but recognizing
         * them lets the caller say "non-finite coordinate" instead of "bad
         * number". */
        if (match_word(p, end, "nan")) {
            *out = NAN;
            return p + 3;
        }
        if (match_word(p, end, "infinity")) {
            *out = neg ? -INFINITY : INFINITY;
            return p + 8;
        }
        if (match_word(p, end, "inf")) {
            *out = neg ? -INFINITY : INFINITY;
            return p + 3;
        }
        return NULL;
    }
    if (p < end && (*p == 'e' || *p == 'E')) {
        const char *q = p + 1;
        int eneg = 0;
        if (q < end && (*q == '+' || *q == '-'))
            eneg = *q++ == '-';
        if (q < end && (unsigned)(*q - '0') < 10) {
            int e = 0;
            while (q < end && (unsigned)(*q - '0') < 10) {
                if (e < 100000) /* far beyond double range; avoids overflow */
                    e = e * 10 + (*q - '0');
                q++;
            }
            exp10 += eneg ? -e : e;
            p = q;
        }
    }
    double v;
    if (mant == 0) {
        v = 0.0;
    } else if (exact && mant <= (1ull << 53) && exp10 >= -22 && exp10 <= 22) {
        v = exp10 >= 0 ? (double)mant * pow10[exp10] : (double)mant / pow10[-exp10];
    } else {
        char buf[128];
        size_t len = (size_t)(p - start);
        if (len < sizeof buf) {
            memcpy(buf, start, len);
            buf[len] = '\0';
            *out = strtod(buf, NULL);
            return p;
        }
        v = (double)mant * pow(10.0, exp10); /* absurdly long literal: close enough */
    }
    *out = neg ? -v : v;
    return p;
}

/* ---- arrays */

int lc_io_u32vec_reserve(lc_io_u32vec *a, size_t extra, size_t limit, const char *file, const char *what, lc_error *err)
{
    if (extra > limit || a->n > limit - extra)
        return lc_err(err, LC_ERR_LIMIT, "%s: too many %s (limit %zu)", file, what, limit);
    size_t need = a->n + extra;
    if (need <= a->cap)
        return 0;
    size_t cap = a->cap ? a->cap : 1024;
    while (cap < need)
        cap = cap > limit / 2 ? limit : cap * 2;
    uint32_t *v = realloc(a->v, cap * sizeof *v);
    if (!v)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for %zu %s", file, cap, what);
    a->v = v;
    a->cap = cap;
    return 0;
}

void lc_io_u32vec_free(lc_io_u32vec *a)
{
    free(a->v);
    memset(a, 0, sizeof *a);
}

/* ---- polylines */

int lc_io_make_lines(lc_scene **sp, const uint32_t *idx, size_t idx_count, uint32_t *offsets, uint32_t line_count,
                     const char *file, lc_error *err)
{
    lc_scene *src = *sp;
    int identity = idx_count == src->vertex_count;
    for (size_t k = 0; identity && k < idx_count; k++)
        identity = idx[k] == k;
    if (identity) {
        src->type = LC_PRIM_LINES;
        src->line_offsets = offsets;
        src->line_count = line_count;
        return 0;
    }
    if (idx_count > LC_MAX_VERTICES) {
        free(offsets);
        return lc_err(err, LC_ERR_LIMIT, "%s: lines reference %zu vertices (limit %u)", file, idx_count,
                      (unsigned)LC_MAX_VERTICES);
    }
    lc_scene *dst = lc_scene_create(src->name, LC_PRIM_LINES);
    if (!dst) {
        free(offsets);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", file);
    }
    int rc = lc_scene_alloc_vertices(dst, (uint32_t)idx_count, src->rgb != NULL, err);
    if (rc)
        goto fail;
    for (size_t k = 0; k < idx_count; k++)
        memcpy(dst->positions + 3 * k, src->positions + 3 * (size_t)idx[k], 3 * sizeof(float));
    if (src->rgb)
        for (size_t k = 0; k < idx_count; k++)
            memcpy(dst->rgb + 3 * k, src->rgb + 3 * (size_t)idx[k], 3 * sizeof(float));
    for (int a = 0; a < src->attribute_count; a++) {
        float *values = malloc((idx_count ? idx_count : 1) * sizeof *values);
        if (!values) {
            rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory", file);
            goto fail;
        }
        const float *from = src->attributes[a].values;
        for (size_t k = 0; k < idx_count; k++)
            values[k] = from[idx[k]];
        rc = lc_scene_add_attribute(dst, src->attributes[a].name, values, err);
        if (rc < 0)
            goto fail;
    }
    memcpy(dst->default_importance, src->default_importance, sizeof dst->default_importance);
    memcpy(dst->default_color, src->default_color, sizeof dst->default_color);
    dst->line_offsets = offsets;
    dst->line_count = line_count;
    lc_scene_destroy(src);
    *sp = dst;
    return 0;
fail:
    free(offsets);
    lc_scene_destroy(dst);
    return rc < 0 ? rc : LC_ERR_INTERNAL;
}

void lc_io_set_defaults(lc_scene *s)
{
    static const char *preferred[] = {"importance", "vt", "scalar"};
    s->default_importance[0] = '\0';
    for (size_t i = 0; i < sizeof preferred / sizeof *preferred && !s->default_importance[0]; i++)
        if (lc_scene_find_attribute(s, preferred[i]) >= 0)
            snprintf(s->default_importance, sizeof s->default_importance, "%s", preferred[i]);
    if (!s->default_importance[0] && s->attribute_count > 0)
        snprintf(s->default_importance, sizeof s->default_importance, "%s", s->attributes[0].name);
    /* Without per-vertex colours lc_scene_finalize chooses (a class label, else the importance). */
    snprintf(s->default_color, sizeof s->default_color, "%s", s->rgb ? "rgb" : "");
}

/* ---- progress */

void lc_io_progress_start(lc_io_progress *p, const char *file)
{
    p->file = file;
    p->started = lc_now();
    p->next = p->started + 1.0;
}

void lc_io_progress_report(lc_io_progress *p, size_t done, size_t total)
{
    double now = lc_now();
    if (now < p->next)
        return;
    p->next = now + 1.0;
    fprintf(stderr, "%s: loading, %.0f %% after %.1f s\n", p->file,
            total ? 100.0 * (double)done / (double)total : 100.0, now - p->started);
}

int lc_io_fail(lc_error *err, int code, const char *file, const char *where, size_t pos, const char *fmt, ...)
{
    char reason[LC_ERROR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    return lc_err(err, code, "%.80s: %s %zu: %s", file, where, pos, reason);
}
