/* VTK legacy and TrackVis loaders: the tables tests/data/loaders/{vtk,trk}/
 * cases.txt, exact values, the VTK writer's round trip and truncated/mutated
 * inputs (run under ASan to catch memory errors). */
#include <errno.h>
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

static int is_trk(const char *path)
{
    size_t n = strlen(path);
    return n >= 4 && strcmp(path + n - 4, ".trk") == 0;
}

static int load_path(const char *path, lc_scene **s, lc_error *err)
{
    return is_trk(path) ? lc_load_trk(path, s, err) : lc_load_vtk(path, s, err);
}

static int load_memory(const char *path, const void *data, size_t size, lc_scene **s, lc_error *err)
{
    const char *base = lc_io_basename(path);
    return is_trk(path) ? lc_load_trk_memory(data, size, base, s, err) : lc_load_vtk_memory(data, size, base, s, err);
}

static lc_scene *must_load(const char *file)
{
    char path[512];
    snprintf(path, sizeof path, "%s%s", DATA, file);
    lc_scene *s = NULL;
    lc_error err = {0};
    int rc = load_path(path, &s, &err);
    CHECK(rc == 0 && s, "%s: %s", file, err.msg);
    return s;
}

static void test_cases(void)
{
    int vtk = run_case_table(DATA "vtk/", load_path, load_memory);
    int trk = run_case_table(DATA "trk/", load_path, load_memory);
    CHECK(vtk >= 25 && trk >= 12, "only %d VTK and %d TrackVis cases", vtk, trk);
}

static void test_exact_values(void)
{
    /* ASCII vs binary, classic vs 5.1: the same scene. */
    lc_scene *a = must_load("vtk/valid/lines_ascii.vtk"), *b = must_load("vtk/valid/lines_be.vtk");
    lc_scene *c = must_load("vtk/valid/lines_v51.vtk");
    if (a && b)
        same_scene(a, b, 0, "lines ascii vs binary");
    if (a && c) {
        static const uint32_t off[3] = {0, 3, 5};
        static const float speed[5] = {1, 2, 3, 3, 4};
        static const float vmag[5] = {5, 1, 1, 1, 0};
        CHECK(memcmp(a->line_offsets, off, sizeof off) == 0 && memcmp(c->line_offsets, off, sizeof off) == 0,
              "vtk line offsets (point 2 duplicated)");
        CHECK(memcmp(a->positions, c->positions, 15 * sizeof(float)) == 0, "classic vs 5.1 positions");
        CHECK(memcmp(a->attributes[0].values, speed, sizeof speed) == 0, "speed gathered along the lines");
        int v = lc_scene_find_attribute(a, "velocity_magnitude");
        CHECK(v >= 0 && memcmp(a->attributes[v].values, vmag, sizeof vmag) == 0, "vector magnitude");
    }
    lc_scene_destroy(a);
    lc_scene_destroy(b);
    lc_scene_destroy(c);

    lc_scene *s = must_load("vtk/valid/surface_ascii.vtk");
    if (s) { /* quad fan, triangle, then a strip with alternating winding */
        static const uint32_t tris[15] = {0, 1, 2, 0, 2, 3, 0, 2, 3, 3, 2, 4, 4, 2, 5};
        CHECK(s->triangle_count == 5 && memcmp(s->triangles, tris, sizeof tris) == 0, "fan and strip triangles");
        CHECK(s->rgb && s->rgb[12] == 0.5f && s->rgb[3] == 0 && s->rgb[4] == 1, "ASCII colour scalars");
        int u1 = lc_scene_find_attribute(s, "uv_1");
        CHECK(u1 >= 0 && s->attributes[u1].values[5] == 1.0f, "second component as its own attribute");
    }
    lc_scene_destroy(s);

    lc_scene *q = must_load("vtk/valid/surface_v51_be.vtk");
    if (q) {
        static const uint32_t tris[9] = {0, 1, 2, 0, 2, 3, 0, 2, 3};
        CHECK(memcmp(q->triangles, tris, sizeof tris) == 0, "5.1 binary polygons");
        CHECK(q->rgb && q->rgb[0] == 1 && q->rgb[1] == 0 && q->rgb[10] == 1, "binary uchar colours");
        CHECK(q->attributes[0].values[0] == -1 && q->attributes[0].values[3] == 300, "short scalars");
    }
    lc_scene_destroy(q);

    lc_scene *le = must_load("trk/valid/tracts_le.trk"), *be = must_load("trk/valid/tracts_be.trk");
    if (le && be)
        same_scene(le, be, 0, "trk little vs big endian");
    if (le) {
        static const uint32_t off[3] = {0, 3, 7};
        static const float length[7] = {10, 10, 10, 20, 20, 20, 20};
        static const float col2[7] = {3, 3, 3, 6, 6, 6, 6};
        CHECK(memcmp(le->line_offsets, off, sizeof off) == 0, "trk line offsets (1-point track dropped)");
        int l = lc_scene_find_attribute(le, "length"), c2 = lc_scene_find_attribute(le, "col_2");
        CHECK(l >= 0 && memcmp(le->attributes[l].values, length, sizeof length) == 0, "property broadcast");
        CHECK(c2 >= 0 && memcmp(le->attributes[c2].values, col2, sizeof col2) == 0, "multi-value scalar name");
        /* stored (0, 4, 1) voxel-mm, LAS, 64 voxels of 2 x 2 x 3 mm: RAS+ mm as nibabel */
        CHECK(fabs(le->positions[3 * 6] - 127) < 1e-5 && fabs(le->positions[3 * 6 + 1] - 3) < 1e-5 &&
                  fabs(le->positions[3 * 6 + 2] + 0.5) < 1e-5,
              "trk point in RAS+ mm: %g %g %g", le->positions[3 * 6], le->positions[3 * 6 + 1],
              le->positions[3 * 6 + 2]);
    }
    lc_scene_destroy(le);
    lc_scene_destroy(be);
}

/* lc_save_vtk then lc_load_vtk gives back the scene (rgb through bytes). */
static void test_roundtrip(const char *dir)
{
    static const lc_prim_type types[3] = {LC_PRIM_POINTS, LC_PRIM_LINES, LC_PRIM_TRIANGLES};
    for (int t = 0; t < 3; t++) {
        lc_error err = {0};
        lc_scene *s = lc_scene_create("synthetic", types[t]);
        uint32_t n = 48;
        CHECK(s && lc_scene_alloc_vertices(s, n, t != 1, &err) == 0, "alloc: %s", err.msg);
        for (uint32_t i = 0; i < 3 * n; i++) {
            s->positions[i] = (float)sin(i * 0.731) * 1000.0f + 1.0f / 3.0f;
            if (s->rgb)
                s->rgb[i] = (float)(i % 256) / 255.0f;
        }
        const char *names[2] = {"importance", "temperature"};
        for (int a = 0; a < 2; a++) {
            float *v = malloc(n * sizeof *v);
            for (uint32_t i = 0; i < n; i++)
                v[i] = (float)cos(i * (a + 1.3)) * 7.0f;
            lc_scene_add_attribute(s, names[a], v, &err);
        }
        if (types[t] == LC_PRIM_LINES) {
            s->line_count = 3;
            s->line_offsets = malloc(4 * sizeof(uint32_t));
            uint32_t off[4] = {0, 10, 30, 48};
            memcpy(s->line_offsets, off, sizeof off);
        } else if (types[t] == LC_PRIM_TRIANGLES) {
            s->triangle_count = n - 2;
            s->triangles = malloc(3 * sizeof(uint32_t) * (n - 2));
            for (uint32_t i = 0; i + 2 < n; i++)
                s->triangles[3 * i] = i, s->triangles[3 * i + 1] = i + 1, s->triangles[3 * i + 2] = i + 2;
        }
        char path[512];
        snprintf(path, sizeof path, "%s/round%d.vtk", dir, t);
        CHECK(lc_save_vtk(s, path, &err) == 0, "save: %s", err.msg);
        lc_scene *r = NULL;
        CHECK(lc_load_vtk(path, &r, &err) == 0, "reload: %s", err.msg);
        if (r)
            same_scene(s, r, 0.5 / 255.0 + 1e-6, lc_prim_type_name(types[t]));
        lc_scene_destroy(r);
        lc_scene_destroy(s);
        unlink(path);
    }
}

/* Every prefix and random byte edits of the valid files: an error with a
 * message or a scene that finalizes, never a crash or a leak. */
static void test_mutations(void)
{
    static const char *const files[] = {"vtk/valid/lines_ascii.vtk",    "vtk/valid/lines_be.vtk",
                                        "vtk/valid/lines_v51.vtk",      "vtk/valid/surface_ascii.vtk",
                                        "vtk/valid/surface_v51_be.vtk", "vtk/valid/points_crlf.vtk",
                                        "trk/valid/tracts_le.trk",      "trk/valid/tracts_be.trk"};
    check_prefixes_and_mutations(DATA, files, sizeof files / sizeof *files, "0123456789 \n-.e%\xff\x80\x7f",
                                 0x2545f4914f6cdd1dull, load_memory);
}

int main(void)
{
    lc_log_set_level(LC_LOG_ERROR); /* the cases trigger expected warnings */
    char dir[] = "/tmp/lc_loaders_vtk_XXXXXX";
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    test_cases();
    test_exact_values();
    test_roundtrip(dir);
    test_mutations();
    rmdir(dir);
    return lc_test_finish();
}
