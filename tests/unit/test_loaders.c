/* PLY/OBJ loaders and writers: the table of valid and invalid files in
 * tests/data/loaders/cases.txt, exact values, round trips, the number parser
 * and truncated/mutated inputs (run under ASan to catch memory errors). */
#include <errno.h>
#include <float.h>
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

static int ends_with(const char *s, const char *suffix)
{
    size_t a = strlen(s), b = strlen(suffix);
    return a >= b && strcmp(s + a - b, suffix) == 0;
}

static int load_any(const char *path, lc_scene **s, lc_error *err)
{
    return ends_with(path, ".obj") ? lc_load_obj(path, s, err) : lc_load_ply(path, s, err);
}

static int load_any_memory(const char *path, const void *data, size_t size, lc_scene **s, lc_error *err)
{
    const char *base = lc_io_basename(path);
    return ends_with(path, ".obj") ? lc_load_obj_memory(data, size, base, s, err)
                                   : lc_load_ply_memory(data, size, base, s, err);
}

/* The PLY/OBJ table (tests/data/loaders/cases.txt). */
static void test_cases(void)
{
    int cases = run_case_table(DATA, load_any, load_any_memory);
    CHECK(cases >= 40, "only %d cases in cases.txt", cases);
}

static lc_scene *must_load(const char *file)
{
    char path[512];
    snprintf(path, sizeof path, "%s%s", DATA, file);
    lc_scene *s = NULL;
    lc_error err = {0};
    int rc = load_any(path, &s, &err);
    CHECK(rc == 0 && s, "%s: %s", file, err.msg);
    return s;
}

static void test_exact_values(void)
{
    lc_scene *a = must_load("valid/tetra_ascii.ply");
    lc_scene *le = must_load("valid/tetra_le.ply");
    lc_scene *be = must_load("valid/tetra_be.ply");
    if (a && le && be) {
        same_scene(a, le, 0, "tetra ascii vs little endian");
        same_scene(a, be, 0, "tetra ascii vs big endian");
        static const float rgb1[3] = {0, 1, 0};
        CHECK(memcmp(a->rgb + 3, rgb1, sizeof rgb1) == 0, "tetra rgb of vertex 1");
        static const uint32_t tris[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
        CHECK(memcmp(a->triangles, tris, sizeof tris) == 0, "tetra triangles");
        CHECK(a->attributes[0].values[2] == 0.25f, "tetra importance of vertex 2");
    }
    lc_scene_destroy(a);
    lc_scene_destroy(le);
    lc_scene_destroy(be);

    lc_scene *p = must_load("valid/polygons.ply");
    if (p) { /* fans: pentagon 0..4, then quad 3 2 5 0 */
        static const uint32_t tris[15] = {0, 1, 2, 0, 2, 3, 0, 3, 4, 3, 2, 5, 3, 5, 0};
        CHECK(p->triangle_count == 5 && memcmp(p->triangles, tris, sizeof tris) == 0, "polygon fans");
    }
    lc_scene_destroy(p);

    lc_scene *t = must_load("valid/point_types.ply");
    if (t) {
        int u32 = lc_scene_find_attribute(t, "u32"), c8 = lc_scene_find_attribute(t, "c8");
        CHECK(u32 >= 0 && t->attributes[u32].values[0] == 4e9f, "uint attribute");
        CHECK(c8 >= 0 && t->attributes[c8].values[2] == -128.0f, "char attribute");
        CHECK(t->positions[3] == -1000.0f && t->positions[4] == 32767.0f && t->positions[5] == 255.0f,
              "double/int16/uchar coordinates");
    }
    lc_scene_destroy(t);

    lc_scene *l = must_load("valid/lines.ply");
    if (l) { /* vertex 2 duplicated: the lines are [0 1 2] and [2 3 4] */
        static const uint32_t off[3] = {0, 3, 6};
        static const float speed[6] = {1, 2, 3, 3, 4, 5};
        CHECK(l->line_count == 2 && memcmp(l->line_offsets, off, sizeof off) == 0, "ply line offsets");
        CHECK(memcmp(l->attributes[0].values, speed, sizeof speed) == 0, "ply line attribute gathered");
        CHECK(l->positions[9] == 2.0f && l->positions[10] == 0.0f, "ply duplicated vertex position");
    }
    lc_scene_destroy(l);

    lc_scene *o = must_load("valid/lines.obj");
    if (o) {
        static const uint32_t off[3] = {0, 3, 5};
        static const float vt[5] = {0.1f, 0.2f, 0.3f, 0.3f, 0.4f};
        CHECK(o->line_count == 2 && memcmp(o->line_offsets, off, sizeof off) == 0, "obj line offsets");
        int a = lc_scene_find_attribute(o, "vt");
        CHECK(a >= 0 && memcmp(o->attributes[a].values, vt, sizeof vt) == 0, "obj vt per line vertex");
        CHECK(o->positions[12] == 2.0f && o->positions[13] == 1.0f, "obj relative index resolved");
    }
    lc_scene_destroy(o);

    lc_scene *m = must_load("valid/mesh.obj");
    if (m) {
        static const uint32_t tris[9] = {0, 1, 2, 0, 2, 3, 0, 1, 4};
        static const float vt[5] = {0.5f, 0.75f, 0, 0, 0.75f};
        CHECK(memcmp(m->triangles, tris, sizeof tris) == 0, "obj mesh triangles");
        CHECK(memcmp(m->attributes[0].values, vt, sizeof vt) == 0, "obj mesh vt per vertex");
    }
    lc_scene_destroy(m);

    lc_scene *c = must_load("valid/points_rgb.obj");
    if (c) {
        static const float rgb[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
        CHECK(memcmp(c->rgb, rgb, sizeof rgb) == 0, "obj vertex colours (missing = white)");
    }
    lc_scene_destroy(c);
}

/* ---- round trips */

static lc_scene *make_scene(lc_prim_type type, int with_rgb)
{
    lc_error err = {0};
    lc_scene *s = lc_scene_create("synthetic", type);
    uint32_t n = 50;
    if (!s || lc_scene_alloc_vertices(s, n, with_rgb, &err))
        return s;
    for (uint32_t i = 0; i < 3 * n; i++)
        s->positions[i] = (float)sin(i * 0.731) * 1000.0f + 1.0f / 3.0f;
    if (with_rgb)
        for (uint32_t i = 0; i < 3 * n; i++)
            s->rgb[i] = (float)(i % 256) / 255.0f;
    const char *names[2] = {"importance", "temperature"};
    for (int a = 0; a < 2; a++) {
        float *v = malloc(n * sizeof *v);
        for (uint32_t i = 0; i < n; i++)
            v[i] = (float)cos(i * (a + 1.3)) * 1e-3f + (float)a;
        lc_scene_add_attribute(s, names[a], v, &err);
    }
    snprintf(s->default_importance, sizeof s->default_importance, "importance");
    if (type == LC_PRIM_LINES) {
        static const uint32_t off[5] = {0, 2, 20, 22, 50}; /* includes a two-vertex line */
        s->line_count = 4;
        s->line_offsets = malloc(sizeof off);
        memcpy(s->line_offsets, off, sizeof off);
    } else if (type == LC_PRIM_TRIANGLES) {
        s->triangle_count = 40;
        s->triangles = malloc(3 * 40 * sizeof(uint32_t));
        for (uint32_t t = 0; t < 40; t++)
            for (int k = 0; k < 3; k++)
                s->triangles[3 * t + k] = (t * 7 + (uint32_t)k * 13) % n;
    }
    return s;
}

static void test_roundtrip(const char *dir)
{
    for (int type = 0; type < 3; type++) {
        for (int rgb = 0; rgb < 2; rgb++) {
            lc_scene *s = make_scene((lc_prim_type)type, rgb);
            char ply[512], obj[512], what[64];
            snprintf(ply, sizeof ply, "%s/rt_%d_%d.ply", dir, type, rgb);
            snprintf(obj, sizeof obj, "%s/rt_%d_%d.obj", dir, type, rgb);
            lc_error err = {0};
            int rc = lc_save_ply(s, ply, &err);
            CHECK(rc == 0, "save_ply: %s", err.msg);
            lc_scene *back = NULL;
            rc = lc_load_ply(ply, &back, &err);
            CHECK(rc == 0, "load_ply round trip: %s", err.msg);
            snprintf(what, sizeof what, "ply round trip %s rgb=%d", lc_prim_type_name((lc_prim_type)type), rgb);
            if (back) {
                same_scene(s, back, 0.5 / 255.0 + 1e-6, what);
                CHECK(strcmp(back->default_importance, "importance") == 0, "%s: default importance", what);
            }
            lc_scene_destroy(back);

            rc = lc_save_obj(s, obj, &err);
            CHECK(rc == 0, "save_obj: %s", err.msg);
            back = NULL;
            rc = lc_load_obj(obj, &back, &err);
            CHECK(rc == 0, "load_obj round trip: %s", err.msg);
            snprintf(what, sizeof what, "obj round trip %s rgb=%d", lc_prim_type_name((lc_prim_type)type), rgb);
            if (back) {
                /* OBJ keeps positions, colours, connectivity and the importance in vt. */
                lc_scene *ref = s;
                CHECK(back->attribute_count == 1 && strcmp(back->attributes[0].name, "vt") == 0, "%s: vt", what);
                CHECK(back->vertex_count == ref->vertex_count &&
                          memcmp(back->attributes[0].values, ref->attributes[0].values,
                                 sizeof(float) * ref->vertex_count) == 0,
                      "%s: vt equals the importance", what);
                int keep = ref->attribute_count;
                ref->attribute_count = 0; /* compare the rest without attributes */
                same_scene(ref, back, 0, what);
                ref->attribute_count = keep;
            }
            lc_scene_destroy(back);

            /* A finalized scene (with derived attributes) also goes through. */
            rc = lc_scene_finalize(s, NULL, &err);
            CHECK(rc == 0, "finalize synthetic %s: %s", what, err.msg);
            if (rc == 0) {
                CHECK(lc_save_ply(s, ply, &err) == 0, "save finalized: %s", err.msg);
                back = NULL;
                CHECK(lc_scene_load_file(ply, &back, &err) == 0, "reload finalized: %s", err.msg);
                if (back)
                    CHECK(back->attribute_count == s->attribute_count, "%s: %d attributes after reload, %d before",
                          what, back->attribute_count, s->attribute_count);
                lc_scene_destroy(back);
            }
            unlink(ply);
            unlink(obj);
            lc_scene_destroy(s);
        }
    }
}

static void test_load_file(const char *dir)
{
    size_t size;
    char *bytes = read_all(DATA "valid/tetra_le.ply", &size);
    char path[512];
    snprintf(path, sizeof path, "%s/Upper.Case.PLY", dir);
    FILE *f = fopen(path, "wb");
    CHECK(f && bytes, "temp file");
    if (f && bytes)
        fwrite(bytes, 1, size, f);
    if (f)
        fclose(f);
    free(bytes);
    lc_scene *s = NULL;
    lc_error err = {0};
    CHECK(lc_scene_load_file(path, &s, &err) == 0, "upper-case extension: %s", err.msg);
    CHECK(s && strcmp(s->name, "Upper.Case") == 0, "scene named after the stem: '%s'", s ? s->name : "");
    CHECK(s && s->finalized, "finalized");
    lc_scene_destroy(s);
    unlink(path);

    s = NULL;
    CHECK(lc_scene_load_file(DATA "cases.txt", &s, &err) == LC_ERR_UNSUPPORTED && !s, "unknown extension");
    CHECK(strstr(err.msg, "cases.txt") != NULL, "unknown extension message: %s", err.msg);
    CHECK(lc_scene_load_file("/nonexistent/x.obj", &s, &err) == LC_ERR_IO && !s, "missing file");
    CHECK(strstr(err.msg, "/nonexistent/x.obj: cannot open") != NULL, "missing file message: %s", err.msg);
    snprintf(path, sizeof path, "%s/x.ply", dir);
    CHECK(lc_save_ply(&(lc_scene){.vertex_count = 0}, "/nonexistent/dir/x.ply", &err) == LC_ERR_IO, "unwritable path");
}

/* ---- hostile sizes */

static void test_hostile(void)
{
    /* Claims 4e9 vertices in a few bytes: must fail on the size check, never
     * try to allocate (an allocation failure would say "out of memory"). */
    static const char le[] = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
                             "property float x\nproperty float y\nproperty float z\nend_header\n\0\0\0\0";
    lc_scene *s = NULL;
    lc_error err = {0};
    int rc = lc_load_ply_memory(le, sizeof le - 1, "big.ply", &s, &err);
    CHECK(rc == LC_ERR_INVALID && !s &&
              strstr(err.msg, "big.ply: line 3: vertex count 4000000000 exceeds the file size"),
          "hostile count: %s", err.msg);

    /* A count that fits the file but exceeds the cap (records of 0 bytes are
     * impossible, so build one of 1-byte records: 2^28 + 1 of them). */
    size_t n = (size_t)LC_MAX_VERTICES + 1;
    const char *head = "ply\nformat binary_little_endian 1.0\nelement vertex 268435457\nproperty uchar x\n"
                       "property uchar y\nproperty uchar z\nend_header\n";
    size_t hl = strlen(head);
    char *big = calloc(1, hl + 3 * n);
    if (big) {
        memcpy(big, head, hl);
        rc = lc_load_ply_memory(big, hl + 3 * n, "cap.ply", &s, &err);
        CHECK(rc == LC_ERR_LIMIT && strstr(err.msg, "exceeds the limit"), "vertex cap: %s", err.msg);
        free(big);
    }

    /* Header without a newline at all, and NULs. */
    static const char nul[] = "ply\nformat ascii 1.0\0\nend_header\n";
    rc = lc_load_ply_memory(nul, sizeof nul - 1, "nul.ply", &s, &err);
    CHECK(rc == LC_ERR_INVALID && strstr(err.msg, "NUL byte"), "NUL in header: %s", err.msg);
    rc = lc_load_ply_memory(NULL, 0, NULL, &s, &err);
    CHECK(rc == LC_ERR_INVALID && !s, "NULL input");
    rc = lc_load_obj_memory(NULL, 0, NULL, &s, &err);
    CHECK(rc == LC_ERR_INVALID && !s, "NULL input obj");
}

/* ---- robustness: every prefix and many single-byte mutations */

static void test_mutations(void)
{
    static const char *const files[] = {
        "valid/tetra_ascii.ply", "valid/tetra_le.ply",    "valid/tetra_be.ply", "valid/skip_elements_le.ply",
        "valid/lines.ply",       "valid/point_types.ply", "valid/lines.obj",    "valid/mesh.obj",
        "valid/points_rgb.obj"};
    check_prefixes_and_mutations(DATA, files, sizeof files / sizeof *files, "0123456789 \n-.e/#nfvl\xff\x80",
                                 0x9e3779b97f4a7c15ull, load_any_memory);
}

/* ---- the number parser against strtod */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static uint32_t rng(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (uint32_t)rng_state;
}

static void test_parse_double(void)
{
    static const char *ok[] = {"0",
                               "-0",
                               "1",
                               "-0.5",
                               "0.1",
                               "1.",
                               ".5",
                               "-.5e+2",
                               "1e-45",
                               "3.4028235e38",
                               "1e400",
                               "-1e400",
                               "1e-400",
                               "123456789012345678901234",
                               "0.30000000000000004",
                               "9007199254740993",
                               "2.2250738585072014e-308",
                               "4.9e-324",
                               "1E5",
                               "+7",
                               "00012.50",
                               "1e22",
                               "1e23",
                               "8.589973e9",
                               "0.000000000000000000000000000001"};
    for (size_t i = 0; i < sizeof ok / sizeof *ok; i++) {
        const char *s = ok[i], *end = s + strlen(s);
        double v = -12345, ref = strtod(s, NULL);
        const char *q = lc_io_parse_double(s, end, &v);
        CHECK(q == end && memcmp(&v, &ref, sizeof v) == 0, "parse '%s': %.17g vs strtod %.17g", s, v, ref);
    }
    static const struct {
        const char *s;
        int consumed; /* -1: no number */
    } partial[] = {{"abc", -1}, {"+", -1},  {"-", -1}, {".", -1},    {"e5", -1},
                   {"1e", 1},   {"1e+", 1}, {"2x", 1}, {"1.5.5", 3}, {"", -1}};
    for (size_t i = 0; i < sizeof partial / sizeof *partial; i++) {
        const char *s = partial[i].s;
        double v;
        const char *q = lc_io_parse_double(s, s + strlen(s), &v);
        int got = q ? (int)(q - s) : -1;
        CHECK(got == partial[i].consumed, "parse '%s' consumed %d, expected %d", s, got, partial[i].consumed);
    }
    double v;
    CHECK(lc_io_parse_double("nan", "nan" + 3, &v) && isnan(v), "nan");
    CHECK(lc_io_parse_double("-Infinity", "-Infinity" + 9, &v) && isinf(v) && v < 0, "-Infinity");
    CHECK(lc_io_parse_double("INF", "INF" + 3, &v) && isinf(v) && v > 0, "INF");
    /* The end bound is respected: "12" of "123". */
    CHECK(lc_io_parse_double("123", "123" + 2, &v) && v == 12, "bounded by end");

    int mismatches = 0;
    for (int i = 0; i < 200000; i++) {
        char buf[64];
        uint64_t bits = ((uint64_t)rng() << 32) | rng();
        double d;
        memcpy(&d, &bits, sizeof d);
        if (!isfinite(d))
            continue;
        static const char *formats[] = {"%.17g", "%.9g", "%g", "%.6f", "%.3e"};
        const char *fmt = formats[i % 5];
        if (i % 5 == 3)
            d = fmod(d, 1e6); /* %f of huge numbers is long; keep it realistic */
        snprintf(buf, sizeof buf, fmt, d);
        double ref = strtod(buf, NULL), got;
        const char *q = lc_io_parse_double(buf, buf + strlen(buf), &got);
        if (!q || *q || memcmp(&ref, &got, sizeof got) != 0) {
            if (mismatches++ < 5)
                CHECK(0, "parse '%s': %.17g vs strtod %.17g", buf, got, ref);
        }
    }
    CHECK(mismatches == 0, "%d mismatches against strtod", mismatches);
}

int main(void)
{
    lc_log_set_level(LC_LOG_ERROR); /* the cases trigger expected warnings */
    char dir[] = "/tmp/lc_loaders_XXXXXX";
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    test_parse_double();
    test_cases();
    test_exact_values();
    test_roundtrip(dir);
    test_load_file(dir);
    test_hostile();
    test_mutations();
    rmdir(dir);
    return lc_test_finish();
}
