/* Point tables (.csv, .tsv, .xyz): the table tests/data/loaders/csv/cases.txt,
 * a round trip through this test's own writer (every separator, %.9g keeps
 * floats exact) and truncated/mutated inputs. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io_util.h"
#include "lc_test.h"
#include "loader_test_util.h"
#include "loaders.h"
#include "scene.h"

#define DATA LUCENT_TEST_DATA "/loaders/"

static int load_path(const char *path, lc_scene **s, lc_error *err) { return lc_load_csv(path, s, err); }

static int load_memory(const char *path, const void *data, size_t size, lc_scene **s, lc_error *err)
{
    return lc_load_csv_memory(data, size, lc_io_basename(path), s, err);
}

/* Writes the scene's points with a header: x y z and every attribute. */
static int write_table(const lc_scene *s, const char *path, char sep)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fprintf(f, "# written by test_loaders_tables\nx%cy%cz", sep, sep);
    for (int a = 0; a < s->attribute_count; a++)
        fprintf(f, "%c%s", sep, s->attributes[a].name);
    fputc('\n', f);
    for (uint32_t v = 0; v < s->vertex_count; v++) {
        fprintf(f, "%.9g%c%.9g%c%.9g", s->positions[3 * v], sep, s->positions[3 * v + 1], sep, s->positions[3 * v + 2]);
        for (int a = 0; a < s->attribute_count; a++)
            fprintf(f, "%c%.9g", sep, s->attributes[a].values[v]);
        fputc('\n', f);
    }
    return fclose(f);
}

static void test_roundtrip(const char *dir)
{
    lc_error err = {0};
    lc_scene *s = lc_scene_create("synthetic", LC_PRIM_POINTS);
    uint32_t n = 500;
    CHECK(s && lc_scene_alloc_vertices(s, n, 0, &err) == 0, "alloc: %s", err.msg);
    for (uint32_t i = 0; i < 3 * n; i++)
        s->positions[i] = (float)sin(i * 0.731) * 1e4f + 1.0f / 3.0f;
    const char *names[2] = {"density", "temperature_K"};
    for (int a = 0; a < 2; a++) {
        float *v = malloc(n * sizeof *v);
        for (uint32_t i = 0; i < n; i++)
            v[i] = (float)cos(i * (a + 1.3)) * 7e-3f;
        lc_scene_add_attribute(s, names[a], v, &err);
    }
    static const char seps[3] = {',', '\t', ' '};
    static const char *const ext[3] = {"csv", "tsv", "xyz"};
    for (int k = 0; k < 3; k++) {
        char path[512];
        snprintf(path, sizeof path, "%s/round.%s", dir, ext[k]);
        CHECK(write_table(s, path, seps[k]) == 0, "write %s", path);
        lc_scene *r = NULL;
        CHECK(lc_scene_load_file(path, &r, &err) == 0, "reload %s: %s", path, err.msg);
        if (r)
            same_scene(s, r, 0, path);
        lc_scene_destroy(r);
        unlink(path);
    }
    lc_scene_destroy(s);
}

static void test_mutations(void)
{
    static const char *const files[] = {"csv/valid/points.csv", "csv/valid/lonlat.tsv", "csv/valid/cloud.xyz",
                                        "csv/valid/nan_row_crlf.csv"};
    check_prefixes_and_mutations(DATA, files, sizeof files / sizeof *files, "0123456789 ,\t\n\r\"#.e-xyz",
                                 0x2545f4914f6cdd1dull, load_memory);
}

int main(void)
{
    lc_log_set_level(LC_LOG_ERROR); /* the cases trigger expected warnings */
    char dir[] = "/tmp/lc_loaders_tables_XXXXXX";
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    int cases = run_case_table(DATA "csv/", load_path, load_memory);
    CHECK(cases >= 13, "only %d point-table cases", cases);
    test_roundtrip(dir);
    test_mutations();
    rmdir(dir);
    return lc_test_finish();
}
