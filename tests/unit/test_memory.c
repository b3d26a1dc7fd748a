/* The compact vertex layout's encoders (round trips within their error
 * bounds, the blend layout each demo gets), the memory estimate, the
 * --max-memory refusal message and byte-size parsing. No GL. */
#include <math.h>
#include <string.h>

#include "demo.h"
#include "lc_test.h"
#include "memory.h"
#include "vertex_pack.h"

/* common.glsl's vertex_frame for a compact word. */
static void decode_direction(uint32_t w, double out[3])
{
    if (w == 0x80008000u) {
        out[0] = out[1] = out[2] = 0;
        return;
    }
    double x = fmax((int16_t)(w & 0xffff) / 32767.0, -1.0), y = fmax((int16_t)(w >> 16) / 32767.0, -1.0);
    double z = 1.0 - fabs(x) - fabs(y), t = fmax(-z, 0.0);
    x += x >= 0 ? -t : t;
    y += y >= 0 ? -t : t;
    double l = sqrt(x * x + y * y + z * z);
    out[0] = x / l, out[1] = y / l, out[2] = z / l;
}

static void test_directions(void)
{
    float d[3 * 6] = {0, 0, 1, 0, 0, -1, 1, 0, 0, 0.6f, -0.8f, 0, -0.48f, 0.6f, -0.64f, 0, 0, 0};
    uint32_t w[6];
    lc_pack_directions(d, 6, w);
    for (int v = 0; v < 6; v++) {
        double r[3];
        decode_direction(w[v], r);
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(r[c], d[3 * v + c], 2e-4, "direction round trip");
    }
    CHECK(w[5] == 0x80008000u && w[1] != 0x80008000u, "zero vector code is reserved");
}

static void test_positions(void)
{
    enum { N = 3000 };
    static float p[3 * N];
    for (int i = 0; i < 3 * N; i++)
        p[i] = (float)(sin(i * 0.37) * 100.0 + (i % 3) * 5.0);
    static uint32_t words[(3 * N + 1) / 2];
    static float chunks[8 * ((N + LC_POSITION_CHUNK - 1) / LC_POSITION_CHUNK)];
    lc_pack_positions(p, N, 0, words, chunks);
    double worst = 0;
    for (int v = 0; v < N; v++)
        for (int c = 0; c < 3; c++) {
            size_t h = 3 * (size_t)v + c;
            uint32_t q = (words[h >> 1] >> ((h & 1) * 16)) & 0xffff;
            const float *ch = chunks + 8 * (v >> LC_POSITION_CHUNK_SHIFT);
            double x = ch[c] + (double)ch[4 + c] * q;
            double err = fabs(x - p[h]) / (ch[4 + c] * 65535.0);
            worst = err > worst ? err : worst;
        }
    /* Half a code plus float rounding of the chunk's scale. */
    CHECK(worst <= 0.5 / 65535.0 + 1e-6, "position error %.3g of the chunk extent", worst);
}

static void test_layouts_and_estimate(void)
{
    static const struct {
        const char *demo;
        lc_blend_layout want;
    } cases[] = {{"points", LC_BLEND_IMPLICIT}, {"tornado", LC_BLEND_PAIR}, {"surface", LC_BLEND_TRIPLE}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        lc_demo_desc desc = {.count = strcmp(cases[i].demo, "points") == 0    ? 20000
                                      : strcmp(cases[i].demo, "surface") == 0 ? 40
                                                                              : 20};
        lc_scene *s = NULL;
        lc_error err = {0};
        CHECK(lc_demo_create(cases[i].demo, &desc, &s, &err) == 0, "%s: %s", cases[i].demo, err.msg);
        if (!s)
            continue;
        CHECK(lc_pack_blend_layout(s) == cases[i].want, "%s: blend layout %d", cases[i].demo,
              (int)lc_pack_blend_layout(s));
        lc_gpu_memory compact, exact;
        lc_gpu_scene_estimate(s, NULL, &compact);
        lc_gpu_scene_estimate(s, &(lc_gpu_scene_desc){.exact_positions = 1}, &exact);
        CHECK(compact.total * 3 < exact.total * 2, "%s: compact %llu vs exact %llu bytes", cases[i].demo,
              (unsigned long long)compact.total, (unsigned long long)exact.total);
        uint64_t need = lc_memory_estimate(s, NULL, 1, 1);
        CHECK(lc_memory_check(s, NULL, 1, 1, need, &err) == 0, "%s: fits its own estimate", cases[i].demo);
        CHECK(lc_memory_check(s, NULL, 1, 1, need - 1, &err) == LC_ERR_LIMIT && strstr(err.msg, "--max-memory") &&
                  strstr(err.msg, s->name),
              "%s: refusal names the dataset and the limit: %s", cases[i].demo, err.msg);
        /* After the release only counts remain, and the estimate does not change. */
        lc_scene_release_vertex_arrays(s);
        CHECK(lc_memory_estimate(s, NULL, 1, 1) == need, "%s: estimate after release", cases[i].demo);
        CHECK(lc_scene_bytes(s) <= ((size_t)s->line_count + 1) * 4, "%s: %zu bytes left", cases[i].demo,
              lc_scene_bytes(s));
        CHECK(lc_scene_set_element_budget(s, 10, &err) == LC_ERR_INVALID || s->type == LC_PRIM_POINTS,
              "%s: no element rebuild after release", cases[i].demo);
        lc_scene_destroy(s);
    }
}

static void test_parse_bytes(void)
{
    static const struct {
        const char *text;
        int ok;
        unsigned long long bytes;
    } cases[] = {{"1000", 1, 1000},
                 {"64k", 1, 65536},
                 {"512M", 1, 512ull << 20},
                 {"20G", 1, 20ull << 30},
                 {"1.5G", 1, 3ull << 29},
                 {"2GB", 1, 2ull << 30},
                 {"", 0, 0},
                 {"-1", 0, 0},
                 {"12X", 0, 0},
                 {"5GiB", 0, 0}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        unsigned long long v = 0;
        int rc = lc_memory_parse_bytes(cases[i].text, &v);
        CHECK((rc == 0) == cases[i].ok && (!cases[i].ok || v == cases[i].bytes), "\"%s\" -> rc %d, %llu", cases[i].text,
              rc, v);
    }
}

int main(void)
{
    test_directions();
    test_positions();
    test_layouts_and_estimate();
    test_parse_bytes();
    return lc_test_finish();
}
