/* Helpers shared by the dataset-reader tests: whole-file reads, scene
 * comparison, the cases.txt table runner and the prefix/mutation sweep. */
#ifndef LC_LOADER_TEST_UTIL_H
#define LC_LOADER_TEST_UTIL_H

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_util.h"
#include "lc_test.h"
#include "loaders.h"
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

/* Checks one "key=value" expectation of a cases.txt line against a loaded scene. */
static void check_key(const lc_scene *s, const char *file, const char *key, const char *value)
{
    char attrs[512] = "";
    if (strcmp(key, "type") == 0) {
        CHECK(strcmp(lc_prim_type_name(s->type), value) == 0, "%s: type %s, expected %s", file,
              lc_prim_type_name(s->type), value);
    } else if (strcmp(key, "vertices") == 0) {
        CHECK(s->vertex_count == strtoul(value, NULL, 10), "%s: %u vertices, expected %s", file, s->vertex_count,
              value);
    } else if (strcmp(key, "lines") == 0) {
        CHECK(s->line_count == strtoul(value, NULL, 10), "%s: %u lines, expected %s", file, s->line_count, value);
        CHECK(s->line_offsets && s->line_offsets[0] == 0 && s->line_offsets[s->line_count] == s->vertex_count,
              "%s: line offsets do not cover the vertices", file);
    } else if (strcmp(key, "triangles") == 0) {
        CHECK(s->triangle_count == strtoul(value, NULL, 10), "%s: %u triangles, expected %s", file, s->triangle_count,
              value);
    } else if (strcmp(key, "rgb") == 0) {
        CHECK((s->rgb != NULL) == (atoi(value) != 0), "%s: rgb %s, expected %s", file, s->rgb ? "yes" : "no", value);
        /* without colours of its own the loader leaves the choice to lc_scene_finalize */
        CHECK(strcmp(s->default_color, s->rgb ? "rgb" : "") == 0, "%s: default colour '%s'", file, s->default_color);
    } else if (strcmp(key, "attrs") == 0) {
        for (int i = 0; i < s->attribute_count; i++)
            snprintf(attrs + strlen(attrs), sizeof attrs - strlen(attrs), "%s%s", i ? "," : "", s->attributes[i].name);
        CHECK(strcmp(attrs, strcmp(value, "-") == 0 ? "" : value) == 0, "%s: attributes '%s', expected '%s'", file,
              attrs, value);
    } else if (strcmp(key, "importance") == 0) {
        CHECK(strcmp(s->default_importance, strcmp(value, "-") == 0 ? "" : value) == 0,
              "%s: default importance '%s', expected '%s'", file, s->default_importance, value);
    } else if (strcmp(key, "sum") == 0 || strcmp(key, "asum") == 0 || strcmp(key, "rgbsum") == 0) {
        double want = strtod(value, NULL), got = NAN;
        if (key[0] == 's')
            got = sum_floats(s->positions, 3 * (size_t)s->vertex_count);
        else if (key[0] == 'r')
            got = s->rgb ? sum_floats(s->rgb, 3 * (size_t)s->vertex_count) : NAN;
        else {
            int a = lc_scene_find_attribute(s, s->default_importance);
            got = a >= 0 ? sum_floats(s->attributes[a].values, s->vertex_count) : NAN;
        }
        char what[160];
        snprintf(what, sizeof what, "%s: %s", file, key);
        CHECK_NEAR(got, want, 1e-5 * fmax(1.0, fabs(want)), what);
    } else {
        CHECK(0, "%s: unknown key '%s' in cases.txt", file, key);
    }
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

/* Loads a file from disk with the reader a test dispatches to. */
typedef int (*loader_test_path_fn)(const char *path, lc_scene **s, lc_error *err);

/* Runs the table dir/cases.txt: lines "FILE key=value ... [msg=TEXT]", FILE
 * relative to dir. Every file loads the same from disk and from memory; an
 * expected error (key "error" = status name) carries TEXT, leaves no scene and
 * reads the same through lc_scene_load_file; a valid file also loads, finalized
 * and named after its stem, through lc_scene_load_file. Returns the case count. */
static int run_case_table(const char *dir, loader_test_path_fn load_path, loader_test_memory_fn load_memory)
{
    char table[512];
    snprintf(table, sizeof table, "%scases.txt", dir);
    FILE *f = fopen(table, "r");
    CHECK(f != NULL, "cannot open %s: %s", table, strerror(errno));
    if (!f)
        return 0;
    char line[1024];
    int cases = 0;
    while (fgets(line, sizeof line, f)) {
        line[strcspn(line, "\r\n")] = '\0';
        if (!line[0] || line[0] == '#')
            continue;
        char *msg = strstr(line, " msg=");
        if (msg) {
            *msg = '\0';
            msg += 5;
        }
        char *save = NULL, *file = strtok_r(line, " ", &save);
        char path[512];
        snprintf(path, sizeof path, "%s%s", dir, file);
        cases++;
        lc_scene *s = NULL, *m = NULL, *fs = NULL;
        lc_error err = {0}, merr = {0}, ferr = {0};
        int rc = load_path(path, &s, &err);
        size_t size = 0;
        char *bytes = read_all(path, &size);
        CHECK(bytes != NULL, "%s: cannot read", file);
        int mrc = bytes ? load_memory(path, bytes, size, &m, &merr) : -1;
        CHECK(mrc == rc, "%s: memory loader rc %d vs %d", file, mrc, rc);
        char *kv;
        int expect_error = 0;
        while ((kv = strtok_r(NULL, " ", &save))) {
            char *eq = strchr(kv, '=');
            if (!eq)
                continue;
            *eq = '\0';
            if (strcmp(kv, "error") == 0) {
                expect_error = 1;
                CHECK(rc != 0 && strcmp(lc_status_name(rc), eq + 1) == 0, "%s: status %s (%s), expected %s", file,
                      lc_status_name(rc), err.msg, eq + 1);
            } else if (rc == 0) {
                check_key(s, file, kv, eq + 1);
            }
        }
        int frc = lc_scene_load_file(path, &fs, &ferr);
        if (expect_error) {
            CHECK(s == NULL && m == NULL, "%s: scene returned with an error", file);
            CHECK(msg && strstr(err.msg, msg) != NULL, "%s: message '%s' lacks '%s'", file, err.msg, msg ? msg : "");
            CHECK(strcmp(err.msg, merr.msg) == 0, "%s: memory loader says '%s'", file, merr.msg);
            CHECK(frc == rc && fs == NULL && strcmp(ferr.msg, err.msg) == 0, "%s: lc_scene_load_file says '%s'", file,
                  ferr.msg);
        } else {
            CHECK(rc == 0, "%s: %s", file, err.msg);
            if (rc == 0 && mrc == 0)
                same_scene(s, m, 0, file);
            CHECK(frc == 0 && fs && fs->finalized, "%s: lc_scene_load_file: %s", file, ferr.msg);
            if (fs) {
                char stem[LC_NAME_LEN];
                lc_io_stem(file, stem, sizeof stem);
                CHECK(strcmp(fs->name, stem) == 0, "%s: scene name '%s'", file, fs->name);
            }
        }
        lc_scene_destroy(fs);
        lc_scene_destroy(s);
        lc_scene_destroy(m);
        free(bytes);
    }
    fclose(f);
    return cases;
}

#endif
