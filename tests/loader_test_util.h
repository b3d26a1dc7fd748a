/* Helpers shared by the dataset-reader tests: whole-file reads, scene
 * comparison, and the prefix/mutation robustness sweep. */
#ifndef LC_LOADER_TEST_UTIL_H
#define LC_LOADER_TEST_UTIL_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lc_test.h"
#include "scene.h"

static char *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    fclose(f);
    if (buf)
        buf[n] = '\0';
    *size = (size_t)n;
    return buf;
}

static int same_scene(const lc_scene *a, const lc_scene *b, double rgb_tol, const char *what)
{
    int before = lc_test_failed;
    CHECK(a->type == b->type, "%s: type %d vs %d", what, a->type, b->type);
    CHECK(a->vertex_count == b->vertex_count, "%s: vertices %u vs %u", what, a->vertex_count, b->vertex_count);
    if (lc_test_failed != before)
        return 0;
    CHECK(memcmp(a->positions, b->positions, 3 * sizeof(float) * a->vertex_count) == 0, "%s: positions", what);
    CHECK(!a->rgb == !b->rgb, "%s: rgb presence", what);
    if (a->rgb && b->rgb) {
        double worst = 0;
        for (size_t i = 0; i < 3 * (size_t)a->vertex_count; i++)
            worst = fmax(worst, fabs(a->rgb[i] - b->rgb[i]));
        CHECK(worst <= rgb_tol, "%s: rgb differs by %g", what, worst);
    }
    CHECK(a->line_count == b->line_count, "%s: lines %u vs %u", what, a->line_count, b->line_count);
    if (a->line_count == b->line_count && a->line_count)
        CHECK(memcmp(a->line_offsets, b->line_offsets, sizeof(uint32_t) * (a->line_count + 1)) == 0, "%s: line offsets",
              what);
    CHECK(a->triangle_count == b->triangle_count, "%s: triangles %u vs %u", what, a->triangle_count, b->triangle_count);
    if (a->triangle_count == b->triangle_count && a->triangle_count)
        CHECK(memcmp(a->triangles, b->triangles, 3 * sizeof(uint32_t) * a->triangle_count) == 0, "%s: triangle indices",
              what);
    for (int i = 0; i < a->attribute_count; i++) {
        int j = lc_scene_find_attribute(b, a->attributes[i].name);
        CHECK(j >= 0, "%s: attribute %s missing", what, a->attributes[i].name);
        if (j >= 0)
            CHECK(memcmp(a->attributes[i].values, b->attributes[j].values, sizeof(float) * a->vertex_count) == 0,
                  "%s: attribute %s values", what, a->attributes[i].name);
    }
    return lc_test_failed == before;
}

static double sum_floats(const float *v, size_t n)
{
    double s = 0;
    for (size_t i = 0; i < n; i++)
        s += v[i];
    return s;
}

/* Loads data (named after path) with the reader a test dispatches to. */
typedef int (*loader_test_memory_fn)(const char *path, const void *data, size_t size, lc_scene **s, lc_error *err);

/* Every prefix of each file (in an exact-size buffer, so ASan sees overreads)
 * and 3000 random byte edits: each must end in an error with a message or in a
 * scene that also finalizes, never a crash or a leak. `interesting` are bytes
 * the format's syntax cares about; seed makes the edits reproducible. */
static void check_prefixes_and_mutations(const char *dir, const char *const *files, size_t nfiles,
                                         const char *interesting, uint64_t seed, loader_test_memory_fn load)
{
    uint64_t state = seed;
#define NEXT() (state ^= state << 13, state ^= state >> 7, state ^= state << 17, (uint32_t)state)
    size_t ninteresting = strlen(interesting);
    int loaded = 0, failed = 0;
    for (size_t fi = 0; fi < nfiles; fi++) {
        char path[512];
        snprintf(path, sizeof path, "%s%s", dir, files[fi]);
        size_t size;
        char *bytes = read_all(path, &size);
        CHECK(bytes != NULL, "%s", path);
        if (!bytes)
            continue;
        for (size_t len = 0; len <= size; len++) {
            char *copy = malloc(len ? len : 1);
            memcpy(copy, bytes, len);
            lc_scene *s = NULL;
            lc_error err = {0};
            int rc = load(path, copy, len, &s, &err);
            CHECK(rc == 0 ? s != NULL : s == NULL && err.msg[0], "%s prefix %zu: rc %d", files[fi], len, rc);
            rc == 0 ? loaded++ : failed++;
            lc_scene_destroy(s);
            free(copy);
        }
        char *copy = malloc(size);
        for (int iter = 0; iter < 3000; iter++) {
            memcpy(copy, bytes, size);
            int edits = 1 + (int)(NEXT() % 4);
            for (int e = 0; e < edits; e++) {
                size_t at = NEXT() % size;
                copy[at] = NEXT() % 2 ? (char)NEXT() : interesting[NEXT() % ninteresting];
            }
            lc_scene *s = NULL;
            lc_error err = {0};
            int rc = load(path, copy, size, &s, &err);
            CHECK(rc == 0 ? s != NULL : s == NULL && err.msg[0], "%s mutation %d: rc %d", files[fi], iter, rc);
            if (rc == 0) {
                /* Whatever loads must also survive finalize (indices in range etc.). */
                lc_elements_desc desc = {.line_budget = 64, .patch_count = 8};
                lc_error ferr = {0};
                (void)lc_scene_finalize(s, &desc, &ferr);
            }
            lc_scene_destroy(s);
        }
        free(copy);
        free(bytes);
    }
#undef NEXT
    CHECK(loaded > 0 && failed > 0, "prefixes: %d loaded, %d failed", loaded, failed);
}

#endif
