/* Scene cache file: a finalized scene and its levels of detail in one file
 * with a key and a payload hash, read back only when both match and every
 * index is in range (scene_cache.h). */
#include "scene_cache.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "lod.h"

/* Bump when the layout below or what finalize and the level build derive
 * changes: an old cache is then stale, never misread. */
#define CACHE_VERSION                                                                                                  \
    3u /* 2: timed lines derive motion attributes (scene_motion.c); 3: lines their measures (scene_measures.c) */
static const char MAGIC[8] = {'L', 'C', 'S', 'C', 'E', 'N', 'E', '\n'};

/* ---- Hashing: four lanes of xxHash-style rounds over 32-byte blocks. */

#define P1 0x9E3779B185EBCA87ull
#define P2 0xC2B2AE3D27D4EB4Full
#define P3 0x165667B19E3779F9ull

static uint64_t rotl(uint64_t x, int r) { return (x << r) | (x >> (64 - r)); }
static uint64_t round64(uint64_t acc, uint64_t v) { return rotl(acc + v * P2, 31) * P1; }
static uint64_t fold(uint64_t h, uint64_t v) { return rotl(h ^ round64(0, v), 27) * P1 + P3; }

uint64_t lc_scene_cache_hash(const void *data, size_t n, uint64_t seed)
{
    const unsigned char *p = data;
    uint64_t lane[4] = {seed + P1 + P2, seed + P2, seed, seed - P1}, w;
    size_t i = 0;
    for (; i + 32 <= n; i += 32)
        for (int k = 0; k < 4; k++) {
            memcpy(&w, p + i + 8 * k, 8);
            lane[k] = round64(lane[k], w);
        }
    uint64_t h = rotl(lane[0], 1) + rotl(lane[1], 7) + rotl(lane[2], 12) + rotl(lane[3], 18) + (uint64_t)n;
    for (; i + 8 <= n; i += 8) {
        memcpy(&w, p + i, 8);
        h = fold(h, w);
    }
    for (; i < n; i++)
        h = fold(h, p[i]);
    h ^= h >> 33, h *= P2, h ^= h >> 29, h *= P3, h ^= h >> 32;
    return h;
}

int lc_scene_cache_key_of(const char *path, const lc_elements_desc *desc, const char *extra, lc_scene_cache_key *out,
                          lc_error *err)
{
    memset(out, 0, sizeof *out);
    FILE *f = fopen(path, "rb");
    struct stat st;
    if (!f || fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        if (f)
            fclose(f);
        return lc_err(err, LC_ERR_IO, "%s: cannot read for the scene cache key: %s", path,
                      f ? "not a regular file" : strerror(errno));
    }
    enum { BLOCK = 1 << 20 };
    unsigned char *buf = malloc(BLOCK);
    if (!buf) {
        fclose(f);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", path);
    }
    uint64_t h = 0, total = 0;
    size_t got;
    while ((got = fread(buf, 1, BLOCK, f)) > 0) {
        h = lc_scene_cache_hash(buf, got, h);
        total += got;
    }
    int bad = ferror(f);
    fclose(f);
    free(buf);
    if (bad)
        return lc_err(err, LC_ERR_IO, "%s: read error while hashing", path);
    out->file_size = total;
    out->mtime_sec = (int64_t)st.st_mtim.tv_sec;
    out->mtime_nsec = (int64_t)st.st_mtim.tv_nsec;
    out->content_hash = h;
    lc_elements_desc d = desc ? *desc : (lc_elements_desc){0};
    char settings[320];
    snprintf(settings, sizeof settings, "v%u lines=%u patches=%u sampling=%d lod=%d/%g/%d/%d %s", CACHE_VERSION,
             d.line_budget, d.patch_count, (int)d.patch_sampling, LC_LOD_MAX_LEVELS, LC_LOD_SHRINK,
             LC_LOD_LADDER_FINEST, LC_LOD_LADDER_STEPS, extra ? extra : "");
    out->settings_hash = lc_scene_cache_hash(settings, strlen(settings), CACHE_VERSION);
    return 0;
}

/* ---- The file: a header, then the payload in a fixed order. */

typedef struct header {
    char magic[8];
    uint32_t version, header_bytes;
    lc_scene_cache_key key;
    uint64_t payload_bytes, payload_hash;
} header;

/* The scene's counts and small fields, first in the payload: every array's
 * length follows from them, so a reader knows the payload's size before it
 * allocates anything. */
typedef struct meta {
    char name[LC_NAME_LEN];
    char default_importance[LC_NAME_LEN];
    char default_color[LC_NAME_LEN];
    uint32_t type, vertex_count, line_count, triangle_count;
    uint32_t attribute_count, has_rgb, has_normals, has_tangents;
    uint32_t element_count, adjacency_count, lod_count, lod_steps;
    int32_t has_view, geographic;
    double bounds[6], view_direction[3], view_up[3], step_hours;
} meta;

typedef struct attr_meta {
    char name[LC_NAME_LEN];
    float min, max, p02, p98, auto_lo, auto_hi;
} attr_meta;

typedef struct level_meta {
    double error;
    uint64_t primitives;
    uint64_t has_indices;
} level_meta;

typedef struct io {
    FILE *f;
    uint64_t hash, bytes;
    int failed;
} io;

static void put(io *w, const void *p, size_t n)
{
    if (w->failed || n == 0)
        return;
    if (fwrite(p, 1, n, w->f) != n)
        w->failed = 1;
    w->hash = lc_scene_cache_hash(p, n, w->hash);
    w->bytes += n;
}

static void get(io *r, void *p, size_t n)
{
    if (r->failed || n == 0)
        return;
    if (fread(p, 1, n, r->f) != n) {
        r->failed = 1;
        return;
    }
    r->hash = lc_scene_cache_hash(p, n, r->hash);
    r->bytes += n;
}

static void free_lod(lc_lod *lod)
{
    lc_lod_free(lod);
    free(lod);
}

static size_t level_index_count(uint32_t type, uint64_t primitives)
{
    return primitives * (type == LC_PRIM_LINES ? 2 : 3);
}

static int write_payload(io *w, const lc_scene *s, const lc_lod *lod)
{
    const lc_elements *e = &s->elements;
    size_t n = s->vertex_count;
    meta m = {0};
    snprintf(m.name, sizeof m.name, "%s", s->name);
    snprintf(m.default_importance, sizeof m.default_importance, "%s", s->default_importance);
    snprintf(m.default_color, sizeof m.default_color, "%s", s->default_color);
    m.type = (uint32_t)s->type, m.vertex_count = s->vertex_count, m.line_count = s->line_count;
    m.triangle_count = s->triangle_count, m.attribute_count = (uint32_t)s->attribute_count;
    m.has_rgb = s->rgb != NULL, m.has_normals = s->normals != NULL, m.has_tangents = s->tangents != NULL;
    m.element_count = e->count, m.adjacency_count = e->adjacency_count, m.lod_count = (uint32_t)lod->count;
    m.lod_steps = s->lod_steps, m.has_view = s->has_view, m.geographic = s->trajectory.geographic;
    memcpy(m.bounds, s->bounds, sizeof m.bounds);
    memcpy(m.view_direction, s->view_direction, sizeof m.view_direction);
    memcpy(m.view_up, s->view_up, sizeof m.view_up);
    m.step_hours = s->trajectory.step_hours;
    put(w, &m, sizeof m);
    level_meta lv[LC_LOD_MAX_LEVELS]; /* in one piece, as the reader reads them */
    for (int i = 0; i < lod->count; i++)
        lv[i] = (level_meta){lod->levels[i].error, lod->levels[i].primitives, lod->levels[i].indices != NULL};
    put(w, lv, lod->count * sizeof *lv);
    put(w, s->positions, n * 3 * sizeof(float));
    if (s->rgb)
        put(w, s->rgb, n * 3 * sizeof(float));
    if (s->normals)
        put(w, s->normals, n * 3 * sizeof(float));
    if (s->tangents)
        put(w, s->tangents, n * 3 * sizeof(float));
    if (s->type == LC_PRIM_LINES)
        put(w, s->line_offsets, ((size_t)s->line_count + 1) * sizeof(uint32_t));
    if (s->type == LC_PRIM_TRIANGLES)
        put(w, s->triangles, (size_t)s->triangle_count * 3 * sizeof(uint32_t));
    for (int a = 0; a < s->attribute_count; a++) {
        const lc_attribute *at = &s->attributes[a];
        attr_meta am = {.min = at->min, .max = at->max, .p02 = at->p02, .p98 = at->p98};
        am.auto_lo = at->auto_lo, am.auto_hi = at->auto_hi;
        snprintf(am.name, sizeof am.name, "%s", at->name);
        put(w, &am, sizeof am);
        put(w, at->values, n * sizeof(float));
    }
    put(w, e->vertex_elements, n * 4 * sizeof(uint32_t));
    put(w, e->vertex_weights, n * 4 * sizeof(float));
    put(w, e->adjacency_offsets, ((size_t)e->count + 1) * sizeof(uint32_t));
    put(w, e->adjacency, (size_t)e->adjacency_count * sizeof(uint32_t));
    for (int i = 0; i < lod->count; i++)
        if (lod->levels[i].indices)
            put(w, lod->levels[i].indices, level_index_count(m.type, lod->levels[i].primitives) * sizeof(uint32_t));
    return w->failed;
}

int lc_scene_cache_write(const char *cache_path, const lc_scene_cache_key *key, lc_scene *s, lc_error *err)
{
    if (!s->finalized || s->released || !s->positions || s->part_of || !s->elements.vertex_elements)
        return lc_err(err, LC_ERR_INVALID, "%s: only a whole finalized scene with its arrays is cached", s->name);
    if (!s->lod) { /* built once: the upload copies them (scene.h lod) */
        lc_lod *lod = calloc(1, sizeof *lod);
        if (!lod)
            return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", s->name);
        int rc = lc_lod_build(s, lod, err);
        if (rc) {
            free(lod);
            return rc;
        }
        s->lod = lod;
        s->lod_free = free_lod;
    }
    char tmp[4096];
    if (snprintf(tmp, sizeof tmp, "%s.%ld.tmp", cache_path, (long)getpid()) >= (int)sizeof tmp)
        return lc_err(err, LC_ERR_INVALID, "scene cache path too long");
    /* A new file only, never through a link planted at its name, readable by
     * the daemon's user alone (the cache holds the data's content). */
    int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    FILE *f = fd >= 0 ? fdopen(fd, "wb") : NULL;
    if (!f) {
        int e = errno;
        if (fd >= 0)
            close(fd), unlink(tmp);
        return lc_err(err, LC_ERR_IO, "%s: cannot write: %s", tmp, strerror(e));
    }
    header h = {.version = CACHE_VERSION, .header_bytes = sizeof(header), .key = *key};
    memcpy(h.magic, MAGIC, sizeof MAGIC);
    io w = {.f = f};
    int bad = fwrite(&h, sizeof h, 1, f) != 1 || write_payload(&w, s, s->lod);
    h.payload_bytes = w.bytes, h.payload_hash = w.hash;
    bad = bad || fseek(f, 0, SEEK_SET) != 0 || fwrite(&h, sizeof h, 1, f) != 1;
    bad = fclose(f) != 0 || bad;
    if (bad || rename(tmp, cache_path) != 0) {
        int e = errno;
        unlink(tmp);
        return lc_err(err, LC_ERR_IO, "%s: cannot write: %s", cache_path, bad ? "write failed" : strerror(e));
    }
    return 0;
}

/* ---- Reading: sizes checked against the file before allocating, the hash
 * after reading, and every index before the scene is handed out. */

static int corrupt(lc_error *err, const char *path, const char *why)
{
    return lc_err(err, LC_ERR_INVALID, "%s: corrupt: %s", path, why);
}

static int names_ok(const meta *m)
{
    return memchr(m->name, 0, LC_NAME_LEN) && memchr(m->default_importance, 0, LC_NAME_LEN) &&
           memchr(m->default_color, 0, LC_NAME_LEN);
}

/* The payload bytes the counts of m and the levels lv imply (attribute
 * records included); UINT64_MAX when a count is out of its range. */
static uint64_t payload_size(const meta *m, const level_meta *lv)
{
    uint64_t n = m->vertex_count;
    if (m->type != LC_PRIM_POINTS && m->type != LC_PRIM_LINES && m->type != LC_PRIM_TRIANGLES)
        return UINT64_MAX;
    if (n == 0 || n > LC_MAX_VERTICES || m->line_count > LC_MAX_PRIMITIVES || m->triangle_count > LC_MAX_PRIMITIVES ||
        m->attribute_count > LC_MAX_ATTRIBUTES || m->lod_count < 1 || m->lod_count > LC_LOD_MAX_LEVELS ||
        m->element_count > LC_MAX_VERTICES || !names_ok(m))
        return UINT64_MAX;
    uint64_t b = sizeof(meta) + m->lod_count * sizeof(level_meta);
    b += n * 12 * (1 + (m->has_rgb != 0) + (m->has_normals != 0) + (m->has_tangents != 0));
    if (m->type == LC_PRIM_LINES)
        b += ((uint64_t)m->line_count + 1) * 4;
    if (m->type == LC_PRIM_TRIANGLES)
        b += (uint64_t)m->triangle_count * 12;
    b += m->attribute_count * (sizeof(attr_meta) + n * 4);
    b += n * 32 + ((uint64_t)m->element_count + 1) * 4 + (uint64_t)m->adjacency_count * 4;
    for (uint32_t i = 0; i < m->lod_count; i++) {
        if (lv[i].primitives > (uint64_t)LC_MAX_PRIMITIVES * 3)
            return UINT64_MAX;
        if (lv[i].has_indices)
            b += level_index_count(m->type, lv[i].primitives) * 4;
    }
    return b;
}

static int all_below(const uint32_t *v, size_t n, uint32_t bound)
{
    for (size_t i = 0; i < n; i++)
        if (v[i] >= bound)
            return 0;
    return 1;
}

static int increasing_to(const uint32_t *off, uint32_t count, uint32_t end)
{
    if (off[0] != 0 || off[count] != end)
        return 0;
    for (uint32_t i = 0; i < count; i++)
        if (off[i + 1] < off[i])
            return 0;
    return 1;
}

/* What lc_scene_finalize guarantees and the renderer indexes with. */
static const char *check_scene(const lc_scene *s, const lc_lod *lod)
{
    size_t n = s->vertex_count;
    for (size_t i = 0; i < n * 3; i++)
        if (!isfinite(s->positions[i]))
            return "a non-finite position";
    if (s->type == LC_PRIM_LINES && (s->line_count == 0 || s->line_offsets[s->line_count] > s->vertex_count))
        return "line offsets beyond the vertices";
    if (s->type == LC_PRIM_LINES) {
        for (uint32_t i = 0; i < s->line_count; i++)
            if (s->line_offsets[i + 1] < s->line_offsets[i])
                return "line offsets decrease";
    }
    if (s->type == LC_PRIM_TRIANGLES &&
        (!s->triangle_count || !all_below(s->triangles, s->triangle_count * 3ull, s->vertex_count)))
        return "a triangle index out of range";
    const lc_elements *e = &s->elements;
    if (e->count == 0 || !all_below(e->vertex_elements, n * 4, e->count))
        return "a vertex element out of range";
    if (!increasing_to(e->adjacency_offsets, e->count, e->adjacency_count) ||
        !all_below(e->adjacency, e->adjacency_count, e->count))
        return "element adjacency out of range";
    /* The levels as lc_lod_build makes them: points one level without
     * indices; lines indices at every level; triangles at every level but 0
     * (s->triangles); each coarser level no larger than the one before, its
     * error finite and no smaller. */
    uint64_t prims = lc_scene_primitive_count(s);
    if (s->type == LC_PRIM_POINTS && (lod->count != 1 || lod->levels[0].indices))
        return "a point scene with levels of detail";
    for (int i = 0; i < lod->count; i++) {
        const lc_lod_level *l = &lod->levels[i];
        int want = s->type == LC_PRIM_LINES || (s->type == LC_PRIM_TRIANGLES && i > 0);
        if (want != (l->indices != NULL))
            return "a level of detail without its indices";
        if (l->primitives > prims || (i > 0 && l->primitives > lod->levels[i - 1].primitives))
            return "a level of detail larger than the one before";
        if (!isfinite(l->error) || l->error < 0 || (i > 0 && l->error < lod->levels[i - 1].error))
            return "a level of detail's error out of order";
        if (l->indices && !all_below(l->indices, level_index_count(s->type, l->primitives), s->vertex_count))
            return "a level-of-detail index out of range";
    }
    if (s->type == LC_PRIM_TRIANGLES && lod->levels[0].primitives != prims)
        return "level 0 is not the scene's triangles";
    if (s->type == LC_PRIM_LINES &&
        (!lod->levels[0].indices || lod->levels[0].primitives != lc_scene_primitive_count(s)))
        return "level 0 is not the scene's segments";
    return NULL;
}

static void *alloc_into(void **slot, size_t bytes, int *nomem)
{
    *slot = malloc(bytes ? bytes : 1);
    if (!*slot)
        *nomem = 1;
    return *slot;
}

/* Reads the payload after m into s and lod (arrays allocated here). */
static int read_arrays(io *r, const meta *m, const level_meta *lv, lc_scene *s, lc_lod *lod)
{
    size_t n = m->vertex_count;
    int nomem = 0;
    s->vertex_count = m->vertex_count;
    if (alloc_into((void **)&s->positions, n * 12, &nomem))
        get(r, s->positions, n * 12);
    if (m->has_rgb && alloc_into((void **)&s->rgb, n * 12, &nomem))
        get(r, s->rgb, n * 12);
    if (m->has_normals && alloc_into((void **)&s->normals, n * 12, &nomem))
        get(r, s->normals, n * 12);
    if (m->has_tangents && alloc_into((void **)&s->tangents, n * 12, &nomem))
        get(r, s->tangents, n * 12);
    s->line_count = m->type == LC_PRIM_LINES ? m->line_count : 0;
    if (m->type == LC_PRIM_LINES && alloc_into((void **)&s->line_offsets, (s->line_count + 1ull) * 4, &nomem))
        get(r, s->line_offsets, (s->line_count + 1ull) * 4);
    s->triangle_count = m->type == LC_PRIM_TRIANGLES ? m->triangle_count : 0;
    if (m->type == LC_PRIM_TRIANGLES && alloc_into((void **)&s->triangles, s->triangle_count * 12ull, &nomem))
        get(r, s->triangles, s->triangle_count * 12ull);
    for (uint32_t a = 0; a < m->attribute_count && !nomem && !r->failed; a++) {
        attr_meta am;
        get(r, &am, sizeof am);
        lc_attribute *at = &s->attributes[s->attribute_count++];
        memcpy(at->name, am.name, LC_NAME_LEN);
        at->name[LC_NAME_LEN - 1] = 0;
        at->min = am.min, at->max = am.max, at->p02 = am.p02, at->p98 = am.p98;
        at->auto_lo = am.auto_lo, at->auto_hi = am.auto_hi;
        if (alloc_into((void **)&at->values, n * 4, &nomem))
            get(r, at->values, n * 4);
        /* the flags lc_scene_finalize sets, from the name and the values */
        at->smaller_matters = lc_attribute_smaller_matters(at->name);
        at->categorical = at->values && !r->failed && lc_attribute_categorical(at, n);
    }
    lc_elements *e = &s->elements;
    e->count = m->element_count, e->adjacency_count = m->adjacency_count;
    if (alloc_into((void **)&e->vertex_elements, n * 16, &nomem))
        get(r, e->vertex_elements, n * 16);
    if (alloc_into((void **)&e->vertex_weights, n * 16, &nomem))
        get(r, e->vertex_weights, n * 16);
    if (alloc_into((void **)&e->adjacency_offsets, (e->count + 1ull) * 4, &nomem))
        get(r, e->adjacency_offsets, (e->count + 1ull) * 4);
    if (alloc_into((void **)&e->adjacency, e->adjacency_count * 4ull, &nomem))
        get(r, e->adjacency, e->adjacency_count * 4ull);
    lod->count = (int)m->lod_count;
    for (uint32_t i = 0; i < m->lod_count; i++) {
        lod->levels[i].error = lv[i].error, lod->levels[i].primitives = lv[i].primitives;
        size_t bytes = level_index_count(m->type, lv[i].primitives) * 4;
        if (lv[i].has_indices && alloc_into((void **)&lod->levels[i].indices, bytes, &nomem))
            get(r, lod->levels[i].indices, bytes);
    }
    return nomem ? LC_ERR_NOMEM : r->failed ? LC_ERR_INVALID : 0;
}

/* The payload after header h: counts checked against h and the file before
 * anything is allocated, then every array read into a new scene and levels
 * (*s, *lod; the caller frees them), its chained hash and length in *r. */
static int read_body(FILE *f, const char *path, const header *h, io *r, lc_scene **s_out, lc_lod **lod_out,
                     lc_error *err)
{
    struct stat st;
    *s_out = NULL, *lod_out = NULL;
    if (fstat(fileno(f), &st) != 0 || (uint64_t)st.st_size != sizeof *h + h->payload_bytes)
        return corrupt(err, path, "its length differs from its header's");
    meta m;
    level_meta lv[LC_LOD_MAX_LEVELS];
    get(r, &m, sizeof m);
    if (r->failed || m.lod_count < 1 || m.lod_count > LC_LOD_MAX_LEVELS)
        return corrupt(err, path, "bad counts");
    get(r, lv, m.lod_count * sizeof *lv);
    if (r->failed || payload_size(&m, lv) != h->payload_bytes)
        return corrupt(err, path, "its counts do not match its length");
    lc_scene *s = lc_scene_create(m.name, (lc_prim_type)m.type);
    lc_lod *lod = calloc(1, sizeof *lod);
    if (!s || !lod) {
        lc_scene_destroy(s);
        free(lod);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", path);
    }
    *s_out = s, *lod_out = lod;
    int rc = read_arrays(r, &m, lv, s, lod);
    if (rc == LC_ERR_NOMEM)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", path);
    snprintf(s->default_importance, sizeof s->default_importance, "%s", m.default_importance);
    snprintf(s->default_color, sizeof s->default_color, "%s", m.default_color);
    memcpy(s->bounds, m.bounds, sizeof m.bounds);
    s->has_view = m.has_view;
    memcpy(s->view_direction, m.view_direction, sizeof m.view_direction);
    memcpy(s->view_up, m.view_up, sizeof m.view_up);
    s->lod_steps = m.lod_steps;
    s->trajectory = (lc_trajectory_info){.geographic = m.geographic, .step_hours = m.step_hours};
    return rc ? corrupt(err, path, "shorter than its counts") : 0;
}

static int read_header(FILE *f, const char *path, header *h, lc_error *err)
{
    if (fread(h, sizeof *h, 1, f) != 1)
        return corrupt(err, path, "shorter than its header");
    if (memcmp(h->magic, MAGIC, sizeof MAGIC) != 0 || h->header_bytes != sizeof *h)
        return corrupt(err, path, "not a scene cache");
    if (h->version != CACHE_VERSION)
        return lc_err(err, LC_ERR_INVALID, "%s: stale: cache version %u, this build writes %u", path, h->version,
                      CACHE_VERSION);
    return 0;
}

static int read_file(FILE *f, const char *path, const lc_scene_cache_key *key, lc_scene **out, lc_error *err)
{
    header h;
    int rc = read_header(f, path, &h, err);
    if (rc)
        return rc;
    if (h.key.file_size != key->file_size || h.key.mtime_sec != key->mtime_sec || h.key.mtime_nsec != key->mtime_nsec)
        return lc_err(err, LC_ERR_INVALID, "%s: stale: the data file's size or modification time changed", path);
    if (h.key.content_hash != key->content_hash)
        return lc_err(err, LC_ERR_INVALID, "%s: stale: the data file's content changed", path);
    if (h.key.settings_hash != key->settings_hash)
        return lc_err(err, LC_ERR_INVALID, "%s: stale: made with other settings", path);
    io r = {.f = f};
    lc_scene *s = NULL;
    lc_lod *lod = NULL;
    rc = read_body(f, path, &h, &r, &s, &lod, err);
    const char *why = rc                                                       ? NULL
                      : r.hash != h.payload_hash || r.bytes != h.payload_bytes ? "its payload hash differs"
                                                                               : check_scene(s, lod);
    if (rc || why) {
        lc_scene_destroy(s);
        if (lod)
            free_lod(lod);
        return rc ? rc : corrupt(err, path, why);
    }
    s->lod = lod;
    s->lod_free = free_lod;
    s->finalized = 1;
    *out = s;
    return 0;
}

int lc_scene_cache_seal(const char *cache_path, lc_scene_cache_key *key, lc_error *err)
{
    FILE *f = fopen(cache_path, "r+b");
    if (!f)
        return lc_err(err, errno == ENOENT ? LC_ERR_NOT_FOUND : LC_ERR_IO, "%s: %s", cache_path, strerror(errno));
    header h;
    io r = {.f = f};
    lc_scene *s = NULL;
    lc_lod *lod = NULL;
    int rc = read_header(f, cache_path, &h, err);
    if (!rc)
        rc = read_body(f, cache_path, &h, &r, &s, &lod, err);
    lc_scene_destroy(s);
    if (lod)
        free_lod(lod);
    if (!rc) {
        h.payload_hash = r.hash;
        if (fseek(f, 0, SEEK_SET) != 0 || fwrite(&h, sizeof h, 1, f) != 1)
            rc = lc_err(err, LC_ERR_IO, "%s: cannot write its header", cache_path);
        if (key)
            *key = h.key;
    }
    fclose(f);
    return rc;
}

int lc_scene_cache_read(const char *cache_path, const lc_scene_cache_key *key, lc_scene **out, lc_error *err)
{
    *out = NULL;
    FILE *f = fopen(cache_path, "rb");
    if (!f)
        return lc_err(err, errno == ENOENT ? LC_ERR_NOT_FOUND : LC_ERR_IO, "%s: %s", cache_path, strerror(errno));
    int rc = read_file(f, cache_path, key, out, err);
    fclose(f);
    return rc;
}
