/* Scene cache (render/scene/scene_cache.h): a demo scene of each primitive type
 * written and read back equals the finalized scene array for array and its
 * levels of detail equal a fresh build's; a changed data file (content, size
 * or mtime), a changed setting, a damaged byte and every truncation each give
 * a miss with a reason (stale or corrupt) and never a scene. */
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "demo.h"
#include "lc_test.h"
#include "lod.h"
#include "scene.h"
#include "scene_cache.h"

static char dir[] = "/tmp/lc_scene_cache_XXXXXX";

static void write_bytes(const char *path, const void *p, size_t n)
{
    FILE *f = fopen(path, "wb");
    CHECK(f && fwrite(p, 1, n, f) == n, "write %s", path);
    if (f)
        fclose(f);
}

static unsigned char *read_all(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    *n = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *p = malloc(*n ? *n : 1);
    if (p && fread(p, 1, *n, f) != *n) {
        free(p);
        p = NULL;
    }
    fclose(f);
    return p;
}

static int same(const void *a, const void *b, size_t n) { return (!a && !b) || (a && b && memcmp(a, b, n) == 0); }

static void check_equal(const lc_scene *a, const lc_scene *b, const lc_lod *fresh)
{
    size_t n = a->vertex_count;
    CHECK(b->finalized && b->type == a->type && b->vertex_count == a->vertex_count, "%s: counts", a->name);
    CHECK(strcmp(a->name, b->name) == 0, "%s: name %s", a->name, b->name);
    CHECK(same(a->positions, b->positions, n * 12) && same(a->rgb, b->rgb, n * 12), "%s: positions", a->name);
    CHECK(same(a->normals, b->normals, n * 12) && same(a->tangents, b->tangents, n * 12), "%s: frames", a->name);
    CHECK(a->line_count == b->line_count && a->triangle_count == b->triangle_count, "%s: topology", a->name);
    if (a->line_count)
        CHECK(same(a->line_offsets, b->line_offsets, (a->line_count + 1ull) * 4), "%s: offsets", a->name);
    if (a->triangle_count)
        CHECK(same(a->triangles, b->triangles, a->triangle_count * 12ull), "%s: triangles", a->name);
    CHECK(a->attribute_count == b->attribute_count, "%s: attributes", a->name);
    for (int i = 0; i < a->attribute_count && i < b->attribute_count; i++) {
        const lc_attribute *x = &a->attributes[i], *y = &b->attributes[i];
        CHECK(strcmp(x->name, y->name) == 0 && same(x->values, y->values, n * 4), "%s: attribute %s", a->name, x->name);
        CHECK(x->min == y->min && x->max == y->max && x->p02 == y->p02 && x->p98 == y->p98 &&
                  x->auto_lo == y->auto_lo && x->auto_hi == y->auto_hi,
              "%s: ranges of %s", a->name, x->name);
    }
    CHECK(memcmp(a->bounds, b->bounds, sizeof a->bounds) == 0, "%s: bounds", a->name);
    CHECK(strcmp(a->default_importance, b->default_importance) == 0 && strcmp(a->default_color, b->default_color) == 0,
          "%s: defaults", a->name);
    CHECK(a->has_view == b->has_view && memcmp(a->view_direction, b->view_direction, 24) == 0, "%s: view", a->name);
    const lc_elements *e = &a->elements, *f = &b->elements;
    CHECK(e->count == f->count && e->adjacency_count == f->adjacency_count, "%s: element counts", a->name);
    CHECK(same(e->vertex_elements, f->vertex_elements, n * 16) && same(e->vertex_weights, f->vertex_weights, n * 16),
          "%s: blends", a->name);
    CHECK(same(e->adjacency_offsets, f->adjacency_offsets, (e->count + 1ull) * 4) &&
              same(e->adjacency, f->adjacency, e->adjacency_count * 4ull),
          "%s: adjacency", a->name);
    /* The cached levels are what a fresh build gives. */
    lc_lod x = *fresh, y;
    lc_error err = {0};
    CHECK(b->lod != NULL && lc_lod_build(b, &y, &err) == 0, "lod: %s", err.msg);
    CHECK(x.count == y.count, "%s: %d levels vs %d", a->name, x.count, y.count);
    for (int i = 0; i < x.count && i < y.count; i++) {
        size_t k = x.levels[i].primitives * (a->type == LC_PRIM_LINES ? 2 : 3) * 4;
        CHECK(x.levels[i].primitives == y.levels[i].primitives && x.levels[i].error == y.levels[i].error &&
                  same(x.levels[i].indices, y.levels[i].indices, k),
              "%s: level %d", a->name, i);
    }
    lc_lod_free(&y);
}

/* A read that must miss: no scene, the code and the reason's word. */
static void expect_miss(const char *cache, const lc_scene_cache_key *key, const char *word, const char *what)
{
    lc_scene *s = (lc_scene *)1;
    lc_error err = {0};
    int rc = lc_scene_cache_read(cache, key, &s, &err);
    CHECK(rc != 0 && s == NULL && strstr(err.msg, word), "%s: rc %d, \"%s\" (want %s)", what, rc, err.msg, word);
    if (rc == 0)
        lc_scene_destroy(s);
}

static void round_trip(const char *demo, uint64_t count)
{
    lc_error err = {0};
    lc_scene *s = NULL;
    lc_demo_desc desc = {.count = count};
    CHECK(lc_demo_create(demo, &desc, &s, &err) == 0, "%s: %s", demo, err.msg);
    if (!s)
        return;
    char data[256], cache[256];
    snprintf(data, sizeof data, "%s/%s.data", dir, demo);
    snprintf(cache, sizeof cache, "%s/%s.lcscene", dir, demo);
    write_bytes(data, demo, strlen(demo)); /* stands for the file the scene was read from */
    lc_scene_cache_key key;
    CHECK(lc_scene_cache_key_of(data, NULL, NULL, &key, &err) == 0, "key: %s", err.msg);
    expect_miss(cache, &key, "No such file", "absent");
    lc_lod fresh;
    CHECK(lc_lod_build(s, &fresh, &err) == 0, "lod: %s", err.msg);
    /* A link planted at the temporary file's name: the write fails and the
     * link's target is untouched. */
    char tmp[300], victim[256];
    snprintf(tmp, sizeof tmp, "%s.%ld.tmp", cache, (long)getpid());
    snprintf(victim, sizeof victim, "%s/%s.victim", dir, demo);
    write_bytes(victim, "victim", 6);
    CHECK(symlink(victim, tmp) == 0, "%s: symlink", demo);
    CHECK(lc_scene_cache_write(cache, &key, s, &err) != 0, "%s: a write through a planted link fails", demo);
    struct stat vs;
    CHECK(stat(victim, &vs) == 0 && vs.st_size == 6, "%s: the link's target is untouched (%lld bytes)", demo,
          (long long)vs.st_size);
    unlink(tmp);
    unlink(victim);
    CHECK(lc_scene_cache_write(cache, &key, s, &err) == 0, "%s: write: %s", demo, err.msg);
    struct stat cs;
    CHECK(stat(cache, &cs) == 0 && (cs.st_mode & 0777) == 0600, "%s: the cache file is 0600 (%o)", demo,
          (unsigned)(cs.st_mode & 0777));
    CHECK(s->lod != NULL, "%s: the written levels stay with the scene", demo);
    lc_scene *r = NULL;
    CHECK(lc_scene_cache_read(cache, &key, &r, &err) == 0 && r, "%s: read: %s", demo, err.msg);
    if (r) {
        check_equal(s, r, &fresh);
        if (s->type != LC_PRIM_POINTS) { /* other elements: the cached levels (which follow them) go */
            lc_scene *again = NULL;
            CHECK(lc_scene_cache_read(cache, &key, &again, &err) == 0, "reread: %s", err.msg);
            CHECK(again && lc_scene_set_element_budget(again, again->elements.count / 2 + 1, &err) == 0 &&
                      again->lod == NULL,
                  "%s: a new element budget drops the cached levels (%s)", demo, err.msg);
            lc_scene_destroy(again);
        }
        /* The copy renders like the scene after the release too (no leak, no double free). */
        lc_scene_release_vertex_arrays(r);
        CHECK(r->lod == NULL, "%s: the cached levels go with the vertex arrays", demo);
        lc_scene_destroy(r);
    }

    /* A changed setting (the element budget) and a changed extra string. */
    lc_scene_cache_key other;
    lc_elements_desc more = {.line_budget = 12345, .patch_count = 77};
    CHECK(lc_scene_cache_key_of(data, &more, NULL, &other, &err) == 0, "key: %s", err.msg);
    expect_miss(cache, &other, "stale", "another element budget");
    CHECK(lc_scene_cache_key_of(data, NULL, "reader=2", &other, &err) == 0, "key: %s", err.msg);
    expect_miss(cache, &other, "stale", "another setting string");

    /* The data file touched (same bytes, new mtime), then changed in place
     * with the size and mtime restored (only the content hash tells). */
    struct stat st;
    stat(data, &st);
    struct timespec times[2] = {st.st_atim, {st.st_mtim.tv_sec + 5, st.st_mtim.tv_nsec}};
    utimensat(AT_FDCWD, data, times, 0);
    CHECK(lc_scene_cache_key_of(data, NULL, NULL, &other, &err) == 0, "key: %s", err.msg);
    expect_miss(cache, &other, "modification time", "touched data file");
    char changed[64];
    snprintf(changed, sizeof changed, "%s", demo);
    changed[0] ^= 0x20;
    write_bytes(data, changed, strlen(changed));
    times[1] = st.st_mtim;
    utimensat(AT_FDCWD, data, times, 0);
    CHECK(lc_scene_cache_key_of(data, NULL, NULL, &other, &err) == 0, "key: %s", err.msg);
    CHECK(other.file_size == key.file_size && other.mtime_sec == key.mtime_sec, "same size and mtime");
    expect_miss(cache, &other, "content changed", "changed content");

    /* Damage: a flipped byte in the payload at many places, then every
     * truncation in steps (and each of the first 200 lengths). */
    size_t n = 0;
    unsigned char *bytes = read_all(cache, &n);
    CHECK(bytes && n > 4096, "%s: cache of %zu bytes", demo, n);
    char bad[300];
    snprintf(bad, sizeof bad, "%s/bad.lcscene", dir);
    uint64_t lcg = 12345;
    for (int i = 0; bytes && i < 64; i++) {
        lcg = lcg * 6364136223846793005ull + 1442695040888963407ull;
        size_t at = 100 + (size_t)((lcg >> 11) % (n - 100)); /* past the key: the payload or its hash */
        bytes[at] ^= (unsigned char)(1u << (i % 8));
        write_bytes(bad, bytes, n);
        bytes[at] ^= (unsigned char)(1u << (i % 8));
        expect_miss(bad, &key, "corrupt", "flipped byte");
    }
    size_t step = n / 41 + 1;
    for (size_t len = 0; bytes && len < n; len += len < 200 ? 1 : step) {
        write_bytes(bad, bytes, len);
        expect_miss(bad, &key, "corrupt", "truncated");
    }
    /* Extra bytes after a whole file are damage too. */
    if (bytes) {
        unsigned char *longer = calloc(n + 16, 1);
        memcpy(longer, bytes, n);
        write_bytes(bad, longer, n + 16);
        expect_miss(bad, &key, "corrupt", "trailing bytes");
        free(longer);
    }
    free(bytes);
    lc_lod_free(&fresh);
    unlink(bad);
    unlink(data);
    unlink(cache);
    lc_scene_destroy(s);
}

/* A crafted, self-consistent cache (sealed after the edit, so its hash
 * matches): a point scene whose one level claims 3e8 primitives without
 * indices, which once crashed serve at every start. The reader refuses it. */
static void crafted_level(void)
{
    lc_error err = {0};
    lc_scene *s = NULL;
    lc_demo_desc desc = {.count = 4000};
    CHECK(lc_demo_create("points", &desc, &s, &err) == 0, "points: %s", err.msg);
    if (!s)
        return;
    char data[256], cache[256];
    snprintf(data, sizeof data, "%s/crafted.data", dir);
    snprintf(cache, sizeof cache, "%s/crafted.lcscene", dir);
    write_bytes(data, "crafted", 7);
    lc_scene_cache_key key;
    CHECK(lc_scene_cache_key_of(data, NULL, NULL, &key, &err) == 0 && lc_scene_cache_write(cache, &key, s, &err) == 0,
          "crafted: write: %s", err.msg);
    size_t n = 0;
    unsigned char *b = read_all(cache, &n);
    /* The level record: error 0.0, primitives = the point count, no indices. */
    unsigned char want[24] = {0};
    uint64_t count = s->vertex_count, huge = 300000000ull;
    memcpy(want + 8, &count, 8);
    size_t at = 0;
    for (size_t i = 0; b && i + 24 <= n && !at; i++)
        if (memcmp(b + i, want, 24) == 0)
            at = i;
    CHECK(at > 0, "crafted: the level record is in the file");
    if (b && at) {
        memcpy(b + at + 8, &huge, 8);
        write_bytes(cache, b, n);
        lc_scene_cache_key sealed;
        CHECK(lc_scene_cache_seal(cache, &sealed, &err) == 0 && memcmp(&sealed, &key, sizeof key) == 0,
              "crafted: sealed: %s", err.msg);
        lc_scene *r = NULL;
        int rc = lc_scene_cache_read(cache, &key, &r, &err);
        CHECK(rc != 0 && !r && strstr(err.msg, "corrupt") && strstr(err.msg, "level"),
              "crafted: a level of 3e8 primitives is refused: %s", err.msg);
        lc_scene_destroy(r);
    }
    free(b);
    unlink(cache);
    unlink(data);
    lc_scene_destroy(s);
}

int main(void)
{
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    round_trip("tornado", 24);  /* lines with tangents and levels of detail */
    round_trip("points", 4000); /* points, one element each */
    round_trip("surface", 48);  /* triangles with normals and simplified levels */
    crafted_level();
    /* The hash sees every byte and its position. */
    unsigned char a[100] = {0}, b[100] = {0};
    b[99] = 1;
    CHECK(lc_scene_cache_hash(a, 100, 0) != lc_scene_cache_hash(b, 100, 0), "last byte");
    CHECK(lc_scene_cache_hash(a, 99, 0) != lc_scene_cache_hash(a, 100, 0), "length");
    CHECK(lc_scene_cache_hash(a, 100, 0) != lc_scene_cache_hash(a, 100, 1), "seed");
    rmdir(dir);
    return lc_test_finish();
}
