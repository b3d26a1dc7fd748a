/* Red-team regressions of the readers and the scene (issue 12): files that the
 * test writes itself. Duplicate attribute names in TrackVis and PLY headers
 * (a use-after-free: the duplicate replaced an attribute the reader was still
 * filling), a FIFO given as a dataset (open() blocked forever), and a line
 * whose length overflows a float (float -> unsigned casts of NaN/inf in the
 * element budget). */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "elements.h"
#include "lc_test.h"
#include "loaders.h"
#include "scene.h"
#include "trk.h"

static void put_i16(unsigned char *p, int16_t v) { memcpy(p, &v, 2); }
static void put_i32(unsigned char *p, int32_t v) { memcpy(p, &v, 4); }
static void put_f32(unsigned char *p, float v) { memcpy(p, &v, 4); }

static int attr_index(const lc_scene *s, const char *name) { return lc_scene_find_attribute(s, name); }

/* A little-endian .trk with one 3-point track, n_scalars scalars named by
 * `scalar_names` (20-byte slots) and n_properties properties named likewise;
 * scalar k of point i is 10*k + i, property k is 100 + k. */
static unsigned char *make_trk(int ns, const char *const *scalar_names, int np, const char *const *prop_names,
                               size_t *size)
{
    const int points = 3;
    size_t n = 1000 + 4 + (size_t)points * 4 * (3 + (size_t)ns) + 4 * (size_t)np;
    unsigned char *d = calloc(1, n);
    memcpy(d, "TRACK", 5);
    for (int k = 0; k < 3; k++) /* voxel size 1 mm: the RAS+ transform needs a positive one */
        put_f32(d + 12 + 4 * k, 1.0f);
    put_i16(d + 36, (int16_t)ns);
    for (int k = 0; k < ns && k < 10; k++)
        memcpy(d + 38 + 20 * k, scalar_names[k], strlen(scalar_names[k]));
    put_i16(d + 238, (int16_t)np);
    for (int k = 0; k < np && k < 10; k++)
        memcpy(d + 240 + 20 * k, prop_names[k], strlen(prop_names[k]));
    put_i32(d + 988, 1);
    put_i32(d + 992, 2);
    put_i32(d + 996, 1000);
    unsigned char *p = d + 1000;
    put_i32(p, points);
    p += 4;
    for (int i = 0; i < points; i++) {
        put_f32(p, (float)i);
        put_f32(p + 4, 0);
        put_f32(p + 8, 0);
        p += 12;
        for (int k = 0; k < ns; k++, p += 4)
            put_f32(p, (float)(10 * k + i));
    }
    for (int k = 0; k < np; k++, p += 4)
        put_f32(p, (float)(100 + k));
    *size = n;
    return d;
}

/* Every attribute has a distinct name and the values the file holds. */
static void test_trk_duplicate_names(void)
{
    static const char *const dup[] = {"scalar_1", "scalar_1"};
    static const char *const props[] = {"fa", "fa", "scalar_0"};
    size_t n = 0;
    unsigned char *d = make_trk(2, dup, 3, props, &n);
    lc_scene *s = NULL;
    lc_error err = {0};
    int rc = lc_load_trk_memory(d, n, "dup.trk", &s, &err);
    CHECK(rc == 0 && s, "dup.trk loads: %s", err.msg);
    if (s) {
        CHECK(s->attribute_count == 5, "5 attributes kept (2 scalars, 3 properties), got %d", s->attribute_count);
        for (int a = 0; a < s->attribute_count; a++)
            for (int b = a + 1; b < s->attribute_count; b++)
                CHECK(strcmp(s->attributes[a].name, s->attributes[b].name) != 0, "names distinct: %s",
                      s->attributes[a].name);
        /* File order is attribute order: scalars first, then properties. */
        for (int k = 0; k < 2 && k < s->attribute_count; k++)
            for (int i = 0; i < 3; i++)
                CHECK(s->attributes[k].values[i] == (float)(10 * k + i), "scalar %d (%s) point %d = %g", k,
                      s->attributes[k].name, i, s->attributes[k].values[i]);
        for (int k = 0; k < 3 && 2 + k < s->attribute_count; k++)
            CHECK(s->attributes[2 + k].values[2] == (float)(100 + k), "property %d (%s) = %g", k,
                  s->attributes[2 + k].name, s->attributes[2 + k].values[2]);
        CHECK(attr_index(s, "scalar_1") == 0, "the first 'scalar_1' keeps its name");
    }
    lc_scene_destroy(s);
    free(d);

    /* Many duplicates: the unique names never collide with one another. */
    static const char *const same[] = {"a", "a", "a", "a", "a", "a", "a", "a", "a", "a"};
    d = make_trk(10, same, 0, NULL, &n);
    s = NULL;
    rc = lc_load_trk_memory(d, n, "same.trk", &s, &err);
    CHECK(rc == 0 && s && s->attribute_count == 10, "ten scalars named 'a': %s", rc ? err.msg : "");
    for (int k = 0; s && k < s->attribute_count; k++)
        CHECK(s->attributes[k].values[1] == (float)(10 * k + 1), "scalar %d value", k);
    lc_scene_destroy(s);
    free(d);
}

/* Unique names come from the scene: taken names get _2, _3, ... */
static void test_unique_name(void)
{
    lc_scene *s = lc_scene_create("u", LC_PRIM_POINTS);
    lc_scene_alloc_vertices(s, 1, 0, NULL);
    char name[LC_NAME_LEN];
    lc_scene_unique_attribute_name(s, "v", name);
    CHECK(strcmp(name, "v") == 0, "free name kept: %s", name);
    lc_error err = {0};
    lc_scene_add_attribute(s, "v", calloc(1, sizeof(float)), &err);
    lc_scene_add_attribute(s, "v_2", calloc(1, sizeof(float)), &err);
    lc_scene_unique_attribute_name(s, "v", name);
    CHECK(strcmp(name, "v_3") == 0, "v, v_2 taken -> v_3: %s", name);
    char longname[LC_NAME_LEN + 8];
    memset(longname, 'x', sizeof longname - 1);
    longname[sizeof longname - 1] = '\0';
    longname[LC_NAME_LEN - 1] = '\0';
    lc_scene_add_attribute(s, longname, calloc(1, sizeof(float)), &err);
    lc_scene_unique_attribute_name(s, longname, name);
    CHECK(strlen(name) < LC_NAME_LEN && lc_scene_find_attribute(s, name) < 0, "long taken name shortened: %s", name);
    lc_scene_destroy(s);
}

static char tmpdir[] = "/tmp/lucent_hostile_XXXXXX";

static void test_ply_duplicate_names(void)
{
    char path[256];
    snprintf(path, sizeof path, "%s/dup.ply", tmpdir);
    FILE *f = fopen(path, "w");
    fputs("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
          "property float s\nproperty float s\nproperty float t\nend_header\n0 0 0 1 2 3\n1 0 0 4 5 6\n2 0 0 7 8 9\n",
          f);
    fclose(f);
    lc_scene *s = NULL;
    lc_error err = {0};
    int rc = lc_scene_load_file(path, &s, &err);
    CHECK(rc == 0 && s, "dup.ply loads: %s", err.msg);
    int si = s ? attr_index(s, "s") : -1, ti = s ? attr_index(s, "t") : -1;
    CHECK(si >= 0 && ti >= 0, "attributes s and t present");
    if (si >= 0 && ti >= 0) {
        CHECK(s->attributes[si].values[0] == 1 && s->attributes[si].values[2] == 7, "first 's' kept: %g %g",
              s->attributes[si].values[0], s->attributes[si].values[2]);
        CHECK(s->attributes[ti].values[1] == 6, "'t' after the duplicate read in place: %g",
              s->attributes[ti].values[1]);
    }
    lc_scene_destroy(s);
    unlink(path);
}

/* A FIFO must be refused at once (before, open() blocked waiting for a writer). */
static void test_fifo(void)
{
    char path[256];
    snprintf(path, sizeof path, "%s/pipe.ply", tmpdir);
    if (mkfifo(path, 0600) != 0) {
        CHECK(0, "mkfifo %s", path);
        return;
    }
    pid_t pid = fork();
    if (pid == 0) {
        alarm(5); /* a hang becomes SIGALRM */
        lc_scene *s = NULL;
        lc_error err = {0};
        int rc = lc_scene_load_file(path, &s, &err);
        _exit(rc != 0 && strstr(err.msg, "not a regular file") ? 0 : 1);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0,
          "FIFO refused as 'not a regular file' without blocking "
          "(status %d)",
          status);
    unlink(path);
}

/* Coordinates of +-3e38: each segment is longer than FLT_MAX. Every line still
 * gets its elements, ids stay in range and the budget holds. */
static void test_infinite_line_length(void)
{
    const float P[] = {-3e38f, 0, 0, 3e38f, 0, 0, -3e38f, 1, 0, 3e38f, 1, 0, /* line 0: 4 points */
                       0,      2, 0, 1,     2, 0, 2,      2, 0};             /* line 1: 3 points */
    const uint32_t off[] = {0, 4, 7};
    lc_element_geometry g = {
        .name = "huge", .type = LC_PRIM_LINES, .vertex_count = 7, .positions = P, .line_count = 2, .line_offsets = off};
    lc_elements_desc desc = {.line_budget = 5};
    lc_elements e = {0};
    lc_error err = {0};
    int rc = lc_elements_build(&g, &desc, &e, &err);
    CHECK(rc == 0, "elements of a line longer than FLT_MAX: %s", err.msg);
    if (rc == 0) {
        CHECK(e.count >= 2 && e.count <= 5, "one element per line at least, budget 5 kept: %u", e.count);
        int in_range = 1;
        for (uint32_t v = 0; v < 7; v++)
            for (int k = 0; k < 4; k++)
                in_range &= e.vertex_elements[4 * v + k] < e.count;
        CHECK(in_range, "every vertex names elements in range");
        CHECK(e.vertex_elements[4 * 0 + 3] != e.vertex_elements[4 * 4 + 3], "the two lines have their own elements");
    }
    lc_elements_free(&e);
}

int main(void)
{
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        return 1;
    }
    test_trk_duplicate_names();
    test_unique_name();
    test_ply_duplicate_names();
    test_fifo();
    test_infinite_line_length();
    rmdir(tmpdir);
    return lc_test_finish();
}
