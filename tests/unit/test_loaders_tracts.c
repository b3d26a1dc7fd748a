/* Tractogram and line-set readers (MRtrix .tck, TRX, LineVis .binlines) and
 * TrackVis world space: the tables tests/data/loaders/{tck,trx,binlines}/cases.txt,
 * round trips through this test's own writers, nibabel's standard files (when
 * Debian's python3-nibabel is installed) and truncated/mutated inputs. */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zip.h>

#include "io_util.h"
#include "lc_test.h"
#include "loader_test_util.h"
#include "loaders.h"
#include "scene.h"

#define DATA LUCENT_TEST_DATA "/loaders/"
#define NIBABEL_DATA "/usr/lib/python3/dist-packages/nibabel/tests/data/"

static int has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    return n >= e && strcmp(path + n - e, ext) == 0;
}

static int load_path(const char *path, lc_scene **s, lc_error *err)
{
    if (has_ext(path, ".tck"))
        return lc_load_tck(path, s, err);
    if (has_ext(path, ".trk"))
        return lc_load_trk(path, s, err);
    if (has_ext(path, ".trx"))
        return lc_load_trx(path, s, err);
    return lc_load_binlines(path, s, err);
}

static int load_memory(const char *path, const void *data, size_t size, lc_scene **s, lc_error *err)
{
    const char *base = lc_io_basename(path);
    if (has_ext(path, ".tck"))
        return lc_load_tck_memory(data, size, base, s, err);
    if (has_ext(path, ".trk"))
        return lc_load_trk_memory(data, size, base, s, err);
    if (has_ext(path, ".trx")) {
        struct stat st;
        if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) /* a TRX directory has no in-memory form */
            return lc_load_trx(path, s, err);
        return lc_load_trx_memory(data, size, base, s, err);
    }
    return lc_load_binlines_memory(data, size, base, s, err);
}

static lc_scene *must_load(const char *path)
{
    lc_scene *s = NULL;
    lc_error err = {0};
    int rc = load_path(path, &s, &err);
    CHECK(rc == 0 && s, "%s: %s", path, err.msg);
    return s;
}

/* ---- the test's own writers */

static void put_u32(FILE *f, uint32_t v, int big)
{
    unsigned char b[4];
    for (int i = 0; i < 4; i++)
        b[big ? 3 - i : i] = (unsigned char)(v >> (8 * i));
    fwrite(b, 1, 4, f);
}

static void put_f32(FILE *f, float x, int big)
{
    uint32_t u;
    memcpy(&u, &x, 4);
    put_u32(f, u, big);
}

static void put_f64(FILE *f, double x, int big)
{
    uint64_t u;
    memcpy(&u, &x, 8);
    put_u32(f, (uint32_t)(big ? u >> 32 : u), big);
    put_u32(f, (uint32_t)(big ? u : u >> 32), big);
}

/* MRtrix .tck of the scene's lines: elem 4 or 8 bytes, either byte order. */
static int write_tck(const lc_scene *s, const char *path, int elem, int big)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    const char *type = elem == 4 ? (big ? "Float32BE" : "Float32LE") : (big ? "Float64BE" : "Float64LE");
    char head[256];
    int n = snprintf(head, sizeof head, "mrtrix tracks\ncount: %u\ndatatype: %s\nfile: . ", s->line_count, type);
    int off = n + 4 + 4; /* "NNN\nEND\n" with a three-digit offset */
    fprintf(f, "%s%03d\nEND\n", head, off);
    for (uint32_t l = 0; l < s->line_count; l++) {
        for (uint32_t v = s->line_offsets[l]; v < s->line_offsets[l + 1]; v++)
            for (int k = 0; k < 3; k++)
                elem == 4 ? put_f32(f, s->positions[3 * v + k], big) : put_f64(f, s->positions[3 * v + k], big);
        for (int k = 0; k < 3; k++)
            elem == 4 ? put_f32(f, NAN, big) : put_f64(f, NAN, big);
    }
    for (int k = 0; k < 3; k++)
        elem == 4 ? put_f32(f, INFINITY, big) : put_f64(f, INFINITY, big);
    return fclose(f);
}

/* LineVis .binlines of the scene: version 1 (no names) or 2 (names). */
static int write_binlines(const lc_scene *s, const char *path, int version)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    put_u32(f, (uint32_t)version, 0);
    put_u32(f, s->line_count, 0);
    put_u32(f, (uint32_t)s->attribute_count, 0);
    if (version >= 2)
        for (int a = 0; a < s->attribute_count; a++) {
            uint32_t len = (uint32_t)strlen(s->attributes[a].name);
            put_u32(f, len, 0);
            fwrite(s->attributes[a].name, 1, len, f);
        }
    for (uint32_t l = 0; l < s->line_count; l++) {
        uint32_t first = s->line_offsets[l], n = s->line_offsets[l + 1] - first;
        put_u32(f, n, 0);
        fwrite(s->positions + 3 * (size_t)first, sizeof(float), 3 * (size_t)n, f);
        for (int a = 0; a < s->attribute_count; a++)
            fwrite(s->attributes[a].values + first, sizeof(float), n, f);
    }
    return fclose(f);
}

/* TRX of the scene's lines with float32 or float16 positions, as a directory
 * or a zip (libzip, stored): header.json, positions, offsets, dpv/NAME.float32. */
static uint16_t float_to_half(float f) /* exact for the halves the test uses */
{
    uint32_t u;
    memcpy(&u, &f, 4);
    uint16_t sign = (uint16_t)(u >> 16 & 0x8000);
    int e = (int)(u >> 23 & 0xff) - 127 + 15;
    if ((u & 0x7fffffff) == 0)
        return sign;
    return (uint16_t)(sign | e << 10 | (u >> 13 & 0x3ff));
}

static int write_trx(const lc_scene *s, const char *path, int half, int as_zip)
{
    size_t n = s->vertex_count, pos_bytes = 3 * n * (half ? 2 : 4);
    unsigned char *pos = malloc(pos_bytes);
    uint32_t *off = malloc(s->line_count * sizeof *off);
    for (size_t i = 0; i < 3 * n; i++) {
        if (half) {
            uint16_t h = float_to_half(s->positions[i]);
            pos[2 * i] = (unsigned char)h, pos[2 * i + 1] = (unsigned char)(h >> 8);
        } else {
            memcpy(pos + 4 * i, &s->positions[i], 4); /* the test runs on little-endian hosts */
        }
    }
    memcpy(off, s->line_offsets, s->line_count * sizeof *off);
    char header[256];
    snprintf(header, sizeof header, "{\"NB_VERTICES\": %u, \"NB_STREAMLINES\": %u}", s->vertex_count, s->line_count);
    const char *names[2 + LC_MAX_ATTRIBUTES + 1];
    const void *data[2 + LC_MAX_ATTRIBUTES + 1];
    size_t sizes[2 + LC_MAX_ATTRIBUTES + 1];
    char attr_names[LC_MAX_ATTRIBUTES][LC_NAME_LEN + 16];
    int count = 0;
    names[count] = "header.json", data[count] = header, sizes[count++] = strlen(header);
    names[count] = half ? "positions.3.float16" : "positions.3.float32", data[count] = pos, sizes[count++] = pos_bytes;
    names[count] = "offsets.uint32", data[count] = off, sizes[count++] = s->line_count * sizeof *off;
    for (int a = 0; a < s->attribute_count; a++) {
        snprintf(attr_names[a], sizeof attr_names[a], "dpv/%s.float32", s->attributes[a].name);
        names[count] = attr_names[a], data[count] = s->attributes[a].values, sizes[count++] = n * sizeof(float);
    }
    int rc = 0;
    if (as_zip) {
        int ze;
        zip_t *z = zip_open(path, ZIP_CREATE | ZIP_TRUNCATE, &ze);
        for (int i = 0; z && i < count; i++) {
            zip_source_t *src = zip_source_buffer(z, data[i], sizes[i], 0);
            zip_int64_t idx = src ? zip_file_add(z, names[i], src, ZIP_FL_OVERWRITE) : -1;
            if (idx < 0)
                rc = -1;
            else
                zip_set_file_compression(z, (zip_uint64_t)idx, i % 2 ? ZIP_CM_DEFLATE : ZIP_CM_STORE, 0);
        }
        if (!z || zip_close(z) != 0)
            rc = -1;
    } else {
        char p[600];
        mkdir(path, 0755);
        snprintf(p, sizeof p, "%s/dpv", path);
        mkdir(p, 0755);
        for (int i = 0; i < count; i++) {
            snprintf(p, sizeof p, "%s/%s", path, names[i]);
            FILE *f = fopen(p, "wb");
            if (!f || fwrite(data[i], 1, sizes[i], f) != sizes[i])
                rc = -1;
            if (f)
                fclose(f);
        }
    }
    free(pos);
    free(off);
    return rc;
}

static void remove_trx_dir(const char *path, const lc_scene *s)
{
    char p[600];
    static const char *const files[] = {"header.json", "positions.3.float32", "positions.3.float16", "offsets.uint32"};
    for (size_t i = 0; i < sizeof files / sizeof *files; i++) {
        snprintf(p, sizeof p, "%s/%s", path, files[i]);
        unlink(p);
    }
    for (int a = 0; a < s->attribute_count; a++) {
        snprintf(p, sizeof p, "%s/dpv/%s.float32", path, s->attributes[a].name);
        unlink(p);
    }
    snprintf(p, sizeof p, "%s/dpv", path);
    rmdir(p);
    rmdir(path);
}

/* Three lines of 40, 25 and 7 vertices with two attributes. */
static lc_scene *synthetic_lines(int attributes)
{
    lc_error err = {0};
    lc_scene *s = lc_scene_create("synthetic", LC_PRIM_LINES);
    uint32_t n = 72;
    CHECK(s && lc_scene_alloc_vertices(s, n, 0, &err) == 0, "alloc: %s", err.msg);
    for (uint32_t i = 0; i < 3 * n; i++)
        s->positions[i] = (float)sin(i * 0.731) * 100.0f + 1.0f / 3.0f;
    const char *names[2] = {"fa", "curvature_k"};
    for (int a = 0; a < attributes; a++) {
        float *v = malloc(n * sizeof *v);
        for (uint32_t i = 0; i < n; i++)
            v[i] = (float)cos(i * (a + 1.3)) * 7.0f;
        lc_scene_add_attribute(s, names[a], v, &err);
    }
    s->line_count = 3;
    s->line_offsets = malloc(4 * sizeof(uint32_t));
    static const uint32_t off[4] = {0, 40, 65, 72};
    memcpy(s->line_offsets, off, sizeof off);
    return s;
}

static void test_roundtrip(const char *dir)
{
    lc_scene *plain = synthetic_lines(0), *attributed = synthetic_lines(2);
    static const struct {
        int elem, big;
    } tck_kinds[4] = {{4, 0}, {4, 1}, {8, 0}, {8, 1}};
    for (int k = 0; k < 4; k++) {
        char path[512];
        snprintf(path, sizeof path, "%s/round%d.tck", dir, k);
        CHECK(write_tck(plain, path, tck_kinds[k].elem, tck_kinds[k].big) == 0, "write %s", path);
        lc_scene *r = must_load(path);
        if (r)
            same_scene(plain, r, 0, path);
        lc_scene_destroy(r);
        unlink(path);
    }
    /* TRX: float32 positions exactly; float16 on a copy whose coordinates are
     * halves (multiples of 1/8 below 256). */
    lc_scene *halves = synthetic_lines(2);
    for (uint32_t i = 0; halves && i < 3 * halves->vertex_count; i++)
        halves->positions[i] = roundf(halves->positions[i] * 8) / 8;
    for (int k = 0; k < 4; k++) {
        char path[512];
        snprintf(path, sizeof path, "%s/round%d.trx", dir, k);
        const lc_scene *src = k < 2 ? attributed : halves;
        CHECK(write_trx(src, path, k >= 2, k % 2) == 0, "write %s", path);
        lc_scene *r = must_load(path);
        if (r)
            same_scene(src, r, 0, path);
        lc_scene_destroy(r);
        if (k % 2)
            unlink(path);
        else
            remove_trx_dir(path, src);
    }
    lc_scene_destroy(halves);
    for (int version = 1; version <= 2; version++) {
        char path[512];
        snprintf(path, sizeof path, "%s/round%d.binlines", dir, version);
        CHECK(write_binlines(attributed, path, version) == 0, "write %s", path);
        lc_scene *r = must_load(path);
        if (r && version == 2) {
            same_scene(attributed, r, 0, path);
        } else if (r) { /* version 1 has no names: attribute_K */
            CHECK(r->attribute_count == 2 && strcmp(r->attributes[1].name, "attribute_1") == 0, "v1 names");
            CHECK(r->vertex_count == attributed->vertex_count &&
                      memcmp(r->attributes[1].values, attributed->attributes[1].values, 72 * sizeof(float)) == 0,
                  "v1 attribute values");
        }
        lc_scene_destroy(r);
        unlink(path);
    }
    lc_scene_destroy(plain);
    lc_scene_destroy(attributed);
}

static void test_cases(void)
{
    int tck = run_case_table(DATA "tck/", load_path, load_memory);
    int bin = run_case_table(DATA "binlines/", load_path, load_memory);
    int trx = run_case_table(DATA "trx/", load_path, load_memory);
    CHECK(tck >= 16 && bin >= 10 && trx >= 14, "only %d .tck, %d .binlines and %d .trx cases", tck, bin, trx);
    /* A TRX directory (float64 positions, int32 offsets) holds what the zip
     * f32.trx holds; its arrays are read in name order. */
    lc_scene *zip = must_load(DATA "trx/valid/f32.trx"), *dir = must_load(DATA "trx/valid/dir.trx");
    if (zip && dir) {
        same_scene(zip, dir, 0, "trx directory vs zip");
        CHECK(strcmp(dir->attributes[0].name, "color_0") == 0 && strcmp(dir->name, "dir") == 0,
              "directory: first attribute %s, name %s", dir->attributes[0].name, dir->name);
    }
    lc_scene_destroy(zip);
    lc_scene_destroy(dir);
}

/* nibabel's standard.trk (RAS), standard.LPS.trk and standard.tck hold the same
 * 120 streamlines: loaded, they must lie on the same RAS+ mm points. */
static void test_nibabel_standard(void)
{
    if (access(NIBABEL_DATA "standard.tck", R_OK) != 0) {
        printf("skip: nibabel test data not installed (apt-get install python3-nibabel)\n");
        return;
    }
    lc_scene *tck = must_load(NIBABEL_DATA "standard.tck");
    const char *trks[2] = {NIBABEL_DATA "standard.trk", NIBABEL_DATA "standard.LPS.trk"};
    for (int i = 0; i < 2 && tck; i++) {
        lc_scene *trk = must_load(trks[i]);
        if (!trk)
            continue;
        CHECK(trk->vertex_count == tck->vertex_count && trk->line_count == tck->line_count, "%s: counts", trks[i]);
        double worst = 0;
        for (size_t k = 0; trk->vertex_count == tck->vertex_count && k < 3 * (size_t)tck->vertex_count; k++)
            worst = fmax(worst, fabs(trk->positions[k] - tck->positions[k]));
        CHECK(worst < 1e-5, "%s: points differ from standard.tck by %g mm", trks[i], worst);
        lc_error err = {0};
        CHECK(lc_scene_finalize(trk, NULL, &err) == 0, "%s", err.msg);
        static const double want[6] = {-0.5, -1.5, -1, 3.5, 13.5, 13}; /* nibabel's bounds */
        for (int b = 0; b < 6; b++)
            CHECK(fabs(trk->bounds[b] - want[b]) < 1e-5, "%s: bound %d is %g, nibabel says %g", trks[i], b,
                  trk->bounds[b], want[b]);
        lc_scene_destroy(trk);
    }
    lc_scene_destroy(tck);
}

static void test_mutations(void)
{
    static const char *const files[] = {"tck/valid/lines_f32le.tck",  "tck/valid/lines_f64be.tck",
                                        "binlines/valid/v1.binlines", "binlines/valid/v2.binlines",
                                        "trx/valid/f32.trx",          "trx/valid/f16_deflated.trx"};
    check_prefixes_and_mutations(DATA, files, sizeof files / sizeof *files, "0123456789 \n.:END\xff\x80\x7f\x01",
                                 0x9e3779b97f4a7c15ull, load_memory);
}

int main(void)
{
    lc_log_set_level(LC_LOG_ERROR); /* the cases trigger expected warnings */
    char dir[] = "/tmp/lc_loaders_tracts_XXXXXX";
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    test_cases();
    test_roundtrip(dir);
    test_nibabel_standard();
    test_mutations();
    rmdir(dir);
    return lc_test_finish();
}
