/* Shared body of the dataset-reader fuzz harnesses: load from memory, check the
 * error contract, and finalize what loads so that the scene code sees every
 * structure a parser can emit. */
#ifndef LC_FUZZ_SCENE_LOADER_H
#define LC_FUZZ_SCENE_LOADER_H

#include <stdint.h>
#include <stdlib.h>

#include "loaders.h"
#include "scene.h"

typedef int (*fuzz_memory_loader)(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);

static inline int fuzz_scene_loader(fuzz_memory_loader load, const char *name, const uint8_t *data, size_t size)
{
    lc_log_threshold = LC_LOG_ERROR; /* warnings about skipped input would flood the output */
    lc_scene *s = NULL;
    lc_error err = {0};
    int rc = load(data, size, name, &s, &err);
    if (rc != 0) {
        if (s || !err.msg[0]) /* contract: an error leaves no scene and says why */
            abort();
        return 0;
    }
    if (!s)
        abort();
    /* Small budgets keep finalize fast on large fuzzed counts. */
    lc_elements_desc desc = {.line_budget = 64, .patch_count = 8};
    lc_scene_finalize(s, &desc, &err);
    lc_scene_destroy(s);
    return 0;
}

#endif
