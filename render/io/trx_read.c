/* TRX reader: the arrays of a zip archive (libzip) or a directory, described
 * by header.json (jansson). Every array's size is checked against the header's
 * counts before it is read, and a zip entry's claimed size against its
 * compressed size, so a hostile archive cannot make us allocate without bound. */
#include <dirent.h>
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zip.h>

#include "io_util.h"
#include "trx.h"

#define MAX_ENTRIES 4096
#define MAX_HEADER_BYTES (1u << 20)
#define MAX_DEFLATE_RATIO 1100 /* deflate cannot do better than ~1032:1 */

typedef struct trx_entry {
    char name[256]; /* "positions.3.float16", "dpv/fa.float32", ... */
    uint64_t size;
    uint64_t packed; /* compressed size (zip) */
    zip_uint64_t index;
    const unsigned char *data; /* after fetch */
    void *owned;               /* malloc'd copy (zip) */
    lc_io_file file;           /* mapping (directory) */
} trx_entry;

typedef struct trx_load {
    const char *file;
    lc_error *err;
    zip_t *zip;                 /* or NULL for a directory */
    const char *dir;            /* directory path */
    const unsigned char *zdata; /* the archive's bytes (zip) */
    size_t zsize;
    trx_entry *e;
    int n;
    uint64_t nv, ns;  /* NB_VERTICES, NB_STREAMLINES */
    lc_io_part *part; /* the streamlines this process keeps (the second pass) */
} trx_load;

typedef struct dtype {
    const char *name;
    int bytes;
    char kind; /* 'i' signed, 'u' unsigned, 'f' float */
} dtype;

static const dtype dtypes[] = {{"int8", 1, 'i'},    {"uint8", 1, 'u'},   {"int16", 2, 'i'},  {"uint16", 2, 'u'},
                               {"int32", 4, 'i'},   {"uint32", 4, 'u'},  {"int64", 8, 'i'},  {"uint64", 8, 'u'},
                               {"float16", 2, 'f'}, {"float32", 4, 'f'}, {"float64", 8, 'f'}};

static int fail(trx_load *T, int code, const char *entry, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static int fail(trx_load *T, int code, const char *entry, const char *fmt, ...)
{
    char reason[LC_ERROR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    if (entry)
        return lc_err(T->err, code, "%.80s: entry '%.60s': %s", T->file, entry, reason);
    return lc_err(T->err, code, "%.80s: %s", T->file, reason);
}

static float half_to_float(uint16_t h)
{
    int e = (h >> 10) & 0x1f, m = h & 0x3ff;
    float f = e == 0 ? ldexpf((float)m, -24) : e == 31 ? (m ? NAN : INFINITY) : ldexpf((float)(m | 0x400), e - 25);
    return h & 0x8000 ? -f : f;
}

static double get_value(const unsigned char *p, const dtype *t)
{
    switch (t->bytes) {
    case 1: return t->kind == 'i' ? (double)(int8_t)p[0] : (double)p[0];
    case 2: {
        uint16_t u = (uint16_t)(p[0] | p[1] << 8);
        return t->kind == 'f' ? (double)half_to_float(u) : t->kind == 'i' ? (double)(int16_t)u : (double)u;
    }
    case 4: {
        uint32_t u = lc_io_get_u32(p, 0);
        return t->kind == 'f' ? (double)lc_io_get_f32(p, 0) : t->kind == 'i' ? (double)(int32_t)u : (double)u;
    }
    default: {
        uint64_t u = lc_io_get_u64(p, 0);
        return t->kind == 'f' ? lc_io_get_f64(p, 0) : t->kind == 'i' ? (double)(int64_t)u : (double)u;
    }
    }
}

/* Splits "NAME[.K].DTYPE" (after any folder): returns the dtype or NULL, the
 * name length and K (1 when absent). */
static const dtype *parse_name(const char *base, size_t *name_len, uint64_t *k)
{
    const char *dot = strrchr(base, '.');
    if (!dot || dot == base)
        return NULL;
    const dtype *t = NULL;
    for (size_t i = 0; i < sizeof dtypes / sizeof *dtypes && !t; i++)
        if (strcmp(dot + 1, dtypes[i].name) == 0)
            t = &dtypes[i];
    if (!t)
        return NULL;
    *k = 1;
    *name_len = (size_t)(dot - base);
    const char *prev = dot - 1;
    while (prev > base && *prev >= '0' && *prev <= '9')
        prev--;
    if (prev > base && *prev == '.' && prev + 1 < dot && dot - prev <= 7) {
        *k = strtoull(prev + 1, NULL, 10);
        *name_len = (size_t)(prev - base);
    }
    return *name_len ? t : NULL;
}

static int add_entry(trx_load *T, const char *name, uint64_t size, uint64_t packed, zip_uint64_t index)
{
    if (T->n == MAX_ENTRIES)
        return fail(T, LC_ERR_LIMIT, NULL, "more than %d entries", MAX_ENTRIES);
    if (strlen(name) >= sizeof T->e[0].name)
        return 0; /* not a name we read */
    trx_entry *e = &T->e[T->n++];
    memset(e, 0, sizeof *e);
    snprintf(e->name, sizeof e->name, "%s", name);
    e->size = size;
    e->packed = packed;
    e->index = index;
    return 0;
}

static int list_zip(trx_load *T, const void *data, size_t size)
{
    T->zdata = data;
    T->zsize = size;
    zip_error_t ze;
    zip_error_init(&ze);
    zip_source_t *src = zip_source_buffer_create(data, size, 0, &ze);
    if (src)
        T->zip = zip_open_from_source(src, ZIP_RDONLY, &ze);
    if (!T->zip) {
        int rc = fail(T, LC_ERR_INVALID, NULL, "not a readable zip archive (%s)", zip_error_strerror(&ze));
        if (src)
            zip_source_free(src);
        zip_error_fini(&ze);
        return rc;
    }
    zip_error_fini(&ze);
    zip_int64_t count = zip_get_num_entries(T->zip, 0);
    for (zip_int64_t i = 0; i < count; i++) {
        zip_stat_t st;
        if (zip_stat_index(T->zip, (zip_uint64_t)i, 0, &st) != 0 || !(st.valid & ZIP_STAT_NAME))
            continue;
        size_t len = strlen(st.name);
        if (len == 0 || st.name[len - 1] == '/')
            continue;
        int rc = add_entry(T, st.name, st.size, st.comp_size, (zip_uint64_t)i);
        if (rc)
            return rc;
    }
    return 0;
}

static int visible(const struct dirent *e) { return e->d_name[0] != '.'; }

/* The regular files of T->dir/sub, by name. */
static int list_dir(trx_load *T, const char *sub)
{
    char path[1024];
    snprintf(path, sizeof path, "%s%s%s", T->dir, sub[0] ? "/" : "", sub);
    struct dirent **names = NULL;
    int n = scandir(path, &names, visible, alphasort);
    if (n < 0)
        return sub[0] ? 0 : fail(T, LC_ERR_IO, NULL, "cannot open the directory");
    int rc = 0;
    for (int i = 0; i < n; i++) {
        char rel[300], full[1400];
        snprintf(rel, sizeof rel, "%s%s%s", sub, sub[0] ? "/" : "", names[i]->d_name);
        snprintf(full, sizeof full, "%s/%s", T->dir, rel);
        struct stat st;
        if (!rc && stat(full, &st) == 0 && S_ISREG(st.st_mode))
            rc = add_entry(T, rel, (uint64_t)st.st_size, (uint64_t)st.st_size, 0);
        free(names[i]);
    }
    free(names);
    return rc;
}

static trx_entry *find(trx_load *T, const char *prefix)
{
    for (int i = 0; i < T->n; i++)
        if (strncmp(T->e[i].name, prefix, strlen(prefix)) == 0)
            return &T->e[i];
    return NULL;
}

/* Makes e->data hold e->size bytes (which the caller has checked). */
/* A stored (uncompressed) entry's bytes inside the archive itself, found
 * through the central directory and the local header, so that a stored TRX is
 * read without a copy (as TRX files usually are). NULL when the entry is
 * compressed, the archive needs ZIP64 or anything does not add up; the caller
 * then lets libzip copy (and check) the entry. libzip has opened the archive,
 * so its structure is known to be sound; every offset is still bounded here. */
static const unsigned char *stored_bytes(const trx_load *T, const trx_entry *e)
{
    const unsigned char *z = T->zdata;
    size_t n = T->zsize, eocd = SIZE_MAX;
    for (size_t back = 22; back <= n && back <= 22 + 65535 && eocd == SIZE_MAX; back++)
        if (lc_io_get_u32(z + n - back, 0) == 0x06054b50)
            eocd = n - back;
    if (eocd == SIZE_MAX)
        return NULL;
    uint32_t entries = (uint32_t)(z[eocd + 10] | z[eocd + 11] << 8), cd = lc_io_get_u32(z + eocd + 16, 0);
    size_t name_len = strlen(e->name), pos = cd;
    for (uint32_t i = 0; i < entries && i < MAX_ENTRIES; i++) {
        if (pos > n || n - pos < 46 || lc_io_get_u32(z + pos, 0) != 0x02014b50)
            return NULL;
        unsigned method = (unsigned)(z[pos + 10] | z[pos + 11] << 8);
        uint32_t packed = lc_io_get_u32(z + pos + 20, 0), size = lc_io_get_u32(z + pos + 24, 0);
        size_t nl = (size_t)(z[pos + 28] | z[pos + 29] << 8), el = (size_t)(z[pos + 30] | z[pos + 31] << 8),
               cl = (size_t)(z[pos + 32] | z[pos + 33] << 8);
        uint32_t local = lc_io_get_u32(z + pos + 42, 0);
        if (n - pos - 46 < nl)
            return NULL;
        if (nl == name_len && memcmp(z + pos + 46, e->name, nl) == 0) {
            if (method != 0 || packed != size || size != e->size || size == 0xFFFFFFFFu || local == 0xFFFFFFFFu ||
                (size_t)local > n || n - local < 30 || lc_io_get_u32(z + local, 0) != 0x04034b50)
                return NULL;
            size_t start = (size_t)local + 30 + (size_t)(z[local + 26] | z[local + 27] << 8) +
                           (size_t)(z[local + 28] | z[local + 29] << 8);
            return start <= n && n - start >= size ? z + start : NULL;
        }
        pos += 46 + nl + el + cl;
    }
    return NULL;
}

static int fetch(trx_load *T, trx_entry *e)
{
    if (e->data)
        return 0;
    if (!T->zip) {
        char full[1400];
        snprintf(full, sizeof full, "%s/%s", T->dir, e->name);
        lc_error ferr = {0};
        if (lc_io_file_open(full, &e->file, &ferr) != 0)
            return fail(T, ferr.code, e->name, "%s", ferr.msg);
        if (e->file.size != e->size)
            return fail(T, LC_ERR_INVALID, e->name, "changed size while loading");
        e->data = (const unsigned char *)e->file.data;
        return 0;
    }
    if ((e->data = stored_bytes(T, e)))
        return 0;
    if (e->size > e->packed * MAX_DEFLATE_RATIO + 65536)
        return fail(T, LC_ERR_INVALID, e->name, "claims %llu bytes from %llu compressed", (unsigned long long)e->size,
                    (unsigned long long)e->packed);
    if (e->size > SIZE_MAX - 1)
        return fail(T, LC_ERR_LIMIT, e->name, "too large");
    e->owned = malloc(e->size ? (size_t)e->size : 1);
    if (!e->owned)
        return fail(T, LC_ERR_NOMEM, e->name, "out of memory for %llu bytes", (unsigned long long)e->size);
    zip_file_t *zf = zip_fopen_index(T->zip, e->index, 0);
    zip_int64_t got = zf ? zip_fread(zf, e->owned, e->size) : -1;
    if (zf)
        zip_fclose(zf);
    if (got < 0 || (uint64_t)got != e->size)
        return fail(T, LC_ERR_INVALID, e->name, "cannot read the %llu bytes of the entry (%s)",
                    (unsigned long long)e->size, zf ? "truncated or corrupt" : zip_strerror(T->zip));
    e->data = e->owned;
    return 0;
}

static int read_header(trx_load *T)
{
    trx_entry *h = NULL;
    for (int i = 0; i < T->n && !h; i++)
        if (strcmp(T->e[i].name, "header.json") == 0)
            h = &T->e[i];
    if (!h)
        return fail(T, LC_ERR_INVALID, NULL, "no header.json (not a TRX file?)");
    if (h->size > MAX_HEADER_BYTES)
        return fail(T, LC_ERR_LIMIT, h->name, "%llu bytes (limit %u)", (unsigned long long)h->size, MAX_HEADER_BYTES);
    int rc = fetch(T, h);
    if (rc)
        return rc;
    json_error_t je;
    json_t *root = json_loadb((const char *)h->data, (size_t)h->size, JSON_REJECT_DUPLICATES, &je);
    if (!root || !json_is_object(root)) {
        json_decref(root);
        return fail(T, LC_ERR_INVALID, h->name, "line %d: %s", je.line, root ? "not a JSON object" : je.text);
    }
    static const char *const keys[2] = {"NB_VERTICES", "NB_STREAMLINES"};
    uint64_t *vals[2] = {&T->nv, &T->ns};
    const uint64_t caps[2] = {LC_MAX_VERTICES, LC_MAX_PRIMITIVES};
    for (int k = 0; k < 2; k++) {
        json_t *v = json_object_get(root, keys[k]);
        if (!json_is_integer(v) || json_integer_value(v) < 0) {
            json_decref(root);
            return fail(T, LC_ERR_INVALID, h->name, "%s is missing or not a non-negative integer", keys[k]);
        }
        *vals[k] = (uint64_t)json_integer_value(v);
        if (*vals[k] > caps[k]) {
            json_decref(root);
            return fail(T, LC_ERR_LIMIT, h->name, "%s %llu exceeds the limit %llu", keys[k],
                        (unsigned long long)*vals[k], (unsigned long long)caps[k]);
        }
    }
    json_decref(root);
    return 0;
}

/* The entry's dtype and component count, its size checked against rows. */
static int check_array(trx_load *T, trx_entry *e, const char *base, uint64_t rows, const dtype **t, uint64_t *k)
{
    size_t name_len;
    *t = parse_name(base, &name_len, k);
    if (!*t)
        return fail(T, LC_ERR_INVALID, e->name, "name is not NAME[.COMPONENTS].DTYPE with a known dtype");
    if (*k == 0 || *k > 1024)
        return fail(T, LC_ERR_INVALID, e->name, "%llu components", (unsigned long long)*k);
    uint64_t want = rows * *k * (uint64_t)(*t)->bytes;
    if (e->size != want)
        return fail(T, LC_ERR_INVALID, e->name, "%llu bytes, expected %llu (%llu x %llu x %d)",
                    (unsigned long long)e->size, (unsigned long long)want, (unsigned long long)rows,
                    (unsigned long long)*k, (*t)->bytes);
    return fetch(T, e);
}

/* An unsigned index from an integer array element; UINT64_MAX if negative. */
static uint64_t get_index(const unsigned char *p, const dtype *t)
{
    if (t->bytes == 8) {
        uint64_t u = lc_io_get_u64(p, 0);
        return t->kind == 'i' && (int64_t)u < 0 ? UINT64_MAX : u;
    }
    double v = get_value(p, t);
    return v < 0 ? UINT64_MAX : (uint64_t)v;
}

typedef struct trx_attr {
    const trx_entry *e;
    const dtype *t;
    uint64_t k, j; /* components, this one */
    int per_vertex;
    char name[LC_NAME_LEN];
} trx_attr;

/* The per-vertex and per-streamline arrays, checked and read. */
static int collect_attributes(trx_load *T, trx_attr *attrs, int *count)
{
    int n = 0, warned = 0;
    for (int i = 0; i < T->n; i++) {
        trx_entry *e = &T->e[i];
        int per_vertex = strncmp(e->name, "dpv/", 4) == 0;
        if (!per_vertex && strncmp(e->name, "dps/", 4) != 0)
            continue;
        const dtype *t;
        uint64_t k;
        int rc = check_array(T, e, e->name + 4, per_vertex ? T->nv : T->ns, &t, &k);
        if (rc)
            return rc;
        size_t name_len;
        parse_name(e->name + 4, &name_len, &k);
        for (uint64_t j = 0; j < k; j++) {
            if (n == LC_IO_MAX_FILE_ATTRIBUTES) {
                if (!warned++)
                    LC_WARN(LC_IO_LOG, "%s: more than %d attributes, '%s' and later ones skipped", T->file,
                            LC_IO_MAX_FILE_ATTRIBUTES, e->name);
                break;
            }
            trx_attr *a = &attrs[n++];
            a->e = e, a->t = t, a->k = k, a->j = j, a->per_vertex = per_vertex;
            int len = name_len < 40 ? (int)name_len : 40;
            if (k == 1)
                snprintf(a->name, sizeof a->name, "%.*s", len, e->name + 4);
            else
                snprintf(a->name, sizeof a->name, "%.*s_%llu", len, e->name + 4, (unsigned long long)j);
            for (char *c = a->name; *c; c++) /* names travel in URLs and PLY headers */
                if (*c == ' ' || (unsigned char)*c < 32)
                    *c = '_';
        }
    }
    *count = n;
    return 0;
}

static int finite3(const unsigned char *p, const dtype *t, float out[3])
{
    for (int c = 0; c < 3; c++)
        out[c] = (float)get_value(p + (size_t)c * (size_t)t->bytes, t);
    return isfinite(out[0]) && isfinite(out[1]) && isfinite(out[2]);
}

/* The bytes a load of the header's counts needs at least (the scene's arrays,
 * the finalize's per-vertex ones, the offsets and every array a zip makes us
 * inflate), checked against the load budget before anything is inflated: a
 * few kilobytes of deflated zeros may declare gigabytes. */
static int check_budget(trx_load *T)
{
    uint64_t file_bytes = T->zsize, inflated = 0, vertex_arrays = 1;
    for (int i = 0; i < T->n; i++) {
        const trx_entry *e = &T->e[i];
        int read = strncmp(e->name, "positions.", 10) == 0 || strncmp(e->name, "offsets.", 8) == 0 ||
                   strncmp(e->name, "dpv/", 4) == 0 || strncmp(e->name, "dps/", 4) == 0;
        if (!T->zip)
            file_bytes += e->size;
        else if (read)
            inflated += e->size < (1ull << 50) ? e->size : (1ull << 50); /* declared, unchecked yet */
        vertex_arrays += strncmp(e->name, "dpv/", 4) == 0;
    }
    uint64_t extra = T->nv * 4 * vertex_arrays + T->ns * 16 + inflated;
    char what[96];
    snprintf(what, sizeof what, "%llu vertices in %llu streamlines", (unsigned long long)T->nv,
             (unsigned long long)T->ns);
    return lc_io_check_load(T->file, file_bytes, T->nv, extra, what, T->err);
}

static int trx_build(trx_load *T, lc_scene **out)
{
    int rc = read_header(T);
    if (!rc)
        rc = check_budget(T);
    if (rc)
        return rc;
    if (T->ns == 0)
        return fail(T, LC_ERR_INVALID, "header.json", "NB_STREAMLINES is 0: no streamline");
    trx_entry *pe = find(T, "positions."), *oe = find(T, "offsets.");
    if (!pe || !oe)
        return fail(T, LC_ERR_INVALID, NULL, "no %s array", pe ? "offsets" : "positions");
    const dtype *pt, *ot;
    uint64_t pk, ok;
    if ((rc = check_array(T, pe, pe->name, T->nv, &pt, &pk)))
        return rc;
    if (pk != 3 || pt->kind != 'f')
        return fail(T, LC_ERR_INVALID, pe->name, "positions must be 3 float components (float16/32/64)");
    size_t name_len;
    ot = parse_name(oe->name, &name_len, &ok);
    if (!ot || ot->kind == 'f')
        return fail(T, LC_ERR_INVALID, oe->name, "offsets need an integer dtype");
    uint64_t rows = oe->size == (T->ns + 1) * (uint64_t)ot->bytes ? T->ns + 1 : T->ns;
    if ((rc = check_array(T, oe, oe->name, rows, &ot, &ok)))
        return rc;

    uint64_t *start = malloc((size_t)(T->ns + 1) * sizeof *start);
    if (!start)
        return fail(T, LC_ERR_NOMEM, oe->name, "out of memory for %llu offsets", (unsigned long long)T->ns);
    lc_scene *s = NULL;
    for (uint64_t l = 0; l < rows; l++)
        start[l] = get_index(oe->data + l * (uint64_t)ot->bytes, ot);
    start[T->ns] = rows > T->ns && start[T->ns] != T->nv ? UINT64_MAX : T->nv;
    for (uint64_t l = 0; l <= T->ns; l++)
        if (start[l] > T->nv || (l == 0 ? start[0] != 0 : start[l] < start[l - 1])) {
            rc = fail(T, LC_ERR_INVALID, oe->name, "offset %llu is out of order or outside 0..NB_VERTICES (%llu)%s",
                      (unsigned long long)l, (unsigned long long)T->nv,
                      l == T->ns ? ": the last one must be NB_VERTICES" : "");
            goto done;
        }

    /* Pass 1: the points and streamlines kept. */
    uint64_t points = 0, lines = 0, dropped = 0, short_lines = 0;
    lc_io_progress progress;
    lc_io_progress_start(&progress, T->file);
    for (uint64_t l = 0; l < T->ns; l++) {
        if ((l & 0xFFFF) == 0)
            lc_io_progress_report(&progress, (size_t)start[l], 2 * (size_t)T->nv); /* two passes */
        uint64_t run = 0;
        for (uint64_t v = start[l]; v < start[l + 1]; v++) {
            float p[3];
            finite3(pe->data + v * 3 * (uint64_t)pt->bytes, pt, p) ? run++ : dropped++;
        }
        if (run >= 2) {
            points += run, lines++;
            if ((rc = lc_io_part_count(T->part, (uint32_t)run, T->file, T->err)) != 0)
                goto done;
        } else {
            short_lines++;
        }
    }
    if (points > LC_MAX_VERTICES || lines > LC_MAX_PRIMITIVES) {
        rc = fail(T, LC_ERR_LIMIT, pe->name, "%llu points in %llu streamlines exceed the limits",
                  (unsigned long long)points, (unsigned long long)lines);
        goto done;
    }
    if (dropped && lc_io_part_speaks(T->part))
        LC_WARN(LC_IO_LOG, "%s: %llu points with NaN/Inf coordinates dropped", T->file, (unsigned long long)dropped);
    if (short_lines && lc_io_part_speaks(T->part))
        LC_WARN(LC_IO_LOG, "%s: %llu streamlines with fewer than 2 points skipped", T->file,
                (unsigned long long)short_lines);
    if (lines == 0) {
        rc = fail(T, LC_ERR_INVALID, pe->name, "no streamline with two or more points");
        goto done;
    }
    if ((rc = lc_io_part_choose(T->part, (uint32_t)lines, points, T->file, T->err)) != 0)
        goto done;
    points = T->part->points, lines = T->part->last - T->part->first;
    trx_attr attrs[LC_IO_MAX_FILE_ATTRIBUTES];
    float *values[LC_IO_MAX_FILE_ATTRIBUTES];
    int nattr = 0;
    if ((rc = collect_attributes(T, attrs, &nattr)))
        goto done;
    s = lc_scene_create(T->file, LC_PRIM_LINES);
    if (!s) {
        rc = lc_err(T->err, LC_ERR_NOMEM, "%s: out of memory", T->file);
        goto done;
    }
    if ((rc = lc_scene_alloc_vertices(s, (uint32_t)points, 0, T->err)))
        goto done;
    s->line_offsets = calloc((size_t)lines + 1, sizeof *s->line_offsets);
    s->line_count = (uint32_t)lines;
    if (!s->line_offsets) {
        rc = lc_err(T->err, LC_ERR_NOMEM, "%s: out of memory for %llu streamlines", T->file, (unsigned long long)lines);
        goto done;
    }
    for (int a = 0; a < nattr; a++) { /* the scene owns them on every path */
        float *v = malloc((size_t)points * sizeof *v);
        if (!v) {
            rc = lc_err(T->err, LC_ERR_NOMEM, "%s: out of memory for attributes", T->file);
            goto done;
        }
        for (int k = 0; lc_scene_find_attribute(s, attrs[a].name) >= 0; k++) /* never replace an earlier one */
            snprintf(attrs[a].name, LC_NAME_LEN, "attribute_%d_%d", a, k);
        int idx = lc_scene_add_attribute(s, attrs[a].name, v, T->err);
        if (idx < 0) {
            rc = idx;
            goto done;
        }
        values[a] = s->attributes[idx].values;
    }

    /* Pass 2: fill, with the kept streamlines of this process's share. */
    uint64_t w = 0, line = 0, kept = 0;
    for (uint64_t l = 0; l < T->ns && kept < T->part->last; l++) {
        if ((l & 0xFFFF) == 0)
            lc_io_progress_report(&progress, (size_t)(T->nv + start[l]), 2 * (size_t)T->nv);
        if (!lc_io_part_keeps(T->part, kept)) { /* before the share: only whether it is kept */
            uint64_t run = 0;
            float p[3];
            for (uint64_t v = start[l]; v < start[l + 1]; v++)
                run += finite3(pe->data + v * 3 * (uint64_t)pt->bytes, pt, p);
            kept += run >= 2;
            continue;
        }
        uint64_t first = w;
        for (uint64_t v = start[l]; v < start[l + 1] && w < points; v++) {
            if (!finite3(pe->data + v * 3 * (uint64_t)pt->bytes, pt, s->positions + 3 * w))
                continue;
            for (int a = 0; a < nattr; a++) {
                const trx_attr *at = &attrs[a];
                uint64_t row = at->per_vertex ? v : l;
                values[a][w] = (float)get_value(at->e->data + (row * at->k + at->j) * (uint64_t)at->t->bytes, at->t);
            }
            w++;
        }
        if (w - first >= 2)
            s->line_offsets[++line] = (uint32_t)w, kept++;
        else
            w = first; /* a short streamline is not kept */
    }
    lc_io_set_defaults(s);
done:
    free(start);
    if (rc) {
        lc_scene_destroy(s);
        s = NULL;
    }
    *out = s;
    return rc;
}

static int load_trx_zip(const void *data, size_t size, const char *name, lc_io_part *part, lc_scene **out,
                        lc_error *err)
{
    *out = NULL;
    trx_load T = {.file = name ? name : "<memory>", .err = err, .part = part};
    T.e = calloc(MAX_ENTRIES, sizeof *T.e);
    if (!T.e)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", T.file);
    int rc = list_zip(&T, data ? data : "", data ? size : 0);
    if (!rc)
        rc = trx_build(&T, out);
    for (int i = 0; i < T.n; i++)
        free(T.e[i].owned);
    if (T.zip)
        zip_discard(T.zip);
    free(T.e);
    return rc;
}

int lc_load_trx_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err)
{
    lc_io_part whole = {0};
    return load_trx_zip(data, size, name, &whole, out, err);
}

/* A .trx file or directory, whole (rank 0 of size 0) or a process's share. */
static int load_trx(const char *path, int rank, int size, lc_scene **out, lc_error *err)
{
    *out = NULL;
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        lc_io_part part = {.rank = rank, .size = size};
        trx_load T = {.file = lc_io_basename(path), .err = err, .dir = path, .part = &part};
        T.e = calloc(MAX_ENTRIES, sizeof *T.e);
        if (!T.e)
            return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", T.file);
        int rc = list_dir(&T, "");
        if (!rc)
            rc = list_dir(&T, "dpv");
        if (!rc)
            rc = list_dir(&T, "dps");
        if (!rc)
            rc = trx_build(&T, out);
        for (int i = 0; i < T.n; i++)
            lc_io_file_close(&T.e[i].file);
        free(T.e);
        lc_io_part_free(&part);
        if (!rc)
            lc_io_stem(path, (*out)->name, sizeof(*out)->name);
        return rc;
    }
    return lc_io_load_path_part(path, load_trx_zip, rank, size, out, err);
}

int lc_load_trx(const char *path, lc_scene **out, lc_error *err) { return load_trx(path, 0, 0, out, err); }

int lc_load_trx_part(const char *path, int rank, int size, lc_scene **out, lc_error *err)
{
    return load_trx(path, rank, size, out, err);
}
