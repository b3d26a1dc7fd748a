/* Shared body of the dataset-reader fuzz harnesses: load from memory, check the
 * error contract, check that a file read in parts gives what the whole reader
 * gives, and finalize what loads so that the scene code sees every structure a
 * parser can emit. */
#ifndef LC_FUZZ_SCENE_LOADER_H
#define LC_FUZZ_SCENE_LOADER_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "loaders.h"
#include "scene.h"

typedef int (*fuzz_memory_loader)(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
typedef int (*fuzz_part_loader)(const char *path, int rank, int size, lc_scene **out, lc_error *err);

/* An invariant broken: say which before aborting, so a replay names it. */
static inline void fuzz_fail(const char *what, int parts, int rank)
{
    fprintf(stderr, "fuzz: %s (rank %d of %d)\n", what, rank, parts);
    abort();
}

static inline int fuzz_same_floats(const float *a, const float *b, size_t n)
{
    return n == 0 || (a && b && memcmp(a, b, n * sizeof *a) == 0);
}

/* Part `rank` of `parts` against the whole scene: its vertices are the whole's
 * from `base` on (positions, colours, every attribute the same bits), its lines
 * the whole's from `line` on. Returns the part's vertex count. */
static inline uint32_t fuzz_check_part(const lc_scene *whole, const lc_scene *p, uint64_t base, uint64_t line,
                                       int parts, int rank)
{
    if (p->type != whole->type || base + p->vertex_count > whole->vertex_count)
        fuzz_fail("a part holds other primitives or more vertices than the whole", parts, rank);
    size_t n = p->vertex_count;
    if (!fuzz_same_floats(whole->positions + 3 * base, p->positions, 3 * n))
        fuzz_fail("a part's positions differ from the whole's", parts, rank);
    if (!whole->rgb != !p->rgb || (p->rgb && !fuzz_same_floats(whole->rgb + 3 * base, p->rgb, 3 * n)))
        fuzz_fail("a part's colours differ from the whole's", parts, rank);
    if (p->attribute_count != whole->attribute_count)
        fuzz_fail("a part has other attributes than the whole", parts, rank);
    for (int a = 0; a < p->attribute_count; a++)
        if (strcmp(p->attributes[a].name, whole->attributes[a].name) != 0 ||
            !fuzz_same_floats(whole->attributes[a].values + base, p->attributes[a].values, n))
            fuzz_fail("a part's attribute differs from the whole's", parts, rank);
    if (whole->type == LC_PRIM_LINES) {
        if (line + p->line_count > whole->line_count || (p->line_count && !p->line_offsets))
            fuzz_fail("a part holds more lines than the whole", parts, rank);
        for (uint32_t l = 0; l <= p->line_count && p->line_offsets; l++)
            if ((uint64_t)p->line_offsets[l] + base != whole->line_offsets[line + l])
                fuzz_fail("a part's lines are not the whole's", parts, rank);
    }
    return p->vertex_count;
}

/* Reads the input as a file in 2 and in 3 parts (what `lucent render --mpi`
 * ranks do) and checks that the parts tile the whole: the same error or none,
 * and together every vertex and line in order. A reader may refuse parts of
 * input it reads only whole (LC_ERR_UNSUPPORTED: a VTK file without LINES, a
 * PLY mesh), then for every rank alike. */
static inline void fuzz_scene_parts(fuzz_part_loader load_part, const char *name, const lc_scene *whole,
                                    const uint8_t *data, size_t size)
{
    const char *ext = strrchr(name, '.');
    char path[64];
    snprintf(path, sizeof path, "/tmp/lucent-fuzz-XXXXXX%s", ext ? ext : "");
    int fd = mkstemps(path, ext ? (int)strlen(ext) : 0);
    if (fd < 0)
        return; /* no scratch space: nothing to check */
    int written = size == 0 || write(fd, data, size) == (ssize_t)size;
    close(fd);
    for (int parts = 2; written && parts <= 3; parts++) {
        uint64_t base = 0, line = 0;
        int unsupported = 0;
        for (int rank = 0; rank < parts; rank++) {
            lc_scene *p = NULL;
            lc_error err = {0};
            int rc = load_part(path, rank, parts, &p, &err);
            if (rc != 0 && (p || !err.msg[0]))
                fuzz_fail("a part's error left a scene or said nothing", parts, rank);
            if (rc == LC_ERR_UNSUPPORTED && (rank == 0 || unsupported)) {
                unsupported = 1;
                continue;
            }
            if (unsupported || (rc != 0) != !whole) {
                fprintf(stderr, "fuzz: whole %s, part: %s\n", whole ? "read" : "refused", rc ? err.msg : "read");
                fuzz_fail("the whole reader and a part reader disagree", parts, rank);
            }
            if (rc != 0)
                continue;
            base += fuzz_check_part(whole, p, base, line, parts, rank);
            line += p->line_count;
            lc_scene_destroy(p);
        }
        if (whole && !unsupported &&
            (base != whole->vertex_count || (whole->type == LC_PRIM_LINES && line != whole->line_count)))
            fuzz_fail("the parts together miss vertices or lines of the whole", parts, parts);
    }
    unlink(path);
}

static inline int fuzz_scene_loader(fuzz_memory_loader load, fuzz_part_loader load_part, const char *name,
                                    const uint8_t *data, size_t size)
{
    lc_log_threshold = LC_LOG_ERROR; /* warnings about skipped input would flood the output */
    lc_scene *s = NULL;
    lc_error err = {0};
    int rc = load(data, size, name, &s, &err);
    if (rc != 0 && (s || !err.msg[0])) /* contract: an error leaves no scene and says why */
        abort();
    if (rc == 0 && !s)
        abort();
    if (load_part)
        fuzz_scene_parts(load_part, name, s, data, size);
    if (!s)
        return 0;
    /* Small budgets keep finalize fast on large fuzzed counts. */
    lc_elements_desc desc = {.line_budget = 64, .patch_count = 8};
    lc_scene_finalize(s, &desc, &err);
    lc_scene_destroy(s);
    return 0;
}

#endif
