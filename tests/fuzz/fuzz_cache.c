/* libFuzzer harness for the scene cache reader (render/scene/scene_cache.h).
 * A cache file carries a payload hash, so mutated bytes alone would only ever
 * reach the hash check. Instead the input edits a valid cache of a small demo
 * scene: its first byte picks the scene (points, lines or triangles), each
 * following 5 bytes are one edit (a little-endian offset into the file, modulo
 * its length, and the byte to put there). The edited file is sealed
 * (lc_scene_cache_seal recomputes its hash wherever its counts are
 * consistent) and read with the key it claims, so counts, levels of detail,
 * indices and offsets reach the reader's structural checks. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "demo.h"
#include "scene.h"
#include "scene_cache.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define BASES 3
static uint8_t *base[BASES];
static size_t base_len[BASES];
static char path[64];

/* The valid caches the inputs edit, written once per process. */
static int prepare(void)
{
    static const struct {
        const char *demo;
        uint64_t count;
    } demos[BASES] = {{"points", 300}, {"tornado", 6}, {"surface", 12}};
    snprintf(path, sizeof path, "/tmp/lc_fuzz_cache_%ld.lcscene", (long)getpid());
    lc_scene_cache_key key = {.file_size = 1, .mtime_sec = 2, .mtime_nsec = 3, .content_hash = 4, .settings_hash = 5};
    for (int i = 0; i < BASES; i++) {
        lc_error err = {0};
        lc_scene *s = NULL;
        lc_demo_desc desc = {.count = demos[i].count};
        if (lc_demo_create(demos[i].demo, &desc, &s, &err) != 0 || lc_scene_cache_write(path, &key, s, &err) != 0) {
            fprintf(stderr, "fuzz_cache: %s: %s\n", demos[i].demo, err.msg);
            lc_scene_destroy(s);
            return -1;
        }
        lc_scene_destroy(s);
        FILE *f = fopen(path, "rb");
        if (!f)
            return -1;
        fseek(f, 0, SEEK_END);
        base_len[i] = (size_t)ftell(f);
        fseek(f, 0, SEEK_SET);
        base[i] = malloc(base_len[i]);
        int ok = base[i] && fread(base[i], 1, base_len[i], f) == base_len[i];
        fclose(f);
        if (!ok)
            return -1;
    }
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static int ready = 0;
    if (!ready)
        ready = prepare() == 0 ? 1 : -1;
    if (ready < 0 || size < 1)
        return 0;
    int b = data[0] % BASES;
    uint8_t *file = malloc(base_len[b]);
    if (!file)
        return 0;
    memcpy(file, base[b], base_len[b]);
    for (size_t i = 1; i + 5 <= size; i += 5) {
        uint32_t at =
            (uint32_t)data[i] | (uint32_t)data[i + 1] << 8 | (uint32_t)data[i + 2] << 16 | (uint32_t)data[i + 3] << 24;
        file[at % base_len[b]] = data[i + 4];
    }
    FILE *f = fopen(path, "wb");
    int ok = f && fwrite(file, 1, base_len[b], f) == base_len[b];
    if (f)
        fclose(f);
    free(file);
    lc_error err = {0};
    lc_scene_cache_key key;
    if (ok && lc_scene_cache_seal(path, &key, &err) == 0) {
        lc_scene *s = NULL;
        if (lc_scene_cache_read(path, &key, &s, &err) == 0)
            lc_scene_destroy(s);
    }
    unlink(path);
    return 0;
}
